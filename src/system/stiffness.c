/* S^ = D^T T D^ + P, the Schur complement of the scaled mixed system, in
 * CSR, block size 3.
 *
 * Interface k contributes diag(s) (R B)^T K_G (R B) diag(s) to the rows of
 * its two blocks (s the dof scales, zero at prescribed dofs, whose rows are
 * identity rows), where K_G = sum_p A_p E_p^T C_p E_p condenses the
 * portions' tangents C_p (bw_kernel_condense): exact, because the (r,r)
 * block of the scaled system is the identity. A rank assembles the rows of
 * its own blocks only, summing every interface touching them: K_G of an
 * elastic interface is computed where it is needed (the law's tangent is
 * the same for every portion); with per-portion tangents the owner of an
 * interface condenses them and one scatter brings K_G (9 numbers) to the
 * ranks whose rows need it. Nothing is stashed for another rank.
 *
 * The pattern (a row per dof of an owned block with free dofs, nd
 * columns per such neighbour, itself included, sorted) is built once; new
 * tangents rewrite the values in place, in the arrays PETSc uses, so that a
 * factorisation can be redone without a new analysis (same nonzero
 * pattern) and an AMG hierarchy can keep its aggregates.
 *
 * Where the values never change (BwMixedSetValuesFixed: a linear analysis
 * of elastic joints) the couplings that are round-off of zero are left
 * out: between dof kinds whose entries are all |s_ij| <= BW_S_ROUNDOFF,
 * S^ having a unit diagonal (the dof scaling). An assembly symmetric about a plane normal to X3 (every extruded 2D
 * wall) has no coupling between its in-plane dofs (u1, u2, w3) and its
 * out-of-plane ones (u3, w1, w2): the assembled couplings are sums of
 * terms that cancel (lever arms along X3, first moments of the portions
 * about the mid-plane), 5e-17 of the diagonal on the 1e5-block wall of
 * bench/large_wall3d.yaml. Without them S^ is two independent problems of
 * 3 dofs per block, and a factorisation's ordering finds them: half the
 * factor's entries (the 1e5-block wall: 7.7e7 against 1.5e8) and a
 * quarter of its flops. An entry dropped is at most BW_S_ROUNDOFF of the
 * diagonal, about what the factorisation's own round-off changes, and the
 * outer iterations run on the exact operator K. */
#include <string.h>
#include "system/mixed_impl.h"
#include "util/compat.h"
#include "blockwall/kernels.h"

/* Entries of S^ at most this (its diagonal is 1) are round-off of zero; see above. */
#define BW_S_ROUNDOFF (8 * PETSC_MACHINE_EPSILON)

/* The interfaces touching owned blocks with free dofs, sorted: the K_G
 * the rows need. */
static PetscErrorCode BwMixedStiffnessInterfaces(BwMixed mx)
{
  PetscInt n = 0;

  PetscFunctionBeginUser;
  for (PetscInt e = 0; e < mx->nown_blocks; e++) n += mx->adj_offsets[mx->own_blocks[e] + 1] - mx->adj_offsets[mx->own_blocks[e]];
  PetscCall(PetscMalloc1(n + 1, &mx->kg_interfaces));
  n = 0;
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e];
    if (mx->qrow[b] < 0) continue;
    for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) mx->kg_interfaces[n++] = mx->adj[a];
  }
  PetscCall(PetscSortRemoveDupsInt(&n, mx->kg_interfaces));
  mx->nkg = n;
  PetscCall(PetscCalloc1(mx->nd * mx->nd * n + 1, &mx->kg));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* K_G (nd x nd, row-major) of interface k from its law's elastic tangent: the
 * law evaluated at zero jump and a virgin state, the same for every
 * portion. */
