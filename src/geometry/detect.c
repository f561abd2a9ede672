/* Interfaces between blocks whose edges face each other, and the uniform
 * spatial hash that finds candidate edges in O(N) expected time.
 *
 * The rule, for edge a of block i and edge b of block j (i < j), with
 * outward unit normals na, nb (counter-clockwise polygons: na = (d2, -d1)/|d|
 * for the edge direction d):
 *   - facing:  na . nb <= -cos(0.01 rad)
 *   - frame:   n = (na - nb)/|na - nb| points from i into j, t = (n2, -n1),
 *              s and h the coordinates along t and n from a's first vertex
 *   - overlap: the s-intervals of a and b share [s0, s1] with s1 - s0 > delta
 *   - gap:     g(s) = h_b(s) - h_a(s) lies in [-delta, gapmax] at s0 and s1
 *   - piece:   the mid-plane segment from (s0, (h_a+h_b)/2) to (s1, ...).
 * Pieces of one pair that lie on one line and touch (an edge split by an
 * extra vertex, a block over two collinear edges) merge into one interface:
 * the union of their s-intervals on the first piece's mid-plane; G is its
 * middle, l its length, theta = atan2(t2, t1). Pieces of one pair on
 * different lines or separated along the line stay separate interfaces.
 *
 * Order, which makes the result deterministic and independent of the frame
 * (rotating or translating the assembly leaves it unchanged): by i, j, then
 * the first edge of i a piece lies on, then the distance along that edge
 * from its first vertex, then the edge of j. Candidates come from the hash;
 * a pair given in a file (BwDetectPair) tries every edge of i against every
 * edge of j, and both go through the same piece and merge code, so they agree
 * to the last bit.
 *
 * In parallel each rank detects among the blocks of its region
 * (spatial.c), keeping the pairs it decides: every pair is decided by one
 * rank, which holds both its blocks whole, and the edge order within a
 * block is the file's, so each pair's pieces, their order and their merge
 * are the serial reader's to the last bit. */
#include <stdint.h>
#include <stdlib.h>
#include "geometry/validate.h"
#include "util/compat.h"

/* ------------------------------------------------------------ tolerances */

PetscErrorCode BwToleranceCompute(MPI_Comm comm, PetscInt nv_global, PetscInt vstart, PetscInt nv, const PetscReal xy[], PetscInt nb, const PetscInt offsets[], PetscReal e, BwTolerance *tol)
{
  const PetscInt ns = PetscMin(nv_global, 4096);
  PetscInt       n = 0, b = 0;
  PetscReal     *len, *all, xmax = 0, gmax;
  PetscMPIInt    size, *counts, *displs, mine;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < 2 * nv; k++) xmax = PetscMax(xmax, PetscAbsReal(xy[k]));
  PetscCallMPI(MPIU_Allreduce(&xmax, &gmax, 1, MPIU_REAL, MPIU_MAX, comm));
  /* an even sample of the edges, by global vertex row: the median of 4096
   * is as good as the median of millions for setting a tolerance, and
   * costs nothing; each rank measures the samples among its rows */
  PetscCall(PetscMalloc2(ns + 1, &len, ns + 1, &all));
  for (PetscInt s = 0; s < ns; s++) {
    PetscInt v = (PetscInt)(((int64_t)s * nv_global) / ns) - vstart, v1;
    if (v < 0 || v >= nv) continue;
    while (offsets[b + 1] <= v) b++; /* block of row v: rows ascend with s */
    v1       = v + 1 < offsets[b + 1] ? v + 1 : offsets[b];
    len[n++] = PetscSqrtReal(PetscSqr(xy[2 * v1] - xy[2 * v]) + PetscSqr(xy[2 * v1 + 1] - xy[2 * v + 1]));
  }
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscMalloc2(size, &counts, size + 1, &displs));
  mine = (PetscMPIInt)n;
  PetscCallMPI(MPI_Allgather(&mine, 1, MPI_INT, counts, 1, MPI_INT, comm));
  displs[0] = 0;
  for (PetscMPIInt r = 0; r < size; r++) displs[r + 1] = displs[r] + counts[r];
  PetscCallMPI(MPI_Allgatherv(len, mine, MPIU_REAL, all, counts, displs, MPIU_REAL, comm));
  n = displs[size];
  PetscCall(PetscSortReal(n, all));
  tol->edge      = n ? all[n / 2] : 0;
  tol->delta     = 1e-6 * tol->edge + 1e-12 * gmax;
  tol->thickness = e;
  tol->gapmax    = e * (1 + 1e-6) + tol->delta;
  tol->cosang    = PetscCosReal(BW_FACING_ANGLE);
  PetscCall(PetscFree2(counts, displs));
  PetscCall(PetscFree2(len, all));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ spatial hash */

