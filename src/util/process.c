#define _POSIX_C_SOURCE 200809L /* setenv */
#include <stdlib.h>
#include <string.h>

#include "process.h"

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
  {
    const char *world = getenv("OMPI_COMM_WORLD_SIZE"), *local = getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
    int         singleton = !world && !getenv("PMIX_RANK") && !getenv("PMI_RANK");
    if (singleton || (world && local && !strcmp(world, local))) setenv("OMPI_MCA_pml", "ob1", 0);
  }
  /* Not OMPI_MCA_ess_singleton_isolated (no orted for a run started
   * without mpiexec, 0.2 s faster): isolated singletons share one session
   * directory, and two running at once failed in orte_session_dir when one
   * removed it as the other made it (dim3.nonlinear.tilt_slide, ctest -j2). */
}
