#define _XOPEN_SOURCE 700 /* setenv, mkdtemp, nftw */
#define _GNU_SOURCE       /* RTLD_DEFAULT */
#include <dirent.h>
#include <dlfcn.h>
#include <errno.h>
#include <ftw.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "process.h"

/* The private directory under which Open MPI keeps an isolated
 * singleton's session directory ("" when there is none); removed at exit. */
static char  bw_session_base[PATH_MAX];
static pid_t bw_session_owner; /* a forked child that exits leaves it */

static int BwRemoveEntry(const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
  (void)st;
  (void)flag;
  (void)ftw;
  (void)remove(path);
  return 0;
}

/* A directory and everything in it, depth first, links not followed */
static void BwRemoveTree(const char *path) { (void)nftw(path, BwRemoveEntry, 16, FTW_DEPTH | FTW_PHYS); }

void BwProcessRemoveSessionBase(void)
{
  if (!bw_session_base[0] || getpid() != bw_session_owner) return;
  /* the directory is this process's alone: whatever Open MPI left in it
   * (after a failed start) goes with it */
  BwRemoveTree(bw_session_base);
  bw_session_base[0] = 0;
}

/* The private directories of singletons that died by a signal (no exit
 * handler ran): blockwall-PID-* of this user, whose PID is gone. */
static void BwRemoveStaleSessionBases(const char *tmp)
{
  DIR           *dir = opendir(tmp);
  struct dirent *e;
  if (!dir) return;
  while ((e = readdir(dir))) {
    char        path[PATH_MAX];
    char       *end;
    struct stat st;
    long        pid;
    if (strncmp(e->d_name, "blockwall-", 10)) continue;
    pid = strtol(e->d_name + 10, &end, 10);
    if (end == e->d_name + 10 || *end != '-' || pid <= 0 || pid == (long)getpid()) continue;
    if (kill((pid_t)pid, 0) == 0 || errno != ESRCH) continue; /* alive, or not ours to tell */
    if (snprintf(path, sizeof(path), "%s/%s", tmp, e->d_name) >= (int)sizeof(path)) continue;
    if (lstat(path, &st) || !S_ISDIR(st.st_mode) || st.st_uid != geteuid()) continue;
    BwRemoveTree(path);
  }
  closedir(dir);
}

/* One rank started without mpiexec. Left to itself, Open MPI 4.1 forks an
 * orted for it and connects through PMIx (a small scene: 0.29 s, 0.15 s
 * isolated);
 * and in MPI_Finalize it unloads its PMIx component before it stops the
 * progress thread that can still run that component's events: about once
 * in 650 runs on a loaded machine the process died of SIGSEGV after its
 * last line (two cores, 2026-11-27: the progress thread in libevent at an
 * unmapped address where mca_pmix_ext3x.so had been, the main thread in
 * opal_progress_thread_finalize), and with the component kept loaded the
 * event hung on a torn-down lock instead. Isolated (ess_singleton_isolated)
 * the singleton starts alone: no orted, no PMIx server, no such event.
 * Isolated singletons all name their session directory alike
 * (ompi.HOST.UID/jf.0 under the temporary directory), and two at once
 * failed in orte_session_dir when one removed it as the other made it; so
 * each gets a directory of its own (orte_tmpdir_base), removed at exit,
 * or by the next singleton if this one was killed. A
 * user's own choice of either variable wins; without a writable temporary
 * directory the singleton starts as Open MPI would. */
static void BwProcessIsolateSingleton(void)
{
  const char *tmp = getenv("TMPDIR");
  if (getenv("OMPI_MCA_ess_singleton_isolated")) return;
  if (!getenv("OMPI_MCA_orte_tmpdir_base")) {
    if (!tmp || !tmp[0]) tmp = "/tmp";
    BwRemoveStaleSessionBases(tmp);
    if (snprintf(bw_session_base, sizeof(bw_session_base), "%s/blockwall-%ld-XXXXXX", tmp, (long)getpid()) >= (int)sizeof(bw_session_base) || !mkdtemp(bw_session_base)) {
      bw_session_base[0] = 0;
      return;
    }
    bw_session_owner = getpid();
    if (atexit(BwProcessRemoveSessionBase) || setenv("OMPI_MCA_orte_tmpdir_base", bw_session_base, 1)) {
      BwProcessRemoveSessionBase();
      return;
    }
  }
  setenv("OMPI_MCA_ess_singleton_isolated", "1", 1);
}

