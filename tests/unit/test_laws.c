/* Per-portion joint laws (include/blockwall/laws.h) against closed forms and invariants:
 *   elastic     bw_law_elastic and bw_law_coulomb inside the surfaces: r = C (j - jpl), tangent C
 *   cutoff      perfectly plastic opening past ft/kn: rn = ft, opening = dn - ft/kn, mode 1
 *   coulomb     perfectly plastic sliding under a fixed compressive dn, both signs, psi = 0, 0.2, phi:
 *               rt = +-(c - rn tanphi), opening = tanpsi |slip|, rn = kn (dn - opening), mode 2
 *   corner      trial = corner + C (a m1 + b m2): r at the corner, multipliers a, b recovered, mode 3
 *   apex        the cone's apex (perfectly plastic and after c softened), and the lowered
 *               cut-off of tanpsi = 0
 *   notension   ft = c = 0 opened: r = 0 exactly, mode 3, zero tangent; closed: friction only
 *   soft_mode1  opening in many steps: rn = ft(k1) and int rn d(opening) -> GfI (second order)
 *   soft_mode2  sliding in many steps: rt + rn tanphi = c(k2) and int c d(slip) -> GfII
 *   unload      from plastic states a smaller jump is elastic with C, state unchanged
 *   tangent     consistent tangent against central differences of the kernel, every regime
 *   property    10^4 random trials and states: admissible stress, multipliers >= 0, k non-decreasing
 *   bad         statuses of bad parameters, jumps and states
 * Three dimensions (ns = 3, the circular cone):
 *   cone3d      sliding pushed in 8 directions of the joint's plane: |tau| = c - rn tanphi in each
 *               (closed form), tau and the slip along the push, opening tanpsi k2
 *   extrude3d   ns = 3 without b gives the ns = 2 law (10^4 random cases)
 *   rotate3d    rotating jump and slip about n rotates stress, slip and tangent (10^4 cases)
 *   property3d  admissibility, flow rule and the 3x3 tangent against differences (10^4 cases)
 *   bad3d       ns not 2 or 3, non-finite b jump or slip; the elastic 3D law */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "blockwall/laws.h"

static int failures = 0;

#define CHECK(cond, ...) \
  do { \
    if (!(cond)) { \
      failures++; \
      printf("FAIL %s:%d: ", __FILE__, __LINE__); \
      printf(__VA_ARGS__); \
      printf("\n"); \
    } \
  } while (0)

static void expect_close(const char *what, double got, double want, double tol, double scale)
{
  double err = fabs(got - want) / (scale > 0 ? scale : 1);
  if (!(err <= tol)) {
    printf("FAIL %s: got %.17g, want %.17g (relative error %.3e > %.1e)\n", what, got, want, err, tol);
    failures++;
  }
}

enum { SLIP = BW_LAW_STATE_SLIP, OPEN = BW_LAW_STATE_OPENING, K1 = BW_LAW_STATE_K1, K2 = BW_LAW_STATE_K2 };

static const double KT = 4e10, KN = 1e11; /* [N/m^3]: E = 1 GPa over a 10 mm joint */

typedef struct {
  double      r[2], T[4], s[BW_LAW_NSTATE];
  signed char mode;
  int         status;
} Ret;

static Ret law(const double par[], const double s_in[], double dt, double dn)
{
  Ret    o;
  double j[2] = {dt, dn};
  memset(&o, 0, sizeof(o));
  bw_law_coulomb(2, 1, par, s_in, j, o.r, o.T, o.s, &o.mode, &o.status);
  return o;
}

static void set_par(double par[], double ft, double c, double tphi, double tpsi, double gfI, double gfII)
{
  par[BW_LAW_PAR_KT]     = KT;
  par[BW_LAW_PAR_KN]     = KN;
  par[BW_LAW_PAR_FT]     = ft;
  par[BW_LAW_PAR_C]      = c;
  par[BW_LAW_PAR_TANPHI] = tphi;
  par[BW_LAW_PAR_TANPSI] = tpsi;
  par[BW_LAW_PAR_GFI]    = gfI;
  par[BW_LAW_PAR_GFII]   = gfII;
  par[BW_LAW_PAR_FC]     = 0; /* no cap */
  par[BW_LAW_PAR_CSS]    = 9;
  par[BW_LAW_PAR_GFC]    = -1;
  par[BW_LAW_PAR_KP]     = 0;
}

static double strength(double s0, double gf, double k) { return gf > 0 ? s0 * exp(-s0 * k / gf) : s0; }

/* f1, f2+, f2- at stress r and internal variables (k1, k2) of state s */
static void surfaces(const double par[], const double r[2], const double s[], double f[3])
{
  double ft = strength(par[BW_LAW_PAR_FT], par[BW_LAW_PAR_GFI], s[K1]);
  double c  = strength(par[BW_LAW_PAR_C], par[BW_LAW_PAR_GFII], s[K2]);
  double tp = par[BW_LAW_PAR_TANPHI];
  f[0]      = r[1] - ft;
  f[1]      = r[0] + r[1] * tp - c;
  f[2]      = -r[0] + r[1] * tp - c;
}

static double maxabs4(const double t[4])
{
  double m = 0;
  for (int i = 0; i < 4; i++) m = fmax(m, fabs(t[i]));
  return m;
}

static void test_elastic(void)
{
  /* Same floating-point operations as the kernels: 1e-15 relative is round-off. */
  enum { NS = BW_LAW_NSTATE };
  double       par[BW_LAW_NPAR], r[6], T[12], s_out[3 * NS];
  signed char  mode[3];
  int          st;
  const double s_in[3 * NS] = {1e-5, 2e-5, 3e-5, 4e-5, 0, -2e-5, 0, 0, 1e-4, 0, 0, 0, 0, 0, 0};
  const double j[6]     = {1.5e-5, 1e-5, -3e-5, 2e-6, 7e-7, -4e-7};
  set_par(par, 2e5, 3e5, 0.75, 0.2, 12, 50);
  bw_law_elastic(2, 3, par, s_in, j, r, T, s_out, mode, &st);
  CHECK(st == BW_LAW_OK, "elastic status %d", st);
  for (int p = 0; p < 3; p++) {
    expect_close("elastic rt", r[2 * p], KT * (j[2 * p] - s_in[NS * p + SLIP]), 1e-15, KT * fabs(j[2 * p] - s_in[NS * p]));
    expect_close("elastic rn", r[2 * p + 1], KN * (j[2 * p + 1] - s_in[NS * p + OPEN]), 1e-15, KN * fabs(j[2 * p + 1] - s_in[NS * p + 1]));
    CHECK(T[4 * p] == KT && T[4 * p + 1] == 0 && T[4 * p + 2] == 0 && T[4 * p + 3] == KN, "elastic tangent of portion %d", p);
    CHECK(!memcmp(s_in + NS * p, s_out + NS * p, NS * sizeof(double)) && mode[p] == 0, "elastic state of portion %d", p);
  }
  /* the plastic law inside its surfaces (intact, and softened with a plastic jump) */
  for (int p = 0; p < 3; p += 2) {
    Ret o = law(par, s_in + NS * p, j[2 * p] * 0.1 + s_in[NS * p], j[2 * p + 1] * 0.1 + s_in[NS * p + 1]);
    CHECK(o.status == 0 && o.mode == 0, "coulomb inside: status %d mode %d", o.status, o.mode);
    expect_close("coulomb inside rt", o.r[0], KT * (j[2 * p] * 0.1 + s_in[NS * p] - s_in[NS * p]), 1e-15, fabs(o.r[0]));
    expect_close("coulomb inside rn", o.r[1], KN * (j[2 * p + 1] * 0.1 + s_in[NS * p + 1] - s_in[NS * p + 1]), 1e-15, fabs(o.r[1]));
    CHECK(o.T[0] == KT && o.T[1] == 0 && o.T[2] == 0 && o.T[3] == KN, "coulomb inside: tangent not C");
    CHECK(!memcmp(o.s, s_in + NS * p, sizeof(o.s)), "coulomb inside: state changed");
  }
}

static void test_cutoff(void)
{
  /* Perfectly plastic cut-off; rt = kt dt keeps the cone inactive (|rt| + ft tanphi < c).
   * rn = ft is set, opening = dn - rn/kn one subtraction: 1e-15 of the jump; k1 sums the
   * multipliers of 20 steps: 1e-13. */
  double       par[BW_LAW_NPAR], s[BW_LAW_NSTATE] = {0, 0, 0, 0};
  const double ft = 2e5, dt = 1e-6;
  set_par(par, ft, 3e5, 0.75, 0.2, 0, 0);
  for (int i = 0; i <= 20; i++) {
    double dn = i * 10 * ft / KN / 20;
    Ret    o  = law(par, s, dt, dn);
    CHECK(o.status == 0, "cutoff status %d", o.status);
    expect_close("cutoff rt = kt dt", o.r[0], KT * dt, 1e-15, KT * dt);
    if (dn <= ft / KN * (1 + 1e-12)) { /* step 2 is the elastic limit itself, up to rounding */
      CHECK(o.mode == 0, "cutoff: step %d below ft/kn has mode %d", i, o.mode);
      expect_close("cutoff elastic rn", o.r[1], KN * dn, 1e-15, ft);
    } else {
      CHECK(o.mode == 1, "cutoff: step %d has mode %d", i, o.mode);
      expect_close("cutoff rn = ft", o.r[1], ft, 1e-15, ft);
      expect_close("cutoff opening = dn - ft/kn", o.s[OPEN], dn - ft / KN, 1e-15, dn);
      expect_close("cutoff k1 = opening", o.s[K1], o.s[OPEN], 1e-13, dn);
      CHECK(o.s[SLIP] == 0 && o.s[K2] == 0, "cutoff: slip %g k2 %g", o.s[SLIP], o.s[K2]);
      CHECK(o.T[0] == KT && o.T[1] == 0 && o.T[2] == 0 && fabs(o.T[3]) <= 1e-15 * KN, "cutoff tangent (%g %g %g %g)", o.T[0], o.T[1], o.T[2], o.T[3]);
    }
    memcpy(s, o.s, sizeof(s));
  }
}

static void test_coulomb(void)
{
  /* Perfectly plastic sliding at fixed dn = -2e-5 (rn = -2 MPa before dilatancy), dt in 30
   * steps to +-3e-4. Stresses on the surface to round-off (1e-14 of c - rn tanphi); the path's
   * sums of multipliers to 1e-12. The final state against the one-step closed form
   * slip = (kt |dt| + kn dn tanphi - c) / (kt + kn tanphi tanpsi) (a linear surface with a
   * constant flow: backward Euler is exact and path-independent under monotonic loading). */
  const double c = 3e5, tphi = 0.75, dn = -2e-5, tpsis[3] = {0, 0.2, 0.75};
  for (int q = 0; q < 3; q++)
    for (int sgn = -1; sgn <= 1; sgn += 2) {
      double par[BW_LAW_NPAR], s[BW_LAW_NSTATE] = {0, 0, 0, 0}, tpsi = tpsis[q], dt = 0;
      Ret    o;
      set_par(par, 2e5, c, tphi, tpsi, 0, 0);
      for (int i = 0; i <= 30; i++) {
        dt = sgn * i * 3e-4 / 30;
        o  = law(par, s, dt, dn);
        CHECK(o.status == 0, "coulomb status %d", o.status);
        if (KT * fabs(dt) <= c - KN * dn * tphi) {
          CHECK(o.mode == 0, "coulomb: elastic step %d has mode %d", i, o.mode);
        } else {
          double scale = c - o.r[1] * tphi;
          CHECK(o.mode == 2, "coulomb psi %g sign %d step %d: mode %d", tpsi, sgn, i, o.mode);
          CHECK(o.r[1] < 0, "coulomb: rn = %g not compressive", o.r[1]);
          expect_close("coulomb rt = +-(c - rn tanphi)", o.r[0], sgn * (c - o.r[1] * tphi), 1e-14, scale);
          expect_close("coulomb slip = dt - rt/kt", o.s[SLIP], dt - o.r[0] / KT, 1e-14, fabs(dt));
          expect_close("coulomb opening = tanpsi |slip|", o.s[OPEN], tpsi * fabs(o.s[SLIP]), 1e-12, fabs(o.s[SLIP]));
          expect_close("coulomb rn = kn (dn - opening)", o.r[1], KN * (dn - o.s[OPEN]), 1e-14, fabs(o.r[1]));
          expect_close("coulomb k2 = |slip|", o.s[K2], fabs(o.s[SLIP]), 1e-12, fabs(o.s[SLIP]));
          CHECK(o.s[K1] == 0, "coulomb: k1 = %g", o.s[K1]);
        }
        memcpy(s, o.s, sizeof(s));
      }
      expect_close("coulomb slip, closed form", o.s[SLIP], sgn * (KT * fabs(dt) + KN * dn * tphi - c) / (KT + KN * tphi * tpsi), 1e-12, fabs(dt));
    }
}

