/* Running-bond walls (interface.md, "Geometry the generators make" and
 * "running_bond additions").
 *
 * n = units_per_course (whole or half), unit l_u x h_u, joint thickness e,
 * half unit l_h = (l_u - e)/2; course k in y in [k (h_u+e), k (h_u+e) + h_u]:
 *   whole n:  L = n l_u + (n-1) e
 *             even courses: n full units from x = 0
 *             odd courses:  half unit, n-1 full units, half unit
 *   half n = N + 1/2:  L = N (l_u + e) + l_h
 *             even courses: N full units, then a half unit
 *             odd courses:  a half unit, then N full units
 *   foundation [0,L] x [-e-h_f, -e], top beam [0,L] x [y_top+e, y_top+e+h_b]
 * so every head joint sits over the middle of a unit below. Units whose
 * centroid lies in an opening (closed rectangle x0,y0,x1,y1) are left out.
 * With split_units every full unit is two blocks of length l_u/2 with no gap
 * between them, joined by an interface of kind `unit` (a potential crack).
 *
 * Interfaces come from the pattern itself, not from a search: head joints
 * join neighbours in a course (length h_u, n from left to right, theta =
 * -pi/2); bed joints join blocks of adjacent rows over their x-overlap, found
 * by one merge sweep of the two rows' sorted intervals (n upwards, theta = 0).
 * Everything is O(N). Interfaces are emitted sorted by (i, j).
 * Block order: foundation, courses bottom to top each from the left, top beam. */
#include "geometry/geometry.h"
#include "util/compat.h"
#include "util/log.h"

typedef struct {
  PetscInt  first, n;  /* block indices first..first+n-1, left to right */
  PetscReal y0, y1;    /* extent of the row */
  PetscReal *x0, *x1;  /* extents of its blocks */
} BwRow;

/* Bed joints between row `lo` (below) and row `hi` (above); collects the
 * interface as (i, j, x-centre, length) into the arrays. */
