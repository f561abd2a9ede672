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
  PetscReal  box[4];
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
  for (PetscInt k = 0; k < g->nscenesets; k++) {
    PetscCall(PetscFree(g->scenesets[k].name));
    PetscCall(PetscFree(g->scenesets[k].blocks));
  }
  PetscCall(PetscFree(g->scenesets));
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
      if (nbox != 4) PetscCall(BwSceneError(scene, optbox, "must hold 4 numbers x0, y0, x1, y1, got %" PetscInt_FMT, nbox));
      if (!(box[0] <= box[2] && box[1] <= box[3])) PetscCall(BwSceneError(scene, optbox, "needs x0 <= x1 and y0 <= y1, got [%g, %g, %g, %g]", (double)box[0], (double)box[1], (double)box[2], (double)box[3]));
      PetscCall(PetscArraycpy(set->box, box, 4));
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

/* The scene's sets, made once the blocks exist: a name the generator or
 * the file already gave, an empty box, an index past the last block are
 * errors naming the key. */
static PetscErrorCode BwGeometryMakeSceneSets(BwGeometry g, BwScene scene)
{
  PetscReal lo[2] = {PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[2] = {PETSC_MIN_REAL, PETSC_MIN_REAL}, tol;
  PetscInt *found;

  PetscFunctionBeginUser;
  if (!g->nscenesets) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt b = 0; b < g->nblocks; b++)
    for (int d = 0; d < 2; d++) {
      lo[d] = PetscMin(lo[d], g->centroid[2 * b + d]);
      hi[d] = PetscMax(hi[d], g->centroid[2 * b + d]);
    }
  /* a centroid on the box's edge as written (0.3) may be computed a few ulps
   * outside it (0.30000000000000004): the closed box is widened by round-off */
  tol = 1e-12 * (PetscAbsReal(hi[0] - lo[0]) + PetscAbsReal(hi[1] - lo[1]) + PetscAbsReal(lo[0]) + PetscAbsReal(lo[1]));
  PetscCall(PetscMalloc1(g->nblocks, &found));
  for (PetscInt k = 0; k < g->nscenesets; k++) {
    struct _n_BwSceneSet *set = &g->scenesets[k];
    PetscInt              s, nf = 0;

    PetscCall(BwGeometryFindSet(g, set->name, &s));
    if (s >= 0) {
      char opt[PETSC_MAX_OPTION_NAME + 1];
      PetscCall(PetscSNPrintf(opt, sizeof(opt), "-sets_%s", set->name));
      char have[1024];
      PetscCall(BwGeometryGetSetNames(g, have, sizeof(have)));
      PetscCall(BwSceneError(scene, opt, "set '%s' is already a set of the geometry (%s): a scene set needs a name of its own", set->name, have));
    }
    if (set->isbox) {
      const PetscReal *q = set->box;
      for (PetscInt b = 0; b < g->nblocks; b++) {
        const PetscReal *c = &g->centroid[2 * b];
        if (c[0] >= q[0] - tol && c[0] <= q[2] + tol && c[1] >= q[1] - tol && c[1] <= q[3] + tol) found[nf++] = b;
      }
      if (!nf) PetscCall(BwSceneError(scene, set->option, "set '%s' is empty: no block's centroid lies in the box [%g, %g, %g, %g] (centroids span [%g, %g, %g, %g])", set->name, (double)q[0], (double)q[1], (double)q[2], (double)q[3], (double)lo[0], (double)lo[1], (double)hi[0], (double)hi[1]));
    } else {
      /* where each block was listed first (-1: not yet): linear in the
       * list, however long */
      PetscInt *first;
      PetscCall(PetscMalloc1(g->nblocks, &first));
      for (PetscInt b = 0; b < g->nblocks; b++) first[b] = -1;
      for (PetscInt q = 0; q < set->n; q++) {
        const PetscInt b = set->blocks[q];
        if (b >= g->nblocks) PetscCall(BwSceneError(scene, set->option, "lists block %" PetscInt_FMT " (element %" PetscInt_FMT "), but the geometry has %" PetscInt_FMT " blocks (0 to %" PetscInt_FMT ")", b, q + 1, g->nblocks, g->nblocks - 1));
        if (first[b] >= 0) PetscCall(BwSceneError(scene, set->option, "lists block %" PetscInt_FMT " twice (elements %" PetscInt_FMT " and %" PetscInt_FMT ")", b, first[b] + 1, q + 1));
        first[b]    = q;
        found[nf++] = b;
      }
      PetscCall(PetscFree(first));
    }
    PetscCall(BwGeometryAddSet(g, set->name, nf, found));
  }
  PetscCall(PetscFree(found));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometrySetUp(BwGeometry g, BwScene scene, PetscReal thickness)
{
  PetscFunctionBeginUser;
  PetscCall(g->generator->generate(g->generator, g, scene, thickness));
  PetscCall(BwGeometryComputeCentroids(g));
  PetscCall(BwGeometryMakeSceneSets(g, scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}
