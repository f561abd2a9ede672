/* The XDMF file beside the HDF5 result (see xdmf.h for what it describes).
 *
 * Layout, and why:
 * - One Domain with two Uniform grids, "blocks" and "interfaces": ParaView
 *   opens them as one multiblock data set, so blocks and interfaces can be
 *   shown and coloured independently.
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
 * - Keys in their XDMF 2 spelling (TopologyType, GeometryType,
 *   AttributeType, NumberType), which XDMF 3 readers accept as well, so
 *   ParaView's Xdmf3 readers and its legacy Xdmf reader both open the file. */
#include <string.h>
#include "output/xdmf.h"
#include "util/compat.h"

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
 * or Polygon (with its count) as in 2D. */
static PetscInt BwXdmfTopologyLength(BwGeometry g)
{
  PetscInt len = 0;

  if (g->dim == 3) {
    for (PetscInt b = 0; b < g->nblocks; b++) {
      len += 2;
      for (PetscInt f = g->face_offsets[b]; f < g->face_offsets[b + 1]; f++) len += 1 + g->face_voffsets[f + 1] - g->face_voffsets[f];
    }
    return len;
  }
  for (PetscInt b = 0; b < g->nblocks; b++) len += 1 + (BwXdmfCellType(g, b) == BW_XDMF_POLYGON) + g->offsets[b + 1] - g->offsets[b];
  return len;
}

static int BwXdmfPolygonType(PetscInt nv)
{
  return nv == 3 ? BW_XDMF_TRIANGLE : nv == 4 ? BW_XDMF_QUADRILATERAL : BW_XDMF_POLYGON;
}

static PetscInt BwXdmfInterfaceTopologyLength(BwGeometry g)
{
  PetscInt len = 0;

  if (g->dim != 3) return 2 * g->ninterfaces;
  for (PetscInt k = 0; k < g->ninterfaces; k++) {
    PetscInt nv = g->poly_offsets[k + 1] - g->poly_offsets[k];
    len += 1 + (BwXdmfPolygonType(nv) == BW_XDMF_POLYGON) + nv;
  }
  return len;
}

/* 3D: the polyhedra, the interface polygons, and u + w x (x - c) at the
 * vertices of the owned blocks. */
