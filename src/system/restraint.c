/* Restraint: the ways an assembly can move without deforming any joint,
 * found before a solver meets a singular matrix, reported with the blocks
 * and the free motion. (Replicated data: every rank finds the same and all
 * raise the same error.)
 *
 * 1. Rigid motions of each connected group (blocks joined by interfaces).
 *    A rigid motion about the group's mean centroid (x0, y0) moves block b by
 *      (a1 - w (c_b2 - y0),  a2 + w (c_b1 - x0),  w)
 *    and a prescribed dof of block b forbids the motions that move that dof,
 *    so, exactly:
 *      translation along x free  <=>  no u1 prescribed in the group
 *      translation along y free  <=>  no u2 prescribed
 *      a rotation free           <=>  no w prescribed, all u1-prescribed
 *                                     centroids at one y, all u2-prescribed
 *                                     ones at one x; its centre is
 *                                     (that x or x0, that y or y0).
 *    With m >= 2 every interface has the full stiffness
 *    diag(kt A, kn A, kn I (1 - 1/m^2)), any relative motion of two joined
 *    blocks strains it, and this test is exact.
 * 2. m = 1: an interface has no bending stiffness, it is a hinge at G.
 *    a) a block all of whose interfaces have one centre G turns about G
 *       unless its own prescribed dofs stop that rotation (w, or u1 with its
 *       centroid off G's horizontal line, or u2 off G's vertical line);
 *    b) a group with more free dofs than the 2 constraints per hinge of its
 *       interfaces (those touching a free dof) is a mechanism (more unknowns
 *       than equations in the kinematics).
 *    Both are sufficient, not necessary: hinges can also leave a motion free
 *    where other parts of the group are over-constrained. That, and any
 *    other singularity, is what BwMixedCheckMechanism finds numerically when
 *    a solver reports one.
 * 3. BwMixedCheckMechanism: inverse iteration on the scaled Schur complement
 *    S^ (unit diagonal), shifted by sigma = 1e-10 ||S^|| so that it can be
 *    factored. Each step shrinks the other eigen-directions against the
 *    smallest by (lambda_1 + sigma)/(lambda_2 + sigma): for a mechanism
 *    (lambda_1 = 0) and even a soft assembly's lambda_2 = 1e-6, four steps
 *    from a fixed start vector leave 1e-16. A Rayleigh quotient of magnitude
 *    below 1e-14 ||S^|| (either sign: round-off) means a mechanism: true ones read 1e-18..1e-16 (the m = 1
 *    four-bar: 7.6e-18), while joints of stiffness contrast 1e12 read 1e-13
 *    and are no mechanism (a real128 Cholesky factors them), only a system
 *    too ill-conditioned for double precision, which the solver reports as
 *    such with the residual it reached; the eigenvector
 *    is the free motion, reported block by block as a rotation about a
 *    point or a translation. It costs one more Cholesky factorisation of
 *    S^, so it runs when something asks: a solver that meets null pivots
 *    or a breakdown, or an m = 1 assembly, where 1-2 are not exact. */
#include <petscksp.h>
#include "system/mixed_impl.h"
#include "util/compat.h"
#include "util/factor.h"
#include "util/exchange.h"

/* Eigen-decomposition of a symmetric n x n matrix a (row-major, destroyed)
 * by cyclic Jacobi rotations: eigenvalues lam[n], eigenvectors as the
 * columns of v. For the 6 x 6 normal matrices of the 3D restraint check. */
static void BwJacobiEigen(PetscInt n, PetscReal a[], PetscReal lam[], PetscReal v[])
{
  for (PetscInt i = 0; i < n; i++)
    for (PetscInt j = 0; j < n; j++) v[i * n + j] = i == j;
  for (int sweep = 0; sweep < 60; sweep++) {
    PetscReal off = 0, on = 0;
    for (PetscInt i = 0; i < n; i++)
      for (PetscInt j = 0; j < n; j++) {
        if (i == j) on += PetscSqr(a[i * n + j]);
        else off += PetscSqr(a[i * n + j]);
      }
    if (off <= 1e-32 * on || off == 0) break;
    for (PetscInt p = 0; p < n; p++)
      for (PetscInt q = p + 1; q < n; q++) {
        PetscReal apq = a[p * n + q], theta, t, c, sn;
        if (apq == 0) continue;
        theta = (a[q * n + q] - a[p * n + p]) / (2 * apq);
        t     = (theta >= 0 ? 1 : -1) / (PetscAbsReal(theta) + PetscSqrtReal(theta * theta + 1));
        c     = 1 / PetscSqrtReal(t * t + 1);
        sn    = t * c;
        for (PetscInt k = 0; k < n; k++) { /* columns p, q */
          PetscReal akp = a[k * n + p], akq = a[k * n + q];
          a[k * n + p]  = c * akp - sn * akq;
          a[k * n + q]  = sn * akp + c * akq;
        }
        for (PetscInt k = 0; k < n; k++) { /* rows p, q */
          PetscReal apk = a[p * n + k], aqk = a[q * n + k];
          a[p * n + k]  = c * apk - sn * aqk;
          a[q * n + k]  = sn * apk + c * aqk;
        }
        for (PetscInt k = 0; k < n; k++) {
          PetscReal vkp = v[k * n + p], vkq = v[k * n + q];
          v[k * n + p]  = c * vkp - sn * vkq;
          v[k * n + q]  = sn * vkp + c * vkq;
        }
      }
  }
  for (PetscInt i = 0; i < n; i++) lam[i] = a[i * n + i];
}

/* A rigid motion (a, w) of 3D blocks in words: a translation along a
 * direction, or a rotation about an axis through a point (about X1, X2, X3
 * where the axis is one of them); x0 is the point the motion is taken about. */
