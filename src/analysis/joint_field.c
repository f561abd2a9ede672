/* BwJointField: see joint_field.h. Storage per owned portion, with ns stress
 * components (2 in 2D, 3 in 3D): the committed and the trial state (ns + 2
 * each), the tangent (ns x ns, committed and last), the plastic jump for
 * output (ns), the modes (1 byte each). Owned interface e's portions start
 * at poff[e]: m each in 2D, as many as its polygon has in 3D. */
#include "analysis/joint_field.h"
#include "util/compat.h"

struct _n_BwJointField {
  MPI_Comm        comm;
  BwModel         model;
  PetscInt        ns, nst, nown, *poff;
  const PetscInt *own;
  PetscReal      *committed, *trial, *tangent, *plastic, *committed_tangent;
  signed char    *mode, *committed_mode, *seen_mode, *older_mode, *flips;
  PetscInt        flip_limit, quiet;
  PetscReal      *newton_tangent;
  PetscReal      *stress;   /* the last evaluation's stresses (ns per portion) */
  const BwPortions *portions;
  PetscInt        nfailed, failed_k;
  int             failed_status;
  /* IMPL-EX: the plastic jump's rate per unit of the path parameter (ns per
   * portion, allocated on first use), the span of the step being solved
   * (0: none; the commit turns the step's increment into the rates), and
   * the measure of the implicit update (largest |C^-1/2 dr|, |C^-1/2 r|) */
  PetscReal      *rate, span, *elastic_tangent;
  PetscBool       extrapolate, measure;
  PetscReal       err_diff, err_scale, err_scale_last;
};

static const PetscInt BwJointFieldPlasticIndex[3] = {BW_LAW_STATE_SLIP, BW_LAW_STATE_OPENING, BW_LAW_STATE_SLIP_B};

/* IMPL-EX: component a of portion i's plastic jump extrapolated over the
 * step's span from its committed value and rate */
static inline PetscReal BwJointFieldExtrapolated(BwJointField f, PetscInt i, PetscInt a)
{
  return f->committed[f->nst * i + BwJointFieldPlasticIndex[a]] + f->span * f->rate[f->ns * i + a];
}

/* C = diag(kt, kn[, kt]) of interface k, ns x ns row-major. */
static void BwJointFieldElastic(BwJointField f, PetscInt k, PetscReal c[])
{
  for (PetscInt a = 0; a < f->ns * f->ns; a++) c[a] = 0;
  for (PetscInt a = 0; a < f->ns; a++) c[(f->ns + 1) * a] = a == 1 ? f->model->kn[k] : f->model->kt[k];
}