static void test_corner(void)
{
  /* Trial = corner + C (a m1 + b m2+-) with a = 2e-5, b = 1e-5: the return is the corner
   * (rn = ft, rt = +-(c - ft tanphi)) with multipliers (a, b) >= 0, recovered from k1, k2
   * to 1e-12 (differences of jumps of 1e-5). Perfectly plastic: the tangent is zero to
   * round-off (1e-12 kn). */
  const double ft = 2e5, c = 3e5, tphi = 0.75, a = 2e-5, b = 1e-5, tpsis[3] = {0, 0.2, 0.75};
  for (int q = 0; q < 3; q++)
    for (int sgn = -1; sgn <= 1; sgn += 2) {
      double par[BW_LAW_NPAR], s0[BW_LAW_NSTATE] = {0, 0, 0, 0}, f[3], tpsi = tpsis[q];
      double rtc = sgn * (c - ft * tphi);
      set_par(par, ft, c, tphi, tpsi, 0, 0);
      Ret o = law(par, s0, rtc / KT + sgn * b, ft / KN + a + tpsi * b);
      CHECK(o.status == 0 && o.mode == 3, "corner psi %g sign %d: status %d mode %d", tpsi, sgn, o.status, o.mode);
      expect_close("corner rn", o.r[1], ft, 1e-15, ft);
      expect_close("corner rt", o.r[0], rtc, 1e-15, c);
      surfaces(par, o.r, o.s, f);
      CHECK(fabs(f[0]) <= 1e-15 * c && fabs(f[sgn > 0 ? 1 : 2]) <= 1e-15 * c && f[sgn > 0 ? 2 : 1] < 0, "corner surfaces %g %g %g", f[0], f[1], f[2]);
      expect_close("corner multiplier dl1 = a", o.s[K1], a, 1e-12, a);
      expect_close("corner multiplier dl2 = b", o.s[K2], b, 1e-12, b);
      CHECK(o.s[K1] >= 0 && o.s[K2] >= 0, "corner: negative multiplier");
      expect_close("corner slip", o.s[SLIP], sgn * b, 1e-12, b);
      expect_close("corner opening = a + tanpsi b", o.s[OPEN], a + tpsi * b, 1e-12, a);
      CHECK(maxabs4(o.T) <= 1e-12 * KN, "corner tangent not zero: %g", maxabs4(o.T));
    }
}

static void test_apex(void)
{
  const double tphi = 0.75;
  double       par[BW_LAW_NPAR], f[3];
  /* 1. Perfectly plastic, apex rn = c/tanphi = 2e5 below ft = 5e5: trial = apex + C (a m2+ + b m2-),
   *    a = 3e-5, b = 1e-5: r = apex, f2+ = f2- = 0, multipliers from k2 = a + b and slip = a - b,
   *    mode 2, zero tangent. */
  for (int q = 0; q < 2; q++) {
    double tpsi = q ? 0.75 : 0.2, a = 3e-5, b = 1e-5, s0[BW_LAW_NSTATE] = {0, 0, 0, 0};
    set_par(par, 5e5, 1.5e5, tphi, tpsi, 0, 0);
    Ret o = law(par, s0, a - b, 2e5 / KN + tpsi * (a + b));
    CHECK(o.status == 0 && o.mode == 2, "apex psi %g: status %d mode %d", tpsi, o.status, o.mode);
    CHECK(o.r[0] == 0, "apex rt = %g", o.r[0]);
    expect_close("apex rn = c/tanphi", o.r[1], 2e5, 1e-15, 2e5);
    surfaces(par, o.r, o.s, f);
    CHECK(fabs(f[1]) <= 1e-15 * 2e5 && fabs(f[2]) <= 1e-15 * 2e5 && f[0] < 0, "apex surfaces %g %g %g", f[0], f[1], f[2]);
    expect_close("apex dl2+ = (k2 + slip)/2", 0.5 * (o.s[K2] + o.s[SLIP]), a, 1e-12, a);
    expect_close("apex dl2- = (k2 - slip)/2", 0.5 * (o.s[K2] - o.s[SLIP]), b, 1e-12, a);
    expect_close("apex opening = tanpsi k2", o.s[OPEN], tpsi * (a + b), 1e-12, a);
    CHECK(o.s[K1] == 0 && maxabs4(o.T) <= 1e-12 * KN, "apex: k1 %g, tangent %g", o.s[K1], maxabs4(o.T));
  }
  /* 2. After c softened (k2 = 5e-4: c = 3e5 e^-3, apex 2.0e4 below ft = 2e5), pure opening
   *    dn = 1e-4: rt = 0, rn = c(k2)/tanphi, the opening is dilatancy of the apex return,
   *    mode 2. rn is set from the returned k2 (1e-14); the multiplier sum from the Newton
   *    (residual 1e-14 of the 1e7 Pa trial stress over kn: 1e-12 of the opening). */
  {
    double s[BW_LAW_NSTATE] = {1e-5, 0, 0, 5e-4}, tpsi = 0.2;
    set_par(par, 2e5, 3e5, tphi, tpsi, 12, 50);
    Ret o = law(par, s, 1e-5, 1e-4);
    CHECK(o.status == 0 && o.mode == 2, "softened apex: status %d mode %d", o.status, o.mode);
    CHECK(o.r[0] == 0, "softened apex rt = %g", o.r[0]);
    expect_close("softened apex rn = c(k2)/tanphi", o.r[1], strength(3e5, 50, o.s[K2]) / tphi, 1e-14, o.r[1]);
    CHECK(o.s[K2] > s[K2] && o.s[K1] == 0, "softened apex: k1 %g k2 %g", o.s[K1], o.s[K2]);
    expect_close("softened apex: no slip", o.s[SLIP], s[SLIP], 1e-15, 1e-5);
    expect_close("softened apex: opening = tanpsi dk2", o.s[OPEN], tpsi * (o.s[K2] - s[K2]), 1e-12, o.s[OPEN]);
    surfaces(par, o.r, o.s, f);
    CHECK(fabs(f[1]) <= 1e-14 * 3e5 && fabs(f[2]) <= 1e-14 * 3e5 && f[0] < 0, "softened apex surfaces %g %g %g", f[0], f[1], f[2]);
  }
  /* 3. tanpsi = 0: the cone has no normal flow, so a trial above an apex lying below the
   *    cut-off returns with the cut-off lowered to the apex: r = (0, c/tanphi), slip and
   *    opening the trial's excess, k1 = opening, k2 = |slip|, mode 3. Perfectly plastic
   *    and with c softening (k2 = |slip| softens the apex: rn = c(k2)/tanphi). */
  for (int soft = 0; soft < 2; soft++) {
    double s0[BW_LAW_NSTATE] = {0, 0, 0, 0}, sl = -2e-5, op = 3e-5;
    set_par(par, 5e5, 1.5e5, tphi, 0, 0, soft ? 50 : 0);
    Ret    o    = law(par, s0, sl, 2e5 / KN + op);
    double apex = strength(1.5e5, soft ? 50 : 0, fabs(sl)) / tphi;
    CHECK(o.status == 0 && o.mode == 3, "lowered cut-off: status %d mode %d", o.status, o.mode);
    CHECK(o.r[0] == 0, "lowered cut-off rt = %g", o.r[0]);
    expect_close("lowered cut-off rn = c(k2)/tanphi", o.r[1], apex, 1e-15, apex);
    expect_close("lowered cut-off slip", o.s[SLIP], sl, 1e-15, op);
    expect_close("lowered cut-off opening", o.s[OPEN], 2e5 / KN + op - apex / KN, 1e-14, op);
    expect_close("lowered cut-off k1 = opening", o.s[K1], o.s[OPEN], 1e-14, op);
    expect_close("lowered cut-off k2 = |slip|", o.s[K2], fabs(sl), 1e-15, op);
    if (!soft) {
      /* continuous with the sliding return just below the apex level (0.01 Pa below) */
      Ret u = law(par, s0, sl, 2e5 / KN - 1e-13);
      CHECK(u.mode == 2 && fabs(u.r[0] - o.r[0]) <= 0.02 && fabs(u.r[1] - o.r[1]) <= 0.02,
            "lowered cut-off not continuous with sliding below the apex: (%g %g) vs (%g %g)", u.r[0], u.r[1], o.r[0], o.r[1]);
    }
  }
}

static void test_notension(void)
{
  /* ft = c = 0: opened (dn > 0, |dt| <= dn / tanpsi) the stress is exactly zero, jpl = j,
   * mode 3, zero tangent, and the plastic jump splits into k1 + tanpsi k2 = opening,
   * k2 = |slip|. Closed and sliding: rt = -rn tanphi. */
  const double tphi = 0.7, tpsis[3] = {0, 0.3, 0.7};
  for (int q = 0; q < 3; q++)
    for (int soft = 0; soft < 2; soft++)
      for (int sgn = -1; sgn <= 1; sgn += 2) {
        double par[BW_LAW_NPAR], tpsi = tpsis[q], s[BW_LAW_NSTATE] = {3e-6, 1e-6, 1e-6, 5e-6};
        double dt = sgn * 2e-5, dn = 1e-4;
        set_par(par, 0, 0, tphi, tpsi, soft ? 12 : 0, soft ? 50 : 0);
        Ret o = law(par, s, dt, dn);
        CHECK(o.status == 0 && o.mode == 3, "no-tension open psi %g: status %d mode %d", tpsi, o.status, o.mode);
        CHECK(o.r[0] == 0 && o.r[1] == 0, "no-tension open: r = (%g %g)", o.r[0], o.r[1]);
        CHECK(o.s[SLIP] == dt && o.s[OPEN] == dn, "no-tension open: jpl = (%g %g)", o.s[SLIP], o.s[OPEN]);
        CHECK(maxabs4(o.T) <= 1e-12 * KN, "no-tension open: tangent %g", maxabs4(o.T));
        expect_close("no-tension k2 = |d slip|", o.s[K2] - s[K2], fabs(dt - s[SLIP]), 1e-12, fabs(dt));
        expect_close("no-tension k1 + tanpsi k2 = d opening", o.s[K1] - s[K1] + tpsi * (o.s[K2] - s[K2]), dn - s[OPEN], 1e-12, dn);
        /* closed, sliding: rn = kn (dn - opening) < 0 */
        o = law(par, s, s[SLIP] + sgn * 1e-4, s[OPEN] - 1e-5);
        CHECK(o.status == 0 && o.mode == 2, "no-tension sliding: status %d mode %d", o.status, o.mode);
        expect_close("no-tension sliding rt = -rn tanphi", o.r[0], -sgn * o.r[1] * tphi, 1e-14, fabs(o.r[0]));
      }
}

/* Opening (mode I) or sliding at fixed compression (mode II) in n steps of the jump over
 * 30 characteristic lengths l = Gf/s0 past the elastic limit. Returns the dissipated
 * softening energy by the trapezoidal rule over the plastic jump, and by backward Euler's
 * own sum (end-of-step stress), both relative to Gf; *hmax = largest step of k over l. */
