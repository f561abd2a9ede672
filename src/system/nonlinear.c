/* The residual of the mixed system with nonlinear joints (model.md,
 * "Nonlinear joints"), in the scaling of mixed.h:
 *
 *   F_r = -r~ + G^{1/2} sigma(j(q))       sigma: the joint law per portion
 *   F_q = D^T r~ + P q~ - b_q
 *
 * j(q) is the portion's jump with the prescribed values lifted; in the
 * scaled system (D^ q~ - b_r)_p = (a_t j_t, a_n j_n), a = sqrt(A_p k), and
 * G^{1/2} sigma = (A_p sigma_t / a_t, A_p sigma_n / a_n). With elastic
 * joints sigma = C j and F = K x - b exactly; otherwise dF/dx is K with
 * the laws' tangents (BwMixedSetTangents), the Newton matrix. The law is
 * a callback, so the system knows no law and the laws no scaling. */
#include "system/mixed_impl.h"
#include "util/compat.h"

PetscErrorCode BwMixedResidual(BwMixed mx, Vec x, Vec b, BwPortionLawFn law, void *ctx, Vec F)
{
  Vec          xr, xq, br, bq, fr, fq;
  PetscScalar *f;
  const PetscScalar *r;
  PetscReal   *jump, *sigma;
  const PetscInt ns = mx->ns;

  PetscFunctionBeginUser;
  PetscCall(VecGetSubVector(x, mx->isr, &xr));
  PetscCall(VecGetSubVector(x, mx->isq, &xq));
  PetscCall(VecGetSubVector(b, mx->isr, &br));
  PetscCall(VecGetSubVector(b, mx->isq, &bq));
  PetscCall(VecGetSubVector(F, mx->isr, &fr));
  PetscCall(VecGetSubVector(F, mx->isq, &fq));
  /* scaled jumps, then per interface: the law, and F_r in place */
  PetscCall(MatMult(mx->D, xq, fr));
  PetscCall(VecAXPY(fr, -1.0, br));
  PetscCall(PetscMalloc2(ns * mx->portions.maxnp, &jump, ns * mx->portions.maxnp, &sigma));
  PetscCall(VecGetArray(fr, &f));
  PetscCall(VecGetArrayRead(xr, &r));
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
    PetscInt           k  = mx->own_interfaces[e], off = mx->rrow[k] - mx->rstart;
    PetscScalar       *fk = f + off;
    const PetscScalar *rk = r + off;
    PetscReal          skt, skn;
    const PetscReal   *sqa;
    PetscInt           np = BwMixedPortions(mx, k, NULL, NULL, NULL, &sqa);
    /* D^ q is sqrt(A_p) C^1/2 j per portion; the law's stress enters the
     * scaled compatibility row as sqrt(A_p) C^-1/2 sigma */
    BwMixedStiffnessRoots(mx, k, &skt, &skn);
    for (PetscInt p = 0; p < np; p++)
      for (PetscInt a = 0; a < ns; a++) jump[ns * p + a] = PetscRealPart(fk[ns * p + a]) / (sqa[p] * (a == 1 ? skn : skt));
    PetscCall(law(ctx, e, k, jump, sigma));
    for (PetscInt p = 0; p < np; p++)
      for (PetscInt a = 0; a < ns; a++) fk[ns * p + a] = -rk[ns * p + a] + sqa[p] * sigma[ns * p + a] / (a == 1 ? skn : skt);
  }
  PetscCall(VecRestoreArrayRead(xr, &r));
  PetscCall(VecRestoreArray(fr, &f));
  PetscCall(PetscFree2(jump, sigma));
  /* equilibrium rows: D^T r~ + P q~ - b_q */
  PetscCall(VecPointwiseMult(fq, mx->pmask, xq));
  PetscCall(VecAXPY(fq, -1.0, bq));
  PetscCall(MatMultTransposeAdd(mx->D, xr, fq, fq));
  PetscCall(VecRestoreSubVector(F, mx->isq, &fq));
  PetscCall(VecRestoreSubVector(F, mx->isr, &fr));
  PetscCall(VecRestoreSubVector(b, mx->isq, &bq));
  PetscCall(VecRestoreSubVector(b, mx->isr, &br));
  PetscCall(VecRestoreSubVector(x, mx->isq, &xq));
  PetscCall(VecRestoreSubVector(x, mx->isr, &xr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMixedDofRow(BwMixed mx, PetscInt gblock, PetscInt dof, PetscInt *row, PetscReal *scale, PetscReal *value)
{
  const PetscInt nd = mx->nd, b = BwGeometryLocalBlock(mx->geom, gblock);
  PetscReal      loc[3] = {-2, 0, -PETSC_MAX_REAL}, glob[3];

  PetscFunctionBeginUser;
  PetscCheck(dof >= 0 && dof < nd, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "no dof %" PetscInt_FMT, dof);
  /* the owner knows; every rank learns */
  if (b >= 0 && b < mx->geom->nown_blocks) {
    loc[0] = mx->model->prescribed[nd * b + dof] || mx->krow_q[b] < 0 ? -1 : (PetscReal)(mx->krow_q[b] + dof);
    loc[1] = mx->qscale ? mx->qscale[nd * b + dof] : 1;
    loc[2] = mx->model->value[nd * b + dof];
  }
  PetscCallMPI(MPIU_Allreduce(loc, glob, 3, MPIU_REAL, MPIU_MAX, mx->comm));
  PetscCheck(glob[0] >= -1, mx->comm, PETSC_ERR_ARG_OUTOFRANGE, "no block %" PetscInt_FMT, gblock);
  *row = (PetscInt)glob[0];
  if (scale) *scale = glob[1];
  if (value) *value = glob[2];
  PetscFunctionReturn(PETSC_SUCCESS);
}
