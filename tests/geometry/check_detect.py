"""Detection on a running-bond wall of 1e5 blocks written to a file without
/interfaces/blocks (316 courses of 316 units, foundation, top beam).

  analytic      the detected interfaces are the construction's (geomlib:
                bed joints over each x-overlap, head joints between
                neighbours): the same pairs in the same order, G, theta and l
                to 1e-12 of the wall's size
  generator     and the running_bond generator's, for the same wall: the
                same pairs, G, theta, l (head joints there are
                BW_JOINT_HEAD, here bed: only the law differs)
Geometry only (test_geometry): a solve of 1e5 blocks would test the solver.
The time is printed, not asserted: bench/detect_scaling.py measures it.
"""
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, HERE)
from bwrun import Failure, expect  # noqa: E402
import geomlib  # noqa: E402

COURSES, UNITS, LU, HU, E, HF, HB = 316, 316, 0.21, 0.052, 0.01, 0.1, 0.1


def compare(got, pairs, centers, angles, lengths, what):
    expect(got["interfaces/blocks"].shape == pairs.shape, f"{what}: {len(got['interfaces/blocks'])} interfaces, expected {len(pairs)}")
    bad = np.nonzero(np.any(got["interfaces/blocks"] != pairs, axis=1))[0]
    expect(len(bad) == 0, f"{what}: interface {bad[:1]} is {got['interfaces/blocks'][bad[:1]]}, expected {pairs[bad[:1]]}")
    size = np.max(np.abs(centers))
    e_g = np.max(np.abs(got["interfaces/center"] - centers)) / size
    e_l = np.max(np.abs(got["interfaces/length"] - lengths)) / size
    e_t = np.max(np.abs(geomlib.angle_diff(got["interfaces/angle"], angles)))
    expect(e_g < 1e-12 and e_l < 1e-12 and e_t < 1e-12, f"{what}: G {e_g:.1e}, l {e_l:.1e}, theta {e_t:.1e}")
    return max(e_g, e_l, e_t)


def main(which):
    blocks, inter, sets = geomlib.running_bond(COURSES, UNITS, LU, HU, E, HF, HB)
    pairs = np.array([(i, j) for i, j, *_ in inter], np.int64)
    centers = np.array([g for _, _, g, _, _ in inter])
    angles = np.array([t for *_, t, _ in inter])
    lengths = np.array([l for *_, l in inter])
    with tempfile.TemporaryDirectory() as tmp:
        geo, scene = os.path.join(tmp, "wall.h5"), os.path.join(tmp, "wall.yaml")
        geomlib.write_geometry(geo, blocks, sets=sets)
        geomlib.write_scene(scene, geo)
        code, out, err, got = geomlib.geometry_only(scene, dump=os.path.join(tmp, "file.h5"))
        expect(code == 0, f"detection failed: {err}")
        print(f"file, detected: {out.strip()}")
        if which == "analytic":
            e = compare(got, pairs, centers, angles, lengths, "detected vs construction")
            print(f"{len(blocks)} blocks: the {len(pairs)} detected interfaces are the construction's (within {e:.1e})")
        else:
            args = ["-geometry_generator", "running_bond", "-geometry_running_bond_courses", COURSES,
                    "-geometry_running_bond_units_per_course", UNITS, "-geometry_running_bond_unit_length", LU,
                    "-geometry_running_bond_unit_height", HU, "-geometry_running_bond_foundation_height", HF,
                    "-geometry_running_bond_top_beam_height", HB]
            code, out, err, gen = geomlib.geometry_only(scene, args, dump=os.path.join(tmp, "gen.h5"))
            expect(code == 0, f"running_bond generator failed: {err}")
            print(f"running_bond generator: {out.strip()}")
            expect(np.array_equal(gen["blocks/centroid"].shape, got["blocks/centroid"].shape), "not the same blocks")
            expect(np.max(np.abs(gen["blocks/centroid"] - got["blocks/centroid"])) < 1e-12 * np.max(np.abs(centers)), "block centroids differ")
            e = compare(got, gen["interfaces/blocks"], gen["interfaces/center"], gen["interfaces/angle"], gen["interfaces/length"], "file vs running_bond")
            nhead = int(np.sum(gen["interfaces/kind"] == 1))
            expect(nhead == int(np.sum(np.isclose(angles, -np.pi / 2))), "head joints of the generator")
            print(f"detected interfaces = running_bond's: {len(gen['interfaces/blocks'])} ({nhead} head joints), within {e:.1e}")


if __name__ == "__main__":
    if sys.argv[1:] not in (["analytic"], ["generator"]):  # not the generator's checks under a mistyped name
        sys.exit(f"check_detect.py: unknown case {sys.argv[1:]} (analytic, generator)")
    try:
        main(sys.argv[1])
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
