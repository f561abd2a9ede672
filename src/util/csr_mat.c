/* BwMatFromCSR (csr_mat.h). */
#include "util/csr_mat.h"
#include "util/compat.h"

/* An array PETSc uses in place, freed with the object. */
static PetscErrorCode BwComposeArray(PetscObject obj, const char name[], void *array)
{
  PetscContainer c;

  PetscFunctionBeginUser;
  PetscCall(PetscContainerCreate(PetscObjectComm(obj), &c));
  PetscCall(PetscContainerSetPointer(c, array));
  PetscCall(BwContainerFreeWithIt(c));
  PetscCall(PetscObjectCompose(obj, name, (PetscObject)c));
  PetscCall(PetscContainerDestroy(&c));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMatFromCSR(MPI_Comm comm, PetscInt m, PetscInt n, PetscInt M, PetscInt N, const char prefix[], PetscInt *ia, PetscInt *ja, PetscReal *va, Mat *A, BwCSRValues *vals)
{
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (size == 1) {
    PetscCall(MatCreateSeqAIJWithArrays(comm, m, n, ia, ja, va, A));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRi", ia));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRj", ja));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRv", va));
    if (vals) {
      vals->di = ia;
      vals->dv = va;
      vals->oi = NULL;
      vals->ov = NULL;
    }
  } else {
    PetscInt   cstart, *di, *dj, *oi, *oj, nd = 0, no = 0;
    PetscReal *dv, *ov;
    PetscCallMPI(MPI_Scan(&n, &cstart, 1, MPIU_INT, MPI_SUM, comm));
    cstart -= n;
    for (PetscInt e = 0; e < ia[m]; e++) {
      if (ja[e] >= cstart && ja[e] < cstart + n) nd++;
      else no++;
    }
    PetscCall(PetscMalloc1(m + 1, &di));
    PetscCall(PetscMalloc1(nd + 1, &dj));
    PetscCall(PetscMalloc1(nd + 1, &dv));
    PetscCall(PetscMalloc1(m + 1, &oi));
    PetscCall(PetscMalloc1(no + 1, &oj));
    PetscCall(PetscMalloc1(no + 1, &ov));
    di[0] = oi[0] = 0;
    for (PetscInt r = 0; r < m; r++) {
      di[r + 1] = di[r];
      oi[r + 1] = oi[r];
      for (PetscInt e = ia[r]; e < ia[r + 1]; e++) {
        if (ja[e] >= cstart && ja[e] < cstart + n) {
          dj[di[r + 1]]   = ja[e] - cstart;
          dv[di[r + 1]++] = va[e];
        } else {
          oj[oi[r + 1]]   = ja[e];
          ov[oi[r + 1]++] = va[e];
        }
      }
    }
    PetscCall(PetscFree(ia));
    PetscCall(PetscFree(ja));
    PetscCall(PetscFree(va));
    PetscCall(MatCreateMPIAIJWithSplitArrays(comm, m, n, M, N, di, dj, dv, oi, oj, ov, A));
    /* the matrix uses the arrays in place; they are freed with it */
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRdi", di));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRdj", dj));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRdv", dv));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRoi", oi));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRoj", oj));
    PetscCall(BwComposeArray((PetscObject)*A, "BwCSRov", ov));
    if (vals) {
      vals->di = di;
      vals->dv = dv;
      vals->oi = oi;
      vals->ov = ov;
    }
  }
  PetscCall(MatSetOptionsPrefix(*A, prefix));
  PetscFunctionReturn(PETSC_SUCCESS);
}
