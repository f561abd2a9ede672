/* BwH5File (see h5file.h): each step is local calls, then an agreement,
 * then collective calls, each followed by an agreement, so that no rank
 * enters a collective HDF5 call that another rank has given up. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <string.h>
#include <unistd.h>
#include "output/h5file.h"
#include "util/compat.h"
#include "util/signals.h"

/* How long a step that needs every rank may take before the rank gives up
 * (BwDeadlineArm): a base, and the time to move a dataset at 20 MB/s. */
#define BW_H5_STEP_SECONDS 60.0
#define BW_H5_STEP_RATE    2e7

struct _n_BwH5File {
  MPI_Comm comm;
  hid_t    file, dxpl;
  PetscBool serial; /* one rank: the POSIX driver */
  char     path[PETSC_MAX_PATH_LEN];
  char     display[PETSC_MAX_PATH_LEN]; /* the file as the user named it, for messages */
  int      failed; /* agreed by every rank */
  int      errnum; /* the system's reason, if any rank saw one */
  char     what[128];
  int      seen;          /* this rank saw a step fail (before any agreement) */
  char     seen_what[160]; /* ... which, and why */
  double   budget;        /* seconds the current collective step may take */
};

/* Every wait for the other ranks has a deadline: armed before each
 * collective call (BwH5Step, with the bytes it moves) and before the
 * agreement that follows it, disarmed when the agreement returns. Should
 * the wait never end (another rank left a collective call on an error),
 * the process ends with the error this rank knows of. */
static void BwH5Arm(BwH5File f)
{
  char msg[PETSC_MAX_PATH_LEN + 512];

  if (f->seen) snprintf(msg, sizeof(msg), "output.file: writing '%s' failed (%s); nothing was written", f->display, f->seen_what);
  else snprintf(msg, sizeof(msg), "output.file: writing '%s' failed (a collective HDF5 call made no progress for %.0f s); nothing was written", f->display, f->budget);
  BwDeadlineArm(f->budget, msg);
}

static void BwH5Step(BwH5File f, double bytes)
{
  f->budget = BW_H5_STEP_SECONDS + bytes / BW_H5_STEP_RATE;
  BwH5Arm(f);
}

