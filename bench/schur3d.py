#!/usr/bin/env python3
"""The 3D Schur solve against the size of the wall (issue 29, item 2):
bench/large_wall3d.yaml at N x N units, stresses not written, one run per
(size, ranks, candidate, load, depth), measured from outside:

  - the Richardson steps (/solver iterations) and the inner CG iterations
    of each step (-schur_ksp_converged_reason),
  - the peak resident memory of every rank (/usr/bin/time around each
    rank), summed over the ranks, per block,
  - /solver accuracy_met, residual, schur_solve.

    python3 bench/schur3d.py --sizes 100,316 --candidates gamg,gamg_bend [--loads oop,inplane] [--depths 0.1,0.3] [--ranks 1]

Candidates are named sets of options (CANDIDATES below); --extra adds
options to every run. Prints one markdown row per run (and appends them to
--out if given). No timings are kept as figures: the machine is shared, the
seconds printed are rough indications only."""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import time

import h5py

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SCENE = os.path.join(HERE, "large_wall3d.yaml")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")

CANDIDATES = {
    "auto": [],
    "cholesky": ["-solver_schur", "cholesky"],
    "gamg": ["-solver_schur", "gamg"],
    "hypre": ["-solver_schur", "hypre"],
}
LOADS = {
    "oop": [],  # the bench scene: self-weight, top load with an out-of-plane part
    "inplane": ["-loads_top_beam", "1.0e5,-1.6e6,0,0,0,0"],
}


def run(exe, n, ranks, cand, load, depth, extra):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.h5")
        cmd = [exe, "-scene", SCENE, "-geometry_running_bond_courses", str(n), "-geometry_running_bond_units_per_course", str(n),
               "-geometry_depth", str(depth), "-output_stresses", "false", "-output_file", out, "-schur_ksp_converged_reason",
               *CANDIDATES.get(cand, []), *LOADS[load], *extra]
        timed = ["/usr/bin/time", "-f", "MAXRSS %M CPU %U %S", *cmd]
        if ranks > 1:
            timed = ["mpiexec", "--oversubscribe", "-n", str(ranks), *timed]
        t0 = time.perf_counter()
        p = subprocess.run(timed, capture_output=True, text=True, env=ENV)
        wall = time.perf_counter() - t0
        rss = [int(k) * 1024 for k in re.findall(r"MAXRSS (\d+)", p.stderr)]
        cpu = sum(float(u) + float(s) for u, s in re.findall(r"CPU ([\d.]+) ([\d.]+)", p.stderr))
        inner = [int(m.group(2)) for m in re.finditer(r"Linear schur_ solve (converged|diverged) due to \S+ iterations (\d+)", p.stdout)]
        row = dict(n=n, ranks=ranks, cand=cand, load=load, depth=depth, rc=p.returncode, rss=sum(rss), inner=inner, wall=wall, cpu=cpu)
        if len(rss) != ranks:
            row["rc"], row["error"] = row["rc"] or -1, f"{len(rss)} of {ranks} ranks measured"
        if p.returncode == 0:
            with h5py.File(out) as f:
                s = dict(f["solver"].attrs)
                row["blocks"] = f["blocks/displacement"].shape[0]
            dec = lambda v: v.decode() if isinstance(v, bytes) else v  # noqa: E731
            row.update(steps=int(s["iterations"]), acc=int(s["accuracy_met"]), res=float(s["residual"]),
                       schur=dec(s["schur_solve"]), method=dec(s["method_used"]), fallback=int(s["fallback"]),
                       fwd=float(s["forward_error_estimate"]))
        else:
            row["error"] = (p.stderr.strip().splitlines() or ["?"])[-1][:200]
        return row


def fmt(r, extra):
    if r["rc"]:
        return f"| {r['n']}x{r['n']} | ? | {r['ranks']} | {r['cand']} {' '.join(extra)} | {r['load']} | {r['depth']} | failed: {r['error']} |||||"
    its = "/".join(map(str, r["inner"])) or "-"
    return (f"| {r['n']}x{r['n']} | {r['blocks']} | {r['ranks']} | {r['cand']} {' '.join(extra)} | {r['load']} | {r['depth']} | "
            f"{r['steps']} | {its} | {r['rss'] / r['blocks'] / 1024:.1f} | {r['acc']} | {r['res']:.1e} | {r['schur']}{' (fallback)' if r['fallback'] else ''} | ~{r['cpu']:.0f} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "bin", "blockwall"))
    ap.add_argument("--label", default="", help="prefix of the candidate's name in the rows (e.g. the build)")
    ap.add_argument("--sizes", default="100")
    ap.add_argument("--ranks", default="1")
    ap.add_argument("--candidates", default="gamg")
    ap.add_argument("--loads", default="oop")
    ap.add_argument("--depths", default="0.1")
    ap.add_argument("--extra", default="", help="options added to every run, space-separated")
    ap.add_argument("--out", help="append the rows to this file")
    a = ap.parse_args()
    extra = a.extra.split()
    for n in map(int, a.sizes.split(",")):
        for ranks in map(int, a.ranks.split(",")):
            for cand in a.candidates.split(","):
                for load in a.loads.split(","):
                    for depth in map(float, a.depths.split(",")):
                        r = run(a.exe, n, ranks, cand, load, depth, extra)
                        r["cand"] = a.label + cand
                        line = fmt(r, extra)
                        print(line, flush=True)
                        if a.out:
                            with open(a.out, "a") as f:
                                f.write(line + "\n")


if __name__ == "__main__":
    sys.exit(main())
