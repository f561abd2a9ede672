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
 * the result file, written by BwOutput in its collective write:
 *   /xdmf/topology             int64   Mixed connectivity of the blocks
 *   /xdmf/vertex_displacement  float64 (V, 3)  u(x) of each vertex, z = 0
 *   /xdmf/interface_points     float64 (2I, 2) G -/+ l/2 t per interface
 *   /xdmf/interface_topology   int64   (I, 2)  2k, 2k+1
 * In 3D the blocks are Polyhedron cells (their faces), /xdmf/vertex_displacement
 * is u + w x (x - c), the interfaces are the polygons /interfaces/vertices
 * with /xdmf/interface_topology their Mixed list, and there are no
 * /xdmf/interface_points. */
#pragma once
#include <stdint.h>
#include "geometry/geometry.h"

/* The /xdmf datasets as this rank writes them: the replicated ones whole,
 * the vertex displacement for the vertices of the blocks it owns. */
typedef struct {
  PetscInt   ntopology;
  int64_t   *topology;
  PetscReal *interface_points;   /* 2D: 4 per interface */
  PetscInt   ninterface_topology;
  int64_t   *interface_topology; /* 2D: 2 per interface; 3D: the Mixed list of the interface polygons */
  PetscInt   nvertex_rows;       /* vertices of the owned blocks, ascending */
  PetscInt  *vertex_rows;
  PetscReal *vertex_displacement; /* 3 per row */
} BwXdmfData;

/* own[] (ascending) are the blocks this rank owns, displacement[] their
 * u1, u2, w about the centroid. */
PetscErrorCode BwXdmfDataCreate(BwGeometry geom, PetscInt nown, const PetscInt own[], const PetscReal displacement[], BwXdmfData *x);
PetscErrorCode BwXdmfDataDestroy(BwXdmfData *x);
/* The XDMF path of a result file: its extension replaced by .xdmf. */
PetscErrorCode BwXdmfPath(const char h5file[], char xdmffile[], size_t len);
/* Writes xdmffile describing h5file (only its basename is referenced);
 * serial, called by one rank once the HDF5 file is complete. With nsteps
 * > 0, a temporal collection over the steps written (/steps/NNNNNN, their
 * vertex displacement in /xdmf/steps/NNNNNN); m_state > 0: the portions'
 * state (/interfaces/state, m per interface) is a field. */
PetscErrorCode BwXdmfWrite(const char h5file[], const char xdmffile[], BwGeometry geom, PetscInt nsteps, const PetscInt steps[], PetscInt m_state, PetscBool stresses);
