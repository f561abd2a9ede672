/* The dimension-general kernels (bw_kernel_*) against closed forms and
 * first principles (model.md, "Three dimensions"):
 *   kg        K_G(m, m_b) of a rectangle l_t x l_b: diag(kt A, kn A, kt A,
 *             kn I_b (1 - 1/m_b^2), kt (I_t (1 - 1/m^2) + I_b (1 - 1/m_b^2)),
 *             kn I_t (1 - 1/m^2)), torsion included, off-diagonals zero,
 *             1e-12, m and m_b = 1..12
 *   frame     the frame rule: a bed joint has t = X1, b = X3; a head joint
 *             t = -X2, b = X3; a joint normal to X3 takes b from X2; any
 *             normal gives a right-handed orthonormal frame (t x n = b)
 *   rigid     the jump of every portion equals Q (u_j(x) - u_i(x)) at its
 *             centroid x = G + xi t + eta b, with u_b(x) = u_b + w_b x (x -
 *             c_b) (rigid-body kinematics, not the kernels' matrices), and
 *             the six rigid motions of the pair give dG = 0
 *   adjoint   sum_p A_p j_p . r_p = dG . H r (the stresses' work), and the
 *             rows of D^ give (R B)^T K_G (R B) = sum of their outer products
 *   restrict  an extruded 2D interface (frame of theta, rectangle l x s,
 *             m x m_b portions): R B, K_G, jumps and resultants on the 2D
 *             components equal the 2D kernels' (bw_interface_*), for every
 *             m_b, and K_G couples them to nothing else
 *   bad       dimension and frame statuses
 * Random data from a fixed linear congruential sequence. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "blockwall/kernels.h"

static int failures = 0;

static void expect_close(const char *what, double got, double want, double tol, double scale)
{
  double err = fabs(got - want) / (scale > 0 ? scale : 1);
  if (!(err <= tol)) {
    printf("FAIL %s: got %.17g, want %.17g (relative error %.3e > %.1e)\n", what, got, want, err, tol);
    failures++;
  }
}

static unsigned long long seed = 20261124ULL;
static double             uniform(double a, double b)
{
  seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
  return a + (b - a) * (double)(seed >> 11) / 9007199254740992.0;
}

static void cross(const double a[3], const double b[3], double c[3])
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void check(int st, const char *what)
{
  if (st) printf("FAIL %s: status %d\n", what, st), failures++;
}

static void test_kg(void)
{
  const double lt = 0.25, lb = 0.12, kn = 8e10, kt = 3e10, A = lt * lb, It = lb * lt * lt * lt / 12, Ib = lt * lb * lb * lb / 12;
  const double c[9] = {kt, 0, 0, 0, kn, 0, 0, 0, kt};
  double       area[144], xi[144], eta[144], kg[36];
  int          st;
  for (int m = 1; m <= 12; m++)
    for (int mb = 1; mb <= 12; mb++) {
      double want[6] = {kt * A, kn * A, kt * A, kn * Ib * (1 - 1.0 / (mb * mb)), kt * (It * (1 - 1.0 / (m * m)) + Ib * (1 - 1.0 / (mb * mb))), kn * It * (1 - 1.0 / (m * m))};
      double scale[6] = {kt * A, kn * A, kt * A, kn * Ib, kt * (It + Ib), kn * It};
      bw_kernel_rectangle_portions(m, mb, lt, lb, area, xi, eta, &st);
      check(st, "rectangle_portions");
      bw_kernel_condense(3, m * mb, area, xi, eta, 1, c, kg, &st);
      check(st, "condense");
      for (int a = 0; a < 6; a++)
        for (int b = 0; b < 6; b++) {
          char what[64];
          snprintf(what, sizeof(what), "K_G(m=%d, m_b=%d)[%d][%d]", m, mb, a, b);
          expect_close(what, kg[6 * a + b], a == b ? want[a] : 0.0, 1e-12, sqrt(scale[a] * scale[b]));
        }
    }
  /* the portions: t index fastest, equal areas, centroids of the cells */
  bw_kernel_rectangle_portions(3, 2, 0.3, 0.2, area, xi, eta, &st);
  expect_close("portion 1 xi", xi[1], 0.0, 1e-15, 1);
  expect_close("portion 1 eta", eta[1], -0.05, 1e-15, 1);
  expect_close("portion 3 xi", xi[3], -0.1, 1e-15, 1);
  expect_close("portion 3 eta", eta[3], 0.05, 1e-15, 1);
  expect_close("portion area", area[5], 0.01, 1e-15, 1);
}

