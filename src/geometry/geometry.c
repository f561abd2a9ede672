/* BwGeometry: storage for blocks, interfaces and sets, the generator
 * registry, and centroids/areas of the polygons by the shoelace formula
 *   A = 1/2 sum (x_k y_k+1 - x_k+1 y_k),  c = 1/(6A) sum (p_k + p_k+1)(x_k y_k+1 - x_k+1 y_k).
 * Vertices are shifted by the polygon's first vertex before the sums so that
 * an assembly far from the origin keeps its digits. */
#include "geometry/geometry.h"
#include "util/compat.h"

/* A set given in the scene: the blocks whose centroid lies in a closed box,
 * or a list of block indices. */
struct _n_BwSceneSet {
  char      *name;
  char       option[PETSC_MAX_OPTION_NAME + 1]; /* -sets_NAME_box or -sets_NAME_blocks, for messages */
  PetscBool  isbox;
  PetscReal  box[6]; /* x0, y0, z0, x1, y1, z1 (z: all of X3 unless given) */
  PetscInt   n, *blocks;
};

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
  (*geom)->dim   = 2;
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
  PetscCall(PetscFree(g->volume));
  PetscCall(PetscFree(g->frame));
  PetscCall(PetscFree(g->iarea));
  PetscCall(PetscFree(g->poly_offsets));
  PetscCall(PetscFree(g->poly));
  PetscCall(PetscFree(g->face_offsets));
  PetscCall(PetscFree(g->face_voffsets));
  PetscCall(PetscFree(g->face_vertices));
  for (PetscInt k = 0; k < g->nscenesets; k++) {
    PetscCall(PetscFree(g->scenesets[k].name));
    PetscCall(PetscFree(g->scenesets[k].blocks));
  }
  PetscCall(PetscFree(g->scenesets));
  PetscCall(PetscFree(g->kt));
  PetscCall(PetscFree(g->gblock));
  PetscCall(PetscFree(g->block_rank));
  PetscCall(PetscFree(g->block_rindex));
  PetscCall(PetscFree(g->gvoffset));
  PetscCall(PetscFree(g->giface));
  PetscCall(PetscFree(g->gpoly_offset));
  for (PetscInt s = 0; s < g->nsets; s++) PetscCall(PetscFree(g->setname[s]));
  PetscCall(PetscFree(g->setname));
  PetscCall(PetscFree(g->setoffsets));
  PetscCall(PetscFree(g->setblocks));
  PetscCall(PetscFree(g->setpos));
  PetscCall(PetscFree(g->setsize_global));
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
  PetscFunctionBeginUser;
  PetscCall(BwGeometryAddSetAt(g, name, n, blocks, NULL));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometryAddSetAt(BwGeometry g, const char name[], PetscInt n, const PetscInt blocks[], const PetscInt pos[])
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
    PetscCall(PetscRealloc(sizeof(PetscInt) * (size_t)nb, &g->setpos));
    g->maxsetblocks = nb;
  }
  PetscCall(PetscStrallocpy(name, &g->setname[g->nsets]));
  PetscCall(PetscArraycpy(g->setblocks + have, blocks, n));
  for (PetscInt q = 0; q < n; q++) g->setpos[have + q] = pos ? pos[q] : -1;
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

void BwGeometrySplit(MPI_Comm comm, PetscInt n, PetscInt *start, PetscInt *end)
{
  PetscMPIInt size, rank;

  MPI_Comm_size(comm, &size);
  MPI_Comm_rank(comm, &rank);
  *start = (PetscInt)(((PetscInt64)n * rank) / size);
  *end   = (PetscInt)(((PetscInt64)n * (rank + 1)) / size);
}

