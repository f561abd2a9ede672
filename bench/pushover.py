#!/usr/bin/env python3
"""Pushover benchmarks (issue "Walls to collapse"), medians of --reps runs
with min and max, written as a dated section into bench/results.md:

  j4d    the TU Eindhoven wall J4D (examples/j4d.yaml: 4.5 units per course,
         split units, 0.30 MPa held, top beam kept horizontal), 100
         displacement steps to 4 mm, 1 rank (target <= 10 s)
  large  a running-bond wall of ~1e4 blocks with the same joints, driven
         under dissipation control (displacement control cannot follow its
         snap-back: it stopped 2 steps past the peak) to well past its peak,
         2 ranks (target: 50 steps past the peak, to below 0.8 of it, in
         <= 120 s); per run: steps, steps past the peak, the last lambda
         over the peak, Newton iterations per step, linear solves per step,
         set-ups (factorisations) per run

  j4d_cap  examples/j4d_cap.yaml: J4D with the compressive cap, under
         dissipation control past its peaks to 4 mm, 1 rank (target <= 5 s)

usage: bench/pushover.py [--parts j4d,j4d_cap,large] [--reps 3] [--scheme auto|newton|implex]
                         [--exe build/bin/blockwall] [--old OTHER/bin/blockwall]
(--scheme: analysis.pushover.scheme for every part; default: the scene's;
--old: a second build, its runs alternated with --exe's, a table each)
"""
import argparse
import os
import statistics
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "python"))
sys.path.insert(0, os.path.join(ROOT, "bench"))
import blockwall as bw  # noqa: E402
from machine import append_section, machine, section_head  # noqa: E402

LARGE = """title: 1e4-block running-bond wall pushover
geometry:
  generator: running_bond
  depth: 0.1
  running_bond: {{courses: {courses}, units_per_course: {units}, unit_length: 0.21, unit_height: 0.052, foundation: true, top_beam: true}}
joints: {{law: dry, kn: 82.0e9, kt: 36.0e9, thickness: 0.01, strength: {{tension: 0.25e6, cohesion: 0.35e6, friction: 0.75, dilatancy: 0, tension_energy: 18, shear_energy: 125}}}}
discretization: {{m: 8}}
supports: {{foundation: {{u1: 0, u2: 0, w: 0}}, top_beam: {{w: 0}}}}
loads: {{top_beam: [0, {N}, 0]}}
analysis:
  type: pushover
  pushover: {{loads: {{top_beam: [1, 0, 0]}}, control: {control}, monitor: {{set: top_beam, dof: u1}}, target: {target}, steps: {steps}}}
output: {{file: out.h5, stresses: false, xdmf: false}}
"""


def one(scene, ranks, args=(), exe=None):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.h5")
        t0 = time.perf_counter()
        bw.run(scene, ["-output_file", out, "-progress", "false", *args], ranks, exe=exe)
        dt = time.perf_counter() - t0
        res = bw.read(out)
    s = res.solver
    h = res.history
    peak = int(h["load_factor"].argmax())
    n = len(h["load_factor"])
    stop = s["stop_reason"]
    return {"time": dt, "steps": n - 1, "past_peak": n - 1 - peak, "peak": h["load_factor"].max(),
            "last_over_peak": h["load_factor"][-1] / h["load_factor"].max(),
            "peak_monitor": h["monitor"][peak], "its": s["newton_iterations"], "solves": s["linear_solves"],
            "setups": s.get("setups", -1), "stop": stop, "blocks": res.displacement.shape[0]}


def fmt(xs):
    return f"{statistics.median(xs):.2f} s ({min(xs):.2f}–{max(xs):.2f})"


def table(title, runs):
    r = runs[-1]
    lines = ["", f"### {title}", "",
             f"Whole run (median of {len(runs)}, min–max): {fmt([x['time'] for x in runs])}; {r['blocks']} blocks.", "",
             "| steps | past the peak | peak load [N] | at monitor [m] | last / peak | Newton iterations per step | linear solves per step | set-ups (factorisations) | stop |",
             "|---:|---:|---:|---:|---:|---:|---:|---:|---|",
             f"| {r['steps']} | {r['past_peak']} | {r['peak']:.1f} | {r['peak_monitor']:.3e} | {r['last_over_peak']:.3f} | {r['its'] / max(1, r['steps']):.1f} | "
             f"{r['solves'] / max(1, r['steps']):.1f} | {r['setups']} | {r['stop'][:90]} |"]
    return lines


def alternated(builds, reps, run):
    """reps runs of each build, alternated run by run (both see the same
    machine); [(label, runs)] in the order of builds"""
    runs = [[] for _ in builds]
    for _ in range(reps):
        for i, (_, exe) in enumerate(builds):
            runs[i].append(run(exe))
    return [(label, rs) for (label, _), rs in zip(builds, runs)]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--parts", default="j4d,large")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results.md"))
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--scheme", default=None)
    ap.add_argument("--exe", default=None, help="the build measured (default: $BW_EXE or build/bin/blockwall)")
    ap.add_argument("--old", default=None, help="a second build, alternated run by run with --exe's")
    a = ap.parse_args()
    builds = [("", a.exe)] + ([(f" (old build: {a.old})", a.old)] if a.old else [])
    extra = ["-analysis_pushover_scheme", a.scheme] if a.scheme else []
    lines = [section_head("bench/pushover.py" + (f" --scheme {a.scheme}" if a.scheme else "")), "",
             f"Machine: {machine()}"]
    parts = set(a.parts.split(","))
    examples = (("j4d", "j4d.yaml", "J4D wall (split units), 100 displacement steps to 4 mm, 1 rank (target ≤ 10 s)"),
                # the same wall with the compressive cap, under dissipation
                # control past its peaks to 4 mm (issue 20: <= 5 s)
                ("j4d_cap", "j4d_cap.yaml", "J4D wall with the compressive cap (examples/j4d_cap.yaml), dissipation control to 4 mm, 1 rank (target ≤ 5 s)"))
    for part, name, title in examples:
        if part not in parts:
            continue
        runs = alternated(builds, a.reps, lambda exe: one(os.path.join(ROOT, "examples", name), 1, extra, exe))
        for label, rs in runs:
            for r in rs:
                print(f"  {part}{label}: {r['time']:.2f} s, {r['steps']} steps", flush=True)
            lines += table(title + label, rs)
    if "large" in parts:
        with tempfile.TemporaryDirectory() as tmp:
            scene = os.path.join(tmp, "large.yaml")
            with open(scene, "w") as f:
                # 100 courses of 100 units: 10 052 blocks, 21.99 m long; 0.30 MPa.
                # Dissipation control: displacement steps of 0.1 mm while the
                # joints are elastic, then energy steps of about that path
                # length; at most 150 steps (the peak, 984 kN at 2.17 mm, is
                # a snap-back displacement control stopped at)
                f.write(LARGE.format(courses=100, units=100, N=-0.30e6 * 21.99 * 0.1, control="dissipation", target=15e-3, steps=150))
            runs = alternated(builds, a.reps, lambda exe: one(scene, 2, extra, exe))
        for label, rs in runs:
            for r in rs:
                print(f"  large{label}: {r['time']:.2f} s, {r['steps']} steps, {r['past_peak']} past the peak, last {r['last_over_peak']:.3f} of the peak", flush=True)
            lines += table("~1e4-block wall, same joints, dissipation control past the peak, 2 ranks (target: 50 steps past the peak, to below 0.8 of it, ≤ 120 s)" + label, rs)
    append_section(lines, a.out, not a.no_write)


if __name__ == "__main__":
    main()
