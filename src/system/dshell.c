/* D^ as a shell matrix: the same operator as the assembled D^, stored by
 * its structure instead of its entries.
 *
 * For interface k with lever/rotation operator R B (3 x 6), dof scales
 * s = diag(S)^-1/2 of its two blocks and portions x_p, A_p = s l/m:
 *   shear row p:   D^_p = sqrt(A_p kt) (R B)_t  diag(s)
 *   normal row p:  D^_p = sqrt(A_p kn) ((R B)_n + x_p (R B)_phi) diag(s)
 * so D^_k = U_k W_k with W_k = R B diag(s) (3 x 6, 18 numbers) and U_k fixed
 * by (kt, kn, l, m). Storing W_k, the six column indices and three scalars
 * costs ~200 bytes per interface instead of 2m x 6 entries (2.3 KB at
 * m = 16). Products cost the same flops as with the assembled matrix:
 *   y = D^ q:    w = W_k q_k, then y_p = a_t w_t, y_p' = a_n (w_n + x_p w_phi)
 *   q = D^T y:   (T, N, M) = (a_t sum y_p, a_n sum y_p', a_n sum x_p y_p'),
 *                q_k += W_k^T (T, N, M)
 * Dofs of blocks owned by other ranks come through one scatter (forward for
 * D^ q, reverse with addition for D^T y); none on one rank. */
#include "system/mixed.h"
#include "util/compat.h"
#include "blockwall/kernels.h"

typedef struct {
  PetscInt   m, n;      /* portions; owned interfaces */
  PetscReal *w;         /* 18 per interface: W_k row-major (t, n, phi) x 6 */
  PetscInt  *col;       /* 6 per interface: local dof index, ghost index nq_local + g, or -1 */
  PetscReal *at, *an, *len;
  PetscInt   nq_local;
  Vec        ghost;     /* dofs of other ranks' blocks, sequential */
  VecScatter scatter;   /* q vector -> ghost */
} BwDShell;

