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
 * by shape. Products cost the same flops as with the assembled matrix:
 *   y = D^ q:    dG = W_k q_k; j = E_p dG (kernel); y_p = sqrt(A_p) (skt j_t, skn j_n)
 *   q = D^T y:   (T, N, M) = H (y_p (skt, skn) / sqrt(A_p)) (kernel); q_k += W_k^T (T, N, M)
 * The assembled rows come from the same kernels (bw_kernel_operator), so
 * D^ is defined once. Dofs of blocks owned by other ranks come through one
 * scatter (forward for D^ q, reverse with addition for D^T y); none on one
 * rank. */
#include "system/mixed_impl.h"
#include "util/compat.h"
#include "blockwall/kernels.h"

typedef struct {
  PetscInt   m, n;    /* most portions of an interface; owned interfaces */
  PetscReal *w;       /* 18 per interface: W_k row-major (t, n, phi) x 6 */
  PetscInt  *col;     /* 2 per interface: first dof of block i, j: local q index, nq_local + ghost index, or -1 */
  PetscReal *skt, *skn; /* per interface: sqrt(kt), sqrt(kn) */
  PetscInt  *first, *np, *row; /* per interface: its first portion in the table, its portions, its first row of y */
  const BwPortions *portions;
  PetscReal *work;    /* 2m */
  PetscInt   nq_local;
  Vec        ghost;   /* dofs of other ranks' blocks, sequential */
  VecScatter scatter; /* q vector -> ghost */
} BwDShell;

