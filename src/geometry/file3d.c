/* 3D geometry files (interface.md, "HDF5 geometry input, 3D"): every block
 * the convex hull of its vertices (polyhedra.c), the overlap check, and the
 * interfaces between facing faces.
 *
 * Tolerances, as in 2D (validate.h) with the block's size for the edge:
 *   delta  = 1e-6 * (median bounding-box diagonal of the blocks)
 *            + 1e-12 * (largest |coordinate|)
 *   gapmax = e (1 + 1e-6) + delta, the widest gap between facing faces
 *   facing = outward normals opposite within 1e-3 rad
 *   overlap of facing faces: area above 1e-9 of the smaller face.
 *
 * Facing faces fi of block i and fj of block j (i < j): the mid-plane has
 * the normal n = (n_i - n_j)/|n_i - n_j| (from i into j) and lies halfway
 * between the two faces; both faces, projected onto it, are intersected
 * (Sutherland-Hodgman: both are convex), and the intersection is the
 * interface polygon, counter-clockwise about n. Two convex blocks touch
 * across at most one plane (model.md's invariant 4): where several face
 * pairs qualify the largest intersection is the interface.
 *
 * Candidates: every block's box grown by gapmax is hashed into the cells
 * (size: the median diagonal) it covers, and the pairs sharing a cell are
 * tested, each once: linear in the number of blocks for a masonry
 * assembly. A block covering more than 4096 cells (a long foundation) is
 * tested against every block whose box meets its own instead.
 *
 * Overlap (every pair of candidates, whether the interfaces are detected
 * or listed): the separating-axis test of two convex polyhedra (the faces'
 * normals of both and the cross products of their edges) first; where the
 * projections overlap by more than delta along every axis, the volume the
 * interiors share (block i clipped by every face plane of block j), and
 * the blocks overlap when it exceeds BW_OVERLAP_VOLUME of the smaller
 * block's volume (interface.md: "interiors sharing more than a relative
 * tolerance of the smaller volume"). Touching faces of dry joints (depth
 * 0) do not overlap, nor does a corner drawn a little into a neighbour.
 *
 * In parallel (file.c) each rank builds the hulls of its share; the
 * candidates are those of the blocks of each rank's region (spatial.c),
 * each pair taken by the one rank that decides it, whose interface goes
 * to the rank of the pair's first block: the candidate set (the pairs
 * whose boxes, grown by gapmax, meet) does not depend on the grid that
 * finds it, so every rank sees the serial reader's pairs and computes
 * their polygons with the same arithmetic. Listed pairs are computed by
 * the rank deciding them, their rows grouped where their first block is. */
#include <stdlib.h>
#include <string.h>
#include "geometry/validate.h"
#include "blockwall/kernels.h"
#include "util/compat.h"
#include "util/exchange.h"

#define BW_FACING_ANGLE_3D 1e-3
#define BW_BIG_CELLS       4096
#define BW_OVERLAP_VOLUME  1e-6

typedef struct {
  PetscReal delta, gapmax, cosang;
} BwTol3;

