#!/usr/bin/env python3
"""Benchmark: running-bond walls of about 1e3, 1e4, 1e5 (and 1e6) blocks,
m = 16, on 1 and 2 ranks, the default path (auto: fieldsplit Schur with the
assembled S^ factored by MUMPS) beside the condensed reference (S^ factored
by MUMPS Cholesky, stresses recovered from the displacements).

Writes bench/results.md (appending a dated section) with the machine, the
date, the commit, and per run: seconds per phase, peak memory per block
(resident, summed over ranks), iterations, residual.

usage: bench/run_bench.py [--sizes 1e3,1e4,1e5] [--ranks 1,2] [--out bench/results.md]
"""
import argparse
import datetime
import os
import resource
import subprocess
import tempfile

import h5py

from machine import machine

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXE = os.path.join(ROOT, "build", "bin", "blockwall")
SCENE = os.path.join(ROOT, "examples", "large_wall.yaml")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
PHASES = ("generate", "partition", "assemble", "setup", "solve", "recover", "write")


def wall_for(blocks):
    """courses x units with courses ~ units and about `blocks` blocks."""
    side = max(2, int(round(blocks ** 0.5)))
    return side, side


def run(blocks, ranks, method, extra=()):
    courses, units = wall_for(blocks)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "b.h5")
        cmd = [EXE, "-scene", SCENE, "-geometry_running_bond_courses", str(courses),
               "-geometry_running_bond_units_per_course", str(units), "-discretization_m", "16",
               "-solver_method", method, "-output_file", out, "-output_stresses", "false",
               "-output_xdmf", "false", "-progress", "false", *extra]
        if ranks > 1:
            cmd = ["mpiexec", "--oversubscribe", "-n", str(ranks), *cmd]
        # a run that needs more than 21 GiB fails with an allocation error
        # instead of waking the kernel's OOM killer
        limit = lambda: resource.setrlimit(resource.RLIMIT_AS, (21 << 30, 21 << 30))
        p = subprocess.run(cmd, capture_output=True, text=True, env=ENV, preexec_fn=limit)
        if p.returncode:
            return {"error": p.stderr.strip().splitlines()[-1] if p.stderr.strip() else f"exit {p.returncode}"}
        with h5py.File(out) as f:
            s = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f["solver"].attrs.items()}
            s["blocks"] = len(f["blocks/offsets"]) - 1
        return s


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", default="1e3,1e4,1e5")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results.md"))
    ap.add_argument("--methods", default="auto,condensed")
    args = ap.parse_args()
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    lines = [f"\n## {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC, commit {commit}\n",
             f"Machine: {machine()}\n",
             "| blocks | ranks | method | used | it | residual | " + " | ".join(PHASES) + " | total [s] | peak B/block |",
             "|---:|---:|---|---|---:|---:|" + "---:|" * len(PHASES) + "---:|---:|"]
    for size in (int(float(x)) for x in args.sizes.split(",")):
        for ranks in (int(x) for x in args.ranks.split(",")):
            for method in args.methods.split(","):
                s = run(size, ranks, method)
                if "error" in s:
                    lines.append(f"| ~{size:.0e} | {ranks} | {method} | failed: {s['error']} |")
                else:
                    per = s["memory_peak_bytes"] / s["blocks"]
                    lines.append(f"| {s['blocks']} | {ranks} | {method} | {s['method_used']} | {s['iterations']} | "
                                 f"{s['residual']:.1e} | " + " | ".join(f"{s['seconds_' + p]:.2f}" for p in PHASES) +
                                 f" | {s['seconds_total']:.2f} | {per:.0f} |")
                print(lines[-1], flush=True)
    with open(args.out, "a") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
