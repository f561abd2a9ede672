/* The portions' table (see portions.h). */
#include "system/portions.h"
#include "util/compat.h"
#include "blockwall/kernels.h"

typedef struct {
  PetscReal length;
  PetscInt  k;
} BwLengthKey;

static int BwLengthKeyCompare(const void *a, const void *b)
{
  const BwLengthKey *x = (const BwLengthKey *)a, *y = (const BwLengthKey *)b;
  if (x->length != y->length) return x->length < y->length ? -1 : 1;
  return x->k < y->k ? -1 : x->k > y->k;
}

PetscErrorCode BwPortionsCreate2D(PetscInt n, const PetscInt pair[], const PetscReal length[], PetscReal depth, PetscInt m, BwPortions *P)
{
  BwLengthKey *keys;
  PetscInt     nl = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(P, sizeof(*P)));
  P->dim         = 2;
  P->ninterfaces = n;
  P->maxnp       = m;
  PetscCall(PetscMalloc1(n + 1, &P->layout));
  PetscCall(PetscMalloc1(n + 1, &keys));
  /* distinct lengths, exactly: equal lengths give equal portions bit for bit */
  for (PetscInt k = 0; k < n; k++) keys[k] = (BwLengthKey){length[k], k};
  qsort(keys, (size_t)n, sizeof(*keys), BwLengthKeyCompare);
  for (PetscInt a = 0; a < n; a++) {
    if (a == 0 || keys[a].length != keys[a - 1].length) nl++;
    P->layout[keys[a].k] = nl - 1;
  }
  P->nlayouts = nl;
  PetscCall(PetscMalloc1(nl + 1, &P->offsets));
  PetscCall(PetscMalloc5(nl * m + 1, &P->area, nl * m + 1, &P->xi, nl * m + 1, &P->eta, nl * m + 1, &P->sqrt_area, nl * m + 1, &P->inv_sqrt_area));
  for (PetscInt l = 0, a = 0; a < n; a++) {
    int status;
    if (a > 0 && keys[a].length == keys[a - 1].length) continue;
    P->offsets[l] = l * m;
    bw_kernel_rectangle_portions((int)m, 1, keys[a].length, depth, P->area + l * m, P->xi + l * m, P->eta + l * m, &status);
    PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "interface %" PetscInt_FMT " (blocks %" PetscInt_FMT ", %" PetscInt_FMT ") has a non-positive or non-finite length (%g m) or depth (%g m)", keys[a].k, pair[2 * keys[a].k], pair[2 * keys[a].k + 1], (double)keys[a].length, (double)depth);
    for (PetscInt p = l * m; p < (l + 1) * m; p++) {
      P->sqrt_area[p]     = PetscSqrtReal(P->area[p]);
      P->inv_sqrt_area[p] = 1 / P->sqrt_area[p];
    }
    l++;
  }
  P->offsets[nl] = nl * m;
  PetscCall(PetscFree(keys));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwPortionsDestroy(BwPortions *P)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(P->layout));
  PetscCall(PetscFree(P->offsets));
  PetscCall(PetscFree5(P->area, P->xi, P->eta, P->sqrt_area, P->inv_sqrt_area));
  PetscCall(PetscMemzero(P, sizeof(*P)));
  PetscFunctionReturn(PETSC_SUCCESS);
}
