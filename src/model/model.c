/* BwModel: joint laws, portions, supports, loads and self-weight read from
 * the scene and laid out per block and per interface.
 *
 * Supports and loads are keyed by block-set name (supports.<set>.u1,
 * loads.<set>), so their option names are built from the geometry's sets;
 * any supports_* / loads_* option that matches no set is reported with the
 * file line it came from, since a misspelt set would otherwise leave a block
 * silently free or unloaded. */
#include <ctype.h>
#include <string.h>
#include "model/model.h"
#include "util/compat.h"

#define BW_GRAVITY 9.81

static const char *const BwDofNames2D[3] = {"u1", "u2", "w"};
static const char *const BwDofNames3D[6] = {"u1", "u2", "u3", "w1", "w2", "w3"};

const char *const *BwModelDofNames(BwModel model)
{
  return model->nd == 6 ? BwDofNames3D : BwDofNames2D;
}

PetscErrorCode BwModelCreate(MPI_Comm comm, BwModel *model)
{
  PetscFunctionBeginUser;
  PetscCall(PetscNew(model));
  (*model)->comm = comm;
  (*model)->m    = 16;
  (*model)->mb   = 1;
  (*model)->nd   = 3;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwModelDestroy(BwModel *model)
{
  PetscFunctionBeginUser;
  if (!*model) PetscFunctionReturn(PETSC_SUCCESS);
  for (int k = 0; k < BW_JOINT_NKINDS; k++) PetscCall(BwJointLawDestroy(&(*model)->law[k]));
  PetscCall(PetscFree2((*model)->kn, (*model)->kt));
  PetscCall(PetscFree3((*model)->prescribed, (*model)->value, (*model)->load));
  PetscCall(PetscFree(*model));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The block set an option under `prefix` names, with one of `suffix`
 * after it: "supports_top_beam_u1" -> set top_beam, dof 0. Set names may
 * hold '_', so the name is split at each suffix and looked up in a map of
 * the set names: linear in the number of keys (a scan of every set for
 * every key made 600 loaded sets quadratic). *set = -1: no such set. */
static void BwModelParseSetKey(const BwNameMap *sets, const char name[], size_t plen, PetscInt nsuffix, const char *const suffix[], PetscInt *set, PetscInt *which)
{
  size_t n = strlen(name);
  char   buf[PETSC_MAX_OPTION_NAME];

  *set = *which = -1;
  for (PetscInt k = 0; k < nsuffix && *set < 0; k++) {
    size_t ls = strlen(suffix[k]);
    if (n < plen + ls + 1 || n - plen >= sizeof(buf) || !BwSameName(name + n - ls, suffix[k])) continue;
    memcpy(buf, name + plen, n - plen - ls);
    buf[n - plen - ls] = 0;
    *set               = BwNameMapGet(sets, buf);
    *which             = k;
  }
}

static PetscBool BwHasPrefixCI(const char name[], const char prefix[])
{
  for (; *prefix; name++, prefix++)
    if (!*name || tolower((unsigned char)*name) != tolower((unsigned char)*prefix)) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* A key under `prefix` that names no set and dof: if it starts with a set's
 * name, the set's own key is of the wrong kind (supports.foundation: [0, 0,
 * 0], loads.top_beam: {a: 1}) and reading it says so; else the set does not
 * exist. */
static PetscErrorCode BwModelUnknownSet(BwModel model, BwScene scene, const BwNameMap *setmap, const char name[], size_t plen, PetscBool loads, const char what[])
{
  char opt[PETSC_MAX_OPTION_NAME + 1], sets[1024], buf[PETSC_MAX_OPTION_NAME];

  PetscFunctionBeginUser;
  for (size_t k = plen; name[k] && k - plen < sizeof(buf); k++) {
    if (name[k + 1] && name[k + 1] != '_') continue;
    memcpy(buf, name + plen, k + 1 - plen);
    buf[k + 1 - plen] = 0;
    if (BwNameMapGet(setmap, buf) < 0) continue;
    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-%.*s", (int)(k + 1), name));
    if (loads) {
      PetscReal *f;
      PetscInt   n;
      PetscCall(BwSceneRealArray(scene, opt, model->nd == 6 ? "F1, F2, F3, M1, M2, M3" : "F1, F2, M3", &f, &n, NULL));
      PetscCall(PetscFree(f));
    } else {
      const char *const *dofs = BwModelDofNames(model);
      PetscCall(BwSceneRequireMapping(scene, opt, model->nd == 6 ? "u1, u2, u3, w1, w2, w3: prescribed values" : "u1, u2, w: prescribed values"));
      for (int c = 0; c < model->nd; c++) {
        char      dof[PETSC_MAX_OPTION_NAME + 4];
        PetscReal v;
        PetscCall(PetscSNPrintf(dof, sizeof(dof), "%s_%s", opt, dofs[c]));
        if (BwHasPrefixCI(name, dof + 1)) PetscCall(BwSceneReal(scene, dof, "prescribed value", &v, NULL));
      }
    }
  }
  PetscCall(PetscSNPrintf(opt, sizeof(opt), "-%s", name));
  PetscCall(BwGeometryGetSetNames(model->geom, sets, sizeof(sets)));
  PetscCall(BwSceneError(scene, opt, "%s (sets: %s)", what, sets));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwModelSetMap(BwGeometry g, BwNameMap *map)
{
  PetscFunctionBeginUser;
  PetscCall(BwNameMapInit(map));
  for (PetscInt s = 0; s < g->nsets; s++) PetscCall(BwNameMapAdd(map, g->setname[s], s, NULL));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwModelSetLoads(BwModel model, BwScene scene, const char prefix[])
{
  PetscFunctionBeginUser;
  PetscCall(BwModelReadLoads(model, scene, prefix, PETSC_TRUE, model->load));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwModelReadLoads(BwModel model, BwScene scene, const char prefix[], PetscBool gravity, PetscReal load[])
{
  BwGeometry g = model->geom;
  BwNameMap  sets;
  PetscInt   n;
  char     **names, key[PETSC_MAX_OPTION_NAME], opt[PETSC_MAX_OPTION_NAME + 1];
  PetscReal  density = model->gravity_density;
  PetscBool  set;
  size_t     plen;

  PetscFunctionBeginUser;
  const PetscInt    nd    = model->nd;
  const char *const what  = nd == 6 ? "F1, F2, F3, M1, M2, M3" : "F1, F2, M3";

  PetscCall(PetscArrayzero(load, nd * g->nblocks));
  PetscCall(BwModelSetMap(g, &sets));
  /* loads.<set> = [F1, F2, M3] | [F1, F2, F3, M1, M2, M3] on every block of the set */
  PetscCall(PetscSNPrintf(key, sizeof(key), "%sloads_", prefix));
  PetscCall(PetscSNPrintf(opt, sizeof(opt), "-%sloads", prefix));
  PetscCall(BwSceneRequireMapping(scene, opt, nd == 6 ? "block set: [F1, F2, F3, M1, M2, M3]" : "block set: [F1, F2, M3]"));
  PetscCall(BwSceneListOptions(scene, key, &n, &names));
  plen = strlen(key);
  for (PetscInt o = 0; o < n; o++) {
    const char *const none[1] = {""};
    PetscInt          s, which, nf;
    PetscReal        *f;

    BwModelParseSetKey(&sets, names[o], plen, 1, none, &s, &which);
    if (s < 0) PetscCall(BwModelUnknownSet(model, scene, &sets, names[o], plen, PETSC_TRUE, "does not name a block set"));
    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-%s", names[o]));
    PetscCall(BwSceneRealArray(scene, opt, nd == 6 ? "F1, F2, F3, M1, M2, M3 on every block of the set [N, N m]" : "F1, F2, M3 on every block of the set [N, N, N m]", &f, &nf, NULL));
    if (nf != nd) {
      if (nf == 9 - nd) PetscCall(BwSceneError(scene, opt, "has %" PetscInt_FMT " values, a load of a %s scene; this scene is %s: %" PetscInt_FMT " values %s", nf, nd == 6 ? "2D" : "3D", nd == 6 ? "3D" : "2D", nd, what));
      PetscCall(BwSceneError(scene, opt, "must have %" PetscInt_FMT " values %s, got %" PetscInt_FMT, nd, what, nf));
    }
    for (PetscInt q = g->setoffsets[s]; q < g->setoffsets[s + 1]; q++)
      for (PetscInt c = 0; c < nd; c++) load[nd * g->setblocks[q] + c] += f[c];
    PetscCall(PetscFree(f));
  }
  PetscCall(PetscStrArrayDestroy(&names));
  PetscCall(BwNameMapDestroy(&sets));
  if (!gravity) PetscFunctionReturn(PETSC_SUCCESS);
  /* self-weight: a case may give its own density */
  if (prefix[0]) {
    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-%sgravity", prefix));
    PetscCall(BwSceneRequireMapping(scene, opt, "density"));
    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-%sgravity_density", prefix));
    PetscCall(BwSceneReal(scene, opt, "Block density of this case [kg/m^3]", &density, &set));
    if (set && !(density >= 0)) PetscCall(BwSceneError(scene, opt, "must be >= 0, got %g", (double)density));
  }
  if (g->dim == 3)
    for (PetscInt b = 0; b < g->nblocks; b++) load[nd * b + 1] -= density * BW_GRAVITY * g->volume[b];
  else
    for (PetscInt b = 0; b < g->nblocks; b++) load[nd * b + 1] -= density * BW_GRAVITY * g->area[b] * g->depth;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwModelSetFromOptions(BwModel model, BwScene scene)
{
  PetscInt  m       = model->m;
  PetscReal density = 0;

  PetscFunctionBeginUser;
  PetscCall(BwSceneHelpSection(scene, "Joints (scene key joints.*)"));
  PetscCall(BwJointLawCreate(&model->law[BW_JOINT_BED]));
  PetscCall(BwJointLawSetFromOptions(model->law[BW_JOINT_BED], scene, "joints_", NULL));
  PetscCall(BwSceneHelpSection(scene, "Discretisation and self-weight (scene keys discretization.*, gravity.*)"));
  PetscCall(BwSceneRequireMapping(scene, "-discretization", "m"));
  PetscCall(BwSceneRequireMapping(scene, "-gravity", "density"));
  PetscCall(BwSceneInt(scene, "-discretization_m", "Portions m per interface (piecewise-constant stresses)", &m, NULL));
  PetscCall(BwSceneReal(scene, "-gravity_density", "Block density for self-weight -density*9.81*area*depth on F2 [kg/m^3]", &density, NULL));
  if (m < 1) PetscCall(BwSceneError(scene, "-discretization_m", "must be >= 1, got %" PetscInt_FMT, m));
  if (m > 1048576) PetscCall(BwSceneError(scene, "-discretization_m", "must be <= 1048576, got %" PetscInt_FMT, m));
  if (!(density >= 0)) PetscCall(BwSceneError(scene, "-gravity_density", "must be >= 0, got %g", (double)density));
  model->m               = m;
  model->gravity_density = density;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwModelInterfaceLaw(BwModel model, PetscInt k, BwJointLaw *law, PetscReal par[])
{
  BwJointLaw l = model->law[model->geom->kind[k]];

  PetscFunctionBeginUser;
  if (law) *law = l;
  if (par) {
    PetscCall(PetscArraycpy(par, l->par, BW_LAW_NPAR));
    par[BW_LAW_PAR_KN] = model->kn[k];
    par[BW_LAW_PAR_KT] = model->kt[k];
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscBool BwModelTangentSymmetric(BwModel model)
{
  for (int kind = 0; kind < BW_JOINT_NKINDS; kind++) {
    BwJointLaw law = model->law[kind];
    if (law && law->strength && law->par[BW_LAW_PAR_TANPSI] != law->par[BW_LAW_PAR_TANPHI]) return PETSC_FALSE;
    /* a hardening or softening cap: k3 grows with the stress's direction, which
     * the associated flow does not make symmetric */
    if (law && law->strength && law->par[BW_LAW_PAR_FC] > 0 && law->par[BW_LAW_PAR_GFC] > 0) return PETSC_FALSE;
  }
  return PETSC_TRUE;
}

PetscErrorCode BwModelAllocate(BwModel model, BwGeometry g)
{
  PetscInt nb = g->nblocks, ni = g->ninterfaces;

  PetscFunctionBeginUser;
  PetscCheck(!model->geom, model->comm, PETSC_ERR_ORDER, "BwModelAllocate: the model already has a geometry");
  model->geom = g;
  PetscCall(PetscCalloc2(ni, &model->kn, ni, &model->kt));
  model->nd = g->dim == 3 ? 6 : 3;
  PetscCall(PetscCalloc3(model->nd * nb, &model->prescribed, model->nd * nb, &model->value, model->nd * nb, &model->load));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwModelSetUp(BwModel model, BwGeometry g, BwScene scene)
{
  PetscInt  ni = g->ninterfaces, n;
  BwNameMap sets;
  char    **names;

  PetscFunctionBeginUser;
  PetscCall(BwModelAllocate(model, g));
  /* head joints (unset keys as joints.*) and cracks in units (a law of their
   * own: a mortar joint's stiffness and strength mean nothing inside a unit)
   * are read only where the geometry has them, on any rank */
  {
    PetscInt here[BW_JOINT_NKINDS] = {0, 0, 0}, any[BW_JOINT_NKINDS];
    for (PetscInt k = 0; k < ni; k++) here[g->kind[k]] = 1;
    PetscCallMPI(MPIU_Allreduce(here, any, BW_JOINT_NKINDS, MPIU_INT, MPI_MAX, model->comm));
    for (int kind = 0; kind < BW_JOINT_NKINDS; kind++) {
      if (!any[kind] || model->law[kind]) continue;
    PetscCall(BwJointLawCreate(&model->law[kind]));
    if (kind == BW_JOINT_HEAD) {
      PetscCall(BwSceneHelpSection(scene, "Head joints (scene key joints.head.*, running_bond; unset keys as joints.*)"));
      PetscCall(BwJointLawSetFromOptions(model->law[kind], scene, "joints_head_", model->law[BW_JOINT_BED]));
    } else {
      PetscCall(BwSceneHelpSection(scene, "Cracks inside units (scene key joints.unit.*, running_bond.split_units)"));
      PetscCall(BwSceneRequireMapping(scene, "-joints_unit", "the law of the cracks inside the units"));
      PetscCall(BwJointLawSetFromOptions(model->law[kind], scene, "joints_unit_", NULL));
    }
    }
  }
  /* the stiffness that scales each interface's stresses: its law's elastic
   * one, or the file's own kn, kt */
  for (PetscInt k = 0; k < ni; k++) {
    const BwJointLaw law = model->law[g->kind[k]];
    model->kn[k]         = g->kn ? g->kn[k] : law->par[BW_LAW_PAR_KN];
    model->kt[k]         = g->kt ? g->kt[k] : law->par[BW_LAW_PAR_KT];
  }
  for (int kind = 0; kind < BW_JOINT_NKINDS; kind++)
    if (model->law[kind] && model->law[kind]->strength) model->nonlinear = PETSC_TRUE;

  /* discretization.m_b: 3D only */
  {
    PetscInt  mb = 4;
    PetscBool set;
    PetscCall(BwSceneInt(scene, "-discretization_m_b", "3D: portions m_b along b per interface (default 4)", &mb, &set));
    if (set && g->dim != 3) PetscCall(BwSceneError(scene, "-discretization_m_b", "has no meaning in 2D (the portions of a 2D interface are one row along t); it is a key of 3D scenes (geometry.dimension: 3)"));
    if (g->dim == 3) {
      if (mb < 1) PetscCall(BwSceneError(scene, "-discretization_m_b", "must be >= 1, got %" PetscInt_FMT, mb));
      if (mb > 1048576) PetscCall(BwSceneError(scene, "-discretization_m_b", "must be <= 1048576, got %" PetscInt_FMT, mb));
      model->mb = mb;
    }
  }

  /* Supports: supports.<set>.<dof> = prescribed value. A dof of the other
   * dimension (w in 3D, u3 or w1 in 2D) is named as such. */
  {
    const PetscInt     nd = model->nd;
    const char *const *dofs = BwModelDofNames(model), *const *other = nd == 6 ? BwDofNames2D : BwDofNames3D;
    const char        *dofs_list = nd == 6 ? "u1, u2, u3, w1, w2, w3" : "u1, u2, w";
    char               help[128], suffix_buf[6][8], other_buf[6][8];
    const char        *suffix[6], *osuffix[6];

    for (PetscInt c = 0; c < nd; c++) {
      PetscCall(PetscSNPrintf(suffix_buf[c], sizeof(suffix_buf[c]), "_%s", dofs[c]));
      suffix[c] = suffix_buf[c];
    }
    for (PetscInt c = 0; c < 9 - nd; c++) {
      PetscCall(PetscSNPrintf(other_buf[c], sizeof(other_buf[c]), "_%s", other[c]));
      osuffix[c] = other_buf[c];
    }
    PetscCall(PetscSNPrintf(help, sizeof(help), "Supports (scene key supports.<set>.{%s}: prescribed value [m or rad], 0 = fixed)", dofs_list));
    PetscCall(BwSceneHelpSection(scene, help));
    PetscCall(PetscSNPrintf(help, sizeof(help), "block set: {%s: value, ...}", dofs_list));
    PetscCall(BwSceneRequireMapping(scene, "-supports", help));
    PetscCall(BwModelSetMap(g, &sets));
    PetscCall(BwSceneListOptions(scene, "supports_", &n, &names));
    for (PetscInt o = 0; o < n; o++) {
      char      opt[PETSC_MAX_OPTION_NAME + 1], msg[128];
      PetscInt  s, c;
      PetscReal v = 0;

      BwModelParseSetKey(&sets, names[o], strlen("supports_"), nd, suffix, &s, &c);
      if (s < 0) {
        PetscInt so, co;
        BwModelParseSetKey(&sets, names[o], strlen("supports_"), 9 - nd, osuffix, &so, &co);
        PetscCall(PetscSNPrintf(opt, sizeof(opt), "-%s", names[o]));
        if (so >= 0) PetscCall(BwSceneError(scene, opt, "names dof %s, which has no meaning in %s: the dofs of a %s scene are %s", other[co], nd == 6 ? "3D" : "2D", nd == 6 ? "3D" : "2D", dofs_list));
        PetscCall(PetscSNPrintf(msg, sizeof(msg), "does not name a block set and a dof %s", dofs_list));
        PetscCall(BwModelUnknownSet(model, scene, &sets, names[o], strlen("supports_"), PETSC_FALSE, msg));
      }
      PetscCall(PetscSNPrintf(opt, sizeof(opt), "-supports_%s", g->setname[s]));
      PetscCall(PetscSNPrintf(help, sizeof(help), "%s: prescribed values", dofs_list));
      PetscCall(BwSceneRequireMapping(scene, opt, help));
      PetscCall(PetscSNPrintf(opt, sizeof(opt), "-%s", names[o]));
      PetscCall(BwSceneReal(scene, opt, "Prescribed dof of every block of the set [m or rad]", &v, NULL));
      {
        PetscInt  clash = -1; /* the lowest global id prescribed twice here */
        PetscReal other = 0;
        for (PetscInt q = g->setoffsets[s]; q < g->setoffsets[s + 1]; q++) {
          PetscInt b = g->setblocks[q];
          if (model->prescribed[nd * b + c] && model->value[nd * b + c] != v && (clash < 0 || g->gblock[b] < clash)) {
            clash = g->gblock[b];
            other = model->value[nd * b + c];
          }
          model->prescribed[nd * b + c] = PETSC_TRUE;
          model->value[nd * b + c]      = v;
        }
        PetscCall(BwSceneErrorAgree(scene, clash >= 0 ? PETSC_TRUE : PETSC_FALSE, opt, "prescribes %g on block %" PetscInt_FMT ", which another set already prescribes to %g", (double)v, clash, (double)other));
      }
    }
  }
  PetscCall(PetscStrArrayDestroy(&names));
  PetscCall(BwNameMapDestroy(&sets));

  PetscCall(BwSceneHelpSection(scene, model->nd == 6 ? "Loads (scene key loads.<set>: [F1, F2, F3, M1, M2, M3] at each block's centroid [N, N m])" : "Loads (scene key loads.<set>: [F1, F2, M3] at each block's centroid [N, N, N m])"));
  PetscCall(BwModelSetLoads(model, scene, ""));
  PetscFunctionReturn(PETSC_SUCCESS);
}
