/* BwScene: reads the scene file (YAML) into the PETSc options database.
 *
 * PETSc 3.18 cannot read YAML sequences, and its own YAML reader forgets
 * where each key came from, so the file is parsed here with libyaml's event
 * API. Parsing happens in two passes: the whole file is first turned into a
 * list of nodes (one per key, in document order, with its line), and only if
 * that succeeds are the leaves inserted, so a broken file leaves the database
 * untouched. The node list then answers "where does -joints_E come from" for
 * error messages and is the skeleton that BwSceneGetText re-emits.
 *
 * Reading an option here must never mark it used, or BwSceneCheckUnused would
 * miss the very mistakes it exists to catch. PETSc 3.18 has no non-marking
 * lookup, but PetscOptionsLeftGet lists the unused options with their values
 * without marking them, and for an option already used a PetscOptionsFindPair
 * changes nothing: BwOptionPeek combines the two.
 *
 * PETSc 3.18 does not record where an option came from, so every option the
 * file did not insert is attributed to the command line (it may also come
 * from PETSC_OPTIONS or a .petscrc, which is where the user would look). */
#include "scene/scene.h"
#include "util/compat.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

/* PETSc keeps at most this much of an error message (PetscErrorBaseMessage). */
#define BW_MSG_LEN 1024
/* Deeper nesting than this is a mistake in the file, not a scene. */
#define BW_MAX_DEPTH 32

typedef enum {
  BW_NODE_MAPPING,
  BW_NODE_SCALAR,
  BW_NODE_SEQUENCE
} BwNodeKind;

typedef struct {
  BwNodeKind kind;
  int        depth;    /* 0 for top-level keys */
  int        line;     /* 1-based line of the key */
  char      *key;      /* as written: "E" */
  char      *dotted;   /* "joints.E", for messages */
  char      *name;     /* option name without '-': "joints_E" */
  char      *value;    /* leaves: the file's text, sequences comma-joined; NULL if empty */
  PetscBool  inserted; /* leaves: the file's value went into the database */
} BwSceneNode;

struct _p_BwScene {
  MPI_Comm     comm;
  char        *path; /* as given, for messages */
  char        *dir;
  PetscInt     nnodes, maxnodes;
  BwSceneNode *nodes;
};

/* Blockwall's sections: command-line options in them (the section's name
 * itself, or it followed by '_') are part of the scene as run, so
 * BwSceneGetText writes them out. */
static const char *const BwSceneSections[] = {"title", "geometry", "joints", "discretization", "supports", "loads", "gravity", "solver", "output"};

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

/* Option names are case-insensitive in PETSc; these compare like it does,
 * without a PETSc call, so they can sit in conditions. */
static PetscBool BwSameName(const char a[], const char b[])
{
  for (; *a && *b; a++, b++)
    if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return PETSC_FALSE;
  return (PetscBool)(*a == *b);
}

