/* BwGeometryDistribute: from the generators' D0 shares to each rank's local
 * piece (geometry.h).
 *
 *   1. global numbering: vertex rows, interface ids, polygon rows and set
 *      positions by exclusive scans over the D0 shares (each rank's share is
 *      a contiguous range of block ids, so rank order is id order);
 *   2. the partition: the block graph of the D0 shares (each block's row:
 *      its neighbours across the interfaces homed at it and, sent back by
 *      their homes, those whose interfaces it is the second block of) cut
 *      by PETSc's MatPartitioning (PT-Scotch in Debian's PETSc), weighted
 *      by 1 + each block's interfaces; or `natural`: the D0 share itself;
 *   3. the moves, each a pair of all-to-all exchanges: a block goes to its
 *      new owner and, as a ghost, to the owners of its neighbours across an
 *      interface; an interface goes to the owners of its two blocks;
 *   4. local indices: owned blocks, then ghosts, each ascending in global
 *      id; interfaces ascending; each ghost's index on its owner.
 *
 * Nothing here is of the whole assembly's size: the arrays are of the D0
 * share, of the local piece, or of the number of ranks. One rank keeps its
 * share as its piece (identity maps, no exchange). */
#include <string.h>
#include <petscmat.h>
#include "geometry/geometry.h"
#include "util/compat.h"
#include "util/exchange.h"

const char *const BwPartitionMethods[] = {"auto", "natural", "graph", "BwPartitionMethod", "BW_PARTITION_", NULL};

/* ------------------------------------------------------------ exchanges */

/* The rank whose D0 share holds global block gid (start[]: every rank's
 * first id, size + 1 entries). */
static PetscMPIInt BwRangeOwner(const PetscInt start[], PetscMPIInt size, PetscInt gid)
{
  PetscMPIInt lo = 0, hi = size;
  while (hi - lo > 1) {
    PetscMPIInt mid = (lo + hi) / 2;
    if (start[mid] <= gid) lo = mid;
    else hi = mid;
  }
  return lo;
}

/* The value the D0 share of a block holds for it (BwQuery's answer). */
typedef struct {
  PetscInt        start;
  const PetscInt *owned;
} BwShareValue;

static PetscErrorCode BwShareAnswer(void *ctx, PetscInt gid, PetscInt ans[])
{
  BwShareValue *v = (BwShareValue *)ctx;
  ans[0]          = v->owned[gid - v->start];
  return PETSC_SUCCESS;
}

/* values[q] = owned[] of block gids[q] on the rank whose D0 share holds it. */
static PetscErrorCode BwQueryBlocks(BwGeometry g, const PetscInt start[], PetscInt n, const PetscInt gids[], const PetscInt owned[], PetscInt values[])
{
  PetscMPIInt *dest, size;
  BwShareValue v = {g->block_start, owned};

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(g->comm, &size));
  PetscCall(PetscMalloc1(n + 1, &dest));
  for (PetscInt q = 0; q < n; q++) dest[q] = BwRangeOwner(start, size, gids[q]);
  PetscCall(BwQuery(g->comm, n, dest, gids, 1, BwShareAnswer, &v, values));
  PetscCall(PetscFree(dest));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ numbering */

/* Global interface ids (where the generator gave none), the global first
 * vertex row of each block, of each interface polygon (3D), and every set
 * member's row in its set's list. */
