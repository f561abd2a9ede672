/* The inside of BwScene, shared by the files of src/scene (parse.c, values.c,
 * check.c, emit.c); nothing else includes it. */
#pragma once
#include "scene/scene.h"
#include "util/namemap.h"

/* PETSc keeps at most this much of an error message (PetscErrorBaseMessage). */
#define BW_MSG_LEN 1024

typedef enum {
  BW_NODE_MAPPING,
  BW_NODE_SCALAR,
  BW_NODE_SEQUENCE
} BwNodeKind;

typedef struct {
  BwNodeKind kind;
  int        depth;    /* 0 for top-level keys */
  int        line;     /* 1-based line of the key */
  PetscInt   parent;   /* node index, -1 at the top */
  PetscInt   count;    /* sequences: number of elements */
  char      *key;      /* as written: "E" */
  char      *dotted;   /* "joints.E", for messages */
  char      *name;     /* option name without '-': "joints_E" */
  char      *value;    /* leaves: the file's text, sequences comma-joined; NULL if empty */
  PetscBool  own;      /* in one of blockwall's sections: read through BwScene, never through PETSc's database */
  PetscBool  used;     /* read by a BwScene getter (own keys) */
} BwSceneNode;

/* An option given on the command line (or PETSC_OPTIONS), as found in
 * PETSc's database when the scene was loaded. */
typedef struct {
  char     *name;  /* without '-' */
  char     *value; /* NULL: given without a value */
  PetscBool own;   /* in one of blockwall's sections */
} BwSceneArg;

struct _p_BwScene {
  MPI_Comm     comm;
  char        *path; /* as given, for messages; NULL without a file */
  char        *dir;
  PetscBool    help; /* -help: the getters print what they read */
  PetscInt     nnodes, maxnodes;
  BwSceneNode *nodes;
  BwNameMap    nodemap; /* node name -> node */
  PetscInt     nargs;
  BwSceneArg  *args;
  BwNameMap    argmap; /* command-line option name -> arg */
  /* names every getter asked for, set or not: the vocabulary that unknown
   * keys are compared with to suggest what was meant */
  PetscInt     nasked, maxasked;
  char       **asked;
  BwNameMap    askedmap;
};

/* Is `name` (without '-') in one of blockwall's sections? */
PetscBool BwSceneOwns(const char name[]);
/* `name` is `word` or continues it after '_' (case-insensitive). */
PetscBool BwInWord(const char name[], const char word[]);
PetscBool BwHasPrefix(const char name[], const char prefix[]);
PetscInt  BwSceneFindNode(BwScene scene, const char name[]);

/* A growing text buffer (parse.c): sequences joined with ',' and the scene
 * text re-emitted. */
typedef struct {
  char  *s;
  size_t len, cap;
} BwText;
PetscErrorCode BwTextPut(BwText *t, const char s[], size_t n);
PetscErrorCode BwTextPuts(BwText *t, const char s[]);
