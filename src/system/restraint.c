/* Restraint: find the blocks that can move without deforming any joint
 * before a solver meets a singular matrix, and name them. */
#include "system/mixed.h"
#include "util/compat.h"

/* Blocks with a free dof but no interface at all, and connected groups of
 * blocks none of which has a prescribed dof, can move freely: report them by
 * name before any solver sees a singular matrix. (Replicated data: every
 * rank finds the same and errors together.) */
PetscErrorCode BwMixedCheckRestraint(BwMixed mx)
{
  BwGeometry geom = mx->geom;
  PetscInt   nb = geom->nblocks, *comp, *stack, ncomp = 0;
  PetscBool *held;
  char       list[512];

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(nb, &comp, nb, &stack));
  for (PetscInt b = 0; b < nb; b++) comp[b] = -1;
  for (PetscInt b0 = 0; b0 < nb; b0++) {
    PetscInt top = 0;
    if (comp[b0] >= 0) continue;
    comp[b0]     = ncomp;
    stack[top++] = b0;
    while (top) {
      PetscInt b = stack[--top];
      for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) {
        PetscInt k = mx->adj[a], o = geom->pair[2 * k] == b ? geom->pair[2 * k + 1] : geom->pair[2 * k];
        if (comp[o] < 0) {
          comp[o]      = ncomp;
          stack[top++] = o;
        }
      }
    }
    ncomp++;
  }
  PetscCall(PetscCalloc1(ncomp, &held));
  for (PetscInt b = 0; b < nb; b++)
    for (PetscInt c = 0; c < 3; c++)
      if (mx->model->prescribed[3 * b + c]) held[comp[b]] = PETSC_TRUE;
  for (PetscInt b = 0; b < nb; b++) {
    PetscInt c = comp[b], count = 0, len;
    if (held[c]) continue;
    list[0] = 0;
    for (PetscInt o = b; o < nb; o++) {
      if (comp[o] != c) continue;
      if (count < 12) {
        char item[32];
        PetscCall(PetscSNPrintf(item, sizeof(item), "%s%" PetscInt_FMT, count ? ", " : "", o));
        PetscCall(PetscStrlcat(list, item, sizeof(list)));
      } else if (count == 12) PetscCall(PetscStrlcat(list, ", ...", sizeof(list)));
      count++;
    }
    PetscCall(PetscStrlen(list, (size_t *)&len));
    PetscCall(PetscFree(held));
    PetscCall(PetscFree2(comp, stack));
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "the assembly is not restrained: block%s %s (%" PetscInt_FMT " block%s) %s no path of interfaces to a support; free motion: rigid translation and rotation", count > 1 ? "s" : "", list, count, count > 1 ? "s" : "", count > 1 ? "have" : "has");
  }
  PetscCall(PetscFree(held));
  PetscCall(PetscFree2(comp, stack));
  PetscFunctionReturn(PETSC_SUCCESS);
}

