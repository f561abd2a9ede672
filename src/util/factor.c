/* BwFactorPackage (see factor.h). */
#include "util/factor.h"
#include "util/compat.h"

PetscErrorCode BwFactorPackage(MPI_Comm comm, BwFactorKind kind, MatSolverType *type)
{
  PetscMPIInt size;
  PetscBool   lu = kind == BW_FACTOR_CHOLESKY ? PETSC_FALSE : PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  *type = NULL;
#if defined(PETSC_HAVE_SUITESPARSE)
  /* one rank, Cholesky: CHOLMOD's supernodal factor is faster than MUMPS's
   * on the 6 x 6 blocks of a 3D S^ (a 1e5-block wall: 6.9 s against 9.7 s
   * with two BLAS threads, bench/results.md) */
  if (size == 1 && !lu) {
    *type = MATSOLVERCHOLMOD;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
#endif
#if defined(PETSC_HAVE_MUMPS)
  *type = MATSOLVERMUMPS;
  PetscFunctionReturn(PETSC_SUCCESS);
#endif
  if (size > 1) {
#if defined(PETSC_HAVE_SUPERLU_DIST)
    if (lu) *type = MATSOLVERSUPERLU_DIST;
#endif
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  if (!lu) {
#if defined(PETSC_HAVE_SUITESPARSE)
    *type = MATSOLVERCHOLMOD;
#else
    *type = MATSOLVERPETSC;
#endif
    PetscFunctionReturn(PETSC_SUCCESS);
  }
#if defined(PETSC_HAVE_SUPERLU)
  *type = MATSOLVERSUPERLU;
#elif defined(PETSC_HAVE_SUITESPARSE)
  *type = MATSOLVERUMFPACK;
#else
  if (kind == BW_FACTOR_LU) *type = MATSOLVERPETSC;
#endif
  PetscFunctionReturn(PETSC_SUCCESS);
}

const char *BwFactorPackages(void)
{
  return "MUMPS:"
#if defined(PETSC_HAVE_MUMPS)
         "yes"
#else
         "no"
#endif
         " CHOLMOD:"
#if defined(PETSC_HAVE_SUITESPARSE)
         "yes"
#else
         "no"
#endif
         " SuperLU_DIST:"
#if defined(PETSC_HAVE_SUPERLU_DIST)
         "yes"
#else
         "no"
#endif
         " hypre:"
#if defined(PETSC_HAVE_HYPRE)
         "yes"
#else
         "no"
#endif
    ;
}
