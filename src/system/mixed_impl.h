/* The inside of BwMixed, shared by the files of src/system; nothing else
 * includes it. */
#pragma once
#include <petscsf.h>
#include "system/mixed.h"
#include "util/log.h"
#include "system/portions.h"
#include "util/csr_mat.h"


/* Sizes per dimension (model.md, "Three dimensions"): dofs per block, and
 * as many components of dG; stress components per portion. */
#define BW_MAX_ND 6
#define BW_MAX_NS 3

struct _n_BwMixed {
  MPI_Comm   comm;
  BwGeometry geom;
  BwModel    model;
  PetscInt   dim, nd, ns; /* 2, 3, 2 | 3, 6, 3 */
  PetscInt   m;
  BwPortions portions; /* of every interface: areas and centroids, shared by shape */
  /* layout, per local block and interface of the geometry's local piece:
   * the owner rank of each interface (a block's is geom->block_rank); per
   * block the global row of its first dof in K (nd consecutive rows) and
   * in the q vectors (columns of D^, rows of S^), -1 for a block without
   * free dofs; per interface the global row of its first stress in K and
   * in the r vectors (rows of D^), and its slot among all owned interfaces
   * numbered rank after rank (the K_G vector's order) */
  PetscMPIInt *interface_owner;
  PetscInt    *krow_q, *qrow, *krow_r, *rrow, *islot;
  PetscSF      block_sf; /* owners -> ghosts */
  PetscInt     nown_blocks, *own_blocks, nown_interfaces, *own_interfaces;
  PetscInt     nown_q;          /* owned blocks with unknowns */
  PetscInt    *own_interface_gid, *own_portion_start, nportions_global; /* for the output's rows */
  PetscInt     edge_cut;        /* interfaces between blocks of different ranks */
  PetscReal    imbalance;       /* largest rank's blocks over the mean */
  PetscInt     kstart, qstart, rstart, nlocal, nr_local, nq_local, nr_global, nq_global;
  /* local block -> local interfaces (CSR; complete for owned blocks) */
  PetscInt *adj_offsets, *adj;
  /* per block dof: 1/sqrt(diag S) of the elastic system, 1 where prescribed */
  PetscReal *qscale;
  /* the operators */
  BwStorage storage;
  Mat       K, D, S;
  BwCSRValues svals; /* S^'s values as PETSc holds them, for the refill */
  PetscBool  values_fixed; /* BwMixedSetValuesFixed: no refill; S^ without its round-off entries */
  PetscInt   s_groups;     /* the groups of dof kinds that never couple (1: none split) */
  PetscInt   s_group[BW_MAX_ND]; /* each dof kind's group */
  PetscInt   s_dropped;    /* the entries of the local rows left out between them */
  PetscInt   maxdeg; /* most interfaces of an owned block */
  PetscInt   values_state; /* bumped when BwMixedSetTangents changes the operators' values */
  /* a spring on one dof in the operators (BwMixedSetSpring): the block's
   * global id (-1: none) and its local index where it is owned here (-1:
   * not here) */
  PetscInt   spring_gblock, spring_block, spring_dof;
  PetscReal  spring;
  IS        isr, isq;
  Vec       pmask;        /* q layout: 1 at prescribed dofs */
  /* tangents: 4 per portion of the owned interfaces (physical), NULL for
   * the elastic ones; and the interface stiffness K_G (9 per interface) of
   * every interface touching an owned block, from them */
  PetscReal *tangent;
  PetscReal *scaled_tangent; /* T = C^-1/2 C_t C^-1/2, 4 per portion, from tangent */
  PetscInt   nkg, *kg_interfaces; /* sorted */
  PetscReal *kg;
  /* what a refill must redo: the owned interfaces whose tangents changed
   * since the last refill (NULL: all), the K_G of kg_interfaces that
   * changed, the spring's block at the last write (its rows change with it) */
  PetscBool *tangent_changed, *kg_changed;
  PetscInt   spring_written;
  /* refills only: (R B)^T K_G (R B) of each interface of kg_interfaces (4
   * nd^2 values; its two blocks' rows both need it), valid until its K_G
   * changes: computed once per change instead of once per block row
   * (about S^'s own values in size) */
  PetscReal *s6;
  PetscBool *s6_valid;
  VecScatter kg_scatter;          /* owners' K_G -> ranks that assemble rows with them */
  Vec        kg_owned, kg_ghost;
};

/* data[n b .. n b + n) of every ghost b from its owner (n items of type). */
PetscErrorCode BwMixedGhostBcast(BwMixed mx, PetscInt n, MPI_Datatype type, void *data);
/* Column offset (0 or nd) of block b in interface k's 2 nd columns. */
static inline PetscInt BwSide(BwMixed mx, PetscInt k, PetscInt b) { return mx->geom->pair[2 * k] == b ? 0 : mx->nd; }
/* R B of interface k (rb[nd][2 nd]); PETSC_ERR_PLIB on a kernel failure. */
PetscErrorCode BwMixedCompatibility(BwMixed mx, PetscInt k, PetscReal rb[]);
/* For each interface of mx->kg_interfaces, its index among all interfaces
 * numbered rank after rank (the owners' order of the K_G vector). */
PetscErrorCode BwMixedInterfaceSlots(BwMixed mx, PetscInt slot[]);
/* Rigid motion r of the assembly (translations along the axes, then
 * rotations: about X3 in 2D, X1, X2, X3 in 3D) about x0 at block b (u[nd]). */
void BwMixedRigidMotion(BwMixed mx, PetscInt r, PetscInt b, const PetscReal x0[], PetscReal u[]);
/* Interface k's elastic tangent C = diag(kt, kn[, kt]) (c[ns][ns]). */
void BwMixedElasticTangent(BwMixed mx, PetscInt k, PetscReal c[]);
/* Interface k's square roots of its scaling stiffness, sqrt(kt) and sqrt(kn):
 * portion p's stresses are scaled by sqrt(A_p) times them. */
void BwMixedStiffnessRoots(BwMixed mx, PetscInt k, PetscReal *skt, PetscReal *skn);
/* Interface k's portions: their number and areas, centroids, sqrt(A_p). */
static inline PetscInt BwMixedPortions(BwMixed mx, PetscInt k, const PetscReal **area, const PetscReal **xi, const PetscReal **eta, const PetscReal **sqa)
{
  const BwPortions *P = &mx->portions;
  PetscInt          f = BwPortionsFirst(P, k);
  if (area) *area = P->area + f;
  if (xi) *xi = P->xi + f;
  if (eta) *eta = P->eta + f;
  if (sqa) *sqa = P->sqrt_area + f;
  return BwPortionsCount(P, k);
}
/* D^ as a shell (operator.c) or assembled (CSR rows of the owned interfaces). */
PetscErrorCode BwMixedCreateDShell(BwMixed mx, Mat *D);
PetscErrorCode BwMixedAssembleD(BwMixed mx, PetscBool tangent, Mat *D);
/* S^ (stiffness.c): pattern and values, and the refill. */
PetscErrorCode BwMixedAssembleS(BwMixed mx);
PetscErrorCode BwMixedRefillS(BwMixed mx);
/* BwMixedCheck's local sums of b - K x (operator.c): the stress rows'
 * |b_r - (K x)_r|^2, |T D^ q~ - b_r|^2, then the q rows' |b_q - (K x)_q|^2,
 * |b_q|^2, then |b_r|^2, |r~|^2. */
PetscErrorCode BwMixedResidualSums(BwMixed mx, Vec x, Vec b, PetscReal loc[6]);
