#!/usr/bin/env python3
"""Benchmark (issue 29, "What a cluster user needs to know"): weak scaling,
the same blocks per rank on 1, 2, 4, 8 and 16 ranks (oversubscribed on this
2-core machine), for a 2D and a 3D running-bond wall, stresses not written.

Per run: the solver's iterations (/solver iterations: the outer Krylov
iterations; and the Schur solve's CG iterations summed over the run, from
-schur_ksp_converged_reason, when S^ is solved by CG + GAMG), each rank's
peak resident memory measured from outside (GNU time around each rank),
and the bytes each rank sent as PETSc counts them (-log_view, "MPI Msg
Len": the sum over the ranks / ranks, and the largest rank's; blockwall's
own all-to-all moves of the
partition are not in PETSc's count). Time only where the ranks do not
outnumber the cores.

The Schur complement is solved by CG + GAMG (solver.schur: gamg), the path
that scales (`auto` factors S^ below 2e5 blocks in 3D, 5e4 in 2D).

Appends a dated section to bench/results.md (or --out).

usage: bench/weak_scaling.py [--ranks 1,2,4,8,16] [--per-rank-2d 20000] [--per-rank-3d 4000] [--out FILE]
"""
import argparse
import datetime
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile

import h5py

import rank_peaks
from machine import machine

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXE = os.path.join(ROOT, "build", "bin", "blockwall")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1", OMPI_MCA_mpi_yield_when_idle="1")
SCENES = {"2d": os.path.join(ROOT, "examples", "large_wall.yaml"), "3d": os.path.join(ROOT, "bench", "large_wall3d.yaml")}


def run(name, units, ranks, timeout=3600):
    key = "-geometry_running_bond"
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "o.h5")
        cmd = ["mpiexec", "-n", str(ranks), *rank_peaks.wrap(tmp), EXE, "-scene", SCENES[name], f"{key}_courses", str(units),
               f"{key}_units_per_course", str(units), "-output_stresses", "false", "-output_xdmf", "false",
               "-output_file", out, "-solver_schur", "gamg", "-schur_ksp_converged_reason", "-log_view"]
        p = subprocess.run(cmd, capture_output=True, text=True, env=ENV, timeout=timeout)
        if p.returncode:
            sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout[-3000:]}\n{p.stderr[-2000:]}")
        peaks = rank_peaks.read(tmp, ranks)
        with h5py.File(out, "r") as f:
            sv = dict(f["solver"].attrs)
            blocks = f["blocks/displacement"].shape[0]
    cg = [int(m) for m in re.findall(r"Linear schur_ solve converged due to \w+ iterations (\d+)", p.stdout)]
    m = re.search(r"MPI Msg Len \(bytes\):\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)", p.stdout)
    # PETSc's columns: the largest rank's bytes, max/min, the mean message's
    # length, the sum over the ranks; a rank's bytes are the sum / ranks
    sent = (float(m.group(4)) / ranks, float(m.group(1))) if m else (float("nan"), float("nan"))
    return dict(blocks=blocks, peaks=peaks, outer=int(sv["iterations"]), cg=cg, sent=sent,
                seconds=float(sv["seconds_total"]), met=int(sv["accuracy_met"]), cut=int(sv["partition_edge_cut"]))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ranks", default="1,2,4,8,16")
    ap.add_argument("--per-rank-2d", type=int, default=20000)
    ap.add_argument("--per-rank-3d", type=int, default=4000)
    ap.add_argument("--parts", default="2d,3d")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results.md"))
    a = ap.parse_args()
    ranks = [int(r) for r in a.ranks.split(",")]
    cores = os.cpu_count()
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    lines = [f"\n## Weak scaling (bench/weak_scaling.py), {datetime.datetime.utcnow():%Y-%m-%d %H:%M} UTC, {commit}\n",
             f"{machine()}\n",
             "The same blocks per rank (square running-bond walls, m = 16 in 2D, m = 8, m_b = 4 in 3D; stresses not "
             "written), S^ by CG + GAMG (`-solver_schur gamg`). CG: the Schur solve's iterations, each solve's count "
             "(one per outer iteration). Memory: each rank's peak from GNU time around it. Sent: PETSc's 'MPI Msg Len' "
             "(-log_view): the bytes of PETSc's messages over all ranks / ranks, and the largest rank's (blockwall's own all-to-all "
             "moves of the partition are not counted). Time only where ranks <= cores; 1 run each.\n",
             "| wall | ranks | blocks | blocks per rank | outer iterations | CG iterations per Schur solve | peak per rank [MB] (mean, max) "
             "| sent per rank [MB] (mean, max) | edge cut | accuracy_met | time [s] |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for name in a.parts.split(","):
        per = a.per_rank_2d if name == "2d" else a.per_rank_3d
        for n in ranks:
            units = int(round(math.sqrt(per * n)))
            r = run(name, units, n)
            mean, mx = statistics.mean(r["peaks"]) / 2**20, max(r["peaks"]) / 2**20
            cg = f"{min(r['cg'])}-{max(r['cg'])}" if r["cg"] else "-"
            t = f"{r['seconds']:.1f}" if n <= cores else "(oversubscribed)"
            row = (f"| {name} {units}^2 | {n} | {r['blocks']} | {r['blocks'] / n:.0f} | {r['outer']} | {cg} | {mean:.0f}, {mx:.0f} | "
                   f"{r['sent'][0] / 2**20:.2f}, {r['sent'][1] / 2**20:.2f} | {r['cut']} | {r['met']} | {t} |")
            print(row, flush=True)
            lines.append(row)
    with open(a.out, "a") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
