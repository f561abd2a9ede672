/* BwScene: the scene file (YAML) turned into PETSc options.
 *
 * Every scene key is a PETSc option: nested mapping keys joined by '_'
 * (discretization.m -> -discretization_m), sequences written comma-separated
 * (loads.top_beam: [5e4, -3e4, 0] -> -loads_top_beam 5e4,-3e4,0; nested
 * sequences flattened). The command line overrides the file: a key whose
 * option is already in the database is recorded but not inserted. Each key
 * keeps the file and line it came from, so that a bad value or an unused key
 * is reported as "scene.yaml:12: joints.E must be > 0, got -1".
 *
 * Rank 0 reads the file and broadcasts its text; every rank parses it, so the
 * options database is identical everywhere. */
#pragma once
#include <petscsys.h>

typedef struct _p_BwScene *BwScene;

PetscErrorCode BwSceneCreate(MPI_Comm comm, BwScene *scene);
/* Reads, parses and inserts the file's keys. Errors (missing file, YAML
 * syntax, duplicate key, key without value, non-scalar key) carry file:line. */
PetscErrorCode BwSceneLoad(BwScene scene, const char path[]);
/* Directory of the scene file ("." if none), for paths relative to it. */
PetscErrorCode BwSceneGetDirectory(BwScene scene, const char *dir[]);
/* Where the value in effect of `option` (name with leading '-') comes from,
 * formatted as the start of an error line:
 *   "scene.yaml:12: joints.E"            value from the file
 *   "command line: -joints_E"            value from the command line
 *   "-joints_E"                          not set anywhere (a default)       */
PetscErrorCode BwSceneLocate(BwScene scene, const char option[], char buf[], size_t len);
/* Raise a user-input error (PETSC_ERR_USER_INPUT) whose message is one line:
 * "<BwSceneLocate(option)> <formatted text>". Use as
 *   PetscCheck(E > 0, ...) -> if (!(E > 0)) return BwSceneError(scene, "-joints_E", "must be > 0, got %g", E);  */
PetscErrorCode BwSceneError(BwScene scene, const char option[], const char fmt[], ...) PETSC_ATTRIBUTE_FORMAT(3, 4);
/* Names (without '-') of every option in the database that starts with
 * `prefix` (e.g. "supports_"), from the file or the command line, sorted.
 * Free with PetscStrArrayDestroy(&names). */
PetscErrorCode BwSceneListOptions(BwScene scene, const char prefix[], PetscInt *n, char ***names);
/* Error (one line, with file:line for file keys) for the first option in
 * the database that nothing has queried. Options whose name starts with one
 * of `exempt` prefixes (without '-') are skipped, and so are those PETSc
 * reads only at PetscFinalize (log_view, options_left, malloc_*, ...). */
PetscErrorCode BwSceneCheckUnused(BwScene scene, PetscInt nexempt, const char *const exempt[]);
/* The scene as run: the file's keys in their nesting with the values in
 * effect (command-line overrides applied), then every command-line option of
 * blockwall's sections that the file did not have, as flattened keys
 * (discretization_m: 8), which load back to the same options. Caller frees
 * with PetscFree. Identical on every rank. */
PetscErrorCode BwSceneGetText(BwScene scene, char **text);
PetscErrorCode BwSceneDestroy(BwScene *scene);
