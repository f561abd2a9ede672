/* BwGeometry: storage for blocks, interfaces and sets, the generator
 * registry, and centroids/areas of the polygons by the shoelace formula
 *   A = 1/2 sum (x_k y_k+1 - x_k+1 y_k),  c = 1/(6A) sum (p_k + p_k+1)(x_k y_k+1 - x_k+1 y_k).
 * Vertices are shifted by the polygon's first vertex before the sums so that
 * an assembly far from the origin keeps its digits. */
#include "geometry/geometry.h"
#include "util/compat.h"

static PetscFunctionList BwGeometryList = NULL;
const char *const        BwJointKindNames[BW_JOINT_NKINDS] = {"bed", "head", "unit"};

PetscErrorCode BwGeometryRegister(const char name[], BwGeneratorCreate create)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFunctionListAdd(&BwGeometryList, name, create));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwGeometryRegisterAll(void)
{
  PetscFunctionBeginUser;
  if (BwGeometryList) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(BwGeometryRegister("two_blocks", BwGeneratorCreate_TwoBlocks));
  PetscCall(BwGeometryRegister("file", BwGeneratorCreate_File));
  PetscCall(BwGeometryRegister("running_bond", BwGeneratorCreate_RunningBond));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometryCreate(MPI_Comm comm, BwGeometry *geom)
{
  PetscFunctionBeginUser;
  PetscCall(PetscNew(geom));
  (*geom)->comm  = comm;
  (*geom)->depth = 0.1;
  PetscCall(PetscMalloc1(1, &(*geom)->offsets));
  (*geom)->offsets[0] = 0;
  PetscCall(PetscMalloc1(1, &(*geom)->setoffsets));
  (*geom)->setoffsets[0] = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometryDestroy(BwGeometry *geom)
{
  BwGeometry g;

  PetscFunctionBeginUser;
  if (!*geom) PetscFunctionReturn(PETSC_SUCCESS);
  g = *geom;
  if (g->generator && g->generator->destroy) PetscCall(g->generator->destroy(g->generator));
  PetscCall(PetscFree(g->generator));
  PetscCall(PetscFree(g->offsets));
  PetscCall(PetscFree(g->vertices));
  PetscCall(PetscFree(g->centroid));
  PetscCall(PetscFree(g->area));
  PetscCall(PetscFree(g->pair));
  PetscCall(PetscFree(g->center));
  PetscCall(PetscFree(g->angle));
  PetscCall(PetscFree(g->length));
  PetscCall(PetscFree(g->kind));
  PetscCall(PetscFree(g->kn));
  PetscCall(PetscFree(g->kt));
  for (PetscInt s = 0; s < g->nsets; s++) PetscCall(PetscFree(g->setname[s]));
  PetscCall(PetscFree(g->setname));
  PetscCall(PetscFree(g->setoffsets));
  PetscCall(PetscFree(g->setblocks));
  PetscCall(PetscFree(*geom));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometryAddBlock(BwGeometry g, PetscInt nv, const PetscReal xy[], PetscInt *b)
{
  PetscFunctionBeginUser;
  if (g->nblocks + 1 > g->maxblocks) {
    PetscInt n = PetscMax(2 * g->maxblocks, 16);
    PetscCall(PetscRealloc(sizeof(PetscInt) * (size_t)(n + 1), &g->offsets));
    PetscCall(PetscRealloc(sizeof(PetscReal) * 2 * (size_t)n, &g->centroid));
    PetscCall(PetscRealloc(sizeof(PetscReal) * (size_t)n, &g->area));
    g->maxblocks = n;
  }
  if (g->nvertices + nv > g->maxvertices) {
    PetscInt n = PetscMax(2 * g->maxvertices, PetscMax(g->nvertices + nv, 64));
    PetscCall(PetscRealloc(sizeof(PetscReal) * 2 * (size_t)n, &g->vertices));
    g->maxvertices = n;
  }
  PetscCall(PetscArraycpy(g->vertices + 2 * g->nvertices, xy, 2 * nv));
  g->nvertices += nv;
  if (b) *b = g->nblocks;
  g->nblocks++;
  g->offsets[g->nblocks] = g->nvertices;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometryAddRectangle(BwGeometry g, PetscReal x0, PetscReal y0, PetscReal x1, PetscReal y1, PetscInt *b)
{
  const PetscReal xy[8] = {x0, y0, x1, y0, x1, y1, x0, y1};

  PetscFunctionBeginUser;
  PetscCall(BwGeometryAddBlock(g, 4, xy, b));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometryAddInterface(BwGeometry g, PetscInt i, PetscInt j, const PetscReal center[2], PetscReal angle, PetscReal length, BwJointKind kind)
{
  PetscInt k = g->ninterfaces;

  PetscFunctionBeginUser;
  if (k + 1 > g->maxinterfaces) {
    PetscInt n = PetscMax(2 * g->maxinterfaces, 16);
    PetscCall(PetscRealloc(sizeof(PetscInt) * 2 * (size_t)n, &g->pair));
    PetscCall(PetscRealloc(sizeof(PetscReal) * 2 * (size_t)n, &g->center));
    PetscCall(PetscRealloc(sizeof(PetscReal) * (size_t)n, &g->angle));
    PetscCall(PetscRealloc(sizeof(PetscReal) * (size_t)n, &g->length));
    PetscCall(PetscRealloc(sizeof(BwJointKind) * (size_t)n, &g->kind));
    g->maxinterfaces = n;
  }
  g->pair[2 * k]       = i;
  g->pair[2 * k + 1]   = j;
  g->center[2 * k]     = center[0];
  g->center[2 * k + 1] = center[1];
  g->angle[k]          = angle;
  g->length[k]         = length;
  g->kind[k]           = kind;
  g->ninterfaces++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometryAddSet(BwGeometry g, const char name[], PetscInt n, const PetscInt blocks[])
{
  PetscInt have = g->setoffsets[g->nsets];

  PetscFunctionBeginUser;
  if (g->nsets + 1 > g->maxsets) {
    PetscInt ns = PetscMax(2 * g->maxsets, 8);
    PetscCall(PetscRealloc(sizeof(char *) * (size_t)ns, &g->setname));
    PetscCall(PetscRealloc(sizeof(PetscInt) * (size_t)(ns + 1), &g->setoffsets));
    g->maxsets = ns;
  }
  if (have + n > g->maxsetblocks) {
    PetscInt nb = PetscMax(2 * g->maxsetblocks, PetscMax(have + n, 16));
    PetscCall(PetscRealloc(sizeof(PetscInt) * (size_t)nb, &g->setblocks));
    g->maxsetblocks = nb;
  }
  PetscCall(PetscStrallocpy(name, &g->setname[g->nsets]));
  PetscCall(PetscArraycpy(g->setblocks + have, blocks, n));
  g->nsets++;
  g->setoffsets[g->nsets] = have + n;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometryFindSet(BwGeometry g, const char name[], PetscInt *set)
{
  PetscFunctionBeginUser;
  *set = -1;
  for (PetscInt s = 0; s < g->nsets; s++) {
    PetscBool match;
    PetscCall(PetscStrcmp(g->setname[s], name, &match));
    if (match) {
      *set = s;
      break;
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometryGetSetNames(BwGeometry g, char buf[], size_t len)
{
  PetscFunctionBeginUser;
  buf[0] = 0;
  for (PetscInt s = 0; s < g->nsets; s++) {
    if (s) PetscCall(PetscStrlcat(buf, ", ", len));
    PetscCall(PetscStrlcat(buf, g->setname[s], len));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometryComputeCentroids(BwGeometry g)
{
  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < g->nblocks; b++) {
    const PetscReal *v  = g->vertices + 2 * g->offsets[b];
    PetscInt         nv = g->offsets[b + 1] - g->offsets[b];
    PetscReal        a = 0, cx = 0, cy = 0;

    for (PetscInt k = 0; k < nv; k++) {
      PetscInt  k1 = (k + 1) % nv;
      PetscReal x0 = v[2 * k] - v[0], y0 = v[2 * k + 1] - v[1];
      PetscReal x1 = v[2 * k1] - v[0], y1 = v[2 * k1 + 1] - v[1];
      PetscReal cross = x0 * y1 - x1 * y0;
      a += cross;
      cx += (x0 + x1) * cross;
      cy += (y0 + y1) * cross;
    }
    a *= 0.5;
    g->area[b] = a;
    if (a != 0) {
      g->centroid[2 * b]     = v[0] + cx / (6 * a);
      g->centroid[2 * b + 1] = v[1] + cy / (6 * a);
    } else {
      g->centroid[2 * b]     = v[0];
      g->centroid[2 * b + 1] = v[1];
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometrySetFromOptions(BwGeometry g, BwScene scene)
{
  char              generator[64] = "two_blocks";
  BwGeneratorCreate create;

  PetscFunctionBeginUser;
  PetscCall(BwGeometryRegisterAll());
  PetscCall(BwSceneHelpSection(scene, "Geometry (scene key geometry.*)"));
  PetscCall(BwSceneRequireMapping(scene, "-geometry", "generator, depth and the generator's keys"));
  PetscCall(BwSceneString(scene, "-geometry_generator", "Block assembly generator: two_blocks, running_bond or file", generator, sizeof(generator), NULL));
  PetscCall(BwSceneReal(scene, "-geometry_depth", "Out-of-plane depth s of blocks and interfaces [m]", &g->depth, NULL));
  if (!(g->depth > 0)) PetscCall(BwSceneError(scene, "-geometry_depth", "must be > 0, got %g", (double)g->depth));
  PetscCall(PetscFunctionListFind(BwGeometryList, generator, &create));
  if (!create) {
    char         names[256] = "";
    const char **list;
    int          n;

    PetscCall(PetscFunctionListGet(BwGeometryList, &list, &n));
    for (int l = 0; l < n; l++) {
      if (!list[l] || !list[l][0]) continue;
      if (names[0]) PetscCall(PetscStrlcat(names, ", ", sizeof(names)));
      PetscCall(PetscStrlcat(names, list[l], sizeof(names)));
    }
    PetscCall(PetscFree(list));
    PetscCall(BwSceneError(scene, "-geometry_generator", "must be one of %s, got '%s'", names, generator));
  }
  PetscCall(PetscNew(&g->generator));
  PetscCall((*create)(g->generator));
  PetscCall(g->generator->setfromoptions(g->generator, g, scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometrySetUp(BwGeometry g, BwScene scene, PetscReal thickness)
{
  PetscFunctionBeginUser;
  PetscCall(g->generator->generate(g->generator, g, scene, thickness));
  PetscCall(BwGeometryComputeCentroids(g));
  PetscFunctionReturn(PETSC_SUCCESS);
}
