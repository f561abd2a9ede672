/* BwModel: what the scene says about the physics, given the geometry.
 *
 *   joint laws   mortar: kn = E/e, kt = E/(2(1+nu) e);  dry: kn, kt given [N/m^3]
 *   portions     m per interface (discretization.m)
 *   supports     block set -> prescribed dofs (u1, u2, w) and their values
 *   loads        block set -> (F1, F2, M3) at each block's centroid, plus the
 *                self-weight -density * 9.81 * area * depth on F2
 *
 * Per block it holds which dofs are prescribed, their values and the total
 * applied load; per interface the stiffness (kn, kt) in force. */
#pragma once
#include "geometry/geometry.h"

typedef enum { BW_LAW_MORTAR = 0, BW_LAW_DRY = 1 } BwJointLawType;

typedef struct {
  BwJointLawType type;
  PetscReal      thickness; /* e [m], the gap between block faces */
  PetscReal      E, nu;     /* mortar [Pa, -] */
  PetscReal      kn, kt;    /* in force [N/m^3] (derived for mortar) */
} BwJointLaw;

/* Reads joints.* (prefix "joints_") or joints.head.* ("joints_head_", whose
 * unset keys inherit from `parent`). */
PetscErrorCode BwJointLawSetFromOptions(BwJointLaw *law, BwScene scene, const char prefix[], const BwJointLaw *parent);

typedef struct _n_BwModel *BwModel;
struct _n_BwModel {
  BwGeometry geom;
  PetscInt   m;
  PetscReal  gravity_density;
  PetscReal *kn, *kt;     /* per interface */
  PetscBool *prescribed;  /* 3 per block */
  PetscReal *value;       /* 3 per block: prescribed value (0 where free) */
  PetscReal *load;        /* 3 per block: F1, F2, M3 applied, self-weight included */
};

PetscErrorCode BwModelCreate(BwGeometry geom, BwModel *model);
PetscErrorCode BwModelSetFromOptions(BwModel model, BwScene scene, const BwJointLaw *bed, const BwJointLaw *head);
PetscErrorCode BwModelDestroy(BwModel *model);
