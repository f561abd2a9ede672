/* BwJointLaw: how the joints of one kind (bed, head, unit) respond, per
 * portion: stress and ns x ns tangent from the jump and the portion's
 * state, in 2D (ns = 2) and 3D (ns = 3) alike.
 *
 * A law has two parts, each chosen by name from a registry:
 *   the elastic part (joints.law)   mortar: kn = E/e, kt = E/(2(1+nu) e)
 *                                   dry:    kn, kt given [N/m^3]
 *   the kernel                      elastic: r = C (j - jpl), tangent C
 *                                   coulomb (joints.strength given): tension
 *                                   cut-off, Coulomb friction with cohesion,
 *                                   dilatancy, exponential softening
 *                                   (model.md, "Nonlinear joints")
 *                                   coulomb_cap (strength.compression given):
 *                                   the same with the compressive cap
 * The kernels are pure Fortran (include/blockwall/laws.h); nothing outside
 * a law assumes a scalar kn or kt: assembly asks the law for the portions'
 * tangents. Another elastic parametrisation or strength law is one more
 * entry in a registry, not edits elsewhere. */
#pragma once
#include "scene/scene.h"
#include "blockwall/laws.h"

typedef void (*BwLawKernel)(int ns, int n, const double par[], const double state_in[], const double jump[], double stress[], double tangent[], double state_out[], signed char mode[], int *status);

typedef struct _n_BwJointLaw *BwJointLaw;
struct _n_BwJointLaw {
  char        type[32];          /* elastic part: mortar | dry */
  char        kernel_name[32];   /* elastic | coulomb | coulomb_cap */
  char        prefix[64];        /* its keys: joints_, joints_head_, joints_unit_ */
  PetscReal   thickness;         /* e [m]: the gap between block faces (mortar: also kn = E/e) */
  PetscReal   E, nu;             /* mortar [Pa, -] */
  PetscReal   par[BW_LAW_NPAR];  /* the kernel's parameters: kt, kn, ft, c, tan phi, tan psi, GfI, GfII, fc, Css, Gfc, kappa_p */
  PetscBool   strength;          /* joints.*.strength given: the law is nonlinear */
  BwLawKernel kernel;
};

/* Elastic parts: reads the law's own keys under law->prefix, fills
 * law->par[KT], par[KN] and law->thickness. */
typedef PetscErrorCode (*BwJointLawElastic)(BwJointLaw law, BwScene scene, PetscBool inherited);
PetscErrorCode BwJointLawRegister(const char name[], BwJointLawElastic elastic);
PetscErrorCode BwJointLawKernelRegister(const char name[], BwLawKernel kernel);

PetscErrorCode BwJointLawCreate(BwJointLaw *law);
/* Reads <prefix>law, the elastic part's keys and <prefix>strength.*; keys
 * not given keep the values of `parent` (NULL: the defaults). */
PetscErrorCode BwJointLawSetFromOptions(BwJointLaw law, BwScene scene, const char prefix[], BwJointLaw parent);
/* Stress, tangent, new state and mode of n portions with ns stress
 * components (2 in 2D, 3 in 3D) from their jumps, with the parameters par
 * (the law's, or an interface's own stiffness); an error names `what` (the
 * interface) when the kernel fails. */
PetscErrorCode BwJointLawEvaluate(BwJointLaw law, const PetscReal par[], PetscInt ns, PetscInt n, const PetscReal state_in[], const PetscReal jump[], PetscReal stress[], PetscReal tangent[], PetscReal state_out[], signed char mode[], const char what[]);
PetscErrorCode BwJointLawDestroy(BwJointLaw *law);
