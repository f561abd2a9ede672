/* BwScene: the scene file (YAML) and the command line, read as typed keys.
 *
 * Every scene key is also an option: nested mapping keys joined by '_'
 * (discretization.m -> -discretization_m), sequences written comma-separated
 * (loads.top_beam: [5e4, -3e4, 0] -> -loads_top_beam 5e4,-3e4,0; nested
 * sequences flattened). The command line overrides the file. Each key keeps
 * the file and line it came from, so that a bad value is reported as
 * "scene.yaml:12: joints.E must be > 0, got -1" and the same value given on
 * the command line as "command line: -joints_E must be > 0, got -1".
 *
 * Keys of blockwall's own sections (title, geometry, joints, discretization,
 * supports, loads, gravity, solver, output, cases, analysis, sets,
 * progress) live here, not in PETSc's options database: PETSc 3.18 holds at
 * most 512 options and forgets where each came from, and a scene may have
 * thousands of keys (a load per set). They are read through the typed
 * getters below, which check the value's type (a number, an integer that
 * fits, a boolean, one of a list, a sequence) and finiteness, mark the key
 * used and, with -help, print it with its default. Every other key of the
 * file (ksp_type: cg) is inserted into PETSc's database as an option, for
 * PETSc to read.
 *
 * Rank 0 reads the file and broadcasts its text; every rank parses it, so
 * every rank holds the same keys. */
#pragma once
#include <petscsys.h>

typedef struct _p_BwScene *BwScene;

PetscErrorCode BwSceneCreate(MPI_Comm comm, BwScene *scene);
/* Reads and parses the file (path NULL: no file, command line only) and
 * records the command line. Errors (missing file, YAML syntax, duplicate
 * key, key without value, non-scalar key, an option given without a value
 * where the key takes one) carry file:line. */
PetscErrorCode BwSceneLoad(BwScene scene, const char path[]);
/* Directory of the scene file ("." if none), for paths relative to it. */
PetscErrorCode BwSceneGetDirectory(BwScene scene, const char *dir[]);
/* Where the value in effect of `option` (name with or without '-') comes
 * from, formatted as the start of an error line:
 *   "scene.yaml:12: joints.E"            value from the file
 *   "command line: -joints_E"            value from the command line
 *   "-joints_E"                          not set anywhere (a default)       */
PetscErrorCode BwSceneLocate(BwScene scene, const char option[], char buf[], size_t len);
/* Raise a user-input error (PETSC_ERR_USER_INPUT) whose message is one line:
 * "<BwSceneLocate(option)> <formatted text>". Collective in effect: every
 * rank holds the same keys and raises the same error. */
PetscErrorCode BwSceneError(BwScene scene, const char option[], const char fmt[], ...) PETSC_ATTRIBUTE_FORMAT(3, 4);
/* The same for a check each rank makes on its own piece (collective): if
 * any rank is `bad`, every rank raises the lowest such rank's message. */
PetscErrorCode BwSceneErrorAgree(BwScene scene, PetscBool bad, const char option[], const char fmt[], ...) PETSC_ATTRIBUTE_FORMAT(4, 5);

/* Typed getters. `option` is the option name with '-'; `help` says what it
 * is, with its unit. *value holds the default on entry and the value in
 * effect on return; *set (may be NULL) says whether the file or the command
 * line gave one. A value of the wrong type, non-finite, or out of the type's
 * range is an error naming the key. */
PetscErrorCode BwSceneReal(BwScene scene, const char option[], const char help[], PetscReal *value, PetscBool *set);
PetscErrorCode BwSceneInt(BwScene scene, const char option[], const char help[], PetscInt *value, PetscBool *set);
PetscErrorCode BwSceneBool(BwScene scene, const char option[], const char help[], PetscBool *value, PetscBool *set);
/* One of names[0..n) (case-insensitive); *value is its index. */
PetscErrorCode BwSceneEnum(BwScene scene, const char option[], const char help[], PetscInt n, const char *const names[], PetscInt *value, PetscBool *set);
/* A single value, taken as text (a title, a path). */
PetscErrorCode BwSceneString(BwScene scene, const char option[], const char help[], char value[], size_t len, PetscBool *set);
/* A sequence of numbers (a single number is a sequence of one); *values is
 * allocated (PetscFree), NULL when not set. */
