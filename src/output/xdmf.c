/* The XDMF file beside the HDF5 result (see xdmf.h for what it describes).
 *
 * Layout, and why:
 * - One Domain with two Uniform grids, "blocks" and "interfaces" (in 3D
 *   with /portions datasets a third, "portions"): ParaView opens them as
 *   one multiblock data set, so each can be shown and coloured on its own.
 * - Blocks: a Mixed topology, because blocks may have different vertex
 *   counts (a file geometry may hold any polygon). Each cell is its XDMF
 *   type code followed by its vertex ids; a Polygon (code 3) also carries
 *   its vertex count. A convex quadrilateral is written as Quadrilateral
 *   (code 5) and a triangle as Triangle (code 4) instead of Polygon: the
 *   same cell to ParaView, but meshio (5.3), the reader our tests use, knows
 *   no Polygon in a Mixed topology, so walls of rectangular blocks (every
 *   generator's) stay readable by it too. A non-convex quadrilateral stays
 *   a Polygon, which VTK triangulates correctly where a quad would not.
 *   The vertices are /blocks/vertices as they are (Geometry XY); the
 *   connectivity is /xdmf/topology, written by BwOutput.
 * - Interfaces: Polyline cells of 2 nodes, points G -/+ l/2 t, t = (cos
 *   theta, sin theta), so the line lies where the joint's mid-plane is.
 * - Fields are cell data at their HDF5 datasets; the only point field is
 *   the rigid-body displacement of every vertex,
 *       u(x) = (u1 - w (x2 - c2), u2 + w (x1 - c1), 0),
 *   with 3 components so that Warp By Vector moves the polygons' corners
 *   (a cell field cannot warp anything). The per-portion stresses (I, m, 2)
 *   are no field of a line cell and are left to the HDF5 file.
 * - 3D: a block is a Polyhedron cell (its faces), u(x) = u + w x (x - c);
 *   an interface is its polygon (/interfaces/vertices). A portion is the
 *   polygon BwPortionsCreate3D cut, the m x m_b cell of the interface's
 *   bounding box clipped to it, at G + xi t + eta b, one cell per row of
 *   the /portions datasets, so that stress, state, plastic_jump and area
 *   are its cell fields. Interfaces and portions lie between two blocks that move
 *   apart: their point field vertex_displacement is the mean of the two
 *   blocks' u + w x (x - c), which keeps them midway, as the mid-plane is.
 *   Each interface's portions are written by the rank that owns it, one
 *   point per polygon corner (a corner shared by two portions is written
 *   twice: rows then follow the portions, not a search for neighbours).
 * - Keys in their XDMF 2 spelling (TopologyType, GeometryType,
 *   AttributeType, NumberType), which XDMF 3 readers accept as well, so
 *   ParaView's Xdmf3 readers and its legacy Xdmf reader both open the file. */
#include <string.h>
#include "output/xdmf.h"
#include "util/compat.h"
#include "util/exchange.h"

/* Cell type codes of XDMF (XdmfTopologyType). */
enum { BW_XDMF_POLYGON = 0x3, BW_XDMF_TRIANGLE = 0x4, BW_XDMF_QUADRILATERAL = 0x5, BW_XDMF_POLYHEDRON = 0x10 };

static int BwXdmfCellType(BwGeometry g, PetscInt b)
{
  PetscInt         n = g->offsets[b + 1] - g->offsets[b];
  const PetscReal *v = g->vertices + 2 * g->offsets[b];

  if (n == 3) return BW_XDMF_TRIANGLE;
  if (n != 4) return BW_XDMF_POLYGON;
  /* counter-clockwise and convex: every corner turns left */
  for (PetscInt k = 0; k < 4; k++) {
    const PetscReal *p = v + 2 * k, *q = v + 2 * ((k + 1) % 4), *r = v + 2 * ((k + 2) % 4);
    if ((q[0] - p[0]) * (r[1] - q[1]) - (q[1] - p[1]) * (r[0] - q[0]) <= 0) return BW_XDMF_POLYGON;
  }
  return BW_XDMF_QUADRILATERAL;
}

/* 3D: a block is a Polyhedron cell: its code, its number of faces, then
 * per face its number of vertices and their ids (VTK's Xdmf3 reader reads
 * it as a VTK polyhedron). An interface polygon: Triangle, Quadrilateral
 * or Polygon (with its count) as in 2D. The entries of local block b: */
static PetscInt BwXdmfBlockTopologyLength(BwGeometry g, PetscInt b)
{
  PetscInt len = 0;

  if (g->dim == 3) {
    len = 2;
    for (PetscInt f = g->face_offsets[b]; f < g->face_offsets[b + 1]; f++) len += 1 + g->face_voffsets[f + 1] - g->face_voffsets[f];
    return len;
  }
  return 1 + (BwXdmfCellType(g, b) == BW_XDMF_POLYGON) + g->offsets[b + 1] - g->offsets[b];
}

