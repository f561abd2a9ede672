/* The paper's two stacked blocks (section 3): block 0 = [0,l] x [0,a],
 * block 1 = [0,l] x [a+e, 2a+e], one interface (0,1) with G = (l/2, a+e/2)
 * and theta = 0. Sets: bottom = {0}, top = {1}. */
#include "geometry/geometry.h"
#include "util/compat.h"

typedef struct {
  PetscReal l, a;
} BwTwoBlocks;

static PetscErrorCode BwTwoBlocksSetFromOptions(BwGenerator gen, BwGeometry g, BwScene scene)
{
  BwTwoBlocks *o = (BwTwoBlocks *)gen->data;

  PetscFunctionBeginUser;
  PetscCall(BwSceneHelpSection(scene, "Two stacked blocks (scene key geometry.two_blocks.*)"));
  PetscCall(BwSceneRequireMapping(scene, "-geometry_two_blocks", "length, height"));
  PetscCall(BwSceneReal(scene, "-geometry_two_blocks_length", "Block and interface length l [m]", &o->l, NULL));
  PetscCall(BwSceneReal(scene, "-geometry_two_blocks_height", "Height a of both blocks [m]", &o->a, NULL));
  if (!(o->l > 0)) PetscCall(BwSceneError(scene, "-geometry_two_blocks_length", "must be > 0, got %g", (double)o->l));
  if (!(o->a > 0)) PetscCall(BwSceneError(scene, "-geometry_two_blocks_height", "must be > 0, got %g", (double)o->a));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The share of this rank (geometry.h): its blocks of the two, and the
 * interface where block 0 is. */
static PetscErrorCode BwTwoBlocksGenerate(BwGenerator gen, BwGeometry g, BwScene scene, PetscReal e)
{
  const BwTwoBlocks *o = (BwTwoBlocks *)gen->data;
  const PetscReal    l = o->l, a = o->a;
  const PetscInt     bottom = 0, top = 1;
  PetscInt           b0, b1;
  PetscReal          G[2];

  PetscFunctionBeginUser;
  BwGeometrySplit(g->comm, 2, &b0, &b1);
  if (b0 <= 0 && 0 < b1) PetscCall(BwGeometryAddRectangle(g, 0, 0, l, a, NULL));
  if (b0 <= 1 && 1 < b1) PetscCall(BwGeometryAddRectangle(g, 0, a + e, l, 2 * a + e, NULL));
  PetscCall(BwGeometrySetShare(g, b1 - b0));
  G[0] = l / 2;
  G[1] = a + e / 2;
  if (b0 == 0 && b1 > 0) PetscCall(BwGeometryAddInterface(g, 0, 1, G, 0.0, l, BW_JOINT_BED));
  g->ninterfaces_global = 1;
  PetscCall(BwGeometryAddSet(g, "bottom", b0 <= 0 && 0 < b1 ? 1 : 0, &bottom));
  PetscCall(BwGeometryAddSet(g, "top", b0 <= 1 && 1 < b1 ? 1 : 0, &top));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwTwoBlocksDestroy(BwGenerator gen)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(gen->data));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeneratorCreate_TwoBlocks(BwGenerator gen)
{
  BwTwoBlocks *o;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&o));
  o->l                = 0.2;
  o->a                = 0.1;
  gen->data           = o;
  gen->setfromoptions = BwTwoBlocksSetFromOptions;
  gen->generate       = BwTwoBlocksGenerate;
  gen->destroy        = BwTwoBlocksDestroy;
  PetscFunctionReturn(PETSC_SUCCESS);
}
