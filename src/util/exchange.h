/* Exchanges between ranks of variable records, and questions about items
 * another rank holds: what moving a distributed assembly needs, with
 * memory of the records moved (and of the number of ranks), never of the
 * whole assembly.
 *
 *   BwPacker: bytes per destination rank, then one all-to-all of the
 *   counts and one of the bytes (MPI_Alltoallv);
 *   BwQuery: each rank asks the owner of each of its keys, the owner's
 *   callback answers with `nans` integers per key. */
#pragma once
#include <string.h>
#include <petscsys.h>

typedef struct {
  PetscMPIInt size;
  size_t     *len, *cap;
  char      **buf;
} BwPacker;

PetscErrorCode BwPackerCreate(MPI_Comm comm, BwPacker *p);
PetscErrorCode BwPackerDestroy(BwPacker *p);
/* Appends n bytes for rank dest. */
PetscErrorCode BwPack(BwPacker *p, PetscMPIInt dest, const void *data, size_t n);
/* Every rank's bytes to every rank: *recv holds what arrived, rank after
 * rank, *nrecv bytes (PetscFree by the caller); rbytes (may be NULL; size
 * ranks, PetscFree by the caller): how many came from each rank. */
PetscErrorCode BwPackerExchange(MPI_Comm comm, BwPacker *p, char **recv, size_t *nrecv, int **rbytes);

/* Reads n bytes at *at and advances it. */
static inline void BwUnpack(const char **at, void *data, size_t n)
{
  if (n) memcpy(data, *at, n);
  *at += n;
}

/* The answer to `key` on the rank that holds it: nans integers. */
typedef PetscErrorCode (*BwQueryAnswer)(void *ctx, PetscInt key, PetscInt ans[]);
/* For each q < n: ask rank dest[q] about key[q]; its callback's answer
 * lands in values[nans q .. nans q + nans). Collective. */
PetscErrorCode BwQuery(MPI_Comm comm, PetscInt n, const PetscMPIInt dest[], const PetscInt key[], PetscInt nans, BwQueryAnswer answer, void *ctx, PetscInt values[]);
/* The same with answers of `size` bytes each, into values + size q. */
typedef PetscErrorCode (*BwQueryAnswerBytes)(void *ctx, PetscInt key, void *ans);
PetscErrorCode BwQueryBytes(MPI_Comm comm, PetscInt n, const PetscMPIInt dest[], const PetscInt key[], size_t size, BwQueryAnswerBytes answer, void *ctx, void *values);

/* The global offsets of ragged items with ids 0..N-1 spread over the ranks
 * in any order (this rank holds n of them, ids gids[] with counts[]):
 * offsets[q] = the sum of the counts of the items of smaller id, *total
 * the sum of all. The ids are split evenly over the ranks, each sums its
 * range in order: nothing of size N on any rank. Collective. */
PetscErrorCode BwRaggedOffsets(MPI_Comm comm, PetscInt n, const PetscInt gids[], const PetscInt counts[], PetscInt N, PetscInt offsets[], PetscInt *total);
