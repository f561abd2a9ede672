/* BwMixed's layout: who owns what, the numbering of the unknowns, the dof
 * scales, and the accessors (see mixed.h for the system itself).
 *
 * Ownership: a rank owns the blocks the partition gives it and the
 * interfaces whose first block it owns (the second block's owner when the
 * first has no free dof, so that fixed supports do not pull work to one
 * rank). It assembles only its own rows: the 2m stress rows of its
 * interfaces and the 3 dof rows of its blocks that have free dofs; nothing
 * is stashed for another rank. */
#include "system/mixed_impl.h"
#include "util/compat.h"
#include "blockwall/kernels.h"

const char *const BwStorages[] = {"shell", "nest", "aij", "BwStorage", "BW_STORAGE_", NULL};

static PetscBool BwHasUnknowns(BwModel model, PetscInt b)
{
  return (PetscBool)!(model->prescribed[3 * b] && model->prescribed[3 * b + 1] && model->prescribed[3 * b + 2]);
}

PetscErrorCode BwMixedCompatibility(BwMixed mx, PetscInt k, PetscReal rb[18])
{
  BwGeometry     g = mx->geom;
  const PetscInt i = g->pair[2 * k], j = g->pair[2 * k + 1];
  int            status;

  PetscFunctionBeginUser;
  bw_interface_compatibility(&g->centroid[2 * i], &g->centroid[2 * j], &g->center[2 * k], g->angle[k], rb, &status);
  PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "kernel failed on interface %" PetscInt_FMT, k);
  PetscFunctionReturn(PETSC_SUCCESS);
}

void BwMixedStiffnessRoots(BwMixed mx, PetscInt k, PetscReal *skt, PetscReal *skn)
{
  *skt = PetscSqrtReal(mx->model->kt[k]);
  *skn = PetscSqrtReal(mx->model->kn[k]);
}

/* 1/sqrt(diag S) per free dof of the elastic system: the dof's own stiffness
 * summed over its block's interfaces, whichever rank owns them (the kernel
 * is recomputed rather than communicated), for the blocks this rank uses:
 * its own and those of the interfaces touching them or owned by it. A free
 * dof without stiffness is caught as a mechanism before; a prescribed dof
 * has scale 1. */
