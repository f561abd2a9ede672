/* Checks of a block assembly read from a file: each defect is one line
 * naming the file, the dataset and the block, and the first one found wins.
 *
 * Polygons (per block, O(n log n) in its vertex count n: pairs of edges
 *   from the sweeps of polygon_sweep.c, or all pairs when n is small; their
 *   coordinates were found finite before the tolerances were computed):
 *   at least 3 vertices; consecutive vertices (and the
 *   last and the first) more than delta apart; non-adjacent edges more than
 *   delta apart (else the polygon crosses itself; this also catches edges
 *   folding back onto their neighbour, whose far end then touches the edge
 *   before); |area| > delta * perimeter / 2 (a polygon thinner than delta
 *   has zero area: this is what a triangle with collinear corners fails). A
 *   clockwise polygon (area < 0) is reversed, its vertex 0 kept first.
 * Overlaps (O(N) with the spatial hash over bounding boxes): two blocks
 * whose boxes overlap by more than delta in x and y are intersected
 *   area(A n B) = sum over convex pieces C of B of area(clip(A, C))
 * (Sutherland-Hodgman: clipping any polygon by a convex one gives the area
 * of their intersection exactly, since the chords it adds along each clip
 * line cancel in the shoelace sum); B is split into triangles by ear
 * clipping when neither block is convex. They overlap when that area
 * exceeds delta * (smaller perimeter): faces pressed into each other by
 * less than delta are touching, not overlapping.
 * Connection: every block has an interface (with more than one block). A
 * block that touches nothing is almost always a gap drawn wider than e, and
 * would otherwise surface later as "not restrained" or as a block that
 * carries its own load alone. Separate groups of several blocks are
 * allowed (two walls in one file); restraint.c requires each to be held. */
#include "geometry/validate.h"
#include "util/compat.h"

static inline PetscReal BwCross(PetscReal ax, PetscReal ay, PetscReal bx, PetscReal by) { return ax * by - ay * bx; }

/* Edges k (k -> k+1) and l > k + 1 of a polygon: more than d apart, unless
 * they are neighbours through vertex 0. */