PetscErrorCode BwJointFieldCreate(BwMixed mixed, BwJointField *field)
{
  BwJointField     f;
  BwMixedOwnership own;
  PetscInt         n;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&f));
  PetscCall(BwMixedGetModel(mixed, &f->model));
  PetscCall(BwMixedGetOwnership(mixed, &own));
  f->comm = f->model->comm;
  f->ns   = own.ns;
  f->nst  = BW_LAW_NSTATE_OF(own.ns);
  f->nown = own.nown_interfaces;
  f->own  = own.own_interfaces;
  PetscCall(PetscMalloc1(f->nown + 1, &f->poff));
  f->poff[0] = 0;
  for (PetscInt e = 0; e < f->nown; e++) f->poff[e + 1] = f->poff[e] + BwPortionsCount(own.portions, f->own[e]);
  n = f->poff[f->nown];
  {
    const PetscInt ns = f->ns, nst = f->nst;
    PetscCall(PetscCalloc5(nst * n + 1, &f->committed, nst * n + 1, &f->trial, ns * ns * n + 1, &f->tangent, ns * n + 1, &f->plastic, ns * ns * n + 1, &f->committed_tangent));
    PetscCall(PetscCalloc5(n + 1, &f->mode, n + 1, &f->committed_mode, n + 1, &f->seen_mode, n + 1, &f->older_mode, n + 1, &f->flips));
    PetscCall(PetscCalloc1(ns * ns * n + 1, &f->newton_tangent));
    PetscCall(PetscCalloc1(ns * n + 1, &f->stress));
    /* before any evaluation: the elastic tangents */
    for (PetscInt e = 0; e < f->nown; e++)
      for (PetscInt p = f->poff[e]; p < f->poff[e + 1]; p++) BwJointFieldElastic(f, f->own[e], f->tangent + ns * ns * p);
    PetscCall(PetscArraycpy(f->committed_tangent, f->tangent, ns * ns * n));
  }
  f->portions   = own.portions;
  f->failed_k   = -1;
  f->flip_limit = 2;
  *field        = f;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldDestroy(BwJointField *field)
{
  PetscFunctionBeginUser;
  if (!*field) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFree5((*field)->committed, (*field)->trial, (*field)->tangent, (*field)->plastic, (*field)->committed_tangent));
  PetscCall(PetscFree5((*field)->mode, (*field)->committed_mode, (*field)->seen_mode, (*field)->older_mode, (*field)->flips));
  PetscCall(PetscFree((*field)->newton_tangent));
  PetscCall(PetscFree((*field)->stress));
  PetscCall(PetscFree((*field)->rate));
  PetscCall(PetscFree((*field)->elastic_tangent));
  PetscCall(PetscFree((*field)->poff));
  PetscCall(PetscFree(*field));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldBegin(BwJointField f)
{
  PetscFunctionBeginUser;
  f->nfailed       = 0;
  f->failed_k      = -1;
  f->failed_status = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldLaw(void *ctx, PetscInt e, PetscInt k, const PetscReal jump[], PetscReal stress[])
{
  BwJointField f = (BwJointField)ctx;
  BwJointLaw   law;
  PetscReal    par[BW_LAW_NPAR];
  PetscInt     off = f->poff[e], np = f->poff[e + 1] - off, ns = f->ns;
  int          status;

  PetscFunctionBeginUser;
  if (f->extrapolate) {
    /* IMPL-EX: linear in the jump; the trial state is the committed one
     * (set once per step, BwJointFieldSetExtrapolation) and the tangents
     * the elastic ones (BwJointFieldGetTangents) */
    const PetscReal kt = f->model->kt[k], kn = f->model->kn[k];
    for (PetscInt p = 0, i = off; p < np; p++, i++)
      for (PetscInt a = 0; a < ns; a++) stress[ns * p + a] = (a == 1 ? kn : kt) * (jump[ns * p + a] - BwJointFieldExtrapolated(f, i, a));
    PetscCall(PetscArraycpy(f->stress + ns * off, stress, ns * np));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(BwModelInterfaceLaw(f->model, k, &law, par));
  law->kernel((int)ns, (int)np, par, f->committed + f->nst * off, jump, stress, f->tangent + ns * ns * off, f->trial + f->nst * off, f->mode + off, &status);
  if (status == BW_LAW_OK) PetscCall(PetscArraycpy(f->stress + ns * off, stress, ns * np));
  if (status == BW_LAW_OK && f->measure) {
    /* the implicit update of an extrapolated step: how far the stresses
     * the step was solved with lie from the return mapping's, in the
     * energy norm (|C^-1/2 .|), against the portion's own stress or the
     * smaller of its strengths (a crack's error is measured on its tensile
     * strength, not on the crushing stress at the toe, and a large cohesion
     * that only keeps a joint from sliding does not hide it), at least 1 %
     * of the largest stress of the last measure */
    PetscReal sft = par[BW_LAW_PAR_FT] / PetscSqrtReal(par[BW_LAW_PAR_KN]), sc = par[BW_LAW_PAR_C] / PetscSqrtReal(par[BW_LAW_PAR_KT]);
    PetscReal strength = sft > 0 && sc > 0 ? PetscMin(sft, sc) : PetscMax(sft, sc);
    for (PetscInt p = 0, i = off; p < np; p++, i++) {
      PetscReal diff2 = 0, own2 = 0, scale;
      for (PetscInt a = 0; a < ns; a++) {
        PetscReal ka = a == 1 ? par[BW_LAW_PAR_KN] : par[BW_LAW_PAR_KT];
        PetscReal dr = stress[ns * p + a] - ka * (jump[ns * p + a] - BwJointFieldExtrapolated(f, i, a));
        diff2 += dr * dr / ka;
        own2 += stress[ns * p + a] * stress[ns * p + a] / ka;
      }
      scale        = PetscMax(PetscSqrtReal(own2), strength);
      f->err_scale = PetscMax(f->err_scale, scale);
      scale        = PetscMax(scale, 0.01 * f->err_scale_last);
      if (scale > 0) f->err_diff = PetscMax(f->err_diff, PetscSqrtReal(diff2) / scale);
    }
  }
  if (status != BW_LAW_OK) {
    /* a finite stand-in keeps the residual evaluable; the step fails */
    if (!f->nfailed) {
      f->failed_k      = k;
      f->failed_status = status;
    }
    f->nfailed++;
    for (PetscInt p = 0; p < np; p++)
      for (PetscInt a = 0; a < ns; a++) stress[ns * p + a] = par[a == 1 ? BW_LAW_PAR_KN : BW_LAW_PAR_KT] * (PetscIsNormalReal(jump[ns * p + a]) ? jump[ns * p + a] : 0);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldFailed(BwJointField f, PetscBool *failed, char why[], size_t len)
{
  static const char *const reason[] = {"", "a non-positive stiffness", "an invalid strength", "no admissible stress (its return mapping did not converge)", "a non-finite jump", "a non-finite or negative state", "a wrong number of stress components"};
  PetscInt                 loc[2] = {f->nfailed, f->nfailed ? -f->failed_k : PETSC_MIN_INT}, glob[2];

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(loc, glob, 2, MPIU_INT, MPI_MAX, f->comm));
  *failed = glob[0] > 0 ? PETSC_TRUE : PETSC_FALSE;
  if (why) why[0] = 0;
  if (*failed && why) {
    /* the lowest interface index that failed, with the reason its owner saw */
    PetscInt k = -glob[1];
    int      st = f->failed_k == k ? f->failed_status : 0, stg;
    PetscCallMPI(MPI_Allreduce(&st, &stg, 1, MPI_INT, MPI_MAX, f->comm));
    PetscCall(PetscSNPrintf(why, len, "the joint law of interface %" PetscInt_FMT " (blocks %" PetscInt_FMT ", %" PetscInt_FMT ") found %s", k, f->model->geom->pair[2 * k], f->model->geom->pair[2 * k + 1], stg > 0 && stg < 7 ? reason[stg] : "an error"));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldGetTangents(BwJointField f, PetscBool committed, const PetscReal **tangent)
{
  PetscInt nt = f->ns * f->ns;

  PetscFunctionBeginUser;
  if (committed && !f->extrapolate) {
    *tangent = f->committed_tangent;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  /* A portion that keeps changing mode within a step sits at a kink of its
   * law, typically between softening and elastic unloading, where the two
   * one-sided tangents have opposite signs and Newton cycles. Such a
   * portion enters the Newton matrix with its elastic stiffness instead (a
   * secant bound on both sides): the iteration stays a descent for it and
   * converges, linearly in that portion, quadratically elsewhere. */
  if (f->extrapolate) {
    /* IMPL-EX: the elastic stiffness everywhere, the same matrix every step */
    if (!f->elastic_tangent) {
      PetscCall(PetscMalloc1(nt * f->poff[f->nown] + 1, &f->elastic_tangent));
      for (PetscInt e = 0; e < f->nown; e++)
        for (PetscInt i = f->poff[e]; i < f->poff[e + 1]; i++) BwJointFieldElastic(f, f->own[e], f->elastic_tangent + nt * i);
    }
    *tangent = f->elastic_tangent;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscArraycpy(f->newton_tangent, f->tangent, nt * f->poff[f->nown]));
  for (PetscInt e = 0; e < f->nown; e++)
    for (PetscInt i = f->poff[e]; i < f->poff[e + 1]; i++)
      if (f->flips[i] >= f->flip_limit) BwJointFieldElastic(f, f->own[e], f->newton_tangent + nt * i);
  *tangent = f->newton_tangent;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldBeginStep(BwJointField f)
{
  PetscInt n = f->poff[f->nown];

  PetscFunctionBeginUser;
  PetscCall(PetscArrayzero(f->flips, n));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldCommit(BwJointField f)
{
  PetscInt n = f->poff[f->nown];

  PetscFunctionBeginUser;
  if (f->span > 0) {
    /* an IMPL-EX step: its plastic increment per unit span, for the next */
    const PetscInt ns = f->ns, nst = f->nst;
    for (PetscInt i = 0; i < n; i++)
      for (PetscInt a = 0; a < ns; a++) f->rate[ns * i + a] = (f->trial[nst * i + BwJointFieldPlasticIndex[a]] - f->committed[nst * i + BwJointFieldPlasticIndex[a]]) / f->span;
    f->span = 0;
  }
  PetscCall(PetscArraycpy(f->committed, f->trial, f->nst * n));
  PetscCall(PetscArraycpy(f->committed_mode, f->mode, n));
  PetscCall(PetscArraycpy(f->committed_tangent, f->tangent, f->ns * f->ns * n));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldPlasticWork(BwJointField f, PetscReal *work)
{
  const PetscInt *jpl = BwJointFieldPlasticIndex;
  PetscReal       loc = 0;
  const PetscInt  ns = f->ns, nst = f->nst;

  PetscFunctionBeginUser;
  if (f->extrapolate) {
    /* an extrapolated evaluation keeps the committed state: nothing flowed
     * (the implicit update's work is what counts); the flag is the same on
     * every rank, so every rank returns here */
    *work = 0;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  for (PetscInt e = 0; e < f->nown; e++) {
    const PetscReal *area = f->portions->area + BwPortionsFirst(f->portions, f->own[e]);
    for (PetscInt p = 0, i = f->poff[e]; i < f->poff[e + 1]; p++, i++)
      for (PetscInt a = 0; a < ns; a++) loc += area[p] * f->stress[ns * i + a] * (f->trial[nst * i + jpl[a]] - f->committed[nst * i + jpl[a]]);
  }
  PetscCallMPI(MPI_Allreduce(&loc, work, 1, MPIU_REAL, MPIU_SUM, f->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldGetState(BwJointField f, const signed char **mode, PetscReal **plastic)
{
  PetscInt n = f->poff[f->nown], ns = f->ns, nst = f->nst;

  PetscFunctionBeginUser;
  if (mode) *mode = f->committed_mode;
  if (plastic) {
    for (PetscInt i = 0; i < n; i++) {
      f->plastic[ns * i]     = f->committed[nst * i + BW_LAW_STATE_SLIP];
      f->plastic[ns * i + 1] = f->committed[nst * i + BW_LAW_STATE_OPENING];
      if (ns == 3) f->plastic[ns * i + 2] = f->committed[nst * i + BW_LAW_STATE_SLIP_B];
    }
    *plastic = f->plastic;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldCount(BwJointField f, PetscInt count[4])
{
  PetscInt loc[4] = {0, 0, 0, 0};

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < f->poff[f->nown]; i++) loc[f->committed_mode[i] & 3]++;
  PetscCallMPI(MPI_Allreduce(loc, count, 4, MPIU_INT, MPI_SUM, f->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldCountCrushed(BwJointField f, PetscInt *crushed)
{
  PetscInt loc = 0;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < f->poff[f->nown]; i++) loc += (f->committed_mode[i] & BW_LAW_MODE_CRUSHED) ? 1 : 0;
  PetscCallMPI(MPI_Allreduce(&loc, crushed, 1, MPIU_INT, MPI_SUM, f->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}


PetscErrorCode BwJointFieldModeChanges(BwJointField f, PetscBool first, PetscInt *changes)
{
  PetscInt loc = 0, n = f->poff[f->nown];

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < n; i++) {
    if (first) {
      /* the step's first evaluation (zero increment) is no iterate */
      f->seen_mode[i] = f->older_mode[i] = f->mode[i];
      continue;
    }
    if (f->mode[i] != f->seen_mode[i]) {
      loc++;
      /* back to the mode it had before: an oscillation */
      if (f->mode[i] == f->older_mode[i] && f->flips[i] < 100) f->flips[i]++;
      f->older_mode[i] = f->seen_mode[i];
      f->seen_mode[i]  = f->mode[i];
    }
  }
  PetscCallMPI(MPI_Allreduce(&loc, changes, 1, MPIU_INT, MPI_SUM, f->comm));
  /* the active sets have settled (two evaluations without a change):
   * consistent tangents again everywhere */
  f->quiet = first || *changes ? 0 : f->quiet + 1;
  if (f->quiet >= 2) PetscCall(PetscArrayzero(f->flips, n));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldSetExtrapolation(BwJointField f, PetscBool on, PetscReal span)
{
  PetscFunctionBeginUser;
  if (!f->rate) PetscCall(PetscCalloc1(f->ns * f->poff[f->nown] + 1, &f->rate));
  PetscCheck(!on || span > 0, f->comm, PETSC_ERR_ARG_OUTOFRANGE, "an extrapolated step needs a span > 0");
  if (on) {
    /* no portion leaves its committed state or mode within the step */
    PetscInt n = f->poff[f->nown];
    PetscCall(PetscArraycpy(f->trial, f->committed, f->nst * n));
    PetscCall(PetscArraycpy(f->mode, f->committed_mode, n));
  }
  f->extrapolate = on;
  f->measure     = PETSC_FALSE;
  f->span        = on ? span : 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldMeasureExtrapolation(BwJointField f)
{
  PetscFunctionBeginUser;
  PetscCheck(f->extrapolate && f->span > 0, f->comm, PETSC_ERR_ORDER, "the implicit update follows an extrapolated solve");
  f->extrapolate = PETSC_FALSE;
  f->measure     = PETSC_TRUE;
  f->err_diff    = 0;
  f->err_scale   = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldExtrapolationError(BwJointField f, PetscReal *error)
{
  PetscReal loc[2] = {f->err_diff, f->err_scale}, all[2];

  PetscFunctionBeginUser;
  PetscCallMPI(MPIU_Allreduce(loc, all, 2, MPIU_REAL, MPIU_MAX, f->comm));
  *error            = all[0];
  f->err_scale_last = all[1];
  f->measure = PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

