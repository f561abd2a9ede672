#!/usr/bin/env python3
"""Does every pushover reach its end, and do the runs of one wall tell one
story? (issue 30) The crushing walls examples/j4d_cap.yaml, j6d.yaml and
j7d.yaml to 4 mm, each at three step counts, with OpenBLAS and with
Debian's reference BLAS (LD_LIBRARY_PATH, as tools/test's second pass), 1
rank, under a scheme (analysis.pushover.scheme); written as a dated section
into bench/results.md: per run whether it reached 4 mm, its largest load
and where, its load at 4 mm, steps and time; per wall the spread of the
peaks (target: within 2 % of each other) and of the loads at 4 mm (within
3 % of the peak).

usage: bench/paths.py [--scheme implex] [--steps 400,600,900] [--walls j4d_cap,j6d,j7d]
       (walls of our own: j4d_cap_060, j4d_cap_tall, j4d_cap_window, see VARIANTS)
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "python"))
sys.path.insert(0, os.path.join(ROOT, "bench"))
import blockwall as bw  # noqa: E402
from machine import append_section, machine, section_head  # noqa: E402

REF = "/usr/lib/x86_64-linux-gnu"
TARGET = 4.0e-3
# walls of our own, made from examples/j4d_cap.yaml by replacing lines:
# another precompression (0.60 MPa: the settlement of 0.30 MPa doubled,
# elastic at step 0), another height (27 courses, 0.30 MPa held as a force,
# the top beam free to rise), an opening (a 0.3 x 0.3 m window, 0.30 MPa
# held as a force)
HELD = ("  top_beam: {u2: -7.61237249e-05, w: 0}\n", "  top_beam: {w: 0}\nloads:\n  top_beam: [0, -29700, 0]\n")
VARIANTS = {
    "j4d_cap_060": ("j4d_cap.yaml", [("  top_beam: {u2: -7.61237249e-05, w: 0}", "  top_beam: {u2: -1.522474498e-04, w: 0}")]),
    "j4d_cap_tall": ("j4d_cap.yaml", [("    courses: 18", "    courses: 27"), HELD]),
    "j4d_cap_window": ("j4d_cap.yaml", [("    top_beam_height: 0.1", "    top_beam_height: 0.1\n    openings: [[0.35, 0.45, 0.65, 0.75]]"), HELD]),
}


def scene_file(wall, tmp):
    if wall not in VARIANTS:
        return os.path.join(ROOT, "examples", f"{wall}.yaml")
    base, subs = VARIANTS[wall]
    text = open(os.path.join(ROOT, "examples", base)).read()
    for old, new in subs:
        if old not in text:
            raise SystemExit(f"bench/paths.py: examples/{base} no longer has {old!r}")
        text = text.replace(old, new)
    path = os.path.join(tmp, f"{wall}.yaml")
    with open(path, "w") as f:
        f.write(text)
    return path


def one(wall, steps, scheme, blas):
    env = dict(os.environ)
    if blas == "reference":
        env["LD_LIBRARY_PATH"] = f"{REF}/blas:{REF}/lapack" + (":" + env["LD_LIBRARY_PATH"] if env.get("LD_LIBRARY_PATH") else "")
    # absolute: the run's working directory is a temporary one
    exe = os.path.abspath(os.environ.get("BW_EXE", os.path.join(ROOT, "build", "bin", "blockwall")))
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.h5")
        cmd = [exe, "-scene", scene_file(wall, tmp), "-output_file", out, "-output_steps", "last",
               "-output_xdmf", "false", "-analysis_pushover_target", str(TARGET), "-analysis_pushover_steps", str(steps),
               "-analysis_pushover_scheme", scheme]
        t0 = time.perf_counter()
        p = subprocess.run(cmd, env=env, capture_output=True, text=True, cwd=tmp)
        dt = time.perf_counter() - t0
        if p.returncode:
            return {"ok": False, "time": dt, "stop": p.stderr.strip().splitlines()[-1][:80] if p.stderr.strip() else f"exit {p.returncode}"}
        res = bw.read(out)
        lam, mon = res.history["load_factor"], res.history["monitor"]
        s = res.solver
    k = int(np.argmax(lam))
    reached = mon[-1] >= TARGET * (1 - 1e-9)
    return {"ok": True, "time": dt, "reached": reached, "peak": lam[k], "at": mon[k], "end": lam[-1], "end_at": mon[-1],
            "steps": len(lam) - 1, "its": int(s["newton_iterations"]), "scheme": s.get("scheme", ""),
            "from": int(s.get("implex_from_step", -1)), "stop": str(s["stop_reason"])}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scheme", default="implex")
    ap.add_argument("--steps", default="400,600,900")
    ap.add_argument("--walls", default="j4d_cap,j6d,j7d")
    ap.add_argument("--blas", default="openblas,reference")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results.md"))
    ap.add_argument("--no-write", action="store_true")
    a = ap.parse_args()
    lines = [section_head(f"bench/paths.py --scheme {a.scheme}"), "",
             f"Machine: {machine()}", "",
             "The crushing walls to 4 mm, 1 rank (issue 30: every run reaches 4 mm; one wall's peaks within 2 % of each other, its loads at 4 mm within 3 % of the peak).", "",
             "| wall | steps | BLAS | reached 4 mm | peak [kN] at [mm] | at 4 mm [kN] | steps taken | Newton its | scheme | time [s] | stop |",
             "|---|---:|---|---|---|---:|---:|---:|---|---:|---|"]
    summary = []
    total = reached = 0
    for wall in a.walls.split(","):
        rows = []
        for steps in (int(s) for s in a.steps.split(",")):
            for blas in a.blas.split(","):
                r = one(wall, steps, a.scheme, blas)
                total += 1
                if not r["ok"]:
                    lines.append(f"| {wall} | {steps} | {blas} | error | | | | | | {r['time']:.1f} | {r['stop']} |")
                    print(f"{wall} {steps} {blas}: error {r['stop']}", flush=True)
                    continue
                reached += bool(r["reached"])
                rows.append(r)
                sch = r["scheme"] + (f" from step {r['from']}" if r["scheme"] == "newton+implex" else "")
                lines.append(f"| {wall} | {steps} | {blas} | {'yes' if r['reached'] else 'no'} | {r['peak'] / 1e3:.2f} at {r['at'] * 1e3:.2f} | "
                             f"{r['end'] / 1e3:.2f}{'' if r['reached'] else f' (at {r[chr(101) + chr(110) + chr(100) + chr(95) + chr(97) + chr(116)] * 1e3:.2f} mm)'} | {r['steps']} | {r['its']} | {sch} | {r['time']:.1f} | {r['stop'][:60]} |")
                print(lines[-1], flush=True)
        if rows:
            peaks = np.array([r["peak"] for r in rows])
            ends = np.array([r["end"] for r in rows if r["reached"]])
            sp = (peaks.max() - peaks.min()) / peaks.max()
            se = (ends.max() - ends.min()) / peaks.max() if len(ends) else float("nan")
            summary.append(f"- {wall}: peaks {peaks.min() / 1e3:.2f}–{peaks.max() / 1e3:.2f} kN (spread {100 * sp:.1f} % of the largest: "
                           f"{'met' if sp <= 0.02 else 'missed'}); loads at 4 mm {ends.min() / 1e3 if len(ends) else float('nan'):.2f}–"
                           f"{ends.max() / 1e3 if len(ends) else float('nan'):.2f} kN (spread {100 * se:.1f} % of the peak: {'met' if se <= 0.03 else 'missed'})")
    lines += ["", f"{reached} of {total} runs reach 4 mm.", ""] + summary
    append_section(lines, a.out, not a.no_write)


if __name__ == "__main__":
    main()
