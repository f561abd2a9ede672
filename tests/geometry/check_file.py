"""geometry.generator: file, end to end.

  case2         the paper's case 2 written as a geometry file: block 2's
                displacement and the stresses against model.md's closed form
                (the same formula as tests/paper), 1e-10
  roundtrip     an output file read back as the geometry gives the same
                results to 1e-12: two_blocks and a running_bond wall with
                head joints of another law (their kn, kt travel in the file),
                with /interfaces/blocks kept and with it deleted (detected)
  paths         geometry.file relative to the scene file's directory from
                the scene, relative to the working directory from the
                command line
  ranks         a wall from a file on 1 and 3 ranks: same results to 1e-10
  depth         the root attribute depth overrides geometry.depth: stresses
                scale by 1/s
  dry           dry joints (e = 0, blocks touching): two blocks against the
                closed form with kn, kt given and lever arm a/2; a dry
                running-bond wall detected from a file has the generator's
                interfaces (corners touching at a point are not interfaces)
"""
import os
import shutil
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(HERE, "..", "paper"))
sys.path.insert(0, HERE)
from bwrun import ENV, EXE, Failure, call, expect, read, rel_err, run, solve  # noqa: E402
from check_paper import SCENE as PAPER_SCENE, closed_form  # noqa: E402
import geomlib  # noqa: E402

RESULTS = ("blocks/displacement", "blocks/reaction", "interfaces/resultant", "interfaces/relative_displacement",
           "interfaces/stress", "interfaces/center", "interfaces/angle", "interfaces/length", "interfaces/blocks",
           "interfaces/kn", "interfaces/kt", "blocks/centroid")


def same(a, b, tol, what):
    for key in RESULTS:
        if key == "interfaces/angle":
            e = np.max(np.abs(geomlib.angle_diff(a[key], b[key]))) if len(a[key]) else 0.0
        else:
            e = rel_err(a[key], b[key])
        expect(a[key].shape == b[key].shape, f"{what}: {key} shapes {a[key].shape} vs {b[key].shape}")
        expect(e <= tol, f"{what}: {key} differs by {e:.2e} (> {tol:.0e})")


def case2():
    with tempfile.TemporaryDirectory() as tmp:
        blocks, _, sets = geomlib.two_blocks()
        geomlib.write_geometry(os.path.join(tmp, "g.h5"), blocks, sets=sets)
        geomlib.write_scene(os.path.join(tmp, "s.yaml"), "g.h5", supports={"bottom": {"u1": 0, "u2": 0, "w": 0}},
                            loads={"top": (1000, -1000, 0)})
        res = solve(os.path.join(tmp, "s.yaml"))
    q_ref, stress_ref = closed_form(0.2, 0.1, 1000, -1000)
    e = rel_err(res["blocks/displacement"][1], q_ref)
    expect(e < 1e-10, f"case 2 from a file: displacement {res['blocks/displacement'][1]} vs closed form {q_ref}: {e:.1e}")
    e2 = rel_err(res["interfaces/stress"][0], stress_ref)
    expect(e2 < 1e-10, f"case 2 from a file: stresses vs closed form {e2:.1e}")
    expect(np.allclose(res["interfaces/center"][0], [0.1, 0.105], rtol=0, atol=1e-15), f"G = {res['interfaces/center'][0]}")
    print(f"case 2 from a file: displacement vs closed form {e:.1e}, stresses {e2:.1e}")


def strip_interfaces(src, dst):
    shutil.copy(src, dst)
    with h5py.File(dst, "r+") as f:
        for k in list(f["interfaces"].keys()):
            del f["interfaces"][k]


