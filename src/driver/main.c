static const char help[] = "blockwall: static equilibrium of rigid blocks joined by elastic interfaces,\n"
                           "mixed form (block displacements and piecewise-constant interface stresses).\n"
                           "Usage: mpiexec -n N blockwall -scene SCENE.yaml [scene options] [PETSc options]\n"
                           "Every scene key is an option: nested keys joined by '_' (-discretization_m 8).\n\n";

/* The driver, as numbered steps:
 *   1. scene file -> options database            (BwScene)
 *   2. joint laws, geometry, supports and loads  (BwJointLaw, BwGeometry, BwModel)
 *   3. output target and solver options, checked before any work
 *   4. layout and assembly of the scaled mixed system (BwMixed)
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
  char           path[PETSC_MAX_PATH_LEN] = "", title[256] = "";
  PetscBool      has_scene, help;
  BwJointLaw     bed, head;
  BwTimings      t = {0};
  PetscLogDouble t0, t1;

  PetscFunctionBeginUser;
  PetscCall(PetscTime(&t0));
  PetscCall(BwLogRegister());
  PetscCall(PetscOptionsHasHelp(NULL, &help));

  /* 1. scene */
  PetscCall(BwSceneCreate(comm, &run->scene));
  PetscOptionsBegin(comm, NULL, "blockwall", NULL);
  PetscCall(PetscOptionsString("-scene", "Scene file (YAML); every key is also an option", NULL, path, path, sizeof(path), &has_scene));
  PetscCall(PetscOptionsString("-title", "Free text describing the scene", NULL, title, title, sizeof(title), NULL));
  PetscOptionsEnd();
  if (has_scene) PetscCall(BwSceneLoad(run->scene, path));
  else PetscCheck(help, comm, PETSC_ERR_USER_INPUT, "-scene SCENE.yaml is required (run with -help for the options)");
  if (has_scene) { /* -title is read again now that the file's keys are in */
    PetscCall(PetscOptionsGetString(NULL, NULL, "-title", title, sizeof(title), NULL));
  }

  /* 2. physics and geometry */
  PetscCall(BwLogStagePush(BW_STAGE_GENERATE));
  PetscCall(BwJointLawSetFromOptions(&bed, run->scene, "joints_", NULL));
  PetscCall(BwGeometryCreate(comm, &run->geom));
  PetscCall(BwGeometrySetFromOptions(run->geom, run->scene, bed.thickness));
  head = bed;
  for (PetscInt k = 0; k < run->geom->ninterfaces; k++)
    if (run->geom->kind[k] == BW_JOINT_HEAD) {
      PetscCall(BwJointLawSetFromOptions(&head, run->scene, "joints_head_", &bed));
      break;
    }
  PetscCall(BwModelCreate(run->geom, &run->model));
  PetscCall(BwModelSetFromOptions(run->model, run->scene, &bed, &head));
  PetscCall(PetscLogStagePop());
  PetscCall(PetscTime(&t1));
  t.generate = t1 - t0;

  /* 3. output and solver options */
  PetscCall(BwOutputCreate(comm, &run->output));
  PetscCall(BwOutputSetFromOptions(run->output, run->scene));
  PetscCall(BwSolverCreate(comm, &run->solver));
  PetscCall(BwSolverSetFromOptions(run->solver, run->scene));
  if (help && !has_scene) PetscFunctionReturn(PETSC_SUCCESS);

  /* 4. assembly */
  PetscCall(BwLogStagePush(BW_STAGE_ASSEMBLE));
  PetscCall(PetscTime(&t0));
  PetscCall(BwMixedCreate(run->model, NULL, &run->mixed));
  PetscCall(BwMixedAssemble(run->mixed));
  PetscCall(PetscTime(&t1));
  t.assemble = t1 - t0;
  PetscCall(PetscLogStagePop());

  /* 5. solve */
  PetscCall(BwLogStagePush(BW_STAGE_SOLVE));
  PetscCall(BwSolverSolve(run->solver, run->mixed));
  t.setup = run->solver->seconds_setup;
  t.solve = run->solver->seconds_solve;
  PetscCall(PetscLogStagePop());

  /* 6. recover and check */
  PetscCall(BwLogStagePush(BW_STAGE_RECOVER));
  PetscCall(PetscTime(&t0));
  PetscCall(BwMixedRecover(run->mixed, run->mixed->x, &run->results));
  PetscCall(BwMixedCheck(run->mixed, run->mixed->x, &run->results, &run->solver->check));
  PetscCall(PetscTime(&t1));
  t.recover = t1 - t0;
  PetscCall(PetscLogStagePop());
  {
    PetscInt    n;
    const char *idle[3];
    PetscCall(BwSolverGetIdlePrefixes(run->solver, &n, idle));
    PetscCall(BwSceneCheckUnused(run->scene, n, idle));
  }

  /* 7. write and report */
  PetscCall(BwSceneGetText(run->scene, &run->text));
  t.total = t.generate + t.assemble + t.setup + t.solve + t.recover;
  PetscCall(BwLogStagePush(BW_STAGE_WRITE));
  PetscCall(BwOutputWrite(run->output, run->mixed, &run->results, run->solver, run->text, &t));
  PetscCall(PetscLogStagePop());
  {
    BwSolver    s = run->solver;
    PetscMPIInt size;
    PetscCallMPI(MPI_Comm_size(comm, &size));
    PetscCall(PetscPrintf(comm, "blockwall %s%s%s\n", BW_VERSION, title[0] ? ": " : "", title));
    PetscCall(PetscPrintf(comm, "  blocks %" PetscInt_FMT ", interfaces %" PetscInt_FMT ", m %" PetscInt_FMT ", ranks %d\n", run->geom->nblocks, run->geom->ninterfaces, run->model->m, size));
    PetscCall(PetscPrintf(comm, "  unknowns: q %" PetscInt_FMT " (block dofs), r %" PetscInt_FMT " (stresses)\n", run->mixed->nq_global, run->mixed->nr_global));
    PetscCall(PetscPrintf(comm, "  method: %s (requested %s), iterations %" PetscInt_FMT "%s%s\n", BwMethods[s->used], BwMethods[s->requested], s->iterations, s->fallback ? ", fallback: " : "", s->fallback_reason));
    PetscCall(PetscPrintf(comm, "  residual %.3e (equilibrium %.3e, compatibility %.3e; rtol %.1e)\n", (double)s->check.residual, (double)s->check.equilibrium, (double)s->check.compatibility, (double)s->rtol));
    PetscCall(PetscPrintf(comm, "  equilibrium error (reactions + loads) %.3e\n", (double)s->check.equilibrium_error));
    PetscCall(PetscPrintf(comm, "  time [s]: generate %.3f, assemble %.3f, setup %.3f, solve %.3f, recover %.3f, write %.3f, total %.3f\n", t.generate, t.assemble, t.setup, t.solve, t.recover, t.write, t.total));
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

  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  /* Errors are reported once, as one line, by this driver: no PETSc
   * traceback, no HDF5 error stack. */
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  ierr = BwRunMain(PETSC_COMM_WORLD, &run);
  if (ierr) {
    char *specific = NULL;
    PetscErrorMessage(ierr, NULL, &specific);
    if (rank == 0) fprintf(stderr, "blockwall: error: %s\n", specific && specific[0] ? specific : "unknown error");
    code = ierr == PETSC_ERR_USER_INPUT ? 1 : 2;
  }
  if (BwRunDestroy(&run)) code = code ? code : 3;
  PetscPopErrorHandler();
  if (PetscFinalize()) code = code ? code : 3;
  return code;
}