static PetscErrorCode BwDShellDestroy(Mat A)
{
  BwDShell *ctx;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &ctx));
  PetscCall(PetscFree4(ctx->w, ctx->col, ctx->skt, ctx->skn));
  PetscCall(PetscFree4(ctx->first, ctx->np, ctx->row, ctx->work));
  PetscCall(VecDestroy(&ctx->ghost));
  PetscCall(VecScatterDestroy(&ctx->scatter));
  PetscCall(PetscFree(ctx));
  PetscFunctionReturn(PETSC_SUCCESS);
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
  for (PetscInt e = 0; e < ctx->n; e++) {
    const PetscReal *w  = ctx->w + 18 * e, *sqa = ctx->portions->sqrt_area + ctx->first[e];
    const PetscReal *xi = ctx->portions->xi + ctx->first[e], *eta = ctx->portions->eta + ctx->first[e];
    PetscReal        dg[3] = {0, 0, 0};
    PetscScalar     *ye    = yy + ctx->row[e];
    int              status;
    for (PetscInt s = 0; s < 2; s++) {
      PetscInt           c = ctx->col[2 * e + s];
      const PetscScalar *x;
      if (c < 0) continue;
      x = c < ctx->nq_local ? ql + c : qg + (c - ctx->nq_local);
      for (PetscInt f = 0; f < 3; f++) {
        PetscReal v = PetscRealPart(x[f]);
        dg[0] += w[3 * s + f] * v;
        dg[1] += w[6 + 3 * s + f] * v;
        dg[2] += w[12 + 3 * s + f] * v;
      }
    }
    bw_kernel_jumps(2, (int)ctx->np[e], xi, eta, dg, ye, &status);
    for (PetscInt p = 0; p < ctx->np[e]; p++) {
      ye[2 * p] *= sqa[p] * ctx->skt[e];
      ye[2 * p + 1] *= sqa[p] * ctx->skn[e];
    }
  }
  PetscCall(VecRestoreArray(y, &yy));
  PetscCall(VecRestoreArrayRead(q, &ql));
  if (ctx->scatter) PetscCall(VecRestoreArrayRead(ctx->ghost, &qg));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwDShellMultTransposeAdd(Mat A, Vec y, Vec q0, Vec q)
{
  BwDShell          *ctx;
  const PetscScalar *yy;
  PetscScalar       *ql, *qg = NULL;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &ctx));
  if (q0 != q) PetscCall(VecCopy(q0, q));
  if (ctx->scatter) {
    PetscCall(VecZeroEntries(ctx->ghost));
    PetscCall(VecGetArray(ctx->ghost, &qg));
  }
  PetscCall(VecGetArray(q, &ql));
  PetscCall(VecGetArrayRead(y, &yy));
  for (PetscInt e = 0; e < ctx->n; e++) {
    const PetscReal   *w  = ctx->w + 18 * e, *isqa = ctx->portions->inv_sqrt_area + ctx->first[e];
    const PetscReal   *area = ctx->portions->area + ctx->first[e], *xi = ctx->portions->xi + ctx->first[e], *eta = ctx->portions->eta + ctx->first[e];
    const PetscScalar *ye = yy + ctx->row[e];
    PetscReal          f3[3];
    int                status;
    for (PetscInt p = 0; p < ctx->np[e]; p++) {
      ctx->work[2 * p]     = ctx->skt[e] * isqa[p] * PetscRealPart(ye[2 * p]);
      ctx->work[2 * p + 1] = ctx->skn[e] * isqa[p] * PetscRealPart(ye[2 * p + 1]);
    }
    bw_kernel_resultants(2, (int)ctx->np[e], area, xi, eta, ctx->work, f3, &status);
    for (PetscInt s = 0; s < 2; s++) {
      PetscInt     c = ctx->col[2 * e + s];
      PetscScalar *x;
      if (c < 0) continue;
      x = c < ctx->nq_local ? ql + c : qg + (c - ctx->nq_local);
      for (PetscInt f = 0; f < 3; f++) x[f] += w[3 * s + f] * f3[0] + w[6 + 3 * s + f] * f3[1] + w[12 + 3 * s + f] * f3[2];
    }
  }
  PetscCall(VecRestoreArrayRead(y, &yy));
  PetscCall(VecRestoreArray(q, &ql));
  if (ctx->scatter) {
    PetscCall(VecRestoreArray(ctx->ghost, &qg));
    PetscCall(VecScatterBegin(ctx->scatter, ctx->ghost, q, ADD_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterEnd(ctx->scatter, ctx->ghost, q, ADD_VALUES, SCATTER_REVERSE));
  }
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
static PetscErrorCode BwMixedScaledCompatibility(BwMixed mx, PetscInt k, PetscReal w[18])
{
  PetscReal rb[18];

  PetscFunctionBeginUser;
  PetscCall(BwMixedCompatibility(mx, k, rb));
  for (PetscInt c = 0; c < 6; c++) {
    PetscInt  b = mx->geom->pair[2 * k + c / 3];
    PetscReal s = mx->model->prescribed[3 * b + c % 3] ? 0 : mx->qscale[3 * b + c % 3];
    for (PetscInt r = 0; r < 3; r++) w[6 * r + c] = rb[6 * r + c] * s;
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
  PetscCall(PetscMalloc4(18 * ctx->n + 1, &ctx->w, 2 * ctx->n + 1, &ctx->col, ctx->n + 1, &ctx->skt, ctx->n + 1, &ctx->skn));
  PetscCall(PetscMalloc4(ctx->n + 1, &ctx->first, ctx->n + 1, &ctx->np, ctx->n + 1, &ctx->row, 2 * mx->portions.maxnp, &ctx->work));
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
    PetscCall(BwMixedScaledCompatibility(mx, k, ctx->w + 18 * e));
    for (PetscInt s = 0; s < 2; s++) {
      PetscInt r = mx->qrow[geom->pair[2 * k + s]], gi;
      if (r < 0) ctx->col[2 * e + s] = -1;
      else if (r >= mx->qstart && r < qend) ctx->col[2 * e + s] = r - mx->qstart;
      else {
        PetscCall(PetscFindInt(r, nghost, ghosts, &gi));
        ctx->col[2 * e + s] = mx->nq_local + 3 * gi;
      }
    }
    BwMixedStiffnessRoots(mx, k, &ctx->skt[e], &ctx->skn[e]);
    ctx->first[e] = BwPortionsFirst(&mx->portions, k);
    ctx->np[e]    = BwPortionsCount(&mx->portions, k);
    ctx->row[e]   = e ? ctx->row[e - 1] + 2 * ctx->np[e - 1] : 0;
  }
  {
    /* the scatter is collective: every rank creates one if any rank needs it */
    PetscInt any = nghost, anyg;
    PetscCallMPI(MPIU_Allreduce(&any, &anyg, 1, MPIU_INT, MPI_MAX, mx->comm));
    if (anyg) {
      IS  is;
      Vec q;
      PetscCall(VecCreateSeq(PETSC_COMM_SELF, 3 * nghost, &ctx->ghost));
      for (PetscInt g = 0; g < nghost; g++) ghosts[g] /= 3; /* a block's first q row is 3 x its q index */
      PetscCall(ISCreateBlock(PETSC_COMM_SELF, 3, nghost, ghosts, PETSC_COPY_VALUES, &is));
      PetscCall(VecCreateMPIWithArray(mx->comm, 1, mx->nq_local, mx->nq_global, NULL, &q));
      PetscCall(VecScatterCreate(q, is, ctx->ghost, NULL, &ctx->scatter));
      PetscCall(VecDestroy(&q));
      PetscCall(ISDestroy(&is));
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

/* T = C^-1/2 C_t C^-1/2 of portion p of owned interface e (row-major 2x2). */
static inline void BwScaledTangent(BwMixed mx, PetscInt e, PetscInt p, PetscReal T[4])
{
  const PetscReal *t = mx->scaled_tangent + 4 * (mx->m * e + p);

  T[0] = t[0];
  T[1] = t[1];
  T[2] = t[2];
  T[3] = t[3];
}

PetscErrorCode BwMixedApplyTangent(BwMixed mx, Vec yr)
{
  PetscScalar *y;

  PetscFunctionBeginUser;
  if (!mx->tangent) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(VecGetArray(yr, &y));
  for (PetscInt e = 0; e < mx->nown_interfaces; e++)
    for (PetscInt p = 0; p < mx->m; p++) {
      PetscScalar *v = y + 2 * (mx->m * e + p), t0 = v[0], t1 = v[1];
      PetscReal    T[4];
      BwScaledTangent(mx, e, p, T);
      v[0] = T[0] * t0 + T[1] * t1;
      v[1] = T[2] * t0 + T[3] * t1;
    }
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

/* An array PETSc uses in place, freed with the object. */
static PetscErrorCode BwComposeArray(PetscObject obj, const char name[], void *array)
{
  PetscContainer c;

  PetscFunctionBeginUser;
  PetscCall(PetscContainerCreate(PetscObjectComm(obj), &c));
  PetscCall(PetscContainerSetPointer(c, array));
  PetscCall(BwContainerFreeWithIt(c));
  PetscCall(PetscObjectCompose(obj, name, (PetscObject)c));
  PetscCall(PetscContainerDestroy(&c));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The matrix from local CSR rows (global column indices, sorted), used in
 * place: on one rank as they are, on more split into the diagonal part
 * (local column indices) and the off-diagonal part (global), the layout
 * MPIAIJ keeps. PETSc does not copy them; they are freed with the matrix. */
PetscErrorCode BwMatFromCSR(BwMixed mx, PetscInt m, PetscInt n, PetscInt M, PetscInt N, const char prefix[], PetscInt *ia, PetscInt *ja, PetscReal *va, Mat *A, BwCSRValues *vals)
{
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(mx->comm, &size));
  if (size == 1) {
    PetscCall(MatCreateSeqAIJWithArrays(mx->comm, m, n, ia, ja, va, A));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRi", ia));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRj", ja));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRv", va));
    if (vals) {
      vals->di = ia;
      vals->dv = va;
      vals->oi = NULL;
      vals->ov = NULL;
    }
  } else {
    PetscInt   cstart, *di, *dj, *oi, *oj, nd = 0, no = 0;
    PetscReal *dv, *ov;
    PetscCallMPI(MPI_Scan(&n, &cstart, 1, MPIU_INT, MPI_SUM, mx->comm));
    cstart -= n;
    for (PetscInt e = 0; e < ia[m]; e++) {
      if (ja[e] >= cstart && ja[e] < cstart + n) nd++;
      else no++;
    }
    PetscCall(PetscMalloc1(m + 1, &di));
    PetscCall(PetscMalloc1(nd + 1, &dj));
    PetscCall(PetscMalloc1(nd + 1, &dv));
    PetscCall(PetscMalloc1(m + 1, &oi));
    PetscCall(PetscMalloc1(no + 1, &oj));
    PetscCall(PetscMalloc1(no + 1, &ov));
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
    /* the matrix uses the arrays in place; they are freed with it */
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRdi", di));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRdj", dj));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRdv", dv));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRoi", oi));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRoj", oj));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRov", ov));
    if (vals) {
      vals->di = di;
      vals->dv = dv;
      vals->oi = oi;
      vals->ov = ov;
    }
  }
  PetscCall(MatSetOptionsPrefix(*A, prefix));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedAssembleD(BwMixed mx, PetscBool tangent, Mat *D)
{
  BwGeometry geom = mx->geom;
  PetscInt   m2 = 2 * mx->m, *ia, *ja, n = 0, cols[6];
  PetscReal *va, *d, w[18];

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(mx->nr_local + 1, &ia));
  ia[0] = 0;
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
    PetscInt k = mx->own_interfaces[e], nf = 0;
    for (PetscInt s = 0; s < 2; s++) nf += mx->qrow[geom->pair[2 * k + s]] >= 0 ? 3 : 0;
    for (PetscInt p = 0; p < m2; p++, n++) ia[n + 1] = ia[n] + nf;
  }
  PetscCall(PetscMalloc1(ia[mx->nr_local] + 1, &ja));
  PetscCall(PetscMalloc1(ia[mx->nr_local] + 1, &va));
  PetscCall(PetscMalloc1(6 * m2, &d));
  n = 0;
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
    PetscInt         k = mx->own_interfaces[e], nc = 0;
    const PetscReal *area, *xi, *eta;
    PetscInt         np = BwMixedPortions(mx, k, &area, &xi, &eta, NULL);
    int              status;
    PetscCall(BwMixedScaledCompatibility(mx, k, w));
    bw_kernel_operator(2, (int)np, area, xi, eta, mx->model->kt[k], mx->model->kn[k], w, d, &status);
    PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "kernel failed on interface %" PetscInt_FMT, k);
    if (tangent && mx->tangent)
      for (PetscInt p = 0; p < mx->m; p++) {
        PetscReal T[4], *rt = d + 6 * (2 * p), *rn = rt + 6;
        BwScaledTangent(mx, e, p, T);
        for (PetscInt c = 0; c < 6; c++) {
          PetscReal t0 = rt[c], t1 = rn[c];
          rt[c] = T[0] * t0 + T[1] * t1;
          rn[c] = T[2] * t0 + T[3] * t1;
        }
      }
    for (PetscInt s = 0; s < 2; s++) {
      PetscInt r = mx->qrow[geom->pair[2 * k + s]];
      if (r >= 0)
        for (PetscInt f = 0; f < 3; f++) cols[nc++] = 3 * s + f;
    }
    for (PetscInt p = 0; p < m2; p++, n++) {
      PetscInt at0 = ia[n];
      for (PetscInt c = 0; c < nc; c++) {
        PetscInt blk = geom->pair[2 * k + cols[c] / 3];
        ja[at0 + c]  = mx->qrow[blk] + cols[c] % 3;
        va[at0 + c]  = d[6 * p + cols[c]];
      }
      BwSortRow(nc, ja + at0, va + at0);
    }
  }
  PetscCall(PetscFree(d));
  PetscCall(BwMatFromCSR(mx, mx->nr_local, mx->nq_local, mx->nr_global, mx->nq_global, "mixed_D_", ia, ja, va, D, NULL));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* y_q += spring x_q at the spring's dof (on the rank that owns it). */
