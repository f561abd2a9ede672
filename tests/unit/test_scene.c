/* Unit tests of src/scene (BwScene): the YAML scene file and the command
 * line read as typed keys, where each value came from, unused keys, and the
 * scene as run.
 *
 *   test_scene CASE [TMPFILE] [PETSc options]
 *
 * runs one case from the YAML files in tests/unit/scene_cases, which must be
 * the working directory (messages name the files as given, relative to it).
 * Options on the command line play the user's command line. Every rank runs
 * the same checks; the exit code is non-zero if any failed, with a FAIL line
 * on stderr for each. */
#include "scene/scene.h"
#include "util/compat.h"
#include "util/process.h"

#include <stdio.h>
#include <string.h>

static int         bw_failures = 0;
static const char *bw_tmpfile  = NULL; /* TMPFILE, for the round trip */

#define BwTestCheck(cond, ...) \
  do { \
    if (!(cond)) { \
      bw_failures++; \
      fprintf(stderr, "FAIL %s:%d: ", __FILE__, __LINE__); \
      fprintf(stderr, __VA_ARGS__); \
      fputc('\n', stderr); \
    } \
  } while (0)

/* Blockwall's sections, as the contract of BwSceneGetText lists them. */
static const char *const BwTestSections[] = {"title", "geometry", "joints", "discretization", "supports", "loads", "gravity", "solver", "output", "cases", "analysis", "sets", "progress"};

static PetscBool BwTestInSections(const char name[])
{
  for (size_t i = 0; i < PETSC_STATIC_ARRAY_LENGTH(BwTestSections); i++) {
    size_t n = strlen(BwTestSections[i]);

    if (!strncmp(name, BwTestSections[i], n) && (name[n] == 0 || name[n] == '_')) return PETSC_TRUE;
  }
  return PETSC_FALSE;
}

/* The value in effect of an option, as text, read as the application
 * would (which marks it used): blockwall's keys through the scene, the
 * others from PETSc's database. */
