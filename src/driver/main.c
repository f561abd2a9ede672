#define _POSIX_C_SOURCE 200809L /* setenv */
static const char help[] = "blockwall: static equilibrium of rigid blocks joined by elastic interfaces,\n"
                           "mixed form (block displacements and piecewise-constant interface stresses).\n"
                           "Usage: mpiexec -n N blockwall -scene SCENE.yaml [scene options] [PETSc options]\n"
                           "Every scene key is an option: nested keys joined by '_' (-discretization_m 8).\n\n";

/* The driver, as numbered steps:
 *   1. scene file and command line, typed keys    (BwScene)
 *   2. every key that does not depend on the geometry (BwModel, BwGeometry,
 *      BwOutput, BwSolver), then options nobody reads are refused
 *   3. geometry, joint stiffness, supports and loads (BwGeometry, BwModel),
 *      then every unread key of blockwall's is refused, before any work
 *   4. partition (METIS, more than one rank), layout and assembly of the
 *      scaled mixed system (BwMixed)
 *   5. solve: fieldsplit Schur, MUMPS fallback   (BwSolver)
 *   6. recover results, self-check, refuse options nothing used
 *   7. write HDF5 (temporary name, then rename) and print the summary
 * Errors print one line on stderr and exit non-zero without output. */
#include <hdf5.h>
#include "scene/scene.h"
#include "model/model.h"
#include "system/mixed.h"
#include "solver/solver.h"
#include "output/output.h"
#include "util/log.h"
#include "util/compat.h"
#include "util/signals.h"

typedef struct {
  BwScene    scene;
  BwGeometry geom;
  BwModel    model;
  BwMixed    mixed;
  BwSolver   solver;
  BwOutput   output;
  BwResults  results;
  char      *text;
} BwRun;