static int BwXdmfPolygonType(PetscInt nv)
{
  return nv == 3 ? BW_XDMF_TRIANGLE : nv == 4 ? BW_XDMF_QUADRILATERAL : BW_XDMF_POLYGON;
}

/* 3D: the entries of local interface k's polygon. */
static PetscInt BwXdmfInterfaceTopologyLength(BwGeometry g, PetscInt k)
{
  PetscInt nv = g->poly_offsets[k + 1] - g->poly_offsets[k];
  return 1 + (BwXdmfPolygonType(nv) == BW_XDMF_POLYGON) + nv;
}

/* u + w x (x - c) of the rigid motion q = (u, w) of a block of centroid
 * c at x, times s, added to out[3]. */
static void BwXdmfAddRigidMotion(const PetscReal q[6], const PetscReal c[3], const PetscReal x[3], PetscReal s, PetscReal out[3])
{
  const PetscReal *u = q, *w = q + 3, r[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]};

  out[0] += s * (u[0] + w[1] * r[2] - w[2] * r[1]);
  out[1] += s * (u[1] + w[2] * r[0] - w[0] * r[2]);
  out[2] += s * (u[2] + w[0] * r[1] - w[1] * r[0]);
}

/* The displacement of a point x of interface k whose blocks' rigid
 * motions are pair[0..6) and pair[6..12): the mean of the two. */
static void BwXdmfInterfaceMotion(BwGeometry geom, PetscInt k, const PetscReal pair[], const PetscReal x[3], PetscReal out[3])
{
  out[0] = out[1] = out[2] = 0;
  BwXdmfAddRigidMotion(pair, geom->centroid + 3 * geom->pair[2 * k], x, 0.5, out);
  BwXdmfAddRigidMotion(pair + 6, geom->centroid + 3 * geom->pair[2 * k + 1], x, 0.5, out);
}

/* 3D portions: every layout's portion polygons in (xi, eta), cut from the
 * layout's polygon (BwPortionsPolygons3D), and where each
 * interface's portions go in /xdmf/portion_points and portion_topology. An
 * interface of a layout takes that layout's polygons in its own frame: its
 * portions, areas and centroids are the layout's. */
typedef struct {
  PetscInt  *voff;   /* per entry p of the portions' arrays (P->offsets): its vertices voff[p]..voff[p+1]-1 */
  PetscReal *verts;  /* 2 per vertex, counter-clockwise in (xi, eta) */
  PetscInt  *points, *topology; /* per interface + 1: offsets of its rows in the two datasets */
} BwXdmfLayouts;

