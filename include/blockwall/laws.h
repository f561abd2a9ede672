/* C prototypes of the per-portion joint laws (src/kernels/joint_law_kernels.f90,
 * bind(C); model.md, "Nonlinear joints"). All are pure: data in, data out, no I/O,
 * no MPI; each reports a BwLawStatus through its last argument.
 *
 * Per portion (tension and opening positive): jump j = (dt, dn) [m], plastic jump
 * jpl = (slip, opening) [m], stress r = (rt, rn) = C (j - jpl) [Pa], C = diag(kt, kn).
 *   tension cut-off  f1 = rn - ft(k1) <= 0,                flow (0, 1),              dk1 = dl1
 *   Coulomb          f2 = |rt| + rn tanphi - c(k2) <= 0,   flow (sign(rt), tanpsi),  dk2 = dl2
 *   ft(k1) = ft0 exp(-ft0 k1 / GfI), c(k2) = c0 exp(-c0 k2 / GfII) when GfI, GfII > 0,
 *   constant (perfectly plastic) when GfI, GfII <= 0.
 * Backward Euler from state_in (the converged state of the previous step) to the trial
 * jump, multi-surface (Koiter) return with the cone as two surfaces sharing k2, and the
 * consistent tangent dr/dj (non-symmetric when tanpsi != tanphi, zero at a corner of
 * perfectly plastic surfaces, C when elastic). With tanpsi = 0 a trial above a cone
 * apex lying below the cut-off returns to the apex with the cut-off's flow (the cut-off
 * is lowered to min(ft, c/tanphi)): the cone alone has no normal flow there.
 * The local problem is solved reliably while the softening moduli stay below the
 * stiffnesses, ft0^2/GfI < kn and c0^2/GfII < kt; past them (a snap-back within one
 * portion) BW_LAW_NOT_CONVERGED may come back.
 *
 * Three dimensions (ns = 3): r = (rt, rn, rb), tau = (rt, rb), C = diag(kt, kn, kt);
 * the Coulomb surface is the circular cone |tau| + rn tanphi <= c(k2), its flow
 * (tau/|tau|, tanpsi), k2 the accumulated length of plastic slip. Every surface and
 * flow is radial in tau and C isotropic on it, so the return keeps the trial tau's
 * direction e and is the 2D return above in the meridian plane (|tau|, rn): apex and
 * corners included, exactly. Consistent 3x3 tangent with the circle's shrinking
 * kt (|tau|/|tau_tr|) (I - e e^T) on tau (model.md, "Three dimensions").
 *
 * Arguments: ns stress components per portion (2 in 2D, 3 in 3D); n portions of one
 * interface share par[BW_LAW_NPAR]. Arrays are interleaved per portion: jump[ns n]
 * and stress[ns n] in the order (shear t, normal[, shear b]), state_in[(ns+3) n] and
 * state_out[(ns+3) n] as BW_LAW_NSTATE_OF(ns) entries BW_LAW_STATE_*, tangent[ns ns n] as
 * the row-major ns x ns dr/dj (2D: drt/ddt, drt/ddn, drn/ddt, drn/ddn), mode[n] a
 * BwLawMode.
 * On a non-zero status the outputs are undefined (portions before the failing one are
 * written). The C caller validates user input and names the key; the status is a last
 * safety net. */
#pragma once

