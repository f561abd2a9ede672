/* BwScene, part 3: keys and options nothing read, and listings by prefix.
 *
 * A key or option that nothing read is an error: a typo must not pass
 * silently. The check runs twice: before any heavy work (every key of
 * blockwall's and every option outside the solvers' prefixes must have been
 * read by then), and after the solve for the options PETSc's solvers read
 * only when they are set up. The message names where the key was written and
 * the nearest name blockwall asked for, when one is close. */
#include <ctype.h>
#include <stdlib.h>
#include <string.h>
#include "scene/scene_impl.h"
#include "util/compat.h"

/* Options legitimately unused when BwSceneCheckUnused runs: PETSc reads them
 * only at PetscFinalize, lazily (first viewer, window or GPU), when an error
 * happens, or at PetscInitialize only in some builds. An entry matches the
 * option itself and every option continuing it after '_' ("log" matches
 * -log_view_memory). */
static const char *const BwScenePetscOptions[] = {
  "log",                      /* -log_view*, -log_trace, ...: reports at PetscFinalize */
  "options_left",             /* read by PetscFinalize */
  "options_view",             /* read by PetscFinalize */
  "options_monitor",          /* read while options are inserted, before anything marks it */
  "help",                     /* -help, -help_intro: handled by PetscInitialize and each object */
  "version",                  /* handled by PetscInitialize */
  "malloc",                   /* -malloc_debug, -malloc_dump, ...: partly read at PetscFinalize */
  "memory_view",              /* memory report at PetscFinalize */
  "objects_dump",             /* leaked-object report at PetscFinalize */
  "citations",                /* citation list at PetscFinalize */
  "get_total_flops",          /* flop count at PetscFinalize */
  "on_error",                 /* -on_error_abort, ...: read only when an error happens */
  "no_signal_handler",        /* read by PetscInitialize only in some configurations */
  "check_pointer_intensity",  /* debug builds only */
  "fp_trap",                  /* read by PetscInitialize only in some configurations */
  "viewer",                   /* -viewer_binary_*, ...: read when such a viewer is created */
  "skip_petscrc",             /* read while options are inserted */
  "info",                     /* -info, -info_exclude: read only in some builds */
  "display",                  /* X11: read when a window would be opened */
  "nox",                      /* X11: read when a window would be opened */
  "history",                  /* read by PetscInitialize only in some builds */
  "saws",                     /* SAWs web server, only when PETSc has it */
  "mpi_linear_solver_server", /* read only when the server is enabled */
  "use_gpu_aware_mpi",        /* read when a GPU is set up, maybe never */
  "device",                   /* -device_enable, ...: read when a GPU is set up */
};

/* Edit distance (insertions, deletions, substitutions; case-insensitive),
 * or a large number once it exceeds `cap`. */
static PetscInt BwDistance(const char a[], const char b[], PetscInt cap)
{
  PetscInt la = (PetscInt)strlen(a), lb = (PetscInt)strlen(b), row[PETSC_MAX_OPTION_NAME + 1];

  if (la > PETSC_MAX_OPTION_NAME || lb > PETSC_MAX_OPTION_NAME || PetscAbsInt(la - lb) > cap) return cap + 1;
  for (PetscInt j = 0; j <= lb; j++) row[j] = j;
  for (PetscInt i = 1; i <= la; i++) {
    PetscInt diag = row[0], best;
    row[0] = i;
    best   = row[0];
    for (PetscInt j = 1; j <= lb; j++) {
      PetscInt up = row[j];
      PetscInt c  = tolower((unsigned char)a[i - 1]) == tolower((unsigned char)b[j - 1]) ? 0 : 1;
      row[j]      = PetscMin(PetscMin(row[j] + 1, row[j - 1] + 1), diag + c);
      diag        = up;
      best        = PetscMin(best, row[j]);
    }
    if (best > cap) return cap + 1;
  }
  return row[lb];
}

/* " (did you mean -x?)" for the name blockwall asked for that is nearest to
 * `name`: a few edits away, or `name` with a section prefix left out
 * (-running_bond_courses for -geometry_running_bond_courses). */
