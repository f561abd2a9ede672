/* BwNewton: see newton.h. */
#include "analysis/newton.h"
#include "util/compat.h"

/* Dissipation control: the step's energy met to this, relative (below) */
#define BW_NEWTON_ENERGY_RTOL 1e-3

struct _n_BwNewton {
  BwProblem   *p;
  BwMixed      mx;
  BwJointField field;
  PetscInt     nb;
  /* x: the committed state; xn: the iterate; xt: a line-search trial */
  Vec          x, xn, xt, F, Ft, dx, dx2, b, b0, bP;
  PetscReal    lambda_committed;
  PetscReal    rtol;
  PetscInt     maxit;
  /* displacement control */
  PetscInt     mon_row, mon_block, mon_dof;
  PetscReal    mon_scale;
  PetscReal    mon_fixed; /* the monitor's value where its dof is prescribed (mon_row < 0) */
  /* the last solve */
  PetscInt     its, total_its, total_solves;
  PetscReal    residual;
  char         reason[512];
  PetscBool    failed_elastic; /* the last dissipation solve failed because no portion flows */
  PetscReal   *load0, *pattern;
  BwLog        log; /* the linear solves' own phases, quietly (a pushover makes thousands) */
  PetscBool    debug; /* analysis.newton_monitor: one line per iteration */
  /* dissipation control: the energy gradient, the last step's balance */
  Vec          g, e, dx3; /* e: the monitor's unit vector; dx3 = K'^-1 e */
  PetscReal    step_work, step_dissipation, last_dlambda, lambda_trial, gross_work;
  PetscReal    step_plastic; /* the portions' own plastic work of the last converged solve (BwJointFieldPlasticWork) */
  PetscReal    lambda_solved; /* lambda of the last converged solve */
  PetscInt     dx2_state;     /* the operator's values state dx2 = K'^-1 bP was solved with (-1: none) */
  PetscInt     dx3_state;     /* the same for dx3 = K'^-1 e */
  PetscReal    pattern_on_monitor; /* s where bP = s e (the pattern pushes the monitor's dof alone), else 0 */
  PetscBool    keep_start;    /* analysis.newton_keep_start (BwNewtonAttempt) */
  PetscBool    matrix_of_committed; /* the Newton matrix is that of the last iteration of a converged solve */
};