static PetscErrorCode BwXdmfLayoutsCreate(BwGeometry geom, const BwPortions *P, BwXdmfLayouts *L)
{
  const PetscInt ni = geom->ninterfaces, np = P->offsets[P->nlayouts], mm = P->m * P->mb;
  PetscInt       maxv = 0, *lv, *lpoints, *ltopology;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < ni; k++) maxv = PetscMax(maxv, geom->poly_offsets[k + 1] - geom->poly_offsets[k]);
  PetscCall(PetscMalloc4(np + 1, &L->voff, 2 * (maxv + 4) * np + 1, &L->verts, ni + 1, &L->points, ni + 1, &L->topology));
  PetscCall(PetscMalloc3(mm + 1, &lv, P->nlayouts + 1, &lpoints, P->nlayouts + 1, &ltopology));
  L->voff[0] = 0;
  for (PetscInt l = 0; l < P->nlayouts; l++) {
    const PetscInt o = P->offsets[l], n = P->offsets[l + 1] - o;
    PetscCall(BwPortionsPolygons3D(P, l, lv, L->verts + 2 * L->voff[o]));
    ltopology[l] = 0;
    for (PetscInt p = 0; p < n; p++) {
      L->voff[o + p + 1] = L->voff[o] + lv[p + 1];
      ltopology[l] += 1 + (BwXdmfPolygonType(lv[p + 1] - lv[p]) == BW_XDMF_POLYGON) + lv[p + 1] - lv[p];
    }
    lpoints[l] = lv[n];
  }
  L->points[0] = L->topology[0] = 0;
  for (PetscInt k = 0; k < ni; k++) {
    L->points[k + 1]   = L->points[k] + lpoints[P->layout[k]];
    L->topology[k + 1] = L->topology[k] + ltopology[P->layout[k]];
  }
  PetscCall(PetscFree3(lv, lpoints, ltopology));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwXdmfLayoutsDestroy(BwXdmfLayouts *L)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree4(L->voff, L->verts, L->points, L->topology));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwXdmfLayoutCreate(BwGeometry geom, const BwMixedOwnership *own, PetscBool portions, BwXdmfLayout *L)
{
  const PetscInt nown = geom->nown_blocks, noi = own->nown_interfaces;
  PetscInt      *gid, *cnt;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(L, sizeof(*L)));
  L->sizes.dim           = geom->dim;
  L->sizes.nblocks       = geom->nblocks_global;
  L->sizes.nvertices     = geom->nvertices_global;
  L->sizes.ninterfaces   = geom->ninterfaces_global;
  L->sizes.npolyvertices = geom->dim == 3 ? geom->npolyvertices_global : 0;
  PetscCall(PetscMalloc2(PetscMax(nown, noi) + 1, &gid, PetscMax(nown, noi) + 1, &cnt));
  PetscCall(PetscMalloc1(nown + 1, &L->topology_start));
  for (PetscInt b = 0; b < nown; b++) {
    gid[b] = geom->gblock[b];
    cnt[b] = BwXdmfBlockTopologyLength(geom, b);
  }
  PetscCall(BwRaggedOffsets(geom->comm, nown, gid, cnt, geom->nblocks_global, L->topology_start, &L->sizes.ntopology));
  if (geom->dim == 3) {
    PetscCall(PetscMalloc1(noi + 1, &L->itopology_start));
    for (PetscInt e = 0; e < noi; e++) {
      gid[e] = geom->giface[own->own_interfaces[e]];
      cnt[e] = BwXdmfInterfaceTopologyLength(geom, own->own_interfaces[e]);
    }
    PetscCall(BwRaggedOffsets(geom->comm, noi, gid, cnt, geom->ninterfaces_global, L->itopology_start, &L->sizes.ninterface_topology));
  } else L->sizes.ninterface_topology = 2 * geom->ninterfaces_global;
  if (portions) {
    BwXdmfLayouts PL;
    PetscInt     *tcnt, np = 0;
    PetscCall(BwXdmfLayoutsCreate(geom, own->portions, &PL));
    PetscCall(PetscMalloc1(noi + 1, &L->ppoint_start));
    PetscCall(PetscMalloc1(noi + 1, &L->ptopology_start));
    PetscCall(PetscMalloc1(noi + 1, &tcnt));
    for (PetscInt e = 0; e < noi; e++) {
      PetscInt k = own->own_interfaces[e];
      gid[e]     = geom->giface[k];
      cnt[e]     = PL.points[k + 1] - PL.points[k];
      tcnt[e]    = PL.topology[k + 1] - PL.topology[k];
      np += BwPortionsCount(own->portions, k);
    }
    PetscCall(BwRaggedOffsets(geom->comm, noi, gid, cnt, geom->ninterfaces_global, L->ppoint_start, &L->sizes.nportion_points));
    PetscCall(BwRaggedOffsets(geom->comm, noi, gid, tcnt, geom->ninterfaces_global, L->ptopology_start, &L->sizes.nportion_topology));
    PetscCallMPI(MPIU_Allreduce(&np, &L->sizes.nportions, 1, MPIU_INT, MPI_SUM, geom->comm));
    PetscCall(PetscFree(tcnt));
    PetscCall(BwXdmfLayoutsDestroy(&PL));
  }
  PetscCall(PetscFree2(gid, cnt));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwXdmfLayoutDestroy(BwXdmfLayout *L)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(L->topology_start));
  PetscCall(PetscFree(L->itopology_start));
  PetscCall(PetscFree(L->ppoint_start));
  PetscCall(PetscFree(L->ptopology_start));
  PetscCall(PetscMemzero(L, sizeof(*L)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 3D, the owned interfaces' portions: their polygons at G + xi t + eta b,
 * each counter-clockwise about n as the interface polygons are (so its
 * (xi, eta) order reversed, t x b = -n), as Mixed cells of their points,
 * and the interface motion at every point; rows from the layout. */
static PetscErrorCode BwXdmfPortionsCreate(BwGeometry geom, const BwMixedOwnership *own, const BwXdmfLayout *XL, const PetscReal pair[], BwXdmfData *x)
{
  const BwPortions *P = own->portions;
  BwXdmfLayouts     L;
  PetscInt          n = 0, nt = 0;

  PetscFunctionBeginUser;
  PetscCall(BwXdmfLayoutsCreate(geom, P, &L));
  for (PetscInt e = 0; e < own->nown_interfaces; e++) {
    PetscInt k = own->own_interfaces[e];
    x->nportion_rows += L.points[k + 1] - L.points[k];
    x->nportion_topology_rows += L.topology[k + 1] - L.topology[k];
  }
  PetscCall(PetscMalloc5(x->nportion_rows + 1, &x->portion_rows, 3 * x->nportion_rows + 1, &x->portion_points, 3 * x->nportion_rows + 1, &x->portion_displacement, x->nportion_topology_rows + 1, &x->portion_topology_rows, x->nportion_topology_rows + 1, &x->portion_topology));
  for (PetscInt e = 0; e < own->nown_interfaces; e++) {
    const PetscInt   k = own->own_interfaces[e], l = P->layout[k];
    const PetscReal *G = geom->center + 3 * k, *t = geom->frame + 9 * k, *b = t + 6;
    PetscInt         point = XL->ppoint_start[e];

    for (PetscInt r = 0; r < L.topology[k + 1] - L.topology[k]; r++) x->portion_topology_rows[nt + r] = XL->ptopology_start[e] + r;
    for (PetscInt p = P->offsets[l]; p < P->offsets[l + 1]; p++) {
      const PetscInt nv = L.voff[p + 1] - L.voff[p];
      const int      type = BwXdmfPolygonType(nv);
      x->portion_topology[nt++] = type;
      if (type == BW_XDMF_POLYGON) x->portion_topology[nt++] = nv;
      for (PetscInt v = L.voff[p + 1] - 1; v >= L.voff[p]; v--, n++) {
        const PetscReal xi = L.verts[2 * v], eta = L.verts[2 * v + 1];
        PetscReal      *X = x->portion_points + 3 * n;
        for (int d = 0; d < 3; d++) X[d] = G[d] + xi * t[d] + eta * b[d];
        BwXdmfInterfaceMotion(geom, k, pair + 12 * e, X, x->portion_displacement + 3 * n);
        x->portion_rows[n]        = point;
        x->portion_topology[nt++] = point++;
      }
    }
  }
  PetscCall(BwXdmfLayoutsDestroy(&L));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The vertex rows of the owned blocks (global, ascending) and their rigid
 * displacements u(x). */
static PetscErrorCode BwXdmfVertexRows(BwGeometry geom, const BwResults *res, BwXdmfData *x)
{
  const PetscInt nown = geom->nown_blocks, d = geom->dim;
  PetscInt       k = 0;

  PetscFunctionBeginUser;
  x->nvertex_rows = geom->offsets[nown] - geom->offsets[0];
  PetscCall(PetscMalloc2(x->nvertex_rows + 1, &x->vertex_rows, 3 * x->nvertex_rows + 1, &x->vertex_displacement));
  for (PetscInt b = 0; b < nown; b++) {
    const PetscReal *c = geom->centroid + d * b;
    for (PetscInt v = geom->offsets[b]; v < geom->offsets[b + 1]; v++, k++) {
      PetscReal *out = x->vertex_displacement + 3 * k;
      x->vertex_rows[k] = geom->gvoffset[b] + (v - geom->offsets[b]);
      if (d == 3) {
        out[0] = out[1] = out[2] = 0;
        BwXdmfAddRigidMotion(res->displacement + 6 * b, c, geom->vertices + 3 * v, 1, out);
      } else {
        const PetscReal *u = res->displacement + 3 * b, *p = geom->vertices + 2 * v;
        out[0]             = u[0] - u[2] * (p[1] - c[1]);
        out[1]             = u[1] + u[2] * (p[0] - c[0]);
        out[2]             = 0;
      }
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 3D: the polyhedra, the interface polygons, u + w x (x - c) at the
 * vertices of the owned blocks and the interface motion at those of the
 * owned interfaces' polygons (and portions). */
static PetscErrorCode BwXdmfDataCreate3D(BwGeometry geom, const BwMixedOwnership *own, const BwXdmfLayout *L, const BwResults *res, PetscBool portions, BwXdmfData *x)
{
  const PetscInt nown = geom->nown_blocks;
  PetscInt       k = 0;

  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < nown; b++) x->ntopology_rows += BwXdmfBlockTopologyLength(geom, b);
  PetscCall(PetscMalloc2(x->ntopology_rows + 1, &x->topology_rows, x->ntopology_rows + 1, &x->topology));
  for (PetscInt b = 0; b < nown; b++) {
    PetscInt r = L->topology_start[b];
    x->topology_rows[k] = r++;
    x->topology[k++]    = BW_XDMF_POLYHEDRON;
    x->topology_rows[k] = r++;
    x->topology[k++]    = geom->face_offsets[b + 1] - geom->face_offsets[b];
    for (PetscInt f = geom->face_offsets[b]; f < geom->face_offsets[b + 1]; f++) {
      x->topology_rows[k] = r++;
      x->topology[k++]    = geom->face_voffsets[f + 1] - geom->face_voffsets[f];
      for (PetscInt v = geom->face_voffsets[f]; v < geom->face_voffsets[f + 1]; v++) {
        x->topology_rows[k] = r++;
        x->topology[k++]    = geom->gvoffset[b] + (geom->face_vertices[v] - geom->offsets[b]);
      }
    }
  }
  for (PetscInt e = 0; e < own->nown_interfaces; e++) x->ninterface_topology_rows += BwXdmfInterfaceTopologyLength(geom, own->own_interfaces[e]);
  PetscCall(PetscMalloc2(x->ninterface_topology_rows + 1, &x->interface_topology_rows, x->ninterface_topology_rows + 1, &x->interface_topology));
  k = 0;
  for (PetscInt e = 0; e < own->nown_interfaces; e++) {
    PetscInt i = own->own_interfaces[e], nv = geom->poly_offsets[i + 1] - geom->poly_offsets[i], r = L->itopology_start[e];
    int      type = BwXdmfPolygonType(nv);
    x->interface_topology_rows[k] = r++;
    x->interface_topology[k++]    = type;
    if (type == BW_XDMF_POLYGON) {
      x->interface_topology_rows[k] = r++;
      x->interface_topology[k++]    = nv;
    }
    for (PetscInt v = 0; v < nv; v++) {
      x->interface_topology_rows[k] = r++;
      x->interface_topology[k++]    = geom->gpoly_offset[i] + v;
    }
  }
  PetscCall(BwXdmfVertexRows(geom, res, x));
  for (PetscInt e = 0; e < own->nown_interfaces; e++) {
    PetscInt i = own->own_interfaces[e];
    x->ninterface_rows += geom->poly_offsets[i + 1] - geom->poly_offsets[i];
  }
  PetscCall(PetscMalloc2(x->ninterface_rows + 1, &x->interface_rows, 3 * x->ninterface_rows + 1, &x->interface_displacement));
  k = 0;
  for (PetscInt e = 0; e < own->nown_interfaces; e++) {
    PetscInt i = own->own_interfaces[e];
    for (PetscInt v = geom->poly_offsets[i]; v < geom->poly_offsets[i + 1]; v++, k++) {
      x->interface_rows[k] = geom->gpoly_offset[i] + (v - geom->poly_offsets[i]);
      BwXdmfInterfaceMotion(geom, i, res->pair + 12 * e, geom->poly + 3 * v, x->interface_displacement + 3 * k);
    }
  }
  if (portions) PetscCall(BwXdmfPortionsCreate(geom, own, L, res->pair, x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwXdmfDataCreate(BwGeometry geom, const BwMixedOwnership *own, const BwXdmfLayout *L, const BwResults *res, PetscBool portions, BwXdmfData *x)
{
  const PetscInt nown = geom->nown_blocks, noi = own->nown_interfaces;
  PetscInt       k = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(x, sizeof(*x)));
  if (geom->dim == 3) {
    PetscCall(BwXdmfDataCreate3D(geom, own, L, res, portions, x));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  for (PetscInt b = 0; b < nown; b++) x->ntopology_rows += BwXdmfBlockTopologyLength(geom, b);
  PetscCall(PetscMalloc2(x->ntopology_rows + 1, &x->topology_rows, x->ntopology_rows + 1, &x->topology));
  for (PetscInt b = 0; b < nown; b++) {
    int      type = BwXdmfCellType(geom, b);
    PetscInt r    = L->topology_start[b];
    x->topology_rows[k] = r++;
    x->topology[k++]    = type;
    if (type == BW_XDMF_POLYGON) {
      x->topology_rows[k] = r++;
      x->topology[k++]    = geom->offsets[b + 1] - geom->offsets[b];
    }
    for (PetscInt v = 0; v < geom->offsets[b + 1] - geom->offsets[b]; v++) {
      x->topology_rows[k] = r++;
      x->topology[k++]    = geom->gvoffset[b] + v;
    }
  }
  x->ninterface_rows2 = noi;
  PetscCall(PetscMalloc3(noi + 1, &x->interface_rows2, 4 * noi + 1, &x->interface_points, 2 * noi + 1, &x->interface_topology2));
  for (PetscInt e = 0; e < noi; e++) {
    PetscInt  i = own->own_interfaces[e], gi = geom->giface[i];
    PetscReal h = 0.5 * geom->length[i], t[2] = {PetscCosReal(geom->angle[i]), PetscSinReal(geom->angle[i])};
    for (int d = 0; d < 2; d++) {
      x->interface_points[4 * e + d]     = geom->center[2 * i + d] - h * t[d];
      x->interface_points[4 * e + 2 + d] = geom->center[2 * i + d] + h * t[d];
    }
    x->interface_rows2[e]            = gi;
    x->interface_topology2[2 * e]     = 2 * gi;
    x->interface_topology2[2 * e + 1] = 2 * gi + 1;
  }
  PetscCall(BwXdmfVertexRows(geom, res, x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwXdmfDataDestroy(BwXdmfData *x)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree2(x->topology_rows, x->topology));
  PetscCall(PetscFree3(x->interface_rows2, x->interface_points, x->interface_topology2));
  PetscCall(PetscFree2(x->interface_topology_rows, x->interface_topology));
  PetscCall(PetscFree2(x->vertex_rows, x->vertex_displacement));
  PetscCall(PetscFree2(x->interface_rows, x->interface_displacement));
  PetscCall(PetscFree5(x->portion_rows, x->portion_points, x->portion_displacement, x->portion_topology_rows, x->portion_topology));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwXdmfPath(const char h5file[], char xdmffile[], size_t len)
{
  const char *slash = strrchr(h5file, '/'), *base = slash ? slash + 1 : h5file, *dot = strrchr(base, '.');
  int         n;

  PetscFunctionBeginUser;
  /* no extension, a hidden file's leading dot, or already .xdmf: append */
  if (!dot || dot == base || !strcmp(dot, ".xdmf")) dot = base + strlen(base);
  n = snprintf(xdmffile, len, "%.*s.xdmf", (int)(dot - h5file), h5file);
  PetscCheck(n >= 0 && (size_t)n < len, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "output.file: '%s' is too long for its .xdmf name", h5file);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The characters XML does not allow as they are in an element's text. */
static PetscErrorCode BwXmlEscape(const char in[], char out[], size_t len)
{
  size_t k = 0;

  PetscFunctionBeginUser;
  for (const char *c = in; *c; c++) {
    const char *s = *c == '&' ? "&amp;" : *c == '<' ? "&lt;" : *c == '>' ? "&gt;" : NULL;
    size_t      n = s ? strlen(s) : 1;
    PetscCheck(k + n < len, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "output.file: '%s' is too long", in);
    if (s) memcpy(out + k, s, n);
    else out[k] = *c;
    k += n;
  }
  out[k] = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A DataItem pointing at dataset `path` of the result file `ref`. */
static PetscErrorCode BwXdmfItem(FILE *fp, const char indent[], const char ref[], const char path[], const char dims[], const char type[], int precision)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "%s<DataItem Dimensions=\"%s\" NumberType=\"%s\" Precision=\"%d\" Format=\"HDF\">%s:%s</DataItem>\n", indent, dims, type, precision, ref, path));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A field: `n` rows (points or cells) of `width` values (1: a scalar). */
static PetscErrorCode BwXdmfField(FILE *fp, const char ref[], const char name[], const char center[], const char path[], PetscInt n, PetscInt width, const char type[], int precision)
{
  char dims[64];

  PetscFunctionBeginUser;
  if (width > 1) PetscCall(PetscSNPrintf(dims, sizeof(dims), "%" PetscInt_FMT " %" PetscInt_FMT, n, width));
  else PetscCall(PetscSNPrintf(dims, sizeof(dims), "%" PetscInt_FMT, n));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"%s\">\n", name, width == 1 ? "Scalar" : width <= 3 ? "Vector" : "Matrix", center));
  PetscCall(BwXdmfItem(fp, "        ", ref, path, dims, type, precision));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      </Attribute>\n"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The 3D portions grid's sizes: cells, points, the Mixed list's length
 * (nportions 0: no portions grid). */
typedef struct {
  PetscInt  nportions, npoints, ntopology;
  PetscBool stresses;
} BwXdmfPortionGrid;

/* The grids of one state: `at` is "" for the file's final state, or a
 * step's group "/steps/NNNNNN" (with "/xdmf/steps/NNNNNN" for its point
 * displacements). m_state > 0: a pushover's portion states are fields. */
static PetscErrorCode BwXdmfGrids(FILE *fp, const char ref[], const BwXdmfSizes *S, const BwXdmfPortionGrid *pg, const char at[], PetscInt step, PetscInt m_state)
{
  char           dims[64], path[128], topo[128], xat[64];
  PetscInt       nb = S->nblocks, nv = S->nvertices, ni = S->ninterfaces;
  const PetscInt d = S->dim, nd = d == 3 ? 6 : 3;
  const char    *xy = d == 3 ? "XYZ" : "XY";

  PetscFunctionBeginUser;
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "    <Grid Name=\"blocks\" GridType=\"Uniform\">\n"));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      <Topology TopologyType=\"Mixed\" NumberOfElements=\"%" PetscInt_FMT "\">\n", nb));
  PetscCall(PetscSNPrintf(dims, sizeof(dims), "%" PetscInt_FMT, S->ntopology));
  PetscCall(BwXdmfItem(fp, "        ", ref, "/xdmf/topology", dims, "Int", 8));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      </Topology>\n      <Geometry GeometryType=\"%s\">\n", xy));
  PetscCall(PetscSNPrintf(dims, sizeof(dims), "%" PetscInt_FMT " %" PetscInt_FMT, nv, d));
  PetscCall(BwXdmfItem(fp, "        ", ref, "/blocks/vertices", dims, "Float", 8));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      </Geometry>\n"));
  if (step >= 0) PetscCall(PetscSNPrintf(xat, sizeof(xat), "/xdmf/steps/%06" PetscInt_FMT, step));
  else PetscCall(PetscStrncpy(xat, "/xdmf", sizeof(xat)));
  PetscCall(PetscSNPrintf(topo, sizeof(topo), "%s/vertex_displacement", xat));
  PetscCall(BwXdmfField(fp, ref, "vertex_displacement", "Node", topo, nv, 3, "Float", 8));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/blocks/displacement", at));
  PetscCall(BwXdmfField(fp, ref, "displacement", "Cell", path, nb, nd, "Float", 8));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/blocks/reaction", at));
  PetscCall(BwXdmfField(fp, ref, "reaction", "Cell", path, nb, nd, "Float", 8));
  if (step < 0) {
    PetscCall(BwXdmfField(fp, ref, "load", "Cell", "/blocks/load", nb, nd, "Float", 8));
    PetscCall(BwXdmfField(fp, ref, "prescribed", "Cell", "/blocks/prescribed", nb, nd, "Char", 1));
  }
  PetscCall(BwXdmfField(fp, ref, "centroid", "Cell", "/blocks/centroid", nb, d, "Float", 8));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "    </Grid>\n"));

  /* an empty grid is an error to some readers: no interfaces, no grid */
  if (ni > 0) {
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "    <Grid Name=\"interfaces\" GridType=\"Uniform\">\n"));
    if (d == 3) {
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      <Topology TopologyType=\"Mixed\" NumberOfElements=\"%" PetscInt_FMT "\">\n", ni));
      PetscCall(PetscSNPrintf(dims, sizeof(dims), "%" PetscInt_FMT, S->ninterface_topology));
      PetscCall(BwXdmfItem(fp, "        ", ref, "/xdmf/interface_topology", dims, "Int", 8));
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      </Topology>\n      <Geometry GeometryType=\"XYZ\">\n"));
      PetscCall(PetscSNPrintf(dims, sizeof(dims), "%" PetscInt_FMT " 3", S->npolyvertices));
      PetscCall(BwXdmfItem(fp, "        ", ref, "/interfaces/vertices", dims, "Float", 8));
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      </Geometry>\n"));
      PetscCall(PetscSNPrintf(path, sizeof(path), "%s/interface_displacement", xat));
      PetscCall(BwXdmfField(fp, ref, "vertex_displacement", "Node", path, S->npolyvertices, 3, "Float", 8));
      PetscCall(BwXdmfField(fp, ref, "area", "Cell", "/interfaces/area", ni, 1, "Float", 8));
    } else {
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      <Topology TopologyType=\"Polyline\" NodesPerElement=\"2\" NumberOfElements=\"%" PetscInt_FMT "\">\n", ni));
      PetscCall(PetscSNPrintf(dims, sizeof(dims), "%" PetscInt_FMT " 2", ni));
      PetscCall(BwXdmfItem(fp, "        ", ref, "/xdmf/interface_topology", dims, "Int", 8));
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      </Topology>\n      <Geometry GeometryType=\"XY\">\n"));
      PetscCall(PetscSNPrintf(dims, sizeof(dims), "%" PetscInt_FMT " 2", 2 * ni));
      PetscCall(BwXdmfItem(fp, "        ", ref, "/xdmf/interface_points", dims, "Float", 8));
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      </Geometry>\n"));
    }
    PetscCall(PetscSNPrintf(path, sizeof(path), "%s/interfaces/resultant", at));
    PetscCall(BwXdmfField(fp, ref, "resultant", "Cell", path, ni, nd, "Float", 8));
    PetscCall(PetscSNPrintf(path, sizeof(path), "%s/interfaces/relative_displacement", at));
    PetscCall(BwXdmfField(fp, ref, "relative_displacement", "Cell", path, ni, nd, "Float", 8));
    if (d == 2 && m_state > 0) {
      /* the mode of each portion: m components per interface */
      PetscCall(PetscSNPrintf(path, sizeof(path), "%s/interfaces/state", at));
      PetscCall(BwXdmfField(fp, ref, "state", "Cell", path, ni, m_state, "Char", 1));
    }
    PetscCall(BwXdmfField(fp, ref, "kn", "Cell", "/interfaces/kn", ni, 1, "Float", 8));
    PetscCall(BwXdmfField(fp, ref, "kt", "Cell", "/interfaces/kt", ni, 1, "Float", 8));
    PetscCall(BwXdmfField(fp, ref, "blocks", "Cell", "/interfaces/blocks", ni, 2, "Int", 8));
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "    </Grid>\n"));
  }

  if (pg->nportions > 0) {
    const PetscInt np = pg->nportions;
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "    <Grid Name=\"portions\" GridType=\"Uniform\">\n"));
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      <Topology TopologyType=\"Mixed\" NumberOfElements=\"%" PetscInt_FMT "\">\n", np));
    PetscCall(PetscSNPrintf(dims, sizeof(dims), "%" PetscInt_FMT, pg->ntopology));
    PetscCall(BwXdmfItem(fp, "        ", ref, "/xdmf/portion_topology", dims, "Int", 8));
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      </Topology>\n      <Geometry GeometryType=\"XYZ\">\n"));
    PetscCall(PetscSNPrintf(dims, sizeof(dims), "%" PetscInt_FMT " 3", pg->npoints));
    PetscCall(BwXdmfItem(fp, "        ", ref, "/xdmf/portion_points", dims, "Float", 8));
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      </Geometry>\n"));
    PetscCall(PetscSNPrintf(path, sizeof(path), "%s/portion_displacement", xat));
    PetscCall(BwXdmfField(fp, ref, "vertex_displacement", "Node", path, pg->npoints, 3, "Float", 8));
    if (pg->stresses) {
      PetscCall(PetscSNPrintf(path, sizeof(path), "%s/portions/stress", at));
      PetscCall(BwXdmfField(fp, ref, "stress", "Cell", path, np, 3, "Float", 8));
    }
    if (m_state > 0) {
      PetscCall(PetscSNPrintf(path, sizeof(path), "%s/portions/state", at));
      PetscCall(BwXdmfField(fp, ref, "state", "Cell", path, np, 1, "Char", 1));
      /* the plastic jump is the final state's only (no step has it) */
      if (step < 0) PetscCall(BwXdmfField(fp, ref, "plastic_jump", "Cell", "/portions/plastic_jump", np, 3, "Float", 8));
    }
    PetscCall(BwXdmfField(fp, ref, "area", "Cell", "/portions/area", np, 1, "Float", 8));
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "    </Grid>\n"));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwXdmfWrite(const char h5file[], const char xdmffile[], const BwXdmfSizes *sizes, PetscInt nsteps, const PetscInt steps[], PetscInt m_state, PetscBool stresses)
{
  const char       *slash = strrchr(h5file, '/');
  char              ref[3 * PETSC_MAX_PATH_LEN];
  FILE             *fp;
  BwXdmfPortionGrid pg = {sizes->nportions, sizes->nportion_points, sizes->nportion_topology, stresses};

  PetscFunctionBeginUser;
  PetscCall(BwXmlEscape(slash ? slash + 1 : h5file, ref, sizeof(ref)));
  PetscCall(PetscFOpen(PETSC_COMM_SELF, xdmffile, "w", &fp));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "<?xml version=\"1.0\" ?>\n<!-- blockwall %s: blocks and interfaces of the HDF5 file named below, which must stay beside this file -->\n", BW_VERSION));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "<Xdmf Version=\"3.0\">\n  <Domain>\n"));
  if (!nsteps) PetscCall(BwXdmfGrids(fp, ref, sizes, &pg, "", -1, m_state));
  else {
    /* a temporal collection over the written steps (time = step number,
     * which grows where the load factor may not): ParaView plays it */
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "  <Grid Name=\"steps\" GridType=\"Collection\" CollectionType=\"Temporal\">\n"));
    for (PetscInt s = 0; s < nsteps; s++) {
      char at[64];
      PetscCall(PetscSNPrintf(at, sizeof(at), "/steps/%06" PetscInt_FMT, steps[s]));
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "  <Grid Name=\"step %06" PetscInt_FMT "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n", steps[s]));
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "    <Time Value=\"%" PetscInt_FMT "\"/>\n", steps[s]));
      PetscCall(BwXdmfGrids(fp, ref, sizes, &pg, at, steps[s], m_state));
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "  </Grid>\n"));
    }
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "  </Grid>\n"));
  }
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "  </Domain>\n</Xdmf>\n"));
  PetscCheck(!ferror(fp), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "output.xdmf: cannot write '%s'", xdmffile);
  PetscCall(PetscFClose(PETSC_COMM_SELF, fp));
  PetscFunctionReturn(PETSC_SUCCESS);
}