def roundtrip_one(tmp, name, scene, args, head_law):
    out = os.path.join(tmp, f"{name}.h5")
    run(scene, [*args, "-output_file", out, "-output_xdmf", "0"])
    ref = read(out)
    sup = {"bottom": {"u1": 0, "u2": 0, "w": 0}} if name == "two_blocks" else {"foundation": {"u1": 0, "u2": 0, "w": 0}}
    loads = {"top": (1000, -1000, 0)} if name == "two_blocks" else {"top_beam": (5e4, -3e4, 0)}
    m = int(ref["attrs"]["m"])
    for variant in ("explicit", "detected"):
        geo = out if variant == "explicit" else os.path.join(tmp, f"{name}_nointerfaces.h5")
        if variant == "detected":
            strip_interfaces(out, geo)
        s = os.path.join(tmp, f"{name}_{variant}.yaml")
        geomlib.write_scene(s, geo, supports=sup, loads=loads, m=m)
        got = solve(s)
        if variant == "explicit" or not head_law:
            same(got, ref, 1e-12, f"{name} read back ({variant})")
        else:
            # detected interfaces take joints.* everywhere: same geometry, head joints with the bed law
            for key in ("interfaces/blocks", "interfaces/center", "interfaces/length", "blocks/centroid"):
                e = rel_err(got[key], ref[key])
                expect(e <= 1e-12, f"{name} detected: {key} differs by {e:.1e}")
            e = np.max(np.abs(geomlib.angle_diff(got["interfaces/angle"], ref["interfaces/angle"])))
            expect(e <= 1e-12, f"{name} detected: angles differ by {e:.1e}")
        print(f"{name}: output read back ({variant} interfaces): {len(ref['interfaces/blocks'])} interfaces, "
              f"displacements within {rel_err(got['blocks/displacement'], ref['blocks/displacement']):.1e}")


def roundtrip():
    wall_args = ["-geometry_generator", "running_bond", "-geometry_running_bond_courses", 6,
                 "-geometry_running_bond_units_per_course", 5, "-joints_head_E", 2e8, "-joints_head_nu", 0.25,
                 "-supports_foundation_u1", 0, "-supports_foundation_u2", 0, "-supports_foundation_w", 0,
                 "-loads_top_beam", "5e4,-3e4,0", "-discretization_m", 8]
    with tempfile.TemporaryDirectory() as tmp:
        roundtrip_one(tmp, "two_blocks", PAPER_SCENE, [], False)
        wall = os.path.join(tmp, "wall.yaml")
        with open(wall, "w") as f:
            f.write("geometry: {generator: running_bond}\njoints: {law: mortar, thickness: 0.01, E: 1.0e9, nu: 0.2}\n")
        roundtrip_one(tmp, "wall", wall, wall_args, True)


def paths():
    with tempfile.TemporaryDirectory() as tmp:
        blocks, _, sets = geomlib.two_blocks()
        os.makedirs(os.path.join(tmp, "scenes", "geo"))
        os.makedirs(os.path.join(tmp, "cwd", "geo"))
        geomlib.write_geometry(os.path.join(tmp, "scenes", "geo", "g.h5"), blocks, sets=sets)
        # a different assembly under the same relative name from the working directory: which one was read shows
        geomlib.write_geometry(os.path.join(tmp, "cwd", "geo", "g.h5"), geomlib.two_blocks(l=0.4)[0], sets=sets)
        scene = os.path.join(tmp, "scenes", "s.yaml")
        geomlib.write_scene(scene, "geo/g.h5", supports={"bottom": {"u1": 0, "u2": 0, "w": 0}}, loads={"top": (1000, 0, 0)})
        for where, args, want_l in (("scene file", [], 0.2), ("command line", ["-geometry_file", "geo/g.h5"], 0.4)):
            out = os.path.join(tmp, "out.h5")
            p = call([EXE, "-scene", scene, *args, "-output_file", out], cwd=os.path.join(tmp, "cwd"), env=ENV)
            expect(p.returncode == 0, f"{where}: {p.stderr}")
            length = read(out)["interfaces/length"][0]
            expect(abs(length - want_l) < 1e-12, f"geometry.file from the {where}: read l = {length}, expected {want_l}")
            print(f"geometry.file from the {where}: resolved as expected (l = {length})")


def ranks():
    with tempfile.TemporaryDirectory() as tmp:
        blocks, _, sets = geomlib.running_bond(8, 6)
        geomlib.write_geometry(os.path.join(tmp, "w.h5"), blocks, sets=sets)
        s = os.path.join(tmp, "s.yaml")
        geomlib.write_scene(s, "w.h5", supports={"foundation": {"u1": 0, "u2": 0, "w": 0}},
                            loads={"top_beam": (5e4, -3e4, 0)}, m=8)
        one, three = solve(s), solve(s, np_ranks=3)
    same(three, one, 1e-10, "1 vs 3 ranks")
    expect(three["solver"]["ranks"] == 3, "not run on 3 ranks")
    print(f"file geometry on 1 and 3 ranks: {len(one['interfaces/blocks'])} interfaces, "
          f"displacements within {rel_err(three['blocks/displacement'], one['blocks/displacement']):.1e}")