static void soften(int mode2, int n, double *err_trap, double *err_be, double *hmax)
{
  const double ft = 2e5, c = 3e5, tphi = 0.75, gfI = 12, gfII = 50, dn2 = -1e-5;
  double       par[BW_LAW_NPAR], s[BW_LAW_NSTATE] = {0, 0, 0, 0};
  const double s0 = mode2 ? c : ft, gf = mode2 ? gfII : gfI, l = gf / s0;
  /* the elastic limit as the first point: there the stress is s0 and no plastic jump */
  const double j0 = mode2 ? (c - KN * dn2 * tphi) / KT : ft / KN, h = 30 * l / n;
  double       prev = s0, e_trap = 0, e_be = 0;
  set_par(par, ft, c, tphi, 0, gfI, gfII);
  *hmax = 0;
  for (int i = 1; i <= n; i++) {
    Ret    o    = mode2 ? law(par, s, j0 + i * h, dn2) : law(par, s, 0, j0 + i * h);
    int    kv   = mode2 ? K2 : K1, jv = mode2 ? SLIP : OPEN;
    double k    = o.s[kv], dk = o.s[kv] - s[kv], djpl = o.s[jv] - s[jv];
    double want = s0 * exp(-s0 * k / gf);
    /* the softening part of the stress: rn, or rt + rn tanphi (= c(k2)) */
    double sig = mode2 ? o.r[0] + o.r[1] * tphi : o.r[1];
    CHECK(o.status == 0 && o.mode == (mode2 ? 2 : 1), "softening mode %d step %d: status %d mode %d", mode2 + 1, i, o.status, o.mode);
    /* The stress is set from the returned k: rn to 1e-12 of ft(k1) itself. In mode II rt =
     * c(k2) - rn tanphi, with c(k2) down to 1e-13 of the friction part rn tanphi (7.5e5 Pa):
     * rt to 1e-14 of |rt| (c(k2) alone would only be recovered to eps |rn tanphi|). */
    if (mode2)
      expect_close("rt = c0 exp(-c0 k2/GfII) - rn tanphi", o.r[0], want - o.r[1] * tphi, 1e-14, fabs(o.r[0]));
    else
      expect_close("rn = ft0 exp(-ft0 k1/GfI)", o.r[1], want, 1e-12, want);
    /* d jpl = dk up to the local Newton's residual, 1e-14 of the trial stress (~1e6 Pa) over
     * the stiffness: ~1e-19 m against steps of 6e-6 m */
    expect_close("plastic jump = k increment", djpl, dk, 1e-12, h);
    if (mode2) expect_close("mode II: rn fixed", o.r[1], KN * dn2, 1e-15, KN * fabs(dn2));
    e_trap += 0.5 * (prev + sig) * djpl;
    e_be += sig * djpl;
    *hmax = fmax(*hmax, dk / l);
    prev = sig;
    memcpy(s, o.s, sizeof(s));
  }
  *err_trap = fabs(e_trap - gf) / gf;
  *err_be   = fabs(e_be - gf) / gf;
}

static void test_softening(int mode2)
{
  /* The trapezoidal rule on s0 exp(-k/l) with steps h has relative error (h/l)^2/12 (plus the
   * tail exp(-30) = 1e-13): we accept 1.2 (hmax/l)^2/12 and ask the error to fall by 4 +- 10%
   * when the steps halve (second order: the kernel puts every state on the exact curve).
   * Backward Euler's own dissipation sum is first order (error ~ h/(2l)): printed, and
   * asked to halve. */
  double et1, eb1, h1, et2, eb2, h2;
  soften(mode2, 300, &et1, &eb1, &h1);
  soften(mode2, 600, &et2, &eb2, &h2);
  printf("mode %s: energy error trapezoid %.3e -> %.3e (ratio %.2f), backward Euler %.3e -> %.3e (ratio %.2f), hmax/l %.3f\n",
         mode2 ? "II" : "I", et1, et2, et1 / et2, eb1, eb2, eb1 / eb2, h1);
  CHECK(et1 <= 1.2 * h1 * h1 / 12 + 1e-12 && et2 <= 1.2 * h2 * h2 / 12 + 1e-12, "energy error above (h/l)^2/12");
  CHECK(fabs(et1 / et2 - 4) <= 0.4, "trapezoid energy not second order: ratio %g", et1 / et2);
  CHECK(fabs(eb1 / eb2 - 2) <= 0.2, "backward Euler energy not first order: ratio %g", eb1 / eb2);
}

static void test_unload(void)
{
  /* From plastic states (sliding with cohesion softening and dilatancy; opening with tension
   * softening), a smaller jump is elastic: r = C (j - jpl) with the initial C, state bitwise
   * unchanged, mode 0. Reloading to the plastic point is elastic again (its trial stress is
   * the returned one to round-off), and loading past it continues as if never unloaded. */
  double par[BW_LAW_NPAR];
  set_par(par, 2e5, 3e5, 0.75, 0.2, 12, 50);
  for (int open = 0; open < 2; open++) {
    double s[BW_LAW_NSTATE] = {0, 0, 0, 0}, dn = open ? 0 : -2e-5, dt = open ? 1e-6 : 0;
    Ret    o;
    for (int i = 1; i <= 10; i++) {
      if (open)
        dn = i * 3e-5;
      else
        dt = i * 2e-5;
      o = law(par, s, dt, dn);
      CHECK(o.status == 0, "unload: loading step %d status %d", i, o.status);
      memcpy(s, o.s, sizeof(s));
    }
    CHECK(o.mode == (open ? 1 : 2), "unload: the last loading step has mode %d", o.mode);
    Ret    top = o;
    double dtu = open ? dt : 0.8 * dt, dnu = open ? 0.9 * dn : dn;
    Ret    u   = law(par, s, dtu, dnu);
    CHECK(u.status == 0 && u.mode == 0, "unload: mode %d", u.mode);
    CHECK(!memcmp(u.s, s, sizeof(s)), "unload: state changed");
    expect_close("unload rt = kt (dt - slip)", u.r[0], KT * (dtu - s[SLIP]), 1e-15, fabs(u.r[0]) + 1);
    expect_close("unload rn = kn (dn - opening)", u.r[1], KN * (dnu - s[OPEN]), 1e-15, fabs(u.r[1]) + 1);
    CHECK(u.T[0] == KT && u.T[1] == 0 && u.T[2] == 0 && u.T[3] == KN, "unload tangent not C");
    Ret back = law(par, u.s, dt, dn);
    CHECK(back.mode == 0 && !memcmp(back.s, s, sizeof(s)), "reload to the plastic point: mode %d", back.mode);
    /* the stored jpl = j - r/C is rounded: eps of C j (3e7 Pa here), not of r (1e3 Pa) */
    expect_close("reload rt", back.r[0], top.r[0], 1e-15, KT * fabs(dt) + KN * fabs(dn));
    expect_close("reload rn", back.r[1], top.r[1], 1e-15, KT * fabs(dt) + KN * fabs(dn));
    Ret on = law(par, back.s, open ? dt : 1.1 * dt, open ? 1.1 * dn : dn), direct = law(par, s, open ? dt : 1.1 * dt, open ? 1.1 * dn : dn);
    CHECK(on.mode == (open ? 1 : 2) && !memcmp(on.s, direct.s, sizeof(s)) && !memcmp(on.r, direct.r, sizeof(on.r)), "reload past the plastic point differs");
  }
}

/* Central differences of the kernel: step h = 1e-6 of the jump. Errors relative to
 * max(kt, kn): round-off eps |r| / h ~ 1e-10, the local Newton's residual 1e-14 |r_tr| / h
 * ~ 1e-8, truncation (h / l)^2 ~ 1e-12 (l = Gf / s0 >= 6e-5 m, jumps <= 1e-3 m). We accept
 * 1e-6: a softening term of the tangent (>= 1e-3 kn here) is then checked to 1e-3 or better.
 * The mode is checked at the point and both perturbations: no region boundary is crossed. */
static double fd_check(const char *name, const double par[], const double s[], double dt, double dn, int want_mode, double *asym)
{
  Ret    o = law(par, s, dt, dn);
  double h = 1e-6 * fmax(fmax(fabs(dt), fabs(dn)), 1e-6), err = 0, fd[4];
  CHECK(o.status == 0 && o.mode == want_mode, "tangent %s: status %d mode %d (want %d)", name, o.status, o.mode, want_mode);
  for (int c = 0; c < 2; c++) {
    Ret p = law(par, s, dt + (c == 0) * h, dn + (c == 1) * h), m = law(par, s, dt - (c == 0) * h, dn - (c == 1) * h);
    CHECK(p.mode == want_mode && m.mode == want_mode, "tangent %s: perturbation changes the mode (%d %d)", name, p.mode, m.mode);
    for (int row = 0; row < 2; row++) fd[2 * row + c] = (p.r[row] - m.r[row]) / (2 * h);
  }
  for (int i = 0; i < 4; i++) err = fmax(err, fabs(fd[i] - o.T[i]) / KN);
  *asym = fabs(o.T[1] - o.T[2]) / KN;
  printf("tangent %-34s mode %d  T/kn = [%+.6e %+.6e; %+.6e %+.6e]  |T - T_fd|/kn = %.2e\n", name, o.mode, o.T[0] / KN, o.T[1] / KN, o.T[2] / KN,
         o.T[3] / KN, err);
  CHECK(err <= 1e-6, "tangent %s: error %.3e", name, err);
  return err;
}

static void test_tangent(void)
{
  const double ft = 2e5, c = 3e5, tphi = 0.75;
  double       par[BW_LAW_NPAR], asym, worst = 0;
  struct {
    const char *name;
    double      ft, c, tphi, tpsi, gfI, gfII, s[BW_LAW_NSTATE], dt, dn;
    int         mode;
    int         symmetric; /* 1: tangent symmetric (psi = phi), 0: not (psi != phi), -1: either */
  } cases[] = {
    {"elastic", ft, c, tphi, 0.2, 12, 50, {0, 0, 0, 0}, 1e-6, -1e-6, 0, 1},
    {"cut-off", ft, c, tphi, 0.2, 0, 0, {0, 0, 0, 0}, 1e-6, 1e-5, 1, 1},
    {"cut-off softening", ft, c, tphi, 0.2, 12, 50, {0, 1e-4, 1e-4, 0}, 1e-6, 1.1e-4, 1, 1},
    {"cut-off softening psi=phi", ft, c, tphi, tphi, 12, 50, {2e-6, 1e-4, 1e-4, 0}, -1e-6, 1.3e-4, 1, 1},
    {"Coulomb+ psi=0.2", ft, c, tphi, 0.2, 0, 0, {0, 0, 0, 0}, 2e-4, -2e-5, 2, 0},
    {"Coulomb- psi=0.2", ft, c, tphi, 0.2, 0, 0, {0, 0, 0, 0}, -2e-4, -2e-5, 2, 0},
    {"Coulomb+ psi=0", ft, c, tphi, 0, 0, 0, {0, 0, 0, 0}, 2e-4, -2e-5, 2, 0},
    {"Coulomb- psi=phi", ft, c, tphi, tphi, 0, 0, {0, 0, 0, 0}, -2e-4, -2e-5, 2, 1},
    {"Coulomb+ softening psi=0.2", ft, c, tphi, 0.2, 12, 50, {1e-4, 2e-5, 0, 1e-4}, 2.5e-4, -2e-5, 2, 0},
    {"Coulomb- softening psi=phi", ft, c, tphi, tphi, 12, 50, {-1e-4, 7.5e-5, 0, 1e-4}, -2.5e-4, 5e-5, 2, 1},
    {"Coulomb+ softening psi=0", ft, c, tphi, 0, 12, 50, {1e-4, 0, 0, 1e-4}, 2.5e-4, -2e-5, 2, 0},
    {"Tresca (tanphi=0) softening", ft, c, 0, 0, 12, 50, {0, 0, 0, 1e-4}, 1e-4, -1e-5, 2, 1},
    {"corner+ psi=0.2", ft, c, tphi, 0.2, 0, 0, {0, 0, 0, 0}, 1.5e5 / KT + 1e-5, ft / KN + 2.2e-5, 3, -1},
    {"corner- softening psi=0.2", ft, c, tphi, 0.2, 12, 50, {0, 2e-5, 2e-5, 2e-5}, -1.5e5 / KT - 3e-5, ft / KN + 6e-5, 3, 0},
    {"corner+ softening psi=phi", ft, c, tphi, tphi, 12, 50, {0, 2e-5, 2e-5, 0}, 1.5e5 / KT + 3e-5, ft / KN + 8e-5, 3, 1},
    {"corner+ softening psi=0", ft, c, tphi, 0, 12, 50, {0, 2e-5, 2e-5, 2e-5}, 1.5e5 / KT + 3e-5, ft / KN + 6e-5, 3, 0},
    {"apex psi=0.2", 5e5, 1.5e5, tphi, 0.2, 0, 0, {0, 0, 0, 0}, 2e-5, 2e5 / KN + 0.2 * 4e-5, 2, -1},
    {"apex softening psi=0.2", ft, c, tphi, 0.2, 12, 50, {1e-5, 0, 0, 5e-4}, 1.5e-5, 1e-4, 2, -1}, /* rt = 0: T12 = T21 = 0 */
    {"apex softening psi=phi", ft, c, tphi, tphi, 12, 50, {1e-5, 0, 0, 5e-4}, 0.5e-5, 1e-4, 2, 1},
    {"lowered cut-off psi=0 softening", ft, c, tphi, 0, 12, 50, {1e-5, 0, 0, 5e-4}, 2e-5, 1e-4, 3, 0},
  };
  for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
    set_par(par, cases[i].ft, cases[i].c, cases[i].tphi, cases[i].tpsi, cases[i].gfI, cases[i].gfII);
    worst = fmax(worst, fd_check(cases[i].name, par, cases[i].s, cases[i].dt, cases[i].dn, cases[i].mode, &asym));
    /* asymmetry: kn tanphi kt / A against kn tanpsi kt / A, far above round-off when psi != phi */
    if (cases[i].symmetric == 1) CHECK(asym <= 1e-12, "tangent %s: not symmetric (%g)", cases[i].name, asym);
    if (cases[i].symmetric == 0) CHECK(asym >= 1e-3, "tangent %s: symmetric (%g) though psi != phi", cases[i].name, asym);
  }
  printf("tangent: worst |T - T_fd| / kn over all regimes %.2e\n", worst);
}

