/* BwNameMap: open addressing with linear probing; the table doubles when
 * half full, so probes stay short and the total work linear. */
#include <ctype.h>
#include "util/namemap.h"
#include "util/compat.h"

PetscBool BwSameName(const char a[], const char b[])
{
  for (; *a && *b; a++, b++)
    if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return PETSC_FALSE;
  return (PetscBool)(*a == *b);
}

static size_t BwNameHash(const char s[])
{
  size_t h = 1469598103934665603ull;

  for (; *s; s++) h = (h ^ (unsigned char)tolower((unsigned char)*s)) * 1099511628211ull;
  return h;
}

PetscErrorCode BwNameMapInit(BwNameMap *map)
{
  PetscFunctionBeginUser;
  map->cap = 64;
  map->n   = 0;
  PetscCall(PetscCalloc2(map->cap, &map->name, map->cap, &map->value));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscInt BwNameMapSlot(const BwNameMap *map, const char name[])
{
  PetscInt s = (PetscInt)(BwNameHash(name) & (size_t)(map->cap - 1));

  while (map->name[s] && !BwSameName(map->name[s], name)) s = (s + 1) & (map->cap - 1);
  return s;
}

PetscErrorCode BwNameMapAdd(BwNameMap *map, const char name[], PetscInt value, PetscInt *existing)
{
  PetscInt s;

  PetscFunctionBeginUser;
  if (2 * (map->n + 1) > map->cap) {
    BwNameMap big = {2 * map->cap, 0, NULL, NULL};

    PetscCall(PetscCalloc2(big.cap, &big.name, big.cap, &big.value));
    for (PetscInt i = 0; i < map->cap; i++) {
      if (!map->name[i]) continue;
      s            = BwNameMapSlot(&big, map->name[i]);
      big.name[s]  = map->name[i];
      big.value[s] = map->value[i];
      big.n++;
    }
    PetscCall(PetscFree2(map->name, map->value));
    *map = big;
  }
  s = BwNameMapSlot(map, name);
  if (existing) *existing = map->name[s] ? map->value[s] : -1;
  if (map->name[s]) PetscFunctionReturn(PETSC_SUCCESS);
  map->name[s]  = name;
  map->value[s] = value;
  map->n++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscInt BwNameMapGet(const BwNameMap *map, const char name[])
{
  PetscInt s;

  if (!map->cap) return -1;
  s = BwNameMapSlot(map, name);
  return map->name[s] ? map->value[s] : -1;
}

PetscErrorCode BwNameMapDestroy(BwNameMap *map)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree2(map->name, map->value));
  map->cap = map->n = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}
