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
  PetscReal         *r;           /* ns per portion of the interfaces held elsewhere, physical */
  PetscReal         *q;           /* nd per needed block, physical */
  PetscInt           nd;
  Vec                x;           /* the solution, read in place for what this rank holds */
  const PetscScalar *xl;
} BwGhosts;

static PetscErrorCode BwGhostsGather(BwMixed mx, Vec x, BwGhosts *gh)
{
  BwGeometry         geom = mx->geom;
  const PetscInt     nd = mx->nd, ns = mx->ns;
  PetscInt           n, *from, lo = mx->kstart, hi = mx->kstart + mx->nlocal, nremote = 0, nrr = 0;
  IS                 isfrom;
  Vec                loc;
  VecScatter         sct;
  const PetscScalar *a;

  PetscFunctionBeginUser;
  gh->nd = nd;
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
    gh->roff[e]  = -1;
    if (row < lo || row >= hi) {
      gh->roff[e] = nrr;
      nrr += ns * BwPortionsCount(&mx->portions, gh->ints[e]);
    }
  }
  nremote = nrr;
  for (PetscInt e = 0; e < gh->nblk; e++) {
    PetscInt row = mx->krow_q[gh->blks[e]];
    if (row >= 0 && (row < lo || row >= hi)) nremote += nd;
  }
  PetscCall(PetscMalloc1(nremote + 1, &from));
  n = 0;
  for (PetscInt e = 0; e < gh->nint; e++)
    if (gh->roff[e] >= 0)
      for (PetscInt p = 0; p < ns * BwPortionsCount(&mx->portions, gh->ints[e]); p++) from[n++] = mx->krow_r[gh->ints[e]] + p;
  for (PetscInt e = 0; e < gh->nblk; e++) {
    PetscInt row = mx->krow_q[gh->blks[e]];
    if (row >= 0 && (row < lo || row >= hi))
      for (PetscInt c = 0; c < nd; c++) from[n++] = row + c;
  }
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, n, from, PETSC_OWN_POINTER, &isfrom));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, n, &loc));
  PetscCall(VecScatterCreate(x, isfrom, loc, NULL, &sct));
  PetscCall(VecScatterBegin(sct, x, loc, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sct, x, loc, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterDestroy(&sct));
  PetscCall(ISDestroy(&isfrom));

  /* unscale what came from elsewhere; this rank's own stays in x */
  PetscCall(PetscMalloc2(nrr + 1, &gh->r, nd * gh->nblk + 1, &gh->q));
  gh->x = x;
  PetscCall(VecGetArrayRead(x, &gh->xl));
  PetscCall(VecGetArrayRead(loc, &a));
  n = 0;
  for (PetscInt e = 0; e < gh->nint; e++) {
    PetscInt         k = gh->ints[e], np = BwPortionsCount(&mx->portions, k);
    PetscReal        skt, skn, sk[BW_MAX_NS];
    const PetscReal *isqa = mx->portions.inv_sqrt_area + BwPortionsFirst(&mx->portions, k);
    if (gh->roff[e] < 0) continue;
    BwMixedStiffnessRoots(mx, k, &skt, &skn);
    for (PetscInt c = 0; c < ns; c++) sk[c] = c == 1 ? skn : skt;
    for (PetscInt p = 0; p < np; p++)
      for (PetscInt c = 0; c < ns; c++) gh->r[gh->roff[e] + ns * p + c] = PetscRealPart(a[n + ns * p + c]) * sk[c] * isqa[p];
    n += ns * np;
  }
  for (PetscInt e = 0; e < gh->nblk; e++) {
    PetscInt         b = gh->blks[e], row = mx->krow_q[b];
    const PetscReal *sc = &mx->qscale[nd * b];
    PetscBool        mine = row >= lo && row < hi;
    for (PetscInt c = 0; c < nd; c++) {
      if (mx->model->prescribed[nd * b + c]) gh->q[nd * e + c] = mx->model->value[nd * b + c];
      else gh->q[nd * e + c] = PetscRealPart(mine ? gh->xl[row - lo + c] : a[n + c]) * sc[c];
    }
    if (row >= 0 && !mine) n += nd;
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
  *q = gh->q + gh->nd * loc;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The physical stresses of interface k (ns per portion: rt, rn[, rb])
 * into out[]: unscaled from x where this rank holds them, else gathered. */
static PetscErrorCode BwGhostStress(BwMixed mx, const BwGhosts *gh, PetscInt k, PetscReal out[])
{
  PetscInt loc;

  PetscFunctionBeginUser;
  PetscCall(PetscFindInt(k, gh->nint, gh->ints, &loc));
  PetscCheck(loc >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "interface %" PetscInt_FMT " not gathered", k);
  const PetscInt ns = mx->ns, np = BwPortionsCount(&mx->portions, k);
  if (gh->roff[loc] >= 0) PetscCall(PetscArraycpy(out, gh->r + gh->roff[loc], ns * np));
  else {
    const PetscScalar *src = gh->xl + (mx->krow_r[k] - mx->kstart);
    const PetscReal   *isqa = mx->portions.inv_sqrt_area + BwPortionsFirst(&mx->portions, k);
    PetscReal          skt, skn, sk[BW_MAX_NS];
    BwMixedStiffnessRoots(mx, k, &skt, &skn);
    for (PetscInt c = 0; c < ns; c++) sk[c] = c == 1 ? skn : skt;
    for (PetscInt p = 0; p < np; p++)
      for (PetscInt c = 0; c < ns; c++) out[ns * p + c] = PetscRealPart(src[ns * p + c]) * sk[c] * isqa[p];
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedRecover(BwMixed mx, Vec x, const PetscReal load[], PetscBool stresses, BwResults *res)
{
  BwGeometry     geom = mx->geom;
  const PetscInt nd = mx->nd, ns = mx->ns;
  BwGhosts       gh;
  PetscReal     *work;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(ns * mx->portions.maxnp, &work));
  PetscCall(PetscLogEventBegin(BwEvents[BW_EVENT_GATHER], 0, 0, 0, 0));
  PetscCall(BwGhostsGather(mx, x, &gh));
  PetscCall(PetscLogEventEnd(BwEvents[BW_EVENT_GATHER], 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(BwEvents[BW_EVENT_RESULTS], 0, 0, 0, 0));
  PetscCall(PetscCalloc6(nd * mx->nown_blocks + 1, &res->displacement, nd * mx->nown_blocks + 1, &res->reaction, nd * mx->nown_interfaces + 1, &res->relative, nd * mx->nown_interfaces + 1, &res->resultant, stresses ? mx->nr_local + 1 : 0, &res->stress, 2 * nd * mx->nown_interfaces + 1, &res->pair));
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
    PetscInt         k = mx->own_interfaces[e], i = geom->pair[2 * k], j = geom->pair[2 * k + 1];
    const PetscReal *qi, *qj, *area, *xi, *eta;
    PetscInt         np = BwMixedPortions(mx, k, &area, &xi, &eta, NULL);
    PetscReal       *r, rb[2 * BW_MAX_ND * BW_MAX_ND], *dg = &res->relative[nd * e];
    int              status;

    /* output order: the stresses' own order, portion after portion */
    r = stresses ? &res->stress[mx->rrow[k] - mx->rstart] : work;
    PetscCall(BwGhostStress(mx, &gh, k, r));
    PetscCall(BwGhostBlock(&gh, i, &qi));
    PetscCall(BwGhostBlock(&gh, j, &qj));
    PetscCall(PetscArraycpy(&res->pair[2 * nd * e], qi, nd));
    PetscCall(PetscArraycpy(&res->pair[2 * nd * e + nd], qj, nd));
    PetscCall(BwMixedCompatibility(mx, k, rb));
    for (PetscInt a = 0; a < nd; a++) {
      dg[a] = 0;
      for (PetscInt c = 0; c < nd; c++) dg[a] += rb[2 * nd * a + c] * qi[c] + rb[2 * nd * a + nd + c] * qj[c];
    }
    bw_kernel_resultants((int)mx->dim, (int)np, area, xi, eta, r, &res->resultant[nd * e], &status);
    PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "kernel failed on interface %" PetscInt_FMT, k);
  }
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt         b = mx->own_blocks[e];
    const PetscReal *qb;
    PetscReal        f[BW_MAX_ND] = {0};
    PetscBool        any = PETSC_FALSE;

    PetscCall(BwGhostBlock(&gh, b, &qb));
    for (PetscInt c = 0; c < nd; c++) {
      res->displacement[nd * e + c] = qb[c];
      any                           = (PetscBool)(any || mx->model->prescribed[nd * b + c]);
    }
    if (!any) continue;
    /* (D^T r)_b = sum over b's interfaces of (R B)_b^T H r, H r summed
     * from the stresses, whichever rank owns the interface */
    for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) {
      PetscInt         k = mx->adj[a], side = BwSide(mx, k, b);
      PetscReal        rb[2 * BW_MAX_ND * BW_MAX_ND], h[BW_MAX_ND];
      const PetscReal *area, *xi, *eta;
      PetscInt         np = BwMixedPortions(mx, k, &area, &xi, &eta, NULL);
      int              status;
      PetscCall(BwGhostStress(mx, &gh, k, work));
      bw_kernel_resultants((int)mx->dim, (int)np, area, xi, eta, work, h, &status);
      PetscCall(BwMixedCompatibility(mx, k, rb));
      for (PetscInt c = 0; c < nd; c++)
        for (PetscInt r = 0; r < nd; r++) f[c] += rb[2 * nd * r + side + c] * h[r];
    }
    for (PetscInt c = 0; c < nd; c++) res->reaction[nd * e + c] = mx->model->prescribed[nd * b + c] ? f[c] - load[nd * b + c] : 0;
  }
  PetscCall(BwGhostsFree(&gh));
  PetscCall(PetscFree(work));
  PetscCall(PetscLogEventEnd(BwEvents[BW_EVENT_RESULTS], 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwResultsFree(BwResults *res)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree6(res->displacement, res->reaction, res->relative, res->resultant, res->stress, res->pair));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Residual norms of the scaled system, split into its two block rows, each
 * relative to the forces involved: the loads or, where they vanish (a scene
 * moved by prescribed displacements only), the stresses. */
PetscErrorCode BwMixedCheck(BwMixed mx, Vec x, Vec b, const PetscReal load[], const BwResults *res, BwCheck *check)
{
  PetscReal loc[6], glob[6];

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(BwEvents[BW_EVENT_CHECK], 0, 0, 0, 0));
  PetscCall(BwMixedResidualSums(mx, x, b, loc));
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
    BwGeometry     geom = mx->geom;
    const PetscInt d = geom->dim, nd = mx->nd;
    PetscReal      x0[3] = {0, 0, 0}, lo[3] = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[3] = {PETSC_MIN_REAL, PETSC_MIN_REAL, PETSC_MIN_REAL}, L = 0, w[7] = {0}, wg[7];
    {
      /* the mean centroid, the centroids' box and a block's size, over all
       * ranks (each sums its owned blocks) */
      PetscReal sum[4] = {0, 0, 0, 0}, gsum[4], glo[3], ghi[3];
      for (PetscInt b = 0; b < geom->nown_blocks; b++)
        for (PetscInt c = 0; c < d; c++) {
          sum[c] += geom->centroid[d * b + c] / geom->nblocks_global;
          lo[c] = PetscMin(lo[c], geom->centroid[d * b + c]);
          hi[c] = PetscMax(hi[c], geom->centroid[d * b + c]);
        }
      /* the block that sets the floor of L: global block 0's size, as one
       * rank holds it */
      sum[3] = geom->nown_blocks && geom->gblock[0] == 0 ? BwGeometryBlockSize(geom, 0) : 0;
      PetscCallMPI(MPIU_Allreduce(sum, gsum, 4, MPIU_REAL, MPIU_SUM, mx->comm));
      PetscCallMPI(MPIU_Allreduce(lo, glo, 3, MPIU_REAL, MPIU_MIN, mx->comm));
      PetscCallMPI(MPIU_Allreduce(hi, ghi, 3, MPIU_REAL, MPIU_MAX, mx->comm));
      for (PetscInt c = 0; c < d; c++) {
        x0[c] = gsum[c];
        L += PetscSqr(ghi[c] - glo[c]);
      }
      L = PetscMax(PetscSqrtReal(L), gsum[3]);
    }
    for (PetscInt e = 0; e < mx->nown_blocks; e++) {
      PetscInt b = mx->own_blocks[e];
      /* the wrench of the loads and of the reactions about x0: forces, then
       * moments (M3 in 2D; M1, M2, M3 in 3D) with the forces' own moment
       * arm x (c - x0), divided by L */
      for (PetscInt src = 0; src < 2; src++) {
        const PetscReal *F = src ? &res->reaction[nd * e] : &load[nd * b];
        PetscReal        arm[3] = {0, 0, 0}, f3[3] = {0, 0, 0}, mom[3], amom[3];
        for (PetscInt c = 0; c < d; c++) arm[c] = geom->centroid[d * b + c] - x0[c], f3[c] = F[c];
        mom[0] = arm[1] * f3[2] - arm[2] * f3[1];
        mom[1] = arm[2] * f3[0] - arm[0] * f3[2];
        mom[2] = arm[0] * f3[1] - arm[1] * f3[0];
        amom[0] = PetscAbsReal(arm[1] * f3[2]) + PetscAbsReal(arm[2] * f3[1]);
        amom[1] = PetscAbsReal(arm[2] * f3[0]) + PetscAbsReal(arm[0] * f3[2]);
        amom[2] = PetscAbsReal(arm[0] * f3[1]) + PetscAbsReal(arm[1] * f3[0]);
        for (PetscInt c = 0; c < d; c++) {
          w[c] += F[c];
          w[6] += PetscAbsReal(F[c]);
        }
        for (PetscInt c = d; c < nd; c++) {
          PetscInt axis = d == 2 ? 2 : c - d;
          w[3 + axis] += (F[c] + mom[axis]) / L;
          w[6] += (PetscAbsReal(F[c]) + amom[axis]) / L;
        }
      }
    }
    PetscCall(MPIU_Allreduce(w, wg, 7, MPIU_REAL, MPIU_SUM, mx->comm));
    {
      PetscReal num = 0;
      for (PetscInt c = 0; c < 6; c++) num += PetscSqr(wg[c]);
      num = PetscSqrtReal(num);
      /* nothing loaded and nothing moved: nothing to balance */
      check->equilibrium_error = wg[6] > 0 ? num / wg[6] : 0;
    }
  }
  PetscCall(PetscLogEventEnd(BwEvents[BW_EVENT_CHECK], 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}
