/* The pushover analysis (analysis.type: pushover): the constant loads
 * first (step 0, lambda = 0), then a load pattern times a growing
 * multiplier lambda, to a target, in equal increments cut in halves where
 * Newton fails (interface.md, "Pushover"):
 *
 *   analysis.pushover.loads        the pattern P: set -> [F1, F2, M3]
 *                                  (3D: [F1, F2, F3, M1, M2, M3])
 *   analysis.pushover.body_force   [a1, a2] (3D: [a1, a2, a3]): adds a times
 *                                  every block's weight to P (needs
 *                                  gravity.density > 0); along X3 with
 *                                  gravity held, the tilting table
 *   analysis.pushover.control      load: lambda prescribed per step;
 *                                  displacement: the monitor dof prescribed,
 *                                  lambda an unknown (newton.h)
 *   analysis.pushover.monitor      {set, dof}: that dof of the set's first block
 *                                  (u1, u2, w; 3D: u1, u2, u3, w1, w2, w3)
 *   analysis.pushover.target       final lambda (load) or monitor value
 *   analysis.pushover.steps        equal increments to the target
 *   analysis.pushover.min_step     smallest cut-back, a fraction of one increment
 *   analysis.pushover.tolerance    Newton: relative true residual
 *   analysis.pushover.max_iterations
 *   analysis.pushover.on_reversal  stop (default) | continue
 *   output.steps                   last | all | every_N
 *
 * After a failed step the increment is halved; after two successes in a
 * row it doubles again, up to the nominal one. The run ends when the target
 * is reached, or when no state beyond the last converged one is found even
 * with the smallest increment: under load control the collapse, under
 * displacement control the end of what it can follow, or (on_reversal:
 * stop) at the first step past the peak whose lambda has changed sign, the
 * collapse under held loads (stop_reason says which). Every converged state is a step of the history (cut-backs add
 * steps); only converged states are written. */
#include <string.h>
#include "analysis/analysis.h"
#include "analysis/newton.h"
#include "analysis/capacity.h"
#include "util/compat.h"

/* Steps after an energy cut-back whose energy may not grow (BwPushoverSteps).
 * Measured on examples/j4d_cap.yaml, j6d.yaml and j7d.yaml with 500, 600
 * or 800, and 700 or 900 steps, OpenBLAS and the reference BLAS, on an
 * Intel Xeon (2026-11-26): with 4, 15 of the 18 runs reached their target
 * (12 without the hold) and J4D with the cap took 0 to 12 % fewer Newton
 * iterations; which runs stop depends on round-off (bench/results.md). */
#define BW_PUSHOVER_HOLD 4

/* IMPL-EX: `steps` sets its largest increment (one nominal increment of
 * the monitor, also under dissipation control, whose energy steps aim at
 * two: an IMPL-EX step's error grows with its length, and its steps cost a
 * solve each on a kept factor); cut steps add to them, up to this many
 * times `steps` in all. */
#define BW_PUSHOVER_IMPLEX_MOST 20
#define BW_PUSHOVER_IMPLEX_SHORTEST 16
#define BW_PUSHOVER_IMPLEX_CUTS 2

typedef enum { BW_CONTROL_LOAD = 0, BW_CONTROL_DISPLACEMENT = 1, BW_CONTROL_DISSIPATION = 2 } BwControl;
static const char *const BwControls[] = {"load", "displacement", "dissipation"};

/* The solution scheme of the steps: Newton with the consistent tangent;
 * IMPL-EX (joint_field.h), every step one linear solve on the elastic
 * matrix with the plastic jumps extrapolated, cut where its error exceeds
 * implex_tolerance; auto, Newton until dissipation control can follow the
 * path no further (a stall where many portions swap between softening and
 * unloading), then IMPL-EX from that converged state to the end. */
typedef enum { BW_SCHEME_AUTO = 0, BW_SCHEME_NEWTON = 1, BW_SCHEME_IMPLEX = 2 } BwScheme;
static const char *const BwSchemes[] = {"auto", "newton", "implex"};

typedef struct {
  BwControl  control;
  PetscReal *pattern; /* nd per block */
  PetscInt   monitor_block, monitor_dof;
  char       monitor_set[256];
  PetscReal  target, min_step, tolerance;
  PetscReal  dissipation_step; /* the first energy per step under dissipation control; 0: from the first step that dissipates */
  PetscInt   steps, max_iterations;
  PetscInt   every; /* output.steps: 0 last, 1 all, N every N-th */
  PetscBool  stop_on_reversal; /* analysis.pushover.on_reversal: stop (default) | continue */
  BwScheme   scheme;           /* analysis.pushover.scheme */
  PetscReal  implex_tolerance; /* IMPL-EX: the largest error a step keeps (above it the step is cut) */
} BwPushover;

/* The first converged step past the peak whose lambda has the other sign
 * than the largest |lambda| before it (lambda * lambda_peak <= 0,
 * lambda_peak != 0), -1 if none: where the assembly no longer carries the
 * held loads (interface.md, additions of 2026-11-26). */
static PetscInt BwReversalStep(PetscInt n, const PetscReal lambda[])
{
  PetscInt big = 0;
  for (PetscInt s = 1; s < n; s++) {
    if (lambda[big] != 0 && lambda[s] * lambda[big] <= 0) return s;
    if (PetscAbsReal(lambda[s]) > PetscAbsReal(lambda[big])) big = s;
  }
  return -1;
}

