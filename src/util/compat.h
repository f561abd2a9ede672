/* PETSc 3.18 (Debian 12) predates PETSC_SUCCESS. */
#pragma once
#include <petscsys.h>
#ifndef PETSC_SUCCESS
#define PETSC_SUCCESS ((PetscErrorCode)0)
#endif