static PetscErrorCode BwMixedElasticStiffness(BwMixed mx, PetscInt k, PetscReal kg[])
{
  BwGeometry  g = mx->geom;
  BwJointLaw  law;
  PetscReal   par[BW_LAW_NPAR], state[BW_LAW_NSTATE_MAX] = {0}, jump[BW_MAX_NS] = {0}, stress[BW_MAX_NS], tangent[BW_MAX_NS * BW_MAX_NS], state_out[BW_LAW_NSTATE_MAX];
  signed char mode;
  char        what[128];
  int         status;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(what, sizeof(what), "interface %" PetscInt_FMT " (blocks %" PetscInt_FMT ", %" PetscInt_FMT ")", k, g->pair[2 * k], g->pair[2 * k + 1]));
  PetscCall(BwModelInterfaceLaw(mx->model, k, &law, par));
  PetscCall(BwJointLawEvaluate(law, par, mx->ns, 1, state, jump, stress, tangent, state_out, &mode, what));
  {
    const PetscReal *area, *xi, *eta;
    PetscInt         np = BwMixedPortions(mx, k, &area, &xi, &eta, NULL);
    bw_kernel_condense((int)mx->dim, (int)np, area, xi, eta, 1, tangent, kg, &status);
  }
  PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "kernel failed on %s", what);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* K_G of every interface the rows need, into mx->kg. */
