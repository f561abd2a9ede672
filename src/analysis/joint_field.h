/* BwJointField: the joint laws at every portion of the interfaces a rank
 * owns, with their state: what a nonlinear analysis carries from step to
 * step (the plastic jumps and the softening variables, model.md
 * "Nonlinear joints"), and what one evaluation leaves (the tangents for
 * the Newton matrix, the mode of each portion).
 *
 * The state of the last converged step is `committed`; an evaluation at a
 * trial solution (BwJointFieldLaw, the callback of BwMixedResidual) starts
 * from it and writes the trial state, so a failed step or a rejected line
 * search costs nothing to undo; BwJointFieldCommit accepts the trial.
 *
 * It lives with the analyses that carry it, above src/system and
 * src/model, because it is built on both: the owned interfaces and their
 * portions come from the mixed layout (BwMixed), each interface's law and
 * stiffness from the model (BwModelInterfaceLaw, model->kn, kt). src/law
 * below holds only the pointwise laws (registry and kernels), which the
 * model uses. */
#pragma once
#include "system/mixed.h"
#include "law/law.h"

typedef struct _n_BwJointField *BwJointField;

PetscErrorCode BwJointFieldCreate(BwMixed mixed, BwJointField *field);
PetscErrorCode BwJointFieldDestroy(BwJointField *field);
/* BwPortionLawFn: the stress of owned interface e (input index k) from its
 * jumps; a law that fails is recorded, not raised (BwJointFieldFailed). */
PetscErrorCode BwJointFieldLaw(void *field, PetscInt e, PetscInt k, const PetscReal jump[], PetscReal stress[]);
/* Before an evaluation: forget the failures of the last one. */
PetscErrorCode BwJointFieldBegin(BwJointField field);
/* After it (collective): whether a law failed on any rank, and a line
 * naming the first interface where it did. */
PetscErrorCode BwJointFieldFailed(BwJointField field, PetscBool *failed, char why[], size_t len);
/* The tangents of the last evaluation, or (committed) those the last
 * converged state was reached with, ns x ns per portion (BwMixedSetTangents).
 * The committed ones start a step: re-evaluated at the converged state
 * with a zero increment, a portion on its yield surface answers with its
 * elastic stiffness, a poor predictor of a flow that goes on. */
PetscErrorCode BwJointFieldGetTangents(BwJointField field, PetscBool committed, const PetscReal **tangent);
/* The plastic work of the step from the committed state to the last
 * evaluation (collective): sum over portions of A_p r . (jpl - jpl_n), r
 * the returned stress (backward Euler, as the return mapping itself). Zero
 * where nothing flows, and where a portion opens without tension (r = 0 on
 * the cut-off), whatever the quadrature error of an energy balance. */
PetscErrorCode BwJointFieldPlasticWork(BwJointField field, PetscReal *work);
/* The trial state becomes the committed one (a converged step). */
PetscErrorCode BwJointFieldCommit(BwJointField field);
/* Per owned portion: the committed mode (0 elastic, 1 open, 2 sliding,
 * 3 both; one per portion of the owned interfaces, in their order) and
 * plastic jump (slip, opening[, slip along b]; ns per portion), for
 * output; and the counts of open, sliding and both over all ranks. */
PetscErrorCode BwJointFieldGetState(BwJointField field, const signed char **mode, PetscReal **plastic);
PetscErrorCode BwJointFieldCount(BwJointField field, PetscInt count[4]);
/* Portions on the compressive cap (mode bit 4) over all ranks; they are
 * also counted above by their cut-off and cone bits (a portion only on the
 * cap as elastic there). */
PetscErrorCode BwJointFieldCountCrushed(BwJointField field, PetscInt *crushed);
/* A new step from the committed state: the portions' mode changes are
 * counted from here (BwJointFieldGetTangents). */
PetscErrorCode BwJointFieldBeginStep(BwJointField field);
/* Portions whose mode differs from the last call's (collective): how much
 * the active sets still move between Newton iterations. */
PetscErrorCode BwJointFieldModeChanges(BwJointField field, PetscBool first, PetscInt *changes);

/* IMPL-EX (Oliver, Huespe & Cante 2008): a step whose laws are linear.
 * With extrapolation on, every portion answers r = C (j - jpl~), jpl~ =
 * jpl_n + span * rate, rate the plastic jump's increment per unit of the
 * path parameter over the last committed step, with the elastic tangent C
 * and its committed state unchanged: no portion chooses a mode inside the
 * step, so the step is one linear solve whose answer is a continuous
 * function of its data (round-off cannot pick a branch). With it off the
 * laws return-map again; an evaluation then (BwJointFieldExtrapolationError)
 * is the step's implicit update: the state committed, and the difference
 * between its stresses and the extrapolated ones, the step's error.
 * span: the step's increment of the path parameter (> 0). */
PetscErrorCode BwJointFieldSetExtrapolation(BwJointField field, PetscBool on, PetscReal span);
/* Before the implicit evaluation that follows an extrapolated solve: the
 * next evaluation also measures, per portion, |C^-1/2 (r - r~)| against
 * the portion's own |C^-1/2 r| or strength (ft, c), at least 1 % of the
 * largest |C^-1/2 r| of the last measure; r the return mapping's stress,
 * r~ the extrapolated one at the same jumps. The get (collective) gives the
 * largest over all portions. */
PetscErrorCode BwJointFieldMeasureExtrapolation(BwJointField field);
PetscErrorCode BwJointFieldExtrapolationError(BwJointField field, PetscReal *error);
