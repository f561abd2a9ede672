/* Which sparse direct solver this PETSc has, for a factorisation of a
 * matrix on `comm`: the one blockwall uses where it factors (the Schur
 * complement S^, the whole saddle matrix, the mechanism check). Decided
 * from petscconf.h, so a PETSc without MUMPS (a cluster's own build) still
 * runs, on the paths it can take.
 *   Cholesky, one rank:     MUMPS, else CHOLMOD (SuiteSparse), else PETSc's own
 *   Cholesky, more ranks:   MUMPS, else none
 *   LU, one rank:           MUMPS, else SuperLU, else UMFPACK, else none
 *   LU, more ranks:         MUMPS, else SuperLU_DIST, else none
 * A saddle matrix needs pivoting, which PETSc's own LU does not do.
 * *type is NULL when there is none. */
#pragma once
#include <petscmat.h>

PetscErrorCode BwFactorPackage(MPI_Comm comm, PetscBool lu, MatSolverType *type);
/* One line naming what this PETSc offers, for messages. */
const char *BwFactorPackages(void);