static PetscErrorCode BwMixedCondense(BwMixed mx)
{
  const PetscInt nkg = mx->nd * mx->nd;

  PetscFunctionBeginUser;
  if (!mx->tangent) {
    for (PetscInt e = 0; e < mx->nkg; e++) {
      PetscReal kg[BW_MAX_ND * BW_MAX_ND];
      PetscCall(BwMixedElasticStiffness(mx, mx->kg_interfaces[e], kg));
      if (mx->kg_changed) mx->kg_changed[e] = memcmp(kg, mx->kg + nkg * e, sizeof(PetscReal) * nkg) ? PETSC_TRUE : PETSC_FALSE;
      PetscCall(PetscArraycpy(mx->kg + nkg * e, kg, nkg));
    }
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  if (!mx->kg_scatter) {
    PetscInt *slot;
    IS        is;
    PetscCall(VecCreateMPI(mx->comm, nkg * mx->nown_interfaces, PETSC_DETERMINE, &mx->kg_owned));
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, nkg * mx->nkg, &mx->kg_ghost));
    PetscCall(PetscMalloc1(mx->nkg + 1, &slot));
    /* an interface's place among all, in owner order: its global index in
     * the owners' order, from the owned counts of the ranks before */
    PetscCall(BwMixedInterfaceSlots(mx, slot));
    PetscCall(ISCreateBlock(PETSC_COMM_SELF, nkg, mx->nkg, slot, PETSC_COPY_VALUES, &is));
    PetscCall(VecScatterCreate(mx->kg_owned, is, mx->kg_ghost, NULL, &mx->kg_scatter));
    PetscCall(ISDestroy(&is));
    PetscCall(PetscFree(slot));
  }
  {
    PetscScalar       *o;
    const PetscScalar *gh;
    PetscCall(VecGetArray(mx->kg_owned, &o));
    for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
      PetscInt         k = mx->own_interfaces[e];
      if (mx->tangent_changed && !mx->tangent_changed[e]) continue; /* its K_G is in kg_owned already */
      PetscReal        kg[BW_MAX_ND * BW_MAX_ND];
      const PetscReal *area, *xi, *eta;
      PetscInt         np = BwMixedPortions(mx, k, &area, &xi, &eta, NULL);
      int              status;
      bw_kernel_condense((int)mx->dim, (int)np, area, xi, eta, (int)np, mx->tangent + mx->ns * (mx->rrow[k] - mx->rstart), kg, &status);
      PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "kernel failed on interface %" PetscInt_FMT, k);
      for (PetscInt c = 0; c < nkg; c++) o[nkg * e + c] = kg[c];
    }
    PetscCall(VecRestoreArray(mx->kg_owned, &o));
    PetscCall(VecScatterBegin(mx->kg_scatter, mx->kg_owned, mx->kg_ghost, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(mx->kg_scatter, mx->kg_owned, mx->kg_ghost, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecGetArrayRead(mx->kg_ghost, &gh));
    for (PetscInt e = 0; e < mx->nkg; e++) {
      PetscBool changed = PETSC_FALSE;
      for (PetscInt c = nkg * e; c < nkg * (e + 1); c++) {
        changed = (PetscBool)(changed || mx->kg[c] != PetscRealPart(gh[c]));
        mx->kg[c] = PetscRealPart(gh[c]);
      }
      if (mx->kg_changed) mx->kg_changed[e] = changed;
    }
    PetscCall(VecRestoreArrayRead(mx->kg_ghost, &gh));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

typedef struct {
  PetscInt  *nbr, *col; /* neighbour blocks (with free dofs) of the row's block, sorted by q row; their first q rows */
  PetscReal *acc;       /* nd rows x nd nn columns */
} BwRowWork;

/* The nd rows of owned block b: columns (nd per neighbour with free dofs,
 * in q-row order) and, with values, their entries. Returns the number of
 * neighbours. */
static PetscErrorCode BwMixedBlockRows(BwMixed mx, PetscInt b, PetscBool values, BwRowWork *w, PetscInt *nn)
{
  BwGeometry     g  = mx->geom;
  const PetscInt nd = mx->nd;
  PetscInt       n  = 0;

  PetscFunctionBeginUser;
  w->nbr[n++] = mx->qrow[b];
  for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) {
    PetscInt k = mx->adj[a], o = g->pair[2 * k] == b ? g->pair[2 * k + 1] : g->pair[2 * k];
    if (mx->qrow[o] >= 0) w->nbr[n++] = mx->qrow[o];
  }
  PetscCall(PetscSortRemoveDupsInt(&n, w->nbr));
  *nn = n;
  if (!values) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscArrayzero(w->acc, nd * nd * n));
  for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) {
    PetscInt   k = mx->adj[a], side = BwSide(mx, k, b), loc;
    PetscReal  rb[2 * BW_MAX_ND * BW_MAX_ND], own[4 * BW_MAX_ND * BW_MAX_ND], sc[2 * BW_MAX_ND], *s6 = own;
    int        status = BW_KERNEL_OK;
    PetscCall(PetscFindInt(k, mx->nkg, mx->kg_interfaces, &loc));
    PetscCheck(loc >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "interface %" PetscInt_FMT " not condensed", k);
    if (mx->s6) s6 = mx->s6 + 4 * nd * nd * loc;
    if (!mx->s6 || !mx->s6_valid[loc]) {
      PetscCall(BwMixedCompatibility(mx, k, rb));
      bw_kernel_stiffness((int)mx->dim, rb, mx->kg + nd * nd * loc, s6, &status);
      if (mx->s6) mx->s6_valid[loc] = PETSC_TRUE;
    }
    for (PetscInt c = 0; c < 2 * nd; c++) {
      PetscInt blk = g->pair[2 * k + c / nd];
      sc[c]        = mx->model->prescribed[nd * blk + c % nd] ? 0 : mx->qscale[nd * blk + c % nd];
    }
    for (PetscInt s = 0; s < 2; s++) {
      PetscInt blk = g->pair[2 * k + s], f;
      if (mx->qrow[blk] < 0) continue;
      PetscCall(PetscFindInt(mx->qrow[blk], n, w->nbr, &f));
      for (PetscInt r = 0; r < nd; r++)
        for (PetscInt c = 0; c < nd; c++) w->acc[nd * n * r + nd * f + c] += sc[side + r] * s6[2 * nd * (side + r) + nd * s + c] * sc[nd * s + c];
    }
  }
  /* prescribed dofs: identity rows (their columns are zero already) */
  {
    PetscInt self;
    PetscCall(PetscFindInt(mx->qrow[b], n, w->nbr, &self));
    for (PetscInt r = 0; r < nd; r++)
      if (mx->model->prescribed[nd * b + r]) w->acc[nd * n * r + nd * self + r] = 1;
    if (b == mx->spring_block) w->acc[nd * n * mx->spring_dof + nd * self + mx->spring_dof] += mx->spring;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Block b's rows must be written again: an interface of it has a new K_G,
 * or the spring is, or was, on it. */
static PetscBool BwMixedBlockDirty(BwMixed mx, PetscInt b)
{
  if (!mx->tangent_changed || !mx->kg_changed) return PETSC_TRUE;
  if (b == mx->spring_block || b == mx->spring_written) return PETSC_TRUE;
  for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) {
    PetscInt loc;
    if (PetscFindInt(mx->adj[a], mx->nkg, mx->kg_interfaces, &loc) || loc < 0 || mx->kg_changed[loc]) return PETSC_TRUE;
  }
  return PETSC_FALSE;
}

