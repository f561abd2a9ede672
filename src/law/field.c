/* BwJointField: see field.h. Storage per owned portion: the committed and
 * the trial state (4 each), the tangent (4), the plastic jump for output
 * (2), the mode of the last evaluation and of the last commit (1 byte
 * each). */
#include "law/field.h"
#include "util/compat.h"

struct _n_BwJointField {
  MPI_Comm        comm;
  BwModel         model;
  PetscInt        m, nown;
  const PetscInt *own;
  PetscReal      *committed, *trial, *tangent, *plastic, *committed_tangent;
  signed char    *mode, *committed_mode, *seen_mode, *older_mode, *flips;
  PetscInt        flip_limit, quiet;
  PetscReal      *newton_tangent;
  PetscInt        nfailed, failed_k;
  int             failed_status;
};

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
  f->m    = own.m;
  f->nown = own.nown_interfaces;
  f->own  = own.own_interfaces;
  n       = f->m * f->nown;
  PetscCall(PetscCalloc5(BW_LAW_NSTATE * n + 1, &f->committed, BW_LAW_NSTATE * n + 1, &f->trial, 4 * n + 1, &f->tangent, 2 * n + 1, &f->plastic, 4 * n + 1, &f->committed_tangent));
  PetscCall(PetscCalloc5(n + 1, &f->mode, n + 1, &f->committed_mode, n + 1, &f->seen_mode, n + 1, &f->older_mode, n + 1, &f->flips));
  PetscCall(PetscCalloc1(4 * n + 1, &f->newton_tangent));
  /* before any evaluation: the elastic tangents */
  for (PetscInt e = 0; e < f->nown; e++) {
    PetscInt k = f->own[e];
    for (PetscInt p = 0; p < f->m; p++) {
      PetscReal *c = f->tangent + 4 * (f->m * e + p);
      c[0]         = f->model->kt[k];
      c[3]         = f->model->kn[k];
    }
  }
  PetscCall(PetscArraycpy(f->committed_tangent, f->tangent, 4 * n));
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
  PetscInt     off = f->m * e;
  int          status;

  PetscFunctionBeginUser;
  PetscCall(BwModelInterfaceLaw(f->model, k, &law, par));
  law->kernel((int)f->m, par, f->committed + BW_LAW_NSTATE * off, jump, stress, f->tangent + 4 * off, f->trial + BW_LAW_NSTATE * off, f->mode + off, &status);
  if (status != BW_LAW_OK) {
    /* a finite stand-in keeps the residual evaluable; the step fails */
    if (!f->nfailed) {
      f->failed_k      = k;
      f->failed_status = status;
    }
    f->nfailed++;
    for (PetscInt p = 0; p < f->m; p++) {
      stress[2 * p]     = par[BW_LAW_PAR_KT] * (PetscIsNormalReal(jump[2 * p]) ? jump[2 * p] : 0);
      stress[2 * p + 1] = par[BW_LAW_PAR_KN] * (PetscIsNormalReal(jump[2 * p + 1]) ? jump[2 * p + 1] : 0);
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldFailed(BwJointField f, PetscBool *failed, char why[], size_t len)
{
  static const char *const reason[] = {"", "a non-positive stiffness", "an invalid strength", "no admissible stress (its return mapping did not converge)", "a non-finite jump", "a non-finite or negative state"};
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
    PetscCall(PetscSNPrintf(why, len, "the joint law of interface %" PetscInt_FMT " (blocks %" PetscInt_FMT ", %" PetscInt_FMT ") found %s", k, f->model->geom->pair[2 * k], f->model->geom->pair[2 * k + 1], stg > 0 && stg < 6 ? reason[stg] : "an error"));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldGetTangents(BwJointField f, PetscBool committed, const PetscReal **tangent)
{
  PetscInt n = f->m * f->nown;

  PetscFunctionBeginUser;
  if (committed) {
    *tangent = f->committed_tangent;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  /* A portion that keeps changing mode within a step sits at a kink of its
   * law, typically between softening and elastic unloading, where the two
   * one-sided tangents have opposite signs and Newton cycles. Such a
   * portion enters the Newton matrix with its elastic stiffness instead (a
   * secant bound on both sides): the iteration stays a descent for it and
   * converges, linearly in that portion, quadratically elsewhere. */
  PetscCall(PetscArraycpy(f->newton_tangent, f->tangent, 4 * n));
  for (PetscInt i = 0; i < n; i++)
    if (f->flips[i] >= f->flip_limit) {
      PetscInt   k = f->own[i / f->m];
      PetscReal *c = f->newton_tangent + 4 * i;
      c[0]         = f->model->kt[k];
      c[1] = c[2] = 0;
      c[3]         = f->model->kn[k];
    }
  *tangent = f->newton_tangent;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldBeginStep(BwJointField f)
{
  PetscInt n = f->m * f->nown;

  PetscFunctionBeginUser;
  PetscCall(PetscArrayzero(f->flips, n));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldCommit(BwJointField f)
{
  PetscInt n = f->m * f->nown;

  PetscFunctionBeginUser;
  PetscCall(PetscArraycpy(f->committed, f->trial, BW_LAW_NSTATE * n));
  PetscCall(PetscArraycpy(f->committed_mode, f->mode, n));
  PetscCall(PetscArraycpy(f->committed_tangent, f->tangent, 4 * n));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldGetState(BwJointField f, const signed char **mode, PetscReal **plastic)
{
  PetscInt n = f->m * f->nown;

  PetscFunctionBeginUser;
  if (mode) *mode = f->committed_mode;
  if (plastic) {
    for (PetscInt i = 0; i < n; i++) {
      f->plastic[2 * i]     = f->committed[BW_LAW_NSTATE * i + BW_LAW_STATE_SLIP];
      f->plastic[2 * i + 1] = f->committed[BW_LAW_NSTATE * i + BW_LAW_STATE_OPENING];
    }
    *plastic = f->plastic;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwJointFieldCount(BwJointField f, PetscInt count[4])
{
  PetscInt loc[4] = {0, 0, 0, 0};

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < f->m * f->nown; i++) loc[f->committed_mode[i] & 3]++;
  PetscCallMPI(MPI_Allreduce(loc, count, 4, MPIU_INT, MPI_SUM, f->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}


PetscErrorCode BwJointFieldModeChanges(BwJointField f, PetscBool first, PetscInt *changes)
{
  PetscInt loc = 0, n = f->m * f->nown;

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

