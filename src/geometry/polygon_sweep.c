/* Non-adjacent edges of one polygon closer than d, in O(n log n) on any
 * polygon (see validate.h). A uniform grid of the edges, used before, is
 * linear only while the edges are of one size and spread out: a top edge
 * zigzagging with 1e5 steep teeth puts thousands of edges in every cell
 * (1.7 s at 1e5 vertices, over a minute at 1e6).
 *
 * Why it finds every defect. Let s, t be the closest non-adjacent pair,
 * at distance D <= d (D = 0 when they cross).
 *  - Crossing: a Shamos-Hoey sweep (sweep line along u, active edges
 *    ordered by v) finds a crossing pair among the pairs that are ever
 *    neighbours in the order, and every such pair is measured here.
 *  - Touching within d without crossing: the distance of two segments that
 *    do not cross is reached at an endpoint p of one of them (say of s),
 *    at a point c of t. If t spans p's coordinate u, then t is p's
 *    neighbour in the order at p's event: any edge between them on the
 *    line u = p.u would enter the triangle (p, c, foot of p on t), whose
 *    every point other than p is closer than D to t, so that edge (or the
 *    edge after its end inside the triangle) would be a pair closer than
 *    D. If t does not span p.u, c lies within D tan(a) of an endpoint q of
 *    t, a being the angle between t and the sweep direction. Of three
 *    sweeps 60 degrees apart one has a <= 30 degrees: there either t spans
 *    p.u, or |p - q| <= D / cos(30) < 1.16 d, and the pair of vertices
 *    (p, q) is found by the proximity search below.
 *  - Vertices closer than 1.16 d: cells of that size hold at most a few
 *    vertices of a valid polygon (vertices of non-adjacent edges are more
 *    than d apart), so a cell with more than BW_CELL_MAX has a defect among
 *    its first BW_CELL_MAX + 1 vertices; the search is a sort of the cell
 *    keys and bounded work per vertex.
 * The work (comparisons and distances measured) is returned, so that a
 * test can see it stay within a multiple of n log n. */
#include "geometry/validate.h"
#include "util/compat.h"

#define BW_CELL_MAX 8

typedef struct {
  PetscInt  nv;
  PetscReal d;
  const PetscReal *xy;
  PetscReal *u, *v;           /* rotated coordinates of the vertices */
  PetscInt  *order, *rank;    /* vertices by (u, v); rank[vertex] */
  /* the treap of active edges: node k is edge k (vertex k -> k+1) */
  PetscInt  *left, *right, *parent, root;
  PetscInt  *prio;
  PetscBool *active;
  PetscInt64 work;
  PetscInt   found_k, found_l;
} BwSweep;

static inline PetscReal BwCrossS(PetscReal ax, PetscReal ay, PetscReal bx, PetscReal by) { return ax * by - ay * bx; }

static PetscReal BwPointSegmentS(const PetscReal p[2], const PetscReal a[2], const PetscReal b[2])
{
  PetscReal dd[2] = {b[0] - a[0], b[1] - a[1]}, w[2] = {p[0] - a[0], p[1] - a[1]}, l2 = dd[0] * dd[0] + dd[1] * dd[1], s = 0;
  if (l2 > 0) s = PetscMin(1, PetscMax(0, (w[0] * dd[0] + w[1] * dd[1]) / l2));
  return PetscSqrtReal(PetscSqr(w[0] - s * dd[0]) + PetscSqr(w[1] - s * dd[1]));
}

PetscReal BwSegmentDistance(const PetscReal a0[2], const PetscReal a1[2], const PetscReal b0[2], const PetscReal b1[2])
{
  PetscReal o1 = BwCrossS(a1[0] - a0[0], a1[1] - a0[1], b0[0] - a0[0], b0[1] - a0[1]);
  PetscReal o2 = BwCrossS(a1[0] - a0[0], a1[1] - a0[1], b1[0] - a0[0], b1[1] - a0[1]);
  PetscReal o3 = BwCrossS(b1[0] - b0[0], b1[1] - b0[1], a0[0] - b0[0], a0[1] - b0[1]);
  PetscReal o4 = BwCrossS(b1[0] - b0[0], b1[1] - b0[1], a1[0] - b0[0], a1[1] - b0[1]);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return 0;
  return PetscMin(PetscMin(BwPointSegmentS(a0, b0, b1), BwPointSegmentS(a1, b0, b1)), PetscMin(BwPointSegmentS(b0, a0, a1), BwPointSegmentS(b1, a0, a1)));
}

