/* The joint-law registry (src/law): a law read from its keys by name, its
 * elastic part against the closed forms, the kernel it selects, and the
 * 2x2 tangent it returns against central finite differences.
 *
 *   mortar    -joints_law mortar, E, nu, thickness: kn = E/e and
 *             kt = E/(2(1+nu) e) (1e-15); head joints inherit what they do
 *             not set (-joints_head_E doubles kn and kt, keeps nu and e)
 *   dry       -joints_law dry, kn, kt: taken as given
 *   elastic   without strength the kernel is "elastic": stress = C j and
 *             tangent C, exactly
 *   coulomb   with -joints_strength_* the kernel is "coulomb"; at jumps in
 *             each regime (elastic, open, sliding both ways, the corner,
 *             softening) from a state with plastic history, the tangent
 *             against central differences of the stress, h = 1e-7 of the
 *             jump scale: 1e-5 of max(kn, |tangent|) (truncation O(h^2)
 *             times the curvature of the exponential softening, round-off
 *             eps/h), where both sides stay in one regime
 * Usage: test_law_registry -case mortar|dry|elastic|coulomb [joint options] */
#include <petscsys.h>
#include "scene/scene.h"
#include "law/law.h"
#include "util/compat.h"
#include "expect.h"
#include "util/process.h"


static PetscReal Rel(PetscReal a, PetscReal b) { return PetscAbsReal(a - b) / PetscMax(PetscAbsReal(b), 1e-300); }

