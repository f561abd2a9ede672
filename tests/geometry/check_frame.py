"""Frame invariance of file geometries with detected interfaces.

The assembly is written once as given and then rotated by 30 and 217 deg
about the origin and translated by (1e3, -2e3) m, with every load [F1, F2,
M3] turned into (R F, M3). Then, to 1e-9 relative:
  displacements (u1, u2) and reactions rotate: (R u, w), (R r, r3)
  G moves with the frame (R G + shift), theta turns by the rotation,
  l, the resultants (T, N, M), the relative displacements and the stresses
  (local axes) are unchanged, interfaces come out in the same order.
The unrotated case 2 is also held to model.md's closed form, so that the
comparison is anchored to an independent reference.

  two_blocks   the paper's case 2 (l = 0.2, a = 0.1, e = 0.01, E = 1e9,
               nu = 0.2, m = 16, bottom fixed, top loaded [1000, -1000, 0])
  wall         a running-bond wall of 4 courses of 4 units on a fixed
               foundation under a top beam loaded [5e4, -3e4, 2e3]
"""
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(HERE, "..", "paper"))
sys.path.insert(0, HERE)
from bwrun import Failure, expect, rel_err, solve  # noqa: E402
from check_paper import closed_form  # noqa: E402
import geomlib  # noqa: E402

FRAMES = [(30.0, (1e3, -2e3)), (217.0, (1e3, -2e3))]
TOL = 1e-9


def rotate3(v, R):
    v = np.array(v, float)
    out = v.copy()
    out[..., :2] = v[..., :2] @ R.T
    return out


def run(tmp, name, blocks, sets, supports, loads, m):
    path = os.path.join(tmp, f"{name}.h5")
    geomlib.write_geometry(path, blocks, sets=sets)
    scene = os.path.join(tmp, f"{name}.yaml")
    geomlib.write_scene(scene, path, supports=supports, loads=loads, m=m)
    return solve(scene)


def compare(ref, got, deg, shift, what):
    R = geomlib.rotation(deg)
    checks = {
        "blocks/displacement": (got["blocks/displacement"], rotate3(ref["blocks/displacement"], R)),
        "blocks/reaction": (got["blocks/reaction"], rotate3(ref["blocks/reaction"], R)),
        "blocks/centroid": (got["blocks/centroid"] - shift, ref["blocks/centroid"] @ R.T),
        "interfaces/center": (got["interfaces/center"] - shift, ref["interfaces/center"] @ R.T),
        "interfaces/length": (got["interfaces/length"], ref["interfaces/length"]),
        "interfaces/resultant": (got["interfaces/resultant"], ref["interfaces/resultant"]),
        "interfaces/relative_displacement": (got["interfaces/relative_displacement"], ref["interfaces/relative_displacement"]),
        "interfaces/stress": (got["interfaces/stress"], ref["interfaces/stress"]),
    }
    expect(np.array_equal(got["interfaces/blocks"], ref["interfaces/blocks"]),
           f"{what}: interfaces differ or come in another order")
    worst = 0.0
    for key, (a, b) in checks.items():
        # centroids and G are compared after removing the shift: their digits below 1e3 * eps are gone
        scale = np.max(np.abs(b)) if "center" not in key and "centroid" not in key else max(np.max(np.abs(b)), 1.0)
        e = np.max(np.abs(a - b)) / scale
        expect(e <= TOL, f"{what}: {key} differs by {e:.2e} relative")
        worst = max(worst, e)
    da = np.max(np.abs(geomlib.angle_diff(got["interfaces/angle"], ref["interfaces/angle"] + np.radians(deg))))
    expect(da <= TOL, f"{what}: theta does not turn with the frame ({da:.1e} rad)")
    return worst


def case(name, blocks, sets, supports, loads, m, anchor=None):
    with tempfile.TemporaryDirectory() as tmp:
        ref = run(tmp, "ref", blocks, sets, supports, loads, m)
        if anchor:
            anchor(ref)
        for deg, shift in FRAMES:
            R = geomlib.rotation(deg)
            moved = geomlib.transform(blocks, deg, shift)
            rloads = {s: (*(R @ np.array(f[:2], float)), f[2]) for s, f in loads.items()}
            got = run(tmp, f"rot{int(deg)}", moved, sets, supports, rloads, m)
            worst = compare(ref, got, deg, np.array(shift), f"{name} rotated {deg} deg")
            print(f"{name}: rotated {deg:g} deg, shifted {shift}: {len(ref['interfaces/blocks'])} interfaces, "
                  f"all results within {worst:.1e} relative")


def two_blocks():
    blocks, _, sets = geomlib.two_blocks()

    def anchor(ref):
        q_ref, stress_ref = closed_form(0.2, 0.1, 1000, -1000)
        e = rel_err(ref["blocks/displacement"][1], q_ref)
        expect(e < 1e-10, f"case 2 from a file vs closed form: {e:.1e}")
        expect(rel_err(ref["interfaces/stress"][0], stress_ref) < 1e-10, "case 2 stresses vs closed form")

    case("case 2", blocks, sets, {"bottom": {"u1": 0, "u2": 0, "w": 0}}, {"top": (1000, -1000, 0)}, 16, anchor)


def wall():
    blocks, inter, sets = geomlib.running_bond(4, 4)

    def anchor(ref):
        # the detected interfaces are the construction's
        expect(np.array_equal(ref["interfaces/blocks"], np.array([(i, j) for i, j, *_ in inter])), "wall interfaces")
        expect(rel_err(ref["interfaces/center"], np.array([g for _, _, g, _, _ in inter])) < 1e-12, "wall G")

    case("wall", blocks, sets, {"foundation": {"u1": 0, "u2": 0, "w": 0}}, {"top_beam": (5e4, -3e4, 2e3)}, 8, anchor)


if __name__ == "__main__":
    if not sys.argv[1:]:  # nothing would be checked
        sys.exit("check_frame.py: name the case(s) to run")
    try:
        for c in sys.argv[1:]:
            globals()[c]()
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