static PetscReal BwDot(const PetscReal a[3], const PetscReal b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void      BwCross(const PetscReal a[3], const PetscReal b[3], PetscReal c[3])
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

/* The blocks as the build sees them. */
typedef struct {
  PetscInt      nb;
  const PetscReal *x;       /* 3 per vertex */
  const PetscInt  *offsets; /* per block, n + 1 */
  BwPolyhedron    *P;
  PetscReal       *box;     /* 6 per block: lo, hi */
} BwBlocks3;

/* ------------------------------------------------------------ overlap */

static void BwProject(const BwBlocks3 *B, PetscInt b, const PetscReal axis[3], PetscReal *lo, PetscReal *hi)
{
  *lo = PETSC_MAX_REAL;
  *hi = PETSC_MIN_REAL;
  for (PetscInt v = B->offsets[b]; v < B->offsets[b + 1]; v++) {
    PetscReal s = BwDot(axis, &B->x[3 * v]);
    *lo         = PetscMin(*lo, s);
    *hi         = PetscMax(*hi, s);
  }
}

/* The least overlap of the projections of blocks i and j over the
 * separating axes (<= 0: separated or touching). */
static PetscReal BwPenetration(const BwBlocks3 *B, PetscInt i, PetscInt j)
{
  PetscReal best = PETSC_MAX_REAL;
  PetscInt  blk[2] = {i, j};

  for (int s = 0; s < 2; s++) {
    const BwPolyhedron *P = &B->P[blk[s]];
    for (PetscInt f = 0; f < P->nfaces && best > 0; f++) {
      PetscReal a0, a1, b0, b1;
      BwProject(B, i, &P->normal[4 * f], &a0, &a1);
      BwProject(B, j, &P->normal[4 * f], &b0, &b1);
      best = PetscMin(best, PetscMin(a1 - b0, b1 - a0));
    }
  }
  /* edge x edge */
  for (PetscInt fi = 0; fi < B->P[i].nfaces && best > 0; fi++) {
    const BwPolyhedron *Pi = &B->P[i];
    PetscInt            ni = Pi->face_offsets[fi + 1] - Pi->face_offsets[fi];
    for (PetscInt ei = 0; ei < ni && best > 0; ei++) {
      const PetscReal *p0 = &B->x[3 * (B->offsets[i] + Pi->face_vertices[Pi->face_offsets[fi] + ei])];
      const PetscReal *p1 = &B->x[3 * (B->offsets[i] + Pi->face_vertices[Pi->face_offsets[fi] + (ei + 1) % ni])];
      PetscReal        di[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
      for (PetscInt fj = 0; fj < B->P[j].nfaces && best > 0; fj++) {
        const BwPolyhedron *Pj = &B->P[j];
        PetscInt            nj = Pj->face_offsets[fj + 1] - Pj->face_offsets[fj];
        for (PetscInt ej = 0; ej < nj && best > 0; ej++) {
          const PetscReal *q0 = &B->x[3 * (B->offsets[j] + Pj->face_vertices[Pj->face_offsets[fj] + ej])];
          const PetscReal *q1 = &B->x[3 * (B->offsets[j] + Pj->face_vertices[Pj->face_offsets[fj] + (ej + 1) % nj])];
          PetscReal        dj[3] = {q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]}, ax[3], len, a0, a1, b0, b1;
          BwCross(di, dj, ax);
          len = PetscSqrtReal(BwDot(ax, ax));
          if (len <= 1e-9 * PetscSqrtReal(BwDot(di, di) * BwDot(dj, dj))) continue; /* parallel edges */
          for (int k = 0; k < 3; k++) ax[k] /= len;
          BwProject(B, i, ax, &a0, &a1);
          BwProject(B, j, ax, &b0, &b1);
          best = PetscMin(best, PetscMin(a1 - b0, b1 - a0));
        }
      }
    }
  }
  return best;
}

/* A polyhedron as a list of faces, each a polygon of 3D points
 * counter-clockwise seen from outside (n of them, offsets into p). */
typedef struct {
  PetscInt   nf, np, capf, capp;
  PetscInt  *off; /* nf + 1 */
  PetscReal *p;   /* 3 per point */
} BwFaces3;

static PetscErrorCode BwFacesPush(BwFaces3 *F, const PetscReal x[3])
{
  PetscFunctionBeginUser;
  if (F->np == F->capp) {
    F->capp = 2 * F->capp + 64;
    PetscCall(PetscRealloc(sizeof(PetscReal) * 3 * (size_t)F->capp, &F->p));
  }
  for (int k = 0; k < 3; k++) F->p[3 * F->np + k] = x[k];
  F->np++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwFacesInit(BwFaces3 *F)
{
  PetscFunctionBeginUser;
  F->nf = F->np = 0;
  F->capf       = 16;
  F->capp       = 64;
  PetscCall(PetscMalloc1(F->capf, &F->off));
  PetscCall(PetscMalloc1(3 * F->capp, &F->p));
  F->off[0] = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwFacesDestroy(BwFaces3 *F)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(F->off));
  PetscCall(PetscFree(F->p));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwFacesClose(BwFaces3 *F)
{
  PetscFunctionBeginUser;
  if (F->nf + 1 >= F->capf) {
    F->capf = 2 * F->capf + 16;
    PetscCall(PetscRealloc(sizeof(PetscInt) * (size_t)F->capf, &F->off));
  }
  /* a face of fewer than 3 points has no area: dropped */
  if (F->np - F->off[F->nf] < 3) F->np = F->off[F->nf];
  else F->off[++F->nf] = F->np;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The faces of polyhedron i (reset first). */
static PetscErrorCode BwFacesOf(const BwBlocks3 *B, PetscInt i, BwFaces3 *F)
{
  const BwPolyhedron *P = &B->P[i];

  PetscFunctionBeginUser;
  if (!F->off) PetscCall(BwFacesInit(F));
  F->nf = F->np = 0;
  F->off[0]     = 0;
  for (PetscInt f = 0; f < P->nfaces; f++) {
    for (PetscInt k = P->face_offsets[f]; k < P->face_offsets[f + 1]; k++) PetscCall(BwFacesPush(F, &B->x[3 * (B->offsets[i] + P->face_vertices[k])]));
    PetscCall(BwFacesClose(F));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* F clipped to n . x <= d (into G): each face by Sutherland-Hodgman, and
 * the cut closed by a face on the plane, its points ordered
 * counter-clockwise about n (outward there). */
static PetscErrorCode BwFacesClip(const BwFaces3 *F, const PetscReal n[3], PetscReal d, PetscReal tol, BwFaces3 *G, BwFaces3 *cut)
{
  PetscFunctionBeginUser;
  if (!G->off) PetscCall(BwFacesInit(G));
  if (!cut->off) PetscCall(BwFacesInit(cut));
  G->nf = G->np = 0;
  cut->nf = cut->np = 0;
  G->off[0] = cut->off[0] = 0;
  {
    /* nothing beyond the plane: F as it is (a face of F on the plane must
     * not get a second copy as the cut) */
    PetscBool out = PETSC_FALSE;
    for (PetscInt k = 0; k < F->np && !out; k++) out = BwDot(n, &F->p[3 * k]) - d > tol ? PETSC_TRUE : PETSC_FALSE;
    if (!out) {
      for (PetscInt f = 0; f < F->nf; f++) {
        for (PetscInt k = F->off[f]; k < F->off[f + 1]; k++) PetscCall(BwFacesPush(G, &F->p[3 * k]));
        PetscCall(BwFacesClose(G));
      }
      PetscFunctionReturn(PETSC_SUCCESS);
    }
  }
  for (PetscInt f = 0; f < F->nf; f++) {
    PetscInt a0 = F->off[f], m = F->off[f + 1] - a0;
    for (PetscInt k = 0; k < m; k++) {
      const PetscReal *a = &F->p[3 * (a0 + k)], *b = &F->p[3 * (a0 + (k + 1) % m)];
      PetscReal        sa = BwDot(n, a) - d, sb = BwDot(n, b) - d;
      if (sa <= tol) PetscCall(BwFacesPush(G, a));
      if ((sa < -tol && sb > tol) || (sa > tol && sb < -tol)) {
        PetscReal t = sa / (sa - sb), x[3];
        for (int c = 0; c < 3; c++) x[c] = a[c] + t * (b[c] - a[c]);
        PetscCall(BwFacesPush(G, x));
        PetscCall(BwFacesPush(cut, x));
      } else if (PetscAbsReal(sa) <= tol) PetscCall(BwFacesPush(cut, a));
    }
    PetscCall(BwFacesClose(G));
  }
  if (cut->np >= 3) {
    /* the cut's points by their angle about n around their mean */
    PetscReal c[3] = {0, 0, 0}, e1[3], e2[3], len;
    PetscInt  m = cut->np;
    for (PetscInt k = 0; k < m; k++)
      for (int q = 0; q < 3; q++) c[q] += cut->p[3 * k + q] / m;
    /* e1 normal to n, e2 = n x e1 */
    e1[0] = PetscAbsReal(n[0]) < 0.9 ? 1 : 0;
    e1[1] = PetscAbsReal(n[0]) < 0.9 ? 0 : 1;
    e1[2] = 0;
    len = BwDot(e1, n);
    for (int q = 0; q < 3; q++) e1[q] -= len * n[q];
    len = PetscSqrtReal(BwDot(e1, e1));
    for (int q = 0; q < 3; q++) e1[q] /= len;
    BwCross(n, e1, e2);
    {
      PetscReal *ang, *pts;
      PetscInt  *idx;
      PetscCall(PetscMalloc3(m, &ang, m, &idx, 3 * m, &pts));
      for (PetscInt k = 0; k < m; k++) {
        PetscReal v[3] = {cut->p[3 * k] - c[0], cut->p[3 * k + 1] - c[1], cut->p[3 * k + 2] - c[2]};
        ang[k] = PetscAtan2Real(BwDot(v, e2), BwDot(v, e1));
        idx[k] = k;
      }
      PetscCall(PetscSortRealWithPermutation(m, ang, idx));
      for (PetscInt k = 0; k < m; k++)
        for (int q = 0; q < 3; q++) pts[3 * k + q] = cut->p[3 * idx[k] + q];
      for (PetscInt k = 0; k < m; k++) PetscCall(BwFacesPush(G, &pts[3 * k]));
      PetscCall(BwFacesClose(G));
      PetscCall(PetscFree3(ang, idx, pts));
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Volume of a closed polyhedron given by its outward faces (divergence
 * theorem: V = sum over faces of p0 . A / 3, A the face's area vector). */
static PetscReal BwFacesVolume(const BwFaces3 *F)
{
  PetscReal v = 0;
  for (PetscInt f = 0; f < F->nf; f++) {
    PetscInt         a0 = F->off[f], m = F->off[f + 1] - a0;
    const PetscReal *p0 = &F->p[3 * a0];
    PetscReal        A[3] = {0, 0, 0};
    for (PetscInt k = 1; k + 1 < m; k++) {
      const PetscReal *p1 = &F->p[3 * (a0 + k)], *p2 = &F->p[3 * (a0 + k + 1)];
      PetscReal        u[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]}, w[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]}, x[3];
      BwCross(u, w, x);
      for (int q = 0; q < 3; q++) A[q] += x[q] / 2;
    }
    v += BwDot(p0, A) / 3;
  }
  return v;
}

/* The volume blocks i and j share: i clipped by every face plane of j. The
 * points are taken relative to i's centroid, so that the volume's terms
 * are of the blocks' size wherever the assembly lies. */
static PetscErrorCode BwSharedVolume(const BwBlocks3 *B, PetscInt i, PetscInt j, PetscReal tol, BwFaces3 w[3], PetscReal *vol)
{
  const BwPolyhedron *Pj = &B->P[j];
  const PetscReal    *o = B->P[i].centroid;
  BwFaces3           *F = &w[0], *G = &w[1], *tmp;

  PetscFunctionBeginUser;
  PetscCall(BwFacesOf(B, i, F));
  for (PetscInt k = 0; k < F->np; k++)
    for (int q = 0; q < 3; q++) F->p[3 * k + q] -= o[q];
  for (PetscInt f = 0; f < Pj->nfaces && F->nf; f++) {
    const PetscReal *nd = &Pj->normal[4 * f];
    PetscCall(BwFacesClip(F, nd, nd[3] - BwDot(nd, o), tol, G, &w[2]));
    tmp = F;
    F   = G;
    G   = tmp;
  }
  *vol = F->nf ? PetscMax(BwFacesVolume(F), 0) : 0;
  if (F != &w[0]) { /* the result back in w[0] for the caller's reuse */
    BwFaces3 t = w[0];
    w[0]       = *F;
    *F         = t;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Blocks i and j overlap (see the head of this file): *depth > 0 and the
 * shared volume, else *depth <= 0. */
static PetscErrorCode BwOverlap3D(const BwBlocks3 *B, const BwTol3 *tol, PetscInt i, PetscInt j, BwFaces3 w[3], PetscReal *depth, PetscReal *shared)
{
  PetscFunctionBeginUser;
  *shared = 0;
  *depth  = BwPenetration(B, i, j);
  if (*depth <= tol->delta) {
    *depth = 0;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(BwSharedVolume(B, i, j, 1e-3 * tol->delta, w, shared));
  if (!(*shared > BW_OVERLAP_VOLUME * PetscMin(B->P[i].volume, B->P[j].volume))) *depth = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ facing faces */

typedef struct {
  PetscInt   n, cap;
  PetscReal *p; /* 3 per vertex */
} BwPoly3;

/* Clip the convex polygon s (ns vertices, 2 per vertex, counter-clockwise)
 * by the convex counter-clockwise polygon c: Sutherland-Hodgman. */
static PetscInt BwClipConvex(PetscInt ns, const PetscReal s[], PetscInt nc, const PetscReal c[], PetscReal w0[], PetscReal w1[])
{
  PetscInt n = ns;
  memcpy(w0, s, sizeof(PetscReal) * 2 * ns);
  for (PetscInt e = 0; e < nc && n > 0; e++) {
    const PetscReal *a = &c[2 * e], *b = &c[2 * ((e + 1) % nc)];
    PetscInt         m = 0;
    for (PetscInt k = 0; k < n; k++) {
      const PetscReal *p = &w0[2 * k], *q = &w0[2 * ((k + 1) % n)];
      PetscReal        dp = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
      PetscReal        dq = (b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0]);
      if (dp >= 0) {
        w1[2 * m]     = p[0];
        w1[2 * m + 1] = p[1];
        m++;
      }
      if ((dp >= 0) != (dq >= 0)) {
        PetscReal t   = dp / (dp - dq);
        w1[2 * m]     = p[0] + t * (q[0] - p[0]);
        w1[2 * m + 1] = p[1] + t * (q[1] - p[1]);
        m++;
      }
    }
    memcpy(w0, w1, sizeof(PetscReal) * 2 * m);
    n = m;
  }
  return n;
}

static PetscReal BwArea2(PetscInt n, const PetscReal p[], PetscReal c[2])
{
  PetscReal a = 0, cx = 0, cy = 0;
  for (PetscInt k = 0; k < n; k++) {
    const PetscReal *s = &p[2 * k], *t = &p[2 * ((k + 1) % n)];
    PetscReal        cr = (s[0] - p[0]) * (t[1] - p[1]) - (t[0] - p[0]) * (s[1] - p[1]);
    a += cr;
    cx += (s[0] - p[0] + t[0] - p[0]) * cr;
    cy += (s[1] - p[1] + t[1] - p[1]) * cr;
  }
  if (c) {
    c[0] = a != 0 ? p[0] + cx / (3 * a) : p[0];
    c[1] = a != 0 ? p[1] + cy / (3 * a) : p[1];
  }
  return a / 2;
}

/* The interface of blocks i < j, if they have facing faces: its polygon
 * (counter-clockwise about n, on the mid-plane) and normal. */
static PetscErrorCode BwFacing3D(const BwBlocks3 *B, const BwTol3 *tol, PetscInt i, PetscInt j, PetscReal work[], PetscInt maxw, BwPoly3 *out, PetscReal nout[3], PetscBool *found)
{
  const BwPolyhedron *Pi = &B->P[i], *Pj = &B->P[j];
  PetscReal           best = 0;

  PetscFunctionBeginUser;
  *found = PETSC_FALSE;
  for (PetscInt fi = 0; fi < Pi->nfaces; fi++) {
    const PetscReal *ni = &Pi->normal[4 * fi];
    for (PetscInt fj = 0; fj < Pj->nfaces; fj++) {
      const PetscReal *nj = &Pj->normal[4 * fj];
      const PetscInt   ci = Pi->face_offsets[fi + 1] - Pi->face_offsets[fi], cj = Pj->face_offsets[fj + 1] - Pj->face_offsets[fj];
      PetscReal        n[3] = {ni[0] - nj[0], ni[1] - nj[1], ni[2] - nj[2]}, len, gap, mi[3] = {0, 0, 0}, mj[3] = {0, 0, 0}, dm, u[3], v[3], ref[3] = {1, 0, 0};
      PetscReal       *si = work, *sj = work + 2 * maxw, *w0 = work + 4 * maxw, *w1 = work + 8 * maxw, ai, aj, a, c2[2];
      PetscInt         m;
      if (BwDot(ni, nj) > -tol->cosang) continue;
      for (PetscInt k = 0; k < ci; k++)
        for (int d = 0; d < 3; d++) mi[d] += B->x[3 * (B->offsets[i] + Pi->face_vertices[Pi->face_offsets[fi] + k]) + d] / ci;
      for (PetscInt k = 0; k < cj; k++)
        for (int d = 0; d < 3; d++) mj[d] += B->x[3 * (B->offsets[j] + Pj->face_vertices[Pj->face_offsets[fj] + k]) + d] / cj;
      len = PetscSqrtReal(BwDot(n, n));
      for (int d = 0; d < 3; d++) n[d] /= len;
      gap = BwDot(n, mj) - BwDot(n, mi);
      if (gap < -tol->delta || gap > tol->gapmax) continue;
      dm = 0.5 * (BwDot(n, mi) + BwDot(n, mj));
      if (PetscAbsReal(n[0]) > 0.6) ref[0] = 0, ref[1] = 1;
      BwCross(n, ref, u);
      len = PetscSqrtReal(BwDot(u, u));
      for (int d = 0; d < 3; d++) u[d] /= len;
      BwCross(n, u, v);
      /* face i counter-clockwise about n_i ~ n; face j about n_j ~ -n: reversed */
      for (PetscInt k = 0; k < ci; k++) {
        const PetscReal *p = &B->x[3 * (B->offsets[i] + Pi->face_vertices[Pi->face_offsets[fi] + k])];
        si[2 * k]          = BwDot(u, p);
        si[2 * k + 1]      = BwDot(v, p);
      }
      for (PetscInt k = 0; k < cj; k++) {
        const PetscReal *p = &B->x[3 * (B->offsets[j] + Pj->face_vertices[Pj->face_offsets[fj] + cj - 1 - k])];
        sj[2 * k]          = BwDot(u, p);
        sj[2 * k + 1]      = BwDot(v, p);
      }
      ai = BwArea2(ci, si, NULL);
      aj = BwArea2(cj, sj, NULL);
      m  = BwClipConvex(cj, sj, ci, si, w0, w1);
      if (m < 3) continue;
      a = BwArea2(m, w0, c2);
      if (!(a > 1e-9 * PetscMin(ai, aj)) || a <= best) continue;
      best = a;
      /* the polygon without the clipper's repeated points */
      out->n = 0;
      if (out->cap < m) {
        out->cap = 2 * m;
        PetscCall(PetscRealloc(sizeof(PetscReal) * 3 * (size_t)out->cap, &out->p));
      }
      for (PetscInt k = 0; k < m; k++) {
        const PetscReal *p = &w0[2 * k], *q = &w0[2 * ((k + m - 1) % m)];
        if (PetscAbsReal(p[0] - q[0]) <= tol->delta && PetscAbsReal(p[1] - q[1]) <= tol->delta) continue;
        for (int d = 0; d < 3; d++) out->p[3 * out->n + d] = p[0] * u[d] + p[1] * v[d] + dm * n[d];
        out->n++;
      }
      for (int d = 0; d < 3; d++) nout[d] = n[d];
      *found = out->n >= 3 ? PETSC_TRUE : PETSC_FALSE;
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ candidates */

typedef struct {
  uint64_t key;
  PetscInt block;
} BwCellEntry;

static int BwCellEntryCompare(const void *x, const void *y)
{
  const BwCellEntry *a = (const BwCellEntry *)x, *b = (const BwCellEntry *)y;
  if (a->key != b->key) return a->key < b->key ? -1 : 1;
  return a->block < b->block ? -1 : a->block > b->block;
}

static int BwPairCompare(const void *x, const void *y)
{
  const PetscInt *a = (const PetscInt *)x, *b = (const PetscInt *)y;
  if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
  return a[1] < b[1] ? -1 : a[1] > b[1];
}

static PetscBool BwBoxesMeet(const PetscReal *a, const PetscReal *b, PetscReal grow)
{
  for (int d = 0; d < 3; d++)
    if (a[d] > b[3 + d] + grow || b[d] > a[3 + d] + grow) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* Pairs (i < j) whose boxes, grown by gapmax, meet; sorted. */
static PetscErrorCode BwCandidates3D(const BwBlocks3 *B, PetscReal h, PetscReal grow, PetscInt *npairs, PetscInt **pairs)
{
  BwCellEntry *ent = NULL;
  PetscInt     nent = 0, cap = 0, np = 0, pcap = 0, *pr = NULL, nbig = 0, *big;
  PetscReal    o[3] = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL};

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(B->nb + 1, &big));
  for (PetscInt b = 0; b < B->nb; b++)
    for (int d = 0; d < 3; d++) o[d] = PetscMin(o[d], B->box[6 * b + d] - grow);
  for (PetscInt b = 0; b < B->nb; b++) {
    int64_t lo[3], hi[3], ncell = 1;
    for (int d = 0; d < 3; d++) {
      lo[d] = (int64_t)PetscFloorReal((B->box[6 * b + d] - grow - o[d]) / h);
      hi[d] = (int64_t)PetscFloorReal((B->box[6 * b + 3 + d] + grow - o[d]) / h);
      ncell *= hi[d] - lo[d] + 1;
    }
    if (ncell > BW_BIG_CELLS) {
      big[nbig++] = b;
      continue;
    }
    for (int64_t a = lo[0]; a <= hi[0]; a++)
      for (int64_t c = lo[1]; c <= hi[1]; c++)
        for (int64_t e = lo[2]; e <= hi[2]; e++) {
          if (nent + 1 > cap) {
            cap = PetscMax(2 * cap, 1024);
            PetscCall(PetscRealloc(sizeof(BwCellEntry) * (size_t)cap, &ent));
          }
          ent[nent].key     = ((uint64_t)a * 73856093ULL) ^ ((uint64_t)c * 19349663ULL * 1024ULL) ^ ((uint64_t)e * 83492791ULL * 1048576ULL);
          ent[nent++].block = b;
        }
  }
  if (nent) qsort(ent, (size_t)nent, sizeof(BwCellEntry), BwCellEntryCompare);
  for (PetscInt s = 0; s < nent;) {
    PetscInt t = s;
    while (t < nent && ent[t].key == ent[s].key) t++;
    for (PetscInt a = s; a < t; a++)
      for (PetscInt c = a + 1; c < t; c++) {
        PetscInt i = ent[a].block, j = ent[c].block;
        if (i == j || !BwBoxesMeet(&B->box[6 * i], &B->box[6 * j], grow)) continue;
        if (np + 1 > pcap) {
          pcap = PetscMax(2 * pcap, 1024);
          PetscCall(PetscRealloc(sizeof(PetscInt) * 2 * (size_t)pcap, &pr));
        }
        pr[2 * np]     = PetscMin(i, j);
        pr[2 * np + 1] = PetscMax(i, j);
        np++;
      }
    s = t;
  }
  for (PetscInt k = 0; k < nbig; k++)
    for (PetscInt j = 0; j < B->nb; j++) {
      PetscInt i = big[k];
      if (j == i || !BwBoxesMeet(&B->box[6 * i], &B->box[6 * j], grow)) continue;
      if (np + 1 > pcap) {
        pcap = PetscMax(2 * pcap, 1024);
        PetscCall(PetscRealloc(sizeof(PetscInt) * 2 * (size_t)pcap, &pr));
      }
      pr[2 * np]     = PetscMin(i, j);
      pr[2 * np + 1] = PetscMax(i, j);
      np++;
    }
  if (np) qsort(pr, (size_t)np, 2 * sizeof(PetscInt), BwPairCompare);
  /* unique */
  {
    PetscInt u = 0;
    for (PetscInt k = 0; k < np; k++)
      if (!u || pr[2 * k] != pr[2 * (u - 1)] || pr[2 * k + 1] != pr[2 * (u - 1) + 1]) {
        pr[2 * u]     = pr[2 * k];
        pr[2 * u + 1] = pr[2 * k + 1];
        u++;
      }
    np = u;
  }
  PetscCall(PetscFree(ent));
  PetscCall(PetscFree(big));
  *npairs = np;
  *pairs  = pr;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ the build */

static PetscErrorCode BwAddInterface3D(BwGeometry g, PetscInt i, PetscInt j, const BwPoly3 *poly, const PetscReal n[3])
{
  PetscInt  k = g->ninterfaces, w = g->poly_offsets ? g->poly_offsets[k] : 0;
  PetscReal a[3] = {0, 0, 0}, c[3] = {0, 0, 0}, area2 = 0;
  int       status;

  PetscFunctionBeginUser;
  if (k + 1 > g->maxinterfaces) {
    PetscInt m = PetscMax(2 * g->maxinterfaces, 16);
    PetscCall(PetscRealloc(sizeof(PetscInt) * 2 * (size_t)m, &g->pair));
    PetscCall(PetscRealloc(sizeof(PetscReal) * 3 * (size_t)m, &g->center));
    PetscCall(PetscRealloc(sizeof(PetscReal) * 9 * (size_t)m, &g->frame));
    PetscCall(PetscRealloc(sizeof(PetscReal) * (size_t)m, &g->iarea));
    PetscCall(PetscRealloc(sizeof(PetscInt) * (size_t)(m + 1), &g->poly_offsets));
    PetscCall(PetscRealloc(sizeof(BwJointKind) * (size_t)m, &g->kind));
    if (!k) g->poly_offsets[0] = 0;
    g->maxinterfaces = m;
  }
  PetscCall(PetscRealloc(sizeof(PetscReal) * 3 * (size_t)(w + poly->n), &g->poly));
  PetscCall(PetscArraycpy(g->poly + 3 * w, poly->p, 3 * poly->n));
  g->poly_offsets[k + 1] = w + poly->n;
  /* area and centroid by the fan from vertex 0 (area vectors along n) */
  for (PetscInt v = 1; v + 1 < poly->n; v++) {
    const PetscReal *p0 = poly->p, *p1 = poly->p + 3 * v, *p2 = poly->p + 3 * (v + 1);
    PetscReal        e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]}, e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]}, cr[3], t;
    BwCross(e1, e2, cr);
    t = BwDot(cr, n);
    area2 += t;
    for (int d = 0; d < 3; d++) c[d] += t * (p0[d] + p1[d] + p2[d]) / 3;
  }
  for (int d = 0; d < 3; d++) a[d] = c[d] / area2;
  g->pair[2 * k]     = i;
  g->pair[2 * k + 1] = j;
  for (int d = 0; d < 3; d++) g->center[3 * k + d] = a[d];
  g->iarea[k] = area2 / 2;
  g->kind[k]  = BW_JOINT_BED;
  bw_kernel_frame(n, &g->frame[9 * k], &status);
  PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "frame of interface %" PetscInt_FMT, k);
  g->ninterfaces++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The boxes (6 per block: lo, hi) of the blocks of a view. */
static void BwBoxes3D(PetscInt nb, const PetscInt offsets[], const PetscReal x[], PetscReal box[])
{
  for (PetscInt b = 0; b < nb; b++) {
    PetscReal *bx = &box[6 * b];
    for (int d = 0; d < 3; d++) bx[d] = PETSC_MAX_REAL, bx[3 + d] = PETSC_MIN_REAL;
    for (PetscInt v = offsets[b]; v < offsets[b + 1]; v++)
      for (int d = 0; d < 3; d++) {
        bx[d]     = PetscMin(bx[d], x[3 * v + d]);
        bx[3 + d] = PetscMax(bx[3 + d], x[3 * v + d]);
      }
  }
}

/* An interface polygon on its way: the pair (global ids) or the listed
 * row, the normal, the polygon. */
typedef struct {
  PetscInt  i, j, npoly;
  PetscReal n[3];
} BwPolyHead;

typedef struct {
  PetscInt    i, j;
  const char *at;
} BwPolyAt;

static int BwPolyAtCompare(const void *x, const void *y)
{
  const BwPolyAt *a = (const BwPolyAt *)x, *b = (const BwPolyAt *)y;
  if (a->i != b->i) return a->i < b->i ? -1 : 1;
  return (a->j > b->j) - (a->j < b->j);
}

static PetscErrorCode BwPackPoly(BwPacker *p, PetscMPIInt dest, PetscInt i, PetscInt j, const BwPoly3 *poly, const PetscReal n[3])
{
  BwPolyHead h = {i, j, poly->n, {n[0], n[1], n[2]}};

  PetscFunctionBeginUser;
  PetscCall(BwPack(p, dest, &h, sizeof(h)));
  PetscCall(BwPack(p, dest, poly->p, sizeof(PetscReal) * 3 * poly->n));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* What arrived (polygons keyed by (i, j): a pair, or (row, 0): a listed
 * row), added to g in key order with their pairs: a detected one's own, a
 * listed row's from pairs[] (the home rows, in row order). */
static PetscErrorCode BwAddArrived3D(BwGeometry g, const char *recv, size_t nrecv, const PetscInt pairs[])
{
  BwPolyAt *at = NULL;
  PetscInt  n = 0, cap = 0;
  BwPoly3   poly = {0, 0, NULL};

  PetscFunctionBeginUser;
  for (const char *c = recv; c < recv + nrecv;) {
    BwPolyHead h;
    memcpy(&h, c, sizeof(h));
    if (n == cap) {
      cap = PetscMax(2 * cap, 256);
      PetscCall(PetscRealloc(sizeof(BwPolyAt) * (size_t)cap, &at));
    }
    at[n].i    = h.i;
    at[n].j    = h.j;
    at[n++].at = c;
    c += sizeof(h) + sizeof(PetscReal) * 3 * (size_t)h.npoly;
  }
  qsort(at, (size_t)n, sizeof(BwPolyAt), BwPolyAtCompare);
  for (PetscInt k = 0; k < n; k++) {
    const char *c = at[k].at;
    BwPolyHead  h;
    BwUnpack(&c, &h, sizeof(h));
    poly.n = h.npoly;
    poly.p = (PetscReal *)c; /* read only */
    if (pairs) PetscCall(BwAddInterface3D(g, pairs[2 * k], pairs[2 * k + 1], &poly, h.n));
    else PetscCall(BwAddInterface3D(g, h.i, h.j, &poly, h.n));
  }
  PetscCall(PetscFree(at));
  PetscFunctionReturn(PETSC_SUCCESS);
}

typedef struct {
  PetscInt i, j, row;
} BwRow3;

static int BwRow3Compare(const void *x, const void *y)
{
  const BwRow3 *p = (const BwRow3 *)x, *q = (const BwRow3 *)y;
  if (p->i != q->i) return p->i < q->i ? -1 : 1;
  if (p->j != q->j) return p->j < q->j ? -1 : 1;
  return (p->row > q->row) - (p->row < q->row);
}

/* The work of the pairwise phases on this rank's region. */
typedef struct {
  BwBlocks3  R;
  PetscReal *work;
  PetscInt   maxw;
  BwPoly3    poly;
  BwFaces3   fw[3]; /* the overlap check's */
} BwPairWork;

static PetscErrorCode BwPairWorkDestroy(BwPairWork *w)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(w->R.box));
  PetscCall(PetscFree(w->work));
  PetscCall(PetscFree(w->poly.p));
  for (int k = 0; k < 3; k++) PetscCall(BwFacesDestroy(&w->fw[k]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Listed interfaces: the rows of each pair, grouped where its first block
 * is, to the rank deciding the pair; the faults in the serial order (by
 * row: a pair's first row where the blocks do not face, else its second,
 * a repeat); each polygon back to its row's rank. */
static PetscErrorCode BwListed3D(BwGeometry g, const BwShare3D *sh, const BwBlockView *share, const BwBlockView *region, const BwSpatial *sp, const BwTol3 *tol, BwPairWork *w, int64_t stage)
{
  const PetscInt n = sh->nlisted;
  BwRow3        *rows;
  PetscMPIInt   *dec, size;
  BwFault        f;
  BwPacker       p;
  char          *recv;
  size_t         nrecv;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(g->comm, &size));
  BwFaultInit(&f);
  PetscCall(PetscMalloc2(n + 1, &rows, n + 1, &dec));
  PetscCall(BwListedDeciders(g->comm, share, sp, sh->B, n, sh->pairs, dec));
  for (PetscInt k = 0; k < n; k++) {
    rows[k].i   = sh->pairs[2 * k];
    rows[k].j   = sh->pairs[2 * k + 1];
    rows[k].row = k;
  }
  qsort(rows, (size_t)n, sizeof(BwRow3), BwRow3Compare);
  PetscCall(BwPackerCreate(g->comm, &p));
  for (PetscInt r0 = 0; r0 < n;) {
    PetscInt r1 = r0, i = rows[r0].i, j = rows[r0].j, q = dec[rows[r0].row], m;
    while (r1 < n && rows[r1].i == i && rows[r1].j == j) r1++;
    m = r1 - r0;
    if (q < 0) {
      PetscInt k = sh->rows[rows[r0].row];
      BwFaultSet(&f, stage, k, PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: interface %" PetscInt_FMT " joins blocks %" PetscInt_FMT " and %" PetscInt_FMT ", which have no facing faces (outward normals opposite within %g rad, at most e + tolerance = %g m apart, overlapping by more than 1e-9 of the smaller face)", sh->path, k, i, j, (double)BW_FACING_ANGLE_3D, (double)tol->gapmax);
    } else {
      PetscCall(BwPack(&p, q, &i, sizeof(i)));
      PetscCall(BwPack(&p, q, &j, sizeof(j)));
      PetscCall(BwPack(&p, q, &m, sizeof(m)));
      for (PetscInt r = r0; r < r1; r++) PetscCall(BwPack(&p, q, &sh->rows[rows[r].row], sizeof(PetscInt)));
    }
    r0 = r1;
  }
  PetscCall(PetscFree2(rows, dec));
  PetscCall(BwPackerExchange(g->comm, &p, &recv, &nrecv, NULL));
  PetscCall(BwPackerDestroy(&p));
  PetscCall(BwPackerCreate(g->comm, &p));
  for (const char *at = recv; at < recv + nrecv;) {
    PetscInt  i, j, m, li, lj, *row;
    PetscReal nrm[3];
    PetscBool found;
    BwUnpack(&at, &i, sizeof(i));
    BwUnpack(&at, &j, sizeof(j));
    BwUnpack(&at, &m, sizeof(m));
    row = (PetscInt *)at; /* ascending */
    at += sizeof(PetscInt) * (size_t)m;
    PetscCall(PetscFindInt(i, region->n, region->gid, &li));
    PetscCall(PetscFindInt(j, region->n, region->gid, &lj));
    PetscCheck(li >= 0 && lj >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the pair (%" PetscInt_FMT ", %" PetscInt_FMT ") was sent to a rank without its blocks", i, j);
    PetscCall(BwFacing3D(&w->R, tol, li, lj, w->work, w->maxw + 4, &w->poly, nrm, &found));
    if (!found) {
      BwFaultSet(&f, stage, row[0], PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: interface %" PetscInt_FMT " joins blocks %" PetscInt_FMT " and %" PetscInt_FMT ", which have no facing faces (outward normals opposite within %g rad, at most e + tolerance = %g m apart, overlapping by more than 1e-9 of the smaller face)", sh->path, row[0], i, j, (double)BW_FACING_ANGLE_3D, (double)tol->gapmax);
      continue;
    }
    if (m > 1) {
      BwFaultSet(&f, stage, row[1], PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: interface %" PetscInt_FMT " repeats the pair (%" PetscInt_FMT ", %" PetscInt_FMT ") of interface %" PetscInt_FMT ": two convex blocks touch across at most one plane", sh->path, row[1], i, j, row[0]);
      continue;
    }
    PetscCall(BwPackPoly(&p, BwSplitRank(sh->B, size, i), row[0], 0, &w->poly, nrm));
  }
  PetscCall(PetscFree(recv));
  ierr = BwFaultAgree(g->comm, &f);
  if (ierr) PetscCall(BwPackerDestroy(&p));
  PetscCall(ierr);
  PetscCall(BwPackerExchange(g->comm, &p, &recv, &nrecv, NULL));
  PetscCall(BwPackerDestroy(&p));
  /* keyed by row, which the home rows ascend with: their pairs in order */
  PetscCall(BwAddArrived3D(g, recv, nrecv, sh->pairs));
  PetscCheck(g->ninterfaces == n, PETSC_COMM_SELF, PETSC_ERR_PLIB, "%" PetscInt_FMT " listed interfaces came back of %" PetscInt_FMT, g->ninterfaces, n);
  PetscCall(PetscFree(recv));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Candidate pairs of the region that this rank decides: the overlap check
 * (the first overlapping pair, by ids, as a fault), and with `detect` the
 * facing faces, each interface to the rank of its first block. */
static PetscErrorCode BwPairs3D(BwGeometry g, const BwShare3D *sh, const BwBlockView *region, const BwSpatial *sp, const BwTol3 *tol, PetscReal h, BwPairWork *w, PetscBool detect, int64_t stage)
{
  BwDecideCtx    dc = {sp, region};
  PetscInt       np, *pr;
  BwFault        f;
  BwPacker       p;
  char          *recv;
  size_t         nrecv;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  BwFaultInit(&f);
  PetscCall(BwPackerCreate(g->comm, &p));
  PetscCall(BwCandidates3D(&w->R, h > 0 ? h : 1, tol->gapmax, &np, &pr));
  for (PetscInt k = 0; k < np; k++) {
    PetscInt  i = pr[2 * k], j = pr[2 * k + 1];
    PetscReal depth, shared, n[3];
    PetscBool found;
    if (sp->size > 1 && !BwDecideHere(&dc, i, j)) continue;
    PetscCall(BwOverlap3D(&w->R, tol, i, j, w->fw, &depth, &shared));
    if (depth > 0) {
      BwFaultSet(&f, stage, (int64_t)region->gid[i] * sh->B + region->gid[j], PETSC_ERR_USER_INPUT, "%s: /blocks/vertices: blocks %" PetscInt_FMT " and %" PetscInt_FMT " overlap: their interiors share %g m^3, %.3g of the smaller block (tolerance %g), %g m deep along every separating direction", sh->path, region->gid[i], region->gid[j], (double)shared, (double)(shared / PetscMin(w->R.P[i].volume, w->R.P[j].volume)), (double)BW_OVERLAP_VOLUME, (double)depth);
      break;
    }
    if (!detect) continue;
    PetscCall(BwFacing3D(&w->R, tol, i, j, w->work, w->maxw + 4, &w->poly, n, &found));
    if (!found) continue;
    if (sp->size == 1) PetscCall(BwAddInterface3D(g, i, j, &w->poly, n));
    else PetscCall(BwPackPoly(&p, BwSplitRank(sh->B, sp->size, region->gid[i]), region->gid[i], region->gid[j], &w->poly, n));
  }
  PetscCall(PetscFree(pr));
  ierr = BwFaultAgree(g->comm, &f);
  if (ierr) PetscCall(BwPackerDestroy(&p));
  PetscCall(ierr);
  if (detect && sp->size > 1) {
    PetscCall(BwPackerExchange(g->comm, &p, &recv, &nrecv, NULL));
    PetscCall(BwAddArrived3D(g, recv, nrecv, NULL));
    PetscCall(PetscFree(recv));
  }
  PetscCall(BwPackerDestroy(&p));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwFileBuild3D(BwGeometry g, const BwShare3D *sh, PetscReal thickness, int64_t stage)
{
  const PetscInt nb = sh->nb, nv = sh->offsets[nb];
  BwTol3         tol;
  PetscReal      xmax = 0, gxmax, *diag, *box, h;
  PetscInt       nf = 0, nfv = 0;
  BwPolyhedron  *P;
  BwBlockView    share, region;
  BwSpatial      sp;
  BwFault        f;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  /* delta: the median diagonal of every block's box, exactly as the serial
   * reader sorted them all, and the largest |coordinate| */
  PetscCall(PetscMalloc2(6 * nb + 1, &box, nb + 1, &diag));
  BwBoxes3D(nb, sh->offsets, sh->x, box);
  for (PetscInt k = 0; k < 3 * nv; k++) xmax = PetscMax(xmax, PetscAbsReal(sh->x[k]));
  for (PetscInt b = 0; b < nb; b++) {
    const PetscReal *bx = &box[6 * b];
    diag[b]             = sh->offsets[b + 1] > sh->offsets[b] ? PetscSqrtReal(PetscSqr(bx[3] - bx[0]) + PetscSqr(bx[4] - bx[1]) + PetscSqr(bx[5] - bx[2])) : 0;
  }
  PetscCallMPI(MPIU_Allreduce(&xmax, &gxmax, 1, MPIU_REAL, MPIU_MAX, g->comm));
  PetscCall(BwSelectReal(g->comm, nb, diag, sh->B / 2, &h));
  tol.delta  = 1e-6 * h + 1e-12 * gxmax;
  tol.gapmax = thickness * (1 + 1e-6) + tol.delta;
  tol.cosang = PetscCosReal(BW_FACING_ANGLE_3D);
  /* hulls */
  BwFaultInit(&f);
  PetscCall(PetscCalloc1(nb + 1, &P));
  for (PetscInt b = 0; b < nb; b++) {
    if (BwFaultCatch(&f, stage + 1, sh->b0 + b, BwPolyhedronHull(sh->path, sh->b0 + b, sh->vstart + sh->offsets[b], sh->offsets[b + 1] - sh->offsets[b], &sh->x[3 * sh->offsets[b]], tol.delta, &P[b]))) break;
    nf += P[b].nfaces;
    nfv += P[b].face_offsets[P[b].nfaces];
  }
  ierr = BwFaultAgree(g->comm, &f);
  if (ierr) {
    for (PetscInt b = 0; b < nb; b++) PetscCall(BwPolyhedronDestroy(&P[b]));
    PetscCall(PetscFree(P));
    PetscCall(PetscFree2(box, diag));
  }
  PetscCall(ierr);
  /* the blocks into g */
  g->dim = 3;
  PetscCall(PetscRealloc(sizeof(PetscInt) * (size_t)(nb + 1), &g->offsets));
  PetscCall(PetscFree(g->vertices));
  PetscCall(PetscFree(g->centroid));
  PetscCall(PetscFree(g->area));
  PetscCall(PetscMalloc1(3 * (size_t)nv + 1, &g->vertices));
  PetscCall(PetscMalloc1(3 * (size_t)nb + 1, &g->centroid));
  PetscCall(PetscMalloc1(nb + 1, &g->volume));
  PetscCall(PetscMalloc1(nb + 1, &g->face_offsets));
  PetscCall(PetscMalloc1(nf + 1, &g->face_voffsets));
  PetscCall(PetscMalloc1(nfv + 1, &g->face_vertices));
  PetscCall(PetscArraycpy(g->vertices, sh->x, 3 * nv));
  g->nblocks = g->maxblocks = nb;
  g->nvertices = g->maxvertices = nv;
  g->face_offsets[0] = g->face_voffsets[0] = 0;
  nf = nfv = 0;
  for (PetscInt b = 0; b < nb; b++) {
    g->offsets[b] = sh->offsets[b];
    g->volume[b]  = P[b].volume;
    for (int d = 0; d < 3; d++) g->centroid[3 * b + d] = P[b].centroid[d];
    for (PetscInt fc = 0; fc < P[b].nfaces; fc++) {
      for (PetscInt k = P[b].face_offsets[fc]; k < P[b].face_offsets[fc + 1]; k++) g->face_vertices[nfv++] = sh->offsets[b] + P[b].face_vertices[k];
      g->face_voffsets[++nf] = nfv;
    }
    g->face_offsets[b + 1] = nf;
  }
  g->offsets[nb] = nv;

  /* the share as a view, each box grown by what facing faces can be apart
   * (validate.h: gapmax + 2 delta + 1e-3 of the block's diagonal) */
  PetscCall(PetscMemzero(&share, sizeof(share)));
  share.dim     = 3;
  share.n       = nb;
  share.offsets = g->offsets;
  share.x       = g->vertices;
  share.P       = P;
  PetscCall(PetscMalloc2(nb + 1, &share.gid, 6 * nb + 1, &share.gbox));
  for (PetscInt b = 0; b < nb; b++) {
    const PetscReal grow = tol.gapmax + 2 * tol.delta + 1e-3 * diag[b];
    share.gid[b]         = sh->b0 + b;
    for (int d = 0; d < 3; d++) {
      share.gbox[6 * b + d]     = box[6 * b + d] - grow;
      share.gbox[6 * b + 3 + d] = box[6 * b + 3 + d] + grow;
    }
  }
  PetscCall(PetscFree2(box, diag));
  ierr = BwSpatialCreate(g->comm, &share, &sp);
  if (!ierr) ierr = BwSpatialExchange(&sp, &share, &region);
  if (!ierr) {
    BwPairWork w;
    PetscCall(PetscMemzero(&w, sizeof(w)));
    w.R.nb      = region.n;
    w.R.x       = region.x;
    w.R.offsets = region.offsets;
    w.R.P       = region.P;
    PetscCall(PetscMalloc1(6 * region.n + 1, &w.R.box));
    BwBoxes3D(region.n, region.offsets, region.x, w.R.box);
    for (PetscInt b = 0; b < region.n; b++) w.maxw = PetscMax(w.maxw, region.offsets[b + 1] - region.offsets[b]);
    PetscCall(PetscMalloc1(12 * (w.maxw + 4) + 1, &w.work)); /* two faces, and two clips of up to both their vertices */
    ierr = BwPairs3D(g, sh, &region, &sp, &tol, h, &w, sh->listed ? PETSC_FALSE : PETSC_TRUE, stage + 2);
    if (!ierr && sh->listed) ierr = BwListed3D(g, sh, &share, &region, &sp, &tol, &w, stage + 3);
    PetscCall(BwPairWorkDestroy(&w));
    PetscCall(BwBlockViewDestroy(&region));
  }
  for (PetscInt b = 0; b < nb; b++) PetscCall(BwPolyhedronDestroy(&P[b]));
  PetscCall(PetscFree(P));
  PetscCall(PetscFree2(share.gid, share.gbox));
  PetscCall(ierr);
  if (!g->poly_offsets) {
    PetscCall(PetscMalloc1(1, &g->poly_offsets));
    g->poly_offsets[0] = 0;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}
