/* Kernels against closed forms (model.md):
 *   kg      K_G(m) = H G^-1 H^T = diag(kt A, kn A, kn I (1 - 1/m^2)) to 1e-12, m = 1..64
 *           (the paper's Fig. 5: T and N exact for every m, bending error 1/m^2)
 *   rotated D_k and g of an interface at theta = 30 deg against values derived
 *           by hand from D_k = H^T R B; rigid motions of the pair give D q = 0;
 *           S_k = D_k^T G^-1 D_k from the stiffness kernel
 *   recover resultants of the condensed stresses: (T, N, M) = K_G(m) dG        */
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

static void test_kg(void)
{
  const double l = 0.2, s = 0.1, e = 0.01, E = 1e9, nu = 0.2;
  const double kn = E / e, kt = E / (2 * (1 + nu) * e), A = l * s, I = s * l * l * l / 12;
  const double c[2] = {0.1, 0.105}, G[2] = {0.1, 0.105};
  double       d[6 * 128], g[128];

  for (int m = 1; m <= 64; m++) {
    int    st;
    double K[3][3] = {{0}}, want[3] = {kt * A, kn * A, kn * I * (1 - 1.0 / (m * m))}, scale[3] = {kt * A, kn * A, kn * I};
    /* both centroids at G and theta = 0: R B = [-I, I], so columns 3..5 of D are H^T */
    bw_interface_operator(c, c, G, 0.0, l, s, kn, kt, m, d, g, &st);
    if (st) {
      printf("FAIL kernel status %d at m = %d\n", st, m);
      failures++;
      return;
    }
    for (int p = 0; p < 2 * m; p++)
      for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) K[a][b] += d[6 * p + 3 + a] * d[6 * p + 3 + b] / g[p];
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) {
        char what[64];
        snprintf(what, sizeof(what), "K_G(m=%d)[%d][%d]", m, a, b);
        expect_close(what, K[a][b], a == b ? want[a] : 0.0, 1e-12, sqrt(scale[a] * scale[b]));
      }
  }
}

static void test_rotated(void)
{
  const double th = 3.14159265358979323846 / 6, l = 0.2, s = 0.1, kn = 1e11, kt = 4e10;
  const int    m = 2;
  const double ci[2] = {0.0, 0.0}, cj[2] = {0.1, 0.3}, G[2] = {0.05, 0.12};
  const double t[2] = {sqrt(3.0) / 2, 0.5}, n[2] = {-0.5, sqrt(3.0) / 2};
  const double Ap = s * l / m, xp[2] = {-l / 4, l / 4};
  double       d[6 * 4], g[4], k[36], rb[3][6];
  int          st;

  /* R B by hand: rows dt, dn, phi; block i enters with a minus sign */
  const double ai[2] = {G[0] - ci[0], G[1] - ci[1]}, aj[2] = {G[0] - cj[0], G[1] - cj[1]};
  double       rbi[3][3] = {{t[0], t[1], -t[0] * ai[1] + t[1] * ai[0]}, {n[0], n[1], -n[0] * ai[1] + n[1] * ai[0]}, {0, 0, 1}};
  double       rbj[3][3] = {{t[0], t[1], -t[0] * aj[1] + t[1] * aj[0]}, {n[0], n[1], -n[0] * aj[1] + n[1] * aj[0]}, {0, 0, 1}};
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) {
      rb[a][b]     = -rbi[a][b];
      rb[a][3 + b] = rbj[a][b];
    }
  /* spot values computed by hand: the lever term of block j's dt row */
  expect_close("RB[0][5] by hand", rb[0][5], -0.8660254037844386 * (0.12 - 0.3) + 0.5 * (0.05 - 0.1), 1e-15, 1);

  bw_interface_operator(ci, cj, G, th, l, s, kn, kt, m, d, g, &st);
  if (st) {
    printf("FAIL operator status %d\n", st);
    failures++;
    return;
  }
  for (int p = 0; p < m; p++) {
    expect_close("g shear", g[p], Ap / kt, 1e-15, Ap / kt);
    expect_close("g normal", g[m + p], Ap / kn, 1e-15, Ap / kn);
    for (int c = 0; c < 6; c++) {
      char what[64];
      snprintf(what, sizeof(what), "D shear row %d col %d", p, c);
      expect_close(what, d[6 * p + c], Ap * rb[0][c], 1e-14, Ap);
      snprintf(what, sizeof(what), "D normal row %d col %d", p, c);
      expect_close(what, d[6 * (m + p) + c], Ap * (rb[1][c] + xp[p] * rb[2][c]), 1e-14, Ap);
    }
  }
  /* a rigid motion of the pair (a, b, omega about the origin) opens no joint */
  {
    const double a = 1e-3, b = -2e-3, w = 5e-4;
    double       q[6] = {a - w * ci[1], b + w * ci[0], w, a - w * cj[1], b + w * cj[0], w};
    for (int p = 0; p < 2 * m; p++) {
      double dq = 0;
      for (int c = 0; c < 6; c++) dq += d[6 * p + c] * q[c];
      expect_close("D q of a rigid motion", dq, 0.0, 1e-15, Ap * 1e-3);
    }
  }
  /* S_k = D^T G^-1 D */
  bw_interface_stiffness(ci, cj, G, th, l, s, kn, kt, m, k, &st);
  for (int a = 0; a < 6; a++)
    for (int b = 0; b < 6; b++) {
      double want = 0;
      for (int p = 0; p < 2 * m; p++) want += d[6 * p + a] * d[6 * p + b] / g[p];
      expect_close("S_k = D^T G^-1 D", k[6 * a + b], want, 1e-12, kn * l * s);
    }
}

