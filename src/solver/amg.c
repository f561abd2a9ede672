/* The preconditioner of the iterative Schur solve (CG on S^) in 3D:
 * smoothed aggregation (GAMG) on the blocks of ordinary size, with the few
 * blocks that touch very many others ("long" blocks: a top beam over a
 * whole course) eliminated exactly by a change of basis.
 *
 * Why (measured with bench/schur3d.py, a 3D running-bond wall of N x N units bending out
 * of its plane): CG + GAMG with the rigid modes alone took 93-172 CG
 * iterations per Richardson step at 1e5 blocks, growing like N^0.4. Three
 * things made it grow:
 *  - the near-null space: a thin wall bends as a plate, and pieces of
 *    rigid motion per aggregate represent a plate's bending only to first
 *    order; the three constant-curvature modes of the wall's plane
 *    (BwMixedSetNearNullSpace) carry it to second order;
 *  - the aggregation graph: with every coupling kept (threshold -1),
 *    aggregates follow the weak ones as well as the strong; 0.05 of the
 *    scaled diagonal (0.02-0.1 were alike) fixed it;
 *  - the top beam: one block joined to all N units of the top course. In
 *    the squared graph GAMG aggregates on, the whole course is one clique,
 *    so one aggregate swallows it and the top edge's bending has no coarse
 *    representation. Without the beam (the same wall, the load on the top
 *    course), 25 -> 29 iterations from 1e4 to 1e5 blocks; with it, 28 -> 95.
 *
 * The elimination: with w the ordinary dofs and l the long blocks' (nd
 * each),
 *
 *   S^ = [ S_ww  S_wl ]   Z = S_ww^{-1} S_wl (CG + the same GAMG, to 1e-6),
 *        [ S_lw  S_ll ]   T = [ I  -Z ]    T^T S^ T = [ S_ww  E ]
 *                             [ 0   I ]               [ E^T   C ]
 *
 *   E = S_wl - S_ww Z (the residual of Z, small), C = [-Z; I]^T S^ [-Z; I]
 *   (nl x nl, dense, the same on every rank), and the preconditioner
 *
 *   M^{-1} = T diag(GAMG(S_ww), C^{-1}) T^T,
 *
 * symmetric and positive definite for any Z: the long blocks' motions,
 * extended into the wall by the wall's own response, are one exact coarse
 * space of their own, and GAMG sees a wall whose top course is held by a
 * beam that does not move (28 CG iterations at 1e5 blocks, 23 at 1e4;
 * Z to 1e-4 gave 29). Its cost: nl solves of S_ww at each set-up (13 CG
 * iterations each), nl vectors of S^'s size, a copy of S_ww.
 *
 * 2D keeps plain GAMG on S^ with the rigid modes: its inner solves took
 * 9-17 iterations at 1e5 blocks (bench/results.md), and its bending is
 * in-plane elasticity, not a plate's. */
#include "solver/solver_impl.h"
#include "util/compat.h"

/* A block with more neighbours than this is long: an ordinary unit of a
 * masonry wall touches up to ~10 others (3D running bond: 6 to 8), a beam
 * over n units n + 2. */
#define BW_LONG_NEIGHBOURS 32
/* At most this many long blocks are eliminated (those with the most
 * neighbours): each costs nd vectors of S^'s size and nd solves per
 * set-up. */
#define BW_LONG_MAX 4
/* dofs per block in 3D */
#define BW_LONG_ND 6
/* Relative residual of the solves for Z. Measured on bench/large_wall3d.yaml
 * at 100 x 100 units (2026-11-27): 1e-6 and 1e-4 give 8-17 and 11-17 CG
 * iterations per Richardson step (1e-4 sets up in 1.75 s against 3.0 s),
 * but 3e-4 took 72 iterations in its first solve and 1e-3 did not finish in
 * 2 minutes: a cliff 3x from 1e-4, so 1e-6 keeps two decades from it. */
#define BW_LONG_ZTOL 1e-6
/* GAMG's graph threshold in 3D (relative to the scaled diagonal). */
#define BW_GAMG_THRESHOLD_3D 0.05