static PetscErrorCode BwNumberD0(BwGeometry g, PetscInt **gvoff, PetscInt **gpoly)
{
  PetscInt    n = g->ninterfaces, start = 0, nvloc = g->offsets[g->nblocks], vstart = 0;
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(g->comm, &rank));
  PetscCallMPI(MPIU_Allreduce(&nvloc, &g->nvertices_global, 1, MPIU_INT, MPI_SUM, g->comm));
  PetscCallMPI(MPI_Exscan(&nvloc, &vstart, 1, MPIU_INT, MPI_SUM, g->comm));
  if (!rank) vstart = 0;
  PetscCall(PetscMalloc1(g->nblocks + 1, gvoff));
  for (PetscInt b = 0; b < g->nblocks; b++) (*gvoff)[b] = vstart + g->offsets[b];
  if (!g->giface) {
    PetscCallMPI(MPI_Exscan(&n, &start, 1, MPIU_INT, MPI_SUM, g->comm));
    if (!rank) start = 0;
    PetscCall(PetscMalloc1(n + 1, &g->giface));
    for (PetscInt k = 0; k < n; k++) g->giface[k] = start + k;
    PetscCallMPI(MPIU_Allreduce(&n, &g->ninterfaces_global, 1, MPIU_INT, MPI_SUM, g->comm));
  }
  *gpoly = NULL;
  if (g->dim == 3) {
    /* the polygons' rows in interface id order (a file's listed interfaces
     * are spread over the shares in any order) */
    PetscInt *cnt;
    PetscCall(PetscMalloc1(n + 1, gpoly));
    PetscCall(PetscMalloc1(n + 1, &cnt));
    for (PetscInt k = 0; k < n; k++) cnt[k] = g->poly_offsets[k + 1] - g->poly_offsets[k];
    PetscCall(BwRaggedOffsets(g->comm, n, g->giface, cnt, g->ninterfaces_global, *gpoly, &g->npolyvertices_global));
    PetscCall(PetscFree(cnt));
  }
  /* sets: members without a given row take ascending global ids */
  {
    PetscInt *count, *first;
    PetscCall(PetscCalloc2(g->nsets + 1, &count, g->nsets + 1, &first));
    PetscCall(PetscMalloc1(g->nsets + 1, &g->setsize_global));
    for (PetscInt s = 0; s < g->nsets; s++) {
      PetscInt o = g->setoffsets[s], m = g->setoffsets[s + 1] - o;
      count[s] = m;
      /* ascending: sort the members of the range, their positions follow */
      if (m && g->setpos[o] < 0) PetscCall(PetscSortInt(m, g->setblocks + o));
    }
    PetscCallMPI(MPIU_Allreduce(count, g->setsize_global, (PetscMPIInt)g->nsets, MPIU_INT, MPI_SUM, g->comm));
    PetscCallMPI(MPI_Exscan(count, first, (PetscMPIInt)g->nsets, MPIU_INT, MPI_SUM, g->comm));
    if (!rank) PetscCall(PetscArrayzero(first, g->nsets));
    for (PetscInt s = 0; s < g->nsets; s++)
      for (PetscInt q = g->setoffsets[s]; q < g->setoffsets[s + 1]; q++)
        if (g->setpos[q] < 0) g->setpos[q] = first[s] + (q - g->setoffsets[s]);
    PetscCall(PetscFree2(count, first));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ partition */

/* The new owner of each block of the D0 share. */
static PetscErrorCode BwPartitionD0(BwGeometry g, const PetscInt start[], BwPartitionMethod method, PetscMPIInt owner[])
{
  PetscMPIInt rank, size;
  PetscInt    nb = g->nblocks, ni = g->ninterfaces, *deg, *ia, *ja, *w, nrev = 0;
  PetscInt   *rev = NULL;
  BwPacker    p;
  char       *recv;
  size_t      nrecv;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(g->comm, &rank));
  PetscCallMPI(MPI_Comm_size(g->comm, &size));
  if (method == BW_PARTITION_NATURAL || g->nblocks_global < size) {
    for (PetscInt b = 0; b < nb; b++) owner[b] = rank;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  /* the other half of each edge: (j, i) to j's D0 rank */
  PetscCall(BwPackerCreate(g->comm, &p));
  for (PetscInt k = 0; k < ni; k++) {
    PetscInt rec[2] = {g->pair[2 * k + 1], g->pair[2 * k]};
    PetscCall(BwPack(&p, BwRangeOwner(start, size, rec[0]), rec, sizeof(rec)));
  }
  PetscCall(BwPackerExchange(g->comm, &p, &recv, &nrecv, NULL));
  PetscCall(BwPackerDestroy(&p));
  nrev = (PetscInt)(nrecv / (2 * sizeof(PetscInt)));
  rev  = (PetscInt *)recv;
  /* rows: CSR, then sorted and made unique (several interfaces between one
   * pair of blocks are one edge) */
  PetscCall(PetscCalloc1(nb + 1, &deg));
  for (PetscInt k = 0; k < ni; k++) deg[g->pair[2 * k] - g->block_start + 1]++;
  for (PetscInt e = 0; e < nrev; e++) deg[rev[2 * e] - g->block_start + 1]++;
  for (PetscInt b = 0; b < nb; b++) deg[b + 1] += deg[b];
  /* MatCreateMPIAdj takes ia, ja (and the weights) with PetscMalloc and frees them */
  PetscCall(PetscMalloc1(nb + 1, &ia));
  PetscCall(PetscMalloc1(deg[nb] + 1, &ja));
  PetscCall(PetscMalloc1(nb + 1, &w));
  {
    PetscInt *fill;
    PetscCall(PetscMalloc1(nb + 1, &fill));
    PetscCall(PetscArraycpy(fill, deg, nb + 1));
    for (PetscInt k = 0; k < ni; k++) ja[fill[g->pair[2 * k] - g->block_start]++] = g->pair[2 * k + 1];
    for (PetscInt e = 0; e < nrev; e++) ja[fill[rev[2 * e] - g->block_start]++] = rev[2 * e + 1];
    PetscCall(PetscFree(fill));
  }
  ia[0] = 0;
  for (PetscInt b = 0, n = 0; b < nb; b++) {
    PetscInt m = deg[b + 1] - deg[b], u;
    PetscCall(PetscSortInt(m, ja + deg[b]));
    u = 0;
    for (PetscInt e = 0; e < m; e++)
      if (!u || ja[deg[b] + e] != ja[n + u - 1]) ja[n + u++] = ja[deg[b] + e];
    /* the work a block brings: itself and its interfaces' rows */
    w[b] = 1 + m;
    n += u;
    ia[b + 1] = n;
  }
  PetscCall(PetscFree(deg));
  PetscCall(PetscFree(recv));
  {
    Mat             adj;
    MatPartitioning part;
    IS              is;
    const PetscInt *where;
    PetscCall(MatCreateMPIAdj(g->comm, nb, g->nblocks_global, ia, ja, NULL, &adj));
    PetscCall(MatPartitioningCreate(g->comm, &part));
    PetscCall(PetscObjectSetOptionsPrefix((PetscObject)part, "partition_"));
    PetscCall(MatPartitioningSetAdjacency(part, adj));
    PetscCall(MatPartitioningSetVertexWeights(part, w));
#if defined(PETSC_HAVE_PTSCOTCH)
    PetscCall(MatPartitioningSetType(part, MATPARTITIONINGPTSCOTCH));
#elif defined(PETSC_HAVE_PARMETIS)
    PetscCall(MatPartitioningSetType(part, MATPARTITIONINGPARMETIS));
#endif
    PetscCall(MatPartitioningSetFromOptions(part));
    PetscCall(MatPartitioningApply(part, &is));
    g->partitioned = PETSC_TRUE;
    PetscCall(ISGetIndices(is, &where));
    for (PetscInt b = 0; b < nb; b++) owner[b] = (PetscMPIInt)where[b];
    PetscCall(ISRestoreIndices(is, &where));
    PetscCall(ISDestroy(&is));
    PetscCall(MatPartitioningDestroy(&part));
    PetscCall(MatDestroy(&adj));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ moves */

/* The record of a block: header, then its data. */
typedef struct {
  PetscInt    gid, gvoff, nv, nfaces, nfacev, nsets;
  PetscMPIInt owner, pad;
} BwBlockHead;

typedef struct {
  PetscInt gid, i, j, kind, npoly, gpoly;
} BwInterfaceHead;

static PetscErrorCode BwPackBlock(BwGeometry g, BwPacker *p, PetscMPIInt dest, PetscInt b, PetscMPIInt owner, const PetscInt gvoff[], const PetscInt *memb, const PetscInt *mset, const PetscInt *mpos)
{
  const PetscInt d = g->dim, o = g->offsets[b], nv = g->offsets[b + 1] - o;
  BwBlockHead    h;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&h, sizeof(h)));
  h.gid   = g->block_start + b;
  h.gvoff = gvoff[b];
  h.nv    = nv;
  h.owner = owner;
  h.nsets = memb[b + 1] - memb[b];
  if (d == 3) {
    h.nfaces = g->face_offsets[b + 1] - g->face_offsets[b];
    h.nfacev = g->face_voffsets[g->face_offsets[b + 1]] - g->face_voffsets[g->face_offsets[b]];
  }
  PetscCall(BwPack(p, dest, &h, sizeof(h)));
  PetscCall(BwPack(p, dest, g->centroid + d * b, sizeof(PetscReal) * d));
  PetscCall(BwPack(p, dest, d == 3 ? g->volume + b : g->area + b, sizeof(PetscReal)));
  PetscCall(BwPack(p, dest, g->vertices + d * o, sizeof(PetscReal) * d * nv));
  if (d == 3) {
    /* faces: each face's vertex count, then its vertices relative to the block */
    for (PetscInt f = g->face_offsets[b]; f < g->face_offsets[b + 1]; f++) {
      PetscInt n = g->face_voffsets[f + 1] - g->face_voffsets[f];
      PetscCall(BwPack(p, dest, &n, sizeof(n)));
    }
    for (PetscInt f = g->face_offsets[b]; f < g->face_offsets[b + 1]; f++)
      for (PetscInt v = g->face_voffsets[f]; v < g->face_voffsets[f + 1]; v++) {
        PetscInt rel = g->face_vertices[v] - o;
        PetscCall(BwPack(p, dest, &rel, sizeof(rel)));
      }
  }
  for (PetscInt m = memb[b]; m < memb[b + 1]; m++) {
    PetscInt sp[2] = {mset[m], owner == dest ? mpos[m] : -1};
    PetscCall(BwPack(p, dest, sp, sizeof(sp)));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwPackInterface(BwGeometry g, BwPacker *p, PetscMPIInt dest, PetscInt k, const PetscInt gpoly[], int stiff)
{
  const PetscInt  d = g->dim;
  BwInterfaceHead h;

  PetscFunctionBeginUser;
  h.gid   = g->giface[k];
  h.i     = g->pair[2 * k];
  h.j     = g->pair[2 * k + 1];
  h.kind  = (PetscInt)g->kind[k];
  h.npoly = d == 3 ? g->poly_offsets[k + 1] - g->poly_offsets[k] : 0;
  h.gpoly = d == 3 ? gpoly[k] : 0;
  PetscCall(BwPack(p, dest, &h, sizeof(h)));
  PetscCall(BwPack(p, dest, g->center + d * k, sizeof(PetscReal) * d));
  if (d == 3) {
    PetscCall(BwPack(p, dest, g->frame + 9 * k, sizeof(PetscReal) * 9));
    PetscCall(BwPack(p, dest, g->iarea + k, sizeof(PetscReal)));
    PetscCall(BwPack(p, dest, g->poly + 3 * g->poly_offsets[k], sizeof(PetscReal) * 3 * h.npoly));
  } else {
    PetscCall(BwPack(p, dest, g->angle + k, sizeof(PetscReal)));
    PetscCall(BwPack(p, dest, g->length + k, sizeof(PetscReal)));
  }
  if (stiff) {
    PetscReal kk[2] = {g->kn ? g->kn[k] : 0, g->kt ? g->kt[k] : 0};
    PetscCall(BwPack(p, dest, kk, sizeof(kk)));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* What arrived, unpacked into the geometry's arrays (the D0 share's are
 * freed first). */
typedef struct {
  const char *at;
  PetscInt    gid;
  PetscMPIInt owner;
} BwArrived;

static int BwPairCompare(const void *x, const void *y)
{
  const PetscInt *a = x, *b = y;
  if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
  return (a[1] > b[1]) - (a[1] < b[1]);
}

static int BwArrivedCompare(const void *x, const void *y)
{
  const BwArrived *a = x, *b = y;
  return (a->gid > b->gid) - (a->gid < b->gid);
}

static PetscErrorCode BwFreeShare(BwGeometry g)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(g->offsets));
  PetscCall(PetscFree(g->vertices));
  PetscCall(PetscFree(g->centroid));
  PetscCall(PetscFree(g->area));
  PetscCall(PetscFree(g->volume));
  PetscCall(PetscFree(g->face_offsets));
  PetscCall(PetscFree(g->face_voffsets));
  PetscCall(PetscFree(g->face_vertices));
  PetscCall(PetscFree(g->pair));
  PetscCall(PetscFree(g->center));
  PetscCall(PetscFree(g->angle));
  PetscCall(PetscFree(g->length));
  PetscCall(PetscFree(g->kind));
  PetscCall(PetscFree(g->kn));
  PetscCall(PetscFree(g->kt));
  PetscCall(PetscFree(g->frame));
  PetscCall(PetscFree(g->iarea));
  PetscCall(PetscFree(g->poly_offsets));
  PetscCall(PetscFree(g->poly));
  PetscCall(PetscFree(g->giface));
  PetscCall(PetscFree(g->setblocks));
  PetscCall(PetscFree(g->setpos));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwUnpackBlocks(BwGeometry g, const char *recv, size_t nrecv, PetscMPIInt rank)
{
  const PetscInt d = g->dim;
  BwArrived     *arr = NULL;
  PetscInt       n = 0, cap = 0, nv = 0, nf = 0, nfv = 0, nm = 0, nown = 0, *mcount;

  PetscFunctionBeginUser;
  for (const char *at = recv; at < recv + nrecv;) {
    BwBlockHead h;
    const char *rec = at;
    BwUnpack(&at, &h, sizeof(h));
    at += sizeof(PetscReal) * (d + 1 + d * h.nv) + sizeof(PetscInt) * (h.nfaces + h.nfacev + 2 * h.nsets);
    if (n == cap) {
      cap = PetscMax(2 * cap, 64);
      PetscCall(PetscRealloc(sizeof(BwArrived) * (size_t)cap, &arr));
    }
    arr[n].at    = rec;
    arr[n].gid   = h.gid;
    arr[n].owner = h.owner;
    n++;
    nv += h.nv;
    nf += h.nfaces;
    nfv += h.nfacev;
    nm += h.nsets;
    if (h.owner == rank) nown++;
  }
  /* owned first, then ghosts, each ascending */
  {
    BwArrived *sorted;
    PetscInt   io = 0, ig = nown;
    PetscCall(PetscMalloc1(n + 1, &sorted));
    for (PetscInt q = 0; q < n; q++) sorted[arr[q].owner == rank ? io++ : ig++] = arr[q];
    qsort(sorted, (size_t)nown, sizeof(BwArrived), BwArrivedCompare);
    qsort(sorted + nown, (size_t)(n - nown), sizeof(BwArrived), BwArrivedCompare);
    PetscCall(PetscFree(arr));
    arr = sorted;
  }
  g->nblocks     = n;
  g->nown_blocks = nown;
  g->nvertices   = nv;
  g->maxblocks   = n;
  g->maxvertices = nv;
  PetscCall(PetscMalloc1(n + 1, &g->offsets));
  PetscCall(PetscMalloc1(d * nv + 1, &g->vertices));
  PetscCall(PetscMalloc1(d * n + 1, &g->centroid));
  if (d == 3) {
    PetscCall(PetscMalloc1(n + 1, &g->volume));
    PetscCall(PetscMalloc1(n + 1, &g->face_offsets));
    PetscCall(PetscMalloc1(nf + 1, &g->face_voffsets));
    PetscCall(PetscMalloc1(nfv + 1, &g->face_vertices));
    g->face_offsets[0] = g->face_voffsets[0] = 0;
  } else PetscCall(PetscMalloc1(n + 1, &g->area));
  PetscCall(PetscMalloc1(n + 1, &g->gblock));
  PetscCall(PetscMalloc1(n + 1, &g->block_rank));
  PetscCall(PetscMalloc1(n + 1, &g->block_rindex));
  PetscCall(PetscMalloc1(n + 1, &g->gvoffset));
  PetscCall(PetscCalloc1(g->nsets + 1, &mcount));
  g->offsets[0] = 0;
  for (PetscInt b = 0; b < n; b++) {
    const char *at = arr[b].at;
    BwBlockHead h;
    BwUnpack(&at, &h, sizeof(h));
    g->gblock[b]       = h.gid;
    g->block_rank[b]   = h.owner;
    g->block_rindex[b] = -1;
    g->gvoffset[b]     = h.gvoff;
    BwUnpack(&at, g->centroid + d * b, sizeof(PetscReal) * d);
    BwUnpack(&at, d == 3 ? g->volume + b : g->area + b, sizeof(PetscReal));
    BwUnpack(&at, g->vertices + d * g->offsets[b], sizeof(PetscReal) * d * h.nv);
    if (d == 3) {
      PetscInt f0 = g->face_offsets[b];
      for (PetscInt f = 0; f < h.nfaces; f++) {
        PetscInt c;
        BwUnpack(&at, &c, sizeof(c));
        g->face_voffsets[f0 + f + 1] = g->face_voffsets[f0 + f] + c;
      }
      for (PetscInt v = g->face_voffsets[f0]; v < g->face_voffsets[f0 + h.nfaces]; v++) {
        PetscInt rel;
        BwUnpack(&at, &rel, sizeof(rel));
        g->face_vertices[v] = g->offsets[b] + rel;
      }
      g->face_offsets[b + 1] = f0 + h.nfaces;
    }
    for (PetscInt m = 0; m < h.nsets; m++) {
      PetscInt sp[2];
      BwUnpack(&at, sp, sizeof(sp));
      mcount[sp[0] + 1]++;
    }
    g->offsets[b + 1] = g->offsets[b] + h.nv;
  }
  /* sets: members in local index order */
  for (PetscInt s = 0; s < g->nsets; s++) mcount[s + 1] += mcount[s];
  PetscCall(PetscMalloc1(nm + 1, &g->setblocks));
  PetscCall(PetscMalloc1(nm + 1, &g->setpos));
  g->maxsetblocks = nm;
  for (PetscInt s = 0; s <= g->nsets; s++) g->setoffsets[s] = mcount[s];
  for (PetscInt b = 0; b < n; b++) {
    const char *at = arr[b].at;
    BwBlockHead h;
    BwUnpack(&at, &h, sizeof(h));
    at += sizeof(PetscReal) * (d + 1 + d * h.nv) + sizeof(PetscInt) * (h.nfaces + h.nfacev);
    for (PetscInt m = 0; m < h.nsets; m++) {
      PetscInt sp[2];
      BwUnpack(&at, sp, sizeof(sp));
      g->setblocks[mcount[sp[0]]] = b;
      g->setpos[mcount[sp[0]]++]  = sp[1];
    }
  }
  PetscCall(PetscFree(mcount));
  PetscCall(PetscFree(arr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwUnpackInterfaces(BwGeometry g, const char *recv, size_t nrecv, int stiff)
{
  const PetscInt d = g->dim;
  BwArrived     *arr = NULL;
  PetscInt       n = 0, cap = 0, np = 0;

  PetscFunctionBeginUser;
  for (const char *at = recv; at < recv + nrecv;) {
    BwInterfaceHead h;
    const char     *rec = at;
    BwUnpack(&at, &h, sizeof(h));
    at += sizeof(PetscReal) * (d + (d == 3 ? 10 + 3 * h.npoly : 2) + (stiff ? 2 : 0));
    if (n == cap) {
      cap = PetscMax(2 * cap, 64);
      PetscCall(PetscRealloc(sizeof(BwArrived) * (size_t)cap, &arr));
    }
    arr[n].at  = rec;
    arr[n].gid = h.gid;
    n++;
    np += h.npoly;
  }
  qsort(arr, (size_t)n, sizeof(BwArrived), BwArrivedCompare);
  g->ninterfaces   = n;
  g->maxinterfaces = n;
  PetscCall(PetscMalloc1(2 * n + 1, &g->pair));
  PetscCall(PetscMalloc1(n + 1, &g->giface));
  PetscCall(PetscMalloc1(d * n + 1, &g->center));
  PetscCall(PetscMalloc1(n + 1, &g->kind));
  if (d == 3) {
    PetscCall(PetscMalloc1(9 * n + 1, &g->frame));
    PetscCall(PetscMalloc1(n + 1, &g->iarea));
    PetscCall(PetscMalloc1(n + 1, &g->poly_offsets));
    PetscCall(PetscMalloc1(3 * np + 1, &g->poly));
    PetscCall(PetscMalloc1(n + 1, &g->gpoly_offset));
    g->poly_offsets[0] = 0;
  } else {
    PetscCall(PetscMalloc1(n + 1, &g->angle));
    PetscCall(PetscMalloc1(n + 1, &g->length));
  }
  /* only those the generator gave: a missing one is the joint law's */
  if (stiff & 1) PetscCall(PetscMalloc1(n + 1, &g->kn));
  if (stiff & 2) PetscCall(PetscMalloc1(n + 1, &g->kt));
  for (PetscInt k = 0; k < n; k++) {
    const char     *at = arr[k].at;
    BwInterfaceHead h;
    BwUnpack(&at, &h, sizeof(h));
    g->giface[k]       = h.gid;
    g->pair[2 * k]     = BwGeometryLocalBlock(g, h.i);
    g->pair[2 * k + 1] = BwGeometryLocalBlock(g, h.j);
    PetscCheck(g->pair[2 * k] >= 0 && g->pair[2 * k + 1] >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "interface %" PetscInt_FMT " arrived without its blocks %" PetscInt_FMT " and %" PetscInt_FMT, h.gid, h.i, h.j);
    g->kind[k] = (BwJointKind)h.kind;
    BwUnpack(&at, g->center + d * k, sizeof(PetscReal) * d);
    if (d == 3) {
      BwUnpack(&at, g->frame + 9 * k, sizeof(PetscReal) * 9);
      BwUnpack(&at, g->iarea + k, sizeof(PetscReal));
      BwUnpack(&at, g->poly + 3 * g->poly_offsets[k], sizeof(PetscReal) * 3 * h.npoly);
      g->poly_offsets[k + 1] = g->poly_offsets[k] + h.npoly;
      g->gpoly_offset[k]     = h.gpoly;
    } else {
      BwUnpack(&at, g->angle + k, sizeof(PetscReal));
      BwUnpack(&at, g->length + k, sizeof(PetscReal));
    }
    if (stiff) {
      PetscReal kk[2];
      BwUnpack(&at, kk, sizeof(kk));
      if (stiff & 1) g->kn[k] = kk[0];
      if (stiff & 2) g->kt[k] = kk[1];
    }
  }
  PetscCall(PetscFree(arr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Each ghost's index on its owner: its rank among the owner's owned ids. */
static PetscErrorCode BwOwnedIndexAnswer(void *ctx, PetscInt gid, PetscInt ans[])
{
  BwGeometry g = (BwGeometry)ctx;

  PetscFunctionBeginUser;
  PetscCall(PetscFindInt(gid, g->nown_blocks, g->gblock, &ans[0]));
  PetscCheck(ans[0] >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "block %" PetscInt_FMT " asked of a rank that does not own it", gid);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwGhostIndices(BwGeometry g)
{
  const PetscInt nown = g->nown_blocks, ng = g->nblocks - nown;

  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < nown; b++) g->block_rindex[b] = b;
  PetscCall(BwQuery(g->comm, ng, g->block_rank + nown, g->gblock + nown, 1, BwOwnedIndexAnswer, g, g->block_rindex + nown));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* One rank: the share is the piece; the maps are identities. */
static PetscErrorCode BwDistributeOne(BwGeometry g, const PetscInt gvoff[], const PetscInt gpoly[])
{
  const PetscInt n = g->nblocks;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(n + 1, &g->gblock));
  PetscCall(PetscMalloc1(n + 1, &g->block_rank));
  PetscCall(PetscMalloc1(n + 1, &g->block_rindex));
  PetscCall(PetscMalloc1(n + 1, &g->gvoffset));
  for (PetscInt b = 0; b < n; b++) {
    g->gblock[b]       = b;
    g->block_rank[b]   = 0;
    g->block_rindex[b] = b;
    g->gvoffset[b]     = gvoff[b];
  }
  g->nown_blocks = n;
  if (g->dim == 3) {
    PetscCall(PetscMalloc1(g->ninterfaces + 1, &g->gpoly_offset));
    PetscCall(PetscArraycpy(g->gpoly_offset, gpoly, g->ninterfaces));
  }
  /* interfaces in ascending id (a file's listed rows are already; the
   * generators' are numbered in order) */
  for (PetscInt k = 1; k < g->ninterfaces; k++) PetscCheck(g->giface[k] > g->giface[k - 1], PETSC_COMM_SELF, PETSC_ERR_PLIB, "interfaces not in id order");
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeometryDistribute(BwGeometry g, BwPartitionMethod method)
{
  PetscMPIInt  size, rank;
  PetscInt    *gvoff = NULL, *gpoly = NULL, *start, *newowner, *jowner, *memb, *mset, *mpos;
  PetscMPIInt *owner;
  int          stiff = 0, have = (g->kn ? 1 : 0) | (g->kt ? 2 : 0); /* which of kn, kt the generator gave */
  BwPacker     pb, pi;
  char        *recv;
  size_t       nrecv;

  PetscFunctionBeginUser;
  PetscCheck(!g->distributed, g->comm, PETSC_ERR_ORDER, "the geometry is already distributed");
  PetscCallMPI(MPI_Comm_size(g->comm, &size));
  PetscCallMPI(MPI_Comm_rank(g->comm, &rank));
  PetscCall(BwNumberD0(g, &gvoff, &gpoly));
  if (size == 1) {
    PetscCall(BwDistributeOne(g, gvoff, gpoly));
    PetscCall(PetscFree(gvoff));
    PetscCall(PetscFree(gpoly));
    g->distributed = PETSC_TRUE;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCallMPI(MPI_Allreduce(&have, &stiff, 1, MPI_INT, MPI_BOR, g->comm));
  if (method == BW_PARTITION_AUTO) {
#if defined(PETSC_HAVE_PTSCOTCH) || defined(PETSC_HAVE_PARMETIS)
    method = BW_PARTITION_GRAPH;
#else
    method = BW_PARTITION_NATURAL;
#endif
  }
  /* every rank's first block id */
  PetscCall(PetscMalloc1(size + 1, &start));
  {
    PetscInt s = g->block_start;
    PetscCallMPI(MPI_Allgather(&s, 1, MPIU_INT, start, 1, MPIU_INT, g->comm));
    start[size] = g->nblocks_global;
  }
  PetscCall(PetscMalloc1(g->nblocks + 1, &owner));
  PetscCall(BwPartitionD0(g, start, method, owner));
  /* the new owner of every homed interface's second block */
  PetscCall(PetscMalloc2(g->nblocks + 1, &newowner, g->ninterfaces + 1, &jowner));
  for (PetscInt b = 0; b < g->nblocks; b++) newowner[b] = owner[b];
  {
    PetscInt *jgid;
    PetscCall(PetscMalloc1(g->ninterfaces + 1, &jgid));
    for (PetscInt k = 0; k < g->ninterfaces; k++) jgid[k] = g->pair[2 * k + 1];
    PetscCall(BwQueryBlocks(g, start, g->ninterfaces, jgid, newowner, jowner));
    PetscCall(PetscFree(jgid));
  }
  /* set memberships per D0 block: CSR over the share */
  PetscCall(PetscCalloc1(g->nblocks + 1, &memb));
  for (PetscInt q = 0; q < g->setoffsets[g->nsets]; q++) memb[g->setblocks[q] - g->block_start + 1]++;
  for (PetscInt b = 0; b < g->nblocks; b++) memb[b + 1] += memb[b];
  PetscCall(PetscMalloc2(memb[g->nblocks] + 1, &mset, memb[g->nblocks] + 1, &mpos));
  {
    PetscInt *fill;
    PetscCall(PetscMalloc1(g->nblocks + 1, &fill));
    PetscCall(PetscArraycpy(fill, memb, g->nblocks + 1));
    for (PetscInt s = 0; s < g->nsets; s++)
      for (PetscInt q = g->setoffsets[s]; q < g->setoffsets[s + 1]; q++) {
        PetscInt b = g->setblocks[q] - g->block_start;
        mset[fill[b]]   = s;
        mpos[fill[b]++] = g->setpos[q];
      }
    PetscCall(PetscFree(fill));
  }
  /* ghosts: block j to i's new owner (asked of j's D0 rank), block i to j's */
  {
    BwPacker ask;
    PetscInt *dest = NULL, ndest = 0, cap = 0; /* (local D0 block, rank) pairs */
    PetscCall(BwPackerCreate(g->comm, &ask));
    for (PetscInt k = 0; k < g->ninterfaces; k++) {
      PetscInt   i = g->pair[2 * k] - g->block_start, j = g->pair[2 * k + 1];
      PetscMPIInt oi = newowner[i], oj = (PetscMPIInt)jowner[k];
      if (oi == oj) continue;
      if (ndest + 1 > cap) {
        cap = PetscMax(2 * cap, 256);
        PetscCall(PetscRealloc(sizeof(PetscInt) * 2 * (size_t)cap, &dest));
      }
      dest[2 * ndest]     = i;
      dest[2 * ndest + 1] = oj;
      ndest++;
      {
        PetscInt rec[2] = {j, oi};
        PetscCall(BwPack(&ask, BwRangeOwner(start, size, j), rec, sizeof(rec)));
      }
    }
    PetscCall(BwPackerExchange(g->comm, &ask, &recv, &nrecv, NULL));
    PetscCall(BwPackerDestroy(&ask));
    for (const char *at = recv; at < recv + nrecv;) {
      PetscInt rec[2];
      BwUnpack(&at, rec, sizeof(rec));
      if (ndest + 1 > cap) {
        cap = PetscMax(2 * cap, 256);
        PetscCall(PetscRealloc(sizeof(PetscInt) * 2 * (size_t)cap, &dest));
      }
      dest[2 * ndest]     = rec[0] - g->block_start;
      dest[2 * ndest + 1] = rec[1];
      ndest++;
    }
    PetscCall(PetscFree(recv));
    /* (block, rank) unique: a block goes once to each rank that needs it */
    qsort(dest, (size_t)ndest, 2 * sizeof(PetscInt), BwPairCompare);
    PetscCall(BwPackerCreate(g->comm, &pb));
    for (PetscInt b = 0; b < g->nblocks; b++) PetscCall(BwPackBlock(g, &pb, newowner[b], b, newowner[b], gvoff, memb, mset, mpos));
    for (PetscInt e = 0; e < ndest; e++) {
      PetscInt b = dest[2 * e];
      if (e && b == dest[2 * e - 2] && dest[2 * e + 1] == dest[2 * e - 1]) continue;
      PetscCall(BwPackBlock(g, &pb, (PetscMPIInt)dest[2 * e + 1], b, newowner[b], gvoff, memb, mset, mpos));
    }
    PetscCall(PetscFree(dest));
  }
  /* interfaces: to the owners of both blocks */
  PetscCall(BwPackerCreate(g->comm, &pi));
  for (PetscInt k = 0; k < g->ninterfaces; k++) {
    PetscMPIInt oi = newowner[g->pair[2 * k] - g->block_start], oj = (PetscMPIInt)jowner[k];
    PetscCall(BwPackInterface(g, &pi, oi, k, gpoly, stiff));
    if (oj != oi) PetscCall(BwPackInterface(g, &pi, oj, k, gpoly, stiff));
  }
  PetscCall(PetscFree(gvoff));
  PetscCall(PetscFree(gpoly));
  PetscCall(PetscFree(memb));
  PetscCall(PetscFree2(mset, mpos));
  PetscCall(PetscFree2(newowner, jowner));
  PetscCall(PetscFree(owner));
  PetscCall(PetscFree(start));
  /* the share is gone once everything is packed */
  PetscCall(BwFreeShare(g));
  PetscCall(BwPackerExchange(g->comm, &pb, &recv, &nrecv, NULL));
  PetscCall(BwPackerDestroy(&pb));
  PetscCall(BwUnpackBlocks(g, recv, nrecv, rank));
  PetscCall(PetscFree(recv));
  g->distributed = PETSC_TRUE; /* BwGeometryLocalBlock's lookups */
  PetscCall(BwPackerExchange(g->comm, &pi, &recv, &nrecv, NULL));
  PetscCall(BwPackerDestroy(&pi));
  PetscCall(BwUnpackInterfaces(g, recv, nrecv, stiff));
  PetscCall(PetscFree(recv));
  PetscCall(BwGhostIndices(g));
  PetscFunctionReturn(PETSC_SUCCESS);
}
