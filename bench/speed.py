#!/usr/bin/env python3
"""Speed and memory of blockwall against what a user would pick instead,
measured alternately in one run on one machine (issue "One set-up, many
solves"). Every figure is the median of --reps runs, with min and max.

  compare  the ~1e5-block running-bond wall (316 x 316, m = 16, stresses
           written), 1 rank: blockwall (solver.schur auto, gamg, cholesky)
           and bench/scipy_reference/wall_scipy.py (numpy/scipy + CHOLMOD),
           run in turn, round after round; whole process wall time
  cases    the same wall with 1, 2 and 20 load cases (one set-up, a solve
           and a file per case): the cost of the second case against the
           first run, and 20 cases against one
  scale    ~1e4, 1e5, 1e6 blocks on 1 and 2 ranks, stresses written: whole
           run time, peak memory per block (blockwall's own, all ranks),
           and the growth exponent of time from 1e4 to 1e6

Writes a dated section into bench/results.md (machine, CPU model, date,
commit) unless --no-write. Never run two benchmarks at once on a 2-core
machine: they would time each other.

usage: bench/speed.py [--parts compare,cases,scale] [--reps 3] [--sizes 1e4,1e5,1e6]
"""
import argparse
import datetime
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "python"))
import blockwall as bw  # noqa: E402
from machine import machine  # noqa: E402

SCENE = os.path.join(ROOT, "examples", "large_wall.yaml")
SCIPY = os.path.join(ROOT, "bench", "scipy_reference", "wall_scipy.py")
WALL_1E5 = (316, 316)


def side(blocks):
    s = max(2, int(round(blocks ** 0.5)))
    return s, s


def timed(cmd, env=None):
    """Runs cmd; returns (seconds, peak RSS of the child in bytes, stdout). Raises on failure."""
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    out, err = p.communicate()
    dt = time.perf_counter() - t0
    if p.returncode:
        raise RuntimeError(f"{' '.join(cmd)} failed ({p.returncode}):\n{out}\n{err}")
    return dt, out


def blockwall_run(tmp, wall, ranks=1, extra=(), stresses=True):
    courses, units = wall
    out = os.path.join(tmp, "bw.h5")
    args = ["-geometry_running_bond_courses", courses, "-geometry_running_bond_units_per_course", units,
            "-output_file", out, "-output_stresses", "true" if stresses else "false", "-output_xdmf", "false",
            "-progress", "false", *extra]
    cmd = bw.command(SCENE, [str(a) for a in args], ranks)
    dt, _ = timed(cmd, bw.environment())
    res = bw.read(out) if not any(str(e).startswith("-cases_") for e in extra) else None
    attrs = dict(res.solver) if res is not None else {}
    if res is not None:
        attrs["blocks"] = res.displacement.shape[0]
    for f in os.listdir(tmp):
        os.remove(os.path.join(tmp, f))
    return dt, attrs


def scipy_run(tmp, wall):
    courses, units = wall
    out = os.path.join(tmp, "scipy.h5")
    cmd = [sys.executable, SCIPY, "--courses", str(courses), "--units", str(units), "--m", "16", "--out", out,
           "--load", "1.0e5,-1.6e6,0"]
    dt, _ = timed(cmd)
    os.remove(out)
    return dt


def stats(xs):
    return statistics.median(xs), min(xs), max(xs)


def fmt(xs, unit="s", digits=2):
    med, lo, hi = stats(xs)
    return f"{med:.{digits}f} {unit} ({lo:.{digits}f}–{hi:.{digits}f})"


def part_compare(reps, log):
    variants = [("scipy + CHOLMOD script", None), ("blockwall, solver.schur auto", []),
                ("blockwall, solver.schur gamg", ["-solver_schur", "gamg"]),
                ("blockwall, solver.schur cholesky", ["-solver_schur", "cholesky"])]
    times = {name: [] for name, _ in variants}
    mem = {name: [] for name, _ in variants}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(reps):
            for name, extra in variants:
                if extra is None:
                    dt = scipy_run(tmp, WALL_1E5)
                else:
                    dt, attrs = blockwall_run(tmp, WALL_1E5, 1, extra)
                    mem[name].append(attrs["memory_peak_bytes"] / attrs["blocks"] if "blocks" in attrs else float("nan"))
                times[name].append(dt)
                log(f"  round {r + 1}: {name}: {dt:.2f} s")
    ref = statistics.median(times[variants[0][0]])
    lines = ["", "### 1e5 blocks (316 x 316, m = 16, stresses written), 1 rank: blockwall against the scipy script",
             "", f"Whole process wall time, {reps} rounds, variants run in turn within each round.", "",
             "| what | time: median (min–max) | script time / this time |", "|---|---|---:|"]
    for name, _ in variants:
        lines.append(f"| {name} | {fmt(times[name])} | {ref / statistics.median(times[name]):.2f}x |")
    return lines, times