static PetscBool BwHasPrefix(const char name[], const char prefix[])
{
  for (; *prefix; name++, prefix++)
    if (!*name || tolower((unsigned char)*name) != tolower((unsigned char)*prefix)) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* `name` is `word` or continues it after '_'. */
static PetscBool BwInWord(const char name[], const char word[])
{
  size_t n = strlen(word);

  return (PetscBool)(BwHasPrefix(name, word) && (name[n] == 0 || name[n] == '_'));
}

/* ---------------------------------------------------------------- text -- */

typedef struct {
  char  *s;
  size_t len, cap;
} BwText;

static PetscErrorCode BwTextPut(BwText *t, const char s[], size_t n)
{
  PetscFunctionBeginUser;
  if (t->len + n + 1 > t->cap) {
    size_t cap = PetscMax(PetscMax(2 * t->cap, t->len + n + 1), (size_t)256);
    char  *s2;

    PetscCall(PetscMalloc1(cap, &s2));
    PetscCall(PetscArraycpy(s2, t->s, t->len));
    PetscCall(PetscFree(t->s));
    t->s   = s2;
    t->cap = cap;
  }
  PetscCall(PetscArraycpy(t->s + t->len, s, n));
  t->len += n;
  t->s[t->len] = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwTextPuts(BwText *t, const char s[])
{
  PetscFunctionBeginUser;
  PetscCall(BwTextPut(t, s, strlen(s)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Values that YAML reads back verbatim without quotes: numbers and the
 * words PETSc takes as booleans. Everything else is quoted. */
static PetscBool BwIsPlain(const char s[], size_t n)
{
  static const char *const words[] = {"true", "false", "yes", "no", "on", "off"};
  char                     buf[64], *end;

  if (n == 0 || n >= sizeof(buf)) return PETSC_FALSE;
  memcpy(buf, s, n);
  buf[n] = 0;
  for (size_t i = 0; i < PETSC_STATIC_ARRAY_LENGTH(words); i++)
    if (BwSameName(buf, words[i])) return PETSC_TRUE;
  if (!strchr("+-.0123456789", buf[0])) return PETSC_FALSE;
  (void)strtod(buf, &end);
  return (PetscBool)(*end == 0);
}

static PetscErrorCode BwTextPutScalar(BwText *t, const char s[], size_t n)
{
  PetscFunctionBeginUser;
  if (BwIsPlain(s, n)) {
    PetscCall(BwTextPut(t, s, n));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(BwTextPuts(t, "\""));
  for (size_t i = 0; i < n; i++) {
    unsigned char c = (unsigned char)s[i];
    char          esc[8];

    if (c == '"' || c == '\\') PetscCall(PetscSNPrintf(esc, sizeof(esc), "\\%c", c));
    else if (c == '\n') PetscCall(PetscStrncpy(esc, "\\n", sizeof(esc)));
    else if (c == '\t') PetscCall(PetscStrncpy(esc, "\\t", sizeof(esc)));
    else if (c < 0x20 || c == 0x7f) PetscCall(PetscSNPrintf(esc, sizeof(esc), "\\x%02x", c));
    else {
      esc[0] = (char)c;
      esc[1] = 0;
    }
    PetscCall(BwTextPuts(t, esc));
  }
  PetscCall(BwTextPuts(t, "\""));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A comma-separated option value as a flow sequence "[a, b]"; splitting on
 * every comma loads back to the same text. */
static PetscErrorCode BwTextPutSequence(BwText *t, const char s[])
{
  PetscFunctionBeginUser;
  PetscCall(BwTextPuts(t, "["));
  if (s && *s) {
    for (const char *p = s;; p++) {
      const char *q = strchr(p, ',');
      size_t      n = q ? (size_t)(q - p) : strlen(p);

      if (p != s) PetscCall(BwTextPuts(t, ", "));
      PetscCall(BwTextPutScalar(t, p, n));
      if (!q) break;
      p = q;
    }
  }
  PetscCall(BwTextPuts(t, "]"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A command-line value written back as a flow sequence when it is a list of
 * plain numbers (pretty and exact), else as one quoted scalar (exact). */
static PetscBool BwIsPlainList(const char s[])
{
  if (!s || !strchr(s, ',')) return PETSC_FALSE;
  for (const char *p = s;; p++) {
    const char *q = strchr(p, ',');

    if (!BwIsPlain(p, q ? (size_t)(q - p) : strlen(p))) return PETSC_FALSE;
    if (!q) return PETSC_TRUE;
    p = q;
  }
}

/* ------------------------------------------------------------- options -- */

/* Value of option `name` (without '-') without marking it used: *value is a
 * copy to PetscFree, NULL when the option has no value. */
static PetscErrorCode BwOptionPeek(const char name[], PetscBool *found, char **value)
{
  PetscInt  n;
  char    **names, **values;
  PetscBool used;

  PetscFunctionBeginUser;
  *found = PETSC_FALSE;
  if (value) *value = NULL;
  PetscCall(PetscOptionsLeftGet(NULL, &n, &names, &values));
  for (PetscInt i = 0; i < n && !*found; i++) {
    if (!BwSameName(names[i], name)) continue;
    *found = PETSC_TRUE;
    if (value && values[i]) PetscCall(PetscStrallocpy(values[i], value));
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &n, &names, &values));
  if (*found) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscOptionsUsed(NULL, name, &used));
  if (used) {
    char        option[PETSC_MAX_OPTION_NAME];
    const char *v;

    PetscCall(PetscSNPrintf(option, sizeof(option), "-%s", name));
    PetscCall(PetscOptionsFindPair(NULL, NULL, option, &v, found));
    if (value && v) PetscCall(PetscStrallocpy(v, value));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static int BwCompareNames(const void *a, const void *b)
{
  return strcmp(*(char *const *)a, *(char *const *)b);
}

/* Names (without '-') of all options in the database, sorted, in a
 * NULL-terminated array for PetscStrArrayDestroy. PetscOptionsGetAll is the
 * only list of used options, but "-a x -b y" is ambiguous once a value holds
 * spaces (a title "see -b"): every "-word" in it is only a candidate, kept if
 * the database knows it as unused (PetscOptionsLeftGet) or used
 * (PetscOptionsUsed, which is false for names that are not options). */
static PetscErrorCode BwOptionsAll(PetscInt *n, char ***names)
{
  char     *all, *p;
  PetscInt  nleft, count = 0, max = 16;
  char    **left, **leftvalues, **list;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetAll(NULL, &all));
  PetscCall(PetscOptionsLeftGet(NULL, &nleft, &left, &leftvalues));
  PetscCall(PetscMalloc1(max + 1, &list));
  for (p = all; *p;) {
    char     *word = p;
    PetscBool known = PETSC_FALSE, dup = PETSC_FALSE;

    while (*p && *p != ' ') p++;
    if (*p) *p++ = 0;
    if (word[0] != '-' || !isalpha((unsigned char)word[1])) continue;
    word++;
    for (PetscInt i = 0; i < nleft && !known; i++) known = BwSameName(left[i], word);
    if (!known) PetscCall(PetscOptionsUsed(NULL, word, &known));
    for (PetscInt i = 0; i < count && !dup; i++) dup = BwSameName(list[i], word);
    if (!known || dup) continue;
    if (count == max) {
      char **list2;

      max *= 2;
      PetscCall(PetscMalloc1(max + 1, &list2));
      PetscCall(PetscArraycpy(list2, list, count));
      PetscCall(PetscFree(list));
      list = list2;
    }
    PetscCall(PetscStrallocpy(word, &list[count++]));
  }
  list[count] = NULL;
  PetscCall(PetscOptionsLeftRestore(NULL, &nleft, &left, &leftvalues));
  PetscCall(PetscFree(all));
  qsort(list, (size_t)count, sizeof(*list), BwCompareNames);
  *n     = count;
  *names = list;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* --------------------------------------------------------------- nodes -- */

/* The leaf whose option is `name` (with or without '-'), or -1. */
static PetscInt BwSceneFindLeaf(BwScene scene, const char name[])
{
  if (name[0] == '-') name++;
  for (PetscInt i = 0; i < scene->nnodes; i++)
    if (scene->nodes[i].kind != BW_NODE_MAPPING && BwSameName(scene->nodes[i].name, name)) return i;
  return -1;
}

static PetscErrorCode BwSceneAddNode(BwScene scene, BwNodeKind kind, PetscInt parent, const char key[], int line, PetscInt *index)
{
  BwSceneNode *node;

  PetscFunctionBeginUser;
  if (scene->nnodes == scene->maxnodes) {
    BwSceneNode *nodes;

    scene->maxnodes = PetscMax(2 * scene->maxnodes, 32);
    PetscCall(PetscCalloc1(scene->maxnodes, &nodes));
    PetscCall(PetscArraycpy(nodes, scene->nodes, scene->nnodes));
    PetscCall(PetscFree(scene->nodes));
    scene->nodes = nodes;
  }
  *index = scene->nnodes++;
  node   = &scene->nodes[*index];
  node->kind = kind;
  node->line = line;
  PetscCall(PetscStrallocpy(key, &node->key));
  if (parent < 0) {
    node->depth = 0;
    PetscCall(PetscStrallocpy(key, &node->dotted));
    PetscCall(PetscStrallocpy(key, &node->name));
  } else {
    const BwSceneNode *up = &scene->nodes[parent];
    size_t             n  = strlen(up->dotted) + strlen(key) + 2;

    node->depth = up->depth + 1;
    PetscCall(PetscMalloc1(n, &node->dotted));
    PetscCall(PetscMalloc1(n, &node->name));
    PetscCall(PetscSNPrintf(node->dotted, n, "%s.%s", up->dotted, key));
    PetscCall(PetscSNPrintf(node->name, n, "%s_%s", up->name, key));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* -------------------------------------------------------------- parser -- */

typedef struct {
  BwScene       scene;
  yaml_parser_t parser;
  yaml_event_t  event; /* the current event */
  BwText        seq;   /* elements of the sequence being read, here to be freed on errors */
} BwParser;

/* Raise "path:line: <text>" as a user-input error. */
static PetscErrorCode BwParserError(BwParser *p, size_t line, const char fmt[], ...) PETSC_ATTRIBUTE_FORMAT(3, 4);
static PetscErrorCode BwParserError(BwParser *p, size_t line, const char fmt[], ...)
{
  char    msg[BW_MSG_LEN];
  int     k;
  va_list ap;

  PetscFunctionBeginUser;
  k = snprintf(msg, sizeof(msg), "%s:%zu: ", p->scene->path, line);
  if (k > 0 && (size_t)k < sizeof(msg)) {
    va_start(ap, fmt);
    vsnprintf(msg + k, sizeof(msg) - (size_t)k, fmt, ap);
    va_end(ap);
  }
  SETERRQ(p->scene->comm, PETSC_ERR_USER_INPUT, "%s", msg);
}

static size_t BwEventLine(const yaml_event_t *e)
{
  return e->start_mark.line + 1;
}

static PetscErrorCode BwParserNext(BwParser *p)
{
  PetscFunctionBeginUser;
  yaml_event_delete(&p->event);
  if (!yaml_parser_parse(&p->parser, &p->event)) {
    const yaml_parser_t *y    = &p->parser;
    size_t               line = y->problem_mark.line + 1;

    /* Reader errors (bad UTF-8, control characters) carry only an offset. */
    if (y->error == YAML_READER_ERROR) {
      const unsigned char *s = y->input.string.start;

      line = 1;
      for (size_t i = 0; i < y->problem_offset && s + i < y->input.string.end; i++) line += s[i] == '\n';
    }
    if (y->context) PetscCall(BwParserError(p, line, "YAML syntax error: %s (%s at line %zu)", y->problem, y->context, y->context_mark.line + 1));
    PetscCall(BwParserError(p, line, "YAML syntax error: %s", y->problem ? y->problem : "unknown problem"));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Anchors and aliases would let one key stand for several; scenes are small
 * enough to write out, so they are refused rather than half supported. */
static PetscErrorCode BwParserNoAnchor(BwParser *p)
{
  const yaml_event_t *e = &p->event;
  const yaml_char_t  *anchor = NULL;

  PetscFunctionBeginUser;
  if (e->type == YAML_SCALAR_EVENT) anchor = e->data.scalar.anchor;
  else if (e->type == YAML_MAPPING_START_EVENT) anchor = e->data.mapping_start.anchor;
  else if (e->type == YAML_SEQUENCE_START_EVENT) anchor = e->data.sequence_start.anchor;
  if (e->type == YAML_ALIAS_EVENT || anchor) PetscCall(BwParserError(p, BwEventLine(e), "anchors and aliases (&name, *name) are not supported in scene files; write the values out"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* YAML's null: nothing after the colon, "~" or "null" unquoted. */
static PetscBool BwIsNull(const yaml_event_t *e)
{
  const char *v = (const char *)e->data.scalar.value;

  if (e->data.scalar.style != YAML_PLAIN_SCALAR_STYLE) return PETSC_FALSE;
  return (PetscBool)(!v[0] || !strcmp(v, "~") || !strcmp(v, "null") || !strcmp(v, "Null") || !strcmp(v, "NULL"));
}

static const char *BwEventKind(const yaml_event_t *e)
{
  switch (e->type) {
  case YAML_MAPPING_START_EVENT:
    return "a mapping";
  case YAML_SEQUENCE_START_EVENT:
    return "a sequence";
  default:
    return "a single value";
  }
}

/* Appends the elements of the sequence just started to `value`, nested
 * sequences flattened, and counts them in *count. */
static PetscErrorCode BwParseSequence(BwParser *p, const char dotted[], int depth, BwText *value, PetscInt *count)
{
  PetscFunctionBeginUser;
  if (depth > BW_MAX_DEPTH) PetscCall(BwParserError(p, BwEventLine(&p->event), "'%s' is nested deeper than %d levels", dotted, BW_MAX_DEPTH));
  for (;;) {
    yaml_event_t *e = &p->event;

    PetscCall(BwParserNext(p));
    PetscCall(BwParserNoAnchor(p));
    if (e->type == YAML_SEQUENCE_END_EVENT) break;
    if (e->type == YAML_SEQUENCE_START_EVENT) {
      PetscCall(BwParseSequence(p, dotted, depth + 1, value, count));
      continue;
    }
    if (e->type != YAML_SCALAR_EVENT) PetscCall(BwParserError(p, BwEventLine(e), "'%s' is a sequence holding %s; its elements must be numbers, strings or sequences", dotted, BwEventKind(e)));
    if (BwIsNull(e)) PetscCall(BwParserError(p, BwEventLine(e), "an element of '%s' has no value", dotted));
    if (strchr((const char *)e->data.scalar.value, ','))
      PetscCall(BwParserError(p, BwEventLine(e), "element '%s' of '%s' contains ',', which cannot be told apart from the separator in the option value", (const char *)e->data.scalar.value, dotted));
    if ((*count)++) PetscCall(BwTextPuts(value, ","));
    PetscCall(BwTextPut(value, (const char *)e->data.scalar.value, e->data.scalar.length));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Letters, digits and '_' make option names PETSc and the shell take as
 * they are; a top-level key must start with a letter to be an option. */
static PetscBool BwIsValidKey(const char key[], PetscBool top)
{
  if (!key[0] || (top && !isalpha((unsigned char)key[0]))) return PETSC_FALSE;
  for (const char *c = key; *c; c++)
    if (!isalnum((unsigned char)*c) && *c != '_') return PETSC_FALSE;
  return PETSC_TRUE;
}

/* The keys of the mapping just started, under node `parent` (-1: top). */
static PetscErrorCode BwParseMapping(BwParser *p, PetscInt parent, int depth)
{
  BwScene scene = p->scene;

  PetscFunctionBeginUser;
  if (depth > BW_MAX_DEPTH) PetscCall(BwParserError(p, BwEventLine(&p->event), "'%s' is nested deeper than %d levels", scene->nodes[parent].dotted, BW_MAX_DEPTH));
  for (;;) {
    yaml_event_t *e = &p->event;
    char          key[PETSC_MAX_OPTION_NAME]; /* the value's event replaces the key's */
    size_t        line;
    PetscInt      node = -1;
    BwNodeKind    kind;
    char          where[PETSC_MAX_OPTION_NAME + 8]; /* "at the top level" or "in 'joints'" */

    if (parent < 0) PetscCall(PetscStrncpy(where, "at the top level", sizeof(where)));
    else PetscCall(PetscSNPrintf(where, sizeof(where), "in '%s'", scene->nodes[parent].dotted));
    PetscCall(BwParserNext(p));
    if (e->type == YAML_MAPPING_END_EVENT) break;
    PetscCall(BwParserNoAnchor(p));
    if (e->type != YAML_SCALAR_EVENT) PetscCall(BwParserError(p, BwEventLine(e), "a key %s is %s; keys must be names", where, BwEventKind(e)));
    line = BwEventLine(e);
    if (e->data.scalar.length >= sizeof(key)) PetscCall(BwParserError(p, line, "a key %s is longer than %zu characters", where, sizeof(key) - 1));
    PetscCall(PetscStrncpy(key, (const char *)e->data.scalar.value, sizeof(key)));
    if (!BwIsValidKey(key, (PetscBool)(parent < 0)))
      PetscCall(BwParserError(p, line, "invalid key '%s' %s: keys are option names, made of letters, digits and '_'%s", key, where, parent < 0 ? ", starting with a letter" : ""));
    /* Siblings are the nodes of this depth back to the parent. */
    for (PetscInt i = scene->nnodes - 1; i >= 0 && scene->nodes[i].depth >= depth; i--)
      if (scene->nodes[i].depth == depth && BwSameName(scene->nodes[i].key, key)) PetscCall(BwParserError(p, line, "duplicate key '%s' (first at line %d)", scene->nodes[i].dotted, scene->nodes[i].line));

    PetscCall(BwParserNext(p));
    PetscCall(BwParserNoAnchor(p));
    kind = e->type == YAML_MAPPING_START_EVENT ? BW_NODE_MAPPING : e->type == YAML_SEQUENCE_START_EVENT ? BW_NODE_SEQUENCE : BW_NODE_SCALAR;
    PetscCall(BwSceneAddNode(scene, kind, parent, key, (int)line, &node));
    if (strlen(scene->nodes[node].name) + 2 > PETSC_MAX_OPTION_NAME) PetscCall(BwParserError(p, line, "key '%s' makes an option name longer than PETSc's %d characters", scene->nodes[node].dotted, PETSC_MAX_OPTION_NAME - 2));
    if (scene->nodes[node].kind != BW_NODE_MAPPING) {
      BwSceneNode *leaf  = &scene->nodes[node];
      PetscInt     other = BwSceneFindLeaf(scene, leaf->name);

      if (other != node)
        PetscCall(BwParserError(p, line, "key '%s' sets the same option -%s as key '%s' at line %d", leaf->dotted, leaf->name, scene->nodes[other].dotted, scene->nodes[other].line));
    }
    if (e->type == YAML_MAPPING_START_EVENT) {
      PetscCall(BwParseMapping(p, node, depth + 1));
    } else if (e->type == YAML_SEQUENCE_START_EVENT) {
      PetscInt count = 0;

      p->seq.len = 0;
      PetscCall(BwParseSequence(p, scene->nodes[node].dotted, depth + 1, &p->seq, &count));
      if (p->seq.len) PetscCall(PetscStrallocpy(p->seq.s, &scene->nodes[node].value));
    } else {
      if (BwIsNull(e)) PetscCall(BwParserError(p, line, "key '%s' has no value (write \"\" for an option without one)", scene->nodes[node].dotted));
      if (e->data.scalar.length) PetscCall(PetscStrallocpy((const char *)e->data.scalar.value, &scene->nodes[node].value));
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* One document whose top level is a mapping. */
static PetscErrorCode BwParseStream(BwParser *p)
{
  yaml_event_t *e = &p->event;

  PetscFunctionBeginUser;
  PetscCall(BwParserNext(p)); /* stream start */
  PetscCall(BwParserNext(p));
  if (e->type == YAML_STREAM_END_EVENT) PetscCall(BwParserError(p, 1, "the scene file is empty; it must hold a mapping of keys (key: value lines)"));
  PetscCall(BwParserNext(p)); /* the root, after the document start */
  PetscCall(BwParserNoAnchor(p));
  if (e->type != YAML_MAPPING_START_EVENT) PetscCall(BwParserError(p, BwEventLine(e), "the scene must be a mapping of keys (key: value lines) at top level, not %s", BwEventKind(e)));
  PetscCall(BwParseMapping(p, -1, 0));
  PetscCall(BwParserNext(p)); /* document end */
  PetscCall(BwParserNext(p));
  if (e->type == YAML_DOCUMENT_START_EVENT) PetscCall(BwParserError(p, BwEventLine(e), "a scene file holds one YAML document, found a second one"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* --------------------------------------------------------------- scene -- */

PetscErrorCode BwSceneCreate(MPI_Comm comm, BwScene *scene)
{
  PetscFunctionBeginUser;
  PetscCall(PetscNew(scene));
  (*scene)->comm = comm;
  PetscCall(PetscStrallocpy(".", &(*scene)->dir));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rank 0 reads the file; *err is 0 or the errno of the failure. */
static PetscErrorCode BwSceneReadFile(const char path[], char **text, size_t *len, int *err)
{
  FILE  *f;
  size_t cap = 4096, n;

  PetscFunctionBeginUser;
  *text = NULL;
  *len  = 0;
  errno = 0;
  f     = fopen(path, "rb");
  if (!f) {
    *err = errno;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscMalloc1(cap, text));
  while ((n = fread(*text + *len, 1, cap - *len, f)) > 0) {
    *len += n;
    if (*len == cap) {
      char *more;

      PetscCall(PetscMalloc1(2 * cap, &more));
      PetscCall(PetscArraycpy(more, *text, *len));
      PetscCall(PetscFree(*text));
      *text = more;
      cap *= 2;
    }
  }
  *err = ferror(f) ? (errno ? errno : EIO) : 0;
  fclose(f);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneLoad(BwScene scene, const char path[])
{
  PetscMPIInt    rank, count;
  char          *text = NULL, *slash;
  size_t         len  = 0;
  int            err  = 0;
  long long      info[2];
  BwParser       p;
  PetscErrorCode perr;

  PetscFunctionBeginUser;
  PetscCheck(!scene->path, scene->comm, PETSC_ERR_ORDER, "BwSceneLoad: the scene is already loaded from '%s'", scene->path);
  PetscCall(PetscStrallocpy(path, &scene->path));
  PetscCall(PetscFree(scene->dir));
  PetscCall(PetscStrallocpy(path, &scene->dir));
  slash = strrchr(scene->dir, '/');
  if (!slash) PetscCall(PetscStrncpy(scene->dir, ".", 2));
  else slash[slash == scene->dir] = 0; /* keep "/" for a file at the root */

  /* Failure on rank 0 travels with the length, so all ranks raise the same error. */
  PetscCallMPI(MPI_Comm_rank(scene->comm, &rank));
  if (rank == 0) PetscCall(BwSceneReadFile(path, &text, &len, &err));
  info[0] = (long long)len;
  info[1] = err;
  PetscCallMPI(MPI_Bcast(info, 2, MPI_LONG_LONG, 0, scene->comm));
  if (info[1]) {
    PetscCall(PetscFree(text));
    SETERRQ(scene->comm, PETSC_ERR_USER_INPUT, "cannot read scene file '%s': %s", path, strerror((int)info[1]));
  }
  PetscCheck(info[0] < PETSC_MPI_INT_MAX, scene->comm, PETSC_ERR_USER_INPUT, "scene file '%s' is too large (%lld bytes)", path, info[0]);
  len   = (size_t)info[0];
  count = (PetscMPIInt)info[0];
  if (rank != 0) PetscCall(PetscMalloc1(len + 1, &text));
  PetscCallMPI(MPI_Bcast(text, count, MPI_CHAR, 0, scene->comm));

  memset(&p, 0, sizeof(p));
  p.scene = scene;
  PetscCheck(yaml_parser_initialize(&p.parser), PETSC_COMM_SELF, PETSC_ERR_MEM, "libyaml could not create a parser");
  yaml_parser_set_input_string(&p.parser, (const unsigned char *)text, len);
  perr = BwParseStream(&p);
  yaml_event_delete(&p.event);
  yaml_parser_delete(&p.parser);
  PetscCall(PetscFree(p.seq.s));
  PetscCall(PetscFree(text));
  PetscCall(perr);

  /* The command line wins: a key already in the database is only recorded. */
  for (PetscInt i = 0; i < scene->nnodes; i++) {
    BwSceneNode *node = &scene->nodes[i];
    PetscBool    found;
    char         option[PETSC_MAX_OPTION_NAME];

    if (node->kind == BW_NODE_MAPPING) continue;
    PetscCall(BwOptionPeek(node->name, &found, NULL));
    if (found) continue;
    PetscCall(PetscSNPrintf(option, sizeof(option), "-%s", node->name));
    PetscCall(PetscOptionsSetValue(NULL, option, node->value));
    node->inserted = PETSC_TRUE;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneGetDirectory(BwScene scene, const char *dir[])
{
  PetscFunctionBeginUser;
  *dir = scene->dir;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneLocate(BwScene scene, const char option[], char buf[], size_t len)
{
  const char *name = option[0] == '-' ? option + 1 : option;
  PetscInt    leaf = BwSceneFindLeaf(scene, name);
  PetscBool   found;

  PetscFunctionBeginUser;
  if (leaf >= 0 && scene->nodes[leaf].inserted) {
    PetscCall(PetscSNPrintf(buf, len, "%s:%d: %s", scene->path, scene->nodes[leaf].line, scene->nodes[leaf].dotted));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(BwOptionPeek(name, &found, NULL));
  PetscCall(PetscSNPrintf(buf, len, "%s-%s", found ? "command line: " : "", name));
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

PetscErrorCode BwSceneListOptions(BwScene scene, const char prefix[], PetscInt *n, char ***names)
{
  PetscInt count = 0;

  PetscFunctionBeginUser;
  (void)scene; /* the options database is global */
  PetscCall(BwOptionsAll(n, names));
  for (PetscInt i = 0; i < *n; i++) {
    if (BwHasPrefix((*names)[i], prefix)) (*names)[count++] = (*names)[i];
    else PetscCall(PetscFree((*names)[i]));
  }
  (*names)[count] = NULL;
  *n              = count;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneCheckUnused(BwScene scene, PetscInt nexempt, const char *const exempt[])
{
  PetscInt  n, first = -1, leaf = -1;
  char    **names, **values, msg[BW_MSG_LEN] = "";

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsLeftGet(NULL, &n, &names, &values));
  for (PetscInt i = 0; i < n; i++) {
    PetscBool skip = PETSC_FALSE;
    PetscInt  node;

    for (PetscInt j = 0; j < nexempt && !skip; j++) skip = BwHasPrefix(names[i], exempt[j]);
    for (size_t j = 0; j < PETSC_STATIC_ARRAY_LENGTH(BwScenePetscOptions) && !skip; j++) skip = BwInWord(names[i], BwScenePetscOptions[j]);
    if (skip) continue;
    /* Report the earliest file key, else the first command-line option. */
    node = BwSceneFindLeaf(scene, names[i]);
    if (node >= 0 && (leaf < 0 || node < leaf)) leaf = node;
    if (node < 0 && first < 0) first = i;
  }
  if (leaf >= 0) PetscCall(PetscSNPrintf(msg, sizeof(msg), "%s:%d: unknown key '%s' (nothing uses it)", scene->path, scene->nodes[leaf].line, scene->nodes[leaf].dotted));
  else if (first >= 0) PetscCall(PetscSNPrintf(msg, sizeof(msg), "unknown option -%s (nothing uses it)", names[first]));
  PetscCall(PetscOptionsLeftRestore(NULL, &n, &names, &values));
  PetscCheck(!msg[0], scene->comm, PETSC_ERR_USER_INPUT, "%s", msg);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A command-line option of a blockwall section that the file lacks, and
 * that can be written as a top-level key without clashing with the file's
 * (an option "-joints" beside the file's mapping "joints" cannot). */
static PetscBool BwSceneIsExtra(BwScene scene, const char name[])
{
  PetscBool section = PETSC_FALSE;

  for (size_t j = 0; j < PETSC_STATIC_ARRAY_LENGTH(BwSceneSections) && !section; j++) section = BwInWord(name, BwSceneSections[j]);
  if (!section || BwSceneFindLeaf(scene, name) >= 0) return PETSC_FALSE;
  for (PetscInt i = 0; i < scene->nnodes; i++)
    if (scene->nodes[i].depth == 0 && BwSameName(scene->nodes[i].key, name)) return PETSC_FALSE;
  return PETSC_TRUE;
}

PetscErrorCode BwSceneGetText(BwScene scene, char **text)
{
  BwText   t = {NULL, 0, 0};
  PetscInt n;
  char   **names;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < scene->nnodes; i++) {
    const BwSceneNode *node = &scene->nodes[i];
    PetscBool          found;
    char              *value;

    for (int d = 0; d < node->depth; d++) PetscCall(BwTextPuts(&t, "  "));
    PetscCall(BwTextPuts(&t, node->key));
    PetscCall(BwTextPuts(&t, ":"));
    if (node->kind == BW_NODE_MAPPING) {
      PetscBool empty = (PetscBool)(i + 1 == scene->nnodes || scene->nodes[i + 1].depth <= node->depth);

      PetscCall(BwTextPuts(&t, empty ? " {}\n" : "\n"));
      continue;
    }
    PetscCall(BwOptionPeek(node->name, &found, &value));
    if (!found) PetscCall(PetscStrallocpy(node->value, &value));
    PetscCall(BwTextPuts(&t, " "));
    if (node->kind == BW_NODE_SEQUENCE) PetscCall(BwTextPutSequence(&t, value));
    else PetscCall(BwTextPutScalar(&t, value ? value : "", value ? strlen(value) : 0));
    PetscCall(BwTextPuts(&t, "\n"));
    PetscCall(PetscFree(value));
  }

  PetscCall(BwOptionsAll(&n, &names));
  for (PetscInt i = 0, extra = 0; i < n; i++) {
    PetscBool found;
    char     *value;

    if (!BwSceneIsExtra(scene, names[i])) continue;
    if (!extra++) PetscCall(BwTextPuts(&t, "# set on the command line\n"));
    PetscCall(BwOptionPeek(names[i], &found, &value));
    PetscCall(BwTextPuts(&t, names[i]));
    PetscCall(BwTextPuts(&t, ": "));
    if (BwIsPlainList(value)) PetscCall(BwTextPutSequence(&t, value));
    else PetscCall(BwTextPutScalar(&t, value ? value : "", value ? strlen(value) : 0));
    PetscCall(BwTextPuts(&t, "\n"));
    PetscCall(PetscFree(value));
  }
  PetscCall(PetscStrArrayDestroy(&names));
  /* An empty text would not load back: the file must hold a mapping. */
  if (!t.len) PetscCall(BwTextPuts(&t, "{}\n"));
  *text = t.s;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneDestroy(BwScene *scene)
{
  PetscFunctionBeginUser;
  if (!*scene) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt i = 0; i < (*scene)->nnodes; i++) {
    BwSceneNode *node = &(*scene)->nodes[i];

    PetscCall(PetscFree(node->key));
    PetscCall(PetscFree(node->dotted));
    PetscCall(PetscFree(node->name));
    PetscCall(PetscFree(node->value));
  }
  PetscCall(PetscFree((*scene)->nodes));
  PetscCall(PetscFree((*scene)->path));
  PetscCall(PetscFree((*scene)->dir));
  PetscCall(PetscFree(*scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}