/* splitmix64: a fixed, portable random sequence */
static uint64_t rng_state = 20240611u;
static double   uniform(void)
{
  uint64_t z = (rng_state += 0x9e3779b97f4a7c15u);
  z          = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
  z          = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
  z ^= z >> 31;
  return (double)(z >> 11) / 9007199254740992.0;
}

static void test_property(void)
{
  /* 10^4 random laws (perfectly plastic or softening; tanpsi 0, random or tanphi; tanphi 0
   * sometimes; ft, c zero sometimes; apex above or below the cut-off), states and trial jumps
   * from well inside to 100 times past the surfaces. Invariants, with the scale sig = the
   * largest of |r_trial|, ft(k1), c(k2):
   *   - no surface violated at the returned (r, k): f <= 1e-12 sig (the kernel's active-set
   *     tolerance; round-off is ~1e-16 sig, the local Newton's 1e-14 sig);
   *   - k1, k2 non-decreasing; multipliers dl1 = dk1, dl2+- = (dk2 +- dslip)/2 >= -1e-12 sig/k;
   *   - flow: d opening = dl1 + tanpsi dk2;  r = C (j - jpl_out) to 1e-14 sig;
   *   - complementarity: a positive multiplier puts r on its surface (|f| <= 1e-12 sig),
   *     except the lowered cut-off of tanpsi = 0, whose stress is the apex;
   *   - mode 0 leaves the state bitwise unchanged and returns the trial stress;
   *   - the tangent matches central differences to 1e-6 of max(kn, |T|) (see fd_check)
   *     away from region boundaries.
   * The state differences are rounded at the state's own magnitude (k2 up to 3e-4 m), so
   * multiplier signs and the flow identity hold to ~1e-13 sig/k, not to eps. */
  const int n = 10000;
  int       count[4] = {0, 0, 0, 0}, lowered = 0;
  double    worst_f = 0, worst_flow = 0, worst_dl = 0, worst_fd = 0;
  int       nfd = 0;
  for (int it = 0; it < n; it++) {
    double par[BW_LAW_NPAR], s[BW_LAW_NSTATE], f[3];
    double ft = uniform() < 0.2 ? 0 : 1e5 * (0.5 + 4 * uniform()), c = uniform() < 0.2 ? 0 : 1e5 * (0.5 + 4 * uniform());
    double tphi = uniform() < 0.1 ? 0 : 0.3 + 0.7 * uniform(), u = uniform();
    double tpsi = u < 0.3 ? 0 : (u < 0.6 ? tphi : tphi * uniform());
    /* softening: fracture energies of masonry joints, or ones that bring the softening
     * moduli ft^2/GfI, c^2/GfII to 0.3 .. 0.99 of kn, kt (just short of a local snap-back) */
    int    soft = uniform() < 0.5, steep = uniform() < 0.3;
    double gfI = steep ? ft * ft / ((0.3 + 0.69 * uniform()) * KN) : 5 + 50 * uniform();
    double gfII = steep ? c * c / ((0.3 + 0.69 * uniform()) * KT) : 10 + 100 * uniform();
    set_par(par, ft, c, tphi, tpsi, soft ? gfI : 0, soft ? gfII : 0);
    double lI = ft > 0 && soft ? fmin(par[BW_LAW_PAR_GFI] / ft, 1e-4) : 1e-4, lII = c > 0 && soft ? fmin(par[BW_LAW_PAR_GFII] / c, 1e-4) : 1e-4;
    s[SLIP] = 1e-4 * (2 * uniform() - 1);
    s[OPEN] = 1e-4 * uniform();
    s[K1]   = uniform() < 0.3 ? 0 : 3 * lI * uniform();
    s[K2]   = uniform() < 0.3 ? 0 : 3 * lII * uniform();
    /* trial stress magnitude 1e4 .. 1e8 Pa in a random direction */
    double mag = 1e4 * pow(10, 4 * uniform()), ang = 6.283185307179586 * uniform();
    double dt = s[SLIP] + mag * cos(ang) / KT, dn = s[OPEN] + mag * sin(ang) / KN;
    Ret    o  = law(par, s, dt, dn);
    double rtr[2] = {KT * (dt - s[SLIP]), KN * (dn - s[OPEN])};
    double sig = fmax(fmax(fabs(rtr[0]), fabs(rtr[1]) * fmax(1, tphi)), fmax(strength(ft, par[BW_LAW_PAR_GFI], s[K1]), strength(c, par[BW_LAW_PAR_GFII], s[K2])));
    CHECK(o.status == 0, "property %d: status %d", it, o.status);
    if (o.status) continue;
    count[(int)o.mode]++;
    surfaces(par, o.r, o.s, f);
    worst_f = fmax(worst_f, fmax(f[0], fmax(f[1], f[2])) / sig);
    CHECK(f[0] <= 1e-12 * sig && f[1] <= 1e-12 * sig && f[2] <= 1e-12 * sig, "property %d: surface violated %g %g %g (sig %g)", it, f[0], f[1], f[2], sig);
    double dk1 = o.s[K1] - s[K1], dk2 = o.s[K2] - s[K2], dsl = o.s[SLIP] - s[SLIP], dop = o.s[OPEN] - s[OPEN];
    CHECK(dk1 >= 0 && dk2 >= 0, "property %d: k decreased (%g %g)", it, dk1, dk2);
    double tolj = 1e-12 * sig / fmin(KT, KN);
    double dlp = 0.5 * (dk2 + dsl), dlm = 0.5 * (dk2 - dsl);
    worst_dl   = fmax(worst_dl, fmax(-dlp, -dlm) / (sig / fmin(KT, KN)));
    CHECK(dlp >= -tolj && dlm >= -tolj, "property %d: negative cone multiplier (%g %g)", it, dlp, dlm);
    worst_flow = fmax(worst_flow, fabs(dop - dk1 - tpsi * dk2) / (sig / fmin(KT, KN)));
    CHECK(fabs(dop - dk1 - tpsi * dk2) <= tolj, "property %d: opening %g != dk1 + tanpsi dk2 = %g", it, dop, dk1 + tpsi * dk2);
    /* jpl = j - r/C is stored rounded: a few eps of C j and of r */
    double tolr = 1e-15 * (KT * fabs(dt) + KN * fabs(dn) + fabs(o.r[0]) + fabs(o.r[1]));
    CHECK(fabs(o.r[0] - KT * (dt - o.s[SLIP])) <= tolr && fabs(o.r[1] - KN * (dn - o.s[OPEN])) <= tolr, "property %d: r != C (j - jpl)", it);
    int is_lowered = tpsi == 0 && tphi > 0 && o.mode == 3 && f[0] < -1e-12 * sig;
    lowered += is_lowered;
    if (is_lowered)
      CHECK(o.r[0] == 0 && fabs(o.r[1] * tphi - strength(c, par[BW_LAW_PAR_GFII], o.s[K2])) <= 1e-12 * sig, "property %d: lowered cut-off off the apex", it);
    else if (dk1 > tolj)
      CHECK(fabs(f[0]) <= 1e-12 * sig, "property %d: k1 grew off the cut-off (f1 %g)", it, f[0]);
    if (dlp > tolj) CHECK(fabs(f[1]) <= 1e-12 * sig, "property %d: dl2+ > 0 off f2+ (%g)", it, f[1]);
    if (dlm > tolj) CHECK(fabs(f[2]) <= 1e-12 * sig, "property %d: dl2- > 0 off f2- (%g)", it, f[2]);
    /* the tangent against central differences (as in the tangent case, step 1e-6 of the
     * trial jump), where the mode is the same at +-h and +-2h (no region boundary near) */
    {
      double h = 1e-6 * fmax(fmax(fabs(dt - s[SLIP]), fabs(dn - s[OPEN])), 1e-9), fd[4], e = 0;
      int    same = 1;
      for (int cc = 0; cc < 2; cc++) {
        for (int m = 1; m <= 2; m++) {
          Ret p = law(par, s, dt + m * (cc == 0) * h, dn + m * (cc == 1) * h), q = law(par, s, dt - m * (cc == 0) * h, dn - m * (cc == 1) * h);
          same  = same && p.mode == o.mode && q.mode == o.mode;
          if (m == 1)
            for (int row = 0; row < 2; row++) fd[2 * row + cc] = (p.r[row] - q.r[row]) / (2 * h);
        }
      }
      /* near the snap-back bound the tangent grows to 1/(1 - 0.99) kn: errors scale with it */
      for (int q = 0; q < 4; q++) e = fmax(e, fabs(fd[q] - o.T[q]) / fmax(KN, maxabs4(o.T)));
      if (same) {
        nfd++;
        worst_fd = fmax(worst_fd, e);
        CHECK(e <= 1e-6, "property %d: tangent error %.3e (mode %d)", it, e, o.mode);
      }
    }
    if (o.mode == 0) CHECK(!memcmp(o.s, s, sizeof(s)) && o.r[0] == rtr[0] && o.r[1] == rtr[1], "property %d: elastic step changed the state", it);
  }
  printf("property: %d trials, modes 0/1/2/3 = %d/%d/%d/%d (lowered cut-off %d); worst f/sig %.2e, worst -dl kmin/sig %.2e, worst flow "
         "mismatch kmin/sig %.2e; tangent checked at %d, worst |T - T_fd|/max(kn,|T|) %.2e\n",
         n, count[0], count[1], count[2], count[3], lowered, worst_f, worst_dl, worst_flow, nfd, worst_fd);
}

