/* BwMixed: the mixed saddle-point system of model.md, distributed, in the
 * symmetric scaling that makes the compliance block the identity.
 *
 * Unknowns per rank, in this order: the stresses of the interfaces it owns
 * (2m each, a (shear, normal) pair per portion, so the (r,r) block is 2x2
 * block-diagonal), then 3 dofs for each block it owns that has a free dof.
 * A fully prescribed block has no unknown; a prescribed dof of a block with
 * free ones is an identity row, so that every block's three dofs are one
 * block of 3 (GAMG aggregates and smooths by node). Prescribed values are
 * lifted to the right-hand side. With
 *   r~ = G^{1/2} r,  q~ = diag(S)^{1/2} q,  D^ = G^{-1/2} D diag(S)^{-1/2}
 * (G_p = A_p C^-1 with C = diag(kt, kn) the joint's elastic stiffness) the
 * system solved is
 *
 *   [ -I    T D^ ] [ r~ ]   [ -G^{-1/2} D_p u_p ]
 *   [ D^T   P    ] [ q~ ] = [ diag(S)^{-1/2} F  ]
 *
 * T = C^{-1/2} C_t C^{-1/2} per portion, C_t the joint law's tangent: the
 * identity for elastic joints, where the system is the linear one; a 2x2
 * block per portion otherwise (the Newton system of a nonlinear step). P is
 * 1 at prescribed dofs, 0 elsewhere. Every scaled unknown is in sqrt(N m),
 * so residual norms compare like with like; D^ has unit-norm columns. The
 * Schur complement S^ = D^T T D^ + P is assembled interface by interface
 * from the kernels, exact because the (r,r) block is the identity; its
 * values are refilled in place when the tangents change (same pattern). */
#pragma once
#include <petscksp.h>
#include "model/model.h"
#include "system/portions.h"

typedef enum { BW_STORAGE_SHELL = 0, BW_STORAGE_NEST = 1, BW_STORAGE_AIJ = 2 } BwStorage;
extern const char *const BwStorages[];

typedef struct _n_BwMixed *BwMixed;

/* Layout of the model's distributed geometry (its local piece) and the
 * restraint check. */
PetscErrorCode BwMixedCreate(BwModel model, BwMixed *mixed);
/* The operators K (shell, or AIJ with storage aij) and S^ with the elastic
 * tangents. */
PetscErrorCode BwMixedSetUp(BwMixed mixed, BwStorage storage);
/* Before BwMixedSetUp: the operators' values will never change (a linear
 * analysis of elastic joints: no tangents, no spring), so S^ may leave out
 * its entries that are round-off of zero (stiffness.c): an assembly
 * symmetric about a plane normal to X3 then factors as two independent
 * problems. BwMixedSetTangents and BwMixedSetSpring are errors after it. */
PetscErrorCode BwMixedSetValuesFixed(BwMixed mixed, PetscBool fixed);
/* How many independent groups of dof kinds S^ splits into (1: none) and,
 * when more than one, their dof names ("u1 u2 w3 | u3 w1 w2"). */
PetscErrorCode BwMixedGetSchurGroups(BwMixed mixed, PetscInt *ngroups, char desc[], size_t len);
PetscErrorCode BwMixedDestroy(BwMixed *mixed);

/* New tangents: 4 per portion of every owned interface, the joint laws'
 * physical dr/dj in the order of BwMixedGetOwnership's interfaces (NULL:
 * the elastic ones). S^'s values are refilled in place and K follows. */
PetscErrorCode BwMixedSetTangents(BwMixed mixed, const PetscReal tangent[]);
/* A spring of `stiffness` (scaled: 1 is the dof's own elastic stiffness)
 * on dof `dof` of global block `block` in K and S^ (block -1: none). Displacement
 * control solves with it, so that the Newton matrix stays regular on a
 * plateau where the structure has no stiffness along the monitor dof; the
 * residual (BwMixedResidual) never sees it. */
PetscErrorCode BwMixedSetSpring(BwMixed mixed, PetscInt block, PetscInt dof, PetscReal stiffness);
/* The right-hand side for loads F (3 per block, physical) and the model's
 * prescribed values; the one place b is filled. */
PetscErrorCode BwMixedFillRHS(BwMixed mixed, const PetscReal load[], Vec b);

