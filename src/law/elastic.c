/* The elastic parts of the joint laws, by name (joints.law):
 *   mortar  a mortar layer of thickness e:  kn = E/e,  kt = E/(2(1+nu) e)
 *   dry     contact of bare faces:          kn, kt given [N/m^3], e = 0 by default
 * Each reads its own keys and refuses the other's, which would otherwise be
 * ignored silently (E with law: dry). */
#include "law/law.h"
#include "util/compat.h"

static PetscErrorCode BwLawOption(BwJointLaw law, const char key[], char opt[], size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(opt, len, "-%s%s", law->prefix, key));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Keys of the other law must not be given. */
static PetscErrorCode BwLawRefuse(BwJointLaw law, BwScene scene, PetscInt n, const char *const keys[], const char other[], const char instead[])
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < n; k++) {
    char      opt[128];
    PetscReal v = 0;
    PetscBool set;
    PetscCall(BwLawOption(law, keys[k], opt, sizeof(opt)));
    PetscCall(BwSceneReal(scene, opt, "(not for this law)", &v, &set));
    if (set) PetscCall(BwSceneError(scene, opt, "applies to law %s, but the law is %s (give %s)", other, law->type, instead));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PETSC_INTERN PetscErrorCode BwJointLawElastic_Mortar(BwJointLaw law, BwScene scene, PetscBool inherited)
{
  static const char *const dry[2] = {"kn", "kt"};
  char                     oe[128], oE[128], onu[128];

  PetscFunctionBeginUser;
  PetscCall(BwLawOption(law, "thickness", oe, sizeof(oe)));
  PetscCall(BwLawOption(law, "E", oE, sizeof(oE)));
  PetscCall(BwLawOption(law, "nu", onu, sizeof(onu)));
  if (!inherited) {
    law->thickness = 0.01;
    law->E         = 1.0e9;
    law->nu        = 0.2;
  }
  PetscCall(BwSceneReal(scene, oe, "Joint thickness e, the gap between block faces [m]", &law->thickness, NULL));
  PetscCall(BwSceneReal(scene, oE, "Mortar Young's modulus E [Pa]", &law->E, NULL));
  PetscCall(BwSceneReal(scene, onu, "Mortar Poisson's ratio nu [-]", &law->nu, NULL));
  PetscCall(BwLawRefuse(law, scene, 2, dry, "dry", "E and nu"));
  if (!(law->E > 0)) PetscCall(BwSceneError(scene, oE, "must be > 0, got %g", (double)law->E));
  if (!(law->nu > -1 && law->nu < 0.5)) PetscCall(BwSceneError(scene, onu, "must be in (-1, 0.5), got %g", (double)law->nu));
  if (!(law->thickness >= 0)) PetscCall(BwSceneError(scene, oe, "must be >= 0, got %g", (double)law->thickness));
  if (!(law->thickness > 0)) PetscCall(BwSceneError(scene, oe, "must be > 0 for a mortar joint (kn = E/e), got %g", (double)law->thickness));
  law->par[BW_LAW_PAR_KN] = law->E / law->thickness;
  law->par[BW_LAW_PAR_KT] = law->E / (2 * (1 + law->nu) * law->thickness);
  if (!PetscIsNormalReal(law->par[BW_LAW_PAR_KN]) || !PetscIsNormalReal(law->par[BW_LAW_PAR_KT])) PetscCall(BwSceneError(scene, oe, "gives a joint stiffness E/e that is not a finite number (E = %g, e = %g)", (double)law->E, (double)law->thickness));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PETSC_INTERN PetscErrorCode BwJointLawElastic_Dry(BwJointLaw law, BwScene scene, PetscBool inherited)
{
  static const char *const mortar[2] = {"E", "nu"};
  char                     oe[128], okn[128], okt[128];
  PetscBool                sete;

  PetscFunctionBeginUser;
  PetscCall(BwLawOption(law, "thickness", oe, sizeof(oe)));
  PetscCall(BwLawOption(law, "kn", okn, sizeof(okn)));
  PetscCall(BwLawOption(law, "kt", okt, sizeof(okt)));
  if (!inherited) {
    law->par[BW_LAW_PAR_KN] = 1.0e11;
    law->par[BW_LAW_PAR_KT] = 4.0e10;
  }
  PetscCall(BwSceneReal(scene, oe, "Joint thickness e, the gap between block faces [m] (dry default 0)", &law->thickness, &sete));
  if (!sete && !inherited) law->thickness = 0;
  PetscCall(BwSceneReal(scene, okn, "Dry joint normal stiffness kn [N/m^3]", &law->par[BW_LAW_PAR_KN], NULL));
  PetscCall(BwSceneReal(scene, okt, "Dry joint shear stiffness kt [N/m^3]", &law->par[BW_LAW_PAR_KT], NULL));
  PetscCall(BwLawRefuse(law, scene, 2, mortar, "mortar", "kn and kt"));
  if (!(law->thickness >= 0)) PetscCall(BwSceneError(scene, oe, "must be >= 0, got %g", (double)law->thickness));
  if (!(law->par[BW_LAW_PAR_KN] > 0)) PetscCall(BwSceneError(scene, okn, "must be > 0, got %g", (double)law->par[BW_LAW_PAR_KN]));
  if (!(law->par[BW_LAW_PAR_KT] > 0)) PetscCall(BwSceneError(scene, okt, "must be > 0, got %g", (double)law->par[BW_LAW_PAR_KT]));
  PetscFunctionReturn(PETSC_SUCCESS);
}
