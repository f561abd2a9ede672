/* BwSolver: fieldsplit Schur, direct MUMPS, and the automatic fallback
 * between them (see solver.h for the structure of each path). */
#include <petscksp.h>
#include "solver/solver.h"
#include "util/compat.h"

#define BW_SCHUR_GAMG_BLOCKS 200000
/* Hager-Higham iterations (each a pair of solves with the factor) */
#ifndef BW_CONDITION_ITERATIONS
#define BW_CONDITION_ITERATIONS 4
#endif

const char *const BwMethods[] = {"auto", "fieldsplit", "direct", "condensed", "BwMethod", "BW_METHOD_", NULL};

PetscErrorCode BwSolverCreate(MPI_Comm comm, BwSolver *solver)
{
  PetscFunctionBeginUser;
  PetscCall(PetscNew(solver));
  (*solver)->comm      = comm;
  (*solver)->requested = BW_METHOD_AUTO;
  (*solver)->rtol      = 1e-10;
  (*solver)->storage   = BW_STORAGE_SHELL;
  (*solver)->forward_rtol       = -1; /* = rtol unless set */
  (*solver)->forward_estimate   = -1;
  (*solver)->condition_estimate = -1;
  (*solver)->condition_when     = 0; /* auto */
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverDestroy(BwSolver *solver)
{
  PetscFunctionBeginUser;
  if (!*solver) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(KSPDestroy(&(*solver)->fieldsplit));
  PetscCall(KSPDestroy(&(*solver)->direct));
  PetscCall(KSPDestroy(&(*solver)->condensed));
  PetscCall(KSPDestroy(&(*solver)->cholesky));
  PetscCall(VecDestroy(&(*solver)->fw_weight));
  PetscCall(VecDestroy(&(*solver)->fw_prev));
  PetscCall(VecDestroy(&(*solver)->fw_work));
  PetscCall(PetscFree(*solver));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Insert `name value` unless the user already set `name`. */
static PetscErrorCode BwSolverDefault(BwSolver s, const char name[], const char value[])
{
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasName(NULL, NULL, name, &set));
  if (set) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCheck(s->ndefaults < 24, PETSC_COMM_SELF, PETSC_ERR_PLIB, "too many solver defaults");
  PetscCall(PetscOptionsSetValue(NULL, name, value));
  PetscCall(PetscStrncpy(s->defaults[s->ndefaults++], name, sizeof(s->defaults[0])));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverSetFromOptions(BwSolver s, BwScene scene)
{
  PetscInt                 method = s->requested, schur = 0, storage = s->storage;
  PetscBool                fset;
  static const char *const schurs[] = {"auto", "cholesky", "gamg", "BwSchur", "BW_SCHUR_", NULL};

  PetscFunctionBeginUser;
  PetscCall(BwSceneHelpSection(scene, "Solver (scene key solver.*)"));
  PetscCall(BwSceneRequireMapping(scene, "-solver", "method, rtol, ..."));
  PetscCall(BwSceneEnum(scene, "-solver_method", "auto (fieldsplit, MUMPS on failure), fieldsplit, direct, or condensed (benchmark reference)", 4, BwMethods, &method, NULL));
  PetscCall(BwSceneReal(scene, "-solver_rtol", "Required relative true residual of the full mixed system (scaled)", &s->rtol, NULL));
  PetscCall(BwSceneEnum(scene, "-solver_schur", "Schur complement solve of fieldsplit: auto (cholesky below 2e5 blocks, gamg above), cholesky (MUMPS) or gamg (CG+GAMG)", 3, schurs, &schur, NULL));
  PetscCall(BwSceneReal(scene, "-solver_forward_rtol", "Required estimated relative error of the displacements (max norm, rotations times the assembly's size), from the last correction of the refinement on the full system; default solver.rtol", &s->forward_rtol, &fset));
  {
    static const char *const when[] = {"auto", "always", "never"};
    PetscInt                 w      = s->condition_when;
    PetscCall(BwSceneEnum(scene, "-solver_condition_estimate", "1-norm condition estimate of the factored operator (S^, or K~ on the direct path; about five solves with the factor): auto (when the refinement needed more than two steps or missed a tolerance), always, never", 3, when, &w, NULL));
    s->condition_when = w;
  }
  PetscCall(BwSceneEnum(scene, "-solver_storage", "Saddle operator storage: shell (D^ by its structure), nest (D^ assembled) or aij (one assembled matrix)", 3, BwStorages, &storage, NULL));
  s->storage = (BwStorage)storage;
  if (!(s->rtol > 0 && s->rtol < 1)) PetscCall(BwSceneError(scene, "-solver_rtol", "must be in (0, 1), got %g", (double)s->rtol));
  if (!fset) s->forward_rtol = s->rtol;
  if (!(s->forward_rtol > 0 && s->forward_rtol <= 1)) PetscCall(BwSceneError(scene, "-solver_forward_rtol", "must be in (0, 1], got %g", (double)s->forward_rtol));
  s->requested     = (BwMethod)method;
  s->schur_choice  = schur;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The defaults that depend on the assembly's size, once it is known. */
PetscErrorCode BwSolverSetSize(BwSolver s, PetscInt nblocks)
{
  PetscFunctionBeginUser;
  /* By size: MUMPS Cholesky of S^ is exact and robust to stiffness
   * contrast, and as fast as CG + GAMG up to ~1e5 blocks (4.5 s vs 4.1 s at
   * 1e5); above, its fill grows faster than N (19 s vs 12 s at 2.5e5, and
   * 13.5 KB vs 17.5 KB per block), while CG + GAMG stays near linear. */
  s->schur_gamg = s->schur_choice == 2 || (s->schur_choice == 0 && nblocks >= BW_SCHUR_GAMG_BLOCKS) ? PETSC_TRUE : PETSC_FALSE;

  /* Sub-solvers that PCFIELDSPLIT creates take their defaults from the
   * database; the direct path's MUMPS gets a larger work-space margin,
   * since its estimate for saddle-point matrices with delayed pivots is too
   * small (INFOG(1) = -9 seen with the default 20 %). */
  if (s->requested == BW_METHOD_AUTO || s->requested == BW_METHOD_FIELDSPLIT) {
    PetscCall(BwSolverDefault(s, "-fieldsplit_r_ksp_type", "preonly"));
    /* A00 = -I is its own inverse: applying the matrix is the exact solve,
     * without the diagonal Jacobi would extract (0.77 KB per block at m = 16;
     * measured at 1e6 blocks: 2.2-3.5 s of the lower solve became 0.1-0.3 s) */
    PetscCall(BwSolverDefault(s, "-fieldsplit_r_pc_type", "mat"));
    if (s->schur_gamg) {
      PetscCall(BwSolverDefault(s, "-fieldsplit_q_ksp_type", "cg"));
      PetscCall(BwSolverDefault(s, "-fieldsplit_q_pc_type", "gamg"));
      /* 1e-5: three outer steps meet rtol 1e-10 and the forward estimate
       * (9 + 17 + 16 CG iterations at 1e5 blocks); 1e-4 needed four
       * (6 + 14 + 14 + 14), 1e-6 three with more iterations (12 + 20 + 18) */
      PetscCall(BwSolverDefault(s, "-fieldsplit_q_ksp_rtol", "1e-5"));
    } else {
      PetscCall(BwSolverDefault(s, "-fieldsplit_q_ksp_type", "preonly"));
      PetscCall(BwSolverDefault(s, "-fieldsplit_q_pc_type", "cholesky"));
      PetscCall(BwSolverDefault(s, "-fieldsplit_q_pc_factor_mat_solver_type", "mumps"));
      /* null-pivot detection: a singular S^ is reported, not factored into garbage */
      PetscCall(BwSolverDefault(s, "-fieldsplit_q_mat_mumps_icntl_24", "1"));
    }
  }
  /* With CG + GAMG first, auto falls back to the same fieldsplit with the
   * Schur complement factored by MUMPS (prefix cholesky_) before the direct
   * path, which above BW_SCHUR_GAMG_BLOCKS blocks would not fit in memory. */
  if (s->requested == BW_METHOD_AUTO && s->schur_gamg) {
    PetscCall(BwSolverDefault(s, "-cholesky_fieldsplit_r_ksp_type", "preonly"));
    PetscCall(BwSolverDefault(s, "-cholesky_fieldsplit_r_pc_type", "mat"));
    PetscCall(BwSolverDefault(s, "-cholesky_fieldsplit_q_ksp_type", "preonly"));
    PetscCall(BwSolverDefault(s, "-cholesky_fieldsplit_q_pc_type", "cholesky"));
    PetscCall(BwSolverDefault(s, "-cholesky_fieldsplit_q_pc_factor_mat_solver_type", "mumps"));
    PetscCall(BwSolverDefault(s, "-cholesky_fieldsplit_q_mat_mumps_icntl_24", "1"));
  }
  s->direct_fits = nblocks < BW_SCHUR_GAMG_BLOCKS || s->requested == BW_METHOD_DIRECT ? PETSC_TRUE : PETSC_FALSE;
  if (s->requested == BW_METHOD_AUTO || s->requested == BW_METHOD_DIRECT) {
    PetscCall(BwSolverDefault(s, "-direct_mat_mumps_icntl_14", "100"));
    PetscCall(BwSolverDefault(s, "-direct_mat_mumps_icntl_24", "1"));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rigid motions of the whole assembly in the scaled dofs: the near-null
 * space GAMG needs to coarsen a stiffness that supports make definite. */
static PetscErrorCode BwSolverNearNullSpace(BwMixed mx)
{
  Vec          v[3];
  MatNullSpace nsp;
  BwGeometry   geom = mx->geom;
  PetscReal    x0[2] = {0, 0};

  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < geom->nblocks; b++)
    for (PetscInt c = 0; c < 2; c++) x0[c] += geom->centroid[2 * b + c] / geom->nblocks;
  for (PetscInt r = 0; r < 3; r++) {
    PetscCall(MatCreateVecs(mx->S, &v[r], NULL));
    for (PetscInt e = 0; e < mx->nown_blocks; e++) {
      PetscInt  b = mx->own_blocks[e];
      PetscReal u[3];
      if (r < 2) {
        u[0] = r == 0;
        u[1] = r == 1;
        u[2] = 0;
      } else {
        u[0] = -(geom->centroid[2 * b + 1] - x0[1]);
        u[1] = geom->centroid[2 * b] - x0[0];
        u[2] = 1;
      }
      const PetscReal *sc;
      PetscCall(BwMixedQScale(mx, b, &sc));
      for (PetscInt c = 0; c < 3; c++) {
        PetscInt row = mx->sdof[3 * b + c];
        /* q~ = diag(S)^{1/2} q */
        if (row >= 0) PetscCall(VecSetValue(v[r], row, u[c] / sc[c], INSERT_VALUES));
      }
    }
    PetscCall(VecAssemblyBegin(v[r]));
    PetscCall(VecAssemblyEnd(v[r]));
  }
  /* MatNullSpaceCreate wants orthonormal vectors */
  PetscCall(VecNormalize(v[0], NULL));
  for (PetscInt r = 1; r < 3; r++) {
    PetscScalar dots[2];
    PetscCall(VecMDot(v[r], r, v, dots));
    for (PetscInt j = 0; j < r; j++) dots[j] = -dots[j];
    PetscCall(VecMAXPY(v[r], r, dots, v));
    PetscCall(VecNormalize(v[r], NULL));
  }
  PetscCall(MatNullSpaceCreate(mx->comm, PETSC_FALSE, 3, v, &nsp));
  PetscCall(MatSetNearNullSpace(mx->S, nsp));
  PetscCall(MatNullSpaceDestroy(&nsp));
  for (PetscInt r = 0; r < 3; r++) PetscCall(VecDestroy(&v[r]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Forward error of the displacements, estimated from the refinement.
 *
 * A residual that meets rtol does not bound the error once the system is
 * ill-conditioned: on walls whose joints differ by 1e6..1e9 the first step
 * (the condensed solve, whose assembled S^ adds soft joints to stiff ones)
 * met rtol with displacements wrong by 1e-7 (docs/accuracy.md). Each
 * Richardson step is a step of iterative refinement on the full mixed
 * system, and its correction x_k - x_{k-1} measures the error x_{k-1} had:
 *   it = 1: nothing known yet (the correction is x_1 itself);
 *   it = 2: the correction, an upper estimate of x_2's error;
 *   it > 2: the correction times rho / (1 - rho), rho the ratio of the last
 *           two corrections (linear convergence), capped at the correction.
 * At the round-off floor of an ill-conditioned system the corrections stop
 * shrinking (rho ~ 1) and the estimate stays at the error that remains. The
 * norm is the one the stability suite measures with: max norm of the
 * physical displacements, rotations times the assembly's diagonal, relative
 * to the largest. Only the q part is kept (3 values per block): a copy of
 * the stresses would cost 2m values per interface. */
static PetscErrorCode BwSolverForwardSetUp(BwSolver s, BwMixed mx)
{
  BwGeometry geom = mx->geom;
  PetscReal  lo[2] = {PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[2] = {PETSC_MIN_REAL, PETSC_MIN_REAL}, size;

  PetscFunctionBeginUser;
  s->mx = mx;
  if (s->fw_weight) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt v = 0; v < geom->nvertices; v++)
    for (PetscInt c = 0; c < 2; c++) {
      lo[c] = PetscMin(lo[c], geom->vertices[2 * v + c]);
      hi[c] = PetscMax(hi[c], geom->vertices[2 * v + c]);
    }
  size = PetscSqrtReal(PetscSqr(hi[0] - lo[0]) + PetscSqr(hi[1] - lo[1]));
  PetscCall(MatCreateVecs(mx->S, &s->fw_weight, NULL));
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt         b = mx->own_blocks[e];
    const PetscReal *sc;
    PetscCall(BwMixedQScale(mx, b, &sc));
    for (PetscInt c = 0; c < 3; c++) {
      PetscInt row = mx->sdof[3 * b + c];
      /* q = diag(S)^-1/2 q~ */
      if (row >= 0) PetscCall(VecSetValue(s->fw_weight, row, sc[c] * (c == 2 ? size : 1), INSERT_VALUES));
      else s->fw_prescribed = PetscMax(s->fw_prescribed, PetscAbsReal(mx->model->value[3 * b + c]) * (c == 2 ? size : 1));
    }
  }
  PetscCall(VecAssemblyBegin(s->fw_weight));
  PetscCall(VecAssemblyEnd(s->fw_weight));
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &s->fw_prescribed, 1, MPIU_REAL, MPIU_MAX, mx->comm));
  PetscCall(VecDuplicate(s->fw_weight, &s->fw_prev));
  PetscCall(VecDuplicate(s->fw_weight, &s->fw_work));
  PetscFunctionReturn(PETSC_SUCCESS);
}

typedef struct {
  BwSolver s;
  void    *dflt; /* KSPConvergedDefault's context */
} BwConvergedCtx;

/* PETSc 3.18's destroy signature (void *); KSPConvergedDefaultDestroy frees its own context. */
static PetscErrorCode BwConvergedCtxDestroy(void *ctx)
{
  BwConvergedCtx *c = (BwConvergedCtx *)ctx;

  PetscFunctionBeginUser;
  PetscCall(KSPConvergedDefaultDestroy(c->dflt));
  PetscCall(PetscFree(c));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The residual test of PETSc (rtol on the true residual), and then the
 * forward estimate must meet solver.forward_rtol: a step is added while it
 * does not, up to the KSP's iteration limit. */
static PetscErrorCode BwSolverConverged(KSP ksp, PetscInt it, PetscReal rnorm, KSPConvergedReason *reason, void *ctx)
{
  BwConvergedCtx *c  = (BwConvergedCtx *)ctx;
  BwSolver        s  = c->s;
  BwMixed         mx = s->mx;
  Vec             x, xq;
  PetscReal       dn, qn, rel, est;

  PetscFunctionBeginUser;
  PetscCall(KSPConvergedDefault(ksp, it, rnorm, reason, c->dflt));
  if (it == 0) {
    PetscCall(VecZeroEntries(s->fw_prev)); /* x_0 = 0 */
    s->fw_last          = -1;
    s->fw_it            = 0;
    s->forward_estimate = rnorm == 0 ? 0 : PETSC_INFINITY;
  } else if (it != s->fw_it) {
    PetscCall(KSPGetSolution(ksp, &x));
    PetscCall(VecGetSubVector(x, mx->isq, &xq));
    PetscCall(VecWAXPY(s->fw_work, -1.0, s->fw_prev, xq));
    PetscCall(VecPointwiseMult(s->fw_work, s->fw_work, s->fw_weight));
    PetscCall(VecNorm(s->fw_work, NORM_INFINITY, &dn));
    PetscCall(VecCopy(xq, s->fw_prev));
    PetscCall(VecPointwiseMult(s->fw_work, xq, s->fw_weight));
    PetscCall(VecNorm(s->fw_work, NORM_INFINITY, &qn));
    PetscCall(VecRestoreSubVector(x, mx->isq, &xq));
    /* relative to the whole displacement field, prescribed values included:
     * where loads vanish and only prescribed dofs move, the free dofs may be
     * zero up to round-off (a relative correction of round-off to round-off
     * read 7.0 on two blocks) */
    qn  = PetscMax(qn, s->fw_prescribed);
    rel = qn > 0 ? dn / qn : (dn > 0 ? PETSC_INFINITY : 0);
    if (it == 1) est = rel == 0 ? 0 : PETSC_INFINITY;
    else if (it == 2 || !(s->fw_last > 0)) est = rel;
    else {
      PetscReal rho = rel / s->fw_last;
      est           = rho < 0.5 ? rel * rho / (1 - rho) : rel;
    }
    PetscCall(PetscInfo(ksp, "step %" PetscInt_FMT ": displacement correction %.3e (relative), forward estimate %.3e\n", it, (double)rel, (double)est));
    s->fw_last          = rel;
    s->fw_it            = it;
    s->forward_estimate = est;
  }
  if (*reason > 0 && !(s->forward_estimate <= s->forward_rtol)) *reason = KSP_CONVERGED_ITERATING;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwSolverSetConvergenceTest(BwSolver s, KSP ksp)
{
  BwConvergedCtx *c;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&c));
  c->s = s;
  PetscCall(KSPConvergedDefaultCreate(&c->dflt));
  PetscCall(KSPSetConvergenceTest(ksp, BwSolverConverged, c, BwConvergedCtxDestroy));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 1-norm condition number of a symmetric A from its factor (pc applies
 * A^-1): Hager's estimator as refined by Higham (LAPACK's xLACN2), at most
 * four pairs of solves, with Higham's alternating vector as a second guess.
 * The estimate is a lower bound, in practice within a factor 3. */
static PetscErrorCode BwSolverConditionEstimate(PC pc, Mat A, PetscReal *cond)
{
  Vec       x, y, z;
  PetscInt  N, lo, hi, j;
  PetscReal anorm, est = 0, ynorm, zmax, alt;

  PetscFunctionBeginUser;
  PetscCall(MatCreateVecs(A, &x, &y));
  PetscCall(VecDuplicate(x, &z));
  PetscCall(VecGetSize(x, &N));
  PetscCall(VecGetOwnershipRange(x, &lo, &hi));
  PetscCall(MatNorm(A, NORM_1, &anorm));
  PetscCall(VecSet(x, 1.0 / N));
  for (PetscInt k = 0; k < BW_CONDITION_ITERATIONS; k++) {
    PetscScalar *a, ztx;
    PetscCall(PCApply(pc, x, y));
    PetscCall(VecNorm(y, NORM_1, &ynorm));
    if (k > 0 && ynorm <= est) break;
    est = ynorm;
    PetscCall(VecGetArray(y, &a));
    for (PetscInt i = 0; i < hi - lo; i++) a[i] = PetscRealPart(a[i]) >= 0 ? 1.0 : -1.0;
    PetscCall(VecRestoreArray(y, &a));
    PetscCall(PCApply(pc, y, z)); /* A symmetric: A^-T = A^-1 */
    PetscCall(VecDot(z, x, &ztx));
    PetscCall(VecAbs(z));
    PetscCall(VecMax(z, &j, &zmax));
    if (k > 0 && zmax <= PetscRealPart(ztx)) break;
    PetscCall(VecZeroEntries(x));
    if (j >= lo && j < hi) PetscCall(VecSetValue(x, j, 1.0, INSERT_VALUES));
    PetscCall(VecAssemblyBegin(x));
    PetscCall(VecAssemblyEnd(x));
  }
  {
    PetscScalar *a;
    PetscCall(VecGetArray(x, &a));
    for (PetscInt i = lo; i < hi; i++) a[i - lo] = (i % 2 ? -1.0 : 1.0) * (1.0 + (N > 1 ? (PetscReal)i / (N - 1) : 0));
    PetscCall(VecRestoreArray(x, &a));
    PetscCall(PCApply(pc, x, y));
    PetscCall(VecNorm(y, NORM_1, &alt));
    est = PetscMax(est, 2 * alt / (3.0 * N));
  }
  *cond = anorm * est;
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&y));
  PetscCall(VecDestroy(&z));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The factor a path used (the Schur complement's on fieldsplit, the whole
 * system's on direct) and the matrix it factors; NULL when the path
 * factored nothing (CG + GAMG). */
static PetscErrorCode BwSolverGetFactorPC(KSP ksp, PC *fpc, Mat *A)
{
  PC        pc;
  PetscBool fs, factor;

  PetscFunctionBeginUser;
  *fpc = NULL;
  *A   = NULL;
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCFIELDSPLIT, &fs));
  if (fs) {
    KSP     *sub;
    PetscInt n;
    PetscCall(PCFieldSplitSchurGetSubKSP(pc, &n, &sub));
    PetscCall(KSPGetPC(sub[1], &pc));
    PetscCall(PetscFree(sub));
  }
  PetscCall(PetscObjectTypeCompareAny((PetscObject)pc, &factor, PCLU, PCCHOLESKY, ""));
  if (!factor) PetscFunctionReturn(PETSC_SUCCESS);
  *fpc = pc;
  PetscCall(PCGetOperators(pc, A, NULL));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwSolverSetUpFieldsplit(BwSolver s, BwMixed mx, KSP *kspp, const char prefix[], PetscBool gamg)
{
  PC  pc;
  KSP ksp;

  PetscFunctionBeginUser;
  PetscCall(KSPCreate(s->comm, kspp));
  ksp = *kspp;
  if (prefix) PetscCall(KSPSetOptionsPrefix(ksp, prefix));
  PetscCall(KSPSetOperators(ksp, mx->K, mx->K));
  /* Richardson on the unpreconditioned (true) residual: with the Schur
   * complement factored the preconditioner is the exact inverse up to
   * round-off and one step converges; with CG + GAMG to 1e-4 each step
   * gains about four digits (three steps to 1e-11 on a 1.6e5-block wall).
   * It keeps two work vectors, where FGMRES keeps two per iteration: each
   * holds 2m stresses per interface (0.8 KB per block at m = 16), and
   * FGMRES(5) took 24 KB per block where Richardson takes 13 KB. */
  PetscCall(KSPSetType(ksp, KSPRICHARDSON));
  PetscCall(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED));
  PetscCall(KSPSetTolerances(ksp, s->rtol, 0.0, PETSC_DEFAULT, gamg ? 30 : 5));
  PetscCall(KSPGetPC(ksp, &pc));
  /* The type first: PCFieldSplitSetIS does nothing on another PC type. */
  PetscCall(PCSetType(pc, PCFIELDSPLIT));
  PetscCall(PCFieldSplitSetIS(pc, "r", mx->isr));
  PetscCall(PCFieldSplitSetIS(pc, "q", mx->isq));
  PetscCall(PCFieldSplitSetType(pc, PC_COMPOSITE_SCHUR));
  PetscCall(PCFieldSplitSetSchurFactType(pc, PC_FIELDSPLIT_SCHUR_FACT_FULL));
  PetscCall(PCFieldSplitSetSchurPre(pc, PC_FIELDSPLIT_SCHUR_PRE_USER, mx->S));
  if (gamg) PetscCall(BwSolverNearNullSpace(mx));
  PetscCall(KSPSetFromOptions(ksp));
  PetscCall(BwSolverSetConvergenceTest(s, ksp));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwSolverSetUpDirect(BwSolver s, BwMixed mx)
{
  PC  pc;
  Mat aij;

  PetscFunctionBeginUser;
  PetscCall(KSPCreate(s->comm, &s->direct));
  PetscCall(KSPSetOptionsPrefix(s->direct, "direct_"));
  /* MUMPS factors an assembled matrix: the nested operator is converted */
  PetscCall(BwMixedGetAIJ(mx, &aij));
  PetscCall(KSPSetOperators(s->direct, aij, aij));
  PetscCall(MatDestroy(&aij));
  /* Richardson on the unpreconditioned residual around the LU factors is
   * iterative refinement on the full system: one step when the factors are
   * accurate, a few more when pivoting was delayed. */
  PetscCall(KSPSetType(s->direct, KSPRICHARDSON));
  PetscCall(KSPSetNormType(s->direct, KSP_NORM_UNPRECONDITIONED));
  PetscCall(KSPSetTolerances(s->direct, s->rtol, 0.0, PETSC_DEFAULT, 5));
  PetscCall(KSPGetPC(s->direct, &pc));
  PetscCall(PCSetType(pc, PCLU));
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  PetscCall(KSPSetFromOptions(s->direct));
  PetscCall(BwSolverSetConvergenceTest(s, s->direct));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The Schur complement's own operator is D^T (-I)^-1 D^, applied matrix-free
 * through two products with D^ (2m rows per interface); the assembled S^
 * equals it exactly (the (r,r) block is diagonal), with 3 rows per block.
 * An iterative Schur solve (CG + GAMG) therefore iterates on S^ itself:
 * measured on a 5e4-block wall, 13 s of matrix-free products became 0.3 s.
 * A factored Schur solve (preonly) never applies the operator. */
static PetscErrorCode BwSolverSchurOperator(KSP ksp, BwMixed mx)
{
  PC       pc;
  KSP     *sub;
  PetscInt n;

  PetscFunctionBeginUser;
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCFieldSplitSchurGetSubKSP(pc, &n, &sub));
  PetscCall(KSPSetOperators(sub[1], mx->S, mx->S));
  PetscCall(PetscFree(sub));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Null pivots MUMPS found (INFOG(28)) in the factorisation a path used; 0
 * when the path factored nothing with MUMPS. */
static PetscErrorCode BwSolverNullPivots(KSP ksp, PetscInt *npiv)
{
  PC        pc;
  Mat       A, F;
  PetscBool mumps = PETSC_FALSE;

  PetscFunctionBeginUser;
  *npiv = 0;
  PetscCall(BwSolverGetFactorPC(ksp, &pc, &A));
  if (!pc) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PCFactorGetMatrix(pc, &F));
  {
    MatSolverType type;
    PetscCall(MatFactorGetSolverType(F, &type));
    PetscCall(PetscStrcmp(type, MATSOLVERMUMPS, &mumps));
  }
  if (mumps) {
    PetscInt v;
    PetscCall(MatMumpsGetInfog(F, 28, &v));
    *npiv = v;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Runs one path. A PETSc error inside the solver (a factorisation that
 * fails, say) is a failed path, not a failed run: its code is returned in
 * *failed together with the reason, and the caller decides. */
/* *ok: the path met solver.rtol. *usable: it did not (or did) but its answer
 * is a real one: no PETSc error, no failed factorisation, no null pivot, and
 * a finite true residual of at most sqrt(solver.rtol), the most a run may
 * miss its target by and still write a result (with a warning). */
static PetscErrorCode BwSolverRun(BwSolver s, BwMixed mx, BwLog *log, KSP ksp, const char name[], PetscBool *ok, PetscBool *usable, char reason[], size_t len)
{
  PetscErrorCode     ierr;
  KSPConvergedReason kr  = KSP_CONVERGED_ITERATING;
  PC                 pc;
  PCFailedReason     pcr  = PC_NOERROR;
  PetscInt           npiv = 0;

  PetscFunctionBeginUser;
  *ok                   = PETSC_FALSE;
  *usable               = PETSC_FALSE;
  s->forward_estimate   = -1; /* not estimated unless the convergence test runs */
  s->condition_estimate = -1;
  PetscCall(VecZeroEntries(mx->x));
  PetscCall(BwLogBegin(log, BW_PHASE_SETUP));
  ierr = KSPSetUp(ksp);
  if (!ierr && (ksp == s->fieldsplit || ksp == s->cholesky)) ierr = BwSolverSchurOperator(ksp, mx);
  PetscCall(BwLogEnd(log, BW_PHASE_SETUP));
  PetscCall(BwLogBegin(log, BW_PHASE_SOLVE));
  if (!ierr) ierr = KSPSolve(ksp, mx->b, mx->x);
  if (!ierr) {
    PetscCall(KSPGetConvergedReason(ksp, &kr));
    PetscCall(KSPGetIterationNumber(ksp, &s->iterations));
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCGetFailedReason(pc, &pcr));
    if (pcr == PC_NOERROR) PetscCall(BwSolverNullPivots(ksp, &npiv));
    /* The condition of what was factored, while the factor is there: a few
     * solves with it, and the one number that says how far a small residual
     * can be from a small error. Not on a failed or singular factor. In
     * auto, only where the refinement showed trouble (more than two steps,
     * or a stop at the step limit): on an ordinary wall it would cost 0.6 s
     * of 4.2 s at 1e5 blocks and say nothing the forward estimate does not. */
    if (s->condition_when == 1 || (s->condition_when == 0 && (s->iterations > 2 || kr <= 0))) {
      if (pcr == PC_NOERROR && npiv == 0 && (kr > 0 || kr == KSP_DIVERGED_ITS)) {
        PC  fpc;
        Mat A;
        PetscCall(BwSolverGetFactorPC(ksp, &fpc, &A));
        if (fpc) PetscCall(BwSolverConditionEstimate(fpc, A, &s->condition_estimate));
      }
    }
  }
  PetscCall(BwLogEnd(log, BW_PHASE_SOLVE));
  if (ierr) {
    const char *text;
    PetscCall(PetscErrorMessage(ierr, NULL, (char **)&text));
    PetscCall(PetscSNPrintf(reason, len, "%s raised a PETSc error: %s", name, text ? text : "unknown"));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(BwMixedCheck(mx, mx->x, NULL, &s->check));
  if (kr < 0) {
    PetscBool stalled = (pcr == PC_NOERROR && npiv == 0 && (kr == KSP_DIVERGED_ITS || kr == KSP_DIVERGED_DTOL)) ? PETSC_TRUE : PETSC_FALSE;
    /* stagnation at the round-off floor of an ill-conditioned system */
    *usable = stalled && s->check.residual <= PetscSqrtReal(s->rtol) ? PETSC_TRUE : PETSC_FALSE;
    if (stalled && s->check.residual <= s->rtol)
      PetscCall(PetscSNPrintf(reason, len, "%s: the refinement's corrections did not settle in %" PetscInt_FMT " steps: estimated displacement error %.1e above solver.forward_rtol %.1e (true residual %.3e)", name, s->iterations, (double)s->forward_estimate, (double)s->forward_rtol, (double)s->check.residual));
    else
      PetscCall(PetscSNPrintf(reason, len, "%s KSP diverged (%s%s%s) after %" PetscInt_FMT " iterations, true residual %.3e", name, KSPConvergedReasons[kr], pcr != PC_NOERROR ? ", " : "", pcr != PC_NOERROR ? PCFailedReasons[pcr] : "", s->iterations, (double)s->check.residual));
  } else if (npiv > 0) {
    PetscCall(PetscSNPrintf(reason, len, "%s: MUMPS found %" PetscInt_FMT " null pivot%s (a singular system)", name, npiv, npiv > 1 ? "s" : ""));
  } else if (!(s->check.residual <= s->rtol)) {
    PetscCall(PetscSNPrintf(reason, len, "%s true residual of the full system %.3e misses solver.rtol %.3e", name, (double)s->check.residual, (double)s->rtol));
    *usable = s->check.residual <= PetscSqrtReal(s->rtol) ? PETSC_TRUE : PETSC_FALSE;
  } else *ok = *usable = PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The condensed reference: the stiffness S^ factored by MUMPS Cholesky, the
 * stresses recovered from the displacements. */
static PetscErrorCode BwSolverCondensed(BwSolver s, BwMixed mx, BwLog *log)
{
  PC  pc;
  Vec br, bq, xr, xq, rhs;

  PetscFunctionBeginUser;
  PetscCall(KSPCreate(s->comm, &s->condensed));
  PetscCall(KSPSetOptionsPrefix(s->condensed, "condensed_"));
  PetscCall(KSPSetOperators(s->condensed, mx->S, mx->S));
  PetscCall(KSPSetType(s->condensed, KSPPREONLY));
  PetscCall(KSPGetPC(s->condensed, &pc));
  PetscCall(PCSetType(pc, PCCHOLESKY));
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  PetscCall(KSPSetFromOptions(s->condensed));
  PetscCall(BwLogBegin(log, BW_PHASE_SETUP));
  PetscCall(KSPSetUp(s->condensed));
  PetscCall(BwLogEnd(log, BW_PHASE_SETUP));
  PetscCall(BwLogBegin(log, BW_PHASE_SOLVE));
  PetscCall(VecGetSubVector(mx->b, mx->isr, &br));
  PetscCall(VecGetSubVector(mx->b, mx->isq, &bq));
  PetscCall(VecGetSubVector(mx->x, mx->isr, &xr));
  PetscCall(VecGetSubVector(mx->x, mx->isq, &xq));
  PetscCall(VecDuplicate(bq, &rhs));
  PetscCall(MatMultTransposeAdd(mx->D, br, bq, rhs)); /* F^ + D^T b_r */
  PetscCall(KSPSolve(s->condensed, rhs, xq));
  PetscCall(MatMult(mx->D, xq, xr));
  PetscCall(VecAXPY(xr, -1.0, br)); /* r~ = D^ q~ - b_r */
  PetscCall(VecDestroy(&rhs));
  PetscCall(VecRestoreSubVector(mx->x, mx->isq, &xq));
  PetscCall(VecRestoreSubVector(mx->x, mx->isr, &xr));
  PetscCall(VecRestoreSubVector(mx->b, mx->isq, &bq));
  PetscCall(VecRestoreSubVector(mx->b, mx->isr, &br));
  PetscCall(BwLogEnd(log, BW_PHASE_SOLVE));
  s->used       = BW_METHOD_CONDENSED;
  s->iterations = 0;
  PetscCall(BwMixedCheck(mx, mx->x, NULL, &s->check));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Keeps the current answer as the best usable one if it is better than the
 * kept one: by the larger of its true residual and its estimated forward
 * error (an answer that met rtol with a larger error is the worse one). */
static PetscErrorCode BwSolverKeepBest(BwSolver s, BwMixed mx, BwMethod method, Vec *best, BwCheck *check, BwMethod *best_method, PetscInt *its, PetscReal *fwd, PetscReal *cond)
{
  PetscReal now = PetscMax(s->check.residual, s->forward_estimate), kept;

  PetscFunctionBeginUser;
  if (*best) {
    kept = PetscMax(check->residual, *fwd);
    if (!(now < kept)) PetscFunctionReturn(PETSC_SUCCESS);
  } else PetscCall(VecDuplicate(mx->x, best));
  PetscCall(VecCopy(mx->x, *best));
  *check       = s->check;
  *best_method = method;
  *its         = s->iterations;
  *fwd         = s->forward_estimate;
  *cond        = s->condition_estimate;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverSolve(BwSolver s, BwMixed mx, BwLog *log)
{
  PetscBool ok = PETSC_FALSE, usable;
  char      reason[512];
  Vec       best = NULL; /* a usable answer that missed rtol, kept in case nothing does better */
  BwCheck   best_check;
  BwMethod  best_method = BW_METHOD_FIELDSPLIT;
  PetscInt  best_its    = 0;
  PetscReal best_fwd = -1, best_cond = -1;

  PetscFunctionBeginUser;
  s->fallback_reason[0] = 0;
  s->warning[0]         = 0;
  s->accuracy_met       = PETSC_TRUE;
  if (s->requested == BW_METHOD_CONDENSED) {
    PetscCall(BwSolverCondensed(s, mx, log));
    s->ran_condensed = PETSC_TRUE;
    PetscCall(KSPDestroy(&s->condensed));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(BwSolverForwardSetUp(s, mx));
  if (s->requested != BW_METHOD_DIRECT) {
    PetscCall(BwSolverSetUpFieldsplit(s, mx, &s->fieldsplit, NULL, s->schur_gamg));
    s->used = BW_METHOD_FIELDSPLIT;
    PetscCall(BwSolverRun(s, mx, log, s->fieldsplit, "fieldsplit", &ok, &usable, reason, sizeof(reason)));
    if (!ok) {
      if (usable) PetscCall(BwSolverKeepBest(s, mx, BW_METHOD_FIELDSPLIT, &best, &best_check, &best_method, &best_its, &best_fwd, &best_cond));
      if (s->requested == BW_METHOD_AUTO) {
        s->fallback = PETSC_TRUE;
        PetscCall(PetscStrncpy(s->fallback_reason, reason, sizeof(s->fallback_reason)));
      }
    }
  }
  if (!ok && s->requested == BW_METHOD_AUTO && s->schur_gamg) {
    char why[512];
    PetscCall(BwSolverSetUpFieldsplit(s, mx, &s->cholesky, "cholesky_", PETSC_FALSE));
    s->used = BW_METHOD_FIELDSPLIT;
    PetscCall(BwSolverRun(s, mx, log, s->cholesky, "fieldsplit with MUMPS Cholesky of S^", &ok, &usable, why, sizeof(why)));
    if (!ok && usable) PetscCall(BwSolverKeepBest(s, mx, BW_METHOD_FIELDSPLIT, &best, &best_check, &best_method, &best_its, &best_fwd, &best_cond));
    if (!ok) PetscCall(PetscStrncpy(reason, why, sizeof(reason)));
  }
  if (!ok && s->requested != BW_METHOD_FIELDSPLIT && !s->direct_fits) {
    /* the assembled saddle matrix and its factors would not fit */
    PetscCall(PetscStrlcat(reason, "; the direct path was not tried: the saddle matrix of this many blocks does not fit in memory", sizeof(reason)));
  }
  if (!ok && s->requested != BW_METHOD_FIELDSPLIT && s->direct_fits) {
    PetscCall(BwSolverSetUpDirect(s, mx));
    s->used = BW_METHOD_DIRECT;
    PetscCall(BwSolverRun(s, mx, log, s->direct, "direct (MUMPS)", &ok, &usable, reason, sizeof(reason)));
    if (!ok && usable) PetscCall(BwSolverKeepBest(s, mx, BW_METHOD_DIRECT, &best, &best_check, &best_method, &best_its, &best_fwd, &best_cond));
  }
  if (!ok && best) {
    /* Every path stopped above solver.rtol at a residual that still makes
     * an answer (an ill-conditioned system's round-off floor): the best one
     * is written, and the run says so in the summary and in /solver. */
    char cond[64] = "";
    PetscCall(VecCopy(best, mx->x));
    s->check              = best_check;
    s->used               = best_method;
    s->iterations         = best_its;
    s->forward_estimate   = best_fwd;
    s->condition_estimate = best_cond;
    s->accuracy_met       = PETSC_FALSE;
    if (best_cond > 0) PetscCall(PetscSNPrintf(cond, sizeof(cond), ", condition estimate %.1e", (double)best_cond));
    if (s->check.residual <= s->rtol)
      PetscCall(PetscSNPrintf(s->warning, sizeof(s->warning), "estimated displacement error %.1e misses solver.forward_rtol %.1e (true residual %.3e%s): the system is too ill-conditioned for that accuracy in double precision; the answer written is the best of the paths tried (%s)", (double)s->forward_estimate, (double)s->forward_rtol, (double)s->check.residual, cond, BwMethods[best_method]));
    else
      PetscCall(PetscSNPrintf(s->warning, sizeof(s->warning), "true residual %.3e misses solver.rtol %.1e (estimated displacement error %.1e%s): the system is too ill-conditioned for that tolerance in double precision; the answer written is the best of the paths tried (%s)", (double)s->check.residual, (double)s->rtol, (double)s->forward_estimate, cond, BwMethods[best_method]));
    ok = PETSC_TRUE;
  }
  PetscCall(VecDestroy(&best));
  if (!ok) {
    /* no usable answer: a mechanism the static checks missed is named */
    PetscCall(BwMixedCheckMechanism(mx, reason));
    SETERRQ(s->comm, PETSC_ERR_NOT_CONVERGED, "solver failed: %s%s%s%s", reason, s->fallback ? "; before it, " : "", s->fallback ? s->fallback_reason : "", s->requested == BW_METHOD_FIELDSPLIT ? " (solver.method: auto would fall back to MUMPS)" : "");
  }
  /* Defaults inserted for sub-solvers the user replaced stay unused: drop them. */
  for (PetscInt d = 0; d < s->ndefaults; d++) {
    PetscBool used;
    PetscCall(PetscOptionsUsed(NULL, s->defaults[d], &used));
    if (!used) PetscCall(PetscOptionsClearValue(NULL, s->defaults[d]));
  }
  /* The answer is in mx->x: the solvers' factors, hierarchies and work
   * vectors go now, before recovery allocates its own. */
  s->ran_fieldsplit = s->fieldsplit ? PETSC_TRUE : PETSC_FALSE;
  s->ran_direct     = s->direct ? PETSC_TRUE : PETSC_FALSE;
  s->ran_condensed  = s->condensed ? PETSC_TRUE : PETSC_FALSE;
  s->ran_cholesky   = s->cholesky ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(KSPDestroy(&s->cholesky));
  PetscCall(KSPDestroy(&s->fieldsplit));
  PetscCall(KSPDestroy(&s->direct));
  PetscCall(KSPDestroy(&s->condensed));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverGetOptionPrefixes(PetscInt *n, const char *const **prefixes)
{
  static const char *const all[] = {"ksp_", "pc_", "mat_", "fieldsplit_", "direct_", "condensed_", "cholesky_", "mechanism_", "schur_", "mixed_"};

  PetscFunctionBeginUser;
  *n        = (PetscInt)PETSC_STATIC_ARRAY_LENGTH(all);
  *prefixes = all;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverGetIdlePrefixes(BwSolver s, PetscInt *n, const char *prefixes[6])
{
  PetscFunctionBeginUser;
  *n = 0;
  if (!s->ran_fieldsplit) {
    prefixes[(*n)++] = "ksp_";
    prefixes[(*n)++] = "pc_";
    prefixes[(*n)++] = "fieldsplit_";
  }
  if (!s->ran_direct) prefixes[(*n)++] = "direct_";
  if (!s->ran_condensed) prefixes[(*n)++] = "condensed_";
  if (!s->ran_cholesky) prefixes[(*n)++] = "cholesky_";
  PetscFunctionReturn(PETSC_SUCCESS);
}
