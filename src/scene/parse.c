/* BwScene, part 1: reading the scene file (YAML) and the command line.
 *
 * PETSc 3.18 cannot read YAML sequences, and its own YAML reader forgets
 * where each key came from, so the file is parsed here with libyaml's event
 * API into a list of nodes (one per key, in document order, with its line
 * and its option name), found by name through a hash map: parsing and every
 * look-up stay linear in the number of keys (a nested scan for duplicates
 * made 3e4 keys take 31 s). Only when the whole file parses are the keys
 * outside blockwall's sections inserted into PETSc's database, so a broken
 * file leaves it untouched. The command line is recorded at load: which
 * options were given, with which value, so that the file can be overridden
 * and errors can say where a value came from. */
#include "scene/scene_impl.h"
#include "util/compat.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

/* Deeper nesting than this is a mistake in the file, not a scene. */
#define BW_MAX_DEPTH 32

/* ---------------------------------------------------------------- text -- */

PetscErrorCode BwTextPut(BwText *t, const char s[], size_t n)
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

PetscErrorCode BwTextPuts(BwText *t, const char s[])
{
  PetscFunctionBeginUser;
  PetscCall(BwTextPut(t, s, strlen(s)));
  PetscFunctionReturn(PETSC_SUCCESS);
}


/* --------------------------------------------------------------- nodes -- */

/* Blockwall's sections: keys under them are read by the typed getters. */
static const char *const BwSceneSections[] = {"title", "geometry", "joints", "discretization", "supports", "loads", "gravity", "solver", "output", "cases", "analysis", "sets", "progress"};

PetscBool BwHasPrefix(const char name[], const char prefix[])
{
  for (; *prefix; name++, prefix++)
    if (!*name || tolower((unsigned char)*name) != tolower((unsigned char)*prefix)) return PETSC_FALSE;
  return PETSC_TRUE;
}

PetscBool BwInWord(const char name[], const char word[])
{
  size_t n = strlen(word);

  return (PetscBool)(BwHasPrefix(name, word) && (name[n] == 0 || name[n] == '_'));
}

PetscBool BwSceneOwns(const char name[])
{
  for (size_t j = 0; j < PETSC_STATIC_ARRAY_LENGTH(BwSceneSections); j++)
    if (BwInWord(name, BwSceneSections[j])) return PETSC_TRUE;
  return PETSC_FALSE;
}

PetscInt BwSceneFindNode(BwScene scene, const char name[])
{
  if (name[0] == '-') name++;
  return BwNameMapGet(&scene->nodemap, name);
}

/* A new node under `parent` (-1: top); *clash is the node that already
 * has the same option name, or -1. */
