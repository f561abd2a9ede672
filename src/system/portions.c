/* The portions' table (see portions.h). */
#include "system/portions.h"
#include <string.h>
#include "util/compat.h"
#include "blockwall/kernels.h"

/* Distinct lengths, exactly (equal lengths give equal portions bit for
 * bit), by an open-addressing table on their bits: linear in the number of
 * interfaces, where a wall has a handful of lengths. */
typedef struct {
  PetscInt  cap, n, *slot; /* slot: layout + 1, 0 when empty */
  uint64_t *key;
} BwLengthTable;

static uint64_t BwLengthBits(PetscReal x)
{
  uint64_t u;
  memcpy(&u, &x, sizeof(u));
  return u;
}

static PetscErrorCode BwLengthTableGrow(BwLengthTable *t)
{
  BwLengthTable g = {2 * t->cap, t->n, NULL, NULL};

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc2(g.cap, &g.slot, g.cap, &g.key));
  for (PetscInt a = 0; a < t->cap; a++) {
    uint64_t h;
    if (!t->slot[a]) continue;
    for (h = (t->key[a] * 0x9E3779B97F4A7C15ULL) >> 20; g.slot[h % g.cap]; h++) { }
    g.slot[h % g.cap] = t->slot[a];
    g.key[h % g.cap]  = t->key[a];
  }
  PetscCall(PetscFree2(t->slot, t->key));
  *t = g;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the layout of length x, a new one (n) if it is not in the table */
static PetscErrorCode BwLengthTableFind(BwLengthTable *t, PetscReal x, PetscInt *layout, PetscBool *added)
{
  uint64_t k = BwLengthBits(x), h;

  PetscFunctionBeginUser;
  *added = PETSC_FALSE;
  for (h = (k * 0x9E3779B97F4A7C15ULL) >> 20; t->slot[h % t->cap] && t->key[h % t->cap] != k; h++) { }
  if (!t->slot[h % t->cap]) {
    t->slot[h % t->cap] = ++t->n;
    t->key[h % t->cap]  = k;
    *added              = PETSC_TRUE;
  }
  *layout = t->slot[h % t->cap] - 1;
  if (2 * t->n > t->cap) PetscCall(BwLengthTableGrow(t));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwPortionsCreate2D(PetscInt n, const PetscInt pair[], const PetscReal length[], PetscReal depth, PetscInt m, BwPortions *P)
{
  BwLengthTable t = {64, 0, NULL, NULL};
  PetscInt     *first; /* an interface of each layout */

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(P, sizeof(*P)));
  P->dim         = 2;
  P->ninterfaces = n;
  P->maxnp       = m;
  PetscCall(PetscMalloc1(n + 1, &P->layout));
  PetscCall(PetscCalloc2(t.cap, &t.slot, t.cap, &t.key));
  PetscCall(PetscMalloc1(n + 1, &first));
  for (PetscInt k = 0; k < n; k++) {
    PetscBool added;
    PetscCall(BwLengthTableFind(&t, length[k], &P->layout[k], &added));
    if (added) first[P->layout[k]] = k;
  }
  P->nlayouts = t.n;
  PetscCall(PetscFree2(t.slot, t.key));
  PetscCall(PetscMalloc1(P->nlayouts + 1, &P->offsets));
  PetscCall(PetscMalloc5(P->nlayouts * m + 1, &P->area, P->nlayouts * m + 1, &P->xi, P->nlayouts * m + 1, &P->eta, P->nlayouts * m + 1, &P->sqrt_area, P->nlayouts * m + 1, &P->inv_sqrt_area));
  for (PetscInt l = 0; l < P->nlayouts; l++) {
    PetscInt k = first[l];
    int      status;
    P->offsets[l] = l * m;
    bw_kernel_rectangle_portions((int)m, 1, length[k], depth, P->area + l * m, P->xi + l * m, P->eta + l * m, &status);
    if (status != BW_KERNEL_OK) PetscCall(PetscFree(first));
    PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "interface %" PetscInt_FMT " (blocks %" PetscInt_FMT ", %" PetscInt_FMT ") has a non-positive or non-finite length (%g m) or depth (%g m)", k, pair[2 * k], pair[2 * k + 1], (double)length[k], (double)depth);
    for (PetscInt p = l * m; p < (l + 1) * m; p++) {
      P->sqrt_area[p]     = PetscSqrtReal(P->area[p]);
      P->inv_sqrt_area[p] = 1 / P->sqrt_area[p];
    }
  }
  P->offsets[P->nlayouts] = P->nlayouts * m;
  PetscCall(PetscFree(first));
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
