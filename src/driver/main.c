#define _POSIX_C_SOURCE 200809L /* POSIX calls: _exit, and the signal headers below */
#include <unistd.h>           /* _exit */
static const char help[] = "blockwall: static equilibrium of rigid blocks joined by elastic interfaces,\n"
                           "mixed form (block displacements and piecewise-constant interface stresses).\n"
                           "Usage: mpiexec -n N blockwall -scene SCENE.yaml [scene options] [PETSc options]\n"
                           "Every scene key is an option: nested keys joined by '_' (-discretization_m 8).\n\n";

/* The driver, as numbered steps:
 *   1. scene file and command line, typed keys    (BwScene)
 *   2. every key that does not depend on the geometry (BwModel, BwGeometry,
 *      BwOutput, BwSolver, the analysis), then options nobody reads are
 *      refused
 *   3. each rank's share of the geometry (BwGeometry), the partition that
 *      gives each rank its piece (more than one rank), joint stiffness,
 *      supports, loads (BwModel) and the analysis's own keys (load cases),
 *      then every unread key of blockwall's is refused
 *   4. layout and assembly of the scaled mixed system (BwMixed), the
 *      solver bound to it (BwSolver)
 *   5. the analysis: solves, recovery, self-checks, HDF5 output, summary
 * Errors print one line on stderr and exit non-zero without output. */
#include <hdf5.h>
#include "scene/scene.h"
#include "model/model.h"
#include "system/mixed.h"
#include "solver/solver.h"
#include "output/output.h"
#include "analysis/analysis.h"
#include "util/log.h"
#include "util/compat.h"
#include "util/signals.h"
#include "util/process.h"

typedef struct {
  BwProblem  p;
  BwAnalysis analysis;
  BwLog      log;
} BwRun;

