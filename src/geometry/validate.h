/* Internals of the file generator (file.c): checks of a block assembly read
 * from a file (validate.c), and interfaces found between facing edges
 * (detect.c), with the uniform spatial hash both use to stay O(N).
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

typedef struct {
  PetscReal delta, gapmax, cosang, thickness;
  PetscReal edge;   /* median edge length [m] */
} BwTolerance;

/* From the blocks' vertices (finite) and the joint thickness e. */
PetscErrorCode BwToleranceCompute(PetscInt nvertices, const PetscReal xy[], PetscInt nblocks, const PetscInt offsets[], PetscReal thickness, BwTolerance *tol);

/* ---- validate.c: every check raises PETSC_ERR_USER_INPUT with one line
 * "FILE: DATASET: block/interface K ..." ------------------------------- */

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
/* Blocks whose interiors share more than delta * (smaller perimeter) of area. */
PetscErrorCode BwValidateOverlaps(const char file[], BwGeometry g, const BwTolerance *tol);
/* Every block has at least one interface; `detected` adds the detection
 * rule to the message (the likely cause is a gap wider than e). */
PetscErrorCode BwValidateConnected(const char file[], BwGeometry g, PetscBool detected, const BwTolerance *tol);

/* ---- detect.c --------------------------------------------------------- */

/* Interfaces between every pair of blocks with facing edges, added to g in
 * the order (i, j, edge of i, position along it). */
PetscErrorCode BwDetectInterfaces(BwGeometry g, const BwTolerance *tol);

/* The interfaces the same rule finds between blocks i < j only, in the
 * same order: centre G (2 per segment), angle, length. The arrays are
 * reallocated (PetscRealloc) to hold *n segments; *cap is their capacity. */
typedef struct {
  PetscReal center[2], angle, length;
} BwSegment;
PetscErrorCode BwDetectPair(BwGeometry g, const BwTolerance *tol, PetscInt i, PetscInt j, PetscInt *n, PetscInt *cap, BwSegment **seg);

/* ---- the spatial hash (detect.c) ----------------------------------------
 * Items are thick segments: the segment P-Q grown by rx along x and ry
 * along y (an edge: rx = ry = reach; a bounding box: the horizontal segment
 * through its middle, ry = half its height). Cells of size h are hashed
 * into a power-of-two number of buckets; collisions only add candidates,
 * which the exact tests reject. */
typedef void (*BwGridShape)(void *ctx, PetscInt item, PetscReal P[2], PetscReal Q[2], PetscReal *rx, PetscReal *ry);

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

/* ---- polyhedra.c, file3d.c: 3D geometry files --------------------------- */

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
/* Rank 0: a 3D geometry file's blocks (nv vertices xyz, offsets) and its
 * listed interfaces (pairs, or detection when has_pairs is false) into g
 * (dim 3): hulls, volumes, centroids, faces, the overlap check, and the
 * interface polygons between facing faces on their mid-plane. */
PetscErrorCode BwFileBuild3D(BwGeometry g, const char file[], PetscInt nv, const PetscReal xyz[], PetscInt nb, const int64_t offsets[], PetscBool has_pairs, PetscInt ni, const int64_t pairs[], PetscReal thickness);
