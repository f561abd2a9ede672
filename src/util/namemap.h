/* BwNameMap: option names -> an index, case-insensitive like PETSc's option
 * names, in expected O(1) per lookup (open addressing, FNV-1a of the
 * lower-cased name). The scene keeps every key and every command-line
 * option in one, so that a scene of 1e5 keys is read in linear time. The
 * map stores pointers to names owned by the caller. */
#pragma once
#include <petscsys.h>

typedef struct {
  PetscInt     cap, n;   /* slots (a power of 2), entries */
  const char **name;     /* cap slots, NULL when empty */
  PetscInt    *value;
} BwNameMap;

PetscErrorCode BwNameMapInit(BwNameMap *map);
/* Adds name -> value; *existing is the value already stored for the same
 * name (then nothing is changed), or -1. */
PetscErrorCode BwNameMapAdd(BwNameMap *map, const char name[], PetscInt value, PetscInt *existing);
/* The value of `name`, or -1. */
PetscInt       BwNameMapGet(const BwNameMap *map, const char name[]);
PetscErrorCode BwNameMapDestroy(BwNameMap *map);
/* Option names compare like PETSc's: case-insensitively. */
PetscBool      BwSameName(const char a[], const char b[]);