static PetscErrorCode BwMixedScales(BwMixed mx)
{
  BwGeometry g = mx->geom;
  PetscBool *need;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(3 * g->nblocks, &mx->qscale));
  PetscCall(PetscCalloc1(g->nblocks, &need));
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e];
    need[b]    = PETSC_TRUE;
    for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) need[g->pair[2 * mx->adj[a]]] = need[g->pair[2 * mx->adj[a] + 1]] = PETSC_TRUE;
  }
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) need[g->pair[2 * mx->own_interfaces[e]]] = need[g->pair[2 * mx->own_interfaces[e] + 1]] = PETSC_TRUE;
  for (PetscInt b = 0; b < g->nblocks; b++) {
    PetscReal diag[3] = {0, 0, 0};
    for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1] && need[b]; a++) {
      PetscInt  k = mx->adj[a], side = BwSide(mx, k, b);
      PetscReal        rb[18], kg[9], s[36], c[4] = {mx->model->kt[k], 0, 0, mx->model->kn[k]};
      const PetscReal *area, *xi, *eta;
      PetscInt         np = BwMixedPortions(mx, k, &area, &xi, &eta, NULL);
      int              status;
      PetscCall(BwMixedCompatibility(mx, k, rb));
      bw_kernel_condense(2, (int)np, area, xi, eta, 1, c, kg, &status);
      PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "kernel failed on interface %" PetscInt_FMT, k);
      bw_kernel_stiffness(2, rb, kg, s, &status);
      for (PetscInt c3 = 0; c3 < 3; c3++) diag[c3] += s[(side + c3) * 7];
    }
    for (PetscInt c3 = 0; c3 < 3; c3++) mx->qscale[3 * b + c3] = !mx->model->prescribed[3 * b + c3] && diag[c3] > 0 ? 1 / PetscSqrtReal(diag[c3]) : 1;
  }
  PetscCall(PetscFree(need));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedCreate(BwModel model, const PetscMPIInt owner[], BwMixed *mixed)
{
  BwMixed     mx;
  BwGeometry  geom = model->geom;
  PetscInt    nb = geom->nblocks, ni = geom->ninterfaces, m2;
  PetscMPIInt size, rank;
  PetscInt   *nr, *nq, *knext, *qnext, *rnext, *krnext;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&mx));
  mx->comm  = geom->comm;
  mx->geom  = geom;
  mx->model = model;
  mx->spring_block = -1;
  mx->m     = model->m;
  m2        = 2 * mx->m;
  PetscCallMPI(MPI_Comm_size(mx->comm, &size));
  PetscCallMPI(MPI_Comm_rank(mx->comm, &rank));

  /* block -> interfaces */
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
  PetscCall(BwPortionsCreate2D(ni, geom->pair, geom->length, geom->depth, mx->m, &mx->portions));
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
    PetscInt i = geom->pair[2 * k], j = geom->pair[2 * k + 1];
    mx->interface_owner[k] = mx->block_owner[BwHasUnknowns(model, i) ? i : j];
  }

  /* numbering: rank p's rows of K are [its stresses | its blocks' dofs] */
  PetscCall(PetscCalloc6(size + 1, &nr, size + 1, &nq, size, &knext, size, &qnext, size, &rnext, size, &krnext));
  for (PetscInt k = 0; k < ni; k++) nr[mx->interface_owner[k]] += m2;
  for (PetscInt b = 0; b < nb; b++)
    if (BwHasUnknowns(model, b)) nq[mx->block_owner[b]] += 3;
  {
    PetscInt start = 0;
    for (PetscMPIInt p = 0; p < size; p++) {
      krnext[p] = start;
      knext[p]  = start + nr[p];
      qnext[p]  = mx->nq_global;
      rnext[p]  = mx->nr_global;
      if (p == rank) {
        mx->kstart = start;
        mx->qstart = mx->nq_global;
        mx->rstart = mx->nr_global;
      }
      start += nr[p] + nq[p];
      mx->nr_global += nr[p];
      mx->nq_global += nq[p];
    }
  }
  mx->nr_local = nr[rank];
  mx->nq_local = nq[rank];
  mx->nlocal   = nr[rank] + nq[rank];
  PetscCall(PetscMalloc4(nb, &mx->krow_q, nb, &mx->qrow, ni, &mx->krow_r, ni, &mx->rrow));
  for (PetscInt k = 0; k < ni; k++) {
    PetscMPIInt p = mx->interface_owner[k];
    mx->krow_r[k] = krnext[p];
    mx->rrow[k]   = rnext[p];
    krnext[p] += m2;
    rnext[p] += m2;
    if (p == rank) mx->nown_interfaces++;
  }
  for (PetscInt b = 0; b < nb; b++) {
    PetscMPIInt p = mx->block_owner[b];
    if (BwHasUnknowns(model, b)) {
      mx->krow_q[b] = knext[p];
      mx->qrow[b]   = qnext[p];
      knext[p] += 3;
      qnext[p] += 3;
      if (p == rank) mx->nown_q++;
    } else mx->krow_q[b] = mx->qrow[b] = -1;
    if (p == rank) mx->nown_blocks++;
  }
  PetscCall(PetscFree6(nr, nq, knext, qnext, rnext, krnext));
  PetscCall(PetscMalloc2(mx->nown_blocks + 1, &mx->own_blocks, mx->nown_interfaces + 1, &mx->own_interfaces));
  {
    PetscInt n = 0;
    for (PetscInt b = 0; b < nb; b++)
      if (mx->block_owner[b] == rank) mx->own_blocks[n++] = b;
    n = 0;
    for (PetscInt k = 0; k < ni; k++)
      if (mx->interface_owner[k] == rank) mx->own_interfaces[n++] = k;
  }
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e];
    mx->maxdeg = PetscMax(mx->maxdeg, mx->adj_offsets[b + 1] - mx->adj_offsets[b]);
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
  PetscCall(PetscFree2(mx->block_owner, mx->interface_owner));
  PetscCall(PetscFree4(mx->krow_q, mx->qrow, mx->krow_r, mx->rrow));
  PetscCall(PetscFree2(mx->own_blocks, mx->own_interfaces));
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
  own->nblocks         = mx->geom->nblocks;
  own->ninterfaces     = mx->geom->ninterfaces;
  own->m               = mx->m;
  own->nown_blocks     = mx->nown_blocks;
  own->nown_interfaces = mx->nown_interfaces;
  own->own_blocks      = mx->own_blocks;
  own->own_interfaces  = mx->own_interfaces;
  own->nq_global       = mx->nq_global;
  own->nr_global       = mx->nr_global;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedGetModel(BwMixed mx, BwModel *model)
{
  PetscFunctionBeginUser;
  *model = mx->model;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedSetNearNullSpace(BwMixed mx)
{
  Vec          v[3];
  MatNullSpace nsp;
  BwGeometry   geom = mx->geom;
  PetscReal    x0[2] = {0, 0};
  PetscScalar *a[3];

  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < geom->nblocks; b++)
    for (PetscInt c = 0; c < 2; c++) x0[c] += geom->centroid[2 * b + c] / geom->nblocks;
  for (PetscInt r = 0; r < 3; r++) {
    PetscCall(MatCreateVecs(mx->S, &v[r], NULL));
    PetscCall(VecGetArray(v[r], &a[r]));
  }
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e], row = mx->qrow[b] - mx->qstart;
    if (mx->qrow[b] < 0) continue;
    for (PetscInt r = 0; r < 3; r++) {
      PetscReal u[3];
      if (r < 2) {
        u[0] = r == 0;
        u[1] = r == 1;
        u[2] = 0;
      } else {
        u[0] = -(geom->centroid[2 * b + 1] - x0[1]);
        u[1] = geom->centroid[2 * b] - x0[0];
        u[2] = 1;
      }
      /* q~ = diag(S)^{1/2} q; prescribed dofs do not move */
      for (PetscInt c = 0; c < 3; c++) a[r][row + c] = mx->model->prescribed[3 * b + c] ? 0 : u[c] / mx->qscale[3 * b + c];
    }
  }
  for (PetscInt r = 0; r < 3; r++) PetscCall(VecRestoreArray(v[r], &a[r]));
  /* MatNullSpaceCreate wants orthonormal vectors */
  PetscCall(VecNormalize(v[0], NULL));
  for (PetscInt r = 1; r < 3; r++) {
    PetscScalar dots[2];
    PetscCall(VecMDot(v[r], r, v, dots));
    for (PetscInt j = 0; j < r; j++) dots[j] = -dots[j];
    PetscCall(VecMAXPY(v[r], r, dots, v));
    PetscCall(VecNormalize(v[r], NULL));
  }
  PetscCall(MatNullSpaceCreate(mx->comm, PETSC_FALSE, 3, v, &nsp));
  PetscCall(MatSetNearNullSpace(mx->S, nsp));
  PetscCall(MatNullSpaceDestroy(&nsp));
  for (PetscInt r = 0; r < 3; r++) PetscCall(VecDestroy(&v[r]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedForwardWeights(BwMixed mx, Vec weight, PetscReal *prescribed)
{
  BwGeometry   geom = mx->geom;
  PetscReal    lo[2] = {PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[2] = {PETSC_MIN_REAL, PETSC_MIN_REAL}, size, pmax = 0;
  PetscScalar *w;

  PetscFunctionBeginUser;
  for (PetscInt v = 0; v < geom->nvertices; v++)
    for (PetscInt c = 0; c < 2; c++) {
      lo[c] = PetscMin(lo[c], geom->vertices[2 * v + c]);
      hi[c] = PetscMax(hi[c], geom->vertices[2 * v + c]);
    }
  size = PetscSqrtReal(PetscSqr(hi[0] - lo[0]) + PetscSqr(hi[1] - lo[1]));
  PetscCall(VecGetArray(weight, &w));
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e];
    for (PetscInt c = 0; c < 3; c++) {
      PetscReal arm = c == 2 ? size : 1;
      /* q = diag(S)^-1/2 q~; rotations times the assembly's size */
      if (mx->qrow[b] >= 0) w[mx->qrow[b] - mx->qstart + c] = mx->model->prescribed[3 * b + c] ? 0 : mx->qscale[3 * b + c] * arm;
      if (mx->model->prescribed[3 * b + c]) pmax = PetscMax(pmax, PetscAbsReal(mx->model->value[3 * b + c]) * arm);
    }
  }
  PetscCall(VecRestoreArray(weight, &w));
  PetscCallMPI(MPIU_Allreduce(&pmax, prescribed, 1, MPIU_REAL, MPIU_MAX, mx->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}
