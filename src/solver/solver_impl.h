/* The inside of BwSolver, shared by the files of src/solver. */
#pragma once
#include <petscksp.h>
#include "solver/solver.h"
#include "util/factor.h"

/* solver.schur */
typedef enum { BW_SCHUR_AUTO = 0, BW_SCHUR_CHOLESKY = 1, BW_SCHUR_GAMG = 2, BW_SCHUR_HYPRE = 3 } BwSchurSolve;
/* -solver_forward_bound: how the round-off part of the forward estimate is found (estimates.c) */
typedef enum { BW_FORWARD_AUTO = 0, BW_FORWARD_WHOLE = 1, BW_FORWARD_SCHUR = 2, BW_FORWARD_EXTRA = 3 } BwForwardBound;
extern const char *const BwSchurSolves[];
/* CNTL(7) of S^'s block low-rank factor (solver.low_rank; solver.c's
 * BW_LOW_RANK_ROWS says what it bought) */
#define BW_LOW_RANK_TOL 1e-12

/* A path that ran or may run: its outer KSP, kept for the next solve. */
typedef struct {
  const char *name;   /* for messages: "fieldsplit", "fieldsplit with S^ factored", "direct (LU)" */
  KSP         ksp;
  BwMethod    method; /* what /solver calls it */
  PetscBool   ran, ran_once; /* in the last solve; ever (its first solve sets it up) */
  PetscBool   qspace; /* its KSP refines on the block dofs (S~, fieldsplit paths), else on K */
} BwPath;

struct _n_BwSolver {
  MPI_Comm     comm;
  BwMixed      mx;
  BwMethod     requested;
  PetscReal    rtol;
  BwSchurSolve schur;      /* as given */
  PetscBool    schur_iterative; /* the fieldsplit's Schur solve does not factor S^ */
  PetscReal    memory;          /* -solver_memory [GB] the run may use summed over its ranks; 0: what the nodes have available */
  char         schur_choice[256]; /* why auto chose the Schur solve it chose, where memory decided it; "" otherwise */
  PetscInt     low_rank_when; /* -solver_low_rank: 0 auto, 1 always, 2 never */
  PetscBool    low_rank;      /* the fieldsplit path's factor of S^ is MUMPS's block low-rank one (BwSolverSetUp) */
  PetscReal    low_rank_ratio; /* entries of the last low-rank factor over its full-rank count (INFOG(35) / INFOG(29)); -1 none */
  BwStorage    storage;
  PetscInt     expected_solves; /* solves the analysis will make with one operator (BwSolverSetExpectedSolves) */
  PetscBool    direct_fits; /* small enough for a factorisation of the whole saddle matrix */
  PetscInt     condition_when; /* -solver_condition_estimate: 0 auto, 1 always, 2 never */
  BwForwardBound forward_bound; /* whole: K~ assembled; schur: S^'s factor, D^ by its structure; extra: a residual in double-double */
  PetscReal    forward_rtol;   /* -solver_forward_rtol, default solver.rtol */
  /* the paths, in the order auto tries them */
  BwPath       fieldsplit, cholesky, direct, condensed;
  Mat          Sexact; /* S~ applied exactly: the operator of the fieldsplit paths' refinement on q */
  Vec          wq, xq; /* its right-hand side, b_q + D^T b_r, and solution */
  Mat          Kaij; /* the assembled saddle matrix of the direct path, built on demand */
  PetscInt     kaij_state; /* the operators' values state Kaij holds */
  PetscInt     values_seen, setups; /* operator values of the last solve; solves that set up a new factor or hierarchy */
  PetscBool    symmetric;  /* the operators stay symmetric (else LU and GMRES where Cholesky and CG) */
  PetscInt     mumps_analysis; /* INFOG(32) of the last MUMPS factorisation: 1 sequential (on rank 0), 2 parallel; 0 none */
  PetscBool    reproducible; /* -solver_reproducible on several ranks: every factorisation redundant, one sequential factor per rank */
  PetscBool    diagnose;   /* a failed solve names a mechanism (an extra factorisation) */
  PetscBool    forward_check; /* a solve also meets solver.forward_rtol (two refinement steps at least) */
  PetscBool    trivial;    /* no block dof is free: nothing to solve for (BwSolverSetUp) */
  /* outcome of the last solve */
  BwMethod     used;
  const char  *schur_used; /* the Schur solve of the answer's fieldsplit path: cholesky | gamg | hypre; "" otherwise */
  PetscBool    fallback;
  char         fallback_reason[512];
  PetscBool    accuracy_met;
  char         warning[2048];
  PetscInt     iterations;
  BwCheck      check;
  PetscReal    forward_estimate;   /* forward error of the displacements, from the refinement; -1 not estimated */
  PetscReal    condition_estimate; /* 1-norm condition of what was factored; -1 not estimated */
  /* state of the forward estimate during one KSP solve */
  Vec          fw_weight, fw_prev, fw_work;
  PetscReal    fw_last, fw_ratio, fw_prescribed; /* last correction, last ratio of corrections */
  PetscInt     fw_it;
  PetscReal    fw_rprev;    /* the last step's residual norm */
  PetscBool    floor_stall; /* the last refinement stopped at the residual's round-off floor, its displacements within forward_rtol */
  PetscReal    residual_floor; /* where the last refinement stopped within the floor that rounding q to double leaves (BwMixedSchurTermsNorm): that floor relative to |b|, as the residual; else -1 */
};

