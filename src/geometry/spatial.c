/* What the file reader needs to work in parallel and give the serial
 * reader's answer (validate.h): faults agreed by every rank, an exact
 * distributed selection, and the blocks of each region of space brought to
 * one rank.
 *
 * The grid: cells of size h over the global box of every block's grown box,
 * each cell hashed to a rank, h such that the blocks fill about 64 cells
 * per rank (from the summed volume of the grown boxes, not the volume of
 * the global box: a block far from the others does not make the cells of
 * the rest large, and few). With cells much larger than the blocks a block goes to one rank or
 * a few (a box crossing a cell boundary), so a rank receives about 1/size
 * of the blocks, plus the blocks along its cells' boundaries; a block
 * larger than the cells (a foundation under a wall) goes to every rank
 * whose cells it touches, which costs one block per rank. 64 cells per
 * rank keep the ranks' shares within about 1/sqrt(64) = 12 % of each other
 * for a uniform assembly (a random assignment of cells), at the price of
 * more boundary: a 1e5-block wall on 8 ranks has cells of about 14 blocks
 * across, and 15 % of its blocks go to a second rank. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include "geometry/validate.h"
#include "util/compat.h"
#include "util/exchange.h"

#define BW_CELLS_PER_RANK 64

/* ------------------------------------------------------------ faults */

void BwFaultInit(BwFault *f)
{
  f->stage  = INT64_MAX;
  f->index  = INT64_MAX;
  f->code   = PETSC_SUCCESS;
  f->msg[0] = 0;
}

PetscBool BwFaultSet(BwFault *f, int64_t stage, int64_t index, PetscErrorCode code, const char fmt[], ...)
{
  va_list ap;

  if (stage > f->stage || (stage == f->stage && index >= f->index)) return PETSC_TRUE;
  f->stage = stage;
  f->index = index;
  f->code  = code;
  va_start(ap, fmt);
  vsnprintf(f->msg, sizeof(f->msg), fmt, ap);
  va_end(ap);
  return PETSC_TRUE;
}

PetscBool BwFaultCatch(BwFault *f, int64_t stage, int64_t index, PetscErrorCode ierr)
{
  const char *text;

  if (!ierr) return PETSC_FALSE;
  text = BwErrorText(ierr);
  return BwFaultSet(f, stage, index, ierr, "%s", text[0] ? text : "reading the geometry file failed");
}

PetscErrorCode BwFaultAgree(MPI_Comm comm, BwFault *f)
{
  int64_t     key, first[2];
  PetscMPIInt rank, mine, who;
  int         code;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Allreduce(&f->stage, &first[0], 1, MPI_INT64_T, MPI_MIN, comm));
  if (first[0] == INT64_MAX) PetscFunctionReturn(PETSC_SUCCESS);
  key = f->stage == first[0] ? f->index : INT64_MAX;
  PetscCallMPI(MPI_Allreduce(&key, &first[1], 1, MPI_INT64_T, MPI_MIN, comm));
  mine = f->stage == first[0] && f->index == first[1] ? rank : PETSC_MPI_INT_MAX;
  PetscCallMPI(MPI_Allreduce(&mine, &who, 1, MPI_INT, MPI_MIN, comm));
  code = (int)f->code;
  PetscCallMPI(MPI_Bcast(&code, 1, MPI_INT, who, comm));
  PetscCallMPI(MPI_Bcast(f->msg, sizeof(f->msg), MPI_CHAR, who, comm));
  SETERRQ(comm, (PetscErrorCode)code, "%s", f->msg);
}

/* ------------------------------------------------------------ selection */

/* The bits of a double as an unsigned integer of the same order. */
static uint64_t BwRealKey(PetscReal x)
{
  uint64_t u;
  memcpy(&u, &x, sizeof(u));
  return u >> 63 ? ~u : u | (1ULL << 63);
}

static PetscReal BwRealUnkey(uint64_t u)
{
  PetscReal x;
  u = u >> 63 ? u & ~(1ULL << 63) : ~u;
  memcpy(&x, &u, sizeof(x));
  return x;
}

