#!/usr/bin/env python3
"""2D speed before and after the dimension-general code (issue "Walls in
three dimensions": "a 2D run must not get slower"), measured alternately in
one run: the same running-bond wall (examples/large_wall.yaml, m = 16, no
stress dataset) by two builds, round after round, so that both see the same
machine load. Figures: medians of --reps with min and max, per phase
(/solver attributes) and whole process.

usage: bench/dimension_general.py OLD_EXE NEW_EXE [--reps 3] [--cases 1e5:1,1e6:2]
Writes a dated section into bench/results.md unless --no-write. Never run
two benchmarks at once on a 2-core machine."""
import argparse
import datetime
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "python"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import h5py  # noqa: E402
from machine import machine  # noqa: E402

SCENE = os.path.join(ROOT, "examples", "large_wall.yaml")
PHASES = ["assemble", "setup", "solve", "recover", "total"]


def run(exe, blocks, ranks, tmp):
    s = max(2, int(round(blocks ** 0.5)))
    out = os.path.join(tmp, "r.h5")
    cmd = [exe, "-scene", SCENE, "-geometry_running_bond_courses", str(s), "-geometry_running_bond_units_per_course", str(s),
           "-output_file", out, "-output_xdmf", "false", "-output_stresses", "false"]
    if ranks > 1:
        cmd = ["mpiexec", "--oversubscribe", "-n", str(ranks), *cmd]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    if p.returncode:
        raise RuntimeError(f"{' '.join(cmd)}: exit {p.returncode}\n{p.stderr}")
    with h5py.File(out) as f:
        a = dict(f["solver"].attrs)
    row = {ph: float(a[f"seconds_{ph}"]) for ph in PHASES if ph != "total"}
    row["total"] = wall
    return row


def fmt(xs):
    return f"{statistics.median(xs):.3f} ({min(xs):.3f}–{max(xs):.3f})"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--cases", default="1e5:1,1e6:2")
    ap.add_argument("--label-old", default="before")
    ap.add_argument("--label-new", default="after")
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    head = machine()
    lines = []
    with tempfile.TemporaryDirectory() as tmp:
        for case in args.cases.split(","):
            blocks, ranks = float(case.split(":")[0]), int(case.split(":")[1])
            got = {"old": [], "new": []}
            for _ in range(args.reps):
                for which in ("old", "new"):
                    got[which].append(run(getattr(args, which), blocks, ranks, tmp))
            for which, label in (("old", args.label_old), ("new", args.label_new)):
                cells = [fmt([r[ph] for r in got[which]]) for ph in PHASES]
                lines.append(f"| {blocks:.0e} blocks, {ranks} rank{'s' if ranks > 1 else ''} | {label} | " + " | ".join(cells) + " |")
                print(lines[-1], flush=True)
    text = [f"\n## {datetime.datetime.utcnow():%Y-%m-%d %H:%M} UTC: 2D before and after the dimension-general code",
            "", head, "",
            f"Interleaved runs ({args.reps} each) of examples/large_wall.yaml, m = 16, no stresses written; seconds, median (min–max).",
            "", "| wall | build | assemble | setup | solve | recover | whole run |", "|---|---|---|---|---|---|---|", *lines, ""]
    if not args.no_write:
        with open(os.path.join(ROOT, "bench", "results.md"), "a") as f:
            f.write("\n".join(text))
    print("\n".join(text))


if __name__ == "__main__":
    main()
