/* EXPECT for the C unit tests: a failed check prints one FAIL line (on rank
 * 0) and counts, so one run reports every check that failed; main returns
 * non-zero when bw_failures > 0. */
#pragma once
#include <petscsys.h>

static PetscInt bw_failures = 0;

#define EXPECT(cond, ...) \
  do { \
    if (!(cond)) { \
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL " __VA_ARGS__)); \
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "\n")); \
      bw_failures++; \
    } \
  } while (0)
