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
 * In parallel (collective, every rank its D0 share, geometry.h): rank 0
 * reads the metadata (shapes, types, set names, the depth attribute) and
 * tells the others; every rank reads by hyperslabs its balanced range of
 * the blocks (/blocks/offsets of its range and one more, then its vertex
 * rows), a balanced range of the rows of /interfaces/blocks, kn, kt and of
 * each set. Listed interfaces go to the rank of their first block (their
 * row kept as their id), set members to the rank of their block (their
 * row in the list kept as their position). Checks of one block, row or
 * member are made where it was read; the tolerances from reductions and a
 * gathered sample; the pairwise work (overlaps, facing edges or faces) on
 * the blocks of a region of space (spatial.c), each pair by one rank, whose
 * interfaces go to the rank of their first block. Nothing of the size of
 * the assembly is on any rank.
 *
 * Every check the serial reader makes is made, in its order: each fault
 * has its place (a stage and an index: the block, the row, the pair), each
 * phase ends with an agreement (BwFaultAgree) that raises the first fault
 * of all ranks on every rank, with the serial reader's one line.
 *
 * Each rank opens the file read-only with HDF5's default (sec2) driver and
 * reads its hyperslabs, rather than through MPI-IO (H5Pset_fapl_mpio):
 * each rank reads one contiguous range of rows of each dataset, which
 * MPI-IO would read the same way, and the file's opening, its metadata
 * reads and its closing stay local calls: a rank that meets a broken file
 * or a failed read reports it at the next agreement instead of leaving the
 * others inside a collective HDF5 call (the output's hang on a full disk
 * came from one). Measured (peak resident memory of the largest rank,
 * test_geometry on the 1e5-block running-bond file, independent reads):
 * 87.3 MB on 2 ranks and 57.2 MB on 8 with sec2, 88.1 and 58.1 MB through
 * MPI-IO: nothing to gain there for one contiguous slab per rank. */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <hdf5.h>
#include "geometry/validate.h"
#include "util/compat.h"
#include "util/exchange.h"

/* The places of the checks in the serial reader's order (BwFault stages);
 * after the sets (two stages each: members in range, none repeated) come
 * the geometry's: finite vertices, polygons or hulls, overlaps, listed
 * interfaces (BW_STAGE_GEOMETRY). */
enum {
  BW_STAGE_META1,
  BW_STAGE_OPEN,
  BW_STAGE_OFFSETS_FIRST,
  BW_STAGE_OFFSETS_ORDER,
  BW_STAGE_OFFSETS_LAST,
  BW_STAGE_META2,
  BW_STAGE_READ,
  BW_STAGE_PAIRS,
  BW_STAGE_KN,
  BW_STAGE_KT,
  BW_STAGE_SETS
};
#define BW_STAGE_GEOMETRY(d) (BW_STAGE_SETS + 2 * (int64_t)(d)->nsets)

typedef struct {
  char        path[PETSC_MAX_PATH_LEN];        /* as opened; named in every message */
  char        where[PETSC_MAX_PATH_LEN + 64];  /* where geometry.file was set */
  MPI_Comm    comm;
  PetscMPIInt rank, size;
  hid_t       file;
  /* what rank 0 reads and tells every rank */
  PetscInt  dim; /* 2 | 3: the columns of /blocks/vertices */
  PetscInt  nv, nb, ni, nsets;
  PetscBool has_pairs, has_kn, has_kt, has_depth;
  PetscReal depth;
  char    **setname;
  PetscInt *setlen;
  /* this rank's slabs: blocks b0.. b1 - 1, interface rows k0.. k1 - 1 */
  PetscInt   b0, b1, k0, k1;
  int64_t   *offsets; /* b1 - b0 + 1 entries */
  PetscReal *xy;      /* vertex rows offsets[0].. offsets[b1 - b0] - 1 */
  int64_t   *pairs;
  PetscReal *kn, *kt;
  int64_t  **setdata; /* per set: its rows of this rank's range */
  /* routed: the listed interfaces whose first block is here, by row, and
   * the members of each set among this rank's blocks (CSR by set) */
  PetscInt   nhome, *hrow, *hpair;
  PetscReal *hkn, *hkt;
  PetscInt  *msetoff, *mblock, *mpos;
} BwFileData;

