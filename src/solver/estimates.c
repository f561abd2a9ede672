/* What a solve knows about its own accuracy.
 *
 * Forward error of the displacements, from the refinement. A residual that
 * meets rtol does not bound the error once the system is ill-conditioned:
 * on walls whose joints differ by 1e6..1e9 the first step (the condensed
 * solve, whose assembled S^ adds soft joints to stiff ones) met rtol with
 * displacements wrong by 1e-7 (docs/accuracy.md). Each Richardson step is
 * a step of iterative refinement on the full mixed system, and its
 * correction x_k - x_{k-1} measures the error x_{k-1} had:
 *   it = 1: nothing known yet (the correction is x_1 itself);
 *   it = 2: the correction, an upper estimate of x_2's error;
 *   it > 2: while the corrections shrink steadily (the last two ratios of
 *           successive corrections below 1/2: linear convergence), the
 *           correction times rho / (1 - rho), rho the last ratio; else the
 *           larger of the last two corrections.
 * At the round-off floor of an ill-conditioned system the corrections stop
 * shrinking and become noise (1.6e-7, 1.6e-7, then 4e-9 on a stiff cluster
 * whose error was 4e-7): one small correction among them says nothing, so
 * the estimate stays at the size of the noise, the error that remains. The
 * norm is the one the stability suite measures with: max norm of the
 * physical displacements, rotations times the assembly's diagonal, relative
 * to the largest, prescribed values included. Only the q part is kept (3
 * values per block): a copy of the stresses would cost 2m per interface.
 *
 * Condition number of what was factored: Hager's 1-norm estimator as
 * refined by Higham (LAPACK's xLACN2), with the factor. */
#include "solver/solver_impl.h"
#include "util/compat.h"

/* Hager-Higham iterations (each a pair of solves with the factor) */
#define BW_CONDITION_ITERATIONS 4
/* what the extra-precise estimate is multiplied by (BwSolverForwardExtra) */
#define BW_EXTRA_SAFETY 10

PetscErrorCode BwSolverForwardSetUp(BwSolver s)
{
  Mat S;

  PetscFunctionBeginUser;
  if (s->fw_weight) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(BwMixedGetOperators(s->mx, NULL, &S, NULL));
  PetscCall(MatCreateVecs(S, &s->fw_weight, NULL));
  PetscCall(BwMixedForwardWeights(s->mx, s->fw_weight, &s->fw_prescribed));
  PetscCall(VecDuplicate(s->fw_weight, &s->fw_prev));
  PetscCall(VecDuplicate(s->fw_weight, &s->fw_work));
  PetscFunctionReturn(PETSC_SUCCESS);
}

typedef struct {
  BwSolver s;
  void    *dflt; /* KSPConvergedDefault's context */
} BwConvergedCtx;

