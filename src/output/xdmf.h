/* BwXdmf: the XDMF 3 file written beside each HDF5 result file (output.xdmf).
 *
 * ParaView cannot guess that /blocks/vertices and /blocks/offsets are
 * polygons, so the XDMF file tells it: a grid "blocks" (one polygon cell per
 * block, the block results as cell fields, the rigid-body displacement of
 * every vertex as a point field for Warp By Vector) and a grid "interfaces"
 * (one line cell per interface, from G - l/2 t to G + l/2 t, the interface
 * results as cell fields). It only references the HDF5 datasets, by the
 * basename of the result file, so the two files must stay side by side.
 *
 * What XDMF needs and the result schema lacks lives in the group /xdmf of
 * the result file, written by BwOutput in its collective write, each rank
 * the rows of the blocks and interfaces it owns:
 *   /xdmf/topology             int64   Mixed connectivity of the blocks
 *   /xdmf/vertex_displacement  float64 (V, 3)  u(x) of each vertex, z = 0
 *   /xdmf/interface_points     float64 (2I, 2) G -/+ l/2 t per interface
 *   /xdmf/interface_topology   int64   (I, 2)  2k, 2k+1
 * In 3D the blocks are Polyhedron cells (their faces), /xdmf/vertex_displacement
 * is u + w x (x - c), the interfaces are the polygons /interfaces/vertices
 * with /xdmf/interface_topology their Mixed list, and there are no
 * /xdmf/interface_points; instead
 *   /xdmf/interface_displacement (W, 3)  at each row of /interfaces/vertices,
 *                                        the mean of its two blocks' u + w x (x - c)
 * and, where /portions datasets are written (output.stresses, a pushover),
 * a third grid "portions" (one polygon per portion, its cell fields
 * /portions/stress, state, plastic_jump, area):
 *   /xdmf/portion_points       float64 (Q, 3)  every portion's polygon, interface
 *                                              after interface, portions in their order
 *   /xdmf/portion_topology     int64           their Mixed list
 *   /xdmf/portion_displacement float64 (Q, 3)  the mean of the two blocks' motions
 * A pushover's steps have their own /xdmf/steps/NNNNNN/vertex_displacement,
 * interface_displacement and portion_displacement. */
#pragma once
#include <stdint.h>
#include "geometry/geometry.h"
#include "system/mixed.h"

/* What the XDMF file says of the datasets: their global sizes. */
typedef struct {
  PetscInt dim, nblocks, nvertices, ninterfaces, npolyvertices;
  PetscInt ntopology, ninterface_topology;               /* the Mixed lists' lengths */
  PetscInt nportions, nportion_points, nportion_topology; /* 3D portions grid (0: none) */
} BwXdmfSizes;

/* Where this rank's rows go in the ragged /xdmf datasets (collective to
 * make: their offsets in block and interface id order), and the sizes.
 * Made once per result file: the steps of a pushover reuse it. */
typedef struct {
  BwXdmfSizes sizes;
  PetscInt   *topology_start;  /* per owned block: its first entry in /xdmf/topology */
  PetscInt   *itopology_start; /* 3D, per owned interface: in /xdmf/interface_topology */
  PetscInt   *ppoint_start;    /* 3D portions, per owned interface: in /xdmf/portion_points */
  PetscInt   *ptopology_start; /* 3D portions, per owned interface: in /xdmf/portion_topology */
} BwXdmfLayout;

PetscErrorCode BwXdmfLayoutCreate(BwGeometry geom, const BwMixedOwnership *own, PetscBool portions, BwXdmfLayout *L);
PetscErrorCode BwXdmfLayoutDestroy(BwXdmfLayout *L);

/* The /xdmf datasets as this rank writes them: the connectivity of its
 * owned blocks and interfaces, their point displacements (and portion
 * polygons), each with its global rows, ascending. */
typedef struct {
  PetscInt   ntopology_rows;
  PetscInt  *topology_rows;
  int64_t   *topology;
  PetscInt   ninterface_rows2;   /* 2D: owned interfaces */
  PetscInt  *interface_rows2;
  PetscReal *interface_points;   /* 2D: 4 per owned interface */
  int64_t   *interface_topology2; /* 2D: 2 per owned interface */
  PetscInt   ninterface_topology_rows; /* 3D: the Mixed list of the owned interface polygons */
  PetscInt  *interface_topology_rows;
  int64_t   *interface_topology;
  PetscInt   nvertex_rows;       /* vertices of the owned blocks */
  PetscInt  *vertex_rows;
  PetscReal *vertex_displacement; /* 3 per row */
  PetscInt   ninterface_rows;    /* 3D: vertices of the owned interfaces' polygons */
  PetscInt  *interface_rows;
  PetscReal *interface_displacement; /* 3 per row */
  PetscInt   nportion_rows;      /* points of the owned interfaces' portions */
  PetscInt  *portion_rows;
  PetscReal *portion_points, *portion_displacement; /* 3 per row */
  PetscInt   nportion_topology_rows;
  PetscInt  *portion_topology_rows;
  int64_t   *portion_topology;
} BwXdmfData;

/* From the owned blocks' displacements and (3D) the owned interfaces'
 * block pairs (res->pair); portions: the portions grid's data too (3D). */
PetscErrorCode BwXdmfDataCreate(BwGeometry geom, const BwMixedOwnership *own, const BwXdmfLayout *L, const BwResults *res, PetscBool portions, BwXdmfData *x);
PetscErrorCode BwXdmfDataDestroy(BwXdmfData *x);
/* The XDMF path of a result file: its extension replaced by .xdmf. */
PetscErrorCode BwXdmfPath(const char h5file[], char xdmffile[], size_t len);
/* Writes xdmffile describing h5file (only its basename is referenced);
 * serial, called by one rank once the HDF5 file is complete. With nsteps
 * > 0, a temporal collection over the steps written (/steps/NNNNNN, their
 * point displacements in /xdmf/steps/NNNNNN). sizes->nportions > 0: the
 * portions grid (3D), with their stresses if `stresses`. m_state > 0: a
 * pushover's portion states are fields (2D: /interfaces/state, m per
 * interface; 3D: /portions/state, and the final /portions/plastic_jump). */
PetscErrorCode BwXdmfWrite(const char h5file[], const char xdmffile[], const BwXdmfSizes *sizes, PetscInt nsteps, const PetscInt steps[], PetscInt m_state, PetscBool stresses);
