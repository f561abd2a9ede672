"""Run blockwall from a test and read its HDF5 output, on the blockwall
Python package of this checkout (python/blockwall: launch.py, results.py).

The executable and mpiexec come from the environment set by ctest
(BW_EXE, BW_MPIEXEC); every run writes into its own temporary directory.
The names below are the tests' API: run, solve, read, rel_err, expect,
Failure, EXE, ENV, MPIEXEC."""
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import blockwall  # noqa: E402

EXE = os.environ.get("BW_EXE", "build/bin/blockwall")
MPIEXEC = os.environ.get("BW_MPIEXEC", "mpiexec")
ENV = blockwall.environment()


class Failure(Exception):
    pass


def run(scene, args=(), np_ranks=1, expect_ok=True, timeout=600):
    """Run blockwall; returns (returncode, stdout, stderr)."""
    p = blockwall.run(scene, args, np_ranks, exe=EXE, mpiexec=MPIEXEC, check=False, timeout=timeout)
    if expect_ok and p.returncode != 0:
        raise Failure(f"blockwall failed ({p.returncode}): {' '.join(p.cmd)}\n{p.stdout}\n{p.stderr}")
    return p.returncode, p.stdout, p.stderr


def solve(scene, args=(), np_ranks=1):
    """Run blockwall to a temporary file and return its datasets and attributes."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.h5")
        run(scene, [*args, "-output_file", out], np_ranks)
        return read(out)


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
