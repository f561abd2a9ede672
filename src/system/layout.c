/* BwMixed's layout: who owns what, the numbering of the unknowns, the dof
 * scales, and the accessors (see mixed.h for the system itself).
 *
 * Everything here is of the rank's local piece of the geometry (geometry.h:
 * its owned blocks, the interfaces touching them, their other blocks as
 * ghosts). A rank owns the blocks the partition gives it and the interfaces
 * whose first block it owns (the second block's owner when the first has
 * no free dof, so that fixed supports do not pull work to one rank); both
 * owners of an interface's blocks hold it and apply the same rule. It
 * assembles only its own rows: the 2m stress rows of its interfaces and the
 * 3 dof rows of its blocks that have free dofs; nothing is stashed for
 * another rank. The rows of ghost blocks and of interfaces it holds but
 * does not own (their owners number them) come from their owners, once. */
#include "system/mixed_impl.h"
#include "util/compat.h"
#include "blockwall/kernels.h"
#include "util/exchange.h"
#include <string.h>

const char *const BwStorages[] = {"shell", "nest", "aij", "BwStorage", "BW_STORAGE_", NULL};

static PetscBool BwHasUnknowns(BwMixed mx, PetscInt b)
{
  for (PetscInt c = 0; c < mx->nd; c++)
    if (!mx->model->prescribed[mx->nd * b + c]) return PETSC_TRUE;
  return PETSC_FALSE;
}

PetscErrorCode BwMixedCompatibility(BwMixed mx, PetscInt k, PetscReal rb[])
{
  BwGeometry     g = mx->geom;
  const PetscInt i = g->pair[2 * k], j = g->pair[2 * k + 1], d = g->dim;
  int            status;

  PetscFunctionBeginUser;
  if (d == 3) bw_kernel_compatibility(3, &g->centroid[3 * i], &g->centroid[3 * j], &g->center[3 * k], &g->frame[9 * k], rb, &status);
  else bw_interface_compatibility(&g->centroid[d * i], &g->centroid[d * j], &g->center[d * k], g->angle[k], rb, &status);
  PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "kernel failed on interface %" PetscInt_FMT, k);
  PetscFunctionReturn(PETSC_SUCCESS);
}

void BwMixedElasticTangent(BwMixed mx, PetscInt k, PetscReal c[])
{
  const PetscReal kt = mx->model->kt[k], kn = mx->model->kn[k];
  const PetscInt  ns = mx->ns;
  for (PetscInt a = 0; a < ns * ns; a++) c[a] = 0;
  for (PetscInt a = 0; a < ns; a++) c[a * (ns + 1)] = a == 1 ? kn : kt;
}

void BwMixedStiffnessRoots(BwMixed mx, PetscInt k, PetscReal *skt, PetscReal *skn)
{
  *skt = PetscSqrtReal(mx->model->kt[k]);
  *skn = PetscSqrtReal(mx->model->kn[k]);
}

/* 1/sqrt(diag S) per free dof of the elastic system: the dof's own
 * stiffness summed over its block's interfaces (all of them local for an
 * owned block), computed by the owner and sent to the ranks that hold the
 * block as a ghost. A free dof without stiffness is caught as a mechanism
 * before; a prescribed dof has scale 1. */
static PetscErrorCode BwMixedScales(BwMixed mx)
{
  BwGeometry     g  = mx->geom;
  const PetscInt nd = mx->nd;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(nd * g->nblocks + 1, &mx->qscale));
  for (PetscInt b = 0; b < g->nown_blocks; b++) {
    PetscReal diag[BW_MAX_ND] = {0};
    for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) {
      PetscInt  k = mx->adj[a], side = BwSide(mx, k, b);
      PetscReal        rb[2 * BW_MAX_ND * BW_MAX_ND], kg[BW_MAX_ND * BW_MAX_ND], s[4 * BW_MAX_ND * BW_MAX_ND], c[BW_MAX_NS * BW_MAX_NS];
      const PetscReal *area, *xi, *eta;
      PetscInt         np = BwMixedPortions(mx, k, &area, &xi, &eta, NULL);
      int              status;
      BwMixedElasticTangent(mx, k, c);
      PetscCall(BwMixedCompatibility(mx, k, rb));
      bw_kernel_condense((int)mx->dim, (int)np, area, xi, eta, 1, c, kg, &status);
      PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "kernel failed on interface %" PetscInt_FMT, g->giface[k]);
      bw_kernel_stiffness((int)mx->dim, rb, kg, s, &status);
      for (PetscInt c3 = 0; c3 < nd; c3++) diag[c3] += s[(side + c3) * (2 * nd + 1)];
    }
    for (PetscInt c3 = 0; c3 < nd; c3++) mx->qscale[nd * b + c3] = !mx->model->prescribed[nd * b + c3] && diag[c3] > 0 ? 1 / PetscSqrtReal(diag[c3]) : 1;
  }
  PetscCall(BwMixedGhostBcast(mx, nd, MPIU_REAL, mx->qscale));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 3D: the interface polygons in their own coordinates, cut into portions.
 * Interfaces of one class (polygons equal on the grid of BwPolygonStep)
 * share one layout, whose portions are cut from one member's polygon: that
 * member must be the same on every number of ranks, or the portions (and
 * the answers) would move by round-off with the partition. So each class
 * takes the polygon of its member of smallest global id over all ranks:
 * every rank sends one record per class it holds to the class's home rank
 * (its hash modulo the ranks), which answers with the chosen polygon. */