static PetscErrorCode BwMixedAddSpring(BwMixed mx, Vec xq, Vec yq)
{
  PetscInt row = mx->qrow[mx->spring_block];

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
  if (mx->spring_block >= 0) PetscCall(BwMixedAddSpring(mx, xq, yq));
  PetscCall(MatMultTransposeAdd(mx->D, xr, yq, yq));
  PetscCall(VecRestoreSubVector(y, mx->isq, &yq));
  PetscCall(VecRestoreSubVector(y, mx->isr, &yr));
  PetscCall(VecRestoreSubVector(x, mx->isq, &xq));
  PetscCall(VecRestoreSubVector(x, mx->isr, &xr));
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
  if (mx->spring_block >= 0) {
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
  PetscCall(VecSetBlockSize(mx->pmask, 3));
  PetscCall(VecGetArray(mx->pmask, &pm));
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e];
    if (mx->qrow[b] < 0) continue;
    for (PetscInt c = 0; c < 3; c++) pm[mx->qrow[b] - mx->qstart + c] = mx->model->prescribed[3 * b + c] ? 1 : 0;
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
  PetscFunctionBeginUser;
  PetscCheck(block < 0 || (mx->qrow[block] >= 0 && !mx->model->prescribed[3 * block + dof]), mx->comm, PETSC_ERR_ARG_WRONG, "a spring needs a free dof");
  if (block == mx->spring_block && dof == mx->spring_dof && stiffness == mx->spring) PetscFunctionReturn(PETSC_SUCCESS);
  mx->spring_block = block < 0 ? -1 : block;
  mx->spring_dof   = block < 0 ? 0 : dof;
  mx->spring       = block < 0 ? 0 : stiffness;
  PetscCall(BwMixedValuesChanged(mx));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedSetTangents(BwMixed mx, const PetscReal tangent[])
{
  PetscInt n = 4 * mx->m * mx->nown_interfaces;

  PetscFunctionBeginUser;
  if (tangent) {
    if (!mx->tangent) PetscCall(PetscMalloc2(n + 1, &mx->tangent, n + 1, &mx->scaled_tangent));
    PetscCall(PetscArraycpy(mx->tangent, tangent, n));
    /* T = C^-1/2 C_t C^-1/2 once here: every product with K applies it */
    for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
      PetscInt  k  = mx->own_interfaces[e];
      PetscReal st = 1 / PetscSqrtReal(mx->model->kt[k]), sn = 1 / PetscSqrtReal(mx->model->kn[k]);
      for (PetscInt p = 0; p < mx->m; p++) {
        const PetscReal *c = mx->tangent + 4 * (mx->m * e + p);
        PetscReal       *t = mx->scaled_tangent + 4 * (mx->m * e + p);
        t[0]               = c[0] * st * st;
        t[1]               = c[1] * st * sn;
        t[2]               = c[2] * sn * st;
        t[3]               = c[3] * sn * sn;
      }
    }
  } else PetscCall(PetscFree2(mx->tangent, mx->scaled_tangent));
  PetscCall(BwMixedValuesChanged(mx));
  PetscFunctionReturn(PETSC_SUCCESS);
}
