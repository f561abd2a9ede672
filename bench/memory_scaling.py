#!/usr/bin/env python3
"""Benchmark (issue 29, "Memory that divides"): each rank's peak resident
memory, measured from outside the process (GNU time around every rank), for
one wall on 2 and on 8 ranks (oversubscribed here), and the baseline M0 of a
rank running the paper's two-block case on as many ranks.

Targets: sum over the ranks of (peak - M0) on 8 ranks at most 1.15 x that on
2 ranks, and no rank above 1.3 x the mean (of peak - M0).

Scenes, stresses not written:
  2d   examples/large_wall.yaml at 700 x 700 units (4.9e5 blocks)
  3d   bench/large_wall3d.yaml at 300 x 300 units (9.1e4 blocks)

Appends a dated section to bench/results.md (or --out) with the machine line.

usage: bench/memory_scaling.py [--parts 2d,3d] [--ranks 2,8] [--size 700] [--size3d 300] [--args '...'] [--out FILE]
"""
import argparse
import datetime
import os
import statistics
import subprocess
import sys
import tempfile

import rank_peaks
from machine import machine

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXE = os.path.join(ROOT, "build", "bin", "blockwall")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1", OMPI_MCA_mpi_yield_when_idle="1")
SCENES = {"2d": os.path.join(ROOT, "examples", "large_wall.yaml"), "3d": os.path.join(ROOT, "bench", "large_wall3d.yaml"),
          "two": os.path.join(ROOT, "tests", "paper", "two_blocks.yaml")}


def per_rank_peaks(scene, ranks, args, timeout=3600):
    """Each rank's peak RSS [bytes], from GNU time around it; and the run's summary."""
    with tempfile.TemporaryDirectory() as tmp:
        cmd = ["mpiexec", "-n", str(ranks), *rank_peaks.wrap(tmp), EXE, "-scene", scene, "-output_file", os.path.join(tmp, "o.h5"),
               "-output_xdmf", "false", *args]
        p = subprocess.run(cmd, capture_output=True, text=True, env=ENV, timeout=timeout)
        if p.returncode:
            sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
        return rank_peaks.read(tmp, ranks), p.stdout


def part(name, size, ranks, extra=()):
    scene = SCENES[name]
    key = "geometry_running_bond"
    args = [f"-{key}_courses", str(size), f"-{key}_units_per_course", str(size), "-output_stresses", "false", *extra]
    rows = []
    for n in ranks:
        m0 = statistics.mean(per_rank_peaks(SCENES["two"], n, [])[0])
        peaks, out = per_rank_peaks(scene, n, args)
        blocks = int(out.split("blocks ")[1].split(",")[0])
        extra = [p - m0 for p in peaks]
        rows.append((n, blocks, m0, peaks, sum(extra), max(extra) / statistics.mean(extra)))
        print(f"{name} {size}x{size}, {n} ranks: M0 {m0 / 2**20:.1f} MB, peaks {[round(p / 2**20) for p in peaks]} MB, "
              f"sum(peak - M0) {sum(extra) / 2**30:.3f} GB ({sum(extra) / blocks / 1024:.2f} KB per block), "
              f"largest/mean {rows[-1][5]:.3f}", flush=True)
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--parts", default="2d,3d")
    ap.add_argument("--ranks", default="2,8")
    ap.add_argument("--size", type=int, default=700)
    ap.add_argument("--size3d", type=int, default=300)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results.md"))
    ap.add_argument("--args", default="", help="more options for blockwall, e.g. '-solver_schur gamg'")
    a = ap.parse_args()
    ranks = [int(r) for r in a.ranks.split(",")]
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    lines = [f"\n## Memory that divides (bench/memory_scaling.py), {datetime.datetime.utcnow():%Y-%m-%d %H:%M} UTC, {commit}\n",
             f"{machine()}\n",
             "Each rank's peak resident memory from GNU time around it; M0 the mean peak of a rank of the two-block "
             "case on as many ranks; targets: sum(peak - M0) on the most ranks <= 1.15 x on the fewest, largest "
             "rank <= 1.3 x the mean." + (f" Options: `{a.args}`." if a.args else "") + "\n",
             "| wall | ranks | blocks | M0 [MB] | peaks [MB] | sum(peak - M0) [GB] | KB per block | largest / mean |",
             "|---|---|---|---|---|---|---|---|"]
    for name in a.parts.split(","):
        rows = part(name, a.size if name == "2d" else a.size3d, ranks, a.args.split())
        for n, blocks, m0, peaks, s, imb in rows:
            lines.append(f"| {name} {a.size if name == '2d' else a.size3d}^2 | {n} | {blocks} | {m0 / 2**20:.1f} | "
                         f"{', '.join(str(round(p / 2**20)) for p in peaks)} | {s / 2**30:.3f} | {s / blocks / 1024:.2f} | {imb:.3f} |")
        ratio = rows[-1][4] / rows[0][4]
        worst = max(r[5] for r in rows)
        lines.append(f"\n{name}: sum ratio {rows[-1][0]} / {rows[0][0]} ranks {ratio:.3f} (target <= 1.15: "
                     f"{'met' if ratio <= 1.15 else 'missed'}); largest rank / mean at most {worst:.3f} "
                     f"(target <= 1.3: {'met' if worst <= 1.3 else 'missed'})\n")
        print(lines[-1])
    with open(a.out, "a") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