/* The outcome of the last step on every rank: one failure fails all. */
static PetscErrorCode BwH5Agree(BwH5File f, int bad, int errnum, const char what[])
{
  int loc[2] = {bad ? 1 : 0, bad ? errnum : 0}, glob[2];

  PetscFunctionBeginUser;
  if (bad && !f->seen) {
    /* should the agreement never come, this is what the line says */
    f->seen = 1;
    snprintf(f->seen_what, sizeof(f->seen_what), "%s%s%s", what, errnum ? ": " : "", errnum ? strerror(errnum) : "");
  }
  BwH5Arm(f);
  PetscCallMPI(MPI_Allreduce(loc, glob, 2, MPI_INT, MPI_MAX, f->comm));
  BwDeadlineDisarm();
  if (glob[0] && !f->failed) {
    f->failed = 1;
    f->errnum = glob[1];
    PetscCall(PetscStrncpy(f->what, what, sizeof(f->what)));
  }
  /* quietly: BwH5FileClose raises the one message */
  if (f->failed) PetscFunctionReturn(PETSC_ERR_FILE_WRITE);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* call, if nothing failed yet, with its errno kept */
#define BwH5Try(f, var, call) \
  do { \
    errno = 0; \
    (var) = (call); \
    if ((var) < 0) err = errno ? errno : err; \
  } while (0)

PetscErrorCode BwH5FileCreate(MPI_Comm comm, const char path[], const char display[], BwH5File *fp)
{
  BwH5File f;
  hid_t    fapl;
  herr_t   rc  = 0;
  int      err = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&f));
  *fp     = f;
  f->comm = comm;
  f->file = f->dxpl = -1;
  PetscCall(PetscStrncpy(f->path, path, sizeof(f->path)));
  PetscCall(PetscStrncpy(f->display, display, sizeof(f->display)));
  f->budget = BW_H5_STEP_SECONDS;
  BwH5Try(f, fapl, H5Pcreate(H5P_FILE_ACCESS));
  if (fapl >= 0) {
    PetscMPIInt size;
    PetscCallMPI(MPI_Comm_size(comm, &size));
    /* one rank: the POSIX driver (MPI-IO's collective machinery costs 4x
     * for nothing: 0.35 s against 0.09 s for the stresses of 1e5 blocks) */
    f->serial = size == 1 ? PETSC_TRUE : PETSC_FALSE;
    if (f->serial) BwH5Try(f, rc, H5Pset_fapl_sec2(fapl));
    else BwH5Try(f, rc, H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL));
    /* The 1.8 file format: attributes larger than 64 KB (the scene text of
     * a scene with thousands of keys) go to dense storage instead of failing. */
    if (rc >= 0) BwH5Try(f, rc, H5Pset_libver_bounds(fapl, H5F_LIBVER_V18, H5F_LIBVER_LATEST));
    /* closing the file closes what a failed step left open */
    if (rc >= 0) BwH5Try(f, rc, H5Pset_fclose_degree(fapl, H5F_CLOSE_STRONG));
  }
  PetscCall(BwH5Agree(f, fapl < 0 || rc < 0, err, "setting up the file access"));
  BwH5Step(f, 0);
  BwH5Try(f, f->file, H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, fapl));
  H5Pclose(fapl);
  PetscCall(BwH5Agree(f, f->file < 0, err, "creating it"));
  BwH5Try(f, f->dxpl, H5Pcreate(H5P_DATASET_XFER));
  /* Independent transfers: each rank writes its own rows with its own
   * MPI-IO calls, and the agreement after the write tells every rank how
   * it went. A collective transfer (even with H5FD_MPIO_INDIVIDUAL_IO)
   * sets and resets MPI-IO's file view around the write, and ROMIO's
   * MPI_File_set_view is collective: a rank whose write failed (a full
   * disk) left H5Dwrite before the reset while the other waited in it,
   * and the two waited in different collectives for ever
   * (errors.io.diskfull_2: 4 hangs in 150 runs with the CPUs busy, the
   * backtraces in MPI_File_set_view and in this file's agreement). */
  if (f->dxpl >= 0 && !f->serial) BwH5Try(f, rc, H5Pset_dxpl_mpio(f->dxpl, H5FD_MPIO_INDEPENDENT));
  PetscCall(BwH5Agree(f, f->dxpl < 0 || rc < 0, err, "setting up the transfers"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwH5FileGroup(BwH5File f, const char name[])
{
  hid_t g;
  int   err = 0;

  PetscFunctionBeginUser;
  PetscCheck(!f->failed, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "an earlier step failed");
  BwH5Step(f, 0);
  BwH5Try(f, g, H5Gcreate2(f->file, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  PetscCall(BwH5Agree(f, g < 0, err, name));
  BwH5Step(f, 0);
  BwH5Try(f, g, H5Gclose(g));
  PetscCall(BwH5Agree(f, g < 0, err, name));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The rows this rank writes, as a union of hyperslabs of runs of
 * consecutive rows; *count is the number of values. */
static herr_t BwH5Select(hid_t fspace, int rank, const hsize_t dims[], PetscInt nrows, const PetscInt rows[], hsize_t *count)
{
  hsize_t width = 1;
  herr_t  rc    = H5Sselect_none(fspace);

  for (int d = 1; d < rank; d++) width *= dims[d];
  *count = 0;
  for (PetscInt r = 0; r < nrows && rc >= 0;) {
    PetscInt run = 1;
    hsize_t  start[3] = {0, 0, 0}, cnt[3];
    while (r + run < nrows && rows[r + run] == rows[r] + run) run++;
    start[0] = (hsize_t)rows[r];
    cnt[0]   = (hsize_t)run;
    for (int d = 1; d < rank; d++) cnt[d] = dims[d];
    rc = H5Sselect_hyperslab(fspace, H5S_SELECT_OR, start, NULL, cnt, NULL);
    *count += (hsize_t)run * width;
    r += run;
  }
  return rc;
}

static PetscErrorCode BwH5FileWriteRows(BwH5File f, const char name[], hid_t type, int rank, const hsize_t dims[], PetscBool all, PetscInt nrows, const PetscInt rows[], const void *data)
{
  hid_t   fspace = -1, mspace = -1, dset = -1;
  herr_t  rc     = 0;
  hsize_t count  = 0;
  int     err    = 0;

  PetscFunctionBeginUser;
  PetscCheck(!f->failed, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "an earlier step failed");
  /* local: the dataspaces and this rank's selection */
  BwH5Try(f, fspace, H5Screate_simple(rank, dims, NULL));
  if (fspace >= 0 && all) {
    count = 1;
    for (int d = 0; d < rank; d++) count *= dims[d];
    if (count) BwH5Try(f, rc, H5Sselect_all(fspace));
    else BwH5Try(f, rc, H5Sselect_none(fspace));
  } else if (fspace >= 0) BwH5Try(f, rc, BwH5Select(fspace, rank, dims, nrows, rows, &count));
  if (fspace >= 0 && rc >= 0) BwH5Try(f, mspace, H5Screate_simple(1, &count, NULL));
  if (mspace >= 0 && !count) BwH5Try(f, rc, H5Sselect_none(mspace));
  if (BwH5Agree(f, fspace < 0 || mspace < 0 || rc < 0, err, name)) goto done;
  /* collective */
  BwH5Step(f, 0);
  BwH5Try(f, dset, H5Dcreate2(f->file, name, type, fspace, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  if (BwH5Agree(f, dset < 0, err, name)) goto done;
  {
    double bytes = (double)H5Tget_size(type);
    for (int d = 0; d < rank; d++) bytes *= (double)dims[d];
    BwH5Step(f, bytes);
  }
  BwH5Try(f, rc, H5Dwrite(dset, type, mspace, fspace, f->dxpl, data));
  if (BwH5Agree(f, rc < 0, err, name)) goto done;
  BwH5Step(f, 0);
  BwH5Try(f, rc, H5Dclose(dset));
  dset = -1;
  (void)BwH5Agree(f, rc < 0, err, name);
done:
  if (mspace >= 0) H5Sclose(mspace);
  if (fspace >= 0) H5Sclose(fspace);
  /* a dataset left open by a failed step is closed with the file */
  PetscCheck(!f->failed, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "writing %s failed", name);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwH5FileWrite(BwH5File f, const char name[], hid_t type, int rank, const hsize_t dims[], PetscInt nrows, const PetscInt rows[], const void *data)
{
  PetscFunctionBeginUser;
  PetscCall(BwH5FileWriteRows(f, name, type, rank, dims, PETSC_FALSE, nrows, rows, data));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwH5FileWriteAll(BwH5File f, const char name[], hid_t type, int rank, const hsize_t dims[], const void *data)
{
  PetscMPIInt r;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(f->comm, &r));
  PetscCall(BwH5FileWriteRows(f, name, type, rank, dims, r == 0 ? PETSC_TRUE : PETSC_FALSE, 0, NULL, data));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A scalar attribute of type `mtype` (stored as `ftype`). */
static PetscErrorCode BwH5FileAttr(BwH5File f, const char obj[], const char name[], hid_t ftype, hid_t mtype, const void *v)
{
  hid_t  sp = -1, o = -1, a = -1;
  herr_t rc  = 0;
  int    err = 0;

  PetscFunctionBeginUser;
  PetscCheck(!f->failed, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "an earlier step failed");
  BwH5Try(f, sp, H5Screate(H5S_SCALAR));
  if (BwH5Agree(f, sp < 0, err, name)) goto done;
  BwH5Step(f, 0);
  BwH5Try(f, o, H5Oopen(f->file, obj, H5P_DEFAULT));
  if (BwH5Agree(f, o < 0, err, name)) goto done;
  BwH5Step(f, 0);
  BwH5Try(f, a, H5Acreate2(o, name, ftype, sp, H5P_DEFAULT, H5P_DEFAULT));
  if (BwH5Agree(f, a < 0, err, name)) goto done;
  BwH5Step(f, 0);
  BwH5Try(f, rc, H5Awrite(a, mtype, v));
  if (BwH5Agree(f, rc < 0, err, name)) goto done;
  BwH5Step(f, 0);
  BwH5Try(f, rc, H5Aclose(a));
  a = -1;
  if (BwH5Agree(f, rc < 0, err, name)) goto done;
  BwH5Step(f, 0);
  BwH5Try(f, rc, H5Oclose(o));
  o = -1;
  (void)BwH5Agree(f, rc < 0, err, name);
done:
  if (sp >= 0) H5Sclose(sp);
  PetscCheck(!f->failed, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "writing attribute %s failed", name);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwH5FileAttrDouble(BwH5File f, const char obj[], const char name[], double v)
{
  PetscFunctionBeginUser;
  PetscCall(BwH5FileAttr(f, obj, name, H5T_NATIVE_DOUBLE, H5T_NATIVE_DOUBLE, &v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwH5FileAttrInt(BwH5File f, const char obj[], const char name[], long long v)
{
  PetscFunctionBeginUser;
  PetscCall(BwH5FileAttr(f, obj, name, H5T_NATIVE_LLONG, H5T_NATIVE_LLONG, &v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwH5FileAttrString(BwH5File f, const char obj[], const char name[], const char v[])
{
  hid_t          t;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  t = H5Tcopy(H5T_C_S1);
  if (t >= 0) {
    H5Tset_size(t, strlen(v) + 1);
    H5Tset_cset(t, H5T_CSET_UTF8);
  }
  PetscCheck(!BwH5Agree(f, t < 0, 0, name), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "string type");
  ierr = BwH5FileAttr(f, obj, name, t, t, v);
  H5Tclose(t);
  PetscCall(ierr);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwH5FileClose(BwH5File *fp)
{
  BwH5File f = *fp;
  herr_t   rc  = 0;
  int      err = 0;
  char     msg[PETSC_MAX_PATH_LEN + 256];

  PetscFunctionBeginUser;
  if (!f) PetscFunctionReturn(PETSC_SUCCESS);
  if (f->dxpl >= 0) H5Pclose(f->dxpl);
  /* A failed file is garbage, and on a full disk its blocks are what the
   * close needs to write HDF5's metadata: without them the close fails, the
   * file stays open and HDF5 closes it again inside MPI_Finalize, which
   * crashed. */
  if (f->failed) {
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(f->comm, &rank));
    if (!rank && truncate(f->path, 0)) { /* nothing more can be freed */
    }
    BwH5Step(f, 0);
    PetscCallMPI(MPI_Barrier(f->comm));
    BwDeadlineDisarm();
  }
  /* every rank is here, after the same steps: the close is collective */
  BwH5Step(f, 0);
  if (f->file >= 0) BwH5Try(f, rc, H5Fclose(f->file));
  /* A close that failed (the metadata did not fit on a full disk, even
   * with the data truncated away) leaves the file open in HDF5, which
   * closes it again when MPI_Finalize ends the library, and crashes
   * there (HDF5 1.10: a segfault in H5F__close_cb). Such a run ends
   * without MPI_Finalize (main.c). */
  if (rc < 0 && H5Iis_valid(f->file) > 0) BwSkipFinalize();
  f->file = -1;
  (void)BwH5Agree(f, rc < 0, err, "closing it");
  if (f->failed) PetscCall(PetscSNPrintf(msg, sizeof(msg), "%s%s%s", f->what, f->errnum ? ": " : "", f->errnum ? strerror(f->errnum) : ""));
  {
    int failed = f->failed;
    PetscCall(PetscFree(*fp));
    PetscCheck(!failed, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "%s", msg);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}
