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
  PetscCall(PetscMalloc1(mx->nd * g->nblocks, &mx->qscale));
  PetscCall(PetscCalloc1(g->nblocks, &need));
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e];
    need[b]    = PETSC_TRUE;
    for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) need[g->pair[2 * mx->adj[a]]] = need[g->pair[2 * mx->adj[a] + 1]] = PETSC_TRUE;
  }
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) need[g->pair[2 * mx->own_interfaces[e]]] = need[g->pair[2 * mx->own_interfaces[e] + 1]] = PETSC_TRUE;
  for (PetscInt b = 0; b < g->nblocks; b++) {
    const PetscInt nd = mx->nd;
    PetscReal      diag[BW_MAX_ND] = {0};
    for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1] && need[b]; a++) {
      PetscInt  k = mx->adj[a], side = BwSide(mx, k, b);
      PetscReal        rb[2 * BW_MAX_ND * BW_MAX_ND], kg[BW_MAX_ND * BW_MAX_ND], s[4 * BW_MAX_ND * BW_MAX_ND], c[BW_MAX_NS * BW_MAX_NS];
      const PetscReal *area, *xi, *eta;
      PetscInt         np = BwMixedPortions(mx, k, &area, &xi, &eta, NULL);
      int              status;
      BwMixedElasticTangent(mx, k, c);
      PetscCall(BwMixedCompatibility(mx, k, rb));
      bw_kernel_condense((int)mx->dim, (int)np, area, xi, eta, 1, c, kg, &status);
      PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "kernel failed on interface %" PetscInt_FMT, k);
      bw_kernel_stiffness((int)mx->dim, rb, kg, s, &status);
      for (PetscInt c3 = 0; c3 < nd; c3++) diag[c3] += s[(side + c3) * (2 * nd + 1)];
    }
    for (PetscInt c3 = 0; c3 < nd; c3++) mx->qscale[nd * b + c3] = !mx->model->prescribed[nd * b + c3] && diag[c3] > 0 ? 1 / PetscSqrtReal(diag[c3]) : 1;
  }
  PetscCall(PetscFree(need));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 3D: the interface polygons in their own coordinates, cut into portions. */
static PetscErrorCode BwMixedCreatePortions3D(BwMixed mx)
{
  BwGeometry     g  = mx->geom;
  const PetscInt ni = g->ninterfaces;
  PetscReal     *local;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(2 * (size_t)g->poly_offsets[ni] + 1, &local));
  for (PetscInt k = 0; k < ni; k++) BwGeometryInterfaceLocal(g, k, local + 2 * g->poly_offsets[k]);
  PetscCall(BwPortionsCreate3D(ni, g->poly_offsets, local, mx->m, mx->model->mb, &mx->portions));
  PetscCall(PetscFree(local));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedCreate(BwModel model, const PetscMPIInt owner[], BwMixed *mixed)
{
  BwMixed     mx;
  BwGeometry  geom = model->geom;
  PetscInt    nb = geom->nblocks, ni = geom->ninterfaces;
  PetscMPIInt size, rank;
  PetscInt   *nr, *nq, *knext, *qnext, *rnext, *krnext;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&mx));
  mx->comm  = geom->comm;
  mx->geom  = geom;
  mx->model = model;
  mx->spring_block = -1;
  mx->spring_written = -1;
  mx->m     = model->m;
  mx->dim   = geom->dim;
  mx->nd    = geom->dim == 3 ? 6 : 3;
  mx->ns    = geom->dim == 3 ? 3 : 2;
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
  if (geom->dim == 3) PetscCall(BwMixedCreatePortions3D(mx));
  else PetscCall(BwPortionsCreate2D(ni, geom->pair, geom->length, geom->depth, mx->m, &mx->portions));
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
    mx->interface_owner[k] = mx->block_owner[BwHasUnknowns(mx, i) ? i : j];
  }

  /* numbering: rank p's rows of K are [its stresses | its blocks' dofs] */
  PetscCall(PetscCalloc6(size + 1, &nr, size + 1, &nq, size, &knext, size, &qnext, size, &rnext, size, &krnext));
  for (PetscInt k = 0; k < ni; k++) nr[mx->interface_owner[k]] += mx->ns * BwPortionsCount(&mx->portions, k);
  for (PetscInt b = 0; b < nb; b++)
    if (BwHasUnknowns(mx, b)) nq[mx->block_owner[b]] += mx->nd;
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
    krnext[p] += mx->ns * BwPortionsCount(&mx->portions, k);
    rnext[p] += mx->ns * BwPortionsCount(&mx->portions, k);
    if (p == rank) mx->nown_interfaces++;
  }
  for (PetscInt b = 0; b < nb; b++) {
    PetscMPIInt p = mx->block_owner[b];
    if (BwHasUnknowns(mx, b)) {
      mx->krow_q[b] = knext[p];
      mx->qrow[b]   = qnext[p];
      knext[p] += mx->nd;
      qnext[p] += mx->nd;
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
  own->nblocks         = mx->geom->nblocks;
  own->ninterfaces     = mx->geom->ninterfaces;
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
  PetscInt    ni = mx->geom->ninterfaces, *next, *index;
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(mx->comm, &size));
  PetscCall(PetscCalloc2(size + 1, &next, ni + 1, &index));
  for (PetscInt k = 0; k < ni; k++) next[mx->interface_owner[k] + 1]++;
  for (PetscMPIInt p = 0; p < size; p++) next[p + 1] += next[p];
  for (PetscInt k = 0; k < ni; k++) index[k] = next[mx->interface_owner[k]]++;
  for (PetscInt e = 0; e < mx->nkg; e++) slot[e] = index[mx->kg_interfaces[e]];
  PetscCall(PetscFree2(next, index));
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
  PetscReal      lo[3] = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[3] = {PETSC_MIN_REAL, PETSC_MIN_REAL, PETSC_MIN_REAL}, size = 0, pmax = 0;
  PetscScalar   *w;

  PetscFunctionBeginUser;
  for (PetscInt v = 0; v < geom->nvertices; v++)
    for (PetscInt c = 0; c < d; c++) {
      lo[c] = PetscMin(lo[c], geom->vertices[d * v + c]);
      hi[c] = PetscMax(hi[c], geom->vertices[d * v + c]);
    }
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