static PetscErrorCode BwRunDestroy(BwRun *run)
{
  PetscFunctionBeginUser;
  if (run->results.displacement) PetscCall(BwResultsFree(&run->results));
  PetscCall(PetscFree(run->text));
  PetscCall(BwOutputDestroy(&run->output));
  PetscCall(BwSolverDestroy(&run->solver));
  PetscCall(BwMixedDestroy(&run->mixed));
  PetscCall(BwModelDestroy(&run->model));
  PetscCall(BwGeometryDestroy(&run->geom));
  PetscCall(BwSceneDestroy(&run->scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwRunMain(MPI_Comm comm, BwRun *run)
{
  char               path[PETSC_MAX_PATH_LEN] = "", title[256] = "";
  PetscBool          has_scene, help, progress_set;
  BwLog              log;
  PetscMPIInt       *owner = NULL;
  PetscInt           ndeferred;
  const char *const *deferred;

  PetscFunctionBeginUser;
  PetscCall(BwLogCreate(comm, &log));
  PetscCall(PetscOptionsHasHelp(NULL, &help));

  /* 1. scene */
  PetscCall(BwSceneCreate(comm, &run->scene));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", path, sizeof(path), &has_scene));
  PetscCheck(has_scene || help, comm, PETSC_ERR_USER_INPUT, "-scene SCENE.yaml is required (run with -help for the options)");
  PetscCall(BwSceneLoad(run->scene, has_scene ? path : NULL));
  if (help) PetscCall((*PetscHelpPrintf)(comm, "blockwall:\n  -scene <%s>: Scene file (YAML); every key is also an option\n", path));
  PetscCall(BwSceneString(run->scene, "-title", "Free text describing the scene", title, sizeof(title), NULL));
  PetscCall(BwSceneBool(run->scene, "-progress", "One line per phase with time and memory (default: for 10000 blocks or more)", &log.verbose, &progress_set));

  /* 2. every key that does not depend on the geometry: physics, generator,
   * output target, solver */
  PetscCall(BwModelCreate(comm, &run->model));
  PetscCall(BwModelSetFromOptions(run->model, run->scene));
  PetscCall(BwGeometryCreate(comm, &run->geom));
  PetscCall(BwGeometrySetFromOptions(run->geom, run->scene));
  PetscCall(BwOutputCreate(comm, &run->output));
  PetscCall(BwOutputSetFromOptions(run->output, run->scene));
  PetscCall(BwSolverCreate(comm, &run->solver));
  PetscCall(BwSolverSetFromOptions(run->solver, run->scene));
  /* a typo outside blockwall's keys fails now, before any work */
  PetscCall(BwSolverGetOptionPrefixes(&ndeferred, &deferred));
  PetscCall(BwSceneCheckUnused(run->scene, BW_CHECK_FOREIGN, 0, NULL, ndeferred, deferred));

  /* 3. geometry, then what depends on it: joint stiffness, supports, loads */
  PetscCall(BwLogBegin(&log, BW_PHASE_GENERATE));
  if (!(help && !has_scene)) PetscCall(BwGeometrySetUp(run->geom, run->scene, run->model->bed.thickness));
  PetscCall(BwModelSetUp(run->model, run->geom, run->scene));
  PetscCall(BwSolverSetSize(run->solver, run->geom->nblocks));
  if (!progress_set) log.verbose = run->geom->nblocks >= 10000 ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(BwLogEnd(&log, BW_PHASE_GENERATE));
  if (help && !has_scene) PetscFunctionReturn(PETSC_SUCCESS);
  /* every key of blockwall's has been read: the rest are typos, found
   * before the work (the solvers' own options wait for them) */
  PetscCall(BwSceneCheckUnused(run->scene, BW_CHECK_SETUP, 0, NULL, ndeferred, deferred));

  /* 4. partition and assembly */
  PetscCall(BwLogBegin(&log, BW_PHASE_PARTITION));
  PetscCall(BwPartitionBlocks(run->model, &owner));
  PetscCall(BwLogEnd(&log, BW_PHASE_PARTITION));
  PetscCall(BwLogBegin(&log, BW_PHASE_ASSEMBLE));
  PetscCall(BwMixedCreate(run->model, owner, &run->mixed));
  PetscCall(PetscFree(owner));
  run->mixed->storage = run->solver->storage;
  PetscCall(BwMixedAssemble(run->mixed));
  /* With m = 1 an interface carries no moment; the static restraint checks
   * cannot see every hinge mechanism, so S^ is checked numerically. */
  if (run->model->m == 1) PetscCall(BwMixedCheckMechanism(run->mixed, "m = 1 interfaces carry no moment"));
  PetscCall(BwLogEnd(&log, BW_PHASE_ASSEMBLE));

  /* 5. solve (set-up and solve phases inside) */
  PetscCall(BwSolverSolve(run->solver, run->mixed, &log));

  /* 6. recover and check */
  PetscCall(BwLogBegin(&log, BW_PHASE_RECOVER));
  PetscCall(BwMixedRecover(run->mixed, run->mixed->x, run->output->stresses, &run->results));
  PetscCall(BwMixedCheck(run->mixed, run->mixed->x, &run->results, &run->solver->check));
  PetscCall(BwLogEnd(&log, BW_PHASE_RECOVER));
  {
    PetscInt    n;
    const char *idle[6];
    PetscCall(BwSolverGetIdlePrefixes(run->solver, &n, idle));
    PetscCall(BwSceneCheckUnused(run->scene, BW_CHECK_FINAL, n, idle, 0, NULL));
  }

  /* 7. write and report */
  PetscCall(BwSceneGetText(run->scene, &run->text));
  PetscCall(BwLogBegin(&log, BW_PHASE_WRITE));
  PetscCall(BwOutputWrite(run->output, run->mixed, &run->results, run->solver, run->text, &log));
  PetscCall(BwLogEnd(&log, BW_PHASE_WRITE));
  {
    BwSolver       s = run->solver;
    PetscMPIInt    size;
    PetscLogDouble total, cur, peak;
    char           blas[PETSC_MAX_PATH_LEN];

    PetscCallMPI(MPI_Comm_size(comm, &size));
    PetscCall(BwLogTotal(&log, &total));
    PetscCall(BwMemoryUsage(comm, &cur, &peak));
    PetscCall(BwBlasName(blas, sizeof(blas)));
    PetscCall(PetscPrintf(comm, "blockwall %s%s%s\n", BW_VERSION, title[0] ? ": " : "", title));
    PetscCall(PetscPrintf(comm, "  blocks %" PetscInt_FMT ", interfaces %" PetscInt_FMT ", m %" PetscInt_FMT ", ranks %d\n", run->geom->nblocks, run->geom->ninterfaces, run->model->m, size));
    PetscCall(PetscPrintf(comm, "  unknowns: q %" PetscInt_FMT " (block dofs), r %" PetscInt_FMT " (stresses)\n", run->mixed->nq_global, run->mixed->nr_global));
    PetscCall(PetscPrintf(comm, "  method: %s (requested %s), iterations %" PetscInt_FMT "%s%s\n", BwMethods[s->used], BwMethods[s->requested], s->iterations, s->fallback ? ", fallback: " : "", s->fallback_reason));
    PetscCall(PetscPrintf(comm, "  residual %.3e (equilibrium %.3e, compatibility %.3e; rtol %.1e)\n", (double)s->check.residual, (double)s->check.equilibrium, (double)s->check.compatibility, (double)s->rtol));
    PetscCall(PetscPrintf(comm, "  equilibrium error (reactions + loads) %.3e\n", (double)s->check.equilibrium_error));
    if (s->forward_estimate >= 0 || s->condition_estimate > 0) {
      PetscCall(PetscPrintf(comm, "  estimated displacement error "));
      if (s->forward_estimate >= 0) PetscCall(PetscPrintf(comm, "%.1e (forward_rtol %.1e)", (double)s->forward_estimate, (double)s->forward_rtol));
      else PetscCall(PetscPrintf(comm, "not estimated"));
      if (s->condition_estimate > 0) PetscCall(PetscPrintf(comm, "; condition estimate %.1e", (double)s->condition_estimate));
      PetscCall(PetscPrintf(comm, "\n"));
    }
    if (!s->accuracy_met) PetscCall(PetscPrintf(comm, "  WARNING: %s\n", s->warning));
    PetscCall(PetscPrintf(comm, "  time [s]:"));
    for (int p = 0; p < BW_NPHASES; p++) PetscCall(PetscPrintf(comm, " %s %.3f,", BwPhaseNames[p], log.seconds[p]));
    PetscCall(PetscPrintf(comm, " total %.3f\n", total));
    PetscCall(PetscPrintf(comm, "  memory: peak %.1f MB over all ranks (%.0f bytes per block); BLAS %s\n", peak / 1048576.0, peak / (double)run->geom->nblocks, blas));
    PetscCall(PetscPrintf(comm, "  output: %s\n", run->output->file));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  PetscErrorCode ierr;
  BwRun          run = {0};
  PetscMPIInt    rank;
  int            code = 0;

  /* Open MPI's OMPIO prints its own lines on stderr when a write fails (a
   * full disk); ROMIO reports through return codes only, which blockwall
   * turns into its one error line. A user's own choice (OMPI_MCA_io) wins. */
  setenv("OMPI_MCA_io", "^ompio", 0);
  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  /* Errors are reported once, as one line, by this driver: no PETSc
   * traceback, no HDF5 error stack. */
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  PetscCall(BwSignalsInstall(PETSC_COMM_WORLD));
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  ierr = BwSceneCheckArguments(PETSC_COMM_WORLD, argc, argv);
  if (!ierr) ierr = BwRunMain(PETSC_COMM_WORLD, &run);
  if (ierr) {
    char *specific = NULL;
    PetscErrorMessage(ierr, NULL, &specific);
    if (rank == 0) {
      if (ierr == PETSC_ERR_MEM) fprintf(stderr, "blockwall: error: out of memory (in %s): the assembly is too large for this machine's memory with these settings\n", specific && specific[0] ? specific : "blockwall");
      else fprintf(stderr, "blockwall: error: %s\n", specific && specific[0] ? specific : "unknown error");
    }
    /* 1: what the user gave is wrong (scene, command line, a file to read
     * or a place to write); 2: the solve failed */
    code = ierr == PETSC_ERR_USER_INPUT || ierr == PETSC_ERR_FILE_OPEN || ierr == PETSC_ERR_FILE_READ || ierr == PETSC_ERR_FILE_WRITE ? 1 : 2;
  }
  if (BwRunDestroy(&run)) code = code ? code : 3;
  PetscPopErrorHandler();
  if (PetscFinalize()) code = code ? code : 3;
  return code;
}
