/* Layout, assembly, recovery and self-check of the scaled mixed system
 * (see mixed.h for the equations and the block structure).
 *
 * Ownership: a rank owns the blocks the partition gives it and the
 * interfaces whose first block it owns (second block when the first has no
 * free dof, so that fixed supports do not pull work to one rank). It
 * assembles only its own rows: the 2m stress rows of its interfaces (D^ and
 * -I), the dof rows of its blocks (D^T, from every interface touching the
 * block, recomputed by the kernel rather than communicated), and the rows of
 * S^ for its blocks. No off-process values are stashed. */
#include "system/mixed.h"
#include "util/compat.h"
#include "blockwall/kernels.h"
#include "util/log.h"

static const char *const BwKernelMessages[] = {"ok", "has m < 1", "has a non-positive or non-finite length", "has a non-positive or non-finite depth", "has a non-positive or non-finite stiffness kn or kt"};

static PetscErrorCode BwKernelCheck(BwMixed mx, PetscInt k, int status)
{
  PetscFunctionBeginUser;
  PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "interface %" PetscInt_FMT " (blocks %" PetscInt_FMT ", %" PetscInt_FMT ") %s", k, mx->geom->pair[2 * k], mx->geom->pair[2 * k + 1], BwKernelMessages[status]);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* D_k (2m x 6, row-major) and g (2m) of interface k. */
