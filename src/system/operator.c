/* The operators of the mixed system: D^ (by its structure or assembled) and
 * K = [-I, T D^; D^T, P] (a shell over D^, or one assembled matrix).
 *
 * D^ by its structure: for interface k with R B (3 x 6), dof scales s of
 * its two blocks (zero at prescribed dofs, whose values are lifted to the
 * right-hand side) and portion factors sqrt(A_p) (sqrt(kt), sqrt(kn)), the
 * 2m rows are D^_k = U_k W_k with W_k = R B diag(s) (3 x 6, 18 numbers) and
 * U_k the portion map scaled by those factors. Storing W_k, two column
 * indices and three scalars costs ~200 bytes per interface instead of
 * 2m x 6 entries (2.3 KB at m = 16); the portions (portions.h) are shared
 * by shape. In 3D R B = [[-Q, M_i, Q, M_j], [0, -Q, 0, Q]] (Q the frame,
 * M_b = -+Q [G - c_b]x) is kept as Q, M_i and M_j (27 numbers) and the dof
 * scales in the q layout, instead of the 72 of W_k: 1.1 KB less per block
 * (three interfaces a block), a third of a 3D wall's memory beside the
 * solver's own. Products cost the same flops as with the assembled matrix:
 *   y = D^ q:    dG = W_k q_k; j = E_p dG (kernel); y_p = sqrt(A_p) (skt j_t, skn j_n)
 *   q = D^T y:   (T, N, M) = H (y_p (skt, skn) / sqrt(A_p)) (kernel); q_k += W_k^T (T, N, M)
 * The assembled rows come from the same kernels (bw_kernel_operator), so
 * D^ is defined once. Dofs of blocks owned by other ranks come through one
 * scatter (forward for D^ q, reverse with addition for D^T y); none on one
 * rank. */
#include <string.h>
#include "system/mixed_impl.h"
#include "util/compat.h"
#include "blockwall/kernels.h"
#include "util/dd.h"

typedef struct {
  PetscInt   m, n;    /* most portions of an interface; owned interfaces */
  int        dim;     /* 2 | 3: nd = 3 | 6 dofs, ns = 2 | 3 stresses */
  PetscInt   nd, ns;
  PetscReal *w;       /* 2D: 2 nd^2 per interface, W_k row-major nd x 2 nd; 3D: 27, Q, M_i, M_j row-major 3 x 3 */
  PetscReal *scl, *scg; /* 3D: the dof scales (0 at prescribed dofs) in the q layout: owned, ghost */
  PetscInt  *col;     /* 2 per interface: first dof of block i, j: local q index, nq_local + ghost index, or -1 */
  PetscReal *skt, *skn; /* per interface: sqrt(kt), sqrt(kn) */
  PetscInt  *first, *np, *row; /* per interface: its first portion in the table, its portions, its first row of y */
  PetscBool *uniform;          /* per interface: its portions have equal areas */
  const BwPortions *portions;
  PetscReal *work;    /* 2m */
  PetscInt   nq_local;
  Vec        ghost;   /* dofs of other ranks' blocks, sequential */
  VecScatter scatter; /* q vector -> ghost */
  /* the fused product S x = D^T T D^ x (BwSchurShellMult), made on its
   * first use: the ghosts' sums, one interface's stresses */
  Vec          ghost_sum;
  PetscScalar *ye;
} BwDShell;

static PetscErrorCode BwDShellDestroy(Mat A)
{
  BwDShell *ctx;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &ctx));
  PetscCall(PetscFree4(ctx->w, ctx->col, ctx->skt, ctx->skn));
  PetscCall(PetscFree4(ctx->first, ctx->np, ctx->row, ctx->work));
  PetscCall(PetscFree(ctx->uniform));
  PetscCall(PetscFree2(ctx->scl, ctx->scg));
  PetscCall(VecDestroy(&ctx->ghost));
  PetscCall(VecDestroy(&ctx->ghost_sum));
  PetscCall(PetscFree(ctx->ye));
  PetscCall(VecScatterDestroy(&ctx->scatter));
  PetscCall(PetscFree(ctx));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The products' loops, written once for nd dofs and ns stresses and
 * inlined with the dimension's constants, so that 2D keeps its unrolled
 * loops. y_e = D^_e q for owned interface e: its ns np rows. */
static inline void BwDShellMultOneAs(BwDShell *ctx, PetscInt e, const PetscScalar *ql, const PetscScalar *qg, PetscScalar *ye, const int dim, const PetscInt nd, const PetscInt ns, const PetscBool absolute)
{
  const PetscReal *sqa = ctx->portions->sqrt_area + ctx->first[e];
  const PetscReal *xi = ctx->portions->xi + ctx->first[e], *eta = ctx->portions->eta + ctx->first[e];
  PetscReal        dg[BW_MAX_ND] = {0}, sk[BW_MAX_NS];
  int              status;
  if (dim == 2) {
    const PetscReal *w = ctx->w + 2 * nd * nd * e;
    for (PetscInt s = 0; s < 2; s++) {
      PetscInt           c = ctx->col[2 * e + s];
      const PetscScalar *x;
      if (c < 0) continue;
      x = c < ctx->nq_local ? ql + c : qg + (c - ctx->nq_local);
      for (PetscInt f = 0; f < nd; f++) {
        PetscReal v = absolute ? PetscAbsScalar(x[f]) : PetscRealPart(x[f]);
        for (PetscInt r = 0; r < nd; r++) dg[r] += (absolute ? PetscAbsReal(w[2 * nd * r + nd * s + f]) : w[2 * nd * r + nd * s + f]) * v;
      }
    }
  } else {
    /* dG = (sum_s +-Q u_s + M_s w_s, sum_s +-Q w_s), with the scaled dofs */
    const PetscReal *Q = ctx->w + 27 * e;
    for (PetscInt s = 0; s < 2; s++) {
      PetscInt           c = ctx->col[2 * e + s];
      const PetscScalar *x;
      const PetscReal   *sc, *M = Q + 9 * (s + 1), sign = s ? 1 : -1;
      PetscReal          v[6];
      if (c < 0) continue;
      x  = c < ctx->nq_local ? ql + c : qg + (c - ctx->nq_local);
      sc = c < ctx->nq_local ? ctx->scl + c : ctx->scg + (c - ctx->nq_local);
      if (absolute) {
        for (PetscInt f = 0; f < 6; f++) v[f] = PetscAbsReal(sc[f]) * PetscAbsScalar(x[f]);
        for (PetscInt r = 0; r < 3; r++) {
          for (PetscInt c = 0; c < 3; c++) dg[r] += PetscAbsReal(Q[3 * r + c]) * v[c] + PetscAbsReal(M[3 * r + c]) * v[3 + c];
          for (PetscInt c = 0; c < 3; c++) dg[3 + r] += PetscAbsReal(Q[3 * r + c]) * v[3 + c];
        }
        continue;
      }
      for (PetscInt f = 0; f < 6; f++) v[f] = sc[f] * PetscRealPart(x[f]);
      for (PetscInt r = 0; r < 3; r++) {
        dg[r] += sign * (Q[3 * r] * v[0] + Q[3 * r + 1] * v[1] + Q[3 * r + 2] * v[2]) + M[3 * r] * v[3] + M[3 * r + 1] * v[4] + M[3 * r + 2] * v[5];
        dg[3 + r] += sign * (Q[3 * r] * v[3] + Q[3 * r + 1] * v[4] + Q[3 * r + 2] * v[5]);
      }
    }
  }
  if (absolute) bw_kernel_jumps_abs(dim, (int)ctx->np[e], xi, eta, dg, ye, &status);
  else bw_kernel_jumps(dim, (int)ctx->np[e], xi, eta, dg, ye, &status);
  for (PetscInt a = 0; a < ns; a++) sk[a] = a == 1 ? ctx->skn[e] : ctx->skt[e];
  if (ctx->uniform[e]) { /* equal portions (every 2D joint): one factor per component */
    for (PetscInt a = 0; a < ns; a++) sk[a] *= sqa[0];
    for (PetscInt p = 0; p < ctx->np[e]; p++)
      for (PetscInt a = 0; a < ns; a++) ye[ns * p + a] *= sk[a];
  } else
    for (PetscInt p = 0; p < ctx->np[e]; p++)
      for (PetscInt a = 0; a < ns; a++) ye[ns * p + a] *= sqa[p] * sk[a];
}

static inline void BwDShellMultOne(BwDShell *ctx, PetscInt e, const PetscScalar *ql, const PetscScalar *qg, PetscScalar *ye, const int dim, const PetscInt nd, const PetscInt ns)
{
  BwDShellMultOneAs(ctx, e, ql, qg, ye, dim, nd, ns, PETSC_FALSE);
}

static inline void BwDShellMultLoop(BwDShell *ctx, const PetscScalar *ql, const PetscScalar *qg, PetscScalar *yy, const int dim, const PetscInt nd, const PetscInt ns)
{
  for (PetscInt e = 0; e < ctx->n; e++) BwDShellMultOne(ctx, e, ql, qg, yy + ctx->row[e], dim, nd, ns);
}

/* q += D^_e^T y_e for owned interface e (its ns np rows y_e); ctx->work
 * holds the scaled stresses meanwhile. */
