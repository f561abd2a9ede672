/* Phases of a run: log stages (so -log_view shows where time goes), wall
 * time and memory per phase for the summary, the HDF5 /solver attributes and
 * the progress lines a long run prints on rank 0. */
#pragma once
#include <petscsys.h>

typedef enum { BW_PHASE_GENERATE, BW_PHASE_PARTITION, BW_PHASE_ASSEMBLE, BW_PHASE_SETUP, BW_PHASE_SOLVE, BW_PHASE_RECOVER, BW_PHASE_WRITE, BW_NPHASES } BwPhase;
extern const char *const BwPhaseNames[BW_NPHASES];

/* Events inside the phases, registered once by BwLogCreate. */
typedef enum { BW_EVENT_LAYOUT, BW_EVENT_RESTRAINT, BW_EVENT_ASSEMBLE_D, BW_EVENT_ASSEMBLE_S, BW_EVENT_GATHER, BW_EVENT_RESULTS, BW_EVENT_CHECK, BW_NEVENTS } BwEvent;
extern PetscLogEvent BwEvents[BW_NEVENTS];

typedef struct {
  MPI_Comm       comm;
  PetscBool      verbose;            /* print one line per phase */
  PetscLogStage  stage[BW_NPHASES];
  PetscLogDouble seconds[BW_NPHASES]; /* accumulated */
  PetscLogDouble start;               /* of the phase in progress */
  PetscLogDouble t0;                  /* of the run */
} BwLog;

PetscErrorCode BwLogCreate(MPI_Comm comm, BwLog *log);
PetscErrorCode BwLogBegin(BwLog *log, BwPhase phase);
PetscErrorCode BwLogEnd(BwLog *log, BwPhase phase);
PetscErrorCode BwLogTotal(BwLog *log, PetscLogDouble *total);
/* Resident memory summed over ranks [bytes]: now and the peak so far. */
PetscErrorCode BwMemoryUsage(MPI_Comm comm, PetscLogDouble *current, PetscLogDouble *peak);
/* Memory this machine can give now [bytes]: MemAvailable of /proc/meminfo
 * (physical memory where that is missing), or less where the process's
 * cgroup (a batch system's job) has less left under its limit. */
PetscErrorCode BwMemoryAvailable(PetscLogDouble *bytes);
/* The memory each rank can count on [bytes]: its node's available memory
 * (with_held: plus what the run's ranks on the node hold now, for an
 * estimate of the whole run's peak) shared among the ranks on the node,
 * the smallest share over all nodes; per_node (may be NULL): the most
 * ranks on one node. Collective. */
PetscErrorCode BwMemoryPerRank(MPI_Comm comm, PetscBool with_held, PetscLogDouble *bytes, PetscMPIInt *per_node);
/* Refuses, before allocating, `bytes` on each rank when the ranks sharing a
 * node cannot have that much together: one error line saying what was asked
 * for (`what`), what it needs and what the node has. Collective. */
PetscErrorCode BwMemoryRequire(MPI_Comm comm, PetscLogDouble bytes, const char what[]);
/* OpenBLAS's threads: the node's cores shared among the ranks on it (one
 * each when there are as many ranks as cores), unless OPENBLAS_NUM_THREADS
 * or OMP_NUM_THREADS says otherwise. Its default, a thread per core in
 * every rank, oversubscribes the node, and its idle threads spin: on 2
 * ranks of a 2-core machine, 45 % of a pushover's time went to sched_yield.
 * Nothing happens with another BLAS. OpenMP's threads, where PETSc's
 * libraries brought OpenMP (SuperLU_DIST), are shared out alike. */
PetscErrorCode BwBlasSetThreads(MPI_Comm comm);
/* Then, once the size is known: one BLAS thread on a rank whose
 * factorisations have fewer than `rows` BW_BLAS_SHARED_ROWS rows there.
 * Its BLAS calls are too small to share (level-1 operations on vectors of
 * a few thousand entries, fronts of a few hundred rows), and the second
 * thread spins between them: examples/j4d_cap.yaml on 1 rank took 13.6 s
 * with two threads (11.9 s of it system time) against 7.7 s with one; a
 * 2000-block 3D pushover 29.4 s (24.5 s system) against 30.2 s. The
 * 1e5-block 3D wall's factor gains a little from two (4.75 against 5.15
 * s). Unless OPENBLAS_NUM_THREADS or OMP_NUM_THREADS says otherwise. */
#define BW_BLAS_SHARED_ROWS 200000
PetscErrorCode BwBlasSetThreadsForRows(PetscInt rows);
/* Path of the BLAS library this process computes with: the one its dgemm_
 * binds to (else the first BLAS in /proc/self/maps). */
PetscErrorCode BwBlasName(char name[], size_t len);
/* OpenBLAS's kernels in use (openblas_get_corename: "Haswell",
 * "SkylakeX", "Zen", ...), "" for another BLAS. */
PetscErrorCode BwBlasKernels(char name[], size_t len);
