/* Block partition for the distributed mixed system.
 *
 * The block-interface graph (blocks as vertices, one edge per neighbouring
 * pair) is cut by METIS k-way on rank 0 and broadcast: the geometry is
 * replicated, so every rank then derives the whole layout itself. A vertex
 * weighs the rows it brings: its free dofs plus m stress rows per interface
 * (each interface's 2m rows shared between its two blocks). One rank needs
 * no partition and gets none. */
#include <metis.h>
#include "system/mixed_impl.h"
#include "util/compat.h"

PetscErrorCode BwPartitionBlocks(BwModel model, PetscMPIInt **owner)
{
  BwGeometry  geom = model->geom;
  PetscInt    nb = geom->nblocks, ni = geom->ninterfaces;
  PetscMPIInt size, rank;
  int         ok = 1;

  PetscFunctionBeginUser;
  *owner = NULL;
  PetscCallMPI(MPI_Comm_size(geom->comm, &size));
  PetscCallMPI(MPI_Comm_rank(geom->comm, &rank));
  if (size == 1 || nb < size) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscMalloc1(nb, owner));
  if (rank == 0) {
    idx_t  n = (idx_t)nb, ncon = 1, nparts = (idx_t)size, objval, options[METIS_NOPTIONS];
    idx_t *xadj, *adjncy, *vwgt, *part;
    PetscInt *deg;

    PetscCall(PetscCalloc1(nb + 1, &deg));
    PetscCall(PetscMalloc4(nb + 1, &xadj, 2 * ni + 1, &adjncy, nb, &vwgt, nb, &part));
    for (PetscInt k = 0; k < ni; k++) {
      deg[geom->pair[2 * k] + 1]++;
      deg[geom->pair[2 * k + 1] + 1]++;
    }
    for (PetscInt b = 0; b < nb; b++) deg[b + 1] += deg[b];
    for (PetscInt b = 0; b <= nb; b++) xadj[b] = (idx_t)deg[b];
    for (PetscInt k = 0; k < ni; k++) {
      PetscInt i = geom->pair[2 * k], j = geom->pair[2 * k + 1];
      adjncy[deg[i]++] = (idx_t)j;
      adjncy[deg[j]++] = (idx_t)i;
    }
    for (PetscInt b = 0; b < nb; b++) {
      PetscInt free = 0;
      for (PetscInt c = 0; c < model->nd; c++) free += !model->prescribed[model->nd * b + c];
      /* the work of a block: its dofs and the stresses of its interfaces */
      vwgt[b] = (idx_t)(free + model->m * model->mb * (xadj[b + 1] - xadj[b]));
    }
    /* METIS wants a simple graph: two interfaces between the same pair of
     * blocks give a repeated edge, which it tolerates in k-way; no self loops
     * exist (i < j). */
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = 1;
    if (METIS_PartGraphKway(&n, &ncon, xadj, adjncy, vwgt, NULL, NULL, &nparts, NULL, NULL, options, &objval, part) != METIS_OK) ok = 0;
    for (PetscInt b = 0; b < nb; b++) (*owner)[b] = ok ? (PetscMPIInt)part[b] : (PetscMPIInt)((b * (PetscInt)size) / nb);
    PetscCall(PetscFree4(xadj, adjncy, vwgt, part));
    PetscCall(PetscFree(deg));
  }
  PetscCallMPI(MPI_Bcast(&ok, 1, MPI_INT, 0, geom->comm));
  PetscCheck(ok, geom->comm, PETSC_ERR_LIB, "METIS failed to partition %" PetscInt_FMT " blocks into %d parts", nb, size);
  PetscCallMPI(MPI_Bcast(*owner, (PetscMPIInt)nb, MPI_INT, 0, geom->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}