typedef struct {
  Mat         S;
  PetscInt    nl;         /* long dofs (nd per long block), on all ranks */
  PetscInt    lglobal[BW_LONG_MAX * BW_LONG_ND]; /* their rows of S^ */
  IS          isw, isl;   /* ordinary and long rows of S^ this rank owns */
  Mat         Sww, Swl, Sll;
  KSP         kz;         /* the solves for Z, prefix <schur>long_ */
  PC          amg;        /* GAMG on S_ww, prefix <schur> */
  Vec        *Z, rw, yw, el, cl, sw;
  VecScatter  tow, toall; /* S^-vector -> w part; -> every long dof on every rank */
  Vec         lall;       /* the long dofs, sequential, nl */
  Mat         C;          /* sequential dense, LU-factored */
  Vec         t, x;       /* sequential, nl */
  PetscBool   symmetric;
} BwLongPC;

/* The long blocks of S^ (block size nd): the first rows of at most
 * BW_LONG_MAX blocks with more than BW_LONG_NEIGHBOURS neighbours, the
 * most connected first, the same list on every rank. */
static PetscErrorCode BwFindLongBlocks(Mat S, PetscInt nd, PetscInt *nlong, PetscInt first[])
{
  PetscInt    r0, r1, cand[2 * BW_LONG_MAX], *all;
  PetscMPIInt size;
  MPI_Comm    comm;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)S, &comm));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  for (PetscInt k = 0; k < BW_LONG_MAX; k++) cand[2 * k] = cand[2 * k + 1] = -1; /* (neighbours, row) */
  PetscCall(MatGetOwnershipRange(S, &r0, &r1));
  for (PetscInt row = r0; row < r1; row += nd) {
    const PetscInt *cols;
    PetscInt        ncols, nbr = 0, last = -1;
    PetscCall(MatGetRow(S, row, &ncols, &cols, NULL));
    /* the columns are sorted: count the distinct blocks, itself excluded */
    for (PetscInt c = 0; c < ncols; c++)
      if (cols[c] / nd != last) {
        last = cols[c] / nd;
        if (last != row / nd) nbr++;
      }
    PetscCall(MatRestoreRow(S, row, &ncols, &cols, NULL));
    if (nbr <= BW_LONG_NEIGHBOURS || nbr <= cand[2 * (BW_LONG_MAX - 1)]) continue;
    {
      PetscInt k = BW_LONG_MAX - 1;
      for (; k > 0 && cand[2 * (k - 1)] < nbr; k--) {
        cand[2 * k]     = cand[2 * (k - 1)];
        cand[2 * k + 1] = cand[2 * (k - 1) + 1];
      }
      cand[2 * k]     = nbr;
      cand[2 * k + 1] = row;
    }
  }
  PetscCall(PetscMalloc1(2 * BW_LONG_MAX * size, &all));
  PetscCallMPI(MPI_Allgather(cand, 2 * BW_LONG_MAX, MPIU_INT, all, 2 * BW_LONG_MAX, MPIU_INT, comm));
  *nlong = 0;
  for (PetscInt k = 0; k < BW_LONG_MAX; k++) {
    PetscInt best = -1;
    for (PetscInt j = 0; j < BW_LONG_MAX * size; j++)
      if (all[2 * j] > 0 && (best < 0 || all[2 * j] > all[2 * best])) best = j;
    if (best < 0) break;
    first[(*nlong)++] = all[2 * best + 1];
    all[2 * best]     = -1;
  }
  PetscCall(PetscFree(all));
  /* ascending rows, for the index sets */
  PetscCall(PetscSortInt(*nlong, first));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The near-null space of S^ (rigid and bending modes) restricted to the
 * ordinary dofs, orthonormal again, on S_ww. */
