/* The linear analysis: the operator assembled and the solver set up once
 * (factor, AMG hierarchy), then one solve per load case, each with its own
 * self-check and its own result file.
 *
 *   cases:                       optional; without it there is one case,
 *     NAME: {loads: {SET: [F1, F2, M3], ...}, gravity: {density: RHO}}
 *
 * A case replaces the scene's loads (and its self-weight, if it gives a
 * density); geometry, joints, supports and prescribed values are shared.
 * Case NAME goes to output.file with .NAME before the extension. A case
 * whose solve fails writes no file; the others are written and the run
 * ends with an error naming it.
 *
 * With joints that have a strength (joints.*.strength) a case is the
 * equilibrium under its loads with those joints: the loads are applied
 * from the unloaded state by Newton's method on the full mixed system
 * (newton.h), in one step, cut in halves where it fails; the file also
 * holds each portion's state and plastic jump. Loads the joints cannot
 * carry are a failed case. */
#include <string.h>
#include "analysis/analysis.h"
#include "analysis/newton.h"
#include "util/compat.h"

typedef struct {
  PetscInt ncases;
  char   **cases; /* NULL: one case, the scene's loads */
} BwLinear;

static PetscErrorCode BwLinearSetFromOptions(BwAnalysis a, BwProblem *p)
{
  BwLinear *lin = (BwLinear *)a->data;

  PetscFunctionBeginUser;
  PetscCall(BwAnalysisSolverForJoints(p));
  PetscCall(BwSceneHelpSection(p->scene, "Load cases (scene key cases.NAME.loads.<set>, cases.NAME.gravity.density)"));
  PetscCall(BwSceneRequireMapping(p->scene, "-cases", "NAME: {loads: {set: [F1, F2, M3]}, gravity: {density: ...}}"));
  {
    const char *const keys[] = {"loads", "gravity"};
    PetscCall(BwSceneListEntries(p->scene, "cases", 2, keys, "does not name a case's loads or gravity (cases.NAME.loads.SET, cases.NAME.gravity.density)", &lin->ncases, &lin->cases));
  }
  if (!lin->ncases) {
    PetscCall(PetscFree(lin->cases));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  /* every case's keys read now, before the work: a typo in the last case
   * must not wait for the first ones to be solved */
  for (PetscInt c = 0; c < lin->ncases; c++) {
    char prefix[PETSC_MAX_OPTION_NAME], opt[PETSC_MAX_OPTION_NAME + 1];
    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-cases_%s", lin->cases[c]));
    PetscCall(BwSceneRequireMapping(p->scene, opt, "loads, gravity"));
    PetscCall(PetscSNPrintf(prefix, sizeof(prefix), "cases_%s_", lin->cases[c]));
    PetscCall(BwModelSetLoads(p->model, p->scene, prefix));
  }
  /* one operator, ncases right-hand sides: a factor pays */
  PetscCall(BwSolverSetExpectedSolves(p->solver, lin->ncases));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Before the solver is set up: Newton refills the operator many times, a
 * non-associated law makes it non-symmetric, and a singular tangent is a
 * failed step rather than a mechanism to name. */
PetscErrorCode BwAnalysisSolverForJoints(BwProblem *p)
{
  PetscFunctionBeginUser;
  if (!p->model->nonlinear) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(BwSolverSetExpectedSolves(p->solver, 100));
  PetscCall(BwSolverSetSymmetric(p->solver, BwModelTangentSymmetric(p->model)));
  PetscCall(BwSolverSetDiagnose(p->solver, PETSC_FALSE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A case with nonlinear joints: its loads from the unloaded state
 * (BwNewtonRamp); x the converged state. The Newton object is returned
 * for the output of the joints' state. */
static PetscErrorCode BwLinearJoints(BwProblem *p, Vec x, BwNewton *newton, PetscReal *residual)
{
  PetscInt    substeps;
  PetscBool   ok;
  Vec         xc;
  const char *reason;

  PetscFunctionBeginUser;
  PetscCall(BwNewtonCreate(p, p->model->load, NULL, newton));
  PetscCall(BwLogBegin(p->log, BW_PHASE_SOLVE));
  PetscCall(BwNewtonRamp(*newton, 1e-3, &substeps, &ok));
  PetscCall(BwLogEnd(p->log, BW_PHASE_SOLVE));
  PetscCall(BwNewtonGetResult(*newton, NULL, residual, &reason));
  PetscCheck(ok, p->comm, PETSC_ERR_NOT_CONVERGED, "the joints cannot carry the loads: no equilibrium even with 1/1000 of them applied at a time (%s)", reason);
  PetscCall(BwNewtonGetSolution(*newton, &xc, NULL));
  PetscCall(VecCopy(xc, x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwLinearRun(BwAnalysis a, BwProblem *p)
{
  BwLinear *lin    = (BwLinear *)a->data;
  PetscInt  ncases = lin->ncases ? lin->ncases : 1, nfailed = 0;
  Vec       x, b;
  char     *text, files[4 * PETSC_MAX_PATH_LEN] = "", failed[1024] = "", first_error[1024] = "";

  PetscFunctionBeginUser;
  PetscCall(BwSceneGetText(p->scene, &text));
  PetscCall(BwMixedCreateVecs(p->mixed, &x, &b));
  PetscCall(BwProblemPrintHead(p));
  for (PetscInt c = 0; c < ncases; c++) {
    const char    *name = lin->ncases ? lin->cases[c] : NULL;
    char           file[PETSC_MAX_PATH_LEN + 64];
    BwResults      res = {NULL, NULL, NULL, NULL, NULL, NULL};
    BwCheck        check;
    BwReport       report;
    PetscErrorCode ierr;
    BwNewton       newton = NULL;
    PetscReal      nwres  = -1;

    if (name) {
      char prefix[PETSC_MAX_OPTION_NAME];
      PetscCall(PetscSNPrintf(prefix, sizeof(prefix), "cases_%s_", name));
      PetscCall(BwModelSetLoads(p->model, p->scene, prefix));
    }
    PetscCall(BwMixedFillRHS(p->mixed, p->model->load, b));
    if (p->model->nonlinear) ierr = BwLinearJoints(p, x, &newton, &nwres);
    else ierr = BwSolverSolve(p->solver, b, x, p->log);
    if (ierr && name) {
      /* the other cases still run; this one writes nothing */
      PetscCall(PetscSNPrintf(failed + strlen(failed), sizeof(failed) - strlen(failed), "%s%s", nfailed ? ", " : "", name));
      if (!nfailed) PetscCall(PetscStrncpy(first_error, BwErrorText(ierr), sizeof(first_error)));
      nfailed++;
      PetscCall(BwNewtonDestroy(&newton));
      PetscCall(PetscPrintf(p->comm, "  case %s: FAILED: %s\n", name, BwErrorText(ierr)));
      continue;
    }
    PetscCall(ierr);
    PetscCall(BwProblemCheckOptions(p));
    /* the last solve frees the factors before recovery allocates its own */
    if (c == ncases - 1) PetscCall(BwSolverReset(p->solver));
    PetscCall(BwLogBegin(p->log, BW_PHASE_RECOVER));
    PetscCall(BwMixedRecover(p->mixed, x, p->model->load, p->output->stresses, &res));
    PetscCall(BwMixedCheck(p->mixed, x, b, p->model->load, &res, &check));
    PetscCall(BwLogEnd(p->log, BW_PHASE_RECOVER));
    PetscCall(BwReportCreate(&report));
    PetscCall(BwReportString(report, "analysis", "linear"));
    PetscCall(BwSolverReport(p->solver, report));
    PetscCall(BwReportReal(report, "equilibrium_error", check.equilibrium_error));
    if (newton) {
      /* the true residual of the nonlinear system, not of the last Newton
       * correction's linear one; its equilibrium rows do not depend on the
       * law (D^T r~ - F), its compatibility rows do */
      PetscInt its, solves;
      PetscCall(BwNewtonGetCounts(newton, &its, &solves, NULL));
      PetscCall(BwReportReal(report, "residual", nwres));
      PetscCall(BwReportReal(report, "residual_compatibility", -1));
      PetscCall(BwReportInt(report, "newton_iterations", its));
    }
    PetscCall(BwOutputCaseFile(p->output, name, file, sizeof(file)));
    PetscCall(BwLogBegin(p->log, BW_PHASE_WRITE));
    {
      BwOutputData data = {p->mixed, &res, p->model->load, report, text, name, NULL, NULL};
      if (newton) {
        BwJointField field;
        PetscReal   *plastic;
        PetscCall(BwNewtonGetSolution(newton, NULL, &field));
        PetscCall(BwJointFieldGetState(field, &data.state, &plastic));
        data.plastic = plastic;
      }
      PetscCall(BwOutputWrite(p->output, file, &data, p->log));
    }
    PetscCall(BwLogEnd(p->log, BW_PHASE_WRITE));
    if (name) PetscCall(PetscPrintf(p->comm, "  case %s:\n", name));
    PetscCall(BwSolverView(p->solver, PETSC_VIEWER_STDOUT_(p->comm)));
    PetscCall(PetscPrintf(p->comm, "  equilibrium error (reactions + loads) %.3e\n", (double)check.equilibrium_error));
    if (files[0]) PetscCall(PetscStrlcat(files, ", ", sizeof(files)));
    PetscCall(PetscStrlcat(files, file, sizeof(files)));
    if (newton) {
      BwJointField field;
      PetscInt     count[4], crushed;
      PetscCall(BwNewtonGetSolution(newton, NULL, &field));
      PetscCall(BwJointFieldCount(field, count));
      PetscCall(BwJointFieldCountCrushed(field, &crushed));
      PetscCall(PetscPrintf(p->comm, "  joints: %" PetscInt_FMT " portions open, %" PetscInt_FMT " sliding, %" PetscInt_FMT " both, %" PetscInt_FMT " elastic", count[1], count[2], count[3], count[0]));
      if (crushed) PetscCall(PetscPrintf(p->comm, "; %" PetscInt_FMT " crushed (on the cap)", crushed));
      PetscCall(PetscPrintf(p->comm, "; residual of the nonlinear system %.3e\n", (double)nwres));
    }
    PetscCall(BwNewtonDestroy(&newton));
    PetscCall(BwReportDestroy(&report));
    PetscCall(BwResultsFree(&res));
  }
  PetscCall(BwProblemPrintTail(p, files));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&b));
  PetscCall(PetscFree(text));
  PetscCheck(!nfailed, p->comm, PETSC_ERR_NOT_CONVERGED, "load case%s %s failed (the other cases were written): %s", nfailed > 1 ? "s" : "", failed, first_error);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwLinearDestroy(BwAnalysis a)
{
  BwLinear *lin = (BwLinear *)a->data;

  PetscFunctionBeginUser;
  if (lin->cases) PetscCall(PetscStrArrayDestroy(&lin->cases));
  PetscCall(PetscFree(a->data));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwAnalysisCreate_Linear(BwAnalysis a)
{
  BwLinear *lin;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&lin));
  a->data           = lin;
  a->setfromoptions = BwLinearSetFromOptions;
  a->run            = BwLinearRun;
  a->destroy        = BwLinearDestroy;
  PetscFunctionReturn(PETSC_SUCCESS);
}
