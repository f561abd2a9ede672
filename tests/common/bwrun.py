"""Run blockwall from a test and read its HDF5 output (h5py, numpy).

The executable and mpiexec come from the environment set by ctest
(BW_EXE, BW_MPIEXEC); every run writes into its own temporary directory."""
import os
import subprocess
import tempfile

import h5py
import numpy as np

EXE = os.environ.get("BW_EXE", "build/bin/blockwall")
MPIEXEC = os.environ.get("BW_MPIEXEC", "mpiexec")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")


class Failure(Exception):
    pass


def run(scene, args=(), np_ranks=1, expect_ok=True, timeout=600):
    """Run blockwall; returns (returncode, stdout, stderr)."""
    cmd = [EXE, "-scene", scene, *map(str, args)]
    if np_ranks > 1:
        cmd = [MPIEXEC, "--oversubscribe", "-n", str(np_ranks), *cmd]
    p = subprocess.run(cmd, capture_output=True, text=True, env=ENV, timeout=timeout)
    if expect_ok and p.returncode != 0:
        raise Failure(f"blockwall failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout}\n{p.stderr}")
    return p.returncode, p.stdout, p.stderr


def solve(scene, args=(), np_ranks=1):
    """Run blockwall to a temporary file and return its datasets and attributes."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.h5")
        run(scene, [*args, "-output_file", out], np_ranks)
        return read(out)


def read(path):
    res = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: res.__setitem__(name, obj[()]) if isinstance(obj, h5py.Dataset) else None)
        res["attrs"] = {k: v for k, v in f.attrs.items()}
        res["solver"] = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f["solver"].attrs.items()}
    return res


def rel_err(got, want):
    got, want = np.asarray(got, float), np.asarray(want, float)
    scale = np.max(np.abs(want))
    return np.max(np.abs(got - want)) / (scale if scale > 0 else 1.0)


def expect(cond, message):
    if not cond:
        raise Failure(message)
