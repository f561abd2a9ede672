/* BwGeometry: the blocks (polygons, centroids, areas), the interfaces between
 * them (i, j, centre G, angle, length) and named block sets.
 *
 * No rank holds the whole assembly. A generator fills each rank's share of
 * it (its "D0 share": a contiguous range of global block ids, and the
 * interfaces whose first block is in that range, with pair[] in global ids);
 * BwGeometryDistribute then partitions the block graph (more than one rank),
 * moves blocks and interfaces to their owners and adds the ghosts, so that
 * each rank ends with its "local piece": the blocks it owns, every interface
 * touching one of them and the other blocks of those interfaces, all in
 * local indices, with their global ids (gblock, giface) for the output,
 * which is in input order whatever the number of ranks. One rank's share is
 * the whole assembly and nothing moves. (docs/contributing.md, "Distributed
 * geometry", states the contract between generators and the distribution.)
 *
 * Generators are registered by name in a PetscFunctionList
 * (geometry.generator): each reads its keys first (BwGeometrySetFromOptions,
 * before any work, so that every key is known and checked before a large
 * assembly is generated), then generates its share (BwGeometrySetUp). */
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
  PetscBool  distributed; /* the local piece (BwGeometryDistribute) rather than the D0 share */
  PetscInt   partition;   /* partition.method: a BwPartitionMethod */
  PetscBool  partitioned; /* a MatPartitioning ran (options -partition_ were read) */
  /* blocks: the D0 share, global ids block_start.. block_start + nblocks - 1;
   * or the local piece, the nown_blocks owned ones first, then the ghosts,
   * each part ascending in global id */
  PetscInt     nblocks;
  PetscInt     nblocks_global, block_start;
  PetscInt     nown_blocks;
  PetscInt    *gblock;       /* local piece: global id of each local block */
  PetscMPIInt *block_rank;   /* local piece: owner rank */
  PetscInt    *block_rindex; /* local piece: index in the owner's local arrays */
  PetscInt    *gvoffset;     /* local piece: global first vertex row (/blocks/vertices) */
  PetscInt     nvertices_global;
  PetscInt  *offsets;  /* nblocks+1: block b has vertices offsets[b]..offsets[b+1]-1 */
  PetscReal *vertices; /* 2 per vertex, counter-clockwise */
  PetscReal *centroid; /* 2 per block */
  PetscReal *area;     /* per block (2D: of the polygon; 3D: NULL) */
  PetscReal *volume;   /* 3D: per block */
  /* interfaces: the D0 share's (first block in its range; pair[] global
   * ids), or the local piece's (every interface touching an owned block,
   * ascending in global id; pair[] local indices) */
  PetscInt     ninterfaces, ninterfaces_global;
  PetscInt    *giface; /* global id of each (D0: NULL means numbered rank after rank) */
  PetscInt    *pair;   /* 2 per interface: blocks i < j (global ids), n points from i into j */
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
  PetscInt  *gpoly_offset; /* local piece, 3D: global first row of each polygon in /interfaces/vertices */
  PetscInt   npolyvertices_global;
  PetscBool  dim_given;    /* geometry.dimension was in the scene */
  PetscBool  depth_given;  /* geometry.depth was in the scene */
  /* 3D blocks' faces: block b has faces face_offsets[b]..face_offsets[b+1]-1,
   * face f the vertices face_vertices[face_voffsets[f]..face_voffsets[f+1]-1]
   * (indices into vertices), counter-clockwise seen from outside */
  PetscInt *face_offsets, *face_voffsets, *face_vertices;
  /* named block sets: every name on every rank, in one order; the members
   * of this rank's share (D0: global ids) or piece (owned and ghost members,
   * local indices), CSR */
  PetscInt   nsets;
  char     **setname;
  PetscInt  *setoffsets; /* nsets+1 */
  PetscInt  *setblocks;
  PetscInt  *setpos;         /* per member: its row in the set's list as written (/sets/NAME), -1 for a
                              * ghost; D0: NULL means ascending global id */
  PetscInt  *setsize_global; /* per set */
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
/* A generator's D0 share: this rank's `nlocal` blocks follow the lower
 * ranks' (sets block_start and nblocks_global, collective). */
PetscErrorCode BwGeometrySetShare(BwGeometry geom, PetscInt nlocal);
/* The balanced split of n items over the ranks: this rank's [start, end). */
void BwGeometrySplit(MPI_Comm comm, PetscInt n, PetscInt *start, PetscInt *end);
/* D0 share -> local piece (distribute.c, collective): the partition
 * (`method`: natural keeps the D0 share's blocks; graph partitions the block
 * graph with PETSc's MatPartitioning, options prefix -partition_), the
 * blocks and interfaces moved to their owners, the ghosts, local indices. */
typedef enum { BW_PARTITION_AUTO = 0, BW_PARTITION_NATURAL = 1, BW_PARTITION_GRAPH = 2 } BwPartitionMethod;
extern const char *const BwPartitionMethods[];
PetscErrorCode BwGeometryDistribute(BwGeometry geom, BwPartitionMethod method);
/* Local piece: the global sums/extremes a rank cannot see alone. */
PetscErrorCode BwGeometryBoundingBox(BwGeometry geom, PetscReal lo[3], PetscReal hi[3]);
/* Local piece: the smallest global id among the members of set s on every
 * rank, and its local index here (-1 where it is not local). */
PetscErrorCode BwGeometrySetFirst(BwGeometry geom, PetscInt s, PetscInt *gfirst, PetscInt *local);
/* Local piece: the local index of global block `gid`, -1 if not local. */
PetscInt BwGeometryLocalBlock(BwGeometry geom, PetscInt gid);
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
/* A set of the D0 share: its members in this rank's range (global ids);
 * every rank adds every set, in the same order, members or not. pos: each
 * member's row in the set's list as written, or NULL (BwGeometryAddSet):
 * ascending global id. */
PetscErrorCode BwGeometryAddSet(BwGeometry geom, const char name[], PetscInt n, const PetscInt blocks[]);
PetscErrorCode BwGeometryAddSetAt(BwGeometry geom, const char name[], PetscInt n, const PetscInt blocks[], const PetscInt pos[]);
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
