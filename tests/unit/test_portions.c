/* The portions of 3D interfaces (src/system/portions.c, model.md "Three
 * dimensions": the m x m_b grid of equal cells of the polygon's bounding
 * box, cell intersections above 1e-9 A, t index fastest), against closed
 * forms:
 *   rectangle  an l_t x l_b rectangle gives the kernel's equal cells
 *              (bw_kernel_rectangle_portions) to 1e-15
 *   triangle   a triangle about its centroid, m = m_b = 1..32: areas sum to
 *              A and first moments to zero (1e-13), every portion inside
 *              the triangle; the second moment sum A_p xi_p^2 tends to the
 *              triangle's (error falling as the cells shrink); a right
 *              triangle on a 2 x 2 grid has 3 portions (the fourth cell
 *              meets it in a point), numbered t fastest
 *   share      equal polygons one after the other share one layout
 *   polygons   the portions' polygons (BwPortionsPolygons3D) of a hexagon
 *              on a 5 x 3 grid: their shoelace areas and centroids are the
 *              portions' (1e-14), every vertex lies inside the hexagon and
 *              inside its portion's cell of the bounding box (1e-15), the
 *              areas sum to the hexagon's; a polygon that is not the
 *              layout's (another count of portions) is an error */
#include <string.h>
#include <math.h>
#include <petscsys.h>
#include "system/portions.h"
#include "blockwall/kernels.h"
#include "util/compat.h"
#include "util/process.h"

static int failures = 0;

static void expect_close(const char *what, double got, double want, double tol, double scale)
{
  double err = fabs(got - want) / (scale > 0 ? scale : 1);
  if (!(err <= tol)) {
    printf("FAIL %s: got %.17g, want %.17g (relative error %.3e > %.1e)\n", what, got, want, err, tol);
    failures++;
  }
}

