/* BwModel: what the scene says about the physics, given the geometry.
 *
 *   joint laws   one per interface kind (bed, head, unit), BwJointLaw
 *   portions     m per interface (discretization.m)
 *   supports     block set -> prescribed dofs and their values: (u1, u2, w)
 *                in 2D, (u1, u2, u3, w1, w2, w3) in 3D
 *   loads        block set -> (F1, F2, M3) | (F1, F2, F3, M1, M2, M3) at each
 *                block's centroid, plus the self-weight on F2:
 *                -density * 9.81 * area * depth (2D) | * volume (3D)
 *
 * Per block it holds which dofs are prescribed, their values and the total
 * applied load; per interface the elastic stiffness (kn, kt) that scales
 * its stresses. */
#pragma once
#include "geometry/geometry.h"
#include "law/law.h"
#include "util/namemap.h"

typedef struct _n_BwModel *BwModel;
struct _n_BwModel {
  MPI_Comm   comm;
  BwGeometry geom;
  PetscInt   m;
  PetscInt   mb;    /* 3D: portions along b (discretization.m_b); 1 in 2D */
  PetscInt   nd;    /* dofs per block: 3 (2D) | 6 (3D) */
  PetscReal  gravity_density;
  BwJointLaw law[BW_JOINT_NKINDS]; /* joints.*, joints.head.*, joints.unit.* (NULL where no interface has the kind) */
  PetscBool  nonlinear;            /* a law has a strength */
  PetscReal *kn, *kt;     /* per interface: the elastic stiffness that scales its stresses [N/m^3] */
  PetscBool *prescribed;  /* nd per block */
  PetscReal *value;       /* nd per block: prescribed value (0 where free) */
  PetscReal *load;        /* nd per block: forces and moments applied, self-weight included */
};

PetscErrorCode BwModelCreate(MPI_Comm comm, BwModel *model);
/* The keys that do not depend on the geometry: discretization.m,
 * gravity.density, joints.* (whose thickness the generators need). */
PetscErrorCode BwModelSetFromOptions(BwModel model, BwScene scene);
/* Given the geometry: per-interface stiffness (joints.head.* where there
 * are head joints), supports and loads. */
PetscErrorCode BwModelSetUp(BwModel model, BwGeometry geom, BwScene scene);
/* The per-block and per-interface arrays for `geom`, zeroed (BwModelSetUp
 * calls it; a program that builds a model by hand calls it itself). */
PetscErrorCode BwModelAllocate(BwModel model, BwGeometry geom);
/* Interface k's law and its kernel parameters (the law's, with the
 * interface's own stiffness); either may be NULL. */
PetscErrorCode BwModelInterfaceLaw(BwModel model, PetscInt k, BwJointLaw *law, PetscReal par[]);
/* The loads of keys <prefix>loads.<set> and the self-weight (density
 * <prefix>gravity.density if given, else gravity.density), replacing the
 * current ones: prefix "" for the scene's loads, "cases_NAME_" for a case. */
PetscErrorCode BwModelSetLoads(BwModel model, BwScene scene, const char prefix[]);
/* The same into load[] (nd per block): <prefix>loads.<set>, and with
 * `gravity` the self-weight as above. */
PetscErrorCode BwModelReadLoads(BwModel model, BwScene scene, const char prefix[], PetscBool gravity, PetscReal load[]);
/* Whether the joint laws' tangents stay symmetric: no law with strength
 * has dilatancy other than its friction (non-associated flow). */
PetscBool BwModelTangentSymmetric(BwModel model);
/* The names of the nd dofs of a block: u1, u2, w | u1, u2, u3, w1, w2, w3. */
const char *const *BwModelDofNames(BwModel model);
PetscErrorCode BwModelDestroy(BwModel *model);
