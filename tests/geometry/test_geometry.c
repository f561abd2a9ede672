/* Geometry only: the scene's generator (file, running_bond, ...) without
 * assembly or solve, so that detection can be checked and timed on 1e5-1e6
 * blocks, where a solve would dominate.
 *
 *   test_geometry -scene SCENE.yaml [-dump OUT.h5] [-distribute] [scene options]
 *
 * prints "blocks B interfaces I seconds T cpu C" (T: wall time of
 * BwGeometrySetFromOptions, i.e. read, check, detect, broadcast; C: the CPU
 * time rank 0 spent in it, which a loaded machine does not inflate) and,
 * with -dump, writes from rank 0
 *   /blocks/vertices, /blocks/offsets, /blocks/centroid, /blocks/area
 *   /interfaces/blocks, center, angle, length, kind
 * (rank 0's D0 share: the whole geometry on one rank). -distribute: then
 * BwGeometryDistribute, each rank its local piece (the memory a rank
 * needs for the geometry, measured from outside by the tests).
 * Errors: one line on stderr, exit 1 (user input) or 2, as blockwall. */
#include <stdint.h>
#include <stdio.h>
#include <sys/resource.h>
#include <hdf5.h>
#include "geometry/geometry.h"
#include "model/model.h"
#include "util/compat.h"
#include "util/process.h"

static PetscErrorCode BwDumpWrite(hid_t file, const char name[], hid_t type, int rank, hsize_t n0, hsize_t n1, const void *data)
{
  hsize_t dims[2] = {n0, n1};
  hid_t   space, dset;

  PetscFunctionBeginUser;
  space = H5Screate_simple(rank, dims, NULL);
  dset  = H5Dcreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  PetscCheck(dset >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot create %s", name);
  if (n0 && H5Dwrite(dset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s", name);
  H5Dclose(dset);
  H5Sclose(space);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwDump(BwGeometry g, const char path[])
{
  hid_t    file, grp;
  PetscInt nb = g->nblocks, ni = g->ninterfaces, nv = g->offsets[nb];
  int64_t *i64;

  PetscFunctionBeginUser;
  file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  PetscCheck(file >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot create %s", path);
  grp = H5Gcreate2(file, "/blocks", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Gclose(grp);
  grp = H5Gcreate2(file, "/interfaces", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Gclose(grp);
  PetscCall(PetscMalloc1(PetscMax(nb + 1, 2 * ni) + 1, &i64));
  PetscCall(BwDumpWrite(file, "/blocks/vertices", H5T_NATIVE_DOUBLE, 2, (hsize_t)nv, 2, g->vertices));
  for (PetscInt b = 0; b <= nb; b++) i64[b] = g->offsets[b];
  PetscCall(BwDumpWrite(file, "/blocks/offsets", H5T_NATIVE_INT64, 1, (hsize_t)nb + 1, 0, i64));
  PetscCall(BwDumpWrite(file, "/blocks/centroid", H5T_NATIVE_DOUBLE, 2, (hsize_t)nb, 2, g->centroid));
  PetscCall(BwDumpWrite(file, "/blocks/area", H5T_NATIVE_DOUBLE, 1, (hsize_t)nb, 0, g->area));
  for (PetscInt k = 0; k < 2 * ni; k++) i64[k] = g->pair[k];
  PetscCall(BwDumpWrite(file, "/interfaces/blocks", H5T_NATIVE_INT64, 2, (hsize_t)ni, 2, i64));
  PetscCall(BwDumpWrite(file, "/interfaces/center", H5T_NATIVE_DOUBLE, 2, (hsize_t)ni, 2, g->center));
  PetscCall(BwDumpWrite(file, "/interfaces/angle", H5T_NATIVE_DOUBLE, 1, (hsize_t)ni, 0, g->angle));
  PetscCall(BwDumpWrite(file, "/interfaces/length", H5T_NATIVE_DOUBLE, 1, (hsize_t)ni, 0, g->length));
  for (PetscInt k = 0; k < ni; k++) i64[k] = g->kind[k];
  PetscCall(BwDumpWrite(file, "/interfaces/kind", H5T_NATIVE_INT64, 1, (hsize_t)ni, 0, i64));
  PetscCall(PetscFree(i64));
  H5Fclose(file);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* CPU seconds of this process (user + system). */
static double BwCPUTime(void)
{
  struct rusage u;
  getrusage(RUSAGE_SELF, &u);
  return (double)u.ru_utime.tv_sec + 1e-6 * (double)u.ru_utime.tv_usec + (double)u.ru_stime.tv_sec + 1e-6 * (double)u.ru_stime.tv_usec;
}

static PetscErrorCode BwTestMain(MPI_Comm comm, BwScene *scene, BwGeometry *geom)
{
  char           path[PETSC_MAX_PATH_LEN] = "", dump[PETSC_MAX_PATH_LEN] = "";
  PetscBool      has_dump, distribute = PETSC_FALSE;
  BwJointLaw     bed = NULL;
  PetscLogDouble t0, t1;
  double         c0, c1;
  PetscMPIInt    rank;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", path, sizeof(path), NULL));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-dump", dump, sizeof(dump), &has_dump));
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-distribute", &distribute, NULL));
  PetscCall(BwSceneCreate(comm, scene));
  PetscCall(BwSceneLoad(*scene, path));
  PetscCall(BwJointLawCreate(&bed));
  PetscCall(BwJointLawSetFromOptions(bed, *scene, "joints_", NULL));
  PetscCall(BwGeometryCreate(comm, geom));
  PetscCall(BwGeometrySetFromOptions(*geom, *scene));
  PetscCall(PetscTime(&t0));
  c0 = BwCPUTime();
  PetscCall(BwGeometrySetUp(*geom, *scene, bed->thickness));
  PetscCall(BwJointLawDestroy(&bed));
  if (distribute) PetscCall(BwGeometryDistribute(*geom, (BwPartitionMethod)(*geom)->partition));
  c1 = BwCPUTime();
  PetscCall(PetscTime(&t1));
  PetscCall(PetscPrintf(comm, "blocks %" PetscInt_FMT " interfaces %" PetscInt_FMT " seconds %.6f cpu %.6f\n", (*geom)->nblocks, (*geom)->ninterfaces, t1 - t0, c1 - c0));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (has_dump && !rank) PetscCall(BwDump(*geom, dump));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  PetscErrorCode ierr;
  BwScene        scene = NULL;
  BwGeometry     geom  = NULL;
  PetscMPIInt    rank;
  int            code = 0;

  BwProcessDefaults(); /* the libraries run as under blockwall */

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  ierr = BwTestMain(PETSC_COMM_WORLD, &scene, &geom);
  if (ierr) {
    const char *specific = BwErrorText(ierr);
    if (!rank) fprintf(stderr, "test_geometry: error: %s\n", specific[0] ? specific : "unknown");
    code = ierr == PETSC_ERR_USER_INPUT ? 1 : 2;
  }
  if (BwGeometryDestroy(&geom) || BwSceneDestroy(&scene)) code = code ? code : 3;
  PetscPopErrorHandler();
  if (PetscFinalize()) code = code ? code : 3;
  return code;
}