PetscErrorCode BwGeometrySetShare(BwGeometry g, PetscInt nlocal)
{
  PetscInt start = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Exscan(&nlocal, &start, 1, MPIU_INT, MPI_SUM, g->comm));
  {
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(g->comm, &rank));
    if (!rank) start = 0; /* MPI_Exscan leaves rank 0's undefined */
  }
  g->block_start = start;
  PetscCallMPI(MPIU_Allreduce(&nlocal, &g->nblocks_global, 1, MPIU_INT, MPI_SUM, g->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscInt BwGeometryLocalBlock(BwGeometry g, PetscInt gid)
{
  PetscInt at;

  if (!g->distributed) return gid >= g->block_start && gid < g->block_start + g->nblocks ? gid - g->block_start : -1;
  /* owned, then ghosts: each part ascending */
  PetscFindInt(gid, g->nown_blocks, g->gblock, &at);
  if (at >= 0) return at;
  PetscFindInt(gid, g->nblocks - g->nown_blocks, g->gblock + g->nown_blocks, &at);
  return at >= 0 ? g->nown_blocks + at : -1;
}

PetscErrorCode BwGeometryBoundingBox(BwGeometry g, PetscReal lo[3], PetscReal hi[3])
{
  PetscReal l[3] = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL}, h[3] = {PETSC_MIN_REAL, PETSC_MIN_REAL, PETSC_MIN_REAL};
  const PetscInt d = g->dim;

  PetscFunctionBeginUser;
  for (PetscInt v = 0; v < g->offsets[g->nblocks]; v++)
    for (PetscInt c = 0; c < d; c++) {
      l[c] = PetscMin(l[c], g->vertices[d * v + c]);
      h[c] = PetscMax(h[c], g->vertices[d * v + c]);
    }
  if (d == 2) l[2] = h[2] = 0;
  PetscCallMPI(MPIU_Allreduce(l, lo, 3, MPIU_REAL, MPIU_MIN, g->comm));
  PetscCallMPI(MPIU_Allreduce(h, hi, 3, MPIU_REAL, MPIU_MAX, g->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometrySetFirst(BwGeometry g, PetscInt s, PetscInt *gfirst, PetscInt *local)
{
  PetscInt mine = PETSC_MAX_INT, at = -1;

  PetscFunctionBeginUser;
  PetscCheck(g->distributed, g->comm, PETSC_ERR_ORDER, "BwGeometrySetFirst needs the local piece");
  for (PetscInt q = g->setoffsets[s]; q < g->setoffsets[s + 1]; q++) {
    PetscInt b = g->setblocks[q], gid = g->gblock[b];
    if (gid < mine) {
      mine = gid;
      at   = b;
    }
  }
  PetscCallMPI(MPIU_Allreduce(&mine, gfirst, 1, MPIU_INT, MPI_MIN, g->comm));
  *local = *gfirst == mine ? at : -1;
  if (*gfirst == PETSC_MAX_INT) *gfirst = -1;
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
  PetscCall(BwSceneReal(scene, "-geometry_depth", "Out-of-plane depth s of blocks and interfaces (2D), thickness along X3 of the extruded blocks (3D generators) [m]", &g->depth, &g->depth_given));
  if (!(g->depth > 0)) PetscCall(BwSceneError(scene, "-geometry_depth", "must be > 0, got %g", (double)g->depth));
  PetscCall(BwSceneInt(scene, "-geometry_dimension", "2 (blocks are polygons in X1-X2, depth along X3) or 3 (convex polyhedra; the generators extrude their 2D assembly along X3 over [0, depth])", &g->dim, &g->dim_given));
  if (g->dim != 2 && g->dim != 3) PetscCall(BwSceneError(scene, "-geometry_dimension", "must be 2 or 3, got %" PetscInt_FMT, g->dim));
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
  PetscCall(BwSceneHelpSection(scene, "Partition (scene key partition.*; more than one rank)"));
  PetscCall(BwSceneRequireMapping(scene, "-partition", "method"));
  PetscCall(BwSceneEnum(scene, "-partition_method", "How the blocks are shared among the ranks: auto (graph where this PETSc has a parallel graph partitioner, else natural), natural (each rank a range of the input's block order, as the generator or file gives it), graph (PETSc's MatPartitioning on the block graph, PT-Scotch by default; its options under -partition_mat_partitioning_*)", 3, BwPartitionMethods, &g->partition, NULL));
  PetscCall(PetscNew(&g->generator));
  PetscCall((*create)(g->generator));
  PetscCall(g->generator->setfromoptions(g->generator, g, scene));
  PetscCall(BwGeometrySceneSetsFromOptions(g, scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Reads sets.NAME.{box | blocks}, checked now, before any work; the blocks
 * are found once the geometry exists (BwGeometryMakeSceneSets). */
PetscErrorCode BwGeometrySceneSetsFromOptions(BwGeometry g, BwScene scene)
{
  PetscInt n     = 0;
  char   **names = NULL;

  PetscFunctionBeginUser;
  PetscCall(BwSceneHelpSection(scene, "Sets defined in the scene (scene key sets.NAME.box: [x0, y0, x1, y1] (blocks whose centroid lies in the closed box) or sets.NAME.blocks: [b, ...])"));
  PetscCall(BwSceneRequireMapping(scene, "-sets", "NAME: {box: [x0, y0, x1, y1]} or NAME: {blocks: [b, ...]}"));
  {
    const char *const kinds[] = {"box", "blocks"};
    PetscCall(BwSceneListEntries(scene, "sets", 2, kinds, "is not a set definition: a set is a mapping {box: [x0, y0, x1, y1]} or {blocks: [b, ...]}", &n, &names));
  }
  PetscCall(PetscCalloc1(n, &g->scenesets));
  g->nscenesets = n;
  for (PetscInt k = 0; k < n; k++) {
    struct _n_BwSceneSet *set = &g->scenesets[k];
    char                  opt[PETSC_MAX_OPTION_NAME + 1], optbox[PETSC_MAX_OPTION_NAME + 1], optblocks[PETSC_MAX_OPTION_NAME + 1];
    PetscReal            *box = NULL;
    PetscInt              nbox = 0;
    PetscBool             hasbox, hasblocks;

    PetscCall(PetscStrallocpy(names[k], &set->name));
    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-sets_%s", names[k]));
    PetscCall(PetscSNPrintf(optbox, sizeof(optbox), "-sets_%s_box", names[k]));
    PetscCall(PetscSNPrintf(optblocks, sizeof(optblocks), "-sets_%s_blocks", names[k]));
    PetscCall(BwSceneRequireMapping(scene, opt, "box: [x0, y0, x1, y1] or blocks: [b, ...]"));
    PetscCall(BwSceneRealArray(scene, optbox, "The blocks whose centroid lies in the closed box [x0, y0, x1, y1] [m]", &box, &nbox, &hasbox));
    PetscCall(BwSceneIntArray(scene, optblocks, "Block indices (0-based, in the geometry's order)", &set->blocks, &set->n, &hasblocks));
    if (hasbox && hasblocks) PetscCall(BwSceneError(scene, optblocks, "and box both define set '%s': give one of them", names[k]));
    {
      /* a misspelt kind (boxx) named as such, not as a set without one */
      PetscInt nkeys;
      char   **keys;
      PetscCall(BwSceneListChildren(scene, opt, &nkeys, &keys));
      for (PetscInt c = 0; c < nkeys; c++) {
        PetscBool isbox, isblocks;
        PetscCall(PetscStrcmp(keys[c], "box", &isbox));
        PetscCall(PetscStrcmp(keys[c], "blocks", &isblocks));
        if (!isbox && !isblocks) {
          char bad[PETSC_MAX_OPTION_NAME + 1];
          PetscCall(PetscSNPrintf(bad, sizeof(bad), "%s_%s", opt, keys[c]));
          PetscCall(BwSceneError(scene, bad, "is not a key of a set: a set has box: [x0, y0, x1, y1] or blocks: [b, ...]"));
        }
      }
      PetscCall(PetscStrArrayDestroy(&keys));
    }
    if (!hasbox && !hasblocks) PetscCall(BwSceneError(scene, opt, "defines set '%s' by neither box: [x0, y0, x1, y1] nor blocks: [b, ...]", names[k]));
    set->isbox = hasbox;
    PetscCall(PetscStrncpy(set->option, hasbox ? optbox : optblocks, sizeof(set->option)));
    if (hasbox) {
      if (nbox == 6 && g->dim == 3) {
        /* [x0, y0, z0, x1, y1, z1] */
        if (!(box[0] <= box[3] && box[1] <= box[4] && box[2] <= box[5])) PetscCall(BwSceneError(scene, optbox, "needs x0 <= x1, y0 <= y1 and z0 <= z1, got [%g, %g, %g, %g, %g, %g]", (double)box[0], (double)box[1], (double)box[2], (double)box[3], (double)box[4], (double)box[5]));
        PetscCall(PetscArraycpy(set->box, box, 6));
      } else {
        if (nbox != 4) PetscCall(BwSceneError(scene, optbox, g->dim == 3 ? "must hold 4 numbers x0, y0, x1, y1 (any x3) or 6 numbers x0, y0, z0, x1, y1, z1, got %" PetscInt_FMT : "must hold 4 numbers x0, y0, x1, y1, got %" PetscInt_FMT, nbox));
        if (!(box[0] <= box[2] && box[1] <= box[3])) PetscCall(BwSceneError(scene, optbox, "needs x0 <= x1 and y0 <= y1, got [%g, %g, %g, %g]", (double)box[0], (double)box[1], (double)box[2], (double)box[3]));
        /* the x-y box over every x3 */
        set->box[0] = box[0];
        set->box[1] = box[1];
        set->box[2] = PETSC_MIN_REAL;
        set->box[3] = box[2];
        set->box[4] = box[3];
        set->box[5] = PETSC_MAX_REAL;
      }
      PetscCall(PetscFree(box));
    } else {
      if (!set->n) PetscCall(BwSceneError(scene, optblocks, "set '%s' is empty: it lists no block", names[k]));
      for (PetscInt q = 0; q < set->n; q++)
        if (set->blocks[q] < 0) PetscCall(BwSceneError(scene, optblocks, "lists block %" PetscInt_FMT " (element %" PetscInt_FMT "): block indices are >= 0", set->blocks[q], q + 1));
    }
  }
  PetscCall(PetscStrArrayDestroy(&names));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The scene's sets, made on the D0 share once the blocks exist: a name the
 * generator or the file already gave, an empty box, an index past the last
 * block are errors naming the key (collective: every rank sees the same). */
static PetscErrorCode BwGeometryMakeSceneSets(BwGeometry g, BwScene scene)
{
  PetscReal lo[3] = {PETSC_MAX_REAL, PETSC_MAX_REAL, 0}, hi[3] = {PETSC_MIN_REAL, PETSC_MIN_REAL, 0}, glo[3], ghi[3], tol;
  PetscInt *found, *pos, dim = g->dim;

  PetscFunctionBeginUser;
  if (!g->nscenesets) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt b = 0; b < g->nblocks; b++)
    for (int d = 0; d < dim; d++) {
      lo[d] = PetscMin(lo[d], g->centroid[dim * b + d]);
      hi[d] = PetscMax(hi[d], g->centroid[dim * b + d]);
    }
  PetscCallMPI(MPIU_Allreduce(lo, glo, 3, MPIU_REAL, MPIU_MIN, g->comm));
  PetscCallMPI(MPIU_Allreduce(hi, ghi, 3, MPIU_REAL, MPIU_MAX, g->comm));
  /* a centroid on the box's edge as written (0.3) may be computed a few ulps
   * outside it (0.30000000000000004): the closed box is widened by round-off */
  tol = 1e-12 * (PetscAbsReal(ghi[0] - glo[0]) + PetscAbsReal(ghi[1] - glo[1]) + PetscAbsReal(glo[0]) + PetscAbsReal(glo[1]));
  PetscCall(PetscMalloc2(g->nblocks + 1, &found, g->nblocks + 1, &pos));
  for (PetscInt k = 0; k < g->nscenesets; k++) {
    struct _n_BwSceneSet *set = &g->scenesets[k];
    PetscInt              s, nf = 0, total;

    PetscCall(BwGeometryFindSet(g, set->name, &s));
    if (s >= 0) {
      char opt[PETSC_MAX_OPTION_NAME + 1], have[1024];
      PetscCall(PetscSNPrintf(opt, sizeof(opt), "-sets_%s", set->name));
      PetscCall(BwGeometryGetSetNames(g, have, sizeof(have)));
      PetscCall(BwSceneError(scene, opt, "set '%s' is already a set of the geometry (%s): a scene set needs a name of its own", set->name, have));
    }
    if (set->isbox) {
      const PetscReal *q = set->box;
      for (PetscInt b = 0; b < g->nblocks; b++) {
        const PetscReal *c = &g->centroid[dim * b];
        PetscReal        z = dim == 3 ? c[2] : 0;
        if (c[0] >= q[0] - tol && c[0] <= q[3] + tol && c[1] >= q[1] - tol && c[1] <= q[4] + tol && z >= q[2] - tol && z <= q[5] + tol) {
          pos[nf]     = -1; /* ascending global id */
          found[nf++] = g->block_start + b;
        }
      }
      PetscCallMPI(MPIU_Allreduce(&nf, &total, 1, MPIU_INT, MPI_SUM, g->comm));
      if (!total) {
        if (q[2] > PETSC_MIN_REAL)
          PetscCall(BwSceneError(scene, set->option, "set '%s' is empty: no block's centroid lies in the box [%g, %g, %g, %g, %g, %g] (centroids span [%g, %g, %g, %g, %g, %g])", set->name, (double)q[0], (double)q[1], (double)q[2], (double)q[3], (double)q[4], (double)q[5], (double)glo[0], (double)glo[1], (double)glo[2], (double)ghi[0], (double)ghi[1], (double)ghi[2]));
        PetscCall(BwSceneError(scene, set->option, "set '%s' is empty: no block's centroid lies in the box [%g, %g, %g, %g] (centroids span [%g, %g, %g, %g])", set->name, (double)q[0], (double)q[1], (double)q[3], (double)q[4], (double)glo[0], (double)glo[1], (double)ghi[0], (double)ghi[1]));
      }
    } else {
      /* the list is the scene's, the same on every rank: checked whole
       * (sorted, so linear-logarithmic however long), and each rank keeps
       * the members of its range, at their places in the list */
      PetscInt *sorted, *at;
      PetscCall(PetscMalloc2(set->n, &sorted, set->n, &at));
      for (PetscInt q = 0; q < set->n; q++) {
        const PetscInt b = set->blocks[q];
        if (b >= g->nblocks_global) PetscCall(BwSceneError(scene, set->option, "lists block %" PetscInt_FMT " (element %" PetscInt_FMT "), but the geometry has %" PetscInt_FMT " blocks (0 to %" PetscInt_FMT ")", b, q + 1, g->nblocks_global, g->nblocks_global - 1));
        sorted[q] = b;
        at[q]     = q;
      }
      PetscCall(PetscSortIntWithArray(set->n, sorted, at));
      for (PetscInt q = 1; q < set->n; q++)
        if (sorted[q] == sorted[q - 1]) PetscCall(BwSceneError(scene, set->option, "lists block %" PetscInt_FMT " twice (elements %" PetscInt_FMT " and %" PetscInt_FMT ")", sorted[q], PetscMin(at[q], at[q - 1]) + 1, PetscMax(at[q], at[q - 1]) + 1));
      PetscCall(PetscFree2(sorted, at));
      for (PetscInt q = 0; q < set->n; q++) {
        const PetscInt b = set->blocks[q];
        if (b < g->block_start || b >= g->block_start + g->nblocks) continue;
        pos[nf]     = q;
        found[nf++] = b;
      }
    }
    PetscCall(BwGeometryAddSetAt(g, set->name, nf, found, pos));
  }
  PetscCall(PetscFree2(found, pos));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometrySetUp(BwGeometry g, BwScene scene, PetscReal thickness)
{
  PetscFunctionBeginUser;
  PetscCall(g->generator->generate(g->generator, g, scene, thickness));
  PetscCheck(g->nblocks_global > 0, g->comm, PETSC_ERR_PLIB, "the generator did not set its share (BwGeometrySetShare)");
  /* a generator gives polygons (extruded here in 3D); a 3D file gives
   * polyhedra with their volumes and centroids */
  if (!g->volume) {
    PetscCall(BwGeometryComputeCentroids(g));
    if (g->dim == 3) PetscCall(BwGeometryExtrude(g));
  }
  PetscCall(BwGeometryMakeSceneSets(g, scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometryExtrude(BwGeometry g)
{
  const PetscReal s = g->depth;
  PetscReal      *v3, *c3;
  PetscInt        nb = g->nblocks, ni = g->ninterfaces;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(3 * 2 * (size_t)g->nvertices, &v3));
  for (PetscInt b = 0; b < nb; b++) {
    const PetscInt o = g->offsets[b], nv = g->offsets[b + 1] - o;
    for (PetscInt k = 0; k < nv; k++)
      for (PetscInt top = 0; top < 2; top++) {
        PetscReal *p = v3 + 3 * (2 * o + top * nv + k);
        p[0]         = g->vertices[2 * (o + k)];
        p[1]         = g->vertices[2 * (o + k) + 1];
        p[2]         = top ? s : 0;
      }
  }
  /* faces: the bottom ring reversed (outward -X3), the top ring, and the
   * side quadrilaterals (edge, then up: outward for a counter-clockwise ring) */
  {
    PetscInt nf = 0, nfv = 0;
    PetscCall(PetscMalloc1(nb + 1, &g->face_offsets));
    g->face_offsets[0] = 0;
    for (PetscInt b = 0; b < nb; b++) {
      const PetscInt nv = g->offsets[b + 1] - g->offsets[b];
      g->face_offsets[b + 1] = g->face_offsets[b] + nv + 2;
      nfv += 2 * nv + 4 * nv;
    }
    nf = g->face_offsets[nb];
    PetscCall(PetscMalloc1(nf + 1, &g->face_voffsets));
    PetscCall(PetscMalloc1(nfv + 1, &g->face_vertices));
    nf  = 0;
    nfv = 0;
    g->face_voffsets[0] = 0;
    for (PetscInt b = 0; b < nb; b++) {
      const PetscInt o = 2 * g->offsets[b], nv = g->offsets[b + 1] - g->offsets[b];
      for (PetscInt k = nv - 1; k >= 0; k--) g->face_vertices[nfv++] = o + k;
      g->face_voffsets[++nf] = nfv;
      for (PetscInt k = 0; k < nv; k++) g->face_vertices[nfv++] = o + nv + k;
      g->face_voffsets[++nf] = nfv;
      for (PetscInt k = 0; k < nv; k++) {
        const PetscInt k1 = (k + 1) % nv;
        g->face_vertices[nfv++] = o + k;
        g->face_vertices[nfv++] = o + k1;
        g->face_vertices[nfv++] = o + nv + k1;
        g->face_vertices[nfv++] = o + nv + k;
        g->face_voffsets[++nf] = nfv;
      }
    }
  }
  for (PetscInt b = 0; b <= nb; b++) g->offsets[b] *= 2;
  g->nvertices *= 2;
  g->maxvertices = g->nvertices;
  PetscCall(PetscFree(g->vertices));
  g->vertices = v3;

  PetscCall(PetscMalloc1(3 * (size_t)nb, &c3));
  PetscCall(PetscMalloc1(nb, &g->volume));
  for (PetscInt b = 0; b < nb; b++) {
    c3[3 * b]     = g->centroid[2 * b];
    c3[3 * b + 1] = g->centroid[2 * b + 1];
    c3[3 * b + 2] = s / 2;
    g->volume[b]  = g->area[b] * s;
  }
  PetscCall(PetscFree(g->centroid));
  PetscCall(PetscFree(g->area));
  g->centroid = c3;
  g->maxblocks = nb;

  PetscCall(PetscMalloc1(3 * (size_t)ni, &c3));
  PetscCall(PetscMalloc1(9 * (size_t)ni, &g->frame));
  PetscCall(PetscMalloc1(ni, &g->iarea));
  PetscCall(PetscMalloc1(ni + 1, &g->poly_offsets));
  PetscCall(PetscMalloc1(12 * (size_t)ni, &g->poly));
  for (PetscInt k = 0; k < ni; k++) {
    const PetscReal c = PetscCosReal(g->angle[k]), sn = PetscSinReal(g->angle[k]), h = g->length[k] / 2;
    const PetscReal t[3] = {c, sn, 0}, n[3] = {-sn, c, 0}, bb[3] = {0, 0, 1};
    /* corners (xi, eta) = (-h, -s/2), (-h, s/2), (h, s/2), (h, -s/2): counter-clockwise about n (t x b = -n) */
    const PetscReal xi[4] = {-h, -h, h, h}, eta[4] = {-s / 2, s / 2, s / 2, -s / 2};
    PetscReal      *G = c3 + 3 * k;

    G[0] = g->center[2 * k];
    G[1] = g->center[2 * k + 1];
    G[2] = s / 2;
    for (int a = 0; a < 3; a++) {
      g->frame[9 * k + a]     = t[a];
      g->frame[9 * k + 3 + a] = n[a];
      g->frame[9 * k + 6 + a] = bb[a];
    }
    g->iarea[k]            = g->length[k] * s;
    g->poly_offsets[k]     = 4 * k;
    for (int v = 0; v < 4; v++)
      for (int a = 0; a < 3; a++) g->poly[3 * (4 * k + v) + a] = G[a] + xi[v] * t[a] + eta[v] * bb[a];
  }
  g->poly_offsets[ni] = 4 * ni;
  PetscCall(PetscFree(g->center));
  PetscCall(PetscFree(g->angle));
  PetscCall(PetscFree(g->length));
  g->center        = c3;
  g->maxinterfaces = ni;
  g->dim           = 3;
  PetscFunctionReturn(PETSC_SUCCESS);
}

void BwGeometryInterfaceLocal(BwGeometry g, PetscInt k, PetscReal xy[])
{
  const PetscInt   o = g->poly_offsets[k], nv = g->poly_offsets[k + 1] - o;
  const PetscReal *G = &g->center[3 * k], *t = &g->frame[9 * k], *b = &g->frame[9 * k + 6];
  PetscReal        a = 0;

  for (PetscInt v = 0; v < nv; v++) {
    const PetscReal *x    = &g->poly[3 * (o + v)];
    PetscReal        r[3] = {x[0] - G[0], x[1] - G[1], x[2] - G[2]};
    xy[2 * v]             = r[0] * t[0] + r[1] * t[1] + r[2] * t[2];
    xy[2 * v + 1]         = r[0] * b[0] + r[1] * b[1] + r[2] * b[2];
  }
  for (PetscInt v = 0; v < nv; v++) a += xy[2 * v] * xy[2 * ((v + 1) % nv) + 1] - xy[2 * ((v + 1) % nv)] * xy[2 * v + 1];
  if (a < 0)
    for (PetscInt v = 0; v < nv / 2; v++)
      for (int c = 0; c < 2; c++) {
        PetscReal tmp            = xy[2 * v + c];
        xy[2 * v + c]            = xy[2 * (nv - 1 - v) + c];
        xy[2 * (nv - 1 - v) + c] = tmp;
      }
}

PetscReal BwGeometryBlockSize(BwGeometry g, PetscInt b)
{
  return g->dim == 3 ? PetscCbrtReal(g->volume[b]) : PetscSqrtReal(g->area[b]);
}
