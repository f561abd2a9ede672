/* Internals of the file generator (file.c, file3d.c): checks of a block
 * assembly read from a file (validate.c, polyhedra.c), interfaces found
 * between facing edges (detect.c) with the uniform spatial hash both use to
 * stay O(N), and what reading in parallel needs (spatial.c): faults agreed
 * by every rank, the blocks of each region of space brought to one rank.
 *
 * Tolerances, one set per geometry so that every check agrees:
 *   delta   = 1e-6 * (median edge length) + 1e-12 * (largest |coordinate|)
 *             [m]: lengths, gaps and offsets below it are zero. The second
 *             term is the round-off of coordinates far from the origin.
 *   gapmax  = e + 1e-6 e + delta: the widest gap between facing edges.
 *   cosang  = cos(0.01 rad): outward normals of facing edges are
 *             anti-parallel within 0.01 rad (0.57 deg).
 * The median rather than the mean edge length, so that a long foundation
 * under thousands of small units does not set the scale. */
#pragma once
#include "geometry/geometry.h"
#include <stdint.h>

#define BW_FACING_ANGLE 0.01
#define BW_MSG_LEN      1024

typedef struct {
  PetscReal delta, gapmax, cosang, thickness;
  PetscReal edge;   /* median edge length [m] */
} BwTolerance;

/* ---- faults found in parallel (spatial.c) -------------------------------
 * A check that fails records a fault with its place in the serial reader's
 * order: (stage, index), e.g. (the overlap check, i * B + j). Each rank
 * keeps the first it finds; BwFaultAgree (collective) raises the first of
 * all ranks on every rank with that rank's message, so that every rank
 * returns the same error, the one the serial reader would have raised. */
typedef struct {
  int64_t        stage, index; /* INT64_MAX: no fault */
  PetscErrorCode code;
  char           msg[BW_MSG_LEN];
} BwFault;

void BwFaultInit(BwFault *f);
/* Records the fault if it comes before the one held; returns PETSC_TRUE. */
PetscBool BwFaultSet(BwFault *f, int64_t stage, int64_t index, PetscErrorCode code, const char fmt[], ...) PETSC_ATTRIBUTE_FORMAT(5, 6);
/* An error a check raised (its message), as a fault; PETSC_FALSE for none. */
PetscBool BwFaultCatch(BwFault *f, int64_t stage, int64_t index, PetscErrorCode ierr);
/* Collective: nothing if no rank has a fault, else the first one, raised on every rank. */
PetscErrorCode BwFaultAgree(MPI_Comm comm, BwFault *f);

/* The k-th smallest (from 0) of the n values on each rank, exactly (the
 * serial reader's sorted[k]): a radix selection on the bits of the values,
 * 8 reductions of 256 counts. Collective. */
PetscErrorCode BwSelectReal(MPI_Comm comm, PetscInt n, const PetscReal v[], int64_t k, PetscReal *value);

/* The rank whose balanced range (BwGeometrySplit) of N items holds item id. */
PetscMPIInt BwSplitRank(PetscInt N, PetscMPIInt size, PetscInt id);

/* From the blocks' vertices (finite) and the joint thickness e: this rank
 * holds the vertex rows vstart.. vstart + nv - 1 of nv_global, the whole
 * blocks offsets[0..nb] (rows relative to vstart). Collective: the sample
 * of 4096 edges is spread over the ranks by global row and gathered. */
PetscErrorCode BwToleranceCompute(MPI_Comm comm, PetscInt nv_global, PetscInt vstart, PetscInt nv, const PetscReal xy[], PetscInt nb, const PetscInt offsets[], PetscReal thickness, BwTolerance *tol);

/* ---- polyhedra.c -------------------------------------------------------- */

/* A convex polyhedron: its faces (vertex indices local to the block,
 * counter-clockwise seen from outside), their outward unit normals and
 * offsets (4 per face: n, d with n . x = d on the face), volume, centroid. */
typedef struct {
  PetscInt   nfaces;
  PetscInt  *face_offsets, *face_vertices;
  PetscReal *normal;
  PetscReal  volume, centroid[3];
} BwPolyhedron;
/* The convex hull of block b's n vertices x[3 n] (rows first.. in the
 * file), with its checks: fewer than 4 vertices, all on one plane, a vertex
 * that is no corner of the hull. */
PetscErrorCode BwPolyhedronHull(const char file[], PetscInt b, PetscInt first, PetscInt n, const PetscReal x[], PetscReal delta, BwPolyhedron *P);
PetscErrorCode BwPolyhedronDestroy(BwPolyhedron *P);

/* ---- blocks of a region (spatial.c) --------------------------------------
 * Pairwise work (overlaps, facing edges or faces) needs both blocks of a
 * pair on one rank. Every block's box, grown by its reach (2D: gapmax; 3D:
 * gapmax + 2 delta + 1e-3 of its diagonal, what two facing faces tilted by
 * the facing angle can be apart), goes to the ranks of the cells of a
 * uniform grid it touches (cells hashed to ranks); the pair is decided by
 * the rank of the cell that holds the lower corner of the intersection of
 * the two grown boxes, which both were sent to. Two blocks whose grown
 * boxes do not meet have no facing edges or faces and do not overlap. */
