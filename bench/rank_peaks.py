"""Each rank's peak resident memory, measured from outside the process:
GNU time around every rank (mpiexec starts `sh -c 'exec /usr/bin/time ...'`,
which becomes the rank), one file per rank, named by Open MPI's rank (0
without mpiexec)."""
import os


def wrap(tmp):
    """The command words to put before blockwall's (after mpiexec's)."""
    return ["sh", "-c", f'exec /usr/bin/time -f %M -o {tmp}/mem.${{OMPI_COMM_WORLD_RANK:-0}} "$@"', "sh"]


def read(tmp, ranks):
    """The ranks' peaks [bytes], rank 0 first."""
    peaks = []
    for r in range(ranks):
        with open(os.path.join(tmp, f"mem.{r}")) as f:
            peaks.append(int(f.read().split()[-1]) * 1024)
    return peaks