static void test_frame(void)
{
  const double bed[3] = {0, 1, 0}, head[3] = {1, 0, 0}, face[3] = {0, 0, -2};
  const double want_bed[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, want_head[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1}, want_face[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0};
  double       f[9];
  int          st;
  bw_kernel_frame(bed, f, &st);
  for (int k = 0; k < 9; k++) expect_close("bed joint frame", f[k], want_bed[k], 1e-15, 1);
  bw_kernel_frame(head, f, &st);
  for (int k = 0; k < 9; k++) expect_close("head joint frame", f[k], want_head[k], 1e-15, 1);
  /* normal -X3: b = X2, t = n x b = -X3 x X2 = X1 */
  bw_kernel_frame(face, f, &st);
  for (int k = 0; k < 9; k++) expect_close("frame of a joint normal to X3", f[k], want_face[k], 1e-15, 1);
  for (int trial = 0; trial < 200; trial++) {
    double n[3] = {uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)}, txn[3], len = sqrt(dot3(n, n));
    bw_kernel_frame(n, f, &st);
    check(st, "frame");
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) expect_close("frame orthonormal", dot3(f + 3 * a, f + 3 * b), a == b, 1e-14, 1);
    for (int a = 0; a < 3; a++) expect_close("frame's n is the normal", f[3 + a], n[a] / len, 1e-15, 1);
    cross(f, f + 3, txn);
    for (int a = 0; a < 3; a++) expect_close("t x n = b", txn[a], f[6 + a], 1e-14, 1);
    expect_close("b in the plane of X3 and n", f[6 + 0] * n[1] - f[6 + 1] * n[0], 0, 1e-14, 1);
  }
}

/* displacement of material point x of a block with centroid c, dofs q */
static void rigid_motion(const double q[6], const double c[3], const double x[3], double u[3])
{
  double arm[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]}, wx[3];
  cross(q + 3, arm, wx);
  for (int a = 0; a < 3; a++) u[a] = q[a] + wx[a];
}

static void test_rigid(void)
{
  for (int trial = 0; trial < 50; trial++) {
    double ci[3], cj[3], gc[3], n[3], frame[9], rb[72], q[12], dg[6], area[12], xi[12], eta[12], j[36];
    int    st, m = 1 + trial % 4, mb = 1 + (trial / 4) % 3;
    for (int a = 0; a < 3; a++) {
      ci[a] = uniform(-1, 1);
      cj[a] = uniform(-1, 1);
      gc[a] = uniform(-1, 1);
      n[a]  = uniform(-1, 1);
    }
    for (int a = 0; a < 12; a++) q[a] = uniform(-1e-3, 1e-3);
    bw_kernel_frame(n, frame, &st);
    bw_kernel_compatibility(3, ci, cj, gc, frame, rb, &st);
    check(st, "compatibility");
    for (int r = 0; r < 6; r++) {
      dg[r] = 0;
      for (int c = 0; c < 12; c++) dg[r] += rb[12 * r + c] * q[c];
    }
    bw_kernel_rectangle_portions(m, mb, uniform(0.1, 1), uniform(0.1, 1), area, xi, eta, &st);
    bw_kernel_jumps(3, m * mb, xi, eta, dg, j, &st);
    check(st, "jumps");
    for (int p = 0; p < m * mb; p++) {
      double x[3], ui[3], uj[3], du[3];
      for (int a = 0; a < 3; a++) x[a] = gc[a] + xi[p] * frame[a] + eta[p] * frame[6 + a];
      rigid_motion(q, ci, x, ui);
      rigid_motion(q + 6, cj, x, uj);
      for (int a = 0; a < 3; a++) du[a] = uj[a] - ui[a];
      for (int a = 0; a < 3; a++) expect_close("jump = Q (u_j(x) - u_i(x))", j[3 * p + a], dot3(frame + 3 * a, du), 1e-13, 1e-3);
    }
    /* the six rigid motions of the pair about a point x0 */
    for (int k = 0; k < 6; k++) {
      double u0[6] = {0}, x0[3] = {0.3, -0.2, 0.1}, qq[12];
      u0[k] = 1;
      for (int b = 0; b < 2; b++) {
        const double *c = b ? cj : ci;
        double        arm[3] = {c[0] - x0[0], c[1] - x0[1], c[2] - x0[2]}, wx[3];
        cross(u0 + 3, arm, wx);
        for (int a = 0; a < 3; a++) qq[6 * b + a] = u0[a] + wx[a], qq[6 * b + 3 + a] = u0[3 + a];
      }
      for (int r = 0; r < 6; r++) {
        double s = 0;
        for (int c = 0; c < 12; c++) s += rb[12 * r + c] * qq[c];
        expect_close("rigid motion of the pair: dG = 0", s, 0, 1e-14, 1);
      }
    }
  }
}

