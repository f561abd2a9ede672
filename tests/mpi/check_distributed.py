"""The distributed model gives the answer of one rank (issue 29): a scene on
2, 3 and 5 ranks with the graph partitioner, on 3 with the natural one
(each rank a range of the input's blocks), and on 2 over Open MPI's TCP
transport (--mca btl tcp,self, the way ranks on different nodes talk),
against the same scene on 1 rank (no partition, no halo).

Every dataset of the file is compared, none skipped: both files must hold
the same datasets with the same shapes; integers (topology, sets, states,
interface blocks) exactly, reals to TOL of the dataset's largest value.
TOL: 1e-10 for a linear analysis (the partition changes only the order of
the factorisation's sums; the issue's bound), 1e-7 for a pushover, whose
steps are Newton's to a relative residual of 1e-8 (tolerance of the
scenes), so that two runs may stop at different iterates within it.

  gen2d    running-bond wall with an opening (generator)
  gen3d    running-bond wall, 3D, pushed in and out of its plane
  file2d   the arch of the gallery (file geometry, interfaces detected)
  file3d   the U-shaped wall of the gallery (3D file, detected faces)
  push2d   J4D (examples/j4d.yaml) shortened: a cracking wall, 2D
  push3d   the tilting U-wall (examples/u_wall_tilt.yaml) shortened"""
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from bwrun import ENV, EXE, MPIEXEC, Failure, call, expect, read, run  # noqa: E402
import blockwall  # noqa: E402  (bwrun put the checkout's python/ on the path)

EX = os.path.join(ROOT, "examples")
RB = "-geometry_running_bond_"
CASES = {
    "gen2d": (os.path.join(EX, "demo_opening.yaml"), [f"{RB}courses", "24", f"{RB}units_per_course", "9",
                                                      f"{RB}openings", "0.6,0.4,1.3,0.9"], 1e-10),
    "gen3d": (os.path.join(ROOT, "bench", "large_wall3d.yaml"), [f"{RB}courses", "14", f"{RB}units_per_course", "10",
                                                                 "-discretization_m", "4", "-discretization_m_b", "2"], 1e-10),
    "file2d": (os.path.join(EX, "arch.yaml"), [], 1e-10),
    "file3d": (os.path.join(EX, "u_wall.yaml"), [], 1e-10),
    "push2d": (os.path.join(EX, "j4d.yaml"), ["-analysis_pushover_steps", "8", "-analysis_pushover_target", "0.0008",
                                             "-output_steps", "all"], 1e-7),
    "push3d": (os.path.join(EX, "u_wall_tilt.yaml"), ["-analysis_pushover_steps", "6", "-analysis_pushover_target", "-1.0e-3",
                                                     "-output_steps", "all", "-discretization_m", "4", "-discretization_m_b", "2"], 1e-7),
}
NEWTON_TOL = 1e-8  # analysis.pushover.tolerance of the pushover scenes (interface.md default)
RUNS = [(2, "graph", False), (3, "graph", False), (5, "graph", False), (3, "natural", False), (2, "graph", True)]


def compare(one, many, tol, what):
    d1, dn = {k for k in one if k not in ("attrs", "solver")}, {k for k in many if k not in ("attrs", "solver")}
    expect(d1 == dn, f"{what}: datasets on 1 rank only {sorted(d1 - dn)}, here only {sorted(dn - d1)}")
    worst, where = 0.0, ""
    for key in sorted(d1):
        a, b = np.asarray(one[key]), np.asarray(many[key])
        if key == "history/residual":
            # the solver's record, not a result: each step's own round-off
            expect(np.all(b <= NEWTON_TOL), f"{what}: a step's residual {b.max():.1e} above Newton's {NEWTON_TOL:g}")
            continue
        if key == "history/iterations":
            # the solver's record too: Newton on a nonsmooth law, from an
            # iterate within round-off of an active-set switch, takes its
            # own number of iterations to the same answer (17 on 1 rank, 23
            # on 2 at one step of push3d; issue 30). Each step converged
            # (history/residual above); the counts are shown, not compared.
            expect(a.shape == b.shape, f"{what}: {key} shape {a.shape} vs {b.shape}")
            if not np.array_equal(a, b):
                print(f"{what}: Newton iterations {b.tolist()}, on 1 rank {a.tolist()}")
            continue
        expect(a.shape == b.shape and a.dtype.kind == b.dtype.kind, f"{what}: {key} shape {a.shape} {a.dtype} vs {b.shape} {b.dtype}")
        if a.dtype.kind in "iub":
            expect(np.array_equal(a, b), f"{what}: {key} (integers) differs from 1 rank's")
        elif a.dtype.kind == "f" and a.size:
            scale = np.max(np.abs(a))
            e = float(np.max(np.abs(a - b)) / scale) if scale > 0 else float(np.max(np.abs(b)))
            if e > worst:
                worst, where = e, key
            expect(e <= tol, f"{what}: {key} differs from 1 rank's by {e:.2e} of its largest value (tolerance {tol:g})")
    return len(d1), worst, where


def main(case):
    scene, args, tol = CASES[case]
    with tempfile.TemporaryDirectory() as tmp:
        ref = os.path.join(tmp, "one.h5")
        run(scene, [*args, "-output_file", ref, "-output_xdmf", "true"], 1)
        one = read(ref)
        expect(one["solver"]["partition_edge_cut"] == 0 and one["solver"]["partition_imbalance"] == 1.0, "1 rank: a partition")
        for ranks, method, tcp in RUNS:
            out = os.path.join(tmp, f"r{ranks}{method}{int(tcp)}.h5")
            env = dict(ENV, OMPI_MCA_btl="tcp,self") if tcp else ENV
            what = f"{case}, {ranks} ranks, partition {method}{', TCP' if tcp else ''}"
            cmd = blockwall.command(scene, [*args, "-output_file", out, "-output_xdmf", "true", "-partition_method", method],
                                    ranks, exe=EXE, mpiexec=MPIEXEC)
            p = call(cmd, env=env, what="blockwall")
            expect(p.returncode == 0, f"{what}: exit {p.returncode}\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
            many = read(out)
            expect(int(many["solver"]["ranks"]) == ranks, f"{what}: /solver ranks {many['solver']['ranks']}")
            cut = int(many["solver"]["partition_edge_cut"])
            expect(cut > 0, f"{what}: no interface crosses a rank boundary: nothing distributed was checked")
            n, worst, where = compare(one, many, tol, what)
            print(f"{what}: {n} datasets equal to 1 rank's (worst {worst:.1e} in {where}); edge cut {cut}, "
                  f"imbalance {float(many['solver']['partition_imbalance']):.3f}")


if __name__ == "__main__":
    try:
        if len(sys.argv) != 2 or sys.argv[1] not in CASES:
            raise Failure(f"usage: check_distributed.py {{{'|'.join(CASES)}}} (got {sys.argv[1:]})")
        main(sys.argv[1])
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