static PetscErrorCode Evaluate(BwJointLaw law, const PetscReal state[BW_LAW_NSTATE], const PetscReal j[2], PetscReal r[2], PetscReal t[4], signed char *mode)
{
  PetscReal so[BW_LAW_NSTATE];

  PetscFunctionBeginUser;
  PetscCall(BwJointLawEvaluate(law, law->par, 2, 1, state, j, r, t, so, mode, "test"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  BwScene    scene;
  BwJointLaw bed, head;
  char       which[32] = "";

  BwProcessDefaults(); /* the libraries run as under blockwall */

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-case", which, sizeof(which), NULL));
  PetscCall(BwSceneCreate(PETSC_COMM_WORLD, &scene));
  PetscCall(BwSceneLoad(scene, NULL));
  PetscCall(BwJointLawCreate(&bed));
  PetscCall(BwJointLawSetFromOptions(bed, scene, "joints_", NULL));
  if (!strcmp(which, "mortar")) {
    PetscReal E = 1.0e9, nu = 0.25, e = 0.02;
    EXPECT(!strcmp(bed->type, "mortar"), "law %s", bed->type);
    EXPECT(Rel(bed->par[BW_LAW_PAR_KN], E / e) <= 1e-15, "kn %.17g, E/e %.17g", bed->par[BW_LAW_PAR_KN], E / e);
    EXPECT(Rel(bed->par[BW_LAW_PAR_KT], E / (2 * (1 + nu) * e)) <= 1e-15, "kt %.17g, E/(2(1+nu)e) %.17g", bed->par[BW_LAW_PAR_KT], E / (2 * (1 + nu) * e));
    PetscCall(BwJointLawCreate(&head));
    PetscCall(BwJointLawSetFromOptions(head, scene, "joints_head_", bed));
    EXPECT(Rel(head->par[BW_LAW_PAR_KN], 2 * E / e) <= 1e-15 && Rel(head->par[BW_LAW_PAR_KT], 2 * E / (2 * (1 + nu) * e)) <= 1e-15, "head joints: kn %g, kt %g", head->par[BW_LAW_PAR_KN], head->par[BW_LAW_PAR_KT]);
    EXPECT(head->thickness == e && head->nu == nu, "head joints did not inherit nu, thickness: %g, %g", head->nu, head->thickness);
    PetscCall(BwJointLawDestroy(&head));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "mortar: kn = E/e, kt = E/(2(1+nu)e); head joints inherit\n"));
  } else if (!strcmp(which, "dry")) {
    EXPECT(!strcmp(bed->type, "dry") && bed->par[BW_LAW_PAR_KN] == 3e9 && bed->par[BW_LAW_PAR_KT] == 1e9, "dry: %s kn %g kt %g", bed->type, bed->par[BW_LAW_PAR_KN], bed->par[BW_LAW_PAR_KT]);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "dry: kn, kt as given\n"));
  } else if (!strcmp(which, "elastic")) {
    PetscReal st[BW_LAW_NSTATE] = {1e-6, 2e-6}, j[2] = {3e-5, -4e-5}, r[2], t[4]; /* the rest of the state 0 */
    signed char mode;
    EXPECT(!strcmp(bed->kernel_name, "elastic"), "kernel %s without strength", bed->kernel_name);
    PetscCall(Evaluate(bed, st, j, r, t, &mode));
    EXPECT(r[0] == bed->par[BW_LAW_PAR_KT] * (j[0] - st[0]) && r[1] == bed->par[BW_LAW_PAR_KN] * (j[1] - st[1]), "elastic stress (%g, %g)", r[0], r[1]);
    EXPECT(t[0] == bed->par[BW_LAW_PAR_KT] && t[1] == 0 && t[2] == 0 && t[3] == bed->par[BW_LAW_PAR_KN] && mode == 0, "elastic tangent %g %g %g %g", t[0], t[1], t[2], t[3]);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "elastic: stress C (j - jpl), tangent C\n"));
  } else if (!strcmp(which, "coulomb")) {
    const PetscReal kn = bed->par[BW_LAW_PAR_KN], kt = bed->par[BW_LAW_PAR_KT], ft = bed->par[BW_LAW_PAR_FT], c = bed->par[BW_LAW_PAR_C];
    /* states: virgin, and with plastic history (softened strengths) */
    const PetscReal states[2][BW_LAW_NSTATE] = {{0, 0, 0, 0, 0}, {2e-6, 3e-6, 3e-6, 2e-6, 0}};
    /* jumps in the regimes: elastic, open, sliding +, sliding -, corner */
    const PetscReal jumps[5][2] = {{0.2 * c / kt, -0.5 * ft / kn}, {0.1 * c / kt, 3 * ft / kn}, {4 * c / kt, -2 * ft / kn}, {-4 * c / kt, -2 * ft / kn}, {3 * c / kt, 4 * ft / kn}};
    PetscInt        checked = 0, seen[4] = {0, 0, 0, 0};
    PetscReal       worst = 0;
    EXPECT(!strcmp(bed->kernel_name, "coulomb") && bed->strength, "kernel %s with strength", bed->kernel_name);
    for (int s = 0; s < 2; s++)
      for (int q = 0; q < 5; q++) {
        PetscReal   j[2] = {jumps[q][0] + states[s][0], jumps[q][1] + states[s][1]}, r[2], t[4];
        signed char mode;
        PetscCall(Evaluate(bed, states[s], j, r, t, &mode));
        seen[mode & 3]++;
        for (int d = 0; d < 2; d++) {
          PetscReal   h = 1e-7 * (PetscAbsReal(j[0]) + PetscAbsReal(j[1])), jp[2] = {j[0], j[1]}, jm[2] = {j[0], j[1]}, rp[2], rm[2], tp[4], tm[4];
          signed char mp, mm;
          jp[d] += h;
          jm[d] -= h;
          PetscCall(Evaluate(bed, states[s], jp, rp, tp, &mp));
          PetscCall(Evaluate(bed, states[s], jm, rm, tm, &mm));
          if (mp != mode || mm != mode) continue; /* a kink between the two sides */
          for (int i = 0; i < 2; i++) {
            PetscReal fd = (rp[i] - rm[i]) / (2 * h), an = t[2 * i + d], sc = PetscMax(kn, PetscMax(PetscAbsReal(t[0]), PetscAbsReal(t[3])));
            EXPECT(PetscAbsReal(fd - an) <= 1e-5 * sc, "state %d, regime %d (mode %d): dr%d/dj%d kernel %.9e, differences %.9e", s, q, mode, i, d, an, fd);
            worst = PetscMax(worst, PetscAbsReal(fd - an) / sc);
            checked++;
          }
        }
      }
    EXPECT(seen[0] && seen[1] && seen[2], "regimes met: elastic %d, open %d, sliding %d, corner %d", (int)seen[0], (int)seen[1], (int)seen[2], (int)seen[3]);
    EXPECT(checked >= 24, "only %d tangent entries checked", (int)checked);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "coulomb: %d tangent entries against central differences, worst %.1e of max(kn, |T|); modes met %d %d %d %d\n", (int)checked, (double)worst, (int)seen[0], (int)seen[1], (int)seen[2], (int)seen[3]));
  } else {
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL unknown -case %s\n", which));
    bw_failures++;
  }
  PetscCall(BwJointLawDestroy(&bed));
  PetscCall(BwSceneDestroy(&scene));
  PetscCall(PetscFinalize());
  return bw_failures ? 1 : 0;
}