static void test_adjoint(void)
{
  for (int trial = 0; trial < 20; trial++) {
    double ci[3], cj[3], gc[3], n[3], frame[9], rb[72], dg[6], area[20], xi[20], eta[20], j[60], r[60], f[6], kg[36], k[144], d[60 * 12], sum[144] = {0};
    double kt = uniform(1e9, 1e10), kn = uniform(1e10, 1e11), c[9] = {kt, 0, 0, 0, kn, 0, 0, 0, kt}, work = 0, work_g = 0;
    int    st, m = 1 + trial % 5, mb = 1 + trial % 4, np = m * mb;
    for (int a = 0; a < 3; a++) ci[a] = uniform(-1, 1), cj[a] = uniform(-1, 1), gc[a] = uniform(-1, 1), n[a] = uniform(-1, 1);
    for (int a = 0; a < 6; a++) dg[a] = uniform(-1, 1);
    for (int a = 0; a < 3 * np; a++) r[a] = uniform(-1, 1);
    bw_kernel_frame(n, frame, &st);
    bw_kernel_compatibility(3, ci, cj, gc, frame, rb, &st);
    bw_kernel_rectangle_portions(m, mb, uniform(0.1, 1), uniform(0.1, 1), area, xi, eta, &st);
    bw_kernel_jumps(3, np, xi, eta, dg, j, &st);
    bw_kernel_resultants(3, np, area, xi, eta, r, f, &st);
    check(st, "resultants");
    for (int p = 0; p < np; p++)
      for (int a = 0; a < 3; a++) work += area[p] * j[3 * p + a] * r[3 * p + a];
    for (int a = 0; a < 6; a++) work_g += dg[a] * f[a];
    expect_close("sum A_p j_p.r_p = dG.H r", work, work_g, 1e-13, fabs(work) + 1);
    bw_kernel_condense(3, np, area, xi, eta, 1, c, kg, &st);
    bw_kernel_stiffness(3, rb, kg, k, &st);
    bw_kernel_operator(3, np, area, xi, eta, kt, kn, rb, d, &st);
    check(st, "operator");
    for (int row = 0; row < 3 * np; row++)
      for (int a = 0; a < 12; a++)
        for (int b = 0; b < 12; b++) sum[12 * a + b] += d[12 * row + a] * d[12 * row + b];
    for (int a = 0; a < 144; a++) expect_close("(R B)^T K_G (R B) = D^T D", sum[a], k[a], 1e-12, kn);
  }
}

