/* The paper's two stacked blocks (section 3): block 0 = [0,l] x [0,a],
 * block 1 = [0,l] x [a+e, 2a+e], one interface (0,1) with G = (l/2, a+e/2)
 * and theta = 0. Sets: bottom = {0}, top = {1}. */
#include "geometry/geometry.h"
#include "util/compat.h"

PetscErrorCode BwGeneratorTwoBlocks(BwGeometry g, BwScene scene, PetscReal e)
{
  PetscReal       l = 0.2, a = 0.1;
  const PetscInt  bottom = 0, top = 1;
  PetscReal       G[2];

  PetscFunctionBeginUser;
  PetscOptionsBegin(g->comm, NULL, "Two stacked blocks (scene key geometry.two_blocks.*)", NULL);
  PetscCall(PetscOptionsReal("-geometry_two_blocks_length", "Block and interface length l [m]", NULL, l, &l, NULL));
  PetscCall(PetscOptionsReal("-geometry_two_blocks_height", "Height a of both blocks [m]", NULL, a, &a, NULL));
  PetscOptionsEnd();
  if (!(l > 0 && PetscIsNormalReal(l))) PetscCall(BwSceneError(scene, "-geometry_two_blocks_length", "must be > 0, got %g", (double)l));
  if (!(a > 0 && PetscIsNormalReal(a))) PetscCall(BwSceneError(scene, "-geometry_two_blocks_height", "must be > 0, got %g", (double)a));

  PetscCall(BwGeometryAddRectangle(g, 0, 0, l, a, NULL));
  PetscCall(BwGeometryAddRectangle(g, 0, a + e, l, 2 * a + e, NULL));
  G[0] = l / 2;
  G[1] = a + e / 2;
  PetscCall(BwGeometryAddInterface(g, 0, 1, G, 0.0, l, BW_JOINT_BED));
  PetscCall(BwGeometryAddSet(g, "bottom", 1, &bottom));
  PetscCall(BwGeometryAddSet(g, "top", 1, &top));
  PetscFunctionReturn(PETSC_SUCCESS);
}
