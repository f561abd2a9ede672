/* BwSolver: solves the scaled mixed system of BwMixed.
 *
 *   fieldsplit  Richardson on the true residual of the whole system,
 *               preconditioned by PCFIELDSPLIT Schur with full factorisation:
 *               fields r (stresses, A00 = -I, solved exactly by Jacobi) and q
 *               (dofs); the Schur complement is solved with the assembled
 *               S^ = D^T D^ (exact): factored by MUMPS Cholesky, or by CG +
 *               GAMG with the rigid-body near-null space (solver.schur; by
 *               default by size). Options prefix: none (-ksp_*, -pc_*,
 *               -fieldsplit_r_*, -fieldsplit_q_*).
 *   direct      MUMPS LU of the whole system with iterative refinement
 *               (Richardson on the true residual). Prefix: -direct_.
 *   condensed   the reference a benchmark compares with: S^ q~ = F^ + D^T b_r
 *               by MUMPS Cholesky, then r~ = D^ q~ - b_r (the stresses recovered
 *               from the displacements). Prefix: -condensed_. Not a fallback.
 *   auto        fieldsplit; if its KSP fails or the true residual of the
 *               full system misses solver.rtol: when the Schur solve was CG +
 *               GAMG, fieldsplit again with S^ factored by MUMPS (prefix
 *               -cholesky_); then direct, for assemblies small enough for
 *               it (below 2e5 blocks). The reason is recorded. If every path misses rtol but stays within
 *               sqrt(rtol), the best answer is kept with a warning.
 * Defaults are set in code (or inserted into the options database when
 * absent, for the sub-solvers PETSc creates itself) and every option
 * overrides them. */
#pragma once
#include "system/mixed.h"
#include "util/log.h"

typedef enum { BW_METHOD_AUTO = 0, BW_METHOD_FIELDSPLIT = 1, BW_METHOD_DIRECT = 2, BW_METHOD_CONDENSED = 3 } BwMethod;
extern const char *const BwMethods[];

typedef struct _n_BwSolver *BwSolver;
struct _n_BwSolver {
  MPI_Comm  comm;
  BwMethod  requested;
  PetscReal rtol;
  PetscInt  schur_choice; /* solver.schur: 0 auto, 1 cholesky, 2 gamg */
  PetscBool schur_gamg;
  BwStorage storage; /* solver.storage */
  KSP       fieldsplit, cholesky, direct, condensed; /* destroyed when the solve is done */
  PetscBool ran_fieldsplit, ran_cholesky, ran_direct, ran_condensed;
  PetscBool direct_fits; /* small enough for MUMPS on the whole saddle matrix */
  /* outcome */
  BwMethod  used;
  PetscBool fallback;
  char      fallback_reason[512];
  PetscBool accuracy_met; /* the true residual met solver.rtol and the forward estimate its tolerance */
  char      warning[640]; /* why not, when it did not */
  PetscInt  iterations;
  BwCheck   check;
  /* Forward error of the displacements, estimated from the refinement
   * corrections (see BwSolverConverged): relative, max norm, rotations times
   * the assembly's size; -1 where not estimated (the condensed path). */
  PetscReal forward_rtol;      /* -solver_forward_rtol, default solver.rtol */
  PetscReal forward_estimate;
  PetscReal condition_estimate; /* 1-norm condition of S^ (Hager-Higham) where S^ was factored, else -1 */
  PetscInt  condition_when;     /* -solver_condition_estimate: 0 auto, 1 always, 2 never */
  /* state of the forward estimate during one KSP solve */
  BwMixed   mx;
  Vec       fw_weight, fw_prev, fw_work;
  PetscReal fw_last;
  PetscReal fw_prescribed; /* largest prescribed displacement, same weights: part of the field the error is relative to */
  PetscInt  fw_it;
  /* options this object inserted as defaults; cleared again if unused */
  PetscInt ndefaults;
  char     defaults[24][96];
};

PetscErrorCode BwSolverCreate(MPI_Comm comm, BwSolver *solver);
PetscErrorCode BwSolverSetFromOptions(BwSolver solver, BwScene scene);
/* The assembly's size picks the default Schur solve (solver.schur: auto). */
PetscErrorCode BwSolverSetSize(BwSolver solver, PetscInt nblocks);
/* Solves into mixed->x and fills the outcome and the residual check. */
PetscErrorCode BwSolverSolve(BwSolver solver, BwMixed mixed, BwLog *log);
/* Option prefixes of paths that did not run (their options are legitimately
 * unused), for BwSceneCheckUnused. */
/* Option prefixes of the solvers' PETSc objects, some of whose options
 * PETSc reads only when the solver is set up: checked after the solve. */
PetscErrorCode BwSolverGetOptionPrefixes(PetscInt *n, const char *const **prefixes);
PetscErrorCode BwSolverGetIdlePrefixes(BwSolver solver, PetscInt *n, const char *prefixes[6]);
PetscErrorCode BwSolverDestroy(BwSolver *solver);