static void test_restrict(void)
{
  const int keep[3] = {0, 1, 5};
  for (int trial = 0; trial < 24; trial++) {
    double theta = uniform(-3, 3), l = uniform(0.1, 0.5), s = uniform(0.05, 0.3), kt = 4e9, kn = 1e10;
    int    m = 1 + trial % 8, mb = 1 + trial % 3, np = m * mb, st;
    double ci2[2] = {uniform(-1, 1), uniform(-1, 1)}, cj2[2] = {uniform(-1, 1), uniform(-1, 1)}, gc2[2] = {uniform(-1, 1), uniform(-1, 1)};
    double ci3[3] = {ci2[0], ci2[1], s / 2}, cj3[3] = {cj2[0], cj2[1], s / 2}, gc3[3] = {gc2[0], gc2[1], s / 2};
    double frame[9] = {cos(theta), sin(theta), 0, -sin(theta), cos(theta), 0, 0, 0, 1}, n[3] = {-sin(theta), cos(theta), 0}, fr[9];
    double rb2[18], rb3[72], kg2[9], kg3[36], c2[4] = {kt, 0, 0, kn}, c3[9] = {kt, 0, 0, 0, kn, 0, 0, 0, kt};
    double area[24], xi[24], eta[24], dg2[3], dg3[6] = {0}, j2[16], j3[72], r2[16], r3[72], f2[3], f3[6];
    /* the frame rule gives the 2D frame of theta */
    bw_kernel_frame(n, fr, &st);
    for (int a = 0; a < 9; a++) expect_close("frame of a 2D joint", fr[a], frame[a], 1e-15, 1);
    bw_interface_compatibility(ci2, cj2, gc2, theta, rb2, &st);
    bw_kernel_compatibility(3, ci3, cj3, gc3, frame, rb3, &st);
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++)
        for (int side = 0; side < 2; side++) expect_close("R B restricted", rb3[12 * keep[a] + 6 * side + keep[b]], rb2[6 * a + 3 * side + b], 1e-15, 1);
    bw_kernel_rectangle_portions(m, mb, l, s, area, xi, eta, &st);
    bw_kernel_condense(3, np, area, xi, eta, 1, c3, kg3, &st);
    bw_interface_condense(m, l, s, 1, c2, kg2, &st);
    for (int a = 0; a < 6; a++)
      for (int b = 0; b < 6; b++) {
        int ia = a == 0 ? 0 : a == 1 ? 1 : a == 5 ? 2 : -1, ib = b == 0 ? 0 : b == 1 ? 1 : b == 5 ? 2 : -1;
        if (ia >= 0 && ib >= 0) expect_close("K_G restricted = 2D K_G", kg3[6 * a + b], kg2[3 * ia + ib], 1e-12, kn * s * l * l);
        else if (ia >= 0 || ib >= 0) expect_close("K_G couples 2D and out-of-plane components", kg3[6 * a + b], 0, 1e-12, kn * s * l * l);
      }
    /* in-plane jumps and stresses: the 2D portions in every b-row */
    for (int a = 0; a < 3; a++) dg2[a] = uniform(-1, 1), dg3[keep[a]] = dg2[a];
    bw_interface_jumps(m, l, dg2, j2, &st);
    bw_kernel_jumps(3, np, xi, eta, dg3, j3, &st);
    for (int p = 0; p < np; p++) {
      expect_close("jump t", j3[3 * p], j2[2 * (p % m)], 1e-15, 1);
      expect_close("jump n", j3[3 * p + 1], j2[2 * (p % m) + 1], 1e-15, 1);
      expect_close("jump b", j3[3 * p + 2], 0, 1e-15, 1);
    }
    for (int p = 0; p < m; p++) r2[2 * p] = uniform(-1, 1), r2[2 * p + 1] = uniform(-1, 1);
    for (int p = 0; p < np; p++) r3[3 * p] = r2[2 * (p % m)], r3[3 * p + 1] = r2[2 * (p % m) + 1], r3[3 * p + 2] = 0;
    bw_interface_resultants(m, l, s, r2, f2, &st);
    bw_kernel_resultants(3, np, area, xi, eta, r3, f3, &st);
    for (int a = 0; a < 6; a++) {
      int ia = a == 0 ? 0 : a == 1 ? 1 : a == 5 ? 2 : -1;
      expect_close("resultants restricted", f3[a], ia >= 0 ? f2[ia] : 0, 1e-14, s * l);
    }
  }
}

static void test_bad(void)
{
  double a[1] = {1}, x[1] = {0}, z[9] = {0}, f[36];
  int    st;
  bw_kernel_condense(4, 1, a, x, x, 1, z, f, &st);
  if (st != BW_KERNEL_BAD_DIMENSION) printf("FAIL dim = 4 gave status %d\n", st), failures++;
  bw_kernel_frame(z, f, &st);
  if (st != BW_KERNEL_BAD_FRAME) printf("FAIL a zero normal gave status %d\n", st), failures++;
  a[0] = -1;
  bw_kernel_resultants(3, 1, a, x, x, z, f, &st);
  if (st != BW_KERNEL_BAD_LENGTH) printf("FAIL a negative area gave status %d\n", st), failures++;
}

int main(int argc, char **argv)
{
  const char *which = argc > 1 ? argv[1] : "all";
  int         ran   = 0;
  if (!strcmp(which, "kg") || !strcmp(which, "all")) {
    test_kg();
    ran++;
  }
  if (!strcmp(which, "frame") || !strcmp(which, "all")) {
    test_frame();
    ran++;
  }
  if (!strcmp(which, "rigid") || !strcmp(which, "all")) {
    test_rigid();
    ran++;
  }
  if (!strcmp(which, "adjoint") || !strcmp(which, "all")) {
    test_adjoint();
    ran++;
  }
  if (!strcmp(which, "restrict") || !strcmp(which, "all")) {
    test_restrict();
    ran++;
  }
  if (!strcmp(which, "bad") || !strcmp(which, "all")) {
    test_bad();
    ran++;
  }
  if (!ran) { /* a mistyped case name must not pass having checked nothing */
    fprintf(stderr, "FAIL unknown case %s\n", which);
    return 1;
  }
  printf("%s: %s\n", which, failures ? "FAILED" : "passed");
  return failures ? 1 : 0;
}