static inline void BwDShellMultTransposeOneAs(BwDShell *ctx, PetscInt e, const PetscScalar *ye, PetscScalar *ql, PetscScalar *qg, const int dim, const PetscInt nd, const PetscInt ns, const PetscBool absolute)
{
  const PetscReal *isqa = ctx->portions->inv_sqrt_area + ctx->first[e];
  const PetscReal *area = ctx->portions->area + ctx->first[e], *xi = ctx->portions->xi + ctx->first[e], *eta = ctx->portions->eta + ctx->first[e];
  PetscReal        f[BW_MAX_ND], sk[BW_MAX_NS];
  int              status;
  for (PetscInt a = 0; a < ns; a++) sk[a] = a == 1 ? ctx->skn[e] : ctx->skt[e];
  if (ctx->uniform[e]) {
    for (PetscInt a = 0; a < ns; a++) sk[a] *= isqa[0];
    for (PetscInt p = 0; p < ctx->np[e]; p++)
      for (PetscInt a = 0; a < ns; a++) ctx->work[ns * p + a] = sk[a] * PetscRealPart(ye[ns * p + a]);
  } else
    for (PetscInt p = 0; p < ctx->np[e]; p++)
      for (PetscInt a = 0; a < ns; a++) ctx->work[ns * p + a] = sk[a] * isqa[p] * PetscRealPart(ye[ns * p + a]);
  if (absolute) bw_kernel_resultants_abs(dim, (int)ctx->np[e], area, xi, eta, ctx->work, f, &status);
  else bw_kernel_resultants(dim, (int)ctx->np[e], area, xi, eta, ctx->work, f, &status);
  if (dim == 2) {
    const PetscReal *w = ctx->w + 2 * nd * nd * e;
    for (PetscInt s = 0; s < 2; s++) {
      PetscInt     c = ctx->col[2 * e + s];
      PetscScalar *x;
      if (c < 0) continue;
      x = c < ctx->nq_local ? ql + c : qg + (c - ctx->nq_local);
      for (PetscInt g = 0; g < nd; g++) {
        PetscReal acc = 0;
        for (PetscInt r = 0; r < nd; r++) acc += (absolute ? PetscAbsReal(w[2 * nd * r + nd * s + g]) : w[2 * nd * r + nd * s + g]) * f[r];
        x[g] += acc;
      }
    }
  } else {
    /* q_s += diag(s) (+-Q^T F + ..., M_s^T F +- Q^T M) */
    const PetscReal *Q = ctx->w + 27 * e;
    PetscReal        qf[3], qm[3];
    if (absolute) { /* |W^T| f, f >= 0 */
      for (PetscInt s = 0; s < 2; s++) {
        PetscInt         c = ctx->col[2 * e + s];
        PetscScalar     *x;
        const PetscReal *sc, *M = Q + 9 * (s + 1);
        if (c < 0) continue;
        x  = c < ctx->nq_local ? ql + c : qg + (c - ctx->nq_local);
        sc = c < ctx->nq_local ? ctx->scl + c : ctx->scg + (c - ctx->nq_local);
        for (PetscInt g = 0; g < 3; g++) {
          PetscReal af = 0, am = 0;
          for (PetscInt r = 0; r < 3; r++) af += PetscAbsReal(Q[3 * r + g]) * f[r], am += PetscAbsReal(M[3 * r + g]) * f[r] + PetscAbsReal(Q[3 * r + g]) * f[3 + r];
          x[g] += PetscAbsReal(sc[g]) * af;
          x[3 + g] += PetscAbsReal(sc[3 + g]) * am;
        }
      }
      return;
    }
    for (PetscInt g = 0; g < 3; g++) {
      qf[g] = Q[g] * f[0] + Q[3 + g] * f[1] + Q[6 + g] * f[2];
      qm[g] = Q[g] * f[3] + Q[3 + g] * f[4] + Q[6 + g] * f[5];
    }
    for (PetscInt s = 0; s < 2; s++) {
      PetscInt         c = ctx->col[2 * e + s];
      PetscScalar     *x;
      const PetscReal *sc, *M = Q + 9 * (s + 1), sign = s ? 1 : -1;
      if (c < 0) continue;
      x  = c < ctx->nq_local ? ql + c : qg + (c - ctx->nq_local);
      sc = c < ctx->nq_local ? ctx->scl + c : ctx->scg + (c - ctx->nq_local);
      for (PetscInt g = 0; g < 3; g++) {
        x[g] += sc[g] * sign * qf[g];
        x[3 + g] += sc[3 + g] * (M[g] * f[0] + M[3 + g] * f[1] + M[6 + g] * f[2] + sign * qm[g]);
      }
    }
  }
}

static inline void BwDShellMultTransposeOne(BwDShell *ctx, PetscInt e, const PetscScalar *ye, PetscScalar *ql, PetscScalar *qg, const int dim, const PetscInt nd, const PetscInt ns)
{
  BwDShellMultTransposeOneAs(ctx, e, ye, ql, qg, dim, nd, ns, PETSC_FALSE);
}

static inline void BwDShellMultTransposeLoop(BwDShell *ctx, const PetscScalar *yy, PetscScalar *ql, PetscScalar *qg, const int dim, const PetscInt nd, const PetscInt ns, const PetscBool absolute)
{
  for (PetscInt e = 0; e < ctx->n; e++) BwDShellMultTransposeOneAs(ctx, e, yy + ctx->row[e], ql, qg, dim, nd, ns, absolute);
}

