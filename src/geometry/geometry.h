/* BwGeometry: the blocks (polygons, centroids, areas), the interfaces between
 * them (i, j, centre G, angle, length) and named block sets.
 *
 * The geometry is replicated on every rank: it is a few hundred bytes per
 * block, generation is O(N) and deterministic, and every rank then knows the
 * neighbours of what it owns without communication. Generators fill it; they
 * are registered by name in a PetscFunctionList (geometry.generator): each
 * reads its keys first (BwGeometrySetFromOptions, before any work, so that
 * every key is known and checked before a large assembly is generated),
 * then generates (BwGeometrySetUp). */
#pragma once
#include <petscsys.h>
#include "scene/scene.h"

typedef enum { BW_JOINT_BED = 0, BW_JOINT_HEAD = 1, BW_JOINT_UNIT = 2, BW_JOINT_NKINDS = 3 } BwJointKind;
extern const char *const BwJointKindNames[BW_JOINT_NKINDS]; /* "bed", "head", "unit" */

typedef struct _n_BwGeometry  *BwGeometry;
typedef struct _n_BwGenerator *BwGenerator;
struct _n_BwGeometry {
  MPI_Comm   comm;
  PetscInt   dim;   /* 2 (polygons in X1-X2, depth s along X3) | 3 */
  PetscReal  depth; /* s [m] */
  /* blocks */
  PetscInt   nblocks;
  PetscInt  *offsets;  /* nblocks+1: block b has vertices offsets[b]..offsets[b+1]-1 */
  PetscReal *vertices; /* 2 per vertex, counter-clockwise */
  PetscReal *centroid; /* 2 per block */
  PetscReal *area;     /* per block (2D: of the polygon; 3D: NULL) */
  PetscReal *volume;   /* 3D: per block */
  /* interfaces */
  PetscInt     ninterfaces;
  PetscInt    *pair;   /* 2 per interface: blocks i < j, n points from i into j */
  PetscReal   *center; /* 2 per interface: G */
  PetscReal   *angle;  /* theta [rad] of the tangent t */
  PetscReal   *length; /* l [m] */
  BwJointKind *kind;   /* which joint law applies */
  PetscReal   *kn, *kt; /* per-interface stiffness given by the geometry (file), or NULL */
  /* 3D interfaces (NULL in 2D, where angle and length describe them; in 3D
   * angle and length are NULL) */
  PetscReal *frame;        /* 9 per interface: rows t, n, b (model.md's frame rule) */
  PetscReal *iarea;        /* per interface: area A of its polygon */
  PetscInt  *poly_offsets; /* ninterfaces+1 */
  PetscReal *poly;         /* 3 per vertex: the interface polygons on the mid-plane, counter-clockwise about n */
  PetscBool  dim_given;    /* geometry.dimension was in the scene */
  PetscBool  depth_given;  /* geometry.depth was in the scene */
  /* 3D blocks' faces: block b has faces face_offsets[b]..face_offsets[b+1]-1,
   * face f the vertices face_vertices[face_voffsets[f]..face_voffsets[f+1]-1]
   * (indices into vertices), counter-clockwise seen from outside */
  PetscInt *face_offsets, *face_voffsets, *face_vertices;
  /* named block sets, CSR */
  PetscInt   nsets;
  char     **setname;
  PetscInt  *setoffsets; /* nsets+1 */
  PetscInt  *setblocks;
  BwGenerator generator;
  /* sets defined in the scene (sets.NAME.box | sets.NAME.blocks), read with
   * the keys and made once the blocks exist */
  PetscInt              nscenesets;
  struct _n_BwSceneSet *scenesets;
  /* bookkeeping while a generator fills the arrays */
  PetscInt nvertices, maxvertices, maxblocks, maxinterfaces, maxsetblocks, maxsets;
};