static void test_bad(void)
{
  double      par[BW_LAW_NPAR], good[BW_LAW_NPAR], s[2 * BW_LAW_NSTATE] = {0}, j[4] = {1e-5, 1e-5, 1e-5, 1e-5}, r[4], T[8], so[2 * BW_LAW_NSTATE];
  signed char mode[2];
  int         st;
  set_par(good, 2e5, 3e5, 0.75, 0.2, 12, 50);
  struct {
    int    index;
    double value;
    int    want;
  } cases[] = {
    {BW_LAW_PAR_KT, 0, BW_LAW_BAD_STIFFNESS},
    {BW_LAW_PAR_KN, -1e11, BW_LAW_BAD_STIFFNESS},
    {BW_LAW_PAR_KN, NAN, BW_LAW_BAD_STIFFNESS},
    {BW_LAW_PAR_KT, INFINITY, BW_LAW_BAD_STIFFNESS},
    {BW_LAW_PAR_FT, -1, BW_LAW_BAD_STRENGTH},
    {BW_LAW_PAR_C, NAN, BW_LAW_BAD_STRENGTH},
    {BW_LAW_PAR_C, INFINITY, BW_LAW_BAD_STRENGTH},
    {BW_LAW_PAR_TANPHI, -0.1, BW_LAW_BAD_STRENGTH},
    {BW_LAW_PAR_TANPSI, -0.1, BW_LAW_BAD_STRENGTH},
    {BW_LAW_PAR_TANPSI, 0.8, BW_LAW_BAD_STRENGTH}, /* tanpsi > tanphi */
    {BW_LAW_PAR_GFI, NAN, BW_LAW_BAD_STRENGTH},
    {BW_LAW_PAR_GFII, INFINITY, BW_LAW_BAD_STRENGTH},
    {BW_LAW_PAR_GFI, 1e-320, BW_LAW_BAD_STRENGTH}, /* ft/GfI not finite */
    {BW_LAW_PAR_GFI, -1, BW_LAW_OK},               /* no softening */
    {BW_LAW_PAR_GFII, 0, BW_LAW_OK},
  };
  for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
    memcpy(par, good, sizeof(par));
    par[cases[i].index] = cases[i].value;
    bw_law_coulomb(2, 2, par, s, j, r, T, so, mode, &st);
    CHECK(st == cases[i].want, "coulomb: par[%d] = %g gave status %d, want %d", cases[i].index, cases[i].value, st, cases[i].want);
    /* the linear law reads the stiffnesses only */
    bw_law_elastic(2, 2, par, s, j, r, T, so, mode, &st);
    int want = cases[i].want == BW_LAW_BAD_STIFFNESS ? BW_LAW_BAD_STIFFNESS : BW_LAW_OK;
    CHECK(st == want, "elastic: par[%d] = %g gave status %d, want %d", cases[i].index, cases[i].value, st, want);
  }
  /* a bad second portion */
  j[3] = NAN;
  bw_law_coulomb(2, 2, good, s, j, r, T, so, mode, &st);
  CHECK(st == BW_LAW_BAD_JUMP, "NaN jump gave %d", st);
  bw_law_elastic(2, 2, good, s, j, r, T, so, mode, &st);
  CHECK(st == BW_LAW_BAD_JUMP, "elastic: NaN jump gave %d", st);
  j[3] = -INFINITY;
  bw_law_coulomb(2, 2, good, s, j, r, T, so, mode, &st);
  CHECK(st == BW_LAW_BAD_JUMP, "infinite jump gave %d", st);
  j[3]                  = 1e-5;
  s[BW_LAW_NSTATE + BW_LAW_STATE_K1] = -1e-6;
  bw_law_coulomb(2, 2, good, s, j, r, T, so, mode, &st);
  CHECK(st == BW_LAW_BAD_STATE, "k1 < 0 gave %d", st);
  s[BW_LAW_NSTATE + BW_LAW_STATE_K1]   = 0;
  s[BW_LAW_NSTATE + BW_LAW_STATE_SLIP] = NAN;
  bw_law_coulomb(2, 2, good, s, j, r, T, so, mode, &st);
  CHECK(st == BW_LAW_BAD_STATE, "NaN slip gave %d", st);
  s[BW_LAW_NSTATE + BW_LAW_STATE_SLIP] = 0;
  bw_law_coulomb(2, 2, good, s, j, r, T, so, mode, &st);
  CHECK(st == BW_LAW_OK, "good input gave %d", st);
}

/* ------------------------------------------------------------------ three dimensions (ns = 3) */

enum { SLIPB = BW_LAW_STATE_SLIP_B };

typedef struct {
  double      r[3], T[9], s[BW_LAW_NSTATE_MAX];
  signed char mode;
  int         status;
} Ret3;

static Ret3 law3(const double par[], const double s_in[], double dt, double dn, double db)
{
  Ret3   o;
  double j[3] = {dt, dn, db};
  memset(&o, 0, sizeof(o));
  bw_law_coulomb(3, 1, par, s_in, j, o.r, o.T, o.s, &o.mode, &o.status);
  return o;
}

/* A random law, state and trial as in the property test; in 3D the slip and the trial's
 * shear are vectors in the (t, b) plane. Returns sig, the stress scale. */
static double random_case(double par[], double s[], double j[3], int ns)
{
  double ft = uniform() < 0.2 ? 0 : 1e5 * (0.5 + 4 * uniform()), c = uniform() < 0.2 ? 0 : 1e5 * (0.5 + 4 * uniform());
  double tphi = uniform() < 0.1 ? 0 : 0.3 + 0.7 * uniform(), u = uniform();
  double tpsi = u < 0.3 ? 0 : (u < 0.6 ? tphi : tphi * uniform());
  int    soft = uniform() < 0.5, steep = uniform() < 0.3;
  double gfI = steep ? ft * ft / ((0.3 + 0.69 * uniform()) * KN) : 5 + 50 * uniform();
  double gfII = steep ? c * c / ((0.3 + 0.69 * uniform()) * KT) : 10 + 100 * uniform();
  set_par(par, ft, c, tphi, tpsi, soft ? gfI : 0, soft ? gfII : 0);
  double lI = ft > 0 && soft ? fmin(par[BW_LAW_PAR_GFI] / ft, 1e-4) : 1e-4, lII = c > 0 && soft ? fmin(par[BW_LAW_PAR_GFII] / c, 1e-4) : 1e-4;
  double th = 6.283185307179586 * uniform();
  double sl = 1e-4 * uniform(), mag = 1e4 * pow(10, 4 * uniform()), ang = 6.283185307179586 * uniform(), phi = 6.283185307179586 * uniform();
  s[SLIP] = ns == 3 ? sl * cos(th) : 1e-4 * (2 * uniform() - 1);
  s[OPEN] = 1e-4 * uniform();
  s[K1]   = uniform() < 0.3 ? 0 : 3 * lI * uniform();
  s[K2]   = uniform() < 0.3 ? 0 : 3 * lII * uniform();
  s[BW_LAW_STATE_K3] = 0;
  if (ns == 3) s[SLIPB] = sl * sin(th);
  /* trial stress magnitude 1e4 .. 1e8 Pa in a random direction of (tau, rn) */
  j[0] = s[SLIP] + mag * cos(ang) * (ns == 3 ? cos(phi) : 1) / KT;
  j[1] = s[OPEN] + mag * sin(ang) / KN;
  j[2] = ns == 3 ? s[SLIPB] + mag * cos(ang) * sin(phi) / KT : 0;
  return fmax(fmax(mag, fabs(j[1] - s[OPEN]) * KN * fmax(1, tphi)), fmax(strength(ft, par[BW_LAW_PAR_GFI], s[K1]), strength(c, par[BW_LAW_PAR_GFII], s[K2])));
}

static void test_cone3d(void)
{
  /* Perfectly plastic sliding under a fixed compressive dn, pushed in 8 directions of the
   * (t, b) plane, psi = 0, 0.2, phi: the circular cone gives |tau| = c - rn tanphi in every
   * direction (the sliding capacity c A + N tanphi does not depend on the direction, model.md),
   * tau along the pushed direction, the slip vector along it with length k2, the opening
   * tanpsi k2 and rn = kn (dn - opening): closed forms, to round-off. */
  const double c = 3e5, tphi = 0.75, tpsis[3] = {0, 0.2, 0.75}, dn = -2e-5, push = 2e-4;
  double       par[BW_LAW_NPAR], taus[8];
  for (int q = 0; q < 3; q++) {
    double tpsi = tpsis[q];
    set_par(par, 2e5, c, tphi, tpsi, 0, 0);
    for (int d = 0; d < 8; d++) {
      double th = d * 0.7853981633974483, e[2] = {cos(th), sin(th)}, s[BW_LAW_NSTATE_MAX] = {0, 0, 0, 0, 0};
      Ret3   o = law3(par, s, push * e[0], dn, push * e[1]);
      /* sliding with dilatancy: rn = kn (dn - tanpsi k2), |tau| = c - rn tanphi, and
       * |tau| = kt (push - k2) on the slip: k2 = (kt push - c + kn dn tanphi) / (kt + kn tanphi tanpsi) */
      double k2 = (KT * push - c + KN * dn * tphi) / (KT + KN * tphi * tpsi), rn = KN * (dn - tpsi * k2), tau = c - rn * tphi;
      double mag = hypot(o.r[0], o.r[2]);
      CHECK(o.status == 0 && o.mode == 2, "cone3d psi %g direction %d: status %d mode %d", tpsi, d, o.status, o.mode);
      expect_close("cone3d |tau| = c - rn tanphi", mag, tau, 1e-14, tau);
      expect_close("cone3d rn = kn (dn - tanpsi k2)", o.r[1], rn, 1e-13, fabs(rn));
      expect_close("cone3d k2", o.s[K2], k2, 1e-13, k2);
      expect_close("cone3d tau along the push (cross product)", o.r[0] * e[1] - o.r[2] * e[0], 0, 1e-14, tau);
      expect_close("cone3d slip along the push, length k2 (t)", o.s[SLIP], k2 * e[0], 1e-13, k2);
      expect_close("cone3d slip along the push, length k2 (b)", o.s[SLIPB], k2 * e[1], 1e-13, k2);
      expect_close("cone3d opening = tanpsi k2", o.s[OPEN], tpsi * k2, 1e-13, k2);
      taus[d] = mag;
    }
    for (int d = 1; d < 8; d++) expect_close("cone3d the same capacity in every direction", taus[d], taus[0], 1e-14, taus[0]);
  }
  printf("cone3d: |tau| = c - rn tanphi in 8 directions, psi = 0, 0.2, phi\n");
}

static void test_extrude3d(void)
{
  /* The 2D law is the 3D one without b: for 10^4 random laws, states and trials (those of the
   * property test), ns = 3 with db = 0 and no b slip gives the ns = 2 stress, state, mode and
   * tangent (t, n rows and columns), rb = 0, no coupling of b with t and n, and on b the
   * circle's shrinking kt |tau|/|tau_tr| (kt when |tau_tr| = 0 and elastic). */
  const int n = 10000;
  double    worst_r = 0, worst_t = 0;
  for (int it = 0; it < n; it++) {
    double par[BW_LAW_NPAR], s[BW_LAW_NSTATE_MAX] = {0}, j[3];
    double sig = random_case(par, s, j, 2);
    Ret    o2  = law(par, s, j[0], j[1]);
    s[SLIPB]   = 0;
    Ret3 o3    = law3(par, s, j[0], j[1], 0);
    CHECK(o2.status == 0 && o3.status == 0 && o2.mode == o3.mode, "extrude3d %d: status %d %d mode %d %d", it, o2.status, o3.status, o2.mode, o3.mode);
    double er = fmax(fabs(o3.r[0] - o2.r[0]), fabs(o3.r[1] - o2.r[1])) / sig;
    double es = 0, et = 0, tscale = fmax(KN, maxabs4(o2.T));
    for (int k = 0; k < BW_LAW_NSTATE; k++) es = fmax(es, fabs(o3.s[k] - o2.s[k]) * fmin(KT, KN) / sig);
    for (int a = 0; a < 2; a++)
      for (int b = 0; b < 2; b++) et = fmax(et, fabs(o3.T[3 * a + b] - o2.T[2 * a + b]) / tscale);
    worst_r = fmax(worst_r, fmax(er, es));
    worst_t = fmax(worst_t, et);
    CHECK(er <= 1e-13 && es <= 1e-13, "extrude3d %d: stress %.2e, state %.2e of sig", it, er, es);
    CHECK(et <= 1e-12, "extrude3d %d: tangent %.2e", it, et);
    CHECK(o3.r[2] == 0 && o3.s[SLIPB] == 0, "extrude3d %d: rb = %g, b slip %g", it, o3.r[2], o3.s[SLIPB]);
    CHECK(o3.T[2] == 0 && o3.T[5] == 0 && o3.T[6] == 0 && o3.T[7] == 0, "extrude3d %d: b coupled with t, n", it);
    double str = KT * fabs(j[0] - s[SLIP]), want = str > 0 ? KT * fabs(o3.r[0]) / str : o2.T[0];
    expect_close("extrude3d kt |tau|/|tau_tr| on b", o3.T[8], want, 1e-12, tscale);
  }
  printf("extrude3d: %d trials, worst stress/state %.2e of sig, tangent %.2e\n", n, worst_r, worst_t);
}