PetscErrorCode BwMixedCreateVecs(BwMixed mixed, Vec *x, Vec *b);
/* The whole operator K, the Schur complement S^, D^ (r rows, q columns). */
PetscErrorCode BwMixedGetOperators(BwMixed mixed, Mat *K, Mat *S, Mat *D);
/* A counter bumped by every BwMixedSetTangents: a copy of the operators
 * (the direct path's assembled K) is stale when it differs. */
PetscErrorCode BwMixedGetValuesState(BwMixed mixed, PetscInt *state);
/* The stress rows and the dof rows of a K-vector (contiguous on each rank). */
PetscErrorCode BwMixedGetFields(BwMixed mixed, IS *isr, IS *isq);
/* Applies the tangent T to the stress part (in place): y_r <- T y_r. */
PetscErrorCode BwMixedApplyTangent(BwMixed mixed, Vec yr);
/* The prescribed-dof mask P of the q rows (1 at prescribed dofs). */
PetscErrorCode BwMixedGetPrescribedMask(BwMixed mixed, Vec *mask);
/* The refinement on the block dofs (solver.c): the stresses eliminated
 * exactly, r~ = T D^ q~ - b_r, leave S~ q~ = b_q + D^T b_r with
 * S~ = D^T T D^ + P. BwMixedCreateSchurOperator: S~ applied exactly, not
 * from the assembled S^ (whose round-off the refinement corrects), and
 * without a vector of the stresses' size; BwMixedSchurRHS: w = b_q + D^T
 * b_r (w of q size); BwMixedStressesFromDofs: x_r = T D^ x_q - b_r. */
PetscErrorCode BwMixedCreateSchurOperator(BwMixed mixed, Mat *S);
PetscErrorCode BwMixedSchurRHS(BwMixed mixed, Vec b, Vec w);
PetscErrorCode BwMixedStressesFromDofs(BwMixed mixed, Vec b, Vec x);
/* The round-off bound of the displacements without K assembled
 * (solver/estimates.c; operator.c says how): whether this operator has it
 * (D^ held by its structure, elastic, no spring); the q rows' terms hq and
 * the stress rows' gamma_r; and one pass over the stress rows for the bound's estimate
 * (*l1 and acc = D^T (h_r .* sign(h_r .* D^ z))). */
PetscErrorCode BwMixedRoundoffSupported(BwMixed mixed, PetscBool *yes);
/* ||(|w| + |P| |q| + |D^T| |D^| |q|)||_2: eps times it is the floor of the
 * residual w - S~ q that rounding q to double leaves (operator.c). */
PetscErrorCode BwMixedSchurTermsNorm(BwMixed mixed, Vec q, Vec w, PetscReal *norm);
PetscErrorCode BwMixedRoundoffQ(BwMixed mixed, Vec x, Vec b, Vec hq, PetscReal *gamma_r);
PetscErrorCode BwMixedRoundoffSweep(BwMixed mixed, Vec x, Vec b, PetscReal gamma, Vec z, Vec acc, PetscReal *l1);
/* r_q = b_q - P x_q + D^T (b_r - D^ x_q) in double-double, rounded once
 * (operator.c), for the same operators. */
PetscErrorCode BwMixedResidualExtra(BwMixed mixed, Vec x, Vec b, Vec rq);
/* K as one AIJ matrix (new), for a direct factorisation. */
PetscErrorCode BwMixedCreateAIJ(BwMixed mixed, Mat *aij);
/* Rigid motions of the whole assembly in the scaled dofs (GAMG's near-null
 * space), attached to S^; in 3D also the three constant-curvature bending
 * modes of the plane the block centroids spread in (a wall bending as a
 * plate). */
PetscErrorCode BwMixedSetNearNullSpace(BwMixed mixed);
/* Weight of each q row for the forward-error norm: the dof's scale (times
 * the assembly's size for rotations), 0 at prescribed dofs; and the largest
 * weighted prescribed value. */
PetscErrorCode BwMixedForwardWeights(BwMixed mixed, Vec weight, PetscReal *prescribed);

/* Nonlinear joints (nonlinear.c). The law of owned interface e (input
 * index k): stress[2m] from jump[2m], physical, (shear, normal) per portion. */
typedef PetscErrorCode (*BwPortionLawFn)(void *ctx, PetscInt e, PetscInt k, const PetscReal jump[], PetscReal stress[]);
/* F = [-r~ + G^{1/2} sigma(j(q)); D^T r~ + P q~ - b_q] at x for the right-hand
 * side b (its stress rows lift the prescribed values): K x - b when the
 * law is elastic; its derivative is K with the laws' tangents. */