static PetscErrorCode BwIntBufGrow(BwIntBuf *b)
{
  PetscFunctionBeginUser;
  b->cap = PetscMax(2 * b->cap, 64);
  PetscCall(PetscRealloc(sizeof(PetscInt) * (size_t)b->cap, &b->a));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwIntBufPush(BwIntBuf *b, PetscInt v)
{
  PetscFunctionBeginUser;
  if (b->n == b->cap) PetscCall(BwIntBufGrow(b));
  b->a[b->n++] = v;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static inline PetscInt BwGridBucket(const BwGrid *g, int64_t ix, int64_t iy)
{
  uint64_t z = (uint64_t)ix * 0x9E3779B97F4A7C15ULL ^ ((uint64_t)iy + 0x632BE59BD9B4E019ULL);
  z ^= z >> 31;
  z *= 0xBF58476D1CE4E5B9ULL;
  z ^= z >> 29;
  return (PetscInt)(z & (uint64_t)g->mask);
}

static inline int64_t BwGridCell(PetscReal v, PetscReal v0, PetscReal h) { return (int64_t)PetscFloorReal((v - v0) / h); }

/* Buckets of the cells the thick segment of `item` touches, column by
 * column: in each column of cells, the part of P-Q whose grown box reaches
 * the column spans a range of y, grown by ry. The work is proportional to
 * the segment's length over h, whatever its direction. */
static PetscErrorCode BwGridCover(BwGrid *g, PetscInt item)
{
  PetscReal P[2], Q[2], rx, ry, xa, xb, ya, yb;
  int64_t   ix0, ix1;

  PetscFunctionBeginUser;
  g->shape(g->ctx, item, P, Q, &rx, &ry);
  g->cells.n = 0;
  xa         = PetscMin(P[0], Q[0]);
  xb         = PetscMax(P[0], Q[0]);
  ya         = PetscMin(P[1], Q[1]);
  yb         = PetscMax(P[1], Q[1]);
  ix0        = BwGridCell(xa - rx, g->x0, g->h);
  ix1        = BwGridCell(xb + rx, g->x0, g->h);
  for (int64_t ix = ix0; ix <= ix1; ix++) {
    PetscReal lo = PetscMax(g->x0 + (PetscReal)ix * g->h - rx, xa), hi = PetscMin(g->x0 + (PetscReal)(ix + 1) * g->h + rx, xb), ylo, yhi;
    int64_t   iy0, iy1;

    if (lo > hi) lo = hi = PetscMin(PetscMax(lo, xa), xb);
    if (xb > xa) {
      PetscReal y0 = P[1] + (lo - P[0]) * (Q[1] - P[1]) / (Q[0] - P[0]);
      PetscReal y1 = P[1] + (hi - P[0]) * (Q[1] - P[1]) / (Q[0] - P[0]);
      ylo          = PetscMax(PetscMin(y0, y1), ya);
      yhi          = PetscMin(PetscMax(y0, y1), yb);
      if (ylo > yhi) ylo = yhi = PetscMin(PetscMax(ylo, ya), yb);
    } else {
      ylo = ya;
      yhi = yb;
    }
    iy0 = BwGridCell(ylo - ry, g->y0, g->h);
    iy1 = BwGridCell(yhi + ry, g->y0, g->h);
    for (int64_t iy = iy0; iy <= iy1; iy++) PetscCall(BwIntBufPush(&g->cells, BwGridBucket(g, ix, iy)));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGridCreate(PetscInt nitems, BwGridShape shape, void *ctx, const PetscInt group[], PetscReal h, BwGrid *g)
{
  PetscReal xmin = PETSC_MAX_REAL, ymin = PETSC_MAX_REAL, xmax = PETSC_MIN_REAL, ymax = PETSC_MIN_REAL;
  PetscInt  nbuckets = 1024, total = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(g, sizeof(*g)));
  g->shape = shape;
  g->ctx   = ctx;
  g->group = group;
  g->h     = h;
  for (PetscInt k = 0; k < nitems; k++) {
    PetscReal P[2], Q[2], rx, ry;
    shape(ctx, k, P, Q, &rx, &ry);
    xmin = PetscMin(xmin, PetscMin(P[0], Q[0]) - rx);
    xmax = PetscMax(xmax, PetscMax(P[0], Q[0]) + rx);
    ymin = PetscMin(ymin, PetscMin(P[1], Q[1]) - ry);
    ymax = PetscMax(ymax, PetscMax(P[1], Q[1]) + ry);
  }
  if (!nitems) xmin = xmax = ymin = ymax = 0;
  g->x0 = xmin;
  g->y0 = ymin;
  /* Cell indices must stay exact integers in a double. */
  PetscCheck(h > 0 && (xmax - xmin) / h < 1e15 && (ymax - ymin) / h < 1e15, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "the blocks span %g m x %g m, %g times their typical edge of %g m: too wide a range of sizes to find neighbours", (double)(xmax - xmin), (double)(ymax - ymin), (double)(PetscMax(xmax - xmin, ymax - ymin) / h), (double)h);
  while (nbuckets < 2 * nitems && nbuckets < PETSC_MAX_INT / 4) nbuckets *= 2;
  g->mask = nbuckets - 1;
  PetscCall(PetscCalloc1(nbuckets + 1, &g->start));
  for (PetscInt k = 0; k < nitems; k++) {
    PetscCall(BwGridCover(g, k));
    for (PetscInt c = 0; c < g->cells.n; c++) g->start[g->cells.a[c] + 1]++;
    PetscCheck(total <= PETSC_MAX_INT - g->cells.n, PETSC_COMM_SELF, PETSC_ERR_SUP, "spatial hash: more than %d cell entries", (int)PETSC_MAX_INT);
    total += g->cells.n;
  }
  for (PetscInt b = 0; b < nbuckets; b++) g->start[b + 1] += g->start[b];
  PetscCall(PetscMalloc1(total + 1, &g->item));
  /* fill, using start[b] as the fill pointer of bucket b, then shift back */
  for (PetscInt k = 0; k < nitems; k++) {
    PetscCall(BwGridCover(g, k));
    for (PetscInt c = 0; c < g->cells.n; c++) g->item[g->start[g->cells.a[c]]++] = k;
  }
  for (PetscInt b = nbuckets; b > 0; b--) g->start[b] = g->start[b - 1];
  g->start[0] = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGridCandidates(BwGrid *g, PetscInt item)
{
  PetscFunctionBeginUser;
  PetscCall(BwGridCover(g, item));
  PetscCall(PetscSortRemoveDupsInt(&g->cells.n, g->cells.a));
  g->cand.n = 0;
  for (PetscInt c = 0; c < g->cells.n; c++) {
    PetscInt b = g->cells.a[c], lo = g->start[b], hi = g->start[b + 1], skip0 = hi, skip1 = hi;
    if (g->group) {
      /* a bucket's items are in item order, hence in group order: the
       * run of item's own group is [skip0, skip1) */
      PetscInt gr = g->group[item], l = lo, r = hi;
      while (l < r) {
        PetscInt mid = (l + r) / 2;
        if (g->group[g->item[mid]] < gr) l = mid + 1;
        else r = mid;
      }
      skip0 = l;
      r     = hi;
      while (l < r) {
        PetscInt mid = (l + r) / 2;
        if (g->group[g->item[mid]] <= gr) l = mid + 1;
        else r = mid;
      }
      skip1 = l;
    }
    for (PetscInt k = lo; k < hi; k++) {
      if (k == skip0) {
        k = skip1 - 1;
        continue;
      }
      if (g->item[k] > item) PetscCall(BwIntBufPush(&g->cand, g->item[k]));
    }
  }
  PetscCall(PetscSortRemoveDupsInt(&g->cand.n, g->cand.a));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGridDestroy(BwGrid *g)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(g->start));
  PetscCall(PetscFree(g->item));
  PetscCall(PetscFree(g->cells.a));
  PetscCall(PetscFree(g->cand.a));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ facing edges */

/* A facing edge pair: edges a -> a1 of block i and b -> b1 of block j
 * (vertex indices), i < j, and the sort key of the piece. */
typedef struct {
  PetscInt  i, j, a, a1, b, b1;
  PetscReal key;
} BwPiece;

/* The piece's mid-plane segment m0 -> m1 (increasing s) and its normal. */
typedef struct {
  PetscReal m0[2], m1[2], n[2], key;
} BwFace;

/* The rule of the header comment; pure arithmetic, no allocation. */
static PetscBool BwFacing(const PetscReal *v, PetscInt a, PetscInt a1, PetscInt b, PetscInt b1, const BwTolerance *tol, BwFace *f)
{
  const PetscReal *A0 = v + 2 * a, *A1 = v + 2 * a1, *B0 = v + 2 * b, *B1 = v + 2 * b1;
  PetscReal        da[2] = {A1[0] - A0[0], A1[1] - A0[1]}, db[2] = {B1[0] - B0[0], B1[1] - B0[1]};
  PetscReal        la = PetscSqrtReal(da[0] * da[0] + da[1] * da[1]), lb = PetscSqrtReal(db[0] * db[0] + db[1] * db[1]);
  PetscReal        na[2], nb[2], n[2], t[2], ln, sa1, ha1, sb0, hb0, sb1, hb1, lo, hi, s[2], ha[2], hb[2];

  if (!(la > 0 && lb > 0)) return PETSC_FALSE;
  na[0] = da[1] / la;
  na[1] = -da[0] / la;
  nb[0] = db[1] / lb;
  nb[1] = -db[0] / lb;
  if (na[0] * nb[0] + na[1] * nb[1] > -tol->cosang) return PETSC_FALSE;
  n[0] = na[0] - nb[0];
  n[1] = na[1] - nb[1];
  ln   = PetscSqrtReal(n[0] * n[0] + n[1] * n[1]);
  n[0] /= ln;
  n[1] /= ln;
  t[0] = n[1];
  t[1] = -n[0];
  /* coordinates from A0: a runs from s = 0 to s = sa1 (< 0, since t ~ -d_a) */
  sa1 = da[0] * t[0] + da[1] * t[1];
  ha1 = da[0] * n[0] + da[1] * n[1];
  sb0 = (B0[0] - A0[0]) * t[0] + (B0[1] - A0[1]) * t[1];
  hb0 = (B0[0] - A0[0]) * n[0] + (B0[1] - A0[1]) * n[1];
  sb1 = (B1[0] - A0[0]) * t[0] + (B1[1] - A0[1]) * t[1];
  hb1 = (B1[0] - A0[0]) * n[0] + (B1[1] - A0[1]) * n[1];
  lo  = PetscMax(PetscMin(0, sa1), PetscMin(sb0, sb1));
  hi  = PetscMin(PetscMax(0, sa1), PetscMax(sb0, sb1));
  if (!(hi - lo > tol->delta)) return PETSC_FALSE;
  s[0] = lo;
  s[1] = hi;
  for (int k = 0; k < 2; k++) {
    PetscReal gap;
    ha[k] = ha1 * s[k] / sa1;                         /* sa1 != 0: a is nearly along -t */
    hb[k] = hb0 + (s[k] - sb0) * (hb1 - hb0) / (sb1 - sb0);
    gap   = hb[k] - ha[k];
    if (!(gap >= -tol->delta && gap <= tol->gapmax)) return PETSC_FALSE;
  }
  for (int c = 0; c < 2; c++) {
    f->m0[c] = A0[c] + s[0] * t[c] + 0.5 * (ha[0] + hb[0]) * n[c];
    f->m1[c] = A0[c] + s[1] * t[c] + 0.5 * (ha[1] + hb[1]) * n[c];
    f->n[c]  = n[c];
  }
  f->key = -hi; /* distance along a from A0 to the piece's nearer end */
  return PETSC_TRUE;
}

static int BwPieceCompare(const void *x, const void *y)
{
  const BwPiece *p = (const BwPiece *)x, *q = (const BwPiece *)y;
  if (p->i != q->i) return p->i < q->i ? -1 : 1;
  if (p->j != q->j) return p->j < q->j ? -1 : 1;
  if (p->a != q->a) return p->a < q->a ? -1 : 1;
  if (p->key != q->key) return p->key < q->key ? -1 : 1;
  if (p->b != q->b) return p->b < q->b ? -1 : 1;
  return 0;
}

/* Do faces p and q lie on one line and touch along it? */
static PetscBool BwFaceMergeable(const BwFace *p, const BwFace *q, const BwTolerance *tol)
{
  PetscReal t[2] = {p->n[1], -p->n[0]}, s1 = (p->m1[0] - p->m0[0]) * t[0] + (p->m1[1] - p->m0[1]) * t[1];
  PetscReal h1 = (p->m1[0] - p->m0[0]) * p->n[0] + (p->m1[1] - p->m0[1]) * p->n[1], sq[2];
  const PetscReal *m[2] = {q->m0, q->m1};

  if (p->n[0] * q->n[0] + p->n[1] * q->n[1] < tol->cosang) return PETSC_FALSE;
  for (int k = 0; k < 2; k++) {
    PetscReal d[2] = {m[k][0] - p->m0[0], m[k][1] - p->m0[1]};
    PetscReal h    = d[0] * p->n[0] + d[1] * p->n[1];
    sq[k]          = d[0] * t[0] + d[1] * t[1];
    /* offset from p's mid-plane line, which runs from (0, 0) to (s1, h1) */
    if (PetscAbsReal(h - h1 * sq[k] / s1) > 4 * tol->delta) return PETSC_FALSE;
  }
  return PetscMin(sq[0], sq[1]) <= s1 + tol->delta && PetscMax(sq[0], sq[1]) >= -tol->delta ? PETSC_TRUE : PETSC_FALSE;
}

typedef struct {
  PetscInt   n, cap;
  BwSegment *s;
} BwSegBuf;

static PetscErrorCode BwSegBufPush(BwSegBuf *buf, const BwSegment *seg)
{
  PetscFunctionBeginUser;
  if (buf->n == buf->cap) {
    buf->cap = PetscMax(2 * buf->cap, 16);
    PetscCall(PetscRealloc(sizeof(BwSegment) * (size_t)buf->cap, &buf->s));
  }
  buf->s[buf->n++] = *seg;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The interfaces of one pair from its sorted pieces p[0..np), appended to
 * out in the order of each group's first piece. */
static PetscErrorCode BwMergePieces(const PetscReal *v, PetscInt np, const BwPiece p[], const BwTolerance *tol, BwSegBuf *out)
{
  BwFace    one, *f = &one;
  PetscInt *root = NULL;

  PetscFunctionBeginUser;
  if (np > 1) {
    PetscCall(PetscMalloc2(np, &f, np, &root));
    for (PetscInt k = 0; k < np; k++) root[k] = k;
  }
  for (PetscInt k = 0; k < np; k++) {
    PetscBool ok = BwFacing(v, p[k].a, p[k].a1, p[k].b, p[k].b1, tol, &f[k]);
    PetscCheck(ok, PETSC_COMM_SELF, PETSC_ERR_PLIB, "facing edges %" PetscInt_FMT ", %" PetscInt_FMT " no longer face", p[k].a, p[k].b);
  }
  /* union-find, roots at the smallest index so that groups keep sort order */
  for (PetscInt k = 1; k < np; k++)
    for (PetscInt l = 0; l < k; l++) {
      PetscInt rk = k, rl = l;
      while (root[rk] != rk) rk = root[rk];
      while (root[rl] != rl) rl = root[rl];
      if (rk != rl && (BwFaceMergeable(&f[l], &f[k], tol) || BwFaceMergeable(&f[k], &f[l], tol))) {
        if (rk < rl) root[rl] = rk;
        else root[rk] = rl;
      }
    }
  for (PetscInt r = 0; r < np; r++) {
    const BwFace *fr = &f[r];
    PetscReal     t[2] = {fr->n[1], -fr->n[0]}, smin = PETSC_MAX_REAL, smax = PETSC_MIN_REAL, s1, h1, smid, hmid;
    BwSegment     seg;

    if (np > 1) {
      PetscInt rr = r;
      while (root[rr] != rr) rr = root[rr];
      if (rr != r) continue;
    }
    for (PetscInt k = r; k < np; k++) {
      PetscInt rk = k;
      if (np > 1)
        while (root[rk] != rk) rk = root[rk];
      if (rk != r) continue;
      smin = PetscMin(smin, PetscMin((f[k].m0[0] - fr->m0[0]) * t[0] + (f[k].m0[1] - fr->m0[1]) * t[1], (f[k].m1[0] - fr->m0[0]) * t[0] + (f[k].m1[1] - fr->m0[1]) * t[1]));
      smax = PetscMax(smax, PetscMax((f[k].m0[0] - fr->m0[0]) * t[0] + (f[k].m0[1] - fr->m0[1]) * t[1], (f[k].m1[0] - fr->m0[0]) * t[0] + (f[k].m1[1] - fr->m0[1]) * t[1]));
    }
    s1   = (fr->m1[0] - fr->m0[0]) * t[0] + (fr->m1[1] - fr->m0[1]) * t[1];
    h1   = (fr->m1[0] - fr->m0[0]) * fr->n[0] + (fr->m1[1] - fr->m0[1]) * fr->n[1];
    smid = 0.5 * (smin + smax);
    hmid = h1 * smid / s1;
    for (int c = 0; c < 2; c++) seg.center[c] = fr->m0[c] + smid * t[c] + hmid * fr->n[c];
    seg.angle  = PetscAtan2Real(t[1], t[0]) + 0.0; /* no -0 */
    seg.length = smax - smin;
    PetscCall(BwSegBufPush(out, &seg));
  }
  if (np > 1) PetscCall(PetscFree2(f, root));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwDetectPair(const PetscReal x[], const PetscInt o[], const BwTolerance *tol, PetscInt i, PetscInt j, PetscInt *n, PetscInt *cap, BwSegment **seg)
{
  BwPiece *p  = NULL;
  PetscInt np = 0, pcap = 0;
  BwSegBuf out = {0, *cap, *seg};

  PetscFunctionBeginUser;
  for (PetscInt a = o[i]; a < o[i + 1]; a++)
    for (PetscInt b = o[j]; b < o[j + 1]; b++) {
      PetscInt a1 = a + 1 < o[i + 1] ? a + 1 : o[i], b1 = b + 1 < o[j + 1] ? b + 1 : o[j];
      BwFace   f;
      if (!BwFacing(x, a, a1, b, b1, tol, &f)) continue;
      if (np == pcap) {
        pcap = PetscMax(2 * pcap, 8);
        PetscCall(PetscRealloc(sizeof(BwPiece) * (size_t)pcap, &p));
      }
      p[np].i   = i;
      p[np].j   = j;
      p[np].a   = a;
      p[np].a1  = a1;
      p[np].b   = b;
      p[np].b1  = b1;
      p[np].key = f.key;
      np++;
    }
  if (np > 1) qsort(p, (size_t)np, sizeof(BwPiece), BwPieceCompare);
  PetscCall(BwMergePieces(x, np, p, tol, &out));
  PetscCall(PetscFree(p));
  *n   = out.n;
  *cap = out.cap;
  *seg = out.s;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ detection */

/* An edge grown by half the widest gap plus delta on each side: two edges
 * at most gapmax apart then share a cell (the middle of the gap is within
 * reach of both). */
void BwEdgeShape(void *ctx, PetscInt e, PetscReal P[2], PetscReal Q[2], PetscReal *rx, PetscReal *ry)
{
  BwEdgeShapeCtx *c = (BwEdgeShapeCtx *)ctx;
  P[0]              = c->v[2 * e];
  P[1]              = c->v[2 * e + 1];
  Q[0]              = c->v[2 * c->next[e]];
  Q[1]              = c->v[2 * c->next[e] + 1];
  *rx = *ry = c->reach;
}

PetscErrorCode BwDetectInterfaces(const BwBlockView *v, const BwTolerance *tol, BwDecide decide, void *dctx, PetscInt *nout, PetscInt **pairout, BwSegment **segout)
{
  PetscInt       nb = v->n, nv = v->offsets[nb], np = 0, pcap = 0, *blk, *next, *count, nfound = 0, fcap = 0, *pair = NULL;
  BwPiece       *p = NULL, *sorted;
  BwGrid         grid;
  BwEdgeShapeCtx ctx;
  BwSegBuf       out = {0, 0, NULL}, found = {0, 0, NULL};

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(nv, &blk, nv, &next));
  for (PetscInt b = 0; b < nb; b++)
    for (PetscInt e = v->offsets[b]; e < v->offsets[b + 1]; e++) {
      blk[e]  = b;
      next[e] = e + 1 < v->offsets[b + 1] ? e + 1 : v->offsets[b];
    }
  ctx.v     = v->x;
  ctx.next  = next;
  ctx.reach = 0.5 * tol->gapmax + tol->delta;
  /* Cells about the size of a typical edge: an edge then touches a few
   * cells and a cell holds a few edges, whatever the number of blocks. */
  PetscCall(BwGridCreate(nv, BwEdgeShape, &ctx, blk, PetscMax(1.5 * tol->edge, 4 * ctx.reach), &grid));
  for (PetscInt ea = 0; ea < nv; ea++) {
    PetscCall(BwGridCandidates(&grid, ea));
    for (PetscInt c = 0; c < grid.cand.n; c++) {
      PetscInt eb = grid.cand.a[c], a, b;
      BwFace   f;
      if (blk[eb] == blk[ea]) continue;
      a = blk[ea] < blk[eb] ? ea : eb;
      b = blk[ea] < blk[eb] ? eb : ea;
      if (!BwFacing(v->x, a, next[a], b, next[b], tol, &f)) continue;
      /* another rank decides this pair: it holds both blocks too */
      if (decide && !decide(dctx, blk[a], blk[b])) continue;
      if (np == pcap) {
        pcap = PetscMax(2 * pcap, 1024);
        PetscCall(PetscRealloc(sizeof(BwPiece) * (size_t)pcap, &p));
      }
      p[np].i   = blk[a];
      p[np].j   = blk[b];
      p[np].a   = a;
      p[np].a1  = next[a];
      p[np].b   = b;
      p[np].b1  = next[b];
      p[np].key = f.key;
      np++;
    }
  }
  PetscCall(BwGridDestroy(&grid));

  /* counting sort by block i, then a small sort within each block */
  PetscCall(PetscCalloc1(nb + 1, &count));
  PetscCall(PetscMalloc1(np + 1, &sorted));
  for (PetscInt k = 0; k < np; k++) count[p[k].i + 1]++;
  for (PetscInt b = 0; b < nb; b++) count[b + 1] += count[b];
  for (PetscInt k = 0; k < np; k++) sorted[count[p[k].i]++] = p[k];
  PetscCall(PetscFree(p));
  for (PetscInt k0 = 0; k0 < np;) {
    PetscInt k1 = k0;
    while (k1 < np && sorted[k1].i == sorted[k0].i) k1++;
    if (k1 - k0 > 1) qsort(sorted + k0, (size_t)(k1 - k0), sizeof(BwPiece), BwPieceCompare);
    for (PetscInt r0 = k0; r0 < k1;) {
      PetscInt r1 = r0;
      while (r1 < k1 && sorted[r1].j == sorted[r0].j) r1++;
      out.n = 0;
      PetscCall(BwMergePieces(v->x, r1 - r0, sorted + r0, tol, &out));
      for (PetscInt s = 0; s < out.n; s++) {
        if (nfound == fcap) {
          fcap = PetscMax(2 * fcap, 1024);
          PetscCall(PetscRealloc(sizeof(PetscInt) * 2 * (size_t)fcap, &pair));
        }
        pair[2 * nfound]     = sorted[r0].i;
        pair[2 * nfound + 1] = sorted[r0].j;
        nfound++;
        PetscCall(BwSegBufPush(&found, &out.s[s]));
      }
      r0 = r1;
    }
    k0 = k1;
  }
  PetscCall(PetscFree(out.s));
  PetscCall(PetscFree(sorted));
  PetscCall(PetscFree(count));
  PetscCall(PetscFree2(blk, next));
  *nout    = nfound;
  *pairout = pair;
  *segout  = found.s;
  PetscFunctionReturn(PETSC_SUCCESS);
}
