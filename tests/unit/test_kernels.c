/* Kernels against closed forms and hand derivations (model.md):
 *   kg       K_G(m) = sum_p A_p E_p^T C E_p = diag(kt A, kn A, kn I (1 - 1/m^2))
 *            to 1e-12, m = 1..64 (the paper's Fig. 5: T and N exact for every
 *            m, bending error 1/m^2), from one shared tangent (closed form)
 *            and from m per-portion tangents (the sum) alike
 *   rotated  R B and the rows of D^ of an interface at theta = 30 deg against
 *            values derived by hand; rigid motions of the pair give D^ q = 0;
 *            the pair's stiffness (R B)^T K_G (R B) = sum of D^'s rows^T rows
 *   recover  resultants of the portions' elastic stresses = K_G dG; the
 *            jump and resultant kernels are adjoint: sum_p A_p j_p.r_p = dG.H r
 *   tangent  K_G from non-symmetric per-portion tangents against the sum
 *            written out here, and (R B)^T K_G (R B) not symmetrised
 *   bad      every status code
 * Tolerances: 1e-12 relative for sums of m terms of round-off size, 1e-14
 * (1e-15 where a single product) for closed-form single values. */
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

static double xmid(double l, int m, int p) { return -l / 2 + (p + 0.5) * l / m; }

static void test_kg(void)
{
  const double l = 0.2, s = 0.1, e = 0.01, E = 1e9, nu = 0.2;
  const double kn = E / e, kt = E / (2 * (1 + nu) * e), A = l * s, I = s * l * l * l / 12;
  double       c[4 * 64];

  for (int m = 1; m <= 64; m++) {
    for (int nt = 1; nt <= m; nt += (m == 1 ? 1 : m - 1)) {
      double kg[9], want[3] = {kt * A, kn * A, kn * I * (1 - 1.0 / (m * m))}, scale[3] = {kt * A, kn * A, kn * I};
      int    st;
      for (int p = 0; p < nt; p++) {
        c[4 * p]     = kt;
        c[4 * p + 1] = 0;
        c[4 * p + 2] = 0;
        c[4 * p + 3] = kn;
      }
      bw_interface_condense(m, l, s, nt, c, kg, &st);
      if (st) {
        printf("FAIL condense status %d at m = %d\n", st, m);
        failures++;
        return;
      }
      for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
          char what[64];
          snprintf(what, sizeof(what), "K_G(m=%d, nt=%d)[%d][%d]", m, nt, a, b);
          expect_close(what, kg[3 * a + b], a == b ? want[a] : 0.0, 1e-12, sqrt(scale[a] * scale[b]));
        }
    }
  }
}