PetscErrorCode BwNewtonCreate(BwProblem *p, const PetscReal load0[], const PetscReal pattern[], BwNewton *newton)
{
  BwNewton   nw;
  PetscReal *zero;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&nw));
  nw->p       = p;
  nw->mx      = p->mixed;
  nw->nb      = p->geom->nblocks;
  nw->rtol    = 1e-8;
  nw->maxit   = 40;
  nw->mon_row   = -1;
  nw->dx2_state = -1;
  nw->dx3_state = -1;
  nw->keep_start = p->newton_keep_start;
  PetscCall(BwJointFieldCreate(p->mixed, &nw->field));
  PetscCall(BwLogCreate(p->comm, &nw->log));
  nw->debug = p->newton_monitor;
  PetscCall(BwMixedCreateVecs(p->mixed, &nw->x, &nw->b));
  PetscCall(VecDuplicate(nw->x, &nw->xn));
  PetscCall(VecDuplicate(nw->x, &nw->xt));
  PetscCall(VecDuplicate(nw->x, &nw->F));
  PetscCall(VecDuplicate(nw->x, &nw->Ft));
  PetscCall(VecDuplicate(nw->x, &nw->dx));
  PetscCall(VecDuplicate(nw->x, &nw->b0));
  PetscCall(PetscMalloc2(p->model->nd * nw->nb + 1, &nw->load0, p->model->nd * nw->nb + 1, &nw->pattern));
  PetscCall(PetscArraycpy(nw->load0, load0, p->model->nd * nw->nb));
  if (pattern) PetscCall(PetscArraycpy(nw->pattern, pattern, p->model->nd * nw->nb));
  else PetscCall(PetscArrayzero(nw->pattern, p->model->nd * nw->nb));
  PetscCall(BwMixedFillRHS(p->mixed, load0, nw->b0));
  /* bP: the pattern's loads alone (FillRHS lifts the prescribed values too) */
  PetscCall(VecDuplicate(nw->x, &nw->bP));
  PetscCall(PetscCalloc1(p->model->nd * nw->nb + 1, &zero));
  PetscCall(BwMixedFillRHS(p->mixed, nw->pattern, nw->bP));
  PetscCall(BwMixedFillRHS(p->mixed, zero, nw->dx));
  PetscCall(VecAXPY(nw->bP, -1.0, nw->dx));
  PetscCall(PetscFree(zero));
  *newton = nw;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonDestroy(BwNewton *newton)
{
  BwNewton nw = *newton;

  PetscFunctionBeginUser;
  if (!nw) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(BwJointFieldDestroy(&nw->field));
  PetscCall(VecDestroy(&nw->x));
  PetscCall(VecDestroy(&nw->xn));
  PetscCall(VecDestroy(&nw->xt));
  PetscCall(VecDestroy(&nw->F));
  PetscCall(VecDestroy(&nw->Ft));
  PetscCall(VecDestroy(&nw->dx));
  PetscCall(VecDestroy(&nw->dx2));
  PetscCall(VecDestroy(&nw->g));
  PetscCall(VecDestroy(&nw->e));
  PetscCall(VecDestroy(&nw->dx3));
  PetscCall(VecDestroy(&nw->b));
  PetscCall(VecDestroy(&nw->b0));
  PetscCall(VecDestroy(&nw->bP));
  PetscCall(PetscFree2(nw->load0, nw->pattern));
  PetscCall(PetscFree(*newton));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonSetTolerances(BwNewton nw, PetscReal rtol, PetscInt maxit)
{
  PetscFunctionBeginUser;
  nw->rtol  = rtol;
  nw->maxit = maxit;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwVecEntry(Vec, PetscInt, PetscReal *);

PetscErrorCode BwNewtonSetMonitor(BwNewton nw, PetscInt block, PetscInt dof)
{
  PetscInt  row;
  PetscReal scale = 0;

  PetscFunctionBeginUser;
  /* a prescribed monitor (load control of an assembly whose every dof is
   * prescribed) reads its prescribed value; displacement and dissipation
   * control need a free one (checked where they start) */
  PetscCall(BwMixedDofRow(nw->mx, block, dof, &row, &scale, &nw->mon_fixed));
  nw->mon_row   = row;
  nw->mon_block = block;
  nw->mon_dof   = dof;
  nw->mon_scale = scale;
  if (!nw->dx2) PetscCall(VecDuplicate(nw->x, &nw->dx2));
  /* A pushover that pushes where it measures (a top beam's u1, examples/
   * j4d.yaml, bench/pushover.py's walls) has bP = s e: then K'^-1 bP is s
   * K'^-1 e, and dissipation control needs two solves per iteration, not
   * three. Exact: the 1-norm of bP is |s| only where no other entry is
   * nonzero. */
  nw->pattern_on_monitor = 0;
  if (row >= 0) {
    PetscReal s, n1;
    PetscCall(BwVecEntry(nw->bP, row, &s));
    PetscCall(VecNorm(nw->bP, NORM_1, &n1));
    if (s != 0 && n1 == PetscAbsReal(s)) nw->pattern_on_monitor = s;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* v[row] += a on the rank that owns the row. Every rank takes and gives
 * back the array, so that the vector's state (which keeps cached norms
 * valid or not) moves on all of them: a state bumped on one rank only lets
 * the others use a stale cached norm and skip a collective call. */
static PetscErrorCode BwVecAddEntry(Vec v, PetscInt row, PetscReal a)
{
  PetscInt     lo, hi;
  PetscScalar *x;

  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(v, &lo, &hi));
  PetscCall(VecGetArray(v, &x));
  if (row >= lo && row < hi) x[row - lo] += a;
  PetscCall(VecRestoreArray(v, &x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Entry `row` of a K-layout vector, on every rank. */
static PetscErrorCode BwVecEntry(Vec v, PetscInt row, PetscReal *value)
{
  PetscInt           lo, hi;
  const PetscScalar *a;
  PetscReal          loc = 0;

  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(v, &lo, &hi));
  if (row >= lo && row < hi) {
    PetscCall(VecGetArrayRead(v, &a));
    loc = PetscRealPart(a[row - lo]);
    PetscCall(VecRestoreArrayRead(v, &a));
  }
  PetscCallMPI(MPI_Allreduce(&loc, value, 1, MPIU_REAL, MPIU_SUM, PetscObjectComm((PetscObject)v)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonMonitorValue(BwNewton nw, PetscReal *value)
{
  PetscFunctionBeginUser;
  *value = nw->mon_fixed;
  if (nw->mon_row < 0) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(BwVecEntry(nw->x, nw->mon_row, value));
  *value *= nw->mon_scale;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* F at x for (mu, lambda), the relative norm ||F|| / max(||b||, ||r~||),
 * and whether a law failed (collective). */
static PetscErrorCode BwNewtonResidual(BwNewton nw, Vec x, PetscReal mu, PetscReal lambda, Vec F, PetscReal *norm, PetscBool *failed)
{
  PetscReal fn, bn, rn;
  IS        isr;
  Vec       xr;

  PetscFunctionBeginUser;
  PetscCall(VecAXPBYPCZ(nw->b, mu, lambda, 0.0, nw->b0, nw->bP));
  PetscCall(BwJointFieldBegin(nw->field));
  PetscCall(BwMixedResidual(nw->mx, x, nw->b, BwJointFieldLaw, nw->field, F));
  PetscCall(BwJointFieldFailed(nw->field, failed, NULL, 0));
  PetscCall(VecNorm(F, NORM_2, &fn));
  PetscCall(VecNorm(nw->b, NORM_2, &bn));
  PetscCall(BwMixedGetFields(nw->mx, &isr, NULL));
  PetscCall(VecGetSubVector(x, isr, &xr));
  PetscCall(VecNorm(xr, NORM_2, &rn));
  PetscCall(VecRestoreSubVector(x, isr, &xr));
  *norm = fn / PetscMax(PetscMax(bn, rn), PETSC_SMALL * PETSC_SMALL);
  if (bn == 0 && rn == 0) *norm = fn; /* the unloaded, undeformed state */
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The energy balance of a step from the committed state (x0, lambda0) to
 * (x, lambda), with the constant loads held (mu = 1), in the scaled
 * variables of the mixed system, where a product b~.x~ is the physical
 * work and the elastic (r, r) block is -I, so that the stored elastic
 * energy sum_p 1/2 A_p r_p^T C^-1 r_p is 1/2 |r~|^2 exactly:
 *   W = (b0 + (lambda0 + lambda)/2 bP)_q . (x - x0)_q   the loads' work (trapezoid),
 *   dE = 1/2 (|x_r|^2 - |x0_r|^2)                      the change of stored energy,
 *   D = W - dE                                          the energy dissipated.
 * D is the plastic work of the portions up to the trapezoid rule's error
 * on the step (exact where the loads' path is linear in the step, as in a
 * proportional pushover). With `grad`, also dD/dx (in nw->g) and
 * dD/dlambda = 1/2 bP_q . (x - x0)_q (Verhoosel, Remmers & Gutierrez 2009,
 * the dissipation constraint, in its plasticity form: joints unload with
 * their elastic stiffness). */
static PetscErrorCode BwNewtonEnergy(BwNewton nw, Vec x, PetscReal lambda0, PetscReal lambda, PetscBool grad, PetscReal *work, PetscReal *dissipation, PetscReal *dlambda)
{
  IS        isr, isq;
  Vec       xq, x0q, bq, br, xr, x0r, gq, gr, dq;
  PetscReal w1, wP, drx0, drdr;

  PetscFunctionBeginUser;
  PetscCall(BwMixedGetFields(nw->mx, &isr, &isq));
  if (!nw->g) PetscCall(VecDuplicate(nw->x, &nw->g));
  /* the displacement increment, in g's q part as scratch */
  PetscCall(VecGetSubVector(nw->g, isq, &dq));
  PetscCall(VecGetSubVector(x, isq, &xq));
  PetscCall(VecGetSubVector(nw->x, isq, &x0q));
  PetscCall(VecWAXPY(dq, -1.0, x0q, xq));
  PetscCall(VecRestoreSubVector(x, isq, &xq));
  PetscCall(VecRestoreSubVector(nw->x, isq, &x0q));
  PetscCall(VecGetSubVector(nw->b0, isq, &bq));
  PetscCall(VecDot(bq, dq, &w1));
  PetscCall(VecRestoreSubVector(nw->b0, isq, &bq));
  PetscCall(VecGetSubVector(nw->bP, isq, &bq));
  PetscCall(VecDot(bq, dq, &wP));
  PetscCall(VecRestoreSubVector(nw->bP, isq, &bq));
  PetscCall(VecRestoreSubVector(nw->g, isq, &dq));
  /* the change of stored energy as dr.(x0 + dr/2), dr = x_r - x0_r (in g's
   * r part as scratch), not |x_r|^2 - |x0_r|^2: the stored energy of a wall
   * at its peak is ~1e3 J, whose round-off over 1e5 portions (1e-11 J)
   * would be the whole tolerance of a step of 1e-3 J */
  PetscCall(VecGetSubVector(x, isr, &xr));
  PetscCall(VecGetSubVector(nw->x, isr, &x0r));
  PetscCall(VecGetSubVector(nw->g, isr, &gr));
  PetscCall(VecWAXPY(gr, -1.0, x0r, xr));
  PetscCall(VecDot(gr, x0r, &drx0));
  PetscCall(VecDot(gr, gr, &drdr));
  PetscCall(VecRestoreSubVector(nw->g, isr, &gr));
  PetscCall(VecRestoreSubVector(nw->x, isr, &x0r));
  *work        = w1 + 0.5 * (lambda0 + lambda) * wP;
  /* the loads' work without cancellation: where the constant loads take
   * back what the pattern gives (a rocking stack lifting its own weight) the
   * net work is small and would make round-off and the trapezoid rule's
   * error on a curved elastic path look like a dissipating step */
  nw->gross_work = PetscAbsReal(w1) + PetscAbsReal(0.5 * (lambda0 + lambda) * wP);
  *dissipation = *work - (drx0 + 0.5 * drdr); /* 1/2 (|x_r|^2 - |x0_r|^2) */
  if (dlambda) *dlambda = 0.5 * wP;
  if (grad) {
    PetscCall(VecGetSubVector(nw->g, isr, &gr));
    PetscCall(VecAXPBY(gr, -1.0, 0.0, xr));
    PetscCall(VecRestoreSubVector(nw->g, isr, &gr));
    PetscCall(VecGetSubVector(nw->g, isq, &gq));
    PetscCall(VecGetSubVector(nw->b0, isq, &bq));
    PetscCall(VecCopy(bq, gq));
    PetscCall(VecRestoreSubVector(nw->b0, isq, &bq));
    PetscCall(VecGetSubVector(nw->bP, isq, &br));
    PetscCall(VecAXPY(gq, 0.5 * (lambda0 + lambda), br));
    PetscCall(VecRestoreSubVector(nw->bP, isq, &br));
    PetscCall(VecRestoreSubVector(nw->g, isq, &gq));
  }
  PetscCall(VecRestoreSubVector(x, isr, &xr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* K dx = rhs with the current tangents; false (and the reason) if no
 * usable answer. The solver's own checks stand; its error is caught. */
static PetscErrorCode BwNewtonLinearSolve(BwNewton nw, Vec rhs, Vec dx, PetscBool *ok)
{
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  PetscCall(BwSolverSetForwardCheck(nw->p->solver, PETSC_FALSE));
  ierr = BwSolverSolve(nw->p->solver, rhs, dx, &nw->log);
  PetscCall(BwSolverSetForwardCheck(nw->p->solver, PETSC_TRUE));
  PetscCall(PetscPopErrorHandler());
  nw->total_solves++;
  *ok = ierr ? PETSC_FALSE : PETSC_TRUE;
  if (ierr) PetscCall(PetscSNPrintf(nw->reason, sizeof(nw->reason), "the Newton matrix could not be solved (%s)", BwErrorText(ierr)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* x = K'^-1 b for a b that does not change (the pattern's loads, the
 * monitor's unit vector), solved again only where K' changed since
 * (*state: the operator's values state x was solved with, -1 none): an
 * IMPL-EX run's matrix is the same at every step, and a step's first
 * iteration keeps the last step's. A failed solve leaves *state -1. */
static PetscErrorCode BwNewtonSolveOperator(BwNewton nw, Vec b, Vec x, PetscInt *state, PetscBool *ok)
{
  PetscInt now;

  PetscFunctionBeginUser;
  *ok = PETSC_TRUE;
  PetscCall(BwMixedGetValuesState(nw->mx, &now));
  if (now == *state) PetscFunctionReturn(PETSC_SUCCESS);
  *state = -1;
  PetscCall(BwNewtonLinearSolve(nw, b, x, ok));
  if (*ok) *state = now;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* One step of Newton under the given control; target: the monitor's
 * value (displacement) or the energy to dissipate (dissipation). */
static PetscErrorCode BwNewtonAttempt(BwNewton nw, PetscReal mu, PetscReal *lambda, BwNewtonControl control, PetscReal target, PetscBool *converged)
{
  PetscReal lam = *lambda, lam0 = *lambda, norm, after1 = PETSC_MAX_REAL, target_scaled = 0, gscale = 1, recent[6], gtol;
  PetscBool failed = PETSC_FALSE, displacement = control == BW_NEWTON_DISPLACEMENT ? PETSC_TRUE : PETSC_FALSE;
  PetscBool dissipation = control == BW_NEWTON_DISSIPATION ? PETSC_TRUE : PETSC_FALSE;
  PetscInt  changes;

  PetscFunctionBeginUser;
  *converged         = PETSC_FALSE;
  nw->reason[0]      = 0;
  nw->failed_elastic = PETSC_FALSE;
  nw->its            = 0;
  PetscCheck(!displacement || nw->mon_row >= 0, nw->p->comm, PETSC_ERR_ORDER, "displacement control without a monitor");
  PetscCall(VecCopy(nw->x, nw->xn));
  PetscCall(BwJointFieldBeginStep(nw->field));
  if (displacement) {
    PetscReal now;
    PetscCall(BwVecEntry(nw->xn, nw->mon_row, &now));
    target_scaled = target / nw->mon_scale;
    gscale        = PetscMax(PetscAbsReal(target_scaled - now), PetscAbsReal(target_scaled));
  }
  if (dissipation) {
    PetscCheck(target > 0, nw->p->comm, PETSC_ERR_ARG_OUTOFRANGE, "dissipation control needs an energy > 0 per step");
    gscale = target;
  }
  /* The monitor's tolerance, relative to gscale. Under displacement control
   * the target is the point of the curve the user asked for: met to rtol.
   * Under dissipation control it is the step's length along the path, not
   * a result: a step that dissipates 0.1 % more or less than asked is as
   * good a point of the same curve (its own dissipation is what is
   * recorded and what sizes the next step). Meeting it to rtol cost 251 of
   * J4D-cap's 1979 Newton iterations (a factorisation and three solves
   * each; replayed on a recorded run), where the equilibrium had converged
   * an iteration before. */
  gtol = dissipation ? PetscMax(nw->rtol, BW_NEWTON_ENERGY_RTOL) : nw->rtol;
  PetscCall(BwNewtonResidual(nw, nw->xn, mu, lam, nw->F, &norm, &failed));
  for (;;) {
    PetscReal gap = 0, alpha = 1, tnorm = 0, dlam = 0, merit;
    PetscBool ok, accepted = PETSC_FALSE, tfailed = PETSC_FALSE;

    if (failed) {
      PetscCall(BwJointFieldFailed(nw->field, &failed, nw->reason, sizeof(nw->reason)));
      break;
    }
    if (!PetscIsNormalReal(norm) && norm != 0) {
      PetscCall(PetscSNPrintf(nw->reason, sizeof(nw->reason), "the residual is not finite after %" PetscInt_FMT " iterations", nw->its));
      break;
    }
    if (displacement) {
      PetscReal now;
      PetscCall(BwVecEntry(nw->xn, nw->mon_row, &now));
      gap = target_scaled - now;
    }
    if (dissipation) {
      PetscReal w, d;
      PetscCall(BwNewtonEnergy(nw, nw->xn, lam0, lam, PETSC_FALSE, &w, &d, NULL));
      gap = target - d;
    }
    nw->residual = norm;
    merit        = PetscSqrtReal(norm * norm + (gap / gscale) * (gap / gscale));
    PetscCall(BwJointFieldModeChanges(nw->field, nw->its == 0 ? PETSC_TRUE : PETSC_FALSE, &changes));
    if (nw->debug) PetscCall(PetscPrintf(nw->p->comm, "    Newton %" PetscInt_FMT ": residual %.3e, monitor gap %.3e, lambda %.9e, %" PetscInt_FMT " portions changed mode\n", nw->its, (double)norm, (double)(gap / gscale), (double)lam, changes));
    if (norm <= nw->rtol && PetscAbsReal(gap) <= gtol * gscale) {
      *converged = PETSC_TRUE;
      break;
    }
    if (nw->its >= nw->maxit) {
      PetscCall(PetscSNPrintf(nw->reason, sizeof(nw->reason), "Newton did not converge in %" PetscInt_FMT " iterations (relative residual %.3e, tolerance %.1e)", nw->its, (double)norm, (double)nw->rtol));
      break;
    }
    if (nw->its == 1) after1 = merit;
    /* Under dissipation control a step that stalls is given up early: where
     * a few portions keep flipping between softening and unloading they
     * enter the matrix with their elastic stiffness and Newton creeps
     * (5 % per iteration at the peak of a cracking wall, 40 iterations
     * of a factorisation each for nothing), while the step with half the
     * energy converges in a few. Stalled: after 10 iterations, the merit
     * has not halved over the last 5, and it is not within 10 times the
     * tolerance (within it, the creep test below decides). */
    recent[nw->its % 6] = merit;
    /* Creeping just above the tolerance is a stall too: where a handful of
     * portions sit in the matrix with their elastic stiffness the merit
     * falls by a few per cent per iteration (2e-8 to 5e-8 against 1e-8 for
     * 30 iterations on J4D-cap near 4 mm). Stalled as well: the rate of the
     * last 5 iterations, kept up to the iteration limit, would not reach
     * the tolerance. */
    if (dissipation && nw->its >= 10) {
      PetscReal before = recent[(nw->its - 5) % 6], rate = before > 0 ? PetscPowReal(merit / before, 0.2) : 1;
      PetscBool halved = merit <= 0.5 * before ? PETSC_TRUE : PETSC_FALSE;
      PetscBool creep  = merit > nw->rtol && (rate >= 1 || merit * PetscPowReal(rate, (PetscReal)(nw->maxit - nw->its)) > nw->rtol) ? PETSC_TRUE : PETSC_FALSE;
      if ((!halved && merit > 10 * nw->rtol) || creep) {
        PetscCall(PetscSNPrintf(nw->reason, sizeof(nw->reason), "Newton stalled (relative residual %.3e after %" PetscInt_FMT " iterations, %.3e five before)", (double)norm, nw->its, (double)before));
        break;
      }
    }
    if (nw->its >= 3 && merit > 1e3 * PetscMax(after1, nw->rtol)) {
      PetscCall(PetscSNPrintf(nw->reason, sizeof(nw->reason), "Newton diverged (relative residual %.3e after %" PetscInt_FMT " iterations, %.3e after the first)", (double)merit, nw->its, (double)after1));
      break;
    }
    /* The Newton matrix: the tangents of the laws at xn (at the step's
     * start, those the last state converged with); a portion that keeps
     * returning to a mode it left enters with its elastic stiffness
     * (BwJointFieldGetTangents), so that Newton does not cycle at the kink
     * between its softening and its unloading. */
    /* Under load or displacement control a step's first iteration keeps
     * the matrix it finds where that is the last one of the converged step
     * before (the tangents of the iterate before the converged one): the
     * step's own start differs from it by the last correction, and a
     * factorisation is saved per step. On the tilting U-wall of
     * bench/tilt_u_wall.py (MUMPS's LU of 11 850 rows) the same Newton
     * iterations to 1e-14 of lambda with 205 factorisations instead of 314.
     * Not under dissipation control: there the bordered predictor from the
     * committed tangents (elastic on the yield surface) converged in fewer
     * iterations (examples/j4d_cap.yaml 1571 against 1761, j6d 1320
     * against 1379). */
    if (nw->its == 0 && nw->keep_start && !dissipation && nw->matrix_of_committed) {
      if (nw->debug) PetscCall(PetscPrintf(nw->p->comm, "      the Newton matrix of the last step kept\n"));
    } else {
      const PetscReal *t;
      PetscCall(BwJointFieldGetTangents(nw->field, nw->its == 0 ? PETSC_TRUE : PETSC_FALSE, &t));
      PetscCall(BwMixedSetTangents(nw->mx, t));
    }
    /* displacement control: K' = K + e e^T (a spring of the dof's own
     * stiffness on the monitor, so K' stays regular on a plateau) and
     * K' dx1 = -F + e gap, K' dx2 = bP give K dx - bP dlambda = -F with
     * e.dx = gap for dlambda = (gap - e.dx1) / e.dx2, exactly */
    if (dissipation) {
      /* bordered on the energy: K dx - bP dlambda = -F and the linearised
       * constraint D(x + dx, lambda + dlambda) = target. K alone is
       * singular where the joints form a mechanism (a block sliding on a
       * perfectly plastic joint: a plateau of the curve), so the solves
       * use K' = K + e e^T (the monitor's spring, as displacement control)
       * and carry mu = e.dx as a third unknown, exactly:
       *   K' a = -F, K' d = bP, K' c = e,  dx = a + dlambda d + mu c,
       *   (1 - e.c) mu - (e.d) dlambda = e.a                  (mu = e.dx)
       *   (g.c) mu + (g.d + dD/dlambda) dlambda = target - D - g.a
       * a 2 x 2 system that stays regular at a limit point or on a plateau
       * where K dx2 = bP has no answer. Three solves with one factor (two
       * where bP = s e). */
      PetscReal w, d, dDdl, ga, gd, gc, ea, ed, ec, det, rhs2, mu;
      PetscCheck(nw->mon_row >= 0, nw->p->comm, PETSC_ERR_ORDER, "dissipation control without a monitor");
      PetscCall(BwMixedSetSpring(nw->mx, nw->mon_block, nw->mon_dof, 1.0));
      PetscCall(VecScale(nw->F, -1.0));
      PetscCall(BwNewtonLinearSolve(nw, nw->F, nw->dx, &ok));
      PetscCall(VecScale(nw->F, -1.0));
      if (!ok) break;
      if (!nw->dx2) PetscCall(VecDuplicate(nw->x, &nw->dx2));
      if (!nw->e) {
        PetscCall(VecDuplicate(nw->x, &nw->e));
        PetscCall(VecDuplicate(nw->x, &nw->dx3));
        PetscCall(VecZeroEntries(nw->e));
        PetscCall(BwVecAddEntry(nw->e, nw->mon_row, 1.0));
      }
      /* K'^-1 bP and K'^-1 e depend on K' alone; the first is s times
       * the second where bP = s e (BwNewtonSetMonitor) */
      PetscCall(BwNewtonSolveOperator(nw, nw->e, nw->dx3, &nw->dx3_state, &ok));
      if (!ok) break;
      if (nw->pattern_on_monitor != 0) {
        if (nw->dx2_state != nw->dx3_state) {
          PetscCall(VecCopy(nw->dx3, nw->dx2));
          PetscCall(VecScale(nw->dx2, nw->pattern_on_monitor));
          nw->dx2_state = nw->dx3_state;
        }
      } else {
        PetscCall(BwNewtonSolveOperator(nw, nw->bP, nw->dx2, &nw->dx2_state, &ok));
        if (!ok) break;
      }
      PetscCall(BwNewtonEnergy(nw, nw->xn, lam0, lam, PETSC_TRUE, &w, &d, &dDdl));
      PetscCall(VecDot(nw->g, nw->dx, &ga));
      PetscCall(VecDot(nw->g, nw->dx2, &gd));
      PetscCall(VecDot(nw->g, nw->dx3, &gc));
      PetscCall(BwVecEntry(nw->dx, nw->mon_row, &ea));
      PetscCall(BwVecEntry(nw->dx2, nw->mon_row, &ed));
      PetscCall(BwVecEntry(nw->dx3, nw->mon_row, &ec));
      det  = (1 - ec) * (gd + dDdl) + ed * gc;
      rhs2 = target - d - ga;
      {
        /* In an elastic state the loads' work and the stored energy change
         * alike to first order: the constraint does not see lambda (the
         * determinant is round-off against its terms, the work rate). The
         * first iteration then predicts along the load pattern by the last
         * step's increment of lambda (at least 1 % of lambda), which makes
         * the portions at their strength flow; the next ones are bordered. */
        IS        isq;
        Vec       gq, d2q;
        PetscReal rate, rel;
        PetscCall(BwMixedGetFields(nw->mx, NULL, &isq));
        PetscCall(VecGetSubVector(nw->g, isq, &gq));
        PetscCall(VecGetSubVector(nw->dx2, isq, &d2q));
        PetscCall(VecDot(gq, d2q, &rate));
        PetscCall(VecRestoreSubVector(nw->g, isq, &gq));
        PetscCall(VecRestoreSubVector(nw->dx2, isq, &d2q));
        rel = PetscAbsReal(det) / PetscMax(PetscAbsReal(1 - ec) * PetscAbsReal(rate) + PetscAbsReal(ed * gc), PETSC_SMALL * PETSC_SMALL);
        if (!PetscIsNormalReal(det) || rel < 1e-9) {
          if (nw->its > 0 || !(PetscAbsReal(1 - ec) > 0)) {
            PetscCall(PetscSNPrintf(nw->reason, sizeof(nw->reason), "the dissipation constraint does not depend on the load factor here (no portion flows: an elastic state)"));
            nw->failed_elastic = PETSC_TRUE;
            break;
          }
          dlam = PetscMax(PetscAbsReal(nw->last_dlambda), 0.01 * PetscAbsReal(lam));
          if (!(dlam > 0)) dlam = 1.0;
          if (nw->last_dlambda < 0) dlam = -dlam;
          mu = (ea + ed * dlam) / (1 - ec);
        } else {
          dlam = ((1 - ec) * rhs2 - gc * ea) / det;
          mu   = (ea * (gd + dDdl) + ed * rhs2) / det;
        }
      }
      PetscCall(VecAXPBYPCZ(nw->dx, dlam, mu, 1.0, nw->dx2, nw->dx3));
    }
    if (!dissipation) {
    PetscCall(BwMixedSetSpring(nw->mx, displacement ? nw->mon_block : -1, nw->mon_dof, 1.0));
    PetscCall(VecScale(nw->F, -1.0));
    if (displacement) PetscCall(BwVecAddEntry(nw->F, nw->mon_row, gap));
    PetscCall(BwNewtonLinearSolve(nw, nw->F, nw->dx, &ok));
    if (displacement) PetscCall(BwVecAddEntry(nw->F, nw->mon_row, -gap));
    PetscCall(VecScale(nw->F, -1.0));
    if (!ok) break;
    if (displacement) {
      PetscReal d1, d2;
      PetscCall(BwNewtonSolveOperator(nw, nw->bP, nw->dx2, &nw->dx2_state, &ok));
      if (!ok) break;
      PetscCall(BwVecEntry(nw->dx, nw->mon_row, &d1));
      PetscCall(BwVecEntry(nw->dx2, nw->mon_row, &d2));
      if (!(PetscAbsReal(d2) > 0)) {
        PetscCall(PetscSNPrintf(nw->reason, sizeof(nw->reason), "the load pattern does not move the monitor dof (a mechanism of the pattern's own, or a monitor the pattern cannot reach)"));
        break;
      }
      dlam = (gap - d1) / d2;
      PetscCall(VecAXPY(nw->dx, dlam, nw->dx2));
    }
    }
    nw->its++;
    nw->total_its++;
    /* backtracking on the merit (the residual and the monitor's distance
     * to its target, linear in alpha: the correction meets it at alpha =
     * 1): halve the step until it falls enough (Armijo); failing that, the
     * trial with the least merit, or the full step if none fell at all
     * (the residual is not smooth where portions change mode) */
    {
      PetscReal best = PETSC_MAX_REAL, best_alpha = 1;
      for (int ls = 0; ls < 8 && !accepted; ls++, alpha *= 0.5) {
        PetscReal tgap = (1 - alpha) * gap / gscale, tm;
        PetscCall(VecWAXPY(nw->xt, alpha, nw->dx, nw->xn));
        PetscCall(BwNewtonResidual(nw, nw->xt, mu, lam + alpha * dlam, nw->Ft, &tnorm, &tfailed));
        if (dissipation) {
          PetscReal w, d;
          PetscCall(BwNewtonEnergy(nw, nw->xt, lam0, lam + alpha * dlam, PETSC_FALSE, &w, &d, NULL));
          tgap = (target - d) / gscale;
        }
        tm = PetscSqrtReal(tnorm * tnorm + tgap * tgap);
        if (tfailed || !PetscIsNormalReal(tnorm + 1)) continue;
        if (tm <= (1 - 1e-4 * alpha) * merit || (tnorm <= nw->rtol && PetscAbsReal(tgap) <= gtol)) accepted = PETSC_TRUE;
        else if (tm < best) {
          best       = tm;
          best_alpha = alpha;
        }
        if (accepted) break;
      }
      if (!accepted) {
        alpha = best < merit ? best_alpha : 1;
        PetscCall(VecWAXPY(nw->xt, alpha, nw->dx, nw->xn));
        PetscCall(BwNewtonResidual(nw, nw->xt, mu, lam + alpha * dlam, nw->Ft, &tnorm, &tfailed));
      }
    }
    if (nw->debug) PetscCall(PetscPrintf(nw->p->comm, "      step length %g, dlambda %.3e\n", (double)alpha, (double)dlam));
    lam += alpha * dlam;
    PetscCall(VecSwap(nw->xn, nw->xt));
    PetscCall(VecSwap(nw->F, nw->Ft));
    norm   = tnorm;
    failed = tfailed;
  }
  nw->matrix_of_committed = *converged;
  if (*converged) {
    nw->lambda_trial  = lam - lam0;
    nw->lambda_solved = lam;
    *lambda           = lam;
    PetscCall(BwNewtonEnergy(nw, nw->xn, lam0, lam, PETSC_FALSE, &nw->step_work, &nw->step_dissipation, NULL));
    nw->step_work = nw->gross_work;
    PetscCall(BwJointFieldPlasticWork(nw->field, &nw->step_plastic));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonSolve(BwNewton nw, PetscReal mu, PetscReal *lambda, PetscBool displacement, PetscReal target, PetscBool *converged)
{
  PetscFunctionBeginUser;
  PetscCall(BwNewtonAttempt(nw, mu, lambda, displacement ? BW_NEWTON_DISPLACEMENT : BW_NEWTON_LOAD, target, converged));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonSolveDissipation(BwNewton nw, PetscReal *lambda, PetscReal energy, PetscBool *converged)
{
  PetscFunctionBeginUser;
  PetscCall(BwNewtonAttempt(nw, 1.0, lambda, BW_NEWTON_DISSIPATION, energy, converged));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonGetStepEnergy(BwNewton nw, PetscReal *work, PetscReal *dissipation)
{
  PetscFunctionBeginUser;
  if (work) *work = nw->step_work;
  if (dissipation) *dissipation = nw->step_dissipation;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonGetStepPlasticWork(BwNewton nw, PetscReal *plastic)
{
  PetscFunctionBeginUser;
  *plastic = nw->step_plastic;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonSetExtrapolation(BwNewton nw, PetscBool on, PetscReal span)
{
  PetscFunctionBeginUser;
  PetscCall(BwJointFieldSetExtrapolation(nw->field, on, span));
  nw->matrix_of_committed = PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonImplicitUpdate(BwNewton nw, PetscReal *error, PetscReal *residual, PetscBool *ok)
{
  PetscBool failed;

  PetscFunctionBeginUser;
  PetscCall(BwJointFieldMeasureExtrapolation(nw->field));
  PetscCall(BwNewtonResidual(nw, nw->xn, 1.0, nw->lambda_solved, nw->Ft, residual, &failed));
  PetscCall(BwJointFieldExtrapolationError(nw->field, error));
  *ok = failed ? PETSC_FALSE : PETSC_TRUE;
  if (failed) PetscCall(BwJointFieldFailed(nw->field, &failed, nw->reason, sizeof(nw->reason)));
  else PetscCall(BwJointFieldPlasticWork(nw->field, &nw->step_plastic));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonCommit(BwNewton nw)
{
  PetscFunctionBeginUser;
  PetscCall(VecCopy(nw->xn, nw->x));
  PetscCall(BwJointFieldCommit(nw->field));
  nw->last_dlambda = nw->lambda_trial;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonFailedElastic(BwNewton nw, PetscBool *elastic)
{
  PetscFunctionBeginUser;
  *elastic = nw->failed_elastic;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonGetResult(BwNewton nw, PetscInt *its, PetscReal *residual, const char **reason)
{
  PetscFunctionBeginUser;
  if (its) *its = nw->its;
  if (residual) *residual = nw->residual;
  if (reason) *reason = nw->reason;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonGetSolution(BwNewton nw, Vec *x, BwJointField *field)
{
  PetscFunctionBeginUser;
  if (x) *x = nw->x;
  if (field) *field = nw->field;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonGetLoads(BwNewton nw, PetscReal mu, PetscReal lambda, PetscReal load[])
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < nw->p->model->nd * nw->nb; i++) load[i] = mu * nw->load0[i] + lambda * nw->pattern[i];
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonGetCounts(BwNewton nw, PetscInt *iterations, PetscInt *solves, PetscLogDouble *setup)
{
  PetscFunctionBeginUser;
  if (setup) *setup = nw->log.seconds[BW_PHASE_SETUP];
  if (iterations) *iterations = nw->total_its;
  if (solves) *solves = nw->total_solves;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwNewtonRamp(BwNewton nw, PetscReal min_step, PetscInt *substeps, PetscBool *converged)
{
  PetscReal mu = 0, h = 1;
  PetscInt  good = 0;

  PetscFunctionBeginUser;
  *substeps  = 0;
  *converged = PETSC_FALSE;
  while (mu < 1) {
    PetscReal next = PetscMin(1.0, mu + h), lambda = 0;
    PetscBool ok;
    if (1 - next < 1e-12) next = 1;
    PetscCall(BwNewtonSolve(nw, next, &lambda, PETSC_FALSE, 0, &ok));
    if (ok) {
      PetscCall(BwNewtonCommit(nw));
      mu = next;
      (*substeps)++;
      if (++good >= 2) h = PetscMin(1.0, 2 * h);
    } else {
      good = 0;
      h /= 2;
      if (h < min_step) PetscFunctionReturn(PETSC_SUCCESS);
    }
  }
  *converged = PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}