static PetscErrorCode BwConvergedCtxDestroy(BW_CTX_DESTROY_ARG arg)
{
  BwConvergedCtx *c = (BwConvergedCtx *)BW_CTX_FROM_DESTROY(arg);

  PetscFunctionBeginUser;
  PetscCall(BW_CONVERGED_DESTROY(c->dflt));
  PetscCall(PetscFree(c));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The residual test of PETSc (rtol on the true residual), and then the
 * forward estimate must meet solver.forward_rtol: a step is added while it
 * does not, up to the KSP's iteration limit. */
static PetscErrorCode BwSolverConverged(KSP ksp, PetscInt it, PetscReal rnorm, KSPConvergedReason *reason, void *ctx)
{
  BwConvergedCtx *c = (BwConvergedCtx *)ctx;
  BwSolver        s = c->s;
  PetscInt        maxit;
  IS              isq;
  Vec             x, xq;
  PetscReal       dn, qn, rel, est, atol;
  PetscBool       floor;

  PetscFunctionBeginUser;
  PetscCall(KSPConvergedDefault(ksp, it, rnorm, reason, c->dflt));
  if (it == 0) {
    PetscCall(VecZeroEntries(s->fw_prev)); /* x_0 = 0 */
    s->fw_last          = -1;
    s->fw_ratio         = 1;
    s->fw_it            = 0;
    s->forward_estimate = rnorm == 0 ? 0 : PETSC_INFINITY;
    s->fw_rprev         = rnorm;
    s->floor_stall      = PETSC_FALSE;
    s->residual_floor   = -1;
  } else if (it != s->fw_it) {
    PetscInt nx, nq;
    PetscCall(BwMixedGetFields(s->mx, NULL, &isq));
    PetscCall(KSPGetSolution(ksp, &x));
    PetscCall(VecGetSize(x, &nx));
    PetscCall(VecGetSize(s->fw_weight, &nq));
    /* the refinement on q (fieldsplit) or on the whole system (direct) */
    if (nx == nq) {
      PetscCall(PetscObjectReference((PetscObject)x));
      xq = x;
    } else PetscCall(VecGetSubVector(x, isq, &xq));
    PetscCall(VecWAXPY(s->fw_work, -1.0, s->fw_prev, xq));
    PetscCall(VecPointwiseMult(s->fw_work, s->fw_work, s->fw_weight));
    PetscCall(VecNorm(s->fw_work, NORM_INFINITY, &dn));
    PetscCall(VecCopy(xq, s->fw_prev));
    PetscCall(VecPointwiseMult(s->fw_work, xq, s->fw_weight));
    PetscCall(VecNorm(s->fw_work, NORM_INFINITY, &qn));
    if (nx == nq) PetscCall(VecDestroy(&xq));
    else PetscCall(VecRestoreSubVector(x, isq, &xq));
    /* relative to the whole displacement field, prescribed values included:
     * where loads vanish and only prescribed dofs move, the free dofs may be
     * zero up to round-off (a relative correction of round-off to round-off
     * read 7.0 on two blocks) */
    qn  = PetscMax(qn, s->fw_prescribed);
    rel = qn > 0 ? dn / qn : (dn > 0 ? PETSC_INFINITY : 0);
    if (it == 1) est = rel == 0 ? 0 : PETSC_INFINITY;
    else if (it == 2 || !(s->fw_last > 0)) est = rel;
    else {
      PetscReal rho = rel / s->fw_last, before = s->fw_ratio;
      est           = rho < 0.5 && (it == 3 || before < 0.5) ? rel * rho / (1 - rho) : PetscMax(rel, s->fw_last);
      s->fw_ratio   = rho;
    }
    PetscCall(PetscInfo(ksp, "step %" PetscInt_FMT ": displacement correction %.3e (relative), forward estimate %.3e\n", it, (double)rel, (double)est));
    s->fw_last          = rel;
    s->fw_it            = it;
    s->forward_estimate = est;
  }
  if (*reason > 0 && s->forward_check && !(s->forward_estimate <= s->forward_rtol)) *reason = KSP_CONVERGED_ITERATING;
  /* The round-off floor of the residual: a step that gained less than a
   * factor 2 on the residual, from displacements already within
   * forward_rtol, is the refinement at its fixed point; more steps only
   * repeat it (a 2.5e5-block 3D wall: a floor of 3.3e-10 against rtol
   * 1e-10, 27 more steps of CG + GAMG and then a factorisation of S^ that
   * stopped at the same floor, 150 s and 12 GB). Stopped as stalled, from
   * the fifth step: the forward estimate must have seen the corrections
   * turn to noise (estimated 2.7e-21 after three steps on a stiff cluster
   * whose reference error was 5.5e-24: too small to be checked), and the
   * factored paths, whose limit is five, are not changed by it: their
   * fifth step ends at the limit (DIVERGED_ITS), after which the round-off
   * bound of the factor is added to the estimate (solver.c), which a stop
   * as stalled here would skip (stability.tenon_1e-5 with the reference
   * BLAS: an estimate of 1.98e-16 against an error of 2.19e-16). */
  /* A Newton correction (no forward check) has no estimate to wait for:
   * its floor is seen from the second step, once the residual is within
   * sqrt(rtol), all that Newton asks of it (solver.c). Its refinement used
   * to run to the limit of five steps at a floor of 3e-10 (the load
   * vector's solve of displacement control on a cracked 3D wall: 239 of
   * 627 solves of bench/tilt_u_wall.py, four extra solves with the factor
   * each) for an answer that Newton accepts at the first. */
  PetscCall(KSPGetTolerances(ksp, NULL, &atol, NULL, &maxit));
  /* The residual that rounding the displacements to double leaves: on a
   * tall wall eps |S~| |q| exceeds rtol |b| (operator.c; the bench's 3D
   * wall of 1e6 blocks stopped at 3.5e-9 against 1e-10), and a
   * double-precision q cannot be expected to do better (the refinement
   * stops at 0.13-0.18 of this worst case of the rounding). Measured from the third step where the
   * residual misses rtol, so that a refinement stopped at its floor (below)
   * can say why. Not converged there: the stresses recovered from such a q
   * carry its rounding times the joints' stiffness (5e-6 on the stability
   * suite's contrast_random_1e12 at a floor of 3e-4, counted as a silent
   * wrong answer when such stops were let through), which is what a
   * residual above rtol says. Nor stopped earlier than below: at the third
   * step the corrections of CG + GAMG still converge (1.5e-5, 1.3e-10 at
   * 2.5e5 blocks) and their extrapolation (1e-15) cannot see the noise the
   * fourth and fifth show (5e-14). On the block dofs of the fieldsplit
   * paths, where D^ is held by its structure (the factored ones add the
   * factor's round-off bound besides, solver.c). */
  if (*reason == KSP_CONVERGED_ITERATING && s->forward_check && it >= 3 && s->forward_estimate <= s->forward_rtol && atol > 0 && rnorm > atol) {
    PetscBool shell = PETSC_FALSE;
    Vec       x, w;
    PetscInt  nx, nq;
    PetscCall(KSPGetSolution(ksp, &x));
    PetscCall(VecGetSize(x, &nx));
    PetscCall(VecGetSize(s->fw_weight, &nq));
    if (nx == nq) PetscCall(BwMixedRoundoffSupported(s->mx, &shell));
    if (shell) {
      PetscReal terms, bnorm = atol / s->rtol;
      PetscCall(KSPGetRhs(ksp, &w));
      PetscCall(BwMixedSchurTermsNorm(s->mx, x, w, &terms));
      PetscCall(PetscInfo(ksp, "step %" PetscInt_FMT ": residual %.3e, the floor of q in double eps |S~| |q| %.3e (relative to |b|: %.3e against %.3e)\n", it, (double)rnorm, (double)(PETSC_MACHINE_EPSILON * terms), (double)(rnorm / bnorm), (double)(PETSC_MACHINE_EPSILON * terms / bnorm)));
      s->residual_floor = rnorm <= PETSC_MACHINE_EPSILON * terms ? PETSC_MACHINE_EPSILON * terms / bnorm : -1;
    }
  }
  /* With S^ factored the refinement is at its fixed point by the third
   * step (corrections 1.2e-8, then 2.8e-14 at 9e4 blocks): a residual at
   * or below the floor of rounding q (measured above) stops it there,
   * where it used to run to its limit of five for nothing (at 1e6 blocks,
   * two solves with an 8 GB factor). The round-off bound of the factor is
   * still added (solver.c). */
  if (s->forward_check) {
    PetscBool factored = PETSC_FALSE;
    if (it >= 3 && it < 5 && s->residual_floor > 0) {
      PC  fpc;
      Mat A;
      PetscCall(BwSolverGetFactorPC(ksp, &fpc, &A));
      factored = fpc ? PETSC_TRUE : PETSC_FALSE;
    }
    floor = (it >= 5 || factored) && s->forward_estimate <= s->forward_rtol;
  } else floor = it >= 2 && rnorm <= atol / PetscSqrtReal(s->rtol);
  if (*reason == KSP_CONVERGED_ITERATING && floor && it < maxit && s->fw_rprev > 0 && rnorm > 0.5 * s->fw_rprev) {
    PetscCall(PetscInfo(ksp, "step %" PetscInt_FMT ": residual %.3e after %.3e, %s: the round-off floor\n", it, (double)rnorm, (double)s->fw_rprev, s->forward_check ? "displacements within forward_rtol" : "a Newton correction within sqrt(rtol)"));
    s->floor_stall = PETSC_TRUE;
    *reason        = KSP_DIVERGED_DTOL;
  }
  if (it > 0) s->fw_rprev = rnorm;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverSetConvergenceTest(BwSolver s, KSP ksp)
{
  BwConvergedCtx *c;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&c));
  c->s = s;
  PetscCall(KSPConvergedDefaultCreate(&c->dflt));
  PetscCall(KSPSetConvergenceTest(ksp, BwSolverConverged, c, BwConvergedCtxDestroy));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Hager-Higham's steps, shared by the three estimates below: y <- sign(y)
 * (0 counted positive); and, with z = M^T sign(M v) for the 1-norm of M,
 * the stop (max |z| <= z^T v, after the first step) or the next v, the
 * unit vector at the largest |z|. */
static PetscErrorCode BwHagerSigns(Vec y)
{
  PetscScalar *a;
  PetscInt     n;

  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(y, &n));
  PetscCall(VecGetArray(y, &a));
  for (PetscInt i = 0; i < n; i++) a[i] = PetscRealPart(a[i]) >= 0 ? 1.0 : -1.0;
  PetscCall(VecRestoreArray(y, &a));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwHagerNext(Vec z, Vec v, PetscInt k, PetscBool *stop)
{
  PetscScalar ztx;
  PetscReal   zmax;
  PetscInt    j, lo, hi;

  PetscFunctionBeginUser;
  PetscCall(VecDot(z, v, &ztx));
  PetscCall(VecAbs(z));
  PetscCall(VecMax(z, &j, &zmax));
  *stop = k > 0 && zmax <= PetscRealPart(ztx) ? PETSC_TRUE : PETSC_FALSE;
  if (*stop) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(VecGetOwnershipRange(v, &lo, &hi));
  PetscCall(VecZeroEntries(v));
  if (j >= lo && j < hi) PetscCall(VecSetValue(v, j, 1.0, INSERT_VALUES));
  PetscCall(VecAssemblyBegin(v));
  PetscCall(VecAssemblyEnd(v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 1-norm condition number of A from its factor (pc applies A^-1): Hager's
 * estimator as refined by Higham (LAPACK's xLACN2), at most four pairs of
 * solves, with Higham's alternating vector as a second guess. The estimate
 * is a lower bound, in practice within a factor 3. A non-symmetric A needs
 * the transposed solve. */
PetscErrorCode BwSolverConditionEstimate(PC pc, Mat A, PetscBool symmetric, PetscReal *cond)
{
  Vec       x, y, z;
  PetscInt  N, lo, hi;
  PetscReal anorm, est = 0, ynorm, alt;

  PetscFunctionBeginUser;
  PetscCall(MatCreateVecs(A, &x, &y));
  PetscCall(VecDuplicate(x, &z));
  PetscCall(VecGetSize(x, &N));
  PetscCall(VecGetOwnershipRange(x, &lo, &hi));
  PetscCall(MatNorm(A, NORM_1, &anorm));
  PetscCall(VecSet(x, 1.0 / N));
  for (PetscInt k = 0; k < BW_CONDITION_ITERATIONS; k++) {
    PetscBool stop;
    PetscCall(PCApply(pc, x, y));
    PetscCall(VecNorm(y, NORM_1, &ynorm));
    if (k > 0 && ynorm <= est) break;
    est = ynorm;
    PetscCall(BwHagerSigns(y));
    if (symmetric) PetscCall(PCApply(pc, y, z));
    else PetscCall(PCApplyTranspose(pc, y, z));
    PetscCall(BwHagerNext(z, x, k, &stop));
    if (stop) break;
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

PetscErrorCode BwSolverGetFactorPC(KSP ksp, PC *fpc, Mat *A)
{
  PC        pc;
  KSP       inner;
  PetscBool factor;

  PetscFunctionBeginUser;
  *fpc = NULL;
  *A   = NULL;
  PetscCall(BwSchurPCGetInner(ksp, &inner));
  PetscCall(KSPGetPC(inner ? inner : ksp, &pc));
  /* solver.reproducible: a sequential factor on every rank, applied to
   * the parallel vectors by PCREDUNDANT */
  PetscCall(PetscObjectTypeCompareAny((PetscObject)pc, &factor, PCLU, PCCHOLESKY, PCREDUNDANT, ""));
  if (!factor) PetscFunctionReturn(PETSC_SUCCESS);
  *fpc = pc;
  PetscCall(PCGetOperators(pc, A, NULL));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* INFOG(i) of the MUMPS factor a path used; -1 when the path factored
 * nothing with MUMPS. Through PCREDUNDANT: every rank's own factor of the
 * whole matrix, the same on each. */
PetscErrorCode BwSolverMumpsInfog(KSP ksp, PetscInt i, PetscInt *value)
{
  PC  pc;
  Mat A;

  PetscFunctionBeginUser;
  *value = -1;
  PetscCall(BwSolverGetFactorPC(ksp, &pc, &A));
  if (!pc) PetscFunctionReturn(PETSC_SUCCESS);
#if defined(PETSC_HAVE_MUMPS)
  {
    Mat           F;
    MatSolverType type;
    PetscBool     mumps, redundant;
    PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCREDUNDANT, &redundant));
    if (redundant) {
      KSP rksp;
      PetscCall(PCRedundantGetKSP(pc, &rksp));
      PetscCall(KSPGetPC(rksp, &pc));
    }
    PetscCall(PCFactorGetMatrix(pc, &F));
    PetscCall(MatFactorGetSolverType(F, &type));
    PetscCall(PetscStrcmp(type, MATSOLVERMUMPS, &mumps));
    if (mumps) PetscCall(MatMumpsGetInfog(F, i, value));
  }
#endif
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Null pivots MUMPS found (INFOG(28)) in the factorisation a path used; 0
 * when the path factored nothing with MUMPS. */
PetscErrorCode BwSolverNullPivots(KSP ksp, PetscInt *npiv)
{
  PetscFunctionBeginUser;
  PetscCall(BwSolverMumpsInfog(ksp, 28, npiv));
  if (*npiv < 0) *npiv = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* |A| |x| for an assembled AIJ matrix (others are converted): the size of
 * the terms a product with A sums, which bounds the round-off of a
 * residual and of the factorisation row by row. */
static PetscErrorCode BwMatAbsMult(Mat A, Vec x, Vec y)
{
  Mat       B;
  Vec       ax;
  PetscBool mpi, seq;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)A, MATMPIAIJ, &mpi));
  PetscCall(PetscObjectTypeCompare((PetscObject)A, MATSEQAIJ, &seq));
  if (mpi || seq) PetscCall(MatDuplicate(A, MAT_COPY_VALUES, &B));
  else PetscCall(MatConvert(A, MATAIJ, MAT_INITIAL_MATRIX, &B));
  PetscCall(PetscObjectTypeCompare((PetscObject)B, MATMPIAIJ, &mpi));
  {
    Mat       parts[2] = {B, NULL};
    PetscInt  nparts   = 1;
    if (mpi) {
      PetscCall(MatMPIAIJGetSeqAIJ(B, &parts[0], &parts[1], NULL));
      nparts = 2;
    }
    for (PetscInt k = 0; k < nparts; k++) {
      PetscScalar *v;
      MatInfo      info;
      PetscCall(MatGetInfo(parts[k], MAT_LOCAL, &info));
      PetscCall(MatSeqAIJGetArray(parts[k], &v));
      for (PetscInt i = 0; i < (PetscInt)info.nz_used; i++) v[i] = PetscAbsScalar(v[i]);
      PetscCall(MatSeqAIJRestoreArray(parts[k], &v));
    }
  }
  PetscCall(VecDuplicate(x, &ax));
  PetscCall(VecCopy(x, ax));
  PetscCall(VecAbs(ax));
  PetscCall(MatMult(B, ax, y));
  PetscCall(VecDestroy(&ax));
  PetscCall(MatDestroy(&B));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* What the estimates are relative to: the largest displacement of x in
 * their norm (W), prescribed values included. */
static PetscErrorCode BwSolverDisplacementSize(BwSolver s, Vec x, PetscReal *qn)
{
  IS  isq;
  Vec xq;

  PetscFunctionBeginUser;
  PetscCall(BwMixedGetFields(s->mx, NULL, &isq));
  PetscCall(VecGetSubVector(x, isq, &xq));
  PetscCall(VecPointwiseMult(s->fw_work, xq, s->fw_weight));
  PetscCall(VecNorm(s->fw_work, NORM_INFINITY, qn));
  PetscCall(VecRestoreSubVector(x, isq, &xq));
  *qn = PetscMax(*qn, s->fw_prescribed);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A bound on the displacement error that round-off leaves in a solution x
 * of the mixed system K~ x = b, however the refinement went (LAPACK's
 * xGERFS forward error bound, FERR). The refinement's fixed point is
 * limited by the round-off of the residual it computes, |dr| <= (nz + 1)
 * eps |K~| |x| row by row, so
 *   |x - x*| <= |K~^-1| g,   g = (nz + 1) eps |K~| |x|,
 * and || W |K~^-1| g ||_inf = || diag(g) K~^-T W ||_1 is estimated with
 * Hager-Higham's iteration, which needs products with that matrix and its
 * transpose: each is one application of the path's preconditioner (the
 * exact Schur factorisation, or the factor of K~ on the direct path). W
 * keeps the displacement rows with the weights of the refinement's
 * estimate, so the two estimates are in the same norm. Why it is needed:
 * at the round-off floor of an ill-conditioned system the refinement's
 * corrections are the noise of the residual, not the error (a stiff
 * cluster on a soft joint: corrections of 4e-9 where the error was 4.4e-7,
 * and on another CPU they passed a test this one failed); the bound is
 * what the residual's round-off allows, on every CPU. Not a bound on the
 * Schur complement alone: S^'s own round-off is corrected by the
 * refinement, and bounding with it claimed 2e-5 on walls right to 1e-15.
 * Only where the condition estimate runs (trouble seen), as K~ is
 * assembled for |K~|. */
/* The path's preconditioner as an inverse of the whole system. */
static PetscErrorCode BwPathApplyInverse(BwPath *path, PC pc, Vec z, Vec y)
{
  PetscFunctionBeginUser;
  if (path->qspace) PetscCall(BwSchurPCApplyFull(pc, z, y));
  else PetscCall(PCApply(pc, z, y));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSolverForwardBound(BwSolver s, BwPath *path, Vec x, PetscReal *ferr)
{
  Vec       xa, g, v, y, w, wq, xq;
  IS        isq = NULL;
  PetscInt  N, nzmax = 0, rlo, rhi;
  PetscReal est = 0, ynorm, qn;
  PetscBool sub, symmetric = PETSC_FALSE, set;
  PC        pc;
  Mat       A, Aown = NULL;

  PetscFunctionBeginUser;
  PetscCall(BwSolverForwardSetUp(s));
  PetscCall(KSPGetPC(path->ksp, &pc));
  PetscCall(PCGetOperators(pc, &A, NULL));
  /* a fieldsplit path refines on q: its PC inverts S~, and the bound is on
   * the whole system (assembled here), through the Schur PC's elimination */
  set = PETSC_FALSE;
  if (!path->qspace) PetscCall(PetscObjectTypeCompareAny((PetscObject)A, &set, MATSEQAIJ, MATMPIAIJ, ""));
  if (!set) {
    PetscCall(BwMixedCreateAIJ(s->mx, &Aown));
    A = Aown;
  }
  /* the mixed operator is symmetric where the joints' tangents are */
  symmetric = s->symmetric;
  PetscCall(MatCreateVecs(A, &xa, &g));
  PetscCall(VecDuplicate(xa, &v));
  PetscCall(VecDuplicate(xa, &y));
  PetscCall(VecDuplicate(xa, &w));
  PetscCall(VecGetSize(xa, &N));
  /* the solution and the weights in A's space */
  {
    PetscInt nx;
    PetscCall(VecGetSize(x, &nx));
    sub = nx == N ? PETSC_TRUE : PETSC_FALSE; /* A is the whole system */
  }
  PetscCall(BwMixedGetFields(s->mx, NULL, &isq));
  if (sub) {
    PetscCall(VecCopy(x, xa));
    PetscCall(VecZeroEntries(w));
    PetscCall(VecGetSubVector(w, isq, &wq));
    PetscCall(VecCopy(s->fw_weight, wq));
    PetscCall(VecRestoreSubVector(w, isq, &wq));
  } else {
    PetscCall(VecGetSubVector(x, isq, &xq));
    PetscCall(VecCopy(xq, xa));
    PetscCall(VecRestoreSubVector(x, isq, &xq));
    PetscCall(VecCopy(s->fw_weight, w));
  }
  PetscCall(BwSolverDisplacementSize(s, x, &qn));
  /* g = (nz + 1) eps |A| |x| */
  PetscCall(MatGetOwnershipRange(A, &rlo, &rhi));
  for (PetscInt i = rlo; i < rhi; i++) {
    PetscInt ncols;
    PetscCall(MatGetRow(A, i, &ncols, NULL, NULL));
    nzmax = PetscMax(nzmax, ncols);
    PetscCall(MatRestoreRow(A, i, &ncols, NULL, NULL));
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &nzmax, 1, MPIU_INT, MPI_MAX, PetscObjectComm((PetscObject)A)));
  PetscCall(BwMatAbsMult(A, xa, g));
  PetscCall(VecScale(g, (nzmax + 1) * PETSC_MACHINE_EPSILON));
  /* Hager-Higham on M = diag(g) A^-T W: M v = g .* A^-T (w .* v), M^T v = w .* A^-1 (g .* v) */
  PetscCall(VecSet(v, 1.0 / N));
  for (PetscInt k = 0; k < BW_CONDITION_ITERATIONS; k++) {
    PetscBool stop;
    PetscCall(VecPointwiseMult(y, w, v));
    if (symmetric) PetscCall(BwPathApplyInverse(path, pc, y, xa));
    else PetscCall(PCApplyTranspose(pc, y, xa));
    PetscCall(VecPointwiseMult(y, g, xa));
    PetscCall(VecNorm(y, NORM_1, &ynorm));
    if (k > 0 && ynorm <= est) break;
    est = ynorm;
    PetscCall(BwHagerSigns(y));
    PetscCall(VecPointwiseMult(y, g, y));
    PetscCall(BwPathApplyInverse(path, pc, y, xa));
    PetscCall(VecPointwiseMult(xa, w, xa));
    PetscCall(BwHagerNext(xa, v, k, &stop));
    if (stop) break;
  }
  *ferr = qn > 0 ? est / qn : (est > 0 ? PETSC_INFINITY : 0);
  PetscCall(VecDestroy(&xa));
  PetscCall(VecDestroy(&g));
  PetscCall(VecDestroy(&v));
  PetscCall(VecDestroy(&y));
  PetscCall(VecDestroy(&w));
  PetscCall(MatDestroy(&Aown));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The same bound for a system too large to assemble (3D walls above 1e6
 * rows of K~), through the factor of S^ and D^ held by its structure
 * (BwMixedRoundoff*, operator.c): || W (|S~^-1 D^T| h_r + |S~^-1| h_q)
 * ||_inf, h the residual plus its round-off gamma (|K~| |x| + |b|) by
 * rows, estimated as the 1-norm of M = [diag(h_r) D^; diag(h_q)] S~^-T W
 * with Hager-Higham's iteration: each step one solve with the factor and
 * its transpose, and a pass over the stress rows that forms h_r on the
 * fly, so that nothing of the stresses' size is stored
 * (-solver_forward_bound schur). Where the normwise bound cond(S^) eps
 * claimed 1.3e-6 and 3.6e-4 on bench/large_wall3d.yaml at 1e4 and 1e5
 * blocks (bending out of its plane, condition estimate 1.6e12 at 1e5), it
 * gives 3.5e-9 and 3.0e-7 (0.15 and ~1.1 s, two Hager-Higham steps). Still
 * a worst case: on such an axis-parallel wall most products are by 0 or
 * +-1 and exact, and CHOLMOD on 1 rank, MUMPS on 2, CG + GAMG and D^
 * assembled (other roundings) agree to 2.6e-14 at 1e5 blocks; auto takes
 * the extra-precise estimate below. tests/dim3/check_forward_bound.py
 * compares it with the whole system's bound. */
PetscErrorCode BwSolverForwardBoundSchur(BwSolver s, PC fpc, PetscBool symmetric, Vec b, Vec x, PetscReal *ferr)
{
  Vec       hq, v, t, acc, y;
  PetscInt  N;
  PetscReal gamma, est = 0, l1r, ynorm, qn;

  PetscFunctionBeginUser;
  PetscCall(BwSolverForwardSetUp(s));
  PetscCall(VecDuplicate(s->fw_weight, &hq));
  PetscCall(VecDuplicate(hq, &v));
  PetscCall(VecDuplicate(hq, &t));
  PetscCall(VecDuplicate(hq, &acc));
  PetscCall(VecDuplicate(hq, &y));
  PetscCall(BwMixedRoundoffQ(s->mx, x, b, hq, &gamma));
  PetscCall(BwSolverDisplacementSize(s, x, &qn));
  PetscCall(VecGetSize(v, &N));
  PetscCall(VecSet(v, 1.0 / N));
  for (PetscInt k = 0; k < BW_CONDITION_ITERATIONS; k++) {
    PetscReal l1q;
    PetscBool stop;
    /* M v: t = S~^-T (W v); (h_r .* D^ t, h_q .* t) */
    PetscCall(VecPointwiseMult(y, s->fw_weight, v));
    if (symmetric) PetscCall(PCApply(fpc, y, t));
    else PetscCall(PCApplyTranspose(fpc, y, t));
    PetscCall(BwMixedRoundoffSweep(s->mx, x, b, gamma, t, acc, &l1r));
    PetscCall(VecPointwiseMult(y, hq, t));
    PetscCall(VecNorm(y, NORM_1, &l1q));
    ynorm = l1r + l1q;
    if (k > 0 && ynorm <= est) break;
    est = ynorm;
    /* M^T sign(M v) = W S~^-1 (D^T (h_r .* sign) + h_q .* sign) */
    PetscCall(BwHagerSigns(y));
    PetscCall(VecPointwiseMult(y, hq, y));
    PetscCall(VecAXPY(y, 1.0, acc));
    PetscCall(PCApply(fpc, y, t));
    PetscCall(VecPointwiseMult(t, s->fw_weight, t));
    PetscCall(BwHagerNext(t, v, k, &stop));
    if (stop) break;
  }
  *ferr = qn > 0 ? est / qn : (est > 0 ? PETSC_INFINITY : 0);
  PetscCall(VecDestroy(&hq));
  PetscCall(VecDestroy(&v));
  PetscCall(VecDestroy(&t));
  PetscCall(VecDestroy(&acc));
  PetscCall(VecDestroy(&y));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* An estimate of the displacement error from one residual computed in
 * double-double (BwMixedResidualExtra, far below double's round-off):
 * S~^-1 r_q is the error of x_q to first order (extra-precise iterative
 * refinement's measure: Demmel, Hida, Kahan, Li, Mukherjee, Riedy, "Error
 * bounds from extra-precise iterative refinement", ACM TOMS 32, 2006).
 * Not a bound: the factor's solve is itself off by the refinement's
 * contraction where S^ is ill-conditioned; over the stability suite's
 * extreme cases (tests/stability, the true error from a real128 solve) it
 * was within 1.5x of the true error where cond(K~) < 1e6, and off by up to
 * 5.6x on the stiff clusters (cluster_1e6 6.4e-11 against 2.8e-10,
 * cluster_1e12 6.2e-5 against 3.5e-4), hence the factor 10 the estimate
 * carries. It does not see rounded data (a wall 1e6 m from the origin, its
 * lever arms rounded: 2e-16 against 5e-10), which no residual does. Where
 * the worst-case bound through the factor claimed 3.0e-7 on the bench's 3D
 * wall of 1e5 blocks, this gives 1.7e-14, as the spread of four solvers and
 * arithmetics there (2.6e-14) says. */
PetscErrorCode BwSolverForwardExtra(BwSolver s, PC fpc, Vec b, Vec x, PetscReal *ferr)
{
  Vec       r, t;
  PetscReal emax, qn;

  PetscFunctionBeginUser;
  PetscCall(BwSolverForwardSetUp(s));
  PetscCall(VecDuplicate(s->fw_weight, &r));
  PetscCall(VecDuplicate(r, &t));
  PetscCall(BwMixedResidualExtra(s->mx, x, b, r));
  PetscCall(PCApply(fpc, r, t));
  PetscCall(VecPointwiseMult(t, s->fw_weight, t));
  PetscCall(VecNorm(t, NORM_INFINITY, &emax));
  PetscCall(BwSolverDisplacementSize(s, x, &qn));
  *ferr = qn > 0 ? BW_EXTRA_SAFETY * emax / qn : (emax > 0 ? PETSC_INFINITY : 0);
  PetscCall(VecDestroy(&r));
  PetscCall(VecDestroy(&t));
  PetscFunctionReturn(PETSC_SUCCESS);
}
