/* The right-hand side of the scaled mixed system, filled in one place:
 *
 *   stress rows of interface k:  -G^{-1/2} D_p u_p, the prescribed values u_p
 *                                of its two blocks lifted: portion p gets
 *                                -sqrt(A_p) C^1/2 j, j = E_p (R B) u_p
 *   dof rows of block b:         diag(S)^{-1/2} F_b, 0 at prescribed dofs
 *                                (their identity rows keep them at zero)
 *
 * Both use the kernels that define D^ (bw_kernel_jumps). */
#include "system/mixed_impl.h"
#include "util/compat.h"
#include "blockwall/kernels.h"

PetscErrorCode BwMixedFillRHS(BwMixed mx, const PetscReal load[], Vec b)
{
  BwGeometry   g = mx->geom;
  BwModel      model = mx->model;
  PetscScalar *bb;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(b, &bb));
  for (PetscInt e = 0; e < mx->nown_interfaces; e++) {
    PetscInt     k = mx->own_interfaces[e];
    const PetscInt   nd = mx->nd, ns = mx->ns;
    PetscReal        rb[2 * BW_MAX_ND * BW_MAX_ND], v[2 * BW_MAX_ND], dg[BW_MAX_ND] = {0}, skt, skn;
    const PetscReal *xi, *eta, *sqa;
    PetscInt         np = BwMixedPortions(mx, k, NULL, &xi, &eta, &sqa);
    PetscScalar     *y  = bb + (mx->krow_r[k] - mx->kstart);
    int              status;
    PetscCall(BwMixedCompatibility(mx, k, rb));
    for (PetscInt c = 0; c < 2 * nd; c++) {
      PetscInt blk = g->pair[2 * k + c / nd];
      v[c]         = model->prescribed[nd * blk + c % nd] ? model->value[nd * blk + c % nd] : 0;
    }
    for (PetscInt r = 0; r < nd; r++)
      for (PetscInt c = 0; c < 2 * nd; c++) dg[r] += rb[2 * nd * r + c] * v[c];
    bw_kernel_jumps((int)mx->dim, (int)np, xi, eta, dg, y, &status);
    PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "kernel failed on interface %" PetscInt_FMT, k);
    BwMixedStiffnessRoots(mx, k, &skt, &skn);
    for (PetscInt p = 0; p < np; p++)
      for (PetscInt a = 0; a < ns; a++) y[ns * p + a] = -sqa[p] * (a == 1 ? skn : skt) * y[ns * p + a];
  }
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt bl = mx->own_blocks[e];
    if (mx->krow_q[bl] < 0) continue;
    for (PetscInt c = 0; c < mx->nd; c++) bb[mx->krow_q[bl] - mx->kstart + c] = model->prescribed[mx->nd * bl + c] ? 0 : mx->qscale[mx->nd * bl + c] * load[mx->nd * bl + c];
  }
  PetscCall(VecRestoreArray(b, &bb));
  PetscFunctionReturn(PETSC_SUCCESS);
}
