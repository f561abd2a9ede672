#define _GNU_SOURCE /* dladdr, realpath */
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>
#include <dlfcn.h>
#include <stdlib.h>
#include "util/log.h"
#include "util/process.h"
#include "util/compat.h"

const char *const BwPhaseNames[BW_NPHASES] = {"generate", "partition", "assemble", "setup", "solve", "recover", "write"};
PetscLogEvent     BwEvents[BW_NEVENTS];

PetscErrorCode BwLogCreate(MPI_Comm comm, BwLog *log)
{
  static const char *const stages[BW_NPHASES] = {"Generate", "Partition", "Assemble", "Setup", "Solve", "Recover", "Write"};
  static PetscLogStage     registered[BW_NPHASES];
  static PetscBool         done = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(log, sizeof(*log)));
  log->comm = comm;
  if (!done) {
    static const char *const events[BW_NEVENTS] = {"BwLayout", "BwRestraint", "BwAssembleD", "BwAssembleS", "BwGatherGhosts", "BwResults", "BwCheck"};
    PetscClassId             id;
    for (int s = 0; s < BW_NPHASES; s++) PetscCall(PetscLogStageRegister(stages[s], &registered[s]));
    PetscCall(PetscClassIdRegister("blockwall", &id));
    for (int e = 0; e < BW_NEVENTS; e++) PetscCall(PetscLogEventRegister(events[e], id, &BwEvents[e]));
    done = PETSC_TRUE;
  }
  for (int s = 0; s < BW_NPHASES; s++) log->stage[s] = registered[s];
  PetscCall(PetscTime(&log->t0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwLogBegin(BwLog *log, BwPhase phase)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePush(log->stage[phase]));
  PetscCall(PetscTime(&log->start));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwLogEnd(BwLog *log, BwPhase phase)
{
  PetscLogDouble t, dt;

  PetscFunctionBeginUser;
  PetscCall(PetscTime(&t));
  dt = t - log->start;
  log->seconds[phase] += dt;
  PetscCall(PetscLogStagePop());
  if (log->verbose) {
    PetscLogDouble cur, peak;
    PetscCall(BwMemoryUsage(log->comm, &cur, &peak));
    PetscCall(PetscPrintf(log->comm, "[blockwall] %-9s %9.3f s  (elapsed %9.3f s)  memory %9.1f MB, peak %9.1f MB\n", BwPhaseNames[phase], dt, t - log->t0, cur / 1048576.0, peak / 1048576.0));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwLogTotal(BwLog *log, PetscLogDouble *total)
{
  PetscLogDouble t;

  PetscFunctionBeginUser;
  PetscCall(PetscTime(&t));
  *total = t - log->t0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMemoryUsage(MPI_Comm comm, PetscLogDouble *current, PetscLogDouble *peak)
{
  PetscLogDouble loc[2], glob[2];
  struct rusage  ru;

  PetscFunctionBeginUser;
  PetscCall(PetscMemoryGetCurrentUsage(&loc[0]));
  getrusage(RUSAGE_SELF, &ru);
  loc[1] = (PetscLogDouble)ru.ru_maxrss * 1024.0; /* Linux: kilobytes */
  PetscCallMPI(MPI_Allreduce(loc, glob, 2, MPI_DOUBLE, MPI_SUM, comm));
  *current = glob[0];
  *peak    = glob[1];
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* What the memory limits of a cgroup and of its parents leave [bytes]: a
 * batch system's job and step limits sit above the task's cgroup, whose
 * own limit is none; -1 where no limit can be read. */
static PetscLogDouble BwCgroupLeft(const char root[], const char cgroup[], const char limit_file[], const char usage_file[])
{
  char           path[1200], *slash;
  PetscLogDouble best = -1;

  (void)snprintf(path, sizeof(path), "%s", cgroup);
  for (;;) {
    char               dir[1300], file[1400];
    unsigned long long max, cur;
    FILE              *m, *c;
    (void)snprintf(dir, sizeof(dir), "%s%s", root, strcmp(path, "/") ? path : "");
    (void)snprintf(file, sizeof(file), "%s/%s", dir, limit_file);
    if ((m = fopen(file, "r"))) {
      /* "max" (v2) reads as no number: no limit here */
      if (fscanf(m, "%llu", &max) == 1) {
        (void)snprintf(file, sizeof(file), "%s/%s", dir, usage_file);
        if ((c = fopen(file, "r"))) {
          if (fscanf(c, "%llu", &cur) == 1) {
            PetscLogDouble left = cur < max ? (PetscLogDouble)(max - cur) : 0;
            if (best < 0 || left < best) best = left;
          }
          fclose(c);
        }
      }
      fclose(m);
    }
    if (!strcmp(path, "/") || !(slash = strrchr(path, '/'))) break;
    if (slash == path) slash[1] = 0;
    else *slash = 0;
  }
  return best;
}

/* The tightest cgroup limit on this process (v2, or v1's memory
 * controller), less what its cgroup uses; -1 where there is none. */
static PetscLogDouble BwCgroupAvailable(void)
{
  FILE          *f = fopen("/proc/self/cgroup", "r");
  char           line[1024];
  PetscLogDouble best = -1;

  if (!f) return -1;
  while (fgets(line, sizeof(line), f)) {
    PetscLogDouble left = -1;
    char          *colon;
    line[strcspn(line, "\n")] = 0;
    if (!strncmp(line, "0::", 3)) left = BwCgroupLeft("/sys/fs/cgroup", line + 3, "memory.max", "memory.current");
    else if ((colon = strstr(line, ":memory:"))) left = BwCgroupLeft("/sys/fs/cgroup/memory", colon + 8, "memory.limit_in_bytes", "memory.usage_in_bytes");
    if (left >= 0 && (best < 0 || left < best)) best = left;
  }
  fclose(f);
  return best;
}

PetscErrorCode BwMemoryAvailable(PetscLogDouble *bytes)
{
  FILE          *f = fopen("/proc/meminfo", "r");
  char           line[256];
  PetscLogDouble cg = BwCgroupAvailable();

  PetscFunctionBeginUser;
  *bytes = (PetscLogDouble)sysconf(_SC_PHYS_PAGES) * (PetscLogDouble)sysconf(_SC_PAGESIZE);
  if (f) {
    while (fgets(line, sizeof(line), f)) {
      long long kb;
      if (sscanf(line, "MemAvailable: %lld kB", &kb) == 1) {
        *bytes = 1024.0 * (PetscLogDouble)kb;
        break;
      }
    }
    fclose(f);
  }
  if (cg >= 0 && cg < *bytes) *bytes = cg;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMemoryPerRank(MPI_Comm comm, PetscBool with_held, PetscLogDouble *bytes, PetscMPIInt *per_node)
{
  MPI_Comm       node;
  PetscMPIInt    nlocal, local_rank;
  PetscLogDouble avail = 0, held = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node));
  PetscCallMPI(MPI_Comm_size(node, &nlocal));
  PetscCallMPI(MPI_Comm_rank(node, &local_rank));
  /* read once per node (below: given to the node's other ranks), so that
   * the ranks of one node agree */
  if (!local_rank) PetscCall(BwMemoryAvailable(&avail));
  if (with_held) {
    /* what the run's ranks on this node already hold is theirs too */
    PetscCall(PetscMemoryGetCurrentUsage(&held));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &held, 1, MPI_DOUBLE, MPI_SUM, node));
  }
  PetscCallMPI(MPI_Bcast(&avail, 1, MPI_DOUBLE, 0, node));
  PetscCallMPI(MPI_Comm_free(&node));
  /* the most crowded, smallest node decides, the same on every rank */
  *bytes = (avail + held) / nlocal;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, bytes, 1, MPI_DOUBLE, MPI_MIN, comm));
  if (per_node) PetscCallMPI(MPI_Allreduce(&nlocal, per_node, 1, MPI_INT, MPI_MAX, comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwMemoryRequire(MPI_Comm comm, PetscLogDouble bytes, const char what[])
{
  PetscMPIInt    nlocal;
  PetscLogDouble avail;

  PetscFunctionBeginUser;
  PetscCall(BwMemoryPerRank(comm, PETSC_FALSE, &avail, &nlocal));
  PetscCheck(bytes <= avail, comm, PETSC_ERR_USER_INPUT, "%s needs about %.3g GB of memory (%.3g GB on each of the %d ranks of a node), more than the %.3g GB this machine has available", what, bytes * nlocal / 1e9, bytes / 1e9, nlocal, avail * nlocal / 1e9);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwBlasKernels(char name[], size_t len)
{
  const char *kernels = BwProcessOpenBlasKernels();

  PetscFunctionBeginUser;
  (void)snprintf(name, len, "%s", kernels ? kernels : "");
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwBlasName(char name[], size_t len)
{
  FILE *f;
  char  line[4096];
  void *dgemm = dlsym(RTLD_DEFAULT, "dgemm_");
  Dl_info info;

  PetscFunctionBeginUser;
  (void)snprintf(name, len, "unknown");
  /* The library whose dgemm_ the process's calls bind to (the global
   * lookup the dynamic linker resolved them with): the one that computes,
   * even where a second BLAS is mapped too (a libopenblas.so.0 that
   * another library names directly beside libblas.so.3). Its real path:
   * libblas.so.3 resolved to its alternative, e.g. openblas-pthread. */
  if (dgemm && dladdr(dgemm, &info) && info.dli_fname) {
    char *real = realpath(info.dli_fname, NULL);
    (void)snprintf(name, len, "%s", real ? real : info.dli_fname);
    free(real);
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  /* no dgemm_ in the global scope (a BLAS loaded privately): the first
   * BLAS-like library mapped */
  f = fopen("/proc/self/maps", "r");
  if (!f) PetscFunctionReturn(PETSC_SUCCESS);
  while (fgets(line, sizeof(line), f)) {
    char *path = strchr(line, '/');
    if (!path) continue;
    path[strcspn(path, "\n")] = 0;
    if (strstr(path, "libblas") || strstr(path, "libopenblas") || strstr(path, "libmkl_rt") || strstr(path, "libblis")) {
      (void)snprintf(name, len, "%s", path);
      break;
    }
  }
  fclose(f);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwBlasSetThreads(MPI_Comm comm)
{
  MPI_Comm    node;
  PetscMPIInt local;
  long        cores = sysconf(_SC_NPROCESSORS_ONLN);
  void (*set)(int), (*omp)(int);
  int         threads;

  PetscFunctionBeginUser;
  if (getenv("OPENBLAS_NUM_THREADS") || getenv("OMP_NUM_THREADS") || getenv("GOTO_NUM_THREADS")) PetscFunctionReturn(PETSC_SUCCESS);
  *(void **)&set = dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
  /* OpenMP's too, where a library of PETSc's brought it (Debian's
   * SuperLU_DIST, -schur_pc_factor_mat_solver_type superlu_dist): its
   * default, a thread per core in every rank, left a 412-block pushover
   * on 3 ranks of this 2-core machine running for 14 minutes (stopped)
   * that ends in about 10 s with one thread each (2026-11-28) */
  *(void **)&omp = dlsym(RTLD_DEFAULT, "omp_set_num_threads");
  if (!set && !omp) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCallMPI(MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node));
  PetscCallMPI(MPI_Comm_size(node, &local));
  PetscCallMPI(MPI_Comm_free(&node));
  threads = (int)PetscMax(1, cores > 0 ? cores / local : 1);
  if (set) set(threads);
  if (omp) omp(threads);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwBlasSetThreadsForRows(PetscInt rows)
{
  void (*set)(int);

  PetscFunctionBeginUser;
  if (rows >= BW_BLAS_SHARED_ROWS) PetscFunctionReturn(PETSC_SUCCESS);
  if (getenv("OPENBLAS_NUM_THREADS") || getenv("OMP_NUM_THREADS") || getenv("GOTO_NUM_THREADS")) PetscFunctionReturn(PETSC_SUCCESS);
  *(void **)&set = dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
  if (set) set(1);
  PetscFunctionReturn(PETSC_SUCCESS);
}
