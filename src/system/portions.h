/* BwPortions: the portions of every interface (model.md, "Discretisation"
 * and "Three dimensions"): per portion its area A_p, its centroid (xi_p,
 * eta_p) from G along t and b, and sqrt(A_p) and 1/sqrt(A_p), which scale
 * the stresses (the compliance G_p^-1/2 = sqrt(A_p) C^1/2).
 *
 * Interfaces of the same shape share one layout: a running-bond wall has as
 * many layouts as distinct joint lengths, so a million interfaces cost one
 * index each, and the kernels (bw_kernel_*) get the portions as arrays
 * without building them at every call. */
#pragma once
#include <petscsys.h>

typedef struct {
  PetscInt   dim;         /* 2 | 3 */
  PetscInt   ninterfaces, nlayouts, maxnp;
  PetscInt   m, mb;       /* 3D: the grid of the bounding box */
  PetscInt  *layout;      /* per interface: its layout */
  PetscInt  *first;       /* 3D, per layout: an interface of its class (NULL in 2D) */
  PetscInt  *lpoly_offsets; /* 3D, per layout: its polygon lpoly[2 v], v in lpoly_offsets[l]..[l+1]-1 */
  PetscReal *lpoly;
  PetscInt  *offsets;     /* per layout: its portions offsets[l]..offsets[l+1]-1 */
  PetscReal *area, *xi, *eta, *sqrt_area, *inv_sqrt_area;
  PetscBool *uniform;     /* per layout: all its portions have one area */
} BwPortions;

/* 2D: the interfaces of lengths length[k], depth s, each cut into m equal
 * portions (the rectangle l x s in one row); one layout per distinct length.
 * pair[2k], pair[2k+1]: the blocks of interface k, for the message. */
PetscErrorCode BwPortionsCreate2D(PetscInt ninterfaces, const PetscInt pair[], const PetscReal length[], PetscReal depth, PetscInt m, BwPortions *P);
/* 3D: interface k is the convex polygon of vertices poly[2 v], poly[2 v + 1]
 * for v in offsets[k]..offsets[k+1]-1, (xi, eta) from its centre G along t
 * and b, counter-clockwise; it is cut by the m x mb grid of equal cells of
 * its bounding box, and every cell's intersection of area above 1e-9 A is
 * a portion (model.md, "Three dimensions"), numbered with the t index
 * fastest. Each polygon is put on a grid of step 2^-40 of its largest
 * coordinate (a power of two, BwPolygonStep); those equal there share a
 * layout, the portions of the first of them (BwPolygonClass). */
PetscErrorCode BwPortionsCreate3D(PetscInt ninterfaces, const PetscInt offsets[], const PetscReal poly[], PetscInt m, PetscInt mb, BwPortions *P);
/* The class of a polygon of nv vertices (xi, eta): its grid step q (2^-40
 * of its largest coordinate, a power of two), its coordinates on that
 * grid z[2 nv], and their hash: equal for polygons equal on the grid,
 * whatever the rank or the CPU. */
#include <stdint.h>
PetscReal BwPolygonStep(PetscInt nv, const PetscReal poly[]);
void      BwPolygonQuantize(PetscInt nv, const PetscReal poly[], PetscReal q, int64_t z[]);
uint64_t  BwPolygonHash(PetscInt nv, const int64_t z[]);
/* 3D: the polygons of layout l's portions, in their order, as
 * BwPortionsCreate3D cut them from the layout's polygon (nv vertices):
 * portion p's vertices (xi, eta), counter-clockwise, are vertices[2 v],
 * vertices[2 v + 1] for v in voffsets[p]..voffsets[p+1]-1. Room: voffsets
 * m mb + 1, vertices 2 (nv + 4) m mb. */
PetscErrorCode BwPortionsPolygons3D(const BwPortions *P, PetscInt l, PetscInt voffsets[], PetscReal vertices[]);
PetscErrorCode BwPortionsDestroy(BwPortions *P);

/* Interface k's portions: their number and the first of the arrays. */
static inline PetscInt BwPortionsCount(const BwPortions *P, PetscInt k)
{
  PetscInt l = P->layout[k];
  return P->offsets[l + 1] - P->offsets[l];
}
static inline PetscInt BwPortionsFirst(const BwPortions *P, PetscInt k) { return P->offsets[P->layout[k]]; }
