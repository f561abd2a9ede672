#!/usr/bin/env python3
"""The million-block 3D wall (issue 29, "A million 3D blocks on this
machine"): bench/large_wall3d.yaml at N x N units (m = 8, m_b = 4),
stresses not written, on R ranks; scene to HDF5 in seconds (the whole
mpiexec, from outside), each rank's peak resident memory (GNU time around
every rank, bench/rank_peaks.py) summed and per block, the run's own check
(/solver accuracy_met, residual) and where the time went (/solver phases,
Schur path, iterations). Targets: <= 120 s, <= 20 KB per block summed over
the ranks, accuracy_met = 1.

    python3 bench/million3d.py [--exe build/bin/blockwall] [--n 1000] [--ranks 2] [--reps 1] [--args '...'] [--no-write]

Appends a dated section to bench/results.md. It takes the whole machine
(16 GB and both cores at n = 1000): never beside another benchmark."""
import argparse
import datetime
import os
import statistics
import subprocess
import sys
import tempfile
import time

import h5py

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import rank_peaks  # noqa: E402
from machine import machine  # noqa: E402

SCENE = os.path.join(HERE, "large_wall3d.yaml")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
PHASES = ("generate", "partition", "assemble", "setup", "solve", "recover", "write")


def one_run(exe, n, ranks, extra):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.h5")
        cmd = ["mpiexec", "--oversubscribe", "-n", str(ranks), *rank_peaks.wrap(tmp), exe, "-scene", SCENE,
               "-geometry_running_bond_courses", str(n), "-geometry_running_bond_units_per_course", str(n),
               "-output_stresses", "false", "-output_xdmf", "false", "-output_file", out, *extra]
        t0 = time.perf_counter()
        p = subprocess.run(cmd, capture_output=True, text=True, env=ENV)
        seconds = time.perf_counter() - t0
        if p.returncode != 0:
            return {"failed": f"exit {p.returncode}: {(p.stderr or p.stdout).strip()[-400:]}", "seconds": seconds}
        peaks = rank_peaks.read(tmp, ranks)
        with h5py.File(out, "r") as f:
            a = dict(f["solver"].attrs)
            nb = f["blocks/displacement"].shape[0]
    return {"seconds": seconds, "peaks": peaks, "blocks": nb, "attrs": a}


def fmt(xs):
    return f"{statistics.median(xs):.1f} ({min(xs):.1f}–{max(xs):.1f})" if len(xs) > 1 else f"{xs[0]:.1f} (1 run)"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "bin", "blockwall"))
    ap.add_argument("--n", type=int, default=1000)
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--reps", type=int, default=1)
    ap.add_argument("--args", default="", help="more options for blockwall")
    ap.add_argument("--no-write", action="store_true")
    o = ap.parse_args()
    runs = [one_run(o.exe, o.n, o.ranks, o.args.split()) for _ in range(o.reps)]
    ok = [r for r in runs if "failed" not in r]
    lines = [f"## 3D wall of {o.n} x {o.n} units on {o.ranks} ranks (issue 29), "
             f"{datetime.datetime.utcnow():%Y-%m-%d %H:%M} UTC", "", machine(), "",
             f"`bench/million3d.py --n {o.n} --ranks {o.ranks}{' --args ' + repr(o.args) if o.args else ''}`: "
             "bench/large_wall3d.yaml (m = 8, m_b = 4), stresses not written; seconds of the whole mpiexec, "
             "each rank's peak from GNU time.", ""]
    for r in runs:
        if "failed" in r:
            lines.append(f"- a run failed after {r['seconds']:.1f} s: {r['failed']}")
    if ok:
        nb = ok[0]["blocks"]
        a = ok[0]["attrs"]
        kb = [sum(r["peaks"]) / r["blocks"] / 1024 for r in ok]
        lines.append(f"- {nb} blocks: {fmt([r['seconds'] for r in ok])} s scene to HDF5 (target 120 s); "
                     f"{fmt(kb)} KB per block summed over the ranks (target 20); "
                     f"largest rank {max(max(r['peaks']) for r in ok) / 1e9:.2f} GB")
        lines.append("- phases [s] (first run): " + ", ".join(f"{ph} {float(a.get('seconds_' + ph, float('nan'))):.1f}" for ph in PHASES))
        lines.append(f"- Schur solve {a['schur_solve'].decode() if 'schur_solve' in a else '?'}, outer iterations {a.get('iterations', '?')}, "
                     f"true residual {float(a.get('residual', float('nan'))):.2e}, accuracy_met {int(a.get('accuracy_met', -1))}, "
                     f"edge cut {a.get('partition_edge_cut', '?')}, imbalance {float(a.get('partition_imbalance', float('nan'))):.3f}")
    text = "\n".join(lines) + "\n"
    print(text)
    if not o.no_write:
        with open(os.path.join(HERE, "results.md"), "a") as f:
            f.write("\n" + text)


if __name__ == "__main__":
    main()
