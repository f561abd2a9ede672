/* The scaled mixed system (src/system) against its own definition, on a
 * wall with prescribed dofs (identity rows), on any number of ranks:
 *
 *   schur     S^ x = D^T (T (D^ x)) + P x for random x: S^ is assembled
 *             from the condensed interface stiffness K_G (bw_interface_
 *             condense), D^ applies the rows of bw_interface_operator, so
 *             the two sides are computed by different kernels; elastic
 *             tangents, then random non-symmetric ones (each portion's
 *             2x2 tangent perturbed in all four entries). 1e-13 relative to
 *             ||S^|| ||x||: sums of a few dozen products per entry.
 *   aij       K as a shell (views of the fields) and K assembled (AIJ, what
 *             the direct path factors) agree on random vectors, both
 *             tangents. 1e-14: the same products in another order.
 *   refill    S^ refilled in place: tangents A, then B, equal S^ of a
 *             fresh system given B only; back to NULL, equal to the elastic
 *             S^ bit for bit (the same sums in the same order). The matrix
 *             object and its nonzero pattern stay the same (reuse).
 *   inverse   the Schur PC (Richardson + exact block elimination, S^
 *             Cholesky-factored) solves K y = z for random z; the answer
 *             equals an LU solve of the assembled K (a second solver):
 *             1e-10 relative, the system's condition (1e5 here) times the
 *             refinement's tolerance.
 *
 * Usage: test_system -scene wall.yaml -case schur|aij|refill|inverse */
#include <petscksp.h>
#include "scene/scene.h"
#include "model/model.h"
#include "system/mixed.h"
#include "solver/solver_impl.h"
#include "util/compat.h"
#include "expect.h"
#include "util/log.h"
#include "util/process.h"


typedef struct {
  BwScene    scene;
  BwModel    model;
  BwGeometry geom;
} BwTestProblem;

