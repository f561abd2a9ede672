/* The portions' table (see portions.h). */
#include "system/portions.h"
#include <string.h>
#include <math.h>
#include "util/compat.h"
#include "blockwall/kernels.h"

/* Which layouts have portions of one area (bit for bit): products then
 * scale them by one factor per stress component. */
static PetscErrorCode BwPortionsMarkUniform(BwPortions *P)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(P->nlayouts + 1, &P->uniform));
  for (PetscInt l = 0; l < P->nlayouts; l++) {
    P->uniform[l] = PETSC_TRUE;
    for (PetscInt p = P->offsets[l] + 1; p < P->offsets[l + 1]; p++)
      if (P->area[p] != P->area[P->offsets[l]]) P->uniform[l] = PETSC_FALSE;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Distinct lengths, exactly (equal lengths give equal portions bit for
 * bit), by an open-addressing table on their bits: linear in the number of
 * interfaces, where a wall has a handful of lengths. */
typedef struct {
  PetscInt  cap, n, *slot; /* slot: layout + 1, 0 when empty */
  uint64_t *key;
} BwLengthTable;

static uint64_t BwLengthBits(PetscReal x)
{
  uint64_t u;
  memcpy(&u, &x, sizeof(u));
  return u;
}

static PetscErrorCode BwLengthTableGrow(BwLengthTable *t)
{
  BwLengthTable g = {2 * t->cap, t->n, NULL, NULL};

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc2(g.cap, &g.slot, g.cap, &g.key));
  for (PetscInt a = 0; a < t->cap; a++) {
    uint64_t h;
    if (!t->slot[a]) continue;
    for (h = (t->key[a] * 0x9E3779B97F4A7C15ULL) >> 20; g.slot[h % g.cap]; h++) { }
    g.slot[h % g.cap] = t->slot[a];
    g.key[h % g.cap]  = t->key[a];
  }
  PetscCall(PetscFree2(t->slot, t->key));
  *t = g;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the layout of length x, a new one (n) if it is not in the table */
static PetscErrorCode BwLengthTableFind(BwLengthTable *t, PetscReal x, PetscInt *layout, PetscBool *added)
{
  uint64_t k = BwLengthBits(x), h;

  PetscFunctionBeginUser;
  *added = PETSC_FALSE;
  for (h = (k * 0x9E3779B97F4A7C15ULL) >> 20; t->slot[h % t->cap] && t->key[h % t->cap] != k; h++) { }
  if (!t->slot[h % t->cap]) {
    t->slot[h % t->cap] = ++t->n;
    t->key[h % t->cap]  = k;
    *added              = PETSC_TRUE;
  }
  *layout = t->slot[h % t->cap] - 1;
  if (2 * t->n > t->cap) PetscCall(BwLengthTableGrow(t));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwPortionsCreate2D(PetscInt n, const PetscInt pair[], const PetscReal length[], PetscReal depth, PetscInt m, BwPortions *P)
{
  BwLengthTable t = {64, 0, NULL, NULL};
  PetscInt     *first; /* an interface of each layout */

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(P, sizeof(*P)));
  P->dim         = 2;
  P->ninterfaces = n;
  P->maxnp       = m;
  PetscCall(PetscMalloc1(n + 1, &P->layout));
  PetscCall(PetscCalloc2(t.cap, &t.slot, t.cap, &t.key));
  PetscCall(PetscMalloc1(n + 1, &first));
  for (PetscInt k = 0; k < n; k++) {
    PetscBool added;
    PetscCall(BwLengthTableFind(&t, length[k], &P->layout[k], &added));
    if (added) first[P->layout[k]] = k;
  }
  P->nlayouts = t.n;
  PetscCall(PetscFree2(t.slot, t.key));
  PetscCall(PetscMalloc1(P->nlayouts + 1, &P->offsets));
  PetscCall(PetscMalloc5(P->nlayouts * m + 1, &P->area, P->nlayouts * m + 1, &P->xi, P->nlayouts * m + 1, &P->eta, P->nlayouts * m + 1, &P->sqrt_area, P->nlayouts * m + 1, &P->inv_sqrt_area));
  for (PetscInt l = 0; l < P->nlayouts; l++) {
    PetscInt k = first[l];
    int      status;
    P->offsets[l] = l * m;
    bw_kernel_rectangle_portions((int)m, 1, length[k], depth, P->area + l * m, P->xi + l * m, P->eta + l * m, &status);
    if (status != BW_KERNEL_OK) PetscCall(PetscFree(first));
    PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "interface %" PetscInt_FMT " (blocks %" PetscInt_FMT ", %" PetscInt_FMT ") has a non-positive or non-finite length (%g m) or depth (%g m)", k, pair[2 * k], pair[2 * k + 1], (double)length[k], (double)depth);
    for (PetscInt p = l * m; p < (l + 1) * m; p++) {
      P->sqrt_area[p]     = PetscSqrtReal(P->area[p]);
      P->inv_sqrt_area[p] = 1 / P->sqrt_area[p];
    }
  }
  P->offsets[P->nlayouts] = P->nlayouts * m;
  PetscCall(PetscFree(first));
  PetscCall(BwPortionsMarkUniform(P));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The part of convex polygon p (n vertices, counter-clockwise) with
 * lo <= x[axis] (side +1) or x[axis] <= hi (side -1): Sutherland-Hodgman
 * against one line; out has room for n + 1 vertices. */
static PetscInt BwClipAxis(PetscInt n, const PetscReal p[], PetscInt axis, PetscReal at, PetscReal side, PetscReal out[])
{
  PetscInt no = 0;
  for (PetscInt v = 0; v < n; v++) {
    const PetscReal *a = p + 2 * v, *b = p + 2 * ((v + 1) % n);
    PetscReal        da = side * (a[axis] - at), db = side * (b[axis] - at);
    if (da >= 0) {
      out[2 * no]     = a[0];
      out[2 * no + 1] = a[1];
      no++;
    }
    if ((da >= 0) != (db >= 0)) {
      PetscReal t     = da / (da - db);
      out[2 * no]     = a[0] + t * (b[0] - a[0]);
      out[2 * no + 1] = a[1] + t * (b[1] - a[1]);
      no++;
    }
  }
  return no;
}

/* area and centroid of polygon p (n vertices, counter-clockwise) */
static void BwPolygonMoments(PetscInt n, const PetscReal p[], PetscReal *area, PetscReal c[2])
{
  PetscReal a = 0, cx = 0, cy = 0;
  for (PetscInt v = 0; v < n; v++) {
    const PetscReal *s = p + 2 * v, *t = p + 2 * ((v + 1) % n);
    PetscReal        cr = s[0] * t[1] - t[0] * s[1];
    a += cr;
    cx += (s[0] + t[0]) * cr;
    cy += (s[1] + t[1]) * cr;
  }
  *area = 0.5 * a;
  c[0]  = a != 0 ? cx / (3 * a) : 0;
  c[1]  = a != 0 ? cy / (3 * a) : 0;
}

/* The portions of one polygon into the arrays; returns how many. With
 * voff non-NULL, also their polygons: portion p's vertices are
 * voff[p]..voff[p+1]-1 of verts (2 each, voff[0] = 0, counter-clockwise,
 * at most n + 4 a portion), the clipping that gives its area and centroid. */
static PetscInt BwPolygonPortions(PetscInt n, const PetscReal poly[], PetscInt m, PetscInt mb, PetscReal work[], PetscReal area[], PetscReal xi[], PetscReal eta[], PetscInt voff[], PetscReal verts[])
{
  PetscReal lo[2] = {PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[2] = {PETSC_MIN_REAL, PETSC_MIN_REAL}, A, c[2];
  PetscReal *w0 = work, *w1 = work + 2 * (n + 4);
  PetscInt   np = 0;

  if (voff) voff[0] = 0;
  for (PetscInt v = 0; v < n; v++)
    for (PetscInt a = 0; a < 2; a++) {
      lo[a] = PetscMin(lo[a], poly[2 * v + a]);
      hi[a] = PetscMax(hi[a], poly[2 * v + a]);
    }
  BwPolygonMoments(n, poly, &A, c);
  for (PetscInt j = 0; j < mb; j++)
    for (PetscInt i = 0; i < m; i++) {
      /* the cell's four sides; the grid lines at the box's edges are the
       * box itself, so that round-off cuts nothing off */
      PetscReal x0 = i ? lo[0] + (hi[0] - lo[0]) * i / m : lo[0] - 1, x1 = i + 1 < m ? lo[0] + (hi[0] - lo[0]) * (i + 1) / m : hi[0] + 1;
      PetscReal y0 = j ? lo[1] + (hi[1] - lo[1]) * j / mb : lo[1] - 1, y1 = j + 1 < mb ? lo[1] + (hi[1] - lo[1]) * (j + 1) / mb : hi[1] + 1;
      PetscInt  k  = n;
      PetscReal a, cc[2];
      memcpy(w0, poly, sizeof(PetscReal) * 2 * n);
      k = BwClipAxis(k, w0, 0, x0, 1, w1);
      k = BwClipAxis(k, w1, 0, x1, -1, w0);
      k = BwClipAxis(k, w0, 1, y0, 1, w1);
      k = BwClipAxis(k, w1, 1, y1, -1, w0);
      if (k < 3) continue;
      BwPolygonMoments(k, w0, &a, cc);
      if (!(a > 1e-9 * A)) continue;
      area[np] = a;
      xi[np]   = cc[0];
      eta[np]  = cc[1];
      if (voff) {
        memcpy(verts + 2 * voff[np], w0, sizeof(PetscReal) * 2 * k);
        voff[np + 1] = voff[np] + k;
      }
      np++;
    }
  return np;
}

/* Polygon k's coordinates on the grid of step q (see below), as integers. */
void BwPolygonQuantize(PetscInt nv, const PetscReal p[], PetscReal q, int64_t out[])
{
  for (PetscInt a = 0; a < 2 * nv; a++) out[a] = (int64_t)llround(p[a] / q);
}

uint64_t BwPolygonHash(PetscInt nv, const int64_t z[])
{
  uint64_t h = 1469598103934665603ULL ^ (uint64_t)nv;
  for (PetscInt a = 0; a < 2 * nv; a++) h = (h ^ (uint64_t)z[a]) * 1099511628211ULL;
  return h ^ (h >> 29);
}

/* The grid step of polygon p (nv vertices): 2^-40 of its largest
 * coordinate, rounded up to a power of two (the rounding is the same on
 * every rank and CPU). */
PetscReal BwPolygonStep(PetscInt nv, const PetscReal p[])
{
  PetscReal ext = 0;
  for (PetscInt a = 0; a < 2 * nv; a++) ext = PetscMax(ext, PetscAbsReal(p[a]));
  return ext > 0 ? PetscPowReal(2.0, PetscCeilReal(PetscLog2Real(ext)) - 40) : 1;
}

PetscErrorCode BwPortionsCreate3D(PetscInt n, const PetscInt offsets[], const PetscReal poly[], PetscInt m, PetscInt mb, BwPortions *P)
{
  PetscInt   maxv = 0, cap, used = 0, tcap = 16, *table, *rep, nlv = 0;
  PetscReal *work, *qk;
  int64_t   *za, *zb;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(P, sizeof(*P)));
  P->dim         = 3;
  P->ninterfaces = n;
  P->maxnp       = 0;
  P->m           = m;
  P->mb          = mb;
  for (PetscInt k = 0; k < n; k++) maxv = PetscMax(maxv, offsets[k + 1] - offsets[k]);
  /* Interfaces of one shape share a layout. Their polygons, computed from
   * world coordinates, agree only to round-off: each is put on a grid of
   * step q = 2^-40 of its own largest coordinate (a power of two: the
   * rounding is the same on every rank and CPU, and the class of a polygon
   * does not depend on the others), polygons equal there are one class,
   * and its portions are those of its first polygon, within 1e-12 of the
   * others'. (The distributed layout gives every member of a class one
   * polygon, its member of smallest global id: layout.c.) Two polygons
   * that straddle a grid line get layouts of their own: only memory. */
  while (tcap < 2 * n) tcap *= 2;
  PetscCall(PetscMalloc1(tcap, &table));
  for (PetscInt a = 0; a < tcap; a++) table[a] = -1;
  PetscCall(PetscMalloc3(2 * maxv + 1, &za, 2 * maxv + 1, &zb, n + 1, &rep));
  PetscCall(PetscMalloc1(n + 1, &qk));
  PetscCall(PetscMalloc1(4 * (maxv + 4) + 1, &work));
  PetscCall(PetscMalloc1(n + 1, &P->layout));
  PetscCall(PetscMalloc1(n + 1, &P->offsets));
  PetscCall(PetscMalloc1(n + 1, &P->first));
  for (PetscInt k = 0; k < n; k++) {
    PetscInt nv = offsets[k + 1] - offsets[k];
    PetscCheck(nv >= 3, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "interface %" PetscInt_FMT " has a polygon of %" PetscInt_FMT " vertices", k, nv);
    qk[k] = BwPolygonStep(nv, poly + 2 * offsets[k]);
  }
  /* classes first (then the arrays have their size) */
  for (PetscInt k = 0; k < n; k++) {
    const PetscInt nv = offsets[k + 1] - offsets[k];
    uint64_t       h;
    BwPolygonQuantize(nv, poly + 2 * offsets[k], qk[k], za);
    h      = BwPolygonHash(nv, za) ^ (uint64_t)llround(PetscLog2Real(qk[k]));
    rep[k] = -1;
    for (PetscInt s = (PetscInt)(h & (uint64_t)(tcap - 1));; s = (s + 1) & (tcap - 1)) {
      const PetscInt r = table[s];
      if (r < 0) {
        table[s] = k;
        break;
      }
      if (offsets[r + 1] - offsets[r] != nv || qk[r] != qk[k]) continue;
      BwPolygonQuantize(nv, poly + 2 * offsets[r], qk[r], zb);
      if (!memcmp(za, zb, sizeof(int64_t) * 2 * nv)) {
        rep[k] = r;
        break;
      }
    }
    if (rep[k] < 0) {
      P->nlayouts++;
      nlv += nv;
    }
  }
  cap = PetscMax(1, P->nlayouts) * m * mb;
  PetscCall(PetscMalloc5(cap, &P->area, cap, &P->xi, cap, &P->eta, cap, &P->sqrt_area, cap, &P->inv_sqrt_area));
  PetscCall(PetscMalloc1(P->nlayouts + 1, &P->lpoly_offsets));
  PetscCall(PetscMalloc1(2 * nlv + 1, &P->lpoly));
  P->lpoly_offsets[0] = 0;
  P->nlayouts         = 0;
  for (PetscInt k = 0; k < n; k++) {
    PetscInt nv = offsets[k + 1] - offsets[k], np;
    if (rep[k] >= 0) {
      P->layout[k] = P->layout[rep[k]];
      continue;
    }
    np = BwPolygonPortions(nv, poly + 2 * offsets[k], m, mb, work, P->area + used, P->xi + used, P->eta + used, NULL, NULL);
    PetscCheck(np > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "interface %" PetscInt_FMT " has zero area", k);
    PetscCall(PetscArraycpy(P->lpoly + 2 * P->lpoly_offsets[P->nlayouts], poly + 2 * offsets[k], 2 * nv));
    P->lpoly_offsets[P->nlayouts + 1] = P->lpoly_offsets[P->nlayouts] + nv;
    P->first[P->nlayouts]             = k;
    P->layout[k]                      = P->nlayouts;
    P->offsets[P->nlayouts]           = used;
    P->nlayouts++;
    used += np;
    P->maxnp = PetscMax(P->maxnp, np);
  }
  P->offsets[P->nlayouts] = used;
  for (PetscInt p = 0; p < used; p++) {
    P->sqrt_area[p]     = PetscSqrtReal(P->area[p]);
    P->inv_sqrt_area[p] = 1 / P->sqrt_area[p];
  }
  PetscCall(PetscFree(work));
  PetscCall(PetscFree(table));
  PetscCall(PetscFree3(za, zb, rep));
  PetscCall(PetscFree(qk));
  PetscCall(BwPortionsMarkUniform(P));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwPortionsPolygons3D(const BwPortions *P, PetscInt l, PetscInt voffsets[], PetscReal vertices[])
{
  PetscReal     *work, *area, *xi, *eta;
  const PetscInt nv = P->lpoly_offsets[l + 1] - P->lpoly_offsets[l];
  PetscInt       np, want = P->offsets[l + 1] - P->offsets[l];

  PetscFunctionBeginUser;
  PetscCheck(P->dim == 3, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "portion polygons are a 3D notion");
  PetscCall(PetscMalloc4(4 * (nv + 4), &work, P->m * P->mb, &area, P->m * P->mb, &xi, P->m * P->mb, &eta));
  np = BwPolygonPortions(nv, P->lpoly + 2 * P->lpoly_offsets[l], P->m, P->mb, work, area, xi, eta, voffsets, vertices);
  PetscCall(PetscFree4(work, area, xi, eta));
  /* the same polygon through the same clipping: the same portions */
  PetscCheck(np == want, PETSC_COMM_SELF, PETSC_ERR_PLIB, "layout %" PetscInt_FMT " has %" PetscInt_FMT " portions, its polygon cut again %" PetscInt_FMT, l, want, np);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwPortionsDestroy(BwPortions *P)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(P->first));
  PetscCall(PetscFree(P->lpoly_offsets));
  PetscCall(PetscFree(P->lpoly));
  PetscCall(PetscFree(P->uniform));
  PetscCall(PetscFree(P->layout));
  PetscCall(PetscFree(P->offsets));
  PetscCall(PetscFree5(P->area, P->xi, P->eta, P->sqrt_area, P->inv_sqrt_area));
  PetscCall(PetscMemzero(P, sizeof(*P)));
  PetscFunctionReturn(PETSC_SUCCESS);
}
