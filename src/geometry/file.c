/* geometry.generator: file -- blocks, interfaces and sets from an HDF5 file
 * (interface.md, "HDF5 geometry input"):
 *
 *   /blocks/vertices   float (V, 2)   polygons, either orientation
 *   /blocks/offsets    int   (B+1)    block b: vertex rows offsets[b]..offsets[b+1]-1
 *   /interfaces/blocks int   (I, 2)   optional pairs (i, j), i < j
 *   /interfaces/kn, kt float (I)      optional, need /interfaces/blocks
 *   /sets/NAME         int   (k)      optional block sets
 *   root attribute depth              optional, overrides geometry.depth
 *
 * geometry.file is relative to the scene file's directory when the scene
 * file gives it, and to the working directory when the command line does
 * (as any path typed in a shell).
 *
 * Interfaces: with /interfaces/blocks, row k is interface k and its G,
 * theta and l come from the facing edges of its two blocks (detect.c, the
 * same rule as detection); a pair whose blocks face each other along s
 * separate segments must be listed s times, its rows taking the segments in
 * detection order. A pair (i, j) with i > j is an error, not swapped: the
 * normal n points from i into j, and a silent swap would flip the signs of
 * that interface's results. Without /interfaces/blocks every facing pair is
 * found (detect.c). Derived datasets of an output file (/interfaces/center,
 * angle, length, /blocks/centroid, results) are ignored and recomputed, so
 * an output file read back gives the same results whether or not they are
 * there. All interfaces are bed joints (joints.*); kn, kt override them.
 *
 * Rank 0 reads, checks and builds the geometry, the other ranks' shares
 * are empty (BwGeometryShareFromRankZero); an error on rank 0 is broadcast
 * as its one-line message and raised on every rank, so all ranks fail
 * together with the same line. */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <hdf5.h>
#include "geometry/validate.h"
#include "util/compat.h"

#define BW_MSG_LEN 1024

typedef struct {
  char       path[PETSC_MAX_PATH_LEN];     /* as opened; named in every message */
  char       where[PETSC_MAX_PATH_LEN + 64]; /* where geometry.file was set */
  hid_t      file;
  PetscInt   nv, nb, ni;
  PetscReal *xy, *kn, *kt;
  int64_t   *offsets, *pairs;
  PetscBool  has_pairs, has_depth;
  PetscInt   dim; /* 2 | 3: the columns of /blocks/vertices */
  PetscReal  depth;
  PetscInt   nsets, *setlen;
  char     **setname;
  int64_t  **setdata;
} BwFileData;

