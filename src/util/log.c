#include "util/log.h"
#include "util/compat.h"

static PetscLogStage BwStages[BW_NSTAGES];
static PetscBool     BwLogRegistered = PETSC_FALSE;

PetscErrorCode BwLogRegister(void)
{
  static const char *const names[BW_NSTAGES] = {"Generate", "Assemble", "Setup+Solve", "Recover", "Write"};

  PetscFunctionBeginUser;
  if (BwLogRegistered) PetscFunctionReturn(PETSC_SUCCESS);
  for (int s = 0; s < BW_NSTAGES; s++) PetscCall(PetscLogStageRegister(names[s], &BwStages[s]));
  BwLogRegistered = PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwLogStagePush(BwStage stage)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePush(BwStages[stage]));
  PetscFunctionReturn(PETSC_SUCCESS);
}
