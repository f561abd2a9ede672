/* BwScene, part 4: the scene as run, re-emitted as YAML.
 *
 * The file's keys in their nesting with the values in effect (the command
 * line's where it overrides), then the command-line options of blockwall's
 * sections that the file did not have, as flattened top-level keys. Values
 * are written so that they load back to the same text: numbers and
 * booleans plain, everything else quoted. */
#include <stdlib.h>
#include <string.h>
#include "scene/scene_impl.h"
#include "util/compat.h"

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


/* A command-line option of a blockwall section that the file lacks, and
 * that can be written as a top-level key without clashing with the file's
 * (an option "-joints" beside the file's mapping "joints" cannot). */
static PetscBool BwSceneIsExtra(BwScene scene, const BwSceneArg *arg)
{
  PetscInt node = BwSceneFindNode(scene, arg->name);

  if (!arg->own || (node >= 0 && scene->nodes[node].kind != BW_NODE_MAPPING)) return PETSC_FALSE;
  for (PetscInt i = 0; i < scene->nnodes; i++)
    if (scene->nodes[i].depth == 0 && BwSameName(scene->nodes[i].key, arg->name)) return PETSC_FALSE;
  return PETSC_TRUE;
}

static int BwCompareArgs(const void *a, const void *b)
{
  return strcmp((*(const BwSceneArg *const *)a)->name, (*(const BwSceneArg *const *)b)->name);
}

PetscErrorCode BwSceneGetText(BwScene scene, char **text)
{
  BwText             t = {NULL, 0, 0};
  const BwSceneArg **extra;
  PetscInt           nextra = 0;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < scene->nnodes; i++) {
    const BwSceneNode *node = &scene->nodes[i];
    PetscInt           arg  = BwNameMapGet(&scene->argmap, node->name);
    const char        *value;

    for (int d = 0; d < node->depth; d++) PetscCall(BwTextPuts(&t, "  "));
    PetscCall(BwTextPuts(&t, node->key));
    PetscCall(BwTextPuts(&t, ":"));
    if (node->kind == BW_NODE_MAPPING) {
      PetscBool empty = (PetscBool)(i + 1 == scene->nnodes || scene->nodes[i + 1].depth <= node->depth);

      PetscCall(BwTextPuts(&t, empty ? " {}\n" : "\n"));
      continue;
    }
    value = arg >= 0 ? scene->args[arg].value : node->value;
    PetscCall(BwTextPuts(&t, " "));
    if (node->kind == BW_NODE_SEQUENCE) PetscCall(BwTextPutSequence(&t, value));
    else PetscCall(BwTextPutScalar(&t, value ? value : "", value ? strlen(value) : 0));
    PetscCall(BwTextPuts(&t, "\n"));
  }

  PetscCall(PetscMalloc1(scene->nargs + 1, &extra));
  for (PetscInt i = 0; i < scene->nargs; i++)
    if (BwSceneIsExtra(scene, &scene->args[i])) extra[nextra++] = &scene->args[i];
  qsort(extra, (size_t)nextra, sizeof(*extra), BwCompareArgs);
  for (PetscInt i = 0; i < nextra; i++) {
    const char *value = extra[i]->value;
    if (!i) PetscCall(BwTextPuts(&t, "# set on the command line\n"));
    PetscCall(BwTextPuts(&t, extra[i]->name));
    PetscCall(BwTextPuts(&t, ": "));
    if (BwIsPlainList(value)) PetscCall(BwTextPutSequence(&t, value));
    else PetscCall(BwTextPutScalar(&t, value ? value : "", value ? strlen(value) : 0));
    PetscCall(BwTextPuts(&t, "\n"));
  }
  PetscCall(PetscFree(extra));
  /* An empty text would not load back: the file must hold a mapping. */
  if (!t.len) PetscCall(BwTextPuts(&t, "{}\n"));
  *text = t.s;
  PetscFunctionReturn(PETSC_SUCCESS);
}