static PetscErrorCode BwLongNearNullSpace(BwLongPC *ctx)
{
  MatNullSpace nsp, sub;
  PetscBool    has_const;
  PetscInt     n;
  const Vec   *v;
  Vec          w[16];

  PetscFunctionBeginUser;
  PetscCall(MatGetNearNullSpace(ctx->S, &nsp));
  if (!nsp) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(MatNullSpaceGetVecs(nsp, &has_const, &n, &v));
  PetscCheck(!has_const && n <= 16, PETSC_COMM_SELF, PETSC_ERR_PLIB, "unexpected near-null space of S^");
  for (PetscInt r = 0; r < n; r++) {
    PetscScalar dots[16];
    PetscCall(MatCreateVecs(ctx->Sww, &w[r], NULL));
    PetscCall(VecScatterBegin(ctx->tow, v[r], w[r], INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(ctx->tow, v[r], w[r], INSERT_VALUES, SCATTER_FORWARD));
    for (PetscInt pass = 0; pass < 2 && r > 0; pass++) {
      PetscCall(VecMDot(w[r], r, w, dots));
      for (PetscInt j = 0; j < r; j++) dots[j] = -dots[j];
      PetscCall(VecMAXPY(w[r], r, dots, w));
    }
    PetscCall(VecNormalize(w[r], NULL));
  }
  PetscCall(MatNullSpaceCreate(PetscObjectComm((PetscObject)ctx->S), PETSC_FALSE, n, w, &sub));
  PetscCall(MatSetNearNullSpace(ctx->Sww, sub));
  PetscCall(MatNullSpaceDestroy(&sub));
  for (PetscInt r = 0; r < n; r++) PetscCall(VecDestroy(&w[r]));
  /* S^ itself no longer needs it (9 vectors of its size in 3D) */
  PetscCall(MatSetNearNullSpace(ctx->S, NULL));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Z, C and the GAMG hierarchy for the values S^ has now (the first set-up
 * and every refill: the pattern, hence the index sets, stays). */
static PetscErrorCode BwLongPCSetUp(PC pc)
{
  BwLongPC   *ctx;
  MatReuse    reuse;
  PetscInt    l0;
  PetscScalar col[BW_LONG_MAX * BW_LONG_ND], c[BW_LONG_MAX * BW_LONG_ND * BW_LONG_MAX * BW_LONG_ND];

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &ctx));
  reuse = ctx->Sww ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX;
  PetscCall(MatCreateSubMatrix(ctx->S, ctx->isw, ctx->isw, reuse, &ctx->Sww));
  PetscCall(MatCreateSubMatrix(ctx->S, ctx->isw, ctx->isl, reuse, &ctx->Swl));
  PetscCall(MatCreateSubMatrix(ctx->S, ctx->isl, ctx->isl, reuse, &ctx->Sll));
  if (reuse == MAT_INITIAL_MATRIX) {
    Vec q;
    IS  all;
    PetscCall(MatSetOption(ctx->Sww, MAT_SYMMETRIC, ctx->symmetric));
    PetscCall(MatCreateVecs(ctx->Sww, &ctx->rw, &ctx->yw));
    PetscCall(VecDuplicate(ctx->rw, &ctx->sw));
    PetscCall(VecDuplicateVecs(ctx->rw, ctx->nl, &ctx->Z));
    PetscCall(MatCreateVecs(ctx->Sll, &ctx->el, &ctx->cl));
    PetscCall(MatCreateVecs(ctx->S, &q, NULL));
    PetscCall(VecScatterCreate(q, ctx->isw, ctx->rw, NULL, &ctx->tow));
    PetscCall(ISCreateGeneral(PETSC_COMM_SELF, ctx->nl, ctx->lglobal, PETSC_USE_POINTER, &all));
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, ctx->nl, &ctx->lall));
    PetscCall(VecScatterCreate(q, all, ctx->lall, NULL, &ctx->toall));
    PetscCall(ISDestroy(&all));
    PetscCall(VecDestroy(&q));
    PetscCall(VecDuplicate(ctx->lall, &ctx->t));
    PetscCall(VecDuplicate(ctx->lall, &ctx->x));
    PetscCall(BwLongNearNullSpace(ctx));
  }
  PetscCall(KSPSetOperators(ctx->kz, ctx->Sww, ctx->Sww));
  PetscCall(KSPSetUp(ctx->kz));
  /* column j of Z and of C, for each long dof j */
  PetscCall(MatDestroy(&ctx->C));
  PetscCall(VecGetOwnershipRange(ctx->el, &l0, NULL));
  for (PetscInt j = 0; j < ctx->nl; j++) {
    KSPConvergedReason reason;
    const PetscScalar *a;
    PetscCall(VecZeroEntries(ctx->el));
    if (j >= l0 && j < l0 + ctx->nl) PetscCall(VecSetValue(ctx->el, j, 1.0, INSERT_VALUES));
    PetscCall(VecAssemblyBegin(ctx->el));
    PetscCall(VecAssemblyEnd(ctx->el));
    PetscCall(MatMult(ctx->Swl, ctx->el, ctx->sw));
    PetscCall(KSPSolve(ctx->kz, ctx->sw, ctx->Z[j]));
    PetscCall(KSPGetConvergedReason(ctx->kz, &reason));
    if (reason < 0) { /* no C: the apply fails the Schur solve, and auto factors S^ */
      PetscCall(PCSetFailedReason(pc, PC_SUBPC_ERROR));
      PetscFunctionReturn(PETSC_SUCCESS);
    }
    /* C e_j = Z^T (S_ww Z_j - S_wl e_j) + S_ll e_j - S_lw Z_j */
    PetscCall(MatMult(ctx->Sww, ctx->Z[j], ctx->yw));
    PetscCall(VecAXPY(ctx->yw, -1.0, ctx->sw));
    PetscCall(VecMDot(ctx->yw, ctx->nl, ctx->Z, col));
    PetscCall(MatMult(ctx->Sll, ctx->el, ctx->cl));
    PetscCall(VecScale(ctx->cl, -1.0));
    PetscCall(MatMultTransposeAdd(ctx->Swl, ctx->Z[j], ctx->cl, ctx->cl));
    PetscCall(VecScale(ctx->cl, -1.0));
    /* every rank needs all of it: the long dofs are few */
    {
      VecScatter gather;
      Vec        g;
      PetscCall(VecScatterCreateToAll(ctx->cl, &gather, &g));
      PetscCall(VecScatterBegin(gather, ctx->cl, g, INSERT_VALUES, SCATTER_FORWARD));
      PetscCall(VecScatterEnd(gather, ctx->cl, g, INSERT_VALUES, SCATTER_FORWARD));
      PetscCall(VecGetArrayRead(g, &a));
      for (PetscInt i = 0; i < ctx->nl; i++) c[ctx->nl * j + i] = col[i] + a[i]; /* column-major */
      PetscCall(VecRestoreArrayRead(g, &a));
      PetscCall(VecDestroy(&g));
      PetscCall(VecScatterDestroy(&gather));
    }
  }
  PetscCall(MatCreateSeqDense(PETSC_COMM_SELF, ctx->nl, ctx->nl, NULL, &ctx->C));
  {
    PetscScalar *dense;
    PetscCall(MatDenseGetArrayWrite(ctx->C, &dense));
    PetscCall(PetscArraycpy(dense, c, ctx->nl * ctx->nl));
    PetscCall(MatDenseRestoreArrayWrite(ctx->C, &dense));
  }
  PetscCall(MatAssemblyBegin(ctx->C, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(ctx->C, MAT_FINAL_ASSEMBLY));
  {
    MatFactorInfo info;
    PetscCall(MatFactorInfoInitialize(&info));
    PetscCall(MatLUFactor(ctx->C, NULL, NULL, &info));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* y = T diag(GAMG(S_ww), C^{-1}) T^T r */
static PetscErrorCode BwLongPCApply(PC pc, Vec r, Vec y)
{
  BwLongPC          *ctx;
  PetscScalar        dots[BW_LONG_MAX * BW_LONG_ND];
  const PetscScalar *xl;
  PetscInt           y0, y1;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &ctx));
  if (!ctx->C) { /* its set-up failed */
    PetscCall(PCSetFailedReason(pc, PC_SUBPC_ERROR));
    PetscCall(VecSetInf(y));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(VecScatterBegin(ctx->tow, r, ctx->rw, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(ctx->tow, r, ctx->rw, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterBegin(ctx->toall, r, ctx->lall, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(ctx->toall, r, ctx->lall, INSERT_VALUES, SCATTER_FORWARD));
  /* t = r_l - Z^T r_w, x_l = C^{-1} t */
  PetscCall(VecMDot(ctx->rw, ctx->nl, ctx->Z, dots));
  PetscCall(VecCopy(ctx->lall, ctx->t));
  for (PetscInt i = 0; i < ctx->nl; i++) dots[i] = -dots[i];
  {
    PetscScalar *t;
    PetscCall(VecGetArray(ctx->t, &t));
    for (PetscInt i = 0; i < ctx->nl; i++) t[i] += dots[i];
    PetscCall(VecRestoreArray(ctx->t, &t));
  }
  PetscCall(MatSolve(ctx->C, ctx->t, ctx->x));
  /* y_w = GAMG(S_ww) r_w - Z x_l, y_l = x_l */
  PetscCall(PCApply(ctx->amg, ctx->rw, ctx->yw));
  PetscCall(VecGetArrayRead(ctx->x, &xl));
  for (PetscInt i = 0; i < ctx->nl; i++) dots[i] = -xl[i];
  PetscCall(VecMAXPY(ctx->yw, ctx->nl, dots, ctx->Z));
  PetscCall(VecScatterBegin(ctx->tow, ctx->yw, y, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(ctx->tow, ctx->yw, y, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecGetOwnershipRange(y, &y0, &y1));
  for (PetscInt i = 0; i < ctx->nl; i++)
    if (ctx->lglobal[i] >= y0 && ctx->lglobal[i] < y1) PetscCall(VecSetValue(y, ctx->lglobal[i], xl[i], INSERT_VALUES));
  PetscCall(VecRestoreArrayRead(ctx->x, &xl));
  PetscCall(VecAssemblyBegin(y));
  PetscCall(VecAssemblyEnd(y));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwLongPCView(PC pc, PetscViewer viewer)
{
  BwLongPC *ctx;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(PetscViewerASCIIPrintf(viewer, "%" PetscInt_FMT " dofs of long blocks eliminated exactly (Z = S_ww^-1 S_wl by:)\n", ctx->nl));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  PetscCall(KSPView(ctx->kz, viewer));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwLongPCDestroy(PC pc)
{
  BwLongPC *ctx;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(KSPDestroy(&ctx->kz));
  PetscCall(PCDestroy(&ctx->amg));
  PetscCall(ISDestroy(&ctx->isw));
  PetscCall(ISDestroy(&ctx->isl));
  PetscCall(MatDestroy(&ctx->Sww));
  PetscCall(MatDestroy(&ctx->Swl));
  PetscCall(MatDestroy(&ctx->Sll));
  PetscCall(MatDestroy(&ctx->C));
  if (ctx->Z) PetscCall(VecDestroyVecs(ctx->nl, &ctx->Z));
  PetscCall(VecDestroy(&ctx->rw));
  PetscCall(VecDestroy(&ctx->yw));
  PetscCall(VecDestroy(&ctx->sw));
  PetscCall(VecDestroy(&ctx->el));
  PetscCall(VecDestroy(&ctx->cl));
  PetscCall(VecDestroy(&ctx->lall));
  PetscCall(VecDestroy(&ctx->t));
  PetscCall(VecDestroy(&ctx->x));
  PetscCall(VecScatterDestroy(&ctx->tow));
  PetscCall(VecScatterDestroy(&ctx->toall));
  PetscCall(PetscFree(ctx));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* GAMG's defaults of this code, before the options (which override them). */
static PetscErrorCode BwGAMGDefaults(PC pc, PetscInt dim)
{
  PetscFunctionBeginUser;
  PetscCall(PCSetType(pc, PCGAMG));
  /* values refilled with the same pattern keep the aggregates and the
   * interpolation: a new step re-smooths, it does not re-coarsen */
  PetscCall(PCGAMGSetReuseInterpolation(pc, PETSC_TRUE));
  if (dim == 3) {
    PetscReal th = BW_GAMG_THRESHOLD_3D;
    PetscCall(PCGAMGSetThreshold(pc, &th, 1));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwSchurAMGSetUp(BwSolver s, KSP inner)
{
  BwMixedOwnership own;
  PC               pc;
  Mat              S;
  PetscInt         nlong, first[BW_LONG_MAX];
  const char      *prefix;

  PetscFunctionBeginUser;
  PetscCall(BwMixedGetOwnership(s->mx, &own));
  PetscCall(BwMixedGetOperators(s->mx, NULL, &S, NULL));
  PetscCall(BwMixedSetNearNullSpace(s->mx));
  PetscCall(KSPGetPC(inner, &pc));
  nlong = 0;
  if (own.dim == 3) PetscCall(BwFindLongBlocks(S, own.nd, &nlong, first));
  if (!nlong) {
    PetscCall(BwGAMGDefaults(pc, own.dim));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  {
    BwLongPC *ctx;
    PetscInt  r0, r1, nw = 0, nlo = 0, *w, *l;
    PetscCall(PetscNew(&ctx));
    ctx->S         = S;
    ctx->nl        = own.nd * nlong;
    ctx->symmetric = s->symmetric;
    for (PetscInt k = 0; k < nlong; k++)
      for (PetscInt c = 0; c < own.nd; c++) ctx->lglobal[own.nd * k + c] = first[k] + c;
    PetscCall(MatGetOwnershipRange(S, &r0, &r1));
    PetscCall(PetscMalloc2(r1 - r0, &w, ctx->nl, &l));
    for (PetscInt row = r0, k = 0; row < r1; row++) {
      while (k < ctx->nl && ctx->lglobal[k] < row) k++;
      if (k < ctx->nl && ctx->lglobal[k] == row) l[nlo++] = row;
      else w[nw++] = row;
    }
    PetscCall(ISCreateGeneral(s->comm, nw, w, PETSC_COPY_VALUES, &ctx->isw));
    PetscCall(ISCreateGeneral(s->comm, nlo, l, PETSC_COPY_VALUES, &ctx->isl));
    PetscCall(ISSetBlockSize(ctx->isw, own.nd));
    PetscCall(ISSetBlockSize(ctx->isl, own.nd));
    PetscCall(PetscFree2(w, l));
    /* GAMG with the options of the Schur solve's PC (-schur_pc_gamg_...),
     * the solves for Z with their own KSP prefix (-schur_long_ksp_...) */
    PetscCall(KSPGetOptionsPrefix(inner, &prefix));
    PetscCall(PCCreate(s->comm, &ctx->amg));
    PetscCall(PCSetOptionsPrefix(ctx->amg, prefix));
    PetscCall(BwGAMGDefaults(ctx->amg, own.dim));
    PetscCall(KSPCreate(s->comm, &ctx->kz));
    PetscCall(KSPSetOptionsPrefix(ctx->kz, prefix));
    PetscCall(KSPAppendOptionsPrefix(ctx->kz, "long_"));
    PetscCall(KSPSetPC(ctx->kz, ctx->amg));
    PetscCall(KSPSetType(ctx->kz, s->symmetric ? KSPCG : KSPGMRES));
    PetscCall(KSPSetNormType(ctx->kz, KSP_NORM_UNPRECONDITIONED));
    PetscCall(KSPSetTolerances(ctx->kz, BW_LONG_ZTOL, 0.0, PETSC_DEFAULT, PETSC_DEFAULT));
    PetscCall(KSPSetFromOptions(ctx->kz));
    PetscCall(PCSetType(pc, PCSHELL));
    PetscCall(PCShellSetName(pc, "long blocks eliminated, GAMG on the others"));
    PetscCall(PCShellSetContext(pc, ctx));
    PetscCall(PCShellSetSetUp(pc, BwLongPCSetUp));
    PetscCall(PCShellSetApply(pc, BwLongPCApply));
    PetscCall(PCShellSetView(pc, BwLongPCView));
    PetscCall(PCShellSetDestroy(pc, BwLongPCDestroy));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}
