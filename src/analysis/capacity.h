/* What a pushover's capacity curve says, in the terms an assessment uses
 * (interface.md, "past the peak"): the first limit point, the residual
 * load, the displacement-controlled envelope of the curve and its
 * bilinearisation (NTC 2018 / Circolare 2019 for masonry: secant at 0.7
 * F_max, ultimate displacement at 0.8 F_max past the peak, equal energy).
 * Pure functions of the history (loads as load factors, displacements as
 * the monitor's values), the same on every rank. */
#pragma once
#include <petscsys.h>

typedef struct {
  PetscInt  first_peak;                /* step of the first limit point */
  PetscReal first_peak_load_factor, first_peak_monitor;
  PetscReal residual_load_factor, dissipated_energy;
  PetscReal max_load_factor;           /* F_max of the envelope */
  PetscReal stiffness;                 /* k: secant to 0.7 F_max */
  PetscReal ultimate_displacement;     /* d_u (a magnitude, from step 0) */
  PetscReal energy;                    /* E: area under the envelope to d_u */
  PetscReal yield_force, yield_displacement, ductility; /* NaN where no equal-energy root */
  char      note[256];                 /* why the bilinearisation is NaN, or "" */
} BwCapacity;

/* n steps (step 0 first): lambda, monitor and the cumulative dissipation
 * (NULL: 0); sign: the direction of the target (+1 or -1). */
PetscErrorCode BwCapacityCompute(PetscInt n, const PetscReal lambda[], const PetscReal monitor[], const PetscReal dissipation[], PetscReal sign, BwCapacity *cap);
