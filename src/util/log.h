/* Phases of a run: log stages (so -log_view shows where time goes), wall
 * time and memory per phase for the summary, the HDF5 /solver attributes and
 * the progress lines a long run prints on rank 0. */
#pragma once
#include <petscsys.h>

typedef enum { BW_PHASE_GENERATE, BW_PHASE_PARTITION, BW_PHASE_ASSEMBLE, BW_PHASE_SETUP, BW_PHASE_SOLVE, BW_PHASE_RECOVER, BW_PHASE_WRITE, BW_NPHASES } BwPhase;
extern const char *const BwPhaseNames[BW_NPHASES];

typedef struct {
  MPI_Comm       comm;
  PetscBool      verbose;            /* print one line per phase */
  PetscLogStage  stage[BW_NPHASES];
  PetscLogDouble seconds[BW_NPHASES]; /* accumulated */
  PetscLogDouble start;               /* of the phase in progress */
  PetscLogDouble t0;                  /* of the run */
} BwLog;

PetscErrorCode BwLogCreate(MPI_Comm comm, BwLog *log);
PetscErrorCode BwLogBegin(BwLog *log, BwPhase phase);
PetscErrorCode BwLogEnd(BwLog *log, BwPhase phase);
PetscErrorCode BwLogTotal(BwLog *log, PetscLogDouble *total);
/* Resident memory summed over ranks [bytes]: now and the peak so far. */
PetscErrorCode BwMemoryUsage(MPI_Comm comm, PetscLogDouble *current, PetscLogDouble *peak);
/* Path of the BLAS library this process loaded (from /proc/self/maps). */
PetscErrorCode BwBlasName(char name[], size_t len);