static PetscErrorCode BwSceneSuggest(BwScene scene, const char name[], char buf[], size_t len)
{
  PetscInt best = -1, bestd = PETSC_MAX_INT, cap = PetscMax(2, (PetscInt)strlen(name) / 4);
  size_t   ln   = strlen(name);

  PetscFunctionBeginUser;
  buf[0] = 0;
  for (PetscInt i = 0; i < scene->nasked; i++) {
    const char *a  = scene->asked[i];
    size_t      la = strlen(a);
    PetscInt    d;
    if (la > ln && a[la - ln - 1] == '_' && BwSameName(a + la - ln, name)) d = 1;
    else d = BwDistance(name, a, cap);
    if (d <= cap && d < bestd) {
      bestd = d;
      best  = i;
    }
  }
  if (best >= 0) PetscCall(PetscSNPrintf(buf, len, "; did you mean -%s?", scene->asked[best]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneCheckUnused(BwScene scene, BwCheckStage stage, PetscInt nexempt, const char *const exempt[], PetscInt ndeferred, const char *const deferred[])
{
  PetscInt  n, first = -1, leaf = -1;
  char    **names, **values, msg[BW_MSG_LEN] = "", hint[PETSC_MAX_OPTION_NAME + 32];
  PetscBool lazy = PETSC_FALSE;

  PetscFunctionBeginUser;
  /* blockwall's own keys of the file, read or overridden by a getter */
  for (PetscInt i = 0; i < scene->nnodes && leaf < 0 && stage != BW_CHECK_FOREIGN; i++) {
    const BwSceneNode *node = &scene->nodes[i];
    if (stage == BW_CHECK_GEOMETRY && !BwHasPrefix(node->name, "geometry_")) continue;
    if (node->own && node->kind != BW_NODE_MAPPING && !node->used) leaf = i;
  }
  /* PETSc's database: the command line and the file's other keys */
  PetscCall(PetscOptionsLeftGet(NULL, &n, &names, &values));
  for (PetscInt i = 0; i < n; i++) {
    PetscBool skip = PETSC_FALSE, wait = PETSC_FALSE;
    PetscInt  node;

    for (PetscInt j = 0; j < nexempt && !skip; j++) skip = BwHasPrefix(names[i], exempt[j]);
    for (size_t j = 0; j < PETSC_STATIC_ARRAY_LENGTH(BwScenePetscOptions) && !skip; j++) skip = BwInWord(names[i], BwScenePetscOptions[j]);
    for (PetscInt j = 0; j < ndeferred && !skip && !wait; j++) wait = BwHasPrefix(names[i], deferred[j]);
    if (stage == BW_CHECK_FOREIGN && BwSceneOwns(names[i])) continue;
    if (stage == BW_CHECK_GEOMETRY && !BwHasPrefix(names[i], "geometry_")) continue;
    if (skip || (wait && stage != BW_CHECK_FINAL)) continue;
    /* Report the earliest file key, else the first command-line option. */
    node = BwNameMapGet(&scene->argmap, names[i]) >= 0 ? -1 : BwSceneFindNode(scene, names[i]);
    if (node >= 0 && (leaf < 0 || node < leaf)) leaf = node;
    if (node < 0 && first < 0) {
      first = i;
      lazy  = wait;
    }
  }
  if (leaf >= 0) {
    const BwSceneNode *node = &scene->nodes[leaf];
    PetscCall(BwSceneSuggest(scene, node->name, hint, sizeof(hint)));
    PetscCall(PetscSNPrintf(msg, sizeof(msg), "%s:%d: unknown key '%s' (nothing uses it%s)", scene->path, node->line, node->dotted, hint));
  } else if (first >= 0) {
    PetscCall(BwSceneSuggest(scene, names[first], hint, sizeof(hint)));
    PetscCall(PetscSNPrintf(msg, sizeof(msg), "unknown option -%s (nothing uses it%s%s)", names[first], lazy ? ": no solver that ran read it" : "", hint));
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &n, &names, &values));
  PetscCheck(!msg[0], scene->comm, PETSC_ERR_USER_INPUT, "%s", msg);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static int BwCompareNames(const void *a, const void *b)
{
  return strcmp(*(char *const *)a, *(char *const *)b);
}

PetscErrorCode BwSceneListOptions(BwScene scene, const char prefix[], PetscInt *n, char ***names)
{
  PetscInt count = 0;
  char   **list;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(scene->nnodes + scene->nargs + 1, &list));
  for (PetscInt i = 0; i < scene->nnodes; i++) {
    const BwSceneNode *node = &scene->nodes[i];
    if (node->kind != BW_NODE_MAPPING && BwHasPrefix(node->name, prefix) && BwNameMapGet(&scene->argmap, node->name) < 0) PetscCall(PetscStrallocpy(node->name, &list[count++]));
  }
  for (PetscInt i = 0; i < scene->nargs; i++)
    if (BwHasPrefix(scene->args[i].name, prefix)) PetscCall(PetscStrallocpy(scene->args[i].name, &list[count++]));
  list[count] = NULL;
  qsort(list, (size_t)count, sizeof(*list), BwCompareNames);
  *n     = count;
  *names = list;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneListChildren(BwScene scene, const char option[], PetscInt *n, char ***names)
{
  PetscInt parent = BwSceneFindNode(scene, option), count = 0;
  char   **list;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(scene->nnodes + 1, &list));
  if (parent >= 0 && scene->nodes[parent].kind == BW_NODE_MAPPING)
    for (PetscInt i = parent + 1; i < scene->nnodes && scene->nodes[i].depth > scene->nodes[parent].depth; i++)
      if (scene->nodes[i].parent == parent) PetscCall(PetscStrallocpy(scene->nodes[i].key, &list[count++]));
  list[count] = NULL;
  *n          = count;
  *names      = list;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneListEntries(BwScene scene, const char section[], PetscInt nkeys, const char *const keys[], const char what[], PetscInt *n, char ***names)
{
  char     mapping[PETSC_MAX_OPTION_NAME + 1], prefix[PETSC_MAX_OPTION_NAME + 1];
  PetscInt nfile, nopt, count;
  char   **file, **opts, **all;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(mapping, sizeof(mapping), "-%s", section));
  PetscCall(PetscSNPrintf(prefix, sizeof(prefix), "%s_", section));
  PetscCall(BwSceneListChildren(scene, mapping, &nfile, &file));
  PetscCall(BwSceneListOptions(scene, prefix, &nopt, &opts));
  PetscCall(PetscMalloc1(nfile + nopt + 1, &all));
  for (count = 0; count < nfile; count++) all[count] = file[count];
  for (PetscInt o = 0; o < nopt; o++) {
    const char *rest = opts[o] + strlen(prefix);
    size_t      len = strlen(rest), cut = 0;
    PetscBool   known = PETSC_FALSE;
    char        name[PETSC_MAX_OPTION_NAME];

    /* an option under a file entry is that entry's: a misspelt key in it is
     * left to the unused-key check, which names the nearest key */
    for (PetscInt c = 0; c < nfile && !known; c++) {
      size_t l = strlen(all[c]);
      known    = !strncmp(rest, all[c], l) && rest[l] == '_' ? PETSC_TRUE : PETSC_FALSE;
    }
    if (known) continue;
    /* a command-line entry: NAME is what stands before the last _KEY that is
     * followed by '_' or ends the option (cases_wind_loads_top_beam,
     * sets_left_pier_box) */
    for (size_t i = len; i-- > 1 && !cut;) {
      if (rest[i] != '_') continue;
      for (PetscInt k = 0; k < nkeys && !cut; k++) {
        size_t l = strlen(keys[k]);
        if (!strncmp(rest + i + 1, keys[k], l) && (rest[i + 1 + l] == '_' || !rest[i + 1 + l])) cut = i;
      }
    }
    if (!cut) {
      char opt[PETSC_MAX_OPTION_NAME + 1];
      PetscCall(PetscSNPrintf(opt, sizeof(opt), "-%s", opts[o]));
      PetscCall(BwSceneError(scene, opt, "%s", what));
    }
    PetscCall(PetscSNPrintf(name, sizeof(name), "%.*s", (int)cut, rest));
    for (PetscInt c = 0; c < count && !known; c++) PetscCall(PetscStrcmp(all[c], name, &known));
    if (!known) PetscCall(PetscStrallocpy(name, &all[count++]));
  }
  all[count] = NULL;
  PetscCall(PetscFree(file)); /* the names moved to all */
  PetscCall(PetscStrArrayDestroy(&opts));
  *n     = count;
  *names = all;
  PetscFunctionReturn(PETSC_SUCCESS);
}
