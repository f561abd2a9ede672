/* A guard for the tests labelled `input` (tests/CMakeLists.txt), loaded
 * with LD_PRELOAD into the runs they start: the BLAS and LAPACK routines
 * through which every solve, residual and norm of blockwall goes (PETSc's
 * Vec norms and dots, MUMPS' and PETSc's factorizations, GAMG's QR) end the
 * process with one line naming the routine. A test so labelled claims that
 * its runs are refused while their input is read, before any number is
 * computed; tools/test's pass with the reference BLAS leaves these tests
 * out because their verdict cannot depend on the BLAS, and this guard,
 * on every run of them in the other pass, is what checks the claim. */
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

static void bw_noblas(const char *name)
{
  char line[160];
  int  n = snprintf(line, sizeof(line), "tests/common/noblas.c: %s called in a test labelled input (it computes: not an input error)\n", name);
  if (n > 0) (void)!write(2, line, (size_t)n); /* write(2): async-signal-safe, no stdio state */
  abort();
}

#define BW_NOBLAS(name) \
  void name(void); \
  void name(void) { bw_noblas(#name); }

/* Level 1, 2, 3 BLAS */
BW_NOBLAS(ddot_)
BW_NOBLAS(dnrm2_)
BW_NOBLAS(dasum_)
BW_NOBLAS(daxpy_)
BW_NOBLAS(dscal_)
BW_NOBLAS(dcopy_)
BW_NOBLAS(dswap_)
BW_NOBLAS(idamax_)
BW_NOBLAS(dgemv_)
BW_NOBLAS(dger_)
BW_NOBLAS(dtrsv_)
BW_NOBLAS(dgemm_)
BW_NOBLAS(dsyrk_)
BW_NOBLAS(dtrsm_)
BW_NOBLAS(dtrmm_)
/* LAPACK: factorizations, QR, eigenvalues */
BW_NOBLAS(dgetrf_)
BW_NOBLAS(dgetrs_)
BW_NOBLAS(dpotrf_)
BW_NOBLAS(dgeqrf_)
BW_NOBLAS(dormqr_)
BW_NOBLAS(dgesvd_)
BW_NOBLAS(dsyev_)
BW_NOBLAS(dsyevd_)
BW_NOBLAS(dgeev_)
