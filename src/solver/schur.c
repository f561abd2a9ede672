/* The Schur PC: the exact block elimination of the scaled mixed system,
 *
 *   [ -I    T D^ ] [ y_r ]   [ z_r ]        w   = z_q + D^T z_r
 *   [ D^T   P    ] [ y_q ] = [ z_q ]   =>   y_q = S^{-1} w,  S^ = D^T T D^ + P
 *                                           y_r = T D^ y_q - z_r
 *
 * The refinement (solver.c) runs on the block dofs alone: the stress rows
 * are solved exactly by the elimination, so after its first step the
 * residual of the full system lives in the q rows, w - S~ q with S~ the
 * exact Schur complement (BwMixedCreateSchurOperator), and every step is
 * this PC applied to it: y_q = S^{-1} r_q. The stresses follow once, at the
 * end. A refinement on the whole system (as before) kept two work vectors
 * of its size, 2 x 2.3 KB per block of a 3D wall at m = 8, m_b = 4, a fifth
 * of its memory. BwSchurPCApplyFull is the elimination on the whole
 * system, for the round-off bound (estimates.c).
 *
 * A PCSHELL named "schur" rather than a registered PC type: a type would
 * reach into PETSc's private headers, which change between releases. Its
 * Schur solve is a KSP of our own, prefix <outer prefix>schur_ (-schur_*),
 * on S^ itself (3 rows per block) rather than on D^T D^ applied
 * matrix-free (2m rows per interface twice per product: 13 s against
 * 0.3 s on a 5e4-block wall). */
#include "solver/solver_impl.h"
#include "util/compat.h"
#include "util/factor.h"
#include <string.h>
#include <dlfcn.h>

/* Below this many rows a non-symmetric S^ on one rank is factored by
 * PETSc's own LU (BwSolverSetFactor). */
#define BW_OWN_LU_ROWS 1000

typedef struct {
  BwMixed mx;
  Mat     D;
  IS      isr, isq;
  KSP     inner;
  Vec     w; /* q size, for BwSchurPCApplyFull only */
} BwSchurPC;

/* The preconditioner of the refinement on q: y = S^{-1} z by the Schur solve. */
static PetscErrorCode BwSchurPCApply(PC pc, Vec z, Vec y)
{
  BwSchurPC         *ctx;
  KSPConvergedReason reason;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(KSPSolve(ctx->inner, z, y));
  PetscCall(KSPGetConvergedReason(ctx->inner, &reason));
  /* a failed Schur solve fails the outer KSP (DIVERGED_PC_FAILED) */
  if (reason < 0) PetscCall(PCSetFailedReason(pc, PC_SUBPC_ERROR));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSchurPCApplyFull(PC pc, Vec z, Vec y)
{
  BwSchurPC *ctx;
  Vec        yq;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &ctx));
  if (!ctx->w) PetscCall(MatCreateVecs(ctx->D, &ctx->w, NULL));
  PetscCall(BwMixedSchurRHS(ctx->mx, z, ctx->w));
  PetscCall(VecGetSubVector(y, ctx->isq, &yq));
  PetscCall(KSPSolve(ctx->inner, ctx->w, yq));
  PetscCall(VecRestoreSubVector(y, ctx->isq, &yq));
  PetscCall(BwMixedStressesFromDofs(ctx->mx, z, y));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The Schur solve is set up with the outer PC: a factorisation, or an AMG
 * hierarchy, in the set-up phase rather than inside the first apply. */