static PetscErrorCode BwFileDataDestroy(BwFileData *d)
{
  PetscFunctionBeginUser;
  if (d->file > 0) H5Fclose(d->file);
  d->file = -1;
  PetscCall(PetscFree(d->xy));
  PetscCall(PetscFree(d->kn));
  PetscCall(PetscFree(d->kt));
  PetscCall(PetscFree(d->offsets));
  PetscCall(PetscFree(d->pairs));
  for (PetscInt s = 0; s < d->nsets; s++) {
    PetscCall(PetscFree(d->setname[s]));
    PetscCall(PetscFree(d->setdata[s]));
  }
  PetscCall(PetscFree(d->setname));
  PetscCall(PetscFree(d->setdata));
  PetscCall(PetscFree(d->setlen));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ HDF5 */

/* Does `path` exist, with every group on the way? */
static PetscErrorCode BwH5Exists(BwFileData *d, const char path[], PetscBool *exists)
{
  char buf[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  *exists = PETSC_FALSE;
  PetscCall(PetscStrncpy(buf, path, sizeof(buf)));
  for (char *p = buf + 1;; p++) {
    if (*p && *p != '/') continue;
    {
      char   c = *p;
      htri_t e;
      *p = 0;
      e  = H5Lexists(d->file, buf, H5P_DEFAULT);
      *p = c;
      if (e <= 0) PetscFunctionReturn(PETSC_SUCCESS);
    }
    if (!*p) break;
  }
  *exists = PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static const char *BwH5ClassName(H5T_class_t c) { return c == H5T_INTEGER ? "integer" : c == H5T_FLOAT ? "floating-point" : c == H5T_STRING ? "string" : "non-numeric"; }

/* Opens dataset `path`, checks its class and shape: rank 1, or rank 2 with
 * `width` columns. */
static PetscErrorCode BwH5Open(BwFileData *d, const char path[], H5T_class_t cls, int rank, hsize_t width, const char expected[], hid_t *dset, hsize_t *rows)
{
  hid_t       obj, type, space;
  H5T_class_t c;
  int         r;
  hsize_t     dims[H5S_MAX_RANK];
  char        shape[128] = "";

  PetscFunctionBeginUser;
  obj = H5Oopen(d->file, path, H5P_DEFAULT);
  PetscCheck(obj >= 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: %s cannot be opened", d->path, path);
  if (H5Iget_type(obj) != H5I_DATASET) {
    H5Oclose(obj);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: %s is not a dataset; expected %s", d->path, path, expected);
  }
  type = H5Dget_type(obj);
  c    = H5Tget_class(type);
  H5Tclose(type);
  space = H5Dget_space(obj);
  r     = H5Sget_simple_extent_ndims(space);
  if (r >= 0 && r <= H5S_MAX_RANK) H5Sget_simple_extent_dims(space, dims, NULL);
  H5Sclose(space);
  if (c != cls) {
    H5Dclose(obj);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: %s holds %s values; expected %s", d->path, path, BwH5ClassName(c), expected);
  }
  for (int k = 0; k < r; k++) {
    char item[32];
    PetscCall(PetscSNPrintf(item, sizeof(item), "%s%llu", k ? ", " : "", (unsigned long long)dims[k]));
    PetscCall(PetscStrlcat(shape, item, sizeof(shape)));
  }
  if (r != rank || (rank == 2 && dims[1] != width)) {
    H5Dclose(obj);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: %s has shape (%s%s); expected %s", d->path, path, shape, r == 1 ? "," : "", expected);
  }
  PetscCheck(dims[0] < (hsize_t)PETSC_MAX_INT / 4, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: %s has %llu rows, more than this build's PetscInt can index", d->path, path, (unsigned long long)dims[0]);
  *rows = dims[0];
  *dset = obj;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwH5Read(BwFileData *d, const char path[], hid_t dset, hid_t memtype, hsize_t count, void *buf)
{
  herr_t err = 0;

  PetscFunctionBeginUser;
  if (count) err = H5Dread(dset, memtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
  H5Dclose(dset);
  PetscCheck(err >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_READ, "%s: %s cannot be read", d->path, path);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The names of /sets' members in one pass: reading them by index costs a
 * walk of the group each, quadratic in the number of sets (3e4 sets took
 * seconds). */
typedef struct {
  char  **name;
  size_t  n, cap;
  int     err;
} BwLinkNames;

static herr_t BwLinkName(hid_t grp, const char *name, const H5L_info_t *info, void *ctx)
{
  BwLinkNames *l = (BwLinkNames *)ctx;

  (void)grp;
  (void)info;
  if (l->n == l->cap) {
    size_t cap  = l->cap ? 2 * l->cap : 64;
    char **more = (char **)realloc(l->name, cap * sizeof(char *));
    if (!more) return (l->err = 1, -1);
    l->name = more;
    l->cap  = cap;
  }
  if (!(l->name[l->n] = (char *)malloc(strlen(name) + 1))) return (l->err = 1, -1);
  memcpy(l->name[l->n], name, strlen(name) + 1);
  l->n++;
  return 0;
}

static PetscErrorCode BwFileReadSet(BwFileData *d, const char name[]);

static PetscErrorCode BwFileReadSets(BwFileData *d)
{
  PetscBool  exists;
  hid_t      grp;
  H5G_info_t info;

  PetscFunctionBeginUser;
  PetscCall(BwH5Exists(d, "/sets", &exists));
  if (!exists) PetscFunctionReturn(PETSC_SUCCESS);
  grp = H5Oopen(d->file, "/sets", H5P_DEFAULT);
  PetscCheck(grp >= 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /sets cannot be opened", d->path);
  if (H5Iget_type(grp) != H5I_GROUP) {
    H5Oclose(grp);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /sets is not a group; expected one int64 dataset per block set", d->path);
  }
  H5Gget_info(grp, &info);
  PetscCall(PetscCalloc1(info.nlinks + 1, &d->setname));
  PetscCall(PetscCalloc1(info.nlinks + 1, &d->setdata));
  PetscCall(PetscCalloc1(info.nlinks + 1, &d->setlen));
  {
    BwLinkNames l   = {NULL, 0, 0, 0};
    hsize_t     idx = 0;
    herr_t      err = H5Literate(grp, H5_INDEX_NAME, H5_ITER_INC, &idx, BwLinkName, &l);
    PetscErrorCode ierr = PETSC_SUCCESS;
    if (err < 0 || l.n != info.nlinks) {
      for (size_t k = 0; k < l.n; k++) free(l.name[k]);
      free(l.name);
      H5Gclose(grp);
      SETERRQ(PETSC_COMM_SELF, l.err ? PETSC_ERR_MEM : PETSC_ERR_USER_INPUT, "%s: /sets: the names of its members cannot be read", d->path);
    }
    for (size_t k = 0; k < l.n && !ierr; k++) ierr = BwFileReadSet(d, l.name[k]);
    for (size_t k = 0; k < l.n; k++) free(l.name[k]);
    free(l.name);
    H5Gclose(grp);
    PetscCall(ierr);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* One set, /sets/NAME. */
static PetscErrorCode BwFileReadSet(BwFileData *d, const char name[])
{
  PetscFunctionBeginUser;
  {
    char    path[300];
    hid_t   dset;
    hsize_t n;

    PetscCheck(strlen(name) < 256, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /sets: the name of set '%.40s...' is longer than 255 characters", d->path, name);
    /* a set name becomes part of option names (-loads_NAME, -supports_NAME_u1) */
    for (const char *c = name; *c; c++)
      PetscCheck((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') || *c == '_', PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /sets/%s: set names may hold only letters, digits and '_' (they become scene keys loads.NAME, supports.NAME)", d->path, name);
    PetscCall(PetscSNPrintf(path, sizeof(path), "/sets/%s", name));
    PetscCall(PetscStrallocpy(name, &d->setname[d->nsets]));
    d->nsets++;
    PetscCall(BwH5Open(d, path, H5T_INTEGER, 1, 0, "int64 (k): the blocks of the set", &dset, &n));
    d->setlen[d->nsets - 1] = (PetscInt)n;
    PetscCall(PetscMalloc1(n + 1, &d->setdata[d->nsets - 1]));
    PetscCall(BwH5Read(d, path, dset, H5T_NATIVE_INT64, n, d->setdata[d->nsets - 1]));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* For a geometry file that does not exist: what writes it, when a script
 * or a drawing of the same name lies beside it (the gallery's arch.py,
 * stones.py, facade.dxf), so the one error line tells a user on a fresh
 * clone what to run. */
static void BwFileWriterHint(const char path[], char hint[], size_t len)
{
  char   base[PETSC_MAX_PATH_LEN];
  size_t n = strlen(path);

  hint[0] = 0;
  if (n < 4 || n >= sizeof(base) || strcmp(path + n - 3, ".h5")) return;
  snprintf(base, sizeof(base), "%.*s.py", (int)(n - 3), path);
  if (access(base, R_OK) == 0) {
    snprintf(hint, len, "; the script beside it writes it: python3 %s", base);
    return;
  }
  snprintf(base, sizeof(base), "%.*s.dxf", (int)(n - 3), path);
  if (access(base, R_OK) == 0) snprintf(hint, len, "; it is imported from the drawing beside it: tools/import_dxf %s %s (with the options the scene's comments give)", base, path);
}

/* Every dataset read, its shape and type checked. */
static PetscErrorCode BwFileRead(BwFileData *d)
{
  hid_t     fapl, dset;
  hsize_t   rows, nb1;
  PetscBool exists, has_kn, has_kt;
  htri_t    is;

  PetscFunctionBeginUser;
  if (access(d->path, R_OK) != 0) {
    int  err = errno;
    char hint[2 * PETSC_MAX_PATH_LEN + 128];
    BwFileWriterHint(d->path, hint, sizeof(hint));
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: cannot read '%s': %s%s", d->where, d->path, strerror(err), err == ENOENT ? hint : "");
  }
  is = H5Fis_hdf5(d->path);
  PetscCheck(is > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: '%s' is not an HDF5 file", d->where, d->path);
  fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_fclose_degree(fapl, H5F_CLOSE_STRONG); /* closing the file closes what an error left open */
  d->file = H5Fopen(d->path, H5F_ACC_RDONLY, fapl);
  H5Pclose(fapl);
  PetscCheck(d->file >= 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: '%s' cannot be opened as an HDF5 file", d->where, d->path);

  PetscCall(BwH5Exists(d, "/blocks/vertices", &exists));
  PetscCheck(exists, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: no dataset /blocks/vertices; a geometry file needs /blocks/vertices (V, 2) and /blocks/offsets (B+1)", d->path);
  PetscCall(BwH5Exists(d, "/blocks/offsets", &exists));
  PetscCheck(exists, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: no dataset /blocks/offsets; a geometry file needs /blocks/vertices (V, 2) and /blocks/offsets (B+1)", d->path);
  /* the file decides its dimension by the columns of /blocks/vertices */
  d->dim = 2;
  {
    hid_t o = H5Dopen2(d->file, "/blocks/vertices", H5P_DEFAULT);
    if (o >= 0) {
      hid_t   sp = H5Dget_space(o);
      hsize_t dims[H5S_MAX_RANK];
      if (H5Sget_simple_extent_ndims(sp) == 2 && H5Sget_simple_extent_dims(sp, dims, NULL) == 2 && dims[1] == 3) d->dim = 3;
      H5Sclose(sp);
      H5Dclose(o);
    }
  }
  PetscCall(BwH5Open(d, "/blocks/vertices", H5T_FLOAT, 2, (hsize_t)d->dim, d->dim == 3 ? "float64 (V, 3): x1, x2, x3 of every vertex" : "float64 (V, 2): x, y of every vertex (or (V, 3): 3D blocks)", &dset, &rows));
  d->nv = (PetscInt)rows;
  PetscCall(PetscMalloc1(d->dim * d->nv + 1, &d->xy));
  PetscCall(BwH5Read(d, "/blocks/vertices", dset, H5T_NATIVE_DOUBLE, rows, d->xy));
  PetscCall(BwH5Open(d, "/blocks/offsets", H5T_INTEGER, 1, 0, "int64 (B+1): block b has vertex rows offsets[b]..offsets[b+1]-1", &dset, &nb1));
  PetscCheck(nb1 >= 2, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /blocks/offsets has %llu entries; it needs B+1 >= 2 (at least one block)", d->path, (unsigned long long)nb1);
  d->nb = (PetscInt)nb1 - 1;
  PetscCall(PetscMalloc1(nb1, &d->offsets));
  PetscCall(BwH5Read(d, "/blocks/offsets", dset, H5T_NATIVE_INT64, nb1, d->offsets));
  PetscCheck(d->offsets[0] == 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /blocks/offsets[0] = %lld; it must be 0 (block 0 starts at vertex row 0)", d->path, (long long)d->offsets[0]);
  for (PetscInt b = 0; b < d->nb; b++)
    PetscCheck(d->offsets[b + 1] >= d->offsets[b], PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /blocks/offsets is not increasing: offsets[%" PetscInt_FMT "] = %lld < offsets[%" PetscInt_FMT "] = %lld (block %" PetscInt_FMT ")", d->path, b + 1, (long long)d->offsets[b + 1], b, (long long)d->offsets[b], b);
  PetscCheck(d->offsets[d->nb] == d->nv, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /blocks/offsets[%" PetscInt_FMT "] = %lld (the last) must equal the number of rows of /blocks/vertices, %" PetscInt_FMT, d->path, d->nb, (long long)d->offsets[d->nb], d->nv);

  PetscCall(BwH5Exists(d, "/interfaces/blocks", &d->has_pairs));
  PetscCall(BwH5Exists(d, "/interfaces/kn", &has_kn));
  PetscCall(BwH5Exists(d, "/interfaces/kt", &has_kt));
  if (d->has_pairs) {
    PetscCall(BwH5Open(d, "/interfaces/blocks", H5T_INTEGER, 2, 2, "int64 (I, 2): pairs (i, j), i < j", &dset, &rows));
    d->ni = (PetscInt)rows;
    PetscCall(PetscMalloc1(2 * d->ni + 1, &d->pairs));
    PetscCall(BwH5Read(d, "/interfaces/blocks", dset, H5T_NATIVE_INT64, rows, d->pairs));
  } else
    PetscCheck(!has_kn && !has_kt, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: %s is given without /interfaces/blocks; per-interface stiffness needs the interface list (detected interfaces take joints.*)", d->path, has_kn ? "/interfaces/kn" : "/interfaces/kt");
  for (int s = 0; s < 2; s++) {
    const char *path = s ? "/interfaces/kt" : "/interfaces/kn";
    PetscReal **k    = s ? &d->kt : &d->kn;
    if (!(s ? has_kt : has_kn)) continue;
    PetscCall(BwH5Open(d, path, H5T_FLOAT, 1, 0, "float64 (I): one stiffness per interface [N/m^3]", &dset, &rows));
    PetscCheck((PetscInt)rows == d->ni, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: %s has %llu values but /interfaces/blocks has %" PetscInt_FMT " interfaces", d->path, path, (unsigned long long)rows, d->ni);
    PetscCall(PetscMalloc1(d->ni + 1, k));
    PetscCall(BwH5Read(d, path, dset, H5T_NATIVE_DOUBLE, rows, *k));
  }
  PetscCall(BwFileReadSets(d));
  if (H5Aexists(d->file, "depth") > 0) {
    hid_t    a = H5Aopen(d->file, "depth", H5P_DEFAULT), type = H5Aget_type(a), space = H5Aget_space(a);
    hssize_t n = H5Sget_simple_extent_npoints(space);
    H5T_class_t c = H5Tget_class(type);
    herr_t   err = -1;
    H5Tclose(type);
    H5Sclose(space);
    if (c == H5T_FLOAT && n == 1) err = H5Aread(a, H5T_NATIVE_DOUBLE, &d->depth);
    H5Aclose(a);
    PetscCheck(err >= 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: root attribute depth must be one float64 [m]", d->path);
    PetscCheck(d->depth > 0 && PetscIsNormalReal(d->depth), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: root attribute depth = %g; it must be > 0 [m]", d->path, (double)d->depth);
    d->has_depth = PETSC_TRUE;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ checks */

/* Indices, stiffnesses and set members: what needs no geometry. */
static PetscErrorCode BwFileCheckIndices(BwFileData *d)
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < d->ni; k++) {
    int64_t i = d->pairs[2 * k], j = d->pairs[2 * k + 1];
    for (int s = 0; s < 2; s++) {
      int64_t b = s ? j : i;
      PetscCheck(b >= 0 && b < d->nb, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: interface %" PetscInt_FMT " names block %lld, out of range [0, %" PetscInt_FMT ")", d->path, k, (long long)b, d->nb);
    }
    PetscCheck(i != j, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: interface %" PetscInt_FMT " joins block %lld to itself (i = j)", d->path, k, (long long)i);
    PetscCheck(i < j, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: interface %" PetscInt_FMT " is (%lld, %lld) with i > j; pairs must be (i, j) with i < j, the normal n pointing from i into j", d->path, k, (long long)i, (long long)j);
  }
  for (int s = 0; s < 2; s++) {
    const PetscReal *kk = s ? d->kt : d->kn;
    if (!kk) continue;
    for (PetscInt k = 0; k < d->ni; k++)
      PetscCheck(kk[k] > 0 && PetscIsNormalReal(kk[k]), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /interfaces/%s: interface %" PetscInt_FMT " (blocks %lld, %lld) has %s = %g; it must be > 0 and finite [N/m^3]", d->path, s ? "kt" : "kn", k, (long long)d->pairs[2 * k], (long long)d->pairs[2 * k + 1], s ? "kt" : "kn", (double)kk[k]);
  }
  for (PetscInt s = 0; s < d->nsets; s++) {
    int64_t *m = d->setdata[s];
    for (PetscInt k = 0; k < d->setlen[s]; k++)
      PetscCheck(m[k] >= 0 && m[k] < d->nb, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /sets/%s: member %" PetscInt_FMT " is block %lld, out of range [0, %" PetscInt_FMT ")", d->path, d->setname[s], k, (long long)m[k], d->nb);
    /* a block listed twice would take the set's load twice */
    {
      PetscInt *idx;
      PetscCall(PetscMalloc1(d->setlen[s] + 1, &idx));
      for (PetscInt k = 0; k < d->setlen[s]; k++) idx[k] = (PetscInt)m[k];
      PetscCall(PetscSortInt(d->setlen[s], idx));
      for (PetscInt k = 1; k < d->setlen[s]; k++) {
        if (idx[k] != idx[k - 1]) continue;
        {
          PetscInt b = idx[k];
          PetscCall(PetscFree(idx));
          SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /sets/%s lists block %" PetscInt_FMT " more than once", d->path, d->setname[s], b);
        }
      }
      PetscCall(PetscFree(idx));
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

typedef struct {
  PetscInt i, j, row;
} BwRow;

static int BwRowCompare(const void *x, const void *y)
{
  const BwRow *p = (const BwRow *)x, *q = (const BwRow *)y;
  if (p->i != q->i) return p->i < q->i ? -1 : 1;
  if (p->j != q->j) return p->j < q->j ? -1 : 1;
  return p->row < q->row ? -1 : p->row > q->row;
}

/* G, theta, l of each listed interface from its blocks' facing edges. */
static PetscErrorCode BwFileExplicitInterfaces(BwGeometry g, BwFileData *d, const BwTolerance *tol)
{
  BwRow     *rows;
  BwSegment *seg = NULL, *at;
  PetscInt   cap = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(d->ni + 1, &rows, d->ni + 1, &at));
  for (PetscInt k = 0; k < d->ni; k++) {
    rows[k].i   = (PetscInt)d->pairs[2 * k];
    rows[k].j   = (PetscInt)d->pairs[2 * k + 1];
    rows[k].row = k;
  }
  qsort(rows, (size_t)d->ni, sizeof(BwRow), BwRowCompare);
  for (PetscInt r0 = 0; r0 < d->ni;) {
    PetscInt r1 = r0, i = rows[r0].i, j = rows[r0].j, n;
    while (r1 < d->ni && rows[r1].i == i && rows[r1].j == j) r1++;
    PetscCall(BwDetectPair(g, tol, i, j, &n, &cap, &seg));
    if (n == 0 || r1 - r0 != n) {
      PetscInt first = rows[r0].row, extra = r1 - r0 > n ? rows[r0 + n].row : -1;
      PetscCall(PetscFree(seg));
      PetscCall(PetscFree2(rows, at));
      PetscCheck(n > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: interface %" PetscInt_FMT " joins blocks %" PetscInt_FMT " and %" PetscInt_FMT ", which have no facing edges (anti-parallel within %g deg, at most e + tolerance = %g m apart, overlapping by more than %g m)", d->path, first, i, j, (double)(BW_FACING_ANGLE * 180 / PETSC_PI), (double)tol->gapmax, (double)tol->delta);
      PetscCheck(extra < 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: interface %" PetscInt_FMT " repeats the pair (%" PetscInt_FMT ", %" PetscInt_FMT ") of interface %" PetscInt_FMT " (duplicate pair); the two blocks face each other along %" PetscInt_FMT " segment%s", d->path, extra, i, j, first, n, n > 1 ? "s" : "");
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: blocks %" PetscInt_FMT " and %" PetscInt_FMT " face each other along %" PetscInt_FMT " separate segments, but the pair is listed %" PetscInt_FMT " time%s (interface %" PetscInt_FMT "); list it once per segment", d->path, i, j, n, r1 - r0, r1 - r0 > 1 ? "s" : "", first);
    }
    for (PetscInt r = r0; r < r1; r++) at[rows[r].row] = seg[r - r0];
    r0 = r1;
  }
  for (PetscInt k = 0; k < d->ni; k++) PetscCall(BwGeometryAddInterface(g, (PetscInt)d->pairs[2 * k], (PetscInt)d->pairs[2 * k + 1], at[k].center, at[k].angle, at[k].length, BW_JOINT_BED));
  PetscCall(PetscFree(seg));
  PetscCall(PetscFree2(rows, at));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The file's per-interface stiffness and sets into g. */
static PetscErrorCode BwFileStiffnessAndSets(BwGeometry g, BwFileData *d)
{
  PetscFunctionBeginUser;
  for (int s = 0; s < 2; s++) {
    const PetscReal *k = s ? d->kt : d->kn;
    PetscReal      **to = s ? &g->kt : &g->kn;
    if (!k) continue;
    PetscCall(PetscMalloc1(d->ni + 1, to));
    PetscCall(PetscArraycpy(*to, k, d->ni));
  }
  for (PetscInt s = 0; s < d->nsets; s++) {
    PetscInt *members, *pos;
    PetscCall(PetscMalloc2(d->setlen[s] + 1, &members, d->setlen[s] + 1, &pos));
    for (PetscInt k = 0; k < d->setlen[s]; k++) {
      members[k] = (PetscInt)d->setdata[s][k];
      pos[k]     = k; /* written back in the file's order */
    }
    PetscCall(BwGeometryAddSetAt(g, d->setname[s], d->setlen[s], members, pos));
    PetscCall(PetscFree2(members, pos));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rank 0: everything from the file into g. */
static PetscErrorCode BwFileBuild(BwGeometry g, BwFileData *d, PetscReal thickness)
{
  BwTolerance tol;

  PetscFunctionBeginUser;
  PetscCall(BwFileRead(d));
  PetscCall(BwFileCheckIndices(d));
  if (d->dim == 3) {
    PetscCall(BwFileBuild3D(g, d->path, d->nv, d->xy, d->nb, d->offsets, d->has_pairs, d->ni, d->pairs, thickness));
    PetscCall(BwFileStiffnessAndSets(g, d));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  /* finite coordinates first: the tolerances are computed from them */
  for (PetscInt b = 0; b < d->nb; b++) {
    for (int64_t v = d->offsets[b]; v < d->offsets[b + 1]; v++)
      PetscCheck(!PetscIsInfOrNanReal(d->xy[2 * v]) && !PetscIsInfOrNanReal(d->xy[2 * v + 1]), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /blocks/vertices: block %" PetscInt_FMT ": vertex row %lld is not finite (%g, %g)", d->path, b, (long long)v, (double)d->xy[2 * v], (double)d->xy[2 * v + 1]);
  }
  {
    PetscInt *off;
    PetscCall(PetscMalloc1(d->nb + 1, &off));
    for (PetscInt b = 0; b <= d->nb; b++) off[b] = (PetscInt)d->offsets[b];
    PetscCall(BwToleranceCompute(d->nv, d->xy, d->nb, off, thickness, &tol));
    PetscCall(PetscFree(off));
  }
  /* checked and reoriented in place: the raw buffer is ours */
  for (PetscInt b = 0; b < d->nb; b++) {
    PetscInt first = (PetscInt)d->offsets[b], nv = (PetscInt)(d->offsets[b + 1] - d->offsets[b]);
    PetscCall(BwValidatePolygon(d->path, b, first, nv, d->xy + 2 * first, &tol));
    PetscCall(BwGeometryAddBlock(g, nv, d->xy + 2 * first, NULL));
  }
  PetscCall(BwGeometryComputeCentroids(g));
  PetscCall(BwValidateOverlaps(d->path, g, &tol));
  if (d->has_pairs) PetscCall(BwFileExplicitInterfaces(g, d, &tol));
  else PetscCall(BwDetectInterfaces(g, &tol));
  PetscCall(BwValidateConnected(d->path, g, d->has_pairs ? PETSC_FALSE : PETSC_TRUE, &tol));
  PetscCall(BwFileStiffnessAndSets(g, d));
  if (d->has_depth) g->depth = d->depth;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rank 0 read the file and holds every block: its share is the whole
 * assembly, the other ranks' are empty, and BwGeometryDistribute moves the
 * blocks out. The other ranks learn what every share must know: the
 * dimension, the depth, the counts, the set names, whether the file gives
 * stiffnesses. (Rank 0 holds the file's whole geometry while it reads and
 * checks it: the parallel reader replaces this.) */
static PetscErrorCode BwGeometryShareFromRankZero(BwGeometry g)
{
  PetscMPIInt rank;
  PetscInt    n[5]    = {g->nblocks, g->ninterfaces, g->nsets, g->volume ? 3 : 2, g->kn ? 1 : 0};
  PetscInt    namelen = 0;
  char       *names   = NULL;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(g->comm, &rank));
  PetscCallMPI(MPI_Bcast(n, 5, MPIU_INT, 0, g->comm));
  PetscCallMPI(MPI_Bcast(&g->depth, 1, MPIU_REAL, 0, g->comm));
  if (!rank)
    for (PetscInt s = 0; s < n[2]; s++) namelen += (PetscInt)strlen(g->setname[s]) + 1;
  PetscCallMPI(MPI_Bcast(&namelen, 1, MPIU_INT, 0, g->comm));
  PetscCall(PetscMalloc1(namelen + 1, &names));
  if (!rank)
    for (PetscInt s = 0, at = 0; s < n[2]; s++) {
      PetscCall(PetscStrcpy(names + at, g->setname[s]));
      at += (PetscInt)strlen(g->setname[s]) + 1;
    }
  PetscCallMPI(MPI_Bcast(names, (PetscMPIInt)namelen, MPI_CHAR, 0, g->comm));
  if (rank) {
    /* an empty share of the same kind */
    for (PetscInt s = 0, at = 0; s < n[2]; s++) {
      PetscCall(BwGeometryAddSet(g, names + at, 0, NULL));
      at += (PetscInt)strlen(names + at) + 1;
    }
    if (n[3] == 3) {
      g->dim = 3;
      PetscCall(PetscCalloc1(1, &g->volume));
      PetscCall(PetscCalloc1(1, &g->face_offsets));
      PetscCall(PetscCalloc1(1, &g->face_voffsets));
      PetscCall(PetscCalloc1(1, &g->poly_offsets));
    }
  }
  PetscCall(PetscFree(names));
  PetscCall(BwGeometrySetShare(g, rank ? 0 : n[0]));
  g->ninterfaces_global = n[1];
  PetscFunctionReturn(PETSC_SUCCESS);
}

typedef struct {
  char name[PETSC_MAX_PATH_LEN];               /* as written */
  char path[PETSC_MAX_PATH_LEN];               /* as opened */
  char where[PETSC_MAX_PATH_LEN + 64];         /* where geometry.file was set */
} BwFileOptions;

static PetscErrorCode BwFileSetFromOptions(BwGenerator gen, BwGeometry g, BwScene scene)
{
  BwFileOptions *o = (BwFileOptions *)gen->data;
  const char    *dir;
  PetscBool      set;

  PetscFunctionBeginUser;
  PetscCall(BwSceneHelpSection(scene, "Geometry file (scene key geometry.file)"));
  PetscCall(BwSceneString(scene, "-geometry_file", "HDF5 geometry: /blocks/vertices, /blocks/offsets, optional /interfaces/blocks, kn, kt, /sets/NAME (in the scene file: relative to its directory)", o->name, sizeof(o->name), &set));
  if (!set || !o->name[0]) PetscCall(BwSceneError(scene, "-geometry_file", "must name an HDF5 geometry file when geometry.generator is file"));
  PetscCall(BwSceneLocate(scene, "-geometry_file", o->where, sizeof(o->where)));
  PetscCall(BwSceneGetDirectory(scene, &dir));
  if (o->name[0] == '/' || !strncmp(o->where, "command line", 12) || !dir || !strcmp(dir, ".")) PetscCall(PetscStrncpy(o->path, o->name, sizeof(o->path)));
  else PetscCall(PetscSNPrintf(o->path, sizeof(o->path), "%s/%s", dir, o->name));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwFileGenerate(BwGenerator gen, BwGeometry g, BwScene scene, PetscReal thickness)
{
  const BwFileOptions *o = (BwFileOptions *)gen->data;
  BwFileData           d;
  char                 msg[BW_MSG_LEN] = "";
  PetscMPIInt          rank;
  PetscInt             want;
  int                  err = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&d, sizeof(d)));
  d.file = -1;
  PetscCall(PetscStrncpy(d.path, o->path, sizeof(d.path)));
  PetscCall(PetscStrncpy(d.where, o->where, sizeof(d.where)));
  PetscCallMPI(MPI_Comm_rank(g->comm, &rank));
  want = g->dim;
  if (!rank) {
    PetscErrorCode ierr = BwFileBuild(g, &d, thickness);
    if (ierr) {
      const char *specific = BwErrorText(ierr);
      PetscCall(PetscStrncpy(msg, specific[0] ? specific : "reading the geometry file failed", sizeof(msg)));
      err = (int)ierr;
    }
    PetscCall(BwFileDataDestroy(&d));
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, g->comm));
  if (err) {
    PetscCallMPI(MPI_Bcast(msg, sizeof(msg), MPI_CHAR, 0, g->comm));
    SETERRQ(g->comm, (PetscErrorCode)err, "%s", msg);
  }
  PetscCall(BwGeometryShareFromRankZero(g));
  /* the file decides the dimension; a scene that says otherwise is wrong */
  {
    PetscInt have = g->volume ? 3 : 2;
    if (g->dim_given && want != have) PetscCall(BwSceneError(scene, "-geometry_dimension", "is %" PetscInt_FMT ", but the geometry file '%s' holds %" PetscInt_FMT "D blocks (its /blocks/vertices has %" PetscInt_FMT " columns)", want, o->path, have, have));
    if (have == 3 && g->depth_given) PetscCall(BwSceneError(scene, "-geometry_depth", "has no meaning with a 3D geometry file ('%s'): its blocks have their own thickness", o->path));
    g->dim = have;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwFileDestroy(BwGenerator gen)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(gen->data));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeneratorCreate_File(BwGenerator gen)
{
  BwFileOptions *o;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&o));
  gen->data           = o;
  gen->setfromoptions = BwFileSetFromOptions;
  gen->generate       = BwFileGenerate;
  gen->destroy        = BwFileDestroy;
  PetscFunctionReturn(PETSC_SUCCESS);
}