PetscErrorCode BwMixedResidual(BwMixed mixed, Vec x, Vec b, BwPortionLawFn law, void *ctx, Vec F);
/* The global row in K of dof `dof` (0 u1, 1 u2, 2 w) of global block
 * `gblock`, -1 if the dof is prescribed; the physical value is scale times
 * the scaled one; value: its prescribed value (0 where free). Collective:
 * every rank gets the owner's answer. */
PetscErrorCode BwMixedDofRow(BwMixed mixed, PetscInt gblock, PetscInt dof, PetscInt *row, PetscReal *scale, PetscReal *value);

/* Sizes and ownership, for output and analyses. */
typedef struct {
  PetscInt        nblocks, ninterfaces, m;
  PetscInt        dim, nd, ns;         /* 2 | 3; dofs per block; stresses per portion */
  const BwPortions *portions;          /* the portions of every interface */
  PetscInt        nown_blocks, nown_interfaces;
  const PetscInt *own_blocks, *own_interfaces; /* ascending local indices in the geometry's piece */
  PetscInt        nq_global, nr_global;
  const PetscInt *own_block_gid;      /* global ids of the owned blocks (ascending) */
  const PetscInt *own_interface_gid;  /* global ids of the owned interfaces (ascending) */
  const PetscInt *own_portion_start;  /* per owned interface: its first row in the /portions datasets */
  PetscInt        nportions_global;
  PetscInt        edge_cut;  /* interfaces whose two blocks live on different ranks (0 on one) */
  PetscReal       imbalance; /* the largest rank's blocks over the mean (1 on one rank) */
} BwMixedOwnership;
PetscErrorCode BwMixedGetOwnership(BwMixed mixed, BwMixedOwnership *own);
PetscErrorCode BwMixedGetModel(BwMixed mixed, BwModel *model);

/* Error naming the blocks that can move freely (called by BwMixedCreate). */
PetscErrorCode BwMixedCheckRestraint(BwMixed mixed);
/* Numerical check of S^ for a mechanism (restraint.c): a one-line error
 * naming the blocks and their free motion if S^ is singular to working
 * precision, nothing otherwise. Collective; one extra factorisation. */
PetscErrorCode BwMixedCheckMechanism(BwMixed mixed, const char how[]);
/* Its verdict on a Rayleigh quotient rho of S^ (unit vector) against ||S^||. */
PetscBool BwMechanismVerdict(PetscReal rho, PetscReal snorm);

/* Results of the owned blocks and interfaces, physical units. */
typedef struct {
  PetscReal *displacement; /* nd per owned block */
  PetscReal *reaction;     /* nd per owned block (0 at free dofs) */
  PetscReal *relative;     /* nd per owned interface: dt, dn, phi | dt, dn, db, phit, phin, phib */
  PetscReal *resultant;    /* nd per owned interface: T, N, M | T, N, Tb, Mt, Mn, Mb */
  PetscReal *stress;       /* ns per portion of the owned interfaces, in their order, if asked */
  PetscReal *pair;         /* 2 nd per owned interface: the displacements of its blocks i and j,
                              which its rank has at hand and may not own (the XDMF warps the
                              interfaces by them) */
} BwResults;
/* Self-check of a solution x of K x = b: relative norms in the scaled
 * system; the global balance needs the recovered reactions and the loads
 * (res may be NULL: then equilibrium_error is -1). */
typedef struct {
  PetscReal residual;          /* ||b - K x|| / ||b|| */
  PetscReal equilibrium;       /* ||D^T r - F|| / max(||F||, ||r||), scaled */
  PetscReal compatibility;     /* ||D q - G r|| / max(||D q||, ||r||), scaled by G^{-1/2} */
  PetscReal equilibrium_error; /* |sum reactions + sum loads| / sum of their magnitudes (wrench) */
} BwCheck;
PetscErrorCode BwMixedCheck(BwMixed mixed, Vec x, Vec b, const PetscReal load[], const BwResults *res, BwCheck *check);

/* stresses: keep the per-portion stresses (output.stresses), else only
 * their resultants. load: the loads b was filled with (for the reactions). */
PetscErrorCode BwMixedRecover(BwMixed mixed, Vec x, const PetscReal load[], PetscBool stresses, BwResults *res);
PetscErrorCode BwResultsFree(BwResults *res);
