/* BwModel: joint laws, portions, supports, loads and self-weight read from
 * the options database and laid out per block and per interface.
 *
 * Supports and loads are keyed by block-set name (supports.<set>.u1,
 * loads.<set>), so their option names are built from the geometry's sets;
 * any supports_* / loads_* option that matches no set is reported with the
 * file line it came from, since a misspelt set would otherwise leave a block
 * silently free or unloaded. */
#include <string.h>
#include "model/model.h"
#include "util/compat.h"

static const char *const BwJointLawTypes[] = {"mortar", "dry", "BwJointLawType", "BW_LAW_", NULL};
static const char *const BwDofNames[3]     = {"u1", "u2", "w"};
#define BW_GRAVITY 9.81

PetscErrorCode BwJointLawSetFromOptions(BwJointLaw *law, BwScene scene, const char prefix[], const BwJointLaw *parent)
{
  char      opt[6][128];
  PetscBool setE, setnu, setkn, setkt, sete;
  PetscInt  type;

  PetscFunctionBeginUser;
  if (parent) *law = *parent;
  else {
    law->type      = BW_LAW_MORTAR;
    law->thickness = 0.01;
    law->E         = 1.0e9;
    law->nu        = 0.2;
    law->kn        = 1.0e11;
    law->kt        = 4.0e10;
  }
  {
    const char *keys[6] = {"law", "thickness", "E", "nu", "kn", "kt"};
    for (int k = 0; k < 6; k++) PetscCall(PetscSNPrintf(opt[k], sizeof(opt[k]), "-%s%s", prefix, keys[k]));
  }
  type = law->type;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, parent ? "Head joints (scene key joints.head.*, running_bond; unset keys as joints.*)" : "Joints (scene key joints.*)", NULL);
  PetscCall(PetscOptionsEList(opt[0], "Joint law: mortar (E, nu, thickness) or dry (kn, kt)", NULL, BwJointLawTypes, 2, BwJointLawTypes[type], &type, NULL));
  PetscCall(PetscOptionsReal(opt[1], "Joint thickness e, the gap between block faces [m] (dry default 0)", NULL, law->thickness, &law->thickness, &sete));
  PetscCall(PetscOptionsReal(opt[2], "Mortar Young's modulus E [Pa]", NULL, law->E, &law->E, &setE));
  PetscCall(PetscOptionsReal(opt[3], "Mortar Poisson's ratio nu [-]", NULL, law->nu, &law->nu, &setnu));
  PetscCall(PetscOptionsReal(opt[4], "Dry joint normal stiffness kn [N/m^3]", NULL, law->kn, &law->kn, &setkn));
  PetscCall(PetscOptionsReal(opt[5], "Dry joint shear stiffness kt [N/m^3]", NULL, law->kt, &law->kt, &setkt));
  PetscOptionsEnd();
  law->type = (BwJointLawType)type;
  if (law->type == BW_LAW_DRY && !sete && !parent) law->thickness = 0;

  if (!(law->thickness >= 0 && !PetscIsInfOrNanReal(law->thickness))) PetscCall(BwSceneError(scene, opt[1], "must be >= 0, got %g", (double)law->thickness));
  if (law->type == BW_LAW_MORTAR) {
    if (setkn) PetscCall(BwSceneError(scene, opt[4], "applies to law dry, but the law is mortar (give E and nu)"));
    if (setkt) PetscCall(BwSceneError(scene, opt[5], "applies to law dry, but the law is mortar (give E and nu)"));
    if (!(law->E > 0 && PetscIsNormalReal(law->E))) PetscCall(BwSceneError(scene, opt[2], "must be > 0, got %g", (double)law->E));
    if (!(law->nu > -1 && law->nu < 0.5)) PetscCall(BwSceneError(scene, opt[3], "must be in (-1, 0.5), got %g", (double)law->nu));
    if (!(law->thickness > 0)) PetscCall(BwSceneError(scene, opt[1], "must be > 0 for a mortar joint (kn = E/e), got %g", (double)law->thickness));
    law->kn = law->E / law->thickness;
    law->kt = law->E / (2 * (1 + law->nu) * law->thickness);
    if (!PetscIsNormalReal(law->kn) || !PetscIsNormalReal(law->kt)) PetscCall(BwSceneError(scene, opt[1], "gives a joint stiffness E/e that is not a finite number (E = %g, e = %g)", (double)law->E, (double)law->thickness));
  } else {
    if (setE) PetscCall(BwSceneError(scene, opt[2], "applies to law mortar, but the law is dry (give kn and kt)"));
    if (setnu) PetscCall(BwSceneError(scene, opt[3], "applies to law mortar, but the law is dry (give kn and kt)"));
    if (!(law->kn > 0 && PetscIsNormalReal(law->kn))) PetscCall(BwSceneError(scene, opt[4], "must be > 0, got %g", (double)law->kn));
    if (!(law->kt > 0 && PetscIsNormalReal(law->kt))) PetscCall(BwSceneError(scene, opt[5], "must be > 0, got %g", (double)law->kt));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwModelCreate(BwGeometry geom, BwModel *model)
{
  PetscInt nb = geom->nblocks, ni = geom->ninterfaces;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(model));
  (*model)->geom = geom;
  (*model)->m    = 16;
  PetscCall(PetscCalloc2(ni, &(*model)->kn, ni, &(*model)->kt));
  PetscCall(PetscCalloc3(3 * nb, &(*model)->prescribed, 3 * nb, &(*model)->value, 3 * nb, &(*model)->load));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwModelDestroy(BwModel *model)
{
  PetscFunctionBeginUser;
  if (!*model) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFree2((*model)->kn, (*model)->kt));
  PetscCall(PetscFree3((*model)->prescribed, (*model)->value, (*model)->load));
  PetscCall(PetscFree(*model));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Every option under `prefix` (supports_ or loads_) must be <set><suffix>
 * for one of the suffixes; anything else names a set that does not exist. */
static PetscErrorCode BwModelCheckSetKeys(BwModel model, BwScene scene, const char prefix[], PetscInt nsuffix, const char *const suffix[], const char what[])
{
  BwGeometry g = model->geom;
  PetscInt   n;
  char     **names;

  PetscFunctionBeginUser;
  PetscCall(BwSceneListOptions(scene, prefix, &n, &names));
  for (PetscInt o = 0; o < n; o++) {
    PetscBool match = PETSC_FALSE;
    for (PetscInt s = 0; s < g->nsets && !match; s++) {
      for (PetscInt k = 0; k < nsuffix && !match; k++) {
        char want[256];
        PetscCall(PetscSNPrintf(want, sizeof(want), "%s%s%s", prefix, g->setname[s], suffix[k]));
        PetscCall(PetscStrcmp(want, names[o], &match));
      }
    }
    if (!match) {
      char opt[256], sets[1024];
      PetscCall(PetscSNPrintf(opt, sizeof(opt), "-%s", names[o]));
      PetscCall(BwGeometryGetSetNames(g, sets, sizeof(sets)));
      PetscCall(BwSceneError(scene, opt, "%s (sets: %s)", what, sets));
    }
  }
  PetscCall(PetscStrArrayDestroy(&names));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwModelSetFromOptions(BwModel model, BwScene scene, const BwJointLaw *bed, const BwJointLaw *head)
{
  BwGeometry g = model->geom;
  PetscInt   m = model->m;
  PetscReal  density = 0;

  PetscFunctionBeginUser;
  PetscOptionsBegin(g->comm, NULL, "Discretisation and self-weight", NULL);
  PetscCall(PetscOptionsInt("-discretization_m", "Portions m per interface (piecewise-constant stresses)", NULL, m, &m, NULL));
  PetscCall(PetscOptionsReal("-gravity_density", "Block density for self-weight -density*9.81*area*depth on F2 [kg/m^3]", NULL, density, &density, NULL));
  PetscOptionsEnd();
  if (m < 1) PetscCall(BwSceneError(scene, "-discretization_m", "must be >= 1, got %" PetscInt_FMT, m));
  if (m > 1048576) PetscCall(BwSceneError(scene, "-discretization_m", "must be <= 1048576, got %" PetscInt_FMT, m));
  if (!(density >= 0 && !PetscIsInfOrNanReal(density))) PetscCall(BwSceneError(scene, "-gravity_density", "must be >= 0, got %g", (double)density));
  model->m               = m;
  model->gravity_density = density;

  for (PetscInt k = 0; k < g->ninterfaces; k++) {
    const BwJointLaw *law = g->kind[k] == BW_JOINT_HEAD ? head : bed;
    model->kn[k]          = g->kn ? g->kn[k] : law->kn;
    model->kt[k]          = g->kt ? g->kt[k] : law->kt;
  }

  /* Supports: supports.<set>.{u1,u2,w} = prescribed value. */
  PetscOptionsBegin(g->comm, NULL, "Supports (scene key supports.<set>.{u1,u2,w}: prescribed value, 0 = fixed)", NULL);
  for (PetscInt s = 0; s < g->nsets; s++) {
    for (PetscInt c = 0; c < 3; c++) {
      char      opt[256];
      PetscReal v = 0;
      PetscBool set;

      PetscCall(PetscSNPrintf(opt, sizeof(opt), "-supports_%s_%s", g->setname[s], BwDofNames[c]));
      PetscCall(PetscOptionsReal(opt, "Prescribed dof of every block of the set [m or rad]", NULL, v, &v, &set));
      if (!set) continue;
      if (PetscIsInfOrNanReal(v)) PetscCall(BwSceneError(scene, opt, "must be a finite number, got %g", (double)v));
      for (PetscInt q = g->setoffsets[s]; q < g->setoffsets[s + 1]; q++) {
        PetscInt b = g->setblocks[q];
        if (model->prescribed[3 * b + c] && model->value[3 * b + c] != v)
          PetscCall(BwSceneError(scene, opt, "prescribes %g on block %" PetscInt_FMT ", which another set already prescribes to %g", (double)v, b, (double)model->value[3 * b + c]));
        model->prescribed[3 * b + c] = PETSC_TRUE;
        model->value[3 * b + c]      = v;
      }
    }
  }
  PetscOptionsEnd();
  {
    const char *const suffix[3] = {"_u1", "_u2", "_w"};
    PetscCall(BwModelCheckSetKeys(model, scene, "supports_", 3, suffix, "does not name a block set and a dof u1, u2 or w"));
  }

  /* Loads: loads.<set> = [F1, F2, M3] on every block of the set. */
  PetscOptionsBegin(g->comm, NULL, "Loads (scene key loads.<set>: [F1, F2, M3] at each block's centroid [N, N, N m])", NULL);
  for (PetscInt s = 0; s < g->nsets; s++) {
    char      opt[256];
    PetscReal f[3] = {0, 0, 0};
    PetscInt  n    = 3;
    PetscBool set;

    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-loads_%s", g->setname[s]));
    PetscCall(PetscOptionsRealArray(opt, "F1,F2,M3 on every block of the set", NULL, f, &n, &set));
    if (!set) continue;
    if (n != 3) PetscCall(BwSceneError(scene, opt, "must have 3 values F1, F2, M3, got %" PetscInt_FMT, n));
    for (PetscInt c = 0; c < 3; c++)
      if (PetscIsInfOrNanReal(f[c])) PetscCall(BwSceneError(scene, opt, "must hold finite numbers, got %g", (double)f[c]));
    for (PetscInt q = g->setoffsets[s]; q < g->setoffsets[s + 1]; q++)
      for (PetscInt c = 0; c < 3; c++) model->load[3 * g->setblocks[q] + c] += f[c];
  }
  PetscOptionsEnd();
  {
    const char *const suffix[1] = {""};
    PetscCall(BwModelCheckSetKeys(model, scene, "loads_", 1, suffix, "does not name a block set"));
  }
  for (PetscInt b = 0; b < g->nblocks; b++) model->load[3 * b + 1] -= density * BW_GRAVITY * g->area[b] * g->depth;
  PetscFunctionReturn(PETSC_SUCCESS);
}