PetscErrorCode BwSelectReal(MPI_Comm comm, PetscInt n, const PetscReal v[], int64_t k, PetscReal *value)
{
  uint64_t prefix = 0, mask = 0;

  PetscFunctionBeginUser;
  for (int shift = 56; shift >= 0; shift -= 8) {
    int64_t count[256] = {0}, total[256];
    int     digit = 0;
    for (PetscInt q = 0; q < n; q++) {
      uint64_t u = BwRealKey(v[q]);
      if ((u & mask) == prefix) count[(u >> shift) & 255]++;
    }
    PetscCallMPI(MPI_Allreduce(count, total, 256, MPI_INT64_T, MPI_SUM, comm));
    while (digit < 255 && k >= total[digit]) k -= total[digit++];
    prefix |= (uint64_t)digit << shift;
    mask |= (uint64_t)255 << shift;
  }
  *value = BwRealUnkey(prefix);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscMPIInt BwSplitRank(PetscInt N, PetscMPIInt size, PetscInt id)
{
  PetscMPIInt r = (PetscMPIInt)(((PetscInt64)id * size) / PetscMax(N, 1));
  /* BwGeometrySplit's rounding: rank r starts at floor(N r / size) */
  while (r > 0 && ((PetscInt64)N * r) / size > id) r--;
  while (r + 1 < size && ((PetscInt64)N * (r + 1)) / size <= id) r++;
  return r;
}

/* ------------------------------------------------------------ the grid */

PetscErrorCode BwSpatialCreate(MPI_Comm comm, const BwBlockView *share, BwSpatial *s)
{
  const PetscInt d = share->dim;
  PetscReal      lo[3] = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[3] = {PETSC_MIN_REAL, PETSC_MIN_REAL, PETSC_MIN_REAL}, glo[3], ghi[3];
  PetscReal      vol = 0, gvol, ext = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(s, sizeof(*s)));
  s->comm = comm;
  s->dim  = d;
  PetscCallMPI(MPI_Comm_size(comm, &s->size));
  PetscCallMPI(MPI_Comm_rank(comm, &s->rank));
  for (PetscInt b = 0; b < share->n; b++) {
    PetscReal v = 1;
    for (PetscInt c = 0; c < d; c++) {
      lo[c] = PetscMin(lo[c], share->gbox[2 * d * b + c]);
      hi[c] = PetscMax(hi[c], share->gbox[2 * d * b + d + c]);
      v *= share->gbox[2 * d * b + d + c] - share->gbox[2 * d * b + c];
    }
    vol += v;
  }
  PetscCallMPI(MPIU_Allreduce(lo, glo, (PetscMPIInt)d, MPIU_REAL, MPIU_MIN, comm));
  PetscCallMPI(MPIU_Allreduce(hi, ghi, (PetscMPIInt)d, MPIU_REAL, MPIU_MAX, comm));
  PetscCallMPI(MPIU_Allreduce(&vol, &gvol, 1, MPIU_REAL, MPIU_SUM, comm));
  for (PetscInt c = 0; c < d; c++) {
    s->x0[c] = glo[c];
    ext      = PetscMax(ext, ghi[c] - glo[c]);
  }
  s->h = PetscPowReal(gvol / (BW_CELLS_PER_RANK * (PetscReal)s->size), 1 / (PetscReal)d);
  /* at most 1e6 cells along an axis: cell indices stay small integers */
  s->h = PetscMax(s->h, 1e-6 * ext);
  if (!(s->h > 0) || PetscIsInfOrNanReal(s->h)) s->h = ext > 0 && !PetscIsInfOrNanReal(ext) ? ext : 1;
  /* every rank must use the same cells, to the bit: rank 0's h (MPI does
   * not promise a floating-point sum the same last bit on every rank; the
   * bounds, minima and maxima, are exact) */
  PetscCallMPI(MPI_Bcast(&s->h, 1, MPIU_REAL, 0, comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static inline int64_t BwSpatialCell(const BwSpatial *s, PetscInt c, PetscReal x) { return (int64_t)PetscFloorReal((x - s->x0[c]) / s->h); }

static PetscMPIInt BwSpatialCellRank(const BwSpatial *s, const int64_t cell[3])
{
  uint64_t z = (uint64_t)cell[0] * 0x9E3779B97F4A7C15ULL ^ (uint64_t)cell[1] * 0xC2B2AE3D27D4EB4FULL ^ (uint64_t)cell[2] * 0x165667B19E3779F9ULL;
  z ^= z >> 31;
  z *= 0xBF58476D1CE4E5B9ULL;
  z ^= z >> 29;
  z *= 0x94D049BB133111EBULL;
  z ^= z >> 32;
  return (PetscMPIInt)(z % (uint64_t)s->size);
}

PetscMPIInt BwSpatialDecider(const BwSpatial *s, const PetscReal a[], const PetscReal b[])
{
  const PetscInt d       = s->dim;
  int64_t        cell[3] = {0, 0, 0};

  if (s->size == 1) return 0;
  for (PetscInt c = 0; c < d; c++) {
    /* the corner is one of the two lower bounds itself: its cell lies in
     * the range of cells each box was sent to */
    PetscReal corner = PetscMax(a[c], b[c]);
    if (corner > PetscMin(a[d + c], b[d + c])) return -1;
    cell[c] = BwSpatialCell(s, c, corner);
  }
  return BwSpatialCellRank(s, cell);
}

PetscBool BwDecideHere(void *ctx, PetscInt i, PetscInt j)
{
  const BwDecideCtx *c = (const BwDecideCtx *)ctx;
  const PetscInt     d = c->v->dim;
  return BwSpatialDecider(c->s, c->v->gbox + 2 * d * i, c->v->gbox + 2 * d * j) == c->s->rank ? PETSC_TRUE : PETSC_FALSE;
}

/* ------------------------------------------------------------ exchange */

typedef struct {
  PetscInt gid, nv, nfaces, nfv;
} BwBlockRecord;

static PetscErrorCode BwPackBlockRecord(const BwBlockView *v, PetscInt b, BwPacker *p, PetscMPIInt dest)
{
  const PetscInt d = v->dim, o = v->offsets[b];
  BwBlockRecord  h = {v->gid[b], v->offsets[b + 1] - o, 0, 0};

  PetscFunctionBeginUser;
  if (d == 3) {
    h.nfaces = v->P[b].nfaces;
    h.nfv    = v->P[b].face_offsets[h.nfaces];
  }
  PetscCall(BwPack(p, dest, &h, sizeof(h)));
  PetscCall(BwPack(p, dest, v->gbox + 2 * d * b, sizeof(PetscReal) * 2 * d));
  PetscCall(BwPack(p, dest, v->x + d * o, sizeof(PetscReal) * d * h.nv));
  if (d == 2) PetscCall(BwPack(p, dest, v->area + b, sizeof(PetscReal)));
  else {
    const BwPolyhedron *P = &v->P[b];
    PetscCall(BwPack(p, dest, &P->volume, sizeof(PetscReal)));
    PetscCall(BwPack(p, dest, P->centroid, sizeof(PetscReal) * 3));
    PetscCall(BwPack(p, dest, P->normal, sizeof(PetscReal) * 4 * h.nfaces));
    PetscCall(BwPack(p, dest, P->face_offsets, sizeof(PetscInt) * (h.nfaces + 1)));
    PetscCall(BwPack(p, dest, P->face_vertices, sizeof(PetscInt) * h.nfv));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static size_t BwBlockRecordSize(PetscInt d, const BwBlockRecord *h)
{
  size_t n = sizeof(*h) + sizeof(PetscReal) * (size_t)(2 * d + d * h->nv);
  if (d == 2) return n + sizeof(PetscReal);
  return n + sizeof(PetscReal) * (size_t)(4 + 4 * h->nfaces) + sizeof(PetscInt) * (size_t)(h->nfaces + 1 + h->nfv);
}

typedef struct {
  PetscInt    gid;
  const char *at;
} BwRecordAt;

static int BwRecordAtCompare(const void *x, const void *y)
{
  const BwRecordAt *a = (const BwRecordAt *)x, *b = (const BwRecordAt *)y;
  return (a->gid > b->gid) - (a->gid < b->gid);
}

/* The ranks of the cells block b's grown box touches, into ranks[] (*n of
 * them); mark[] (size entries, all -1 on entry and on return) dedupes. */
static void BwSpatialRanks(const BwSpatial *s, const PetscReal gbox[], PetscMPIInt mark[], PetscMPIInt ranks[], PetscMPIInt *n)
{
  const PetscInt d = s->dim;
  int64_t        lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, count = 1;

  *n = 0;
  for (PetscInt c = 0; c < d; c++) {
    lo[c] = BwSpatialCell(s, c, gbox[c]);
    hi[c] = BwSpatialCell(s, c, gbox[d + c]);
    count *= hi[c] - lo[c] + 1;
    if (count > 4 * (int64_t)s->size) break;
  }
  if (count > 4 * (int64_t)s->size) {
    /* more cells than 4 per rank: nearly every rank holds one of them */
    for (PetscMPIInt r = 0; r < s->size; r++) ranks[(*n)++] = r;
    return;
  }
  for (int64_t i = lo[0]; i <= hi[0]; i++)
    for (int64_t j = lo[1]; j <= hi[1]; j++)
      for (int64_t k = lo[2]; k <= hi[2]; k++) {
        int64_t     cell[3] = {i, j, k};
        PetscMPIInt r       = BwSpatialCellRank(s, cell);
        if (mark[r] >= 0) continue;
        mark[r]       = 1;
        ranks[(*n)++] = r;
      }
  for (PetscMPIInt q = 0; q < *n; q++) mark[ranks[q]] = -1;
}

PetscErrorCode BwSpatialExchange(const BwSpatial *s, const BwBlockView *share, BwBlockView *region)
{
  const PetscInt d = share->dim;
  BwPacker       p;
  char          *recv;
  size_t         nrecv;
  PetscMPIInt   *mark, *ranks, nr;
  BwRecordAt    *at = NULL;
  PetscInt       n = 0, cap = 0, nv = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(region, sizeof(*region)));
  if (s->size == 1) {
    *region          = *share;
    region->borrowed = PETSC_TRUE;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(BwPackerCreate(s->comm, &p));
  PetscCall(PetscMalloc2(s->size, &mark, s->size, &ranks));
  for (PetscMPIInt r = 0; r < s->size; r++) mark[r] = -1;
  for (PetscInt b = 0; b < share->n; b++) {
    BwSpatialRanks(s, share->gbox + 2 * d * b, mark, ranks, &nr);
    for (PetscMPIInt q = 0; q < nr; q++) PetscCall(BwPackBlockRecord(share, b, &p, ranks[q]));
  }
  PetscCall(PetscFree2(mark, ranks));
  PetscCall(BwPackerExchange(s->comm, &p, &recv, &nrecv, NULL));
  PetscCall(BwPackerDestroy(&p));
  for (const char *c = recv; c < recv + nrecv;) {
    BwBlockRecord h;
    memcpy(&h, c, sizeof(h));
    if (n == cap) {
      cap = PetscMax(2 * cap, 256);
      PetscCall(PetscRealloc(sizeof(BwRecordAt) * (size_t)cap, &at));
    }
    at[n].gid  = h.gid;
    at[n++].at = c;
    nv += h.nv;
    c += BwBlockRecordSize(d, &h);
  }
  qsort(at, (size_t)n, sizeof(BwRecordAt), BwRecordAtCompare);
  region->dim = d;
  region->n   = n;
  PetscCall(PetscMalloc1(n + 1, &region->gid));
  PetscCall(PetscMalloc1(n + 1, &region->offsets));
  PetscCall(PetscMalloc1(d * nv + 1, &region->x));
  PetscCall(PetscMalloc1(2 * d * n + 1, &region->gbox));
  if (d == 2) PetscCall(PetscMalloc1(n + 1, &region->area));
  else PetscCall(PetscCalloc1(n + 1, &region->P));
  region->offsets[0] = 0;
  for (PetscInt b = 0; b < n; b++) {
    const char   *c = at[b].at;
    BwBlockRecord h;
    BwUnpack(&c, &h, sizeof(h));
    region->gid[b]         = h.gid;
    region->offsets[b + 1] = region->offsets[b] + h.nv;
    BwUnpack(&c, region->gbox + 2 * d * b, sizeof(PetscReal) * 2 * d);
    BwUnpack(&c, region->x + d * region->offsets[b], sizeof(PetscReal) * d * h.nv);
    if (d == 2) BwUnpack(&c, region->area + b, sizeof(PetscReal));
    else {
      BwPolyhedron *P = &region->P[b];
      P->nfaces       = h.nfaces;
      BwUnpack(&c, &P->volume, sizeof(PetscReal));
      BwUnpack(&c, P->centroid, sizeof(PetscReal) * 3);
      PetscCall(PetscMalloc1(4 * h.nfaces + 1, &P->normal));
      PetscCall(PetscMalloc1(h.nfaces + 1, &P->face_offsets));
      PetscCall(PetscMalloc1(h.nfv + 1, &P->face_vertices));
      BwUnpack(&c, P->normal, sizeof(PetscReal) * 4 * h.nfaces);
      BwUnpack(&c, P->face_offsets, sizeof(PetscInt) * (h.nfaces + 1));
      BwUnpack(&c, P->face_vertices, sizeof(PetscInt) * h.nfv);
    }
  }
  PetscCall(PetscFree(at));
  PetscCall(PetscFree(recv));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwBlockViewDestroy(BwBlockView *v)
{
  PetscFunctionBeginUser;
  if (!v->borrowed) {
    PetscCall(PetscFree(v->gid));
    PetscCall(PetscFree(v->offsets));
    PetscCall(PetscFree(v->x));
    PetscCall(PetscFree(v->gbox));
    PetscCall(PetscFree(v->area));
    if (v->P)
      for (PetscInt b = 0; b < v->n; b++) PetscCall(BwPolyhedronDestroy(&v->P[b]));
    PetscCall(PetscFree(v->P));
  }
  PetscCall(PetscMemzero(v, sizeof(*v)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ listed pairs */

static PetscErrorCode BwGrownBoxAnswer(void *ctx, PetscInt gid, void *ans)
{
  const BwBlockView *v = (const BwBlockView *)ctx;
  const PetscInt     d = v->dim;

  PetscFunctionBeginUser;
  PetscCheck(v->n > 0 && gid >= v->gid[0] && gid <= v->gid[v->n - 1], PETSC_COMM_SELF, PETSC_ERR_PLIB, "block %" PetscInt_FMT " asked of a rank whose share does not hold it", gid);
  PetscCall(PetscArraycpy((PetscReal *)ans, v->gbox + 2 * d * (gid - v->gid[0]), 2 * d));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwListedDeciders(MPI_Comm comm, const BwBlockView *share, const BwSpatial *s, PetscInt B, PetscInt n, const PetscInt pairs[], PetscMPIInt decider[])
{
  const PetscInt d = share->dim;
  PetscMPIInt   *dest;
  PetscInt      *key;
  PetscReal     *box;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc3(n + 1, &dest, n + 1, &key, 2 * d * n + 1, &box));
  for (PetscInt k = 0; k < n; k++) {
    key[k]  = pairs[2 * k + 1];
    dest[k] = BwSplitRank(B, s->size, key[k]);
  }
  PetscCall(BwQueryBytes(comm, n, dest, key, sizeof(PetscReal) * 2 * d, BwGrownBoxAnswer, (void *)share, box));
  for (PetscInt k = 0; k < n; k++) decider[k] = BwSpatialDecider(s, share->gbox + 2 * d * (pairs[2 * k] - share->gid[0]), box + 2 * d * k);
  PetscCall(PetscFree3(dest, key, box));
  PetscFunctionReturn(PETSC_SUCCESS);
}
