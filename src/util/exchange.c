/* BwPacker and BwQuery (exchange.h). */
#include <string.h>
#include "util/exchange.h"
#include "util/compat.h"

PetscErrorCode BwPackerCreate(MPI_Comm comm, BwPacker *p)
{
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &p->size));
  PetscCall(PetscCalloc1(p->size, &p->len));
  PetscCall(PetscCalloc1(p->size, &p->cap));
  PetscCall(PetscCalloc1(p->size, &p->buf));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwPackerDestroy(BwPacker *p)
{
  PetscFunctionBeginUser;
  if (!p->buf) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscMPIInt r = 0; r < p->size; r++) PetscCall(PetscFree(p->buf[r]));
  PetscCall(PetscFree(p->len));
  PetscCall(PetscFree(p->cap));
  PetscCall(PetscFree(p->buf));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwPack(BwPacker *p, PetscMPIInt dest, const void *data, size_t n)
{
  PetscFunctionBeginUser;
  if (p->len[dest] + n > p->cap[dest]) {
    size_t cap = PetscMax(2 * p->cap[dest], PetscMax(p->len[dest] + n, (size_t)256));
    PetscCall(PetscRealloc(cap, &p->buf[dest]));
    p->cap[dest] = cap;
  }
  if (n) memcpy(p->buf[dest] + p->len[dest], data, n);
  p->len[dest] += n;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwPackerExchange(MPI_Comm comm, BwPacker *p, char **recv, size_t *nrecv, int **rbytes)
{
  PetscMPIInt size = p->size;
  int        *scount, *rcount, *sdispl, *rdispl;
  char       *send;
  size_t      stotal = 0, rtotal = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(size, &scount));
  PetscCall(PetscMalloc1(size, &rcount));
  PetscCall(PetscMalloc1(size, &sdispl));
  PetscCall(PetscMalloc1(size, &rdispl));
  for (PetscMPIInt r = 0; r < size; r++) {
    PetscCheck(p->len[r] < (size_t)PETSC_MPI_INT_MAX, comm, PETSC_ERR_SUP, "more than 2 GB to move from one rank to another: run on more ranks");
    scount[r] = (int)p->len[r];
    sdispl[r] = (int)stotal;
    stotal += p->len[r];
  }
  PetscCheck(stotal < (size_t)PETSC_MPI_INT_MAX, comm, PETSC_ERR_SUP, "more than 2 GB to move from one rank: run on more ranks");
  PetscCallMPI(MPI_Alltoall(scount, 1, MPI_INT, rcount, 1, MPI_INT, comm));
  for (PetscMPIInt r = 0; r < size; r++) {
    rdispl[r] = (int)rtotal;
    rtotal += (size_t)rcount[r];
  }
  PetscCheck(rtotal < (size_t)PETSC_MPI_INT_MAX, comm, PETSC_ERR_SUP, "more than 2 GB to move to one rank: run on more ranks");
  PetscCall(PetscMalloc1(stotal + 1, &send));
  for (PetscMPIInt r = 0; r < size; r++)
    if (p->len[r]) memcpy(send + sdispl[r], p->buf[r], p->len[r]);
  PetscCall(PetscMalloc1(rtotal + 1, recv));
  PetscCallMPI(MPI_Alltoallv(send, scount, sdispl, MPI_BYTE, *recv, rcount, rdispl, MPI_BYTE, comm));
  *nrecv = rtotal;
  PetscCall(PetscFree(send));
  PetscCall(PetscFree(scount));
  PetscCall(PetscFree(sdispl));
  PetscCall(PetscFree(rdispl));
  if (rbytes) *rbytes = rcount;
  else PetscCall(PetscFree(rcount));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwQueryBytes(MPI_Comm comm, PetscInt n, const PetscMPIInt dest[], const PetscInt key[], size_t size, BwQueryAnswerBytes answer, void *ctx, void *values)
{
  BwPacker ask, reply;
  char    *recv, *back, *ans;
  size_t   nrecv, nback;
  int     *rbytes;

  PetscFunctionBeginUser;
  PetscCall(BwPackerCreate(comm, &ask));
  PetscCall(BwPackerCreate(comm, &reply));
  PetscCall(PetscMalloc1(size + 1, &ans));
  for (PetscInt q = 0; q < n; q++) {
    PetscInt rec[2] = {q, key[q]};
    PetscCall(BwPack(&ask, dest[q], rec, sizeof(rec)));
  }
  PetscCall(BwPackerExchange(comm, &ask, &recv, &nrecv, &rbytes));
  {
    /* the answers go back to each asker, each with the asker's index */
    const char *at = recv;
    for (PetscMPIInt r = 0; r < ask.size; r++)
      for (int k = 0; k < rbytes[r] / (int)(2 * sizeof(PetscInt)); k++) {
        PetscInt rec[2];
        BwUnpack(&at, rec, sizeof(rec));
        PetscCall(answer(ctx, rec[1], ans));
        PetscCall(BwPack(&reply, r, &rec[0], sizeof(PetscInt)));
        PetscCall(BwPack(&reply, r, ans, size));
      }
  }
  PetscCall(PetscFree(recv));
  PetscCall(PetscFree(rbytes));
  PetscCall(BwPackerExchange(comm, &reply, &back, &nback, NULL));
  for (const char *at = back; at < back + nback;) {
    PetscInt q;
    BwUnpack(&at, &q, sizeof(q));
    BwUnpack(&at, (char *)values + size * (size_t)q, size);
  }
  PetscCall(PetscFree(back));
  PetscCall(PetscFree(ans));
  PetscCall(BwPackerDestroy(&ask));
  PetscCall(BwPackerDestroy(&reply));
  PetscFunctionReturn(PETSC_SUCCESS);
}

typedef struct {
  BwQueryAnswer answer;
  void         *ctx;
} BwQueryInts;

static PetscErrorCode BwQueryIntsAnswer(void *ctx, PetscInt key, void *ans)
{
  BwQueryInts *q = (BwQueryInts *)ctx;
  return q->answer(q->ctx, key, (PetscInt *)ans);
}

PetscErrorCode BwQuery(MPI_Comm comm, PetscInt n, const PetscMPIInt dest[], const PetscInt key[], PetscInt nans, BwQueryAnswer answer, void *ctx, PetscInt values[])
{
  BwQueryInts q = {answer, ctx};

  PetscFunctionBeginUser;
  PetscCall(BwQueryBytes(comm, n, dest, key, sizeof(PetscInt) * (size_t)nans, BwQueryIntsAnswer, &q, values));
  PetscFunctionReturn(PETSC_SUCCESS);
}

typedef struct {
  PetscInt  lo;
  PetscInt *acc;
} BwRagged;

static PetscErrorCode BwRaggedAnswer(void *ctx, PetscInt gid, PetscInt ans[])
{
  BwRagged *r = (BwRagged *)ctx;
  ans[0]      = r->acc[gid - r->lo];
  return PETSC_SUCCESS;
}

/* The rank of id `gid` when N ids are split evenly over `size` ranks. */
static PetscMPIInt BwSplitOwner(PetscInt N, PetscMPIInt size, PetscInt gid)
{
  PetscMPIInt r = (PetscMPIInt)(((PetscInt64)gid * size) / PetscMax(N, 1));
  /* the split's own rounding: start(r) = floor(N r / size) */
  while (r > 0 && ((PetscInt64)N * r) / size > gid) r--;
  while (r + 1 < size && ((PetscInt64)N * (r + 1)) / size <= gid) r++;
  return r;
}

PetscErrorCode BwRaggedOffsets(MPI_Comm comm, PetscInt n, const PetscInt gids[], const PetscInt counts[], PetscInt N, PetscInt offsets[], PetscInt *total)
{
  PetscMPIInt  size, rank, *dest;
  PetscInt     lo, hi, sum = 0, base = 0;
  BwPacker     p;
  char        *recv;
  size_t       nrecv;
  BwRagged     r;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  lo = (PetscInt)(((PetscInt64)N * rank) / size);
  hi = (PetscInt)(((PetscInt64)N * (rank + 1)) / size);
  PetscCall(PetscCalloc1(hi - lo + 1, &r.acc));
  r.lo = lo;
  PetscCall(PetscMalloc1(n + 1, &dest));
  PetscCall(BwPackerCreate(comm, &p));
  for (PetscInt q = 0; q < n; q++) {
    PetscInt rec[2] = {gids[q], counts[q]};
    dest[q]         = BwSplitOwner(N, size, gids[q]);
    PetscCall(BwPack(&p, dest[q], rec, sizeof(rec)));
  }
  PetscCall(BwPackerExchange(comm, &p, &recv, &nrecv, NULL));
  PetscCall(BwPackerDestroy(&p));
  for (const char *at = recv; at < recv + nrecv;) {
    PetscInt rec[2];
    BwUnpack(&at, rec, sizeof(rec));
    r.acc[rec[0] - lo] = rec[1];
  }
  PetscCall(PetscFree(recv));
  for (PetscInt k = 0; k < hi - lo; k++) sum += r.acc[k];
  PetscCallMPI(MPI_Exscan(&sum, &base, 1, MPIU_INT, MPI_SUM, comm));
  if (!rank) base = 0;
  PetscCallMPI(MPIU_Allreduce(&sum, total, 1, MPIU_INT, MPI_SUM, comm));
  for (PetscInt k = 0, run = base; k < hi - lo; k++) {
    PetscInt c = r.acc[k];
    r.acc[k]   = run;
    run += c;
  }
  PetscCall(BwQuery(comm, n, dest, gids, 1, BwRaggedAnswer, &r, offsets));
  PetscCall(PetscFree(dest));
  PetscCall(PetscFree(r.acc));
  PetscFunctionReturn(PETSC_SUCCESS);
}