static PetscErrorCode BwXdmfDataCreate3D(BwGeometry geom, PetscInt nown, const PetscInt own[], const PetscReal displacement[], BwXdmfData *x)
{
  PetscInt nb = geom->nblocks, ni = geom->ninterfaces, k = 0;

  PetscFunctionBeginUser;
  x->ntopology           = BwXdmfTopologyLength(geom);
  x->ninterface_topology = BwXdmfInterfaceTopologyLength(geom);
  PetscCall(PetscMalloc3(x->ntopology + 1, &x->topology, 1, &x->interface_points, x->ninterface_topology + 1, &x->interface_topology));
  for (PetscInt b = 0; b < nb; b++) {
    x->topology[k++] = BW_XDMF_POLYHEDRON;
    x->topology[k++] = geom->face_offsets[b + 1] - geom->face_offsets[b];
    for (PetscInt f = geom->face_offsets[b]; f < geom->face_offsets[b + 1]; f++) {
      x->topology[k++] = geom->face_voffsets[f + 1] - geom->face_voffsets[f];
      for (PetscInt v = geom->face_voffsets[f]; v < geom->face_voffsets[f + 1]; v++) x->topology[k++] = geom->face_vertices[v];
    }
  }
  k = 0;
  for (PetscInt i = 0; i < ni; i++) {
    PetscInt nv = geom->poly_offsets[i + 1] - geom->poly_offsets[i];
    int      type = BwXdmfPolygonType(nv);
    x->interface_topology[k++] = type;
    if (type == BW_XDMF_POLYGON) x->interface_topology[k++] = nv;
    for (PetscInt v = geom->poly_offsets[i]; v < geom->poly_offsets[i + 1]; v++) x->interface_topology[k++] = v;
  }
  for (PetscInt e = 0; e < nown; e++) x->nvertex_rows += geom->offsets[own[e] + 1] - geom->offsets[own[e]];
  PetscCall(PetscMalloc2(x->nvertex_rows + 1, &x->vertex_rows, 3 * x->nvertex_rows + 1, &x->vertex_displacement));
  k = 0;
  for (PetscInt e = 0; e < nown; e++) {
    PetscInt         b = own[e];
    const PetscReal *u = displacement + 6 * e, *w = u + 3, *c = geom->centroid + 3 * b;
    for (PetscInt v = geom->offsets[b]; v < geom->offsets[b + 1]; v++, k++) {
      const PetscReal *p = geom->vertices + 3 * v, r[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
      x->vertex_rows[k]                 = v;
      x->vertex_displacement[3 * k]     = u[0] + w[1] * r[2] - w[2] * r[1];
      x->vertex_displacement[3 * k + 1] = u[1] + w[2] * r[0] - w[0] * r[2];
      x->vertex_displacement[3 * k + 2] = u[2] + w[0] * r[1] - w[1] * r[0];
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwXdmfDataCreate(BwGeometry geom, PetscInt nown, const PetscInt own[], const PetscReal displacement[], BwXdmfData *x)
{
  PetscInt nb = geom->nblocks, ni = geom->ninterfaces, k = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(x, sizeof(*x)));
  if (geom->dim == 3) {
    PetscCall(BwXdmfDataCreate3D(geom, nown, own, displacement, x));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  x->ntopology           = BwXdmfTopologyLength(geom);
  x->ninterface_topology = 2 * ni;
  PetscCall(PetscMalloc3(x->ntopology + 1, &x->topology, 4 * ni + 1, &x->interface_points, 2 * ni + 1, &x->interface_topology));
  for (PetscInt b = 0; b < nb; b++) {
    int type = BwXdmfCellType(geom, b);
    x->topology[k++] = type;
    if (type == BW_XDMF_POLYGON) x->topology[k++] = geom->offsets[b + 1] - geom->offsets[b];
    for (PetscInt v = geom->offsets[b]; v < geom->offsets[b + 1]; v++) x->topology[k++] = v;
  }
  for (PetscInt i = 0; i < ni; i++) {
    PetscReal h = 0.5 * geom->length[i], t[2] = {PetscCosReal(geom->angle[i]), PetscSinReal(geom->angle[i])};
    for (int d = 0; d < 2; d++) {
      x->interface_points[4 * i + d]     = geom->center[2 * i + d] - h * t[d];
      x->interface_points[4 * i + 2 + d] = geom->center[2 * i + d] + h * t[d];
    }
    x->interface_topology[2 * i]     = 2 * i;
    x->interface_topology[2 * i + 1] = 2 * i + 1;
  }
  for (PetscInt e = 0; e < nown; e++) x->nvertex_rows += geom->offsets[own[e] + 1] - geom->offsets[own[e]];
  PetscCall(PetscMalloc2(x->nvertex_rows + 1, &x->vertex_rows, 3 * x->nvertex_rows + 1, &x->vertex_displacement));
  k = 0;
  for (PetscInt e = 0; e < nown; e++) {
    PetscInt         b = own[e];
    const PetscReal *u = displacement + 3 * e, *c = geom->centroid + 2 * b;
    for (PetscInt v = geom->offsets[b]; v < geom->offsets[b + 1]; v++, k++) {
      const PetscReal *p = geom->vertices + 2 * v;
      x->vertex_rows[k]                 = v;
      x->vertex_displacement[3 * k]     = u[0] - u[2] * (p[1] - c[1]);
      x->vertex_displacement[3 * k + 1] = u[1] + u[2] * (p[0] - c[0]);
      x->vertex_displacement[3 * k + 2] = 0;
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwXdmfDataDestroy(BwXdmfData *x)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree3(x->topology, x->interface_points, x->interface_topology));
  PetscCall(PetscFree2(x->vertex_rows, x->vertex_displacement));
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

/* The two grids of one state: `at` is "" for the file's final state, or
 * a step's group "/steps/NNNNNN" (with "/xdmf/steps/NNNNNN" for its vertex
 * displacement); `ind` the indentation. */
static PetscErrorCode BwXdmfGrids(FILE *fp, const char ref[], BwGeometry geom, const char at[], PetscInt step, PetscInt m_state)
{
  char           dims[64], path[128], topo[128];
  PetscInt       nb = geom->nblocks, nv = geom->offsets[nb], ni = geom->ninterfaces;
  const PetscInt d = geom->dim, nd = d == 3 ? 6 : 3;
  const char    *xy = d == 3 ? "XYZ" : "XY";

  PetscFunctionBeginUser;
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "    <Grid Name=\"blocks\" GridType=\"Uniform\">\n"));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      <Topology TopologyType=\"Mixed\" NumberOfElements=\"%" PetscInt_FMT "\">\n", nb));
  PetscCall(PetscSNPrintf(dims, sizeof(dims), "%" PetscInt_FMT, BwXdmfTopologyLength(geom)));
  PetscCall(BwXdmfItem(fp, "        ", ref, "/xdmf/topology", dims, "Int", 8));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      </Topology>\n      <Geometry GeometryType=\"%s\">\n", xy));
  PetscCall(PetscSNPrintf(dims, sizeof(dims), "%" PetscInt_FMT " %" PetscInt_FMT, nv, d));
  PetscCall(BwXdmfItem(fp, "        ", ref, "/blocks/vertices", dims, "Float", 8));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      </Geometry>\n"));
  if (step >= 0) PetscCall(PetscSNPrintf(topo, sizeof(topo), "/xdmf/steps/%06" PetscInt_FMT "/vertex_displacement", step));
  else PetscCall(PetscStrncpy(topo, "/xdmf/vertex_displacement", sizeof(topo)));
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
      PetscCall(PetscSNPrintf(dims, sizeof(dims), "%" PetscInt_FMT, BwXdmfInterfaceTopologyLength(geom)));
      PetscCall(BwXdmfItem(fp, "        ", ref, "/xdmf/interface_topology", dims, "Int", 8));
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      </Topology>\n      <Geometry GeometryType=\"XYZ\">\n"));
      PetscCall(PetscSNPrintf(dims, sizeof(dims), "%" PetscInt_FMT " 3", geom->poly_offsets[ni]));
      PetscCall(BwXdmfItem(fp, "        ", ref, "/interfaces/vertices", dims, "Float", 8));
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "      </Geometry>\n"));
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
    if (m_state > 0) {
      /* the mode of each portion: m components per interface */
      PetscCall(PetscSNPrintf(path, sizeof(path), "%s/interfaces/state", at));
      PetscCall(BwXdmfField(fp, ref, "state", "Cell", path, ni, m_state, "Char", 1));
    }
    PetscCall(BwXdmfField(fp, ref, "kn", "Cell", "/interfaces/kn", ni, 1, "Float", 8));
    PetscCall(BwXdmfField(fp, ref, "kt", "Cell", "/interfaces/kt", ni, 1, "Float", 8));
    PetscCall(BwXdmfField(fp, ref, "blocks", "Cell", "/interfaces/blocks", ni, 2, "Int", 8));
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "    </Grid>\n"));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwXdmfWrite(const char h5file[], const char xdmffile[], BwGeometry geom, PetscInt nsteps, const PetscInt steps[], PetscInt m_state, PetscBool stresses)
{
  const char *slash = strrchr(h5file, '/');
  char        ref[3 * PETSC_MAX_PATH_LEN];
  FILE       *fp;

  PetscFunctionBeginUser;
  (void)stresses;
  PetscCall(BwXmlEscape(slash ? slash + 1 : h5file, ref, sizeof(ref)));
  PetscCall(PetscFOpen(PETSC_COMM_SELF, xdmffile, "w", &fp));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "<?xml version=\"1.0\" ?>\n<!-- blockwall %s: blocks and interfaces of the HDF5 file named below, which must stay beside this file -->\n", BW_VERSION));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "<Xdmf Version=\"3.0\">\n  <Domain>\n"));
  if (!nsteps) PetscCall(BwXdmfGrids(fp, ref, geom, "", -1, m_state));
  else {
    /* a temporal collection over the written steps (time = step number,
     * which grows where the load factor may not): ParaView plays it */
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "  <Grid Name=\"steps\" GridType=\"Collection\" CollectionType=\"Temporal\">\n"));
    for (PetscInt s = 0; s < nsteps; s++) {
      char at[64];
      PetscCall(PetscSNPrintf(at, sizeof(at), "/steps/%06" PetscInt_FMT, steps[s]));
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "  <Grid Name=\"step %06" PetscInt_FMT "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n", steps[s]));
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "    <Time Value=\"%" PetscInt_FMT "\"/>\n", steps[s]));
      PetscCall(BwXdmfGrids(fp, ref, geom, at, steps[s], m_state));
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "  </Grid>\n"));
    }
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "  </Grid>\n"));
  }
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "  </Domain>\n</Xdmf>\n"));
  PetscCheck(!ferror(fp), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "output.xdmf: cannot write '%s'", xdmffile);
  PetscCall(PetscFClose(PETSC_COMM_SELF, fp));
  PetscFunctionReturn(PETSC_SUCCESS);
}