static void test_rotated(void)
{
  const double th = 3.14159265358979323846 / 6, l = 0.2, s = 0.1, kn = 1e11, kt = 4e10;
  const int    m = 2;
  const double ci[2] = {0.0, 0.0}, cj[2] = {0.1, 0.3}, G[2] = {0.05, 0.12};
  const double t[2] = {sqrt(3.0) / 2, 0.5}, n[2] = {-0.5, sqrt(3.0) / 2};
  const double Ap = s * l / m, at = sqrt(Ap * kt), an = sqrt(Ap * kn);
  double       d[6 * 4], k[36], rb[3][6], rbk[18], kg[9], c[4] = {kt, 0, 0, kn};
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
  bw_interface_compatibility(ci, cj, G, th, rbk, &st);
  for (int a = 0; a < 3; a++)
    for (int c6 = 0; c6 < 6; c6++) expect_close("R B kernel vs hand", rbk[6 * a + c6], rb[a][c6], 1e-15, 1);

  /* rows of D^: pair p is sqrt(A_p) diag(sqrt kt, sqrt kn) E_p R B */
  bw_interface_operator(m, l, s, kt, kn, rbk, d, &st);
  if (st) {
    printf("FAIL operator status %d\n", st);
    failures++;
    return;
  }
  for (int p = 0; p < m; p++)
    for (int c6 = 0; c6 < 6; c6++) {
      char what[64];
      snprintf(what, sizeof(what), "D^ shear row %d col %d", p, c6);
      expect_close(what, d[6 * (2 * p) + c6], at * rb[0][c6], 1e-14, at);
      snprintf(what, sizeof(what), "D^ normal row %d col %d", p, c6);
      expect_close(what, d[6 * (2 * p + 1) + c6], an * (rb[1][c6] + xmid(l, m, p) * rb[2][c6]), 1e-14, an);
    }
  /* a rigid motion of the pair (a, b, omega about the origin) opens no joint */
  {
    const double a = 1e-3, b = -2e-3, w = 5e-4;
    double       q[6] = {a - w * ci[1], b + w * ci[0], w, a - w * cj[1], b + w * cj[0], w};
    for (int p = 0; p < 2 * m; p++) {
      double dq = 0;
      for (int c6 = 0; c6 < 6; c6++) dq += d[6 * p + c6] * q[c6];
      expect_close("D^ q of a rigid motion", dq, 0.0, 1e-15, at * 1e-3);
    }
  }
  /* the pair's stiffness: (R B)^T K_G (R B) = sum of the rows' outer products */
  bw_interface_condense(m, l, s, 1, c, kg, &st);
  bw_interface_stiffness(rbk, kg, k, &st);
  for (int a = 0; a < 6; a++)
    for (int b = 0; b < 6; b++) {
      double want = 0;
      for (int p = 0; p < 2 * m; p++) want += d[6 * p + a] * d[6 * p + b];
      expect_close("S_k = D^T D^", k[6 * a + b], want, 1e-12, kn * l * s);
    }
}

static void test_recover(void)
{
  const double l = 0.4, s = 0.1, kn = 1e11, kt = 4.1e10, A = l * s, I = s * l * l * l / 12, th = 0.3;
  const int    m = 16;
  const double ci[2] = {0.2, 0.05}, cj[2] = {0.25, 0.16}, G[2] = {0.2, 0.105};
  const double qi[3] = {1e-6, -2e-6, 3e-6}, qj[3] = {-4e-6, 5e-6, -6e-6};
  double       rb[18], dg[3] = {0, 0, 0}, j[32], r[32], f[3], work = 0, ap = A / m;
  int          st;

  bw_interface_compatibility(ci, cj, G, th, rb, &st);
  for (int a = 0; a < 3; a++)
    for (int c = 0; c < 3; c++) dg[a] += rb[6 * a + c] * qi[c] + rb[6 * a + 3 + c] * qj[c];
  bw_interface_jumps(m, l, dg, j, &st);
  for (int p = 0; p < m; p++) {
    r[2 * p]     = kt * j[2 * p];
    r[2 * p + 1] = kn * j[2 * p + 1];
    work += ap * (j[2 * p] * r[2 * p] + j[2 * p + 1] * r[2 * p + 1]);
  }
  bw_interface_resultants(m, l, s, r, f, &st);
  if (st) {
    printf("FAIL recover status %d\n", st);
    failures++;
    return;
  }
  expect_close("T = kt A dt", f[0], kt * A * dg[0], 1e-12, fabs(kt * A * dg[0]));
  expect_close("N = kn A dn", f[1], kn * A * dg[1], 1e-12, fabs(kn * A * dg[1]));
  expect_close("M = kn I (1-1/m^2) phi", f[2], kn * I * (1 - 1.0 / (m * m)) * dg[2], 1e-12, fabs(kn * I * dg[2]));
  expect_close("phi = w_j - w_i", dg[2], qj[2] - qi[2], 1e-15, 1e-6);
  expect_close("sum A_p j.r = dG.H r", work, dg[0] * f[0] + dg[1] * f[1] + dg[2] * f[2], 1e-12, fabs(work));
}

