/* BwOutput: the HDF5 result file (schema in README "HDF5 output").
 *
 * Written collectively by all ranks: replicated data (geometry, loads) by
 * rank 0, results by the rank that owns each block or interface at its
 * input index, so the file does not depend on the number of ranks. The file
 * is written under a temporary name beside the target and renamed when
 * complete; on any error the temporary is removed and the target untouched.
 * It reads the system only through BwMixed's accessors and the attributes
 * through a BwReport: the writer knows no solver's insides. */
#pragma once
#include "system/mixed.h"
#include "util/log.h"
#include "util/report.h"

typedef struct _n_BwOutput *BwOutput;
struct _n_BwOutput {
  MPI_Comm  comm;
  char      file[PETSC_MAX_PATH_LEN];
  PetscBool stresses, xdmf;
};

/* What one result file holds. */
typedef struct {
  BwMixed          mixed;    /* geometry, model and ownership, through its accessors */
  const BwResults *results;  /* of the owned blocks and interfaces */
  const PetscReal *load;     /* 3 per block (replicated): the loads applied */
  BwReport         solver;   /* the /solver attributes */
  const char      *scene;    /* the scene as run */
  const char      *casename; /* root attribute case, or NULL */
} BwOutputData;

PetscErrorCode BwOutputCreate(MPI_Comm comm, BwOutput *out);
/* Reads output.*; fails early if the target's directory cannot be written. */
PetscErrorCode BwOutputSetFromOptions(BwOutput out, BwScene scene);
/* The file of a load case: output.file with .NAME before its extension
 * (out/wall.h5 -> out/wall.wind_left.h5); output.file itself for NULL. */
PetscErrorCode BwOutputCaseFile(BwOutput out, const char casename[], char file[], size_t len);
/* Writes `file` (and its .xdmf). Call inside the log's write phase:
 * seconds_write is the time spent in it up to the attributes, which are
 * written last. */
PetscErrorCode BwOutputWrite(BwOutput out, const char file[], const BwOutputData *data, BwLog *log);
PetscErrorCode BwOutputDestroy(BwOutput *out);