static PetscErrorCode BwPolygonEdges(const char file[], PetscInt b, PetscInt first, PetscInt nv, const PetscReal xy[], PetscInt k, PetscInt l, PetscReal d)
{
  PetscInt k1 = k + 1, l1 = (l + 1) % nv;

  PetscFunctionBeginUser;
  if (l1 == k) PetscFunctionReturn(PETSC_SUCCESS); /* edges nv-1 and 0 share vertex 0 */
  PetscCheck(BwSegmentDistance(xy + 2 * k, xy + 2 * k1, xy + 2 * l, xy + 2 * l1) > d, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "%s: /blocks/vertices: block %" PetscInt_FMT " is self-intersecting: its edges from row %" PetscInt_FMT " to %" PetscInt_FMT " and from row %" PetscInt_FMT " to %" PetscInt_FMT " cross or touch", file, b, first + k, first + k1, first + l, first + l1);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwValidatePolygon(const char file[], PetscInt b, PetscInt first, PetscInt nv, PetscReal xy[], const BwTolerance *tol)
{
  const PetscReal d = tol->delta;
  PetscReal       area = 0, perimeter = 0;

  PetscFunctionBeginUser;
  PetscCheck(nv >= 3, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /blocks/offsets: block %" PetscInt_FMT " has %" PetscInt_FMT " vertices (rows %" PetscInt_FMT "..%" PetscInt_FMT " of /blocks/vertices); a polygon needs at least 3", file, b, nv, first, first + nv - 1);
  for (PetscInt k = 0; k < nv; k++) {
    PetscInt  k1 = (k + 1) % nv;
    PetscReal l  = PetscSqrtReal(PetscSqr(xy[2 * k1] - xy[2 * k]) + PetscSqr(xy[2 * k1 + 1] - xy[2 * k + 1]));
    if (l > d) continue;
    if (k1 == 0)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /blocks/vertices: block %" PetscInt_FMT ": its last vertex (row %" PetscInt_FMT ") repeats its first (row %" PetscInt_FMT ") at (%g, %g): duplicate vertices; list each corner once, the polygon closes by itself", file, b, first + k, first, (double)xy[0], (double)xy[1]);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /blocks/vertices: block %" PetscInt_FMT ": duplicate vertices: consecutive rows %" PetscInt_FMT " and %" PetscInt_FMT " coincide at (%g, %g)", file, b, first + k, first + k1, (double)xy[2 * k], (double)xy[2 * k + 1]);
  }
  /* non-adjacent edges k (k -> k+1) and l: all pairs for small polygons,
   * above the sweeps of polygon_sweep.c, O(n log n) on any polygon (a grid
   * of the edges took 1.7 s at 1e5 vertices on a steep zigzag) */
  if (nv <= 64) {
    for (PetscInt k = 0; k < nv; k++)
      for (PetscInt l = k + 2; l < nv; l++) PetscCall(BwPolygonEdges(file, b, first, nv, xy, k, l, d));
  } else {
    PetscInt   k, l;
    PetscInt64 work;
    PetscCall(BwPolygonCloseEdges(nv, xy, d, &k, &l, &work));
    PetscCall(PetscInfo(NULL, "block %" PetscInt_FMT ": %" PetscInt_FMT " vertices checked for crossing edges with %" PetscInt64_FMT " steps\n", b, nv, work));
    if (k >= 0) PetscCall(BwPolygonEdges(file, b, first, nv, xy, k, l, d));
  }
  for (PetscInt k = 0; k < nv; k++) {
    PetscInt k1 = (k + 1) % nv;
    area += BwCross(xy[2 * k] - xy[0], xy[2 * k + 1] - xy[1], xy[2 * k1] - xy[0], xy[2 * k1 + 1] - xy[1]);
    perimeter += PetscSqrtReal(PetscSqr(xy[2 * k1] - xy[2 * k]) + PetscSqr(xy[2 * k1 + 1] - xy[2 * k + 1]));
  }
  area *= 0.5;
  PetscCheck(PetscAbsReal(area) > 0.5 * d * perimeter, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /blocks/vertices: block %" PetscInt_FMT " (rows %" PetscInt_FMT "..%" PetscInt_FMT ") has zero area (%g m^2 for a perimeter of %g m): its vertices are collinear", file, b, first, first + nv - 1, (double)area, (double)perimeter);
  if (area < 0) {
    for (PetscInt k = 1, l = nv - 1; k < l; k++, l--)
      for (int c = 0; c < 2; c++) {
        PetscReal s     = xy[2 * k + c];
        xy[2 * k + c]   = xy[2 * l + c];
        xy[2 * l + c]   = s;
      }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ overlaps */

typedef struct {
  PetscInt   n, cap;
  PetscReal *a;
} BwRealBuf;

static PetscErrorCode BwRealBufReserve(BwRealBuf *b, PetscInt n)
{
  PetscFunctionBeginUser;
  if (n > b->cap) {
    b->cap = PetscMax(n, 2 * b->cap);
    PetscCall(PetscRealloc(sizeof(PetscReal) * (size_t)b->cap, &b->a));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

typedef struct {
  BwRealBuf s, w0, w1, c; /* shifted subject, clip work, shifted clip */
  BwIntBuf  tri, idx;     /* triangles of a non-convex clip polygon */
} BwClipWork;

/* Signed area of the polygon subject (ns points) inside the convex,
 * counter-clockwise polygon clip (nc points). */
static PetscErrorCode BwClipArea(BwClipWork *w, PetscInt ns, const PetscReal s[], PetscInt nc, const PetscReal c[], PetscReal *area)
{
  BwRealBuf *in = &w->w0, *out = &w->w1, *tmp;
  PetscInt   n  = ns;

  PetscFunctionBeginUser;
  *area = 0;
  PetscCall(BwRealBufReserve(in, 2 * ns));
  PetscCall(PetscArraycpy(in->a, s, 2 * ns));
  for (PetscInt k = 0; k < nc && n > 0; k++) {
    const PetscReal *c0 = c + 2 * k, *c1 = c + 2 * ((k + 1) % nc);
    PetscReal        e[2] = {c1[0] - c0[0], c1[1] - c0[1]};
    PetscInt         m = 0;

    PetscCall(BwRealBufReserve(out, 4 * n + 4));
    for (PetscInt i = 0; i < n; i++) {
      const PetscReal *P = in->a + 2 * i, *Q = in->a + 2 * ((i + 1) % n);
      PetscReal        sp = BwCross(e[0], e[1], P[0] - c0[0], P[1] - c0[1]), sq = BwCross(e[0], e[1], Q[0] - c0[0], Q[1] - c0[1]);
      if (sp >= 0) {
        out->a[2 * m]     = P[0];
        out->a[2 * m + 1] = P[1];
        m++;
      }
      if ((sp >= 0) != (sq >= 0)) {
        PetscReal t       = sp / (sp - sq);
        out->a[2 * m]     = P[0] + t * (Q[0] - P[0]);
        out->a[2 * m + 1] = P[1] + t * (Q[1] - P[1]);
        m++;
      }
    }
    n   = m;
    tmp = in;
    in  = out;
    out = tmp;
  }
  for (PetscInt i = 0; i < n; i++) {
    PetscInt i1 = (i + 1) % n;
    *area += 0.5 * BwCross(in->a[2 * i], in->a[2 * i + 1], in->a[2 * i1], in->a[2 * i1 + 1]);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Ear clipping of a simple counter-clockwise polygon into w->tri (3
 * indices per triangle). An ear is a strictly convex corner whose triangle
 * holds no other vertex; every simple polygon has one, but collinear
 * corners and round-off can hide it: then the flattest corner goes. */
static PetscErrorCode BwTriangulate(BwClipWork *w, PetscInt n, const PetscReal p[])
{
  PetscInt m = n, *idx;

  PetscFunctionBeginUser;
  w->idx.n = w->tri.n = 0;
  for (PetscInt k = 0; k < n; k++) PetscCall(BwIntBufPush(&w->idx, k));
  idx = w->idx.a;
  while (m > 3) {
    PetscInt  ear = -1, flat = 0;
    PetscReal flatness = PETSC_MAX_REAL;
    for (PetscInt k = 0; k < m && ear < 0; k++) {
      PetscInt         a = idx[(k + m - 1) % m], b = idx[k], c = idx[(k + 1) % m];
      const PetscReal *A = p + 2 * a, *B = p + 2 * b, *C = p + 2 * c;
      PetscReal        cr = BwCross(B[0] - A[0], B[1] - A[1], C[0] - B[0], C[1] - B[1]);
      PetscBool        empty = PETSC_TRUE;
      if (PetscAbsReal(cr) < flatness) {
        flatness = PetscAbsReal(cr);
        flat     = k;
      }
      if (cr <= 0) continue;
      for (PetscInt r = 0; r < m && empty; r++) {
        const PetscReal *R = p + 2 * idx[r];
        if (idx[r] == a || idx[r] == b || idx[r] == c) continue;
        if (BwCross(B[0] - A[0], B[1] - A[1], R[0] - A[0], R[1] - A[1]) >= 0 && BwCross(C[0] - B[0], C[1] - B[1], R[0] - B[0], R[1] - B[1]) >= 0 && BwCross(A[0] - C[0], A[1] - C[1], R[0] - C[0], R[1] - C[1]) >= 0) empty = PETSC_FALSE;
      }
      if (empty) ear = k;
    }
    if (ear < 0) ear = flat;
    PetscCall(BwIntBufPush(&w->tri, idx[(ear + m - 1) % m]));
    PetscCall(BwIntBufPush(&w->tri, idx[ear]));
    PetscCall(BwIntBufPush(&w->tri, idx[(ear + 1) % m]));
    for (PetscInt k = ear; k < m - 1; k++) idx[k] = idx[k + 1];
    m--;
  }
  for (PetscInt k = 0; k < 3; k++) PetscCall(BwIntBufPush(&w->tri, idx[k]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscBool BwConvex(PetscInt n, const PetscReal p[])
{
  for (PetscInt k = 0; k < n; k++) {
    const PetscReal *A = p + 2 * k, *B = p + 2 * ((k + 1) % n), *C = p + 2 * ((k + 2) % n);
    PetscReal        e0[2] = {B[0] - A[0], B[1] - A[1]}, e1[2] = {C[0] - B[0], C[1] - B[1]};
    if (BwCross(e0[0], e0[1], e1[0], e1[1]) < -1e-9 * PetscSqrtReal((e0[0] * e0[0] + e0[1] * e0[1]) * (e1[0] * e1[0] + e1[1] * e1[1]))) return PETSC_FALSE;
  }
  return PETSC_TRUE;
}

/* area(A n B) of blocks A, B of view v, coordinates shifted to A's first
 * vertex for their digits. */
static PetscErrorCode BwIntersectionArea(const BwBlockView *v, PetscInt A, PetscInt B, const PetscBool convex[], BwClipWork *w, PetscReal *area)
{
  const PetscReal *o = v->x + 2 * v->offsets[A];
  PetscInt         s = A, c = B, ns, nc;

  PetscFunctionBeginUser;
  if (!convex[B] && convex[A]) {
    s = B;
    c = A;
  }
  ns = v->offsets[s + 1] - v->offsets[s];
  nc = v->offsets[c + 1] - v->offsets[c];
  PetscCall(BwRealBufReserve(&w->s, 2 * ns));
  PetscCall(BwRealBufReserve(&w->c, 2 * nc));
  for (PetscInt k = 0; k < ns; k++)
    for (int d = 0; d < 2; d++) w->s.a[2 * k + d] = v->x[2 * (v->offsets[s] + k) + d] - o[d];
  for (PetscInt k = 0; k < nc; k++)
    for (int d = 0; d < 2; d++) w->c.a[2 * k + d] = v->x[2 * (v->offsets[c] + k) + d] - o[d];
  if (convex[c]) PetscCall(BwClipArea(w, ns, w->s.a, nc, w->c.a, area));
  else {
    *area = 0;
    PetscCall(BwTriangulate(w, nc, w->c.a));
    for (PetscInt t = 0; t < w->tri.n; t += 3) {
      PetscReal tri[6], a;
      for (int k = 0; k < 3; k++)
        for (int d = 0; d < 2; d++) tri[2 * k + d] = w->c.a[2 * w->tri.a[t + k] + d];
      PetscCall(BwClipArea(w, ns, w->s.a, 3, tri, &a));
      *area += a;
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwClipWorkFree(BwClipWork *w)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(w->s.a));
  PetscCall(PetscFree(w->w0.a));
  PetscCall(PetscFree(w->w1.a));
  PetscCall(PetscFree(w->c.a));
  PetscCall(PetscFree(w->tri.a));
  PetscCall(PetscFree(w->idx.a));
  PetscFunctionReturn(PETSC_SUCCESS);
}

void BwBoxShape(void *ctx, PetscInt b, PetscReal P[2], PetscReal Q[2], PetscReal *rx, PetscReal *ry)
{
  const PetscReal *x = (const PetscReal *)ctx + 4 * b;
  P[0]               = x[0];
  Q[0]               = x[2];
  P[1] = Q[1] = 0.5 * (x[1] + x[3]);
  *rx         = 0;
  *ry         = 0.5 * (x[3] - x[1]);
}

PetscErrorCode BwBlockBoxes(const BwBlockView *v, PetscReal box[], PetscReal perimeter[], PetscBool convex[])
{
  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < v->n; b++) {
    const PetscReal *x = v->x + 2 * v->offsets[b];
    PetscInt         n = v->offsets[b + 1] - v->offsets[b];
    box[4 * b] = box[4 * b + 2] = x[0];
    box[4 * b + 1] = box[4 * b + 3] = x[1];
    if (perimeter) perimeter[b] = 0;
    for (PetscInt k = 0; k < n; k++) {
      PetscInt k1    = (k + 1) % n;
      box[4 * b]     = PetscMin(box[4 * b], x[2 * k]);
      box[4 * b + 1] = PetscMin(box[4 * b + 1], x[2 * k + 1]);
      box[4 * b + 2] = PetscMax(box[4 * b + 2], x[2 * k]);
      box[4 * b + 3] = PetscMax(box[4 * b + 3], x[2 * k + 1]);
      if (perimeter) perimeter[b] += PetscSqrtReal(PetscSqr(x[2 * k1] - x[2 * k]) + PetscSqr(x[2 * k1 + 1] - x[2 * k + 1]));
    }
    if (convex) convex[b] = BwConvex(n, x);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGridCheckSpan(MPI_Comm comm, PetscInt n, BwGridShape shape, void *ctx, PetscReal h)
{
  PetscReal lo[2] = {PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[2] = {PETSC_MIN_REAL, PETSC_MIN_REAL}, glo[2], ghi[2];

  PetscFunctionBeginUser;
  /* BwGridCreate's bounds of the items */
  for (PetscInt b = 0; b < n; b++) {
    PetscReal P[2], Q[2], rx, ry;
    shape(ctx, b, P, Q, &rx, &ry);
    lo[0] = PetscMin(lo[0], PetscMin(P[0], Q[0]) - rx);
    hi[0] = PetscMax(hi[0], PetscMax(P[0], Q[0]) + rx);
    lo[1] = PetscMin(lo[1], PetscMin(P[1], Q[1]) - ry);
    hi[1] = PetscMax(hi[1], PetscMax(P[1], Q[1]) + ry);
  }
  PetscCallMPI(MPIU_Allreduce(lo, glo, 2, MPIU_REAL, MPIU_MIN, comm));
  PetscCallMPI(MPIU_Allreduce(hi, ghi, 2, MPIU_REAL, MPIU_MAX, comm));
  PetscCheck(h > 0 && (ghi[0] - glo[0]) / h < 1e15 && (ghi[1] - glo[1]) / h < 1e15, comm, PETSC_ERR_USER_INPUT,
             "the blocks span %g m x %g m, %g times their typical edge of %g m: too wide a range of sizes to find neighbours", (double)(ghi[0] - glo[0]), (double)(ghi[1] - glo[1]), (double)(PetscMax(ghi[0] - glo[0], ghi[1] - glo[1]) / h), (double)h);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwValidateOverlaps(const char file[], const BwBlockView *v, PetscInt B, const BwTolerance *tol, PetscReal h, BwDecide decide, void *dctx, int64_t stage, BwFault *fault)
{
  PetscInt   nb = v->n;
  PetscReal *box, *perimeter, d = tol->delta;
  PetscBool *convex;
  BwGrid     grid;
  BwClipWork w;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&w, sizeof(w)));
  PetscCall(PetscMalloc3(4 * nb + 1, &box, nb + 1, &perimeter, nb + 1, &convex));
  PetscCall(BwBlockBoxes(v, box, perimeter, convex));
  PetscCall(BwGridCreate(nb, BwBoxShape, box, NULL, h, &grid));
  for (PetscInt a = 0; a < nb; a++) {
    PetscCall(BwGridCandidates(&grid, a));
    for (PetscInt c = 0; c < grid.cand.n; c++) {
      PetscInt  b = grid.cand.a[c];
      PetscReal area, allowed;
      if (PetscMin(box[4 * a + 2], box[4 * b + 2]) - PetscMax(box[4 * a], box[4 * b]) <= d) continue;
      if (PetscMin(box[4 * a + 3], box[4 * b + 3]) - PetscMax(box[4 * a + 1], box[4 * b + 1]) <= d) continue;
      if (decide && !decide(dctx, a, b)) continue;
      PetscCall(BwIntersectionArea(v, a, b, convex, &w, &area));
      allowed = d * PetscMin(perimeter[a], perimeter[b]);
      if (area > allowed) {
        /* the view is in id order: the first pair found here is this rank's first */
        PetscInt small = v->area[a] <= v->area[b] ? a : b;
        BwFaultSet(fault, stage, (int64_t)v->gid[a] * B + v->gid[b], PETSC_ERR_USER_INPUT, "%s: /blocks/vertices: blocks %" PetscInt_FMT " and %" PetscInt_FMT " overlap: their interiors share %.4g m^2, %.3g%% of block %" PetscInt_FMT, file, v->gid[a], v->gid[b], (double)area, (double)(100 * area / v->area[small]), v->gid[small]);
        a = nb;
        break;
      }
    }
  }
  PetscCall(BwGridDestroy(&grid));
  PetscCall(PetscFree3(box, perimeter, convex));
  PetscCall(BwClipWorkFree(&w));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ connection */

PetscErrorCode BwValidateConnected(const char file[], MPI_Comm comm, PetscInt B, PetscInt start, PetscInt nb, const PetscInt count[], PetscBool detected, const BwTolerance *tol)
{
  PetscInt    first[13], nfree = 0, total, *all;
  PetscMPIInt size;
  char        list[256] = "", hint[512] = "";

  PetscFunctionBeginUser;
  if (B < 2) PetscFunctionReturn(PETSC_SUCCESS);
  /* each rank's first 13 unconnected blocks, gathered: the ranges ascend
   * with the rank, so the first 13 of all are among them */
  for (PetscInt b = 0; b < nb; b++) {
    if (count[b]) continue;
    if (nfree < 13) first[nfree] = start + b;
    nfree++;
  }
  for (PetscInt k = nfree; k < 13; k++) first[k] = -1;
  PetscCallMPI(MPIU_Allreduce(&nfree, &total, 1, MPIU_INT, MPI_SUM, comm));
  if (!total) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscMalloc1(13 * (size_t)size, &all));
  PetscCallMPI(MPI_Allgather(first, 13, MPIU_INT, all, 13, MPIU_INT, comm));
  nfree = 0;
  for (PetscInt k = 0; k < 13 * (PetscInt)size; k++) {
    if (all[k] < 0) continue;
    if (nfree < 12) {
      char item[32];
      PetscCall(PetscSNPrintf(item, sizeof(item), "%s%" PetscInt_FMT, nfree ? ", " : "", all[k]));
      PetscCall(PetscStrlcat(list, item, sizeof(list)));
    } else if (nfree == 12) PetscCall(PetscStrlcat(list, ", ...", sizeof(list)));
    nfree++;
  }
  PetscCall(PetscFree(all));
  nfree = total;
  if (detected)
    PetscCall(PetscSNPrintf(hint, sizeof(hint), "; interfaces were detected (no /interfaces/blocks): an edge must face another block's edge, anti-parallel within %g deg, at most e + tolerance = %g m from it, and overlap it by more than %g m", (double)(BW_FACING_ANGLE * 180 / PETSC_PI), (double)tol->gapmax, (double)tol->delta));
  else PetscCall(PetscSNPrintf(hint, sizeof(hint), "; /interfaces/blocks names no pair with %s", nfree > 1 ? "them" : "it"));
  SETERRQ(comm, PETSC_ERR_USER_INPUT, "%s: /blocks: block%s %s (%" PetscInt_FMT " block%s) %s unconnected: no interface joins %s to any other block%s", file, nfree > 1 ? "s" : "", list, nfree, nfree > 1 ? "s" : "", nfree > 1 ? "are" : "is", nfree > 1 ? "them" : "it", hint);
}
