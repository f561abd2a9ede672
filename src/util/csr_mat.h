/* BwMatFromCSR: an AIJ matrix from local CSR rows, the arrays used in place.
 *
 * Below src/system, so that the two files that assemble operators (D^ in
 * operator.c, S^ in stiffness.c) both build on it without calling each
 * other. */
#pragma once
#include <petscmat.h>

/* The matrix from local CSR rows m x n of the global M x N (global column
 * indices, sorted), used in place: on one rank as they are, on more split
 * into the diagonal part (local column indices) and the off-diagonal part
 * (global), the layout MPIAIJ keeps. PETSc does not copy them; they are
 * freed with the matrix (ia, ja, va are consumed). vals, if not NULL,
 * receives where PETSc holds the values, for refills in place: row starts
 * and values of the diagonal part (all of it on one rank) and of the
 * off-diagonal part (NULL on one rank); a row's columns, sorted, fall into
 * them in order. */
typedef struct {
  PetscInt  *di, *oi;
  PetscReal *dv, *ov;
} BwCSRValues;
PetscErrorCode BwMatFromCSR(MPI_Comm comm, PetscInt m, PetscInt n, PetscInt M, PetscInt N, const char prefix[], PetscInt *ia, PetscInt *ja, PetscReal *va, Mat *A, BwCSRValues *vals);