static PetscErrorCode BwMixedInterfaceOperator(BwMixed mx, PetscInt k, PetscReal d[], PetscReal g[])
{
  BwGeometry geom = mx->geom;
  const PetscInt i = geom->pair[2 * k], j = geom->pair[2 * k + 1];
  int            status;

  PetscFunctionBeginUser;
  bw_interface_operator(&geom->centroid[2 * i], &geom->centroid[2 * j], &geom->center[2 * k], geom->angle[k], geom->length[k], geom->depth, mx->model->kn[k], mx->model->kt[k], (int)mx->m, d, g, &status);
  PetscCall(BwKernelCheck(mx, k, status));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwMixedInterfaceStiffness(BwMixed mx, PetscInt k, PetscReal s[36])
{
  BwGeometry geom = mx->geom;
  const PetscInt i = geom->pair[2 * k], j = geom->pair[2 * k + 1];
  int            status;

  PetscFunctionBeginUser;
  bw_interface_stiffness(&geom->centroid[2 * i], &geom->centroid[2 * j], &geom->center[2 * k], geom->angle[k], geom->length[k], geom->depth, mx->model->kn[k], mx->model->kt[k], (int)mx->m, s, &status);
  PetscCall(BwKernelCheck(mx, k, status));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Column offset (0 or 3) of block b in interface k's 6 columns. */
static inline PetscInt BwSide(BwMixed mx, PetscInt k, PetscInt b) { return mx->geom->pair[2 * k] == b ? 0 : 3; }

/* 1/sqrt(diag S) for the three dofs of block b, cached. */
PetscErrorCode BwMixedQScale(BwMixed mx, PetscInt b, const PetscReal **scale)
{
  PetscFunctionBeginUser;
  if (mx->qscale[3 * b] < 0) {
    PetscReal diag[3] = {0, 0, 0}, s[36];
    for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) {
      PetscInt k = mx->adj[a], side = BwSide(mx, k, b);
      PetscCall(BwMixedInterfaceStiffness(mx, k, s));
      for (PetscInt c = 0; c < 3; c++) diag[c] += s[(side + c) * 7];
    }
    /* A free dof without stiffness is caught as a mechanism before assembly;
     * prescribed dofs never use their scale. */
    for (PetscInt c = 0; c < 3; c++) mx->qscale[3 * b + c] = diag[c] > 0 ? 1 / PetscSqrtReal(diag[c]) : 0;
  }
  *scale = &mx->qscale[3 * b];
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedCreate(BwModel model, const PetscMPIInt owner[], BwMixed *mixed)
{
  BwMixed     mx;
  BwGeometry  geom = model->geom;
  PetscInt    nb = geom->nblocks, ni = geom->ninterfaces, m2;
  PetscMPIInt size, rank;
  PetscInt   *nr, *nq, *rnext, *qnext, *snext, *srnext;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&mx));
  mx->comm  = geom->comm;
  mx->geom  = geom;
  mx->model = model;
  mx->m     = model->m;
  m2        = 2 * mx->m;
  PetscCallMPI(MPI_Comm_size(mx->comm, &size));
  PetscCallMPI(MPI_Comm_rank(mx->comm, &rank));

  /* block -> interfaces */
  PetscCall(PetscCalloc1(nb + 1, &mx->adj_offsets));
  PetscCall(PetscMalloc1(2 * ni, &mx->adj));
  for (PetscInt k = 0; k < ni; k++) {
    mx->adj_offsets[geom->pair[2 * k] + 1]++;
    mx->adj_offsets[geom->pair[2 * k + 1] + 1]++;
  }
  for (PetscInt b = 0; b < nb; b++) mx->adj_offsets[b + 1] += mx->adj_offsets[b];
  {
    PetscInt *fill;
    PetscCall(PetscMalloc1(nb, &fill));
    PetscCall(PetscArraycpy(fill, mx->adj_offsets, nb));
    for (PetscInt k = 0; k < ni; k++) {
      mx->adj[fill[geom->pair[2 * k]]++]     = k;
      mx->adj[fill[geom->pair[2 * k + 1]]++] = k;
    }
    PetscCall(PetscFree(fill));
  }
  *mixed = mx; /* from here on, BwMixedDestroy cleans up after an error */
  PetscCall(PetscLogEventBegin(BwEvents[BW_EVENT_RESTRAINT], 0, 0, 0, 0));
  PetscCall(BwMixedCheckRestraint(mx));
  PetscCall(PetscLogEventEnd(BwEvents[BW_EVENT_RESTRAINT], 0, 0, 0, 0));

  /* owners */
  PetscCall(PetscMalloc2(nb, &mx->block_owner, ni, &mx->interface_owner));
  if (owner) PetscCall(PetscArraycpy(mx->block_owner, owner, nb));
  else {
    /* contiguous ranges of blocks, as PetscSplitOwnership would give */
    PetscInt b = 0;
    for (PetscMPIInt p = 0; p < size; p++) {
      PetscInt n = nb / size + (p < nb % size ? 1 : 0);
      for (PetscInt e = 0; e < n; e++) mx->block_owner[b++] = p;
    }
  }
  for (PetscInt k = 0; k < ni; k++) {
    PetscInt  i = geom->pair[2 * k], j = geom->pair[2 * k + 1];
    PetscBool ifixed = model->prescribed[3 * i] && model->prescribed[3 * i + 1] && model->prescribed[3 * i + 2];
    mx->interface_owner[k] = mx->block_owner[ifixed ? j : i];
  }

  /* numbering: rank p's rows are [its stresses | its free dofs] */
  PetscCall(PetscCalloc6(size + 1, &nr, size + 1, &nq, size, &rnext, size, &qnext, size, &snext, size, &srnext));
  for (PetscInt k = 0; k < ni; k++) nr[mx->interface_owner[k]] += m2;
  for (PetscInt b = 0; b < nb; b++)
    for (PetscInt c = 0; c < 3; c++)
      if (!model->prescribed[3 * b + c]) nq[mx->block_owner[b]]++;
  {
    PetscInt start = 0;
    for (PetscMPIInt p = 0; p < size; p++) {
      rnext[p] = start;
      qnext[p] = start + nr[p];
      snext[p]  = mx->nq_global;
      srnext[p] = mx->nr_global;
      if (p == rank) {
        mx->rstart = start;
        mx->qstart = mx->nq_global;
      }
      start += nr[p] + nq[p];
      mx->nr_global += nr[p];
      mx->nq_global += nq[p];
    }
  }
  mx->nr_local = nr[rank];
  mx->nq_local = nq[rank];
  mx->nlocal   = nr[rank] + nq[rank];
  PetscCall(PetscMalloc4(3 * nb, &mx->dof, 3 * nb, &mx->sdof, ni, &mx->stress, ni, &mx->srow));
  for (PetscInt k = 0; k < ni; k++) {
    PetscMPIInt p = mx->interface_owner[k];
    mx->stress[k] = rnext[p];
    mx->srow[k]   = srnext[p];
    rnext[p] += m2;
    srnext[p] += m2;
    if (p == rank) mx->nown_interfaces++;
  }
  for (PetscInt b = 0; b < nb; b++) {
    PetscMPIInt p = mx->block_owner[b];
    for (PetscInt c = 0; c < 3; c++) {
      mx->dof[3 * b + c]  = model->prescribed[3 * b + c] ? -1 : qnext[p]++;
      mx->sdof[3 * b + c] = model->prescribed[3 * b + c] ? -1 : snext[p]++;
    }
    if (p == rank) mx->nown_blocks++;
  }
  PetscCall(PetscFree6(nr, nq, rnext, qnext, snext, srnext));
  PetscCall(PetscMalloc2(mx->nown_blocks, &mx->own_blocks, mx->nown_interfaces, &mx->own_interfaces));
  {
    PetscInt n = 0;
    for (PetscInt b = 0; b < nb; b++)
      if (mx->block_owner[b] == rank) mx->own_blocks[n++] = b;
    n = 0;
    for (PetscInt k = 0; k < ni; k++)
      if (mx->interface_owner[k] == rank) mx->own_interfaces[n++] = k;
  }
  PetscCall(PetscMalloc1(3 * nb, &mx->qscale));
  for (PetscInt e = 0; e < 3 * nb; e++) mx->qscale[e] = -1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedDestroy(BwMixed *mixed)
{
  BwMixed mx = *mixed;

  PetscFunctionBeginUser;
  if (!mx) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFree(mx->adj_offsets));
  PetscCall(PetscFree(mx->adj));
  PetscCall(PetscFree2(mx->block_owner, mx->interface_owner));
  PetscCall(PetscFree4(mx->dof, mx->sdof, mx->stress, mx->srow));
  PetscCall(PetscFree2(mx->own_blocks, mx->own_interfaces));
  PetscCall(PetscFree(mx->qscale));
  PetscCall(MatDestroy(&mx->K));
  PetscCall(MatDestroy(&mx->D));
  PetscCall(MatDestroy(&mx->S));
  for (PetscInt k = 0; k < mx->nkeep; k++) PetscCall(PetscFree(mx->keep[k]));
  PetscCall(VecDestroy(&mx->x));
  PetscCall(VecDestroy(&mx->b));
  PetscCall(ISDestroy(&mx->isr));
  PetscCall(ISDestroy(&mx->isq));
  PetscCall(PetscFree(*mixed));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwMixedCreateAIJ(BwMixed mx, PetscInt m, PetscInt n, PetscInt M, PetscInt N, const char prefix[], Mat *A)
{
  PetscFunctionBeginUser;
  PetscCall(MatCreate(mx->comm, A));
  PetscCall(MatSetSizes(*A, m, n, M, N));
  PetscCall(MatSetType(*A, MATAIJ));
  PetscCall(MatSetOptionsPrefix(*A, prefix));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The saddle-point operator is stored as a MatNest of its four blocks:
 *   -I   a constant diagonal                          (no storage)
 *   D^   AIJ, at most 6 non-zeros per stress row      (~12 bytes per non-zero)
 *   D^T  the virtual transpose of D^                  (no storage)
 *   0    an empty AIJ                                 (row pointers only)
 * so the mixed operator costs little more than D^ itself; an assembled AIJ
 * of the whole saddle matrix (mixed.storage aij, and the direct path, which
 * needs it for MUMPS) stores D^ twice plus the diagonal. */
/* Sort a row's (column, value) pairs by column: rows hold at most a few
 * dozen entries, so insertion sort. */
static void BwSortRow(PetscInt n, PetscInt col[], PetscReal val[])
{
  for (PetscInt a = 1; a < n; a++) {
    PetscInt  c = col[a];
    PetscReal v = val[a];
    PetscInt  b = a - 1;
    for (; b >= 0 && col[b] > c; b--) {
      col[b + 1] = col[b];
      val[b + 1] = val[b];
    }
    col[b + 1] = c;
    val[b + 1] = v;
  }
}

/* The matrix from local CSR rows (global column indices, sorted), used in
 * place: on one rank as they are, on more split into the diagonal part
 * (local column indices) and the off-diagonal part (global), the layout
 * MPIAIJ keeps. PETSc does not copy them; they are freed with the BwMixed. */
static PetscErrorCode BwMatFromCSR(BwMixed mx, PetscInt m, PetscInt n, PetscInt M, PetscInt N, const char prefix[], PetscInt *ia, PetscInt *ja, PetscReal *va, Mat *A)
{
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(mx->comm, &size));
  PetscCheck(mx->nkeep + 6 <= 12, PETSC_COMM_SELF, PETSC_ERR_PLIB, "too many kept arrays");
  if (size == 1) {
    PetscCall(MatCreateSeqAIJWithArrays(mx->comm, m, n, ia, ja, va, A));
    mx->keep[mx->nkeep++] = ia;
    mx->keep[mx->nkeep++] = ja;
    mx->keep[mx->nkeep++] = va;
  } else {
    PetscInt  cstart, *di, *dj, *oi, *oj, nd = 0, no = 0;
    PetscReal *dv, *ov;
    PetscCallMPI(MPI_Scan(&n, &cstart, 1, MPIU_INT, MPI_SUM, mx->comm));
    cstart -= n;
    for (PetscInt e = 0; e < ia[m]; e++) {
      if (ja[e] >= cstart && ja[e] < cstart + n) nd++;
      else no++;
    }
    PetscCall(PetscMalloc1(m + 1, &di));
    PetscCall(PetscMalloc1(nd, &dj));
    PetscCall(PetscMalloc1(nd, &dv));
    PetscCall(PetscMalloc1(m + 1, &oi));
    PetscCall(PetscMalloc1(no, &oj));
    PetscCall(PetscMalloc1(no, &ov));
    di[0] = oi[0] = 0;
    for (PetscInt r = 0; r < m; r++) {
      di[r + 1] = di[r];
      oi[r + 1] = oi[r];
      for (PetscInt e = ia[r]; e < ia[r + 1]; e++) {
        if (ja[e] >= cstart && ja[e] < cstart + n) {
          dj[di[r + 1]]   = ja[e] - cstart;
          dv[di[r + 1]++] = va[e];
        } else {
          oj[oi[r + 1]]   = ja[e];
          ov[oi[r + 1]++] = va[e];
        }
      }
    }
    PetscCall(PetscFree(ia));
    PetscCall(PetscFree(ja));
    PetscCall(PetscFree(va));
    PetscCall(MatCreateMPIAIJWithSplitArrays(mx->comm, m, n, M, N, di, dj, dv, oi, oj, ov, A));
    mx->keep[mx->nkeep++] = di;
    mx->keep[mx->nkeep++] = dj;
    mx->keep[mx->nkeep++] = dv;
    mx->keep[mx->nkeep++] = oi;
    mx->keep[mx->nkeep++] = oj;
    mx->keep[mx->nkeep++] = ov;
  }
  PetscCall(MatSetOptionsPrefix(*A, prefix));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rows of D^ for the owned interfaces, built directly in CSR: a stress row
 * has one entry per free dof of the interface's two blocks. Also fills the
 * stress rows of the right-hand side (prescribed values lifted). */
static PetscErrorCode BwMixedAssembleD(BwMixed mx, PetscScalar bb[], Mat *D)
{
  BwGeometry geom = mx->geom;
  PetscInt   m2 = 2 * mx->m, *ia, *ja, n = 0;
  PetscReal *va, *d, *g;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(mx->nr_local + 1, &ia));
  ia[0] = 0;
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
    PetscInt k = mx->own_interfaces[e], nf = 0;
    for (PetscInt c = 0; c < 6; c++) nf += mx->sdof[3 * geom->pair[2 * k + c / 3] + c % 3] >= 0;
    for (PetscInt p = 0; p < m2; p++, n++) ia[n + 1] = ia[n] + nf;
  }
  PetscCall(PetscMalloc1(ia[mx->nr_local], &ja));
  PetscCall(PetscMalloc1(ia[mx->nr_local], &va));
  PetscCall(PetscMalloc2(6 * m2, &d, m2, &g));
  n = 0;
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
    PetscInt         k = mx->own_interfaces[e];
    const PetscReal *sc[2];

    PetscCall(BwMixedInterfaceOperator(mx, k, d, g));
    PetscCall(BwMixedQScale(mx, geom->pair[2 * k], &sc[0]));
    PetscCall(BwMixedQScale(mx, geom->pair[2 * k + 1], &sc[1]));
    for (PetscInt p = 0; p < m2; p++, n++) {
      PetscReal w = 1 / PetscSqrtReal(g[p]), rhs = 0;
      PetscInt  at = ia[n];
      for (PetscInt c = 0; c < 6; c++) {
        PetscInt blk = geom->pair[2 * k + c / 3], col = mx->sdof[3 * blk + c % 3];
        if (col >= 0) {
          ja[at]   = col;
          va[at++] = w * d[6 * p + c] * sc[c / 3][c % 3];
        } else rhs -= w * d[6 * p + c] * mx->model->value[3 * blk + c % 3];
      }
      BwSortRow(at - ia[n], ja + ia[n], va + ia[n]);
      if (bb) bb[mx->stress[k] + p - mx->rstart] = rhs;
    }
  }
  PetscCall(PetscFree2(d, g));
  PetscCall(BwMatFromCSR(mx, mx->nr_local, mx->nq_local, mx->nr_global, mx->nq_global, "mixed_D_", ia, ja, va, D));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rows of S^ for the owned blocks, in CSR: block b's row holds the free dofs
 * of b and of its neighbours, summed over every interface touching b (the
 * kernel is recomputed for interfaces another rank owns rather than
 * communicated). Also fills the dof rows of the right-hand side. */