/* Rotate the shear components (t, b) of a 3D jump, state, stress or tangent by th about n. */
static void rot2(double th, double *x, double *y)
{
  double c = cos(th), s = sin(th), a = c * *x - s * *y, b = s * *x + c * *y;
  *x = a;
  *y = b;
}

static void test_rotate3d(void)
{
  /* Isotropy of the joint in its plane: rotating the trial jump and the plastic slip about n
   * rotates the stress, the slip and the tangent (Q T Q^T) and leaves rn, the opening, k1, k2
   * and the mode, for 10^4 random cases in 3D, to round-off of the stress scale. */
  const int n = 10000;
  double    worst = 0;
  for (int it = 0; it < n; it++) {
    double par[BW_LAW_NPAR], s[BW_LAW_NSTATE_MAX], j[3], th = 6.283185307179586 * uniform();
    double sig = random_case(par, s, j, 3);
    Ret3   a = law3(par, s, j[0], j[1], j[2]);
    double sr[BW_LAW_NSTATE_MAX], jr[3] = {j[0], j[1], j[2]};
    memcpy(sr, s, sizeof(sr));
    rot2(th, &jr[0], &jr[2]);
    rot2(th, &sr[SLIP], &sr[SLIPB]);
    Ret3 b = law3(par, sr, jr[0], jr[1], jr[2]);
    CHECK(a.status == 0 && b.status == 0 && a.mode == b.mode, "rotate3d %d: status %d %d mode %d %d", it, a.status, b.status, a.mode, b.mode);
    rot2(th, &a.r[0], &a.r[2]);
    rot2(th, &a.s[SLIP], &a.s[SLIPB]);
    /* Q T Q^T: rotate the columns, then the rows */
    for (int row = 0; row < 3; row++) rot2(th, &a.T[3 * row], &a.T[3 * row + 2]);
    for (int col = 0; col < 3; col++) rot2(th, &a.T[col], &a.T[6 + col]);
    double e = 0, et = 0, tscale = KN;
    for (int k = 0; k < 3; k++) e = fmax(e, fabs(a.r[k] - b.r[k]) / sig);
    for (int k = 0; k < BW_LAW_NSTATE_MAX; k++) e = fmax(e, fabs(a.s[k] - b.s[k]) * fmin(KT, KN) / sig);
    for (int k = 0; k < 9; k++) tscale = fmax(tscale, fabs(b.T[k]));
    for (int k = 0; k < 9; k++) et = fmax(et, fabs(a.T[k] - b.T[k]) / tscale);
    worst = fmax(worst, e);
    CHECK(e <= 1e-13 && et <= 1e-12, "rotate3d %d: stress/state %.2e of sig, tangent %.2e", it, e, et);
  }
  printf("rotate3d: %d trials, worst %.2e of sig\n", n, worst);
}

static void test_property3d(void)
{
  /* 10^4 random 3D cases (as the 2D property test): no surface violated at the returned
   * (r, k), |tau| + rn tanphi <= c(k2), rn <= ft(k1) (1e-12 sig); k non-decreasing; the slip
   * of the step along the returned tau with length dk2 (the cone's flow; at the apex along
   * the trial tau); d opening = dk1 + tanpsi dk2; r = C (j - jpl); and the 3x3 tangent
   * against central differences (step 1e-6 of the trial jump, where the mode is the same at
   * +-h and +-2h in all three directions) to 1e-6 of max(kn, |T|). Cases with no trial shear
   * (|tau_tr| = 0) are mixed in: there the tangent's b and t columns are the 2D T11. */
  const int n = 10000;
  int       count[4] = {0, 0, 0, 0}, nfd = 0, nzero = 0;
  double    worst_f = 0, worst_fd = 0, worst_flow = 0;
  for (int it = 0; it < n; it++) {
    double par[BW_LAW_NPAR], s[BW_LAW_NSTATE_MAX], j[3];
    double sig = random_case(par, s, j, 3);
    if (it % 10 == 0) {
      j[0] = s[SLIP];
      j[2] = s[SLIPB];
      nzero++;
    }
    Ret3   o = law3(par, s, j[0], j[1], j[2]);
    double tphi = par[BW_LAW_PAR_TANPHI], tpsi = par[BW_LAW_PAR_TANPSI];
    CHECK(o.status == 0, "property3d %d: status %d", it, o.status);
    if (o.status) continue;
    count[(int)o.mode]++;
    double ft = strength(par[BW_LAW_PAR_FT], par[BW_LAW_PAR_GFI], o.s[K1]), c = strength(par[BW_LAW_PAR_C], par[BW_LAW_PAR_GFII], o.s[K2]);
    double tau = hypot(o.r[0], o.r[2]), f1 = o.r[1] - ft, f2 = tau + o.r[1] * tphi - c;
    worst_f = fmax(worst_f, fmax(f1, f2) / sig);
    CHECK(f1 <= 1e-12 * sig && f2 <= 1e-12 * sig, "property3d %d: surface violated %g %g (sig %g)", it, f1, f2, sig);
    double dk1 = o.s[K1] - s[K1], dk2 = o.s[K2] - s[K2], dst = o.s[SLIP] - s[SLIP], dsb = o.s[SLIPB] - s[SLIPB], dop = o.s[OPEN] - s[OPEN];
    double tolj = 1e-12 * sig / fmin(KT, KN);
    CHECK(dk1 >= 0 && dk2 >= 0, "property3d %d: k decreased (%g %g)", it, dk1, dk2);
    /* dk2 = dl2 is the cone's multiplier: the slip's length on the cone's face; at its
     * apex (tau = 0) the flow is any direction of the cone, |d slip| <= dk2 */
    if (tau > 1e-12 * sig) CHECK(fabs(hypot(dst, dsb) - dk2) <= tolj, "property3d %d: |d slip| %g != dk2 %g", it, hypot(dst, dsb), dk2);
    else CHECK(hypot(dst, dsb) <= dk2 + tolj, "property3d %d: at the apex |d slip| %g > dk2 %g", it, hypot(dst, dsb), dk2);
    double ttr[2] = {KT * (j[0] - s[SLIP]), KT * (j[2] - s[SLIPB])}, str = hypot(ttr[0], ttr[1]);
    if (dk2 > tolj && str > 0) CHECK(fabs(dst * ttr[1] - dsb * ttr[0]) <= 1e-12 * dk2 * str && dst * ttr[0] + dsb * ttr[1] > 0, "property3d %d: slip not along tau", it);
    if (str > 0) CHECK(fabs(o.r[0] * ttr[1] - o.r[2] * ttr[0]) <= 1e-12 * sig * str && o.r[0] * ttr[0] + o.r[2] * ttr[1] >= -1e-12 * sig * str, "property3d %d: tau turned from the trial", it);
    worst_flow = fmax(worst_flow, fabs(dop - dk1 - tpsi * dk2) / (sig / fmin(KT, KN)));
    CHECK(fabs(dop - dk1 - tpsi * dk2) <= tolj, "property3d %d: opening %g != dk1 + tanpsi dk2 = %g", it, dop, dk1 + tpsi * dk2);
    double tolr = 1e-15 * (KT * (fabs(j[0]) + fabs(j[2])) + KN * fabs(j[1]) + fabs(o.r[0]) + fabs(o.r[1]) + fabs(o.r[2]));
    CHECK(fabs(o.r[0] - KT * (j[0] - o.s[SLIP])) <= tolr && fabs(o.r[1] - KN * (j[1] - o.s[OPEN])) <= tolr && fabs(o.r[2] - KT * (j[2] - o.s[SLIPB])) <= tolr,
          "property3d %d: r != C (j - jpl)", it);
    if (o.mode == 0) CHECK(!memcmp(o.s, s, sizeof(s)), "property3d %d: elastic step changed the state", it);
    {
      double h = 1e-6 * fmax(fmax(str / KT, fabs(j[1] - s[OPEN])), 1e-9), fd[9], e = 0, tscale = KN;
      int    same = 1;
      for (int cc = 0; cc < 3; cc++)
        for (int m = 1; m <= 2; m++) {
          double dp[3] = {0, 0, 0};
          dp[cc]       = m * h;
          Ret3 p = law3(par, s, j[0] + dp[0], j[1] + dp[1], j[2] + dp[2]), q = law3(par, s, j[0] - dp[0], j[1] - dp[1], j[2] - dp[2]);
          same   = same && p.mode == o.mode && q.mode == o.mode;
          if (m == 1)
            for (int row = 0; row < 3; row++) fd[3 * row + cc] = (p.r[row] - q.r[row]) / (2 * h);
        }
      for (int k = 0; k < 9; k++) tscale = fmax(tscale, fabs(o.T[k]));
      for (int k = 0; k < 9; k++) e = fmax(e, fabs(fd[k] - o.T[k]) / tscale);
      /* at |tau_tr| = 0 on the cone the stress is not differentiable in shear (the apex) */
      /* the jumps (~1e-4 m) are rounded to eps |j| before the kernel forms j - jpl: over a
       * step h that is a stress error of a few eps |j| k / h, beside the 1e-6 of fd_check */
      double jmax = fmax(fmax(fabs(j[0]), fabs(j[1])), fabs(j[2])), tol = 1e-6 + 8 * 2.2e-16 * jmax / h * KN / tscale;
      if (same && !(str == 0 && o.mode >= 2)) {
        nfd++;
        worst_fd = fmax(worst_fd, e);
        CHECK(e <= tol, "property3d %d: tangent error %.3e > %.1e (mode %d)", it, e, tol, o.mode);
      }
    }
  }
  printf("property3d: %d trials (%d without trial shear), modes 0/1/2/3 = %d/%d/%d/%d; worst f/sig %.2e, flow %.2e; "
         "tangent checked at %d, worst |T - T_fd|/max(kn,|T|) %.2e\n",
         n, nzero, count[0], count[1], count[2], count[3], worst_f, worst_flow, nfd, worst_fd);
}

static void test_bad3d(void)
{
  /* ns other than 2 or 3; a NaN b jump or b slip in 3D */
  double      par[BW_LAW_NPAR], s[BW_LAW_NSTATE_MAX] = {0}, j[3] = {1e-5, -1e-5, 1e-5}, r[3], T[9], so[BW_LAW_NSTATE_MAX];
  signed char mode;
  int         st;
  set_par(par, 2e5, 3e5, 0.75, 0.2, 12, 50);
  bw_law_coulomb(4, 1, par, s, j, r, T, so, &mode, &st);
  CHECK(st == BW_LAW_BAD_SIZE, "ns = 4 gave %d", st);
  bw_law_elastic(1, 1, par, s, j, r, T, so, &mode, &st);
  CHECK(st == BW_LAW_BAD_SIZE, "elastic ns = 1 gave %d", st);
  bw_law_coulomb(3, 1, par, s, j, r, T, so, &mode, &st);
  CHECK(st == BW_LAW_OK, "good 3D input gave %d", st);
  j[2] = NAN;
  bw_law_coulomb(3, 1, par, s, j, r, T, so, &mode, &st);
  CHECK(st == BW_LAW_BAD_JUMP, "NaN b jump gave %d", st);
  bw_law_elastic(3, 1, par, s, j, r, T, so, &mode, &st);
  CHECK(st == BW_LAW_BAD_JUMP, "elastic: NaN b jump gave %d", st);
  j[2]     = 1e-5;
  s[SLIPB] = INFINITY;
  bw_law_coulomb(3, 1, par, s, j, r, T, so, &mode, &st);
  CHECK(st == BW_LAW_BAD_STATE, "infinite b slip gave %d", st);
  /* elastic 3D: C (j - jpl), tangent diag(kt, kn, kt) */
  s[SLIPB] = 2e-6;
  bw_law_elastic(3, 1, par, s, j, r, T, so, &mode, &st);
  CHECK(st == 0 && r[0] == KT * j[0] && r[1] == KN * j[1] && r[2] == KT * (j[2] - 2e-6) && T[0] == KT && T[4] == KN && T[8] == KT && T[1] == 0 && T[5] == 0,
        "elastic 3D: r = (%g %g %g)", r[0], r[1], r[2]);
}