static PetscErrorCode BwRunDestroy(BwRun *run)
{
  PetscFunctionBeginUser;
  PetscCall(BwAnalysisDestroy(&run->analysis));
  PetscCall(BwOutputDestroy(&run->p.output));
  PetscCall(BwSolverDestroy(&run->p.solver));
  PetscCall(BwMixedDestroy(&run->p.mixed));
  PetscCall(BwModelDestroy(&run->p.model));
  PetscCall(BwGeometryDestroy(&run->p.geom));
  PetscCall(BwSceneDestroy(&run->p.scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwRunMain(MPI_Comm comm, BwRun *run)
{
  BwProblem         *p    = &run->p;
  char               path[PETSC_MAX_PATH_LEN] = "";
  PetscBool          has_scene, help, progress_set;
  PetscInt           ndeferred;
  const char *const *deferred;
  BwStorage          storage;

  PetscFunctionBeginUser;
  p->comm = comm;
  p->log  = &run->log;
  PetscCall(BwLogCreate(comm, &run->log));
  PetscCall(PetscOptionsHasHelp(NULL, &help));

  /* 1. scene */
  PetscCall(BwSceneCreate(comm, &p->scene));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", path, sizeof(path), &has_scene));
  PetscCheck(has_scene || help, comm, PETSC_ERR_USER_INPUT, "-scene SCENE.yaml is required (run with -help for the options)");
  PetscCall(BwSceneLoad(p->scene, has_scene ? path : NULL));
  if (help) PetscCall((*PetscHelpPrintf)(comm, "blockwall:\n  -scene <%s>: Scene file (YAML); every key is also an option\n", path));
  PetscCall(BwSceneString(p->scene, "-title", "Free text describing the scene", p->title, sizeof(p->title), NULL));
  PetscCall(BwSceneBool(p->scene, "-progress", "One line per phase with time and memory (default: for 10000 blocks or more)", &run->log.verbose, &progress_set));

  /* 2. every key that does not depend on the geometry */
  PetscCall(BwModelCreate(comm, &p->model));
  PetscCall(BwModelSetFromOptions(p->model, p->scene));
  PetscCall(BwGeometryCreate(comm, &p->geom));
  PetscCall(BwGeometrySetFromOptions(p->geom, p->scene));
  PetscCall(BwOutputCreate(comm, &p->output));
  PetscCall(BwOutputSetFromOptions(p->output, p->scene));
  PetscCall(BwSolverCreate(comm, &p->solver));
  PetscCall(BwSolverSetFromOptions(p->solver, p->scene));
  PetscCall(BwAnalysisCreate(p->scene, &run->analysis));
  /* a typo outside blockwall's keys fails now, before any work */
  PetscCall(BwSolverGetOptionPrefixes(&ndeferred, &deferred));
  PetscCall(BwSceneCheckUnused(p->scene, BW_CHECK_FOREIGN, 0, NULL, ndeferred, deferred));

  /* 3. each rank's share of the geometry, then (more than one rank) the
   * partition that gives each its piece; then what depends on it */
  PetscCall(BwLogBegin(p->log, BW_PHASE_GENERATE));
  if (has_scene) PetscCall(BwGeometrySetUp(p->geom, p->scene, p->model->law[BW_JOINT_BED]->thickness));
  if (!progress_set) run->log.verbose = p->geom->nblocks_global >= 10000 ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(BwLogEnd(p->log, BW_PHASE_GENERATE));
  /* the geometry's keys are all read: a typo among them fails before the
   * partition (the keys that name the geometry's sets wait for the model) */
  if (has_scene) PetscCall(BwSceneCheckUnused(p->scene, BW_CHECK_GEOMETRY, 0, NULL, ndeferred, deferred));
  if (!has_scene) {
    /* -help alone: the keys that need a geometry are listed with none */
    PetscCall(BwModelSetUp(p->model, p->geom, p->scene));
    PetscCall(BwAnalysisSetFromOptions(run->analysis, p));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  {
    PetscMPIInt size;
    PetscCallMPI(MPI_Comm_size(comm, &size));
    /* one rank: the piece is the share, nothing is partitioned or logged */
    if (size > 1) PetscCall(BwLogBegin(p->log, BW_PHASE_PARTITION));
    PetscCall(BwGeometryDistribute(p->geom, (BwPartitionMethod)p->geom->partition));
    if (size > 1) PetscCall(BwLogEnd(p->log, BW_PHASE_PARTITION));
  }
  PetscCall(BwLogBegin(p->log, BW_PHASE_ASSEMBLE));
  PetscCall(BwModelSetUp(p->model, p->geom, p->scene));
  PetscCall(BwAnalysisSetFromOptions(run->analysis, p));
  /* every key of blockwall's has been read: the rest are typos, found
   * before the work (the solvers' own options wait for them) */
  PetscCall(BwSceneCheckUnused(p->scene, BW_CHECK_SETUP, 0, NULL, ndeferred, deferred));

  /* 4. assembly, the solver */
  PetscCall(BwMixedCreate(p->model, &p->mixed));
  PetscCall(BwSolverGetStorage(p->solver, &storage));
  /* a linear analysis of elastic joints solves with the operators as
   * assembled: S^ may leave out its round-off entries */
  {
    PetscBool linear;
    PetscCall(PetscStrcmp(run->analysis->type, "linear", &linear));
    PetscCall(BwMixedSetValuesFixed(p->mixed, linear && !p->model->nonlinear ? PETSC_TRUE : PETSC_FALSE));
  }
  PetscCall(BwMixedSetUp(p->mixed, storage));
  /* With m = 1 an interface carries no moment; the static restraint checks
   * cannot see every hinge mechanism, so S^ is checked numerically. */
  if (p->model->m == 1) PetscCall(BwMixedCheckMechanism(p->mixed, "m = 1 interfaces carry no moment"));
  else if (p->model->mb == 1 && p->geom->dim == 3) PetscCall(BwMixedCheckMechanism(p->mixed, "m_b = 1 interfaces carry no moment about t"));
  PetscCall(BwSolverSetUp(p->solver, p->mixed));
  PetscCall(BwLogEnd(p->log, BW_PHASE_ASSEMBLE));

  /* 5. the analysis */
  PetscCall(BwAnalysisRun(run->analysis, p));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A PETSc option with a value PETSc refused (an unknown type name, a
 * number that is none) is bad input, like a bad scene key: the option is
 * found by its value in PETSc's message, among all options given (command
 * line, PETSC_OPTIONS, the scene), so the line can name it. */
static PetscBool BwBadOptionValue(PetscErrorCode ierr, const char specific[], char option[], size_t len)
{
  char     *all = NULL, *save = NULL, *tok, *prev = NULL;
  PetscBool found = PETSC_FALSE;

  if (ierr != PETSC_ERR_ARG_UNKNOWN_TYPE && ierr != PETSC_ERR_ARG_OUTOFRANGE && ierr != PETSC_ERR_ARG_WRONG) return PETSC_FALSE;
  if (PetscOptionsGetAll(NULL, &all) || !all) return PETSC_FALSE;
  for (tok = strtok_r(all, " ", &save); tok && !found; prev = tok, tok = strtok_r(NULL, " ", &save)) {
    const char *at;
    size_t      n = strlen(tok);
    if (!prev || prev[0] != '-' || tok[0] == '-' || n == 0) continue;
    /* the value as a whole word of the message */
    for (at = strstr(specific, tok); at && !found; at = strstr(at + 1, tok)) {
      char before = at == specific ? ' ' : at[-1], after = at[n];
      if ((before == ' ' || before == '\'' || before == '"') && (after == 0 || after == ' ' || after == '\'' || after == '"' || after == ',' || after == '.')) {
        snprintf(option, len, "%s", prev);
        found = PETSC_TRUE;
      }
    }
  }
  (void)PetscFree(all);
  return found;
}

int main(int argc, char **argv)
{
  PetscErrorCode ierr;
  BwRun          run;
  PetscMPIInt    rank;
  int            code = 0;

  BwProcessBlasKernels(argv); /* may start the process again: first */
  BwProcessDefaults();          /* before MPI: util/process.c */
  if (BwSignalsInstallEarly()) {
    fprintf(stderr, "blockwall: error: cannot install a signal handler\n");
    return 3;
  }
  /* MPI first, with blockwall's handlers on (a signal during a slow start
   * is reported), then PETSc with the signals held (signals.h) */
  {
    int provided;
    if (MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
      fprintf(stderr, "blockwall: error: MPI_Init failed\n");
      return 3;
    }
  }
  BwSignalsHold();
  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  PetscCall(PetscMemzero(&run, sizeof(run)));
  /* Errors are reported once, as one line, by this driver: no PETSc
   * traceback, no HDF5 error stack. */
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  PetscCall(BwSignalsInstall(PETSC_COMM_WORLD));
  PetscCall(BwBlasSetThreads(PETSC_COMM_WORLD));
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  ierr = BwSceneCheckArguments(PETSC_COMM_WORLD, argc, argv);
  if (!ierr) ierr = BwRunMain(PETSC_COMM_WORLD, &run);
  BwSignalsFinishing();
  if (ierr) {
    const char *specific = BwErrorText(ierr);
    char        option[256];
    PetscBool   bad_option = BwBadOptionValue(ierr, specific, option, sizeof(option));
    if (rank == 0) {
      if (bad_option) fprintf(stderr, "blockwall: error: option %s: %s (run with -help for the values it takes)\n", option, specific);
      else if (ierr == PETSC_ERR_MEM) fprintf(stderr, "blockwall: error: out of memory (in %s): the assembly is too large for this machine's memory with these settings\n", specific[0] ? specific : "blockwall");
      else fprintf(stderr, "blockwall: error: %s\n", specific[0] ? specific : "unknown error");
    }
    /* 1: what the user gave is wrong (scene, command line, a file to read
     * or a place to write); 2: the solve failed */
    code = bad_option || ierr == PETSC_ERR_USER_INPUT || ierr == PETSC_ERR_FILE_OPEN || ierr == PETSC_ERR_FILE_READ || ierr == PETSC_ERR_FILE_WRITE ? 1 : 2;
  }
  if (BwRunDestroy(&run)) code = code ? code : 3;
  if (BwFinalizeSkipped()) {
    /* HDF5 would crash finalising a file it could not close (h5file.c):
     * the error is printed and the temporary files are gone */
    fflush(stdout);
    fflush(stderr);
    BwProcessRemoveSessionBase(); /* _exit runs no atexit handler */
    _exit(code ? code : 1);
  }
  PetscPopErrorHandler();
  if (PetscFinalize()) code = code ? code : 3;
  if (MPI_Finalize() != MPI_SUCCESS) code = code ? code : 3; /* MPI_Init was blockwall's, not PETSc's */
  return code;
}