def part_cases(reps, log):
    # a scene with N cases given on the command line: each case its own
    # horizontal load on the top beam (one factor, N solves)
    def case_args(n):
        a = []
        for c in range(n):
            a += [f"-cases_c{c:02d}_loads_top_beam", f"{1.0e5 * (1 + 0.1 * c)},-1.6e6,0"]
        return a

    counts = (0, 1, 2, 20)
    times = {n: [] for n in counts}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(reps):
            for n in counts:
                # S^ factored in every run: auto would take GAMG for the one
                # solve of a run without cases, and the comparison would then
                # measure two solvers, not the cost of a case
                dt, _ = blockwall_run(tmp, WALL_1E5, 1, ["-solver_schur", "cholesky", *case_args(n)])
                times[n].append(dt)
                log(f"  round {r + 1}: {n} case(s): {dt:.2f} s")
    one = statistics.median(times[1])
    second = statistics.median(times[2]) - one
    lines = ["", "### Load cases on the 1e5 wall (stresses written, a file per case, solver.schur cholesky), 1 rank", "",
             "| run | time: median (min–max) |", "|---|---|"]
    lines.append(f"| scene without cases | {fmt(times[0])} |")
    for n in counts[1:]:
        lines.append(f"| {n} case{'s' if n > 1 else ''} | {fmt(times[n])} |")
    lines += ["", f"Second case: {second:.2f} s = {100 * second / one:.0f} % of the one-case run "
              f"(target ≤ 15 %); 20 cases / 1 case = {statistics.median(times[20]) / one:.2f}x (target ≤ 4x)."]
    return lines, times


def part_scale(reps, sizes, ranks_list, log):
    rows = ["", "### Scaling, stresses written, solver defaults", "",
            "| blocks | ranks | time: median (min–max) | peak memory per block (median) | Schur solve | steps |",
            "|---:|---:|---|---:|---|---:|"]
    med = {}
    with tempfile.TemporaryDirectory() as tmp:
        for size in sizes:
            wall = side(size)
            for ranks in ranks_list:
                ts, ms, info = [], [], ""
                for r in range(reps):
                    dt, attrs = blockwall_run(tmp, wall, ranks)
                    ts.append(dt)
                    ms.append(attrs["memory_peak_bytes"] / attrs["blocks"])
                    info = (attrs.get("schur_solve", ""), attrs.get("iterations", ""), attrs["blocks"])
                    log(f"  {attrs['blocks']} blocks, {ranks} rank(s), run {r + 1}: {dt:.2f} s, {ms[-1] / 1000:.1f} KB/block")
                med[(size, ranks)] = (statistics.median(ts), info[2])
                rows.append(f"| {info[2]} | {ranks} | {fmt(ts)} | {statistics.median(ms) / 1000:.1f} KB | {info[0]} | {info[1]} |")
    rows.append("")
    lo, hi = min(sizes), max(sizes)
    for ranks in ranks_list:
        if (lo, ranks) in med and (hi, ranks) in med and hi > lo:
            (t0, n0), (t1, n1) = med[(lo, ranks)], med[(hi, ranks)]
            rows.append(f"Growth {n0} → {n1} blocks on {ranks} rank(s): time ∝ N^{math.log(t1 / t0) / math.log(n1 / n0):.2f}.")
    return rows, med


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--parts", default="compare,cases,scale")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--sizes", default="1e4,1e5,1e6")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results.md"))
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no"], capture_output=True, text=True).stdout.strip()
    lines = [f"\n## {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC, commit {commit}{' (with uncommitted changes)' if dirty else ''}, bench/speed.py",
             "", f"Machine: {machine()}"]
    log = lambda s: print(s, flush=True)  # noqa: E731
    parts = args.parts.split(",")
    if "compare" in parts:
        lines += part_compare(args.reps, log)[0]
    if "cases" in parts:
        lines += part_cases(args.reps, log)[0]
    if "scale" in parts:
        sizes = [int(float(s)) for s in args.sizes.split(",")]
        lines += part_scale(args.reps, sizes, [int(r) for r in args.ranks.split(",")], log)[0]
    text = "\n".join(lines) + "\n"
    print(text)
    if not args.no_write:
        with open(args.out, "a") as f:
            f.write(text)


if __name__ == "__main__":
    main()
