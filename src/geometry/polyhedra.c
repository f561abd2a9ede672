/* Convex polyhedra from vertex sets (a 3D block is the convex hull of its
 * vertices, interface.md "HDF5 geometry input, 3D"): the faces, the volume
 * and the centroid, and the checks a file's block must pass.
 *
 * The hull by supporting planes: a plane through three of the vertices with
 * every vertex on its inner side (within delta) is a face plane; the
 * vertices on it (within delta), ordered by their 2D hull in the plane
 * (Andrew's monotone chain, strict turns), are the face. O(n^4) in the
 * vertices of one block, which is what a masonry unit has few of (8 for a
 * brick, 12-20 for a cut stone); the candidate searches between blocks are
 * linear (file3d.c). A vertex that is a strict corner of no face is inside
 * the hull, on a face or an edge, or a repeat: the block is not convex as
 * given, and the error names its row. */
#include <stdlib.h>
#include <string.h>
#include "geometry/validate.h"
#include "util/compat.h"

static void BwSub3(const PetscReal a[3], const PetscReal b[3], PetscReal c[3])
{
  for (int k = 0; k < 3; k++) c[k] = a[k] - b[k];
}
static void BwCross3(const PetscReal a[3], const PetscReal b[3], PetscReal c[3])
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}
static PetscReal BwDot3(const PetscReal a[3], const PetscReal b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

typedef struct {
  PetscReal u, v;
  PetscInt  id;
} BwPlanePoint;

static int BwPlanePointCompare(const void *x, const void *y)
{
  const BwPlanePoint *a = (const BwPlanePoint *)x, *b = (const BwPlanePoint *)y;
  if (a->u != b->u) return a->u < b->u ? -1 : 1;
  if (a->v != b->v) return a->v < b->v ? -1 : 1;
  return a->id < b->id ? -1 : a->id > b->id;
}

static PetscReal BwTurn(const BwPlanePoint *o, const BwPlanePoint *a, const BwPlanePoint *b) { return (a->u - o->u) * (b->v - o->v) - (a->v - o->v) * (b->u - o->u); }

/* Counter-clockwise strict 2D hull of p[n] (sorted in place) into out
 * (ids); points within `eps` of an edge's line (area test eps * |edge|)
 * are not corners. Returns the number of corners. */
static PetscInt BwHull2D(PetscInt n, BwPlanePoint p[], PetscReal eps, PetscInt out[], BwPlanePoint work[])
{
  PetscInt k = 0;
  qsort(p, (size_t)n, sizeof(BwPlanePoint), BwPlanePointCompare);
  for (PetscInt pass = 0; pass < 2; pass++) {
    PetscInt start = k;
    for (PetscInt q = 0; q < n; q++) {
      const BwPlanePoint *c = &p[pass ? n - 1 - q : q];
      while (k - start >= 2) {
        const BwPlanePoint *o = &work[k - 2], *a = &work[k - 1];
        PetscReal           len = PetscSqrtReal(PetscSqr(c->u - o->u) + PetscSqr(c->v - o->v));
        if (BwTurn(o, a, c) > eps * len) break;
        k--;
      }
      work[k++] = *c;
    }
    k--; /* the last point starts the other chain */
  }
  for (PetscInt q = 0; q < k; q++) out[q] = work[q].id;
  return k;
}

PetscErrorCode BwPolyhedronHull(const char file[], PetscInt b, PetscInt first, PetscInt n, const PetscReal x[], PetscReal delta, BwPolyhedron *P)
{
  PetscReal    *planes = NULL; /* 4 per face: outward unit normal, offset */
  PetscInt      nplanes = 0, cap = 0, nidx = 0, capidx = 0, *corner;
  BwPlanePoint *pp, *work;
  PetscInt     *ids;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(P, sizeof(*P)));
  PetscCheck(n >= 4, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /blocks/vertices: block %" PetscInt_FMT " has %" PetscInt_FMT " vertices (rows %" PetscInt_FMT "..%" PetscInt_FMT "); a 3D block needs at least 4", file, b, n, first, first + n - 1);
  /* a repeated vertex first: the hulls of the faces at that corner could
   * each keep a different copy */
  for (PetscInt q = 1; q < n; q++)
    for (PetscInt r = 0; r < q; r++)
      PetscCheck(PetscAbsReal(x[3 * q] - x[3 * r]) > delta || PetscAbsReal(x[3 * q + 1] - x[3 * r + 1]) > delta || PetscAbsReal(x[3 * q + 2] - x[3 * r + 2]) > delta, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /blocks/vertices: block %" PetscInt_FMT ": vertex row %" PetscInt_FMT " (%g, %g, %g) repeats vertex row %" PetscInt_FMT " (within %g m): the block is not convex as given", file, b, first + q, (double)x[3 * q], (double)x[3 * q + 1], (double)x[3 * q + 2], first + r, (double)delta);
  PetscCall(PetscMalloc4(n + 1, &pp, n + 2, &work, n + 1, &ids, n, &corner));
  PetscCall(PetscArrayzero(corner, n));
  PetscCall(PetscMalloc1(n + 1, &P->face_offsets));
  P->face_offsets[0] = 0;
  for (PetscInt a = 0; a < n; a++)
    for (PetscInt c1 = a + 1; c1 < n; c1++)
      for (PetscInt c2 = c1 + 1; c2 < n; c2++) {
        PetscReal e1[3], e2[3], nrm[3], len, d, lo = 0, hi = 0;
        PetscBool known = PETSC_FALSE;
        BwSub3(&x[3 * c1], &x[3 * a], e1);
        BwSub3(&x[3 * c2], &x[3 * a], e2);
        BwCross3(e1, e2, nrm);
        len = PetscSqrtReal(BwDot3(nrm, nrm));
        /* a plane needs a triangle of some size: |e1 x e2| against the
         * longer edge times delta */
        if (len <= delta * PetscMax(PetscSqrtReal(BwDot3(e1, e1)), PetscSqrtReal(BwDot3(e2, e2)))) continue;
        for (int k = 0; k < 3; k++) nrm[k] /= len;
        d = BwDot3(nrm, &x[3 * a]);
        for (PetscInt q = 0; q < n; q++) {
          PetscReal s = BwDot3(nrm, &x[3 * q]) - d;
          lo          = PetscMin(lo, s);
          hi          = PetscMax(hi, s);
        }
        if (lo < -delta && hi > delta) continue; /* vertices on both sides */
        if (lo >= -delta && hi <= delta) continue; /* every vertex on it: planar, caught below */
        if (hi > delta) { /* outward: away from the vertices */
          for (int k = 0; k < 3; k++) nrm[k] = -nrm[k];
          d = -d;
        }
        for (PetscInt f = 0; f < nplanes && !known; f++)
          if (BwDot3(nrm, &planes[4 * f]) > 1 - 1e-12 && PetscAbsReal(planes[4 * f + 3] - d) <= delta) known = PETSC_TRUE;
        if (known) continue;
        {
          /* the face: the vertices on the plane, by their 2D hull */
          PetscReal u[3], v[3], ref[3] = {1, 0, 0};
          PetscInt  m = 0, nc;
          if (PetscAbsReal(nrm[0]) > 0.6) ref[0] = 0, ref[1] = 1;
          BwCross3(nrm, ref, u);
          len = PetscSqrtReal(BwDot3(u, u));
          for (int k = 0; k < 3; k++) u[k] /= len;
          BwCross3(nrm, u, v); /* (u, v, n) right-handed: counter-clockwise in (u, v) is about n */
          for (PetscInt q = 0; q < n; q++)
            if (PetscAbsReal(BwDot3(nrm, &x[3 * q]) - d) <= delta) {
              pp[m].u  = BwDot3(u, &x[3 * q]);
              pp[m].v  = BwDot3(v, &x[3 * q]);
              pp[m].id = q;
              m++;
            }
          nc = BwHull2D(m, pp, delta, ids, work);
          if (nc < 3) continue;
          if (nplanes + 1 > cap) {
            cap = PetscMax(2 * cap, 8);
            PetscCall(PetscRealloc(sizeof(PetscReal) * 4 * (size_t)cap, &planes));
            PetscCall(PetscRealloc(sizeof(PetscInt) * (size_t)(cap + 1), &P->face_offsets));
          }
          if (nidx + nc > capidx) {
            capidx = PetscMax(2 * capidx, nidx + nc + 32);
            PetscCall(PetscRealloc(sizeof(PetscInt) * (size_t)capidx, &P->face_vertices));
          }
          for (int k = 0; k < 3; k++) planes[4 * nplanes + k] = nrm[k];
          planes[4 * nplanes + 3] = d;
          for (PetscInt q = 0; q < nc; q++) {
            P->face_vertices[nidx++] = ids[q];
            corner[ids[q]]           = 1;
          }
          nplanes++;
          P->face_offsets[nplanes] = nidx;
        }
      }
  P->nfaces = nplanes;
  P->normal = planes;
  {
    PetscErrorCode ierr = PETSC_SUCCESS;
    char           msg[512];
    if (nplanes < 4) {
      ierr = PETSC_ERR_USER_INPUT;
      PetscCall(PetscSNPrintf(msg, sizeof(msg), "%s: /blocks/vertices: block %" PetscInt_FMT ": all its %" PetscInt_FMT " vertices (rows %" PetscInt_FMT "..%" PetscInt_FMT ") lie on one plane (within %g m): a 3D block needs volume", file, b, n, first, first + n - 1, (double)delta));
    }
    for (PetscInt q = 0; q < n && !ierr; q++)
      if (!corner[q]) {
        ierr = PETSC_ERR_USER_INPUT;
        PetscCall(PetscSNPrintf(msg, sizeof(msg), "%s: /blocks/vertices: block %" PetscInt_FMT ": vertex row %" PetscInt_FMT " (%g, %g, %g) is not a corner of the block's convex hull (it is inside it, on a face or an edge, or repeated): the block is not convex as given", file, b, first + q, (double)x[3 * q], (double)x[3 * q + 1], (double)x[3 * q + 2]));
      }
    PetscCall(PetscFree4(pp, work, ids, corner));
    if (ierr) {
      PetscCall(BwPolyhedronDestroy(P));
      SETERRQ(PETSC_COMM_SELF, ierr, "%s", msg);
    }
  }
  /* volume and centroid: tetrahedra from vertex 0 over the faces' fans */
  {
    PetscReal vol = 0, c[3] = {0, 0, 0};
    const PetscReal *o = &x[0];
    for (PetscInt f = 0; f < P->nfaces; f++) {
      const PetscInt *fv = &P->face_vertices[P->face_offsets[f]];
      PetscInt        nf = P->face_offsets[f + 1] - P->face_offsets[f];
      for (PetscInt t = 1; t + 1 < nf; t++) {
        PetscReal a[3], bb[3], cc[3], cr[3], v6;
        BwSub3(&x[3 * fv[0]], o, a);
        BwSub3(&x[3 * fv[t]], o, bb);
        BwSub3(&x[3 * fv[t + 1]], o, cc);
        BwCross3(bb, cc, cr);
        v6 = BwDot3(a, cr);
        vol += v6;
        for (int k = 0; k < 3; k++) c[k] += v6 * (a[k] + bb[k] + cc[k]);
      }
    }
    P->volume = vol / 6;
    for (int k = 0; k < 3; k++) P->centroid[k] = o[k] + c[k] / (4 * vol);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwPolyhedronDestroy(BwPolyhedron *P)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(P->face_offsets));
  PetscCall(PetscFree(P->face_vertices));
  PetscCall(PetscFree(P->normal));
  PetscCall(PetscMemzero(P, sizeof(*P)));
  PetscFunctionReturn(PETSC_SUCCESS);
}