/* ------------------------------------------------------------------ the compressive cap (coulomb_cap) */

static const double CAP_KN = 82e9, CAP_KT = 36e9; /* J4D's joints */

/* sbar(k) of model.md ("Compressive cap"), written from its text, and its derivative */
static double cap_sbar(double fc, double gfc, double kp, double k, double *ds)
{
  double sp = fc, si = fc / 3, sm = fc / 2, sr = fc / 10;
  if (!(gfc > 0)) {
    *ds = 0;
    return fc;
  }
  double km = kp + 75 * gfc / (67 * fc), mm = 2 * (sm - sp) / (km - kp);
  if (k <= kp) {
    double w = sqrt(2 * k / kp - k * k / (kp * kp));
    *ds = (sp - si) * (1 / kp - k / (kp * kp)) / w;
    return si + (sp - si) * w;
  }
  if (k <= km) {
    *ds = 2 * (sm - sp) * (k - kp) / ((km - kp) * (km - kp));
    return sp + (sm - sp) * pow((k - kp) / (km - kp), 2);
  }
  *ds = mm * exp(mm * (k - km) / (sm - sr));
  return sr + (sm - sr) * exp(mm * (k - km) / (sm - sr));
}

static void set_cap(double par[], double fc, double css, double gfc, double kp)
{
  par[BW_LAW_PAR_FC]  = fc;
  par[BW_LAW_PAR_CSS] = css;
  par[BW_LAW_PAR_GFC] = gfc;
  par[BW_LAW_PAR_KP]  = kp;
}

static Ret cap_law(const double par[], const double s_in[], double dt, double dn)
{
  Ret    o;
  double j[2] = {dt, dn};
  memset(&o, 0, sizeof(o));
  bw_law_coulomb_cap(2, 1, par, s_in, j, o.r, o.T, o.s, &o.mode, &o.status);
  return o;
}

static void test_cap_uniaxial(void)
{
  /* A portion closed step by step in pure compression (dt = 0), J4D's joints with Lourenço's
   * cap (fc = 10.5 MPa, Gfc = 5 N/mm, kappa_p = 0.093 mm) and the perfectly plastic cap:
   * elastic to rn = -fc/3 (-fc without Gfc), then on the cap at every step, where the
   * closed forms of model.md hold: rn = -sbar(k3) with k3 the accumulated plastic closing
   * (opening = -k3), and the tangent drn/ddn = kn sbar'/(kn + sbar') (from dn = -k3 -
   * sbar(k3)/kn), through hardening, the parabola's softening and the exponential to the
   * residual fc/10. Tolerances: rn to 1e-12 fc (the kernel solves its scalar equation to
   * 1e-14 of the stress scale), k3 from the jump to 1e-12 of kappa_p, the tangent to 1e-9
   * of kn (sbar' from the same formula; rounding of k3 enters through sbar''). */
  const double fc = 10.5e6, gfc = 5000, kp = 0.093e-3;
  for (int soft = 0; soft < 2; soft++) {
    double par[BW_LAW_NPAR], s[BW_LAW_NSTATE] = {0, 0, 0, 0, 0}, km = kp + 75 * gfc / (67 * fc);
    set_par(par, 0.25e6, 0.35e6, 0.75, 0, 18, 125);
    par[BW_LAW_PAR_KT] = CAP_KT;
    par[BW_LAW_PAR_KN] = CAP_KN;
    set_cap(par, fc, 9, soft ? gfc : -1, kp);
    int    nsteps = 600, first = -1, seen[3] = {0, 0, 0};
    double dnmax = soft ? km + 5e-3 : 4 * fc / CAP_KN, worst_r = 0, worst_t = 0;
    for (int i = 1; i <= nsteps; i++) {
      double dn = -dnmax * i / nsteps, ds;
      Ret    o  = cap_law(par, s, 0, dn);
      CHECK(o.status == 0, "cap uniaxial step %d: status %d", i, o.status);
      if (o.status) return;
      double k3 = o.s[BW_LAW_STATE_K3], sb = cap_sbar(fc, soft ? gfc : -1, kp, k3, &ds);
      if (o.mode == 0) {
        CHECK(first < 0 && o.r[1] >= -(soft ? fc / 3 : fc) * (1 + 1e-15), "cap uniaxial step %d: elastic beyond the first yield (rn %g)", i, o.r[1]);
        expect_close("cap elastic rn", o.r[1], CAP_KN * dn, 1e-15, fc);
        continue;
      }
      if (first < 0) first = i;
      CHECK(o.mode == BW_LAW_MODE_CRUSHED, "cap uniaxial step %d: mode %d, want 4", i, o.mode);
      CHECK(o.r[0] == 0, "cap uniaxial step %d: shear %g", i, o.r[0]);
      worst_r = fmax(worst_r, fabs(o.r[1] + sb) / fc);
      expect_close("cap rn = -sbar(k3)", o.r[1], -sb, 1e-12, fc);
      expect_close("cap opening = -k3", o.s[OPEN], -k3, 1e-12, kp);
      expect_close("cap dn = -k3 - sbar/kn", dn, -k3 - sb / CAP_KN, 1e-12, kp);
      double want = CAP_KN * ds / (CAP_KN + ds);
      worst_t     = fmax(worst_t, fabs(o.T[3] - want) / CAP_KN);
      expect_close("cap tangent kn sbar'/(kn + sbar')", o.T[3], want, 1e-9, CAP_KN);
      CHECK(o.T[1] == 0 && o.T[2] == 0, "cap uniaxial step %d: coupling in the tangent", i);
      if (soft) seen[k3 <= kp ? 0 : k3 <= km ? 1 : 2]++;
      memcpy(s, o.s, sizeof(s));
    }
    CHECK(first > 1, "cap uniaxial: no elastic start");
    if (soft) CHECK(seen[0] > 5 && seen[1] > 5 && seen[2] > 5, "cap uniaxial: branches visited %d %d %d", seen[0], seen[1], seen[2]);
    if (soft) CHECK(s[BW_LAW_STATE_K3] > km + 4e-3, "cap uniaxial: not into the residual (k3 %g)", s[BW_LAW_STATE_K3]);
    printf("cap uniaxial (%s): first yield at step %d, worst |rn + sbar|/fc %.2e, worst tangent error/kn %.2e\n", soft ? "Gfc = 5 N/mm" : "perfectly plastic", first, worst_r, worst_t);
  }
}

/* The cap's surface in stress units and the sets of a returned state. */
static double cap_f(const double par[], const double r[2], double k3)
{
  double ds, sb = cap_sbar(par[BW_LAW_PAR_FC], par[BW_LAW_PAR_GFC], par[BW_LAW_PAR_KP], k3, &ds);
  return sqrt(r[1] * r[1] + par[BW_LAW_PAR_CSS] * r[0] * r[0]) - sb;
}

/* A random law with a cap, a state and a trial jump: trial stresses around the cap and
 * its corners with the cone (magnitude 0.05 .. 4 fc, directions weighted to compression). */
static double cap_random_case(double par[], double s[], double j[2])
{
  double fc = 2e6 + 18e6 * uniform(), css = 1 + 11 * uniform(), kp = 2e-5 + 2e-4 * uniform();
  double gfc_min = 67 * fc * fc / (75 * CAP_KN), gfc = uniform() < 0.3 ? -1 : gfc_min * (1.05 + 20 * uniform() * uniform());
  double ft = uniform() < 0.2 ? 0 : 1e5 * (0.5 + 4 * uniform()), c = uniform() < 0.2 ? 0 : 1e5 * (0.5 + 4 * uniform());
  double tphi = uniform() < 0.1 ? 0 : 0.3 + 0.7 * uniform(), u = uniform();
  double tpsi = u < 0.4 ? 0 : (u < 0.7 ? tphi : tphi * uniform());
  int    soft = uniform() < 0.5;
  set_par(par, ft, c, tphi, tpsi, soft ? 5 + 50 * uniform() : 0, soft ? 10 + 100 * uniform() : 0);
  par[BW_LAW_PAR_KT] = CAP_KT;
  par[BW_LAW_PAR_KN] = CAP_KN;
  set_cap(par, fc, css, gfc, kp);
  double km = gfc > 0 ? kp + 75 * gfc / (67 * fc) : kp;
  s[SLIP]             = 1e-4 * (2 * uniform() - 1);
  s[OPEN]             = -1e-4 * uniform();
  s[K1]               = uniform() < 0.5 ? 0 : 1e-4 * uniform();
  s[K2]               = uniform() < 0.5 ? 0 : 1e-3 * uniform();
  s[BW_LAW_STATE_K3]  = uniform() < 0.3 ? 0 : 2 * km * uniform();
  double mag = fc * (0.05 + 4 * uniform()), ang = 3.141592653589793 * (1 + uniform()); /* rn <= 0 */
  if (uniform() < 0.1) ang = 6.283185307179586 * uniform();
  j[0] = s[SLIP] + mag * cos(ang) / (CAP_KT * sqrt(css));
  j[1] = s[OPEN] + mag * sin(ang) / CAP_KN;
  return fmax(mag, fc);
}

