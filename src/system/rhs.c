/* The right-hand side of the scaled mixed system, filled in one place:
 *
 *   stress rows of interface k:  -G^{-1/2} D_p u_p, the prescribed values u_p
 *                                of its two blocks lifted: portion p gets
 *                                -(a_t j_t, a_n j_n), j = E_p (R B) u_p
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
    PetscReal        rb[18], v[6], dg[3] = {0, 0, 0}, skt, skn;
    const PetscReal *xi, *eta, *sqa;
    PetscInt         np = BwMixedPortions(mx, k, NULL, &xi, &eta, &sqa);
    PetscScalar     *y  = bb + (mx->krow_r[k] - mx->kstart);
    int              status;
    PetscCall(BwMixedCompatibility(mx, k, rb));
    for (PetscInt c = 0; c < 6; c++) {
      PetscInt blk = g->pair[2 * k + c / 3];
      v[c]         = model->prescribed[3 * blk + c % 3] ? model->value[3 * blk + c % 3] : 0;
    }
    for (PetscInt r = 0; r < 3; r++)
      for (PetscInt c = 0; c < 6; c++) dg[r] += rb[6 * r + c] * v[c];
    bw_kernel_jumps(2, (int)np, xi, eta, dg, y, &status);
    PetscCheck(status == BW_KERNEL_OK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "kernel failed on interface %" PetscInt_FMT, k);
    BwMixedStiffnessRoots(mx, k, &skt, &skn);
    for (PetscInt p = 0; p < np; p++) {
      y[2 * p]     = -sqa[p] * skt * y[2 * p];
      y[2 * p + 1] = -sqa[p] * skn * y[2 * p + 1];
    }
  }
  for (PetscInt e = 0; e < mx->nown_blocks; e++) {
    PetscInt bl = mx->own_blocks[e];
    if (mx->krow_q[bl] < 0) continue;
    for (PetscInt c = 0; c < 3; c++) bb[mx->krow_q[bl] - mx->kstart + c] = model->prescribed[3 * bl + c] ? 0 : mx->qscale[3 * bl + c] * load[3 * bl + c];
  }
  PetscCall(VecRestoreArray(b, &bb));
  PetscFunctionReturn(PETSC_SUCCESS);
}
