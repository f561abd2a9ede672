/* Log stages, registered once, so that -log_view shows where time goes in
 * the same phases the summary reports. */
#pragma once
#include <petscsys.h>

typedef enum { BW_STAGE_GENERATE, BW_STAGE_ASSEMBLE, BW_STAGE_SOLVE, BW_STAGE_RECOVER, BW_STAGE_WRITE, BW_NSTAGES } BwStage;

PetscErrorCode BwLogRegister(void);
PetscErrorCode BwLogStagePush(BwStage stage);