typedef struct {
  uint64_t    hash;
  PetscReal   q;
  PetscInt    nv, gid, from; /* from: the sender's record index, for the answer */
  PetscMPIInt src, pad;      /* the sender */
} BwClassHead;

static int BwClassCompare(const void *x, const void *y)
{
  const BwClassHead *a = *(const BwClassHead *const *)x, *b = *(const BwClassHead *const *)y;
  int                c;
  if (a->hash != b->hash) return a->hash < b->hash ? -1 : 1;
  if (a->q != b->q) return a->q < b->q ? -1 : 1;
  if (a->nv != b->nv) return a->nv < b->nv ? -1 : 1;
  c = memcmp(a + 1, b + 1, sizeof(int64_t) * 2 * (size_t)a->nv); /* the grid polygon follows the head */
  if (c) return c;
  return (a->gid > b->gid) - (a->gid < b->gid);
}

static PetscErrorCode BwMixedCreatePortions3D(BwMixed mx)
{
  BwGeometry     g  = mx->geom;
  const PetscInt ni = g->ninterfaces;
  PetscReal     *local;
  PetscInt       maxv = 0, nrec = 0, *rec_of;
  PetscMPIInt    size, rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(mx->comm, &size));
  PetscCallMPI(MPI_Comm_rank(mx->comm, &rank));
  PetscCall(PetscMalloc1(2 * (size_t)g->poly_offsets[ni] + 1, &local));
  for (PetscInt k = 0; k < ni; k++) {
    BwGeometryInterfaceLocal(g, k, local + 2 * g->poly_offsets[k]);
    maxv = PetscMax(maxv, g->poly_offsets[k + 1] - g->poly_offsets[k]);
  }
  PetscCall(PetscMalloc1(ni + 1, &rec_of));
  if (size > 1) {
    /* one record per (class, rank): the class's smallest local gid and its polygon */
    const size_t head = sizeof(BwClassHead);
    BwPacker     p, reply;
    char        *recv, *back;
    size_t       nrecv, nback;
    PetscInt    *first; /* per local record: its interface */
    PetscCall(PetscMalloc1(ni + 1, &first));
    {
      /* local classes: sort the local interfaces by class, then gid */
      char  *buf, **ptr;
      size_t rsz = head + sizeof(int64_t) * 2 * (size_t)maxv;
      PetscCall(PetscMalloc2(rsz * (size_t)ni + 1, &buf, ni + 1, &ptr));
      for (PetscInt k = 0; k < ni; k++) {
        BwClassHead    *h  = (BwClassHead *)(buf + rsz * (size_t)k);
        const PetscInt  nv = g->poly_offsets[k + 1] - g->poly_offsets[k];
        const PetscReal *pl = local + 2 * g->poly_offsets[k];
        h->nv               = nv;
        h->q                = BwPolygonStep(nv, pl);
        BwPolygonQuantize(nv, pl, h->q, (int64_t *)(h + 1));
        h->hash = BwPolygonHash(nv, (int64_t *)(h + 1));
        h->gid  = g->giface[k];
        h->from = k;
        ptr[k]  = (char *)h;
      }
      qsort(ptr, (size_t)ni, sizeof(char *), BwClassCompare);
      PetscCall(BwPackerCreate(mx->comm, &p));
      for (PetscInt a = 0; a < ni; a++) {
        BwClassHead *h = (BwClassHead *)ptr[a], *prev = a ? (BwClassHead *)ptr[a - 1] : NULL;
        PetscBool    same = prev && prev->hash == h->hash && prev->q == h->q && prev->nv == h->nv && !memcmp(prev + 1, h + 1, sizeof(int64_t) * 2 * (size_t)h->nv);
        if (!same) {
          /* a new class here: its first (smallest gid) member's record */
          BwClassHead out = *h;
          out.from        = nrec;
          out.src         = rank;
          first[nrec]     = h->from;
          PetscCall(BwPack(&p, (PetscMPIInt)(h->hash % (uint64_t)size), &out, head));
          PetscCall(BwPack(&p, (PetscMPIInt)(h->hash % (uint64_t)size), h + 1, sizeof(int64_t) * 2 * (size_t)h->nv));
          PetscCall(BwPack(&p, (PetscMPIInt)(h->hash % (uint64_t)size), local + 2 * g->poly_offsets[h->from], sizeof(PetscReal) * 2 * (size_t)h->nv));
          nrec++;
        }
        rec_of[h->from] = nrec - 1;
      }
      PetscCall(PetscFree2(buf, ptr));
    }
    PetscCall(BwPackerExchange(mx->comm, &p, &recv, &nrecv, NULL));
    PetscCall(BwPackerDestroy(&p));
    {
      /* the home's records, sorted by class then gid: each class's first
       * record's polygon answers every record of the class */
      PetscInt      n = 0, cap = 64;
      BwClassHead **ptr;
      PetscCall(PetscMalloc1(cap, &ptr));
      for (const char *at = recv; at < recv + nrecv;) {
        BwClassHead *h = (BwClassHead *)at;
        if (n == cap) {
          cap *= 2;
          PetscCall(PetscRealloc(sizeof(*ptr) * (size_t)cap, &ptr));
        }
        ptr[n++] = h;
        at += head + (sizeof(int64_t) + sizeof(PetscReal)) * 2 * (size_t)h->nv;
      }
      qsort(ptr, (size_t)n, sizeof(*ptr), BwClassCompare);
      PetscCall(BwPackerCreate(mx->comm, &reply));
      for (PetscInt a = 0, c0 = 0; a < n; a++) {
        BwClassHead *h = ptr[a], *c = ptr[c0];
        if (!(c->hash == h->hash && c->q == h->q && c->nv == h->nv && !memcmp(c + 1, h + 1, sizeof(int64_t) * 2 * (size_t)h->nv))) c0 = a, c = h;
        PetscCall(BwPack(&reply, h->src, &h->from, sizeof(PetscInt)));
        PetscCall(BwPack(&reply, h->src, (char *)(c + 1) + sizeof(int64_t) * 2 * (size_t)c->nv, sizeof(PetscReal) * 2 * (size_t)c->nv));
      }
      PetscCall(PetscFree(ptr));
    }
    PetscCall(PetscFree(recv));
    PetscCall(BwPackerExchange(mx->comm, &reply, &back, &nback, NULL));
    PetscCall(BwPackerDestroy(&reply));
    {
      /* each record's class polygon, then every member of the record's class takes it */
      PetscReal *cls;
      PetscCall(PetscMalloc1(2 * maxv * nrec + 1, &cls));
      for (const char *at = back; at < back + nback;) {
        PetscInt q, nv;
        BwUnpack(&at, &q, sizeof(q));
        nv = g->poly_offsets[first[q] + 1] - g->poly_offsets[first[q]];
        BwUnpack(&at, cls + 2 * maxv * q, sizeof(PetscReal) * 2 * (size_t)nv);
      }
      for (PetscInt k = 0; k < ni; k++) PetscCall(PetscArraycpy(local + 2 * g->poly_offsets[k], cls + 2 * maxv * rec_of[k], 2 * (g->poly_offsets[k + 1] - g->poly_offsets[k])));
      PetscCall(PetscFree(cls));
    }
    PetscCall(PetscFree(back));
    PetscCall(PetscFree(first));
  }
  PetscCall(BwPortionsCreate3D(ni, g->poly_offsets, local, mx->m, mx->model->mb, &mx->portions));
  PetscCall(PetscFree(rec_of));
  PetscCall(PetscFree(local));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The owner's local index of each interface this rank holds but does not
 * own, its global rows and its slot among all owned interfaces (BwQuery's
 * answer on the owner). */