def depth():
    with tempfile.TemporaryDirectory() as tmp:
        blocks, _, sets = geomlib.two_blocks()
        res = []
        for name, d in (("plain", None), ("deep", 0.25)):
            geomlib.write_geometry(os.path.join(tmp, f"{name}.h5"), blocks, sets=sets, depth=d)
            s = os.path.join(tmp, f"{name}.yaml")
            geomlib.write_scene(s, f"{name}.h5", supports={"bottom": {"u1": 0, "u2": 0, "w": 0}},
                                loads={"top": (1000, -1000, 0)}, extra="")
            res.append(solve(s, ["-geometry_depth", 0.1]))
    expect(abs(res[1]["attrs"]["depth"] - 0.25) < 1e-15, f"depth attribute not used: {res[1]['attrs']['depth']}")
    e = rel_err(res[1]["interfaces/stress"], res[0]["interfaces/stress"] * 0.1 / 0.25)
    expect(e < 1e-10, f"stresses with depth 0.25 vs 0.1: {e:.1e}")
    print(f"root attribute depth 0.25 overrides geometry.depth 0.1: stresses scale by 0.4 to {e:.1e}")


def dry():
    l, a, s, kn, kt, m, (f1, f2, m3) = 0.2, 0.1, 0.1, 1e11, 4e10, 16, (1000.0, -1000.0, 50.0)
    dry_law = {"law": "dry", "kn": kn, "kt": kt}
    with tempfile.TemporaryDirectory() as tmp:
        blocks, _, sets = geomlib.two_blocks(e=0.0)
        geomlib.write_geometry(os.path.join(tmp, "g.h5"), blocks, sets=sets)
        scene = os.path.join(tmp, "s.yaml")
        geomlib.write_scene(scene, "g.h5", joints=dry_law, supports={"bottom": {"u1": 0, "u2": 0, "w": 0}},
                            loads={"top": (f1, f2, m3)}, m=m)
        res = solve(scene)
        # model.md with e = 0: G on the shared face, lever arm a/2 to the top centroid
        area, inertia, h = l * s, s * l**3 / 12, a / 2
        phi = (m3 - h * f1) / (kn * inertia * (1 - 1 / m**2))
        q_ref = np.array([f1 / (kt * area) - phi * h, f2 / (kn * area), phi])
        e = rel_err(res["blocks/displacement"][1], q_ref)
        expect(e < 1e-10, f"dry two blocks: {res['blocks/displacement'][1]} vs closed form {q_ref}: {e:.1e}")
        expect(abs(res["interfaces/center"][0][1] - a) < 1e-15, f"dry G = {res['interfaces/center'][0]}")
        print(f"dry two blocks (e = 0) from a file: displacement vs closed form {e:.1e}")
        gen = ["-geometry_generator", "running_bond", "-geometry_running_bond_courses", 7,
               "-geometry_running_bond_units_per_course", 6, "-joints_law", "dry", "-joints_kn", kn, "-joints_kt", kt]
        wall_scene = os.path.join(tmp, "w.yaml")
        geomlib.write_scene(wall_scene, "unused.h5", joints=dry_law)
        code, out, err, want = geomlib.geometry_only(wall_scene, gen, dump=os.path.join(tmp, "gen.h5"))
        expect(code == 0, f"running_bond, dry: {err}")
        with h5py.File(os.path.join(tmp, "gen.h5"), "r") as f:
            geomlib.write_geometry(os.path.join(tmp, "dw.h5"), [f["blocks/vertices"][()][o0:o1] for o0, o1 in
                                                                 zip(f["blocks/offsets"][()][:-1], f["blocks/offsets"][()][1:])])
        geomlib.write_scene(wall_scene, "dw.h5", joints=dry_law)
        code, out, err, got = geomlib.geometry_only(wall_scene, dump=os.path.join(tmp, "det.h5"))
        expect(code == 0, f"dry wall from a file: {err}")
        expect(np.array_equal(got["interfaces/blocks"], want["interfaces/blocks"]), "dry wall: detected pairs differ from running_bond's")
        e = max(rel_err(got["interfaces/center"], want["interfaces/center"]), rel_err(got["interfaces/length"], want["interfaces/length"]))
        expect(e < 1e-12, f"dry wall: G, l differ by {e:.1e}")
        print(f"dry running-bond wall from a file: the generator's {len(want['interfaces/blocks'])} interfaces, within {e:.1e}")


if __name__ == "__main__":
    if not sys.argv[1:]:  # nothing would be checked
        sys.exit("check_file.py: name the case(s) to run")
    try:
        for case in sys.argv[1:]:
            globals()[case]()
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