static void test_tangent(void)
{
  const double l = 0.3, s = 0.1;
  const int    m = 5;
  double       c[4 * 5], kg[9], want[9] = {0}, rb[18], k[36];
  const double ci[2] = {0, 0}, cj[2] = {0.1, 0.2}, G[2] = {0.05, 0.1};
  int          st;
  /* portions in different states: a non-symmetric (dilatant) one, an open one */
  for (int p = 0; p < m; p++) {
    c[4 * p]     = 4e10 * (1 + p);
    c[4 * p + 1] = p == 2 ? 3e9 : 0;
    c[4 * p + 2] = p == 2 ? -7e9 : 0;
    c[4 * p + 3] = p == 4 ? 0 : 1e11;
  }
  for (int p = 0; p < m; p++) {
    double x = xmid(l, m, p), ap = s * l / m, *cp = c + 4 * p;
    double E[2][3] = {{1, 0, 0}, {0, 1, x}};
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++)
        for (int u = 0; u < 2; u++)
          for (int v = 0; v < 2; v++) want[3 * a + b] += ap * E[u][a] * cp[2 * u + v] * E[v][b];
  }
  bw_interface_condense(m, l, s, m, c, kg, &st);
  for (int e = 0; e < 9; e++) expect_close("K_G from per-portion tangents", kg[e], want[e], 1e-12, 1e11 * l * s);
  bw_interface_compatibility(ci, cj, G, 0.4, rb, &st);
  bw_interface_stiffness(rb, kg, k, &st);
  for (int a = 0; a < 6; a++)
    for (int b = 0; b < 6; b++) {
      double w = 0;
      for (int u = 0; u < 3; u++)
        for (int v = 0; v < 3; v++) w += rb[6 * u + a] * kg[3 * u + v] * rb[6 * v + b];
      expect_close("(R B)^T K_G (R B), not symmetrised", k[6 * a + b], w, 1e-12, 1e11 * l * s);
    }
}

static void test_bad_arguments(void)
{
  const double rb[18] = {0}, dg[3] = {0, 0, 0}, c[4] = {1, 0, 0, 1};
  double       d[24], j[4], f[3], kg[9];
  int          st;
  bw_interface_operator(0, 1, 1, 1, 1, rb, d, &st);
  if (st != BW_KERNEL_BAD_M) printf("FAIL m = 0 gave status %d\n", st), failures++;
  bw_interface_operator(1, -1, 1, 1, 1, rb, d, &st);
  if (st != BW_KERNEL_BAD_LENGTH) printf("FAIL l < 0 gave status %d\n", st), failures++;
  bw_interface_resultants(1, 1, NAN, j, f, &st);
  if (st != BW_KERNEL_BAD_DEPTH) printf("FAIL s = NaN gave status %d\n", st), failures++;
  bw_interface_operator(1, 1, 1, 1, 0, rb, d, &st);
  if (st != BW_KERNEL_BAD_STIFFNESS) printf("FAIL kn = 0 gave status %d\n", st), failures++;
  bw_interface_jumps(2, INFINITY, dg, j, &st);
  if (st != BW_KERNEL_BAD_LENGTH) printf("FAIL l = inf gave status %d\n", st), failures++;
  bw_interface_condense(3, 1, 1, 2, c, kg, &st);
  if (st != BW_KERNEL_BAD_M) printf("FAIL 2 tangents for 3 portions gave status %d\n", st), failures++;
}

int main(int argc, char **argv)
{
  const char *which = argc > 1 ? argv[1] : "all";
  int         ran   = 0;
  if (!strcmp(which, "kg") || !strcmp(which, "all")) {
    test_kg();
    ran++;
  }
  if (!strcmp(which, "rotated") || !strcmp(which, "all")) {
    test_rotated();
    ran++;
  }
  if (!strcmp(which, "recover") || !strcmp(which, "all")) {
    test_recover();
    ran++;
  }
  if (!strcmp(which, "tangent") || !strcmp(which, "all")) {
    test_tangent();
    ran++;
  }
  if (!strcmp(which, "bad") || !strcmp(which, "all")) {
    test_bad_arguments();
    ran++;
  }
  if (!ran) { /* a mistyped case name must not pass having checked nothing */
    fprintf(stderr, "FAIL unknown case %s\n", which);
    return 1;
  }
  printf("%s: %s\n", which, failures ? "FAILED" : "passed");
  return failures ? 1 : 0;
}
