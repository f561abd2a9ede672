/* C prototypes of the Fortran per-interface kernels
 * (src/kernels/interface_kernels.f90, bind(C)). All are pure: data in, data
 * out, no I/O, no MPI; each reports a BwKernelStatus through its last argument
 * (Fortran pure procedures may not return a value and write their arguments).
 *
 * Arguments: ci, cj = centroids of blocks i and j, gc = G (the interface
 * centre), theta = angle of the tangent t [rad], length = l [m], depth = s
 * [m], m = number of portions. Per-portion arrays are interleaved: (shear,
 * normal) pairs portion after portion, 2x2 tangents as row-major quadruples.
 * Matrices are row-major: rb[3][6] has rows (dt, dn, phi) and columns
 * (u1,u2,w)_i, (u1,u2,w)_j. The joint laws' kernels are in laws.h. */
#pragma once

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  BW_KERNEL_OK            = 0,
  BW_KERNEL_BAD_M         = 1, /* m < 1, or a tangent count other than 1 or m */
  BW_KERNEL_BAD_LENGTH    = 2, /* l <= 0 or not finite */
  BW_KERNEL_BAD_DEPTH     = 3, /* s <= 0 or not finite */
  BW_KERNEL_BAD_STIFFNESS = 4  /* kn or kt <= 0 or not finite */
} BwKernelStatus;

/* R B (rb[3][6]): rows dt, dn, phi at G per unit dof of blocks i and j. */
void bw_interface_compatibility(const double ci[2], const double cj[2], const double gc[2], double theta, double rb[18], int *status);
/* Jumps of the portions, j_p = (dt, dn + x_p phi) from dg = (dt, dn, phi) (j[2m]). */
void bw_interface_jumps(int m, double length, const double dg[3], double j[], int *status);
/* Resultants about G, f = H r = (T, N, M), from the portions' stresses r[2m]. */
void bw_interface_resultants(int m, double length, double depth, const double r[], double f[3], int *status);
/* K_G = sum_p A_p E_p^T C_p E_p (kg[3][3]) from nt = m tangents (one per
 * portion) or nt = 1 (one for all, summed in closed form): tangent[4 nt]. */
void bw_interface_condense(int m, double length, double depth, int nt, const double tangent[], double kg[9], int *status);
/* The pair's stiffness (R B)^T K_G (R B) (k[6][6]). */
void bw_interface_stiffness(const double rb[18], const double kg[9], double k[36], int *status);
/* The 2m rows of D^ before the dofs' scaling (d[2m][6]): row pair p is
 * sqrt(A_p) diag(sqrt(kt), sqrt(kn)) E_p R B. */
void bw_interface_operator(int m, double length, double depth, double kt, double kn, const double rb[18], double d[], int *status);

#ifdef __cplusplus
}
#endif
