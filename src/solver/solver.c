/* BwSolver: the paths (fieldsplit with the Schur PC, direct LU, condensed),
 * the automatic fallback between them, and the self-checks of every answer
 * (see solver.h for the structure of each path). */
#include <petscksp.h>
#include "solver/solver_impl.h"
#include <string.h>
#include "util/log.h"
#include "util/compat.h"
#include "util/factor.h"

/* By size and by how often the operator is solved with. A factorisation
 * of S^ is exact and robust to stiffness contrast; for one solve it is as
 * fast as CG + GAMG up to ~5e4 blocks (bench/results.md: 1.06 s against
 * 1.15 s at 3e4, 3.8 s against 3.0 s at 1e5, whole runs); a factor is
 * reused by every further solve (load cases, load steps), where each CG +
 * GAMG solve costs as much as the first, so with more than one solve it
 * pays up to 2e5 blocks. Above, its fill grows faster than N while CG +
 * GAMG stays near linear. The same size bounds the direct path: its saddle
 * matrix and factors would not fit beyond it. */
#define BW_SCHUR_GAMG_BLOCKS     200000
#define BW_SCHUR_GAMG_BLOCKS_ONE 50000
#define BW_DIRECT_ROWS_3D        1000000

/* MUMPS's block low-rank (BLR) factor of a split 3D S^ in a linear
 * analysis, from this many rows of S^: its fronts then reach the sizes BLR
 * compresses (none below ~300 x 300 units of bench/large_wall3d.yaml, 5.4e5
 * rows). The whole run on 2 ranks at BW_LOW_RANK_TOL, stresses not
 * written (bench/results.md, 2026-11-29): 9e4 blocks 20.3 KB per block
 * against 21.1 and 1.5 s slower; 2.5e5 blocks 19.7 against 21.2 KB in the
 * same time; 1e6 blocks 19.0 against 21.7 KB, 107 s against 118 s
 * (medians of 3, 105-113 against 100-121). The
 * factor is the preconditioner of the refinement on the true S~, which
 * took the same three steps to the same floor; at 1e-8 it took five and
 * did not get there. */
#define BW_LOW_RANK_ROWS         1000000

/* A 3D S^ that splits into independent groups of dofs (an extruded wall
 * in a linear analysis: u1 u2 w3 | u3 w1 w2) factors with far less fill,
 * its graph ordered uncompressed (schur.c), and is factored at any size
 * where it fits: bench/large_wall3d.yaml at 1e6 blocks on 2 ranks took
 * 107 s with S^ factored against 1004 s with CG + GAMG (bench/results.md,
 * 2026-11-27 and 2026-11-28). Its memory, the whole run's summed peak per block on 2
 * ranks (m = 8, m_b = 4, stresses not written): 19.6 KB at 9e4 blocks,
 * 20.7 at 2.5e5, 21.4 at 4.9e5, 21.7 at 1e6 (CHOLMOD on 1 rank: 20.5 at
 * 1e6); 8 ranks at 9e4 blocks held ~110 MB more per added rank. The
 * estimate lies a little above each: 20 KB at 9e4 blocks, 0.6 KB more
 * per doubling (the factor's nested-dissection fill), 150 MB per rank. */
static PetscLogDouble BwSplitFactorBytesPerRank(PetscInt nblocks, PetscMPIInt size, PetscBool low_rank)
{
  /* with the factor in block low-rank form (solver.low_rank) the runs
   * measured held 18.1-19.7 KB per block from 2.5e5 to 1e6 blocks on 1 and
   * 2 ranks, and no more at 1e6 than at 2.5e5: 20 KB */
  PetscLogDouble kb = low_rank ? 20.0 : 20.0 + 0.6 * PetscMax(0.0, PetscLog2Real((PetscReal)nblocks / 9e4));

  return (PetscLogDouble)nblocks * kb * 1024 / size + 150e6; /* KB of 1024 bytes, as bench/results.md counts them */
}

const char *const BwMethods[]     = {"auto", "fieldsplit", "direct", "condensed", "BwMethod", "BW_METHOD_", NULL};
const char *const BwSchurSolves[] = {"auto", "cholesky", "gamg", "hypre", "BwSchurSolve", "BW_SCHUR_", NULL};