static PetscErrorCode BwBedJoints(const BwRow *lo, const BwRow *hi, PetscReal tol, PetscInt *nbed, PetscInt (*pair)[2], PetscReal (*geo)[2])
{
  PetscInt a = 0, b = 0;

  PetscFunctionBeginUser;
  while (a < lo->n && b < hi->n) {
    PetscReal x0 = PetscMax(lo->x0[a], hi->x0[b]), x1 = PetscMin(lo->x1[a], hi->x1[b]);
    if (x1 - x0 > tol) {
      pair[*nbed][0] = lo->first + a;
      pair[*nbed][1] = hi->first + b;
      geo[*nbed][0]  = 0.5 * (x0 + x1);
      geo[*nbed][1]  = x1 - x0;
      (*nbed)++;
    }
    if (lo->x1[a] < hi->x1[b]) a++;
    else b++;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

typedef struct {
  PetscInt  i, j;
  PetscReal G[2], angle, length;
  BwJointKind kind;
} BwPendingInterface;

static int BwPendingCompare(const void *pa, const void *pb)
{
  const BwPendingInterface *a = pa, *b = pb;
  if (a->i != b->i) return a->i < b->i ? -1 : 1;
  if (a->j != b->j) return a->j < b->j ? -1 : 1;
  return (a->G[0] > b->G[0]) - (a->G[0] < b->G[0]);
}

static PetscErrorCode BwRunningBondGenerate(BwGenerator gen, BwGeometry g, BwScene scene, PetscReal e);

typedef struct {
  PetscInt   courses, n, nopen; /* n: full units of a course (floor of units_per_course) */
  PetscBool  half;              /* units_per_course is n + 1/2 */
  PetscReal  units, lu, hu, hf, hb, *openings;
  PetscBool  foundation, top_beam, split;
} BwRunningBond;

static PetscErrorCode BwRunningBondSetFromOptions(BwGenerator gen, BwGeometry g, BwScene scene)
{
  BwRunningBond *o = (BwRunningBond *)gen->data;

  PetscFunctionBeginUser;
  PetscCall(BwSceneHelpSection(scene, "Running-bond wall (scene key geometry.running_bond.*)"));
  PetscCall(BwSceneRequireMapping(scene, "-geometry_running_bond", "courses, units_per_course, unit sizes, foundation, top beam, openings"));
  PetscCall(BwSceneInt(scene, "-geometry_running_bond_courses", "Number of courses", &o->courses, NULL));
  PetscCall(BwSceneReal(scene, "-geometry_running_bond_units_per_course", "Full units in a course that starts with one; a half-integer n adds a half unit at the course's end (even courses) or start (odd)", &o->units, NULL));
  PetscCall(BwSceneBool(scene, "-geometry_running_bond_split_units", "Every full unit is two half blocks joined by a potential crack (interface kind unit, law joints.unit)", &o->split, NULL));
  PetscCall(BwSceneReal(scene, "-geometry_running_bond_unit_length", "Unit length l_u [m]", &o->lu, NULL));
  PetscCall(BwSceneReal(scene, "-geometry_running_bond_unit_height", "Unit height h_u [m]", &o->hu, NULL));
  PetscCall(BwSceneBool(scene, "-geometry_running_bond_foundation", "One block under the whole bottom course", &o->foundation, NULL));
  PetscCall(BwSceneReal(scene, "-geometry_running_bond_foundation_height", "Foundation height h_f [m]", &o->hf, NULL));
  PetscCall(BwSceneBool(scene, "-geometry_running_bond_top_beam", "One block over the whole top course", &o->top_beam, NULL));
  PetscCall(BwSceneReal(scene, "-geometry_running_bond_top_beam_height", "Top beam height h_b [m]", &o->hb, NULL));
  PetscCall(BwSceneRealArray(scene, "-geometry_running_bond_openings", "Openings [[x0, y0, x1, y1], ...]: units whose centroid lies inside are left out [m]", &o->openings, &o->nopen, NULL));
  if (o->courses < 1) PetscCall(BwSceneError(scene, "-geometry_running_bond_courses", "must be >= 1, got %" PetscInt_FMT, o->courses));
  /* whole or half: 2n an integer (exactly, as written: 4.5 is exact in binary) */
  if (!(o->units >= 1) || o->units > 0.25 * (PetscReal)PETSC_MAX_INT || 2 * o->units != PetscFloorReal(2 * o->units)) PetscCall(BwSceneError(scene, "-geometry_running_bond_units_per_course", "must be a whole or half number >= 1 (e.g. 10 or 4.5), got %g", (double)o->units));
  o->n    = (PetscInt)PetscFloorReal(o->units);
  o->half = o->units != (PetscReal)o->n ? PETSC_TRUE : PETSC_FALSE;
  if (!(o->lu > 0)) PetscCall(BwSceneError(scene, "-geometry_running_bond_unit_length", "must be > 0, got %g", (double)o->lu));
  if (!(o->hu > 0)) PetscCall(BwSceneError(scene, "-geometry_running_bond_unit_height", "must be > 0, got %g", (double)o->hu));
  if (!(o->hf > 0)) PetscCall(BwSceneError(scene, "-geometry_running_bond_foundation_height", "must be > 0, got %g", (double)o->hf));
  if (!(o->hb > 0)) PetscCall(BwSceneError(scene, "-geometry_running_bond_top_beam_height", "must be > 0, got %g", (double)o->hb));
  if (o->nopen % 4) PetscCall(BwSceneError(scene, "-geometry_running_bond_openings", "must hold 4 numbers x0, y0, x1, y1 per opening, got %" PetscInt_FMT, o->nopen));
  o->nopen /= 4;
  for (PetscInt k = 0; k < o->nopen; k++) {
    const PetscReal *r = &o->openings[4 * k];
    if (!(r[2] > r[0] && r[3] > r[1])) PetscCall(BwSceneError(scene, "-geometry_running_bond_openings", "opening %" PetscInt_FMT " needs x0 < x1 and y0 < y1, got [%g, %g, %g, %g]", k, (double)r[0], (double)r[1], (double)r[2], (double)r[3]));
  }
  {
    /* indices are PetscInt: 4 per block must fit */
    PetscReal blocks = (PetscReal)o->courses * (PetscReal)(o->split ? 2 * o->n + 2 : o->n + 1) + 2;
    if (4 * blocks > (PetscReal)PETSC_MAX_INT) PetscCall(BwSceneError(scene, "-geometry_running_bond_courses", "and units_per_course ask for %.3g blocks; this PETSc's %d-bit indices allow at most %.3g", (double)blocks, (int)(8 * sizeof(PetscInt)), (double)PETSC_MAX_INT / 4));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwRunningBondDestroy(BwGenerator gen)
{
  BwRunningBond *o = (BwRunningBond *)gen->data;

  PetscFunctionBeginUser;
  PetscCall(PetscFree(o->openings));
  PetscCall(PetscFree(gen->data));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwGeneratorCreate_RunningBond(BwGenerator gen)
{
  BwRunningBond *o;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&o));
  o->courses          = 18;
  o->units            = 10;
  o->lu               = 0.21;
  o->hu               = 0.052;
  o->hf               = 0.1;
  o->hb               = 0.1;
  o->foundation       = PETSC_TRUE;
  o->top_beam         = PETSC_TRUE;
  gen->data           = o;
  gen->setfromoptions = BwRunningBondSetFromOptions;
  gen->generate       = BwRunningBondGenerate;
  gen->destroy        = BwRunningBondDestroy;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwRunningBondGenerate(BwGenerator gen, BwGeometry g, BwScene scene, PetscReal e)
{
  const BwRunningBond *o       = (BwRunningBond *)gen->data;
  const PetscInt       courses = o->courses, n = o->n, nopen = o->nopen;
  const PetscReal      lu = o->lu, hu = o->hu, hf = o->hf, hb = o->hb, *openings = o->openings;
  const PetscBool      foundation = o->foundation, top_beam = o->top_beam, split = o->split, halfn = o->half;
  /* blocks of one course at most: n+1 pieces, each full unit two with split */
  const PetscInt       rowmax = split ? 2 * n + 2 : n + 1;
  PetscInt             nrows, nunits = 0, nint = 0, maxint;
  PetscReal            L, half, tol;
  BwRow               *rows;
  BwPendingInterface  *pend;
  PetscReal           *xs0, *xs1;
  PetscBool           *splitnext; /* per row entry: its right neighbour is its unit's other half */
  PetscInt            *units, *bottom, *top, nbottom = 0, ntop = 0;

  PetscFunctionBeginUser;
  if (!(lu > e)) PetscCall(BwSceneError(scene, "-geometry_running_bond_unit_length", "must exceed the joint thickness %g so that half units (l_u - e)/2 exist, got %g", (double)e, (double)lu));
  {
    /* what the generator allocates, on every rank (the geometry is
     * replicated), before it allocates it: ~0.5 KB per block */
    PetscReal blocks = (PetscReal)courses * (PetscReal)rowmax + 2;
    char      what[256];
    PetscCall(PetscSNPrintf(what, sizeof(what), "geometry.running_bond: %" PetscInt_FMT " courses of %" PetscInt_FMT "%s units (%.3g blocks)", courses, n, halfn ? ".5" : "", (double)blocks));
    PetscCall(BwMemoryRequire(g->comm, blocks * 520.0, what));
  }
  half = 0.5 * (lu - e);
  L    = halfn ? n * (lu + e) + half : n * lu + (n - 1) * e;
  tol  = 1e-9 * lu;
  nrows = courses + (foundation ? 1 : 0) + (top_beam ? 1 : 0);
  PetscCall(PetscCalloc1(nrows, &rows));
  PetscCall(PetscMalloc3(courses * rowmax + 2, &xs0, courses * rowmax + 2, &xs1, courses * rowmax + 2, &splitnext));
  PetscCall(PetscMalloc3(courses * rowmax, &units, rowmax, &bottom, rowmax, &top));

  /* blocks, row by row */
  {
    PetscInt r = 0, used = 0;
    if (foundation) {
      rows[r].first    = g->nblocks;
      rows[r].n        = 1;
      rows[r].x0       = xs0 + used;
      rows[r].x1       = xs1 + used;
      rows[r].y0       = -e - hf;
      rows[r].y1       = -e;
      splitnext[used]  = PETSC_FALSE;
      xs0[used]        = 0;
      xs1[used++]      = L;
      PetscCall(BwGeometryAddRectangle(g, 0, -e - hf, L, -e, NULL));
      r++;
    }
    for (PetscInt k = 0; k < courses; k++, r++) {
      PetscReal y0 = k * (hu + e), y1 = y0 + hu;
      PetscBool odd = k % 2 ? PETSC_TRUE : PETSC_FALSE;
      /* pieces of the course, left to right; a half unit first in odd
       * courses, last in even courses of a half-integer n or odd courses of
       * a whole n; positions by formula, not accumulated, so that the same
       * wall is the same to the last bit */
      PetscInt  nu     = halfn ? n + 1 : (odd ? n + 1 : n);
      rows[r].first = g->nblocks;
      rows[r].x0    = xs0 + used;
      rows[r].x1    = xs1 + used;
      rows[r].y0    = y0;
      rows[r].y1    = y1;
      for (PetscInt p = 0; p < nu; p++) {
        PetscReal x0, x1;
        PetscBool open = PETSC_FALSE, full = PETSC_TRUE;
        if (odd && p == 0) {
          x0   = 0;
          x1   = half;
          full = PETSC_FALSE;
        } else if (p == nu - 1 && (halfn ? !odd : odd)) {
          x0   = L - half;
          x1   = L;
          full = PETSC_FALSE;
        } else if (odd) {
          x0 = half + e + (p - 1) * (lu + e);
          x1 = x0 + lu;
        } else {
          x0 = p * (lu + e);
          x1 = x0 + lu;
        }
        for (PetscInt q = 0; q < nopen && !open; q++) {
          const PetscReal *box = &openings[4 * q], cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
          open = (cx >= box[0] && cx <= box[2] && cy >= box[1] && cy <= box[3]) ? PETSC_TRUE : PETSC_FALSE;
        }
        if (open) continue;
        if (split && full) {
          /* the unit's two halves, no gap between them */
          const PetscReal xm = x0 + 0.5 * lu;
          const PetscReal piece[2][2] = {{x0, xm}, {xm, x1}};
          for (int h = 0; h < 2; h++) {
            splitnext[used] = h == 0 ? PETSC_TRUE : PETSC_FALSE;
            xs0[used]       = piece[h][0];
            xs1[used++]     = piece[h][1];
            units[nunits++] = g->nblocks;
            if (k == 0) bottom[nbottom++] = g->nblocks;
            if (k == courses - 1) top[ntop++] = g->nblocks;
            rows[r].n++;
            PetscCall(BwGeometryAddRectangle(g, piece[h][0], y0, piece[h][1], y1, NULL));
          }
          continue;
        }
        splitnext[used] = PETSC_FALSE;
        xs0[used]       = x0;
        xs1[used++]     = x1;
        units[nunits++] = g->nblocks;
        if (k == 0) bottom[nbottom++] = g->nblocks;
        if (k == courses - 1) top[ntop++] = g->nblocks;
        rows[r].n++;
        PetscCall(BwGeometryAddRectangle(g, x0, y0, x1, y1, NULL));
      }
    }
    if (top_beam) {
      PetscReal ytop = (courses - 1) * (hu + e) + hu;
      rows[r].first   = g->nblocks;
      rows[r].n       = 1;
      rows[r].x0      = xs0 + used;
      rows[r].x1      = xs1 + used;
      rows[r].y0      = ytop + e;
      rows[r].y1      = ytop + e + hb;
      splitnext[used] = PETSC_FALSE;
      xs0[used]       = 0;
      xs1[used++]     = L;
      PetscCall(BwGeometryAddRectangle(g, 0, ytop + e, L, ytop + e + hb, NULL));
    }
  }

  /* interfaces: head joints within courses, bed joints between rows */
  maxint = 3 * g->nblocks + 2 * (rowmax + 1);
  PetscCall(PetscMalloc1(maxint, &pend));
  {
    PetscInt (*pair)[2];
    PetscReal(*geo)[2];
    PetscCall(PetscMalloc2(2 * (rowmax + 1), &pair, 2 * (rowmax + 1), &geo));
    for (PetscInt r = 0; r < nrows; r++) {
      const BwRow *row = &rows[r];
      PetscBool    course = !((foundation && r == 0) || (top_beam && r == nrows - 1));
      if (course) {
        const PetscBool *next = splitnext + (row->x0 - xs0);
        for (PetscInt p = 0; p + 1 < row->n; p++) {
          /* the crack inside a split unit: zero thickness; else neighbours
           * only: a unit removed by an opening breaks the joint */
          PetscReal gap = next[p] ? 0 : e;
          if (!next[p] && PetscAbsReal(row->x0[p + 1] - row->x1[p] - e) > tol) continue;
          BwPendingInterface *f = &pend[nint++];
          f->i      = row->first + p;
          f->j      = row->first + p + 1;
          f->G[0]   = row->x1[p] + 0.5 * gap;
          f->G[1]   = 0.5 * (row->y0 + row->y1);
          f->angle  = -0.5 * PETSC_PI;
          f->length = hu;
          f->kind   = next[p] ? BW_JOINT_UNIT : BW_JOINT_HEAD;
        }
      }
      if (r + 1 < nrows) {
        PetscInt  nbed = 0;
        PetscReal ygap;
        PetscCall(BwBedJoints(row, &rows[r + 1], tol, &nbed, pair, geo));
        /* the gap between the rows, from the blocks' own coordinates */
        ygap = 0.5 * (row->y1 + rows[r + 1].y0);
        for (PetscInt q = 0; q < nbed; q++) {
          BwPendingInterface *f = &pend[nint++];
          f->i      = pair[q][0];
          f->j      = pair[q][1];
          f->G[0]   = geo[q][0];
          f->G[1]   = ygap;
          f->angle  = 0;
          f->length = geo[q][1];
          f->kind   = BW_JOINT_BED;
        }
      }
      PetscCheck(nint + 2 * (rowmax + 1) <= maxint, PETSC_COMM_SELF, PETSC_ERR_PLIB, "interface estimate exceeded");
    }
    PetscCall(PetscFree2(pair, geo));
  }
  qsort(pend, (size_t)nint, sizeof(*pend), BwPendingCompare);
  for (PetscInt f = 0; f < nint; f++) PetscCall(BwGeometryAddInterface(g, pend[f].i, pend[f].j, pend[f].G, pend[f].angle, pend[f].length, pend[f].kind));

  /* sets */
  if (foundation) {
    const PetscInt f0 = 0;
    PetscCall(BwGeometryAddSet(g, "foundation", 1, &f0));
  }
  if (top_beam) {
    const PetscInt tb = g->nblocks - 1;
    PetscCall(BwGeometryAddSet(g, "top_beam", 1, &tb));
  }
  PetscCall(BwGeometryAddSet(g, "bottom_course", nbottom, bottom));
  PetscCall(BwGeometryAddSet(g, "top_course", ntop, top));
  PetscCall(BwGeometryAddSet(g, "units", nunits, units));
  {
    PetscInt *all;
    PetscCall(PetscMalloc1(g->nblocks, &all));
    for (PetscInt b = 0; b < g->nblocks; b++) all[b] = b;
    PetscCall(BwGeometryAddSet(g, "all", g->nblocks, all));
    PetscCall(PetscFree(all));
  }
  PetscCall(PetscFree(pend));
  PetscCall(PetscFree3(units, bottom, top));
  PetscCall(PetscFree3(xs0, xs1, splitnext));
  PetscCall(PetscFree(rows));
  PetscFunctionReturn(PETSC_SUCCESS);
}
