/* BwH5File: an HDF5 file written collectively by every rank, where a
 * failure on one rank is a failure on all.
 *
 * Parallel HDF5 needs every rank in every collective call. When a write
 * fails on one rank only (a full disk is seen by the ranks that write the
 * failing blocks), a rank that raised an error at once would leave the
 * others waiting in the next collective call: a hang on 2 ranks; and a file
 * left open at exit is closed by HDF5 after MPI_Finalize: a crash on 1.
 * So every step is followed by an agreement (one MPI_Allreduce of a flag
 * and an errno): after a failure anywhere, every rank skips the remaining
 * steps, returns the same error, and the file is closed collectively.
 * Data are written with independent MPI-IO calls (no collective call in
 * H5Dwrite); HDF5's own collective calls (create, close, metadata) have a
 * deadline. */
#pragma once
#include <hdf5.h>
#include <petscsys.h>

typedef struct _n_BwH5File *BwH5File;

/* Creates (truncates) path, collectively; display names the file in
 * messages (the target of a temporary file). Every collective step has a
 * deadline (BwDeadlineArm) until the file is closed: a rank that waits in a
 * collective call that another rank has left ends the run with the error
 * instead of waiting for ever. */
PetscErrorCode BwH5FileCreate(MPI_Comm comm, const char path[], const char display[], BwH5File *f);
PetscErrorCode BwH5FileGroup(BwH5File f, const char name[]);
/* Dataset `name` of shape dims[0..rank) and type `type`; this rank writes
 * its rows rows[0..nrows) (ascending, each dims[1]*dims[2] values) from
 * `data`, all ranks at once. */
PetscErrorCode BwH5FileWrite(BwH5File f, const char name[], hid_t type, int rank, const hsize_t dims[], PetscInt nrows, const PetscInt rows[], const void *data);
/* The same for replicated data: rank 0 writes every row. */
PetscErrorCode BwH5FileWriteAll(BwH5File f, const char name[], hid_t type, int rank, const hsize_t dims[], const void *data);
/* Scalar attributes of the group or dataset `obj` ("/" for the root). */
PetscErrorCode BwH5FileAttrDouble(BwH5File f, const char obj[], const char name[], double v);
PetscErrorCode BwH5FileAttrInt(BwH5File f, const char obj[], const char name[], long long v);
PetscErrorCode BwH5FileAttrString(BwH5File f, const char obj[], const char name[], const char v[]);
/* Closes the file collectively, whatever happened before; the error of the
 * first failed step (or of the close), the same on every rank, names the
 * step and the system's reason ("/interfaces/stress: No space left on
 * device"). *f is NULL. */
PetscErrorCode BwH5FileClose(BwH5File *f);