static PetscErrorCode BwSchurPCSetUpShell(PC pc)
{
  BwSchurPC *ctx;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(KSPSetUp(ctx->inner));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwSchurPCView(PC pc, PetscViewer viewer)
{
  BwSchurPC *ctx;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(PetscViewerASCIIPrintf(viewer, "Schur complement S^ = D^T T D^ + P, exact block elimination; its solve:\n"));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  PetscCall(KSPView(ctx->inner, viewer));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwSchurPCDestroy(PC pc)
{
  BwSchurPC *ctx;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(KSPDestroy(&ctx->inner));
  PetscCall(VecDestroy(&ctx->w));
  PetscCall(PetscFree(ctx));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverSetFactor(BwSolver s, PC pc, BwFactorKind kind, Mat A)
{
  MatSolverType type;

  PetscFunctionBeginUser;
  if (s->reproducible) {
    /* A parallel factorisation is not the same from one run to the next:
     * MUMPS sums its fronts' contributions in the order its dynamically
     * scheduled tasks end, and SuperLU_DIST on 3 ranks did not repeat
     * itself either (one matrix factored 10 times on 2 ranks by MUMPS, 6
     * on 3 by SuperLU_DIST: 9 and 5 answers differed from the first, by
     * up to 4e-13 and 1.6e-12 of the answer). Past a pushover's peak such
     * differences choose among the paths of the portions that swap (the
     * 412-block wall on 2 ranks: 1.6e-6 apart). A sequential factor of the
     * whole matrix on every rank (PCREDUNDANT, one copy per rank) repeats
     * itself, and the rest of the runs checked did (docs/solvers.md). */
    PetscMPIInt size;
    KSP         rksp;
    PC          rpc;
    PetscCallMPI(MPI_Comm_size(s->comm, &size));
    PetscCall(PCSetType(pc, PCREDUNDANT));
    PetscCall(PCRedundantSetNumber(pc, size));
    PetscCall(PCRedundantGetKSP(pc, &rksp));
    PetscCall(KSPGetPC(rksp, &rpc));
    PetscCall(PCSetType(rpc, kind == BW_FACTOR_CHOLESKY ? PCCHOLESKY : PCLU));
    PetscCall(BwFactorPackage(PETSC_COMM_SELF, kind, &type));
    PetscCheck(type, s->comm, PETSC_ERR_SUP, "solver.reproducible: this PETSc has no sequential sparse %s factorisation (it has %s)", kind == BW_FACTOR_CHOLESKY ? "Cholesky" : "LU", BwFactorPackages());
    PetscCall(PCFactorSetMatSolverType(rpc, type));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PCSetType(pc, kind == BW_FACTOR_CHOLESKY ? PCCHOLESKY : PCLU));
  PetscCall(BwFactorPackage(s->comm, kind, &type));
  PetscCheck(type, s->comm, PETSC_ERR_SUP, "this PETSc has no parallel sparse %s factorisation (it has %s): use solver.schur: gamg, or one rank", kind == BW_FACTOR_CHOLESKY ? "Cholesky" : "LU", BwFactorPackages());
  {
    /* a small non-symmetric S^ on one rank (a Newton matrix of a few
     * hundred blocks, refactored thousands of times in a pushover): PETSc's
     * own LU in a minimum-degree order, whose numeric factorisation costs a
     * third of KLU's here and less than MUMPS's set-up of its fronts
     * (examples/j4d_cap.yaml, 489 rows, 1551 factorisations: 0.25 s
     * against KLU's 0.89 s; MUMPS's took 8.0 s for the whole run where KLU's
     * took 6.7). It does not pivot: a zero pivot (an open joint's zero
     * stiffness near a mechanism) is shifted below, and the factor is the
     * preconditioner of the refinement on the true residual, which removes
     * what the shift changed or fails the solve. */
    PetscInt    rows;
    PetscMPIInt size;
    PetscBool   mumps;
    PetscCallMPI(MPI_Comm_size(s->comm, &size));
    PetscCall(MatGetSize(A, &rows, NULL));
    PetscCall(PetscStrcmp(type, MATSOLVERMUMPS, &mumps));
    if (kind == BW_FACTOR_LU && size == 1 && mumps && rows < BW_OWN_LU_ROWS) {
      type = MATSOLVERPETSC;
      PetscCall(PCFactorSetMatOrderingType(pc, MATORDERINGQMD));
    }
  }
  PetscCall(PCFactorSetMatSolverType(pc, type));
  {
    /* PETSc's own factorisation does not pivot: an open joint's zero
     * stiffness can leave a zero pivot in S^ near a mechanism, where MUMPS
     * would pivot. A shift of the zero pivots keeps the factor usable as a
     * preconditioner; the outer iterations (and the true-residual test)
     * remove what the shift changes. */
    PetscBool own;
    PetscCall(PetscStrcmp(type, MATSOLVERPETSC, &own));
    if (own) PetscCall(PCFactorSetShiftType(pc, MAT_SHIFT_NONZERO));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

#if defined(PETSC_HAVE_MUMPS)
/* Whether the MUMPS that PETSc calls orders in parallel: its wrappers of
 * PT-Scotch's and ParMETIS's parallel orderings (mumps_common's
 * mumps_dgraphinit, mumps_parmetis) exist only where it was built with one
 * of them. A MUMPS without either answers ICNTL(28) = 2 with an error at
 * the analysis (INFOG(1) = -38), and Debian's 5.5 first writes to a
 * negative Fortran unit if its messages are silenced (ICNTL(1) = -1): it
 * cannot be asked by trying. */
static PetscBool BwMumpsOrdersInParallel(void)
{
  static const char *const names[] = {"mumps_dgraphinit_", "mumps_dgraphinit", "MUMPS_DGRAPHINIT", "mumps_parmetis_", "mumps_parmetis", "MUMPS_PARMETIS"};
  for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++)
    if (dlsym(RTLD_DEFAULT, names[i])) return PETSC_TRUE;
  return PETSC_FALSE;
}
#endif

/* The MUMPS factor matrix of a factorisation PC (LU or Cholesky) whose
 * package is MUMPS, its package set up; NULL for any other PC or package.
 * Where its controls are set, after the options (they are read when MUMPS
 * analyses the matrix, and win). */
PetscErrorCode BwSolverGetMumpsFactor(PC pc, Mat *F)
{
  PetscBool factor;

  PetscFunctionBeginUser;
  *F = NULL;
  PetscCall(PetscObjectTypeCompareAny((PetscObject)pc, &factor, PCLU, PCCHOLESKY, ""));
  if (!factor) PetscFunctionReturn(PETSC_SUCCESS);
#if defined(PETSC_HAVE_MUMPS)
  {
    MatSolverType type;
    PetscBool     mumps;
    PetscCall(PCFactorGetMatSolverType(pc, &type));
    PetscCall(PetscStrcmp(type, MATSOLVERMUMPS, &mumps));
    if (mumps) {
      PetscCall(PCFactorSetUpMatSolverType(pc));
      PetscCall(PCFactorGetMatrix(pc, F));
    }
  }
#endif
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* After the options: with MUMPS, null-pivot detection, so that a singular
 * matrix is reported rather than factored into garbage (the options, read
 * when MUMPS analyses the matrix, still win: -..._mat_mumps_icntl_24 0).
 * On several ranks, the analysis in parallel where this MUMPS can
 * (ICNTL(28) = 2, its choice of PT-Scotch or ParMETIS): its sequential
 * analysis gathers the whole graph of the matrix on rank 0 and orders it
 * there, which no rank of a distributed run should hold (what it buys is
 * that memory, not fill: bench/results.md, 2026-11-28). */
PetscErrorCode BwSolverFactorDefaults(PC pc)
{
  Mat F;

  PetscFunctionBeginUser;
  PetscCall(BwSolverGetMumpsFactor(pc, &F));
#if defined(PETSC_HAVE_MUMPS)
  if (F) {
    PetscMPIInt size;
    PetscCall(MatMumpsSetIcntl(F, 24, 1));
    PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)pc), &size));
    if (size > 1 && BwMumpsOrdersInParallel()) {
      PetscCall(MatMumpsSetIcntl(F, 28, 2));
      PetscCall(MatMumpsSetIcntl(F, 29, 0));
    }
  }
#endif
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* S^ of an assembly symmetric about its mid-plane splits into independent
 * groups of dofs (u1 u2 w3 | u3 w1 w2, stiffness.c). PETSc hands MUMPS the
 * block size of S^ (6) as a compression of its graph, one vertex per block
 * (ICNTL(15) = -6), which joins the groups again: the ordering no longer
 * sees them apart. The bench's 3D wall at 60 x 60 units on 2 ranks: 3.2e6
 * entries in the factor and 7.8e8 flops, against 1.6e6 and 2.0e8
 * uncompressed; at 300 x 300 the whole run 7.12 s against 8.34 s, medians
 * of 3 (bench/results.md, 2026-11-28). So uncompressed where S^ splits. PETSc
 * takes ICNTL(15) from the block size at the analysis unless the option
 * is given, so the default goes in as an option; one of the user's wins. */
static PetscErrorCode BwSchurFactorUncompressed(BwSolver s, PC pc)
{
  PetscBool   set;
  PetscInt    groups, v;
  const char *prefix;
  char        name[256];
  Mat         F;

  PetscFunctionBeginUser;
  PetscCall(BwSolverGetMumpsFactor(pc, &F));
  PetscCall(BwMixedGetSchurGroups(s->mx, &groups, NULL, 0));
  if (!F || groups < 2) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PCGetOptionsPrefix(pc, &prefix));
  PetscCall(PetscOptionsHasName(NULL, prefix, "-mat_mumps_icntl_15", &set));
  if (set) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscSNPrintf(name, sizeof(name), "-%smat_mumps_icntl_15", prefix ? prefix : ""));
  PetscCall(PetscOptionsSetValue(NULL, name, "0"));
  /* read once here, so that a run that never factors does not report it unused */
  PetscCall(PetscOptionsGetInt(NULL, prefix, "-mat_mumps_icntl_15", &v, NULL));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* S^ factored by MUMPS in block low-rank form (solver.low_rank): the
 * fronts' off-diagonal blocks compressed to CNTL(7) of their norm, which
 * the refinement on the true S~ takes as its preconditioner's error.
 * Before the options: MUMPS, where one rank would take CHOLMOD (a user's
 * -schur_pc_factor_mat_solver_type still wins). */
static PetscErrorCode BwSchurLowRankPackage(PC pc)
{
  PetscFunctionBeginUser;
#if defined(PETSC_HAVE_MUMPS)
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
#else
  (void)pc;
#endif
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* After the options, S^'s own MUMPS controls, read when MUMPS analyses S^
 * (the factor's options, -schur_mat_mumps_icntl_8 77 and the like, still
 * win):
 * - no scaling (ICNTL(8) = 0). S^ comes with a unit diagonal (the dof
 *   scaling, stiffness.c), so MUMPS's own scaling (ICNTL(8) = 77: in
 *   parallel, an iterative row and column scaling recomputed at every
 *   numerical factorisation) has nothing left to equilibrate, and a
 *   pushover pays for it at every Newton iteration: on the ~1e4-block wall
 *   of bench/pushover.py (2 ranks, 30 steps, 165 LUs of 30 153 rows,
 *   alternated 3 times) 91.6 ms (75.1-95.1) a factorisation without it
 *   against 109.5 ms (104.1-112.4), the same iterations and load factors to
 *   1e-14 (bench/results.md, 2026-11-29). A symmetric S^ (its Cholesky
 *   factor) MUMPS did not scale anyway (INFOG(33) = 0), so linear runs are
 *   as before. Not the direct path's K~, a saddle matrix whose rows differ
 *   by the joints' stiffness.
 * - with low_rank (solver.low_rank), the block low-rank factor: ICNTL(35) =
 *   2 and CNTL(7) = BW_LOW_RANK_TOL (-schur_mat_mumps_cntl_7 1e-10,
 *   -schur_mat_mumps_icntl_35 0 win). */
static PetscErrorCode BwSchurFactorControls(PC pc, PetscBool low_rank)
{
  Mat F;

  PetscFunctionBeginUser;
  PetscCall(BwSolverGetMumpsFactor(pc, &F));
#if defined(PETSC_HAVE_MUMPS)
  if (F) {
    PetscCall(MatMumpsSetIcntl(F, 8, 0));
    if (low_rank) {
      PetscCall(MatMumpsSetIcntl(F, 35, 2));
      PetscCall(MatMumpsSetCntl(F, 7, BW_LOW_RANK_TOL));
    }
  }
#else
  (void)low_rank;
#endif
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSchurPCSetUp(BwSolver s, KSP outer, PetscBool factor)
{
  BwSchurPC  *ctx;
  PC          pc, ipc;
  Mat         S;
  const char *prefix;
  char        inner_prefix[128];
  PetscBool   iterative = factor ? PETSC_FALSE : s->schur_iterative;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&ctx));
  ctx->mx = s->mx;
  PetscCall(BwMixedGetOperators(s->mx, NULL, &S, &ctx->D));
  PetscCall(BwMixedGetFields(s->mx, &ctx->isr, &ctx->isq));
  PetscCall(KSPGetOptionsPrefix(outer, &prefix));
  PetscCall(PetscSNPrintf(inner_prefix, sizeof(inner_prefix), "%sschur_", prefix ? prefix : ""));
  PetscCall(KSPCreate(s->comm, &ctx->inner));
  PetscCall(KSPSetOptionsPrefix(ctx->inner, inner_prefix));
  PetscCall(KSPSetOperators(ctx->inner, S, S));
  PetscCall(KSPGetPC(ctx->inner, &ipc));
  if (!iterative) {
    PetscCall(KSPSetType(ctx->inner, KSPPREONLY));
    PetscCall(BwSolverSetFactor(s, ipc, s->symmetric ? BW_FACTOR_CHOLESKY : BW_FACTOR_LU, S));
    if (!factor && s->low_rank) PetscCall(BwSchurLowRankPackage(ipc));
  } else if (s->schur == BW_SCHUR_HYPRE) {
    PetscCall(KSPSetType(ctx->inner, s->symmetric ? KSPCG : KSPGMRES));
    PetscCall(PCSetType(ipc, PCHYPRE));
    PetscCall(KSPSetTolerances(ctx->inner, 1e-5, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT));
  } else {
    PetscCall(KSPSetType(ctx->inner, s->symmetric ? KSPCG : KSPGMRES));
    /* GAMG, and in 3D the long blocks eliminated (amg.c) */
    PetscCall(BwSchurAMGSetUp(s, ctx->inner));
    /* 1e-5: three outer steps meet rtol 1e-10 and the forward estimate
     * (9 + 17 + 16 CG iterations at 1e5 blocks); 1e-4 needed four
     * (6 + 14 + 14 + 14), 1e-6 three with more iterations (12 + 20 + 18) */
    PetscCall(KSPSetTolerances(ctx->inner, 1e-5, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT));
  }
  PetscCall(KSPSetFromOptions(ctx->inner));
  PetscCall(BwSolverFactorDefaults(ipc));
  PetscCall(BwSchurFactorControls(ipc, !iterative && !factor && s->low_rank ? PETSC_TRUE : PETSC_FALSE));
  PetscCall(BwSchurFactorUncompressed(s, ipc));

  PetscCall(KSPGetPC(outer, &pc));
  PetscCall(PCSetType(pc, PCSHELL));
  PetscCall(PCShellSetName(pc, "schur"));
  PetscCall(PCShellSetContext(pc, ctx));
  PetscCall(PCShellSetApply(pc, BwSchurPCApply));
  PetscCall(PCShellSetSetUp(pc, BwSchurPCSetUpShell));
  PetscCall(PCShellSetView(pc, BwSchurPCView));
  PetscCall(PCShellSetDestroy(pc, BwSchurPCDestroy));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSchurPCGetInner(KSP outer, KSP *inner)
{
  PC          pc;
  PetscBool   shell;
  const char *name = NULL;

  PetscFunctionBeginUser;
  *inner = NULL;
  PetscCall(KSPGetPC(outer, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCSHELL, &shell));
  if (shell) PetscCall(PCShellGetName(pc, &name));
  if (shell && name && !strcmp(name, "schur")) {
    BwSchurPC *ctx;
    PetscCall(PCShellGetContext(pc, &ctx));
    *inner = ctx->inner;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}
