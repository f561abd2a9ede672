/* BwMixedCheckMechanism, the numerical mechanism check a solver calls when
 * it meets a singular matrix, on a mechanism the static checks of
 * BwMixedCheckRestraint cannot see:
 *
 *   block 0  ground, all dofs prescribed
 *   1, 2, 3  a parallelogram four-bar: hinges 0-1 at (0,0), 1-2 at (0,1),
 *            2-3 at (1,1), 0-3 at (1,0); it sways: 1 turns about (0,0),
 *            2 translates along x, 3 turns about (1,0)
 *   block 4  held by three hinges to the ground at (2,0), (3,0), (2.5,0):
 *            rigid, with three more constraints than it needs
 *
 * With m = 1 every interface is a hinge. The group has 12 free dofs and 14
 * hinge equations, so the count of BwMixedCheckRestraint passes, and no
 * block hangs on a single point: the sway is found only numerically.
 *
 *   test_mechanism sway      m = 1: the error names blocks 1, 2, 3 and their motions
 *   test_mechanism sound     m = 2: the same assembly is restrained, no error
 *   test_mechanism verdict   the decision on the Rayleigh quotient: the four-bar's
 *                            quotients as measured on two CPUs (+7.6e-18 AMD,
 *                            -2.9e-17 Intel, ||S^|| = 1) are mechanisms whatever
 *                            their sign; a 1e12 contrast's 1e-13 and NaN are not
 *   test_mechanism scene -scene S.yaml [options]
 *                            the scene's assembly as blockwall builds it, then
 *                            the check: exit 1 and the error line on stderr
 *                            if it is a mechanism, exit 0 if not (for
 *                            check_mechanism.py)
 */
#include <math.h>
#include <string.h>
#include <hdf5.h>
#include "system/mixed.h"
#include "util/compat.h"
#include "util/process.h"

/* Declared in system/mixed.h once the solver calls it (see restraint.c). */

static PetscErrorCode BwBuild(MPI_Comm comm, PetscInt m, BwGeometry *geom, BwModel *model)
{
  BwGeometry      g;
  const PetscReal hinge[7][2] = {{0, 0}, {0, 1}, {1, 1}, {1, 0}, {2, 0}, {3, 0}, {2.5, 0}};
  const PetscInt  pair[7][2]  = {{0, 1}, {1, 2}, {2, 3}, {0, 3}, {0, 4}, {0, 4}, {0, 4}};

  PetscFunctionBeginUser;
  PetscCall(BwGeometryCreate(comm, geom));
  g = *geom;
  PetscCall(BwGeometryAddRectangle(g, -1, -1, 4, -0.01, NULL)); /* 0 ground */
  PetscCall(BwGeometryAddRectangle(g, -0.1, 0.01, 0.1, 0.99, NULL)); /* 1 left post */
  PetscCall(BwGeometryAddRectangle(g, 0, 1.01, 1, 1.2, NULL));       /* 2 beam */
  PetscCall(BwGeometryAddRectangle(g, 0.9, 0.01, 1.1, 0.99, NULL));  /* 3 right post */
  PetscCall(BwGeometryAddRectangle(g, 2, 0.01, 3, 1, NULL));         /* 4 braced block */
  for (PetscInt k = 0; k < 7; k++) PetscCall(BwGeometryAddInterface(g, pair[k][0], pair[k][1], hinge[k], 0.0, 0.1, BW_JOINT_BED));
  PetscCall(BwGeometryComputeCentroids(g));
  /* one rank's share is the whole assembly (this test runs on one) */
  PetscCall(BwGeometrySetShare(g, g->nblocks));
  g->ninterfaces_global = g->ninterfaces;
  PetscCall(BwGeometryDistribute(g, BW_PARTITION_NATURAL));
  PetscCall(BwModelCreate(comm, model));
  PetscCall(BwModelAllocate(*model, g));
  PetscCall(BwJointLawCreate(&(*model)->law[BW_JOINT_BED])); /* elastic, its stiffness per interface below */
  (*model)->m = m;
  for (PetscInt k = 0; k < g->ninterfaces; k++) {
    (*model)->kn[k] = 1e9;
    (*model)->kt[k] = 4e8;
  }
  for (PetscInt c = 0; c < 3; c++) (*model)->prescribed[c] = PETSC_TRUE;
  (*model)->load[3 * 2] = 1000;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The driver's steps 1, 2 and 4 (scene, joint laws, geometry, model, layout
 * and assembly), then the check. */