static PetscErrorCode BwPushoverSetFromOptions(BwAnalysis a, BwProblem *p)
{
  BwPushover *po = (BwPushover *)a->data;
  BwGeometry  g  = p->geom;
  PetscReal  *bf = NULL;
  PetscInt    nbf = 0, control = 0, dof = -1, set = -1, local = -1;
  PetscBool   given, has_target, has_monitor;
  char        steps[64] = "last", dofname[16] = "", doflist[64] = "";
  const PetscInt            nd = p->model->nd, ndim = g->dim;
  const char *const        *dofs = BwModelDofNames(p->model);

  PetscFunctionBeginUser;
  PetscCall(BwAnalysisSolverForJoints(p));
  PetscCall(BwSolverSetExpectedSolves(p->solver, 100));
  PetscCall(BwSceneHelpSection(p->scene, "Pushover (scene key analysis.pushover.*)"));
  PetscCall(BwSceneRequireMapping(p->scene, "-analysis_pushover", "loads, body_force, control, monitor, target, steps, min_step, tolerance, max_iterations, dissipation_step, on_reversal, scheme, implex_tolerance"));
  /* the pattern */
  for (PetscInt c = 0; c < nd; c++) {
    PetscCall(PetscStrlcat(doflist, c ? (c == nd - 1 ? " or " : ", ") : "", sizeof(doflist)));
    PetscCall(PetscStrlcat(doflist, dofs[c], sizeof(doflist)));
  }
  PetscCall(PetscCalloc1(nd * g->nblocks + 1, &po->pattern));
  PetscCall(BwModelReadLoads(p->model, p->scene, "analysis_pushover_", PETSC_FALSE, po->pattern));
  PetscCall(BwSceneRealArray(p->scene, "-analysis_pushover_body_force", ndim == 3 ? "a1, a2, a3: adds lambda (a1, a2, a3) times every block's weight to the pattern (a3 with gravity held: the tilting table)" : "a1, a2: adds lambda (a1, a2) times every block's weight to the pattern", &bf, &nbf, &given));
  if (given) {
    if (nbf != ndim) PetscCall(BwSceneError(p->scene, "-analysis_pushover_body_force", "must have %" PetscInt_FMT " values %s in %" PetscInt_FMT "D, got %" PetscInt_FMT, ndim, ndim == 3 ? "a1, a2, a3" : "a1, a2", ndim, nbf));
    if (!(p->model->gravity_density > 0)) PetscCall(BwSceneError(p->scene, "-analysis_pushover_body_force", "needs the blocks' weight: gravity.density must be > 0"));
    for (PetscInt b = 0; b < g->nblocks; b++) {
      PetscReal w = p->model->gravity_density * 9.81 * (ndim == 3 ? g->volume[b] : g->area[b] * g->depth);
      for (PetscInt c = 0; c < ndim; c++) po->pattern[nd * b + c] += bf[c] * w;
    }
  }
  PetscCall(PetscFree(bf));
  {
    PetscReal norm = 0, all;
    for (PetscInt i = 0; i < nd * g->nblocks; i++) norm = PetscMax(norm, PetscAbsReal(po->pattern[i]));
    PetscCallMPI(MPIU_Allreduce(&norm, &all, 1, MPIU_REAL, MPIU_MAX, p->comm));
    norm = all;
    if (!(norm > 0)) PetscCall(BwSceneError(p->scene, "-analysis_pushover_loads", "the load pattern is zero: give analysis.pushover.loads or analysis.pushover.body_force"));
  }
  /* control and monitor */
  PetscCall(BwSceneEnum(p->scene, "-analysis_pushover_control", "load (lambda prescribed per step), displacement (the monitor dof prescribed, lambda unknown) or dissipation (displacement control while the joints are elastic, then the energy dissipated per step prescribed: follows snap-backs)", 3, BwControls, &control, NULL));
  po->control = (BwControl)control;
  {
    static const char *const on_reversal[] = {"stop", "continue"};
    PetscInt                 choice        = 0;
    PetscCall(BwSceneEnum(p->scene, "-analysis_pushover_on_reversal", "Past the peak, a load factor of the other sign than its largest means the assembly no longer carries the held loads (collapse): stop there (default) or continue to the target or the most steps", 2, on_reversal, &choice, NULL));
    po->stop_on_reversal = choice == 0 ? PETSC_TRUE : PETSC_FALSE;
  }
  {
    PetscInt choice = 0;
    PetscCall(BwSceneEnum(p->scene, "-analysis_pushover_scheme", "auto (Newton; under dissipation control IMPL-EX from where Newton can follow the path no further), newton (the consistent tangent throughout) or implex (each step one linear solve with the plastic jumps extrapolated: no portion chooses a mode inside a step)", 3, BwSchemes, &choice, NULL));
    po->scheme = (BwScheme)choice;
  }
  po->implex_tolerance = 0.05;
  PetscCall(BwSceneReal(p->scene, "-analysis_pushover_implex_tolerance", "IMPL-EX: the largest error a step keeps, a portion's stress against the return mapping's relative to the largest stress (cut below it, down to min_step)", &po->implex_tolerance, NULL));
  if (!(po->implex_tolerance > 0 && po->implex_tolerance < 1)) PetscCall(BwSceneError(p->scene, "-analysis_pushover_implex_tolerance", "must be in (0, 1), got %g", (double)po->implex_tolerance));
  po->dissipation_step = 0;
  PetscCall(BwSceneReal(p->scene, "-analysis_pushover_dissipation_step", "control: dissipation: the energy dissipated per step at first [J] (adapted to Newton's iterations); default: what the first dissipating step dissipated", &po->dissipation_step, &given));
  if (given && !(po->dissipation_step > 0)) PetscCall(BwSceneError(p->scene, "-analysis_pushover_dissipation_step", "must be > 0 [J], got %g", (double)po->dissipation_step));
  if (given && po->control != BW_CONTROL_DISSIPATION) PetscCall(BwSceneError(p->scene, "-analysis_pushover_dissipation_step", "needs analysis.pushover.control: dissipation (the control is %s)", BwControls[po->control]));
  PetscCall(BwSceneRequireMapping(p->scene, "-analysis_pushover_monitor", "set, dof"));
  PetscCall(BwSceneString(p->scene, "-analysis_pushover_monitor_set", "Block set whose first block carries the monitor dof", po->monitor_set, sizeof(po->monitor_set), &has_monitor));
  PetscCall(BwSceneString(p->scene, "-analysis_pushover_monitor_dof", "The monitor dof: u1, u2 or w (3D: u1, u2, u3, w1, w2 or w3)", dofname, sizeof(dofname), &given));
  if (has_monitor) {
    char names[1024];
    PetscCall(BwGeometryFindSet(g, po->monitor_set, &set));
    PetscCall(BwGeometryGetSetNames(g, names, sizeof(names)));
    if (set < 0) PetscCall(BwSceneError(p->scene, "-analysis_pushover_monitor_set", "'%s' does not name a block set (sets: %s)", po->monitor_set, names));
    if (!g->setsize_global[set]) PetscCall(BwSceneError(p->scene, "-analysis_pushover_monitor_set", "set '%s' is empty", po->monitor_set));
    PetscCall(BwGeometrySetFirst(g, set, &po->monitor_block, &local));
    if (!given) PetscCall(BwSceneError(p->scene, "-analysis_pushover_monitor", "needs dof: %s", doflist));
  } else if (given) PetscCall(BwSceneError(p->scene, "-analysis_pushover_monitor", "needs set: the block set whose first block is followed"));
  if (given) {
    for (PetscInt c = 0; c < nd; c++) {
      PetscBool eq;
      PetscCall(PetscStrcasecmp(dofname, dofs[c], &eq));
      if (eq) dof = c;
    }
    if (dof < 0) PetscCall(BwSceneError(p->scene, "-analysis_pushover_monitor_dof", "must be %s in %" PetscInt_FMT "D, got '%s'", doflist, ndim, dofname));
    po->monitor_dof = dof;
  }
  if (!has_monitor) {
    /* load control may do without: the largest component of the pattern */
    PetscReal best = -1;
    if (po->control != BW_CONTROL_LOAD) PetscCall(BwSceneError(p->scene, "-analysis_pushover_monitor", "is required with control: %s (monitor: {set: SET, dof: %s})", BwControls[po->control], doflist));
    /* over the owned blocks of every rank, the first (lowest global dof)
     * of the largest: a free dof, else (every block dof prescribed:
     * nothing moves, the monitor reads its prescribed value) any */
    for (int pass = 0; pass < 2 && best < 0; pass++) {
      struct {
        double value;
        int    index;
      } mine = {-1, 0}, all;
      for (PetscInt b = 0; b < g->nown_blocks; b++)
        for (PetscInt c = 0; c < nd; c++) {
          PetscReal v = PetscAbsReal(po->pattern[nd * b + c]);
          if ((pass || !p->model->prescribed[nd * b + c]) && v > mine.value) {
            mine.value = v;
            mine.index = (int)(nd * g->gblock[b] + c);
          }
        }
      PetscCallMPI(MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE_INT, MPI_MAXLOC, p->comm));
      best = all.value;
      if (best >= 0) {
        po->monitor_block = all.index / nd;
        po->monitor_dof   = all.index % nd;
      }
    }
    PetscCall(PetscSNPrintf(po->monitor_set, sizeof(po->monitor_set), "block %" PetscInt_FMT, po->monitor_block));
  }
  if (has_monitor) {
    PetscBool bad = local >= 0 && p->model->prescribed[nd * local + po->monitor_dof] ? PETSC_TRUE : PETSC_FALSE;
    PetscCall(BwSceneErrorAgree(p->scene, bad, "-analysis_pushover_monitor", "dof %s of block %" PetscInt_FMT " (set %s) is prescribed by the supports; the monitor must be free", dofs[po->monitor_dof], po->monitor_block, po->monitor_set));
  }
  /* the increments */
  po->target = 0;
  PetscCall(BwSceneReal(p->scene, "-analysis_pushover_target", "Final lambda (control: load) or final monitor value [m or rad] (control: displacement)", &po->target, &has_target));
  if (!has_target) PetscCall(BwSceneError(p->scene, "-analysis_pushover_target", "is required: the final lambda (load control) or monitor value (displacement control)"));
  if (po->control == BW_CONTROL_LOAD && !(po->target > 0)) PetscCall(BwSceneError(p->scene, "-analysis_pushover_target", "must be > 0 under load control, got %g", (double)po->target));
  if (po->control == BW_CONTROL_DISSIPATION && !(po->target != 0)) PetscCall(BwSceneError(p->scene, "-analysis_pushover_target", "must not be 0 under dissipation control: the monitor value where the run ends"));
  po->steps = 100;
  PetscCall(BwSceneInt(p->scene, "-analysis_pushover_steps", "Equal increments to the target", &po->steps, NULL));
  if (po->steps < 1) PetscCall(BwSceneError(p->scene, "-analysis_pushover_steps", "must be >= 1, got %" PetscInt_FMT, po->steps));
  po->min_step = 1e-3;
  PetscCall(BwSceneReal(p->scene, "-analysis_pushover_min_step", "Smallest cut-back, a fraction of one increment", &po->min_step, NULL));
  if (!(po->min_step > 0 && po->min_step <= 1)) PetscCall(BwSceneError(p->scene, "-analysis_pushover_min_step", "must be in (0, 1], got %g", (double)po->min_step));
  po->tolerance = 1e-8;
  PetscCall(BwSceneReal(p->scene, "-analysis_pushover_tolerance", "Newton: relative true residual of the full mixed system", &po->tolerance, NULL));
  if (!(po->tolerance > 0 && po->tolerance < 1)) PetscCall(BwSceneError(p->scene, "-analysis_pushover_tolerance", "must be in (0, 1), got %g", (double)po->tolerance));
  po->max_iterations = 40;
  PetscCall(BwSceneInt(p->scene, "-analysis_pushover_max_iterations", "Newton iterations per step", &po->max_iterations, NULL));
  if (po->max_iterations < 1) PetscCall(BwSceneError(p->scene, "-analysis_pushover_max_iterations", "must be >= 1, got %" PetscInt_FMT, po->max_iterations));
  /* output.steps */
  PetscCall(BwSceneString(p->scene, "-output_steps", "Steps written under /steps: last, all or every_N", steps, sizeof(steps), NULL));
  if (!strcmp(steps, "last")) po->every = 0;
  else if (!strcmp(steps, "all")) po->every = 1;
  else {
    char *end = NULL;
    long  n   = strncmp(steps, "every_", 6) ? 0 : strtol(steps + 6, &end, 10);
    if (!(n >= 1 && end && !*end && n < PETSC_MAX_INT)) PetscCall(BwSceneError(p->scene, "-output_steps", "must be last, all or every_N with N >= 1, got '%s'", steps));
    po->every = (PetscInt)n;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The history, on every rank (replicated: a few numbers per step). */
typedef struct {
  PetscInt   n, max;
  PetscReal *lambda, *monitor, *residual, *dissipation;
  PetscInt  *its;
} BwHistory;

/* on_reversal: stop ends the run at the step where lambda changed sign past
 * its peak (both schemes' steps call it after adding the step) */
static PetscErrorCode BwPushoverStopAtReversal(const BwPushover *po, const BwHistory *h, PetscInt step, PetscReal lambda, char stop[], size_t len)
{
  PetscFunctionBeginUser;
  if (po->stop_on_reversal && BwReversalStep(h->n, h->lambda) == step)
    PetscCall(PetscSNPrintf(stop, len, "the load factor changed sign past its peak: lambda %.6g at step %" PetscInt_FMT ", the assembly no longer carries the held loads (collapse; analysis.pushover.on_reversal: continue goes on)", (double)lambda, step));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* dissipation: the energy the step dissipated (accumulated here) */
static PetscErrorCode BwHistoryAdd(BwHistory *h, PetscReal lambda, PetscReal monitor, PetscInt its, PetscReal residual, PetscReal dissipation)
{
  PetscFunctionBeginUser;
  if (h->n == h->max) {
    h->max = PetscMax(64, 2 * h->max);
    PetscCall(PetscRealloc(h->max * sizeof(PetscReal), &h->lambda));
    PetscCall(PetscRealloc(h->max * sizeof(PetscReal), &h->monitor));
    PetscCall(PetscRealloc(h->max * sizeof(PetscReal), &h->residual));
    PetscCall(PetscRealloc(h->max * sizeof(PetscInt), &h->its));
    PetscCall(PetscRealloc(h->max * sizeof(PetscReal), &h->dissipation));
  }
  h->dissipation[h->n] = (h->n ? h->dissipation[h->n - 1] : 0) + dissipation;
  h->lambda[h->n]   = lambda;
  h->monitor[h->n]  = monitor;
  h->its[h->n]      = its;
  h->residual[h->n] = residual;
  h->n++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwHistoryFree(BwHistory *h)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(h->lambda));
  PetscCall(PetscFree(h->monitor));
  PetscCall(PetscFree(h->residual));
  PetscCall(PetscFree(h->its));
  PetscCall(PetscFree(h->dissipation));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The committed state's results (physical) and what the output needs. */
static PetscErrorCode BwPushoverResults(BwProblem *p, BwNewton nw, PetscReal lambda, PetscReal load[], BwResults *res, BwOutputData *data)
{
  Vec          x;
  BwJointField field;
  PetscReal   *plastic;

  PetscFunctionBeginUser;
  PetscCall(BwNewtonGetSolution(nw, &x, &field));
  PetscCall(BwNewtonGetLoads(nw, 1.0, lambda, load));
  PetscCall(BwMixedRecover(p->mixed, x, load, p->output->stresses, res));
  PetscCall(BwJointFieldGetState(field, &data->state, &plastic));
  data->plastic = plastic;
  data->results = res;
  data->load    = load;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwPushoverWriteStep(BwProblem *p, BwNewton nw, BwOutputFile of, PetscInt step, PetscReal lambda, PetscReal load[])
{
  BwResults    res  = {NULL, NULL, NULL, NULL, NULL, NULL};
  BwOutputData data = {p->mixed, NULL, NULL, NULL, NULL, NULL, NULL, NULL};

  PetscFunctionBeginUser;
  PetscCall(BwPushoverResults(p, nw, lambda, load, &res, &data));
  PetscCall(BwOutputWriteStep(of, step, &data));
  PetscCall(BwResultsFree(&res));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* What the IMPL-EX steps did: the first step they made (-1: none), how
 * many were kept and cut, the largest error kept, the largest true
 * residual of the mixed system with the return-mapped stresses. */
typedef struct {
  PetscInt  from_step, steps, cut;
  PetscReal error_max, residual_max;
  char      why[512]; /* auto: why Newton handed over */
} BwImplexStats;

/* IMPL-EX steps from the committed state to the target (joint_field.h):
 * each step is one linear solve on the elastic matrix (its factor kept
 * from step to step) under the control's constraint, with the portions'
 * plastic jumps extrapolated from the last step's rates; then every
 * portion is return-mapped at the solved jumps (the implicit update: the
 * state committed, the rates of the next step), and the difference of the
 * two stresses is the step's error. A step whose error exceeds
 * implex_tolerance is made again shorter (to 0.8 tol/error of itself, at
 * least 0.1, not below min_step of an increment), twice at most; after a
 * kept step the next is scaled by 0.8 tol/error (at most 2), between
 * 1/BW_PUSHOVER_IMPLEX_SHORTEST and one increment (target/steps, under
 * dissipation control too).
 * Nothing in a step is decided by an iteration: no branch is chosen by
 * round-off (a wall whose cracks localise still amplifies a perturbation
 * by its own instability, and a cut decided the other way moves the later
 * steps: docs/nonlinear.md). Under dissipation control the monitor is prescribed (the
 * energy constraint needs the iteration the scheme avoids): a snap-back
 * shows as a drop of lambda within a step. */
static PetscErrorCode BwPushoverImplexSteps(BwAnalysis a, BwProblem *p, BwNewton nw, BwOutputFile of, BwHistory *h, PetscReal mon0, PetscReal *lambda_io, PetscReal load[], BwImplexStats *st, char stop[], size_t len)
{
  BwPushover *po  = (BwPushover *)a->data;
  PetscReal   inc = 1.0 / po->steps, dt = inc, lambda = *lambda_io, t;
  PetscInt    cuts = 0;
  const char *reason;

  PetscFunctionBeginUser;
  t = po->control == BW_CONTROL_LOAD ? lambda / po->target : (h->monitor[h->n - 1] - mon0) / (po->target - mon0);
  if (st->from_step < 0) st->from_step = h->n;
  while (t < 1 - 1e-12 && !stop[0]) {
    PetscReal tn = PetscMin(1.0, t + dt), span, goal, lam = lambda, err = 0, res_true = 0;
    PetscBool ok;
    if (1 - tn < 1e-9 * inc) tn = 1;
    span = tn - t;
    goal = po->control == BW_CONTROL_LOAD ? tn * po->target : mon0 + tn * (po->target - mon0);
    if (po->control == BW_CONTROL_LOAD) lam = goal;
    PetscCall(BwNewtonSetExtrapolation(nw, PETSC_TRUE, span));
    PetscCall(BwNewtonSolve(nw, 1.0, &lam, po->control == BW_CONTROL_LOAD ? PETSC_FALSE : PETSC_TRUE, goal, &ok));
    if (ok) PetscCall(BwNewtonImplicitUpdate(nw, &err, &res_true, &ok));
    if (!ok) {
      PetscCall(BwNewtonGetResult(nw, NULL, NULL, &reason));
      PetscCall(PetscSNPrintf(stop, len, "an IMPL-EX step from monitor = %.6g failed (%s)", (double)h->monitor[h->n - 1], reason));
      break;
    }
    if (err > po->implex_tolerance && cuts < BW_PUSHOVER_IMPLEX_CUTS && span > po->min_step * inc * (1 + 1e-9)) {
      /* the step again, shorter: a portion that starts to flow overshoots
       * its strength by what the step's length decides. At most twice: the
       * error of a portion that flows already also carries the last step's
       * correction, which no shorter step removes (J7D: cut to min_step
       * step after step). The decision is the error against the tolerance
       * only (no count of portions, no mode), so two runs whose errors
       * differ by round-off decide alike unless an error sits on the
       * tolerance to round-off. */
      st->cut++;
      cuts++;
      dt = PetscMax(po->min_step * inc, span * PetscMax(0.1, 0.8 * po->implex_tolerance / err));
      if (p->log->verbose) PetscCall(PetscPrintf(p->comm, "  step %4" PetscInt_FMT ": IMPL-EX error %.3e, cut to %.3g of an increment\n", h->n, (double)err, (double)(dt / inc)));
      continue;
    }
    cuts = 0;
    {
      PetscInt  its, step = h->n;
      PetscReal res, mon, work, dissipated;
      PetscCall(BwNewtonCommit(nw));
      PetscCall(BwNewtonGetResult(nw, &its, &res, NULL));
      PetscCall(BwNewtonMonitorValue(nw, &mon));
      PetscCall(BwNewtonGetStepEnergy(nw, &work, &dissipated));
      lambda = lam;
      t      = tn;
      st->steps++;
      st->error_max    = PetscMax(st->error_max, err);
      st->residual_max = PetscMax(st->residual_max, res_true);
      PetscCall(BwHistoryAdd(h, lambda, mon, its, res, dissipated));
      if (p->log->verbose) PetscCall(PetscPrintf(p->comm, "  step %4" PetscInt_FMT ": lambda %12.5e, monitor %12.5e, IMPL-EX error %.2e (residual with the return-mapped stresses %.1e), dissipated %.3e\n", step, (double)lambda, (double)mon, (double)err, (double)res_true, (double)dissipated));
      if (po->every >= 1 && step % po->every == 0) PetscCall(BwPushoverWriteStep(p, nw, of, step, lambda, load));
      if (step >= BW_PUSHOVER_IMPLEX_MOST * po->steps && t < 1 - 1e-12) PetscCall(PetscSNPrintf(stop, len, "the most steps taken (%d x analysis.pushover.steps = %" PetscInt_FMT ") before the monitor reached the target: IMPL-EX's error kept its steps short (implex_tolerance)", BW_PUSHOVER_IMPLEX_MOST, BW_PUSHOVER_IMPLEX_MOST * po->steps));
      PetscCall(BwPushoverStopAtReversal(po, h, step, lambda, stop, len));
      dt = PetscMin(inc, span * PetscMin(2.0, 0.8 * po->implex_tolerance / PetscMax(err, PETSC_SMALL)));
      dt = PetscMax(dt, inc / BW_PUSHOVER_IMPLEX_SHORTEST);
    }
  }
  PetscCall(BwNewtonSetExtrapolation(nw, PETSC_FALSE, 0));
  *lambda_io = lambda;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwPushoverSteps(BwAnalysis a, BwProblem *p, BwNewton nw, BwOutputFile of, BwHistory *h, PetscReal *lambda_out, BwImplexStats *ist, char stop[], size_t len)
{
  BwPushover *po = (BwPushover *)a->data;
  PetscReal   t = 0, inc = 1.0 / po->steps, hc = inc, lambda = 0, mon0 = 0, load_mon;
  PetscInt    good = 0, substeps, returns = 0, over = 0, hold = 0;
  PetscBool   ok, dissipating = PETSC_FALSE, implex = po->scheme == BW_SCHEME_IMPLEX ? PETSC_TRUE : PETSC_FALSE;
  PetscReal   tau_failed = 0;
  PetscReal   tau = po->dissipation_step, tau_min = 0, tau_max = 0, totalwork = 0;
  /* the path length of a step, ds = sqrt(dmon^2 + (dlambda/k0)^2), with k0
   * the first step's secant stiffness (lambda per monitor): one nominal
   * displacement increment du is the length an energy step aims at when
   * dissipation_step does not fix the energy per step */
  PetscReal   k0 = 0, du = PetscAbsReal(po->target) / po->steps;
  PetscReal  *load;
  const char *reason = "";

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(p->model->nd * p->geom->nblocks + 1, &load));
  /* step 0: the constant loads */
  PetscCall(BwNewtonRamp(nw, po->min_step, &substeps, &ok));
  if (!ok) {
    PetscCall(BwNewtonGetResult(nw, NULL, NULL, &reason));
    PetscCall(PetscFree(load));
    SETERRQ(p->comm, PETSC_ERR_NOT_CONVERGED, "the constant loads (loads, gravity) cannot be carried by the joints: no equilibrium was found for them even in steps of %g of their value (%s)", (double)po->min_step, reason);
  }
  {
    PetscInt  its;
    PetscReal res;
    PetscCall(BwNewtonGetResult(nw, &its, &res, NULL));
    PetscCall(BwNewtonMonitorValue(nw, &mon0));
    PetscCall(BwHistoryAdd(h, 0, mon0, its, res, 0)); /* counted from here: the constant loads' own dissipation is not */
  }
  if (po->every >= 1) PetscCall(BwPushoverWriteStep(p, nw, of, 0, 0, load));
  (void)load_mon;
  /* energy steps aim at twice the nominal increment: the path in
   * (monitor, lambda/k0) is longer than the monitor's way to the target
   * (sqrt(2) on the elastic branch) and a snap-back adds to it, while
   * `steps` is also the most steps taken; at one increment a run never
   * reached its target within them (examples/j4d_cap.yaml: 3.85 of 4 mm
   * in 1400 steps) */
  du = 2 * PetscAbsReal(po->target - mon0) / po->steps;

  while (t < 1 - 1e-12 && !stop[0]) {
    PetscReal tn = t, lam = lambda, goal, work = 0, dissipated = 0, plastic = 0;
    PetscBool by_energy = po->control == BW_CONTROL_DISSIPATION && dissipating ? PETSC_TRUE : PETSC_FALSE;
    if (implex) break; /* IMPL-EX from here (below) */
    if (by_energy) PetscCall(BwNewtonSolveDissipation(nw, &lam, tau, &ok));
    else {
      if (po->control == BW_CONTROL_DISSIPATION) t = (h->monitor[h->n - 1] - mon0) / (po->target - mon0); /* from where energy control left it */
      tn = PetscMin(1.0, t + hc);
      if (1 - tn < 1e-9 * inc) tn = 1;
      goal = po->control == BW_CONTROL_LOAD ? tn * po->target : mon0 + tn * (po->target - mon0);
      if (po->control == BW_CONTROL_LOAD) lam = goal;
      PetscCall(BwNewtonSolve(nw, 1.0, &lam, po->control == BW_CONTROL_LOAD ? PETSC_FALSE : PETSC_TRUE, goal, &ok));
    }
    if (ok) {
      PetscInt  its, step;
      PetscReal res, mon;
      PetscCall(BwNewtonCommit(nw));
      PetscCall(BwNewtonGetResult(nw, &its, &res, NULL));
      PetscCall(BwNewtonMonitorValue(nw, &mon));
      PetscCall(BwNewtonGetStepEnergy(nw, &work, &dissipated));
      PetscCall(BwNewtonGetStepPlasticWork(nw, &plastic));
      lambda     = lam;
      step       = h->n;
      over       = 0;
      tau_failed = 0;
      PetscCall(BwHistoryAdd(h, lambda, mon, its, res, dissipated));
      if (p->log->verbose) PetscCall(PetscPrintf(p->comm, "  step %4" PetscInt_FMT ": lambda %12.5e, monitor %12.5e, %2" PetscInt_FMT " Newton iterations, residual %.1e%s, dissipated %.3e\n", step, (double)lambda, (double)mon, its, (double)res, by_energy ? " (energy control)" : "", (double)dissipated));
      if (po->every >= 1 && step % po->every == 0) PetscCall(BwPushoverWriteStep(p, nw, of, step, lambda, load));
      if (step == 1 && PetscAbsReal(mon - h->monitor[0]) > 0) k0 = PetscAbsReal((lambda - h->lambda[0]) / (mon - h->monitor[0]));
      if (by_energy) {
        /* adapt the energy per step, and stop at the target or after the
         * most steps. A given dissipation_step is the most a step
         * dissipates (the resolution asked for): cut where Newton
         * struggles, back up to it after easy steps. Otherwise the energy
         * per step follows the path: the energy a step needs for one
         * displacement increment grows by orders of magnitude from the
         * first crack to the peak (a 1e4-block wall: 0.1 J at the first
         * crack, steps of 5e-7 m at 0.8 of the peak with it), so it is
         * scaled by du/ds towards steps of one increment's length, by at
         * most 1.5 (2 after a step of 3 iterations or fewer: it grows back
         * quickly from the small steps a peak's cut-backs leave) and at
         * least 0.5 a step, never up after a step of more
         * than 6 iterations (5 or 6 are the norm on a cracking wall's
         * branch), down by 0.6 after one of 10 or more. After a cut-back
         * the energy is held for BW_PUSHOVER_HOLD steps: grown back at
         * once it meets the failure again at each step of a crushing or
         * cracking front (examples/j4d_cap.yaml: 19 of its 23 steps with a
         * cut-back followed one, and the failures were a third of its
         * Newton iterations). */
        PetscReal dl = (lambda - h->lambda[step - 1]) / (k0 > 0 && PetscIsNormalReal(k0) ? k0 : PETSC_MAX_REAL);
        PetscReal dm = mon - h->monitor[step - 1], ds = PetscSqrtReal(dm * dm + dl * dl);
        if (po->dissipation_step > 0) {
          if (its <= 4 && hold == 0) tau = PetscMin(1.5 * tau, tau_max);
          else if (its >= 10) tau *= 0.6;
        } else {
          PetscReal f = ds > 0 ? PetscMax(0.5, PetscMin(its <= 3 ? 2.0 : 1.5, du / ds)) : 1.5;
          if (its > 6) f = PetscMin(f, 1.0);
          if (its >= 10) f = PetscMin(f, 0.6);
          if (hold > 0) f = PetscMin(f, 1.0);
          tau *= f;
          tau_min = tau * po->min_step; /* cut-backs go down to min_step of what the path asks for here */
        }
        if (hold > 0) hold--;
        t = (mon - mon0) / (po->target - mon0);
        if (t >= 1) t = 1;
      } else {
        if (po->control != BW_CONTROL_DISSIPATION) t = tn;
        else t = PetscMin(1.0, (mon - mon0) / (po->target - mon0));
        if (++good >= 2) hc = PetscMin(inc, 2 * hc);
        /* dissipation control takes over once a step dissipates more
         * than 1 % of the loads' work on it (counted without cancellation
         * between the constant loads and the pattern: newton.h), measured
         * by the energy balance (what the constraint controls) and that
         * balance agrees with the portions' own plastic work to a half:
         * where it does not, the balance is mostly its trapezoid error on
         * a curved elastic path (a block rocking on no-tension joints:
         * 14 % of the work against 1.5 % really dissipated by slip near
         * the neutral axis), and energy control there went onto a wrong
         * branch with lambda < 0. */
        if (po->control == BW_CONTROL_DISSIPATION && dissipated > 0.01 * PetscAbsReal(work) && PetscAbsReal(dissipated - plastic) < 0.5 * dissipated) {
          dissipating = PETSC_TRUE;
          if (!(tau > 0)) tau = dissipated;
          tau_min = tau * po->min_step;
          tau_max = tau;
          if (p->log->verbose) PetscCall(PetscPrintf(p->comm, "  energy control from here: %.3e J per step\n", (double)tau));
        }
      }
      if (po->control == BW_CONTROL_DISSIPATION && step >= po->steps && t < 1 - 1e-12) PetscCall(PetscSNPrintf(stop, len, "the most steps taken (analysis.pushover.steps = %" PetscInt_FMT ") before the monitor reached the target", po->steps));
      PetscCall(BwPushoverStopAtReversal(po, h, step, lambda, stop, len));
    } else if (by_energy) {
      PetscBool elastic;
      PetscCall(BwNewtonGetResult(nw, NULL, NULL, &reason));
      PetscCall(BwNewtonFailedElastic(nw, &elastic));
      /* Cut the energy in halves down to tau_min of what the path asks
       * for here. Where even that fails and Newton, not an elastic state,
       * is what failed, IMPL-EX takes over under auto; under newton the
       * step is tried over: 4, 16, ... 4^6 times the energy of the first
       * failure. At a crushing peak of examples/j4d_cap.yaml some
       * hundred portions sit on the cap's peak together and swap between
       * softening and unloading in every iteration of a small step (the
       * residual stalls at 1e-7 against a tolerance of 1e-8, whatever the
       * step), while a step of a few times more energy lets the crushing
       * localise and converges; which of the two a run meets first
       * depends on round-off (Intel's OpenBLAS kernels: stopped there at
       * 3.855 mm; the reference BLAS: passed). */
      if (over > 0 && !elastic) {
        tau *= 4;
        if (++over > 6) {
          /* no step over converged (scheme newton): displacement control
           * again (below) */
          tau = 0;
        }
        else if (p->log->verbose) PetscCall(PetscPrintf(p->comm, "  step %4" PetscInt_FMT ": stepping over with %.3e J (%s)\n", h->n, (double)tau, reason));
      } else if (over > 0) tau = 0;
      else {
        if (!(tau_failed > 0)) tau_failed = tau;
        tau /= 2;
        hold = BW_PUSHOVER_HOLD;
        if (p->log->verbose) PetscCall(PetscPrintf(p->comm, "  step %4" PetscInt_FMT ": energy per step cut to %.3e (%s)\n", h->n, (double)tau, reason));
        if (tau < tau_min && !elastic) {
          /* Under auto, IMPL-EX from here, without stepping over: whether
           * a longer step converges, and onto which branch, is round-off's
           * choice (a wall with a window, 300 steps: with OpenBLAS a step
           * over converged onto a branch that unloaded the wall, lambda
           * through zero at 0.50 mm, where the reference BLAS's step overs
           * failed and IMPL-EX went on to 4 mm). */
          if (po->scheme == BW_SCHEME_AUTO) implex = PETSC_TRUE;
          else {
            over = 1;
            tau  = 4 * tau_failed;
            if (p->log->verbose) PetscCall(PetscPrintf(p->comm, "  step %4" PetscInt_FMT ": stepping over with %.3e J\n", h->n, (double)tau));
          }
        }
      }
      if (tau < tau_min) {
        over = 0;
        /* nothing dissipates any more (elastic unloading, rocking):
         * displacement control again */
        dissipating = PETSC_FALSE;
        tau         = 2 * tau_min / po->min_step;
        hc          = inc;
        good        = 0;
        if (++returns > 2) {
          if (po->scheme == BW_SCHEME_AUTO) implex = PETSC_TRUE;
          else PetscCall(PetscSNPrintf(stop, len, "no converged state beyond monitor = %.6g under energy or displacement control (last failure: %s)", (double)h->monitor[h->n - 1], reason));
        }
      }
    } else {
      PetscCall(BwNewtonGetResult(nw, NULL, NULL, &reason));
      good = 0;
      hc /= 2;
      if (p->log->verbose) PetscCall(PetscPrintf(p->comm, "  step %4" PetscInt_FMT ": cut back to %.3g of an increment (%s)\n", h->n, (double)(hc / inc), reason));
      if (hc < po->min_step * inc * (1 - 1e-12)) {
        if (po->control == BW_CONTROL_DISSIPATION && returns <= 2) {
          /* a snap-back at the peak: no displacement beyond it has a
           * state Newton can reach; energy control from here */
          dissipating = PETSC_TRUE;
          if (!(tau > 0)) tau = po->dissipation_step > 0 ? po->dissipation_step : PetscMax(1e-2 * totalwork, PETSC_SMALL);
          tau_min = tau * po->min_step;
          tau_max = tau;
          hc      = inc;
          if (p->log->verbose) PetscCall(PetscPrintf(p->comm, "  displacement control cannot go on: energy control from here, %.3e J per step\n", (double)tau));
        } else if (po->control == BW_CONTROL_DISSIPATION && po->scheme == BW_SCHEME_AUTO) implex = PETSC_TRUE;
        else if (po->control == BW_CONTROL_LOAD)
          PetscCall(PetscSNPrintf(stop, len, "collapse: no equilibrium beyond lambda = %.6g even with steps of %g of an increment (last failure: %s)", (double)lambda, (double)po->min_step, reason));
        else
          PetscCall(PetscSNPrintf(stop, len, "no converged state beyond monitor = %.6g even with steps of %g of an increment: the end of what displacement control can follow (last failure: %s)", (double)h->monitor[h->n - 1], (double)po->min_step, reason));
      }
    }
    if (ok) totalwork += work;
  }
  if (implex && !stop[0]) {
    /* IMPL-EX from here: asked for, or Newton could follow the path no further */
    if (p->log->verbose && po->scheme == BW_SCHEME_AUTO) PetscCall(PetscPrintf(p->comm, "  Newton can follow the path no further (%s): IMPL-EX from step %" PetscInt_FMT "\n", reason, h->n));
    if (po->scheme == BW_SCHEME_AUTO) PetscCall(PetscSNPrintf(ist->why, sizeof(ist->why), "%s", reason));
    PetscCall(BwPushoverImplexSteps(a, p, nw, of, h, mon0, &lambda, load, ist, stop, len));
  }
  if (!stop[0]) PetscCall(PetscSNPrintf(stop, len, "target reached"));
  /* the last step is always written when steps are */
  if (po->every > 1 && (h->n - 1) % po->every) PetscCall(BwPushoverWriteStep(p, nw, of, h->n - 1, lambda, load));
  if (po->every == 0) PetscCall(BwPushoverWriteStep(p, nw, of, h->n - 1, lambda, load));
  *lambda_out = lambda;
  PetscCall(PetscFree(load));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwPushoverRun(BwAnalysis a, BwProblem *p)
{
  BwPushover    *po = (BwPushover *)a->data;
  BwNewton       nw;
  BwOutputFile   of;
  BwHistory      h = {0, 0, NULL, NULL, NULL, NULL, NULL};
  char          *text, stop[1024] = "";
  PetscReal      lambda = 0, peak = -PETSC_MAX_REAL, peak_mon = 0, *load;
  PetscInt       npeak = 0, nsteps_planned, count[4], crushed = 0, its, solves, reversal = -1;
  PetscErrorCode ierr;
  BwResults      res  = {NULL, NULL, NULL, NULL, NULL, NULL};
  BwOutputData   data = {p->mixed, NULL, NULL, NULL, NULL, NULL, NULL, NULL};
  BwCheck        check;
  BwReport       report;
  BwCapacity     cap;
  Vec            x, b;
  BwImplexStats  ist = {-1, 0, 0, 0, 0, ""};

  PetscFunctionBeginUser;
  PetscCall(BwSceneGetText(p->scene, &text));
  PetscCall(BwProblemPrintHead(p));
  PetscCall(PetscPrintf(p->comm, "  pushover: %s control, target %g, %" PetscInt_FMT " steps, monitor %s of %s (block %" PetscInt_FMT ")\n", BwControls[po->control], (double)po->target, po->steps, BwModelDofNames(p->model)[po->monitor_dof], po->monitor_set, po->monitor_block));
  PetscCall(BwNewtonCreate(p, p->model->load, po->pattern, &nw));
  PetscCall(BwNewtonSetTolerances(nw, po->tolerance, po->max_iterations));
  PetscCall(BwNewtonSetMonitor(nw, po->monitor_block, po->monitor_dof));
  nsteps_planned = po->every == 0 ? 1 : po->steps / po->every + 2;
  PetscCall(BwOutputOpen(p->output, p->output->file, p->mixed, text, nsteps_planned, &of));
  PetscCall(BwLogBegin(p->log, BW_PHASE_SOLVE));
  ierr = BwPushoverSteps(a, p, nw, of, &h, &lambda, &ist, stop, sizeof(stop));
  PetscCall(BwLogEnd(p->log, BW_PHASE_SOLVE));
  if (ierr) {
    PetscCall(BwOutputAbort(&of));
    PetscCall(BwNewtonDestroy(&nw));
    PetscCall(BwHistoryFree(&h));
    PetscCall(PetscFree(text));
    PetscCall(ierr);
  }
  PetscCall(BwProblemCheckOptions(p));
  for (PetscInt s = 0; s < h.n; s++) {
    if (h.lambda[s] > peak) {
      peak     = h.lambda[s];
      peak_mon = h.monitor[s];
      npeak    = s;
    }
  }
  /* Past its peak the pattern's load can fall through zero: where the
   * softened joints no longer carry the constant loads (a joint under a
   * held pull), or where a snap-back unloads the wall and the dissipating
   * zone goes on under a reversed pattern (examples/j7d.yaml with two
   * Newton variants not kept, to lambda = -0.7 of the peak). The run has
   * stopped there (on_reversal: stop), or went on as asked (continue), an
   * equilibrium path but no pushover any more: the step is reported
   * (load_reversal_step, -1 if none), and the summary says so. */
  reversal = BwReversalStep(h.n, h.lambda);

  /* the final state: results, self-check, the file */
  PetscCall(BwLogBegin(p->log, BW_PHASE_RECOVER));
  PetscCall(PetscMalloc1(p->model->nd * p->geom->nblocks + 1, &load));
  PetscCall(BwPushoverResults(p, nw, lambda, load, &res, &data));
  PetscCall(BwNewtonGetSolution(nw, &x, NULL));
  PetscCall(VecDuplicate(x, &b));
  PetscCall(BwMixedFillRHS(p->mixed, load, b));
  PetscCall(BwMixedCheck(p->mixed, x, b, load, &res, &check));
  PetscCall(VecDestroy(&b));
  PetscCall(BwLogEnd(p->log, BW_PHASE_RECOVER));
  {
    PetscLogDouble setup;
    PetscCall(BwNewtonGetCounts(nw, &its, &solves, &setup));
    /* the factorisations inside the steps, as set-up time */
    p->log->seconds[BW_PHASE_SETUP] += setup;
    p->log->seconds[BW_PHASE_SOLVE] -= setup;
  }
  PetscCall(BwReportCreate(&report));
  PetscCall(BwSolverReport(p->solver, report));
  PetscCall(BwReportString(report, "analysis", "pushover"));
  PetscCall(BwReportReal(report, "residual", h.residual[h.n - 1]));
  PetscCall(BwReportReal(report, "residual_compatibility", -1));
  PetscCall(BwReportReal(report, "equilibrium_error", check.equilibrium_error));
  PetscCall(BwReportInt(report, "steps", h.n));
  PetscCall(BwReportReal(report, "peak_load_factor", peak));
  PetscCall(BwReportReal(report, "peak_monitor", peak_mon));
  PetscCall(BwReportString(report, "stop_reason", stop));
  PetscCall(BwReportInt(report, "load_reversal_step", reversal));
  PetscCall(BwCapacityCompute(h.n, h.lambda, h.monitor, h.dissipation, po->target - h.monitor[0] >= 0 ? 1.0 : -1.0, &cap));
  PetscCall(BwReportReal(report, "first_peak_load_factor", cap.first_peak_load_factor));
  PetscCall(BwReportReal(report, "first_peak_monitor", cap.first_peak_monitor));
  PetscCall(BwReportReal(report, "residual_load_factor", cap.residual_load_factor));
  PetscCall(BwReportReal(report, "dissipated_energy", cap.dissipated_energy));
  PetscCall(BwReportReal(report, "ultimate_displacement", cap.ultimate_displacement));
  PetscCall(BwReportReal(report, "bilinear_yield_force", cap.yield_force));
  PetscCall(BwReportReal(report, "bilinear_yield_displacement", cap.yield_displacement));
  PetscCall(BwReportReal(report, "ductility", cap.ductility));
  PetscCall(BwReportString(report, "control", BwControls[po->control]));
  {
    /* the scheme the steps were made with: newton, implex, or newton then
     * implex (auto) from the step where Newton handed over */
    char scheme[64];
    if (ist.from_step < 0) PetscCall(PetscStrncpy(scheme, "newton", sizeof(scheme)));
    else if (ist.from_step <= 1) PetscCall(PetscStrncpy(scheme, "implex", sizeof(scheme)));
    else PetscCall(PetscStrncpy(scheme, "newton+implex", sizeof(scheme)));
    PetscCall(BwReportString(report, "scheme", scheme));
    PetscCall(BwReportInt(report, "implex_from_step", ist.from_step));
    PetscCall(BwReportInt(report, "implex_steps", ist.steps));
    PetscCall(BwReportInt(report, "implex_cut_steps", ist.cut));
    PetscCall(BwReportReal(report, "implex_error_max", ist.error_max));
    PetscCall(BwReportReal(report, "implex_residual_max", ist.residual_max));
  }
  /* what a capacity curve's axes are labelled with: the monitor by name,
   * the load in the pattern's units (|sum of the pattern's forces| in N) */
  PetscCall(BwReportString(report, "monitor_set", po->monitor_set));
  PetscCall(BwReportString(report, "monitor_dof", BwModelDofNames(p->model)[po->monitor_dof]));
  {
    /* |the sum of the pattern's forces| (the first dim components per block) */
    PetscReal f[3] = {0, 0, 0}, all[3];
    for (PetscInt b = 0; b < p->geom->nown_blocks; b++)
      for (PetscInt c = 0; c < p->geom->dim; c++) f[c] += po->pattern[p->model->nd * b + c];
    PetscCallMPI(MPIU_Allreduce(f, all, 3, MPIU_REAL, MPIU_SUM, p->comm));
    for (int c = 0; c < 3; c++) f[c] = all[c];
    PetscCall(BwReportReal(report, "pattern_resultant", PetscSqrtReal(f[0] * f[0] + f[1] * f[1] + f[2] * f[2])));
  }
  PetscCall(BwReportInt(report, "newton_iterations", its));
  PetscCall(BwReportInt(report, "linear_solves", solves));
  data.solver = report;
  data.scene  = text;
  PetscCall(BwLogBegin(p->log, BW_PHASE_WRITE));
  {
    BwOutputHistory hist = {h.n, h.lambda, h.monitor, h.residual, h.its, h.dissipation};
    PetscCall(BwOutputClose(&of, &data, &hist, p->log));
  }
  PetscCall(BwLogEnd(p->log, BW_PHASE_WRITE));

  {
    BwJointField field;
    PetscCall(BwNewtonGetSolution(nw, NULL, &field));
    PetscCall(BwJointFieldCount(field, count));
    PetscCall(BwJointFieldCountCrushed(field, &crushed));
  }
  PetscCall(PetscPrintf(p->comm, "  steps %" PetscInt_FMT " (%" PetscInt_FMT " Newton iterations, %" PetscInt_FMT " linear solves); stop: %s\n", h.n, its, solves, stop));
  PetscCall(PetscPrintf(p->comm, "  peak load factor %.6g at step %" PetscInt_FMT " (monitor %.6g); last: load factor %.6g, monitor %.6g\n", (double)peak, npeak, (double)peak_mon, (double)h.lambda[h.n - 1], (double)h.monitor[h.n - 1]));
  PetscCall(PetscPrintf(p->comm, "  first peak: load factor %.6g at step %" PetscInt_FMT " (monitor %.6g); residual load factor %.6g (%.3g of the peak); dissipated %.6g J\n", (double)cap.first_peak_load_factor, cap.first_peak, (double)cap.first_peak_monitor, (double)cap.residual_load_factor, (double)(cap.residual_load_factor / peak), (double)cap.dissipated_energy));
  if (ist.from_step >= 0) {
    if (ist.from_step > 1) PetscCall(PetscPrintf(p->comm, "  scheme: Newton to step %" PetscInt_FMT ", then IMPL-EX (Newton could follow the path no further: %s)\n", ist.from_step - 1, ist.why));
    PetscCall(PetscPrintf(p->comm, "  IMPL-EX: %" PetscInt_FMT " steps kept, %" PetscInt_FMT " cut; largest error kept %.3g (tolerance %g); largest residual with the return-mapped stresses %.3g\n", ist.steps, ist.cut, (double)ist.error_max, (double)po->implex_tolerance, (double)ist.residual_max));
  }
  if (reversal >= 0 && !po->stop_on_reversal) PetscCall(PetscPrintf(p->comm, "  warning: the load factor changed sign at step %" PetscInt_FMT " (monitor %.6g), past its peak: from there the pattern acts the other way (the softened joints no longer carry the constant loads, or a snap-back unloaded the wall), no pushover any more; /solver load_reversal_step\n", reversal, (double)h.monitor[reversal]));
  if (cap.note[0]) PetscCall(PetscPrintf(p->comm, "  bilinear (NTC 2018): %s; ultimate displacement %.6g\n", cap.note, (double)cap.ultimate_displacement));
  else PetscCall(PetscPrintf(p->comm, "  bilinear (NTC 2018): stiffness %.6g, yield load factor %.6g at %.6g, ultimate displacement %.6g, ductility %.3g\n", (double)cap.stiffness, (double)cap.yield_force, (double)cap.yield_displacement, (double)cap.ultimate_displacement, (double)cap.ductility));
  PetscCall(PetscPrintf(p->comm, "  joints at the end: %" PetscInt_FMT " portions open, %" PetscInt_FMT " sliding, %" PetscInt_FMT " both, %" PetscInt_FMT " elastic", count[1], count[2], count[3], count[0]));
  if (crushed) PetscCall(PetscPrintf(p->comm, "; %" PetscInt_FMT " crushed (on the cap)", crushed));
  PetscCall(PetscPrintf(p->comm, "\n"));
  PetscCall(PetscPrintf(p->comm, "  residual of the nonlinear system %.3e; equilibrium error (reactions + loads) %.3e\n", (double)h.residual[h.n - 1], (double)check.equilibrium_error));
  PetscCall(BwProblemPrintTail(p, p->output->file));
  PetscCall(BwReportDestroy(&report));
  PetscCall(BwResultsFree(&res));
  PetscCall(PetscFree(load));
  PetscCall(BwNewtonDestroy(&nw));
  PetscCall(BwHistoryFree(&h));
  PetscCall(PetscFree(text));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwPushoverDestroy(BwAnalysis a)
{
  BwPushover *po = (BwPushover *)a->data;

  PetscFunctionBeginUser;
  if (po) PetscCall(PetscFree(po->pattern));
  PetscCall(PetscFree(a->data));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwAnalysisCreate_Pushover(BwAnalysis a)
{
  BwPushover *po;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&po));
  a->data           = po;
  a->setfromoptions = BwPushoverSetFromOptions;
  a->run            = BwPushoverRun;
  a->destroy        = BwPushoverDestroy;
  PetscFunctionReturn(PETSC_SUCCESS);
}
