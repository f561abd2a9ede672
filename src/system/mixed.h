/* BwMixed: the mixed saddle-point system of model.md, distributed, in the
 * symmetric scaling that makes the compliance block the identity.
 *
 * Unknowns per rank, in this order: the stresses of the interfaces it owns
 * (2m each), then the free dofs of the blocks it owns (prescribed dofs have
 * no unknown; their values are lifted to the right-hand side). With
 *   r~ = G^{1/2} r,  q~ = diag(S)^{1/2} q,  D^ = G^{-1/2} D diag(S)^{-1/2}
 * the system solved is
 *
 *   [ -I   D^ ] [ r~ ]   [ -G^{-1/2} D_p u_p ]
 *   [ D^T  0  ] [ q~ ] = [ diag(S)^{-1/2} F  ]
 *
 * Every scaled unknown is in sqrt(N m), so the residual norms below compare
 * like with like; D^ has unit-norm columns. The Schur complement
 * S^ = D^T D^ is assembled interface by interface from the kernels (exact,
 * since the (r,r) block is diagonal) and serves as its preconditioning
 * matrix. */
#pragma once
#include <petscksp.h>
#include "model/model.h"

typedef enum { BW_STORAGE_SHELL = 0, BW_STORAGE_NEST = 1, BW_STORAGE_AIJ = 2 } BwStorage;
extern const char *const BwStorages[];

typedef struct _n_BwMixed *BwMixed;
struct _n_BwMixed {
  MPI_Comm   comm;
  BwGeometry geom;
  BwModel    model;
  PetscInt   m;
  /* layout (replicated): owner rank of each block and interface, global row
   * of each free dof (-1 where prescribed) and of each interface's first stress */
  PetscMPIInt *block_owner, *interface_owner;
  PetscInt    *dof, *stress;
  PetscInt    *sdof; /* row of each free dof in S^ and column of D^ (q rows only, same order) */
  PetscInt    *srow; /* row of each interface's first stress in D^ (r rows only) */
  PetscInt     nown_blocks, *own_blocks, nown_interfaces, *own_interfaces;
  PetscInt     rstart, qstart, nlocal, nr_local, nq_local, nr_global, nq_global;
  /* block -> interfaces (CSR, replicated) */
  PetscInt *adj_offsets, *adj;
  /* 1/sqrt(diag S) per block dof, computed on demand (< 0: not yet) */
  PetscReal *qscale;
  /* the system: K = MatNest [-I, D^; D^T, 0] with D^ a shell or AIJ, or
   * one AIJ matrix (solver.storage); set storage before BwMixedAssemble */
  BwStorage storage;
  Mat K, D, S;
  void    *keep[12]; /* CSR arrays D^ and S^ use in place */
  PetscInt nkeep;
  Vec x, b;
  IS  isr, isq;
};

/* Layout from a block partition (owner rank per block, NULL: contiguous
 * ranges), then assembly of K, S and b. */
PetscErrorCode BwMixedCreate(BwModel model, const PetscMPIInt block_owner[], BwMixed *mixed);
/* Owner rank of every block: METIS k-way on more than one rank, NULL on one. */
PetscErrorCode BwPartitionBlocks(BwModel model, PetscMPIInt **owner);
PetscErrorCode BwMixedAssemble(BwMixed mixed);
/* 1/sqrt(diag S) of block b's three dofs (computed on first use, cached). */
PetscErrorCode BwMixedQScale(BwMixed mixed, PetscInt b, const PetscReal **scale);
/* D^ as a shell (dshell.c); fills the stress rows of the right-hand side. */
PetscErrorCode BwMixedCreateDShell(BwMixed mixed, PetscScalar bb[], Mat *D);
/* K as one AIJ matrix (a new reference if it already is one), for MUMPS. */
PetscErrorCode BwMixedGetAIJ(BwMixed mixed, Mat *aij);
/* Error naming the blocks that can move freely (called by BwMixedCreate). */
PetscErrorCode BwMixedCheckRestraint(BwMixed mixed);
/* Numerical check of S^ for a mechanism (restraint.c): a one-line error
 * naming the blocks and their free motion if S^ is singular to working
 * precision, nothing otherwise. Collective; one extra factorisation. */
PetscErrorCode BwMixedCheckMechanism(BwMixed mixed, const char how[]);
/* Its verdict on a Rayleigh quotient rho of S^ (unit vector) against ||S^||. */
PetscBool BwMechanismVerdict(PetscReal rho, PetscReal snorm);
PetscErrorCode BwMixedDestroy(BwMixed *mixed);

/* Results of the owned blocks and interfaces, physical units. */
typedef struct {
  PetscReal *displacement; /* 3 per owned block */
  PetscReal *reaction;     /* 3 per owned block (0 at free dofs) */
  PetscReal *relative;     /* 3 per owned interface: dt, dn, phi */
  PetscReal *resultant;    /* 3 per owned interface: T, N, M */
  PetscReal *stress;       /* 2m per owned interface: (shear, normal) per portion, if asked */
} BwResults;
/* Self-check of a solution x: relative norms in the scaled system; the
 * global balance needs the recovered reactions (res may be NULL: then
 * equilibrium_error is -1). */
typedef struct {
  PetscReal residual;          /* ||b - K x|| / ||b|| */
  PetscReal equilibrium;       /* ||D^T r - F|| / ||F||, scaled */
  PetscReal compatibility;     /* ||D q - G r|| / ||D q||, scaled by G^{-1/2} */
  PetscReal equilibrium_error; /* |sum reactions + sum loads| / |sum loads| (wrench) */
} BwCheck;
PetscErrorCode BwMixedCheck(BwMixed mixed, Vec x, const BwResults *res, BwCheck *check);

/* stresses: keep the per-portion stresses (output.stresses), else only
 * their resultants. */
PetscErrorCode BwMixedRecover(BwMixed mixed, Vec x, PetscBool stresses, BwResults *res);
PetscErrorCode BwResultsFree(BwResults *res);