static PetscErrorCode BwMixedAssembleS(BwMixed mx, PetscScalar bb[])
{
  BwGeometry geom = mx->geom;
  PetscInt  *ia, *ja, nrow = 0, *nbr, ncol, *col, maxdeg = 0;
  PetscReal *va, s[36], *acc[3];

  PetscFunctionBeginUser;
  /* work arrays sized by the largest number of interfaces of an owned block
   * (a foundation under a whole wall has one per unit of the bottom course) */
  for (PetscInt e = 0; e < mx->nown_blocks; e++) maxdeg = PetscMax(maxdeg, mx->adj_offsets[mx->own_blocks[e] + 1] - mx->adj_offsets[mx->own_blocks[e]]);
  PetscCall(PetscMalloc5(maxdeg + 1, &nbr, 3 * (maxdeg + 1), &col, 3 * (maxdeg + 1), &acc[0], 3 * (maxdeg + 1), &acc[1], 3 * (maxdeg + 1), &acc[2]));
  /* pass 1: row lengths */
  PetscCall(PetscMalloc1(mx->nq_local + 1, &ia));
  ia[0] = 0;
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e], nn = 0, len = 0;
    nbr[nn++] = b;
    for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) {
      PetscInt k = mx->adj[a];
      nbr[nn++] = geom->pair[2 * k] == b ? geom->pair[2 * k + 1] : geom->pair[2 * k];
    }
    PetscCall(PetscSortRemoveDupsInt(&nn, nbr));
    for (PetscInt q = 0; q < nn; q++)
      for (PetscInt c = 0; c < 3; c++) len += mx->sdof[3 * nbr[q] + c] >= 0;
    for (PetscInt c = 0; c < 3; c++)
      if (mx->sdof[3 * b + c] >= 0) {
        ia[nrow + 1] = ia[nrow] + len;
        nrow++;
      }
  }
  PetscCall(PetscMalloc1(ia[nrow], &ja));
  PetscCall(PetscMalloc1(ia[nrow], &va));
  /* pass 2: values */
  nrow = 0;
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt         b = mx->own_blocks[e], nn = 0;
    const PetscReal *sb;

    PetscCall(BwMixedQScale(mx, b, &sb));
    for (PetscInt c = 0; c < 3; c++)
      if (mx->dof[3 * b + c] >= 0) bb[mx->dof[3 * b + c] - mx->rstart] = sb[c] * mx->model->load[3 * b + c];
    nbr[nn++] = b;
    for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) {
      PetscInt k = mx->adj[a];
      nbr[nn++] = geom->pair[2 * k] == b ? geom->pair[2 * k + 1] : geom->pair[2 * k];
    }
    PetscCall(PetscSortRemoveDupsInt(&nn, nbr));
    ncol = 0;
    for (PetscInt q = 0; q < nn; q++)
      for (PetscInt c = 0; c < 3; c++)
        if (mx->sdof[3 * nbr[q] + c] >= 0) col[ncol++] = mx->sdof[3 * nbr[q] + c];
    for (PetscInt r = 0; r < 3; r++)
      for (PetscInt f = 0; f < ncol; f++) acc[r][f] = 0;
    for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) {
      PetscInt         k = mx->adj[a], side = BwSide(mx, k, b);
      const PetscReal *sc[2];
      PetscCall(BwMixedInterfaceStiffness(mx, k, s));
      PetscCall(BwMixedQScale(mx, geom->pair[2 * k], &sc[0]));
      PetscCall(BwMixedQScale(mx, geom->pair[2 * k + 1], &sc[1]));
      for (PetscInt c2 = 0; c2 < 6; c2++) {
        PetscInt cidx = mx->sdof[3 * geom->pair[2 * k + c2 / 3] + c2 % 3], f = 0;
        if (cidx < 0) continue;
        while (col[f] != cidx) f++;
        for (PetscInt r = 0; r < 3; r++) acc[r][f] += s[6 * (side + r) + c2] * sc[c2 / 3][c2 % 3];
      }
    }
    for (PetscInt r = 0; r < 3; r++) {
      if (mx->sdof[3 * b + r] < 0) continue;
      for (PetscInt f = 0; f < ncol; f++) {
        ja[ia[nrow] + f] = col[f];
        va[ia[nrow] + f] = acc[r][f] * sb[r];
      }
      BwSortRow(ncol, ja + ia[nrow], va + ia[nrow]);
      nrow++;
    }
  }
  PetscCall(PetscFree5(nbr, col, acc[0], acc[1], acc[2]));
  PetscCall(BwMatFromCSR(mx, mx->nq_local, mx->nq_local, mx->nq_global, mx->nq_global, "schur_", ia, ja, va, &mx->S));
  PetscFunctionReturn(PETSC_SUCCESS);
}