#ifdef __cplusplus
extern "C" {
#endif

/* Positions in par[BW_LAW_NPAR]. */
enum {
  BW_LAW_PAR_KT,     /* shear stiffness kt > 0 [N/m^3] */
  BW_LAW_PAR_KN,     /* normal stiffness kn > 0 [N/m^3] */
  BW_LAW_PAR_FT,     /* tensile strength ft0 >= 0 [Pa] */
  BW_LAW_PAR_C,      /* cohesion c0 >= 0 [Pa] */
  BW_LAW_PAR_TANPHI, /* friction coefficient tan(phi) >= 0 */
  BW_LAW_PAR_TANPSI, /* dilatancy tan(psi), 0 <= tan(psi) <= tan(phi) */
  BW_LAW_PAR_GFI,    /* mode I fracture energy [N/m]; <= 0: no tension softening */
  BW_LAW_PAR_GFII,   /* mode II fracture energy [N/m]; <= 0: no cohesion softening */
  BW_LAW_PAR_FC,     /* coulomb_cap: compressive strength fc > 0 [Pa] */
  BW_LAW_PAR_CSS,    /* coulomb_cap: shear term Css > 0 of the cap */
  BW_LAW_PAR_GFC,    /* coulomb_cap: compressive fracture energy Gfc [N/m]; <= 0: cap perfectly plastic at fc */
  BW_LAW_PAR_KP,     /* coulomb_cap: plastic jump kappa_p > 0 at the cap's peak [m] (read with Gfc > 0) */
  BW_LAW_NPAR
};

/* Positions in a portion's state (state_in, state_out). */
enum {
  BW_LAW_STATE_SLIP,    /* plastic slip [m] */
  BW_LAW_STATE_OPENING, /* plastic opening [m] */
  BW_LAW_STATE_K1,      /* accumulated plastic opening of the cut-off, >= 0 [m] */
  BW_LAW_STATE_K2,      /* accumulated plastic slip magnitude of the cone, >= 0 [m] */
  BW_LAW_STATE_K3,      /* accumulated length of the cap's plastic jump, >= 0 [m] (0 without a cap) */
  BW_LAW_NSTATE,        /* entries of a 2D portion's state */
  BW_LAW_STATE_SLIP_B = BW_LAW_NSTATE, /* 3D: plastic slip along b [m], last */
  BW_LAW_NSTATE_MAX     /* entries of a 3D portion's state */
};
/* Entries of a portion's state with ns stress components. */
#define BW_LAW_NSTATE_OF(ns) ((ns) + 3)

/* Which surfaces the returned stress lies on: a set of bits, so that a
 * corner is the sum of its surfaces. */
typedef enum {
  BW_LAW_MODE_ELASTIC = 0, /* no plastic flow in this step */
  BW_LAW_MODE_OPEN    = 1, /* on the tension cut-off */
  BW_LAW_MODE_SLIDING = 2, /* on the Coulomb cone, its apex included */
  BW_LAW_MODE_CORNER  = 3, /* on both (corner; apex on the cut-off, or lowered cut-off) */
  BW_LAW_MODE_CRUSHED = 4  /* on the compressive cap (6: its corner with the cone) */
} BwLawMode;

typedef enum {
  BW_LAW_OK            = 0,
  BW_LAW_BAD_STIFFNESS = 1, /* kt or kn <= 0 or not finite */
  BW_LAW_BAD_STRENGTH  = 2, /* ft, c, tanphi or tanpsi negative or not finite; tanpsi > tanphi;
                               GfI or GfII not finite, or ft/GfI, c/GfII not finite */
  BW_LAW_NOT_CONVERGED = 3, /* local Newton did not converge (or no admissible active set) */
  BW_LAW_BAD_JUMP      = 4, /* a jump component not finite */
  BW_LAW_BAD_STATE     = 5, /* a state component not finite, or k1, k2 < 0 */
  BW_LAW_BAD_SIZE      = 6  /* ns is neither 2 nor 3 */
} BwLawStatus;

/* Linear joint: stress = C (j - jpl) with jpl from state_in, tangent C, state_out =
 * state_in, mode 0. Only kt and kn of par are read (and checked). */
void bw_law_elastic(int ns, int n, const double par[], const double state_in[], const double jump[], double stress[],
                    double tangent[], double state_out[], signed char mode[], int *status);
/* Tension cut-off and Coulomb friction with optional exponential softening: the return
 * mapping above (in 3D on the cone's meridian plane), the consistent tangent, the
 * updated state and the mode. */
void bw_law_coulomb(int ns, int n, const double par[], const double state_in[], const double jump[], double stress[],
                    double tangent[], double state_out[], signed char mode[], int *status);
/* The same with the compressive cap f3 = rn^2 + Css |tau|^2 - sbar(k3)^2 <= 0 (model.md,
 * "Compressive cap"): associated flow, k3 the accumulated length of its plastic jump,
 * sbar hardening from fc/3 to fc at kappa_p and softening to fc/10 with Gfc past the
 * peak (constant fc without Gfc). Where the Coulomb return's stress lies outside the
 * cap: the return to the cap, else to its corner with the cone; for a given cap
 * multiplier mu the stress is explicit (r_a = r_tr,a / (1 + 2 mu C_aa Css_a), less the
 * cone's flow at the corner), so the return is one bracketed scalar equation in mu.
 * Consistent tangent by implicit differentiation of the local system; non-symmetric
 * while sbar varies. */
void bw_law_coulomb_cap(int ns, int n, const double par[], const double state_in[], const double jump[], double stress[],
                        double tangent[], double state_out[], signed char mode[], int *status);

#ifdef __cplusplus
}
#endif
