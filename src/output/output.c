/* HDF5 output, collective MPI-IO. Each dataset is created by all ranks; a
 * rank selects the rows it writes (a union of runs of consecutive input
 * indices) or nothing, and the transfer is collective. */
#include <errno.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <hdf5.h>
#include "output/output.h"
#include "output/xdmf.h"
#include "util/compat.h"

#define BwH5Call(call) \
  do { \
    if ((call) < 0) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "HDF5 call failed: %s", #call); \
  } while (0)

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
  PetscOptionsBegin(out->comm, NULL, "Output (scene key output.*)", NULL);
  PetscCall(PetscOptionsString("-output_file", "HDF5 result file (written to a temporary name, then renamed)", NULL, out->file, out->file, sizeof(out->file), NULL));
  PetscCall(PetscOptionsBool("-output_stresses", "Write the per-portion stresses /interfaces/stress (resultants are always written)", NULL, out->stresses, &out->stresses, NULL));
  PetscCall(PetscOptionsBool("-output_xdmf", "Write an XDMF file beside the HDF5 file for ParaView", NULL, out->xdmf, &out->xdmf, NULL));
  PetscOptionsEnd();
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

typedef struct {
  hid_t file, dxpl;
} BwH5;

static PetscErrorCode BwH5Group(BwH5 *h, const char name[])
{
  hid_t g;

  PetscFunctionBeginUser;
  g = H5Gcreate2(h->file, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  BwH5Call(g);
  BwH5Call(H5Gclose(g));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Dataset `name` of shape (n, w1[, w2]) and type `mem`; this rank writes the
 * rows rows[0..nrows) (sorted, each `width` values) from `data`. */
static PetscErrorCode BwH5Write(BwH5 *h, const char name[], hid_t type, int rank, const hsize_t dims[], PetscInt nrows, const PetscInt rows[], const void *data)
{
  hid_t   fspace, mspace, dset;
  hsize_t width = 1, count = 0;

  PetscFunctionBeginUser;
  for (int d = 1; d < rank; d++) width *= dims[d];
  fspace = H5Screate_simple(rank, dims, NULL);
  BwH5Call(fspace);
  dset = H5Dcreate2(h->file, name, type, fspace, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  BwH5Call(dset);
  BwH5Call(H5Sselect_none(fspace));
  for (PetscInt r = 0; r < nrows;) {
    PetscInt run = 1;
    hsize_t  start[3] = {0, 0, 0}, cnt[3];
    while (r + run < nrows && rows[r + run] == rows[r] + run) run++;
    start[0] = (hsize_t)rows[r];
    cnt[0]   = (hsize_t)run;
    for (int d = 1; d < rank; d++) cnt[d] = dims[d];
    BwH5Call(H5Sselect_hyperslab(fspace, H5S_SELECT_OR, start, NULL, cnt, NULL));
    count += (hsize_t)run * width;
    r += run;
  }
  mspace = H5Screate_simple(1, &count, NULL);
  BwH5Call(mspace);
  if (!count) BwH5Call(H5Sselect_none(mspace));
  BwH5Call(H5Dwrite(dset, type, mspace, fspace, h->dxpl, data));
  BwH5Call(H5Sclose(mspace));
  BwH5Call(H5Sclose(fspace));
  BwH5Call(H5Dclose(dset));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Replicated data: rank 0 writes all n rows. */
static PetscErrorCode BwH5WriteAll(BwH5 *h, const char name[], hid_t type, int rank, const hsize_t dims[], const void *data)
{
  PetscMPIInt r;
  PetscInt    first = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(MPI_COMM_WORLD, &r));
  if (r == 0 && dims[0] > 0) {
    /* one run covering all rows */
    hid_t   fspace, dset;
    fspace = H5Screate_simple(rank, dims, NULL);
    BwH5Call(fspace);
    dset = H5Dcreate2(h->file, name, type, fspace, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    BwH5Call(dset);
    BwH5Call(H5Dwrite(dset, type, H5S_ALL, H5S_ALL, h->dxpl, data));
    BwH5Call(H5Sclose(fspace));
    BwH5Call(H5Dclose(dset));
  } else PetscCall(BwH5Write(h, name, type, rank, dims, 0, &first, data));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwH5AttrDouble(hid_t obj, const char name[], double v)
{
  hid_t sp, a;

  PetscFunctionBeginUser;
  sp = H5Screate(H5S_SCALAR);
  a  = H5Acreate2(obj, name, H5T_NATIVE_DOUBLE, sp, H5P_DEFAULT, H5P_DEFAULT);
  BwH5Call(a);
  BwH5Call(H5Awrite(a, H5T_NATIVE_DOUBLE, &v));
  BwH5Call(H5Aclose(a));
  BwH5Call(H5Sclose(sp));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwH5AttrInt(hid_t obj, const char name[], long long v)
{
  hid_t sp, a;

  PetscFunctionBeginUser;
  sp = H5Screate(H5S_SCALAR);
  a  = H5Acreate2(obj, name, H5T_NATIVE_LLONG, sp, H5P_DEFAULT, H5P_DEFAULT);
  BwH5Call(a);
  BwH5Call(H5Awrite(a, H5T_NATIVE_LLONG, &v));
  BwH5Call(H5Aclose(a));
  BwH5Call(H5Sclose(sp));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwH5AttrString(hid_t obj, const char name[], const char v[])
{
  hid_t sp, t, a;

  PetscFunctionBeginUser;
  sp = H5Screate(H5S_SCALAR);
  t  = H5Tcopy(H5T_C_S1);
  BwH5Call(H5Tset_size(t, strlen(v) + 1));
  BwH5Call(H5Tset_cset(t, H5T_CSET_UTF8));
  a = H5Acreate2(obj, name, t, sp, H5P_DEFAULT, H5P_DEFAULT);
  BwH5Call(a);
  BwH5Call(H5Awrite(a, t, v));
  BwH5Call(H5Aclose(a));
  BwH5Call(H5Tclose(t));
  BwH5Call(H5Sclose(sp));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwOutputWriteFile(BwOutput out, const char tmp[], BwMixed mx, const BwResults *res, BwSolver s, const char scene_text[], BwLog *log)
{
  BwGeometry     geom = mx->geom;
  BwModel        model = mx->model;
  PetscInt       nb = geom->nblocks, ni = geom->ninterfaces, m = mx->m;
  hid_t          fapl, root, grp;
  BwH5           h;
  hsize_t        dims[3];
  int64_t       *i64;
  signed char   *i8;
  PetscMPIInt    size;
  PetscLogDouble t1;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(out->comm, &size));
  fapl = H5Pcreate(H5P_FILE_ACCESS);
  BwH5Call(H5Pset_fapl_mpio(fapl, out->comm, MPI_INFO_NULL));
  h.file = H5Fcreate(tmp, H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  BwH5Call(H5Pclose(fapl));
  PetscCheck(h.file >= 0, out->comm, PETSC_ERR_FILE_OPEN, "output.file: cannot create '%s'", tmp);
  h.dxpl = H5Pcreate(H5P_DATASET_XFER);
  BwH5Call(H5Pset_dxpl_mpio(h.dxpl, H5FD_MPIO_COLLECTIVE));

  PetscCall(BwH5Group(&h, "/blocks"));
  PetscCall(BwH5Group(&h, "/interfaces"));
  PetscCall(BwH5Group(&h, "/sets"));
  PetscCall(BwH5Group(&h, "/solver"));

  /* input schema, replicated */
  dims[0] = (hsize_t)geom->offsets[nb];
  dims[1] = 2;
  PetscCall(BwH5WriteAll(&h, "/blocks/vertices", H5T_NATIVE_DOUBLE, 2, dims, geom->vertices));
  PetscCall(PetscMalloc1(PetscMax(nb + 1, 2 * ni) + 1, &i64));
  for (PetscInt b = 0; b <= nb; b++) i64[b] = geom->offsets[b];
  dims[0] = (hsize_t)nb + 1;
  PetscCall(BwH5WriteAll(&h, "/blocks/offsets", H5T_NATIVE_INT64, 1, dims, i64));
  for (PetscInt e = 0; e < 2 * ni; e++) i64[e] = geom->pair[e];
  dims[0] = (hsize_t)ni;
  PetscCall(BwH5WriteAll(&h, "/interfaces/blocks", H5T_NATIVE_INT64, 2, dims, i64));
  PetscCall(PetscFree(i64));
  dims[0] = (hsize_t)nb;
  PetscCall(BwH5WriteAll(&h, "/blocks/centroid", H5T_NATIVE_DOUBLE, 2, dims, geom->centroid));
  dims[1] = 3;
  PetscCall(BwH5WriteAll(&h, "/blocks/load", H5T_NATIVE_DOUBLE, 2, dims, model->load));
  PetscCall(PetscMalloc1(3 * nb + 1, &i8));
  for (PetscInt e = 0; e < 3 * nb; e++) i8[e] = model->prescribed[e] ? 1 : 0;
  PetscCall(BwH5WriteAll(&h, "/blocks/prescribed", H5T_NATIVE_SCHAR, 2, dims, i8));
  PetscCall(PetscFree(i8));
  dims[0] = (hsize_t)ni;
  dims[1] = 2;
  PetscCall(BwH5WriteAll(&h, "/interfaces/center", H5T_NATIVE_DOUBLE, 2, dims, geom->center));
  PetscCall(BwH5WriteAll(&h, "/interfaces/angle", H5T_NATIVE_DOUBLE, 1, dims, geom->angle));
  PetscCall(BwH5WriteAll(&h, "/interfaces/length", H5T_NATIVE_DOUBLE, 1, dims, geom->length));
  PetscCall(BwH5WriteAll(&h, "/interfaces/kn", H5T_NATIVE_DOUBLE, 1, dims, model->kn));
  PetscCall(BwH5WriteAll(&h, "/interfaces/kt", H5T_NATIVE_DOUBLE, 1, dims, model->kt));
  for (PetscInt s = 0; s < geom->nsets; s++) {
    char     name[PETSC_MAX_PATH_LEN];
    PetscInt n = geom->setoffsets[s + 1] - geom->setoffsets[s];
    PetscCall(PetscMalloc1(n + 1, &i64));
    for (PetscInt e = 0; e < n; e++) i64[e] = geom->setblocks[geom->setoffsets[s] + e];
    PetscCall(PetscSNPrintf(name, sizeof(name), "/sets/%s", geom->setname[s]));
    dims[0] = (hsize_t)n;
    PetscCall(BwH5WriteAll(&h, name, H5T_NATIVE_INT64, 1, dims, i64));
    PetscCall(PetscFree(i64));
  }

  /* results, distributed at their input indices */
  dims[0] = (hsize_t)nb;
  dims[1] = 3;
  PetscCall(BwH5Write(&h, "/blocks/displacement", H5T_NATIVE_DOUBLE, 2, dims, mx->nown_blocks, mx->own_blocks, res->displacement));
  PetscCall(BwH5Write(&h, "/blocks/reaction", H5T_NATIVE_DOUBLE, 2, dims, mx->nown_blocks, mx->own_blocks, res->reaction));
  dims[0] = (hsize_t)ni;
  PetscCall(BwH5Write(&h, "/interfaces/relative_displacement", H5T_NATIVE_DOUBLE, 2, dims, mx->nown_interfaces, mx->own_interfaces, res->relative));
  PetscCall(BwH5Write(&h, "/interfaces/resultant", H5T_NATIVE_DOUBLE, 2, dims, mx->nown_interfaces, mx->own_interfaces, res->resultant));
  if (out->stresses) {
    dims[1] = (hsize_t)m;
    dims[2] = 2;
    PetscCall(BwH5Write(&h, "/interfaces/stress", H5T_NATIVE_DOUBLE, 3, dims, mx->nown_interfaces, mx->own_interfaces, res->stress));
  }
  if (out->xdmf) { /* what the .xdmf beside this file needs and the schema lacks (xdmf.h) */
    BwXdmfData x;
    PetscCall(BwXdmfDataCreate(geom, mx->nown_blocks, mx->own_blocks, res->displacement, &x));
    PetscCall(BwH5Group(&h, "/xdmf"));
    dims[0] = (hsize_t)x.ntopology;
    PetscCall(BwH5WriteAll(&h, "/xdmf/topology", H5T_NATIVE_INT64, 1, dims, x.topology));
    dims[0] = 2 * (hsize_t)ni;
    dims[1] = 2;
    PetscCall(BwH5WriteAll(&h, "/xdmf/interface_points", H5T_NATIVE_DOUBLE, 2, dims, x.interface_points));
    dims[0] = (hsize_t)ni;
    PetscCall(BwH5WriteAll(&h, "/xdmf/interface_topology", H5T_NATIVE_INT64, 2, dims, x.interface_topology));
    dims[0] = (hsize_t)geom->offsets[nb];
    dims[1] = 3;
    PetscCall(BwH5Write(&h, "/xdmf/vertex_displacement", H5T_NATIVE_DOUBLE, 2, dims, x.nvertex_rows, x.vertex_rows, x.vertex_displacement));
    PetscCall(BwXdmfDataDestroy(&x));
  }

  /* attributes */
  root = H5Gopen2(h.file, "/", H5P_DEFAULT);
  BwH5Call(root);
  PetscCall(BwH5AttrString(root, "version", BW_VERSION));
  PetscCall(BwH5AttrString(root, "scene", scene_text));
  PetscCall(BwH5AttrString(root, "units", "SI"));
  PetscCall(BwH5AttrInt(root, "m", m));
  PetscCall(BwH5AttrDouble(root, "depth", geom->depth));
  BwH5Call(H5Gclose(root));
  grp = H5Gopen2(h.file, "/solver", H5P_DEFAULT);
  BwH5Call(grp);
  PetscCall(BwH5AttrString(grp, "method_requested", BwMethods[s->requested]));
  PetscCall(BwH5AttrString(grp, "method_used", BwMethods[s->used]));
  PetscCall(BwH5AttrInt(grp, "fallback", s->fallback));
  PetscCall(BwH5AttrString(grp, "fallback_reason", s->fallback_reason));
  PetscCall(BwH5AttrInt(grp, "iterations", s->iterations));
  PetscCall(BwH5AttrInt(grp, "accuracy_met", s->accuracy_met));
  PetscCall(BwH5AttrString(grp, "warning", s->warning));
  PetscCall(BwH5AttrDouble(grp, "rtol", s->rtol));
  PetscCall(BwH5AttrDouble(grp, "residual", s->check.residual));
  PetscCall(BwH5AttrDouble(grp, "residual_equilibrium", s->check.equilibrium));
  PetscCall(BwH5AttrDouble(grp, "residual_compatibility", s->check.compatibility));
  PetscCall(BwH5AttrDouble(grp, "forward_rtol", s->forward_rtol));
  PetscCall(BwH5AttrDouble(grp, "forward_error_estimate", s->forward_estimate));
  PetscCall(BwH5AttrDouble(grp, "condition_estimate", s->condition_estimate));
  PetscCall(BwH5AttrDouble(grp, "equilibrium_error", s->check.equilibrium_error));
  PetscCall(BwH5AttrInt(grp, "ranks", size));
  PetscCall(BwH5AttrInt(grp, "unknowns_q", mx->nq_global));
  PetscCall(BwH5AttrInt(grp, "unknowns_r", mx->nr_global));
  {
    char blas[PETSC_MAX_PATH_LEN];
    PetscCall(BwBlasName(blas, sizeof(blas)));
    PetscCall(BwH5AttrString(grp, "blas", blas));
  }
  {
    PetscLogDouble cur, peak;
    PetscCall(BwMemoryUsage(out->comm, &cur, &peak));
    PetscCall(BwH5AttrDouble(grp, "memory_peak_bytes", peak));
  }
  PetscCall(PetscTime(&t1));
  for (int p = 0; p < BW_NPHASES; p++) {
    char name[64];
    PetscCall(PetscSNPrintf(name, sizeof(name), "seconds_%s", BwPhaseNames[p]));
    PetscCall(BwH5AttrDouble(grp, name, log->seconds[p] + (p == BW_PHASE_WRITE ? t1 - log->start : 0)));
  }
  PetscCall(BwH5AttrDouble(grp, "seconds_total", t1 - log->t0));
  BwH5Call(H5Gclose(grp));
  BwH5Call(H5Pclose(h.dxpl));
  BwH5Call(H5Fclose(h.file));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwMakeDirs(const char dir[])
{
  char path[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(path, dir, sizeof(path)));
  for (char *p = path + 1; *p; p++) {
    if (*p != '/') continue;
    *p = 0;
    PetscCheck(mkdir(path, 0777) == 0 || errno == EEXIST, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "output.file: cannot create directory '%s': %s", path, strerror(errno));
    *p = '/';
  }
  PetscCheck(mkdir(path, 0777) == 0 || errno == EEXIST, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "output.file: cannot create directory '%s': %s", path, strerror(errno));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwOutputWrite(BwOutput out, BwMixed mx, const BwResults *res, BwSolver s, const char scene_text[], BwLog *log)
{
  char           tmp[PETSC_MAX_PATH_LEN + 32], dir[PETSC_MAX_PATH_LEN], msg[3 * PETSC_MAX_PATH_LEN] = "";
  char           xdmf[PETSC_MAX_PATH_LEN + 8], xtmp[PETSC_MAX_PATH_LEN + 40];
  PetscMPIInt    rank;
  int            pid = (int)getpid(), ok = 1;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(out->comm, &rank));
  PetscCallMPI(MPI_Bcast(&pid, 1, MPI_INT, 0, out->comm));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp-%d", out->file, pid));
  if (rank == 0) {
    BwDirName(out->file, dir, sizeof(dir));
    if (BwMakeDirs(dir)) {
      ok = 0;
      snprintf(msg, sizeof(msg), "output.file: cannot create directory '%s'", dir);
    }
  }
  PetscCallMPI(MPI_Bcast(&ok, 1, MPI_INT, 0, out->comm));
  PetscCheck(ok, out->comm, PETSC_ERR_FILE_WRITE, "%s", msg);
  ierr = BwOutputWriteFile(out, tmp, mx, res, s, scene_text, log);
  if (ierr) {
    if (rank == 0) unlink(tmp);
    SETERRQ(out->comm, PETSC_ERR_FILE_WRITE, "output.file: writing '%s' failed; nothing was written", out->file);
  }
  PetscCallMPI(MPI_Barrier(out->comm));
  /* The .xdmf is written and renamed before the result file, so a failure
   * leaves neither file behind and an existing result file untouched. */
  if (out->xdmf) {
    PetscCall(BwXdmfPath(out->file, xdmf, sizeof(xdmf)));
    PetscCall(PetscSNPrintf(xtmp, sizeof(xtmp), "%s.tmp-%d", xdmf, pid));
    errno = 0;
    if (rank == 0 && (BwXdmfWrite(out->file, xtmp, mx->geom) || rename(xtmp, xdmf) != 0)) {
      ok = 0;
      snprintf(msg, sizeof(msg), "output.xdmf: cannot write '%s'%s%s; nothing was written", xdmf, errno ? ": " : "", errno ? strerror(errno) : "");
      unlink(xtmp);
      unlink(tmp);
    }
    PetscCallMPI(MPI_Bcast(&ok, 1, MPI_INT, 0, out->comm));
    PetscCheck(ok, out->comm, PETSC_ERR_FILE_WRITE, "%s", msg);
  }
  if (rank == 0 && rename(tmp, out->file) != 0) {
    ok = 0;
    snprintf(msg, sizeof(msg), "output.file: cannot rename '%s' to '%s': %s", tmp, out->file, strerror(errno));
    unlink(tmp);
    if (out->xdmf) unlink(xdmf);
  }
  PetscCallMPI(MPI_Bcast(&ok, 1, MPI_INT, 0, out->comm));
  PetscCheck(ok, out->comm, PETSC_ERR_FILE_WRITE, "%s", msg);
  PetscFunctionReturn(PETSC_SUCCESS);
}
