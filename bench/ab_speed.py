#!/usr/bin/env python3
"""Benchmark: two builds of blockwall on the same scenes, alternated run by
run so that both see the same machine (issue 29, "2D does not get slower":
the distributed model against the replicated one it replaced).

Per case and build: whole-process seconds (scene to HDF5, mpiexec included
for more than one rank) and the peak resident memory summed over the ranks
(GNU time around each rank), median (min-max) of --reps; the answers of the
two builds compared (blocks/displacement, relative to the largest).

    python3 bench/ab_speed.py --old OLD/bin/blockwall [--new build/bin/blockwall] [--reps 3]
        [--cases 2d:316:1:stresses,2d:1000:1,2d:1000:2]

A case is DIM:UNITS:RANKS[:stresses] (a square running-bond wall of UNITS
courses of UNITS units: examples/large_wall.yaml in 2D, bench/large_wall3d.yaml
in 3D; stresses not written unless said). Appends a dated section to
bench/results.md (or --out). Never run two benchmarks at once on a 2-core machine.
"""
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

import rank_peaks
from machine import machine

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = {"2d": os.path.join(ROOT, "examples", "large_wall.yaml"), "3d": os.path.join(ROOT, "bench", "large_wall3d.yaml")}
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1", OMPI_MCA_mpi_yield_when_idle="1")


def once(exe, dim, units, ranks, stresses, out):
    key = "-geometry_running_bond"
    with tempfile.TemporaryDirectory() as tmp:
        cmd = (["mpiexec", "-n", str(ranks)] if ranks > 1 else []) + rank_peaks.wrap(tmp) + [
            exe, "-scene", SCENES[dim], f"{key}_courses", str(units), f"{key}_units_per_course", str(units),
            "-output_stresses", "true" if stresses else "false", "-output_xdmf", "false", "-output_file", out]
        t0 = time.perf_counter()
        p = subprocess.run(cmd, capture_output=True, text=True, env=ENV)
        dt = time.perf_counter() - t0
        if p.returncode:
            sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
        mem = sum(rank_peaks.read(tmp, ranks))
    return dt, mem


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--old", required=True)
    ap.add_argument("--new", default=os.path.join(ROOT, "build", "bin", "blockwall"))
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--cases", default="2d:316:1:stresses,2d:1000:1,2d:1000:2")
    ap.add_argument("--label-old", default="old")
    ap.add_argument("--label-new", default="new")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results.md"))
    a = ap.parse_args()
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    lines = [f"\n## Two builds alternated (bench/ab_speed.py), {datetime.datetime.utcnow():%Y-%m-%d %H:%M} UTC, {commit}\n",
             f"{machine()}\n",
             f"{a.label_old}: `{a.old}`; {a.label_new}: `{a.new}`. Whole-process seconds and peak memory summed over "
             f"the ranks (GNU time), median (min-max) of {a.reps}, the two builds alternated run by run.\n",
             f"| case | blocks | {a.label_old} [s] | {a.label_new} [s] | new / old | {a.label_old} [KB/block] | "
             f"{a.label_new} [KB/block] | displacements apart |", "|---|---|---|---|---|---|---|---|"]
    with tempfile.TemporaryDirectory() as tmp:
        for case in a.cases.split(","):
            f = case.split(":")
            dim, units, ranks, stresses = f[0], int(f[1]), int(f[2]), len(f) > 3 and f[3] == "stresses"
            res = {"old": [], "new": []}
            outs = {k: os.path.join(tmp, f"{k}.h5") for k in res}
            for _ in range(a.reps):
                for k, exe in (("old", a.old), ("new", a.new)):
                    res[k].append(once(exe, dim, units, ranks, stresses, outs[k]))
            with h5py.File(outs["old"]) as fo, h5py.File(outs["new"]) as fn:
                uo, un = fo["blocks/displacement"][()], fn["blocks/displacement"][()]
            apart = float(np.max(np.abs(uo - un)) / np.max(np.abs(uo)))
            nb = len(uo)

            def med(v):
                return f"{statistics.median(v):.2f} ({min(v):.2f}-{max(v):.2f})"
            to, tn = [r[0] for r in res["old"]], [r[0] for r in res["new"]]
            mo, mn = statistics.median(r[1] for r in res["old"]), statistics.median(r[1] for r in res["new"])
            row = (f"| {dim} {units}^2, {ranks} rank{'s' if ranks > 1 else ''}, stresses {'written' if stresses else 'not written'} | "
                   f"{nb} | {med(to)} | {med(tn)} | {statistics.median(tn) / statistics.median(to):.2f} | "
                   f"{mo / nb / 1024:.1f} | {mn / nb / 1024:.1f} | {apart:.1e} |")
            print(row, flush=True)
            lines.append(row)
    with open(a.out, "a") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