static PetscErrorCode BwInterfaceRowsAnswer(void *ctx, PetscInt gid, PetscInt ans[])
{
  BwMixed  mx = (BwMixed)ctx;
  PetscInt lo = 0, hi = mx->nown_interfaces;

  PetscFunctionBeginUser;
  /* own_interfaces ascend in local index, so in global id */
  while (hi - lo > 1) {
    PetscInt mid = (lo + hi) / 2;
    if (mx->geom->giface[mx->own_interfaces[mid]] <= gid) lo = mid;
    else hi = mid;
  }
  PetscCheck(mx->nown_interfaces && mx->geom->giface[mx->own_interfaces[lo]] == gid, PETSC_COMM_SELF, PETSC_ERR_PLIB, "interface %" PetscInt_FMT " asked of a rank that does not own it", gid);
  ans[0] = mx->krow_r[mx->own_interfaces[lo]];
  ans[1] = mx->rrow[mx->own_interfaces[lo]];
  ans[2] = mx->islot[mx->own_interfaces[lo]];
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedGhostBcast(BwMixed mx, PetscInt n, MPI_Datatype type, void *data)
{
  MPI_Datatype unit;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Type_contiguous((PetscMPIInt)n, type, &unit));
  PetscCallMPI(MPI_Type_commit(&unit));
  PetscCall(PetscSFBcastBegin(mx->block_sf, unit, data, data, MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(mx->block_sf, unit, data, data, MPI_REPLACE));
  PetscCallMPI(MPI_Type_free(&unit));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedCreate(BwModel model, BwMixed *mixed)
{
  BwMixed     mx;
  BwGeometry  geom = model->geom;
  PetscInt    nb = geom->nblocks, ni = geom->ninterfaces, nown = geom->nown_blocks;
  PetscMPIInt size, rank;

  PetscFunctionBeginUser;
  PetscCheck(geom->distributed, geom->comm, PETSC_ERR_ORDER, "BwMixedCreate needs the distributed geometry (BwGeometryDistribute)");
  PetscCall(PetscNew(&mx));
  mx->comm  = geom->comm;
  mx->geom  = geom;
  mx->model = model;
  mx->spring_gblock  = -1;
  mx->spring_block   = -1;
  mx->spring_written = -1;
  mx->m     = model->m;
  mx->dim   = geom->dim;
  mx->nd    = geom->dim == 3 ? 6 : 3;
  mx->ns    = geom->dim == 3 ? 3 : 2;
  PetscCallMPI(MPI_Comm_size(mx->comm, &size));
  PetscCallMPI(MPI_Comm_rank(mx->comm, &rank));

  /* block -> interfaces (complete for owned blocks) */
  PetscCall(PetscCalloc1(nb + 1, &mx->adj_offsets));
  PetscCall(PetscMalloc1(2 * ni + 1, &mx->adj));
  for (PetscInt k = 0; k < ni; k++) {
    mx->adj_offsets[geom->pair[2 * k] + 1]++;
    mx->adj_offsets[geom->pair[2 * k + 1] + 1]++;
  }
  for (PetscInt b = 0; b < nb; b++) mx->adj_offsets[b + 1] += mx->adj_offsets[b];
  {
    PetscInt *fill;
    PetscCall(PetscMalloc1(nb + 1, &fill));
    PetscCall(PetscArraycpy(fill, mx->adj_offsets, nb));
    for (PetscInt k = 0; k < ni; k++) {
      mx->adj[fill[geom->pair[2 * k]]++]     = k;
      mx->adj[fill[geom->pair[2 * k + 1]]++] = k;
    }
    PetscCall(PetscFree(fill));
  }
  *mixed = mx; /* from here on, BwMixedDestroy cleans up after an error */
  /* ghosts <- owners: the star forest of the blocks */
  {
    PetscSFNode *remote;
    PetscCall(PetscMalloc1(nb - nown + 1, &remote));
    for (PetscInt b = nown; b < nb; b++) {
      remote[b - nown].rank  = geom->block_rank[b];
      remote[b - nown].index = geom->block_rindex[b];
    }
    PetscInt *leaf; /* the ghosts, after the owned blocks */
    PetscCall(PetscMalloc1(nb - nown + 1, &leaf));
    for (PetscInt b = nown; b < nb; b++) leaf[b - nown] = b;
    PetscCall(PetscSFCreate(mx->comm, &mx->block_sf));
    PetscCall(PetscSFSetGraph(mx->block_sf, nb, nb - nown, leaf, PETSC_OWN_POINTER, remote, PETSC_OWN_POINTER));
  }
  if (geom->dim == 3) PetscCall(BwMixedCreatePortions3D(mx));
  else PetscCall(BwPortionsCreate2D(ni, geom->pair, geom->length, geom->depth, mx->m, &mx->portions));

  /* interface owners: the same rule on both ranks that hold one */
  PetscCall(PetscMalloc1(ni + 1, &mx->interface_owner));
  for (PetscInt k = 0; k < ni; k++) {
    PetscInt i = geom->pair[2 * k], j = geom->pair[2 * k + 1];
    mx->interface_owner[k] = geom->block_rank[BwHasUnknowns(mx, i) ? i : j];
    if (mx->interface_owner[k] == rank) mx->nown_interfaces++;
  }
  PetscCall(PetscMalloc1(mx->nown_interfaces + 1, &mx->own_interfaces));
  mx->nown_interfaces = 0;
  for (PetscInt k = 0; k < ni; k++)
    if (mx->interface_owner[k] == rank) mx->own_interfaces[mx->nown_interfaces++] = k;
  mx->nown_blocks = nown;
  PetscCall(PetscMalloc1(nown + 1, &mx->own_blocks));
  for (PetscInt b = 0; b < nown; b++) mx->own_blocks[b] = b;
  /* the restraint checks count each hinge once, on its owner */
  PetscCall(PetscLogEventBegin(BwEvents[BW_EVENT_RESTRAINT], 0, 0, 0, 0));
  PetscCall(BwMixedCheckRestraint(mx));
  PetscCall(PetscLogEventEnd(BwEvents[BW_EVENT_RESTRAINT], 0, 0, 0, 0));

  /* numbering: rank p's rows of K are [its stresses | its blocks' dofs] */
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) mx->nr_local += mx->ns * BwPortionsCount(&mx->portions, mx->own_interfaces[e]);
  for (PetscInt b = 0; b < nown; b++)
    if (BwHasUnknowns(mx, b)) {
      mx->nq_local += mx->nd;
      mx->nown_q++;
    }
  mx->nlocal = mx->nr_local + mx->nq_local;
  {
    PetscInt loc[4] = {mx->nlocal, mx->nr_local, mx->nq_local, mx->nown_interfaces}, before[4] = {0, 0, 0, 0}, total[4];
    PetscCallMPI(MPI_Exscan(loc, before, 4, MPIU_INT, MPI_SUM, mx->comm));
    if (!rank) before[0] = before[1] = before[2] = before[3] = 0;
    PetscCallMPI(MPIU_Allreduce(loc, total, 4, MPIU_INT, MPI_SUM, mx->comm));
    mx->kstart    = before[0];
    mx->rstart    = before[1];
    mx->qstart    = before[2];
    mx->nr_global = total[1];
    mx->nq_global = total[2];
    PetscCall(PetscMalloc4(nb + 1, &mx->krow_q, nb + 1, &mx->qrow, ni + 1, &mx->krow_r, ni + 1, &mx->rrow));
    PetscCall(PetscMalloc1(ni + 1, &mx->islot));
    {
      PetscInt kr = mx->kstart, r = mx->rstart;
      for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
        PetscInt k = mx->own_interfaces[e], n = mx->ns * BwPortionsCount(&mx->portions, k);
        mx->krow_r[k] = kr;
        mx->rrow[k]   = r;
        mx->islot[k]  = before[3] + e;
        kr += n;
        r += n;
      }
    }
    {
      PetscInt kq = mx->kstart + mx->nr_local, q = mx->qstart;
      for (PetscInt b = 0; b < nown; b++) {
        if (BwHasUnknowns(mx, b)) {
          mx->krow_q[b] = kq;
          mx->qrow[b]   = q;
          kq += mx->nd;
          q += mx->nd;
        } else mx->krow_q[b] = mx->qrow[b] = -1;
      }
    }
  }
  /* the ghosts' rows from their owners */
  PetscCall(BwMixedGhostBcast(mx, 1, MPIU_INT, mx->krow_q));
  PetscCall(BwMixedGhostBcast(mx, 1, MPIU_INT, mx->qrow));
  {
    PetscInt     nother = ni - mx->nown_interfaces, *key, *val, n = 0;
    PetscMPIInt *dest;
    PetscCall(PetscMalloc3(nother + 1, &key, nother + 1, &dest, 3 * nother + 1, &val));
    for (PetscInt k = 0; k < ni; k++)
      if (mx->interface_owner[k] != rank) {
        key[n]    = geom->giface[k];
        dest[n++] = mx->interface_owner[k];
      }
    PetscCall(BwQuery(mx->comm, n, dest, key, 3, BwInterfaceRowsAnswer, mx, val));
    n = 0;
    for (PetscInt k = 0; k < ni; k++)
      if (mx->interface_owner[k] != rank) {
        mx->krow_r[k] = val[3 * n];
        mx->rrow[k]   = val[3 * n + 1];
        mx->islot[k]  = val[3 * n + 2];
        n++;
      }
    PetscCall(PetscFree3(key, dest, val));
  }
  /* the output's rows: the owned interfaces' global ids, their portions'
   * first rows (ragged, in interface id order) */
  {
    PetscInt *cnt;
    PetscCall(PetscMalloc1(mx->nown_interfaces + 1, &mx->own_interface_gid));
    PetscCall(PetscMalloc1(mx->nown_interfaces + 1, &mx->own_portion_start));
    PetscCall(PetscMalloc1(mx->nown_interfaces + 1, &cnt));
    for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
      mx->own_interface_gid[e] = geom->giface[mx->own_interfaces[e]];
      cnt[e]                   = BwPortionsCount(&mx->portions, mx->own_interfaces[e]);
    }
    PetscCall(BwRaggedOffsets(mx->comm, mx->nown_interfaces, mx->own_interface_gid, cnt, geom->ninterfaces_global, mx->own_portion_start, &mx->nportions_global));
    PetscCall(PetscFree(cnt));
  }
  for (PetscInt b = 0; b < nown; b++) mx->maxdeg = PetscMax(mx->maxdeg, mx->adj_offsets[b + 1] - mx->adj_offsets[b]);
  /* the partition's figures: interfaces across ranks (each counted by the
   * rank of its first block) and the largest rank's blocks over the mean */
  {
    PetscInt  cut = 0, most;
    for (PetscInt k = 0; k < ni; k++) {
      PetscInt i = geom->pair[2 * k], j = geom->pair[2 * k + 1];
      if (geom->block_rank[i] != geom->block_rank[j] && geom->block_rank[i] == rank) cut++;
    }
    PetscCallMPI(MPIU_Allreduce(&cut, &mx->edge_cut, 1, MPIU_INT, MPI_SUM, mx->comm));
    PetscCallMPI(MPIU_Allreduce(&nown, &most, 1, MPIU_INT, MPI_MAX, mx->comm));
    mx->imbalance = geom->nblocks_global ? (PetscReal)most * size / geom->nblocks_global : 1;
  }
  PetscCall(BwMixedScales(mx));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedDestroy(BwMixed *mixed)
{
  BwMixed mx = *mixed;

  PetscFunctionBeginUser;
  if (!mx) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFree(mx->adj_offsets));
  PetscCall(PetscFree(mx->adj));
  PetscCall(PetscFree(mx->interface_owner));
  PetscCall(PetscFree4(mx->krow_q, mx->qrow, mx->krow_r, mx->rrow));
  PetscCall(PetscFree(mx->islot));
  PetscCall(PetscFree(mx->own_blocks));
  PetscCall(PetscFree(mx->own_interfaces));
  PetscCall(PetscSFDestroy(&mx->block_sf));
  PetscCall(PetscFree(mx->own_interface_gid));
  PetscCall(PetscFree(mx->own_portion_start));
  PetscCall(PetscFree(mx->qscale));
  PetscCall(BwPortionsDestroy(&mx->portions));
  PetscCall(MatDestroy(&mx->K));
  PetscCall(MatDestroy(&mx->D));
  PetscCall(MatDestroy(&mx->S));
  PetscCall(ISDestroy(&mx->isr));
  PetscCall(ISDestroy(&mx->isq));
  PetscCall(VecDestroy(&mx->pmask));
  PetscCall(PetscFree2(mx->tangent, mx->scaled_tangent));
  PetscCall(PetscFree(mx->kg_interfaces));
  PetscCall(PetscFree(mx->kg));
  PetscCall(PetscFree2(mx->s6, mx->s6_valid));
  PetscCall(PetscFree2(mx->tangent_changed, mx->kg_changed));
  PetscCall(VecScatterDestroy(&mx->kg_scatter));
  PetscCall(VecDestroy(&mx->kg_owned));
  PetscCall(VecDestroy(&mx->kg_ghost));
  PetscCall(PetscFree(*mixed));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedCreateVecs(BwMixed mx, Vec *x, Vec *b)
{
  PetscFunctionBeginUser;
  if (x) PetscCall(VecCreateMPI(mx->comm, mx->nlocal, PETSC_DETERMINE, x));
  if (b) PetscCall(VecCreateMPI(mx->comm, mx->nlocal, PETSC_DETERMINE, b));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedGetOperators(BwMixed mx, Mat *K, Mat *S, Mat *D)
{
  PetscFunctionBeginUser;
  if (K) *K = mx->K;
  if (S) *S = mx->S;
  if (D) *D = mx->D;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedGetValuesState(BwMixed mx, PetscInt *state)
{
  PetscFunctionBeginUser;
  *state = mx->values_state;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedGetFields(BwMixed mx, IS *isr, IS *isq)
{
  PetscFunctionBeginUser;
  if (isr) *isr = mx->isr;
  if (isq) *isq = mx->isq;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedGetPrescribedMask(BwMixed mx, Vec *mask)
{
  PetscFunctionBeginUser;
  *mask = mx->pmask;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedGetOwnership(BwMixed mx, BwMixedOwnership *own)
{
  PetscFunctionBeginUser;
  own->nblocks         = mx->geom->nblocks_global;
  own->ninterfaces     = mx->geom->ninterfaces_global;
  own->m               = mx->m;
  own->dim             = mx->dim;
  own->nd              = mx->nd;
  own->ns              = mx->ns;
  own->portions        = &mx->portions;
  own->nown_blocks     = mx->nown_blocks;
  own->nown_interfaces = mx->nown_interfaces;
  own->own_blocks      = mx->own_blocks;
  own->own_interfaces  = mx->own_interfaces;
  own->nq_global       = mx->nq_global;
  own->nr_global       = mx->nr_global;
  own->own_block_gid     = mx->geom->gblock;
  own->own_interface_gid = mx->own_interface_gid;
  own->own_portion_start = mx->own_portion_start;
  own->nportions_global  = mx->nportions_global;
  own->edge_cut        = mx->edge_cut;
  own->imbalance       = mx->imbalance;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedGetModel(BwMixed mx, BwModel *model)
{
  PetscFunctionBeginUser;
  *model = mx->model;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rigid motion r of the assembly (r < dim translations, then rotations
 * about X3 in 2D, about X1, X2, X3 in 3D, about x0) at block b: its dofs u[nd]. */
void BwMixedRigidMotion(BwMixed mx, PetscInt r, PetscInt b, const PetscReal x0[], PetscReal u[])
{
  const PetscInt   d = mx->dim, nd = mx->nd, nt = d; /* translations */
  const PetscReal *c = &mx->geom->centroid[d * b];
  PetscReal        w[3] = {0, 0, 0}, arm[3] = {0, 0, 0};

  for (PetscInt a = 0; a < nd; a++) u[a] = 0;
  if (r < nt) {
    u[r] = 1;
    return;
  }
  if (d == 2) w[2] = 1;
  else w[r - nt] = 1;
  for (PetscInt a = 0; a < d; a++) arm[a] = c[a] - x0[a];
  /* translation of the centroid w x arm, then the rotation itself */
  {
    PetscReal t[3] = {w[1] * arm[2] - w[2] * arm[1], w[2] * arm[0] - w[0] * arm[2], w[0] * arm[1] - w[1] * arm[0]};
    for (PetscInt a = 0; a < d; a++) u[a] = t[a];
    if (d == 2) u[2] = 1;
    else
      for (PetscInt a = 0; a < 3; a++) u[3 + a] = w[a];
  }
}

PetscErrorCode BwMixedInterfaceSlots(BwMixed mx, PetscInt slot[])
{
  PetscFunctionBeginUser;
  for (PetscInt e = 0; e < mx->nkg; e++) slot[e] = mx->islot[mx->kg_interfaces[e]];
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The plane of the assembly: x0 the mean of the block centroids, e[0..2]
 * the principal axes of their spread, largest first (e[2] the normal of a
 * wall, the direction it is thin across). Sums over owned blocks, reduced. */
static PetscErrorCode BwMixedPrincipalAxes(BwMixed mx, PetscReal x0[3], PetscReal e[9])
{
  const PetscInt   d = mx->dim;
  const PetscReal *c = mx->geom->centroid;
  PetscReal        loc[10] = {0}, all[10], cov[9];

  PetscFunctionBeginUser;
  for (PetscInt e0 = 0; e0 < mx->nown_blocks; e0++) {
    PetscInt b = mx->own_blocks[e0];
    loc[9] += 1;
    for (PetscInt a = 0; a < d; a++) loc[a] += c[d * b + a];
  }
  PetscCallMPI(MPIU_Allreduce(loc, all, 10, MPIU_REAL, MPIU_SUM, mx->comm));
  for (PetscInt a = 0; a < 3; a++) x0[a] = a < d && all[9] > 0 ? all[a] / all[9] : 0;
  for (PetscInt a = 0; a < 9; a++) loc[a] = 0;
  for (PetscInt e0 = 0; e0 < mx->nown_blocks; e0++) {
    PetscInt b = mx->own_blocks[e0];
    for (PetscInt a = 0; a < d; a++)
      for (PetscInt f = 0; f < d; f++) loc[3 * a + f] += (c[d * b + a] - x0[a]) * (c[d * b + f] - x0[f]);
  }
  PetscCallMPI(MPIU_Allreduce(loc, cov, 9, MPIU_REAL, MPIU_SUM, mx->comm));
  /* cyclic Jacobi rotations on the 3x3 covariance (converges in a few sweeps) */
  {
    PetscReal V[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, ev[3];
    PetscInt  order[3] = {0, 1, 2};
    for (PetscInt sweep = 0; sweep < 50; sweep++) {
      PetscReal off = PetscAbsReal(cov[1]) + PetscAbsReal(cov[2]) + PetscAbsReal(cov[5]);
      if (off <= 1e-15 * (PetscAbsReal(cov[0]) + PetscAbsReal(cov[4]) + PetscAbsReal(cov[8])) || off == 0) break;
      for (PetscInt p = 0; p < 2; p++)
        for (PetscInt q = p + 1; q < 3; q++) {
          PetscReal apq = cov[3 * p + q], th, t, cs, sn;
          if (apq == 0) continue;
          th = (cov[3 * q + q] - cov[3 * p + p]) / (2 * apq);
          t  = (th >= 0 ? 1 : -1) / (PetscAbsReal(th) + PetscSqrtReal(th * th + 1));
          cs = 1 / PetscSqrtReal(t * t + 1);
          sn = t * cs;
          for (PetscInt k = 0; k < 3; k++) { /* columns p, q */
            PetscReal akp = cov[3 * k + p], akq = cov[3 * k + q];
            cov[3 * k + p] = cs * akp - sn * akq;
            cov[3 * k + q] = sn * akp + cs * akq;
          }
          for (PetscInt k = 0; k < 3; k++) { /* rows p, q */
            PetscReal apk = cov[3 * p + k], aqk = cov[3 * q + k];
            cov[3 * p + k] = cs * apk - sn * aqk;
            cov[3 * q + k] = sn * apk + cs * aqk;
          }
          for (PetscInt k = 0; k < 3; k++) {
            PetscReal vkp = V[3 * k + p], vkq = V[3 * k + q];
            V[3 * k + p] = cs * vkp - sn * vkq;
            V[3 * k + q] = sn * vkp + cs * vkq;
          }
        }
    }
    for (PetscInt a = 0; a < 3; a++) ev[a] = cov[4 * a];
    /* largest spread first */
    for (PetscInt a = 0; a < 3; a++)
      for (PetscInt f = a + 1; f < 3; f++)
        if (ev[order[f]] > ev[order[a]]) {
          PetscInt t = order[a];
          order[a] = order[f];
          order[f] = t;
        }
    for (PetscInt a = 0; a < 3; a++)
      for (PetscInt f = 0; f < 3; f++) e[3 * a + f] = V[3 * f + order[a]];
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Bending mode k (0: s^2/2, 1: t^2/2, 2: s t) of a plate with in-plane
 * axes e[0], e[1] and normal e[2] through x0, at block b: the deflection f
 * along the normal, the mid-plane's slope as the rotation (w = grad f x n)
 * and the in-plane part -z grad f of the sections that stay normal: zero
 * strain but the curvature, the way a thin plate bends. */
static void BwMixedBendingMode(BwMixed mx, PetscInt k, PetscInt b, const PetscReal x0[], const PetscReal e[], PetscReal u[])
{
  const PetscReal *c = &mx->geom->centroid[3 * b];
  PetscReal        arm[3] = {c[0] - x0[0], c[1] - x0[1], c[2] - x0[2]}, st[3], f, g[3];

  for (PetscInt a = 0; a < 3; a++) st[a] = arm[0] * e[3 * a] + arm[1] * e[3 * a + 1] + arm[2] * e[3 * a + 2];
  {
    const PetscReal s = st[0], t = st[1];
    const PetscReal fs = k == 0 ? s : k == 1 ? 0 : t, ft = k == 0 ? 0 : k == 1 ? t : s;
    f = k == 0 ? s * s / 2 : k == 1 ? t * t / 2 : s * t;
    for (PetscInt a = 0; a < 3; a++) g[a] = fs * e[a] + ft * e[3 + a];
  }
  {
    const PetscReal *n = &e[6];
    for (PetscInt a = 0; a < 3; a++) u[a] = f * n[a] - st[2] * g[a];
    u[3] = g[1] * n[2] - g[2] * n[1];
    u[4] = g[2] * n[0] - g[0] * n[2];
    u[5] = g[0] * n[1] - g[1] * n[0];
  }
}

PetscErrorCode BwMixedSetNearNullSpace(BwMixed mx)
{
  const PetscInt nrig = mx->nd; /* 3 rigid motions in 2D, 6 in 3D */
  PetscInt       nvec = nrig;
  Vec            v[BW_MAX_ND + 3] = {NULL};
  MatNullSpace   nsp;
  PetscReal      x0[3] = {0, 0, 0}, e[9] = {0};
  PetscScalar   *a[BW_MAX_ND + 3];

  PetscFunctionBeginUser;
  if (mx->dim == 3) nvec += 3;
  PetscCall(BwMixedPrincipalAxes(mx, x0, e));
  for (PetscInt r = 0; r < nvec; r++) {
    PetscCall(MatCreateVecs(mx->S, &v[r], NULL));
    PetscCall(VecGetArray(v[r], &a[r]));
  }
  for (PetscInt e0 = 0; e0 < mx->nown_blocks; e0++) {
    PetscInt b = mx->own_blocks[e0], row = mx->qrow[b] - mx->qstart, nd = mx->nd;
    if (mx->qrow[b] < 0) continue;
    for (PetscInt r = 0; r < nvec; r++) {
      PetscReal u[BW_MAX_ND];
      if (r < nrig) BwMixedRigidMotion(mx, r, b, x0, u);
      else BwMixedBendingMode(mx, r - nrig, b, x0, e, u);
      /* q~ = diag(S)^{1/2} q; prescribed dofs do not move */
      for (PetscInt c = 0; c < nd; c++) a[r][row + c] = mx->model->prescribed[nd * b + c] ? 0 : u[c] / mx->qscale[nd * b + c];
    }
  }
  for (PetscInt r = 0; r < nvec; r++) PetscCall(VecRestoreArray(v[r], &a[r]));
  /* MatNullSpaceCreate wants orthonormal vectors: Gram-Schmidt twice (the
   * bending modes are nearly parallel to the rigid ones on a long wall) */
  PetscCall(VecNormalize(v[0], NULL));
  for (PetscInt r = 1; r < nvec; r++) {
    for (PetscInt pass = 0; pass < 2; pass++) {
      PetscScalar dots[BW_MAX_ND + 3];
      PetscCall(VecMDot(v[r], r, v, dots));
      for (PetscInt j = 0; j < r; j++) dots[j] = -dots[j];
      PetscCall(VecMAXPY(v[r], r, dots, v));
    }
    PetscCall(VecNormalize(v[r], NULL));
  }
  PetscCall(MatNullSpaceCreate(mx->comm, PETSC_FALSE, nvec, v, &nsp));
  PetscCall(MatSetNearNullSpace(mx->S, nsp));
  PetscCall(MatNullSpaceDestroy(&nsp));
  for (PetscInt r = 0; r < nvec; r++) PetscCall(VecDestroy(&v[r]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedForwardWeights(BwMixed mx, Vec weight, PetscReal *prescribed)
{
  BwGeometry   geom = mx->geom;
  const PetscInt d = geom->dim, nd = mx->nd;
  PetscReal      lo[3], hi[3], size = 0, pmax = 0;
  PetscScalar   *w;

  PetscFunctionBeginUser;
  PetscCall(BwGeometryBoundingBox(geom, lo, hi));
  for (PetscInt c = 0; c < d; c++) size += PetscSqr(hi[c] - lo[c]);
  size = PetscSqrtReal(size);
  PetscCall(VecGetArray(weight, &w));
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e];
    for (PetscInt c = 0; c < nd; c++) {
      PetscReal arm = c >= d ? size : 1; /* the dofs after the translations are rotations */
      /* q = diag(S)^-1/2 q~; rotations times the assembly's size */
      if (mx->qrow[b] >= 0) w[mx->qrow[b] - mx->qstart + c] = mx->model->prescribed[nd * b + c] ? 0 : mx->qscale[nd * b + c] * arm;
      if (mx->model->prescribed[nd * b + c]) pmax = PetscMax(pmax, PetscAbsReal(mx->model->value[nd * b + c]) * arm);
    }
  }
  PetscCall(VecRestoreArray(weight, &w));
  PetscCallMPI(MPIU_Allreduce(&pmax, prescribed, 1, MPIU_REAL, MPIU_MAX, mx->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}