PetscErrorCode BwSceneRealArray(BwScene scene, const char option[], const char help[], PetscReal **values, PetscInt *n, PetscBool *set);
PetscErrorCode BwSceneIntArray(BwScene scene, const char option[], const char help[], PetscInt **values, PetscInt *n, PetscBool *set);
/* The value in effect as written (sequences comma-joined), unchecked; for
 * code that passes values on rather than using them (tests, tools). */
PetscErrorCode BwSceneText(BwScene scene, const char option[], char value[], size_t len, PetscBool *set);
/* With -help: a section title above the options that follow. */
PetscErrorCode BwSceneHelpSection(BwScene scene, const char title[]);
/* The key `option` of the file, if present, must be a mapping: an error
 * naming it and `what` it should hold otherwise (supports: [bottom]). */
PetscErrorCode BwSceneRequireMapping(BwScene scene, const char option[], const char what[]);

/* Names (without '-') of every key and option that starts with `prefix`
 * (e.g. "supports_"), from the file or the command line, sorted, without
 * marking them used. Free with PetscStrArrayDestroy(&names). Linear in the
 * number of keys. */
PetscErrorCode BwSceneListOptions(BwScene scene, const char prefix[], PetscInt *n, char ***names);
/* Names of the children of the file's mapping `option` (e.g. "-cases":
 * "wind_left", "wind_right"), in file order. */
PetscErrorCode BwSceneListChildren(BwScene scene, const char option[], PetscInt *n, char ***names);
/* Names of the entries of a section that maps NAME -> {KEY: ...} (cases,
 * sets): the file's children of -section in file order, then the names
 * given on the command line only, as -section_NAME_KEY[_...] with KEY one of
 * `keys`. An option under a file entry belongs to it; any other that names
 * no KEY is an error saying `what`. Free with PetscStrArrayDestroy. */
PetscErrorCode BwSceneListEntries(BwScene scene, const char section[], PetscInt nkeys, const char *const keys[], const char what[], PetscInt *n, char ***names);

/* Error (one line, with file:line for file keys, and the nearest name
 * blockwall knows when one is close) for the first key or option that
 * nothing has read. Options whose name starts with one of `exempt` are
 * skipped (solver paths that did not run), and so are those PETSc reads
 * only at PetscFinalize (log_view, options_left, malloc_*, ...). Before the
 * solve, options that start with one of `deferred` (the solvers' prefixes:
 * PETSc reads some of them only when a solver is set up) are left for the
 * final check; right after loading, blockwall's own keys too. */
typedef enum {
  BW_CHECK_FOREIGN,  /* at once after loading: options that are not blockwall's and no solver will read */
  BW_CHECK_GEOMETRY, /* after the geometry is made, before the partition: the geometry's own keys (geometry.*) */
  BW_CHECK_SETUP,    /* after reading every key, before any heavy work: all but `deferred` */
  BW_CHECK_FINAL     /* after the solve: everything */
} BwCheckStage;
PetscErrorCode BwSceneCheckUnused(BwScene scene, BwCheckStage stage, PetscInt nexempt, const char *const exempt[], PetscInt ndeferred, const char *const deferred[]);
/* The scene as run: the file's keys in their nesting with the values in
 * effect (command-line overrides applied), then every command-line option of
 * blockwall's sections that the file did not have, as flattened keys
 * (discretization_m: 8), which load back to the same options. Caller frees
 * with PetscFree. Identical on every rank. */
PetscErrorCode BwSceneGetText(BwScene scene, char **text);
PetscErrorCode BwSceneDestroy(BwScene *scene);
/* The command line itself: an option given twice, or one of blockwall's
 * given without a value, is an error naming it (PETSc would keep one value
 * silently, or read the default). Call before PetscInitialize's options are
 * used, with main's argc and argv. */
PetscErrorCode BwSceneCheckArguments(MPI_Comm comm, int argc, char **argv);