static PetscErrorCode TestRectangle(void)
{
  const PetscReal lt = 0.3, lb = 0.12, poly[8] = {-lt / 2, -lb / 2, lt / 2, -lb / 2, lt / 2, lb / 2, -lt / 2, lb / 2};
  const PetscInt  off[2] = {0, 4};
  double          area[15], xi[15], eta[15];
  int             st;
  BwPortions      P;

  PetscFunctionBeginUser;
  PetscCall(BwPortionsCreate3D(1, off, poly, 5, 3, &P));
  bw_kernel_rectangle_portions(5, 3, lt, lb, area, xi, eta, &st);
  if (BwPortionsCount(&P, 0) != 15) printf("FAIL rectangle: %d portions, want 15\n", (int)BwPortionsCount(&P, 0)), failures++;
  for (PetscInt p = 0; p < 15 && p < BwPortionsCount(&P, 0); p++) {
    expect_close("rectangle area", P.area[p], area[p], 1e-14, area[p]);
    expect_close("rectangle xi", P.xi[p], xi[p], 1e-15, lt);
    expect_close("rectangle eta", P.eta[p], eta[p], 1e-15, lb);
  }
  PetscCall(BwPortionsDestroy(&P));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode TestTriangle(void)
{
  /* vertices (0,0), (0.4,0), (0.1,0.3), moved to their centroid */
  const PetscReal v[6] = {0, 0, 0.4, 0, 0.1, 0.3}, cx = 0.5 / 3, cy = 0.1, A = 0.5 * 0.4 * 0.3;
  PetscReal       poly[6];
  const PetscInt  off[2] = {0, 3};
  /* the triangle's integral of xi^2 about its centroid: A/6 (a^2 + b^2 +
   * c^2 + ab + bc + ca), a, b, c the vertices' xi from the centroid */
  PetscReal x[3], Ieta, prev = PETSC_MAX_REAL;

  PetscFunctionBeginUser;
  for (int a = 0; a < 3; a++) {
    poly[2 * a]     = v[2 * a] - cx;
    poly[2 * a + 1] = v[2 * a + 1] - cy;
    x[a]            = poly[2 * a];
  }
  Ieta = A / 6 * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + x[0] * x[1] + x[1] * x[2] + x[2] * x[0]);
  for (PetscInt m = 1; m <= 32; m *= 2) {
    BwPortions P;
    PetscReal  sa = 0, sx = 0, se = 0, sxx = 0;
    PetscCall(BwPortionsCreate3D(1, off, poly, m, m, &P));
    for (PetscInt p = 0; p < BwPortionsCount(&P, 0); p++) {
      PetscReal l0, l1, l2, X = P.xi[p] + cx, Y = P.eta[p] + cy;
      sa += P.area[p];
      sx += P.area[p] * P.xi[p];
      se += P.area[p] * P.eta[p];
      sxx += P.area[p] * P.xi[p] * P.xi[p];
      if (!(P.area[p] > 1e-9 * A)) printf("FAIL triangle: portion %d of area %g\n", (int)p, (double)P.area[p]), failures++;
      /* inside: barycentric coordinates of the portion's centroid */
      l1 = ((X - 0) * 0.3 - (Y - 0) * 0.1) / (0.4 * 0.3);
      l2 = Y / 0.3;
      l0 = 1 - l1 - l2;
      if (l0 < -1e-12 || l1 < -1e-12 || l2 < -1e-12) printf("FAIL triangle: portion %d's centroid outside\n", (int)p), failures++;
    }
    expect_close("triangle: sum of areas", sa, A, 1e-13, A);
    expect_close("triangle: first moment xi", sx, 0, 1e-13, A * 0.4);
    expect_close("triangle: first moment eta", se, 0, 1e-13, A * 0.3);
    if (m > 1 && !(fabs(sxx - Ieta) < prev)) printf("FAIL triangle: second moment error %g did not fall (was %g)\n", fabs(sxx - Ieta), prev), failures++;
    if (m == 32 && !(fabs(sxx - Ieta) < 2e-3 * Ieta)) printf("FAIL triangle: second moment %g vs Ieta %g at m = 32\n", sxx, Ieta), failures++;
    prev = fabs(sxx - Ieta);
    PetscCall(BwPortionsDestroy(&P));
  }
  {
    const PetscReal right[6] = {-1.0 / 3, -1.0 / 3, 2.0 / 3, -1.0 / 3, -1.0 / 3, 2.0 / 3};
    BwPortions      P;
    PetscCall(BwPortionsCreate3D(1, off, right, 2, 2, &P));
    if (BwPortionsCount(&P, 0) != 3) printf("FAIL right triangle on 2 x 2: %d portions, want 3\n", (int)BwPortionsCount(&P, 0)), failures++;
    else if (!(P.xi[1] > P.xi[0] && P.eta[2] > P.eta[0])) printf("FAIL right triangle: portions not numbered t fastest\n"), failures++;
    PetscCall(BwPortionsDestroy(&P));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode TestShare(void)
{
  const PetscReal sq[8] = {-1, -1, 1, -1, 1, 1, -1, 1}, poly[24] = {-1, -1, 1, -1, 1, 1, -1, 1, -1, -1, 1, -1, 1, 1, -1, 1, -2, -1, 2, -1, 2, 1, -2, 1};
  const PetscInt  off[4] = {0, 4, 8, 12};
  BwPortions      P;

  PetscFunctionBeginUser;
  (void)sq;
  PetscCall(BwPortionsCreate3D(3, off, poly, 4, 2, &P));
  if (P.nlayouts != 2 || P.layout[0] != P.layout[1] || P.layout[2] == P.layout[1]) printf("FAIL share: %d layouts (%d %d %d)\n", (int)P.nlayouts, (int)P.layout[0], (int)P.layout[1], (int)P.layout[2]), failures++;
  PetscCall(BwPortionsDestroy(&P));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode TestPolygons(void)
{
  /* a convex hexagon, counter-clockwise, about the origin */
  const PetscReal hex[12] = {-0.5, -0.2, 0.1, -0.35, 0.45, -0.05, 0.4, 0.25, -0.1, 0.3, -0.55, 0.1}, box[4] = {-0.55, -0.35, 0.45, 0.3};
  const PetscReal tri[6]  = {-0.5, -0.3, 0.5, -0.3, 0, 0.3};
  const PetscInt  off[2] = {0, 6}, m = 5, mb = 3;
  PetscInt        voff[16], nexpect = 0;
  PetscReal       verts[2 * (6 + 4) * 15], A = 0, sum = 0;
  BwPortions      P;

  PetscFunctionBeginUser;
  for (int v = 0; v < 6; v++) A += 0.5 * (hex[2 * v] * hex[(2 * v + 3) % 12] - hex[(2 * v + 2) % 12] * hex[2 * v + 1]);
  PetscCall(BwPortionsCreate3D(1, off, hex, m, mb, &P));
  PetscCall(BwPortionsPolygons3D(&P, 0, voff, verts));
  for (PetscInt p = 0; p < BwPortionsCount(&P, 0); p++) {
    PetscInt  n = voff[p + 1] - voff[p], i = -1, j = -1;
    PetscReal a = 0, cx = 0, cy = 0, *x = verts + 2 * voff[p];
    for (PetscInt v = 0; v < n; v++) {
      PetscReal *s = x + 2 * v, *t = x + 2 * ((v + 1) % n), cr = s[0] * t[1] - t[0] * s[1];
      a += 0.5 * cr;
      cx += (s[0] + t[0]) * cr / 6;
      cy += (s[1] + t[1]) * cr / 6;
      for (int e = 0; e < 6; e++) {
        const PetscReal *h = hex + 2 * e, *k = hex + (2 * e + 2) % 12;
        if ((k[0] - h[0]) * (s[1] - h[1]) - (k[1] - h[1]) * (s[0] - h[0]) < -1e-15) printf("FAIL polygons: portion %d's vertex %d outside the hexagon\n", (int)p, (int)v), failures++;
      }
    }
    expect_close("polygons: area", a, P.area[p], 1e-14, P.area[p]);
    expect_close("polygons: centroid xi", cx / a, P.xi[p], 1e-14, 1);
    expect_close("polygons: centroid eta", cy / a, P.eta[p], 1e-14, 1);
    /* its cell: the one its centroid is in; every vertex within that cell */
    i = (PetscInt)floor((P.xi[p] - box[0]) / (box[2] - box[0]) * m);
    j = (PetscInt)floor((P.eta[p] - box[1]) / (box[3] - box[1]) * mb);
    for (PetscInt v = 0; v < n; v++) {
      PetscReal X = (x[2 * v] - box[0]) / (box[2] - box[0]) * m, Y = (x[2 * v + 1] - box[1]) / (box[3] - box[1]) * mb;
      if (X < i - 1e-15 || X > i + 1 + 1e-15 || Y < j - 1e-15 || Y > j + 1 + 1e-15) printf("FAIL polygons: portion %d's vertex %d outside its cell (%d, %d)\n", (int)p, (int)v, (int)i, (int)j), failures++;
    }
    sum += a;
    nexpect++;
  }
  expect_close("polygons: sum of areas", sum, A, 1e-14, A);
  if (nexpect < 12) printf("FAIL polygons: only %d portions\n", (int)nexpect), failures++;
  {
    /* The same shape given twice, off by round-off (the second hexagon
     * 2^-50 larger), in either order, and a triangle: two layouts, the
     * hexagons' the portions of whichever came first, bit for bit (so the
     * layout gives the members of a class one polygon: layout.c) */
    PetscReal      two[2 * 15], other[2 * 15];
    const PetscInt off3[4] = {0, 6, 12, 15};
    BwPortions     Q[2];
    for (int v = 0; v < 12; v++) two[v] = hex[v], two[12 + v] = hex[v] * (1 + PetscPowReal(2.0, -50));
    for (int v = 0; v < 6; v++) two[24 + v] = tri[v];
    for (int v = 0; v < 12; v++) other[v] = two[12 + v], other[12 + v] = two[v];
    for (int v = 0; v < 6; v++) other[24 + v] = tri[v];
    PetscCall(BwPortionsCreate3D(3, off3, two, m, mb, &Q[0]));
    PetscCall(BwPortionsCreate3D(3, off3, other, m, mb, &Q[1]));
    for (int q = 0; q < 2; q++)
      if (Q[q].nlayouts != 2 || Q[q].layout[0] != Q[q].layout[1]) printf("FAIL polygons: %d layouts for two hexagons and a triangle (order %d)\n", (int)Q[q].nlayouts, q), failures++;
    {
      PetscInt n = BwPortionsCount(&P, 0), f = BwPortionsFirst(&Q[0], 0);
      if (BwPortionsCount(&Q[0], 0) != n || memcmp(Q[0].area + f, P.area, sizeof(PetscReal) * n) || memcmp(Q[0].xi + f, P.xi, sizeof(PetscReal) * n)) printf("FAIL polygons: the class's portions are not its first polygon's\n"), failures++;
    }
    PetscCall(BwPortionsDestroy(&Q[0]));
    PetscCall(BwPortionsDestroy(&Q[1]));
  }
  PetscCall(BwPortionsDestroy(&P));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  const char *which;
  int         ran = 0;

  BwProcessDefaults(); /* the libraries run as under blockwall */

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  which = argc > 1 ? argv[1] : "all";
  if (!strcmp(which, "rectangle") || !strcmp(which, "all")) {
    PetscCall(TestRectangle());
    ran++;
  }
  if (!strcmp(which, "triangle") || !strcmp(which, "all")) {
    PetscCall(TestTriangle());
    ran++;
  }
  if (!strcmp(which, "share") || !strcmp(which, "all")) {
    PetscCall(TestShare());
    ran++;
  }
  if (!strcmp(which, "polygons") || !strcmp(which, "all")) {
    PetscCall(TestPolygons());
    ran++;
  }
  if (!ran) { /* a mistyped case name must not pass having checked nothing */
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL unknown case %s\n", which));
    failures++;
  }
  printf("%s: %s\n", which, failures ? "FAILED" : "passed");
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
