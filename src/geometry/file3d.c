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
 * 0) do not overlap, nor does a corner drawn a little into a neighbour. */
#include <stdlib.h>
#include <string.h>
#include "geometry/validate.h"
#include "blockwall/kernels.h"
#include "util/compat.h"

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
  const int64_t   *offsets; /* per block */
  BwPolyhedron    *P;
  PetscReal       *box;     /* 6 per block: lo, hi */
} BwBlocks3;

/* ------------------------------------------------------------ overlap */

static void BwProject(const BwBlocks3 *B, PetscInt b, const PetscReal axis[3], PetscReal *lo, PetscReal *hi)
{
  *lo = PETSC_MAX_REAL;
  *hi = PETSC_MIN_REAL;
  for (int64_t v = B->offsets[b]; v < B->offsets[b + 1]; v++) {
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

PetscErrorCode BwFileBuild3D(BwGeometry g, const char file[], PetscInt nv, const PetscReal xyz[], PetscInt nb, const int64_t offsets[], PetscBool has_pairs, PetscInt ni, const int64_t pairs[], PetscReal thickness)
{
  BwBlocks3  B;
  BwTol3     tol;
  PetscReal  xmax = 0, *diag, h, *work = NULL;
  PetscInt   maxw = 0, nf = 0, nfv = 0, np, *pr;
  BwPoly3    poly = {0, 0, NULL};
  BwFaces3   fw[3] = {{0, 0, 0, 0, NULL, NULL}, {0, 0, 0, 0, NULL, NULL}, {0, 0, 0, 0, NULL, NULL}}; /* the overlap check's work */

  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < nb; b++)
    for (int64_t v = offsets[b]; v < offsets[b + 1]; v++)
      PetscCheck(!PetscIsInfOrNanReal(xyz[3 * v]) && !PetscIsInfOrNanReal(xyz[3 * v + 1]) && !PetscIsInfOrNanReal(xyz[3 * v + 2]), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /blocks/vertices: block %" PetscInt_FMT ": vertex row %lld is not finite (%g, %g, %g)", file, b, (long long)v, (double)xyz[3 * v], (double)xyz[3 * v + 1], (double)xyz[3 * v + 2]);
  B.nb      = nb;
  B.x       = xyz;
  B.offsets = offsets;
  PetscCall(PetscCalloc1(nb + 1, &B.P));
  PetscCall(PetscMalloc2(6 * nb + 1, &B.box, nb + 1, &diag));
  for (PetscInt k = 0; k < 3 * nv; k++) xmax = PetscMax(xmax, PetscAbsReal(xyz[k]));
  for (PetscInt b = 0; b < nb; b++) {
    PetscReal *bx = &B.box[6 * b];
    for (int d = 0; d < 3; d++) bx[d] = PETSC_MAX_REAL, bx[3 + d] = PETSC_MIN_REAL;
    for (int64_t v = offsets[b]; v < offsets[b + 1]; v++)
      for (int d = 0; d < 3; d++) {
        bx[d]     = PetscMin(bx[d], xyz[3 * v + d]);
        bx[3 + d] = PetscMax(bx[3 + d], xyz[3 * v + d]);
      }
    diag[b] = offsets[b + 1] > offsets[b] ? PetscSqrtReal(PetscSqr(bx[3] - bx[0]) + PetscSqr(bx[4] - bx[1]) + PetscSqr(bx[5] - bx[2])) : 0;
    maxw    = PetscMax(maxw, (PetscInt)(offsets[b + 1] - offsets[b]));
  }
  PetscCall(PetscSortReal(nb, diag));
  h              = diag[nb / 2];
  tol.delta      = 1e-6 * h + 1e-12 * xmax;
  tol.gapmax     = thickness * (1 + 1e-6) + tol.delta;
  tol.cosang     = PetscCosReal(BW_FACING_ANGLE_3D);
  PetscCall(PetscFree2(B.box, diag));
  PetscCall(PetscMalloc1(6 * nb + 1, &B.box));
  for (PetscInt b = 0; b < nb; b++) {
    PetscReal *bx = &B.box[6 * b];
    for (int d = 0; d < 3; d++) bx[d] = PETSC_MAX_REAL, bx[3 + d] = PETSC_MIN_REAL;
    for (int64_t v = offsets[b]; v < offsets[b + 1]; v++)
      for (int d = 0; d < 3; d++) {
        bx[d]     = PetscMin(bx[d], xyz[3 * v + d]);
        bx[3 + d] = PetscMax(bx[3 + d], xyz[3 * v + d]);
      }
  }
  /* hulls, and the blocks into g */
  {
    PetscErrorCode ierr = PETSC_SUCCESS;
    for (PetscInt b = 0; b < nb && !ierr; b++) {
      ierr = BwPolyhedronHull(file, b, (PetscInt)offsets[b], (PetscInt)(offsets[b + 1] - offsets[b]), &xyz[3 * offsets[b]], tol.delta, &B.P[b]);
      if (!ierr) {
        nf += B.P[b].nfaces;
        nfv += B.P[b].face_offsets[B.P[b].nfaces];
      }
    }
    if (ierr) {
      for (PetscInt b = 0; b < nb; b++) PetscCall(BwPolyhedronDestroy(&B.P[b]));
      PetscCall(PetscFree(B.P));
      PetscCall(PetscFree(B.box));
      PetscCall(ierr); /* the hull's message, as it was raised */
    }
  }
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
  PetscCall(PetscArraycpy(g->vertices, xyz, 3 * nv));
  g->nblocks = g->maxblocks = nb;
  g->nvertices = g->maxvertices = nv;
  g->face_offsets[0] = g->face_voffsets[0] = 0;
  nf = nfv = 0;
  for (PetscInt b = 0; b < nb; b++) {
    const BwPolyhedron *P = &B.P[b];
    g->offsets[b] = (PetscInt)offsets[b];
    g->volume[b]  = P->volume;
    for (int d = 0; d < 3; d++) g->centroid[3 * b + d] = P->centroid[d];
    for (PetscInt f = 0; f < P->nfaces; f++) {
      for (PetscInt k = P->face_offsets[f]; k < P->face_offsets[f + 1]; k++) g->face_vertices[nfv++] = (PetscInt)offsets[b] + P->face_vertices[k];
      g->face_voffsets[++nf] = nfv;
    }
    g->face_offsets[b + 1] = nf;
  }
  g->offsets[nb] = nv;

  PetscCall(PetscMalloc1(12 * (maxw + 4) + 1, &work)); /* two faces, and two clips of up to both their vertices */
  if (!has_pairs) {
    /* candidates, the overlap check, the facing faces */
    PetscCall(BwCandidates3D(&B, h > 0 ? h : 1, tol.gapmax, &np, &pr));
    for (PetscInt k = 0; k < np; k++) {
      PetscInt  i = pr[2 * k], j = pr[2 * k + 1];
      PetscReal depth, shared, n[3];
      PetscBool found;
      PetscCall(BwOverlap3D(&B, &tol, i, j, fw, &depth, &shared));
      if (depth > 0) {
        PetscReal frac = shared / PetscMin(B.P[i].volume, B.P[j].volume);
        PetscCall(PetscFree(pr));
        PetscCall(PetscFree(work));
        PetscCall(PetscFree(poly.p));
        for (int w = 0; w < 3; w++) PetscCall(BwFacesDestroy(&fw[w]));
        for (PetscInt b = 0; b < nb; b++) PetscCall(BwPolyhedronDestroy(&B.P[b]));
        PetscCall(PetscFree(B.P));
        PetscCall(PetscFree(B.box));
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /blocks/vertices: blocks %" PetscInt_FMT " and %" PetscInt_FMT " overlap: their interiors share %g m^3, %.3g of the smaller block (tolerance %g), %g m deep along every separating direction", file, i, j, (double)shared, (double)frac, (double)BW_OVERLAP_VOLUME, (double)depth);
      }
      PetscCall(BwFacing3D(&B, &tol, i, j, work, maxw + 4, &poly, n, &found));
      if (found) PetscCall(BwAddInterface3D(g, i, j, &poly, n));
    }
    PetscCall(PetscFree(pr));
  } else {
    PetscErrorCode ierr = PETSC_SUCCESS;
    char           msg[512];
    /* listed interfaces: the blocks are checked for overlap all the same */
    PetscCall(BwCandidates3D(&B, h > 0 ? h : 1, tol.gapmax, &np, &pr));
    for (PetscInt k = 0; k < np && !ierr; k++) {
      PetscInt  i = pr[2 * k], j = pr[2 * k + 1];
      PetscReal depth, shared;
      PetscCall(BwOverlap3D(&B, &tol, i, j, fw, &depth, &shared));
      if (depth > 0) {
        ierr = PETSC_ERR_USER_INPUT;
        PetscCall(PetscSNPrintf(msg, sizeof(msg), "%s: /blocks/vertices: blocks %" PetscInt_FMT " and %" PetscInt_FMT " overlap: their interiors share %g m^3, %.3g of the smaller block (tolerance %g), %g m deep along every separating direction", file, i, j, (double)shared, (double)(shared / PetscMin(B.P[i].volume, B.P[j].volume)), (double)BW_OVERLAP_VOLUME, (double)depth));
      }
    }
    PetscCall(PetscFree(pr));
    for (PetscInt k = 0; k < ni && !ierr; k++) {
      PetscInt  i = (PetscInt)pairs[2 * k], j = (PetscInt)pairs[2 * k + 1];
      PetscReal n[3];
      PetscBool found;
      for (PetscInt l = 0; l < k && !ierr; l++)
        if (pairs[2 * l] == i && pairs[2 * l + 1] == j) {
          ierr = PETSC_ERR_USER_INPUT;
          PetscCall(PetscSNPrintf(msg, sizeof(msg), "%s: /interfaces/blocks: interface %" PetscInt_FMT " repeats the pair (%" PetscInt_FMT ", %" PetscInt_FMT ") of interface %" PetscInt_FMT ": two convex blocks touch across at most one plane", file, k, i, j, l));
        }
      if (ierr) break;
      PetscCall(BwFacing3D(&B, &tol, i, j, work, maxw + 4, &poly, n, &found));
      if (!found) {
        ierr = PETSC_ERR_USER_INPUT;
        PetscCall(PetscSNPrintf(msg, sizeof(msg), "%s: /interfaces/blocks: interface %" PetscInt_FMT " joins blocks %" PetscInt_FMT " and %" PetscInt_FMT ", which have no facing faces (outward normals opposite within %g rad, at most e + tolerance = %g m apart, overlapping by more than 1e-9 of the smaller face)", file, k, i, j, (double)BW_FACING_ANGLE_3D, (double)tol.gapmax));
        break;
      }
      PetscCall(BwAddInterface3D(g, i, j, &poly, n));
    }
    if (ierr) {
      PetscCall(PetscFree(work));
      PetscCall(PetscFree(poly.p));
      for (int w = 0; w < 3; w++) PetscCall(BwFacesDestroy(&fw[w]));
      for (PetscInt b = 0; b < nb; b++) PetscCall(BwPolyhedronDestroy(&B.P[b]));
      PetscCall(PetscFree(B.P));
      PetscCall(PetscFree(B.box));
      SETERRQ(PETSC_COMM_SELF, ierr, "%s", msg);
    }
  }
  if (!g->poly_offsets) {
    PetscCall(PetscMalloc1(1, &g->poly_offsets));
    g->poly_offsets[0] = 0;
  }
  PetscCall(PetscFree(work));
  PetscCall(PetscFree(poly.p));
  for (int w = 0; w < 3; w++) PetscCall(BwFacesDestroy(&fw[w]));
  for (PetscInt b = 0; b < nb; b++) PetscCall(BwPolyhedronDestroy(&B.P[b]));
  PetscCall(PetscFree(B.P));
  PetscCall(PetscFree(B.box));
  PetscFunctionReturn(PETSC_SUCCESS);
}
