/* BwSolver: solves the scaled mixed system of BwMixed, K x = b, and checks
 * the answer; set up once, used for as many right-hand sides (load cases)
 * and as many refilled operators (Newton steps) as a run needs.
 *
 *   fieldsplit  Richardson on the true residual of the whole system,
 *               preconditioned by the exact block elimination of the scaled
 *               system (the Schur PC, schur.c): q~ from S^, then r~ from
 *               T D^ q~ - b_r, on views of the two fields. The Schur solve
 *               is a KSP of its own (prefix schur_): Cholesky (MUMPS, else
 *               CHOLMOD on one rank), or CG + GAMG with the rigid-body
 *               near-null space (solver.schur; by default by size). The
 *               outer KSP has no prefix (-ksp_*).
 *   direct      LU of the whole system (MUMPS, else SuperLU) with iterative
 *               refinement (Richardson on the true residual). Prefix direct_.
 *   condensed   the reference a benchmark compares with: S^ q~ = F^ + D^T b_r
 *               by Cholesky, then r~ = D^ q~ - b_r. Prefix condensed_. Not a
 *               fallback.
 *   auto        fieldsplit; if its KSP fails or the true residual of the
 *               full system misses solver.rtol: when the Schur solve was CG +
 *               GAMG, fieldsplit again with S^ factored (prefix cholesky_,
 *               its Schur solve cholesky_schur_); then direct, for
 *               assemblies small enough for it (below 2e5 blocks). The reason
 *               is recorded. If every path misses rtol but stays within
 *               sqrt(rtol), the best answer is kept with a warning.
 * Every KSP lives as long as the solver: a factorisation, ordering or AMG
 * hierarchy is built at the first solve and reused while the operators keep
 * their values; when BwMixedSetTangents refills them, the factor is redone
 * numerically on the same analysis (the pattern is the same) and GAMG keeps
 * its aggregates. Defaults are set in code on our own KSPs, then
 * KSPSetFromOptions, so every option overrides them. */
#pragma once
#include "system/mixed.h"
#include "util/log.h"
#include "util/report.h"

typedef enum { BW_METHOD_AUTO = 0, BW_METHOD_FIELDSPLIT = 1, BW_METHOD_DIRECT = 2, BW_METHOD_CONDENSED = 3 } BwMethod;
extern const char *const BwMethods[];

typedef struct _n_BwSolver *BwSolver;

PetscErrorCode BwSolverCreate(MPI_Comm comm, BwSolver *solver);
/* Reads solver.* (and -solver_* options without a scene key). */
PetscErrorCode BwSolverSetFromOptions(BwSolver solver, BwScene scene);
/* The storage the operators should use (solver.storage). */
PetscErrorCode BwSolverGetStorage(BwSolver solver, BwStorage *storage);
/* How many solves the analysis expects with the same operator values or
 * pattern (load cases, load steps; default 1): auto factors S^ for larger
 * assemblies when the factor will be reused. Before BwSolverSetUp. */
PetscErrorCode BwSolverSetExpectedSolves(BwSolver solver, PetscInt n);
/* Whether the operators stay symmetric (default): with non-symmetric
 * joint tangents (dilatancy below friction) S^ is factored by LU and an
 * iterative Schur solve is GMRES. Before BwSolverSetUp. */
PetscErrorCode BwSolverSetSymmetric(BwSolver solver, PetscBool symmetric);
/* Whether a solve that finds no usable answer looks for a mechanism to
 * name (default; one more factorisation). A nonlinear analysis, for which
 * a singular tangent is the collapse it is looking for, turns it off. */
PetscErrorCode BwSolverSetDiagnose(BwSolver solver, PetscBool diagnose);
/* Whether a solve must also meet solver.forward_rtol on its estimated
 * displacement error (default), which takes two steps of refinement at
 * least. Newton's corrections need only a small residual: their errors are
 * corrected by the next iteration, which checks the true residual of the
 * nonlinear system itself; without the check, a fieldsplit solve that
 * stalls within sqrt(solver.rtol) is accepted rather than refactored on
 * the direct path. */
PetscErrorCode BwSolverSetForwardCheck(BwSolver solver, PetscBool check);
/* Binds the solver to an assembled system and creates its KSPs (no
 * factorisation yet: that is the first solve's set-up phase). */
PetscErrorCode BwSolverSetUp(BwSolver solver, BwMixed mixed);
/* Solves K x = b (x: the initial guess is ignored), with the fallback and
 * the self-checks of solver.h; the outcome is kept for BwSolverReport. An
 * error (no usable answer) names the mechanism if S^ is singular. */
PetscErrorCode BwSolverSolve(BwSolver solver, Vec b, Vec x, BwLog *log);
/* The outcome of the last solve as /solver attributes, and the lines of the
 * summary that say how it went. */
PetscErrorCode BwSolverReport(BwSolver solver, BwReport report);
PetscErrorCode BwSolverView(BwSolver solver, PetscViewer viewer);
/* Option prefixes of the solvers' PETSc objects (checked after the solve,
 * since PETSc reads some only at set-up), and of the paths that did not run
 * (their options are legitimately unused); also -partition_, the options
 * of the geometry's MatPartitioning (distribute.c), and -matptap_via, the
 * algorithm of GAMG's Galerkin products (docs/cluster.md: allatonce holds
 * 30 % less memory on several ranks, for 2.7x the set-up time). */
PetscErrorCode BwSolverGetOptionPrefixes(PetscInt *n, const char *const **prefixes);
PetscErrorCode BwSolverGetIdlePrefixes(BwSolver solver, PetscInt *n, const char *prefixes[8]);
/* Frees the factors and work vectors (before recovery, to lower the peak). */
PetscErrorCode BwSolverReset(BwSolver solver);
PetscErrorCode BwSolverDestroy(BwSolver *solver);