static void test_recover(void)
{
  const double l = 0.4, s = 0.1, kn = 1e11, kt = 4.1e10, A = l * s, I = s * l * l * l / 12, th = 0.3;
  const int    m = 16;
  const double ci[2] = {0.2, 0.05}, cj[2] = {0.25, 0.16}, G[2] = {0.2, 0.105};
  const double qi[3] = {1e-6, -2e-6, 3e-6}, qj[3] = {-4e-6, 5e-6, -6e-6};
  double       r[32], dg[3], f[3];
  int          st;

  bw_interface_stress(ci, cj, G, th, l, s, kn, kt, m, qi, qj, r, &st);
  bw_interface_recover(ci, cj, G, th, l, s, m, qi, qj, r, dg, f, &st);
  if (st) {
    printf("FAIL recover status %d\n", st);
    failures++;
    return;
  }
  expect_close("T = kt A dt", f[0], kt * A * dg[0], 1e-12, fabs(kt * A * dg[0]));
  expect_close("N = kn A dn", f[1], kn * A * dg[1], 1e-12, fabs(kn * A * dg[1]));
  expect_close("M = kn I (1-1/m^2) phi", f[2], kn * I * (1 - 1.0 / (m * m)) * dg[2], 1e-12, fabs(kn * I * dg[2]));
  expect_close("phi = w_j - w_i", dg[2], qj[2] - qi[2], 1e-15, 1e-6);
}

static void test_bad_arguments(void)
{
  const double c[2] = {0, 0};
  double       d[12], g[2];
  int          st;
  bw_interface_operator(c, c, c, 0, 1, 1, 1, 1, 0, d, g, &st);
  if (st != BW_KERNEL_BAD_M) printf("FAIL m = 0 gave status %d\n", st), failures++;
  bw_interface_operator(c, c, c, 0, -1, 1, 1, 1, 1, d, g, &st);
  if (st != BW_KERNEL_BAD_LENGTH) printf("FAIL l < 0 gave status %d\n", st), failures++;
  bw_interface_operator(c, c, c, 0, 1, NAN, 1, 1, 1, d, g, &st);
  if (st != BW_KERNEL_BAD_DEPTH) printf("FAIL s = NaN gave status %d\n", st), failures++;
  bw_interface_operator(c, c, c, 0, 1, 1, 0, 1, 1, d, g, &st);
  if (st != BW_KERNEL_BAD_STIFFNESS) printf("FAIL kn = 0 gave status %d\n", st), failures++;
}

int main(int argc, char **argv)
{
  const char *which = argc > 1 ? argv[1] : "all";
  if (!strcmp(which, "kg") || !strcmp(which, "all")) test_kg();
  if (!strcmp(which, "rotated") || !strcmp(which, "all")) test_rotated();
  if (!strcmp(which, "recover") || !strcmp(which, "all")) test_recover();
  if (!strcmp(which, "bad") || !strcmp(which, "all")) test_bad_arguments();
  printf("%s: %s\n", which, failures ? "FAILED" : "passed");
  return failures ? 1 : 0;
}