/* Edges k and l share no vertex and are at most d apart: record the pair
 * (the smaller index first) and say so. */
static PetscBool BwSweepPair(BwSweep *S, PetscInt k, PetscInt l)
{
  PetscInt n = S->nv, k1 = (k + 1) % n, l1 = (l + 1) % n;
  if (k < 0 || l < 0 || k == l || k1 == l || l1 == k) return PETSC_FALSE;
  S->work++;
  if (BwSegmentDistance(S->xy + 2 * k, S->xy + 2 * k1, S->xy + 2 * l, S->xy + 2 * l1) > S->d) return PETSC_FALSE;
  S->found_k = PetscMin(k, l);
  S->found_l = PetscMax(k, l);
  return PETSC_TRUE;
}

/* ---- vertices closer than 1.16 d ---------------------------------------- */

typedef struct {
  PetscInt64 cx, cy;
  PetscInt   k;
} BwCellKey;

static int BwCellKeyCompare(const void *a, const void *b)
{
  const BwCellKey *x = (const BwCellKey *)a, *y = (const BwCellKey *)b;
  if (x->cx != y->cx) return x->cx < y->cx ? -1 : 1;
  if (x->cy != y->cy) return x->cy < y->cy ? -1 : 1;
  return x->k < y->k ? -1 : x->k > y->k;
}

/* first key of cell (cx, cy) in the sorted keys, or n */
static PetscInt BwCellFind(PetscInt n, const BwCellKey keys[], PetscInt64 cx, PetscInt64 cy)
{
  PetscInt lo = 0, hi = n;
  while (lo < hi) {
    PetscInt m = lo + (hi - lo) / 2;
    if (keys[m].cx < cx || (keys[m].cx == cx && keys[m].cy < cy)) lo = m + 1;
    else hi = m;
  }
  return lo < n && keys[lo].cx == cx && keys[lo].cy == cy ? lo : n;
}

/* The edges at vertices i and j: the two before and after each. */
static PetscBool BwSweepVertexPair(BwSweep *S, PetscInt i, PetscInt j)
{
  PetscInt n = S->nv, ei[2] = {(i + n - 1) % n, i}, ej[2] = {(j + n - 1) % n, j};
  for (int a = 0; a < 2; a++)
    for (int b = 0; b < 2; b++)
      if (BwSweepPair(S, ei[a], ej[b])) return PETSC_TRUE;
  return PETSC_FALSE;
}

