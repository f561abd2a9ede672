/* Differences between the PETSc releases blockwall builds with: Debian 12's
 * 3.18 and newer ones a cluster may have. */
#pragma once
#include <petscsys.h>
#include <petscversion.h>

/* 3.18 predates PETSC_SUCCESS. */
#ifndef PETSC_SUCCESS
  #define PETSC_SUCCESS ((PetscErrorCode)0)
#endif

/* Context destroy functions take the context's address from 3.23 on
 * (PetscCtxDestroyFn), the context itself before. */
#if PETSC_VERSION_GE(3, 24, 0)
  /* PetscCtxDestroyFn(PetscCtxRt): a void * that holds the context's address */
  #define BW_CTX_DESTROY_ARG        void *
  #define BW_CTX_FROM_DESTROY(a)    (*(void **)(a))
  #define BW_CONVERGED_DESTROY(ctx) KSPConvergedDefaultDestroy(&(ctx))
#elif PETSC_VERSION_GE(3, 23, 0)
  #define BW_CTX_DESTROY_ARG        void **
  #define BW_CTX_FROM_DESTROY(a)    (*(a))
  #define BW_CONVERGED_DESTROY(ctx) KSPConvergedDefaultDestroy(&(ctx))
#else
  #define BW_CTX_DESTROY_ARG        void *
  #define BW_CTX_FROM_DESTROY(a)    (a)
  #define BW_CONVERGED_DESTROY(ctx) KSPConvergedDefaultDestroy(ctx)
#endif

/* The text of a PETSc error's specific message ("" if none). */
static inline const char *BwErrorText(PetscErrorCode ierr)
{
  char *specific = NULL;

  (void)PetscErrorMessage(ierr, NULL, (void *)&specific);
  return specific ? specific : "";
}

/* A container that frees its pointer with PetscFree when destroyed. */
#if PETSC_VERSION_GE(3, 23, 0)
  #define BwContainerFreeWithIt(c) PetscContainerSetCtxDestroy((c), PetscCtxDestroyDefault)
#else
  #define BwContainerFreeWithIt(c) PetscContainerSetUserDestroy((c), PetscContainerUserDestroyDefault)
#endif

/* A matrix's values changed in place (refilled): a new assembly tells
 * whoever built something from them (a factor, a hierarchy) to rebuild it,
 * through the public API (PetscObjectStateIncrease is private). */
#include <petscmat.h>
static inline PetscErrorCode BwMatValuesChanged(Mat A)
{
  PetscFunctionBeginUser;
  PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(PETSC_SUCCESS);
}