static PetscErrorCode BwDescribeRigid3D(const PetscReal a[3], const PetscReal w[3], const PetscReal x0[3], PetscReal size, char buf[], size_t len)
{
  PetscReal wn = PetscSqrtReal(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]), an = PetscSqrtReal(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  static const char *const axes[3] = {"X1", "X2", "X3"};

  PetscFunctionBeginUser;
  if (wn * size <= 1e-6 * an) {
    PetscReal d[3];
    for (int c = 0; c < 3; c++) d[c] = PetscAbsReal(a[c] / an) < 1e-8 ? 0 : a[c] / an;
    for (int c = 0; c < 3; c++)
      if (PetscAbsReal(PetscAbsReal(d[c]) - 1) < 1e-8) {
        PetscCall(PetscSNPrintf(buf, len, "translation along %s", axes[c]));
        PetscFunctionReturn(PETSC_SUCCESS);
      }
    PetscCall(PetscSNPrintf(buf, len, "translation along (%.3g, %.3g, %.3g)", (double)d[0], (double)d[1], (double)d[2]));
  } else {
    /* the axis: direction w, through the point of least motion x0 + w x a / |w|^2 */
    PetscReal e[3], P[3], wa[3] = {w[1] * a[2] - w[2] * a[1], w[2] * a[0] - w[0] * a[2], w[0] * a[1] - w[1] * a[0]};
    int       axis = -1;
    for (int c = 0; c < 3; c++) {
      e[c] = PetscAbsReal(w[c] / wn) < 1e-8 ? 0 : w[c] / wn;
      P[c] = x0[c] + wa[c] / (wn * wn);
      if (PetscAbsReal(P[c]) < 1e-8 * size) P[c] = 0;
      if (PetscAbsReal(PetscAbsReal(e[c]) - 1) < 1e-8) axis = c;
    }
    if (axis >= 0) {
      /* the line: the two coordinates that fix it */
      const int c1 = (axis + 1) % 3, c2 = (axis + 2) % 3, lo = PetscMin(c1, c2), hi = PetscMax(c1, c2);
      PetscCall(PetscSNPrintf(buf, len, "rotation about %s (the line x%d = %.6g, x%d = %.6g)", axes[axis], lo + 1, (double)P[lo], hi + 1, (double)P[hi]));
    }
    else PetscCall(PetscSNPrintf(buf, len, "rotation about the axis (%.3g, %.3g, %.3g) through (%.6g, %.6g, %.6g)", (double)e[0], (double)e[1], (double)e[2], (double)P[0], (double)P[1], (double)P[2]));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ groups */

static PetscInt BwFind(PetscInt parent[], PetscInt x)
{
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x         = parent[x];
  }
  return x;
}

/* label[b] = the smallest global id of block b's group, for every local block. */
static PetscErrorCode BwRestraintLabels(BwMixed mx, PetscInt label[])
{
  BwGeometry g = mx->geom;
  PetscInt   nb = g->nblocks, *parent, *low, *before;
  PetscBool  changed = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc3(nb + 1, &parent, nb + 1, &low, nb + 1, &before));
  for (PetscInt b = 0; b < nb; b++) label[b] = g->gblock[b];
  /* the groups of the piece itself, once */
  for (PetscInt b = 0; b < nb; b++) parent[b] = b;
  for (PetscInt k = 0; k < g->ninterfaces; k++) {
    PetscInt ri = BwFind(parent, g->pair[2 * k]), rj = BwFind(parent, g->pair[2 * k + 1]);
    if (ri != rj) parent[PetscMax(ri, rj)] = PetscMin(ri, rj);
  }
  while (changed) {
    PetscBool here = PETSC_FALSE;
    PetscCall(PetscArraycpy(before, label, nb));
    for (PetscInt b = 0; b < nb; b++) low[b] = PETSC_MAX_INT;
    for (PetscInt b = 0; b < nb; b++) {
      PetscInt r = BwFind(parent, b);
      low[r]     = PetscMin(low[r], label[b]);
    }
    for (PetscInt b = 0; b < nb; b++) label[b] = low[BwFind(parent, b)];
    /* a ghost's label to its owner (the smallest wins), then back */
    PetscCall(PetscSFReduceBegin(mx->block_sf, MPIU_INT, label, label, MPI_MIN));
    PetscCall(PetscSFReduceEnd(mx->block_sf, MPIU_INT, label, label, MPI_MIN));
    PetscCall(PetscSFBcastBegin(mx->block_sf, MPIU_INT, label, label, MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(mx->block_sf, MPIU_INT, label, label, MPI_REPLACE));
    for (PetscInt b = 0; b < nb && !here; b++) here = label[b] != before[b] ? PETSC_TRUE : PETSC_FALSE;
    PetscCallMPI(MPIU_Allreduce(&here, &changed, 1, MPIU_BOOL, MPI_LOR, mx->comm));
  }
  PetscCall(PetscFree3(parent, low, before));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* What a group's check needs, summed over its blocks (any order: the
 * sums are merged on the group's home rank). */
typedef struct {
  PetscInt  label, nblocks, nfree, nrows, nfix, n[6];
  PetscInt  first_seen;           /* the smallest global id among the blocks summed here */
  PetscReal first_size;           /* that block's size */
  PetscReal sum[3], lo[3], hi[3], area;
  PetscReal y1[2], x2[2];         /* 2D: range of u1-prescribed y, u2-prescribed x */
  PetscReal M[36];                /* 3D: the constraint rows' normal matrix (second round) */
} BwGroupSum;

static void BwGroupInit(BwGroupSum *s, PetscInt label)
{
  PetscMemzero(s, sizeof(*s));
  s->label      = label;
  s->first_seen = PETSC_MAX_INT;
  for (int c = 0; c < 3; c++) s->lo[c] = PETSC_MAX_REAL, s->hi[c] = PETSC_MIN_REAL;
  s->y1[0] = s->x2[0] = PETSC_MAX_REAL;
  s->y1[1] = s->x2[1] = PETSC_MIN_REAL;
}

static void BwGroupMerge(BwGroupSum *a, const BwGroupSum *b)
{
  a->nblocks += b->nblocks;
  a->nfree += b->nfree;
  a->nrows += b->nrows;
  a->nfix += b->nfix;
  for (int c = 0; c < 6; c++) a->n[c] += b->n[c];
  if (b->first_seen < a->first_seen) {
    a->first_seen = b->first_seen;
    a->first_size = b->first_size;
  }
  for (int c = 0; c < 3; c++) {
    a->sum[c] += b->sum[c];
    a->lo[c] = PetscMin(a->lo[c], b->lo[c]);
    a->hi[c] = PetscMax(a->hi[c], b->hi[c]);
  }
  a->area += b->area;
  a->y1[0] = PetscMin(a->y1[0], b->y1[0]);
  a->y1[1] = PetscMax(a->y1[1], b->y1[1]);
  a->x2[0] = PetscMin(a->x2[0], b->x2[0]);
  a->x2[1] = PetscMax(a->x2[1], b->x2[1]);
  for (int c = 0; c < 36; c++) a->M[c] += b->M[c];
}

static int BwGroupCompare(const void *x, const void *y)
{
  const BwGroupSum *a = x, *b = y;
  return (a->label > b->label) - (a->label < b->label);
}

/* The sums of this rank's owned blocks, one per group, to each group's
 * home (label % ranks), merged there: *nhome groups, ascending label. */
static PetscErrorCode BwGroupsToHome(MPI_Comm comm, PetscInt n, BwGroupSum loc[], PetscInt *nhome, BwGroupSum **home)
{
  BwPacker    p;
  char       *recv;
  size_t      nrecv;
  PetscMPIInt size;
  PetscInt    m = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(BwPackerCreate(comm, &p));
  for (PetscInt q = 0; q < n; q++) PetscCall(BwPack(&p, (PetscMPIInt)(loc[q].label % size), &loc[q], sizeof(BwGroupSum)));
  PetscCall(BwPackerExchange(comm, &p, &recv, &nrecv, NULL));
  PetscCall(BwPackerDestroy(&p));
  n = (PetscInt)(nrecv / sizeof(BwGroupSum));
  qsort(recv, (size_t)n, sizeof(BwGroupSum), BwGroupCompare);
  {
    BwGroupSum *r = (BwGroupSum *)recv;
    for (PetscInt q = 0; q < n; q++) {
      if (m && r[m - 1].label == r[q].label) BwGroupMerge(&r[m - 1], &r[q]);
      else r[m++] = r[q];
    }
  }
  *nhome = m;
  *home  = (BwGroupSum *)recv;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Each owned block's group sums (first round: counts, centroids, boxes,
 * prescribed dofs), one record per group, ascending label. */
static PetscErrorCode BwGroupsLocal(BwMixed mx, const PetscInt label[], PetscInt *n, BwGroupSum **loc, PetscInt **which)
{
  BwGeometry     g = mx->geom;
  BwModel        model = mx->model;
  const PetscInt d = g->dim, nd = mx->nd, nown = g->nown_blocks;
  PetscInt      *lab, *perm, m = 0;
  BwGroupSum    *s;

  PetscFunctionBeginUser;
  /* the groups present: sorted labels of the owned blocks */
  PetscCall(PetscMalloc1(nown + 1, &lab));
  PetscCall(PetscMalloc1(nown + 1, &perm));
  for (PetscInt b = 0; b < nown; b++) lab[b] = label[b];
  {
    PetscInt cnt = nown;
    PetscCall(PetscSortRemoveDupsInt(&cnt, lab));
    m = cnt;
  }
  PetscCall(PetscMalloc1(m + 1, &s));
  for (PetscInt q = 0; q < m; q++) BwGroupInit(&s[q], lab[q]);
  /* which[b]: the record of owned block b */
  for (PetscInt b = 0; b < nown; b++) PetscCall(PetscFindInt(label[b], m, lab, &perm[b]));
  for (PetscInt b = 0; b < nown; b++) {
    BwGroupSum      *r = &s[perm[b]];
    const PetscReal *c = &g->centroid[d * b];
    r->nblocks++;
    if (g->gblock[b] < r->first_seen) {
      r->first_seen = g->gblock[b];
      r->first_size = BwGeometryBlockSize(g, b);
    }
    for (PetscInt a = 0; a < d; a++) {
      r->sum[a] += c[a];
      r->lo[a] = PetscMin(r->lo[a], c[a]);
      r->hi[a] = PetscMax(r->hi[a], c[a]);
    }
    if (d == 2) r->area += g->area[b];
    for (PetscInt a = 0; a < nd; a++) {
      if (!model->prescribed[nd * b + a]) {
        r->nfree++;
        continue;
      }
      r->n[a]++;
      r->nfix++;
      if (d == 2 && a == 0) {
        r->y1[0] = PetscMin(r->y1[0], c[1]);
        r->y1[1] = PetscMax(r->y1[1], c[1]);
      } else if (d == 2 && a == 1) {
        r->x2[0] = PetscMin(r->x2[0], c[0]);
        r->x2[1] = PetscMax(r->x2[1], c[0]);
      }
    }
  }
  /* the hinge rows of m = 1: each owned interface touching a free dof, on
   * its first block's group */
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
    PetscInt  k = mx->own_interfaces[e], i = g->pair[2 * k], j = g->pair[2 * k + 1], at;
    PetscBool touches = PETSC_FALSE;
    for (PetscInt a = 0; a < nd; a++) touches = (PetscBool)(touches || !model->prescribed[nd * i + a] || !model->prescribed[nd * j + a]);
    if (!touches) continue;
    PetscCall(PetscFindInt(label[i], m, lab, &at));
    if (at >= 0) s[at].nrows += 2;
    else {
      /* its first block is a ghost here: the interface's rows go with a
       * record of their own */
      PetscCall(PetscRealloc(sizeof(BwGroupSum) * (size_t)(m + 2), &s));
      BwGroupInit(&s[m], label[i]);
      s[m++].nrows = 2;
    }
  }
  *n   = m;
  *loc = s;
  if (which) *which = perm;
  else PetscCall(PetscFree(perm));
  PetscCall(PetscFree(lab));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* "3, 4, 9, ..." and the count: the 12 smallest global ids of group
 * `label` over all ranks, to rank `root`. */
static PetscErrorCode BwGroupList(BwMixed mx, const PetscInt label[], PetscInt glabel, PetscMPIInt root, char list[], size_t len)
{
  BwGeometry  g = mx->geom;
  PetscInt    mine[13], nmine = 0, *all = NULL;
  PetscMPIInt size, rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(mx->comm, &size));
  PetscCallMPI(MPI_Comm_rank(mx->comm, &rank));
  /* owned blocks ascend in global id: the first 13 of the group */
  for (PetscInt b = 0; b < g->nown_blocks && nmine < 13; b++)
    if (label[b] == glabel) mine[nmine++] = g->gblock[b];
  for (PetscInt q = nmine; q < 13; q++) mine[q] = PETSC_MAX_INT;
  if (rank == root) PetscCall(PetscMalloc1(13 * size, &all));
  PetscCallMPI(MPI_Gather(mine, 13, MPIU_INT, all, 13, MPIU_INT, root, mx->comm));
  list[0] = 0;
  if (rank == root) {
    PetscInt n = 13 * size, shown = 0;
    PetscCall(PetscSortInt(n, all));
    for (PetscInt q = 0; q < n && all[q] != PETSC_MAX_INT && shown <= 12; q++, shown++) {
      char item[32];
      if (shown == 12) PetscCall(PetscStrlcat(list, ", ...", len));
      else {
        PetscCall(PetscSNPrintf(item, sizeof(item), "%s%" PetscInt_FMT, shown ? ", " : "", all[q]));
        PetscCall(PetscStrlcat(list, item, len));
      }
    }
    PetscCall(PetscFree(all));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The verdict of a 2D group (rigid motions left free by its prescribed
 * dofs, exact for m >= 2; see the top of this file); *fails: 1 if a rigid
 * motion is free, 0 if not; the message with "%s" for the block list. */
static PetscErrorCode BwGroupVerdict2D(const BwGroupSum *g, char fmt[], size_t len, PetscInt *fails)
{
  PetscReal size = PetscMax(PetscMax(g->hi[0] - g->lo[0], g->hi[1] - g->lo[1]), PetscSqrtReal(g->area)), tol = 1e-9 * size;
  PetscBool tx = (PetscBool)(g->n[0] == 0), ty = (PetscBool)(g->n[1] == 0);
  PetscBool rot = (PetscBool)(g->n[2] == 0 && (g->n[0] == 0 || g->y1[1] - g->y1[0] <= tol) && (g->n[1] == 0 || g->x2[1] - g->x2[0] <= tol));
  PetscInt  count = g->nblocks;
  PetscReal x0 = g->sum[0] / g->nblocks, y0 = g->sum[1] / g->nblocks;

  PetscFunctionBeginUser;
  *fails = 0;
  if (!tx && !ty && !rot) PetscFunctionReturn(PETSC_SUCCESS);
  *fails = 1;
  if (tx && ty && rot) {
    PetscCall(PetscSNPrintf(fmt, len, "the assembly is not restrained: block%s %%s (%" PetscInt_FMT " block%s) %s no path of interfaces to a support; free motion: rigid translation and rotation", count > 1 ? "s" : "", count, count > 1 ? "s" : "", count > 1 ? "have" : "has"));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  {
    char what[256] = "";
    if (tx) PetscCall(PetscStrlcat(what, "translation along x (u1)", sizeof(what)));
    if (ty) PetscCall(PetscStrlcat(what, tx ? ", translation along y (u2)" : "translation along y (u2)", sizeof(what)));
    if (rot) {
      char r[128];
      PetscCall(PetscSNPrintf(r, sizeof(r), "%srotation about (%g, %g)", tx || ty ? ", " : "", (double)(g->n[1] ? g->x2[0] : x0), (double)(g->n[0] ? g->y1[0] : y0)));
      PetscCall(PetscStrlcat(what, r, sizeof(what)));
    }
    PetscCall(PetscSNPrintf(fmt, len, "the assembly is not restrained: block%s %%s (%" PetscInt_FMT " block%s) %s held only by prescribed dofs (u1 on %" PetscInt_FMT ", u2 on %" PetscInt_FMT ", w on %" PetscInt_FMT " block%s) that leave a rigid motion free; free motion: %s", count > 1 ? "s" : "", count, count > 1 ? "s" : "", count > 1 ? "are" : "is", g->n[0], g->n[1], g->n[2], g->n[2] == 1 ? "" : "s", what));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 3D: the rigid motions (a, w) about a group's mean centroid x0 that its
 * prescribed dofs leave free, exactly: the null space of the constraint
 * rows (u_b = a + w x (c_b - x0) on a prescribed translation, w_c on a
 * prescribed rotation; w scaled by the group's size L so that the columns
 * weigh alike), from the 6 x 6 normal matrix g->M. With m, m_b >= 2 every
 * interface has the full stiffness of model.md and a relative motion of
 * joined blocks strains it, so the check is exact; m = 1 or m_b = 1
 * leave hinges, which BwMixedCheckMechanism finds. */
static PetscErrorCode BwGroupVerdict3D(BwGroupSum *g, const PetscReal x0[3], PetscReal L, char fmt[], size_t len, PetscInt *fails)
{
  PetscReal lam[6], V[36], lmax = 0;
  PetscInt  nfree = 0, count = g->nblocks;
  char      what[1024] = "";

  PetscFunctionBeginUser;
  *fails = 0;
  BwJacobiEigen(6, g->M, lam, V);
  for (int i = 0; i < 6; i++) lmax = PetscMax(lmax, lam[i]);
  {
    /* the null space, in a basis that reads: rows of (w', a) brought to
     * reduced row echelon form, rotations first, so that a free rotation
     * about an axis is that axis (X1, X2, X3 where it is one) and a free
     * translation its direction, whatever basis the eigensolver gave */
    PetscReal N[6][6];
    PetscInt  k = 0, row = 0;
    for (int i = 0; i < 6; i++) {
      if (lam[i] > 1e-10 * PetscMax(lmax, 1)) continue;
      for (int c = 0; c < 3; c++) N[k][c] = V[6 * (3 + c) + i], N[k][3 + c] = V[6 * c + i];
      k++;
    }
    for (int col = 0; col < 6 && row < k; col++) {
      PetscInt  piv = row;
      PetscReal best = 0;
      for (PetscInt r = row; r < k; r++)
        if (PetscAbsReal(N[r][col]) > best) best = PetscAbsReal(N[r][col]), piv = r;
      if (best < 1e-8) continue;
      for (int c = 0; c < 6; c++) {
        PetscReal t = N[row][c];
        N[row][c]   = N[piv][c];
        N[piv][c]   = t;
      }
      for (int c = 5; c >= 0; c--) N[row][c] /= N[row][col];
      for (PetscInt r = 0; r < k; r++) {
        PetscReal f = N[r][col];
        if (r == row || f == 0) continue;
        for (int c = 0; c < 6; c++) N[r][c] -= f * N[row][c];
      }
      row++;
    }
    for (PetscInt r = 0; r < k; r++) {
      PetscReal a[3], w[3];
      char      one[256];
      for (int c = 0; c < 3; c++) {
        w[c] = PetscAbsReal(N[r][c]) < 1e-12 ? 0 : N[r][c] / L;
        a[c] = PetscAbsReal(N[r][3 + c]) < 1e-12 ? 0 : N[r][3 + c];
      }
      PetscCall(BwDescribeRigid3D(a, w, x0, L, one, sizeof(one)));
      if (nfree) PetscCall(PetscStrlcat(what, ", ", sizeof(what)));
      PetscCall(PetscStrlcat(what, one, sizeof(what)));
      nfree++;
    }
  }
  if (!nfree) PetscFunctionReturn(PETSC_SUCCESS);
  *fails = 1;
  if (!g->nfix) PetscCall(PetscSNPrintf(fmt, len, "the assembly is not restrained: block%s %%s (%" PetscInt_FMT " block%s) %s no path of interfaces to a support; free motion: rigid translation and rotation", count > 1 ? "s" : "", count, count > 1 ? "s" : "", count > 1 ? "have" : "has"));
  else PetscCall(PetscSNPrintf(fmt, len, "the assembly is not restrained: block%s %%s (%" PetscInt_FMT " block%s) %s held only by %" PetscInt_FMT " prescribed dofs that leave %" PetscInt_FMT " rigid motion%s free; free motion: %s", count > 1 ? "s" : "", count, count > 1 ? "s" : "", count > 1 ? "are" : "is", g->nfix, nfree, nfree > 1 ? "s" : "", what));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 3D, second round: each group's mean centroid x0 and size L from its
 * home to every rank with blocks in it, and the constraint rows' normal
 * matrix of the owned blocks back home. */
typedef struct {
  PetscInt          nhome;
  const BwGroupSum *home;
} BwHomeGroups;

static PetscErrorCode BwGroupFrameAnswer(void *ctx, PetscInt label, void *ans)
{
  BwHomeGroups *h  = (BwHomeGroups *)ctx;
  PetscReal    *xl = (PetscReal *)ans;
  PetscInt      at = -1, lo = 0, hi = h->nhome;

  PetscFunctionBeginUser;
  while (hi - lo > 1) { /* home[] ascends in label */
    PetscInt mid = (lo + hi) / 2;
    if (h->home[mid].label <= label) lo = mid;
    else hi = mid;
  }
  if (h->nhome && h->home[lo].label == label) at = lo;
  PetscCheck(at >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "group %" PetscInt_FMT " asked of a rank that is not its home", label);
  xl[3] = h->home[at].first_size;
  for (int c = 0; c < 3; c++) {
    xl[c] = h->home[at].sum[c] / h->home[at].nblocks;
    xl[3] = PetscMax(xl[3], h->home[at].hi[c] - h->home[at].lo[c]);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwGroupsNormal3D(BwMixed mx, PetscInt nloc, BwGroupSum loc[], const PetscInt which[], PetscInt nhome, BwGroupSum home[])
{
  BwGeometry   g = mx->geom;
  BwHomeGroups h = {nhome, home};
  PetscMPIInt  size, *dest;
  PetscInt    *key, nback;
  PetscReal   *xl;
  BwGroupSum  *back;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(mx->comm, &size));
  PetscCall(PetscMalloc3(nloc + 1, &dest, nloc + 1, &key, 4 * nloc + 4, &xl));
  for (PetscInt q = 0; q < nloc; q++) {
    key[q]  = loc[q].label;
    dest[q] = (PetscMPIInt)(loc[q].label % size);
  }
  PetscCall(BwQueryBytes(mx->comm, nloc, dest, key, 4 * sizeof(PetscReal), BwGroupFrameAnswer, &h, xl));
  /* only M goes home now: the other figures were summed in the first round */
  for (PetscInt q = 0; q < nloc; q++) BwGroupInit(&loc[q], key[q]);
  for (PetscInt b = 0; b < g->nown_blocks; b++) {
    const PetscInt q = which[b];
    BwGroupSum    *r = &loc[q];
    PetscReal      rr[3];
    for (int c = 0; c < 3; c++) rr[c] = (g->centroid[3 * b + c] - xl[4 * q + c]) / xl[4 * q + 3];
    for (int c = 0; c < 6; c++) {
      PetscReal row[6] = {0, 0, 0, 0, 0, 0};
      if (!mx->model->prescribed[6 * b + c]) continue;
      if (c < 3) {
        /* (w x r)_c = sum_j eps_cjk w_j r_k; w' = w L */
        row[c]               = 1;
        row[3 + (c + 1) % 3] = rr[(c + 2) % 3];
        row[3 + (c + 2) % 3] = -rr[(c + 1) % 3];
      } else row[c] = 1;
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) r->M[6 * i + j] += row[i] * row[j];
    }
  }
  PetscCall(BwGroupsToHome(mx->comm, nloc, loc, &nback, &back));
  for (PetscInt q = 0, at = 0; q < nback; q++) {
    while (at < nhome && home[at].label < back[q].label) at++;
    PetscCheck(at < nhome && home[at].label == back[q].label, PETSC_COMM_SELF, PETSC_ERR_PLIB, "group %" PetscInt_FMT " came home twice", back[q].label);
    PetscCall(PetscArraycpy(home[at].M, back[q].M, 36));
  }
  PetscCall(PetscFree(back));
  PetscCall(PetscFree3(dest, key, xl));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The first failing candidate over all ranks (lowest key; PETSC_MAX_INT:
 * none), its message from the rank that has it, on every rank. */
static PetscErrorCode BwRestraintFirst(MPI_Comm comm, PetscInt key, const char msg[], char out[], size_t len, PetscInt *first)
{
  PetscInt    g;
  PetscMPIInt rank, mine, from;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPIU_Allreduce(&key, &g, 1, MPIU_INT, MPI_MIN, comm));
  *first = g;
  if (g == PETSC_MAX_INT) PetscFunctionReturn(PETSC_SUCCESS);
  mine = key == g ? rank : PETSC_MPI_INT_MAX;
  PetscCallMPI(MPI_Allreduce(&mine, &from, 1, MPI_INT, MPI_MIN, comm));
  if (rank == from) PetscCall(PetscStrncpy(out, msg, len));
  PetscCallMPI(MPI_Bcast(out, (PetscMPIInt)len, MPI_CHAR, from, comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedCheckRestraint(BwMixed mx)
{
  BwGeometry  geom = mx->geom;
  BwModel     model = mx->model;
  PetscInt   *label, nloc = 0, nhome = 0, *which = NULL, bad = PETSC_MAX_INT, first;
  BwGroupSum *loc, *home;
  char        fmt[1536] = "", msg[1536] = "", list[512];
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(mx->comm, &rank));
  PetscCall(PetscMalloc1(geom->nblocks + 1, &label));
  PetscCall(BwRestraintLabels(mx, label));
  PetscCall(BwGroupsLocal(mx, label, &nloc, &loc, &which));
  {
    /* the first round travels home; in 3D the second needs loc[] again */
    BwGroupSum *copy;
    PetscCall(PetscMalloc1(nloc + 1, &copy));
    PetscCall(PetscArraycpy(copy, loc, nloc));
    PetscCall(BwGroupsToHome(mx->comm, nloc, copy, &nhome, &home));
    PetscCall(PetscFree(copy));
  }
  if (geom->dim == 3) PetscCall(BwGroupsNormal3D(mx, nloc, loc, which, nhome, home));

  /* 1. rigid motions of each group: the first failing group (lowest label) */
  for (PetscInt q = 0; q < nhome && bad == PETSC_MAX_INT; q++) {
    PetscInt fails;
    if (geom->dim == 3) {
      PetscReal x0[3], L = 0;
      for (int c = 0; c < 3; c++) {
        x0[c] = home[q].sum[c] / home[q].nblocks;
        L     = PetscMax(L, home[q].hi[c] - home[q].lo[c]);
      }
      L = PetscMax(L, home[q].first_size);
      PetscCall(BwGroupVerdict3D(&home[q], x0, L, fmt, sizeof(fmt), &fails));
    } else PetscCall(BwGroupVerdict2D(&home[q], fmt, sizeof(fmt), &fails));
    if (fails) bad = home[q].label;
  }
  PetscCall(BwRestraintFirst(mx->comm, bad, fmt, msg, sizeof(msg), &first));
  if (first != PETSC_MAX_INT) {
    PetscCall(BwGroupList(mx, label, first, 0, list, sizeof(list)));
    if (rank == 0) PetscCall(PetscSNPrintf(fmt, sizeof(fmt), msg, list));
    PetscCallMPI(MPI_Bcast(fmt, sizeof(fmt), MPI_CHAR, 0, mx->comm));
    PetscCall(PetscFree(home));
    PetscCall(PetscFree(loc));
    PetscCall(PetscFree(which));
    PetscCall(PetscFree(label));
    SETERRQ(mx->comm, PETSC_ERR_USER_INPUT, "%s", fmt);
  }

  /* 2. hinges (m = 1) */
  if (mx->m == 1 && geom->dim == 2) {
    /* a) an owned block held only at one point: the lowest global id */
    bad = PETSC_MAX_INT;
    for (PetscInt b = 0; b < geom->nown_blocks && bad == PETSC_MAX_INT; b++) {
      PetscInt         a0 = mx->adj_offsets[b], a1 = mx->adj_offsets[b + 1];
      const PetscReal *P, cx = geom->centroid[2 * b], cy = geom->centroid[2 * b + 1];
      PetscReal        tol = 1e-9 * PetscSqrtReal(geom->area[b]);
      PetscBool        pin = PETSC_TRUE;

      if (a1 == a0) continue;
      P = &geom->center[2 * mx->adj[a0]];
      for (PetscInt a = a0 + 1; a < a1 && pin; a++) {
        const PetscReal *Q = &geom->center[2 * mx->adj[a]];
        if (PetscAbsReal(Q[0] - P[0]) > tol || PetscAbsReal(Q[1] - P[1]) > tol) pin = PETSC_FALSE;
      }
      if (!pin) continue;
      if (model->prescribed[3 * b + 2] || (model->prescribed[3 * b] && PetscAbsReal(cy - P[1]) > tol) || (model->prescribed[3 * b + 1] && PetscAbsReal(cx - P[0]) > tol)) continue;
      {
        PetscInt k = mx->adj[a0]; /* its first interface (adj ascends in global id) */
        bad        = geom->gblock[b];
        PetscCall(PetscSNPrintf(fmt, sizeof(fmt), "the assembly is a mechanism: block %" PetscInt_FMT " is held only at G = (%g, %g) (interface %" PetscInt_FMT ", blocks %" PetscInt_FMT " and %" PetscInt_FMT "%s), and with discretization.m = 1 an interface carries no moment (a hinge); free motion: rotation of block %" PetscInt_FMT " about (%g, %g); use m >= 2", bad, (double)geom->center[2 * k], (double)geom->center[2 * k + 1], geom->giface[k], geom->gblock[geom->pair[2 * k]], geom->gblock[geom->pair[2 * k + 1]], a1 - a0 > 1 ? ", and others through the same point" : "", bad, (double)geom->center[2 * k], (double)geom->center[2 * k + 1]));
      }
    }
    PetscCall(BwRestraintFirst(mx->comm, bad, fmt, msg, sizeof(msg), &first));
    if (first != PETSC_MAX_INT) {
      PetscCall(PetscFree(home));
      PetscCall(PetscFree(loc));
      PetscCall(PetscFree(which));
      PetscCall(PetscFree(label));
      SETERRQ(mx->comm, PETSC_ERR_USER_INPUT, "%s", msg);
    }
    /* b) more free dofs than hinge constraints in a group */
    bad = PETSC_MAX_INT;
    for (PetscInt q = 0; q < nhome && bad == PETSC_MAX_INT; q++) {
      const BwGroupSum *g = &home[q];
      if (g->nfree <= g->nrows) continue;
      bad = g->label;
      PetscCall(PetscSNPrintf(fmt, sizeof(fmt), "the assembly is a mechanism: with discretization.m = 1 an interface carries no moment (a hinge at its centre G), and block%s %%s (%" PetscInt_FMT " block%s) %s %" PetscInt_FMT " free dofs against %" PetscInt_FMT " hinge constraints (2 per interface); free motion: at least %" PetscInt_FMT " independent rotations about the interfaces' centres; use m >= 2", g->nblocks > 1 ? "s" : "", g->nblocks, g->nblocks > 1 ? "s" : "", g->nblocks > 1 ? "have" : "has", g->nfree, g->nrows, g->nfree - g->nrows));
    }
    PetscCall(BwRestraintFirst(mx->comm, bad, fmt, msg, sizeof(msg), &first));
    if (first != PETSC_MAX_INT) {
      PetscCall(BwGroupList(mx, label, first, 0, list, sizeof(list)));
      if (rank == 0) PetscCall(PetscSNPrintf(fmt, sizeof(fmt), msg, list));
      PetscCallMPI(MPI_Bcast(fmt, sizeof(fmt), MPI_CHAR, 0, mx->comm));
      PetscCall(PetscFree(home));
      PetscCall(PetscFree(loc));
      PetscCall(PetscFree(which));
      PetscCall(PetscFree(label));
      SETERRQ(mx->comm, PETSC_ERR_USER_INPUT, "%s", fmt);
    }
  }
  PetscCall(PetscFree(home));
  PetscCall(PetscFree(loc));
  PetscCall(PetscFree(which));
  PetscCall(PetscFree(label));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The verdict of the inverse iteration. The Rayleigh quotient of a free
 * motion is zero up to round-off, and round-off has either sign: measured on
 * the m = 1 four-bar, +7.6e-18 on an AMD EPYC and -2.9e-17 on an Intel Xeon
 * (||S^|| ~ 1). So a mechanism is |rho| <= 1e-14 ||S^||, whatever the sign
 * of rho; NaN is no verdict. */
PetscBool BwMechanismVerdict(PetscReal rho, PetscReal snorm)
{
  return (PetscBool)(PetscAbsReal(rho) <= 1e-14 * snorm);
}

/* The size of block b's motion q (nd dofs): translations and rotations
 * times the block's size. */
static PetscReal BwMotionSize(BwMixed mx, PetscInt b, const PetscReal q[])
{
  PetscReal r = BwGeometryBlockSize(mx->geom, b), s = 0;
  for (PetscInt c = 0; c < mx->nd; c++) s += PetscSqr(q[c] * (c >= mx->dim ? r : 1));
  return PetscSqrtReal(s);
}

/* Block b's displacement (u1, u2, w) in words. */
static PetscErrorCode BwDescribeMotion(BwGeometry geom, PetscInt b, const PetscReal q[3], char buf[], size_t len)
{
  PetscReal r = PetscSqrtReal(geom->area[b]), mag = PetscSqrtReal(q[0] * q[0] + q[1] * q[1] + PetscSqr(q[2] * r));

  PetscFunctionBeginUser;
  if (PetscAbsReal(q[2]) * r > 1e-6 * mag) {
    PetscReal P[2] = {geom->centroid[2 * b] - q[1] / q[2], geom->centroid[2 * b + 1] + q[0] / q[2]};
    /* the eigenvector carries round-off: a centre within 1e-8 of the
     * block's size from an axis is on it */
    for (int c = 0; c < 2; c++)
      if (PetscAbsReal(P[c]) < 1e-8 * r) P[c] = 0;
    PetscCall(PetscSNPrintf(buf, len, "block %" PetscInt_FMT " rotates about (%.6g, %.6g)", geom->gblock[b], (double)P[0], (double)P[1]));
  } else {
    PetscReal l = PetscSqrtReal(q[0] * q[0] + q[1] * q[1]);
    PetscReal d[2] = {q[0] / l, q[1] / l};
    for (int c = 0; c < 2; c++)
      if (PetscAbsReal(d[c]) < 1e-8) d[c] = 0;
    PetscCall(PetscSNPrintf(buf, len, "block %" PetscInt_FMT " translates along (%.3g, %.3g)", geom->gblock[b], (double)d[0], (double)d[1]));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* For the solver, when a factorisation finds null pivots or a solve breaks
 * down: an error naming the blocks and the free motion if S^ is singular
 * to working precision, else nothing (the caller reports its own failure).
 * Collective. `how` says what found it ("MUMPS: 2 null pivots"). */
PetscErrorCode BwMixedCheckMechanism(BwMixed mx, const char how[])
{
  BwGeometry         geom = mx->geom;
  Mat                A;
  KSP                ksp;
  PC                 pc;
  Vec                x, y;
  PetscReal          snorm, rho, *q, mmax = 0;
  PetscScalar        dot;
  KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
  PetscInt           lo, hi, nown = geom->nown_blocks, nmove = 0, *moving, nd = mx->nd;
  const PetscScalar *a;
  PetscScalar       *xa;
  char               list[512] = "", motion[1024] = "";

  PetscFunctionBeginUser;
  PetscCheck(mx->S, mx->comm, PETSC_ERR_ARG_WRONGSTATE, "BwMixedCheckMechanism needs the assembled system");
  PetscCall(MatDuplicate(mx->S, MAT_COPY_VALUES, &A));
  PetscCall(MatNorm(A, NORM_INFINITY, &snorm));
  PetscCall(MatShift(A, 1e-10 * snorm));
  PetscCall(MatSetOption(A, MAT_SPD, PETSC_TRUE));
  PetscCall(KSPCreate(mx->comm, &ksp));
  PetscCall(KSPSetOptionsPrefix(ksp, "mechanism_"));
  PetscCall(KSPSetOperators(ksp, A, A));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCCHOLESKY));
  {
    MatSolverType type;
    PetscCall(BwFactorPackage(mx->comm, BW_FACTOR_CHOLESKY, &type));
    /* without a parallel Cholesky the check is not made: nothing is said */
    if (!type) {
      PetscCall(KSPDestroy(&ksp));
      PetscCall(MatDestroy(&A));
      PetscFunctionReturn(PETSC_SUCCESS);
    }
    PetscCall(PCFactorSetMatSolverType(pc, type));
  }
  PetscCall(MatCreateVecs(A, &x, &y));
  /* a start vector that depends on the global row only: the same on any
   * number of ranks, and not orthogonal to a mechanism in practice */
  PetscCall(VecGetOwnershipRange(x, &lo, &hi));
  PetscCall(VecGetArray(x, &xa));
  for (PetscInt r = lo; r < hi; r++) xa[r - lo] = 1 + (PetscReal)((r * 7919) % 101) / 101;
  PetscCall(VecRestoreArray(x, &xa));
  for (int it = 0; it < 4 && reason >= 0; it++) {
    PetscCall(KSPSolve(ksp, x, y));
    PetscCall(KSPGetConvergedReason(ksp, &reason));
    PetscCall(VecNormalize(y, NULL));
    PetscCall(VecCopy(y, x));
  }
  PetscCall(MatMult(mx->S, x, y));
  PetscCall(VecDot(x, y, &dot));
  rho = PetscRealPart(dot);
  PetscCall(KSPDestroy(&ksp));
  PetscCall(MatDestroy(&A));
  /* a failed factorisation of the shifted matrix tells nothing */
  if (reason < 0 || !BwMechanismVerdict(rho, snorm)) {
    PetscCall(VecDestroy(&x));
    PetscCall(VecDestroy(&y));
    PetscFunctionReturn(PETSC_SUCCESS);
  }

  /* the eigenvector in physical dofs, q = diag(S)^{-1/2} q~, per owned
   * block; the moving blocks (more than 1e-3 of the largest motion) and the
   * words for the first five, each rank its own, merged on rank 0 */
  PetscCall(VecGetArrayRead(x, &a));
  PetscCall(PetscMalloc2(nd * nown + 1, &q, nown + 1, &moving));
  for (PetscInt b = 0; b < nown; b++) {
    for (PetscInt c = 0; c < nd; c++) q[nd * b + c] = mx->qrow[b] >= 0 && !mx->model->prescribed[nd * b + c] ? PetscRealPart(a[mx->qrow[b] + c - lo]) * mx->qscale[nd * b + c] : 0;
    mmax = PetscMax(mmax, BwMotionSize(mx, b, &q[nd * b]));
  }
  PetscCall(VecRestoreArrayRead(x, &a));
  {
    PetscReal gmax;
    PetscCallMPI(MPIU_Allreduce(&mmax, &gmax, 1, MPIU_REAL, MPIU_MAX, mx->comm));
    mmax = gmax;
  }
  for (PetscInt b = 0; b < nown; b++)
    if (BwMotionSize(mx, b, &q[nd * b]) > 1e-3 * mmax) moving[nmove++] = b;
  {
    /* each rank's first 13 moving blocks (owned blocks ascend in global
     * id) with the words of its first 5, to rank 0 */
    typedef struct {
      PetscInt gid;
      char     what[200];
    } BwMoving;
    BwMoving   *mine, *all = NULL;
    PetscMPIInt size, rank;
    PetscInt    total;
    PetscCallMPI(MPI_Comm_size(mx->comm, &size));
    PetscCallMPI(MPI_Comm_rank(mx->comm, &rank));
    PetscCallMPI(MPIU_Allreduce(&nmove, &total, 1, MPIU_INT, MPI_SUM, mx->comm));
    PetscCall(PetscCalloc1(13, &mine));
    for (PetscInt e = 0; e < 13; e++) {
      mine[e].gid = e < nmove ? geom->gblock[moving[e]] : PETSC_MAX_INT;
      if (e < PetscMin(nmove, 5)) {
        PetscInt b = moving[e];
        if (nd == 6) {
          char what[160];
          PetscCall(BwDescribeRigid3D(&q[6 * b], &q[6 * b + 3], &geom->centroid[3 * b], BwGeometryBlockSize(geom, b), what, sizeof(what)));
          PetscCall(PetscSNPrintf(mine[e].what, sizeof(mine[e].what), "block %" PetscInt_FMT ": %s", geom->gblock[b], what));
        } else PetscCall(BwDescribeMotion(geom, b, &q[3 * b], mine[e].what, sizeof(mine[e].what)));
      }
    }
    if (!rank) PetscCall(PetscMalloc1(13 * size, &all));
    PetscCallMPI(MPI_Gather(mine, (PetscMPIInt)(13 * sizeof(BwMoving)), MPI_BYTE, all, (PetscMPIInt)(13 * sizeof(BwMoving)), MPI_BYTE, 0, mx->comm));
    if (!rank) {
      /* merged by global id: the lowest 13, the words of the lowest 5 */
      for (PetscInt e = 0, shown = 0; e < 13 * size && shown < 13; shown++) {
        PetscInt best = -1;
        for (PetscInt f = 0; f < 13 * size; f++)
          if (all[f].gid != PETSC_MAX_INT && (best < 0 || all[f].gid < all[best].gid)) best = f;
        if (best < 0) break;
        {
          char item[32];
          PetscCall(PetscSNPrintf(item, sizeof(item), "%s%" PetscInt_FMT, shown ? ", " : "", all[best].gid));
          PetscCall(PetscStrlcat(list, shown < 12 ? item : ", ...", sizeof(list)));
        }
        if (shown < 5) {
          if (shown == 4) PetscCall(PetscStrlcat(motion, ", ...", sizeof(motion)));
          else {
            if (shown) PetscCall(PetscStrlcat(motion, ", ", sizeof(motion)));
            PetscCall(PetscStrlcat(motion, all[best].what, sizeof(motion)));
          }
        }
        all[best].gid = PETSC_MAX_INT;
      }
      PetscCall(PetscFree(all));
    }
    PetscCallMPI(MPI_Bcast(list, sizeof(list), MPI_CHAR, 0, mx->comm));
    PetscCallMPI(MPI_Bcast(motion, sizeof(motion), MPI_CHAR, 0, mx->comm));
    PetscCall(PetscFree(mine));
    nmove = total;
  }
  PetscCall(PetscFree2(q, moving));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&y));
  {
    /* Above a contrast of about 1e12 between joints, double precision no
     * longer separates a soft mode from a free one (measured: 1e13 random
     * and layered contrasts on a 6 x 4 wall read as mechanisms here, while a
     * real128 Cholesky factors them): the message says both. */
    BwModel   model = mx->model;
    PetscReal kmin = PETSC_MAX_REAL, kmax = 0, g[2];
    for (PetscInt k = 0; k < geom->ninterfaces; k++) {
      kmin = PetscMin(kmin, PetscMin(model->kn[k], model->kt[k]));
      kmax = PetscMax(kmax, PetscMax(model->kn[k], model->kt[k]));
    }
    PetscCallMPI(MPIU_Allreduce(&kmin, &g[0], 1, MPIU_REAL, MPIU_MIN, mx->comm));
    PetscCallMPI(MPIU_Allreduce(&kmax, &g[1], 1, MPIU_REAL, MPIU_MAX, mx->comm));
    kmin = g[0];
    kmax = g[1];
    if (kmax > 1e12 * kmin)
      SETERRQ(mx->comm, PETSC_ERR_USER_INPUT, "the assembly is numerically singular (%s): either it is a mechanism, or its joint stiffnesses, from %.1e to %.1e N/m^3 (a contrast of %.0e), differ by more than double precision resolves (about 1e12): block%s %s (%" PetscInt_FMT " block%s) move without deforming any joint at that precision (smallest eigenvalue %.1e of the scaled stiffness, largest about %.1e); free motion: %s", how, (double)kmin, (double)kmax, (double)(kmax / kmin), nmove > 1 ? "s" : "", list, nmove, nmove > 1 ? "s" : "", (double)rho, (double)snorm, motion);
  }
  SETERRQ(mx->comm, PETSC_ERR_USER_INPUT, "the assembly is a mechanism (%s): block%s %s (%" PetscInt_FMT " block%s) can move without deforming any joint (smallest eigenvalue %.1e of the scaled stiffness, largest about %.1e); free motion: %s", how, nmove > 1 ? "s" : "", list, nmove, nmove > 1 ? "s" : "", (double)rho, (double)snorm, motion);
}
