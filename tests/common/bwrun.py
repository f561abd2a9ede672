"""Run blockwall from a test and read its HDF5 output, on the blockwall
Python package of this checkout (python/blockwall: launch.py, results.py).

The executable and mpiexec come from the environment set by ctest
(BW_EXE, BW_MPIEXEC); every run writes into its own temporary directory.
The names below are the tests' API: run, solve, call, start, budget, read,
rel_err, expect, each, share, Failure, TimedOut, EXE, ENV, MPIEXEC.

Every process a test starts goes through run, solve, call or start, and is
watched (blockwall.launch.Watched): if it has not ended when the test's
time is nearly up, the watchdog prints the process tree, a gdb backtrace of
every rank and the run's last output lines, kills the process group, and
the test fails with TimedOut. The test's time is ctest's TIMEOUT of it,
which tests/CMakeLists.txt passes as BW_TEST_TIMEOUT; the watchdog fires
max(30 s, 10 %) before it (the report's gdb runs take 10 s, at most
blockwall.launch.GDB_SECONDS), so that a hang explains itself instead of
being killed mute by ctest."""
import json
import os
import resource
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import blockwall  # noqa: E402

EXE = os.environ.get("BW_EXE", "build/bin/blockwall")
MPIEXEC = os.environ.get("BW_MPIEXEC", "mpiexec")
ENV = blockwall.environment()


class Failure(Exception):
    pass


class TimedOut(Failure, blockwall.launch.RunTimeout):
    """A watched process killed by the watchdog (its report is on stderr)."""


_STARTED = time.monotonic()
TEST_TIMEOUT = float(os.environ.get("BW_TEST_TIMEOUT") or 0) or None
UNTIMED = 1500  # run by hand, outside ctest: ctest's own default
# BW_CALL_LOG=FILE: every process a test runs through call() appends a line
# to FILE (JSON: the test's arguments, the command, its wall and CPU
# seconds, children included), to see where the suite's time goes
CALL_LOG = os.environ.get("BW_CALL_LOG")


def budget(timeout=None):
    """Seconds a process started now may run: `timeout` if given, but never
    past the test's deadline, max(30 s, 10 %) before ctest's TIMEOUT (time
    for the watchdog's report). Past the deadline already: a failure at once."""
    total = TEST_TIMEOUT or UNTIMED
    left = _STARTED + total - max(30.0, 0.1 * total) - time.monotonic()
    if left <= 0:
        raise Failure(f"the test's time is up ({time.monotonic() - _STARTED:.0f} s of its TIMEOUT {total:.0f} s, "
                      f"less the watchdog's margin) before it could start its next process")
    return min(timeout, left) if timeout else left


def start(cmd, timeout=None, env=None, cwd=None, what=None):
    """Start a command watched (blockwall.launch.Watched: readline, proc,
    wait); env None: this process's environment."""
    return blockwall.launch.start(cmd, budget(timeout), env, cwd, what, error=TimedOut)


def call(cmd, timeout=None, env=None, cwd=None, what=None):
    """Run a command to its end, watched: (returncode, stdout, stderr) as
    attributes, like subprocess.run(capture_output=True, text=True)."""
    t0, r0 = time.monotonic(), resource.getrusage(resource.RUSAGE_CHILDREN)
    p = start(cmd, timeout, env, cwd, what).wait()
    if CALL_LOG:
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        with open(CALL_LOG, "a") as f:
            f.write(json.dumps({"test": " ".join(sys.argv), "cmd": " ".join(map(str, cmd)), "wall": time.monotonic() - t0,
                                "cpu": r1.ru_utime + r1.ru_stime - r0.ru_utime - r0.ru_stime}) + "\n")
    return p


# For a run expected to fail. When a rank exits non-zero, Open MPI's
# mpiexec (4.1) stops the job: SIGTERM to its ranks, then it waits
# odls_base_sigkill_timeout (1 s) before it reaps them, even when every
# rank has already exited: `mpiexec -n 2 sh -c 'exit 1'` takes 1.05 to 2.07 s
# here, 0.05 s with the wait at 0. blockwall's ranks agree on an error and
# leave through MPI_Finalize together, so nothing is left to wait for; the
# tests of the launcher's own kill sequence (errors/check_io.py) keep it.
FAILING_ENV = dict(ENV, OMPI_MCA_odls_base_sigkill_timeout="0")


def run(scene, args=(), np_ranks=1, expect_ok=True, timeout=None, extra_env=None):
    """Run blockwall, watched; returns (returncode, stdout, stderr).
    extra_env: more environment variables for the run (e.g. LD_PRELOAD)."""
    env = dict(ENV if expect_ok else FAILING_ENV, **(extra_env or {}))
    p = call(blockwall.command(scene, args, np_ranks, exe=EXE, mpiexec=MPIEXEC), timeout, env, what="blockwall")
    if expect_ok and p.returncode != 0:
        raise Failure(f"blockwall failed ({p.returncode}): {' '.join(p.cmd)}\n{p.stdout}\n{p.stderr}")
    return p.returncode, p.stdout, p.stderr


def solve(scene, args=(), np_ranks=1, extra_env=None, stdout=False):
    """Run blockwall to a temporary file and return its datasets and
    attributes (and its stdout, with stdout=True)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.h5")
        _, text, _ = run(scene, [*args, "-output_file", out], np_ranks, extra_env=extra_env)
        return (read(out), text) if stdout else read(out)


def read(path):
    """{dataset path: array} of every dataset, and "attrs" (root) and "solver" (/solver attributes)."""
    return blockwall.read_datasets(path)


def rel_err(got, want):
    got, want = np.asarray(got, float), np.asarray(want, float)
    scale = np.max(np.abs(want))
    return np.max(np.abs(got - want)) / (scale if scale > 0 else 1.0)


def expect(cond, message):
    if not cond:
        raise Failure(message)


def each(items, check, label=str):
    """check(item) for every item of a test that runs several cases in one
    process: a failure is printed and the next item still runs (a failed
    case does not hide the next); then, if any failed, one line naming them
    and exit 1. Returns {item: check's result} of the items that passed."""
    results, failed = {}, []
    for item in items:
        try:
            results[item] = check(item)
        except Failure as e:
            print(f"FAIL {label(item)}: {e}")
            failed.append(label(item))
    if failed:
        print(f"FAIL: {len(failed)} of {len(items)}: {', '.join(failed)}")
        sys.exit(1)
    return results


def share(items, k, n):
    """The K-th of N consecutive parts of items (K = 1..N), near-equal in
    size: one ctest test's part of a case list."""
    items = list(items)
    return items[(k - 1) * len(items) // n:k * len(items) // n]