typedef struct {
  PetscInt      dim, n;
  PetscInt     *gid;     /* global id of each block, ascending */
  PetscInt     *offsets; /* n + 1: vertex rows of each block in x */
  PetscReal    *x;       /* dim per vertex */
  PetscReal    *gbox;    /* 2 dim per block: the grown box, lo then hi */
  PetscReal    *area;    /* 2D: per block, as the share computed it */
  BwPolyhedron *P;       /* 3D: per block */
  PetscBool     borrowed; /* the arrays belong to someone else (the share, on one rank) */
} BwBlockView;

typedef struct {
  MPI_Comm    comm;
  PetscMPIInt size, rank;
  PetscInt    dim;
  PetscReal   x0[3], h; /* the grid: cell (i, j, k) is [x0 + i h, x0 + (i + 1) h) x ... */
} BwSpatial;

/* The grid over the grown boxes of every rank's share (collective). */
PetscErrorCode BwSpatialCreate(MPI_Comm comm, const BwBlockView *share, BwSpatial *s);
/* The rank that decides the pair of grown boxes a, b; -1 where they do not meet. */
PetscMPIInt BwSpatialDecider(const BwSpatial *s, const PetscReal a[], const PetscReal b[]);
/* Every share's blocks to the ranks of their cells: *region holds the
 * blocks this rank received, ascending in id (collective). One rank: the
 * share itself, borrowed. */
PetscErrorCode BwSpatialExchange(const BwSpatial *s, const BwBlockView *share, BwBlockView *region);
PetscErrorCode BwBlockViewDestroy(BwBlockView *v);
/* Does this rank decide the pair of blocks i, j of view v? (ctx: a BwDecideCtx) */
typedef struct {
  const BwSpatial   *s;
  const BwBlockView *v;
} BwDecideCtx;
typedef PetscBool (*BwDecide)(void *ctx, PetscInt i, PetscInt j);
PetscBool BwDecideHere(void *ctx, PetscInt i, PetscInt j);

/* The shape of an item of the spatial hash (below, detect.c). */
typedef void (*BwGridShape)(void *ctx, PetscInt item, PetscReal P[2], PetscReal Q[2], PetscReal *rx, PetscReal *ry);

/* ---- validate.c: every check gives one line
 * "FILE: DATASET: block/interface K ..." --------------------------------- */

/* One polygon (nv finite vertices xy, block b, vertex rows first.. in the
 * file): fewer than 3 vertices, coinciding consecutive vertices, crossing
 * or touching edges, zero area. A clockwise polygon is reversed in place
 * (vertex 0 stays first). */
PetscErrorCode BwValidatePolygon(const char file[], PetscInt b, PetscInt first, PetscInt nv, PetscReal xy[], const BwTolerance *tol);
/* ---- polygon_sweep.c ---- */
/* Distance of segments a0-a1 and b0-b1 (0 when they cross). */
PetscReal BwSegmentDistance(const PetscReal a0[2], const PetscReal a1[2], const PetscReal b0[2], const PetscReal b1[2]);
/* A pair k < l of edges (k: vertex k -> k+1) that share no vertex and are
 * at most d apart, or k = l = -1 when there is none; O(n log n) on any
 * polygon. work: the steps taken (comparisons, distances, tree rotations). */
PetscErrorCode BwPolygonCloseEdges(PetscInt nv, const PetscReal xy[], PetscReal d, PetscInt *k, PetscInt *l, PetscInt64 *work);
/* The boxes (4 per block: xmin, ymin, xmax, ymax), perimeters and
 * convexity (either may be NULL) of the 2D blocks of v. */
PetscErrorCode BwBlockBoxes(const BwBlockView *v, PetscReal box[], PetscReal perimeter[], PetscBool convex[]);
/* The pairs of blocks of v (decided here: decide may be NULL, all) whose
 * interiors share more than delta * (smaller perimeter) of area: the first,
 * in the order of their ids (i, then j), as a fault of (stage, i B + j),
 * B the number of blocks. h: the cells of the grid of boxes, max(median
 * block extent, delta) of all blocks (any h finds the same pairs: every
 * pair whose boxes overlap shares a cell; this one bounds the cells a
 * box covers, and BwGridCheckSpan has checked it on every rank's boxes). */
PetscErrorCode BwValidateOverlaps(const char file[], const BwBlockView *v, PetscInt B, const BwTolerance *tol, PetscReal h, BwDecide decide, void *ctx, int64_t stage, BwFault *f);
/* The check BwGridCreate makes, made once on the items of every rank's
 * share (n here, of `shape`) before the grids of each rank's region: cells
 * of size h must index the whole span. Collective; the serial message. */
PetscErrorCode BwGridCheckSpan(MPI_Comm comm, PetscInt n, BwGridShape shape, void *ctx, PetscReal h);
/* Every block has at least one interface (collective): count[] the
 * interfaces of this rank's blocks start.. start + nb - 1 of B;
 * `detected` adds the detection rule to the message (the likely cause is a
 * gap wider than e). */