/* Writes the values of the owned rows into the arrays PETSc holds: each
 * row's sorted columns fall in order into the diagonal part (columns of
 * this rank) or the off-diagonal part. Rows whose inputs did not change
 * since the last write keep their values (the same numbers). */
static PetscErrorCode BwMixedWriteS(BwMixed mx, BwRowWork *w)
{
  const PetscInt ndof = mx->nd;
  PetscInt       row = 0, cstart = mx->qstart, cend = mx->qstart + mx->nq_local;

  PetscFunctionBeginUser;
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e], nn;
    if (mx->qrow[b] < 0) continue;
    if (!BwMixedBlockDirty(mx, b)) {
      row += ndof;
      continue;
    }
    PetscCall(BwMixedBlockRows(mx, b, PETSC_TRUE, w, &nn));
    for (PetscInt r = 0; r < ndof; r++, row++) {
      PetscInt nd = mx->svals.di[row], no = mx->svals.oi ? mx->svals.oi[row] : 0;
      for (PetscInt f = 0; f < nn; f++)
        for (PetscInt c = 0; c < ndof; c++) {
          PetscReal v = w->acc[ndof * nn * r + ndof * f + c];
          if (w->nbr[f] >= cstart && w->nbr[f] < cend) mx->svals.dv[nd++] = v;
          else mx->svals.ov[no++] = v;
        }
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The dof groups that never couple: the graph on the nd dof kinds (u1,
 * u2, ... w3) with an edge where some entry of S^ between two kinds is
 * above round-off, over all ranks; its connected components. Then the
 * entries between kinds of different groups (all round-off) are left out
 * of the local CSR rows, in place. Whole kinds are kept together so that
 * the dofs of a block in one group keep one pattern: the factorisation's
 * ordering compresses them into one node, as it does the nd dofs of a
 * block without the split (entries dropped one by one left a pattern per
 * dof: the 1e5-block wall's CHOLMOD analysis took 4.8 s instead of 1.4). */
static PetscErrorCode BwMixedDropRoundoff(BwMixed mx, PetscInt *ia, PetscInt *ja, PetscReal *va)
{
  const PetscInt nd = mx->nd;
  PetscReal      big[BW_MAX_ND * BW_MAX_ND] = {0}, all[BW_MAX_ND * BW_MAX_ND];
  PetscInt       group[BW_MAX_ND], ngroups = 0, n = 0, kept;

  PetscFunctionBeginUser;
  if (!mx->nq_global) PetscFunctionReturn(PETSC_SUCCESS); /* an empty S^ does not split */
  for (PetscInt r = 0; r < mx->nq_local; r++)
    for (PetscInt e = ia[r]; e < ia[r + 1]; e++) {
      PetscInt a = r % nd, b = ja[e] % nd; /* a block's nd rows start at a multiple of nd */
      big[nd * a + b] = PetscMax(big[nd * a + b], PetscAbsReal(va[e]));
    }
  PetscCallMPI(MPI_Allreduce(big, all, nd * nd, MPIU_REAL, MPIU_MAX, mx->comm));
  for (PetscInt a = 0; a < nd; a++) group[a] = -1;
  for (PetscInt a = 0; a < nd; a++) {
    PetscInt stack[BW_MAX_ND], top = 0;
    if (group[a] >= 0) continue;
    group[a]     = ngroups;
    stack[top++] = a;
    while (top) {
      PetscInt c = stack[--top];
      for (PetscInt b = 0; b < nd; b++)
        if (group[b] < 0 && PetscMax(all[nd * c + b], all[nd * b + c]) > BW_S_ROUNDOFF) {
          group[b]     = ngroups;
          stack[top++] = b;
        }
    }
    ngroups++;
  }
  mx->s_groups = ngroups;
  for (PetscInt a = 0; a < nd; a++) mx->s_group[a] = group[a];
  if (ngroups == 1) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt r = 0; r < mx->nq_local; r++) {
    PetscInt start = ia[r];
    ia[r] = n;
    for (PetscInt e = start; e < ia[r + 1]; e++)
      if (group[r % nd] == group[ja[e] % nd]) {
        ja[n]   = ja[e];
        va[n++] = va[e];
      }
  }
  kept             = n;
  mx->s_dropped    = ia[mx->nq_local] - kept;
  ia[mx->nq_local] = kept;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedAssembleS(BwMixed mx)
{
  const PetscInt nd = mx->nd;
  PetscInt      *ia, *ja, row = 0;
  PetscReal     *va;
  BwRowWork      w;

  PetscFunctionBeginUser;
  PetscCall(PetscFree2(mx->s6, mx->s6_valid)); /* sized by the interfaces below */
  PetscCall(BwMixedStiffnessInterfaces(mx));
  PetscCall(BwMixedCondense(mx));
  PetscCall(PetscMalloc3(mx->maxdeg + 1, &w.nbr, mx->maxdeg + 1, &w.col, nd * nd * (mx->maxdeg + 1), &w.acc));
  /* pass 1: the pattern */
  PetscCall(PetscMalloc1(mx->nq_local + 1, &ia));
  ia[0] = 0;
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e], nn;
    if (mx->qrow[b] < 0) continue;
    PetscCall(BwMixedBlockRows(mx, b, PETSC_FALSE, &w, &nn));
    for (PetscInt r = 0; r < nd; r++, row++) ia[row + 1] = ia[row] + nd * nn;
  }
  PetscCall(PetscMalloc1(ia[mx->nq_local] + 1, &ja));
  PetscCall(PetscMalloc1(ia[mx->nq_local] + 1, &va));
  /* pass 2: columns and values, row by row in the rows' sorted order */
  row = 0;
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e], nn;
    if (mx->qrow[b] < 0) continue;
    PetscCall(BwMixedBlockRows(mx, b, PETSC_TRUE, &w, &nn));
    for (PetscInt r = 0; r < nd; r++, row++)
      for (PetscInt f = 0; f < nn; f++)
        for (PetscInt c = 0; c < nd; c++) {
          ja[ia[row] + nd * f + c] = w.nbr[f] + c;
          va[ia[row] + nd * f + c] = w.acc[nd * nn * r + nd * f + c];
        }
  }
  PetscCall(PetscFree3(w.nbr, w.col, w.acc));
  if (mx->values_fixed) {
    /* no refill will need the interfaces' K_G (0.9 KB per block in 3D) */
    PetscCall(PetscFree(mx->kg));
    PetscCall(BwMixedDropRoundoff(mx, ia, ja, va));
    /* give back what the split saved (the 1e5-block 3D wall: 185 MB) */
    PetscCall(PetscRealloc(sizeof(PetscInt) * (ia[mx->nq_local] + 1), &ja));
    PetscCall(PetscRealloc(sizeof(PetscReal) * (ia[mx->nq_local] + 1), &va));
  }
  /* the matrix PETSc uses in place (its values, for a refill) */
  PetscCall(BwMatFromCSR(mx->comm, mx->nq_local, mx->nq_local, mx->nq_global, mx->nq_global, "schur_", ia, ja, va, &mx->S, &mx->svals));
  PetscCall(MatSetBlockSize(mx->S, nd));
  PetscCall(MatSetOption(mx->S, MAT_SYMMETRIC, PETSC_TRUE));
  PetscCall(MatSetOption(mx->S, MAT_SPD, PETSC_TRUE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedGetSchurGroups(BwMixed mx, PetscInt *ngroups, char desc[], size_t len)
{
  const char *const *names = BwModelDofNames(mx->model);

  PetscFunctionBeginUser;
  *ngroups = mx->s_groups > 0 ? mx->s_groups : 1;
  if (!desc) PetscFunctionReturn(PETSC_SUCCESS);
  desc[0] = 0;
  if (*ngroups == 1) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt g = 0; g < *ngroups; g++) {
    PetscBool first = PETSC_TRUE;
    if (g) PetscCall(PetscStrlcat(desc, " | ", len));
    for (PetscInt a = 0; a < mx->nd; a++)
      if (mx->s_group[a] == g) {
        if (!first) PetscCall(PetscStrlcat(desc, " ", len));
        PetscCall(PetscStrlcat(desc, names[a], len));
        first = PETSC_FALSE;
      }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedRefillS(BwMixed mx)
{
  BwRowWork w;
  PetscBool symmetric = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscCheck(!mx->values_fixed, mx->comm, PETSC_ERR_ORDER, "S^ was assembled for values that never change (BwMixedSetValuesFixed) and cannot be refilled");
  PetscCall(PetscLogEventBegin(BwEvents[BW_EVENT_ASSEMBLE_S], 0, 0, 0, 0));
  PetscCall(BwMixedCondense(mx));
  if (!mx->s6) PetscCall(PetscCalloc2(4 * mx->nd * mx->nd * mx->nkg + 1, &mx->s6, mx->nkg + 1, &mx->s6_valid));
  for (PetscInt e = 0; e < mx->nkg; e++)
    if (!mx->kg_changed || mx->kg_changed[e]) mx->s6_valid[e] = PETSC_FALSE;
  PetscCall(PetscMalloc3(mx->maxdeg + 1, &w.nbr, mx->maxdeg + 1, &w.col, mx->nd * mx->nd * (mx->maxdeg + 1), &w.acc));
  PetscCall(BwMixedWriteS(mx, &w));
  mx->spring_written = mx->spring_block;
  /* the new tangents are in K_G now: a refill for the spring alone redoes no interface */
  for (PetscInt e = 0; mx->tangent_changed && e < mx->nown_interfaces; e++) mx->tangent_changed[e] = PETSC_FALSE;
  PetscCall(PetscFree3(w.nbr, w.col, w.acc));
  /* the values changed in place: whoever factored S^ must factor again */
  PetscCall(BwMatValuesChanged(mx->S));
  /* a non-associated flow (tan psi < tan phi) makes the tangents, and S^, unsymmetric */
  for (PetscInt e = 0, ns = mx->ns; mx->tangent && e < mx->nr_local / ns && symmetric; e++)
    for (PetscInt a = 0; a < ns; a++)
      for (PetscInt b = a + 1; b < ns; b++) symmetric = (PetscBool)(symmetric && mx->tangent[ns * ns * e + ns * a + b] == mx->tangent[ns * ns * e + ns * b + a]);
  {
    int loc = symmetric ? 1 : 0, all;
    PetscCallMPI(MPI_Allreduce(&loc, &all, 1, MPI_INT, MPI_LAND, mx->comm));
    symmetric = all ? PETSC_TRUE : PETSC_FALSE;
  }
  PetscCall(MatSetOption(mx->S, MAT_SYMMETRIC, symmetric));
  /* SPD only for elastic joints for good: MUMPS picks LL^T or LDL^T once,
   * at the first factorisation, and softening tangents make S^ indefinite */
  PetscCall(MatSetOption(mx->S, MAT_SPD, symmetric && !mx->tangent && !mx->model->nonlinear));
  PetscCall(PetscLogEventEnd(BwEvents[BW_EVENT_ASSEMBLE_S], 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}