/* A generator: its options (data), read by setfromoptions; generate fills
 * blocks, interfaces and sets, `thickness` being the joint thickness e [m],
 * the gap it leaves between block faces. A type's create function sets the
 * operations, as PETSc's XXXCreate_Type do. */
struct _n_BwGenerator {
  void *data;
  PetscErrorCode (*setfromoptions)(BwGenerator gen, BwGeometry geom, BwScene scene);
  PetscErrorCode (*generate)(BwGenerator gen, BwGeometry geom, BwScene scene, PetscReal thickness);
  PetscErrorCode (*destroy)(BwGenerator gen);
};
typedef PetscErrorCode (*BwGeneratorCreate)(BwGenerator gen);

PetscErrorCode BwGeometryCreate(MPI_Comm comm, BwGeometry *geom);
PetscErrorCode BwGeometryRegister(const char name[], BwGeneratorCreate create);
/* Reads geometry.generator, geometry.depth and the generator's keys. */
PetscErrorCode BwGeometrySetFromOptions(BwGeometry geom, BwScene scene);
/* Reads the scene's sets (sets.NAME.box | blocks); called by
 * BwGeometrySetFromOptions. */
PetscErrorCode BwGeometrySceneSetsFromOptions(BwGeometry geom, BwScene scene);
/* Runs the generator, derives centroids and areas, adds the scene's sets. */
PetscErrorCode BwGeometrySetUp(BwGeometry geom, BwScene scene, PetscReal thickness);
PetscErrorCode BwGeometryDestroy(BwGeometry *geom);

/* Building blocks for generators. */
PetscErrorCode BwGeometryAddBlock(BwGeometry geom, PetscInt nv, const PetscReal xy[], PetscInt *b);
PetscErrorCode BwGeometryAddRectangle(BwGeometry geom, PetscReal x0, PetscReal y0, PetscReal x1, PetscReal y1, PetscInt *b);
PetscErrorCode BwGeometryAddInterface(BwGeometry geom, PetscInt i, PetscInt j, const PetscReal center[2], PetscReal angle, PetscReal length, BwJointKind kind);
PetscErrorCode BwGeometryAddSet(BwGeometry geom, const char name[], PetscInt n, const PetscInt blocks[]);
/* Centroids and areas from the polygons (shoelace formula). */
PetscErrorCode BwGeometryComputeCentroids(BwGeometry geom);
/* A 2D geometry extruded along X3 over [0, depth] into a 3D one: prisms in
 * the same order (bottom ring, then top ring), centroids at depth/2,
 * volumes, each interface the l x depth rectangle of its 2D segment with
 * the frame t = (cos, sin, 0), n = (-sin, cos, 0), b = X3 (the frame rule
 * of model.md gives this frame for these normals). Sets are unchanged. */
PetscErrorCode BwGeometryExtrude(BwGeometry geom);
/* 3D: interface k's polygon in its own coordinates (xi, eta) = ((x - G) . t,
 * (x - G) . b), 2 per vertex into xy[], counter-clockwise in (xi, eta). The
 * polygon is counter-clockwise about n, so clockwise there (t x b = -n):
 * the order is reversed by the sign of its area, whatever the input gave.
 * The point (xi, eta) is G + xi t + eta b. */
void BwGeometryInterfaceLocal(BwGeometry geom, PetscInt k, PetscReal xy[]);
/* A length of block b: sqrt(area) in 2D, cbrt(volume) in 3D. */
PetscReal BwGeometryBlockSize(BwGeometry geom, PetscInt b);
PetscErrorCode BwGeometryFindSet(BwGeometry geom, const char name[], PetscInt *set);
/* Comma-separated list of the set names, for error messages. */
PetscErrorCode BwGeometryGetSetNames(BwGeometry geom, char buf[], size_t len);

PetscErrorCode BwGeneratorCreate_TwoBlocks(BwGenerator gen);
PetscErrorCode BwGeneratorCreate_File(BwGenerator gen);
PetscErrorCode BwGeneratorCreate_RunningBond(BwGenerator gen);
