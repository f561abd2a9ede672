/* BwScene, part 2: typed values of blockwall's keys.
 *
 * A getter finds the value in effect (the command line's, else the file's),
 * marks it used, checks its type and prints it with -help. A value of the
 * wrong type is one error line that names the key where it was written:
 *   scene.yaml:4: discretization.m must be an integer, got 'sixteen'
 *   command line: -joints_E must be a finite number, got '.inf'
 * Numbers are read with strtod/strtoll on the whole text, so "4x", "3.5"
 * for an integer, YAML's .inf and .nan, "1e400" and integers beyond
 * PetscInt are refused as what they are instead of wrapping or reaching
 * PETSc's parser, whose message names no key. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "scene/scene_impl.h"
#include "util/compat.h"

PetscErrorCode BwSceneLocate(BwScene scene, const char option[], char buf[], size_t len)
{
  const char *name = option[0] == '-' ? option + 1 : option;
  PetscInt    node = BwSceneFindNode(scene, name);

  PetscFunctionBeginUser;
  if (BwNameMapGet(&scene->argmap, name) >= 0) PetscCall(PetscSNPrintf(buf, len, "command line: -%s", name));
  else if (node >= 0) PetscCall(PetscSNPrintf(buf, len, "%s:%d: %s", scene->path, scene->nodes[node].line, scene->nodes[node].dotted));
  else PetscCall(PetscSNPrintf(buf, len, "-%s", name));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneError(BwScene scene, const char option[], const char fmt[], ...)
{
  char    msg[BW_MSG_LEN];
  size_t  k;
  va_list ap;

  PetscFunctionBeginUser;
  PetscCall(BwSceneLocate(scene, option, msg, sizeof(msg) - 1));
  k        = strlen(msg);
  msg[k++] = ' ';
  va_start(ap, fmt);
  vsnprintf(msg + k, sizeof(msg) - k, fmt, ap);
  va_end(ap);
  SETERRQ(scene->comm, PETSC_ERR_USER_INPUT, "%s", msg);
}

PetscErrorCode BwSceneErrorAgree(BwScene scene, PetscBool bad, const char option[], const char fmt[], ...)
{
  char        msg[BW_MSG_LEN] = "";
  PetscMPIInt rank, first, mine;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(scene->comm, &rank));
  if (bad) {
    size_t  k;
    va_list ap;
    PetscCall(BwSceneLocate(scene, option, msg, sizeof(msg) - 1));
    k        = strlen(msg);
    msg[k++] = ' ';
    va_start(ap, fmt);
    vsnprintf(msg + k, sizeof(msg) - k, fmt, ap);
    va_end(ap);
  }
  mine = bad ? rank : PETSC_MPI_INT_MAX;
  PetscCallMPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, scene->comm));
  if (first == PETSC_MPI_INT_MAX) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCallMPI(MPI_Bcast(msg, sizeof(msg), MPI_CHAR, first, scene->comm));
  SETERRQ(scene->comm, PETSC_ERR_USER_INPUT, "%s", msg);
}

/* The value in effect of option `name` (without '-'). */
typedef struct {
  PetscBool   found;
  const char *text;  /* NULL: given without a value (command line) or an empty sequence */
  BwNodeKind  kind;  /* what the file holds there; scalar for the command line */
} BwSceneValue;