static void test_cap_property(void)
{
  /* 10^4 random laws with a cap, states and trials (cap_random_case). Invariants, sig the
   * larger of the trial's Q and fc:
   *   - every surface holds at the returned (r, k): cut-off, cone and cap <= 1e-11 sig;
   *   - k3 never decreases; on the cap alone (mode 4) the plastic increment is parallel to
   *     the cap's normal (Css rt, rn) with a positive multiplier and length dk3; at its
   *     corner with the cone (mode 6) it is x (sign rt, tanpsi) + mu (Css rt, rn)/|.| with
   *     x = dk2 >= 0 and mu = dk3 >= 0 (the associated flow, k3 its length);
   *   - r = C (j - jpl);
   *   - the tangent against central differences, where the mode is the same at +-h, +-2h,
   *     to 1e-6 of max(kn, |T|) (as the law without cap).
   * Every trial must find a stress: no BW_LAW_NOT_CONVERGED. */
  const int n = getenv("BW_CAP_TRIALS") ? atoi(getenv("BW_CAP_TRIALS")) : 10000;
  int       count[8] = {0}, nfd = 0;
  double    worst_f = 0, worst_flow = 0, worst_fd = 0;
  for (int it = 0; it < n; it++) {
    double par[BW_LAW_NPAR], s[BW_LAW_NSTATE], j[2], f[3];
    double sig = cap_random_case(par, s, j);
    Ret    o   = cap_law(par, s, j[0], j[1]);
    CHECK(o.status == 0, "cap property %d: status %d", it, o.status);
    if (o.status) printf("  par kt %.17g kn %.17g ft %.17g c %.17g tphi %.17g tpsi %.17g gfI %.17g gfII %.17g fc %.17g css %.17g gfc %.17g kp %.17g\n  s %.17g %.17g %.17g %.17g %.17g j %.17g %.17g\n", par[0], par[1], par[2], par[3], par[4], par[5], par[6], par[7], par[8], par[9], par[10], par[11], s[0], s[1], s[2], s[3], s[4], j[0], j[1]);
    if (o.status) continue;
    count[o.mode & 7]++;
    surfaces(par, o.r, o.s, f);
    double f3 = cap_f(par, o.r, o.s[BW_LAW_STATE_K3]);
    worst_f   = fmax(worst_f, fmax(fmax(f[0], f3), fmax(f[1], f[2])) / sig);
    CHECK(f[0] <= 1e-11 * sig && f[1] <= 1e-11 * sig && f[2] <= 1e-11 * sig && f3 <= 1e-11 * sig, "cap property %d: surface violated %g %g %g %g (sig %g)", it, f[0], f[1], f[2], f3, sig);
    double dk2 = o.s[K2] - s[K2], dk3 = o.s[BW_LAW_STATE_K3] - s[BW_LAW_STATE_K3], d[2] = {o.s[SLIP] - s[SLIP], o.s[OPEN] - s[OPEN]};
    double css = par[BW_LAW_PAR_CSS], nrm[2] = {css * o.r[0], o.r[1]}, nn = hypot(nrm[0], nrm[1]);
    double tolj = 1e-11 * sig / CAP_KT;
    CHECK(dk3 >= 0, "cap property %d: k3 decreased", it);
    if (o.mode & 4) {
      /* the cap's flow along its normal with length dk3, plus the cut-off's (0, dk1) and the
       * cone's dk2 (sign of the trial shear, tanpsi) where the mode has them */
      double sg = j[0] - s[SLIP] >= 0 ? 1 : -1, tpsi = par[BW_LAW_PAR_TANPSI], dk1 = o.s[K1] - s[K1];
      double e = fmax(fabs(d[0] - dk2 * sg - dk3 * nrm[0] / nn), fabs(d[1] - dk1 - dk2 * tpsi - dk3 * nrm[1] / nn));
      worst_flow = fmax(worst_flow, e / (sig / CAP_KT));
      CHECK(e <= tolj && dk1 >= 0 && dk2 >= 0, "cap property %d: flow (%g, dk1 %g, dk2 %g, mode %d)", it, e, dk1, dk2, o.mode);
      CHECK((o.mode & 1 || dk1 == 0) && (o.mode & 2 || dk2 == 0), "cap property %d: k1 or k2 grew off their surfaces (mode %d)", it, o.mode);
      CHECK(fabs(f3) <= 1e-11 * sig, "cap property %d: mode %d off the cap", it, o.mode);
    } else CHECK(dk3 == 0, "cap property %d: k3 grew off the cap (mode %d)", it, o.mode);
    double tolr = 1e-15 * (CAP_KT * fabs(j[0]) + CAP_KN * fabs(j[1]) + fabs(o.r[0]) + fabs(o.r[1]));
    CHECK(fabs(o.r[0] - CAP_KT * (j[0] - o.s[SLIP])) <= tolr && fabs(o.r[1] - CAP_KN * (j[1] - o.s[OPEN])) <= tolr, "cap property %d: r != C (j - jpl)", it);
    {
      double h = 1e-6 * fmax(fmax(fabs(j[0] - s[SLIP]), fabs(j[1] - s[OPEN])), 1e-9), fd[4], e = 0;
      int    same = 1;
      for (int cc = 0; cc < 2; cc++)
        for (int m = 1; m <= 2; m++) {
          Ret p = cap_law(par, s, j[0] + m * (cc == 0) * h, j[1] + m * (cc == 1) * h), q = cap_law(par, s, j[0] - m * (cc == 0) * h, j[1] - m * (cc == 1) * h);
          same  = same && p.mode == o.mode && q.mode == o.mode;
          if (m == 1)
            for (int row = 0; row < 2; row++) fd[2 * row + cc] = (p.r[row] - q.r[row]) / (2 * h);
        }
      for (int q = 0; q < 4; q++) e = fmax(e, fabs(fd[q] - o.T[q]) / fmax(CAP_KN, maxabs4(o.T)));
      if (same) {
        nfd++;
        worst_fd = fmax(worst_fd, e);
        CHECK(e <= 1e-6, "cap property %d: tangent error %.3e (mode %d)", it, e, o.mode);
      }
    }
  }
  printf("cap property: %d trials, modes 0/1/2/3/4/5/6 = %d/%d/%d/%d/%d/%d/%d; worst f/sig %.2e, worst flow mismatch kt/sig %.2e; tangent checked at %d, worst %.2e\n", n, count[0], count[1], count[2], count[3], count[4], count[5], count[6], worst_f, worst_flow, nfd, worst_fd);
  CHECK(count[4] > n / 10 && count[6] > n / 30, "cap property: too few returns to the cap (%d) or its corner (%d)", count[4], count[6]);
}

static void test_cap3d(void)
{
  /* The cap in 3D is the 2D return on the meridian plane: (a) with no b component the ns = 3
   * kernel gives the ns = 2 answer, stress, tangent and state, to round-off (1e-14 sig);
   * (b) a rotation of the (t, b) plane rotates stress, slip and tangent (1e-12 sig; the
   * tangent 1e-9 kn, as the law without cap). 10^4 random cases each. */
  const int n = 10000;
  double    worst_a = 0, worst_b = 0;
  for (int it = 0; it < n; it++) {
    double par[BW_LAW_NPAR], s[BW_LAW_NSTATE_MAX] = {0}, j[3];
    double sig = cap_random_case(par, s, j);
    Ret    o2  = cap_law(par, s, j[0], j[1]);
    double s3[BW_LAW_NSTATE_MAX], j3[3] = {j[0], j[1], 0}, r3[3], T3[9], so3[BW_LAW_NSTATE_MAX];
    signed char m3;
    int         st;
    memcpy(s3, s, sizeof(s3));
    s3[SLIPB] = 0;
    bw_law_coulomb_cap(3, 1, par, s3, j3, r3, T3, so3, &m3, &st);
    CHECK(st == o2.status && m3 == o2.mode, "cap3d %d: status/mode %d/%d vs %d/%d", it, st, m3, o2.status, o2.mode);
    if (o2.status) printf("  par kt %.17g kn %.17g ft %.17g c %.17g tphi %.17g tpsi %.17g gfI %.17g gfII %.17g fc %.17g css %.17g gfc %.17g kp %.17g\n  s %.17g %.17g %.17g %.17g %.17g j %.17g %.17g\n", par[0], par[1], par[2], par[3], par[4], par[5], par[6], par[7], par[8], par[9], par[10], par[11], s[0], s[1], s[2], s[3], s[4], j[0], j[1]);
    double e = fmax(fabs(r3[0] - o2.r[0]), fmax(fabs(r3[1] - o2.r[1]), fabs(r3[2]))) / sig;
    for (int k = 0; k < BW_LAW_NSTATE; k++) e = fmax(e, fabs(so3[k] - o2.s[k]) * CAP_KT / sig);
    e = fmax(e, fmax(fmax(fabs(T3[0] - o2.T[0]), fabs(T3[1] - o2.T[1])), fmax(fabs(T3[3] - o2.T[2]), fabs(T3[4] - o2.T[3]))) / fmax(CAP_KN, maxabs4(o2.T)) * 1e-3);
    worst_a = fmax(worst_a, e);
    CHECK(e <= 1e-12, "cap3d %d: 3D without b differs from 2D by %.2e", it, e);
    /* rotate the shear plane by th: the jump's and the slip's (t, b) parts */
    double th = 6.283185307179586 * uniform(), c = cos(th), sn = sin(th);
    double sr[BW_LAW_NSTATE_MAX], jr[3] = {c * j[0], j[1], sn * j[0]}, rr[3], Tr[9], sor[BW_LAW_NSTATE_MAX];
    signed char mr;
    memcpy(sr, s3, sizeof(sr));
    sr[SLIP]  = c * s3[SLIP];
    sr[SLIPB] = sn * s3[SLIP];
    bw_law_coulomb_cap(3, 1, par, sr, jr, rr, Tr, sor, &mr, &st);
    double eb = fmax(fabs(rr[0] - c * r3[0]), fmax(fabs(rr[1] - r3[1]), fabs(rr[2] - sn * r3[0]))) / sig;
    eb        = fmax(eb, fmax(fabs(sor[SLIP] - c * so3[SLIP]), fabs(sor[SLIPB] - sn * so3[SLIP])) * CAP_KT / sig);
    eb        = fmax(eb, fabs(sor[BW_LAW_STATE_K3] - so3[BW_LAW_STATE_K3]) * CAP_KT / sig);
    /* drn/d(jump along the rotated t) = drn/ddt of the unrotated case */
    eb = fmax(eb, fabs(c * Tr[3] + sn * Tr[5] - T3[3]) / fmax(CAP_KN, fabs(T3[3])) * 1e-3);
    worst_b = fmax(worst_b, eb);
    CHECK(st == 0 && mr == m3 && eb <= 1e-12, "cap3d %d: rotated case differs by %.2e (mode %d vs %d, status %d, 2D status %d)", it, eb, mr, m3, st, o2.status);
  }
  printf("cap3d: %d cases, worst 3D-vs-2D %.2e, worst rotation error %.2e\n", n, worst_a, worst_b);
}

static void test_cap_bad(void)
{
  /* Invalid cap parameters are BW_LAW_BAD_STRENGTH for coulomb_cap; coulomb does not read them. */
  double      par[BW_LAW_NPAR], s[BW_LAW_NSTATE] = {0}, j[2] = {1e-5, -1e-4}, r[2], T[4], so[BW_LAW_NSTATE];
  signed char mode;
  int         st;
  struct {
    int    index;
    double value;
    int    want;
  } cases[] = {
    {BW_LAW_PAR_FC, 0, BW_LAW_BAD_STRENGTH},    {BW_LAW_PAR_FC, -1e6, BW_LAW_BAD_STRENGTH}, {BW_LAW_PAR_FC, NAN, BW_LAW_BAD_STRENGTH},
    {BW_LAW_PAR_CSS, 0, BW_LAW_BAD_STRENGTH},   {BW_LAW_PAR_CSS, INFINITY, BW_LAW_BAD_STRENGTH}, {BW_LAW_PAR_KP, 0, BW_LAW_BAD_STRENGTH},
    {BW_LAW_PAR_GFC, NAN, BW_LAW_BAD_STRENGTH}, {BW_LAW_PAR_GFC, -1, BW_LAW_OK},               {BW_LAW_PAR_KP, 1e-4, BW_LAW_OK},
  };
  for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
    set_par(par, 2e5, 3e5, 0.75, 0.2, 12, 50);
    set_cap(par, 10e6, 9, 5000, 1e-4);
    par[cases[i].index] = cases[i].value;
    bw_law_coulomb_cap(2, 1, par, s, j, r, T, so, &mode, &st);
    CHECK(st == cases[i].want, "coulomb_cap: par[%d] = %g gave status %d, want %d", cases[i].index, cases[i].value, st, cases[i].want);
    bw_law_coulomb(2, 1, par, s, j, r, T, so, &mode, &st);
    CHECK(st == BW_LAW_OK, "coulomb: par[%d] = %g gave status %d", cases[i].index, cases[i].value, st);
  }
  set_cap(par, 10e6, 9, 5000, 1e-4);
  s[BW_LAW_STATE_K3] = -1e-9;
  bw_law_coulomb_cap(2, 1, par, s, j, r, T, so, &mode, &st);
  CHECK(st == BW_LAW_BAD_STATE, "k3 < 0 gave %d", st);
  s[BW_LAW_STATE_K3] = NAN;
  bw_law_coulomb_cap(2, 1, par, s, j, r, T, so, &mode, &st);
  CHECK(st == BW_LAW_BAD_STATE, "NaN k3 gave %d", st);
}

int main(int argc, char **argv)
{
  const char *which = argc > 1 ? argv[1] : "all";
  int         ran   = 0;
#define RUN(name, call) \
  if (!strcmp(which, name) || !strcmp(which, "all")) { \
    call; \
    ran++; \
  }
  RUN("elastic", test_elastic());
  RUN("cutoff", test_cutoff());
  RUN("coulomb", test_coulomb());
  RUN("corner", test_corner());
  RUN("apex", test_apex());
  RUN("notension", test_notension());
  RUN("soft_mode1", test_softening(0));
  RUN("soft_mode2", test_softening(1));
  RUN("unload", test_unload());
  RUN("tangent", test_tangent());
  RUN("property", test_property());
  RUN("bad", test_bad());
  RUN("cone3d", test_cone3d());
  RUN("extrude3d", test_extrude3d());
  RUN("rotate3d", test_rotate3d());
  RUN("property3d", test_property3d());
  RUN("bad3d", test_bad3d());
  RUN("cap_uniaxial", test_cap_uniaxial());
  RUN("cap_property", test_cap_property());
  RUN("cap3d", test_cap3d());
  RUN("cap_bad", test_cap_bad());
  if (!ran) { /* a mistyped case name must not pass having checked nothing */
    fprintf(stderr, "FAIL unknown case %s\n", which);
    return 1;
  }
  printf("%s: %s\n", which, failures ? "FAILED" : "passed");
  return failures ? 1 : 0;
}