void BwProcessDefaults(void)
{
  /* Open MPI's OMPIO prints its own lines on stderr when a write fails (a
   * full disk); ROMIO reports through return codes only, which blockwall
   * turns into its one error line. A user's own choice (OMPI_MCA_io) wins. */
  setenv("OMPI_MCA_io", "^ompio", 0);
  /* PT-Scotch 7 (Debian's, the graph partitioner) bisects in threads that
   * call MPI concurrently, which needs MPI_THREAD_MULTIPLE; MPI here is
   * FUNNELED, and a 5-rank partition crashed in Open MPI's Allreduce
   * about once in 150 runs (kdgraphMapRbPart -> dgraphFold2 in a thread).
   * One Scotch thread per rank: the same algorithm, no concurrent MPI
   * call, and a partition that does not depend on the threads' timing.
   * It overrides a user's value: more threads are only safe with an MPI
   * initialised for them. */
  setenv("SCOTCH_PTHREAD_NUMBER", "1", 1);
  /* Ranks that all run on this machine (or one rank started without
   * mpiexec) talk through shared memory, which Open MPI's ob1 layer does.
   * Left to choose, Debian's Open MPI first loads and probes the Omni-Path
   * and InfiniPath libraries of its cm layer: 0.2 s of the 0.37 s MPI_Init
   * took here, in every process. Where the ranks span machines (the local
   * size below the world's) Open MPI chooses as it would; a user's own
   * choice (OMPI_MCA_pml, --mca pml) wins. MPICH ignores the variable. */
  const char *world = getenv("OMPI_COMM_WORLD_SIZE"), *local = getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  int         singleton = !world && !getenv("PMIX_RANK") && !getenv("PMI_RANK");
  if (singleton || (world && local && !strcmp(world, local))) setenv("OMPI_MCA_pml", "ob1", 0);
  if (singleton) BwProcessIsolateSingleton();
}

const char *BwProcessOpenBlasKernels(void)
{
  char *(*corename)(void);

  *(void **)(&corename) = dlsym(RTLD_DEFAULT, "openblas_get_corename");
  return corename ? corename() : NULL;
}

/* OpenBLAS picks its kernels for the CPU when it is loaded, from the CPU's
 * family and model. Debian 12's OpenBLAS (0.3.21) does not know the Intel
 * Xeons of 2023 on (Sapphire and Emerald Rapids, family 6 models 143 and
 * 207) and falls back to its Prescott kernels (SSE3, 2004): measured on an
 * Emerald Rapids VM, MUMPS's 204 LU factorisations of the tilting U-wall
 * (bench/tilt_u_wall.py) 20.7 s with them, 15.0 s with the Haswell (AVX2)
 * kernels. Where OpenBLAS chose Prescott on a CPU that has AVX2 and FMA
 * (and AVX-512: SkylakeX), the process starts again with
 * OPENBLAS_CORETYPE naming the kernels the CPU runs; OpenBLAS reads it
 * only when loaded. A user's own OPENBLAS_CORETYPE wins, and a process
 * started again finds it set, so this happens at most once. Another BLAS
 * (the reference BLAS, no openblas_get_corename) is left alone. */
void BwProcessBlasKernels(char **argv)
{
  const char *name, *kernels = NULL;

  if (getenv("OPENBLAS_CORETYPE")) return;
  if (!(name = BwProcessOpenBlasKernels()) || strcmp(name, "Prescott")) return;
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl")) kernels = "SkylakeX";
  else if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) kernels = "Haswell";
#endif
  if (!kernels) return;
  {
    /* the executable's own path, not /proc/self/exe: the process keeps its
     * name (ps, pkill, the suite's watchdog find it as blockwall) */
    char    self[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", self, sizeof(self) - 1);
    if (n <= 0 || n >= (ssize_t)sizeof(self) - 1) return;
    self[n] = 0;
    if (setenv("OPENBLAS_CORETYPE", kernels, 1)) return;
    (void)execv(self, argv);
  }
  /* could not start again: go on with the kernels loaded */
  (void)unsetenv("OPENBLAS_CORETYPE");
}