static PetscErrorCode BwSceneAddNode(BwScene scene, BwNodeKind kind, PetscInt parent, const char key[], int line, PetscInt *index, PetscInt *clash)
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
  *index       = scene->nnodes++;
  node         = &scene->nodes[*index];
  node->kind   = kind;
  node->line   = line;
  node->parent = parent;
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
  node->own = BwSceneOwns(node->name);
  PetscCall(BwNameMapAdd(&scene->nodemap, node->name, *index, clash));
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
    PetscInt      node = -1, clash;
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
    PetscCall(BwParserNext(p));
    PetscCall(BwParserNoAnchor(p));
    kind = e->type == YAML_MAPPING_START_EVENT ? BW_NODE_MAPPING : e->type == YAML_SEQUENCE_START_EVENT ? BW_NODE_SEQUENCE : BW_NODE_SCALAR;
    PetscCall(BwSceneAddNode(scene, kind, parent, key, (int)line, &node, &clash));
    if (strlen(scene->nodes[node].name) + 2 > PETSC_MAX_OPTION_NAME) PetscCall(BwParserError(p, line, "key '%s' makes an option name longer than PETSc's %d characters", scene->nodes[node].dotted, PETSC_MAX_OPTION_NAME - 2));
    /* one look-up finds both a repeated key and another spelling of the same
     * option (joints: {E: ..} beside joints_E: ..), in constant time */
    if (clash >= 0) {
      const BwSceneNode *other = &scene->nodes[clash], *self = &scene->nodes[node];
      if (other->parent == parent) PetscCall(BwParserError(p, line, "duplicate key '%s' (first at line %d)", other->dotted, other->line));
      if (self->kind != BW_NODE_MAPPING || other->kind != BW_NODE_MAPPING)
        PetscCall(BwParserError(p, line, "key '%s' sets the same option -%s as key '%s' at line %d", self->dotted, self->name, other->dotted, other->line));
    }
    if (e->type == YAML_MAPPING_START_EVENT) {
      PetscCall(BwParseMapping(p, node, depth + 1));
    } else if (e->type == YAML_SEQUENCE_START_EVENT) {
      PetscInt count = 0;

      p->seq.len = 0;
      PetscCall(BwParseSequence(p, scene->nodes[node].dotted, depth + 1, &p->seq, &count));
      if (p->seq.len) PetscCall(PetscStrallocpy(p->seq.s, &scene->nodes[node].value));
      scene->nodes[node].count = count;
    } else {
      if (BwIsNull(e)) PetscCall(BwParserError(p, line, "key '%s' has no value (write \"\" for an option without one)", scene->nodes[node].dotted));
      PetscCall(PetscStrallocpy((const char *)e->data.scalar.value, &scene->nodes[node].value));
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
  PetscCall(BwNameMapInit(&(*scene)->nodemap));
  PetscCall(BwNameMapInit(&(*scene)->argmap));
  PetscCall(BwNameMapInit(&(*scene)->askedmap));
  PetscCall(PetscOptionsHasHelp(NULL, &(*scene)->help));
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

/* The options of the command line (and PETSC_OPTIONS) not yet used, i.e.
 * all but those PetscInitialize and main() read before the scene. */
static PetscErrorCode BwSceneRecordArguments(BwScene scene)
{
  PetscInt n;
  char   **names, **values;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsLeftGet(NULL, &n, &names, &values));
  PetscCall(PetscCalloc1(n + 1, &scene->args));
  for (PetscInt i = 0; i < n; i++) {
    BwSceneArg *a = &scene->args[scene->nargs];
    PetscCall(PetscStrallocpy(names[i], &a->name));
    if (values[i]) PetscCall(PetscStrallocpy(values[i], &a->value));
    a->own = BwSceneOwns(a->name);
    PetscCall(BwNameMapAdd(&scene->argmap, a->name, scene->nargs, NULL));
    scene->nargs++;
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &n, &names, &values));
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
  PetscCheck(!scene->path && !scene->nargs, scene->comm, PETSC_ERR_ORDER, "BwSceneLoad: the scene is already loaded");
  PetscCall(BwSceneRecordArguments(scene));
  if (!path) PetscFunctionReturn(PETSC_SUCCESS);
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

  /* Keys outside blockwall's sections are PETSc's: inserted as options,
   * unless the command line gives them (it wins). PETSc 3.18's database
   * holds at most 512 options; its error would read "out of memory". */
  for (PetscInt i = 0; i < scene->nnodes; i++) {
    BwSceneNode   *node = &scene->nodes[i];
    char           option[PETSC_MAX_OPTION_NAME];
    PetscErrorCode ierr;

    if (node->kind == BW_NODE_MAPPING || node->own || BwNameMapGet(&scene->argmap, node->name) >= 0) continue;
    PetscCall(PetscSNPrintf(option, sizeof(option), "-%s", node->name));
    PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
    ierr = PetscOptionsSetValue(NULL, option, node->value);
    PetscCall(PetscPopErrorHandler());
    PetscCheck(ierr != PETSC_ERR_MEM, scene->comm, PETSC_ERR_USER_INPUT, "%s:%d: key '%s' is not one of blockwall's, so it goes to PETSc's options database, which is full: PETSc 3.18 holds at most 512 options (command line included; blockwall's own keys do not count)", scene->path, node->line, node->dotted);
    PetscCall(ierr);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneGetDirectory(BwScene scene, const char *dir[])
{
  PetscFunctionBeginUser;
  *dir = scene->dir;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSceneDestroy(BwScene *scene)
{
  BwScene s = *scene;

  PetscFunctionBeginUser;
  if (!s) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt i = 0; i < s->nnodes; i++) {
    BwSceneNode *node = &s->nodes[i];

    PetscCall(PetscFree(node->key));
    PetscCall(PetscFree(node->dotted));
    PetscCall(PetscFree(node->name));
    PetscCall(PetscFree(node->value));
  }
  for (PetscInt i = 0; i < s->nargs; i++) {
    PetscCall(PetscFree(s->args[i].name));
    PetscCall(PetscFree(s->args[i].value));
  }
  for (PetscInt i = 0; i < s->nasked; i++) PetscCall(PetscFree(s->asked[i]));
  PetscCall(PetscFree(s->asked));
  PetscCall(PetscFree(s->args));
  PetscCall(PetscFree(s->nodes));
  PetscCall(BwNameMapDestroy(&s->nodemap));
  PetscCall(BwNameMapDestroy(&s->argmap));
  PetscCall(BwNameMapDestroy(&s->askedmap));
  PetscCall(PetscFree(s->path));
  PetscCall(PetscFree(s->dir));
  PetscCall(PetscFree(*scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* PETSc's rule for what on a command line is an option name rather than a
 * value: '-' (or '--') and a letter, except -inf and -nan. */
static PetscBool BwIsOptionName(const char s[])
{
  if (s[0] != '-') return PETSC_FALSE;
  if (s[1] == '-') s++;
  if (!isalpha((unsigned char)s[1])) return PETSC_FALSE;
  return (PetscBool)!(BwHasPrefix(s + 1, "inf") || BwHasPrefix(s + 1, "nan"));
}

PetscErrorCode BwSceneCheckArguments(MPI_Comm comm, int argc, char **argv)
{
  BwNameMap seen;
  PetscInt  first;

  PetscFunctionBeginUser;
  PetscCall(BwNameMapInit(&seen));
  for (int i = 1; i < argc; i++) {
    const char *name = argv[i];
    if (!BwIsOptionName(name)) continue;
    name += name[1] == '-' ? 2 : 1;
    PetscCall(BwNameMapAdd(&seen, name, i, &first));
    if (first >= 0) {
      PetscCall(BwNameMapDestroy(&seen));
      SETERRQ(comm, PETSC_ERR_USER_INPUT, "command line: %s is given twice (arguments %" PetscInt_FMT " and %d); give it once", argv[i], first, i);
    }
    if (BwSameName(name, "scene") && (i + 1 == argc || BwIsOptionName(argv[i + 1]))) {
      PetscCall(BwNameMapDestroy(&seen));
      SETERRQ(comm, PETSC_ERR_USER_INPUT, "command line: -scene needs a value (the scene file)");
    }
  }
  PetscCall(BwNameMapDestroy(&seen));
  PetscFunctionReturn(PETSC_SUCCESS);
}
