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
 * Interfaces are emitted sorted by (i, j). Each rank makes only its share
 * (BwRunningBondGenerate): O(N / ranks) blocks and interfaces, O(courses)
 * to count the rows.
 * Block order: foundation, courses bottom to top each from the left, top beam. */
#include "geometry/geometry.h"
#include "util/compat.h"
#include "util/log.h"

typedef struct {
  PetscInt   first, n;   /* global block ids first..first+n-1, left to right */
  PetscInt   course;     /* its course, -1 for the foundation and the top beam */
  PetscReal  y0, y1;     /* extent of the row */
  PetscReal *x0, *x1;    /* extents of its blocks */
  PetscBool *splitnext;  /* a block's right neighbour is its unit's other half */
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

/* Piece p (left to right) of course k: its extent and whether it is a full
 * unit. A half unit first in odd courses, last in even courses of a
 * half-integer n or odd courses of a whole n; positions by formula, not
 * accumulated, so that the same wall is the same to the last bit. */
static void BwCoursePiece(const BwRunningBond *o, PetscReal e, PetscReal L, PetscInt k, PetscInt p, PetscReal *x0, PetscReal *x1, PetscBool *full)
{
  const PetscReal lu = o->lu, half = 0.5 * (o->lu - e);
  const PetscBool odd = k % 2 ? PETSC_TRUE : PETSC_FALSE;
  const PetscInt  nu  = o->half ? o->n + 1 : (odd ? o->n + 1 : o->n);

  *full = PETSC_TRUE;
  if (odd && p == 0) {
    *x0   = 0;
    *x1   = half;
    *full = PETSC_FALSE;
  } else if (p == nu - 1 && (o->half ? !odd : odd)) {
    *x0   = L - half;
    *x1   = L;
    *full = PETSC_FALSE;
  } else if (odd) {
    *x0 = half + e + (p - 1) * (lu + e);
    *x1 = *x0 + lu;
  } else {
    *x0 = p * (lu + e);
    *x1 = *x0 + lu;
  }
}

static PetscInt BwCoursePieces(const BwRunningBond *o, PetscInt k)
{
  return o->half ? o->n + 1 : (k % 2 ? o->n + 1 : o->n);
}

/* Whether an opening leaves out the piece [x0, x1] of course k. */
static PetscBool BwInOpening(const BwRunningBond *o, PetscReal e, PetscInt k, PetscReal x0, PetscReal x1)
{
  const PetscReal y0 = k * (o->hu + e), cx = 0.5 * (x0 + x1), cy = y0 + 0.5 * o->hu;
  for (PetscInt q = 0; q < o->nopen; q++) {
    const PetscReal *box = &o->openings[4 * q];
    if (cx >= box[0] && cx <= box[2] && cy >= box[1] && cy <= box[3]) return PETSC_TRUE;
  }
  return PETSC_FALSE;
}

/* Blocks in course k: by formula, unless an opening spans its height, when
 * its pieces are counted one by one. */
static PetscInt BwCourseBlocks(const BwRunningBond *o, PetscReal e, PetscReal L, PetscInt k)
{
  const PetscInt  nu = BwCoursePieces(o, k), halves = o->half ? 1 : (k % 2 ? 2 : 0);
  const PetscReal cy = k * (o->hu + e) + 0.5 * o->hu;
  PetscBool       cut = PETSC_FALSE;
  PetscInt        n = 0;

  for (PetscInt q = 0; q < o->nopen && !cut; q++) cut = cy >= o->openings[4 * q + 1] && cy <= o->openings[4 * q + 3] ? PETSC_TRUE : PETSC_FALSE;
  if (!cut) return o->split ? nu + (nu - halves) : nu;
  for (PetscInt p = 0; p < nu; p++) {
    PetscReal x0, x1;
    PetscBool full;
    BwCoursePiece(o, e, L, k, p, &x0, &x1, &full);
    if (!BwInOpening(o, e, k, x0, x1)) n += o->split && full ? 2 : 1;
  }
  return n;
}

/* Row r's blocks (foundation, courses, top beam), with their global ids
 * from first. */
static PetscErrorCode BwRowBuild(const BwRunningBond *o, PetscReal e, PetscReal L, PetscInt r, PetscInt nrows, PetscInt first, BwRow *row)
{
  const PetscBool foundation = o->foundation, top_beam = o->top_beam;
  const PetscInt  courses = o->courses;

  PetscFunctionBeginUser;
  row->first  = first;
  row->n      = 0;
  row->course = -1;
  if (foundation && r == 0) {
    row->y0 = -e - o->hf;
    row->y1 = -e;
    PetscCall(PetscMalloc3(1, &row->x0, 1, &row->x1, 1, &row->splitnext));
    row->x0[0]        = 0;
    row->x1[0]        = L;
    row->splitnext[0] = PETSC_FALSE;
    row->n            = 1;
  } else if (top_beam && r == nrows - 1) {
    PetscReal ytop = (courses - 1) * (o->hu + e) + o->hu;
    row->y0        = ytop + e;
    row->y1        = ytop + e + o->hb;
    PetscCall(PetscMalloc3(1, &row->x0, 1, &row->x1, 1, &row->splitnext));
    row->x0[0]        = 0;
    row->x1[0]        = L;
    row->splitnext[0] = PETSC_FALSE;
    row->n            = 1;
  } else {
    const PetscInt k = r - (foundation ? 1 : 0), nu = BwCoursePieces(o, k), most = o->split ? 2 * nu : nu;
    row->course = k;
    row->y0     = k * (o->hu + e);
    row->y1     = row->y0 + o->hu;
    PetscCall(PetscMalloc3(most, &row->x0, most, &row->x1, most, &row->splitnext));
    for (PetscInt p = 0; p < nu; p++) {
      PetscReal x0, x1;
      PetscBool full;
      BwCoursePiece(o, e, L, k, p, &x0, &x1, &full);
      if (BwInOpening(o, e, k, x0, x1)) continue;
      if (o->split && full) {
        /* the unit's two halves, no gap between them */
        const PetscReal xm = x0 + 0.5 * o->lu;
        row->x0[row->n]          = x0;
        row->x1[row->n]          = xm;
        row->splitnext[row->n++] = PETSC_TRUE;
        row->x0[row->n]          = xm;
        row->x1[row->n]          = x1;
        row->splitnext[row->n++] = PETSC_FALSE;
      } else {
        row->x0[row->n]          = x0;
        row->x1[row->n]          = x1;
        row->splitnext[row->n++] = PETSC_FALSE;
      }
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwRowFree(BwRow *row)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree3(row->x0, row->x1, row->splitnext));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* This rank's share (geometry.h): the blocks of its range of global ids
 * [b0, b1) (rows are numbered bottom to top, so a range is a band of
 * courses), the interfaces whose first (lower) block is in it, from its
 * rows and the row above, and its members of the sets. Rows are counted
 * by formula (one by one only where an opening spans a course), so a rank
 * builds only its own rows. */
static PetscErrorCode BwRunningBondGenerate(BwGenerator gen, BwGeometry g, BwScene scene, PetscReal e)
{
  const BwRunningBond *o       = (BwRunningBond *)gen->data;
  const PetscInt       courses = o->courses, n = o->n;
  const PetscBool      foundation = o->foundation, top_beam = o->top_beam, halfn = o->half;
  const PetscInt       nrows = courses + (foundation ? 1 : 0) + (top_beam ? 1 : 0);
  PetscInt            *rowfirst, N, b0, b1, rlo, rhi, nint = 0, maxint = 0;
  PetscReal            L, half, tol;
  BwRow               *rows;
  BwPendingInterface  *pend = NULL;

  PetscFunctionBeginUser;
  if (!(o->lu > e)) PetscCall(BwSceneError(scene, "-geometry_running_bond_unit_length", "must exceed the joint thickness %g so that half units (l_u - e)/2 exist, got %g", (double)e, (double)o->lu));
  half = 0.5 * (o->lu - e);
  L    = halfn ? n * (o->lu + e) + half : n * o->lu + (n - 1) * e;
  tol  = 1e-9 * o->lu;
  /* global ids: rows' first blocks */
  PetscCall(PetscMalloc1(nrows + 1, &rowfirst));
  rowfirst[0] = 0;
  for (PetscInt r = 0; r < nrows; r++) {
    PetscInt nb = (foundation && r == 0) || (top_beam && r == nrows - 1) ? 1 : BwCourseBlocks(o, e, L, r - (foundation ? 1 : 0));
    rowfirst[r + 1] = rowfirst[r] + nb;
  }
  N = rowfirst[nrows];
  BwGeometrySplit(g->comm, N, &b0, &b1);
  {
    /* what this rank allocates, before it allocates it: ~0.5 KB per block */
    char what[256];
    PetscCall(PetscSNPrintf(what, sizeof(what), "geometry.running_bond: %" PetscInt_FMT " courses of %" PetscInt_FMT "%s units (%" PetscInt_FMT " blocks, %" PetscInt_FMT " on this rank)", courses, n, halfn ? ".5" : "", N, b1 - b0));
    PetscCall(BwMemoryRequire(g->comm, (PetscReal)(b1 - b0) * 520.0, what));
  }
  /* the rows holding [b0, b1) */
  for (rlo = 0; rlo < nrows && rowfirst[rlo + 1] <= b0; rlo++) { }
  for (rhi = rlo; rhi < nrows && rowfirst[rhi + 1] < b1; rhi++) { }
  if (b1 <= b0) rhi = rlo - 1; /* an empty share */
  PetscCall(PetscCalloc1(nrows + 1, &rows));
  for (PetscInt r = rlo; r <= rhi + 1 && r < nrows; r++) PetscCall(BwRowBuild(o, e, L, r, nrows, rowfirst[r], &rows[r]));

  /* blocks */
  for (PetscInt r = rlo; r <= rhi; r++)
    for (PetscInt p = 0; p < rows[r].n; p++) {
      PetscInt id = rows[r].first + p;
      if (id < b0 || id >= b1) continue;
      PetscCall(BwGeometryAddRectangle(g, rows[r].x0[p], rows[r].y0, rows[r].x1[p], rows[r].y1, NULL));
    }
  PetscCall(BwGeometrySetShare(g, b1 - b0));
  PetscCheck(g->block_start == b0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "running_bond: share starts at %" PetscInt_FMT ", not %" PetscInt_FMT, g->block_start, b0);

  /* interfaces whose first block is ours: head joints within our rows,
   * bed joints from our rows up */
  for (PetscInt r = rlo; r <= rhi; r++) maxint += 3 * rows[r].n + 2 + (r + 1 < nrows ? 2 * rows[r + 1].n + 2 : 0);
  PetscCall(PetscMalloc1(maxint + 1, &pend));
  {
    PetscInt (*pair)[2] = NULL;
    PetscReal(*geo)[2]  = NULL;
    PetscInt  most      = 0;
    for (PetscInt r = rlo; r <= rhi; r++) most = PetscMax(most, rows[r].n + (r + 1 < nrows ? rows[r + 1].n : 0) + 1);
    PetscCall(PetscMalloc2(most + 1, &pair, most + 1, &geo));
    for (PetscInt r = rlo; r <= rhi; r++) {
      const BwRow *row = &rows[r];
      if (row->course >= 0) {
        for (PetscInt p = 0; p + 1 < row->n; p++) {
          /* the crack inside a split unit: zero thickness; else neighbours
           * only: a unit removed by an opening breaks the joint */
          PetscReal           gap = row->splitnext[p] ? 0 : e;
          BwPendingInterface *f;
          if (row->first + p < b0 || row->first + p >= b1) continue;
          if (!row->splitnext[p] && PetscAbsReal(row->x0[p + 1] - row->x1[p] - e) > tol) continue;
          f         = &pend[nint++];
          f->i      = row->first + p;
          f->j      = row->first + p + 1;
          f->G[0]   = row->x1[p] + 0.5 * gap;
          f->G[1]   = 0.5 * (row->y0 + row->y1);
          f->angle  = -0.5 * PETSC_PI;
          f->length = o->hu;
          f->kind   = row->splitnext[p] ? BW_JOINT_UNIT : BW_JOINT_HEAD;
        }
      }
      if (r + 1 < nrows) {
        PetscInt  nbed = 0;
        PetscReal ygap;
        PetscCall(BwBedJoints(row, &rows[r + 1], tol, &nbed, pair, geo));
        /* the gap between the rows, from the blocks' own coordinates */
        ygap = 0.5 * (row->y1 + rows[r + 1].y0);
        for (PetscInt q = 0; q < nbed; q++) {
          BwPendingInterface *f;
          if (pair[q][0] < b0 || pair[q][0] >= b1) continue;
          f         = &pend[nint++];
          f->i      = pair[q][0];
          f->j      = pair[q][1];
          f->G[0]   = geo[q][0];
          f->G[1]   = ygap;
          f->angle  = 0;
          f->length = geo[q][1];
          f->kind   = BW_JOINT_BED;
        }
      }
      PetscCheck(nint <= maxint, PETSC_COMM_SELF, PETSC_ERR_PLIB, "interface estimate exceeded");
    }
    PetscCall(PetscFree2(pair, geo));
  }
  qsort(pend, (size_t)nint, sizeof(*pend), BwPendingCompare);
  for (PetscInt f = 0; f < nint; f++) PetscCall(BwGeometryAddInterface(g, pend[f].i, pend[f].j, pend[f].G, pend[f].angle, pend[f].length, pend[f].kind));
  {
    PetscInt total;
    PetscCallMPI(MPIU_Allreduce(&nint, &total, 1, MPIU_INT, MPI_SUM, g->comm));
    g->ninterfaces_global = total;
  }

  /* sets: every rank names them all; its members are its range's */
  {
    PetscInt *units, *bottom, *top, *all, nu = 0, nbot = 0, ntop = 0, nall = 0, f0 = 0, tb = N - 1;
    PetscCall(PetscMalloc4(b1 - b0 + 1, &units, b1 - b0 + 1, &bottom, b1 - b0 + 1, &top, b1 - b0 + 1, &all));
    for (PetscInt r = rlo; r <= rhi; r++)
      for (PetscInt p = 0; p < rows[r].n; p++) {
        PetscInt id = rows[r].first + p;
        if (id < b0 || id >= b1) continue;
        all[nall++] = id;
        if (rows[r].course < 0) continue;
        units[nu++] = id;
        if (rows[r].course == 0) bottom[nbot++] = id;
        if (rows[r].course == courses - 1) top[ntop++] = id;
      }
    if (foundation) PetscCall(BwGeometryAddSet(g, "foundation", f0 >= b0 && f0 < b1 ? 1 : 0, &f0));
    if (top_beam) PetscCall(BwGeometryAddSet(g, "top_beam", tb >= b0 && tb < b1 ? 1 : 0, &tb));
    PetscCall(BwGeometryAddSet(g, "bottom_course", nbot, bottom));
    PetscCall(BwGeometryAddSet(g, "top_course", ntop, top));
    PetscCall(BwGeometryAddSet(g, "units", nu, units));
    PetscCall(BwGeometryAddSet(g, "all", nall, all));
    PetscCall(PetscFree4(units, bottom, top, all));
  }
  for (PetscInt r = 0; r < nrows; r++)
    if (rows[r].x0) PetscCall(BwRowFree(&rows[r]));
  PetscCall(PetscFree(rows));
  PetscCall(PetscFree(pend));
  PetscCall(PetscFree(rowfirst));
  PetscFunctionReturn(PETSC_SUCCESS);
}
