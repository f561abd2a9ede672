/* The process's environment, set before MPI starts: the choices every
 * blockwall process makes for the libraries beneath it (Open MPI,
 * PT-Scotch), in one place, so that the driver and the test programs run
 * the libraries the same way. */
#pragma once

/* Call first in main(), before MPI_Init or PetscInitialize. */
void BwProcessDefaults(void);

/* Removes the private session directory of a rank started without
 * mpiexec (process.c); runs at exit by itself, call it before _exit. */
void BwProcessRemoveSessionBase(void);

/* Where OpenBLAS fell back to its generic kernels on a CPU it does not
 * know but whose AVX2/AVX-512 it could use, starts the process again with
 * OPENBLAS_CORETYPE set (process.c). Call first in main(), before MPI. */
void BwProcessBlasKernels(char **argv);

/* OpenBLAS's kernels in use (openblas_get_corename: "Haswell", "SkylakeX",
 * "Prescott", ...), NULL for another BLAS. */
const char *BwProcessOpenBlasKernels(void);