static PetscErrorCode BwFileDataDestroy(BwFileData *d)
{
  PetscFunctionBeginUser;
  if (d->file > 0) H5Fclose(d->file);
  d->file = -1;
  for (PetscInt s = 0; s < d->nsets; s++) {
    if (d->setname) PetscCall(PetscFree(d->setname[s]));
    if (d->setdata) PetscCall(PetscFree(d->setdata[s]));
  }
  PetscCall(PetscFree(d->setname));
  PetscCall(PetscFree(d->setdata));
  PetscCall(PetscFree(d->setlen));
  PetscCall(PetscFree(d->offsets));
  PetscCall(PetscFree(d->xy));
  PetscCall(PetscFree(d->pairs));
  PetscCall(PetscFree(d->kn));
  PetscCall(PetscFree(d->kt));
  PetscCall(PetscFree(d->hrow));
  PetscCall(PetscFree(d->hpair));
  PetscCall(PetscFree(d->hkn));
  PetscCall(PetscFree(d->hkt));
  PetscCall(PetscFree(d->msetoff));
  PetscCall(PetscFree(d->mblock));
  PetscCall(PetscFree(d->mpos));
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


/* Rows row0.. row0 + n - 1 of dataset `path` (width columns, 0: one
 * dimension) into buf. */
static PetscErrorCode BwH5ReadRows(BwFileData *d, const char path[], hid_t memtype, hsize_t row0, hsize_t n, hsize_t width, void *buf)
{
  hid_t  dset, fspace, mspace;
  herr_t err = -1;

  PetscFunctionBeginUser;
  if (!n) PetscFunctionReturn(PETSC_SUCCESS);
  dset = H5Dopen2(d->file, path, H5P_DEFAULT);
  if (dset >= 0) {
    hsize_t start[2] = {row0, 0}, count[2] = {n, width};
    fspace = H5Dget_space(dset);
    if (fspace >= 0 && H5Sselect_hyperslab(fspace, H5S_SELECT_SET, start, NULL, count, NULL) >= 0) {
      mspace = H5Screate_simple(width ? 2 : 1, count, NULL);
      if (mspace >= 0) {
        err = H5Dread(dset, memtype, mspace, fspace, H5P_DEFAULT, buf);
        H5Sclose(mspace);
      }
    }
    if (fspace >= 0) H5Sclose(fspace);
    H5Dclose(dset);
  }
  PetscCheck(err >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_READ, "%s: %s cannot be read", d->path, path);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwFileOpen(BwFileData *d)
{
  hid_t fapl;

  PetscFunctionBeginUser;
  fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_fclose_degree(fapl, H5F_CLOSE_STRONG); /* closing the file closes what an error left open */
  d->file = H5Fopen(d->path, H5F_ACC_RDONLY, fapl);
  H5Pclose(fapl);
  PetscCheck(d->file >= 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: '%s' cannot be opened as an HDF5 file", d->where, d->path);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rank 0: the file, its blocks' datasets and their shapes. */
static PetscErrorCode BwFileMeta1(BwFileData *d)
{
  hid_t     dset;
  hsize_t   rows, nb1;
  PetscBool exists;
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
  PetscCall(BwFileOpen(d));
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
  H5Dclose(dset);
  d->nv = (PetscInt)rows;
  PetscCall(BwH5Open(d, "/blocks/offsets", H5T_INTEGER, 1, 0, "int64 (B+1): block b has vertex rows offsets[b]..offsets[b+1]-1", &dset, &nb1));
  H5Dclose(dset);
  PetscCheck(nb1 >= 2, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /blocks/offsets has %llu entries; it needs B+1 >= 2 (at least one block)", d->path, (unsigned long long)nb1);
  d->nb = (PetscInt)nb1 - 1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* One set's name and shape, /sets/NAME. */
static PetscErrorCode BwFileMetaSet(BwFileData *d, const char name[])
{
  char    path[300];
  hid_t   dset;
  hsize_t n;

  PetscFunctionBeginUser;
  PetscCheck(strlen(name) < 256, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /sets: the name of set '%.40s...' is longer than 255 characters", d->path, name);
  /* a set name becomes part of option names (-loads_NAME, -supports_NAME_u1) */
  for (const char *c = name; *c; c++)
    PetscCheck((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') || *c == '_', PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: /sets/%s: set names may hold only letters, digits and '_' (they become scene keys loads.NAME, supports.NAME)", d->path, name);
  PetscCall(PetscSNPrintf(path, sizeof(path), "/sets/%s", name));
  PetscCall(PetscStrallocpy(name, &d->setname[d->nsets]));
  d->nsets++;
  PetscCall(BwH5Open(d, path, H5T_INTEGER, 1, 0, "int64 (k): the blocks of the set", &dset, &n));
  H5Dclose(dset);
  d->setlen[d->nsets - 1] = (PetscInt)n;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwFileMetaSets(BwFileData *d)
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
  PetscCall(PetscCalloc1(info.nlinks + 1, &d->setlen));
  {
    BwLinkNames    l   = {NULL, 0, 0, 0};
    hsize_t        idx = 0;
    herr_t         err = H5Literate(grp, H5_INDEX_NAME, H5_ITER_INC, &idx, BwLinkName, &l);
    PetscErrorCode ierr = PETSC_SUCCESS;
    if (err < 0 || l.n != info.nlinks) {
      for (size_t k = 0; k < l.n; k++) free(l.name[k]);
      free(l.name);
      H5Gclose(grp);
      SETERRQ(PETSC_COMM_SELF, l.err ? PETSC_ERR_MEM : PETSC_ERR_USER_INPUT, "%s: /sets: the names of its members cannot be read", d->path);
    }
    for (size_t k = 0; k < l.n && !ierr; k++) ierr = BwFileMetaSet(d, l.name[k]);
    for (size_t k = 0; k < l.n; k++) free(l.name[k]);
    free(l.name);
    H5Gclose(grp);
    PetscCall(ierr);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rank 0: the interfaces' datasets and their shapes, the sets, the depth. */
static PetscErrorCode BwFileMeta2(BwFileData *d)
{
  hid_t     dset;
  hsize_t   rows;

  PetscFunctionBeginUser;
  PetscCall(BwH5Exists(d, "/interfaces/blocks", &d->has_pairs));
  PetscCall(BwH5Exists(d, "/interfaces/kn", &d->has_kn));
  PetscCall(BwH5Exists(d, "/interfaces/kt", &d->has_kt));
  if (d->has_pairs) {
    PetscCall(BwH5Open(d, "/interfaces/blocks", H5T_INTEGER, 2, 2, "int64 (I, 2): pairs (i, j), i < j", &dset, &rows));
    H5Dclose(dset);
    d->ni = (PetscInt)rows;
  } else
    PetscCheck(!d->has_kn && !d->has_kt, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: %s is given without /interfaces/blocks; per-interface stiffness needs the interface list (detected interfaces take joints.*)", d->path, d->has_kn ? "/interfaces/kn" : "/interfaces/kt");
  for (int s = 0; s < 2; s++) {
    const char *path = s ? "/interfaces/kt" : "/interfaces/kn";
    if (!(s ? d->has_kt : d->has_kn)) continue;
    PetscCall(BwH5Open(d, path, H5T_FLOAT, 1, 0, "float64 (I): one stiffness per interface [N/m^3]", &dset, &rows));
    H5Dclose(dset);
    PetscCheck((PetscInt)rows == d->ni, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s: %s has %llu values but /interfaces/blocks has %" PetscInt_FMT " interfaces", d->path, path, (unsigned long long)rows, d->ni);
  }
  PetscCall(BwFileMetaSets(d));
  if (H5Aexists(d->file, "depth") > 0) {
    hid_t       a = H5Aopen(d->file, "depth", H5P_DEFAULT), type = H5Aget_type(a), space = H5Aget_space(a);
    hssize_t    n = H5Sget_simple_extent_npoints(space);
    H5T_class_t c = H5Tget_class(type);
    herr_t      err = -1;
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

/* Rank 0's metadata to every rank: the flags and sizes, the set names and lengths. */
static PetscErrorCode BwFileShareMeta2(BwFileData *d)
{
  PetscInt n[7] = {d->has_pairs, d->ni, d->has_kn, d->has_kt, d->has_depth, d->nsets, 0};
  char    *names;

  PetscFunctionBeginUser;
  if (!d->rank)
    for (PetscInt s = 0; s < d->nsets; s++) n[6] += (PetscInt)strlen(d->setname[s]) + 1;
  PetscCallMPI(MPI_Bcast(n, 7, MPIU_INT, 0, d->comm));
  PetscCallMPI(MPI_Bcast(&d->depth, 1, MPIU_REAL, 0, d->comm));
  d->has_pairs = n[0] ? PETSC_TRUE : PETSC_FALSE;
  d->ni        = n[1];
  d->has_kn    = n[2] ? PETSC_TRUE : PETSC_FALSE;
  d->has_kt    = n[3] ? PETSC_TRUE : PETSC_FALSE;
  d->has_depth = n[4] ? PETSC_TRUE : PETSC_FALSE;
  if (d->rank) {
    d->nsets = n[5];
    PetscCall(PetscCalloc1(d->nsets + 1, &d->setname));
    PetscCall(PetscCalloc1(d->nsets + 1, &d->setlen));
  }
  PetscCall(PetscMalloc1(n[6] + 1, &names));
  if (!d->rank)
    for (PetscInt s = 0, at = 0; s < d->nsets; s++) {
      PetscCall(PetscStrcpy(names + at, d->setname[s]));
      at += (PetscInt)strlen(d->setname[s]) + 1;
    }
  PetscCallMPI(MPI_Bcast(names, (PetscMPIInt)n[6], MPI_CHAR, 0, d->comm));
  if (d->rank)
    for (PetscInt s = 0, at = 0; s < d->nsets; s++) {
      PetscCall(PetscStrallocpy(names + at, &d->setname[s]));
      at += (PetscInt)strlen(names + at) + 1;
    }
  PetscCall(PetscFree(names));
  if (d->nsets) PetscCallMPI(MPI_Bcast(d->setlen, (PetscMPIInt)d->nsets, MPIU_INT, 0, d->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ slabs */

/* Rank 0 reads the file's metadata; every rank opens the file and reads
 * /blocks/offsets of its range of blocks, checked. */
static PetscErrorCode BwFileReadBlocks(BwGeometry g, BwFileData *d)
{
  BwFault f;
  PetscInt n[3] = {0, 0, 0};

  PetscFunctionBeginUser;
  BwFaultInit(&f);
  if (!d->rank) BwFaultCatch(&f, BW_STAGE_META1, 0, BwFileMeta1(d));
  PetscCall(BwFaultAgree(d->comm, &f));
  if (!d->rank) {
    n[0] = d->dim;
    n[1] = d->nv;
    n[2] = d->nb;
  }
  PetscCallMPI(MPI_Bcast(n, 3, MPIU_INT, 0, d->comm));
  d->dim = n[0];
  d->nv  = n[1];
  d->nb  = n[2];
  if (d->rank) BwFaultCatch(&f, BW_STAGE_OPEN, 0, BwFileOpen(d));
  PetscCall(BwFaultAgree(d->comm, &f));

  BwGeometrySplit(d->comm, d->nb, &d->b0, &d->b1);
  PetscCall(PetscMalloc1(d->b1 - d->b0 + 1, &d->offsets));
  d->offsets[0] = 0;
  if (d->b1 > d->b0 && !BwFaultCatch(&f, BW_STAGE_READ, 0, BwH5ReadRows(d, "/blocks/offsets", H5T_NATIVE_INT64, (hsize_t)d->b0, (hsize_t)(d->b1 - d->b0 + 1), 0, d->offsets))) {
    const int64_t *o = d->offsets;
    if (d->b0 == 0 && o[0] != 0) BwFaultSet(&f, BW_STAGE_OFFSETS_FIRST, 0, PETSC_ERR_USER_INPUT, "%s: /blocks/offsets[0] = %lld; it must be 0 (block 0 starts at vertex row 0)", d->path, (long long)o[0]);
    for (PetscInt b = d->b0; b < d->b1; b++)
      if (o[b + 1 - d->b0] < o[b - d->b0]) {
        BwFaultSet(&f, BW_STAGE_OFFSETS_ORDER, b, PETSC_ERR_USER_INPUT, "%s: /blocks/offsets is not increasing: offsets[%" PetscInt_FMT "] = %lld < offsets[%" PetscInt_FMT "] = %lld (block %" PetscInt_FMT ")", d->path, b + 1, (long long)o[b + 1 - d->b0], b, (long long)o[b - d->b0], b);
        break;
      }
    if (d->b1 == d->nb && o[d->b1 - d->b0] != d->nv) BwFaultSet(&f, BW_STAGE_OFFSETS_LAST, 0, PETSC_ERR_USER_INPUT, "%s: /blocks/offsets[%" PetscInt_FMT "] = %lld (the last) must equal the number of rows of /blocks/vertices, %" PetscInt_FMT, d->path, d->nb, (long long)o[d->b1 - d->b0], d->nv);
  }
  PetscCall(BwFaultAgree(d->comm, &f));
  PetscCall(BwGeometrySetShare(g, d->b1 - d->b0));

  if (!d->rank) BwFaultCatch(&f, BW_STAGE_META2, 0, BwFileMeta2(d));
  PetscCall(BwFaultAgree(d->comm, &f));
  PetscCall(BwFileShareMeta2(d));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* This rank's rows of every dataset. */
static PetscErrorCode BwFileReadSlabs(BwFileData *d)
{
  BwFault        f;
  const PetscInt nbl = d->b1 - d->b0;
  const int64_t  v0 = d->offsets[0], nvl = d->offsets[nbl] - v0;

  PetscFunctionBeginUser;
  BwFaultInit(&f);
  PetscCall(PetscMalloc1(d->dim * nvl + 1, &d->xy));
  BwFaultCatch(&f, BW_STAGE_READ, 0, BwH5ReadRows(d, "/blocks/vertices", H5T_NATIVE_DOUBLE, (hsize_t)v0, (hsize_t)nvl, (hsize_t)d->dim, d->xy));
  BwGeometrySplit(d->comm, d->ni, &d->k0, &d->k1);
  if (d->has_pairs) {
    const hsize_t k0 = (hsize_t)d->k0, n = (hsize_t)(d->k1 - d->k0);
    PetscCall(PetscMalloc1(2 * n + 1, &d->pairs));
    BwFaultCatch(&f, BW_STAGE_READ, 1, BwH5ReadRows(d, "/interfaces/blocks", H5T_NATIVE_INT64, k0, n, 2, d->pairs));
    if (d->has_kn) {
      PetscCall(PetscMalloc1(n + 1, &d->kn));
      BwFaultCatch(&f, BW_STAGE_READ, 2, BwH5ReadRows(d, "/interfaces/kn", H5T_NATIVE_DOUBLE, k0, n, 0, d->kn));
    }
    if (d->has_kt) {
      PetscCall(PetscMalloc1(n + 1, &d->kt));
      BwFaultCatch(&f, BW_STAGE_READ, 3, BwH5ReadRows(d, "/interfaces/kt", H5T_NATIVE_DOUBLE, k0, n, 0, d->kt));
    }
  }
  PetscCall(PetscCalloc1(d->nsets + 1, &d->setdata));
  for (PetscInt s = 0; s < d->nsets; s++) {
    PetscInt r0, r1;
    char     path[300];
    BwGeometrySplit(d->comm, d->setlen[s], &r0, &r1);
    PetscCall(PetscMalloc1(r1 - r0 + 1, &d->setdata[s]));
    PetscCall(PetscSNPrintf(path, sizeof(path), "/sets/%s", d->setname[s]));
    BwFaultCatch(&f, BW_STAGE_READ, 4 + s, BwH5ReadRows(d, path, H5T_NATIVE_INT64, (hsize_t)r0, (hsize_t)(r1 - r0), 0, d->setdata[s]));
  }
  PetscCall(BwFaultAgree(d->comm, &f));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ checks */

typedef struct {
  PetscInt  row, i, j;
  PetscReal kn, kt;
} BwListedRecord;

static int BwListedRowCompare(const void *x, const void *y)
{
  const BwListedRecord *a = (const BwListedRecord *)x, *b = (const BwListedRecord *)y;
  return (a->row > b->row) - (a->row < b->row);
}

/* Indices and stiffnesses of the listed interfaces (row by row), then the
 * rows to the rank of their first block. */
static PetscErrorCode BwFileCheckPairs(BwFileData *d)
{
  BwFault  f;
  BwPacker p;
  char    *recv;
  size_t   nrecv;

  PetscFunctionBeginUser;
  if (!d->has_pairs) PetscFunctionReturn(PETSC_SUCCESS);
  BwFaultInit(&f);
  for (PetscInt k = d->k0; k < d->k1; k++) {
    const int64_t i = d->pairs[2 * (k - d->k0)], j = d->pairs[2 * (k - d->k0) + 1];
    PetscBool     bad = PETSC_FALSE;
    for (int s = 0; s < 2 && !bad; s++) {
      int64_t b = s ? j : i;
      if (!(b >= 0 && b < d->nb)) bad = BwFaultSet(&f, BW_STAGE_PAIRS, k, PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: interface %" PetscInt_FMT " names block %lld, out of range [0, %" PetscInt_FMT ")", d->path, k, (long long)b, d->nb);
    }
    if (!bad && i == j) bad = BwFaultSet(&f, BW_STAGE_PAIRS, k, PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: interface %" PetscInt_FMT " joins block %lld to itself (i = j)", d->path, k, (long long)i);
    if (!bad && i > j) bad = BwFaultSet(&f, BW_STAGE_PAIRS, k, PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: interface %" PetscInt_FMT " is (%lld, %lld) with i > j; pairs must be (i, j) with i < j, the normal n pointing from i into j", d->path, k, (long long)i, (long long)j);
    if (bad) break;
  }
  for (int s = 0; s < 2; s++) {
    const PetscReal *kk = s ? d->kt : d->kn;
    if (!kk) continue;
    for (PetscInt k = d->k0; k < d->k1; k++) {
      const PetscInt q = k - d->k0;
      if (kk[q] > 0 && PetscIsNormalReal(kk[q])) continue;
      BwFaultSet(&f, s ? BW_STAGE_KT : BW_STAGE_KN, k, PETSC_ERR_USER_INPUT, "%s: /interfaces/%s: interface %" PetscInt_FMT " (blocks %lld, %lld) has %s = %g; it must be > 0 and finite [N/m^3]", d->path, s ? "kt" : "kn", k, (long long)d->pairs[2 * q], (long long)d->pairs[2 * q + 1], s ? "kt" : "kn", (double)kk[q]);
      break;
    }
  }
  PetscCall(BwFaultAgree(d->comm, &f));
  /* each row to the rank of its first block, its row kept as its id */
  PetscCall(BwPackerCreate(d->comm, &p));
  for (PetscInt k = d->k0; k < d->k1; k++) {
    const PetscInt q   = k - d->k0;
    BwListedRecord rec = {k, (PetscInt)d->pairs[2 * q], (PetscInt)d->pairs[2 * q + 1], d->kn ? d->kn[q] : 0, d->kt ? d->kt[q] : 0};
    PetscCall(BwPack(&p, BwSplitRank(d->nb, d->size, rec.i), &rec, sizeof(rec)));
  }
  PetscCall(PetscFree(d->pairs));
  PetscCall(PetscFree(d->kn));
  PetscCall(PetscFree(d->kt));
  PetscCall(BwPackerExchange(d->comm, &p, &recv, &nrecv, NULL));
  PetscCall(BwPackerDestroy(&p));
  {
    BwListedRecord *rec = (BwListedRecord *)recv;
    PetscInt        n   = (PetscInt)(nrecv / sizeof(BwListedRecord));
    qsort(rec, (size_t)n, sizeof(BwListedRecord), BwListedRowCompare);
    d->nhome = n;
    PetscCall(PetscMalloc1(n + 1, &d->hrow));
    PetscCall(PetscMalloc1(2 * n + 1, &d->hpair));
    PetscCall(PetscMalloc1(n + 1, &d->hkn));
    PetscCall(PetscMalloc1(n + 1, &d->hkt));
    for (PetscInt k = 0; k < n; k++) {
      d->hrow[k]          = rec[k].row;
      d->hpair[2 * k]     = rec[k].i;
      d->hpair[2 * k + 1] = rec[k].j;
      d->hkn[k]           = rec[k].kn;
      d->hkt[k]           = rec[k].kt;
    }
  }
  PetscCall(PetscFree(recv));
  PetscFunctionReturn(PETSC_SUCCESS);
}

typedef struct {
  PetscInt s, b, pos;
} BwMemberRecord;

static int BwMemberCompare(const void *x, const void *y)
{
  const BwMemberRecord *a = (const BwMemberRecord *)x, *b = (const BwMemberRecord *)y;
  if (a->s != b->s) return a->s < b->s ? -1 : 1;
  if (a->b != b->b) return a->b < b->b ? -1 : 1;
  return (a->pos > b->pos) - (a->pos < b->pos);
}

/* Set members in range where they were read, then each to the rank of its
 * block with its row in the list: a block listed twice meets itself there. */
static PetscErrorCode BwFileCheckSets(BwFileData *d)
{
  BwFault         f;
  BwPacker        p;
  char           *recv;
  size_t          nrecv;
  BwMemberRecord *m;
  PetscInt        n;

  PetscFunctionBeginUser;
  BwFaultInit(&f);
  PetscCall(BwPackerCreate(d->comm, &p));
  for (PetscInt s = 0; s < d->nsets && f.stage == INT64_MAX; s++) {
    PetscInt r0, r1;
    BwGeometrySplit(d->comm, d->setlen[s], &r0, &r1);
    for (PetscInt q = 0; q < r1 - r0; q++) {
      const int64_t  b   = d->setdata[s][q];
      BwMemberRecord rec = {s, (PetscInt)b, r0 + q};
      if (!(b >= 0 && b < d->nb)) {
        /* the sets after it come later in the serial order: not read on */
        BwFaultSet(&f, BW_STAGE_SETS + 2 * s, r0 + q, PETSC_ERR_USER_INPUT, "%s: /sets/%s: member %" PetscInt_FMT " is block %lld, out of range [0, %" PetscInt_FMT ")", d->path, d->setname[s], r0 + q, (long long)b, d->nb);
        break;
      }
      PetscCall(BwPack(&p, BwSplitRank(d->nb, d->size, rec.b), &rec, sizeof(rec)));
    }
  }
  for (PetscInt s = 0; s < d->nsets; s++) PetscCall(PetscFree(d->setdata[s]));
  PetscCall(BwPackerExchange(d->comm, &p, &recv, &nrecv, NULL));
  PetscCall(BwPackerDestroy(&p));
  m = (BwMemberRecord *)recv;
  n = (PetscInt)(nrecv / sizeof(BwMemberRecord));
  qsort(m, (size_t)n, sizeof(BwMemberRecord), BwMemberCompare);
  /* a block listed twice would take the set's load twice */
  for (PetscInt k = 1; k < n; k++)
    if (m[k].s == m[k - 1].s && m[k].b == m[k - 1].b) {
      BwFaultSet(&f, BW_STAGE_SETS + 2 * m[k].s + 1, m[k].b, PETSC_ERR_USER_INPUT, "%s: /sets/%s lists block %" PetscInt_FMT " more than once", d->path, d->setname[m[k].s], m[k].b);
      break;
    }
  PetscCall(PetscCalloc1(d->nsets + 1, &d->msetoff));
  PetscCall(PetscMalloc1(n + 1, &d->mblock));
  PetscCall(PetscMalloc1(n + 1, &d->mpos));
  for (PetscInt k = 0; k < n; k++) {
    d->msetoff[m[k].s + 1]++;
    d->mblock[k] = m[k].b;
    d->mpos[k]   = m[k].pos;
  }
  for (PetscInt s = 0; s < d->nsets; s++) d->msetoff[s + 1] += d->msetoff[s];
  PetscCall(PetscFree(recv));
  PetscCall(BwFaultAgree(d->comm, &f));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Finite coordinates first: the tolerances are computed from them. */
static PetscErrorCode BwFileCheckFinite(BwFileData *d)
{
  BwFault        f;
  const PetscInt D = d->dim;

  PetscFunctionBeginUser;
  BwFaultInit(&f);
  for (PetscInt b = d->b0; b < d->b1 && f.stage == INT64_MAX; b++)
    for (int64_t v = d->offsets[b - d->b0]; v < d->offsets[b + 1 - d->b0]; v++) {
      const PetscReal *x = d->xy + D * (v - d->offsets[0]);
      PetscBool        ok = PETSC_TRUE;
      for (PetscInt c = 0; c < D; c++) ok = ok && !PetscIsInfOrNanReal(x[c]) ? PETSC_TRUE : PETSC_FALSE;
      if (ok) continue;
      if (D == 3) BwFaultSet(&f, BW_STAGE_GEOMETRY(d), v, PETSC_ERR_USER_INPUT, "%s: /blocks/vertices: block %" PetscInt_FMT ": vertex row %lld is not finite (%g, %g, %g)", d->path, b, (long long)v, (double)x[0], (double)x[1], (double)x[2]);
      else BwFaultSet(&f, BW_STAGE_GEOMETRY(d), v, PETSC_ERR_USER_INPUT, "%s: /blocks/vertices: block %" PetscInt_FMT ": vertex row %lld is not finite (%g, %g)", d->path, b, (long long)v, (double)x[0], (double)x[1]);
      break;
    }
  PetscCall(BwFaultAgree(d->comm, &f));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ 2D */

/* A detected interface on its way to the rank of its first block: pair
 * (global ids), its place among the pair's interfaces, its segment. */
typedef struct {
  PetscInt  i, j, seq;
  BwSegment s;
} BwFoundRecord;

static int BwFoundCompare(const void *x, const void *y)
{
  const BwFoundRecord *a = (const BwFoundRecord *)x, *b = (const BwFoundRecord *)y;
  if (a->i != b->i) return a->i < b->i ? -1 : 1;
  if (a->j != b->j) return a->j < b->j ? -1 : 1;
  return (a->seq > b->seq) - (a->seq < b->seq);
}

/* Detection among the blocks of this rank's region, each pair decided by
 * one rank; the interfaces to their first block's rank, in the serial
 * order there: (i, j, then the pair's own order). */
static PetscErrorCode BwFileDetect2D(BwGeometry g, BwFileData *d, const BwBlockView *share, const BwBlockView *region, const BwSpatial *sp, const BwTolerance *tol)
{
  BwDecideCtx    dc = {sp, region};
  PetscInt       n, *pair, *next;
  BwSegment     *seg;
  BwEdgeShapeCtx ectx;
  BwPacker       p;
  char          *recv;
  size_t         nrecv;

  PetscFunctionBeginUser;
  /* the edge grid's check, on every rank's edges */
  PetscCall(PetscMalloc1(share->offsets[share->n] + 1, &next));
  for (PetscInt b = 0; b < share->n; b++)
    for (PetscInt e = share->offsets[b]; e < share->offsets[b + 1]; e++) next[e] = e + 1 < share->offsets[b + 1] ? e + 1 : share->offsets[b];
  ectx.v     = share->x;
  ectx.next  = next;
  ectx.reach = 0.5 * tol->gapmax + tol->delta;
  PetscCall(BwGridCheckSpan(d->comm, share->offsets[share->n], BwEdgeShape, &ectx, PetscMax(1.5 * tol->edge, 4 * ectx.reach)));
  PetscCall(PetscFree(next));
  PetscCall(BwDetectInterfaces(region, tol, d->size > 1 ? BwDecideHere : NULL, &dc, &n, &pair, &seg));
  if (d->size == 1) {
    for (PetscInt k = 0; k < n; k++) PetscCall(BwGeometryAddInterface(g, pair[2 * k], pair[2 * k + 1], seg[k].center, seg[k].angle, seg[k].length, BW_JOINT_BED));
    PetscCall(PetscFree(pair));
    PetscCall(PetscFree(seg));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(BwPackerCreate(d->comm, &p));
  for (PetscInt k = 0, seq = 0; k < n; k++) {
    BwFoundRecord rec;
    seq     = k && pair[2 * k] == pair[2 * k - 2] && pair[2 * k + 1] == pair[2 * k - 1] ? seq + 1 : 0;
    rec.i   = region->gid[pair[2 * k]];
    rec.j   = region->gid[pair[2 * k + 1]];
    rec.seq = seq;
    rec.s   = seg[k];
    PetscCall(BwPack(&p, BwSplitRank(d->nb, d->size, rec.i), &rec, sizeof(rec)));
  }
  PetscCall(PetscFree(pair));
  PetscCall(PetscFree(seg));
  PetscCall(BwPackerExchange(d->comm, &p, &recv, &nrecv, NULL));
  PetscCall(BwPackerDestroy(&p));
  {
    BwFoundRecord *rec = (BwFoundRecord *)recv;
    PetscInt       m   = (PetscInt)(nrecv / sizeof(BwFoundRecord));
    qsort(rec, (size_t)m, sizeof(BwFoundRecord), BwFoundCompare);
    for (PetscInt k = 0; k < m; k++) PetscCall(BwGeometryAddInterface(g, rec[k].i, rec[k].j, rec[k].s.center, rec[k].s.angle, rec[k].s.length, BW_JOINT_BED));
  }
  PetscCall(PetscFree(recv));
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
  return (p->row > q->row) - (p->row < q->row);
}

/* Local index in view v of global block gid (v ascending in id), -1 if absent. */
static PetscInt BwViewFind(const BwBlockView *v, PetscInt gid)
{
  PetscInt at;
  PetscFindInt(gid, v->n, v->gid, &at);
  return at;
}

/* The result for one listed row, back to the rank of its first block. */
typedef struct {
  PetscInt  row;
  BwSegment s;
} BwListedResult;

static int BwListedResultCompare(const void *x, const void *y)
{
  const BwListedResult *a = (const BwListedResult *)x, *b = (const BwListedResult *)y;
  return (a->row > b->row) - (a->row < b->row);
}

/* G, theta, l of each listed interface from its blocks' facing edges: the
 * rows of a pair (grouped where its first block is) go to the rank that
 * decides the pair, which holds both blocks; a pair whose grown boxes do
 * not meet has no facing edges. The serial order of the faults: by pair. */
static PetscErrorCode BwFileListed2D(BwGeometry g, BwFileData *d, const BwBlockView *share, const BwBlockView *region, const BwSpatial *sp, const BwTolerance *tol)
{
  const PetscInt n = d->nhome, B = d->nb;
  BwRow         *rows;
  PetscMPIInt   *dec;
  BwFault        f;
  BwPacker       p;
  char          *recv;
  size_t         nrecv;
  BwSegment     *seg = NULL;
  PetscInt       cap = 0;

  PetscFunctionBeginUser;
  BwFaultInit(&f);
  PetscCall(PetscMalloc2(n + 1, &rows, n + 1, &dec));
  PetscCall(BwListedDeciders(d->comm, share, sp, B, n, d->hpair, dec));
  for (PetscInt k = 0; k < n; k++) {
    rows[k].i   = d->hpair[2 * k];
    rows[k].j   = d->hpair[2 * k + 1];
    rows[k].row = k; /* index into the home arrays for now */
  }
  qsort(rows, (size_t)n, sizeof(BwRow), BwRowCompare);
  PetscCall(BwPackerCreate(d->comm, &p));
  for (PetscInt r0 = 0; r0 < n;) {
    PetscInt    r1 = r0, i = rows[r0].i, j = rows[r0].j, q = dec[rows[r0].row], m;
    while (r1 < n && rows[r1].i == i && rows[r1].j == j) r1++;
    m = r1 - r0;
    if (q < 0) {
      BwFaultSet(&f, BW_STAGE_GEOMETRY(d) + 3, (int64_t)i * B + j, PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: interface %" PetscInt_FMT " joins blocks %" PetscInt_FMT " and %" PetscInt_FMT ", which have no facing edges (anti-parallel within %g deg, at most e + tolerance = %g m apart, overlapping by more than %g m)", d->path, d->hrow[rows[r0].row], i, j, (double)(BW_FACING_ANGLE * 180 / PETSC_PI), (double)tol->gapmax, (double)tol->delta);
    } else {
      PetscCall(BwPack(&p, q, &i, sizeof(i)));
      PetscCall(BwPack(&p, q, &j, sizeof(j)));
      PetscCall(BwPack(&p, q, &m, sizeof(m)));
      for (PetscInt r = r0; r < r1; r++) PetscCall(BwPack(&p, q, &d->hrow[rows[r].row], sizeof(PetscInt)));
    }
    r0 = r1;
  }
  PetscCall(PetscFree2(rows, dec));
  PetscCall(BwPackerExchange(d->comm, &p, &recv, &nrecv, NULL));
  PetscCall(BwPackerDestroy(&p));
  /* the deciding rank: BwDetectPair on both blocks, as the serial reader */
  PetscCall(BwPackerCreate(d->comm, &p));
  for (const char *at = recv; at < recv + nrecv;) {
    PetscInt i, j, m, li, lj, ns, *row;
    BwUnpack(&at, &i, sizeof(i));
    BwUnpack(&at, &j, sizeof(j));
    BwUnpack(&at, &m, sizeof(m));
    row = (PetscInt *)at; /* ascending */
    at += sizeof(PetscInt) * (size_t)m;
    li = BwViewFind(region, i);
    lj = BwViewFind(region, j);
    PetscCheck(li >= 0 && lj >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the pair (%" PetscInt_FMT ", %" PetscInt_FMT ") was sent to a rank without its blocks", i, j);
    PetscCall(BwDetectPair(region->x, region->offsets, tol, li, lj, &ns, &cap, &seg));
    if (ns == 0 || m != ns) {
      const int64_t key = BW_STAGE_GEOMETRY(d) + 3, index = (int64_t)i * B + j;
      PetscInt      first = row[0], extra = m > ns ? row[ns] : -1;
      if (ns == 0) BwFaultSet(&f, key, index, PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: interface %" PetscInt_FMT " joins blocks %" PetscInt_FMT " and %" PetscInt_FMT ", which have no facing edges (anti-parallel within %g deg, at most e + tolerance = %g m apart, overlapping by more than %g m)", d->path, first, i, j, (double)(BW_FACING_ANGLE * 180 / PETSC_PI), (double)tol->gapmax, (double)tol->delta);
      else if (extra >= 0) BwFaultSet(&f, key, index, PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: interface %" PetscInt_FMT " repeats the pair (%" PetscInt_FMT ", %" PetscInt_FMT ") of interface %" PetscInt_FMT " (duplicate pair); the two blocks face each other along %" PetscInt_FMT " segment%s", d->path, extra, i, j, first, ns, ns > 1 ? "s" : "");
      else BwFaultSet(&f, key, index, PETSC_ERR_USER_INPUT, "%s: /interfaces/blocks: blocks %" PetscInt_FMT " and %" PetscInt_FMT " face each other along %" PetscInt_FMT " separate segments, but the pair is listed %" PetscInt_FMT " time%s (interface %" PetscInt_FMT "); list it once per segment", d->path, i, j, ns, m, m > 1 ? "s" : "", first);
      continue;
    }
    for (PetscInt r = 0; r < m; r++) {
      BwListedResult res = {row[r], seg[r]};
      PetscCall(BwPack(&p, BwSplitRank(B, d->size, i), &res, sizeof(res)));
    }
  }
  PetscCall(PetscFree(seg));
  PetscCall(PetscFree(recv));
  {
    PetscErrorCode ierr = BwFaultAgree(d->comm, &f);
    if (ierr) PetscCall(BwPackerDestroy(&p));
    PetscCall(ierr);
  }
  PetscCall(BwPackerExchange(d->comm, &p, &recv, &nrecv, NULL));
  PetscCall(BwPackerDestroy(&p));
  {
    BwListedResult *res = (BwListedResult *)recv;
    PetscInt        m   = (PetscInt)(nrecv / sizeof(BwListedResult));
    PetscCheck(m == n, PETSC_COMM_SELF, PETSC_ERR_PLIB, "%" PetscInt_FMT " listed interfaces came back of %" PetscInt_FMT, m, n);
    qsort(res, (size_t)m, sizeof(BwListedResult), BwListedResultCompare);
    /* the home rows are in row order too */
    for (PetscInt k = 0; k < n; k++) PetscCall(BwGeometryAddInterface(g, d->hpair[2 * k], d->hpair[2 * k + 1], res[k].s.center, res[k].s.angle, res[k].s.length, BW_JOINT_BED));
  }
  PetscCall(PetscFree(recv));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Every block has an interface: the count of each block's interfaces,
 * those of its second blocks sent to their ranks. */
static PetscErrorCode BwFileConnected(BwGeometry g, BwFileData *d, const BwTolerance *tol)
{
  const PetscInt nbl = d->b1 - d->b0;
  PetscInt      *count;
  BwPacker       p;
  char          *recv;
  size_t         nrecv;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(nbl + 1, &count));
  PetscCall(BwPackerCreate(d->comm, &p));
  for (PetscInt k = 0; k < g->ninterfaces; k++) {
    const PetscInt j = g->pair[2 * k + 1];
    count[g->pair[2 * k] - d->b0]++;
    if (j < d->b1) count[j - d->b0]++;
    else PetscCall(BwPack(&p, BwSplitRank(d->nb, d->size, j), &j, sizeof(j)));
  }
  PetscCall(BwPackerExchange(d->comm, &p, &recv, &nrecv, NULL));
  PetscCall(BwPackerDestroy(&p));
  for (size_t q = 0; q < nrecv / sizeof(PetscInt); q++) count[((PetscInt *)recv)[q] - d->b0]++;
  PetscCall(PetscFree(recv));
  {
    PetscErrorCode ierr = BwValidateConnected(d->path, d->comm, d->nb, d->b0, nbl, count, d->has_pairs ? PETSC_FALSE : PETSC_TRUE, tol);
    PetscCall(PetscFree(count));
    PetscCall(ierr);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The 2D share: polygons checked and oriented, the tolerances, overlaps,
 * interfaces, connection. */
static PetscErrorCode BwFileBuild2D(BwGeometry g, BwFileData *d, PetscReal thickness)
{
  const PetscInt nbl = d->b1 - d->b0, v0 = (PetscInt)d->offsets[0], nvl = (PetscInt)(d->offsets[nbl] - v0);
  PetscInt      *off;
  BwTolerance    tol;
  BwFault        f;
  BwBlockView    share, region;
  BwSpatial      sp;
  PetscReal     *box, *ext, h;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(nbl + 1, &off));
  for (PetscInt b = 0; b <= nbl; b++) off[b] = (PetscInt)(d->offsets[b] - v0);
  PetscCall(BwToleranceCompute(d->comm, d->nv, v0, nvl, d->xy, nbl, off, thickness, &tol));
  /* checked and reoriented in place: the raw buffer is ours */
  BwFaultInit(&f);
  for (PetscInt b = 0; b < nbl; b++)
    if (BwFaultCatch(&f, BW_STAGE_GEOMETRY(d) + 1, d->b0 + b, BwValidatePolygon(d->path, d->b0 + b, v0 + off[b], off[b + 1] - off[b], d->xy + 2 * off[b], &tol))) break;
  ierr = BwFaultAgree(d->comm, &f);
  if (ierr) PetscCall(PetscFree(off));
  PetscCall(ierr);
  for (PetscInt b = 0; b < nbl; b++) PetscCall(BwGeometryAddBlock(g, off[b + 1] - off[b], d->xy + 2 * off[b], NULL));
  PetscCall(PetscFree(off));
  PetscCall(PetscFree(d->xy));
  PetscCall(BwGeometryComputeCentroids(g));

  /* the share as a view, each block's box grown by gapmax (validate.h) */
  PetscCall(PetscMemzero(&share, sizeof(share)));
  share.dim     = 2;
  share.n       = nbl;
  share.offsets = g->offsets;
  share.x       = g->vertices;
  share.area    = g->area;
  PetscCall(PetscMalloc4(nbl + 1, &share.gid, 4 * nbl + 1, &share.gbox, 4 * nbl + 1, &box, nbl + 1, &ext));
  PetscCall(BwBlockBoxes(&share, box, NULL, NULL));
  for (PetscInt b = 0; b < nbl; b++) {
    share.gid[b] = d->b0 + b;
    for (int c = 0; c < 2; c++) {
      share.gbox[4 * b + c]     = box[4 * b + c] - tol.gapmax;
      share.gbox[4 * b + 2 + c] = box[4 * b + 2 + c] + tol.gapmax;
    }
    ext[b] = PetscMax(box[4 * b + 2] - box[4 * b], box[4 * b + 3] - box[4 * b + 1]);
  }
  /* the overlap grid's cells: the median block extent of all blocks */
  PetscCall(BwSelectReal(d->comm, nbl, ext, d->nb / 2, &h));
  h    = PetscMax(h, tol.delta);
  ierr = BwGridCheckSpan(d->comm, nbl, BwBoxShape, box, h);
  if (!ierr) ierr = BwSpatialCreate(d->comm, &share, &sp);
  if (!ierr) ierr = BwSpatialExchange(&sp, &share, &region);
  if (!ierr) {
    BwDecideCtx dc = {&sp, &region};
    BwFaultInit(&f);
    ierr = BwValidateOverlaps(d->path, &region, d->nb, &tol, h, d->size > 1 ? BwDecideHere : NULL, &dc, BW_STAGE_GEOMETRY(d) + 2, &f);
    if (!ierr) ierr = BwFaultAgree(d->comm, &f);
    if (!ierr) ierr = d->has_pairs ? BwFileListed2D(g, d, &share, &region, &sp, &tol) : BwFileDetect2D(g, d, &share, &region, &sp, &tol);
    PetscCall(BwBlockViewDestroy(&region));
  }
  PetscCall(PetscFree4(share.gid, share.gbox, box, ext));
  PetscCall(ierr);
  PetscCall(BwFileConnected(g, d, &tol));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ the share */

/* Listed interfaces' ids and stiffnesses, the sets, the depth into g. */
static PetscErrorCode BwFileFinish(BwGeometry g, BwFileData *d)
{
  PetscFunctionBeginUser;
  if (d->has_pairs) {
    PetscCheck(g->ninterfaces == d->nhome, PETSC_COMM_SELF, PETSC_ERR_PLIB, "%" PetscInt_FMT " listed interfaces of %" PetscInt_FMT, g->ninterfaces, d->nhome);
    PetscCall(PetscMalloc1(d->nhome + 1, &g->giface));
    PetscCall(PetscArraycpy(g->giface, d->hrow, d->nhome));
    g->ninterfaces_global = d->ni;
    for (int s = 0; s < 2; s++) {
      PetscReal **to = s ? &g->kt : &g->kn;
      if (!(s ? d->has_kt : d->has_kn)) continue;
      PetscCall(PetscMalloc1(d->nhome + 1, to));
      PetscCall(PetscArraycpy(*to, s ? d->hkt : d->hkn, d->nhome));
    }
  }
  /* every set on every rank, its members here written back in the file's order */
  for (PetscInt s = 0; s < d->nsets; s++) PetscCall(BwGeometryAddSetAt(g, d->setname[s], d->msetoff[s + 1] - d->msetoff[s], d->mblock + d->msetoff[s], d->mpos + d->msetoff[s]));
  if (d->has_depth) g->depth = d->depth;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwFileBuild(BwGeometry g, BwFileData *d, PetscReal thickness)
{
  PetscFunctionBeginUser;
  PetscCall(BwFileReadBlocks(g, d));
  PetscCall(BwFileReadSlabs(d));
  PetscCall(BwFileCheckPairs(d));
  PetscCall(BwFileCheckSets(d));
  PetscCall(BwFileCheckFinite(d));
  if (d->dim == 3) {
    BwShare3D      sh;
    const PetscInt nbl = d->b1 - d->b0;
    PetscInt      *off;
    PetscErrorCode ierr;
    PetscCall(PetscMalloc1(nbl + 1, &off));
    for (PetscInt b = 0; b <= nbl; b++) off[b] = (PetscInt)(d->offsets[b] - d->offsets[0]);
    sh.path      = d->path;
    sh.B         = d->nb;
    sh.b0        = d->b0;
    sh.nb        = nbl;
    sh.vstart    = (PetscInt)d->offsets[0];
    sh.nv_global = d->nv;
    sh.offsets   = off;
    sh.x         = d->xy;
    sh.listed    = d->has_pairs;
    sh.nlisted   = d->nhome;
    sh.rows      = d->hrow;
    sh.pairs     = d->hpair;
    ierr         = BwFileBuild3D(g, &sh, thickness, BW_STAGE_GEOMETRY(d));
    PetscCall(PetscFree(off));
    PetscCall(ierr);
  } else PetscCall(BwFileBuild2D(g, d, thickness));
  PetscCall(BwFileFinish(g, d));
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
  PetscInt             want = g->dim;
  PetscErrorCode       ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&d, sizeof(d)));
  d.file = -1;
  d.comm = g->comm;
  PetscCallMPI(MPI_Comm_rank(d.comm, &d.rank));
  PetscCallMPI(MPI_Comm_size(d.comm, &d.size));
  PetscCall(PetscStrncpy(d.path, o->path, sizeof(d.path)));
  PetscCall(PetscStrncpy(d.where, o->where, sizeof(d.where)));
  /* every error is raised on every rank (the agreements), the file closed */
  ierr = BwFileBuild(g, &d, thickness);
  PetscCall(BwFileDataDestroy(&d));
  PetscCall(ierr);
  /* the file decides the dimension; a scene that says otherwise is wrong */
  if (g->dim_given && want != d.dim) PetscCall(BwSceneError(scene, "-geometry_dimension", "is %" PetscInt_FMT ", but the geometry file '%s' holds %" PetscInt_FMT "D blocks (its /blocks/vertices has %" PetscInt_FMT " columns)", want, o->path, d.dim, d.dim));
  if (d.dim == 3 && g->depth_given) PetscCall(BwSceneError(scene, "-geometry_depth", "has no meaning with a 3D geometry file ('%s'): its blocks have their own thickness", o->path));
  g->dim = d.dim;
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
