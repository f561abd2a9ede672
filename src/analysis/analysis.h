/* Analyses, registered by name (analysis.type):
 *   linear    one set-up, one solve per load case (cases.*), one result
 *             file per case
 *   pushover  incremental-iterative: constant loads, then a load pattern
 *             times a growing multiplier, under load or displacement
 *             control, Newton on the full mixed system (pushover.c)
 * An analysis gets the problem as the driver built it (scene, geometry,
 * model, assembled system, solver, output) and does the rest: loads,
 * solves, recovery, checks, output, the summary. It reads its own keys in
 * setfromoptions, before any work, so that typos are caught first. */
#pragma once
#include "solver/solver.h"
#include "output/output.h"

typedef struct {
  MPI_Comm   comm;
  BwScene    scene;
  BwGeometry geom;
  BwModel    model;
  BwMixed    mixed;
  BwSolver   solver;
  BwOutput   output;
  BwLog     *log;
  char       title[256];
  PetscBool  checked; /* the solvers' own options were checked */
  PetscBool  newton_monitor; /* analysis.newton_monitor: a line per Newton iteration */
  PetscBool  newton_keep_start; /* analysis.newton_keep_start: see BwNewtonAttempt */
} BwProblem;

typedef struct _n_BwAnalysis *BwAnalysis;
struct _n_BwAnalysis {
  char  type[32];
  void *data;
  /* its keys, given the geometry (case loads name sets) */
  PetscErrorCode (*setfromoptions)(BwAnalysis, BwProblem *);
  PetscErrorCode (*run)(BwAnalysis, BwProblem *);
  PetscErrorCode (*destroy)(BwAnalysis);
};
typedef PetscErrorCode (*BwAnalysisCreateFn)(BwAnalysis);

PetscErrorCode BwAnalysisRegister(const char name[], BwAnalysisCreateFn create);
/* Reads analysis.type and creates that analysis. */
PetscErrorCode BwAnalysisCreate(BwScene scene, BwAnalysis *analysis);
PetscErrorCode BwAnalysisSetFromOptions(BwAnalysis analysis, BwProblem *problem);
PetscErrorCode BwAnalysisRun(BwAnalysis analysis, BwProblem *problem);
PetscErrorCode BwAnalysisDestroy(BwAnalysis *analysis);

PetscErrorCode BwAnalysisCreate_Linear(BwAnalysis analysis);

/* Shared by the analyses: the summary's head (blocks, interfaces,
 * unknowns) and tail (times, memory, BLAS), and the /solver attributes
 * every file carries. */
PetscErrorCode BwProblemPrintHead(BwProblem *p);
PetscErrorCode BwProblemPrintTail(BwProblem *p, const char files[]);
PetscErrorCode BwProblemReport(BwProblem *p, BwReport report);
/* After the first solve and before the first file: the options PETSc's
 * solvers read only when set up, now that they were; once. */
PetscErrorCode BwProblemCheckOptions(BwProblem *p);
/* With joints that have a strength: the solver told, before it is set up,
 * that its operator will be refilled many times, may be non-symmetric and
 * may be singular (a collapse, not an error to diagnose). */
PetscErrorCode BwAnalysisSolverForJoints(BwProblem *p);
