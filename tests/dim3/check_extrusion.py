"""The extrusion invariant (model.md, "Three dimensions", invariant 1): a 2D
scene and its extrusion along X3 (geometry.dimension: 3, in-plane loads)
give the same u1, u2 and w3 = w, with u3 = w1 = w2 = 0, and in every row of
b-portions the 2D portion stresses (rt, rn), with rb = 0; resultants
(T, N, Mb) = (T, N, M) with Tb = Mt = Mn = 0. All to 1e-10 relative (of the
largest displacement, rotation times the assembly's size, stress and
resultant), on the 3D run's ranks (1 or 3) against the 2D run on 1 rank.

  paper_N    the paper's case N (Tab. 1), tests/paper/two_blocks.yaml and its
             extrusion tests/dim3/two_blocks.yaml, with an applied moment M3
             too (case 9: F1 = 1000, F2 = -1000, M3 = 50 N m)
  wall       a 4 x 3 running-bond wall (bed and head joints, half units)
             under a top load with a horizontal part and self-weight
  prescribed the paper's blocks with block 1 pulled by prescribed u1, u2, w
             (w3 in 3D)

usage: check_extrusion.py CASE [RANKS]
       check_extrusion.py SPEC...   SPEC: CASE or CASE:RANKS[,RANKS...]
                                    (the 2D run once per case)
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import Failure, each, expect, solve  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
PAPER2, PAPER3 = os.path.join(HERE, "..", "paper", "two_blocks.yaml"), os.path.join(HERE, "two_blocks.yaml")
WALL2, WALL3 = os.path.join(HERE, "..", "wall", "wall.yaml"), os.path.join(HERE, "wall.yaml")
TAB1 = {1: (0.2, 0.1, 1000, 0, 0), 2: (0.2, 0.1, 1000, -1000, 0), 3: (0.2, 0.2, 1000, -1000, 0),
        4: (0.2, 0.4, 1000, -1000, 0), 5: (0.4, 0.1, 1000, 0, 0), 6: (0.4, 0.1, 1000, -1000, 0),
        7: (0.4, 0.2, 1000, -2000, 0), 8: (0.4, 0.4, 1000, -4000, 0), 9: (0.2, 0.1, 1000, -1000, 50)}
TOL = 1e-10


def size(res):
    v = res["blocks/vertices"]
    return float(np.linalg.norm(v[:, :2].max(axis=0) - v[:, :2].min(axis=0)))


def compare(r2, r3, what):
    """Every invariant of the extrusion, 2D result r2 against 3D result r3."""
    L = size(r2)
    q2, q3 = r2["blocks/displacement"], r3["blocks/displacement"]
    expect(q3.shape == (q2.shape[0], 6), f"{what}: 3D displacement has shape {q3.shape}")
    # (u1, u2, w3) against (u1, u2, w); rotations weighed by the assembly's size
    w = np.array([1, 1, L])
    scale = np.max(np.abs(q2 * w))
    e_in = np.max(np.abs((q3[:, [0, 1, 5]] - q2) * w)) / scale
    e_out = np.max(np.abs(q3[:, [2, 3, 4]] * np.array([1, L, L]))) / scale
    expect(e_in < TOL, f"{what}: (u1, u2, w3) differ from 2D (u1, u2, w) by {e_in:.2e} (relative)")
    expect(e_out < TOL, f"{what}: u3, w1, w2 are {e_out:.2e} of the in-plane motion, not 0")
    # resultants: (T, N, Mb) = (T, N, M); Tb, Mt, Mn = 0
    f2, f3 = r2["interfaces/resultant"], r3["interfaces/resultant"]
    fscale = np.max(np.abs(f2 * np.array([1, 1, 1 / L])))
    e_f = np.max(np.abs((f3[:, [0, 1, 5]] - f2) * np.array([1, 1, 1 / L]))) / fscale
    e_f0 = np.max(np.abs(f3[:, [2, 3, 4]] * np.array([1, 1 / L, 1 / L]))) / fscale
    expect(e_f < TOL, f"{what}: resultants (T, N, Mb) differ from 2D (T, N, M) by {e_f:.2e}")
    expect(e_f0 < TOL, f"{what}: Tb, Mt, Mn are {e_f0:.2e} of the resultants, not 0")
    # stresses: every row of b-portions holds the 2D portions
    s2 = r2["interfaces/stress"]  # (I, m, 2)
    off, s3 = r3["interfaces/portion_offsets"], r3["portions/stress"]
    m = s2.shape[1]
    sscale = np.max(np.abs(s2))
    worst, worst_b = 0.0, 0.0
    for k in range(s2.shape[0]):
        p = s3[off[k]:off[k + 1]]
        expect(len(p) % m == 0, f"{what}: interface {k} has {len(p)} portions, not a multiple of m = {m}")
        rows = p.reshape(-1, m, 3)
        worst = max(worst, np.max(np.abs(rows[:, :, :2] - s2[k][None])) / sscale)
        worst_b = max(worst_b, np.max(np.abs(rows[:, :, 2])) / sscale)
    expect(worst < TOL, f"{what}: portion stresses (rt, rn) differ from 2D by {worst:.2e}")
    expect(worst_b < TOL, f"{what}: rb is {worst_b:.2e} of the stresses, not 0")
    for key in ("residual", "equilibrium_error"):
        expect(r3["solver"][key] < 1e-12, f"{what}: 3D {key} {r3['solver'][key]:.2e}")
    print(f"{what}: (u1, u2, w3) {e_in:.1e}, out of plane {e_out:.1e}, resultants {e_f:.1e}/{e_f0:.1e}, "
          f"stresses {worst:.1e}, rb {worst_b:.1e}")


def scenes(case):
    """(2D scene, its options, the 3D scene, its options) of a case."""
    if case.startswith("paper_") and case[6:].isdigit() and int(case[6:]) in TAB1:
        l, a, f1, f2, m3 = TAB1[int(case.split("_")[1])]
        geo = ["-geometry_two_blocks_length", l, "-geometry_two_blocks_height", a]
        return PAPER2, [*geo, "-loads_top", f"{f1},{f2},{m3}"], PAPER3, [*geo, "-loads_top", f"{f1},{f2},0,0,0,{m3}"]
    if case == "wall":
        common = ["-gravity_density", 1800]
        return WALL2, [*common, "-loads_top_beam", "3000,-1.0e4,0"], WALL3, [*common, "-loads_top_beam", "3000,-1.0e4,0,0,0,0"]
    if case == "prescribed":
        return (PAPER2, ["-supports_top_u1", 1e-6, "-supports_top_u2", -2e-6, "-supports_top_w", 3e-5, "-loads_top", "0,0,0"],
                PAPER3, ["-supports_top_u1", 1e-6, "-supports_top_u2", -2e-6, "-supports_top_w3", 3e-5,
                         "-supports_top_u3", 0, "-supports_top_w1", 0, "-supports_top_w2", 0, "-loads_top", "0,0,0,0,0,0"])
    raise SystemExit(f"unknown case {case}")


def main():
    """check_extrusion.py CASE [RANKS], or SPEC... with SPEC = CASE or
    CASE:RANKS,RANKS...: each case's 2D run once (1 rank), against its 3D
    run on each rank count (default 1); every spec run and reported."""
    args = sys.argv[1:]
    specs = [f"{args[0]}:{args[1]}"] if len(args) == 2 and args[1].isdigit() else args

    def one(spec):
        case, _, counts = spec.partition(":")
        s2, o2, s3, o3 = scenes(case)
        r2 = solve(s2, o2)
        for ranks in [int(n) for n in counts.split(",")] if counts else [1]:
            compare(r2, solve(s3, o3, ranks), f"{case} on {ranks} rank{'s' if ranks > 1 else ''}")
    each(specs, one)


if __name__ == "__main__":
    try:
        main()
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