static PetscErrorCode BwSweepProximity(BwSweep *S, PetscBool *found)
{
  const PetscReal r = 1.16 * S->d;
  PetscInt        n = S->nv;
  BwCellKey      *keys;
  PetscReal       x0 = PETSC_MAX_REAL, y0 = PETSC_MAX_REAL;

  PetscFunctionBeginUser;
  *found = PETSC_FALSE;
  PetscCall(PetscMalloc1(n, &keys));
  for (PetscInt k = 0; k < n; k++) {
    x0 = PetscMin(x0, S->xy[2 * k]);
    y0 = PetscMin(y0, S->xy[2 * k + 1]);
  }
  for (PetscInt k = 0; k < n; k++) {
    keys[k].cx = (PetscInt64)PetscFloorReal((S->xy[2 * k] - x0) / r);
    keys[k].cy = (PetscInt64)PetscFloorReal((S->xy[2 * k + 1] - y0) / r);
    keys[k].k  = k;
  }
  qsort(keys, (size_t)n, sizeof(*keys), BwCellKeyCompare);
  for (PetscInt a = 0; a < n && !*found; a++) {
    const PetscInt i = keys[a].k;
    for (int dx = -1; dx <= 1 && !*found; dx++)
      for (int dy = -1; dy <= 1 && !*found; dy++) {
        PetscInt first = BwCellFind(n, keys, keys[a].cx + dx, keys[a].cy + dy);
        for (PetscInt c = first; c < n && c < first + BW_CELL_MAX + 1 && keys[c].cx == keys[a].cx + dx && keys[c].cy == keys[a].cy + dy && !*found; c++) {
          const PetscInt j = keys[c].k;
          S->work++;
          if (j <= i) continue;
          *found = BwSweepVertexPair(S, i, j);
        }
      }
  }
  PetscCall(PetscFree(keys));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ---- the sweep ---------------------------------------------------------- */

/* v of edge e on the line u (its end's v beyond its ends; a clamp of pv to
 * its range when it is parallel to the line) */
static PetscReal BwEdgeV(const BwSweep *S, PetscInt e, PetscReal u, PetscReal pv)
{
  PetscInt  e1 = (e + 1) % S->nv;
  PetscReal u0 = S->u[e], u1 = S->u[e1], v0 = S->v[e], v1 = S->v[e1], t;
  if (u0 == u1) return PetscMin(PetscMax(pv, PetscMin(v0, v1)), PetscMax(v0, v1));
  t = (u - u0) / (u1 - u0);
  t = PetscMin(1, PetscMax(0, t));
  return v0 + t * (v1 - v0);
}

/* The direction of edge e leaving vertex p, as a slope dv/du (+-inf when
 * parallel to the sweep line), to order the edges that start at p. */
static PetscReal BwEdgeSlope(const BwSweep *S, PetscInt e)
{
  PetscInt  e1 = (e + 1) % S->nv;
  PetscReal du = S->u[e1] - S->u[e], dv = S->v[e1] - S->v[e];
  if (du == 0) return dv > 0 ? PETSC_INFINITY : PETSC_NINFINITY;
  return dv / du;
}

/* e (starting at vertex p) below node f at p's event? */
static PetscBool BwSweepBelow(BwSweep *S, PetscInt e, PetscInt p, PetscInt f)
{
  PetscReal vf = BwEdgeV(S, f, S->u[p], S->v[p]);
  S->work++;
  if (S->v[p] != vf) return S->v[p] < vf ? PETSC_TRUE : PETSC_FALSE;
  return BwEdgeSlope(S, e) < BwEdgeSlope(S, f) ? PETSC_TRUE : PETSC_FALSE;
}

static void BwTreapRotateUp(BwSweep *S, PetscInt x)
{
  PetscInt p = S->parent[x], g = S->parent[p];
  if (S->left[p] == x) {
    S->left[p] = S->right[x];
    if (S->right[x] >= 0) S->parent[S->right[x]] = p;
    S->right[x] = p;
  } else {
    S->right[p] = S->left[x];
    if (S->left[x] >= 0) S->parent[S->left[x]] = p;
    S->left[x] = p;
  }
  S->parent[p] = x;
  S->parent[x] = g;
  if (g < 0) S->root = x;
  else if (S->left[g] == p) S->left[g] = x;
  else S->right[g] = x;
}

static void BwTreapInsert(BwSweep *S, PetscInt e, PetscInt p)
{
  PetscInt at = S->root, up = -1;
  PetscBool below = PETSC_FALSE;
  while (at >= 0) {
    up    = at;
    below = BwSweepBelow(S, e, p, at);
    at    = below ? S->left[at] : S->right[at];
  }
  S->left[e] = S->right[e] = -1;
  S->parent[e]             = up;
  if (up < 0) S->root = e;
  else if (below) S->left[up] = e;
  else S->right[up] = e;
  while (S->parent[e] >= 0 && S->prio[e] < S->prio[S->parent[e]]) {
    S->work++;
    BwTreapRotateUp(S, e);
  }
  S->active[e] = PETSC_TRUE;
}

static void BwTreapDelete(BwSweep *S, PetscInt e)
{
  while (S->left[e] >= 0 || S->right[e] >= 0) {
    PetscInt c = S->left[e] < 0 ? S->right[e] : S->right[e] < 0 ? S->left[e] : (S->prio[S->left[e]] < S->prio[S->right[e]] ? S->left[e] : S->right[e]);
    S->work++;
    BwTreapRotateUp(S, c);
  }
  if (S->parent[e] < 0) S->root = -1;
  else if (S->left[S->parent[e]] == e) S->left[S->parent[e]] = -1;
  else S->right[S->parent[e]] = -1;
  S->parent[e] = -1;
  S->active[e] = PETSC_FALSE;
}

static PetscInt BwTreapNext(BwSweep *S, PetscInt x, PetscBool up)
{
  PetscInt *fwd = up ? S->right : S->left, *bwd = up ? S->left : S->right;
  if (fwd[x] >= 0) {
    x = fwd[x];
    while (bwd[x] >= 0) x = bwd[x], S->work++;
    return x;
  }
  while (S->parent[x] >= 0 && fwd[S->parent[x]] == x) x = S->parent[x], S->work++;
  return S->parent[x];
}

/* the active edges just below and just above point p */
static void BwTreapAround(BwSweep *S, PetscInt p, PetscInt *lo, PetscInt *hi)
{
  PetscInt at = S->root;
  *lo = *hi = -1;
  while (at >= 0) {
    S->work++;
    if (S->v[p] <= BwEdgeV(S, at, S->u[p], S->v[p])) {
      *hi = at;
      at  = S->left[at];
    } else {
      *lo = at;
      at  = S->right[at];
    }
  }
}

/* (u, v) order of vertices */
static BwSweep *bw_sort_sweep; /* qsort has no context argument */
static int      BwVertexCompare(const void *a, const void *b)
{
  PetscInt i = *(const PetscInt *)a, j = *(const PetscInt *)b;
  const BwSweep *S = bw_sort_sweep;
  if (S->u[i] != S->u[j]) return S->u[i] < S->u[j] ? -1 : 1;
  if (S->v[i] != S->v[j]) return S->v[i] < S->v[j] ? -1 : 1;
  return i < j ? -1 : i > j;
}

static PetscErrorCode BwSweepOnce(BwSweep *S, PetscReal angle, PetscBool *found)
{
  const PetscInt  n = S->nv;
  const PetscReal c = PetscCosReal(angle), s = PetscSinReal(angle);
  uint64_t        seed = 0x9E3779B97F4A7C15ULL;

  PetscFunctionBeginUser;
  *found = PETSC_FALSE;
  for (PetscInt k = 0; k < n; k++) {
    S->u[k]     = c * S->xy[2 * k] + s * S->xy[2 * k + 1];
    S->v[k]     = -s * S->xy[2 * k] + c * S->xy[2 * k + 1];
    S->order[k] = k;
    S->left[k] = S->right[k] = S->parent[k] = -1;
    S->active[k]                            = PETSC_FALSE;
    seed                                    = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    S->prio[k]                              = (PetscInt)(seed >> 33);
  }
  S->root       = -1;
  bw_sort_sweep = S;
  qsort(S->order, (size_t)n, sizeof(PetscInt), BwVertexCompare);
  for (PetscInt r = 0; r < n; r++) S->rank[S->order[r]] = r;
  for (PetscInt r = 0; r < n && !*found; r++) {
    const PetscInt p = S->order[r], inc[2] = {(p + n - 1) % n, p}, other[2] = {(p + n - 1) % n, (p + 1) % n};
    PetscInt       started[2], ns = 0, lo, hi;
    for (int a = 0; a < 2; a++) {
      if (S->rank[other[a]] < r) BwTreapDelete(S, inc[a]);
      else started[ns++] = inc[a];
    }
    for (int a = 0; a < ns; a++) BwTreapInsert(S, started[a], p);
    if (ns) {
      PetscInt low = started[0], high = started[0];
      if (ns == 2 && BwSweepBelow(S, started[1], p, started[0])) low = started[1];
      else if (ns == 2) high = started[1];
      lo = BwTreapNext(S, low, PETSC_FALSE);
      hi = BwTreapNext(S, high, PETSC_TRUE);
    } else {
      BwTreapAround(S, p, &lo, &hi);
      if (BwSweepPair(S, lo, hi)) *found = PETSC_TRUE;
    }
    for (int a = 0; a < 2 && !*found; a++)
      if (BwSweepPair(S, inc[a], lo) || BwSweepPair(S, inc[a], hi)) *found = PETSC_TRUE;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwPolygonCloseEdges(PetscInt nv, const PetscReal xy[], PetscReal d, PetscInt *k, PetscInt *l, PetscInt64 *work)
{
  BwSweep   S;
  PetscBool found = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&S, sizeof(S)));
  S.nv = nv;
  S.d  = d;
  S.xy = xy;
  S.found_k = S.found_l = -1;
  PetscCall(BwSweepProximity(&S, &found));
  if (!found) {
    PetscCall(PetscMalloc5(nv, &S.u, nv, &S.v, nv, &S.order, nv, &S.rank, nv, &S.prio));
    PetscCall(PetscMalloc4(nv, &S.left, nv, &S.right, nv, &S.parent, nv, &S.active));
    /* three directions 60 degrees apart, turned off the axes that drawn
     * walls follow so that few edges lie along a sweep line */
    for (int a = 0; a < 3 && !found; a++) PetscCall(BwSweepOnce(&S, 0.3 + a * PETSC_PI / 3, &found));
    PetscCall(PetscFree5(S.u, S.v, S.order, S.rank, S.prio));
    PetscCall(PetscFree4(S.left, S.right, S.parent, S.active));
  }
  *k    = S.found_k;
  *l    = S.found_l;
  *work = S.work;
  PetscFunctionReturn(PETSC_SUCCESS);
}