static PetscErrorCode BwScene_(MPI_Comm comm, BwScene *scene, BwGeometry *geom, BwModel *model, BwMixed *mx)
{
  char path[PETSC_MAX_PATH_LEN] = "";

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", path, sizeof(path), NULL));
  PetscCall(BwSceneCreate(comm, scene));
  PetscCall(BwSceneLoad(*scene, path));
  PetscCall(BwModelCreate(comm, model));
  PetscCall(BwModelSetFromOptions(*model, *scene));
  PetscCall(BwGeometryCreate(comm, geom));
  PetscCall(BwGeometrySetFromOptions(*geom, *scene));
  PetscCall(BwGeometrySetUp(*geom, *scene, (*model)->law[BW_JOINT_BED]->thickness));
  PetscCall(BwGeometryDistribute(*geom, BW_PARTITION_AUTO));
  PetscCall(BwModelSetUp(*model, *geom, *scene));
  PetscCall(BwMixedCreate(*model, mx));
  PetscCall(BwMixedSetUp(*mx, BW_STORAGE_SHELL));
  PetscCall(BwMixedCheckMechanism(*mx, "test"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  BwGeometry     geom  = NULL;
  BwModel        model = NULL;
  BwMixed        mx    = NULL;
  PetscErrorCode ierr;
  char           which[32] = "sway";
  int            fail      = 0;

  BwProcessDefaults(); /* the libraries run as under blockwall */

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  if (argc > 1) PetscCall(PetscStrncpy(which, argv[1], sizeof(which)));
  if (!strcmp(which, "scene")) {
    BwScene     scene = NULL;
    PetscMPIInt rank;
    PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    ierr = BwScene_(PETSC_COMM_WORLD, &scene, &geom, &model, &mx);
    PetscCall(PetscPopErrorHandler());
    PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
    if (ierr) {
      const char *msg = BwErrorText(ierr);
      if (!rank) fprintf(stderr, "test_mechanism: error: %s\n", msg[0] ? msg : "unknown");
      fail = ierr == PETSC_ERR_USER_INPUT ? 1 : 2;
    } else PetscCall(PetscPrintf(PETSC_COMM_WORLD, "no mechanism\n"));
    PetscCall(BwMixedDestroy(&mx));
    PetscCall(BwModelDestroy(&model));
    PetscCall(BwGeometryDestroy(&geom));
    PetscCall(BwSceneDestroy(&scene));
    PetscCall(PetscFinalize());
    return fail;
  }
  if (!strcmp(which, "verdict")) {
    const PetscReal rho[6]  = {7.6e-18, -2.9e-17, 0.0, 1e-13, -1e-13, NAN};
    const PetscBool want[6] = {PETSC_TRUE, PETSC_TRUE, PETSC_TRUE, PETSC_FALSE, PETSC_FALSE, PETSC_FALSE};
    for (int k = 0; k < 6; k++)
      if (BwMechanismVerdict(rho[k], 1.0) != want[k]) {
        fprintf(stderr, "FAIL: Rayleigh quotient %g of ||S^|| = 1: verdict %s, expected %s\n", (double)rho[k], want[k] ? "sound" : "mechanism", want[k] ? "mechanism" : "sound");
        fail = 1;
      }
    PetscCall(PetscFinalize());
    return fail;
  }
  if (strcmp(which, "sway") && strcmp(which, "sound")) { /* not another case's checks under a mistyped name */
    fprintf(stderr, "FAIL unknown case %s\n", which);
    PetscCall(PetscFinalize());
    return 1;
  }
  PetscCall(BwBuild(PETSC_COMM_WORLD, strcmp(which, "sound") ? 1 : 2, &geom, &model));
  PetscCall(BwMixedCreate(model, &mx)); /* the static checks pass */
  PetscCall(BwMixedSetUp(mx, BW_STORAGE_SHELL));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = BwMixedCheckMechanism(mx, "test");
  PetscCall(PetscPopErrorHandler());
  if (!strcmp(which, "sound")) {
    if (ierr) {
      fprintf(stderr, "FAIL: a restrained assembly was reported as a mechanism\n");
      fail = 1;
    }
  } else {
    const char *msg = BwErrorText(ierr);
    const char *want[] = {"mechanism (test)", "blocks 1, 2, 3 (3 blocks)", "block 1 rotates about (0, 0)", "block 2 translates along (", "block 3 rotates about (1, 0)"};
    if (ierr != PETSC_ERR_USER_INPUT || !msg[0]) {
      fprintf(stderr, "FAIL: the four-bar sway was not reported (error %d)\n", (int)ierr);
      fail = 1;
    } else {
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s\n", msg));
      for (size_t w = 0; w < sizeof(want) / sizeof(want[0]); w++)
        if (!strstr(msg, want[w])) {
          fprintf(stderr, "FAIL: '%s' not in the message\n", want[w]);
          fail = 1;
        }
    }
  }
  PetscCall(BwMixedDestroy(&mx));
  PetscCall(BwModelDestroy(&model));
  PetscCall(BwGeometryDestroy(&geom));
  PetscCall(PetscFinalize());
  return fail;
}