static PetscErrorCode ProblemCreate(BwTestProblem *p)
{
  char path[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", path, sizeof(path), NULL));
  PetscCall(BwSceneCreate(PETSC_COMM_WORLD, &p->scene));
  PetscCall(BwSceneLoad(p->scene, path));
  PetscCall(BwModelCreate(PETSC_COMM_WORLD, &p->model));
  PetscCall(BwModelSetFromOptions(p->model, p->scene));
  PetscCall(BwGeometryCreate(PETSC_COMM_WORLD, &p->geom));
  PetscCall(BwGeometrySetFromOptions(p->geom, p->scene));
  PetscCall(BwGeometrySetUp(p->geom, p->scene, p->model->law[BW_JOINT_BED]->thickness));
  PetscCall(BwGeometryDistribute(p->geom, BW_PARTITION_AUTO));
  PetscCall(BwModelSetUp(p->model, p->geom, p->scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ProblemDestroy(BwTestProblem *p)
{
  PetscFunctionBeginUser;
  PetscCall(BwModelDestroy(&p->model));
  PetscCall(BwGeometryDestroy(&p->geom));
  PetscCall(BwSceneDestroy(&p->scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode MixedCreate(BwTestProblem *p, BwStorage storage, BwMixed *mx)
{

  PetscFunctionBeginUser;
  PetscCall(BwMixedCreate(p->model, mx));
  PetscCall(BwMixedSetUp(*mx, storage));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Random tangents around the elastic diag(kt, kn) of each portion, the same
 * on any number of ranks (drawn per interface from its input index). */
static PetscErrorCode RandomTangents(BwMixed mx, PetscInt seed, PetscBool symmetric, PetscReal **tangent)
{
  BwMixedOwnership own;
  BwModel          model;

  PetscFunctionBeginUser;
  PetscCall(BwMixedGetOwnership(mx, &own));
  PetscCall(BwMixedGetModel(mx, &model));
  PetscCall(PetscMalloc1(4 * own.m * own.nown_interfaces + 1, tangent));
  for (PetscInt e = 0; e < own.nown_interfaces; e++) {
    PetscInt k = own.own_interfaces[e];
    for (PetscInt p = 0; p < own.m; p++) {
      PetscReal *c = *tangent + 4 * (own.m * e + p), g = PetscSqrtReal(model->kt[k] * model->kn[k]);
      /* a cheap hash: reproducible, independent of the partition */
      unsigned   h = (unsigned)(2654435761u * (unsigned)(k * 131 + p * 7 + seed * 1009 + 1));
      PetscReal  r[4];
      for (int i = 0; i < 4; i++) {
        h    = h * 1103515245u + 12345u;
        r[i] = ((h >> 8) & 0xffff) / 65535.0; /* in [0, 1] */
      }
      c[0] = model->kt[k] * (0.3 + r[0]);
      c[1] = g * 0.4 * (r[1] - 0.5);
      c[2] = g * 0.4 * (r[2] - 0.3);
      c[3] = model->kn[k] * (0.3 + r[3]);
      /* symmetric: positive definite, |c01| <= 0.2 g < sqrt(c00 c11) */
      if (symmetric) c[2] = c[1];
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ||A x - y|| / scale */
static PetscReal RelDiff(Vec a, Vec b, PetscReal scale)
{
  Vec       d;
  PetscReal n;

  VecDuplicate(a, &d);
  VecWAXPY(d, -1.0, b, a);
  VecNorm(d, NORM_2, &n);
  VecDestroy(&d);
  return n / scale;
}

static PetscErrorCode RandomVec(Vec x, PetscRandom rnd)
{
  PetscFunctionBeginUser;
  PetscCall(VecSetRandom(x, rnd));
  PetscCall(VecShift(x, -0.5));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CaseSchur(BwTestProblem *p, PetscRandom rnd)
{
  BwMixed    mx;
  Mat        S, D;
  Vec        x, y, w, r, mask;
  PetscReal *tangent, snorm, xnorm, err, worst = 0;
  IS         isr;

  PetscFunctionBeginUser;
  PetscCall(MixedCreate(p, BW_STORAGE_SHELL, &mx));
  PetscCall(RandomTangents(mx, 1, PETSC_FALSE, &tangent));
  PetscCall(BwMixedGetOperators(mx, NULL, &S, &D));
  PetscCall(BwMixedGetPrescribedMask(mx, &mask));
  PetscCall(BwMixedGetFields(mx, &isr, NULL));
  PetscCall(MatCreateVecs(S, &x, &y));
  PetscCall(VecDuplicate(y, &w));
  PetscCall(MatCreateVecs(D, NULL, &r));
  for (int pass = 0; pass < 2; pass++) {
    if (pass == 1) PetscCall(BwMixedSetTangents(mx, tangent));
    PetscCall(MatNorm(S, NORM_FROBENIUS, &snorm));
    for (int trial = 0; trial < 3; trial++) {
      PetscCall(RandomVec(x, rnd));
      PetscCall(VecNorm(x, NORM_2, &xnorm));
      PetscCall(MatMult(S, x, y));
      PetscCall(MatMult(D, x, r));
      PetscCall(BwMixedApplyTangent(mx, r));
      PetscCall(VecPointwiseMult(w, mask, x));
      PetscCall(MatMultTransposeAdd(D, r, w, w));
      err = RelDiff(y, w, snorm * xnorm);
      EXPECT(err <= 1e-13, "S^ x against D^T T D^ x + P x (%s tangents): relative difference %.3e > 1e-13", pass ? "random non-symmetric" : "elastic", (double)err);
      worst = PetscMax(worst, err);
    }
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "S^ = D^T T D^ + P to %.1e, elastic and non-symmetric tangents\n", (double)worst));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&y));
  PetscCall(VecDestroy(&w));
  PetscCall(VecDestroy(&r));
  PetscCall(PetscFree(tangent));
  PetscCall(BwMixedDestroy(&mx));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CaseAIJ(BwTestProblem *p, PetscRandom rnd)
{
  BwMixed    shell, aij;
  Mat        Ks, Ka, Ka0;
  Vec        x, ys, ya;
  PetscReal *tangent, knorm, xnorm, err, worst = 0;

  PetscFunctionBeginUser;
  PetscCall(MixedCreate(p, BW_STORAGE_SHELL, &shell));
  PetscCall(MixedCreate(p, BW_STORAGE_AIJ, &aij));
  PetscCall(RandomTangents(shell, 2, PETSC_FALSE, &tangent));
  PetscCall(BwMixedGetOperators(shell, &Ks, NULL, NULL));
  PetscCall(BwMixedGetOperators(aij, &Ka0, NULL, NULL));
  PetscCall(MatCreateVecs(Ks, &x, &ys));
  PetscCall(VecDuplicate(ys, &ya));
  for (int pass = 0; pass < 2; pass++) {
    if (pass == 1) {
      PetscCall(BwMixedSetTangents(shell, tangent));
      PetscCall(BwMixedSetTangents(aij, tangent));
    }
    PetscCall(BwMixedGetOperators(aij, &Ka, NULL, NULL));
    EXPECT(Ka == Ka0, "the assembled K was replaced by a new matrix on refill (a KSP holding it would not see the new values)");
    PetscCall(MatNorm(Ka, NORM_FROBENIUS, &knorm));
    for (int trial = 0; trial < 3; trial++) {
      PetscCall(RandomVec(x, rnd));
      PetscCall(VecNorm(x, NORM_2, &xnorm));
      PetscCall(MatMult(Ks, x, ys));
      PetscCall(MatMult(Ka, x, ya));
      err = RelDiff(ys, ya, knorm * xnorm);
      EXPECT(err <= 1e-14, "K shell against K assembled (%s tangents): relative difference %.3e > 1e-14", pass ? "random non-symmetric" : "elastic", (double)err);
      worst = PetscMax(worst, err);
    }
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "K shell = K assembled to %.1e, elastic and non-symmetric tangents\n", (double)worst));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&ys));
  PetscCall(VecDestroy(&ya));
  PetscCall(PetscFree(tangent));
  PetscCall(BwMixedDestroy(&shell));
  PetscCall(BwMixedDestroy(&aij));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CaseRefill(BwTestProblem *p)
{
  BwMixed          mx, fresh;
  Mat              S, S0, Sf, Selastic;
  PetscReal       *ta, *tb, snorm, err;
  MatInfo          info0, info1;

  PetscFunctionBeginUser;
  PetscCall(MixedCreate(p, BW_STORAGE_SHELL, &mx));
  PetscCall(MixedCreate(p, BW_STORAGE_SHELL, &fresh));
  PetscCall(RandomTangents(mx, 3, PETSC_FALSE, &ta));
  PetscCall(RandomTangents(mx, 4, PETSC_FALSE, &tb));
  PetscCall(BwMixedGetOperators(mx, NULL, &S0, NULL));
  PetscCall(MatDuplicate(S0, MAT_COPY_VALUES, &Selastic));
  PetscCall(MatGetInfo(S0, MAT_GLOBAL_SUM, &info0));

  PetscCall(BwMixedSetTangents(mx, ta));
  PetscCall(BwMixedSetTangents(mx, tb));
  PetscCall(BwMixedSetTangents(fresh, tb));
  PetscCall(BwMixedGetOperators(mx, NULL, &S, NULL));
  PetscCall(BwMixedGetOperators(fresh, NULL, &Sf, NULL));
  PetscCall(MatGetInfo(S, MAT_GLOBAL_SUM, &info1));
  EXPECT(S == S0, "S^ was replaced by a new matrix on refill");
  EXPECT(info1.nz_used == info0.nz_used, "S^'s nonzeros changed on refill: %g -> %g", info0.nz_used, info1.nz_used);
  PetscCall(MatNorm(Sf, NORM_FROBENIUS, &snorm));
  PetscCall(MatAXPY(Sf, -1.0, S, SAME_NONZERO_PATTERN));
  PetscCall(MatNorm(Sf, NORM_FROBENIUS, &err));
  err /= snorm;
  EXPECT(err <= 1e-15, "S^ refilled A then B against a fresh S^ with B: relative difference %.3e > 1e-15", (double)err);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "refilled S^ (A, then B) = fresh S^ (B) to %.1e\n", (double)err));

  PetscCall(BwMixedSetTangents(mx, NULL));
  PetscCall(MatNorm(Selastic, NORM_FROBENIUS, &snorm));
  PetscCall(MatAXPY(Selastic, -1.0, S, SAME_NONZERO_PATTERN));
  PetscCall(MatNorm(Selastic, NORM_FROBENIUS, &err));
  EXPECT(err == 0, "S^ back to elastic tangents differs from the elastic S^ by %.3e (relative)", (double)(err / snorm));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "back to elastic: S^ equal bit for bit\n"));
  PetscCall(MatDestroy(&Selastic));
  PetscCall(PetscFree(ta));
  PetscCall(PetscFree(tb));
  PetscCall(BwMixedDestroy(&mx));
  PetscCall(BwMixedDestroy(&fresh));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CaseInverse(BwTestProblem *p, PetscRandom rnd)
{
  BwMixed    mx;
  BwSolver   solver;
  Mat        K;
  Vec        z, y, ylu;
  PetscReal  err, ynorm, *tangent;
  BwLog      log;

  PetscFunctionBeginUser;
  PetscCall(BwLogCreate(PETSC_COMM_WORLD, &log));
  PetscCall(MixedCreate(p, BW_STORAGE_SHELL, &mx));
  PetscCall(RandomTangents(mx, 5, PETSC_TRUE, &tangent));
  PetscCall(BwSolverCreate(PETSC_COMM_WORLD, &solver));
  PetscCall(BwSolverSetFromOptions(solver, p->scene));
  PetscCall(BwSolverSetUp(solver, mx));
  PetscCall(BwMixedGetOperators(mx, &K, NULL, NULL));
  PetscCall(MatCreateVecs(K, &y, &z));
  PetscCall(VecDuplicate(y, &ylu));
  /* elastic, then refilled with random symmetric positive definite
   * tangents: the solver must refactor S^ (a stale factor would still
   * converge, slowly: hence the bound on the steps of refinement) */
  for (int pass = 0; pass < 2; pass++) {
    Mat Kaij;
    KSP lu;
    PC  pc;
    if (pass == 1) PetscCall(BwMixedSetTangents(mx, tangent));
    PetscCall(BwMixedCreateAIJ(mx, &Kaij));
    PetscCall(KSPCreate(PETSC_COMM_WORLD, &lu));
    PetscCall(KSPSetOptionsPrefix(lu, "test_lu_"));
    PetscCall(KSPSetOperators(lu, Kaij, Kaij));
    PetscCall(KSPSetType(lu, KSPPREONLY));
    PetscCall(KSPGetPC(lu, &pc));
    PetscCall(PCSetType(pc, PCLU));
    PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
    PetscCall(KSPSetFromOptions(lu));
    for (int trial = 0; trial < 2; trial++) {
      PetscCall(RandomVec(z, rnd));
      PetscCall(BwSolverSolve(solver, z, y, &log));
      PetscCall(KSPSolve(lu, z, ylu));
      PetscCall(VecNorm(ylu, NORM_2, &ynorm));
      err = RelDiff(y, ylu, ynorm);
      EXPECT(err <= 1e-10, "Schur-PC solve against LU of the assembled K (%s tangents): relative difference %.3e > 1e-10", pass ? "refilled" : "elastic", (double)err);
      EXPECT(solver->used == BW_METHOD_FIELDSPLIT && !solver->fallback, "the solve used %s%s", BwMethods[solver->used], solver->fallback ? " after a fallback" : "");
      EXPECT(solver->iterations <= 4, "%" PetscInt_FMT " steps of refinement with %s tangents (a stale factor?)", solver->iterations, pass ? "refilled" : "elastic");
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s tangents: K y = z by the Schur PC equals LU's y to %.1e in %" PetscInt_FMT " steps\n", pass ? "refilled" : "elastic", (double)err, solver->iterations));
    }
    PetscCall(KSPDestroy(&lu));
    PetscCall(MatDestroy(&Kaij));
  }
  PetscCall(VecDestroy(&z));
  PetscCall(VecDestroy(&y));
  PetscCall(VecDestroy(&ylu));
  PetscCall(PetscFree(tangent));
  PetscCall(BwSolverDestroy(&solver));
  PetscCall(BwMixedDestroy(&mx));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  BwTestProblem p;
  PetscRandom   rnd;
  char          which[32] = "";

  BwProcessDefaults(); /* the libraries run as under blockwall */

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-case", which, sizeof(which), NULL));
  PetscCall(ProblemCreate(&p));
  PetscCall(PetscRandomCreate(PETSC_COMM_WORLD, &rnd));
  PetscCall(PetscRandomSetSeed(rnd, 20261123));
  PetscCall(PetscRandomSeed(rnd));
  if (!strcmp(which, "schur")) PetscCall(CaseSchur(&p, rnd));
  else if (!strcmp(which, "aij")) PetscCall(CaseAIJ(&p, rnd));
  else if (!strcmp(which, "refill")) PetscCall(CaseRefill(&p));
  else if (!strcmp(which, "inverse")) PetscCall(CaseInverse(&p, rnd));
  else {
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL unknown -case %s\n", which));
    bw_failures++;
  }
  PetscCall(PetscRandomDestroy(&rnd));
  PetscCall(ProblemDestroy(&p));
  PetscCall(PetscFinalize());
  return bw_failures ? 1 : 0;
}
