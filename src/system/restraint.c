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

/* "3, 4, 9, ..." for the blocks b >= first with comp[b] == c. */
static PetscErrorCode BwBlockList(PetscInt nb, const PetscInt comp[], PetscInt c, PetscInt first, char list[], size_t len, PetscInt *count)
{
  PetscFunctionBeginUser;
  list[0] = 0;
  *count  = 0;
  for (PetscInt o = first; o < nb; o++) {
    if (comp[o] != c) continue;
    if (*count < 12) {
      char item[32];
      PetscCall(PetscSNPrintf(item, sizeof(item), "%s%" PetscInt_FMT, *count ? ", " : "", o));
      PetscCall(PetscStrlcat(list, item, len));
    } else if (*count == 12) PetscCall(PetscStrlcat(list, ", ...", len));
    (*count)++;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

typedef struct {
  PetscInt  first, nblocks, nfree, nrows, n[3];
  PetscReal x0, y0, area, xmin, xmax, ymin, ymax; /* centroid mean and box */
  PetscReal y1[2], x2[2];                         /* range of u1-prescribed y, u2-prescribed x */
} BwGroup;

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

/* 3D: the rigid motions (a, w) about a group's mean centroid x0 that its
 * prescribed dofs leave free, exactly: the null space of the constraint
 * rows (u_b = a + w x (c_b - x0) on a prescribed translation, w_c on a
 * prescribed rotation; w scaled by the group's size L so that the columns
 * weigh alike), from the 6 x 6 normal matrix. With m, m_b >= 2 every
 * interface has the full stiffness of model.md and a relative motion of
 * joined blocks strains it, so the check is exact; m = 1 or m_b = 1
 * leave hinges, which BwMixedCheckMechanism finds. */
static PetscErrorCode BwRestraintGroups3D(BwMixed mx, PetscInt ncomp, const PetscInt comp[], char motion[], size_t mlen, PetscErrorCode *ierr)
{
  BwGeometry geom = mx->geom;
  BwModel    model = mx->model;
  PetscInt   nb = geom->nblocks;
  PetscReal *x0, *lo, *hi, *M;
  PetscInt  *count, *nfix;
  char       list[512];

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc6(3 * ncomp, &x0, 3 * ncomp, &lo, 3 * ncomp, &hi, 36 * ncomp, &M, ncomp, &count, ncomp, &nfix));
  for (PetscInt c = 0; c < 3 * ncomp; c++) lo[c] = PETSC_MAX_REAL, hi[c] = PETSC_MIN_REAL;
  for (PetscInt b = 0; b < nb; b++) {
    const PetscReal *cb = &geom->centroid[3 * b];
    PetscInt         g  = comp[b];
    count[g]++;
    for (int c = 0; c < 3; c++) {
      x0[3 * g + c] += cb[c];
      lo[3 * g + c] = PetscMin(lo[3 * g + c], cb[c]);
      hi[3 * g + c] = PetscMax(hi[3 * g + c], cb[c]);
    }
  }
  for (PetscInt g = 0; g < ncomp; g++)
    for (int c = 0; c < 3; c++) x0[3 * g + c] /= count[g];
  for (PetscInt b = 0; b < nb; b++) {
    PetscInt  g = comp[b];
    PetscReal L = 0, r[3];
    for (int c = 0; c < 3; c++) L = PetscMax(L, hi[3 * g + c] - lo[3 * g + c]);
    L = PetscMax(L, BwGeometryBlockSize(geom, b));
    for (int c = 0; c < 3; c++) r[c] = (geom->centroid[3 * b + c] - x0[3 * g + c]) / L;
    for (int c = 0; c < 6; c++) {
      PetscReal row[6] = {0, 0, 0, 0, 0, 0};
      if (!model->prescribed[6 * b + c]) continue;
      nfix[g]++;
      if (c < 3) {
        /* (w x r)_c = sum_j eps_cjk w_j r_k; w' = w L */
        row[c]                 = 1;
        row[3 + (c + 1) % 3] = r[(c + 2) % 3];
        row[3 + (c + 2) % 3] = -r[(c + 1) % 3];
      } else row[c] = 1;
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) M[36 * g + 6 * i + j] += row[i] * row[j];
    }
  }
  *ierr = PETSC_SUCCESS;
  for (PetscInt g = 0; g < ncomp && !*ierr; g++) {
    PetscReal lam[6], V[36], lmax = 0, L = 0;
    PetscInt  nfree = 0, n, first = -1;
    char      what[1024] = "";

    for (PetscInt b = 0; b < nb && first < 0; b++)
      if (comp[b] == g) first = b;
    for (int c = 0; c < 3; c++) L = PetscMax(L, hi[3 * g + c] - lo[3 * g + c]);
    L = PetscMax(L, BwGeometryBlockSize(geom, first));
    BwJacobiEigen(6, &M[36 * g], lam, V);
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
        PetscCall(BwDescribeRigid3D(a, w, &x0[3 * g], L, one, sizeof(one)));
        if (nfree) PetscCall(PetscStrlcat(what, ", ", sizeof(what)));
        PetscCall(PetscStrlcat(what, one, sizeof(what)));
        nfree++;
      }
    }
    if (!nfree) continue;
    PetscCall(BwBlockList(nb, comp, g, first, list, sizeof(list), &n));
    *ierr = PETSC_ERR_USER_INPUT;
    if (!nfix[g]) PetscCall(PetscSNPrintf(motion, mlen, "the assembly is not restrained: block%s %s (%" PetscInt_FMT " block%s) %s no path of interfaces to a support; free motion: rigid translation and rotation", n > 1 ? "s" : "", list, n, n > 1 ? "s" : "", n > 1 ? "have" : "has"));
    else PetscCall(PetscSNPrintf(motion, mlen, "the assembly is not restrained: block%s %s (%" PetscInt_FMT " block%s) %s held only by %" PetscInt_FMT " prescribed dofs that leave %" PetscInt_FMT " rigid motion%s free; free motion: %s", n > 1 ? "s" : "", list, n, n > 1 ? "s" : "", n > 1 ? "are" : "is", nfix[g], nfree, nfree > 1 ? "s" : "", what));
  }
  PetscCall(PetscFree6(x0, lo, hi, M, count, nfix));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedCheckRestraint(BwMixed mx)
{
  BwGeometry geom = mx->geom;
  BwModel    model = mx->model;
  PetscInt   nb = geom->nblocks, *comp, *stack, ncomp = 0;
  BwGroup   *grp;
  char       list[512], motion[1536];
  PetscErrorCode ierr = PETSC_SUCCESS;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(nb, &comp, nb, &stack));
  for (PetscInt b = 0; b < nb; b++) comp[b] = -1;
  for (PetscInt b0 = 0; b0 < nb; b0++) {
    PetscInt top = 0;
    if (comp[b0] >= 0) continue;
    comp[b0]     = ncomp;
    stack[top++] = b0;
    while (top) {
      PetscInt b = stack[--top];
      for (PetscInt a = mx->adj_offsets[b]; a < mx->adj_offsets[b + 1]; a++) {
        PetscInt k = mx->adj[a], o = geom->pair[2 * k] == b ? geom->pair[2 * k + 1] : geom->pair[2 * k];
        if (comp[o] < 0) {
          comp[o]      = ncomp;
          stack[top++] = o;
        }
      }
    }
    ncomp++;
  }
  if (geom->dim == 3) {
    PetscCall(BwRestraintGroups3D(mx, ncomp, comp, motion, sizeof(motion), &ierr));
    PetscCall(PetscFree2(comp, stack));
    PetscCheck(!ierr, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s", motion);
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscCalloc1(ncomp, &grp));
  for (PetscInt c = 0; c < ncomp; c++) {
    grp[c].first = -1;
    grp[c].xmin = grp[c].ymin = grp[c].y1[0] = grp[c].x2[0] = PETSC_MAX_REAL;
    grp[c].xmax = grp[c].ymax = grp[c].y1[1] = grp[c].x2[1] = PETSC_MIN_REAL;
  }
  for (PetscInt b = 0; b < nb; b++) {
    BwGroup        *g  = &grp[comp[b]];
    const PetscReal cx = geom->centroid[2 * b], cy = geom->centroid[2 * b + 1];
    if (g->first < 0) g->first = b;
    g->nblocks++;
    g->x0 += cx;
    g->y0 += cy;
    g->area += geom->area[b];
    g->xmin = PetscMin(g->xmin, cx);
    g->xmax = PetscMax(g->xmax, cx);
    g->ymin = PetscMin(g->ymin, cy);
    g->ymax = PetscMax(g->ymax, cy);
    for (PetscInt c = 0; c < 3; c++) {
      if (!model->prescribed[3 * b + c]) {
        g->nfree++;
        continue;
      }
      g->n[c]++;
      if (c == 0) {
        g->y1[0] = PetscMin(g->y1[0], cy);
        g->y1[1] = PetscMax(g->y1[1], cy);
      } else if (c == 1) {
        g->x2[0] = PetscMin(g->x2[0], cx);
        g->x2[1] = PetscMax(g->x2[1], cx);
      }
    }
  }
  for (PetscInt k = 0; k < geom->ninterfaces; k++) {
    PetscInt  i = geom->pair[2 * k], j = geom->pair[2 * k + 1];
    PetscBool touches = PETSC_FALSE; /* a free dof: its 2 rows constrain something */
    for (PetscInt c = 0; c < 3; c++) touches = (PetscBool)(touches || !model->prescribed[3 * i + c] || !model->prescribed[3 * j + c]);
    if (touches) grp[comp[i]].nrows += 2;
  }

  /* 1. rigid motions of each group */
  for (PetscInt c = 0; c < ncomp && !ierr; c++) {
    BwGroup  *g = &grp[c];
    PetscReal size = PetscMax(PetscMax(g->xmax - g->xmin, g->ymax - g->ymin), PetscSqrtReal(g->area)), tol = 1e-9 * size;
    PetscBool tx = (PetscBool)(g->n[0] == 0), ty = (PetscBool)(g->n[1] == 0);
    PetscBool rot = (PetscBool)(g->n[2] == 0 && (g->n[0] == 0 || g->y1[1] - g->y1[0] <= tol) && (g->n[1] == 0 || g->x2[1] - g->x2[0] <= tol));
    PetscInt  count;

    if (!tx && !ty && !rot) continue;
    g->x0 /= g->nblocks;
    g->y0 /= g->nblocks;
    PetscCall(BwBlockList(nb, comp, c, g->first, list, sizeof(list), &count));
    if (tx && ty && rot) {
      ierr = PETSC_ERR_USER_INPUT;
      PetscCall(PetscSNPrintf(motion, sizeof(motion), "the assembly is not restrained: block%s %s (%" PetscInt_FMT " block%s) %s no path of interfaces to a support; free motion: rigid translation and rotation", count > 1 ? "s" : "", list, count, count > 1 ? "s" : "", count > 1 ? "have" : "has"));
      break;
    }
    {
      char what[256] = "";
      if (tx) PetscCall(PetscStrlcat(what, "translation along x (u1)", sizeof(what)));
      if (ty) PetscCall(PetscStrlcat(what, tx ? ", translation along y (u2)" : "translation along y (u2)", sizeof(what)));
      if (rot) {
        char r[128];
        PetscCall(PetscSNPrintf(r, sizeof(r), "%srotation about (%g, %g)", tx || ty ? ", " : "", (double)(g->n[1] ? g->x2[0] : g->x0), (double)(g->n[0] ? g->y1[0] : g->y0)));
        PetscCall(PetscStrlcat(what, r, sizeof(what)));
      }
      ierr = PETSC_ERR_USER_INPUT;
      PetscCall(PetscSNPrintf(motion, sizeof(motion), "the assembly is not restrained: block%s %s (%" PetscInt_FMT " block%s) %s held only by prescribed dofs (u1 on %" PetscInt_FMT ", u2 on %" PetscInt_FMT ", w on %" PetscInt_FMT " block%s) that leave a rigid motion free; free motion: %s", count > 1 ? "s" : "", list, count, count > 1 ? "s" : "", count > 1 ? "are" : "is", g->n[0], g->n[1], g->n[2], g->n[2] == 1 ? "" : "s", what));
    }
  }

  /* 2. hinges */
  if (!ierr && mx->m == 1) {
    for (PetscInt b = 0; b < nb && !ierr; b++) {
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
        PetscInt k = mx->adj[a0];
        ierr       = PETSC_ERR_USER_INPUT;
        PetscCall(PetscSNPrintf(motion, sizeof(motion), "the assembly is a mechanism: block %" PetscInt_FMT " is held only at G = (%g, %g) (interface %" PetscInt_FMT ", blocks %" PetscInt_FMT " and %" PetscInt_FMT "%s), and with discretization.m = 1 an interface carries no moment (a hinge); free motion: rotation of block %" PetscInt_FMT " about (%g, %g); use m >= 2", b, (double)P[0], (double)P[1], k, geom->pair[2 * k], geom->pair[2 * k + 1], a1 - a0 > 1 ? ", and others through the same point" : "", b, (double)P[0], (double)P[1]));
      }
    }
    for (PetscInt c = 0; c < ncomp && !ierr; c++) {
      BwGroup *g = &grp[c];
      PetscInt count;
      if (g->nfree <= g->nrows) continue;
      PetscCall(BwBlockList(nb, comp, c, g->first, list, sizeof(list), &count));
      ierr = PETSC_ERR_USER_INPUT;
      PetscCall(PetscSNPrintf(motion, sizeof(motion), "the assembly is a mechanism: with discretization.m = 1 an interface carries no moment (a hinge at its centre G), and block%s %s (%" PetscInt_FMT " block%s) %s %" PetscInt_FMT " free dofs against %" PetscInt_FMT " hinge constraints (2 per interface); free motion: at least %" PetscInt_FMT " independent rotations about the interfaces' centres; use m >= 2", count > 1 ? "s" : "", list, count, count > 1 ? "s" : "", count > 1 ? "have" : "has", g->nfree, g->nrows, g->nfree - g->nrows));
    }
  }
  PetscCall(PetscFree(grp));
  PetscCall(PetscFree2(comp, stack));
  PetscCheck(!ierr, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s", motion);
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
    PetscCall(PetscSNPrintf(buf, len, "block %" PetscInt_FMT " rotates about (%.6g, %.6g)", b, (double)P[0], (double)P[1]));
  } else {
    PetscReal l = PetscSqrtReal(q[0] * q[0] + q[1] * q[1]);
    PetscReal d[2] = {q[0] / l, q[1] / l};
    for (int c = 0; c < 2; c++)
      if (PetscAbsReal(d[c]) < 1e-8) d[c] = 0;
    PetscCall(PetscSNPrintf(buf, len, "block %" PetscInt_FMT " translates along (%.3g, %.3g)", b, (double)d[0], (double)d[1]));
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
  Vec                x, y, all;
  VecScatter         sct;
  PetscReal          snorm, rho, *q, mmax = 0;
  PetscScalar        dot;
  KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
  PetscInt           lo, hi, nb = geom->nblocks, nmove = 0, *moving, nd = mx->nd;
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

  /* the eigenvector in physical dofs, q = diag(S)^{-1/2} q~, on every rank */
  PetscCall(VecGetArray(x, &xa));
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt b = mx->own_blocks[e];
    for (PetscInt c = 0; c < nd && mx->qrow[b] >= 0; c++) xa[mx->qrow[b] + c - lo] *= mx->model->prescribed[nd * b + c] ? 0 : mx->qscale[nd * b + c];
  }
  PetscCall(VecRestoreArray(x, &xa));
  PetscCall(VecScatterCreateToAll(x, &sct, &all));
  PetscCall(VecScatterBegin(sct, x, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sct, x, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterDestroy(&sct));
  PetscCall(PetscMalloc2(nd * nb, &q, nb, &moving));
  PetscCall(VecGetArrayRead(all, &a));
  for (PetscInt b = 0; b < nb; b++) {
    for (PetscInt c = 0; c < nd; c++) q[nd * b + c] = mx->qrow[b] >= 0 ? PetscRealPart(a[mx->qrow[b] + c]) : 0;
    mmax = PetscMax(mmax, BwMotionSize(mx, b, &q[nd * b]));
  }
  PetscCall(VecRestoreArrayRead(all, &a));
  for (PetscInt b = 0; b < nb; b++)
    if (BwMotionSize(mx, b, &q[nd * b]) > 1e-3 * mmax) moving[nmove++] = b;
  for (PetscInt e = 0; e < PetscMin(nmove, 13); e++) {
    char item[32];
    PetscCall(PetscSNPrintf(item, sizeof(item), "%s%" PetscInt_FMT, e ? ", " : "", moving[e]));
    PetscCall(PetscStrlcat(list, e < 12 ? item : ", ...", sizeof(list)));
  }
  for (PetscInt e = 0; e < PetscMin(nmove, 5); e++) {
    char item[260];
    if (e == 4) PetscCall(PetscStrlcat(motion, ", ...", sizeof(motion)));
    else {
      if (nd == 6) {
        char what[200];
        PetscCall(BwDescribeRigid3D(&q[6 * moving[e]], &q[6 * moving[e] + 3], &geom->centroid[3 * moving[e]], BwGeometryBlockSize(geom, moving[e]), what, sizeof(what)));
        PetscCall(PetscSNPrintf(item, sizeof(item), "block %" PetscInt_FMT ": %s", moving[e], what));
      } else PetscCall(BwDescribeMotion(geom, moving[e], &q[3 * moving[e]], item, sizeof(item)));
      if (e) PetscCall(PetscStrlcat(motion, ", ", sizeof(motion)));
      PetscCall(PetscStrlcat(motion, item, sizeof(motion)));
    }
  }
  PetscCall(PetscFree2(q, moving));
  PetscCall(VecDestroy(&all));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&y));
  {
    /* Above a contrast of about 1e12 between joints, double precision no
     * longer separates a soft mode from a free one (measured: 1e13 random
     * and layered contrasts on a 6 x 4 wall read as mechanisms here, while a
     * real128 Cholesky factors them): the message says both. */
    BwModel   model = mx->model;
    PetscReal kmin = PETSC_MAX_REAL, kmax = 0;
    for (PetscInt k = 0; k < geom->ninterfaces; k++) {
      kmin = PetscMin(kmin, PetscMin(model->kn[k], model->kt[k]));
      kmax = PetscMax(kmax, PetscMax(model->kn[k], model->kt[k]));
    }
    if (kmax > 1e12 * kmin)
      SETERRQ(mx->comm, PETSC_ERR_USER_INPUT, "the assembly is numerically singular (%s): either it is a mechanism, or its joint stiffnesses, from %.1e to %.1e N/m^3 (a contrast of %.0e), differ by more than double precision resolves (about 1e12): block%s %s (%" PetscInt_FMT " block%s) move without deforming any joint at that precision (smallest eigenvalue %.1e of the scaled stiffness, largest about %.1e); free motion: %s", how, (double)kmin, (double)kmax, (double)(kmax / kmin), nmove > 1 ? "s" : "", list, nmove, nmove > 1 ? "s" : "", (double)rho, (double)snorm, motion);
  }
  SETERRQ(mx->comm, PETSC_ERR_USER_INPUT, "the assembly is a mechanism (%s): block%s %s (%" PetscInt_FMT " block%s) can move without deforming any joint (smallest eigenvalue %.1e of the scaled stiffness, largest about %.1e); free motion: %s", how, nmove > 1 ? "s" : "", list, nmove, nmove > 1 ? "s" : "", (double)rho, (double)snorm, motion);
}
