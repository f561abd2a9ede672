/* BwJointLaw: the registries, the common keys (law, strength) and the
 * kernel call. The elastic parts are in elastic.c. */
#include <string.h>
#include "law/law.h"
#include "util/compat.h"

static PetscFunctionList BwJointLawList = NULL, BwJointLawKernelList = NULL;

PetscErrorCode BwJointLawRegister(const char name[], BwJointLawElastic elastic)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFunctionListAdd(&BwJointLawList, name, elastic));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointLawKernelRegister(const char name[], BwLawKernel kernel)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFunctionListAdd(&BwJointLawKernelList, name, kernel));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PETSC_INTERN PetscErrorCode BwJointLawElastic_Mortar(BwJointLaw, BwScene, PetscBool);
PETSC_INTERN PetscErrorCode BwJointLawElastic_Dry(BwJointLaw, BwScene, PetscBool);

static PetscErrorCode BwJointLawRegisterAll(void)
{
  PetscFunctionBeginUser;
  if (BwJointLawList) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(BwJointLawRegister("mortar", BwJointLawElastic_Mortar));
  PetscCall(BwJointLawRegister("dry", BwJointLawElastic_Dry));
  PetscCall(BwJointLawKernelRegister("elastic", bw_law_elastic));
  PetscCall(BwJointLawKernelRegister("coulomb", bw_law_coulomb));
  PetscCall(BwJointLawKernelRegister("coulomb_cap", bw_law_coulomb_cap));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointLawCreate(BwJointLaw *law)
{
  PetscFunctionBeginUser;
  PetscCall(PetscNew(law));
  PetscCall(PetscStrncpy((*law)->type, "mortar", sizeof((*law)->type)));
  PetscCall(PetscStrncpy((*law)->kernel_name, "elastic", sizeof((*law)->kernel_name)));
  (*law)->thickness             = 0.01;
  (*law)->E                     = 1.0e9;
  (*law)->nu                    = 0.2;
  (*law)->par[BW_LAW_PAR_KN]    = 1.0e11;
  (*law)->par[BW_LAW_PAR_KT]    = 4.0e10;
  (*law)->par[BW_LAW_PAR_GFI]   = -1;
  (*law)->par[BW_LAW_PAR_GFII]  = -1;
  (*law)->par[BW_LAW_PAR_CSS]   = 9.0;
  (*law)->par[BW_LAW_PAR_GFC]   = -1;
  (*law)->kernel                = bw_law_elastic;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointLawDestroy(BwJointLaw *law)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(*law));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* "-<prefix><key>" */
static PetscErrorCode BwLawKey(BwJointLaw law, const char key[], char opt[], size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(opt, len, "-%s%s", law->prefix, key));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* joints.*.strength: tension cut-off, Coulomb friction, softening, and the
 * compressive cap (model.md, "Compressive cap"). */
#define BW_STRENGTH_NKEYS 10
static PetscErrorCode BwJointLawStrength(BwJointLaw law, BwScene scene)
{
  static const char *const keys[BW_STRENGTH_NKEYS]  = {"strength_tension", "strength_cohesion", "strength_friction", "strength_dilatancy", "strength_tension_energy", "strength_shear_energy", "strength_compression", "strength_compression_shear", "strength_compression_energy", "strength_compression_peak_plastic"};
  static const int         index[BW_STRENGTH_NKEYS] = {BW_LAW_PAR_FT, BW_LAW_PAR_C, BW_LAW_PAR_TANPHI, BW_LAW_PAR_TANPSI, BW_LAW_PAR_GFI, BW_LAW_PAR_GFII, BW_LAW_PAR_FC, BW_LAW_PAR_CSS, BW_LAW_PAR_GFC, BW_LAW_PAR_KP};
  /* what a strength block of its own leaves out */
  static const PetscReal   plain[BW_STRENGTH_NKEYS] = {0, 0, 0, 0, -1, -1, 0, 9.0, -1, 0};
  static const char *const help[BW_STRENGTH_NKEYS]  = {"Tensile strength ft >= 0 [Pa] (0: no tension)", "Cohesion c >= 0 [Pa]", "Friction coefficient tan(phi) >= 0", "Dilatancy tan(psi), 0 <= tan(psi) <= tan(phi)", "Mode I fracture energy GfI > 0 [J/m^2]: exponential softening of ft", "Mode II fracture energy GfII > 0 [J/m^2]: exponential softening of c", "Compressive strength fc > 0 [Pa]: the compressive cap (absent or 0: any compression)", "Shear term Css > 0 of the cap rn^2 + Css |tau|^2 <= sbar^2", "Compressive fracture energy Gfc > 0 [J/m^2]: hardening and softening of the cap (absent: perfectly plastic at fc)", "Plastic compression kappa_p > 0 [m] at the cap's peak (with compression_energy)"};
  enum { FT, C, TANPHI, TANPSI, GFI, GFII, FC, CSS, GFC, KP };
  char      opt[BW_STRENGTH_NKEYS][128], mapping[128];
  PetscBool set[BW_STRENGTH_NKEYS], any = PETSC_FALSE;
  PetscReal v[BW_STRENGTH_NKEYS], kn = law->par[BW_LAW_PAR_KN];

  PetscFunctionBeginUser;
  PetscCall(BwLawKey(law, "strength", mapping, sizeof(mapping)));
  PetscCall(BwSceneRequireMapping(scene, mapping, "tension, cohesion, friction, dilatancy, tension_energy, shear_energy, compression, compression_shear, compression_energy, compression_peak_plastic"));
  for (int k = 0; k < BW_STRENGTH_NKEYS; k++) {
    PetscCall(BwLawKey(law, keys[k], opt[k], sizeof(opt[k])));
    v[k] = law->par[index[k]];
    PetscCall(BwSceneReal(scene, opt[k], help[k], &v[k], &set[k]));
    any = (PetscBool)(any || set[k]);
  }
  if (!any) PetscFunctionReturn(PETSC_SUCCESS); /* inherited as it is, or none */
  if (!law->strength) {
    /* a strength block of its own: what it does not give is the plain default */
    for (int k = 0; k < BW_STRENGTH_NKEYS; k++)
      if (!set[k]) v[k] = plain[k];
  }
  for (int k = 0; k < 4; k++)
    if (!(v[k] >= 0)) PetscCall(BwSceneError(scene, opt[k], "must be >= 0, got %g", (double)v[k]));
  if (!(v[TANPSI] <= v[TANPHI])) PetscCall(BwSceneError(scene, opt[TANPSI], "must not exceed the friction coefficient tan(phi) = %g, got %g", (double)v[TANPHI], (double)v[TANPSI]));
  for (int k = GFI; k <= GFII; k++)
    if (set[k] && !(v[k] > 0)) PetscCall(BwSceneError(scene, opt[k], "must be > 0 (leave it out for no softening), got %g", (double)v[k]));
  /* A portion softens more steeply than it is stiff when ft^2/GfI >= kn:
   * its stress would snap back within one portion, which no return mapping
   * can follow (the kernel's local problem has no unique solution). */
  if (v[GFI] > 0 && !(v[FT] * v[FT] / v[GFI] < kn))
    PetscCall(BwSceneError(scene, opt[GFI], "must exceed ft^2/kn = %g J/m^2 (ft = %g Pa, kn = %g N/m^3), else a portion snaps back", (double)(v[FT] * v[FT] / kn), (double)v[FT], (double)kn));
  if (v[GFII] > 0 && !(v[C] * v[C] / v[GFII] < law->par[BW_LAW_PAR_KT]))
    PetscCall(BwSceneError(scene, opt[GFII], "must exceed c^2/kt = %g J/m^2 (c = %g Pa, kt = %g N/m^3), else a portion snaps back", (double)(v[C] * v[C] / law->par[BW_LAW_PAR_KT]), (double)v[C], (double)law->par[BW_LAW_PAR_KT]));
  /* The cap: fc > 0 turns it on; its other keys mean nothing without it. */
  /* 0 turns off a cap a head or unit joint would inherit from joints.strength */
  if (set[FC] && !(v[FC] >= 0 && PetscIsNormalReal(v[FC] + 1))) PetscCall(BwSceneError(scene, opt[FC], "must be > 0 (0 or left out: no cap), got %g", (double)v[FC]));
  for (int k = CSS; k <= KP; k++) {
    if (set[k] && !(v[FC] > 0)) PetscCall(BwSceneError(scene, opt[k], "applies only with a compressive strength (strength.compression)"));
    if (set[k] && !(v[k] > 0 && PetscIsNormalReal(v[k]))) PetscCall(BwSceneError(scene, opt[k], "must be > 0, got %g", (double)v[k]));
  }
  if (v[FC] > 0 && v[GFC] > 0) {
    if (!(v[KP] > 0)) PetscCall(BwSceneError(scene, opt[GFC], "needs strength.compression_peak_plastic (kappa_p > 0, the plastic compression at the cap's peak [m])"));
    /* the softening parabola's steepest slope, 2 (sm - sp)/(km - kp) =
     * -67 fc^2/(75 Gfc), must stay below kn, as for the cut-off above */
    if (!(67 * v[FC] * v[FC] / (75 * v[GFC]) < kn))
      PetscCall(BwSceneError(scene, opt[GFC], "must exceed 67 fc^2/(75 kn) = %g J/m^2 (fc = %g Pa, kn = %g N/m^3), else a portion snaps back in compression", (double)(67 * v[FC] * v[FC] / (75 * kn)), (double)v[FC], (double)kn));
  }
  for (int k = 0; k < BW_STRENGTH_NKEYS; k++) law->par[index[k]] = v[k];
  law->strength = PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointLawSetFromOptions(BwJointLaw law, BwScene scene, const char prefix[], BwJointLaw parent)
{
  char              opt[128], mapping[128], names[128] = "";
  const char      **list;
  int               nlist;
  PetscInt          type = 0, ntypes = 0;
  const char       *types[8];
  BwJointLawElastic elastic;
  PetscBool         set;

  PetscFunctionBeginUser;
  PetscCall(BwJointLawRegisterAll());
  if (parent) {
    char keep[64];
    PetscCall(PetscStrncpy(keep, prefix, sizeof(keep)));
    *law = *parent;
    PetscCall(PetscStrncpy(law->prefix, keep, sizeof(law->prefix)));
  } else PetscCall(PetscStrncpy(law->prefix, prefix, sizeof(law->prefix)));
  PetscCall(PetscSNPrintf(mapping, sizeof(mapping), "-%s", prefix));
  mapping[strlen(mapping) - 1] = 0; /* -joints, -joints_head */
  PetscCall(BwSceneRequireMapping(scene, mapping, "law, thickness, E, nu or kn, kt, strength"));
  PetscCall(PetscFunctionListGet(BwJointLawList, &list, &nlist));
  for (int l = 0; l < nlist && ntypes < 8; l++) {
    if (!list[l] || !list[l][0]) continue;
    if (!strcmp(list[l], law->type)) type = ntypes;
    types[ntypes++] = list[l];
  }
  PetscCall(BwLawKey(law, "law", opt, sizeof(opt)));
  PetscCall(BwSceneEnum(scene, opt, "Joint law: mortar (E, nu, thickness) or dry (kn, kt)", ntypes, types, &type, &set));
  /* a law changed from the parent's does not inherit the other law's values */
  if (set && parent && strcmp(types[type], parent->type)) parent = NULL;
  PetscCall(PetscStrncpy(law->type, types[type], sizeof(law->type)));
  PetscCall(PetscFree(list));
  PetscCall(PetscFunctionListFind(BwJointLawList, law->type, &elastic));
  PetscCheck(elastic, PETSC_COMM_SELF, PETSC_ERR_PLIB, "joint law %s is not registered (%s)", law->type, names);
  PetscCall(elastic(law, scene, parent ? PETSC_TRUE : PETSC_FALSE));
  PetscCall(BwJointLawStrength(law, scene));
  PetscCall(PetscStrncpy(law->kernel_name, !law->strength ? "elastic" : law->par[BW_LAW_PAR_FC] > 0 ? "coulomb_cap" : "coulomb", sizeof(law->kernel_name)));
  PetscCall(PetscFunctionListFind(BwJointLawKernelList, law->kernel_name, &law->kernel));
  PetscCheck(law->kernel, PETSC_COMM_SELF, PETSC_ERR_PLIB, "joint law kernel %s is not registered", law->kernel_name);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointLawEvaluate(BwJointLaw law, const PetscReal par[], PetscInt ns, PetscInt n, const PetscReal state_in[], const PetscReal jump[], PetscReal stress[], PetscReal tangent[], PetscReal state_out[], signed char mode[], const char what[])
{
  static const char *const why[] = {"", "has a non-positive or non-finite stiffness", "has an invalid strength", "found no admissible stress (the return mapping did not converge)", "met a non-finite jump", "met a non-finite or negative state", "was called with a number of stress components other than 2 or 3"};
  int                      status;

  PetscFunctionBeginUser;
  law->kernel((int)ns, (int)n, par, state_in, jump, stress, tangent, state_out, mode, &status);
  PetscCheck(status == BW_LAW_OK, PETSC_COMM_SELF, PETSC_ERR_NOT_CONVERGED, "%s: the %s joint law %s", what, law->kernel_name, status > 0 && status < 7 ? why[status] : "failed");
  PetscFunctionReturn(PETSC_SUCCESS);
}