static PetscErrorCode BwTestGet(BwScene scene, const char option[], char value[], size_t len, PetscBool *set)
{
  PetscFunctionBeginUser;
  value[0] = 0;
  if (BwTestInSections(option + 1)) PetscCall(BwSceneText(scene, option, value, len, set));
  else PetscCall(PetscOptionsGetString(NULL, NULL, option, value, len, set));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The option has exactly this value. */
static PetscErrorCode BwTestOption(BwScene scene, const char option[], const char expected[])
{
  char      value[512];
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(BwTestGet(scene, option, value, sizeof(value), &set));
  BwTestCheck(set, "%s: not set, expected '%s'", option, expected);
  if (set) BwTestCheck(!strcmp(value, expected), "%s: got '%s', expected '%s'", option, value, expected);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwTestLocate(BwScene scene, const char option[], const char expected[])
{
  char where[256];

  PetscFunctionBeginUser;
  PetscCall(BwSceneLocate(scene, option, where, sizeof(where)));
  BwTestCheck(!strcmp(where, expected), "locate %s: got '%s', expected '%s'", option, where, expected);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* `ierr` is a user-input error whose message is exactly `expected`. */
static PetscErrorCode BwTestError(PetscErrorCode ierr, const char expected[])
{
  const char *message;

  PetscFunctionBeginUser;
  BwTestCheck(ierr == PETSC_ERR_USER_INPUT, "expected error code %d, got %d, for '%s'", PETSC_ERR_USER_INPUT, (int)ierr, expected);
  if (!ierr) PetscFunctionReturn(PETSC_SUCCESS);
  message = BwErrorText(ierr);
  BwTestCheck(!strcmp(message, expected), "error message\n  got:      '%s'\n  expected: '%s'", message, expected);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwTestList(BwScene scene, const char prefix[], PetscInt nexpected, const char *const expected[])
{
  PetscInt n;
  char   **names;

  PetscFunctionBeginUser;
  PetscCall(BwSceneListOptions(scene, prefix, &n, &names));
  BwTestCheck(n == nexpected, "list '%s': got %d names, expected %d", prefix, (int)n, (int)nexpected);
  for (PetscInt i = 0; i < PetscMin(n, nexpected); i++) BwTestCheck(!strcmp(names[i], expected[i]), "list '%s'[%d]: got '%s', expected '%s'", prefix, (int)i, names[i], expected[i]);
  PetscCall(PetscStrArrayDestroy(&names));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* values.yaml as loaded without command-line options. */
static const char *const BwTestValues[][2] = {
  {"-title", "Two-storey wall, with opening"},
  {"-geometry_width", "4.5"},
  {"-geometry_height", "3"},
  {"-geometry_openings", "0.5,0.8,1.5,2.0,2.5,0.8,3.5,2.0"},
  {"-joints_E", "3e9"},
  {"-joints_nu", "0.2"},
  {"-joints_tension", "false"},
  {"-discretization_m", "4"},
  {"-discretization_n", "2"},
  {"-loads_top_beam", "5e4,-3e4,0"},
  {"-loads_label", "quoted: value"},
  {"-loads_note", "single # quoted"},
  {"-gravity", "true"},
  {"-solver_type", "direct"},
  {"-output_file", "out/wall.h5"},
  {"-ksp_type", "cg"},
};

/* Checks values.yaml's options, replacing those in `changed` (pairs). */
static PetscErrorCode BwTestValuesLoaded(BwScene scene, PetscInt nchanged, const char *const changed[][2])
{
  PetscFunctionBeginUser;
  for (size_t i = 0; i < PETSC_STATIC_ARRAY_LENGTH(BwTestValues); i++) {
    const char *expected = BwTestValues[i][1];

    for (PetscInt j = 0; j < nchanged; j++)
      if (!strcmp(changed[j][0], BwTestValues[i][0])) expected = changed[j][1];
    PetscCall(BwTestOption(scene, BwTestValues[i][0], expected));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Nested keys, sequences, nested sequences, spaces, booleans, quotes. */
static PetscErrorCode BwTestCaseValues(void)
{
  BwScene           scene;
  const char       *dir;
  PetscReal        *openings;
  PetscInt          n, m = 0;
  PetscBool         set, tension = PETSC_TRUE;
  const char *const joints[] = {"joints_E", "joints_nu", "joints_tension"};

  PetscFunctionBeginUser;
  PetscCall(BwSceneCreate(PETSC_COMM_WORLD, &scene));
  PetscCall(BwSceneGetDirectory(scene, &dir));
  BwTestCheck(!strcmp(dir, "."), "directory before load: got '%s'", dir);
  PetscCall(BwSceneLoad(scene, "values.yaml"));
  PetscCall(BwTestValuesLoaded(scene, 0, NULL));

  /* The values mean what they say to the typed getters. */
  PetscCall(BwSceneRealArray(scene, "-geometry_openings", "test", &openings, &n, &set));
  BwTestCheck(set && n == 8 && openings[0] == 0.5 && openings[3] == 2.0 && openings[4] == 2.5 && openings[7] == 2.0, "-geometry_openings as reals: n = %d", (int)n);
  PetscCall(PetscFree(openings));
  PetscCall(BwSceneBool(scene, "-joints_tension", "test", &tension, &set));
  BwTestCheck(set && !tension, "-joints_tension as a bool");
  PetscCall(BwSceneInt(scene, "-discretization_m", "test", &m, &set));
  BwTestCheck(set && m == 4, "-discretization_m as an int: %d", (int)m);
  /* blockwall's keys never reach PETSc's database; the others do */
  PetscCall(PetscOptionsHasName(NULL, NULL, "-joints_E", &set));
  BwTestCheck(!set, "-joints_E is in PETSc's database");
  PetscCall(PetscOptionsHasName(NULL, NULL, "-ksp_type", &set));
  BwTestCheck(set, "-ksp_type is not in PETSc's database");
  /* An empty mapping sets nothing. */
  PetscCall(BwTestList(scene, "supports_", 0, NULL));
  PetscCall(BwTestList(scene, "joints_", 3, joints));

  PetscCall(BwTestLocate(scene, "-joints_E", "values.yaml:8: joints.E"));
  PetscCall(BwTestLocate(scene, "-geometry_openings", "values.yaml:6: geometry.openings"));
  PetscCall(BwTestLocate(scene, "-title", "values.yaml:2: title"));
  PetscCall(BwTestLocate(scene, "-solver_rtol", "-solver_rtol"));
  PetscCall(BwSceneGetDirectory(scene, &dir));
  BwTestCheck(!strcmp(dir, "."), "directory of values.yaml: got '%s'", dir);
  PetscCall(BwSceneCheckUnused(scene, BW_CHECK_FINAL, 0, NULL, 0, NULL));
  PetscCall(BwSceneDestroy(&scene));
  BwTestCheck(!scene, "BwSceneDestroy left the handle set");
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwTestCaseDirectory(void)
{
  BwScene     scene;
  const char *dir;

  PetscFunctionBeginUser;
  PetscCall(BwSceneCreate(PETSC_COMM_WORLD, &scene));
  PetscCall(BwSceneLoad(scene, "../scene_cases/values.yaml"));
  PetscCall(BwSceneGetDirectory(scene, &dir));
  BwTestCheck(!strcmp(dir, "../scene_cases"), "directory: got '%s'", dir);
  PetscCall(BwTestLocate(scene, "-joints_E", "../scene_cases/values.yaml:8: joints.E"));
  PetscCall(BwSceneDestroy(&scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Run with -discretization_m 8 -JOINTS_E 1e9 -solver_rtol 1e-9
 * -test_extra 1 -options_left no: the command line wins over the file,
 * whatever the case of the option name. */
static PetscErrorCode BwTestCaseOverride(void)
{
  BwScene           scene;
  PetscErrorCode    ierr;
  const char *const changed[][2] = {
    {"-discretization_m", "8"  },
    {"-joints_E",         "1e9"},
  };
  const char *const solver[] = {"solver_rtol", "solver_type"};
  const char *const exempt[] = {"test_"};

  PetscFunctionBeginUser;
  PetscCall(BwSceneCreate(PETSC_COMM_WORLD, &scene));
  PetscCall(BwSceneLoad(scene, "values.yaml"));
  PetscCall(BwTestList(scene, "solver_", 2, solver));
  PetscCall(BwTestLocate(scene, "-discretization_m", "command line: -discretization_m"));
  PetscCall(BwTestLocate(scene, "-joints_E", "command line: -joints_E"));
  PetscCall(BwTestLocate(scene, "-solver_rtol", "command line: -solver_rtol"));
  PetscCall(BwTestLocate(scene, "-discretization_n", "values.yaml:13: discretization.n"));
  /* Locating reads no option: all are still unused. Right after loading,
   * only what is not blockwall's is checked: -test_extra. */
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = BwSceneCheckUnused(scene, BW_CHECK_SETUP, PETSC_STATIC_ARRAY_LENGTH(exempt), exempt, 0, NULL);
  PetscCall(PetscPopErrorHandler());
  PetscCall(BwTestError(ierr, "values.yaml:2: unknown key 'title' (nothing uses it)"));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = BwSceneCheckUnused(scene, BW_CHECK_FOREIGN, 0, NULL, 1, (const char *const[]){"ksp_"});
  PetscCall(PetscPopErrorHandler());
  PetscCall(BwTestError(ierr, "unknown option -test_extra (nothing uses it)"));

  PetscCall(BwTestValuesLoaded(scene, PETSC_STATIC_ARRAY_LENGTH(changed), changed));
  PetscCall(BwTestOption(scene, "-solver_rtol", "1e-9"));
  PetscCall(BwSceneCheckUnused(scene, BW_CHECK_FINAL, PETSC_STATIC_ARRAY_LENGTH(exempt), exempt, 0, NULL));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = BwSceneCheckUnused(scene, BW_CHECK_FINAL, 0, NULL, 0, NULL);
  PetscCall(PetscPopErrorHandler());
  PetscCall(BwTestError(ierr, "unknown option -test_extra (nothing uses it)"));
  PetscCall(BwSceneDestroy(&scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* BwSceneError's three forms; run with -discretization_m 8. */
static PetscErrorCode BwTestCaseErrorFormat(void)
{
  BwScene        scene;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(BwSceneCreate(PETSC_COMM_WORLD, &scene));
  PetscCall(BwSceneLoad(scene, "values.yaml"));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = BwSceneError(scene, "-joints_nu", "must be < 0.5, got %g", 0.7);
  PetscCall(BwTestError(ierr, "values.yaml:9: joints.nu must be < 0.5, got 0.7"));
  ierr = BwSceneError(scene, "-discretization_m", "must be even, got %d", 7);
  PetscCall(BwTestError(ierr, "command line: -discretization_m must be even, got 7"));
  ierr = BwSceneError(scene, "-solver_maxit", "must be > 0, got %d", 0);
  PetscCall(BwTestError(ierr, "-solver_maxit must be > 0, got 0"));
  PetscCall(PetscPopErrorHandler());
  PetscCall(BwSceneDestroy(&scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* unknown.yaml has joints.foo, which nothing reads. */
static PetscErrorCode BwTestCaseUnknownKey(void)
{
  BwScene        scene;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(BwSceneCreate(PETSC_COMM_WORLD, &scene));
  PetscCall(BwSceneLoad(scene, "unknown.yaml"));
  PetscCall(BwTestOption(scene, "-title", "unknown key"));
  PetscCall(BwTestOption(scene, "-joints_E", "3e9"));
  {
    /* asked for, not set: the vocabulary the suggestion comes from */
    PetscReal food = 0;
    PetscBool set;
    PetscCall(BwSceneReal(scene, "-joints_food", "test", &food, &set));
    BwTestCheck(!set, "-joints_food is set");
  }
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = BwSceneCheckUnused(scene, BW_CHECK_SETUP, 0, NULL, 0, NULL);
  PetscCall(PetscPopErrorHandler());
  /* the nearest name asked for is suggested */
  PetscCall(BwTestError(ierr, "unknown.yaml:5: unknown key 'joints.foo' (nothing uses it; did you mean -joints_food?)"));
  PetscCall(BwSceneDestroy(&scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Files that must not load, and the one-line message each gives. */
static const char *const BwTestBadFiles[][3] = {
  {"err_syntax",       "syntax.yaml",       "syntax.yaml:4: YAML syntax error: did not find expected ',' or ']' (while parsing a flow sequence at line 3)"},
  {"err_duplicate",    "duplicate.yaml",    "duplicate.yaml:6: duplicate key 'joints' (first at line 1)"},
  {"err_nested_dup",   "nested_dup.yaml",   "nested_dup.yaml:6: duplicate key 'joints.E' (first at line 2)"},
  {"err_novalue",      "novalue.yaml",      "novalue.yaml:3: key 'joints.nu' has no value (write \"\" for an option without one)"},
  {"err_notmapping",   "notmapping.yaml",   "notmapping.yaml:2: the scene must be a mapping of keys (key: value lines) at top level, not a sequence"},
  {"err_alias",        "alias.yaml",        "alias.yaml:1: anchors and aliases (&name, *name) are not supported in scene files; write the values out"},
  {"err_nonscalarkey", "nonscalarkey.yaml", "nonscalarkey.yaml:2: a key in 'loads' is a sequence; keys must be names"},
  {"err_collision",    "collision.yaml",    "collision.yaml:3: key 'joints_E' sets the same option -joints_E as key 'joints.E' at line 2"},
  {"err_empty",        "empty.yaml",        "empty.yaml:1: the scene file is empty; it must hold a mapping of keys (key: value lines)"},
  {"err_missing",      "missing.yaml",      "cannot read scene file 'missing.yaml': No such file or directory"},
};

static PetscErrorCode BwTestBadFile(const char file[], const char expected[])
{
  BwScene        scene;
  PetscErrorCode ierr;
  PetscBool      set;

  PetscFunctionBeginUser;
  PetscCall(BwSceneCreate(PETSC_COMM_WORLD, &scene));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = BwSceneLoad(scene, file);
  PetscCall(PetscPopErrorHandler());
  PetscCall(BwTestError(ierr, expected));
  /* A file that does not load inserts nothing. */
  PetscCall(PetscOptionsHasName(NULL, NULL, "-ksp_type", &set));
  BwTestCheck(!set, "%s: -ksp_type inserted by a file that failed", file);
  PetscCall(BwSceneDestroy(&scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The scene options in effect: the file's keys and command-line options of
 * blockwall's sections, as (name, value) with value "" for none. */
static PetscErrorCode BwTestSnapshot(BwScene scene, PetscInt *n, char ***names, char ***values)
{
  PetscInt count = 0;

  PetscFunctionBeginUser;
  PetscCall(BwSceneListOptions(scene, "", n, names));
  PetscCall(PetscCalloc1(*n + 1, values));
  for (PetscInt i = 0; i < *n; i++) {
    char      where[256], option[256], value[512];
    PetscBool set;

    PetscCall(PetscSNPrintf(option, sizeof(option), "-%s", (*names)[i]));
    PetscCall(BwSceneLocate(scene, option, where, sizeof(where)));
    if (!strncmp(where, "command line: ", 14) && !BwTestInSections((*names)[i])) {
      PetscCall(PetscFree((*names)[i]));
      continue;
    }
    PetscCall(BwTestGet(scene, option, value, sizeof(value), &set));
    (*names)[count] = (*names)[i];
    PetscCall(PetscStrallocpy(value, &(*values)[count++]));
  }
  (*names)[count] = NULL;
  *n              = count;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Run with TMPFILE and -discretization_m 8 -title "cmd: title"
 * -loads_top_beam 1,2,3 -solver_rtol 1e-9 -output_dir "a b"
 * -ksp_rtol 1e-3: the text of the scene as run loads back, in a cleared
 * database, to the same scene options. */
static PetscErrorCode BwTestCaseRoundTrip(void)
{
  BwScene           scene;
  char             *text, *text2, *comment;
  PetscInt          n, n2;
  char            **names, **values, **names2, **values2;
  PetscMPIInt       rank;
  PetscBool         used;
  const char *const lines[] = {
    "title: \"cmd: title\"\n",
    "  openings: [0.5, 0.8, 1.5, 2.0, 2.5, 0.8, 3.5, 2.0]\n",
    "discretization:\n  m: 8\n  n: 2\n",
    "supports: {}\n",
    "  top_beam: [1, 2, 3]\n",
    "  label: \"quoted: value\"\n",
    "  tension: false\n",
    "  file: \"out/wall.h5\"\n",
    "ksp_type: \"cg\"\n",
    "# set on the command line\n",
    "\noutput_dir: \"a b\"\n",
    "\nsolver_rtol: 1e-9\n",
  };

  PetscFunctionBeginUser;
  BwTestCheck(bw_tmpfile, "roundtrip needs a temporary file name");
  if (!bw_tmpfile) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(BwSceneCreate(PETSC_COMM_WORLD, &scene));
  PetscCall(BwSceneLoad(scene, "values.yaml"));
  PetscCall(BwSceneGetText(scene, &text));
  for (size_t i = 0; i < PETSC_STATIC_ARRAY_LENGTH(lines); i++) BwTestCheck(strstr(text, lines[i]), "scene text lacks '%s'", lines[i]);
  BwTestCheck(!strstr(text, "ksp_rtol"), "scene text has -ksp_rtol, not a scene option");
  /* Getting the text reads no option. */
  PetscCall(PetscOptionsUsed(NULL, "title", &used));
  BwTestCheck(!used, "BwSceneGetText marked -title used");
  PetscCall(PetscOptionsUsed(NULL, "output_dir", &used));
  BwTestCheck(!used, "BwSceneGetText marked -output_dir used");
  PetscCall(BwTestSnapshot(scene, &n, &names, &values));
  BwTestCheck(n == 18, "%d scene options before the round trip, expected 18", (int)n);
  PetscCall(BwSceneDestroy(&scene));

  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  if (rank == 0) {
    FILE *f = fopen(bw_tmpfile, "w");

    BwTestCheck(f, "cannot write %s", bw_tmpfile);
    if (f) {
      fputs(text, f);
      fclose(f);
    }
  }
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  PetscCall(PetscOptionsClear(NULL));
  PetscCall(BwSceneCreate(PETSC_COMM_WORLD, &scene));
  PetscCall(BwSceneLoad(scene, bw_tmpfile));
  PetscCall(BwTestSnapshot(scene, &n2, &names2, &values2));
  BwTestCheck(n2 == n, "%d scene options after the round trip, %d before", (int)n2, (int)n);
  for (PetscInt i = 0; i < PetscMin(n, n2); i++) {
    BwTestCheck(!strcmp(names[i], names2[i]), "option %d: '%s' before, '%s' after", (int)i, names[i], names2[i]);
    BwTestCheck(!strcmp(values[i], values2[i]), "-%s: '%s' before, '%s' after", names[i], values[i], values2[i]);
  }
  /* Loaded back, the command-line options are file keys: the same text
   * without the comment. */
  PetscCall(BwSceneGetText(scene, &text2));
  comment = strstr(text, "# set on the command line\n");
  if (comment) memmove(comment, comment + strlen("# set on the command line\n"), strlen(comment + strlen("# set on the command line\n")) + 1);
  BwTestCheck(!strcmp(text, text2), "text after the round trip differs:\n%s---\n%s", text, text2);
  if (bw_failures) fprintf(stderr, "scene text:\n%s", text2);
  PetscCall(PetscFree(text));
  PetscCall(PetscFree(text2));
  PetscCall(PetscStrArrayDestroy(&names));
  PetscCall(PetscStrArrayDestroy(&values));
  PetscCall(PetscStrArrayDestroy(&names2));
  PetscCall(PetscStrArrayDestroy(&values2));
  PetscCall(BwSceneDestroy(&scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static const struct {
  const char *name;
  PetscErrorCode (*run)(void);
} BwTestCases[] = {
  {"values",       BwTestCaseValues     },
  {"directory",    BwTestCaseDirectory  },
  {"override",     BwTestCaseOverride   },
  {"error_format", BwTestCaseErrorFormat},
  {"unknown_key",  BwTestCaseUnknownKey },
  {"roundtrip",    BwTestCaseRoundTrip  },
};

int main(int argc, char **argv)
{
  const char *name  = argc > 1 ? argv[1] : "";
  PetscBool   found = PETSC_FALSE;

  if (argc > 2 && argv[2][0] != '-') bw_tmpfile = argv[2];

  BwProcessDefaults(); /* the libraries run as under blockwall */

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  for (size_t i = 0; i < PETSC_STATIC_ARRAY_LENGTH(BwTestCases); i++) {
    if (strcmp(name, BwTestCases[i].name)) continue;
    PetscCall(BwTestCases[i].run());
    found = PETSC_TRUE;
  }
  for (size_t i = 0; i < PETSC_STATIC_ARRAY_LENGTH(BwTestBadFiles); i++) {
    if (strcmp(name, BwTestBadFiles[i][0])) continue;
    PetscCall(BwTestBadFile(BwTestBadFiles[i][1], BwTestBadFiles[i][2]));
    found = PETSC_TRUE;
  }
  BwTestCheck(found, "unknown case '%s'", name);
  PetscCall(PetscFinalize());
  return bw_failures ? 1 : 0;
}
