/* From the scaled solution back to physical results, and the self-check.
 *
 *   q = diag(S)^{-1/2} q~ (prescribed dofs take their values),  r = G^{-1/2} r~
 *   (r_p = r~_p (a_t, a_n) / A_p per portion, a = sqrt(A_p k))
 *   dG = R B q, (T, N, M) = H r            (kernels bw_interface_compatibility, bw_kernel_resultants)
 *   reaction_b = (D^T r)_b - F_b  at prescribed dofs      (model.md)
 *
 * A rank needs the stresses of every interface touching its blocks and the
 * dofs of both blocks of its interfaces: one scatter brings them. */
#include "system/mixed_impl.h"
#include "util/compat.h"
#include "blockwall/kernels.h"
#include "util/log.h"

typedef struct {
  PetscInt           nint, *ints; /* interfaces needed, sorted */
  PetscInt          *roff;        /* per needed interface: offset of its stresses in r, -1 when this rank holds them */
  PetscInt           nblk, *blks; /* blocks needed, sorted */
  PetscReal         *r;           /* 2m per interface held elsewhere, physical */
  PetscReal         *q;           /* 3 per needed block, physical */
  Vec                x;           /* the solution, read in place for what this rank holds */
  const PetscScalar *xl;
} BwGhosts;

static PetscErrorCode BwGhostsGather(BwMixed mx, Vec x, BwGhosts *gh)
{
  BwGeometry         geom = mx->geom;
  PetscInt           m2 = 2 * mx->m, n, *from, lo = mx->kstart, hi = mx->kstart + mx->nlocal, nremote = 0, nrint = 0;
  IS                 isfrom;
  Vec                loc;
  VecScatter         sct;
  const PetscScalar *a;

  PetscFunctionBeginUser;
  /* needed interfaces and blocks */
  n = mx->nown_interfaces;
  for (PetscInt e = 0; e < mx->nown_blocks; e++) n += mx->adj_offsets[mx->own_blocks[e] + 1] - mx->adj_offsets[mx->own_blocks[e]];
  PetscCall(PetscMalloc1(n, &gh->ints));
  gh->nint = 0;
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) gh->ints[gh->nint++] = mx->own_interfaces[e];
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e];
    for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) gh->ints[gh->nint++] = mx->adj[a];
  }
  PetscCall(PetscSortRemoveDupsInt(&gh->nint, gh->ints));
  PetscCall(PetscMalloc1(mx->nown_blocks + 2 * gh->nint, &gh->blks));
  gh->nblk = 0;
  for (PetscInt e = 0; e < mx->nown_blocks; e++) gh->blks[gh->nblk++] = mx->own_blocks[e];
  for (PetscInt e = 0; e < gh->nint; e++) {
    gh->blks[gh->nblk++] = geom->pair[2 * gh->ints[e]];
    gh->blks[gh->nblk++] = geom->pair[2 * gh->ints[e] + 1];
  }
  PetscCall(PetscSortRemoveDupsInt(&gh->nblk, gh->blks));

  /* Entries this rank holds are read in place (no copy of its stresses);
   * one scatter brings the others (none on one rank), in the order they
   * are used below. */
  PetscCall(PetscMalloc1(gh->nint + 1, &gh->roff));
  for (PetscInt e = 0; e < gh->nint; e++) {
    PetscInt row = mx->krow_r[gh->ints[e]];
    gh->roff[e]  = row < lo || row >= hi ? m2 * nrint++ : -1;
  }
  nremote = m2 * nrint;
  for (PetscInt e = 0; e < gh->nblk; e++) {
    PetscInt row = mx->krow_q[gh->blks[e]];
    if (row >= 0 && (row < lo || row >= hi)) nremote += 3;
  }
  PetscCall(PetscMalloc1(nremote + 1, &from));
  n = 0;
  for (PetscInt e = 0; e < gh->nint; e++)
    if (gh->roff[e] >= 0)
      for (PetscInt p = 0; p < m2; p++) from[n++] = mx->krow_r[gh->ints[e]] + p;
  for (PetscInt e = 0; e < gh->nblk; e++) {
    PetscInt row = mx->krow_q[gh->blks[e]];
    if (row >= 0 && (row < lo || row >= hi))
      for (PetscInt c = 0; c < 3; c++) from[n++] = row + c;
  }
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, n, from, PETSC_OWN_POINTER, &isfrom));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, n, &loc));
  PetscCall(VecScatterCreate(x, isfrom, loc, NULL, &sct));
  PetscCall(VecScatterBegin(sct, x, loc, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sct, x, loc, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterDestroy(&sct));
  PetscCall(ISDestroy(&isfrom));

  /* unscale what came from elsewhere; this rank's own stays in x */
  PetscCall(PetscMalloc2(m2 * nrint + 1, &gh->r, 3 * gh->nblk + 1, &gh->q));
  gh->x = x;
  PetscCall(VecGetArrayRead(x, &gh->xl));
  PetscCall(VecGetArrayRead(loc, &a));
  n = 0;
  for (PetscInt e = 0; e < gh->nint; e++) {
    PetscInt         k = gh->ints[e];
    PetscReal        skt, skn;
    const PetscReal *isqa = mx->portions.inv_sqrt_area + BwPortionsFirst(&mx->portions, k);
    if (gh->roff[e] < 0) continue;
    BwMixedStiffnessRoots(mx, k, &skt, &skn);
    for (PetscInt p = 0; p < mx->m; p++) {
      gh->r[gh->roff[e] + 2 * p]     = PetscRealPart(a[n + 2 * p]) * skt * isqa[p];
      gh->r[gh->roff[e] + 2 * p + 1] = PetscRealPart(a[n + 2 * p + 1]) * skn * isqa[p];
    }
    n += m2;
  }
  for (PetscInt e = 0; e < gh->nblk; e++) {
    PetscInt         b = gh->blks[e], row = mx->krow_q[b];
    const PetscReal *sc = &mx->qscale[3 * b];
    PetscBool        mine = row >= lo && row < hi;
    for (PetscInt c = 0; c < 3; c++) {
      if (mx->model->prescribed[3 * b + c]) gh->q[3 * e + c] = mx->model->value[3 * b + c];
      else gh->q[3 * e + c] = PetscRealPart(mine ? gh->xl[row - lo + c] : a[n + c]) * sc[c];
    }
    if (row >= 0 && !mine) n += 3;
  }
  PetscCall(VecRestoreArrayRead(loc, &a));
  PetscCall(VecDestroy(&loc));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwGhostsFree(BwGhosts *gh)
{
  PetscFunctionBeginUser;
  PetscCall(VecRestoreArrayRead(gh->x, &gh->xl));
  PetscCall(PetscFree(gh->ints));
  PetscCall(PetscFree(gh->roff));
  PetscCall(PetscFree(gh->blks));
  PetscCall(PetscFree2(gh->r, gh->q));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwGhostBlock(const BwGhosts *gh, PetscInt b, const PetscReal **q)
{
  PetscInt loc;

  PetscFunctionBeginUser;
  PetscCall(PetscFindInt(b, gh->nblk, gh->blks, &loc));
  PetscCheck(loc >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "block %" PetscInt_FMT " not gathered", b);
  *q = gh->q + 3 * loc;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The physical stresses of interface k (2m, (shear, normal) per portion)
 * into out[]: unscaled from x where this rank holds them, else gathered. */
static PetscErrorCode BwGhostStress(BwMixed mx, const BwGhosts *gh, PetscInt k, PetscReal out[])
{
  PetscInt loc;

  PetscFunctionBeginUser;
  PetscCall(PetscFindInt(k, gh->nint, gh->ints, &loc));
  PetscCheck(loc >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "interface %" PetscInt_FMT " not gathered", k);
  if (gh->roff[loc] >= 0) PetscCall(PetscArraycpy(out, gh->r + gh->roff[loc], 2 * mx->m));
  else {
    const PetscScalar *src = gh->xl + (mx->krow_r[k] - mx->kstart);
    const PetscReal   *isqa = mx->portions.inv_sqrt_area + BwPortionsFirst(&mx->portions, k);
    PetscReal          skt, skn;
    BwMixedStiffnessRoots(mx, k, &skt, &skn);
    for (PetscInt p = 0; p < mx->m; p++) {
      out[2 * p]     = PetscRealPart(src[2 * p]) * skt * isqa[p];
      out[2 * p + 1] = PetscRealPart(src[2 * p + 1]) * skn * isqa[p];
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedRecover(BwMixed mx, Vec x, const PetscReal load[], PetscBool stresses, BwResults *res)
{
  BwGeometry geom = mx->geom;
  PetscInt   m = mx->m, m2 = 2 * m;
  BwGhosts   gh;
  PetscReal *work;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(m2, &work));
  PetscCall(PetscLogEventBegin(BwEvents[BW_EVENT_GATHER], 0, 0, 0, 0));
  PetscCall(BwGhostsGather(mx, x, &gh));
  PetscCall(PetscLogEventEnd(BwEvents[BW_EVENT_GATHER], 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(BwEvents[BW_EVENT_RESULTS], 0, 0, 0, 0));
  PetscCall(PetscCalloc5(3 * mx->nown_blocks + 1, &res->displacement, 3 * mx->nown_blocks + 1, &res->reaction, 3 * mx->nown_interfaces + 1, &res->relative, 3 * mx->nown_interfaces + 1, &res->resultant, stresses ? m2 * mx->nown_interfaces + 1 : 0, &res->stress));
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
    PetscInt         k = mx->own_interfaces[e], i = geom->pair[2 * k], j = geom->pair[2 * k + 1];
    const PetscReal *qi, *qj;
    PetscReal       *r;
    PetscReal        rb[18], *dg = &res->relative[3 * e];
    int              status;

    /* output order (I, m, 2): the stresses' own order */
    r = stresses ? &res->stress[m2 * e] : work;
    PetscCall(BwGhostStress(mx, &gh, k, r));
    PetscCall(BwGhostBlock(&gh, i, &qi));
    PetscCall(BwGhostBlock(&gh, j, &qj));
    PetscCall(BwMixedCompatibility(mx, k, rb));
    for (PetscInt a = 0; a < 3; a++) {
      dg[a] = 0;
      for (PetscInt c = 0; c < 3; c++) dg[a] += rb[6 * a + c] * qi[c] + rb[6 * a + 3 + c] * qj[c];
    }
    {
      const PetscReal *area, *xi, *eta;
      PetscInt         np = BwMixedPortions(mx, k, &area, &xi, &eta, NULL);
      bw_kernel_resultants(2, (int)np, area, xi, eta, r, &res->resultant[3 * e], &status);
    }
    PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "kernel failed on interface %" PetscInt_FMT, k);
  }
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt         b = mx->own_blocks[e];
    const PetscReal *qb;
    PetscReal        f[3] = {0, 0, 0};

    PetscCall(BwGhostBlock(&gh, b, &qb));
    for (PetscInt c = 0; c < 3; c++) res->displacement[3 * e + c] = qb[c];
    if (!(mx->model->prescribed[3 * b] || mx->model->prescribed[3 * b + 1] || mx->model->prescribed[3 * b + 2])) continue;
    /* (D^T r)_b = sum over b's interfaces of (R B)_b^T (T, N, M), H r summed
     * from the stresses, whichever rank owns the interface */
    for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) {
      PetscInt  k = mx->adj[a], side = BwSide(mx, k, b);
      PetscReal        rb[18], h[3];
      const PetscReal *area, *xi, *eta;
      PetscInt         np = BwMixedPortions(mx, k, &area, &xi, &eta, NULL);
      int              status;
      PetscCall(BwGhostStress(mx, &gh, k, work));
      bw_kernel_resultants(2, (int)np, area, xi, eta, work, h, &status);
      PetscCall(BwMixedCompatibility(mx, k, rb));
      for (PetscInt c = 0; c < 3; c++) f[c] += rb[side + c] * h[0] + rb[6 + side + c] * h[1] + rb[12 + side + c] * h[2];
    }
    for (PetscInt c = 0; c < 3; c++) res->reaction[3 * e + c] = mx->model->prescribed[3 * b + c] ? f[c] - load[3 * b + c] : 0;
  }
  PetscCall(BwGhostsFree(&gh));
  PetscCall(PetscFree(work));
  PetscCall(PetscLogEventEnd(BwEvents[BW_EVENT_RESULTS], 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwResultsFree(BwResults *res)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree5(res->displacement, res->reaction, res->relative, res->resultant, res->stress));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Residual norms of the scaled system, split into its two block rows, each
 * relative to the forces involved: the loads or, where they vanish (a scene
 * moved by prescribed displacements only), the stresses. */
PetscErrorCode BwMixedCheck(BwMixed mx, Vec x, Vec b, const PetscReal load[], const BwResults *res, BwCheck *check)
{
  Vec                Kx;
  const PetscScalar *kx, *bb, *xx;
  PetscReal          loc[6] = {0, 0, 0, 0, 0, 0}, glob[6];

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(BwEvents[BW_EVENT_CHECK], 0, 0, 0, 0));
  PetscCall(VecDuplicate(x, &Kx));
  PetscCall(MatMult(mx->K, x, Kx));
  PetscCall(VecGetArrayRead(Kx, &kx));
  PetscCall(VecGetArrayRead(b, &bb));
  PetscCall(VecGetArrayRead(x, &xx));
  for (PetscInt e = 0; e < mx->nr_local; e++) {
    PetscReal res_r = PetscRealPart(bb[e] - kx[e]);
    PetscReal dq    = PetscRealPart(kx[e] + xx[e] - bb[e]); /* T D^ q~ including prescribed dofs */
    loc[0] += res_r * res_r;
    loc[1] += dq * dq;
    loc[4] += PetscRealPart(bb[e] * bb[e]);
    loc[5] += PetscRealPart(xx[e] * xx[e]);
  }
  for (PetscInt e = mx->nr_local; e < mx->nlocal; e++) {
    PetscReal res_q = PetscRealPart(bb[e] - kx[e]);
    loc[2] += res_q * res_q;
    loc[3] += PetscRealPart(bb[e] * bb[e]);
  }
  PetscCall(VecRestoreArrayRead(Kx, &kx));
  PetscCall(VecRestoreArrayRead(b, &bb));
  PetscCall(VecRestoreArrayRead(x, &xx));
  PetscCall(VecDestroy(&Kx));
  PetscCall(MPIU_Allreduce(loc, glob, 6, MPIU_REAL, MPIU_SUM, mx->comm));
  {
    PetscReal bnorm = PetscSqrtReal(glob[3] + glob[4]), eq = PetscMax(glob[3], glob[5]), co = PetscMax(glob[1], glob[5]);
    check->residual      = bnorm > 0 ? PetscSqrtReal(glob[0] + glob[2]) / bnorm : PetscSqrtReal(glob[0] + glob[2]);
    check->compatibility = co > 0 ? PetscSqrtReal(glob[0] / co) : PetscSqrtReal(glob[0]);
    check->equilibrium   = eq > 0 ? PetscSqrtReal(glob[2] / eq) : PetscSqrtReal(glob[2]);
  }

  /* Global balance: the wrench of reactions + loads about the mean centroid,
   * moments divided by the assembly's size so all three terms are forces,
   * relative to the forces involved: the sum of the magnitudes of every
   * block's contribution to that wrench, loads and reactions. (Relative to
   * the resultant of the loads alone it read 1.0 on correct answers whose
   * loads sum to zero: prescribed displacements only, self-balanced loads.) */
  check->equilibrium_error = -1;
  if (res) {
    BwGeometry geom = mx->geom;
    PetscReal  x0[2] = {0, 0}, lo[2] = {PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[2] = {PETSC_MIN_REAL, PETSC_MIN_REAL}, L, w[4] = {0, 0, 0, 0}, wg[4];
    for (PetscInt b = 0; b < geom->nblocks; b++)
      for (PetscInt c = 0; c < 2; c++) {
        x0[c] += geom->centroid[2 * b + c] / geom->nblocks;
        lo[c] = PetscMin(lo[c], geom->centroid[2 * b + c]);
        hi[c] = PetscMax(hi[c], geom->centroid[2 * b + c]);
      }
    L = PetscMax(PetscSqrtReal(PetscSqr(hi[0] - lo[0]) + PetscSqr(hi[1] - lo[1])), PetscSqrtReal(geom->area[0]));
    for (PetscInt e = 0; e < mx->nown_blocks; e++) {
      PetscInt         b = mx->own_blocks[e];
      const PetscReal *F = &load[3 * b], *R = &res->reaction[3 * e];
      PetscReal        dx = geom->centroid[2 * b] - x0[0], dy = geom->centroid[2 * b + 1] - x0[1];
      PetscReal        f[3] = {F[0] + R[0], F[1] + R[1], (F[2] + R[2] + dx * (F[1] + R[1]) - dy * (F[0] + R[0])) / L};
      for (PetscInt c = 0; c < 3; c++) w[c] += f[c];
      w[3] += PetscAbsReal(F[0]) + PetscAbsReal(F[1]) + (PetscAbsReal(F[2]) + PetscAbsReal(dx * F[1]) + PetscAbsReal(dy * F[0])) / L;
      w[3] += PetscAbsReal(R[0]) + PetscAbsReal(R[1]) + (PetscAbsReal(R[2]) + PetscAbsReal(dx * R[1]) + PetscAbsReal(dy * R[0])) / L;
    }
    PetscCall(MPIU_Allreduce(w, wg, 4, MPIU_REAL, MPIU_SUM, mx->comm));
    {
      PetscReal num = PetscSqrtReal(PetscSqr(wg[0]) + PetscSqr(wg[1]) + PetscSqr(wg[2]));
      /* nothing loaded and nothing moved: nothing to balance */
      check->equilibrium_error = wg[3] > 0 ? num / wg[3] : 0;
    }
  }
  PetscCall(PetscLogEventEnd(BwEvents[BW_EVENT_CHECK], 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}