PetscErrorCode BwSolverCreate(MPI_Comm comm, BwSolver *solver)
{
  BwSolver s;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&s));
  s->comm               = comm;
  s->requested          = BW_METHOD_AUTO;
  s->rtol               = 1e-10;
  s->expected_solves    = 1;
  s->symmetric          = PETSC_TRUE;
  s->diagnose           = PETSC_TRUE;
  s->forward_check      = PETSC_TRUE;
  s->storage            = BW_STORAGE_SHELL;
  s->forward_rtol       = -1; /* = rtol unless set */
  s->forward_estimate   = -1;
  s->condition_estimate = -1;
  s->low_rank_ratio     = -1;
  s->fieldsplit.name    = "fieldsplit";
  s->fieldsplit.method  = BW_METHOD_FIELDSPLIT;
  s->cholesky.name      = "fieldsplit with S^ factored";
  s->cholesky.method    = BW_METHOD_FIELDSPLIT;
  s->direct.name        = "direct (LU)";
  s->direct.method      = BW_METHOD_DIRECT;
  s->condensed.name     = "condensed";
  s->condensed.method   = BW_METHOD_CONDENSED;
  *solver               = s;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverReset(BwSolver s)
{
  PetscFunctionBeginUser;
  PetscCall(KSPDestroy(&s->fieldsplit.ksp));
  PetscCall(KSPDestroy(&s->cholesky.ksp));
  PetscCall(KSPDestroy(&s->direct.ksp));
  PetscCall(KSPDestroy(&s->condensed.ksp));
  PetscCall(MatDestroy(&s->Kaij));
  PetscCall(MatDestroy(&s->Sexact));
  PetscCall(VecDestroy(&s->wq));
  PetscCall(VecDestroy(&s->xq));
  PetscCall(VecDestroy(&s->fw_weight));
  PetscCall(VecDestroy(&s->fw_prev));
  PetscCall(VecDestroy(&s->fw_work));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverDestroy(BwSolver *solver)
{
  PetscFunctionBeginUser;
  if (!*solver) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(BwSolverReset(*solver));
  PetscCall(PetscFree(*solver));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverSetFromOptions(BwSolver s, BwScene scene)
{
  PetscInt                 method = s->requested, schur = s->schur, storage = s->storage, w = s->condition_when, fb = s->forward_bound, lr = s->low_rank_when;
  PetscBool                fset;
  static const char *const when[] = {"auto", "always", "never"}, *bounds[] = {"auto", "whole", "schur", "extra"};

  PetscFunctionBeginUser;
  PetscCall(BwSceneHelpSection(scene, "Solver (scene key solver.*)"));
  PetscCall(BwSceneRequireMapping(scene, "-solver", "method, rtol, ..."));
  PetscCall(BwSceneEnum(scene, "-solver_method", "auto (fieldsplit, a factorisation on failure), fieldsplit, direct, or condensed (benchmark reference)", 4, BwMethods, &method, NULL));
  PetscCall(BwSceneReal(scene, "-solver_rtol", "Required relative true residual of the full mixed system (scaled)", &s->rtol, NULL));
  PetscCall(BwSceneEnum(scene, "-solver_schur", "Schur complement solve of fieldsplit: auto (cholesky below 5e4 blocks, or 2e5 in 3D or when the analysis solves more than once; gamg above; in 3D where S^ splits into independent groups, cholesky at any size where its memory estimate fits solver.memory), cholesky, gamg (CG + GAMG) or hypre (CG + BoomerAMG)", 4, BwSchurSolves, &schur, NULL));
  PetscCall(BwSceneReal(scene, "-solver_memory", "Memory the run may use [GB], summed over its ranks, for auto's choice of the Schur solve; 0: what the nodes have available when the solver is set up (MemAvailable, or less under a batch system's cgroup limit), shared among the ranks of each node", &s->memory, NULL));
  PetscCall(BwSceneEnum(scene, "-solver_low_rank", "S^ factored by MUMPS in block low-rank form (BLR, CNTL(7) = 1e-12; the refinement on the true S~ removes what it drops): auto (a split 3D S^ of 1e6 rows or more in a linear analysis, where it holds less in less time; MUMPS's then on one rank too, in CHOLMOD's place), always (MUMPS's on one rank too), never", 3, when, &lr, NULL));
  PetscCall(BwSceneReal(scene, "-solver_forward_rtol", "Required estimated relative error of the displacements (max norm, rotations times the assembly's size), from the last correction of the refinement on the full system; default solver.rtol", &s->forward_rtol, &fset));
  PetscCall(BwSceneEnum(scene, "-solver_condition_estimate", "1-norm condition estimate of the factored operator (S^, or K~ on the direct path; about five solves with the factor): auto (when the refinement needed more than two steps or missed a tolerance, unless it stopped at the named floor of rounding the displacements), always, never", 3, when, &w, NULL));
  PetscCall(BwSceneEnum(scene, "-solver_forward_bound", "The round-off part of the forward estimate, where the condition is estimated: auto (extra where D^ is held by its structure, else whole; in 3D above 1e6 rows of K~ cond eps), whole (LAPACK's bound, K~ assembled), schur (the same bound through S^'s factor, nothing of the stresses' size stored), extra (10 x the error that one residual in double-double shows)", 4, bounds, &fb, NULL));
  PetscCall(BwSceneEnum(scene, "-solver_storage", "Saddle operator storage: shell (D^ by its structure), nest (D^ assembled) or aij (one assembled matrix)", 3, BwStorages, &storage, NULL));
  PetscCall(BwSceneBool(scene, "-solver_reproducible", "On several ranks, factor every matrix whole on each rank, sequentially (PCREDUNDANT), so that a run repeats itself bit for bit on the same machine and ranks (a parallel factorisation, MUMPS's or SuperLU_DIST's, does not). Each rank holds the whole factor, and a factorisation takes as long as on one rank (docs/solvers.md)", &s->reproducible, NULL));
  {
    PetscMPIInt size;
    PetscCallMPI(MPI_Comm_size(s->comm, &size));
    if (size == 1) s->reproducible = PETSC_FALSE; /* one rank repeats itself as it is */
  }
  if (!(s->rtol > 0 && s->rtol < 1)) PetscCall(BwSceneError(scene, "-solver_rtol", "must be in (0, 1), got %g", (double)s->rtol));
  if (!fset) s->forward_rtol = s->rtol;
  if (!(s->memory >= 0)) PetscCall(BwSceneError(scene, "-solver_memory", "must be >= 0 GB (0: what the nodes have available), got %g", (double)s->memory));
#if !defined(PETSC_HAVE_MUMPS)
  if (lr == 1) PetscCall(BwSceneError(scene, "-solver_low_rank", "always: this PETSc has no MUMPS (it has %s)", BwFactorPackages()));
#endif
  if (lr == 1 && s->reproducible) PetscCall(BwSceneError(scene, "-solver_low_rank", "always: not with solver.reproducible, whose factors are sequential ones of the whole matrix on every rank"));
  if (!(s->forward_rtol > 0 && s->forward_rtol <= 1)) PetscCall(BwSceneError(scene, "-solver_forward_rtol", "must be in (0, 1], got %g", (double)s->forward_rtol));
#if !defined(PETSC_HAVE_HYPRE)
  if (schur == BW_SCHUR_HYPRE) PetscCall(BwSceneError(scene, "-solver_schur", "hypre: this PETSc has no hypre (it has %s)", BwFactorPackages()));
#endif
  s->requested      = (BwMethod)method;
  s->schur          = (BwSchurSolve)schur;
  s->storage        = (BwStorage)storage;
  s->condition_when = w;
  s->low_rank_when  = lr;
  s->forward_bound  = (BwForwardBound)fb;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverGetStorage(BwSolver s, BwStorage *storage)
{
  PetscFunctionBeginUser;
  *storage = s->storage;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Richardson on the unpreconditioned (true) residual: with the Schur
 * complement factored the preconditioner is the exact inverse up to
 * round-off and one step converges (a second checks it); with CG + GAMG
 * each step gains about five digits. It keeps two work vectors, where
 * FGMRES keeps two per iteration. On the fieldsplit paths it refines on
 * the block dofs (A = S~, schur.c), its vectors 3 or 6 values per block;
 * on the direct path on the whole system (A = K~). */
static PetscErrorCode BwSolverOuterKSP(BwSolver s, const char prefix[], PetscInt maxit, Mat A, KSP *ksp)
{
  PetscFunctionBeginUser;
  PetscCall(KSPCreate(s->comm, ksp));
  if (prefix) PetscCall(KSPSetOptionsPrefix(*ksp, prefix));
  PetscCall(KSPSetOperators(*ksp, A, A));
  PetscCall(KSPSetType(*ksp, KSPRICHARDSON));
  PetscCall(KSPSetNormType(*ksp, KSP_NORM_UNPRECONDITIONED));
  PetscCall(KSPSetTolerances(*ksp, s->rtol, 0.0, PETSC_DEFAULT, maxit));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwSolverCreateFieldsplit(BwSolver s, BwPath *path, const char prefix[], PetscBool factor)
{
  PetscFunctionBeginUser;
  if (!s->Sexact) {
    PetscCall(BwMixedCreateSchurOperator(s->mx, &s->Sexact));
    PetscCall(MatCreateVecs(s->Sexact, &s->wq, &s->xq));
  }
  PetscCall(BwSolverOuterKSP(s, prefix, factor || !s->schur_iterative ? 5 : 30, s->Sexact, &path->ksp));
  path->qspace = PETSC_TRUE;
  PetscCall(BwSchurPCSetUp(s, path->ksp, factor));
  PetscCall(KSPSetFromOptions(path->ksp));
  PetscCall(BwSolverSetConvergenceTest(s, path->ksp));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* LU of the whole saddle matrix, assembled for the occasion (MUMPS needs
 * entries), with iterative refinement: one step when the factors are
 * accurate, a few more when pivoting was delayed. */
static PetscErrorCode BwSolverCreateDirect(BwSolver s)
{
  PC pc;

  PetscFunctionBeginUser;
  PetscCall(BwMixedCreateAIJ(s->mx, &s->Kaij));
  PetscCall(BwMixedGetValuesState(s->mx, &s->kaij_state));
  PetscCall(BwSolverOuterKSP(s, "direct_", 5, s->Kaij, &s->direct.ksp));
  PetscCall(KSPGetPC(s->direct.ksp, &pc));
  PetscCall(BwSolverSetFactor(s, pc, BW_FACTOR_LU_PIVOTING, s->Kaij));
  PetscCall(KSPSetFromOptions(s->direct.ksp));
  PetscCall(BwSolverFactorDefaults(pc));
#if defined(PETSC_HAVE_MUMPS)
  {
    Mat F;
    /* a larger work space: MUMPS's estimate for saddle matrices with
     * delayed pivots is too small (INFOG(1) = -9 seen with 20 %) */
    PetscCall(BwSolverGetMumpsFactor(pc, &F));
    if (F) PetscCall(MatMumpsSetIcntl(F, 14, 100));
  }
#endif
  PetscCall(BwSolverSetConvergenceTest(s, s->direct.ksp));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverSetSymmetric(BwSolver s, PetscBool symmetric)
{
  PetscFunctionBeginUser;
  PetscCheck(!s->mx, s->comm, PETSC_ERR_ORDER, "BwSolverSetSymmetric after BwSolverSetUp");
  s->symmetric = symmetric;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverSetForwardCheck(BwSolver s, PetscBool check)
{
  PetscFunctionBeginUser;
  s->forward_check = check;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverSetDiagnose(BwSolver s, PetscBool diagnose)
{
  PetscFunctionBeginUser;
  s->diagnose = diagnose;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverSetExpectedSolves(BwSolver s, PetscInt n)
{
  PetscFunctionBeginUser;
  s->expected_solves = n;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* auto on a split 3D S^: factored where the estimate of the run's memory
 * fits what each rank can have (solver.memory, or its node's available
 * memory and what the run holds already, shared among the node's ranks:
 * read without the 6 GB the 1e6-block wall held by then, it chose GAMG,
 * whose set-up the machine could not hold), else CG + GAMG, which holds
 * less (15.8 KB per block on 1 rank at 1e6 blocks, against 20.5). The
 * same choice on every rank. */
static PetscErrorCode BwSolverChooseSplitFactor(BwSolver s, PetscInt nblocks, PetscBool low_rank)
{
  PetscMPIInt    size;
  PetscLogDouble need, avail;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(s->comm, &size));
  need = BwSplitFactorBytesPerRank(nblocks, size, low_rank);
  if (s->memory > 0) avail = s->memory * 1e9 / size;
  else PetscCall(BwMemoryPerRank(s->comm, PETSC_TRUE, &avail, NULL)); /* the estimate is of the whole run, what it holds already included */
  s->schur_iterative = need <= avail ? PETSC_FALSE : PETSC_TRUE;
  PetscCall(PetscSNPrintf(s->schur_choice, sizeof(s->schur_choice), "%s (S^ splits; the run with S^ factored%s needs about %.3g GB, %s the %.3g GB %s)", s->schur_iterative ? "CG + GAMG" : "S^ factored", low_rank ? " in block low-rank form" : "", need * size / 1e9, s->schur_iterative ? "more than" : "within", avail * size / 1e9, s->memory > 0 ? "of solver.memory" : "available"));
  PetscCall(PetscInfo(NULL, "auto's Schur solve: %s\n", s->schur_choice));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Whether a factor of S^ on the fieldsplit path would be MUMPS's block
 * low-rank one (solver.low_rank): always, or in auto for a split 3D S^ of
 * BW_LOW_RANK_ROWS rows or more in a linear analysis. On one rank too,
 * where MUMPS's then replaces CHOLMOD's: the 1e6-block wall on 1 rank
 * took 170.5 s and 18.1 KB per block against CHOLMOD's 182.2 s and 20.3
 * (bench/results.md, 2026-11-29). */
static PetscBool BwSolverLowRankWanted(BwSolver s, const BwMixedOwnership *own, PetscInt groups)
{
#if defined(PETSC_HAVE_MUMPS)
  if (s->reproducible || s->low_rank_when == 2) return PETSC_FALSE;
  if (s->low_rank_when == 1) return PETSC_TRUE;
  return own->dim == 3 && groups > 1 && s->expected_solves == 1 && own->nq_global >= BW_LOW_RANK_ROWS ? PETSC_TRUE : PETSC_FALSE;
#else
  (void)s;
  (void)own;
  (void)groups;
  return PETSC_FALSE;
#endif
}

PetscErrorCode BwSolverSetUp(BwSolver s, BwMixed mx)
{
  BwMixedOwnership own;
  PetscBool        low_rank;
  PetscInt         groups;

  PetscFunctionBeginUser;
  s->mx = mx;
  PetscCall(BwMixedGetOwnership(mx, &own));
  /* Every block dof prescribed: the displacement field is given, the
   * stresses follow from it (K is -I on them, with no q rows), and there
   * is nothing to factor: a Schur complement of no rows handed to CHOLMOD
   * printed its error on a good run. */
  s->trivial = own.nq_global == 0 ? PETSC_TRUE : PETSC_FALSE;
  if (s->trivial) PetscFunctionReturn(PETSC_SUCCESS);
  {
    PetscInt q0, q1;
    Mat      S;
    PetscCall(BwMixedGetOperators(mx, NULL, &S, NULL));
    PetscCall(MatGetOwnershipRange(S, &q0, &q1));
    PetscCall(BwBlasSetThreadsForRows(q1 - q0));
  }
  PetscCall(BwMixedGetSchurGroups(mx, &groups, NULL, 0));
  low_rank = BwSolverLowRankWanted(s, &own, groups);
  if (s->schur == BW_SCHUR_AUTO) {
    MatSolverType type;
    /* a PETSc with no sparse factorisation on this many ranks (a cluster's
     * build without MUMPS) leaves auto the iterative Schur solve */
    PetscCall(BwFactorPackage(s->comm, s->symmetric ? BW_FACTOR_CHOLESKY : BW_FACTOR_LU, &type));
    /* 3D: CG + GAMG converges slowly on walls thin across X3 (their
     * out-of-plane bending): a 3D running-bond wall of 3e4 blocks took
     * 40-80 CG steps per solve and 8.7 s against 0.95 s with S^ factored
     * (1e5 blocks: 74 s against 3.5 s, with 12 s of factorisation), so 3D
     * factors S^ up to BW_SCHUR_GAMG_BLOCKS blocks for one solve too */
    const PetscInt limit = own.dim == 3 || s->expected_solves > 1 ? BW_SCHUR_GAMG_BLOCKS : BW_SCHUR_GAMG_BLOCKS_ONE;
    s->schur_iterative = !type || own.nblocks >= limit ? PETSC_TRUE : PETSC_FALSE;
    s->schur_choice[0] = 0;
    if (type && own.dim == 3 && groups > 1) PetscCall(BwSolverChooseSplitFactor(s, own.nblocks, low_rank));
  }
  else s->schur_iterative = s->schur == BW_SCHUR_GAMG || s->schur == BW_SCHUR_HYPRE ? PETSC_TRUE : PETSC_FALSE;
  s->direct_fits = own.nblocks < BW_SCHUR_GAMG_BLOCKS || s->requested == BW_METHOD_DIRECT ? PETSC_TRUE : PETSC_FALSE;
  /* 3D: 3 m m_b stress rows per interface (96 at m = 8, m_b = 4, against
   * 32 in 2D at m = 16), and a graph that fills more: a sparse LU of the
   * saddle matrix of 1e4 blocks (2.9e6 rows) was still ordering after 10
   * minutes here, while fieldsplit had the answer in 20 s. The direct
   * path (and the factor's round-off bound, which assembles the same
   * matrix) is kept to saddle matrices below 1e6 rows. */
  if (own.dim == 3 && own.nr_global + own.nq_global >= BW_DIRECT_ROWS_3D && s->requested != BW_METHOD_DIRECT) s->direct_fits = PETSC_FALSE;
  s->low_rank = low_rank && !s->schur_iterative ? PETSC_TRUE : PETSC_FALSE;
  if (s->requested == BW_METHOD_AUTO || s->requested == BW_METHOD_FIELDSPLIT) PetscCall(BwSolverCreateFieldsplit(s, &s->fieldsplit, NULL, PETSC_FALSE));
  PetscCall(BwSolverForwardSetUp(s));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The condensed reference: S^ factored, the stresses recovered from the
 * displacements. */
static PetscErrorCode BwSolverCondensed(BwSolver s, Vec b, Vec x, BwLog *log)
{
  PC  pc;
  Mat S;
  IS  isq;
  Vec xq, rhs;

  PetscFunctionBeginUser;
  PetscCall(BwMixedGetOperators(s->mx, NULL, &S, NULL));
  PetscCall(BwMixedGetFields(s->mx, NULL, &isq));
  if (!s->condensed.ksp) {
    PetscCall(KSPCreate(s->comm, &s->condensed.ksp));
    PetscCall(KSPSetOptionsPrefix(s->condensed.ksp, "condensed_"));
    PetscCall(KSPSetOperators(s->condensed.ksp, S, S));
    PetscCall(KSPSetType(s->condensed.ksp, KSPPREONLY));
    PetscCall(KSPGetPC(s->condensed.ksp, &pc));
    PetscCall(BwSolverSetFactor(s, pc, BW_FACTOR_CHOLESKY, S));
    PetscCall(KSPSetFromOptions(s->condensed.ksp));
  }
  s->condensed.ran = PETSC_TRUE;
  PetscCall(BwLogBegin(log, BW_PHASE_SETUP));
  PetscCall(KSPSetUp(s->condensed.ksp));
  PetscCall(BwLogEnd(log, BW_PHASE_SETUP));
  PetscCall(BwLogBegin(log, BW_PHASE_SOLVE));
  PetscCall(MatCreateVecs(S, &rhs, NULL));
  PetscCall(BwMixedSchurRHS(s->mx, b, rhs)); /* F^ + D^T b_r */
  PetscCall(VecGetSubVector(x, isq, &xq));
  PetscCall(KSPSolve(s->condensed.ksp, rhs, xq));
  PetscCall(VecRestoreSubVector(x, isq, &xq));
  PetscCall(VecDestroy(&rhs));
  PetscCall(BwMixedStressesFromDofs(s->mx, b, x)); /* r~ = T D^ q~ - b_r */
  PetscCall(BwLogEnd(log, BW_PHASE_SOLVE));
  s->used       = BW_METHOD_CONDENSED;
  s->iterations = 0;
  PetscCall(BwMixedCheck(s->mx, x, b, NULL, NULL, &s->check));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Runs one path. A PETSc error inside the solver (a factorisation that
 * fails, say) is a failed path, not a failed run: *ok says whether it met
 * solver.rtol; *usable whether its answer is a real one all the same: no
 * PETSc error, no failed factorisation, no null pivot, and a finite true
 * residual of at most sqrt(solver.rtol), the most a run may miss its
 * target by and still write a result (with a warning). */
static PetscErrorCode BwSolverRun(BwSolver s, BwPath *path, Vec b, Vec x, BwLog *log, PetscBool *ok, PetscBool *usable, char reason[], size_t len)
{
  PetscErrorCode     ierr;
  KSPConvergedReason kr  = KSP_CONVERGED_ITERATING;
  PC                 pc;
  PCFailedReason     pcr  = PC_NOERROR;
  PetscInt           npiv = 0;

  PetscFunctionBeginUser;
  *ok                   = PETSC_FALSE;
  *usable               = PETSC_FALSE;
  path->ran             = PETSC_TRUE;
  s->forward_estimate   = -1; /* not estimated unless the convergence test runs */
  s->condition_estimate = -1;
  s->residual_floor     = -1;
  s->iterations         = 0;
  PetscCall(VecZeroEntries(x));
  /* a PETSc error in a solver is a failed path: caught, not raised */
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  {
    PetscInt state;
    PetscCall(BwMixedGetValuesState(s->mx, &state));
    if (state != s->values_seen || !path->ran_once) s->setups++;
    s->values_seen = state;
    path->ran_once = PETSC_TRUE;
  }
  PetscCall(BwLogBegin(log, BW_PHASE_SETUP));
  ierr = KSPSetUp(path->ksp);
  PetscCall(BwLogEnd(log, BW_PHASE_SETUP));
  PetscCall(BwLogBegin(log, BW_PHASE_SOLVE));
  if (!ierr && path->qspace) {
    /* on the block dofs: w = b_q + D^T b_r, S~ q = w to solver.rtol of the
     * whole right-hand side (the residual of the full system once the
     * stresses are T D^ q - b_r), then the stresses */
    IS        isq;
    PetscReal bnorm;
    ierr = VecNorm(b, NORM_2, &bnorm);
    if (!ierr) ierr = KSPSetTolerances(path->ksp, 0.0, s->rtol * bnorm, PETSC_DEFAULT, PETSC_DEFAULT);
    if (!ierr) ierr = BwMixedSchurRHS(s->mx, b, s->wq);
    /* into a vector of the solver's own, not a view of x: the KSP keeps a
     * reference to its solution after the solve, which a view restored to
     * x must not outlive */
    if (!ierr) ierr = KSPSolve(path->ksp, s->wq, s->xq);
    if (!ierr) ierr = BwMixedGetFields(s->mx, NULL, &isq);
    if (!ierr) ierr = VecISCopy(x, isq, SCATTER_FORWARD, s->xq);
    if (!ierr) ierr = BwMixedStressesFromDofs(s->mx, b, x);
  } else if (!ierr) ierr = KSPSolve(path->ksp, b, x);
  PetscCall(PetscPopErrorHandler());
  if (!ierr) {
    PetscCall(KSPGetConvergedReason(path->ksp, &kr));
    PetscCall(KSPGetIterationNumber(path->ksp, &s->iterations));
    PetscCall(KSPGetPC(path->ksp, &pc));
    PetscCall(PCGetFailedReason(pc, &pcr));
    if (pcr == PC_NOERROR) PetscCall(BwSolverNullPivots(path->ksp, &npiv));
    if (pcr == PC_NOERROR && !s->reproducible) {
      /* where MUMPS ordered what it factored (INFOG(32): 1 on rank 0, 2 in
       * parallel), for /solver: the factors are gone by then */
      PetscInt v;
      PetscCall(BwSolverMumpsInfog(path->ksp, 32, &v));
      if (v > 0) s->mumps_analysis = v;
      if (s->low_rank && path == &s->fieldsplit) {
        /* the factor's entries with and without its compression; a
         * negative INFOG counts millions */
        PetscInt  full, blr;
        PetscReal nf, nb;
        PetscCall(BwSolverMumpsInfog(path->ksp, 29, &full));
        PetscCall(BwSolverMumpsInfog(path->ksp, 35, &blr));
        nf = full < 0 ? -1e6 * (PetscReal)full : (PetscReal)full;
        nb = blr < 0 ? -1e6 * (PetscReal)blr : (PetscReal)blr;
        if (nf > 0 && nb > 0) s->low_rank_ratio = nb / nf;
      }
    }
    /* The condition of what was factored, while the factor is there: a few
     * solves with it, and the one number that says how far a small residual
     * can be from a small error. In auto, only where the refinement showed
     * trouble (more than two steps, or a stop at the step limit): on an
     * ordinary wall it would cost 0.6 s of 4.2 s at 1e5 blocks and say
     * nothing the forward estimate does not. Not for a Newton correction
     * (no forward check), which has no bound to add it to: the next
     * iteration measures the nonlinear residual itself. */
    if (s->condition_when == 1 || (s->condition_when == 0 && s->forward_check && (s->iterations > 2 || kr <= 0))) {
      if (pcr == PC_NOERROR && npiv == 0 && (kr > 0 || kr == KSP_DIVERGED_ITS || (kr == KSP_DIVERGED_DTOL && s->floor_stall))) {
        PC        fpc;
        Mat       A;
        PetscBool sym = PETSC_FALSE, set;
        PetscCall(BwSolverGetFactorPC(path->ksp, &fpc, &A));
        if (fpc) {
          /* not in auto where the refinement stopped at the floor of
           * rounding q, which the run names (estimates.c): the condition
           * adds nothing there to what the floor and the round-off part
           * below say, and its five solves with the factor were a third
           * of the solve phase of a 2.5e5-block 3D wall (3.1 of 8.4 s) */
          PetscBool at_floor = kr == KSP_DIVERGED_DTOL && s->floor_stall && s->residual_floor > 0 ? PETSC_TRUE : PETSC_FALSE;
          PetscCall(MatIsSymmetricKnown(A, &set, &sym));
          if (s->condition_when == 1 || !at_floor) PetscCall(BwSolverConditionEstimate(fpc, A, (PetscBool)(set && sym), &s->condition_estimate));
          /* and what round-off in the factor allows: the refinement's
           * corrections alone can be the residual's noise */
          /* which round-off part: -solver_forward_bound; auto the
           * extra-precise residual's estimate wherever the operator has it
           * (estimates.c: it tracked the true error of every extreme case
           * of the stability suite within 6x, where the worst-case bounds
           * were up to 1e7 above it), else the whole system's bound where
           * K~ can be assembled, else cond eps */
          BwForwardBound how   = s->forward_bound == BW_FORWARD_AUTO ? BW_FORWARD_EXTRA : s->forward_bound;
          PetscBool      shell = PETSC_FALSE;
          if (s->forward_check && path->qspace && (how == BW_FORWARD_SCHUR || how == BW_FORWARD_EXTRA)) PetscCall(BwMixedRoundoffSupported(s->mx, &shell));
          if (shell) {
            PetscReal bound;
            if (how == BW_FORWARD_SCHUR) PetscCall(BwSolverForwardBoundSchur(s, fpc, (PetscBool)(set && sym), b, x, &bound));
            else PetscCall(BwSolverForwardExtra(s, fpc, b, x, &bound));
            PetscCall(PetscInfo(path->ksp, "forward estimate from the refinement %.3e, round-off %s %.3e\n", (double)s->forward_estimate, how == BW_FORWARD_SCHUR ? "bound through the factor of S^" : "estimate from a residual in double-double", (double)bound));
            s->forward_estimate = PetscMax(s->forward_estimate, bound);
          } else if (s->forward_check && (s->direct_fits || how == BW_FORWARD_WHOLE)) {
            PetscReal bound;
            PetscCall(BwSolverForwardBound(s, path, x, &bound));
            PetscCall(PetscInfo(path->ksp, "forward estimate from the refinement %.3e, round-off bound from the factor %.3e\n", (double)s->forward_estimate, (double)bound));
            s->forward_estimate = PetscMax(s->forward_estimate, bound);
          } else if (s->forward_check && s->forward_estimate >= 0 && s->condition_estimate > 0) {
            /* too large for the componentwise bound (it assembles the
             * saddle matrix): the normwise one, condition times unit
             * round-off, pessimistic but never below what round-off allows */
            PetscCall(PetscInfo(path->ksp, "forward estimate from the refinement %.3e, normwise round-off bound %.3e\n", (double)s->forward_estimate, (double)(s->condition_estimate * PETSC_MACHINE_EPSILON)));
            s->forward_estimate = PetscMax(s->forward_estimate, s->condition_estimate * PETSC_MACHINE_EPSILON);
          }
          /* At the floor the displacements are q rounded to double: a unit
           * or two in the last place of the largest, which no estimate below
           * a few eps can vouch for (the stability suite's tenon_1e-5 with
           * the reference BLAS, stopped at the floor at its fourth step: an
           * error of 2.19e-16 against an estimate of 1.86e-16) */
          if (at_floor && s->forward_estimate >= 0) s->forward_estimate = PetscMax(s->forward_estimate, 4 * PETSC_MACHINE_EPSILON);
        }
      }
    }
  }
  PetscCall(BwLogEnd(log, BW_PHASE_SOLVE));
  if (ierr) {
    PetscCall(PetscSNPrintf(reason, len, "%s raised a PETSc error: %s", path->name, BwErrorText(ierr)));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  {
    /* A Newton correction that converged or stopped at its floor:
     * Richardson's last residual, b - K x
     * with the unpreconditioned norm, is the true residual of the x it
     * returns (it stops before updating x), so the check's second product
     * with K is not needed (11 % of a small pushover's instructions) */
    PetscBool   richardson = PETSC_FALSE;
    KSPNormType nt;
    PetscCall(PetscObjectTypeCompare((PetscObject)path->ksp, KSPRICHARDSON, &richardson));
    PetscCall(KSPGetNormType(path->ksp, &nt));
    if (!s->forward_check && (kr > 0 || (kr == KSP_DIVERGED_DTOL && s->floor_stall)) && richardson && nt == KSP_NORM_UNPRECONDITIONED) {
      PetscReal rnorm, bnorm;
      PetscCall(KSPGetResidualNorm(path->ksp, &rnorm));
      PetscCall(VecNorm(b, NORM_2, &bnorm));
      s->check.residual          = bnorm > 0 ? rnorm / bnorm : rnorm;
      s->check.equilibrium       = -1;
      s->check.compatibility     = -1;
      s->check.equilibrium_error = -1;
    } else PetscCall(BwMixedCheck(s->mx, x, b, NULL, NULL, &s->check));
  }
  if (kr < 0) {
    PetscBool stalled = (pcr == PC_NOERROR && npiv == 0 && (kr == KSP_DIVERGED_ITS || kr == KSP_DIVERGED_DTOL)) ? PETSC_TRUE : PETSC_FALSE;
    /* stagnation at the round-off floor of an ill-conditioned system */
    *usable = stalled && s->check.residual <= PetscSqrtReal(s->rtol) ? PETSC_TRUE : PETSC_FALSE;
    if (stalled && s->floor_stall && !(s->check.residual <= s->rtol)) {
      PetscCall(PetscSNPrintf(reason, len, "%s stopped at the round-off floor of the residual after %" PetscInt_FMT " steps: true residual %.3e, estimated displacement error %.1e", path->name, s->iterations, (double)s->check.residual, (double)s->forward_estimate));
      if (s->residual_floor > 0) {
        char more[96];
        PetscCall(PetscSNPrintf(more, sizeof(more), " (eps |S~| |q| / |b| %.1e)", (double)s->residual_floor));
        PetscCall(PetscStrlcat(reason, more, len));
      }
    } else if (stalled && s->check.residual <= s->rtol)
      PetscCall(PetscSNPrintf(reason, len, "%s: the refinement's corrections did not settle in %" PetscInt_FMT " steps: estimated displacement error %.1e above solver.forward_rtol %.1e (true residual %.3e)", path->name, s->iterations, (double)s->forward_estimate, (double)s->forward_rtol, (double)s->check.residual));
    else
      PetscCall(PetscSNPrintf(reason, len, "%s KSP diverged (%s%s%s) after %" PetscInt_FMT " iterations, true residual %.3e", path->name, KSPConvergedReasons[kr], pcr != PC_NOERROR ? ", " : "", pcr != PC_NOERROR ? PCFailedReasons[pcr] : "", s->iterations, (double)s->check.residual));
  } else if (npiv > 0) {
    PetscCall(PetscSNPrintf(reason, len, "%s: MUMPS found %" PetscInt_FMT " null pivot%s (a singular system)", path->name, npiv, npiv > 1 ? "s" : ""));
  } else if (!(s->check.residual <= s->rtol)) {
    PetscCall(PetscSNPrintf(reason, len, "%s true residual of the full system %.3e misses solver.rtol %.3e", path->name, (double)s->check.residual, (double)s->rtol));
    *usable = s->check.residual <= PetscSqrtReal(s->rtol) ? PETSC_TRUE : PETSC_FALSE;
  } else if (s->forward_check && !(s->forward_estimate <= s->forward_rtol)) {
    /* the residual met rtol, but the factor's round-off bound says the
     * displacements may not be right to forward_rtol */
    PetscCall(PetscSNPrintf(reason, len, "%s: estimated displacement error %.1e (round-off bound of the factor, condition estimate %.1e) above solver.forward_rtol %.1e (true residual %.3e)", path->name, (double)s->forward_estimate, (double)s->condition_estimate, (double)s->forward_rtol, (double)s->check.residual));
    *usable = PETSC_TRUE;
  } else *ok = *usable = PETSC_TRUE;
  if (*ok) s->residual_floor = -1; /* met: no floor to name */
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The best usable answer so far (by the larger of its true residual and
 * its estimated forward error: an answer that met rtol with a larger error
 * is the worse one). */
typedef struct {
  Vec       x;      /* a copy, made only when another path is about to overwrite the solution */
  PetscBool in_x;   /* the best answer is the one in the solution vector itself */
  PetscBool any;
  BwCheck   check;
  BwMethod  method;
  PetscInt  its;
  PetscReal   fwd, cond;
  const char *schur;
  PetscReal   floor; /* the residual's floor where its refinement stopped there (estimates.c), else -1 */
} BwBest;

static PetscErrorCode BwSolverKeepBest(BwSolver s, BwMethod method, Vec x, BwBest *best)
{
  PetscReal now = PetscMax(s->check.residual, s->forward_estimate);

  PetscFunctionBeginUser;
  if (best->any && !(now < PetscMax(best->check.residual, best->fwd))) PetscFunctionReturn(PETSC_SUCCESS);
  (void)x;
  best->any    = PETSC_TRUE;
  best->in_x   = PETSC_TRUE;
  best->check  = s->check;
  best->method = method;
  best->its    = s->iterations;
  best->fwd    = s->forward_estimate;
  best->cond   = s->condition_estimate;
  best->schur  = s->schur_used;
  best->floor  = s->residual_floor;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Before another path overwrites x: the best answer so far saved (one
 * copy of a solution-sized vector, 0.8 KB per block at m = 16 in 2D, 2.3
 * KB at m = 8, m_b = 4 in 3D, paid only where a second path runs). */
static PetscErrorCode BwSolverSaveBest(Vec x, BwBest *best)
{
  PetscFunctionBeginUser;
  if (!best->in_x) PetscFunctionReturn(PETSC_SUCCESS);
  if (!best->x) PetscCall(VecDuplicate(x, &best->x));
  PetscCall(VecCopy(x, best->x));
  best->in_x = PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverSolve(BwSolver s, Vec b, Vec x, BwLog *log)
{
  PetscBool ok = PETSC_FALSE, usable;
  PetscInt  others = 0; /* paths run after the first */
  char      reason[512] = "";
  BwBest    best = {NULL, PETSC_FALSE, PETSC_FALSE, {0, 0, 0, 0}, BW_METHOD_FIELDSPLIT, 0, -1, -1, NULL, -1};

  PetscFunctionBeginUser;
  s->fallback           = PETSC_FALSE;
  s->fallback_reason[0] = 0;
  s->warning[0]         = 0;
  s->accuracy_met       = PETSC_TRUE;
  s->residual_floor     = -1;
  s->low_rank_ratio     = -1;
  if (s->trivial) {
    /* K = -I (stress rows only): x = -b, exactly; the displacements are
     * the prescribed ones, exactly too */
    PetscCall(VecCopy(b, x));
    PetscCall(VecScale(x, -1.0));
    s->iterations       = 0;
    s->schur_used       = "";
    s->forward_estimate = 0;
    PetscCall(BwMixedCheck(s->mx, x, b, NULL, NULL, &s->check));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  if (s->requested == BW_METHOD_CONDENSED) {
    PetscCall(BwSolverCondensed(s, b, x, log));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  if (s->requested != BW_METHOD_DIRECT) {
    s->used       = BW_METHOD_FIELDSPLIT;
    s->schur_used = !s->schur_iterative ? (s->symmetric ? "cholesky" : "lu") : s->schur == BW_SCHUR_HYPRE ? "hypre" : "gamg";
    PetscCall(BwSolverRun(s, &s->fieldsplit, b, x, log, &ok, &usable, reason, sizeof(reason)));
    /* A Newton correction (no forward check) that stalled within
     * sqrt(solver.rtol) is good enough: the next iteration measures the
     * nonlinear residual itself. Falling back to the direct path instead
     * cost a saddle-matrix factorisation per iteration (1.2 s a solve on a
     * 2000-block 3D wall whose cracked joints left S^'s factor at a
     * residual of 3e-10). */
    if (!ok && usable && !s->forward_check) ok = PETSC_TRUE;
    if (!ok) {
      if (usable) PetscCall(BwSolverKeepBest(s, BW_METHOD_FIELDSPLIT, x, &best));
      if (s->requested == BW_METHOD_AUTO) {
        s->fallback = PETSC_TRUE;
        PetscCall(PetscStrncpy(s->fallback_reason, reason, sizeof(s->fallback_reason)));
      }
    }
  }
  /* A low-rank factor that did not get there: the same path with S^'s
   * factor in full rank, the low-rank one freed first (at 1e6 blocks the
   * two would not fit together); the next solves keep the full rank. At
   * the floor of rounding q a full-rank factor stops at the same place. */
  if (!ok && s->requested == BW_METHOD_AUTO && s->low_rank && !s->floor_stall) {
    char why[512];
    PetscCall(BwSolverSaveBest(x, &best));
    PetscCall(KSPDestroy(&s->fieldsplit.ksp));
    s->low_rank       = PETSC_FALSE;
    s->low_rank_ratio = -1;
    PetscCall(BwSolverCreateFieldsplit(s, &s->fieldsplit, NULL, PETSC_FALSE));
    s->fieldsplit.ran_once = PETSC_FALSE;
    s->used                = BW_METHOD_FIELDSPLIT;
    PetscCall(PetscStrlcat(s->fallback_reason, " with S^'s factor in block low-rank form; S^ factored again in full rank", sizeof(s->fallback_reason)));
    others++;
    PetscCall(BwSolverRun(s, &s->fieldsplit, b, x, log, &ok, &usable, why, sizeof(why)));
    if (!ok && usable) PetscCall(BwSolverKeepBest(s, BW_METHOD_FIELDSPLIT, x, &best));
    if (!ok) PetscCall(PetscStrncpy(reason, why, sizeof(reason)));
  }
  /* With an iterative Schur solve first, auto falls back to the same
   * fieldsplit with S^ factored before the direct path, which above
   * BW_SCHUR_GAMG_BLOCKS blocks would not fit in memory. */
  if (!ok && s->requested == BW_METHOD_AUTO && s->schur_iterative) {
    char           why[512];
    MatSolverType  type;
    PetscCall(BwFactorPackage(s->comm, s->symmetric ? BW_FACTOR_CHOLESKY : BW_FACTOR_LU, &type));
    /* stopped at the residual's round-off floor with the displacements
     * within forward_rtol: S^ factored refines against the same residual
     * and stops at the same floor, after a factorisation that may not fit
     * in memory where CG + GAMG was chosen */
    if (type && s->floor_stall) {
      PetscCall(PetscStrlcat(reason, "; S^ was not factored: the refinement stopped at the round-off floor of the residual, where a factorisation stops too", sizeof(reason)));
      type = NULL;
    }
    if (type) {
      if (!s->cholesky.ksp) PetscCall(BwSolverCreateFieldsplit(s, &s->cholesky, "cholesky_", PETSC_TRUE));
      s->used       = BW_METHOD_FIELDSPLIT;
      s->schur_used = s->symmetric ? "cholesky" : "lu";
      PetscCall(BwSolverSaveBest(x, &best));
      others++;
      PetscCall(BwSolverRun(s, &s->cholesky, b, x, log, &ok, &usable, why, sizeof(why)));
      if (!ok && usable && !s->forward_check) ok = PETSC_TRUE; /* a Newton correction, as above */
      if (!ok && usable) PetscCall(BwSolverKeepBest(s, BW_METHOD_FIELDSPLIT, x, &best));
      if (!ok) PetscCall(PetscStrncpy(reason, why, sizeof(reason)));
    }
  }
  if (!ok && s->requested != BW_METHOD_FIELDSPLIT) {
    MatSolverType type;
    PetscCall(BwFactorPackage(s->comm, BW_FACTOR_LU_PIVOTING, &type));
    if (!s->direct_fits) PetscCall(PetscStrlcat(reason, "; the direct path was not tried: the saddle matrix of this many blocks does not fit in memory", sizeof(reason)));
    else if (!type) PetscCall(PetscStrlcat(reason, "; the direct path was not tried: this PETSc has no sparse LU with pivoting on this many ranks", sizeof(reason)));
    else {
      char why[512];
      if (!s->direct.ksp) PetscCall(BwSolverCreateDirect(s));
      else {
        /* new tangents since it was assembled: the same pattern, new values */
        PetscInt state;
        PetscCall(BwMixedGetValuesState(s->mx, &state));
        if (state != s->kaij_state) {
          Mat K;
          PetscCall(BwMixedCreateAIJ(s->mx, &K));
          PetscCall(MatCopy(K, s->Kaij, SAME_NONZERO_PATTERN));
          PetscCall(MatDestroy(&K));
          s->kaij_state = state;
        }
      }
      s->used       = BW_METHOD_DIRECT;
      s->schur_used = "";
      PetscCall(BwSolverSaveBest(x, &best));
      others++;
      PetscCall(BwSolverRun(s, &s->direct, b, x, log, &ok, &usable, why, sizeof(why)));
      if (!ok && usable) PetscCall(BwSolverKeepBest(s, BW_METHOD_DIRECT, x, &best));
      if (!ok) PetscCall(PetscStrncpy(reason, why, sizeof(reason)));
    }
  }
  if (!ok && best.any) {
    /* Every path stopped above solver.rtol at a residual that still makes
     * an answer (an ill-conditioned system's round-off floor): the best one
     * is written, and the run says so in the summary and in /solver. */
    char cond[64] = "";
    if (!best.in_x) PetscCall(VecCopy(best.x, x));
    s->check              = best.check;
    s->used               = best.method;
    s->schur_used         = best.schur;
    s->iterations         = best.its;
    s->forward_estimate   = best.fwd;
    s->condition_estimate = best.cond;
    s->accuracy_met       = PETSC_FALSE;
    s->residual_floor     = best.floor;
    if (best.cond > 0) PetscCall(PetscSNPrintf(cond, sizeof(cond), ", condition estimate %.1e", (double)best.cond));
    if (s->check.residual <= s->rtol)
      PetscCall(PetscSNPrintf(s->warning, sizeof(s->warning), "estimated displacement error %.1e misses solver.forward_rtol %.1e (true residual %.3e%s): the system is too ill-conditioned for that accuracy in double precision; the answer written is %s (%s)", (double)s->forward_estimate, (double)s->forward_rtol, (double)s->check.residual, cond, others ? "the best of the paths tried" : "that of the only path run", BwMethods[best.method]));
    else
      PetscCall(PetscSNPrintf(s->warning, sizeof(s->warning), "true residual %.3e misses solver.rtol %.1e (estimated displacement error %.1e%s): the system is too ill-conditioned for that tolerance in double precision; the answer written is %s (%s)", (double)s->check.residual, (double)s->rtol, (double)s->forward_estimate, cond, others ? "the best of the paths tried" : "that of the only path run", BwMethods[best.method]));
    if (best.floor > 0 && !(s->check.residual <= s->rtol)) {
      /* why: the residual that rounding the displacements to double leaves */
      char more[200];
      PetscCall(PetscSNPrintf(more, sizeof(more), "; rounding the displacements to double alone leaves a residual up to %.1e here, so double precision cannot be expected to meet rtol (the stresses recovered from them carry that rounding)", (double)best.floor));
      PetscCall(PetscStrlcat(s->warning, more, sizeof(s->warning)));
    }
    if (!others && s->fallback) {
      /* The first path's answer is the one written: nothing fell back
       * (/solver fallback says why the first path was abandoned). Why no
       * other path ran goes with the warning. */
      char more[sizeof(s->fallback_reason) + 64];
      PetscCall(PetscSNPrintf(more, sizeof(more), "; no other path ran: %s", reason));
      PetscCall(PetscStrlcat(s->warning, more, sizeof(s->warning)));
      s->fallback           = PETSC_FALSE;
      s->fallback_reason[0] = 0;
    }
    ok = PETSC_TRUE;
  }
  PetscCall(VecDestroy(&best.x));
  if (!ok) {
    /* no usable answer: a mechanism the static checks missed is named */
    if (s->diagnose) PetscCall(BwMixedCheckMechanism(s->mx, reason));
    SETERRQ(s->comm, PETSC_ERR_NOT_CONVERGED, "solver failed: %s%s%s%s", reason, s->fallback ? "; before it, " : "", s->fallback ? s->fallback_reason : "", s->requested == BW_METHOD_FIELDSPLIT ? " (solver.method: auto would fall back to a factorisation)" : "");
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Where MUMPS ordered the matrix it last factored on several ranks:
 * "parallel", or "rank 0", which held the matrix's whole graph for it (a
 * MUMPS built without PT-Scotch or ParMETIS, Debian's); "" on one rank,
 * with solver.reproducible, or without a MUMPS factorisation. */
static const char *BwSolverFactorAnalysis(BwSolver s)
{
  PetscMPIInt size;

  if (MPI_Comm_size(s->comm, &size) != MPI_SUCCESS || size < 2) return "";
  return s->mumps_analysis == 2 ? "parallel" : s->mumps_analysis == 1 ? "rank 0" : "";
}

PetscErrorCode BwSolverReport(BwSolver s, BwReport r)
{
  PetscFunctionBeginUser;
  PetscCall(BwReportString(r, "method_requested", BwMethods[s->requested]));
  /* "none": every block dof prescribed, no system solved */
  PetscCall(BwReportString(r, "method_used", s->trivial ? "none" : BwMethods[s->used]));
  PetscCall(BwReportInt(r, "setups", s->setups));
  PetscCall(BwReportString(r, "schur_solve", s->used == BW_METHOD_FIELDSPLIT && s->schur_used ? s->schur_used : ""));
  {
    PetscInt groups;
    char     desc[128];
    PetscCall(BwMixedGetSchurGroups(s->mx, &groups, desc, sizeof(desc)));
    PetscCall(BwReportInt(r, "schur_groups", groups));
    PetscCall(BwReportString(r, "schur_group_dofs", desc));
  }
  PetscCall(BwReportString(r, "factor_analysis", BwSolverFactorAnalysis(s)));
  PetscCall(BwReportReal(r, "factor_low_rank_ratio", s->low_rank_ratio));
  PetscCall(BwReportInt(r, "fallback", s->fallback));
  PetscCall(BwReportString(r, "fallback_reason", s->fallback_reason));
  PetscCall(BwReportInt(r, "iterations", s->iterations));
  PetscCall(BwReportInt(r, "accuracy_met", s->accuracy_met));
  PetscCall(BwReportString(r, "warning", s->warning));
  PetscCall(BwReportReal(r, "rtol", s->rtol));
  PetscCall(BwReportReal(r, "residual", s->check.residual));
  PetscCall(BwReportReal(r, "residual_floor", s->residual_floor));
  PetscCall(BwReportReal(r, "residual_equilibrium", s->check.equilibrium));
  PetscCall(BwReportReal(r, "residual_compatibility", s->check.compatibility));
  PetscCall(BwReportReal(r, "forward_rtol", s->forward_rtol));
  PetscCall(BwReportReal(r, "forward_error_estimate", s->forward_estimate));
  PetscCall(BwReportReal(r, "condition_estimate", s->condition_estimate));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverView(BwSolver s, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  if (s->trivial) PetscCall(PetscViewerASCIIPrintf(viewer, "  method: none (requested %s): every block dof is prescribed, the stresses follow from the prescribed motions\n", BwMethods[s->requested]));
  else PetscCall(PetscViewerASCIIPrintf(viewer, "  method: %s (requested %s), iterations %" PetscInt_FMT "%s%s\n", BwMethods[s->used], BwMethods[s->requested], s->iterations, s->fallback ? ", fallback: " : "", s->fallback_reason));
  {
    PetscInt groups;
    char     desc[128];
    PetscCall(BwMixedGetSchurGroups(s->mx, &groups, desc, sizeof(desc)));
    if (groups > 1) PetscCall(PetscViewerASCIIPrintf(viewer, "  S^ splits into %" PetscInt_FMT " independent groups of dofs (%s)\n", groups, desc));
    if (s->schur_choice[0]) PetscCall(PetscViewerASCIIPrintf(viewer, "  auto's Schur solve: %s\n", s->schur_choice));
  }
  {
    const char *where = BwSolverFactorAnalysis(s);
    if (!strcmp(where, "rank 0")) PetscCall(PetscViewerASCIIPrintf(viewer, "  MUMPS ordered the factored matrix on rank 0, which held its whole graph (this MUMPS has neither PT-Scotch nor ParMETIS: docs/cluster.md)\n"));
    else if (where[0]) PetscCall(PetscViewerASCIIPrintf(viewer, "  MUMPS ordered the factored matrix in parallel\n"));
  }
  if (s->low_rank_ratio > 0) PetscCall(PetscViewerASCIIPrintf(viewer, "  S^'s factor in block low-rank form (MUMPS BLR): %.0f %% of the full-rank factor's entries\n", (double)(100 * s->low_rank_ratio)));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  residual %.3e (equilibrium %.3e, compatibility %.3e; rtol %.1e)\n", (double)s->check.residual, (double)s->check.equilibrium, (double)s->check.compatibility, (double)s->rtol));
  if (s->forward_estimate >= 0 || s->condition_estimate > 0) {
    PetscCall(PetscViewerASCIIPrintf(viewer, "  estimated displacement error "));
    if (s->forward_estimate >= 0) PetscCall(PetscViewerASCIIPrintf(viewer, "%.1e (forward_rtol %.1e)", (double)s->forward_estimate, (double)s->forward_rtol));
    else PetscCall(PetscViewerASCIIPrintf(viewer, "not estimated"));
    if (s->condition_estimate > 0) PetscCall(PetscViewerASCIIPrintf(viewer, "; condition estimate %.1e", (double)s->condition_estimate));
    PetscCall(PetscViewerASCIIPrintf(viewer, "\n"));
  }
  if (!s->accuracy_met) PetscCall(PetscViewerASCIIPrintf(viewer, "  WARNING: %s\n", s->warning));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverGetOptionPrefixes(PetscInt *n, const char *const **prefixes)
{
  static const char *const all[] = {"ksp_", "pc_", "mat_", "matptap_", "schur_", "direct_", "condensed_", "cholesky_", "mechanism_", "mixed_", "partition_"};

  PetscFunctionBeginUser;
  *n        = (PetscInt)PETSC_STATIC_ARRAY_LENGTH(all);
  *prefixes = all;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverGetIdlePrefixes(BwSolver s, PetscInt *n, const char *prefixes[8])
{
  PetscFunctionBeginUser;
  *n = 0;
  if (!s->fieldsplit.ran) {
    prefixes[(*n)++] = "ksp_";
    prefixes[(*n)++] = "pc_";
    prefixes[(*n)++] = "schur_";
  }
  if (!s->direct.ran) prefixes[(*n)++] = "direct_";
  if (!s->condensed.ran) prefixes[(*n)++] = "condensed_";
  if (!s->cholesky.ran) prefixes[(*n)++] = "cholesky_";
  PetscFunctionReturn(PETSC_SUCCESS);
}
