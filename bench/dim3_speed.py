#!/usr/bin/env python3
"""3D speed and memory (issue "Walls in three dimensions"): blockwall on a
3D running-bond wall (bench/large_wall3d.yaml: m = 8, m_b = 4, stresses
written) against bench/scipy_reference/wall3d_scipy.py (numpy/scipy +
CHOLMOD on the condensed stiffness, the same model, the same outputs),
alternated in one run so that both see the same machine; and blockwall's
time against the number of blocks on 2 ranks.

    python3 bench/dim3_speed.py [--exe build/bin/blockwall] [--reps 3] [--sizes 100,173,316] [--no-write]

Figures: whole-process seconds and peak resident memory (/usr/bin/time),
median (min-max) of --reps; how far the two answers are apart
(displacements, rotations times the wall's size, relative to the largest). Appends a dated section to
bench/results.md. Never run two benchmarks at once on a 2-core machine."""
import argparse
import datetime
import os
import statistics
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from machine import machine  # noqa: E402

SCENE = os.path.join(HERE, "large_wall3d.yaml")
SCIPY = os.path.join(HERE, "scipy_reference", "wall3d_scipy.py")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def timed(cmd):
    """Seconds and peak RSS [bytes] of one process (of its largest rank under mpiexec)."""
    t0 = time.perf_counter()
    p = subprocess.run(["/usr/bin/time", "-f", "MAXRSS %M", *cmd], capture_output=True, text=True, env=ENV)
    wall = time.perf_counter() - t0
    if p.returncode:
        raise RuntimeError(f"{' '.join(cmd)}: exit {p.returncode}\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    rss = max(int(line.split()[1]) for line in p.stderr.splitlines() if line.startswith("MAXRSS")) * 1024
    return wall, rss, p.stdout


def blockwall(exe, n, out, ranks=1):
    cmd = [exe, "-scene", SCENE, "-geometry_running_bond_courses", str(n), "-geometry_running_bond_units_per_course", str(n),
           "-output_file", out]
    if ranks > 1:
        cmd = ["mpiexec", "--oversubscribe", "-n", str(ranks), *cmd]
    wall, rss, _ = timed(cmd)
    with h5py.File(out) as f:
        peak = float(f["solver"].attrs["memory_peak_bytes"])
        nb = f["blocks/displacement"].shape[0]
    return wall, max(rss, peak if ranks == 1 else 0), nb, peak


def scipy_ref(n, out):
    wall, rss, _ = timed([sys.executable, SCIPY, "--courses", str(n), "--units", str(n), "--out", out])
    return wall, rss


def fmt(xs, scale=1.0, digits=2):
    xs = [x * scale for x in xs]
    return f"{statistics.median(xs):.{digits}f} ({min(xs):.{digits}f}–{max(xs):.{digits}f})"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "bin", "blockwall"))
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--n", type=int, default=316, help="courses = units per course of the comparison wall")
    ap.add_argument("--sizes", default="100,173,316", help="courses = units for the growth on 2 ranks")
    ap.add_argument("--no-write", action="store_true")
    a = ap.parse_args()
    lines = []
    with tempfile.TemporaryDirectory() as tmp:
        bw_out, py_out = os.path.join(tmp, "bw.h5"), os.path.join(tmp, "py.h5")
        bw_t, bw_m, py_t, py_m = [], [], [], []
        for r in range(a.reps):
            t, m, nb, _ = blockwall(a.exe, a.n, bw_out)
            bw_t.append(t)
            bw_m.append(m / nb)
            t, m = scipy_ref(a.n, py_out)
            py_t.append(t)
            py_m.append(m / nb)
            print(f"rep {r + 1}: blockwall {bw_t[-1]:.2f} s {bw_m[-1] / 1024:.1f} KB/block, scipy+CHOLMOD {py_t[-1]:.2f} s {py_m[-1] / 1024:.1f} KB/block", flush=True)
        with h5py.File(bw_out) as f, h5py.File(py_out) as g:
            x, y = g["blocks/displacement"][()], f["blocks/displacement"][()]
            L = float(np.ptp(f["blocks/vertices"][()], axis=0).max())
            w = np.array([1, 1, 1, L, L, L])  # rotations times the wall's size
            agree = float(np.max(np.abs(x - y) * w) / np.max(np.abs(y) * w))
            acc = dict(f["solver"].attrs)
        lines += [f"3D running-bond wall {a.n} x {a.n} ({nb} blocks), m = 8, m_b = 4, stresses written, 1 rank; "
                  f"{a.reps} alternated runs each, whole process, median (min–max):", "",
                  "| program | seconds | peak memory per block [KB] |", "|---|---|---|",
                  f"| blockwall (schur {acc.get('schur_solve', b'').decode() if isinstance(acc.get('schur_solve'), bytes) else acc.get('schur_solve')}) | {fmt(bw_t)} | {fmt(bw_m, 1 / 1024, 1)} |",
                  f"| numpy/scipy + CHOLMOD (bench/scipy_reference/wall3d_scipy.py) | {fmt(py_t)} | {fmt(py_m, 1 / 1024, 1)} |", "",
                  f"Speed-up {statistics.median(py_t) / statistics.median(bw_t):.2f} (target >= 2), blockwall {statistics.median(bw_m) / 1024:.1f} KB per block (target <= 25). "
                  f"The displacements agree to {agree:.1e} (rotations times the wall's size, relative to the largest); blockwall's estimated displacement "
                  f"error {float(acc['forward_error_estimate']):.1e}, condition estimate {float(acc['condition_estimate']):.1e}.", ""]
        growth = []
        for n in [int(s) for s in a.sizes.split(",")]:
            ts, nbs = [], 0
            for _ in range(a.reps):
                t, _, nbs, peak = blockwall(a.exe, n, bw_out, ranks=2)
                ts.append(t)
            growth.append((nbs, statistics.median(ts), min(ts), max(ts), peak / nbs))
            print(f"2 ranks, {nbs} blocks: {statistics.median(ts):.2f} s", flush=True)
        lines += ["blockwall on 2 ranks against the number of blocks (whole process, median (min–max)):", "",
                  "| blocks | seconds | peak memory per block over all ranks [KB] |", "|---|---|---|"]
        for nb, med, lo, hi, mem in growth:
            lines.append(f"| {nb} | {med:.2f} ({lo:.2f}–{hi:.2f}) | {mem / 1024:.1f} |")
        if len(growth) > 1:
            p = np.polyfit(np.log([g[0] for g in growth]), np.log([g[1] for g in growth]), 1)[0]
            lines += ["", f"Time grows as N^{p:.2f} from {growth[0][0]} to {growth[-1][0]} blocks (target: no worse than N^1.15 to 1e6)."]
    text = "\n".join(lines)
    print(text)
    if not a.no_write:
        m = machine()
        head = f"\n## {datetime.datetime.utcnow():%Y-%m-%d %H:%M} UTC: 3D walls against numpy/scipy + CHOLMOD\n\n{m}\n\n"
        with open(os.path.join(HERE, "results.md"), "a") as f:
            f.write(head + text + "\n")


if __name__ == "__main__":
    main()