static PetscErrorCode BwDShellDestroy(Mat A)
{
  BwDShell *ctx;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &ctx));
  PetscCall(PetscFree4(ctx->w, ctx->col, ctx->at, ctx->an));
  PetscCall(PetscFree(ctx->len));
  PetscCall(VecDestroy(&ctx->ghost));
  PetscCall(VecScatterDestroy(&ctx->scatter));
  PetscCall(PetscFree(ctx));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static inline PetscReal BwPortion(PetscReal l, PetscInt m, PetscInt p) { return l * (((PetscReal)p + 0.5) / (PetscReal)m - 0.5); }

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
    const PetscReal *w = ctx->w + 18 * e;
    const PetscInt  *c = ctx->col + 6 * e;
    PetscReal        v[3] = {0, 0, 0};
    PetscScalar     *ye   = yy + 2 * ctx->m * e;
    for (PetscInt f = 0; f < 6; f++) {
      PetscReal x;
      if (c[f] < 0) continue;
      x = PetscRealPart(c[f] < ctx->nq_local ? ql[c[f]] : qg[c[f] - ctx->nq_local]);
      v[0] += w[f] * x;
      v[1] += w[6 + f] * x;
      v[2] += w[12 + f] * x;
    }
    for (PetscInt p = 0; p < ctx->m; p++) {
      ye[p]          = ctx->at[e] * v[0];
      ye[ctx->m + p] = ctx->an[e] * (v[1] + BwPortion(ctx->len[e], ctx->m, p) * v[2]);
    }
  }
  PetscCall(VecRestoreArray(y, &yy));
  PetscCall(VecRestoreArrayRead(q, &ql));
  if (ctx->scatter) PetscCall(VecRestoreArrayRead(ctx->ghost, &qg));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwDShellMultTranspose(Mat A, Vec y, Vec q)
{
  BwDShell          *ctx;
  const PetscScalar *yy;
  PetscScalar       *ql, *qg = NULL;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &ctx));
  PetscCall(VecZeroEntries(q));
  if (ctx->scatter) {
    PetscCall(VecZeroEntries(ctx->ghost));
    PetscCall(VecGetArray(ctx->ghost, &qg));
  }
  PetscCall(VecGetArray(q, &ql));
  PetscCall(VecGetArrayRead(y, &yy));
  for (PetscInt e = 0; e < ctx->n; e++) {
    const PetscReal   *w  = ctx->w + 18 * e;
    const PetscInt    *c  = ctx->col + 6 * e;
    const PetscScalar *ye = yy + 2 * ctx->m * e;
    PetscReal          f3[3] = {0, 0, 0};
    for (PetscInt p = 0; p < ctx->m; p++) {
      f3[0] += PetscRealPart(ye[p]);
      f3[1] += PetscRealPart(ye[ctx->m + p]);
      f3[2] += BwPortion(ctx->len[e], ctx->m, p) * PetscRealPart(ye[ctx->m + p]);
    }
    f3[0] *= ctx->at[e];
    f3[1] *= ctx->an[e];
    f3[2] *= ctx->an[e];
    for (PetscInt f = 0; f < 6; f++) {
      PetscReal v;
      if (c[f] < 0) continue;
      v = w[f] * f3[0] + w[6 + f] * f3[1] + w[12 + f] * f3[2];
      if (c[f] < ctx->nq_local) ql[c[f]] += v;
      else qg[c[f] - ctx->nq_local] += v;
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

PetscErrorCode BwMixedCreateDShell(BwMixed mx, PetscScalar bb[], Mat *D)
{
  BwGeometry geom = mx->geom;
  BwDShell  *ctx;
  PetscInt   nghost = 0, *ghosts, m = mx->m;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&ctx));
  ctx->m        = m;
  ctx->n        = mx->nown_interfaces;
  ctx->nq_local = mx->nq_local;
  PetscCall(PetscMalloc4(18 * ctx->n, &ctx->w, 6 * ctx->n, &ctx->col, ctx->n, &ctx->at, ctx->n, &ctx->an));
  PetscCall(PetscMalloc1(ctx->n, &ctx->len));
  /* columns owned elsewhere, sorted and unique: the ghost layout */
  PetscCall(PetscMalloc1(6 * ctx->n + 1, &ghosts));
  for (PetscInt e = 0; e < ctx->n; e++) {
    PetscInt k = mx->own_interfaces[e];
    for (PetscInt c = 0; c < 6; c++) {
      PetscInt col = mx->sdof[3 * geom->pair[2 * k + c / 3] + c % 3];
      if (col >= 0 && (col < mx->qstart || col >= mx->qstart + mx->nq_local)) ghosts[nghost++] = col;
    }
  }
  PetscCall(PetscSortRemoveDupsInt(&nghost, ghosts));
  for (PetscInt e = 0; e < ctx->n; e++) {
    PetscInt         k = mx->own_interfaces[e], i = geom->pair[2 * k], j = geom->pair[2 * k + 1];
    PetscReal        rb[18], area = geom->depth * geom->length[k];
    const PetscReal *sc[2];
    int              status;

    bw_interface_compatibility(&geom->centroid[2 * i], &geom->centroid[2 * j], &geom->center[2 * k], geom->angle[k], rb, &status);
    PetscCall(BwMixedQScale(mx, i, &sc[0]));
    PetscCall(BwMixedQScale(mx, j, &sc[1]));
    for (PetscInt c = 0; c < 6; c++) {
      PetscReal sca = sc[c / 3][c % 3];
      PetscInt  col = mx->sdof[3 * geom->pair[2 * k + c / 3] + c % 3], gi;
      for (PetscInt r = 0; r < 3; r++) ctx->w[18 * e + 6 * r + c] = rb[6 * r + c] * sca;
      if (col < 0) ctx->col[6 * e + c] = -1;
      else if (col >= mx->qstart && col < mx->qstart + mx->nq_local) ctx->col[6 * e + c] = col - mx->qstart;
      else {
        PetscCall(PetscFindInt(col, nghost, ghosts, &gi));
        ctx->col[6 * e + c] = mx->nq_local + gi;
      }
    }
    ctx->at[e]  = PetscSqrtReal(area / m * mx->model->kt[k]);
    ctx->an[e]  = PetscSqrtReal(area / m * mx->model->kn[k]);
    ctx->len[e] = geom->length[k];
    /* stress rows of the right-hand side: prescribed values lifted */
    {
      PetscReal v[3] = {0, 0, 0};
      for (PetscInt c = 0; c < 6; c++) {
        PetscInt blk = geom->pair[2 * k + c / 3];
        if (mx->sdof[3 * blk + c % 3] >= 0) continue;
        for (PetscInt r = 0; r < 3; r++) v[r] += rb[6 * r + c] * mx->model->value[3 * blk + c % 3];
      }
      for (PetscInt p = 0; p < m; p++) {
        bb[mx->stress[k] - mx->rstart + p]     = -ctx->at[e] * v[0];
        bb[mx->stress[k] - mx->rstart + m + p] = -ctx->an[e] * (v[1] + BwPortion(geom->length[k], m, p) * v[2]);
      }
    }
  }
  {
    /* the scatter is collective: every rank creates one if any rank needs it */
    PetscInt any = nghost, anyg;
    PetscCallMPI(MPIU_Allreduce(&any, &anyg, 1, MPIU_INT, MPI_MAX, mx->comm));
    if (anyg) {
      IS  is;
      Vec q;
      PetscCall(VecCreateSeq(PETSC_COMM_SELF, nghost, &ctx->ghost));
      PetscCall(ISCreateGeneral(PETSC_COMM_SELF, nghost, ghosts, PETSC_COPY_VALUES, &is));
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
  PetscCall(MatShellSetOperation(*D, MATOP_DESTROY, (void (*)(void))BwDShellDestroy));
  PetscFunctionReturn(PETSC_SUCCESS);
}
