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
  /* nonlinear joints (NULL for elastic ones) */
  const signed char *state;   /* one per portion of the owned interfaces: 0 elastic, 1 open, 2 sliding, 3 both */
  const PetscReal   *plastic; /* ns per portion: plastic slip and opening [m] (3D: slip t, opening, slip b) */
} BwOutputData;

/* The history of an incremental analysis (rank 0's arrays; n converged
 * steps, step 0 first). */
typedef struct {
  PetscInt         n;
  const PetscReal *load_factor, *monitor, *residual;
  const PetscInt  *iterations;
  const PetscReal *dissipation; /* cumulative energy dissipated [J] (NULL: not written) */
} BwOutputHistory;

/* A result file written over a run: steps as they converge, the final
 * state and the attributes at the end, published (renamed) only then. */
typedef struct _n_BwOutputFile *BwOutputFile;

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
/* Opens `file` under a temporary name for a run that will write about
 * nsteps steps (for the free-space check); collective. */
PetscErrorCode BwOutputOpen(BwOutput out, const char file[], BwMixed mixed, const char scene[], PetscInt nsteps, BwOutputFile *of);
/* Step `step` under /steps/NNNNNN: displacement, reaction, resultant,
 * relative displacement, state and (output.stresses) stress. */
PetscErrorCode BwOutputWriteStep(BwOutputFile of, PetscInt step, const BwOutputData *data);
/* The final state, the history (NULL: none) and the attributes; then the
 * file (and its .xdmf, a temporal collection over the steps written) is
 * published. *of is NULL afterwards, whatever happened. */
PetscErrorCode BwOutputClose(BwOutputFile *of, const BwOutputData *data, const BwOutputHistory *history, BwLog *log);
/* Drops an open file: nothing is published. */
PetscErrorCode BwOutputAbort(BwOutputFile *of);
PetscErrorCode BwOutputDestroy(BwOutput *out);