PetscErrorCode BwValidateConnected(const char file[], MPI_Comm comm, PetscInt B, PetscInt start, PetscInt nb, const PetscInt count[], PetscBool detected, const BwTolerance *tol);

/* ---- detect.c --------------------------------------------------------- */

/* An interface found between blocks i < j: centre G, angle, length. */
typedef struct {
  PetscReal center[2], angle, length;
} BwSegment;
/* Interfaces between every pair of blocks of v with facing edges that this
 * rank decides (decide NULL: all), in the order (i, j, edge of i, position
 * along it): pair[2 k], pair[2 k + 1] (indices into v) and seg[k]; the
 * arrays are allocated here (PetscFree). */
PetscErrorCode BwDetectInterfaces(const BwBlockView *v, const BwTolerance *tol, BwDecide decide, void *ctx, PetscInt *n, PetscInt **pair, BwSegment **seg);

/* The interfaces the same rule finds between blocks i < j of vertices x,
 * offsets o only, in the same order. The array is reallocated
 * (PetscRealloc) to hold *n segments; *cap is its capacity. */
PetscErrorCode BwDetectPair(const PetscReal x[], const PetscInt o[], const BwTolerance *tol, PetscInt i, PetscInt j, PetscInt *n, PetscInt *cap, BwSegment **seg);

/* ---- the spatial hash (detect.c) ----------------------------------------
 * Items are thick segments: the segment P-Q grown by rx along x and ry
 * along y (an edge: rx = ry = reach; a bounding box: the horizontal segment
 * through its middle, ry = half its height). Cells of size h are hashed
 * into a power-of-two number of buckets; collisions only add candidates,
 * which the exact tests reject. */
typedef struct {
  PetscInt n, cap;
  PetscInt *a;
} BwIntBuf;

typedef struct {
  PetscReal   x0, y0, h;
  PetscInt    mask;   /* buckets - 1 */
  PetscInt   *start;  /* buckets + 1 */
  PetscInt   *item;   /* bucket-sorted entries */
  BwGridShape     shape;
  void           *ctx;
  const PetscInt *group; /* optional, non-decreasing in the item index */
  BwIntBuf        cells, cand;
} BwGrid;

/* group (may be NULL): items of one group are never each other's
 * candidates (the edges of one block), and are skipped as a run in each
 * bucket, not one by one: a block of 1e6 short edges put 1e4 of its own
 * edges in every cell it crossed. */
PetscErrorCode BwGridCreate(PetscInt nitems, BwGridShape shape, void *ctx, const PetscInt group[], PetscReal h, BwGrid *grid);
/* Items > `item` (of other groups) whose cells share a bucket with
 * `item`'s, sorted, unique: grid->cand.a[0 .. grid->cand.n). */
PetscErrorCode BwGridCandidates(BwGrid *grid, PetscInt item);
PetscErrorCode BwGridDestroy(BwGrid *grid);
PetscErrorCode BwIntBufPush(BwIntBuf *buf, PetscInt v);
/* The shapes of the two grids: an edge grown by `reach` (ctx: BwEdgeShapeCtx),
 * a block's box (ctx: 4 reals per block, xmin, ymin, xmax, ymax). */
typedef struct {
  const PetscReal *v;
  const PetscInt  *next; /* next vertex of the same polygon */
  PetscReal        reach;
} BwEdgeShapeCtx;
void BwEdgeShape(void *ctx, PetscInt e, PetscReal P[2], PetscReal Q[2], PetscReal *rx, PetscReal *ry);
void BwBoxShape(void *ctx, PetscInt b, PetscReal P[2], PetscReal Q[2], PetscReal *rx, PetscReal *ry);

/* ---- file.c, file3d.c ---------------------------------------------------- */

/* What the reader holds while it builds a 3D share (file3d.c): this rank's
 * blocks b0.. b0 + nb - 1 of B (vertex rows vstart.., offsets relative to
 * it), the listed interfaces homed here (rows[], pairs[] in global ids), and
 * the file's name for the messages. */
typedef struct {
  const char      *path;
  PetscInt         B, b0, nb, vstart, nv_global;
  const PetscInt  *offsets;
  const PetscReal *x;
  PetscBool        listed;
  PetscInt         nlisted, *rows, *pairs;
} BwShare3D;
/* Collective: a 3D geometry file's share into g (dim 3): hulls, volumes,
 * centroids, faces, the overlap check, and the interface polygons between
 * facing faces on their mid-plane (detected, or the listed ones, each by
 * its row). Faults are agreed, in the serial reader's order from `stage`. */
PetscErrorCode BwFileBuild3D(BwGeometry g, const BwShare3D *sh, PetscReal thickness, int64_t stage);
/* The listed interfaces homed here, rows[] with pairs (i, j), grouped by
 * pair: each group's deciding rank (from the grown boxes of i, here, and
 * of j, asked of its share) or -1 where the boxes do not meet. Collective. */
PetscErrorCode BwListedDeciders(MPI_Comm comm, const BwBlockView *share, const BwSpatial *s, PetscInt B, PetscInt n, const PetscInt pairs[], PetscMPIInt decider[]);