static PetscErrorCode BwDShellMult(Mat A, Vec q, Vec y)
{
  BwDShell          *ctx;
  const PetscScalar *ql, *qg = NULL;
  PetscScalar       *yy;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &ctx));
  if (ctx->scatter) {
    PetscCall(VecScatterBegin(ctx->scatter, q, ctx->ghost, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(ctx->scatter, q, ctx->ghost, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecGetArrayRead(ctx->ghost, &qg));
  }
  PetscCall(VecGetArrayRead(q, &ql));
  PetscCall(VecGetArray(y, &yy));
  if (ctx->dim == 2) BwDShellMultLoop(ctx, ql, qg, yy, 2, 3, 2);
  else BwDShellMultLoop(ctx, ql, qg, yy, 3, 6, 3);
  PetscCall(VecRestoreArray(y, &yy));
  PetscCall(VecRestoreArrayRead(q, &ql));
  if (ctx->scatter) PetscCall(VecRestoreArrayRead(ctx->ghost, &qg));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* q += D^T y, or with absolute |D^T| |y| (the sizes of its terms, for the
 * round-off bound below), the ghosts' sums sent to their owners. */
static PetscErrorCode BwDShellTransposeAdd(BwDShell *ctx, Vec y, Vec q, PetscBool absolute)
{
  const PetscScalar *yy;
  PetscScalar       *ql, *qg = NULL;

  PetscFunctionBeginUser;
  if (ctx->scatter) {
    PetscCall(VecZeroEntries(ctx->ghost));
    PetscCall(VecGetArray(ctx->ghost, &qg));
  }
  PetscCall(VecGetArray(q, &ql));
  PetscCall(VecGetArrayRead(y, &yy));
  if (ctx->dim == 2) BwDShellMultTransposeLoop(ctx, yy, ql, qg, 2, 3, 2, absolute);
  else BwDShellMultTransposeLoop(ctx, yy, ql, qg, 3, 6, 3, absolute);
  PetscCall(VecRestoreArrayRead(y, &yy));
  PetscCall(VecRestoreArray(q, &ql));
  if (ctx->scatter) {
    PetscCall(VecRestoreArray(ctx->ghost, &qg));
    PetscCall(VecScatterBegin(ctx->scatter, ctx->ghost, q, ADD_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterEnd(ctx->scatter, ctx->ghost, q, ADD_VALUES, SCATTER_REVERSE));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwDShellMultTransposeAdd(Mat A, Vec y, Vec q0, Vec q)
{
  BwDShell *ctx;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &ctx));
  if (q0 != q) PetscCall(VecCopy(q0, q));
  PetscCall(BwDShellTransposeAdd(ctx, y, q, PETSC_FALSE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwDShellMultTranspose(Mat A, Vec y, Vec q)
{
  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(q));
  PetscCall(BwDShellMultTransposeAdd(A, y, q, q));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* W_k = R B diag(s), with the columns of prescribed dofs zero. */
static PetscErrorCode BwMixedScaledCompatibility(BwMixed mx, PetscInt k, PetscReal w[])
{
  const PetscInt nd = mx->nd;
  PetscReal      rb[2 * BW_MAX_ND * BW_MAX_ND];

  PetscFunctionBeginUser;
  PetscCall(BwMixedCompatibility(mx, k, rb));
  for (PetscInt c = 0; c < 2 * nd; c++) {
    PetscInt  b = mx->geom->pair[2 * k + c / nd];
    PetscReal s = mx->model->prescribed[nd * b + c % nd] ? 0 : mx->qscale[nd * b + c % nd];
    for (PetscInt r = 0; r < nd; r++) w[2 * nd * r + c] = rb[2 * nd * r + c] * s;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedCreateDShell(BwMixed mx, Mat *D)
{
  BwGeometry geom = mx->geom;
  BwDShell  *ctx;
  PetscInt   nghost = 0, *ghosts, m = mx->m, qend = mx->qstart + mx->nq_local;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&ctx));
  ctx->m        = m;
  ctx->n        = mx->nown_interfaces;
  ctx->nq_local = mx->nq_local;
  ctx->portions = &mx->portions;
  ctx->dim = (int)mx->dim;
  ctx->nd  = mx->nd;
  ctx->ns  = mx->ns;
  PetscCall(PetscMalloc4((mx->dim == 3 ? 27 : 2 * mx->nd * mx->nd) * ctx->n + 1, &ctx->w, 2 * ctx->n + 1, &ctx->col, ctx->n + 1, &ctx->skt, ctx->n + 1, &ctx->skn));
  PetscCall(PetscMalloc4(ctx->n + 1, &ctx->first, ctx->n + 1, &ctx->np, ctx->n + 1, &ctx->row, mx->ns * mx->portions.maxnp, &ctx->work));
  PetscCall(PetscMalloc1(ctx->n + 1, &ctx->uniform));
  /* blocks owned elsewhere, by their first q row, sorted and unique: the ghost layout */
  PetscCall(PetscMalloc1(2 * ctx->n + 1, &ghosts));
  for (PetscInt e = 0; e < ctx->n; e++) {
    PetscInt k = mx->own_interfaces[e];
    for (PetscInt s = 0; s < 2; s++) {
      PetscInt r = mx->qrow[geom->pair[2 * k + s]];
      if (r >= 0 && (r < mx->qstart || r >= qend)) ghosts[nghost++] = r;
    }
  }
  PetscCall(PetscSortRemoveDupsInt(&nghost, ghosts));
  for (PetscInt e = 0; e < ctx->n; e++) {
    PetscInt k = mx->own_interfaces[e];
    if (mx->dim == 2) PetscCall(BwMixedScaledCompatibility(mx, k, ctx->w + 2 * mx->nd * mx->nd * e));
    else {
      /* Q, M_i, M_j from the kernel's R B (6 x 12, row-major) */
      PetscReal rb[2 * BW_MAX_ND * BW_MAX_ND], *Q = ctx->w + 27 * e;
      PetscCall(BwMixedCompatibility(mx, k, rb));
      for (PetscInt r = 0; r < 3; r++)
        for (PetscInt c = 0; c < 3; c++) {
          Q[3 * r + c]      = rb[12 * r + 6 + c];
          Q[9 + 3 * r + c]  = rb[12 * r + 3 + c];
          Q[18 + 3 * r + c] = rb[12 * r + 9 + c];
        }
    }
    for (PetscInt s = 0; s < 2; s++) {
      PetscInt r = mx->qrow[geom->pair[2 * k + s]], gi;
      if (r < 0) ctx->col[2 * e + s] = -1;
      else if (r >= mx->qstart && r < qend) ctx->col[2 * e + s] = r - mx->qstart;
      else {
        PetscCall(PetscFindInt(r, nghost, ghosts, &gi));
        ctx->col[2 * e + s] = mx->nq_local + mx->nd * gi;
      }
    }
    BwMixedStiffnessRoots(mx, k, &ctx->skt[e], &ctx->skn[e]);
    ctx->first[e] = BwPortionsFirst(&mx->portions, k);
    ctx->np[e]    = BwPortionsCount(&mx->portions, k);
    ctx->uniform[e] = mx->portions.uniform[mx->portions.layout[k]];
    ctx->row[e]   = e ? ctx->row[e - 1] + mx->ns * ctx->np[e - 1] : 0;
  }
  {
    /* the scatter is collective: every rank creates one if any rank needs it */
    PetscInt any = nghost, anyg;
    PetscCallMPI(MPIU_Allreduce(&any, &anyg, 1, MPIU_INT, MPI_MAX, mx->comm));
    if (anyg) {
      IS  is;
      Vec q;
      PetscCall(VecCreateSeq(PETSC_COMM_SELF, mx->nd * nghost, &ctx->ghost));
      for (PetscInt g = 0; g < nghost; g++) ghosts[g] /= mx->nd; /* a block's first q row is nd x its q index */
      PetscCall(ISCreateBlock(PETSC_COMM_SELF, mx->nd, nghost, ghosts, PETSC_COPY_VALUES, &is));
      PetscCall(VecCreateMPIWithArray(mx->comm, 1, mx->nq_local, mx->nq_global, NULL, &q));
      PetscCall(VecScatterCreate(q, is, ctx->ghost, NULL, &ctx->scatter));
      PetscCall(VecDestroy(&q));
      PetscCall(ISDestroy(&is));
    }
  }
  if (mx->dim == 3) {
    /* the dof scales in the q layout: the owned blocks', then the ghosts' */
    PetscCall(PetscMalloc2(mx->nq_local + 1, &ctx->scl, mx->nd * nghost + 1, &ctx->scg));
    for (PetscInt e = 0; e < mx->nown_blocks; e++) {
      PetscInt b = mx->own_blocks[e];
      if (mx->qrow[b] < 0) continue;
      for (PetscInt c = 0; c < mx->nd; c++) ctx->scl[mx->qrow[b] - mx->qstart + c] = mx->model->prescribed[mx->nd * b + c] ? 0 : mx->qscale[mx->nd * b + c];
    }
    for (PetscInt e = 0; e < ctx->n; e++) {
      PetscInt k = mx->own_interfaces[e];
      for (PetscInt s = 0; s < 2; s++) {
        PetscInt b = geom->pair[2 * k + s], c = ctx->col[2 * e + s];
        if (c < mx->nq_local) continue; /* owned, or no unknowns */
        for (PetscInt f = 0; f < mx->nd; f++) ctx->scg[c - mx->nq_local + f] = mx->model->prescribed[mx->nd * b + f] ? 0 : mx->qscale[mx->nd * b + f];
      }
    }
  }
  PetscCall(PetscFree(ghosts));
  PetscCall(MatCreateShell(mx->comm, mx->nr_local, mx->nq_local, mx->nr_global, mx->nq_global, ctx, D));
  PetscCall(MatShellSetOperation(*D, MATOP_MULT, (void (*)(void))BwDShellMult));
  PetscCall(MatShellSetOperation(*D, MATOP_MULT_TRANSPOSE, (void (*)(void))BwDShellMultTranspose));
  PetscCall(MatShellSetOperation(*D, MATOP_MULT_TRANSPOSE_ADD, (void (*)(void))BwDShellMultTransposeAdd));
  PetscCall(MatShellSetOperation(*D, MATOP_DESTROY, (void (*)(void))BwDShellDestroy));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The local index of owned interface k's first portion: tangents and the
 * stresses of owned interfaces are stored portion after portion. */
static inline PetscInt BwLocalPortion(BwMixed mx, PetscInt k) { return (mx->rrow[k] - mx->rstart) / mx->ns; }

/* v <- T v with T = C^-1/2 C_t C^-1/2 of a portion (row-major ns x ns) */
static inline void BwApplyScaledTangent(PetscInt ns, const PetscReal T[], PetscScalar v[])
{
  PetscScalar t[BW_MAX_NS];
  for (PetscInt a = 0; a < ns; a++) t[a] = v[a];
  for (PetscInt a = 0; a < ns; a++) {
    v[a] = 0;
    for (PetscInt b = 0; b < ns; b++) v[a] += T[ns * a + b] * t[b];
  }
}

/* The owned portions are stored one after the other, interface after
 * interface (BwLocalPortion), so T is applied portion by portion over the
 * whole stress part, with the dimension's constant sizes. */
static inline void BwApplyTangentLoop(PetscInt n, const PetscReal *T, PetscScalar *y, const PetscInt ns)
{
  for (PetscInt p = 0; p < n; p++) BwApplyScaledTangent(ns, T + ns * ns * p, y + ns * p);
}

PetscErrorCode BwMixedApplyTangent(BwMixed mx, Vec yr)
{
  PetscScalar *y;
  PetscInt     n = mx->nr_local / mx->ns;

  PetscFunctionBeginUser;
  if (!mx->tangent) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(VecGetArray(yr, &y));
  if (mx->ns == 2) BwApplyTangentLoop(n, mx->scaled_tangent, y, 2);
  else BwApplyTangentLoop(n, mx->scaled_tangent, y, 3);
  PetscCall(VecRestoreArray(yr, &y));
  PetscFunctionReturn(PETSC_SUCCESS);
}

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


PetscErrorCode BwMixedAssembleD(BwMixed mx, PetscBool tangent, Mat *D)
{
  BwGeometry     geom = mx->geom;
  const PetscInt nd = mx->nd, ns = mx->ns;
  PetscInt      *ia, *ja, n = 0, cols[2 * BW_MAX_ND];
  PetscReal     *va, *d, w[2 * BW_MAX_ND * BW_MAX_ND];

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(mx->nr_local + 1, &ia));
  ia[0] = 0;
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
    PetscInt k = mx->own_interfaces[e], nf = 0, nrows = ns * BwPortionsCount(&mx->portions, k);
    for (PetscInt s = 0; s < 2; s++) nf += mx->qrow[geom->pair[2 * k + s]] >= 0 ? nd : 0;
    for (PetscInt p = 0; p < nrows; p++, n++) ia[n + 1] = ia[n] + nf;
  }
  PetscCall(PetscMalloc1(ia[mx->nr_local] + 1, &ja));
  PetscCall(PetscMalloc1(ia[mx->nr_local] + 1, &va));
  PetscCall(PetscMalloc1(2 * nd * ns * mx->portions.maxnp, &d));
  n = 0;
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
    PetscInt         k = mx->own_interfaces[e], nc = 0;
    const PetscReal *area, *xi, *eta;
    PetscInt         np = BwMixedPortions(mx, k, &area, &xi, &eta, NULL);
    int              status;
    PetscCall(BwMixedScaledCompatibility(mx, k, w));
    bw_kernel_operator((int)mx->dim, (int)np, area, xi, eta, mx->model->kt[k], mx->model->kn[k], w, d, &status);
    PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "kernel failed on interface %" PetscInt_FMT, k);
    if (tangent && mx->tangent) {
      PetscInt lp = BwLocalPortion(mx, k);
      for (PetscInt p = 0; p < np; p++) {
        const PetscReal *T = mx->scaled_tangent + ns * ns * (lp + p);
        PetscReal       *rows = d + 2 * nd * ns * p;
        for (PetscInt c = 0; c < 2 * nd; c++) {
          PetscScalar v[BW_MAX_NS];
          for (PetscInt a = 0; a < ns; a++) v[a] = rows[2 * nd * a + c];
          BwApplyScaledTangent(ns, T, v);
          for (PetscInt a = 0; a < ns; a++) rows[2 * nd * a + c] = PetscRealPart(v[a]);
        }
      }
    }
    for (PetscInt s = 0; s < 2; s++) {
      PetscInt r = mx->qrow[geom->pair[2 * k + s]];
      if (r >= 0)
        for (PetscInt f = 0; f < nd; f++) cols[nc++] = nd * s + f;
    }
    for (PetscInt p = 0; p < ns * np; p++, n++) {
      PetscInt at0 = ia[n];
      for (PetscInt c = 0; c < nc; c++) {
        PetscInt blk = geom->pair[2 * k + cols[c] / nd];
        ja[at0 + c]  = mx->qrow[blk] + cols[c] % nd;
        va[at0 + c]  = d[2 * nd * p + cols[c]];
      }
      BwSortRow(nc, ja + at0, va + at0);
    }
  }
  PetscCall(PetscFree(d));
  PetscCall(BwMatFromCSR(mx->comm, mx->nr_local, mx->nq_local, mx->nr_global, mx->nq_global, "mixed_D_", ia, ja, va, D, NULL));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* y_q += spring x_q at the spring's dof (on the rank that owns it). */
static PetscErrorCode BwMixedAddSpring(BwMixed mx, Vec xq, Vec yq)
{
  PetscInt row = mx->spring_block >= 0 ? mx->qrow[mx->spring_block] : -1;

  PetscFunctionBeginUser;
  /* every rank takes the arrays: the state of yq moves everywhere (a state
   * bumped on one rank only leaves stale cached norms on the others) */
  {
    const PetscScalar *x;
    PetscScalar       *y;
    PetscCall(VecGetArrayRead(xq, &x));
    PetscCall(VecGetArray(yq, &y));
    if (row >= 0 && row >= mx->qstart && row < mx->qstart + mx->nq_local) y[row - mx->qstart + mx->spring_dof] += mx->spring * x[row - mx->qstart + mx->spring_dof];
    PetscCall(VecRestoreArray(yq, &y));
    PetscCall(VecRestoreArrayRead(xq, &x));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* K = [-I, T D^; D^T, P] applied through views of the two fields. */
static PetscErrorCode BwKShellMult(Mat K, Vec x, Vec y)
{
  BwMixed mx;
  Vec     xr, xq, yr, yq;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(K, &mx));
  PetscCall(VecGetSubVector(x, mx->isr, &xr));
  PetscCall(VecGetSubVector(x, mx->isq, &xq));
  PetscCall(VecGetSubVector(y, mx->isr, &yr));
  PetscCall(VecGetSubVector(y, mx->isq, &yq));
  PetscCall(MatMult(mx->D, xq, yr));
  PetscCall(BwMixedApplyTangent(mx, yr));
  PetscCall(VecAXPY(yr, -1.0, xr));
  PetscCall(VecPointwiseMult(yq, mx->pmask, xq));
  if (mx->spring_gblock >= 0) PetscCall(BwMixedAddSpring(mx, xq, yq));
  PetscCall(MatMultTransposeAdd(mx->D, xr, yq, yq));
  PetscCall(VecRestoreSubVector(y, mx->isq, &yq));
  PetscCall(VecRestoreSubVector(y, mx->isr, &yr));
  PetscCall(VecRestoreSubVector(x, mx->isq, &xq));
  PetscCall(VecRestoreSubVector(x, mx->isr, &xr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The Schur complement applied exactly, S~ x = P x (+ the spring) +
 * D^T T D^ x, the operator of the refinement on q (BwMixedCreateSchurOperator).
 * With D^ by its structure, interface by interface: D^_e x into a buffer
 * of one interface's stresses, T, then D^_e^T of it added to y, so that no
 * vector of the stresses' size is needed (2.3 KB per block in 3D at m = 8,
 * m_b = 4). Other storages go through one stress-sized vector. */
/* y = S~ x as above, or with absolute the sizes of its terms, |P| |x| +
 * |D^T| (|D^| |x|) (BwMixedSchurTermsNorm; the elastic operator held by
 * its structure, without a spring). */
static PetscErrorCode BwSchurShellApply(BwMixed mx, Vec x, Vec y, PetscBool absolute)
{
  BwDShell          *ctx;
  const PetscScalar *xl, *xg = NULL;
  PetscScalar       *yl, *yg = NULL;

  PetscFunctionBeginUser;
  PetscCall(VecPointwiseMult(y, mx->pmask, x));
  if (absolute) {
    PetscCheck(mx->storage == BW_STORAGE_SHELL && !mx->tangent && mx->spring_gblock < 0, mx->comm, PETSC_ERR_SUP, "the sizes of S~'s terms need the elastic operator held by its structure");
    PetscCall(VecAbs(y));
  }
  if (mx->spring_gblock >= 0) PetscCall(BwMixedAddSpring(mx, x, y));
  if (mx->storage != BW_STORAGE_SHELL) {
    Vec r;
    PetscCall(MatCreateVecs(mx->D, NULL, &r));
    PetscCall(MatMult(mx->D, x, r));
    PetscCall(BwMixedApplyTangent(mx, r));
    PetscCall(MatMultTransposeAdd(mx->D, r, y, y));
    PetscCall(VecDestroy(&r));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(MatShellGetContext(mx->D, &ctx));
  if (!ctx->ye) PetscCall(PetscMalloc1(mx->ns * mx->portions.maxnp + 1, &ctx->ye));
  if (ctx->scatter) {
    if (!ctx->ghost_sum) PetscCall(VecDuplicate(ctx->ghost, &ctx->ghost_sum));
    PetscCall(VecScatterBegin(ctx->scatter, x, ctx->ghost, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(ctx->scatter, x, ctx->ghost, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecGetArrayRead(ctx->ghost, &xg));
    PetscCall(VecZeroEntries(ctx->ghost_sum));
    PetscCall(VecGetArray(ctx->ghost_sum, &yg));
  }
  PetscCall(VecGetArrayRead(x, &xl));
  PetscCall(VecGetArray(y, &yl));
  for (PetscInt e = 0; e < ctx->n; e++) {
    PetscInt lp = BwLocalPortion(mx, mx->own_interfaces[e]), np = ctx->np[e];
    if (mx->dim == 2) {
      BwDShellMultOneAs(ctx, e, xl, xg, ctx->ye, 2, 3, 2, absolute);
      if (mx->tangent) BwApplyTangentLoop(np, mx->scaled_tangent + 4 * lp, ctx->ye, 2);
      BwDShellMultTransposeOneAs(ctx, e, ctx->ye, yl, yg, 2, 3, 2, absolute);
    } else {
      BwDShellMultOneAs(ctx, e, xl, xg, ctx->ye, 3, 6, 3, absolute);
      if (mx->tangent) BwApplyTangentLoop(np, mx->scaled_tangent + 9 * lp, ctx->ye, 3);
      BwDShellMultTransposeOneAs(ctx, e, ctx->ye, yl, yg, 3, 6, 3, absolute);
    }
  }
  PetscCall(VecRestoreArray(y, &yl));
  PetscCall(VecRestoreArrayRead(x, &xl));
  if (ctx->scatter) {
    PetscCall(VecRestoreArrayRead(ctx->ghost, &xg));
    PetscCall(VecRestoreArray(ctx->ghost_sum, &yg));
    PetscCall(VecScatterBegin(ctx->scatter, ctx->ghost_sum, y, ADD_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterEnd(ctx->scatter, ctx->ghost_sum, y, ADD_VALUES, SCATTER_REVERSE));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwSchurShellMult(Mat S, Vec x, Vec y)
{
  BwMixed mx;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(S, &mx));
  PetscCall(BwSchurShellApply(mx, x, y, PETSC_FALSE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The size of the terms of w - S~ q: |w| + |P| |q| + |D^T| (|D^| |q|),
 * interface by interface as BwSchurShellMult forms the product. Rounding q
 * to double (and the product's own rounding) moves the residual by up to
 * eps times this: on a tall wall the displacements are sums of many
 * joints' jumps, and the stiff joints see each ulp of them (bench's 3D
 * wall: 0.13-0.18 of eps times it measured at 30, 100 and 200 courses, in
 * double and in double-double alike): the worst case of the rounding, so
 * a double-precision q cannot be expected to have a residual far below
 * it. For the elastic operator held by its structure,
 * without a spring (BwMixedRoundoffSupported). */
PetscErrorCode BwMixedSchurTermsNorm(BwMixed mx, Vec q, Vec w, PetscReal *norm)
{
  Vec y;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(q, &y));
  PetscCall(BwSchurShellApply(mx, q, y, PETSC_TRUE));
  {
    PetscScalar       *yy;
    const PetscScalar *ww;
    PetscInt           n;
    PetscCall(VecGetLocalSize(y, &n));
    PetscCall(VecGetArray(y, &yy));
    PetscCall(VecGetArrayRead(w, &ww));
    for (PetscInt i = 0; i < n; i++) yy[i] = PetscAbsScalar(yy[i]) + PetscAbsScalar(ww[i]);
    PetscCall(VecRestoreArrayRead(w, &ww));
    PetscCall(VecRestoreArray(y, &yy));
  }
  PetscCall(VecNorm(y, NORM_2, norm));
  PetscCall(VecDestroy(&y));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedCreateSchurOperator(BwMixed mx, Mat *S)
{
  PetscFunctionBeginUser;
  PetscCall(MatCreateShell(mx->comm, mx->nq_local, mx->nq_local, mx->nq_global, mx->nq_global, mx, S));
  PetscCall(MatShellSetOperation(*S, MATOP_MULT, (void (*)(void))BwSchurShellMult));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedSchurRHS(BwMixed mx, Vec b, Vec w)
{
  Vec br, bq;

  PetscFunctionBeginUser;
  PetscCall(VecGetSubVector(b, mx->isr, &br));
  PetscCall(VecGetSubVector(b, mx->isq, &bq));
  PetscCall(MatMultTransposeAdd(mx->D, br, bq, w));
  PetscCall(VecRestoreSubVector(b, mx->isq, &bq));
  PetscCall(VecRestoreSubVector(b, mx->isr, &br));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedStressesFromDofs(BwMixed mx, Vec b, Vec x)
{
  Vec br, xr, xq;

  PetscFunctionBeginUser;
  PetscCall(VecGetSubVector(b, mx->isr, &br));
  PetscCall(VecGetSubVector(x, mx->isr, &xr));
  PetscCall(VecGetSubVector(x, mx->isq, &xq));
  PetscCall(MatMult(mx->D, xq, xr));
  PetscCall(BwMixedApplyTangent(mx, xr));
  PetscCall(VecAXPY(xr, -1.0, br));
  PetscCall(VecRestoreSubVector(x, mx->isq, &xq));
  PetscCall(VecRestoreSubVector(x, mx->isr, &xr));
  PetscCall(VecRestoreSubVector(b, mx->isr, &br));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The sums BwMixedCheck needs of b - K x, by block row (see mixed.h),
 * without a vector of K's size where D^ is a shell: the q rows through one
 * q-sized vector, the stress rows interface by interface (D^_e q~ into a
 * buffer of one interface's rows), so that the check of a 3D wall costs no
 * copy of its stresses (2.3 KB per block at m = 8, m_b = 4). */
PetscErrorCode BwMixedResidualSums(BwMixed mx, Vec x, Vec b, PetscReal loc[6])
{
  const PetscInt     ns = mx->ns;
  Vec                xr, xq, br, bq, kq;
  const PetscScalar *xx, *bb, *kk, *ql, *qg = NULL;
  BwDShell          *ctx;
  PetscScalar       *ye;

  PetscFunctionBeginUser;
  for (PetscInt c = 0; c < 6; c++) loc[c] = 0;
  if (mx->storage != BW_STORAGE_SHELL) {
    Vec Kx;
    PetscCall(VecDuplicate(x, &Kx));
    PetscCall(MatMult(mx->K, x, Kx));
    PetscCall(VecGetArrayRead(Kx, &kk));
    PetscCall(VecGetArrayRead(b, &bb));
    PetscCall(VecGetArrayRead(x, &xx));
    for (PetscInt e = 0; e < mx->nr_local; e++) {
      PetscReal res_r = PetscRealPart(bb[e] - kk[e]), dq = PetscRealPart(kk[e] + xx[e] - bb[e]); /* T D^ q~ including prescribed dofs */
      loc[0] += res_r * res_r;
      loc[1] += dq * dq;
      loc[4] += PetscRealPart(bb[e] * bb[e]);
      loc[5] += PetscRealPart(xx[e] * xx[e]);
    }
    for (PetscInt e = mx->nr_local; e < mx->nlocal; e++) {
      PetscReal res_q = PetscRealPart(bb[e] - kk[e]);
      loc[2] += res_q * res_q;
      loc[3] += PetscRealPart(bb[e] * bb[e]);
    }
    PetscCall(VecRestoreArrayRead(Kx, &kk));
    PetscCall(VecRestoreArrayRead(b, &bb));
    PetscCall(VecRestoreArrayRead(x, &xx));
    PetscCall(VecDestroy(&Kx));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(VecGetSubVector(x, mx->isr, &xr));
  PetscCall(VecGetSubVector(x, mx->isq, &xq));
  PetscCall(VecGetSubVector(b, mx->isr, &br));
  PetscCall(VecGetSubVector(b, mx->isq, &bq));
  /* q rows: P q~ (+ the spring) + D^T r~ */
  PetscCall(VecDuplicate(xq, &kq));
  PetscCall(VecPointwiseMult(kq, mx->pmask, xq));
  if (mx->spring_gblock >= 0) PetscCall(BwMixedAddSpring(mx, xq, kq));
  PetscCall(MatMultTransposeAdd(mx->D, xr, kq, kq));
  PetscCall(VecGetArrayRead(kq, &kk));
  PetscCall(VecGetArrayRead(bq, &bb));
  for (PetscInt e = 0; e < mx->nq_local; e++) {
    PetscReal res_q = PetscRealPart(bb[e] - kk[e]);
    loc[2] += res_q * res_q;
    loc[3] += PetscRealPart(bb[e] * bb[e]);
  }
  PetscCall(VecRestoreArrayRead(bq, &bb));
  PetscCall(VecRestoreArrayRead(kq, &kk));
  PetscCall(VecDestroy(&kq));
  /* stress rows: -r~ + T D^ q~, an interface at a time */
  PetscCall(MatShellGetContext(mx->D, &ctx));
  if (ctx->scatter) {
    PetscCall(VecScatterBegin(ctx->scatter, xq, ctx->ghost, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(ctx->scatter, xq, ctx->ghost, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecGetArrayRead(ctx->ghost, &qg));
  }
  PetscCall(PetscMalloc1(ns * mx->portions.maxnp + 1, &ye));
  PetscCall(VecGetArrayRead(xq, &ql));
  PetscCall(VecGetArrayRead(xr, &xx));
  PetscCall(VecGetArrayRead(br, &bb));
  for (PetscInt e = 0; e < ctx->n; e++) {
    PetscInt           k = mx->own_interfaces[e], lp = BwLocalPortion(mx, k), np = ctx->np[e];
    const PetscScalar *xe = xx + ctx->row[e], *be = bb + ctx->row[e];
    if (mx->dim == 2) BwDShellMultOne(ctx, e, ql, qg, ye, 2, 3, 2);
    else BwDShellMultOne(ctx, e, ql, qg, ye, 3, 6, 3);
    if (mx->tangent)
      for (PetscInt p = 0; p < np; p++) BwApplyScaledTangent(ns, mx->scaled_tangent + ns * ns * (lp + p), ye + ns * p);
    for (PetscInt i = 0; i < ns * np; i++) {
      PetscReal dq = PetscRealPart(ye[i] - be[i]), res_r = PetscRealPart(be[i] + xe[i] - ye[i]);
      loc[0] += res_r * res_r;
      loc[1] += dq * dq;
      loc[4] += PetscRealPart(be[i] * be[i]);
      loc[5] += PetscRealPart(xe[i] * xe[i]);
    }
  }
  PetscCall(VecRestoreArrayRead(br, &bb));
  PetscCall(VecRestoreArrayRead(xr, &xx));
  PetscCall(VecRestoreArrayRead(xq, &ql));
  PetscCall(PetscFree(ye));
  if (ctx->scatter) PetscCall(VecRestoreArrayRead(ctx->ghost, &qg));
  PetscCall(VecRestoreSubVector(b, mx->isq, &bq));
  PetscCall(VecRestoreSubVector(b, mx->isr, &br));
  PetscCall(VecRestoreSubVector(x, mx->isq, &xq));
  PetscCall(VecRestoreSubVector(x, mx->isr, &xr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The round-off bound of the displacements for a system too large to be
 * assembled (solver/estimates.c, BwSolverForwardBoundSchur): LAPACK's
 * forward error bound |x - x*| <= |K~^-1| g, g = |b - K~ x| + gamma (|K~|
 * |x| + |b|), restricted to the displacement rows, whose rows of K~^-1 are
 * [S~^-1 D^T, S~^-1] (S~ = D^T D^ + P: x_q = S~^-1 (b_q + D^T b_r)). |K~|
 * |x| is formed the way the products form it, |D^| as |E_p| |W_k|
 * (bw_kernel_jumps_abs), so it bounds their rounding; D^T stays inside
 * S~^-1 D^T, whose pairs of equal and opposite forces would otherwise be
 * bounded as loads of one sign (a bound with |S^| alone claimed 2e-5 on
 * walls right to 1e-15). For the elastic operator held by its structure,
 * without a spring: where else the whole system is assembled. */
PetscErrorCode BwMixedRoundoffSupported(BwMixed mx, PetscBool *yes)
{
  PetscFunctionBeginUser;
  *yes = mx->storage == BW_STORAGE_SHELL && !mx->tangent && mx->spring_gblock < 0 ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* hq = |b_q - (K~ x)_q| + gamma_q (|b_q| + |P| |x_q| + |D^T| |x_r|) by
 * rows, and gamma_r for the stress rows. gamma = d eps, d the most
 * roundings a term of the row's sum goes through in the products as they
 * are computed (Higham, Accuracy and Stability, 2nd ed., sec. 3.1: a sum of
 * terms each rounded at most d times errs by at most gamma_d times the sum
 * of their sizes), rather than LAPACK's one count of the longest row for
 * every row: in 3D a stress row of D^ q~ is a jump of three components of
 * dG (12 products each), scaled, then added to b_r and x_r: 2 nd + 6; a
 * block row sums over its portions (two terms each for a moment), W^T
 * (2 nd), its interfaces, P and b_q: 2 np + 2 nd + deg + 4. The top beam
 * of a 3D wall touches a course of units: by the longest row every row's
 * bound grew a hundredfold. */
PetscErrorCode BwMixedRoundoffQ(BwMixed mx, Vec x, Vec b, Vec hq, PetscReal *gamma_r)
{
  BwDShell *ctx;
  Vec       xr, xq, br, bq, a;

  PetscFunctionBeginUser;
  *gamma_r = (2 * mx->nd + 6) * PETSC_MACHINE_EPSILON;
  PetscCall(MatShellGetContext(mx->D, &ctx));
  PetscCall(VecGetSubVector(x, mx->isr, &xr));
  PetscCall(VecGetSubVector(x, mx->isq, &xq));
  PetscCall(VecGetSubVector(b, mx->isr, &br));
  PetscCall(VecGetSubVector(b, mx->isq, &bq));
  /* |b_q - P x_q - D^T x_r| */
  PetscCall(VecPointwiseMult(hq, mx->pmask, xq));
  PetscCall(MatMultTransposeAdd(mx->D, xr, hq, hq));
  PetscCall(VecAYPX(hq, -1.0, bq));
  PetscCall(VecAbs(hq));
  /* |D^T| |x_r| */
  PetscCall(VecDuplicate(hq, &a));
  PetscCall(VecZeroEntries(a));
  PetscCall(BwDShellTransposeAdd(ctx, xr, a, PETSC_TRUE));
  {
    PetscScalar       *av, *h;
    const PetscScalar *xv, *bv, *pv;
    PetscInt           n;
    PetscCall(VecGetLocalSize(a, &n));
    PetscCall(VecGetArray(a, &av));
    PetscCall(VecGetArray(hq, &h));
    PetscCall(VecGetArrayRead(xq, &xv));
    PetscCall(VecGetArrayRead(bq, &bv));
    PetscCall(VecGetArrayRead(mx->pmask, &pv));
    for (PetscInt i = 0; i < n; i++) av[i] = PetscRealPart(av[i]) + PetscAbsScalar(bv[i]) + PetscAbsScalar(pv[i] * xv[i]);
    for (PetscInt e = 0; e < mx->nown_blocks; e++) {
      PetscInt  bl = mx->own_blocks[e], i0 = mx->qrow[bl] - mx->qstart;
      PetscReal gamma_q = (2 * mx->portions.maxnp + 2 * mx->nd + (mx->adj_offsets[bl + 1] - mx->adj_offsets[bl]) + 4) * PETSC_MACHINE_EPSILON;
      if (mx->qrow[bl] < 0) continue;
      for (PetscInt c = 0; c < mx->nd; c++) h[i0 + c] += gamma_q * PetscRealPart(av[i0 + c]);
    }
    PetscCall(VecRestoreArrayRead(mx->pmask, &pv));
    PetscCall(VecRestoreArrayRead(bq, &bv));
    PetscCall(VecRestoreArrayRead(xq, &xv));
    PetscCall(VecRestoreArray(hq, &h));
    PetscCall(VecRestoreArray(a, &av));
  }
  PetscCall(VecDestroy(&a));
  PetscCall(VecRestoreSubVector(b, mx->isq, &bq));
  PetscCall(VecRestoreSubVector(b, mx->isr, &br));
  PetscCall(VecRestoreSubVector(x, mx->isq, &xq));
  PetscCall(VecRestoreSubVector(x, mx->isr, &xr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* One pass over the stress rows for the Hager-Higham estimate of the bound
 * (estimates.c), without a vector of the stresses' size: with h_r =
 * |b_r + x_r - D^ x_q| + gamma (|x_r| + |D^| |x_q| + |b_r|) made an
 * interface at a time, y_r = h_r .* (D^ z): *l1 = ||y_r||_1 (over all
 * ranks), and acc = D^T (h_r .* sign(y_r)). */
PetscErrorCode BwMixedRoundoffSweep(BwMixed mx, Vec x, Vec b, PetscReal gamma, Vec z, Vec acc, PetscReal *l1)
{
  const PetscInt     ns = mx->ns;
  BwDShell          *ctx;
  Vec                xr, xq, br, gx = NULL;
  const PetscScalar *xl, *xg = NULL, *zl, *zg = NULL, *xx, *bb;
  PetscScalar       *al, *ag = NULL, *de, *ae, *te, *ye;
  PetscReal          sum = 0;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(mx->D, &ctx));
  PetscCall(VecGetSubVector(x, mx->isr, &xr));
  PetscCall(VecGetSubVector(x, mx->isq, &xq));
  PetscCall(VecGetSubVector(b, mx->isr, &br));
  PetscCall(VecZeroEntries(acc));
  if (ctx->scatter) {
    /* the ghosts of x_q and of z, and acc's sums for other ranks' blocks */
    PetscCall(VecDuplicate(ctx->ghost, &gx));
    if (!ctx->ghost_sum) PetscCall(VecDuplicate(ctx->ghost, &ctx->ghost_sum));
    PetscCall(VecScatterBegin(ctx->scatter, xq, gx, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(ctx->scatter, xq, gx, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterBegin(ctx->scatter, z, ctx->ghost, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(ctx->scatter, z, ctx->ghost, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecGetArrayRead(ctx->ghost, &zg));
    PetscCall(VecGetArrayRead(gx, &xg));
    PetscCall(VecZeroEntries(ctx->ghost_sum));
    PetscCall(VecGetArray(ctx->ghost_sum, &ag));
  }
  PetscCall(PetscMalloc4(ns * mx->portions.maxnp + 1, &de, ns * mx->portions.maxnp + 1, &ae, ns * mx->portions.maxnp + 1, &te, ns * mx->portions.maxnp + 1, &ye));
  PetscCall(VecGetArrayRead(xq, &xl));
  PetscCall(VecGetArrayRead(z, &zl));
  PetscCall(VecGetArray(acc, &al));
  PetscCall(VecGetArrayRead(xr, &xx));
  PetscCall(VecGetArrayRead(br, &bb));
  for (PetscInt e = 0; e < ctx->n; e++) {
    const PetscScalar *xe = xx + ctx->row[e], *be = bb + ctx->row[e];
    if (mx->dim == 2) {
      BwDShellMultOneAs(ctx, e, xl, xg, de, 2, 3, 2, PETSC_FALSE);
      BwDShellMultOneAs(ctx, e, xl, xg, ae, 2, 3, 2, PETSC_TRUE);
      BwDShellMultOneAs(ctx, e, zl, zg, te, 2, 3, 2, PETSC_FALSE);
    } else {
      BwDShellMultOneAs(ctx, e, xl, xg, de, 3, 6, 3, PETSC_FALSE);
      BwDShellMultOneAs(ctx, e, xl, xg, ae, 3, 6, 3, PETSC_TRUE);
      BwDShellMultOneAs(ctx, e, zl, zg, te, 3, 6, 3, PETSC_FALSE);
    }
    for (PetscInt i = 0; i < ns * ctx->np[e]; i++) {
      PetscReal h = PetscAbsScalar(be[i] + xe[i] - de[i]) + gamma * (PetscAbsScalar(xe[i]) + PetscRealPart(ae[i]) + PetscAbsScalar(be[i]));
      PetscReal y = h * PetscRealPart(te[i]);
      sum += PetscAbsReal(y);
      ye[i] = y >= 0 ? h : -h;
    }
    if (mx->dim == 2) BwDShellMultTransposeOneAs(ctx, e, ye, al, ag, 2, 3, 2, PETSC_FALSE);
    else BwDShellMultTransposeOneAs(ctx, e, ye, al, ag, 3, 6, 3, PETSC_FALSE);
  }
  PetscCall(VecRestoreArrayRead(br, &bb));
  PetscCall(VecRestoreArrayRead(xr, &xx));
  PetscCall(VecRestoreArray(acc, &al));
  PetscCall(VecRestoreArrayRead(z, &zl));
  PetscCall(VecRestoreArrayRead(xq, &xl));
  PetscCall(PetscFree4(de, ae, te, ye));
  if (ctx->scatter) {
    PetscCall(VecRestoreArrayRead(gx, &xg));
    PetscCall(VecRestoreArrayRead(ctx->ghost, &zg));
    PetscCall(VecRestoreArray(ctx->ghost_sum, &ag));
    PetscCall(VecScatterBegin(ctx->scatter, ctx->ghost_sum, acc, ADD_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterEnd(ctx->scatter, ctx->ghost_sum, acc, ADD_VALUES, SCATTER_REVERSE));
    PetscCall(VecDestroy(&gx));
  }
  PetscCall(VecRestoreSubVector(b, mx->isr, &br));
  PetscCall(VecRestoreSubVector(x, mx->isq, &xq));
  PetscCall(VecRestoreSubVector(x, mx->isr, &xr));
  PetscCallMPI(MPIU_Allreduce(&sum, l1, 1, MPIU_REAL, MPIU_SUM, mx->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The block rows of the residual of the full system for stresses that
 * solve their rows, r_q = b_q - P x_q + D^T (b_r - D^ x_q), in
 * double-double and rounded once at the end: its error is far below
 * double's round-off, so S~^-1 r_q is the error of x_q itself, not the
 * noise of a residual computed in double (estimates.c). D^ as its factors
 * are stored (W_k, the dof scales, sqrt(A_p), sqrt(k)), products exact;
 * D^T the exact transpose of that (sqrt(A_p) where the products use A_p
 * / sqrt(A_p)). Sums for other ranks' blocks travel as two doubles, hi and
 * lo, added in double at the owner: exact where two ranks' nearly opposite
 * sums meet, as on a partition's boundary. For the operators of
 * BwMixedRoundoffSupported. */
PetscErrorCode BwMixedResidualExtra(BwMixed mx, Vec x, Vec b, Vec rq)
{
  const PetscInt     nd = mx->nd, ns = mx->ns, mp = mx->portions.maxnp;
  const int          dim = (int)mx->dim;
  BwDShell          *ctx;
  Vec                xq, br, bq, gh = NULL, gl = NULL, sh = NULL, sl = NULL;
  const PetscScalar *xl, *xg = NULL, *bb, *bql, *pm;
  PetscScalar       *ghi = NULL, *glo = NULL, *r;
  PetscReal         *jh, *jl, *rh, *rl;
  BwDD              *acc;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(mx->D, &ctx));
  PetscCall(VecGetSubVector(x, mx->isq, &xq));
  PetscCall(VecGetSubVector(b, mx->isr, &br));
  PetscCall(VecGetSubVector(b, mx->isq, &bq));
  if (ctx->scatter) {
    PetscCall(VecScatterBegin(ctx->scatter, xq, ctx->ghost, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(ctx->scatter, xq, ctx->ghost, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecGetArrayRead(ctx->ghost, &xg));
    PetscCall(VecDuplicate(ctx->ghost, &gh));
    PetscCall(VecDuplicate(ctx->ghost, &gl));
    PetscCall(VecZeroEntries(gh));
    PetscCall(VecZeroEntries(gl));
    PetscCall(VecGetArray(gh, &ghi));
    PetscCall(VecGetArray(gl, &glo));
  }
  PetscCall(PetscCalloc1(mx->nq_local + 1, &acc));
  PetscCall(PetscMalloc4(ns * mp, &jh, ns * mp, &jl, ns * mp, &rh, ns * mp, &rl));
  PetscCall(VecGetArrayRead(xq, &xl));
  PetscCall(VecGetArrayRead(br, &bb));
  for (PetscInt e = 0; e < ctx->n; e++) {
    const PetscInt   np  = ctx->np[e];
    const PetscReal *sqa = ctx->portions->sqrt_area + ctx->first[e], *xi = ctx->portions->xi + ctx->first[e], *eta = ctx->portions->eta + ctx->first[e];
    BwDD             dg[BW_MAX_ND] = {{0, 0}}, f[BW_MAX_ND];
    PetscReal        dgh[BW_MAX_ND], dgl[BW_MAX_ND], fh[BW_MAX_ND], fl[BW_MAX_ND];
    int              status;
    /* dG = W_k q_k */
    for (PetscInt s = 0; s < 2; s++) {
      PetscInt           c = ctx->col[2 * e + s];
      const PetscScalar *xv;
      if (c < 0) continue;
      xv = c < ctx->nq_local ? xl + c : xg + (c - ctx->nq_local);
      if (dim == 2) {
        const PetscReal *w = ctx->w + 2 * nd * nd * e;
        for (PetscInt rr = 0; rr < nd; rr++)
          for (PetscInt g = 0; g < nd; g++) dg[rr] = BwDDAdd(dg[rr], BwDDProd(w[2 * nd * rr + nd * s + g], PetscRealPart(xv[g])));
      } else {
        const PetscReal *Q = ctx->w + 27 * e, *M = Q + 9 * (s + 1), *sc = c < ctx->nq_local ? ctx->scl + c : ctx->scg + (c - ctx->nq_local);
        const PetscReal  sign = s ? 1 : -1;
        BwDD             v[6];
        for (PetscInt g = 0; g < 6; g++) v[g] = BwDDProd(sc[g], PetscRealPart(xv[g]));
        for (PetscInt rr = 0; rr < 3; rr++)
          for (PetscInt g = 0; g < 3; g++) {
            dg[rr]     = BwDDAdd(dg[rr], BwDDAdd(BwDDScale(sign * Q[3 * rr + g], v[g]), BwDDScale(M[3 * rr + g], v[3 + g])));
            dg[3 + rr] = BwDDAdd(dg[3 + rr], BwDDScale(sign * Q[3 * rr + g], v[3 + g]));
          }
      }
    }
    for (PetscInt g = 0; g < nd; g++) dgh[g] = dg[g].hi, dgl[g] = dg[g].lo;
    bw_kernel_jumps_dd(dim, (int)np, xi, eta, dgh, dgl, jh, jl, &status);
    PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "kernel failed on an interface");
    /* t = sqrt(k) (b_r - sqrt(A_p) sqrt(k) j), then D^T's sqrt(A_p) as the kernel's area */
    for (PetscInt p = 0; p < np; p++)
      for (PetscInt a = 0; a < ns; a++) {
        PetscInt  i  = ns * p + a;
        PetscReal sk = a == 1 ? ctx->skn[e] : ctx->skt[e];
        BwDD      y  = BwDDScale(sqa[p], BwDDScale(sk, (BwDD){jh[i], jl[i]})), t;
        t            = BwDDScale(sk, BwDDAdd((BwDD){PetscRealPart(bb[ctx->row[e] + i]), 0}, (BwDD){-y.hi, -y.lo}));
        rh[i] = t.hi, rl[i] = t.lo;
      }
    bw_kernel_resultants_dd(dim, (int)np, sqa, xi, eta, rh, rl, fh, fl, &status);
    PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "kernel failed on an interface");
    for (PetscInt g = 0; g < nd; g++) f[g] = (BwDD){fh[g], fl[g]};
    /* q_k += W_k^T f */
    for (PetscInt s = 0; s < 2; s++) {
      PetscInt c = ctx->col[2 * e + s];
      BwDD     add[BW_MAX_ND] = {{0, 0}};
      if (c < 0) continue;
      if (dim == 2) {
        const PetscReal *w = ctx->w + 2 * nd * nd * e;
        for (PetscInt g = 0; g < nd; g++)
          for (PetscInt rr = 0; rr < nd; rr++) add[g] = BwDDAdd(add[g], BwDDScale(w[2 * nd * rr + nd * s + g], f[rr]));
      } else {
        const PetscReal *Q = ctx->w + 27 * e, *M = Q + 9 * (s + 1), *sc = c < ctx->nq_local ? ctx->scl + c : ctx->scg + (c - ctx->nq_local);
        const PetscReal  sign = s ? 1 : -1;
        for (PetscInt g = 0; g < 3; g++) {
          BwDD u = {0, 0}, m = {0, 0};
          for (PetscInt rr = 0; rr < 3; rr++) {
            u = BwDDAdd(u, BwDDScale(sign * Q[3 * rr + g], f[rr]));
            m = BwDDAdd(m, BwDDAdd(BwDDScale(M[3 * rr + g], f[rr]), BwDDScale(sign * Q[3 * rr + g], f[3 + rr])));
          }
          add[g]     = BwDDScale(sc[g], u);
          add[3 + g] = BwDDScale(sc[3 + g], m);
        }
      }
      for (PetscInt g = 0; g < nd; g++) {
        if (c < ctx->nq_local) acc[c + g] = BwDDAdd(acc[c + g], add[g]);
        else {
          BwDD sum = BwDDAdd((BwDD){PetscRealPart(ghi[c - ctx->nq_local + g]), PetscRealPart(glo[c - ctx->nq_local + g])}, add[g]);
          ghi[c - ctx->nq_local + g] = sum.hi;
          glo[c - ctx->nq_local + g] = sum.lo;
        }
      }
    }
  }
  PetscCall(VecRestoreArrayRead(br, &bb));
  PetscCall(VecRestoreArrayRead(xq, &xl));
  PetscCall(PetscFree4(jh, jl, rh, rl));
  if (ctx->scatter) {
    PetscCall(VecRestoreArrayRead(ctx->ghost, &xg));
    PetscCall(VecRestoreArray(gh, &ghi));
    PetscCall(VecRestoreArray(gl, &glo));
    PetscCall(VecDuplicate(rq, &sh));
    PetscCall(VecDuplicate(rq, &sl));
    PetscCall(VecZeroEntries(sh));
    PetscCall(VecZeroEntries(sl));
    PetscCall(VecScatterBegin(ctx->scatter, gh, sh, ADD_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterEnd(ctx->scatter, gh, sh, ADD_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterBegin(ctx->scatter, gl, sl, ADD_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterEnd(ctx->scatter, gl, sl, ADD_VALUES, SCATTER_REVERSE));
    PetscCall(VecDestroy(&gh));
    PetscCall(VecDestroy(&gl));
  }
  /* + b_q - P x_q, once rounded */
  PetscCall(VecGetArrayRead(bq, &bql));
  PetscCall(VecGetArrayRead(mx->pmask, &pm));
  PetscCall(VecGetArrayRead(xq, &xl));
  PetscCall(VecGetArray(rq, &r));
  {
    const PetscScalar *hv = NULL, *lv = NULL;
    if (sh) {
      PetscCall(VecGetArrayRead(sh, &hv));
      PetscCall(VecGetArrayRead(sl, &lv));
    }
    for (PetscInt i = 0; i < mx->nq_local; i++) {
      BwDD t = BwDDAdd(acc[i], BwDDTwoSum(PetscRealPart(bql[i]), -PetscRealPart(pm[i] * xl[i])));
      if (sh) t = BwDDAdd(t, BwDDTwoSum(PetscRealPart(hv[i]), PetscRealPart(lv[i])));
      r[i] = t.hi + t.lo;
    }
    if (sh) {
      PetscCall(VecRestoreArrayRead(sh, &hv));
      PetscCall(VecRestoreArrayRead(sl, &lv));
    }
  }
  PetscCall(VecRestoreArray(rq, &r));
  PetscCall(VecRestoreArrayRead(xq, &xl));
  PetscCall(VecRestoreArrayRead(mx->pmask, &pm));
  PetscCall(VecRestoreArrayRead(bq, &bql));
  PetscCall(VecDestroy(&sh));
  PetscCall(VecDestroy(&sl));
  PetscCall(PetscFree(acc));
  PetscCall(VecRestoreSubVector(b, mx->isq, &bq));
  PetscCall(VecRestoreSubVector(b, mx->isr, &br));
  PetscCall(VecRestoreSubVector(x, mx->isq, &xq));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* K = [-I, T D^; D^T, P] as one AIJ matrix, from a nest of its blocks. */
PetscErrorCode BwMixedCreateAIJ(BwMixed mx, Mat *aij)
{
  Mat D, TD, A00, A11, Dt, blocks[4], nest;
  IS  is[2];
  Vec diag;

  PetscFunctionBeginUser;
  /* the assembled D^ (its own copy when the operator uses a shell) */
  PetscCall(BwMixedAssembleD(mx, PETSC_FALSE, &D));
  if (mx->tangent) PetscCall(BwMixedAssembleD(mx, PETSC_TRUE, &TD));
  else {
    PetscCall(PetscObjectReference((PetscObject)D));
    TD = D;
  }
  PetscCall(MatCreateConstantDiagonal(mx->comm, mx->nr_local, mx->nr_local, mx->nr_global, mx->nr_global, -1.0, &A00));
  PetscCall(MatCreateTranspose(D, &Dt));
  PetscCall(MatCreate(mx->comm, &A11));
  PetscCall(MatSetSizes(A11, mx->nq_local, mx->nq_local, mx->nq_global, mx->nq_global));
  PetscCall(MatSetType(A11, MATAIJ));
  PetscCall(MatXAIJSetPreallocation(A11, 1, NULL, NULL, NULL, NULL));
  PetscCall(MatSetOption(A11, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
  PetscCall(VecDuplicate(mx->pmask, &diag));
  PetscCall(VecCopy(mx->pmask, diag));
  if (mx->spring_gblock >= 0) {
    Vec one;
    PetscCall(VecDuplicate(diag, &one));
    PetscCall(VecSet(one, 1.0));
    PetscCall(BwMixedAddSpring(mx, one, diag));
    PetscCall(VecDestroy(&one));
  }
  PetscCall(MatAssemblyBegin(A11, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(A11, MAT_FINAL_ASSEMBLY));
  PetscCall(MatDiagonalSet(A11, diag, INSERT_VALUES));
  PetscCall(VecDestroy(&diag));
  blocks[0] = A00;
  blocks[1] = TD;
  blocks[2] = Dt;
  blocks[3] = A11;
  is[0]     = mx->isr;
  is[1]     = mx->isq;
  PetscCall(MatCreateNest(mx->comm, 2, is, 2, is, blocks, &nest));
  PetscCall(MatConvert(nest, MATAIJ, MAT_INITIAL_MATRIX, aij));
  PetscCall(MatDestroy(&nest));
  PetscCall(MatDestroy(&A00));
  PetscCall(MatDestroy(&Dt));
  PetscCall(MatDestroy(&A11));
  PetscCall(MatDestroy(&TD));
  PetscCall(MatDestroy(&D));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedSetUp(BwMixed mx, BwStorage storage)
{
  PetscScalar *pm;

  PetscFunctionBeginUser;
  mx->storage = storage;
  PetscCall(ISCreateStride(mx->comm, mx->nr_local, mx->kstart, 1, &mx->isr));
  PetscCall(ISCreateStride(mx->comm, mx->nq_local, mx->kstart + mx->nr_local, 1, &mx->isq));
  PetscCall(VecCreateMPI(mx->comm, mx->nq_local, mx->nq_global, &mx->pmask));
  PetscCall(VecSetBlockSize(mx->pmask, mx->nd));
  PetscCall(VecGetArray(mx->pmask, &pm));
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e];
    if (mx->qrow[b] < 0) continue;
    for (PetscInt c = 0; c < mx->nd; c++) pm[mx->qrow[b] - mx->qstart + c] = mx->model->prescribed[mx->nd * b + c] ? 1 : 0;
  }
  PetscCall(VecRestoreArray(mx->pmask, &pm));
  PetscCall(PetscLogEventBegin(BwEvents[BW_EVENT_ASSEMBLE_D], 0, 0, 0, 0));
  if (storage == BW_STORAGE_SHELL) PetscCall(BwMixedCreateDShell(mx, &mx->D));
  else PetscCall(BwMixedAssembleD(mx, PETSC_FALSE, &mx->D));
  PetscCall(PetscLogEventEnd(BwEvents[BW_EVENT_ASSEMBLE_D], 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(BwEvents[BW_EVENT_ASSEMBLE_S], 0, 0, 0, 0));
  PetscCall(BwMixedAssembleS(mx));
  PetscCall(PetscLogEventEnd(BwEvents[BW_EVENT_ASSEMBLE_S], 0, 0, 0, 0));
  if (storage == BW_STORAGE_AIJ) PetscCall(BwMixedCreateAIJ(mx, &mx->K));
  else {
    PetscCall(MatCreateShell(mx->comm, mx->nlocal, mx->nlocal, PETSC_DETERMINE, PETSC_DETERMINE, mx, &mx->K));
    PetscCall(MatShellSetOperation(mx->K, MATOP_MULT, (void (*)(void))BwKShellMult));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedSetValuesFixed(BwMixed mx, PetscBool fixed)
{
  PetscFunctionBeginUser;
  PetscCheck(!mx->S, mx->comm, PETSC_ERR_ORDER, "BwMixedSetValuesFixed before BwMixedSetUp");
  mx->values_fixed = fixed;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* New values of the operators (same pattern): S^ refilled, K told. */
static PetscErrorCode BwMixedValuesChanged(BwMixed mx)
{
  PetscFunctionBeginUser;
  mx->values_state++;
  PetscCall(BwMixedRefillS(mx));
  if (mx->storage == BW_STORAGE_AIJ) {
    /* same pattern (a tangent mixes the two rows of a portion, whose
     * columns are the same): new values into the matrix the KSPs hold */
    Mat K;
    PetscCall(BwMixedCreateAIJ(mx, &K));
    PetscCall(MatCopy(K, mx->K, SAME_NONZERO_PATTERN));
    PetscCall(MatDestroy(&K));
  } else PetscCall(BwMatValuesChanged(mx->K));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedSetSpring(BwMixed mx, PetscInt block, PetscInt dof, PetscReal stiffness)
{
  PetscInt local = block < 0 ? -1 : BwGeometryLocalBlock(mx->geom, block);

  PetscFunctionBeginUser;
  if (local >= mx->geom->nown_blocks) local = -1; /* a ghost here: its owner adds it */
  {
    PetscBool bad = local >= 0 && (mx->qrow[local] < 0 || mx->model->prescribed[mx->nd * local + dof]) ? PETSC_TRUE : PETSC_FALSE, any;
    PetscCallMPI(MPIU_Allreduce(&bad, &any, 1, MPIU_BOOL, MPI_LOR, mx->comm));
    PetscCheck(!any, mx->comm, PETSC_ERR_ARG_WRONG, "a spring needs a free dof");
  }
  if (block == mx->spring_gblock && dof == mx->spring_dof && stiffness == mx->spring) PetscFunctionReturn(PETSC_SUCCESS);
  mx->spring_gblock = block < 0 ? -1 : block;
  mx->spring_block  = local;
  mx->spring_dof    = block < 0 ? 0 : dof;
  mx->spring        = block < 0 ? 0 : stiffness;
  PetscCall(BwMixedValuesChanged(mx));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedSetTangents(BwMixed mx, const PetscReal tangent[])
{
  const PetscInt ns = mx->ns;
  PetscInt       n  = ns * ns * (mx->nr_local / ns); /* ns x ns per owned portion */

  PetscFunctionBeginUser;
  if (!mx->tangent_changed) PetscCall(PetscCalloc2(mx->nown_interfaces + 1, &mx->tangent_changed, mx->nkg + 1, &mx->kg_changed));
  if (tangent) {
    PetscBool first = mx->tangent ? PETSC_FALSE : PETSC_TRUE;
    if (!mx->tangent) PetscCall(PetscMalloc2(n + 1, &mx->tangent, n + 1, &mx->scaled_tangent));
    /* which interfaces' tangents changed since the last refill (which
     * clears the flags): a Newton iteration changes those of the portions
     * that flow, and the refill redoes only what they touch */
    for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
      PetscInt k = mx->own_interfaces[e], lp = BwLocalPortion(mx, k), np = BwPortionsCount(&mx->portions, k);
      if (first || memcmp(mx->tangent + ns * ns * lp, tangent + ns * ns * lp, sizeof(PetscReal) * ns * ns * np)) mx->tangent_changed[e] = PETSC_TRUE;
    }
    {
      /* nothing changed on any rank (IMPL-EX steps, a step's first
       * iteration on the tangents it converged with): the matrix and its
       * factor stand */
      PetscBool any = PETSC_FALSE, all;
      for (PetscInt e = 0; e < mx->nown_interfaces && !any; e++) any = mx->tangent_changed[e];
      PetscCallMPI(MPIU_Allreduce(&any, &all, 1, MPIU_BOOL, MPI_LOR, mx->comm));
      if (!all) PetscFunctionReturn(PETSC_SUCCESS);
    }
    PetscCall(PetscArraycpy(mx->tangent, tangent, n));
    /* T = C^-1/2 C_t C^-1/2 once here: every product with K applies it */
    for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
      PetscInt  k = mx->own_interfaces[e], lp = BwLocalPortion(mx, k), np = BwPortionsCount(&mx->portions, k);
      PetscReal st = 1 / PetscSqrtReal(mx->model->kt[k]), sn = 1 / PetscSqrtReal(mx->model->kn[k]), sc[BW_MAX_NS];
      if (!mx->tangent_changed[e]) continue;
      for (PetscInt a = 0; a < ns; a++) sc[a] = a == 1 ? sn : st;
      for (PetscInt p = 0; p < np; p++) {
        const PetscReal *c = mx->tangent + ns * ns * (lp + p);
        PetscReal       *t = mx->scaled_tangent + ns * ns * (lp + p);
        for (PetscInt a = 0; a < ns; a++)
          for (PetscInt b = 0; b < ns; b++) t[ns * a + b] = c[ns * a + b] * sc[a] * sc[b];
      }
    }
  } else {
    PetscCall(PetscFree2(mx->tangent, mx->scaled_tangent));
    for (PetscInt e = 0; e < mx->nown_interfaces; e++) mx->tangent_changed[e] = PETSC_TRUE;
  }
  PetscCall(BwMixedValuesChanged(mx));
  PetscFunctionReturn(PETSC_SUCCESS);
}
