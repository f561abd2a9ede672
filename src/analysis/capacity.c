/* BwCapacity: see capacity.h. */
#include <math.h>
#include <string.h>
#include "analysis/capacity.h"
#include "util/compat.h"

/* The displacement-controlled envelope: d measured from step 0 along the
 * target's sign; a step enters when it reaches a new maximum of d, and
 * where the path comes back past that maximum after a snap-back the point
 * at it (interpolated on the step that crosses it) enters first: the
 * snap-back becomes a vertical drop. */
static PetscErrorCode BwCapacityEnvelope(PetscInt n, const PetscReal lambda[], const PetscReal monitor[], PetscReal sign, PetscInt *ne, PetscReal **d, PetscReal **f)
{
  PetscReal dmax;
  PetscInt  k = 0;
  PetscBool behind = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(2 * n + 1, d, 2 * n + 1, f));
  (*d)[k]   = 0;
  (*f)[k++] = lambda[0];
  dmax      = 0;
  for (PetscInt i = 1; i < n; i++) {
    PetscReal di = sign * (monitor[i] - monitor[0]), dp = sign * (monitor[i - 1] - monitor[0]);
    if (di > dmax) {
      if (behind && di > dp) {
        PetscReal a = (dmax - dp) / (di - dp);
        (*d)[k]   = dmax;
        (*f)[k++] = lambda[i - 1] + a * (lambda[i] - lambda[i - 1]);
      }
      (*d)[k]   = di;
      (*f)[k++] = lambda[i];
      dmax      = di;
      behind    = PETSC_FALSE;
    } else behind = PETSC_TRUE;
  }
  *ne = k;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwCapacityCompute(PetscInt n, const PetscReal lambda[], const PetscReal monitor[], const PetscReal dissipation[], PetscReal sign, BwCapacity *cap)
{
  PetscReal *d, *f, fmax = -PETSC_MAX_REAL, d07 = NAN, du, e = 0;
  PetscInt   ne = 0, imax = 0;
  PetscBool  found = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(cap, sizeof(*cap)));
  cap->first_peak = n - 1;
  for (PetscInt i = 0; i + 1 < n; i++)
    if (lambda[i + 1] < lambda[i]) {
      cap->first_peak = i;
      break;
    }
  if (cap->first_peak == n - 1)
    for (PetscInt i = 0; i < n; i++)
      if (lambda[i] > lambda[cap->first_peak]) cap->first_peak = i;
  cap->first_peak_load_factor = lambda[cap->first_peak];
  cap->first_peak_monitor     = monitor[cap->first_peak];
  cap->residual_load_factor   = lambda[n - 1];
  cap->dissipated_energy      = dissipation ? dissipation[n - 1] : 0;

  PetscCall(BwCapacityEnvelope(n, lambda, monitor, sign, &ne, &d, &f));
  for (PetscInt i = 0; i < ne; i++)
    if (f[i] > fmax) {
      fmax = f[i];
      imax = i;
    }
  cap->max_load_factor = fmax;
  /* k: the secant to the first point at 0.7 F_max */
  for (PetscInt i = 1; i < ne && isnan(d07); i++)
    if (f[i] >= 0.7 * fmax) {
      PetscReal a = f[i] > f[i - 1] ? (0.7 * fmax - f[i - 1]) / (f[i] - f[i - 1]) : 1;
      d07         = d[i - 1] + a * (d[i] - d[i - 1]);
    }
  cap->stiffness = d07 > 0 ? 0.7 * fmax / d07 : NAN;
  /* d_u: the first fall to 0.8 F_max after F_max, else the last point */
  du = d[ne - 1];
  for (PetscInt i = imax + 1; i < ne; i++)
    if (f[i] <= 0.8 * fmax) {
      PetscReal a = f[i - 1] > f[i] ? (f[i - 1] - 0.8 * fmax) / (f[i - 1] - f[i]) : 1;
      du          = d[i - 1] + a * (d[i] - d[i - 1]);
      found       = PETSC_TRUE;
      /* the area to d_u ends on the interpolated point */
      for (PetscInt j = 1; j < i; j++) e += 0.5 * (f[j] + f[j - 1]) * (d[j] - d[j - 1]);
      e += 0.5 * (f[i - 1] + 0.8 * fmax) * (du - d[i - 1]);
      break;
    }
  if (!found)
    for (PetscInt j = 1; j < ne; j++) e += 0.5 * (f[j] + f[j - 1]) * (d[j] - d[j - 1]);
  cap->ultimate_displacement = du;
  cap->energy                = e;
  {
    PetscReal k = cap->stiffness, disc = du * du - 2 * e / k;
    /* an elastic-brittle envelope (a snap-back from the elastic branch)
     * has 2 E/k = d_u^2 up to round-off: F_y = F_max, ductility 1 */
    if (disc < 0 && disc > -1e-9 * du * du) disc = 0;
    if (!(k > 0)) {
      cap->yield_force = cap->yield_displacement = cap->ductility = NAN;
      PetscCall(PetscSNPrintf(cap->note, sizeof(cap->note), "no bilinearisation: the envelope never reaches 0.7 of its maximum above step 0"));
    } else if (disc < 0) {
      cap->yield_force = cap->yield_displacement = cap->ductility = NAN;
      PetscCall(PetscSNPrintf(cap->note, sizeof(cap->note), "no equal-energy bilinearisation: the curve still hardens at d_u (2 E/k = %.3g > d_u^2 = %.3g)", (double)(2 * e / k), (double)(du * du)));
    } else {
      cap->yield_force        = k * (du - PetscSqrtReal(disc));
      cap->yield_displacement = cap->yield_force / k;
      cap->ductility          = cap->yield_displacement > 0 ? du / cap->yield_displacement : NAN;
    }
  }
  PetscCall(PetscFree2(d, f));
  PetscFunctionReturn(PETSC_SUCCESS);
}
