"""Running blockwall from Python: one launcher for scripts, examples and tests.

    from blockwall import run, solve
    r = run("examples/demo.yaml", ["-discretization_m", 8], ranks=2)   # r.returncode, r.stdout, r.stderr
    res = solve("examples/demo.yaml", ranks=2)                          # Results of a temporary output

The executable: `exe`, else $BW_EXE, else `blockwall` on $PATH, else the
build tree's build/bin/blockwall beside this package's source checkout.
mpiexec: `mpiexec`, else $BW_MPIEXEC, else `mpiexec` on $PATH; it is used
only for ranks > 1. With Open MPI the launcher passes --oversubscribe
(more ranks than cores, as on a laptop or a 2-core CI machine) and sets
OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1, without which
Open MPI refuses to start as root (containers, CI)."""
from __future__ import annotations

import functools
import os
import shutil
import subprocess
import tempfile
from dataclasses import dataclass

from .results import read

ROOT_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
            "OMPI_MCA_rmaps_base_oversubscribe": "1"}


class RunError(RuntimeError):
    """blockwall exited non-zero; the message holds the command, stdout and stderr."""

    def __init__(self, message, result):
        super().__init__(message)
        self.result = result


@dataclass
class RunResult:
    cmd: list
    returncode: int
    stdout: str
    stderr: str


def environment(base=None):
    """The environment blockwall runs in: `base` (default os.environ) plus Open MPI's root and oversubscribe variables."""
    return dict(os.environ if base is None else base, **ROOT_ENV)


def find_executable(exe=None):
    if exe:
        return os.fspath(exe)
    if os.environ.get("BW_EXE"):
        return os.environ["BW_EXE"]
    found = shutil.which("blockwall")
    if found:
        return found
    checkout = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    return os.path.join(checkout, "build", "bin", "blockwall")


def find_mpiexec(mpiexec=None):
    return os.fspath(mpiexec) if mpiexec else os.environ.get("BW_MPIEXEC") or shutil.which("mpiexec") or "mpiexec"


@functools.lru_cache(maxsize=8)
def is_open_mpi(mpiexec):
    try:
        p = subprocess.run([mpiexec, "--version"], capture_output=True, text=True, timeout=60, env=environment())
    except (OSError, subprocess.SubprocessError):
        return False
    text = p.stdout + p.stderr
    return "Open MPI" in text or "OpenRTE" in text


def command(scene, args=(), ranks=1, exe=None, mpiexec=None):
    """The command line that runs `scene` on `ranks` ranks."""
    cmd = [find_executable(exe), "-scene", os.fspath(scene), *map(str, args)]
    if ranks > 1:
        launcher = find_mpiexec(mpiexec)
        extra = ["--oversubscribe"] if is_open_mpi(launcher) else []
        cmd = [launcher, *extra, "-n", str(int(ranks)), *cmd]
    return cmd


def run(scene, args=(), ranks=1, exe=None, mpiexec=None, check=True, timeout=None, cwd=None, env=None):
    """Run blockwall on `scene` with extra options `args` on `ranks` MPI ranks.
    Returns a RunResult; with check=True a non-zero exit raises RunError."""
    cmd = command(scene, args, ranks, exe, mpiexec)
    p = subprocess.run(cmd, capture_output=True, text=True, env=environment(env), timeout=timeout, cwd=cwd)
    result = RunResult(cmd, p.returncode, p.stdout, p.stderr)
    if check and p.returncode != 0:
        raise RunError(f"blockwall failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout}\n{p.stderr}", result)
    return result


def solve(scene, args=(), ranks=1, output=None, **kwargs):
    """Run blockwall and read its result: to `output` if given (kept), else
    to a temporary file (removed after reading). Returns Results."""
    if output is not None:
        run(scene, [*args, "-output_file", os.fspath(output)], ranks, **kwargs)
        return read(output)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.h5")
        run(scene, [*args, "-output_file", out], ranks, **kwargs)
        return read(out)
