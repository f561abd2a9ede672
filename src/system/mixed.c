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
static PetscErrorCode BwMixedQScale(BwMixed mx, PetscInt b, const PetscReal **scale)
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
  PetscInt   *nr, *nq, *rnext, *qnext, *snext;

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
  PetscCall(BwMixedCheckRestraint(mx));

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
  PetscCall(PetscCalloc5(size + 1, &nr, size + 1, &nq, size, &rnext, size, &qnext, size, &snext));
  for (PetscInt k = 0; k < ni; k++) nr[mx->interface_owner[k]] += m2;
  for (PetscInt b = 0; b < nb; b++)
    for (PetscInt c = 0; c < 3; c++)
      if (!model->prescribed[3 * b + c]) nq[mx->block_owner[b]]++;
  {
    PetscInt start = 0;
    for (PetscMPIInt p = 0; p < size; p++) {
      rnext[p] = start;
      qnext[p] = start + nr[p];
      snext[p] = mx->nq_global;
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
  PetscCall(PetscMalloc3(3 * nb, &mx->dof, 3 * nb, &mx->sdof, ni, &mx->stress));
  for (PetscInt k = 0; k < ni; k++) {
    PetscMPIInt p = mx->interface_owner[k];
    mx->stress[k] = rnext[p];
    rnext[p] += m2;
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
  PetscCall(PetscFree5(nr, nq, rnext, qnext, snext));
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
  PetscCall(PetscFree3(mx->dof, mx->sdof, mx->stress));
  PetscCall(PetscFree2(mx->own_blocks, mx->own_interfaces));
  PetscCall(PetscFree(mx->qscale));
  PetscCall(MatDestroy(&mx->K));
  PetscCall(MatDestroy(&mx->S));
  PetscCall(VecDestroy(&mx->x));
  PetscCall(VecDestroy(&mx->b));
  PetscCall(ISDestroy(&mx->isr));
  PetscCall(ISDestroy(&mx->isq));
  PetscCall(PetscFree(*mixed));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static inline PetscBool BwOwnsRow(BwMixed mx, PetscInt row) { return row >= mx->rstart && row < mx->rstart + mx->nlocal; }

/* Exact preallocation of K and S from the layout. */
static PetscErrorCode BwMixedPreallocate(BwMixed mx)
{
  BwGeometry  geom = mx->geom;
  PetscInt    m2 = 2 * mx->m, *kd, *ko, *sd, *so, nbr[512];
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(mx->comm, &rank));
  PetscCall(PetscCalloc4(mx->nlocal, &kd, mx->nlocal, &ko, mx->nq_local, &sd, mx->nq_local, &so));
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
    PetscInt k = mx->own_interfaces[e], row = mx->stress[k] - mx->rstart, dn = 1, on = 0;
    for (PetscInt c = 0; c < 6; c++) {
      PetscInt blk = geom->pair[2 * k + c / 3], col = mx->dof[3 * blk + c % 3];
      if (col < 0) continue;
      if (BwOwnsRow(mx, col)) dn++;
      else on++;
    }
    for (PetscInt p = 0; p < m2; p++) {
      kd[row + p] = dn;
      ko[row + p] = on;
    }
  }
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e], dn = 0, on = 0, nn = 0, sdn = 0, son = 0;
    nbr[nn++] = b;
    for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) {
      PetscInt k = mx->adj[a];
      if (mx->interface_owner[k] == rank) dn += m2;
      else on += m2;
      PetscCheck(nn < 512, PETSC_COMM_SELF, PETSC_ERR_SUP, "block %" PetscInt_FMT " has more than 511 interfaces", b);
      nbr[nn++] = geom->pair[2 * k] == b ? geom->pair[2 * k + 1] : geom->pair[2 * k];
    }
    PetscCall(PetscSortRemoveDupsInt(&nn, nbr));
    for (PetscInt n = 0; n < nn; n++)
      for (PetscInt c = 0; c < 3; c++) {
        PetscInt col = mx->sdof[3 * nbr[n] + c];
        if (col < 0) continue;
        if (col >= mx->qstart && col < mx->qstart + mx->nq_local) sdn++;
        else son++;
      }
    for (PetscInt c = 0; c < 3; c++) {
      PetscInt row = mx->dof[3 * b + c];
      if (row < 0) continue;
      row -= mx->rstart;
      kd[row] = dn;
      ko[row] = on;
      sd[row - mx->nr_local] = sdn;
      so[row - mx->nr_local] = son;
    }
  }
  PetscCall(MatCreate(mx->comm, &mx->K));
  PetscCall(MatSetSizes(mx->K, mx->nlocal, mx->nlocal, PETSC_DETERMINE, PETSC_DETERMINE));
  PetscCall(MatSetType(mx->K, MATAIJ));
  PetscCall(MatSetOptionsPrefix(mx->K, "saddle_"));
  PetscCall(MatSetFromOptions(mx->K));
  PetscCall(MatXAIJSetPreallocation(mx->K, 1, kd, ko, NULL, NULL));
  PetscCall(MatSetOption(mx->K, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  PetscCall(MatSetOption(mx->K, MAT_SYMMETRIC, PETSC_TRUE));
  PetscCall(MatSetOption(mx->K, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
  PetscCall(MatCreate(mx->comm, &mx->S));
  PetscCall(MatSetSizes(mx->S, mx->nq_local, mx->nq_local, PETSC_DETERMINE, PETSC_DETERMINE));
  PetscCall(MatSetType(mx->S, MATAIJ));
  PetscCall(MatSetOptionsPrefix(mx->S, "schur_"));
  PetscCall(MatSetFromOptions(mx->S));
  PetscCall(MatXAIJSetPreallocation(mx->S, 1, sd, so, NULL, NULL));
  PetscCall(MatSetOption(mx->S, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  PetscCall(MatSetOption(mx->S, MAT_SPD, PETSC_TRUE));
  PetscCall(MatSetOption(mx->S, MAT_SPD_ETERNAL, PETSC_TRUE));
  PetscCall(PetscFree4(kd, ko, sd, so));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedAssemble(BwMixed mx)
{
  BwGeometry geom = mx->geom;
  BwModel    model = mx->model;
  PetscInt   m2 = 2 * mx->m, *cols, *idx;
  PetscReal *d, *g, *vals, s[36];

  PetscFunctionBeginUser;
  PetscCall(BwMixedPreallocate(mx));
  PetscCall(MatCreateVecs(mx->K, &mx->x, &mx->b));
  PetscCall(PetscMalloc4(6 * m2, &d, m2, &g, m2 + 8, &cols, m2 + 8, &vals));

  /* stress rows of owned interfaces: [ D^  -I ], rhs -G^{-1/2} D_p u_p */
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
    PetscInt         k = mx->own_interfaces[e];
    const PetscReal *sc[2];

    PetscCall(BwMixedInterfaceOperator(mx, k, d, g));
    PetscCall(BwMixedQScale(mx, geom->pair[2 * k], &sc[0]));
    PetscCall(BwMixedQScale(mx, geom->pair[2 * k + 1], &sc[1]));
    for (PetscInt p = 0; p < m2; p++) {
      PetscInt  row = mx->stress[k] + p, n = 0;
      PetscReal w = 1 / PetscSqrtReal(g[p]), rhs = 0;
      cols[n]   = row;
      vals[n++] = -1;
      for (PetscInt c = 0; c < 6; c++) {
        PetscInt blk = geom->pair[2 * k + c / 3], col = mx->dof[3 * blk + c % 3];
        if (col >= 0) {
          cols[n]   = col;
          vals[n++] = w * d[6 * p + c] * sc[c / 3][c % 3];
        } else rhs -= w * d[6 * p + c] * model->value[3 * blk + c % 3];
      }
      PetscCall(MatSetValues(mx->K, 1, &row, n, cols, vals, INSERT_VALUES));
      PetscCall(VecSetValue(mx->b, row, rhs, INSERT_VALUES));
    }
  }
  /* dof rows of owned blocks: [ D^T 0 ] in K, S^ = sum_k scaled S_k, rhs F^ */
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt         b = mx->own_blocks[e];
    const PetscReal *sb;

    PetscCall(BwMixedQScale(mx, b, &sb));
    for (PetscInt c = 0; c < 3; c++)
      if (mx->dof[3 * b + c] >= 0) PetscCall(VecSetValue(mx->b, mx->dof[3 * b + c], sb[c] * model->load[3 * b + c], INSERT_VALUES));
    for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) {
      PetscInt         k = mx->adj[a], side = BwSide(mx, k, b);
      const PetscReal *sc[2];

      PetscCall(BwMixedInterfaceOperator(mx, k, d, g));
      PetscCall(BwMixedInterfaceStiffness(mx, k, s));
      PetscCall(BwMixedQScale(mx, geom->pair[2 * k], &sc[0]));
      PetscCall(BwMixedQScale(mx, geom->pair[2 * k + 1], &sc[1]));
      for (PetscInt p = 0; p < m2; p++) cols[p] = mx->stress[k] + p;
      for (PetscInt c = 0; c < 3; c++) {
        PetscInt row = mx->dof[3 * b + c], n = 0;
        if (row < 0) continue;
        for (PetscInt p = 0; p < m2; p++) vals[p] = d[6 * p + side + c] / PetscSqrtReal(g[p]) * sb[c];
        PetscCall(MatSetValues(mx->K, 1, &row, m2, cols, vals, INSERT_VALUES));
        row = mx->sdof[3 * b + c];
        for (PetscInt c2 = 0; c2 < 6; c2++) {
          PetscInt blk = geom->pair[2 * k + c2 / 3], col = mx->sdof[3 * blk + c2 % 3];
          if (col < 0) continue;
          cols[m2 + n] = col; /* cols[0..m2) still holds the stress rows */
          vals[n++]    = s[6 * (side + c) + c2] * sb[c] * sc[c2 / 3][c2 % 3];
        }
        idx = cols + m2;
        PetscCall(MatSetValues(mx->S, 1, &row, n, idx, vals, ADD_VALUES));
      }
    }
  }
  PetscCall(PetscFree4(d, g, cols, vals));
  PetscCall(MatAssemblyBegin(mx->K, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyBegin(mx->S, MAT_FINAL_ASSEMBLY));
  PetscCall(VecAssemblyBegin(mx->b));
  PetscCall(MatAssemblyEnd(mx->K, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(mx->S, MAT_FINAL_ASSEMBLY));
  PetscCall(VecAssemblyEnd(mx->b));

  PetscCall(ISCreateStride(mx->comm, mx->nr_local, mx->rstart, 1, &mx->isr));
  PetscCall(ISCreateStride(mx->comm, mx->nq_local, mx->rstart + mx->nr_local, 1, &mx->isq));
  PetscFunctionReturn(PETSC_SUCCESS);
}
