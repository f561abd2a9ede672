#define _POSIX_C_SOURCE 200809L /* setenv */
#include <stdlib.h>

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
  /* Not OMPI_MCA_ess_singleton_isolated (no orted for a run started
   * without mpiexec, 0.2 s faster): isolated singletons share one session
   * directory, and two running at once failed in orte_session_dir when one
   * removed it as the other made it (dim3.nonlinear.tilt_slide, ctest -j2). */
}
