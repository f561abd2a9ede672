/* BwOutput: the HDF5 result file (schema in README "HDF5 output").
 *
 * Written collectively by all ranks: replicated data (geometry, loads) by
 * rank 0, results by the rank that owns each block or interface at its
 * input index, so the file does not depend on the number of ranks. The file
 * is written under a temporary name beside the target and renamed when
 * complete; on any error the temporary is removed and the target untouched. */
#pragma once
#include "solver/solver.h"

typedef struct _n_BwOutput *BwOutput;
struct _n_BwOutput {
  MPI_Comm  comm;
  char      file[PETSC_MAX_PATH_LEN];
  PetscBool stresses, xdmf;
};

PetscErrorCode BwOutputCreate(MPI_Comm comm, BwOutput *out);
/* Reads output.*; fails early if the target's directory cannot be written. */
PetscErrorCode BwOutputSetFromOptions(BwOutput out, BwScene scene);
/* Call inside the log's write phase: seconds_write is the time spent in it
 * up to the attributes, which are written last. */
PetscErrorCode BwOutputWrite(BwOutput out, BwMixed mixed, const BwResults *res, BwSolver solver, const char scene_text[], BwLog *log);
PetscErrorCode BwOutputDestroy(BwOutput *out);