const char *const BwStorages[] = {"shell", "nest", "aij", "BwStorage", "BW_STORAGE_", NULL};

/* K = [-I, D; D^T, 0] as a MatNest around the given D. */
static PetscErrorCode BwMixedNest(BwMixed mx, Mat D, Mat *K)
{
  Mat A00, A11, Dt, blocks[4];
  IS  is[2];

  PetscFunctionBeginUser;
  PetscCall(MatCreateConstantDiagonal(mx->comm, mx->nr_local, mx->nr_local, mx->nr_global, mx->nr_global, -1.0, &A00));
  PetscCall(MatCreateTranspose(D, &Dt));
  PetscCall(BwMixedCreateAIJ(mx, mx->nq_local, mx->nq_local, mx->nq_global, mx->nq_global, "mixed_zero_", &A11));
  PetscCall(MatXAIJSetPreallocation(A11, 1, NULL, NULL, NULL, NULL));
  PetscCall(MatAssemblyBegin(A11, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(A11, MAT_FINAL_ASSEMBLY));
  blocks[0] = A00;
  blocks[1] = D;
  blocks[2] = Dt;
  blocks[3] = A11;
  is[0]     = mx->isr;
  is[1]     = mx->isq;
  PetscCall(MatCreateNest(mx->comm, 2, is, 2, is, blocks, K));
  PetscCall(MatDestroy(&A00));
  PetscCall(MatDestroy(&Dt));
  PetscCall(MatDestroy(&A11));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedAssemble(BwMixed mx)
{
  PetscScalar *bb;

  PetscFunctionBeginUser;
  PetscCall(VecCreateMPI(mx->comm, mx->nlocal, PETSC_DETERMINE, &mx->b));
  PetscCall(VecDuplicate(mx->b, &mx->x));
  PetscCall(VecGetArray(mx->b, &bb));
  PetscCall(PetscLogEventBegin(BwEvents[BW_EVENT_ASSEMBLE_D], 0, 0, 0, 0));
  if (mx->storage == BW_STORAGE_SHELL) PetscCall(BwMixedCreateDShell(mx, bb, &mx->D));
  else PetscCall(BwMixedAssembleD(mx, bb, &mx->D));
  PetscCall(PetscLogEventEnd(BwEvents[BW_EVENT_ASSEMBLE_D], 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(BwEvents[BW_EVENT_ASSEMBLE_S], 0, 0, 0, 0));
  PetscCall(BwMixedAssembleS(mx, bb));
  PetscCall(PetscLogEventEnd(BwEvents[BW_EVENT_ASSEMBLE_S], 0, 0, 0, 0));
  PetscCall(VecRestoreArray(mx->b, &bb));
  PetscCall(MatSetOption(mx->S, MAT_SPD, PETSC_TRUE));
  PetscCall(MatSetOption(mx->S, MAT_SPD_ETERNAL, PETSC_TRUE));
  PetscCall(ISCreateStride(mx->comm, mx->nr_local, mx->rstart, 1, &mx->isr));
  PetscCall(ISCreateStride(mx->comm, mx->nq_local, mx->rstart + mx->nr_local, 1, &mx->isq));
  PetscCall(BwMixedNest(mx, mx->D, &mx->K));
  if (mx->storage == BW_STORAGE_AIJ) {
    Mat aij;
    PetscCall(BwMixedGetAIJ(mx, &aij));
    PetscCall(MatDestroy(&mx->K));
    mx->K = aij;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedGetAIJ(BwMixed mx, Mat *aij)
{
  PetscBool isaij, shell;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)mx->K, MATMPIAIJ, &isaij));
  if (!isaij) PetscCall(PetscObjectTypeCompare((PetscObject)mx->K, MATSEQAIJ, &isaij));
  PetscCall(PetscObjectTypeCompare((PetscObject)mx->D, MATSHELL, &shell));
  if (isaij) {
    PetscCall(PetscObjectReference((PetscObject)mx->K));
    *aij = mx->K;
  } else if (shell) {
    /* MUMPS needs entries: D^ assembled for the occasion */
    Mat D, K;
    PetscCall(BwMixedAssembleD(mx, NULL, &D));
    PetscCall(BwMixedNest(mx, D, &K));
    PetscCall(MatConvert(K, MATAIJ, MAT_INITIAL_MATRIX, aij));
    PetscCall(MatDestroy(&K));
    PetscCall(MatDestroy(&D));
  } else PetscCall(MatConvert(mx->K, MATAIJ, MAT_INITIAL_MATRIX, aij));
  PetscFunctionReturn(PETSC_SUCCESS);
}
