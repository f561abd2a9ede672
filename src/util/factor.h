/* Which sparse direct solver this PETSc has, for a factorisation of a
 * matrix on `comm`: the one blockwall uses where it factors (the Schur
 * complement S^, the whole saddle matrix, the mechanism check). Decided
 * from petscconf.h, so a PETSc without MUMPS (a cluster's own build) still
 * runs, on the paths it can take.
 *   Cholesky, one rank:        CHOLMOD (SuiteSparse), else MUMPS, else PETSc's own
 *   LU of S^, one rank:        MUMPS, else SuperLU, else UMFPACK, else PETSc's own
 *   LU of a saddle, one rank:  MUMPS, else SuperLU, else UMFPACK, else none
 *   more ranks:                MUMPS, else SuperLU_DIST for LU, else none
 * A saddle matrix (zero displacement block) needs pivoting, which PETSc's
 * own LU does not do; S^ (a tangent stiffness with a positive diagonal
 * from its elastic or residual stiffness) does not.
 * *type is NULL when there is none. */
#pragma once
#include <petscmat.h>

typedef enum {
  BW_FACTOR_CHOLESKY,   /* symmetric S^ */
  BW_FACTOR_LU,         /* non-symmetric S^: no pivoting needed */
  BW_FACTOR_LU_PIVOTING /* the whole saddle matrix */
} BwFactorKind;

PetscErrorCode BwFactorPackage(MPI_Comm comm, BwFactorKind kind, MatSolverType *type);
/* One line naming what this PETSc offers, for messages. */
const char *BwFactorPackages(void);
