/* Load, unload and reload a block on a sliding joint through BwNewton
 * under displacement control (tests/unit/newton_block.yaml): the pushover
 * contract has no cycles, the solver does, and plasticity must unload
 * elastically.
 *
 *   loading    two elastic points give the initial stiffness k0 (dlambda/du),
 *              which is kt A (the moment-free push shears the joint only);
 *              at u = 5 and 10 um the joint slides at lambda = c A + N tan(phi)
 *              = 950 N exactly (1e-10)
 *   unloading  back to 9 and 8 um: lambda = 950 - k0 (10 um - u), the initial
 *              stiffness (1e-8: the elastic range spans 2 * 950 / k0)
 *   reverse    back to 5 um: sliding the other way, lambda = -950 (1e-10)
 *   reloading  to 6 um: -950 + k0 * 1 um (1e-8), and to 14 um: 950 again
 * Run on 1 and 2 ranks. */
#include <petscksp.h>
#include "scene/scene.h"
#include "model/model.h"
#include "analysis/analysis.h"
#include "analysis/newton.h"
#include "util/compat.h"
#include "expect.h"
#include "util/process.h"


/* lambda at monitor u (one converged solve, committed). */
static PetscErrorCode Go(BwNewton nw, PetscReal u, PetscReal *lambda)
{
  PetscBool ok;
  PetscReal mon;

  PetscFunctionBeginUser;
  PetscCall(BwNewtonSolve(nw, 1.0, lambda, PETSC_TRUE, u, &ok));
  if (!ok) {
    const char *why;
    PetscCall(BwNewtonGetResult(nw, NULL, NULL, &why));
    SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_NOT_CONVERGED, "no equilibrium at u = %g: %s", (double)u, why);
  }
  PetscCall(BwNewtonCommit(nw));
  PetscCall(BwNewtonMonitorValue(nw, &mon));
  PetscCheck(PetscAbsReal(mon - u) <= 1e-12 * PetscAbsReal(u) + 1e-20, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "monitor %g, asked %g", (double)mon, (double)u);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "u = %5.2f um: lambda = %.12g\n", (double)(u * 1e6), (double)*lambda));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  BwProblem    p;
  BwLog        log;
  BwNewton     nw;
  PetscReal   *pattern, lam = 0, l1, l2, k0, cap = 950, um = 1e-6;
  PetscInt     top, gtop, substeps;
  PetscBool    ok;
  char         path[PETSC_MAX_PATH_LEN];

  BwProcessDefaults(); /* the libraries run as under blockwall */

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscMemzero(&p, sizeof(p)));
  p.comm = PETSC_COMM_WORLD;
  PetscCall(BwLogCreate(p.comm, &log));
  p.log = &log;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", path, sizeof(path), NULL));
  PetscCall(BwSceneCreate(p.comm, &p.scene));
  PetscCall(BwSceneLoad(p.scene, path));
  PetscCall(BwModelCreate(p.comm, &p.model));
  PetscCall(BwModelSetFromOptions(p.model, p.scene));
  PetscCall(BwGeometryCreate(p.comm, &p.geom));
  PetscCall(BwGeometrySetFromOptions(p.geom, p.scene));
  PetscCall(BwGeometrySetUp(p.geom, p.scene, p.model->law[BW_JOINT_BED]->thickness));
  PetscCall(BwGeometryDistribute(p.geom, BW_PARTITION_AUTO));
  PetscCall(BwModelSetUp(p.model, p.geom, p.scene));
  PetscCall(BwSolverCreate(p.comm, &p.solver));
  PetscCall(BwSolverSetFromOptions(p.solver, p.scene));
  PetscCall(BwAnalysisSolverForJoints(&p));
  PetscCall(BwMixedCreate(p.model, &p.mixed));
  PetscCall(BwMixedSetUp(p.mixed, BW_STORAGE_SHELL));
  PetscCall(BwSolverSetUp(p.solver, p.mixed));

  /* the pattern: a horizontal force at the joint's level (moment-free) */
  /* the top block: its global id on every rank, its pattern on its owner */
  PetscCall(BwGeometryFindSet(p.geom, "top", &top));
  PetscCall(BwGeometrySetFirst(p.geom, top, &gtop, &top));
  PetscCall(PetscCalloc1(3 * p.geom->nblocks, &pattern));
  if (top >= 0 && top < p.geom->nown_blocks) {
    pattern[3 * top]     = 1;
    pattern[3 * top + 2] = 0.055;
  }
  PetscCall(BwNewtonCreate(&p, p.model->load, pattern, &nw));
  PetscCall(BwNewtonSetTolerances(nw, 1e-10, 40));
  PetscCall(BwNewtonSetMonitor(nw, gtop, 0));
  PetscCall(BwNewtonRamp(nw, 1e-3, &substeps, &ok));
  PetscCheck(ok, p.comm, PETSC_ERR_PLIB, "the block does not carry its load");

  PetscCall(Go(nw, 0.25 * um, &l1));
  lam = l1;
  PetscCall(Go(nw, 0.5 * um, &lam));
  l2 = lam;
  k0 = (l2 - l1) / (0.25 * um);
  EXPECT(PetscAbsReal(k0 - 4.0e10 * 0.02) <= 1e-10 * k0, "initial stiffness %.12g, kt A = %g", (double)k0, 4.0e10 * 0.02);
  EXPECT(PetscAbsReal(l2 / (0.5 * um) - k0) <= 1e-8 * k0, "the first points are not on one line through the origin: %g, %g", (double)k0, (double)(l2 / (0.5 * um)));
  PetscCall(Go(nw, 5 * um, &lam));
  EXPECT(PetscAbsReal(lam - cap) <= 1e-10 * cap, "sliding at %.12g, expected %g", (double)lam, (double)cap);
  PetscCall(Go(nw, 10 * um, &lam));
  EXPECT(PetscAbsReal(lam - cap) <= 1e-10 * cap, "sliding at %.12g, expected %g", (double)lam, (double)cap);
  for (PetscReal u = 9; u >= 8; u -= 1) {
    PetscCall(Go(nw, u * um, &lam));
    EXPECT(PetscAbsReal(lam - (cap - k0 * (10 - u) * um)) <= 1e-8 * cap, "unloading to %g um: %.12g, elastic would be %.12g", (double)u, (double)lam, (double)(cap - k0 * (10 - u) * um));
  }
  PetscCall(Go(nw, 5 * um, &lam));
  EXPECT(PetscAbsReal(lam + cap) <= 1e-10 * cap, "reverse sliding at %.12g, expected %g", (double)lam, (double)-cap);
  PetscCall(Go(nw, 6 * um, &lam));
  EXPECT(PetscAbsReal(lam - (-cap + k0 * um)) <= 1e-8 * cap, "reloading to 6 um: %.12g, elastic would be %.12g", (double)lam, (double)(-cap + k0 * um));
  PetscCall(Go(nw, 14 * um, &lam));
  EXPECT(PetscAbsReal(lam - cap) <= 1e-10 * cap, "sliding again at %.12g, expected %g", (double)lam, (double)cap);
  PetscCall(PetscPrintf(p.comm, "initial stiffness %.6e N/m; unloading and reloading on it, sliding at +-%g N\n", (double)k0, (double)cap));

  PetscCall(PetscFree(pattern));
  PetscCall(BwNewtonDestroy(&nw));
  PetscCall(BwSolverDestroy(&p.solver));
  PetscCall(BwMixedDestroy(&p.mixed));
  PetscCall(BwModelDestroy(&p.model));
  PetscCall(BwGeometryDestroy(&p.geom));
  PetscCall(BwSceneDestroy(&p.scene));
  PetscCall(PetscFinalize());
  return bw_failures ? 1 : 0;
}
