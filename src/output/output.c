/* HDF5 output, collective MPI-IO. Each dataset is created by all ranks; a
 * rank selects the rows it writes (a union of runs of consecutive input
 * indices) or nothing, and the transfer is collective. */
#include <errno.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>
#include <hdf5.h>
#include "output/output.h"
#include "output/xdmf.h"
#include "output/h5file.h"
#include "util/signals.h"
#include "util/compat.h"

PetscErrorCode BwOutputCreate(MPI_Comm comm, BwOutput *out)
{
  PetscFunctionBeginUser;
  PetscCall(PetscNew(out));
  (*out)->comm     = comm;
  (*out)->stresses = PETSC_TRUE;
  (*out)->xdmf     = PETSC_TRUE;
  PetscCall(PetscStrncpy((*out)->file, "out/blockwall.h5", sizeof((*out)->file)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwOutputDestroy(BwOutput *out)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(*out));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The directory of `path` ("." if none). */
static void BwDirName(const char path[], char dir[], size_t len)
{
  const char *slash = strrchr(path, '/');
  if (!slash) snprintf(dir, len, ".");
  else if (slash == path) snprintf(dir, len, "/");
  else snprintf(dir, len, "%.*s", (int)(slash - path), path);
}

/* Can the directory be written, or created (its nearest existing ancestor written)? */
static int BwDirWritable(const char dir[], char why[], size_t len)
{
  char        d[PETSC_MAX_PATH_LEN];
  struct stat st;

  snprintf(d, sizeof(d), "%s", dir);
  for (;;) {
    if (stat(d, &st) == 0) {
      if (!S_ISDIR(st.st_mode)) {
        snprintf(why, len, "'%s' is not a directory", d);
        return 0;
      }
      if (access(d, W_OK | X_OK) != 0) {
        snprintf(why, len, "directory '%s': %s", d, strerror(errno));
        return 0;
      }
      return 1;
    }
    {
      char parent[PETSC_MAX_PATH_LEN];
      BwDirName(d, parent, sizeof(parent));
      if (!strcmp(parent, d)) break;
      snprintf(d, sizeof(d), "%s", parent);
    }
  }
  snprintf(why, len, "no directory of '%s' exists", dir);
  return 0;
}

PetscErrorCode BwOutputSetFromOptions(BwOutput out, BwScene scene)
{
  char        dir[PETSC_MAX_PATH_LEN], why[PETSC_MAX_PATH_LEN + 64];
  int         ok = 1;
  struct stat st;
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCall(BwSceneHelpSection(scene, "Output (scene key output.*)"));
  PetscCall(BwSceneRequireMapping(scene, "-output", "file, stresses, xdmf"));
  PetscCall(BwSceneString(scene, "-output_file", "HDF5 result file (written to a temporary name, then renamed)", out->file, sizeof(out->file), NULL));
  PetscCall(BwSceneBool(scene, "-output_stresses", "Write the per-portion stresses /interfaces/stress (resultants are always written)", &out->stresses, NULL));
  PetscCall(BwSceneBool(scene, "-output_xdmf", "Write an XDMF file beside the HDF5 file for ParaView", &out->xdmf, NULL));
  if (!out->file[0]) PetscCall(BwSceneError(scene, "-output_file", "must name a file"));
  /* Fail before the solve, not after it, when the result cannot be written. */
  PetscCallMPI(MPI_Comm_rank(out->comm, &rank));
  if (rank == 0) {
    BwDirName(out->file, dir, sizeof(dir));
    ok = BwDirWritable(dir, why, sizeof(why));
    if (ok && stat(out->file, &st) == 0 && (S_ISDIR(st.st_mode) || access(out->file, W_OK) != 0)) {
      ok = 0;
      snprintf(why, sizeof(why), "'%s' %s", out->file, S_ISDIR(st.st_mode) ? "is a directory" : "exists and is not writable");
    }
  }
  PetscCallMPI(MPI_Bcast(&ok, 1, MPI_INT, 0, out->comm));
  PetscCallMPI(MPI_Bcast(why, sizeof(why), MPI_CHAR, 0, out->comm));
  if (!ok) PetscCall(BwSceneError(scene, "-output_file", "cannot be written: %s", why));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The portions of the owned interfaces as rows of /portions (their global
 * numbering follows /interfaces/portion_offsets). */
static PetscErrorCode BwOutputPortionRows(const BwMixedOwnership *own, PetscInt *nrows, PetscInt **rows)
{
  const BwPortions *P = own->portions;
  PetscInt          n = 0;

  PetscFunctionBeginUser;
  for (PetscInt e = 0; e < own->nown_interfaces; e++) n += BwPortionsCount(P, own->own_interfaces[e]);
  PetscCall(PetscMalloc1(n + 1, rows));
  *nrows = 0;
  for (PetscInt e = 0; e < own->nown_interfaces; e++)
    for (PetscInt p = 0; p < BwPortionsCount(P, own->own_interfaces[e]); p++) (*rows)[(*nrows)++] = own->own_portion_start[e] + p;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* An offsets dataset (N + 1) int64 of ragged items 0..N-1 spread over the
 * ranks: each rank writes the starts of its items (global ids gids[],
 * ascending), and the rank of item N - 1 (rank 0 when N = 0) the total. */
static PetscErrorCode BwOutputWriteOffsets(BwH5File h, MPI_Comm comm, const char name[], PetscInt N, PetscInt n, const PetscInt gids[], const PetscInt start[], PetscInt total)
{
  PetscInt   *rows, m = n;
  int64_t    *v;
  hsize_t     dims[1] = {(hsize_t)N + 1};
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscMalloc2(n + 2, &rows, n + 2, &v));
  for (PetscInt q = 0; q < n; q++) {
    rows[q] = gids[q];
    v[q]    = start[q];
  }
  if ((N > 0 && n > 0 && gids[n - 1] == N - 1) || (N == 0 && rank == 0)) {
    rows[m] = N;
    v[m++]  = total;
  }
  PetscCall(BwH5FileWrite(h, name, H5T_NATIVE_INT64, 1, dims, m, rows, v));
  PetscCall(PetscFree2(rows, v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The sets: each rank its owned members at their rows of the list. */
static PetscErrorCode BwOutputWriteSets(BwH5File h, BwGeometry geom)
{
  PetscFunctionBeginUser;
  for (PetscInt s = 0; s < geom->nsets; s++) {
    char     name[PETSC_MAX_PATH_LEN];
    PetscInt n = 0, *rows;
    int64_t *v;
    hsize_t  dims[1] = {(hsize_t)geom->setsize_global[s]};
    PetscCall(PetscMalloc2(geom->setoffsets[s + 1] - geom->setoffsets[s] + 1, &rows, geom->setoffsets[s + 1] - geom->setoffsets[s] + 1, &v));
    for (PetscInt q = geom->setoffsets[s]; q < geom->setoffsets[s + 1]; q++) {
      if (geom->setpos[q] < 0) continue; /* a ghost: its owner writes it */
      rows[n] = geom->setpos[q];
      v[n++]  = geom->gblock[geom->setblocks[q]];
    }
    /* rows ascending, the members with them (a file's list may have any order) */
    {
      PetscInt *perm;
      int64_t  *w;
      PetscCall(PetscMalloc2(n + 1, &perm, n + 1, &w));
      for (PetscInt q = 0; q < n; q++) perm[q] = q;
      PetscCall(PetscSortIntWithPermutation(n, rows, perm));
      for (PetscInt q = 0; q < n; q++) w[q] = v[perm[q]];
      PetscCall(PetscSortInt(n, rows));
      PetscCall(PetscSNPrintf(name, sizeof(name), "/sets/%s", geom->setname[s]));
      PetscCall(BwH5FileWrite(h, name, H5T_NATIVE_INT64, 1, dims, n, rows, w));
      PetscCall(PetscFree2(perm, w));
    }
    PetscCall(PetscFree2(rows, v));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The input schema's block datasets of the owned blocks (global rows):
 * vertices, offsets, centroid, load, prescribed. */
static PetscErrorCode BwOutputWriteBlocks(BwH5File h, BwGeometry geom, BwModel model, const PetscReal load[])
{
  const PetscInt d = geom->dim, nd = model->nd, nown = geom->nown_blocks, nv = geom->offsets[nown];
  PetscInt      *rows;
  signed char   *i8;
  hsize_t        dims[2];

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(nv + 1, &rows));
  for (PetscInt b = 0; b < nown; b++)
    for (PetscInt v = geom->offsets[b]; v < geom->offsets[b + 1]; v++) rows[v] = geom->gvoffset[b] + (v - geom->offsets[b]);
  dims[0] = (hsize_t)geom->nvertices_global;
  dims[1] = (hsize_t)d;
  PetscCall(BwH5FileWrite(h, "/blocks/vertices", H5T_NATIVE_DOUBLE, 2, dims, nv, rows, geom->vertices));
  PetscCall(PetscFree(rows));
  PetscCall(BwOutputWriteOffsets(h, geom->comm, "/blocks/offsets", geom->nblocks_global, nown, geom->gblock, geom->gvoffset, geom->nvertices_global));
  dims[0] = (hsize_t)geom->nblocks_global;
  dims[1] = (hsize_t)d;
  PetscCall(BwH5FileWrite(h, "/blocks/centroid", H5T_NATIVE_DOUBLE, 2, dims, nown, geom->gblock, geom->centroid));
  dims[1] = (hsize_t)nd;
  PetscCall(BwH5FileWrite(h, "/blocks/load", H5T_NATIVE_DOUBLE, 2, dims, nown, geom->gblock, load));
  PetscCall(PetscMalloc1(nd * nown + 1, &i8));
  for (PetscInt e = 0; e < nd * nown; e++) i8[e] = model->prescribed[e] ? 1 : 0;
  PetscCall(BwH5FileWrite(h, "/blocks/prescribed", H5T_NATIVE_SCHAR, 2, dims, nown, geom->gblock, i8));
  PetscCall(PetscFree(i8));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The owned interfaces' values of a per-interface array (w per
 * interface), contiguous in their order. */
static PetscErrorCode BwOutputGather(const BwMixedOwnership *own, PetscInt w, const PetscReal all[], PetscReal **out)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(w * own->nown_interfaces + 1, out));
  for (PetscInt e = 0; e < own->nown_interfaces; e++)
    for (PetscInt c = 0; c < w; c++) (*out)[w * e + c] = all[w * own->own_interfaces[e] + c];
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The input schema's interface datasets of the owned interfaces: blocks,
 * kn, kt, and those the dimension has (2D: center, angle, length; 3D:
 * center, frame, area, the polygons). */
static PetscErrorCode BwOutputWriteInterfaces(BwH5File h, BwGeometry geom, BwModel model, const BwMixedOwnership *own)
{
  const PetscInt  d = geom->dim, noi = own->nown_interfaces;
  const PetscInt *rows = own->own_interface_gid;
  int64_t        *i64;
  PetscReal      *v;
  hsize_t         dims[3];

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(2 * noi + 1, &i64));
  for (PetscInt e = 0; e < noi; e++) {
    PetscInt k      = own->own_interfaces[e];
    i64[2 * e]     = geom->gblock[geom->pair[2 * k]];
    i64[2 * e + 1] = geom->gblock[geom->pair[2 * k + 1]];
  }
  dims[0] = (hsize_t)geom->ninterfaces_global;
  dims[1] = 2;
  PetscCall(BwH5FileWrite(h, "/interfaces/blocks", H5T_NATIVE_INT64, 2, dims, noi, rows, i64));
  PetscCall(PetscFree(i64));
  dims[1] = (hsize_t)d;
  PetscCall(BwOutputGather(own, d, geom->center, &v));
  PetscCall(BwH5FileWrite(h, "/interfaces/center", H5T_NATIVE_DOUBLE, 2, dims, noi, rows, v));
  PetscCall(PetscFree(v));
  if (d == 3) {
    dims[1] = dims[2] = 3;
    PetscCall(BwOutputGather(own, 9, geom->frame, &v));
    PetscCall(BwH5FileWrite(h, "/interfaces/frame", H5T_NATIVE_DOUBLE, 3, dims, noi, rows, v));
    PetscCall(PetscFree(v));
    PetscCall(BwOutputGather(own, 1, geom->iarea, &v));
    PetscCall(BwH5FileWrite(h, "/interfaces/area", H5T_NATIVE_DOUBLE, 1, dims, noi, rows, v));
    PetscCall(PetscFree(v));
  } else {
    PetscCall(BwOutputGather(own, 1, geom->angle, &v));
    PetscCall(BwH5FileWrite(h, "/interfaces/angle", H5T_NATIVE_DOUBLE, 1, dims, noi, rows, v));
    PetscCall(PetscFree(v));
    PetscCall(BwOutputGather(own, 1, geom->length, &v));
    PetscCall(BwH5FileWrite(h, "/interfaces/length", H5T_NATIVE_DOUBLE, 1, dims, noi, rows, v));
    PetscCall(PetscFree(v));
  }
  PetscCall(BwOutputGather(own, 1, model->kn, &v));
  PetscCall(BwH5FileWrite(h, "/interfaces/kn", H5T_NATIVE_DOUBLE, 1, dims, noi, rows, v));
  PetscCall(PetscFree(v));
  PetscCall(BwOutputGather(own, 1, model->kt, &v));
  PetscCall(BwH5FileWrite(h, "/interfaces/kt", H5T_NATIVE_DOUBLE, 1, dims, noi, rows, v));
  PetscCall(PetscFree(v));
  if (d == 3) {
    PetscInt *starts, n = 0, *prow;
    PetscCall(PetscMalloc1(noi + 1, &starts));
    for (PetscInt e = 0; e < noi; e++) {
      PetscInt k = own->own_interfaces[e];
      starts[e]  = geom->gpoly_offset[k];
      n += geom->poly_offsets[k + 1] - geom->poly_offsets[k];
    }
    PetscCall(BwOutputWriteOffsets(h, geom->comm, "/interfaces/offsets", geom->ninterfaces_global, noi, rows, starts, geom->npolyvertices_global));
    PetscCall(PetscFree(starts));
    PetscCall(PetscMalloc2(n + 1, &prow, 3 * n + 1, &v));
    n = 0;
    for (PetscInt e = 0; e < noi; e++) {
      PetscInt k = own->own_interfaces[e];
      for (PetscInt p = geom->poly_offsets[k]; p < geom->poly_offsets[k + 1]; p++, n++) {
        prow[n] = geom->gpoly_offset[k] + (p - geom->poly_offsets[k]);
        for (int c = 0; c < 3; c++) v[3 * n + c] = geom->poly[3 * p + c];
      }
    }
    dims[0] = (hsize_t)geom->npolyvertices_global;
    dims[1] = 3;
    PetscCall(BwH5FileWrite(h, "/interfaces/vertices", H5T_NATIVE_DOUBLE, 2, dims, n, prow, v));
    PetscCall(PetscFree2(prow, v));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Whether the file has /portions datasets (3D, stresses or a pushover's
 * states), and so the XDMF a portions grid. */
static PetscBool BwOutputHasPortions(BwOutput out, BwGeometry geom, const BwOutputData *data)
{
  return geom->dim == 3 && (out->stresses || data->state) ? PETSC_TRUE : PETSC_FALSE;
}

/* What XDMF needs that the schema lacks (xdmf.h): the connectivity and, of
 * the state under `group` ("/xdmf" for the final state), the point
 * displacements; step: only the latter, under a new group
 * "/xdmf/steps/NNNNNN". */
static PetscErrorCode BwOutputWriteXdmf(BwH5File h, const char group[], BwGeometry geom, const BwMixedOwnership *own, const BwXdmfLayout *L, const BwResults *res, PetscBool portions, PetscBool step)
{
  BwXdmfData         x;
  const BwXdmfSizes *S = &L->sizes;
  char               name[128];
  hsize_t            dims[2];

  PetscFunctionBeginUser;
  PetscCall(BwXdmfDataCreate(geom, own, L, res, portions, &x));
  /* the group after the data, as the writer did before the portions
   * came: a pushover's path follows round-off, and with the group first
   * J4D to 4 mm in 6 steps on 2 ranks moved by 2e-16 at step 1 and took
   * 27 steps instead of 22 */
  if (step) PetscCall(BwH5FileGroup(h, group));
  else {
    dims[0] = (hsize_t)S->ntopology;
    PetscCall(BwH5FileWrite(h, "/xdmf/topology", H5T_NATIVE_INT64, 1, dims, x.ntopology_rows, x.topology_rows, x.topology));
    if (geom->dim == 3) {
      dims[0] = (hsize_t)S->ninterface_topology;
      PetscCall(BwH5FileWrite(h, "/xdmf/interface_topology", H5T_NATIVE_INT64, 1, dims, x.ninterface_topology_rows, x.interface_topology_rows, x.interface_topology));
    } else {
      /* two points per interface: rows 2k and 2k + 1 */
      PetscInt *rows2;
      PetscCall(PetscMalloc1(2 * x.ninterface_rows2 + 1, &rows2));
      for (PetscInt e = 0; e < x.ninterface_rows2; e++) {
        rows2[2 * e]     = 2 * x.interface_rows2[e];
        rows2[2 * e + 1] = 2 * x.interface_rows2[e] + 1;
      }
      dims[0] = 2 * (hsize_t)S->ninterfaces;
      dims[1] = 2;
      PetscCall(BwH5FileWrite(h, "/xdmf/interface_points", H5T_NATIVE_DOUBLE, 2, dims, 2 * x.ninterface_rows2, rows2, x.interface_points));
      PetscCall(PetscFree(rows2));
      dims[0] = (hsize_t)S->ninterfaces;
      PetscCall(BwH5FileWrite(h, "/xdmf/interface_topology", H5T_NATIVE_INT64, 2, dims, x.ninterface_rows2, x.interface_rows2, x.interface_topology2));
    }
    if (portions) {
      /* ragged like the portions: each rank its interfaces' rows */
      dims[0] = (hsize_t)S->nportion_points;
      dims[1] = 3;
      PetscCall(BwH5FileWrite(h, "/xdmf/portion_points", H5T_NATIVE_DOUBLE, 2, dims, x.nportion_rows, x.portion_rows, x.portion_points));
      dims[0] = (hsize_t)S->nportion_topology;
      PetscCall(BwH5FileWrite(h, "/xdmf/portion_topology", H5T_NATIVE_INT64, 1, dims, x.nportion_topology_rows, x.portion_topology_rows, x.portion_topology));
    }
  }
  dims[0] = (hsize_t)S->nvertices;
  dims[1] = 3;
  PetscCall(PetscSNPrintf(name, sizeof(name), "%s/vertex_displacement", group));
  PetscCall(BwH5FileWrite(h, name, H5T_NATIVE_DOUBLE, 2, dims, x.nvertex_rows, x.vertex_rows, x.vertex_displacement));
  if (geom->dim == 3) {
    dims[0] = (hsize_t)S->npolyvertices;
    PetscCall(PetscSNPrintf(name, sizeof(name), "%s/interface_displacement", group));
    PetscCall(BwH5FileWrite(h, name, H5T_NATIVE_DOUBLE, 2, dims, x.ninterface_rows, x.interface_rows, x.interface_displacement));
  }
  if (portions) {
    dims[0] = (hsize_t)S->nportion_points;
    PetscCall(PetscSNPrintf(name, sizeof(name), "%s/portion_displacement", group));
    PetscCall(BwH5FileWrite(h, name, H5T_NATIVE_DOUBLE, 2, dims, x.nportion_rows, x.portion_rows, x.portion_displacement));
  }
  PetscCall(BwXdmfDataDestroy(&x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The results of the owned blocks and interfaces at their global rows;
 * the portions' (3D) or the interfaces' per-portion datasets (2D). */
static PetscErrorCode BwOutputWriteResults(BwOutput out, BwH5File h, const char g[], const BwOutputData *data, const BwMixedOwnership *own, BwGeometry geom, PetscBool final)
{
  const BwResults *res = data->results;
  const PetscInt   nd  = own->nd;
  hsize_t          dims[3];
  char             name[128];

  PetscFunctionBeginUser;
  dims[0] = (hsize_t)own->nblocks;
  dims[1] = (hsize_t)nd;
  PetscCall(PetscSNPrintf(name, sizeof(name), "%s/blocks/displacement", g));
  PetscCall(BwH5FileWrite(h, name, H5T_NATIVE_DOUBLE, 2, dims, own->nown_blocks, own->own_block_gid, res->displacement));
  PetscCall(PetscSNPrintf(name, sizeof(name), "%s/blocks/reaction", g));
  PetscCall(BwH5FileWrite(h, name, H5T_NATIVE_DOUBLE, 2, dims, own->nown_blocks, own->own_block_gid, res->reaction));
  dims[0] = (hsize_t)own->ninterfaces;
  PetscCall(PetscSNPrintf(name, sizeof(name), "%s/interfaces/%s", g, final ? "relative_displacement" : "resultant"));
  PetscCall(BwH5FileWrite(h, name, H5T_NATIVE_DOUBLE, 2, dims, own->nown_interfaces, own->own_interface_gid, final ? res->relative : res->resultant));
  PetscCall(PetscSNPrintf(name, sizeof(name), "%s/interfaces/%s", g, final ? "resultant" : "relative_displacement"));
  PetscCall(BwH5FileWrite(h, name, H5T_NATIVE_DOUBLE, 2, dims, own->nown_interfaces, own->own_interface_gid, final ? res->resultant : res->relative));
  if (geom->dim == 3) {
    PetscInt nrows = 0, *rows = NULL;
    if (!BwOutputHasPortions(out, geom, data)) PetscFunctionReturn(PETSC_SUCCESS);
    PetscCall(BwOutputPortionRows(own, &nrows, &rows));
    PetscCall(PetscSNPrintf(name, sizeof(name), "%s/portions", g));
    PetscCall(BwH5FileGroup(h, name));
    dims[0] = (hsize_t)own->nportions_global;
    if (final) {
      const BwPortions *P = own->portions;
      PetscReal        *cen, *area;
      PetscInt          n = 0;
      PetscCall(BwOutputWriteOffsets(h, out->comm, "/interfaces/portion_offsets", own->ninterfaces, own->nown_interfaces, own->own_interface_gid, own->own_portion_start, own->nportions_global));
      PetscCall(PetscMalloc2(2 * nrows + 1, &cen, nrows + 1, &area));
      for (PetscInt e = 0; e < own->nown_interfaces; e++) {
        PetscInt k = own->own_interfaces[e], f = BwPortionsFirst(P, k), np = BwPortionsCount(P, k);
        for (PetscInt p = f; p < f + np; p++, n++) {
          cen[2 * n]     = P->xi[p];
          cen[2 * n + 1] = P->eta[p];
          area[n]        = P->area[p];
        }
      }
      dims[1] = 2;
      PetscCall(BwH5FileWrite(h, "/portions/center", H5T_NATIVE_DOUBLE, 2, dims, nrows, rows, cen));
      PetscCall(BwH5FileWrite(h, "/portions/area", H5T_NATIVE_DOUBLE, 1, dims, nrows, rows, area));
      PetscCall(PetscFree2(cen, area));
    }
    dims[1] = 3;
    if (data->state) {
      /* a pushover's joints: the portions' state (and plastic jump: slip
       * t, opening, slip b), in place of 2D's /interfaces/state */
      PetscCall(PetscSNPrintf(name, sizeof(name), "%s/portions/state", g));
      PetscCall(BwH5FileWrite(h, name, H5T_NATIVE_SCHAR, 1, dims, nrows, rows, data->state));
    }
    if (out->stresses) {
      PetscCall(PetscSNPrintf(name, sizeof(name), "%s/portions/stress", g));
      PetscCall(BwH5FileWrite(h, name, H5T_NATIVE_DOUBLE, 2, dims, nrows, rows, res->stress));
    }
    if (data->state && final) PetscCall(BwH5FileWrite(h, "/portions/plastic_jump", H5T_NATIVE_DOUBLE, 2, dims, nrows, rows, data->plastic));
    PetscCall(PetscFree(rows));
  } else {
    dims[1] = (hsize_t)own->m;
    dims[2] = 2;
    if (out->stresses && final) {
      PetscCall(PetscSNPrintf(name, sizeof(name), "%s/interfaces/stress", g));
      PetscCall(BwH5FileWrite(h, name, H5T_NATIVE_DOUBLE, 3, dims, own->nown_interfaces, own->own_interface_gid, res->stress));
    }
    if (data->state) {
      PetscCall(PetscSNPrintf(name, sizeof(name), "%s/interfaces/state", g));
      PetscCall(BwH5FileWrite(h, name, H5T_NATIVE_SCHAR, 2, dims, own->nown_interfaces, own->own_interface_gid, data->state));
    }
    if (out->stresses && !final) {
      PetscCall(PetscSNPrintf(name, sizeof(name), "%s/interfaces/stress", g));
      PetscCall(BwH5FileWrite(h, name, H5T_NATIVE_DOUBLE, 3, dims, own->nown_interfaces, own->own_interface_gid, res->stress));
    }
    if (data->state && final) PetscCall(BwH5FileWrite(h, "/interfaces/plastic_jump", H5T_NATIVE_DOUBLE, 3, dims, own->nown_interfaces, own->own_interface_gid, data->plastic));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwOutputWriteFile(BwOutput out, BwH5File h, const BwXdmfLayout *xlayout, const BwOutputData *data, const BwOutputHistory *hist, PetscBool have_steps, BwLog *log)
{
  BwModel          model;
  BwGeometry       geom;
  BwMixedOwnership own;
  const BwResults *res = data->results;
  PetscInt         m;
  hsize_t          dims[3];
  PetscMPIInt      size;
  PetscLogDouble   t1;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(out->comm, &size));
  PetscCall(BwMixedGetModel(data->mixed, &model));
  PetscCall(BwMixedGetOwnership(data->mixed, &own));
  geom = model->geom;
  m    = own.m;

  PetscCall(BwH5FileGroup(h, "/blocks"));
  PetscCall(BwH5FileGroup(h, "/interfaces"));
  PetscCall(BwH5FileGroup(h, "/sets"));
  PetscCall(BwH5FileGroup(h, "/solver"));
  if (out->xdmf && !have_steps) PetscCall(BwH5FileGroup(h, "/xdmf"));

  /* the input schema, each rank its owned blocks and interfaces */
  PetscCall(BwOutputWriteBlocks(h, geom, model, data->load));
  PetscCall(BwOutputWriteInterfaces(h, geom, model, &own));
  PetscCall(BwOutputWriteSets(h, geom));
  /* the results, at their input indices */
  PetscCall(BwOutputWriteResults(out, h, "", data, &own, geom, PETSC_TRUE));
  if (hist) {
    int64_t *its;
    PetscCall(BwH5FileGroup(h, "/history"));
    dims[0] = (hsize_t)hist->n;
    PetscCall(BwH5FileWriteAll(h, "/history/load_factor", H5T_NATIVE_DOUBLE, 1, dims, hist->load_factor));
    PetscCall(BwH5FileWriteAll(h, "/history/monitor", H5T_NATIVE_DOUBLE, 1, dims, hist->monitor));
    PetscCall(BwH5FileWriteAll(h, "/history/residual", H5T_NATIVE_DOUBLE, 1, dims, hist->residual));
    if (hist->dissipation) PetscCall(BwH5FileWriteAll(h, "/history/dissipation", H5T_NATIVE_DOUBLE, 1, dims, hist->dissipation));
    PetscCall(PetscMalloc1(hist->n + 1, &its));
    for (PetscInt i = 0; i < hist->n; i++) its[i] = hist->iterations ? hist->iterations[i] : 0;
    PetscCall(BwH5FileWriteAll(h, "/history/iterations", H5T_NATIVE_INT64, 1, dims, its));
    PetscCall(PetscFree(its));
  }
  if (out->xdmf) PetscCall(BwOutputWriteXdmf(h, "/xdmf", geom, &own, xlayout, res, BwOutputHasPortions(out, geom, data), PETSC_FALSE));

  /* attributes */
  PetscCall(BwH5FileAttrString(h, "/", "version", BW_VERSION));
  PetscCall(BwH5FileAttrString(h, "/", "scene", data->scene));
  PetscCall(BwH5FileAttrString(h, "/", "units", "SI"));
  PetscCall(BwH5FileAttrInt(h, "/", "dimension", geom->dim));
  PetscCall(BwH5FileAttrInt(h, "/", "m", m));
  if (geom->dim == 3) PetscCall(BwH5FileAttrInt(h, "/", "m_b", model->mb));
  else PetscCall(BwH5FileAttrDouble(h, "/", "depth", geom->depth));
  if (data->casename) PetscCall(BwH5FileAttrString(h, "/", "case", data->casename));
  for (PetscInt i = 0; i < data->solver->n; i++) {
    const BwReportItem *it = &data->solver->item[i];
    if (it->type == BW_REPORT_REAL) PetscCall(BwH5FileAttrDouble(h, "/solver", it->name, it->real));
    else if (it->type == BW_REPORT_INT) PetscCall(BwH5FileAttrInt(h, "/solver", it->name, it->integer));
    else PetscCall(BwH5FileAttrString(h, "/solver", it->name, it->text));
  }
  PetscCall(BwH5FileAttrInt(h, "/solver", "ranks", size));
  PetscCall(BwH5FileAttrInt(h, "/solver", "unknowns_q", own.nq_global));
  PetscCall(BwH5FileAttrInt(h, "/solver", "unknowns_r", own.nr_global));
  PetscCall(BwH5FileAttrInt(h, "/solver", "partition_edge_cut", own.edge_cut));
  PetscCall(BwH5FileAttrDouble(h, "/solver", "partition_imbalance", own.imbalance));
  {
    char blas[PETSC_MAX_PATH_LEN];
    PetscCall(BwBlasName(blas, sizeof(blas)));
    PetscCall(BwH5FileAttrString(h, "/solver", "blas", blas));
    PetscCall(BwBlasKernels(blas, sizeof(blas)));
    PetscCall(BwH5FileAttrString(h, "/solver", "blas_kernels", blas));
  }
  {
    PetscLogDouble cur, peak;
    PetscCall(BwMemoryUsage(out->comm, &cur, &peak));
    PetscCall(BwH5FileAttrDouble(h, "/solver", "memory_peak_bytes", peak));
  }
  PetscCall(PetscTime(&t1));
  for (int p = 0; p < BW_NPHASES; p++) {
    char name[64];
    PetscCall(PetscSNPrintf(name, sizeof(name), "seconds_%s", BwPhaseNames[p]));
    PetscCall(BwH5FileAttrDouble(h, "/solver", name, log->seconds[p] + (p == BW_PHASE_WRITE ? t1 - log->start : 0)));
  }
  PetscCall(BwH5FileAttrDouble(h, "/solver", "seconds_total", t1 - log->t0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The directories of `dir` that do not exist are created, outermost first;
 * *first is the outermost one created (empty if none), for BwRemoveDirs. */
static PetscErrorCode BwMakeDirs(const char dir[], char first[], size_t len)
{
  char path[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  first[0] = 0;
  PetscCall(PetscStrncpy(path, dir, sizeof(path)));
  for (char *p = path + 1;; p++) {
    char c = *p;
    if (c && c != '/') continue;
    *p = 0;
    if (mkdir(path, 0777) == 0) {
      if (!first[0]) PetscCall(PetscStrncpy(first, path, len));
    } else PetscCheck(errno == EEXIST, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "output.file: cannot create directory '%s': %s", path, strerror(errno));
    *p = c;
    if (!c) break;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Removes what BwMakeDirs created: dir and its parents up to first. */
static void BwRemoveDirs(const char dir[], const char first[])
{
  char path[PETSC_MAX_PATH_LEN];

  if (!first[0]) return;
  snprintf(path, sizeof(path), "%s", dir);
  for (;;) {
    char *slash;
    if (rmdir(path) != 0 || !strcmp(path, first)) return;
    slash = strrchr(path, '/');
    if (!slash || slash == path) return;
    *slash = 0;
  }
}

/* An upper estimate of the result file's size: every dataset, the scene
 * text, and HDF5's headers (a few hundred bytes per object, a margin for
 * its metadata blocks). */
static PetscLogDouble BwOutputBytesOwned(BwOutput out, BwMixed mx, PetscInt nsteps)
{
  BwModel          model;
  BwGeometry       g;
  BwMixedOwnership own;
  PetscLogDouble   nb, ni, nv, bytes;

  (void)BwMixedGetModel(mx, &model);
  (void)BwMixedGetOwnership(mx, &own);
  g     = model->geom;
  /* this rank's share of the file: its owned blocks and interfaces */
  nb    = g->nown_blocks;
  ni    = own.nown_interfaces;
  nv    = g->offsets[g->nown_blocks];
  if (g->dim == 3) {
    /* vertices, offsets, centroid, load, prescribed, displacement, reaction;
     * interfaces: blocks, center, frame, area, kn, kt, polygons, relative
     * displacement, resultant; portions (with stresses or states): centre,
     * area, offsets, stress, state and plastic jump. A portion polygon's
     * points are its cell's corners inside the interface, the interface's
     * corners inside the cell and the crossings of grid lines and edges
     * (each line crosses a convex polygon twice, each crossing a point of
     * two cells): at most 4 m m_b + 4 (m + m_b) + 4 nv per interface. */
    const PetscInt  m = model->m, mb = model->mb;
    PetscLogDouble  np = ni * m * mb, nw = 0, npt, nfv = 0, nf = 0;
    for (PetscInt e = 0; e < own.nown_interfaces; e++) nw += g->poly_offsets[own.own_interfaces[e] + 1] - g->poly_offsets[own.own_interfaces[e]];
    for (PetscInt b = 0; b < g->nown_blocks; b++) {
      nf += g->face_offsets[b + 1] - g->face_offsets[b];
      nfv += g->face_voffsets[g->face_offsets[b + 1]] - g->face_voffsets[g->face_offsets[b]];
    }
    npt = ni * (4.0 * m * mb + 4.0 * (m + mb)) + 4 * nw;
    const PetscBool portions = out->stresses || model->nonlinear;
    bytes = nv * 24 + (nb + 1) * 8 + nb * (24 + 48 + 6 + 48 + 48) + ni * (16 + 24 + 72 + 8 + 8 + 8 + 8 + 48 + 48) + nw * 24;
    if (portions) bytes += np * (16 + 8) + ni * 8;
    if (out->stresses) bytes += np * 24;
    if (model->nonlinear) bytes += np * 25;
    /* XDMF: the polyhedra's and polygons' Mixed lists, the point
     * displacements of blocks and interfaces; portions: their points, Mixed
     * list (type, count, ids) and point displacements */
    if (out->xdmf) bytes += (nfv + 2 * nb + nf) * 8.0 + (nw + 2 * ni) * 8.0 + nv * 24 + nw * 24;
    if (out->xdmf && portions) bytes += npt * (24 + 8 + 24) + np * 16;
    /* each step: displacement, reaction, resultant, relative displacement,
     * the portions' state and stresses, the point displacements for XDMF */
    bytes += nsteps * (nb * 96.0 + ni * 96.0 + np * ((model->nonlinear ? 1 : 0) + (out->stresses ? 24 : 0)) + (out->xdmf ? (nv + nw + (portions ? npt : 0)) * 24.0 : 0) + 4096);
  } else {
    bytes = nv * 16 + (nb + 1) * 8 + nb * (16 + 24 + 3 + 24 + 24) + ni * (16 + 16 + 8 + 8 + 8 + 8 + 24 + 24);
    if (out->stresses) bytes += ni * model->m * 16;
    if (out->xdmf) bytes += (nv + 2 * nb) * 8 + ni * (32 + 16) + nv * 24;
    if (model->nonlinear) bytes += ni * model->m * 17.0;
    /* each step: displacement, reaction, resultant, relative displacement,
     * state, the stresses if asked, the vertex displacement for XDMF */
    bytes += nsteps * (nb * 48.0 + ni * (48.0 + model->m * (1 + (out->stresses ? 16 : 0))) + (out->xdmf ? nv * 24.0 : 0) + 4096);
  }
  bytes += g->setoffsets[g->nsets] * 8.0;
  return bytes;
}

/* Bytes the result file will take, about (5 % over the datasets), for the
 * free-space check before writing: every rank's share summed (collective). */
static PetscErrorCode BwOutputBytes(BwOutput out, BwMixed mx, const char scene_text[], PetscInt nsteps, PetscLogDouble *bytes)
{
  PetscLogDouble mine = BwOutputBytesOwned(out, mx, nsteps), all;
  BwModel        model;

  PetscFunctionBeginUser;
  PetscCall(BwMixedGetModel(mx, &model));
  PetscCallMPI(MPIU_Allreduce(&mine, &all, 1, MPIU_PETSCLOGDOUBLE, MPI_SUM, out->comm));
  all += model->geom->nsets * 1024.0 + 2.0 * strlen(scene_text) + 65536 + 64 * 1024.0;
  *bytes = 1.05 * all;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwOutputCaseFile(BwOutput out, const char casename[], char file[], size_t len)
{
  const char *slash, *dot;

  PetscFunctionBeginUser;
  if (!casename) {
    PetscCall(PetscStrncpy(file, out->file, len));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  slash = strrchr(out->file, '/');
  dot   = strrchr(out->file, '.');
  if (!dot || (slash && dot < slash)) PetscCall(PetscSNPrintf(file, len, "%s.%s", out->file, casename));
  else PetscCall(PetscSNPrintf(file, len, "%.*s.%s%s", (int)(dot - out->file), out->file, casename, dot));
  PetscFunctionReturn(PETSC_SUCCESS);
}

struct _n_BwOutputFile {
  BwOutput   out;
  BwMixed    mixed;
  BwH5File   h;
  char       file[PETSC_MAX_PATH_LEN], tmp[PETSC_MAX_PATH_LEN + 32], dir[PETSC_MAX_PATH_LEN], created[PETSC_MAX_PATH_LEN];
  char       xdmf[PETSC_MAX_PATH_LEN + 8], xtmp[PETSC_MAX_PATH_LEN + 40];
  PetscInt   nsteps, maxsteps, *steps; /* the steps written, for the XDMF's temporal collection (rank 0) */
  PetscMPIInt rank;
  PetscBool    have_xlayout;
  BwXdmfLayout xlayout; /* where this rank's rows go in the ragged /xdmf datasets, made once */
};

/* The XDMF layout of the file, made at its first use (collective). */
static PetscErrorCode BwOutputXdmfLayout(BwOutputFile of, const BwOutputData *data)
{
  BwModel          model;
  BwMixedOwnership own;

  PetscFunctionBeginUser;
  if (of->have_xlayout) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(BwMixedGetModel(of->mixed, &model));
  PetscCall(BwMixedGetOwnership(of->mixed, &own));
  PetscCall(BwXdmfLayoutCreate(model->geom, &own, BwOutputHasPortions(of->out, model->geom, data), &of->xlayout));
  of->have_xlayout = PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Removes what an unpublished file left (rank 0). */
static void BwOutputFileUnlink(BwOutputFile of)
{
  if (of->rank != 0) return;
  unlink(of->tmp);
  unlink(of->xtmp);
  BwTemporaryRemove(of->tmp);
  BwTemporaryRemove(of->xtmp);
  BwRemoveDirs(of->dir, of->created);
}

static PetscErrorCode BwOutputFileFree(BwOutputFile *of)
{
  PetscFunctionBeginUser;
  PetscCall(BwXdmfLayoutDestroy(&(*of)->xlayout));
  PetscCall(PetscFree((*of)->steps));
  PetscCall(PetscFree(*of));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwOutputOpen(BwOutput out, const char file[], BwMixed mixed, const char scene[], PetscInt nsteps, BwOutputFile *ofp)
{
  BwOutputFile   of;
  char           msg[3 * PETSC_MAX_PATH_LEN] = "";
  int            pid = (int)getpid(), ok = 1;
  PetscLogDouble need = 0;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  *ofp = NULL;
  PetscCall(PetscNew(&of));
  of->out   = out;
  of->mixed = mixed;
  PetscCallMPI(MPI_Comm_rank(out->comm, &of->rank));
  PetscCallMPI(MPI_Bcast(&pid, 1, MPI_INT, 0, out->comm));
  PetscCall(PetscStrncpy(of->file, file, sizeof(of->file)));
  PetscCall(PetscSNPrintf(of->tmp, sizeof(of->tmp), "%s.tmp-%d", file, pid));
  PetscCall(BwXdmfPath(file, of->xdmf, sizeof(of->xdmf)));
  PetscCall(PetscSNPrintf(of->xtmp, sizeof(of->xtmp), "%s.tmp-%d", of->xdmf, pid));
  BwDirName(file, of->dir, sizeof(of->dir));
  PetscCall(BwOutputBytes(out, mixed, scene, nsteps, &need));
  if (of->rank == 0) {
    struct statvfs fs;
    if (BwMakeDirs(of->dir, of->created, sizeof(of->created))) {
      ok = 0;
      snprintf(msg, sizeof(msg), "output.file: cannot create directory '%s': %s", of->dir, strerror(errno));
    } else if (statvfs(of->dir, &fs) == 0 && (PetscLogDouble)fs.f_bavail * (PetscLogDouble)fs.f_frsize < need) {
      /* refused before a byte is written: a full disk met halfway ends in
       * a half-written file, which the temporary name only hides */
      ok = 0;
      snprintf(msg, sizeof(msg), "output.file: '%s' needs about %.3g MB and its file system has %.3g MB free; nothing was written", file, need / 1048576.0, (double)fs.f_bavail * (double)fs.f_frsize / 1048576.0);
      BwRemoveDirs(of->dir, of->created);
    }
    if (ok) PetscCall(BwTemporaryAdd(of->tmp));
    if (ok && out->xdmf) PetscCall(BwTemporaryAdd(of->xtmp));
  }
  PetscCallMPI(MPI_Bcast(&ok, 1, MPI_INT, 0, out->comm));
  if (!ok) {
    PetscCallMPI(MPI_Bcast(msg, sizeof(msg), MPI_CHAR, 0, out->comm));
    PetscCall(BwOutputFileFree(&of));
    SETERRQ(out->comm, PETSC_ERR_FILE_WRITE, "%s", msg);
  }
  ierr = BwH5FileCreate(out->comm, of->tmp, of->file, &of->h);
  if (ierr) {
    const char *text = BwErrorText(ierr);
    if (of->h) (void)BwH5FileClose(&of->h);
    BwOutputFileUnlink(of);
    PetscCall(BwOutputFileFree(&of));
    SETERRQ(out->comm, PETSC_ERR_FILE_WRITE, "output.file: writing '%s' failed (%s); nothing was written", file, text[0] ? text : "HDF5 error");
  }
  *ofp = of;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwOutputAbort(BwOutputFile *ofp)
{
  BwOutputFile of = *ofp;

  PetscFunctionBeginUser;
  if (!of) PetscFunctionReturn(PETSC_SUCCESS);
  if (of->h) (void)BwH5FileClose(&of->h);
  BwOutputFileUnlink(of);
  PetscCall(BwOutputFileFree(ofp));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwOutputWriteStepData(BwOutputFile of, PetscInt step, const BwOutputData *data)
{
  BwOutput         out = of->out;
  BwModel          model;
  BwMixedOwnership own;
  const BwResults *res = data->results;
  char             g[64], name[128];

  PetscFunctionBeginUser;
  PetscCall(BwMixedGetModel(of->mixed, &model));
  PetscCall(BwMixedGetOwnership(of->mixed, &own));
  if (!of->nsteps) {
    PetscCall(BwH5FileGroup(of->h, "/steps"));
    if (out->xdmf) {
      PetscCall(BwH5FileGroup(of->h, "/xdmf"));
      PetscCall(BwH5FileGroup(of->h, "/xdmf/steps"));
    }
  }
  PetscCall(PetscSNPrintf(g, sizeof(g), "/steps/%06" PetscInt_FMT, step));
  PetscCall(BwH5FileGroup(of->h, g));
  PetscCall(PetscSNPrintf(name, sizeof(name), "%s/blocks", g));
  PetscCall(BwH5FileGroup(of->h, name));
  PetscCall(PetscSNPrintf(name, sizeof(name), "%s/interfaces", g));
  PetscCall(BwH5FileGroup(of->h, name));
  PetscCall(BwOutputWriteResults(out, of->h, g, data, &own, model->geom, PETSC_FALSE));
  if (out->xdmf) {
    PetscCall(BwOutputXdmfLayout(of, data));
    PetscCall(PetscSNPrintf(name, sizeof(name), "/xdmf/steps/%06" PetscInt_FMT, step));
    PetscCall(BwOutputWriteXdmf(of->h, name, model->geom, &own, &of->xlayout, res, BwOutputHasPortions(out, model->geom, data), PETSC_TRUE));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwOutputWriteStep(BwOutputFile of, PetscInt step, const BwOutputData *data)
{
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  ierr = BwOutputWriteStepData(of, step, data);
  if (ierr) SETERRQ(of->out->comm, PETSC_ERR_FILE_WRITE, "output.file: writing step %" PetscInt_FMT " of '%s' failed (%s)", step, of->file, BwErrorText(ierr));
  if (of->nsteps == of->maxsteps) {
    of->maxsteps = PetscMax(16, 2 * of->maxsteps);
    PetscCall(PetscRealloc(of->maxsteps * sizeof(PetscInt), &of->steps));
  }
  of->steps[of->nsteps++] = step;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwOutputClose(BwOutputFile *ofp, const BwOutputData *data, const BwOutputHistory *history, BwLog *log)
{
  BwOutputFile     of = *ofp;
  BwOutput         out = of->out;
  BwModel          model;
  BwMixedOwnership own;
  char             msg[3 * PETSC_MAX_PATH_LEN] = "";
  int              ok = 1;
  PetscErrorCode   ierr, cerr;

  PetscFunctionBeginUser;
  PetscCall(BwMixedGetModel(of->mixed, &model));
  PetscCall(BwMixedGetOwnership(of->mixed, &own));
  /* every rank takes the same path through the file, failed or not */
  if (out->xdmf) PetscCall(BwOutputXdmfLayout(of, data));
  ierr = BwOutputWriteFile(out, of->h, &of->xlayout, data, history, of->nsteps > 0 ? PETSC_TRUE : PETSC_FALSE, log);
  cerr = BwH5FileClose(&of->h);
  if (ierr || cerr) {
    const char *text = BwErrorText(cerr ? cerr : ierr);
    char        file[PETSC_MAX_PATH_LEN];
    PetscCall(PetscStrncpy(file, of->file, sizeof(file)));
    BwOutputFileUnlink(of);
    PetscCall(BwOutputFileFree(ofp));
    SETERRQ(out->comm, PETSC_ERR_FILE_WRITE, "output.file: writing '%s' failed (%s); nothing was written", file, text[0] ? text : "HDF5 error");
  }
  /* rank 0 publishes: the .xdmf, then both files renamed with signals
   * blocked, so that a reader finds the old pair or the new one */
  if (of->rank == 0) {
    const char *from[2] = {of->xtmp, of->tmp}, *to[2] = {of->xdmf, of->file};
    int         n = out->xdmf ? 2 : 1, failed;
    errno = 0;
    if (out->xdmf && BwXdmfWrite(of->file, of->xtmp, &of->xlayout.sizes, of->nsteps, of->steps, data->state ? model->m : 0, out->stresses)) {
      ok = 0;
      snprintf(msg, sizeof(msg), "output.xdmf: cannot write '%s'%s%s; nothing was written", of->xdmf, errno ? ": " : "", errno ? strerror(errno) : "");
    } else if (BwRenameAll(n, out->xdmf ? from : from + 1, out->xdmf ? to : to + 1, &failed)) {
      ok = 0;
      snprintf(msg, sizeof(msg), "output.file: cannot rename '%s' to '%s': %s; nothing was written", (out->xdmf ? from : from + 1)[failed], (out->xdmf ? to : to + 1)[failed], strerror(errno));
      if (out->xdmf && failed == 1) unlink(of->xdmf); /* it describes a file that was not published */
    }
    if (!ok) BwOutputFileUnlink(of);
    BwTemporaryRemove(of->tmp);
    BwTemporaryRemove(of->xtmp);
  }
  PetscCall(BwOutputFileFree(ofp));
  PetscCallMPI(MPI_Bcast(&ok, 1, MPI_INT, 0, out->comm));
  if (!ok) PetscCallMPI(MPI_Bcast(msg, sizeof(msg), MPI_CHAR, 0, out->comm));
  PetscCheck(ok, out->comm, PETSC_ERR_FILE_WRITE, "%s", msg);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwOutputWrite(BwOutput out, const char file[], const BwOutputData *data, BwLog *log)
{
  BwOutputFile of;

  PetscFunctionBeginUser;
  PetscCall(BwOutputOpen(out, file, data->mixed, data->scene, 0, &of));
  PetscCall(BwOutputClose(&of, data, NULL, log));
  PetscFunctionReturn(PETSC_SUCCESS);
}
