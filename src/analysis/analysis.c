/* The analysis registry, and what every analysis prints and records. */
#include "analysis/analysis.h"
#include <string.h>
#include "util/compat.h"

static PetscFunctionList BwAnalysisList = NULL;

PetscErrorCode BwAnalysisRegister(const char name[], BwAnalysisCreateFn create)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFunctionListAdd(&BwAnalysisList, name, create));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PETSC_INTERN PetscErrorCode BwAnalysisCreate_Pushover(BwAnalysis);

static PetscErrorCode BwAnalysisRegisterAll(void)
{
  PetscFunctionBeginUser;
  if (BwAnalysisList) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(BwAnalysisRegister("linear", BwAnalysisCreate_Linear));
  PetscCall(BwAnalysisRegister("pushover", BwAnalysisCreate_Pushover));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwAnalysisCreate(BwScene scene, BwAnalysis *analysis)
{
  const char        **list;
  const char         *names[8];
  int                 nlist;
  PetscInt            n = 0, type = 0;
  BwAnalysisCreateFn  create;

  PetscFunctionBeginUser;
  PetscCall(BwAnalysisRegisterAll());
  PetscCall(PetscFunctionListGet(BwAnalysisList, &list, &nlist));
  for (int l = 0; l < nlist && n < 8; l++)
    if (list[l] && list[l][0]) names[n++] = list[l];
  PetscCall(BwSceneHelpSection(scene, "Analysis (scene key analysis.*)"));
  PetscCall(BwSceneRequireMapping(scene, "-analysis", "type and its keys"));
  for (PetscInt k = 0; k < n; k++)
    if (!strcmp(names[k], "linear")) type = k;
  PetscCall(BwSceneEnum(scene, "-analysis_type", "Analysis: linear (one solve per load case) or pushover (incremental-iterative, nonlinear joints)", n, names, &type, NULL));
  PetscCall(PetscNew(analysis));
  PetscCall(PetscStrncpy((*analysis)->type, names[type], sizeof((*analysis)->type)));
  PetscCall(PetscFree(list));
  PetscCall(PetscFunctionListFind(BwAnalysisList, (*analysis)->type, &create));
  PetscCall((*create)(*analysis));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwAnalysisSetFromOptions(BwAnalysis a, BwProblem *p)
{
  PetscFunctionBeginUser;
  PetscCall(BwSceneBool(p->scene, "-analysis_newton_monitor", "Nonlinear joints: one line per Newton iteration (residual, monitor gap, modes changed)", &p->newton_monitor, NULL));
  p->newton_keep_start = PETSC_TRUE;
  PetscCall(BwSceneBool(p->scene, "-analysis_newton_keep_start", "Nonlinear joints, load or displacement control: a step's first Newton iteration keeps the matrix (its factor) of the last iteration of the step before", &p->newton_keep_start, NULL));
  if (a->setfromoptions) PetscCall(a->setfromoptions(a, p));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwAnalysisRun(BwAnalysis a, BwProblem *p)
{
  PetscFunctionBeginUser;
  PetscCall(a->run(a, p));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwAnalysisDestroy(BwAnalysis *a)
{
  PetscFunctionBeginUser;
  if (!*a) PetscFunctionReturn(PETSC_SUCCESS);
  if ((*a)->destroy) PetscCall((*a)->destroy(*a));
  PetscCall(PetscFree(*a));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwProblemPrintHead(BwProblem *p)
{
  PetscMPIInt      size;
  BwMixedOwnership own;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(p->comm, &size));
  PetscCall(BwMixedGetOwnership(p->mixed, &own));
  PetscCall(PetscPrintf(p->comm, "blockwall %s%s%s\n", BW_VERSION, p->title[0] ? ": " : "", p->title));
  PetscCall(PetscPrintf(p->comm, "  blocks %" PetscInt_FMT ", interfaces %" PetscInt_FMT ", m %" PetscInt_FMT ", ranks %d\n", own.nblocks, own.ninterfaces, own.m, size));
  PetscCall(PetscPrintf(p->comm, "  unknowns: q %" PetscInt_FMT " (block dofs), r %" PetscInt_FMT " (stresses)\n", own.nq_global, own.nr_global));
  PetscCall(PetscPrintf(p->comm, "  partition: edge cut %" PetscInt_FMT " interfaces, imbalance %.3f (largest rank's blocks over the mean)\n", own.edge_cut, (double)own.imbalance));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwProblemPrintTail(BwProblem *p, const char files[])
{
  PetscLogDouble total, cur, peak;
  char           blas[PETSC_MAX_PATH_LEN], kernels[64];

  PetscFunctionBeginUser;
  PetscCall(BwLogTotal(p->log, &total));
  PetscCall(BwMemoryUsage(p->comm, &cur, &peak));
  PetscCall(BwBlasName(blas, sizeof(blas)));
  PetscCall(PetscPrintf(p->comm, "  time [s]:"));
  for (int ph = 0; ph < BW_NPHASES; ph++) PetscCall(PetscPrintf(p->comm, " %s %.3f,", BwPhaseNames[ph], p->log->seconds[ph]));
  PetscCall(PetscPrintf(p->comm, " total %.3f\n", total));
  PetscCall(BwBlasKernels(kernels, sizeof(kernels)));
  PetscCall(PetscPrintf(p->comm, "  memory: peak %.1f MB over all ranks (%.0f bytes per block); BLAS %s%s%s%s\n", peak / 1048576.0, peak / (double)p->geom->nblocks_global, blas, kernels[0] ? " (OpenBLAS " : "", kernels, kernels[0] ? " kernels)" : ""));
  PetscCall(PetscPrintf(p->comm, "  output: %s\n", files));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwProblemCheckOptions(BwProblem *p)
{
  PetscInt    n;
  const char *idle[8];

  PetscFunctionBeginUser;
  if (p->checked) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(BwSolverGetIdlePrefixes(p->solver, &n, idle));
  /* one rank, or partition.method natural: no MatPartitioning read them */
  if (!p->geom->partitioned) idle[n++] = "partition_";
  PetscCall(BwSceneCheckUnused(p->scene, BW_CHECK_FINAL, n, idle, 0, NULL));
  p->checked = PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwProblemReport(BwProblem *p, BwReport report)
{
  PetscFunctionBeginUser;
  PetscCall(BwReportString(report, "analysis", "linear"));
  PetscFunctionReturn(PETSC_SUCCESS);
}
