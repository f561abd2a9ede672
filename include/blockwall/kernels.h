/* C prototypes of the Fortran per-interface kernels
 * (src/kernels/interface_kernels.f90, bind(C)). All are pure: data in, data
 * out, no I/O, no MPI; each reports a BwKernelStatus through its last argument
 * (Fortran pure procedures may not return a value and write their arguments).
 *
 * Arguments common to all: ci, cj = centroids of blocks i and j, gc = G (the
 * interface centre), theta = angle of the tangent t [rad], length = l [m],
 * depth = s [m], kn, kt [N/m^3], m = number of portions. Matrices are
 * row-major: d[2m][6] has rows rt_1..rt_m, rn_1..rn_m and columns
 * (u1,u2,w)_i, (u1,u2,w)_j. */
#pragma once

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  BW_KERNEL_OK            = 0,
  BW_KERNEL_BAD_M         = 1, /* m < 1 */
  BW_KERNEL_BAD_LENGTH    = 2, /* l <= 0 or not finite */
  BW_KERNEL_BAD_DEPTH     = 3, /* s <= 0 or not finite */
  BW_KERNEL_BAD_STIFFNESS = 4  /* kn or kt <= 0 or not finite */
} BwKernelStatus;

/* R B (rb[3][6]): rows dt, dn, phi at G per unit dof of blocks i and j. */
void bw_interface_compatibility(const double ci[2], const double cj[2], const double gc[2], double theta, double rb[18], int *status);
/* The compliance diagonal g[2m] = (A_p/kt.., A_p/kn..) alone. */
void bw_interface_compliance(double length, double depth, double kn, double kt, int m, double g[], int *status);
/* D_k = H^T R B (d[2m][6]) and the compliance diagonal g[2m] = (A_p/kt.., A_p/kn..). */
void bw_interface_operator(const double ci[2], const double cj[2], const double gc[2], double theta, double length,
                          double depth, double kn, double kt, int m, double d[], double g[], int *status);
/* S_k = D_k^T G^-1 D_k (k[6][6], symmetric). */
void bw_interface_stiffness(const double ci[2], const double cj[2], const double gc[2], double theta, double length,
                           double depth, double kn, double kt, int m, double k[36], int *status);
/* dg = (dt, dn, phi) = R B q at G, and resultants f = H r = (T, N, M). */
void bw_interface_recover(const double ci[2], const double cj[2], const double gc[2], double theta, double length,
                         double depth, int m, const double qi[3], const double qj[3], const double r[], double dg[3],
                         double f[3], int *status);
/* r = G^-1 H^T R B q (r[2m]): the stresses of the condensed model. */
void bw_interface_stress(const double ci[2], const double cj[2], const double gc[2], double theta, double length,
                        double depth, double kn, double kt, int m, const double qi[3], const double qj[3], double r[], int *status);

#ifdef __cplusplus
}
#endif
