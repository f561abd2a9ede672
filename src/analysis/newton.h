/* BwNewton: the equilibrium of the mixed system with nonlinear joints at
 * one load level, by Newton's method on the full system (model.md,
 * "Nonlinear joints"), starting from the last converged state.
 *
 * The right-hand side is b = mu b0 + lambda bP: b0 the constant loads with
 * the prescribed values, bP the load pattern. Under load control lambda is
 * given; under displacement control lambda is an unknown and one dof (the
 * monitor) is prescribed instead: each iteration solves K dx1 = -F and
 * K dx2 = bP with the same factor and takes dlambda from the constraint
 * (bordering). The Newton matrix is K with the joint laws' tangents
 * (BwMixedSetTangents: S^ refilled in place, refactored on the same
 * analysis). A backtracking line search on the true residual ||F|| keeps
 * iterates from overshooting where portions open or slide.
 *
 * Converged when the true residual of the full mixed system, relative to
 * max(||b||, ||r~||), is below the tolerance (and the monitor sits at its
 * target). A step that fails (the iteration limit, a singular Newton
 * matrix, a law that finds no admissible stress, a residual that grows a
 * million-fold) leaves the committed state as it was: the caller cuts the
 * step. */
#pragma once
#include "analysis/analysis.h"
#include "analysis/joint_field.h"

typedef struct _n_BwNewton *BwNewton;

/* pattern: the load pattern P (3 per block, replicated; NULL: none), load0
 * the constant loads F0 (3 per block). */
PetscErrorCode BwNewtonCreate(BwProblem *p, const PetscReal load0[], const PetscReal pattern[], BwNewton *newton);
PetscErrorCode BwNewtonDestroy(BwNewton *newton);
PetscErrorCode BwNewtonSetTolerances(BwNewton newton, PetscReal rtol, PetscInt maxit);
/* The monitor dof `dof` of global block `block`: under displacement control it follows
 * the values given to BwNewtonSolve, which needs it free; a prescribed one
 * (load control of an assembly whose every dof is prescribed) reads its
 * prescribed value. */
PetscErrorCode BwNewtonSetMonitor(BwNewton newton, PetscInt block, PetscInt dof);
/* The monitor's current physical value (collective). */
PetscErrorCode BwNewtonMonitorValue(BwNewton newton, PetscReal *value);
/* Solves for the state at (mu, lambda) under load control, or at (mu,
 * monitor = target) under displacement control (*lambda: in, the last
 * converged value; out, the new one). On success the joint field's trial
 * state is the new one (BwNewtonCommit accepts it); on failure the
 * solution is restored and *converged is false, with the reason. */
PetscErrorCode BwNewtonSolve(BwNewton newton, PetscReal mu, PetscReal *lambda, PetscBool displacement, PetscReal target, PetscBool *converged);
/* The controls of a step: lambda given; the monitor given (lambda an
 * unknown); the energy the step dissipates given (lambda an unknown). */
typedef enum { BW_NEWTON_LOAD, BW_NEWTON_DISPLACEMENT, BW_NEWTON_DISSIPATION } BwNewtonControl;
/* Dissipation control (constant loads held, mu = 1): the step from the
 * committed state that dissipates `energy` [J] (loads' work minus the
 * change of stored elastic energy; newton.c, BwNewtonEnergy), lambda an
 * unknown of a bordered Newton (two solves per iteration with the same
 * factor). Fails in an elastic state, where no lambda changes the
 * dissipation to first order. */
PetscErrorCode BwNewtonSolveDissipation(BwNewton newton, PetscReal *lambda, PetscReal energy, PetscBool *converged);
/* The last converged step's work of the loads and energy dissipated [J];
 * the work is counted without cancellation, |constant loads' work| +
 * |the pattern's work|, the scale a dissipation is measured against. */
PetscErrorCode BwNewtonGetStepEnergy(BwNewton newton, PetscReal *work, PetscReal *dissipation);
/* The portions' own plastic work over the last converged solve, sum of
 * A_p r . d jpl (BwJointFieldPlasticWork): zero where nothing flows or a
 * portion opens without tension, whatever the quadrature error of the
 * energy balance above. */
PetscErrorCode BwNewtonGetStepPlasticWork(BwNewton nw, PetscReal *plastic);
/* The constant loads applied from the unloaded state (mu: 0 -> 1, lambda
 * = 0), under load control, in one step cut in halves where Newton fails
 * (down to min_step) and lengthened again after successes; each converged
 * part is committed. *substeps: how many it took. */
PetscErrorCode BwNewtonRamp(BwNewton newton, PetscReal min_step, PetscInt *substeps, PetscBool *converged);
/* IMPL-EX steps (joint_field.h, BwJointFieldSetExtrapolation): with `on`,
 * the next solves see every law extrapolated over `span` of the path
 * parameter, linear with the elastic tangent, so BwNewtonSolve converges in
 * one iteration on a matrix that does not change from step to step;
 * BwNewtonImplicitUpdate then return-maps every portion at the solved jumps
 * (the state BwNewtonCommit accepts, whose plastic increment gives the next
 * step's rates) and gives the step's errors (BwJointFieldExtrapolationError), and the
 * true residual of the mixed system with the return-mapped stresses. */
PetscErrorCode BwNewtonSetExtrapolation(BwNewton newton, PetscBool on, PetscReal span);
PetscErrorCode BwNewtonImplicitUpdate(BwNewton newton, PetscReal *error, PetscReal *residual, PetscBool *ok);
/* Accept the last converged solve as the state further steps start from. */
PetscErrorCode BwNewtonCommit(BwNewton newton);
/* The last solve: iterations, relative true residual, the reason it failed. */
PetscErrorCode BwNewtonGetResult(BwNewton newton, PetscInt *its, PetscReal *residual, const char **reason);
/* Whether the last dissipation-controlled solve failed because the state
 * is elastic (the constraint does not see lambda), not because Newton did
 * not converge. */
PetscErrorCode BwNewtonFailedElastic(BwNewton newton, PetscBool *elastic);
/* The committed solution (K layout) and the joint field. */
PetscErrorCode BwNewtonGetSolution(BwNewton newton, Vec *x, BwJointField *field);
/* The loads of the committed state, mu F0 + lambda P (3 per block, replicated). */
PetscErrorCode BwNewtonGetLoads(BwNewton newton, PetscReal mu, PetscReal lambda, PetscReal load[]);
/* Totals over the run: Newton iterations, linear solves, seconds spent
 * setting the solver up (factorisations of the Newton matrices). */
PetscErrorCode BwNewtonGetCounts(BwNewton newton, PetscInt *iterations, PetscInt *solves, PetscLogDouble *setup);