/* schur.c: the Schur PC on an outer KSP, its Schur solve with prefix
 * <outer prefix>schur_ (Cholesky when factor, else by solver.schur). */
PetscErrorCode BwSchurPCSetUp(BwSolver s, KSP outer, PetscBool factor);
/* The KSP of the Schur solve of a fieldsplit path (NULL for other paths). */
PetscErrorCode BwSchurPCGetInner(KSP outer, KSP *inner);
/* The Schur PC's elimination on whole-system vectors (z, y of K's size). */
PetscErrorCode BwSchurPCApplyFull(PC pc, Vec z, Vec y);
/* Factor-PC defaults for a Cholesky or LU with the package this PETSc has:
 * null-pivot detection with MUMPS. */
PetscErrorCode BwSolverSetFactor(BwSolver s, PC pc, BwFactorKind kind, Mat A);
PetscErrorCode BwSolverFactorDefaults(PC pc);
/* The MUMPS factor matrix of a factorisation PC whose package is MUMPS; NULL otherwise (schur.c) */
PetscErrorCode BwSolverGetMumpsFactor(PC pc, Mat *F);

/* amg.c: the preconditioner of an iterative Schur solve on inner (its
 * KSP type set): GAMG with the near-null space of S^, and in 3D the blocks
 * with very many neighbours eliminated exactly. */
PetscErrorCode BwSchurAMGSetUp(BwSolver s, KSP inner);

/* estimates.c */
PetscErrorCode BwSolverForwardSetUp(BwSolver s);
PetscErrorCode BwSolverSetConvergenceTest(BwSolver s, KSP ksp);
PetscErrorCode BwSolverConditionEstimate(PC pc, Mat A, PetscBool symmetric, PetscReal *cond);
/* Round-off bound on the displacement error of x from A's factor (LAPACK's FERR) */
PetscErrorCode BwSolverForwardBound(BwSolver s, BwPath *path, Vec x, PetscReal *ferr);
/* The same without K assembled, through S^'s factor (estimates.c) */
PetscErrorCode BwSolverForwardBoundSchur(BwSolver s, PC fpc, PetscBool symmetric, Vec b, Vec x, PetscReal *ferr);
/* 10 x the error S~^-1 r_q from a residual in double-double (estimates.c) */
PetscErrorCode BwSolverForwardExtra(BwSolver s, PC fpc, Vec b, Vec x, PetscReal *ferr);
/* The factor a path used (the Schur complement's on fieldsplit, the whole
 * system's on direct) and the matrix it factors; NULL when it factored
 * nothing (CG + GAMG). */
PetscErrorCode BwSolverGetFactorPC(KSP ksp, PC *fpc, Mat *A);
PetscErrorCode BwSolverNullPivots(KSP ksp, PetscInt *npiv);
/* INFOG(i) of the MUMPS factor a path used; -1 where it used none */
PetscErrorCode BwSolverMumpsInfog(KSP ksp, PetscInt i, PetscInt *value);