static PetscErrorCode BwSceneAsk(BwScene scene, const char name[])
{
  PetscFunctionBeginUser;
  if (BwNameMapGet(&scene->askedmap, name) >= 0) PetscFunctionReturn(PETSC_SUCCESS);
  if (scene->nasked == scene->maxasked) {
    char **more;
    scene->maxasked = PetscMax(2 * scene->maxasked, 64);
    PetscCall(PetscMalloc1(scene->maxasked, &more));
    PetscCall(PetscArraycpy(more, scene->asked, scene->nasked));
    PetscCall(PetscFree(scene->asked));
    scene->asked = more;
    /* the map points into the old array's strings, which did not move */
  }
  PetscCall(PetscStrallocpy(name, &scene->asked[scene->nasked]));
  PetscCall(BwNameMapAdd(&scene->askedmap, scene->asked[scene->nasked], scene->nasked, NULL));
  scene->nasked++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwSceneFind(BwScene scene, const char option[], BwSceneValue *v)
{
  const char *name = option[0] == '-' ? option + 1 : option;
  PetscInt    arg  = BwNameMapGet(&scene->argmap, name), node = BwSceneFindNode(scene, name);

  PetscFunctionBeginUser;
  PetscCall(BwSceneAsk(scene, name));
  v->found = PETSC_FALSE;
  v->text  = NULL;
  v->kind  = BW_NODE_SCALAR;
  /* the file's key counts as read even where the command line overrides it */
  if (node >= 0) scene->nodes[node].used = PETSC_TRUE;
  if (arg >= 0) {
    const char *pv;
    PetscBool   flg;
    char        opt[PETSC_MAX_OPTION_NAME + 1];
    /* marks it used in PETSc's database, where it lives */
    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-%s", name));
    PetscCall(PetscOptionsFindPair(NULL, NULL, opt, &pv, &flg));
    v->found = PETSC_TRUE;
    v->text  = scene->args[arg].value;
  } else if (node >= 0) {
    v->found = PETSC_TRUE;
    v->text  = scene->nodes[node].value;
    v->kind  = scene->nodes[node].kind;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static const char *BwKindName(BwNodeKind k) { return k == BW_NODE_MAPPING ? "a mapping" : k == BW_NODE_SEQUENCE ? "a sequence" : "a single value"; }

/* A single value is wanted: not a mapping, not a sequence, not missing. */
static PetscErrorCode BwSceneWantScalar(BwScene scene, const char option[], const BwSceneValue *v, const char what[])
{
  PetscFunctionBeginUser;
  if (v->kind != BW_NODE_SCALAR) PetscCall(BwSceneError(scene, option, "must be %s, got %s", what, BwKindName(v->kind)));
  if (!v->text) PetscCall(BwSceneError(scene, option, "needs a value (%s)", what));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* YAML's spellings of infinity and not-a-number. */
static PetscBool BwIsNonFiniteWord(const char s[])
{
  static const char *const words[] = {".inf", "-.inf", "+.inf", ".nan", "inf", "-inf", "+inf", "nan", "infinity", "-infinity", "+infinity"};

  for (size_t i = 0; i < PETSC_STATIC_ARRAY_LENGTH(words); i++)
    if (BwSameName(s, words[i])) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* text -> finite double; *ok false with a reason otherwise. */
static void BwParseReal(const char text[], PetscReal *x, const char **why)
{
  char  *end;
  double d;

  *why = NULL;
  if (!text[0]) {
    *why = "an empty value";
    return;
  }
  errno = 0;
  d     = strtod(text, &end);
  if (end == text || *end || isspace((unsigned char)text[0])) {
    *why = BwIsNonFiniteWord(text) ? "non-finite" : "not a number";
    return;
  }
  if (!isfinite(d)) {
    *why = "non-finite";
    return;
  }
  *x = (PetscReal)d;
}

static PetscErrorCode BwSceneHelpLine(BwScene scene, const char option[], const char value[], const char help[])
{
  PetscFunctionBeginUser;
  if (scene->help) PetscCall((*PetscHelpPrintf)(scene->comm, "  %s <%s>: %s\n", option, value, help));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneHelpSection(BwScene scene, const char title[])
{
  PetscFunctionBeginUser;
  if (scene->help) PetscCall((*PetscHelpPrintf)(scene->comm, "%s:\n", title));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneReal(BwScene scene, const char option[], const char help[], PetscReal *value, PetscBool *set)
{
  BwSceneValue v;
  char         shown[64];

  PetscFunctionBeginUser;
  PetscCall(BwSceneFind(scene, option, &v));
  if (v.found) {
    const char *why;
    PetscCall(BwSceneWantScalar(scene, option, &v, "a number"));
    BwParseReal(v.text, value, &why);
    if (why && !strcmp(why, "non-finite")) PetscCall(BwSceneError(scene, option, "must be a finite number, got '%s'", v.text));
    if (why) PetscCall(BwSceneError(scene, option, "must be a number, got %s%s%s", v.text[0] ? "'" : "", v.text[0] ? v.text : why, v.text[0] ? "'" : ""));
  }
  if (set) *set = v.found;
  PetscCall(PetscSNPrintf(shown, sizeof(shown), "%g", (double)*value));
  PetscCall(BwSceneHelpLine(scene, option, shown, help));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneInt(BwScene scene, const char option[], const char help[], PetscInt *value, PetscBool *set)
{
  BwSceneValue v;
  char         shown[64];

  PetscFunctionBeginUser;
  PetscCall(BwSceneFind(scene, option, &v));
  if (v.found) {
    char     *end;
    long long x;
    PetscCall(BwSceneWantScalar(scene, option, &v, "an integer"));
    errno = 0;
    x     = strtoll(v.text, &end, 10);
    if (!v.text[0] || end == v.text || *end || isspace((unsigned char)v.text[0])) PetscCall(BwSceneError(scene, option, "must be an integer, got %s%s%s", v.text[0] ? "'" : "", v.text[0] ? v.text : "an empty value", v.text[0] ? "'" : ""));
    /* what does not fit is refused as written, never wrapped */
    if (errno == ERANGE || x > PETSC_MAX_INT || x < PETSC_MIN_INT) PetscCall(BwSceneError(scene, option, "must be an integer from %" PetscInt_FMT " to %" PetscInt_FMT ", got '%s'", (PetscInt)PETSC_MIN_INT, (PetscInt)PETSC_MAX_INT, v.text));
    *value = (PetscInt)x;
  }
  if (set) *set = v.found;
  PetscCall(PetscSNPrintf(shown, sizeof(shown), "%" PetscInt_FMT, *value));
  PetscCall(BwSceneHelpLine(scene, option, shown, help));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneBool(BwScene scene, const char option[], const char help[], PetscBool *value, PetscBool *set)
{
  static const char *const yes[] = {"true", "yes", "on", "1"}, *const no[] = {"false", "no", "off", "0"};
  BwSceneValue             v;

  PetscFunctionBeginUser;
  PetscCall(BwSceneFind(scene, option, &v));
  if (v.found) {
    PetscBool known = PETSC_FALSE;
    if (v.kind != BW_NODE_SCALAR) PetscCall(BwSceneError(scene, option, "must be true or false, got %s", BwKindName(v.kind)));
    if (!v.text) { /* a flag without a value, PETSc's convention: true */
      *value = PETSC_TRUE;
      known  = PETSC_TRUE;
    }
    for (int i = 0; i < 4 && !known; i++) {
      if (BwSameName(v.text, yes[i])) *value = PETSC_TRUE, known = PETSC_TRUE;
      else if (BwSameName(v.text, no[i])) *value = PETSC_FALSE, known = PETSC_TRUE;
    }
    if (!known) PetscCall(BwSceneError(scene, option, "must be true or false, got '%s'", v.text));
  }
  if (set) *set = v.found;
  PetscCall(BwSceneHelpLine(scene, option, *value ? "true" : "false", help));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwListNames(PetscInt n, const char *const names[], char buf[], size_t len)
{
  PetscFunctionBeginUser;
  buf[0] = 0;
  for (PetscInt i = 0; i < n; i++) {
    if (i) PetscCall(PetscStrlcat(buf, i + 1 == n ? " or " : ", ", len));
    PetscCall(PetscStrlcat(buf, names[i], len));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneEnum(BwScene scene, const char option[], const char help[], PetscInt n, const char *const names[], PetscInt *value, PetscBool *set)
{
  BwSceneValue v;
  char         list[512], text[1024];

  PetscFunctionBeginUser;
  PetscCall(BwListNames(n, names, list, sizeof(list)));
  PetscCall(BwSceneFind(scene, option, &v));
  if (v.found) {
    PetscInt k = 0;
    if (v.kind != BW_NODE_SCALAR || !v.text) PetscCall(BwSceneError(scene, option, "must be one of %s, got %s", list, v.text || v.kind != BW_NODE_SCALAR ? BwKindName(v.kind) : "no value"));
    while (k < n && !BwSameName(v.text, names[k])) k++;
    if (k == n) PetscCall(BwSceneError(scene, option, "must be one of %s, got '%s'", list, v.text));
    *value = k;
  }
  if (set) *set = v.found;
  PetscCall(PetscSNPrintf(text, sizeof(text), "%s (%s)", help, list));
  PetscCall(BwSceneHelpLine(scene, option, names[*value], text));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneString(BwScene scene, const char option[], const char help[], char value[], size_t len, PetscBool *set)
{
  BwSceneValue v;

  PetscFunctionBeginUser;
  PetscCall(BwSceneFind(scene, option, &v));
  if (v.found) {
    PetscCall(BwSceneWantScalar(scene, option, &v, "a single value"));
    if (strlen(v.text) >= len) PetscCall(BwSceneError(scene, option, "is longer than %zu characters", len - 1));
    PetscCall(PetscStrncpy(value, v.text, len));
  }
  if (set) *set = v.found;
  PetscCall(BwSceneHelpLine(scene, option, value, help));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A comma-separated text split into its elements, each checked by `parse`. */
static PetscErrorCode BwSceneArray(BwScene scene, const char option[], const char help[], PetscBool integer, void **values, PetscInt *n, PetscBool *set)
{
  BwSceneValue v;

  PetscFunctionBeginUser;
  *values = NULL;
  *n      = 0;
  PetscCall(BwSceneFind(scene, option, &v));
  if (set) *set = v.found;
  PetscCall(BwSceneHelpLine(scene, option, "", help));
  if (!v.found) PetscFunctionReturn(PETSC_SUCCESS);
  if (v.kind == BW_NODE_MAPPING) PetscCall(BwSceneError(scene, option, "must be a sequence of %s, got a mapping", integer ? "integers" : "numbers"));
  if (!v.text && v.kind == BW_NODE_SCALAR) PetscCall(BwSceneError(scene, option, "needs a value (%s)", integer ? "integers separated by ','" : "numbers separated by ','"));
  if (!v.text) PetscFunctionReturn(PETSC_SUCCESS); /* [] */
  {
    PetscInt    count = 1, k = 0;
    const char *p     = v.text;
    char        item[256];
    for (const char *c = v.text; *c; c++) count += *c == ',';
    if (integer) PetscCall(PetscMalloc1(count, (PetscInt **)values));
    else PetscCall(PetscMalloc1(count, (PetscReal **)values));
    for (;; k++) {
      const char *q = strchr(p, ',');
      size_t      l = q ? (size_t)(q - p) : strlen(p);
      if (l >= sizeof(item)) l = sizeof(item) - 1;
      memcpy(item, p, l);
      item[l] = 0;
      if (integer) {
        char     *end;
        long long x;
        errno = 0;
        x     = strtoll(item, &end, 10);
        if (!item[0] || *end || end == item || isspace((unsigned char)item[0])) PetscCall(BwSceneError(scene, option, "must hold integers, got '%s' (element %" PetscInt_FMT ")", item, k + 1));
        if (errno == ERANGE || x > PETSC_MAX_INT || x < PETSC_MIN_INT) PetscCall(BwSceneError(scene, option, "must hold integers from %" PetscInt_FMT " to %" PetscInt_FMT ", got '%s' (element %" PetscInt_FMT ")", (PetscInt)PETSC_MIN_INT, (PetscInt)PETSC_MAX_INT, item, k + 1));
        ((PetscInt *)*values)[k] = (PetscInt)x;
      } else {
        const char *why;
        BwParseReal(item, &((PetscReal *)*values)[k], &why);
        if (why) PetscCall(BwSceneError(scene, option, "must hold finite numbers, got %s%s%s (element %" PetscInt_FMT ")", item[0] ? "'" : "", item[0] ? item : "an empty value", item[0] ? "'" : "", k + 1));
      }
      if (!q) break;
      p = q + 1;
    }
    *n = k + 1;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneRealArray(BwScene scene, const char option[], const char help[], PetscReal **values, PetscInt *n, PetscBool *set)
{
  PetscFunctionBeginUser;
  PetscCall(BwSceneArray(scene, option, help, PETSC_FALSE, (void **)values, n, set));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneIntArray(BwScene scene, const char option[], const char help[], PetscInt **values, PetscInt *n, PetscBool *set)
{
  PetscFunctionBeginUser;
  PetscCall(BwSceneArray(scene, option, help, PETSC_TRUE, (void **)values, n, set));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneText(BwScene scene, const char option[], char value[], size_t len, PetscBool *set)
{
  BwSceneValue v;

  PetscFunctionBeginUser;
  PetscCall(BwSceneFind(scene, option, &v));
  PetscCall(PetscStrncpy(value, v.text ? v.text : "", len));
  if (set) *set = v.found;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneRequireMapping(BwScene scene, const char option[], const char what[])
{
  PetscInt node = BwSceneFindNode(scene, option);

  PetscFunctionBeginUser;
  if (node >= 0 && scene->nodes[node].kind != BW_NODE_MAPPING) {
    const BwSceneNode *n = &scene->nodes[node];
    SETERRQ(scene->comm, PETSC_ERR_USER_INPUT, "%s:%d: %s must be a mapping (%s), got %s", scene->path, n->line, n->dotted, what, BwKindName(n->kind));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}
