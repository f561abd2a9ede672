/* C prototypes of the Fortran per-interface kernels
 * (src/kernels/interface_kernels.f90, bind(C)). All are pure: data in, data
 * out, no I/O, no MPI; each reports a BwKernelStatus through its last argument
 * (Fortran pure procedures may not return a value and write their arguments).
 *
 * bw_kernel_*: written once for dim = 2 and 3 (model.md, "Three
 * dimensions"): nd = 3 | 6 dofs per block ((u1, u2, w3) | (u1, u2, u3, w1,
 * w2, w3)), the same number nd of components of dG ((dt, dn, phib) | (dt,
 * dn, db, phit, phin, phib)), ns = 2 | 3 stress components ((rt, rn) |
 * (rt, rn, rb)). An interface is its centre gc, its frame (double
 * frame[3][3], rows t, n, b) and its np portions: areas and centroids
 * (xi, eta) from G along t and b (eta = 0 in 2D).
 *
 * bw_interface_*: the 2D interface of angle theta, length l, depth s and m
 * equal portions, through the general kernels:
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
  BW_KERNEL_BAD_STIFFNESS = 4, /* kn or kt <= 0 or not finite */
  BW_KERNEL_BAD_DIMENSION = 5, /* dim other than 2 or 3 */
  BW_KERNEL_BAD_FRAME     = 6  /* a zero or non-finite normal */
} BwKernelStatus;

/* ---- general kernels (dim = 2 | 3) ---- */
/* The frame of an interface with normal n (any length): b = X3 projected
 * onto the plane (X2 if that is shorter than 1e-6), t = n x b. */
void bw_kernel_frame(const double normal[3], double frame[9], int *status);
/* The m x mb equal portions of a rectangle lt x lb centred on G along
 * (t, b), t index fastest (area, xi, eta: m mb each; eta = 0 if mb = 1). */
void bw_kernel_rectangle_portions(int m, int mb, double lt, double lb, double area[], double xi[], double eta[], int *status);
/* R B (rb[nd][2 nd]) from centroids ci, cj and centre gc (dim coordinates). */
void bw_kernel_compatibility(int dim, const double ci[], const double cj[], const double gc[], const double frame[9], double rb[], int *status);
/* j_p = E_p dG (j[np][ns]) from dg[nd]. */
void bw_kernel_jumps(int dim, int np, const double xi[], const double eta[], const double dg[], double j[], int *status);
/* f = H r = sum_p A_p E_p^T r_p (f[nd]) from r[np][ns]. */
void bw_kernel_resultants(int dim, int np, const double area[], const double xi[], const double eta[], const double r[], double f[], int *status);
/* The sizes of the terms those two sum, for round-off bounds: |E_p| a
 * (j[np][ns]) from a[nd] >= 0, and sum_p A_p |E_p|^T |r_p| (f[nd]). */
void bw_kernel_jumps_abs(int dim, int np, const double xi[], const double eta[], const double a[], double j[], int *status);
void bw_kernel_resultants_abs(int dim, int np, const double area[], const double xi[], const double eta[], const double r[], double f[], int *status);
/* The same two in double-double (value = hi + lo), for a residual far
 * below double's round-off: j = E_p dg, f = sum_p A_p E_p^T r_p. */
void bw_kernel_jumps_dd(int dim, int np, const double xi[], const double eta[], const double dg_hi[], const double dg_lo[], double j_hi[], double j_lo[], int *status);
void bw_kernel_resultants_dd(int dim, int np, const double area[], const double xi[], const double eta[], const double r_hi[], const double r_lo[], double f_hi[], double f_lo[], int *status);
/* K_G = sum_p A_p E_p^T C_p E_p (kg[nd][nd]) from nt = np tangents or one
 * (tangent[nt][ns][ns], row-major). */
void bw_kernel_condense(int dim, int np, const double area[], const double xi[], const double eta[], int nt, const double tangent[], double kg[], int *status);
/* (R B)^T K_G (R B) (k[2 nd][2 nd]). */
void bw_kernel_stiffness(int dim, const double rb[], const double kg[], double k[], int *status);
/* The rows of D^ (d[np][ns][2 nd]): sqrt(A_p) C^1/2 E_p R B, C = diag(kt, kn, kt). */
void bw_kernel_operator(int dim, int np, const double area[], const double xi[], const double eta[], double kt, double kn, const double rb[], double d[], int *status);

/* ---- the 2D interface (theta, l, s, m) ---- */

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
