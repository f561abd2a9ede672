"""Assemblies that can move without deforming a joint are reported before
any solve, naming the blocks and the free motion, with exit code 1, one
line on stderr and nothing written; assemblies just short of that solve.

  hinge        the paper's two blocks with m = 1: the top block hangs on one
               interface without bending stiffness, it turns about
               G = (0.1, 0.105)
  u1_only      the two blocks with only u1 of the bottom block prescribed:
               free are the translation along y and a rotation about the
               point on the bottom centroid's level, (0.1, 0.05)
  pinned_foundation  a running-bond wall whose foundation has u1, u2 fixed,
               w free: the whole wall turns about the foundation's centroid
  unconnected  a file with a fixed two-block stack and, apart, a second stack
               with no support: blocks 2, 3 have no path to a support
  arch_m1      the 9-voussoir arch with m = 1: 27 free dofs against 20 hinge
               equations, at least 7 free motions
  four_bar     a parallelogram four-bar from a file with m = 1 -- two posts on
               the ground, a beam across them, and beside it a comb standing
               on the ground on three feet (three interfaces with it): 12 free
               dofs, 14 hinge equations, no block on a single hinge, so the
               static checks pass, and a vertical load on the beam does no
               work on the sway, so a solver can return an answer with any
               amount of it. BwMixedCheckMechanism (test_mechanism scene,
               the hook for the solver) names the posts and the beam and their
               motions: rotations about the posts' feet, a translation along
               x; with m = 2 it finds none.
  sound        controls that must solve: the two blocks held by u1, u2 of the
               bottom block and w of the top one (restrained, no dof twice);
               a running-bond wall with m = 1 (every unit on two or more
               hinges); the answers balance the loads
"""
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(HERE, "..", "paper"))
sys.path.insert(0, HERE)
from bwrun import Failure, expect, run, solve  # noqa: E402
from check_paper import SCENE as PAPER  # noqa: E402
import geomlib  # noqa: E402

WALL = ["-geometry_generator", "running_bond", "-geometry_running_bond_courses", 4,
        "-geometry_running_bond_units_per_course", 4, "-loads_top_beam", "5e4,-3e4,0"]


def refused(name, scene, args, wants):
    with tempfile.TemporaryDirectory() as tmp:
        target = os.path.join(tmp, "result.h5")
        code, out, err = run(scene, [*args, "-output_file", target], expect_ok=False)
        lines = [l for l in err.splitlines() if l.strip()]
        expect(code == 1, f"{name}: exit code {code}, expected 1 (user input)\n{err}")
        expect(len(lines) == 1, f"{name}: expected one line on stderr, got {len(lines)}:\n{err}")
        for w in wants:
            expect(w in lines[0], f"{name}: {w!r} not in {lines[0]!r}")
        expect(os.listdir(tmp) == [], f"{name}: files written: {os.listdir(tmp)}")
        print(f"{name}: {lines[0]}")


def wall_scene(tmp):
    path = os.path.join(tmp, "wall.yaml")
    with open(path, "w") as f:
        f.write("geometry: {generator: running_bond}\njoints: {law: mortar, thickness: 0.01, E: 1.0e9, nu: 0.2}\n")
    return path


def hinge():
    refused("hinge", PAPER, ["-discretization_m", 1],
            ["mechanism", "block 1 is held only at G = (0.1, 0.105)", "interface 0", "discretization.m = 1",
             "free motion: rotation of block 1 about (0.1, 0.105)"])


def u1_only():
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "s.yaml")
        with open(scene, "w") as f:
            f.write("geometry: {generator: two_blocks}\nsupports:\n  bottom: {u1: 0}\nloads: {top: [1000, -1000, 0]}\n")
        refused("u1_only", scene, [], ["not restrained", "blocks 0, 1 (2 blocks)", "u1 on 1, u2 on 0, w on 0 blocks",
                                       "free motion: translation along y (u2), rotation about (0.1, 0.05)"])


def pinned_foundation():
    with tempfile.TemporaryDirectory() as tmp:
        # 20 blocks: foundation, courses of 4, 5, 4, 5 units (odd ones: two halves and 3 full), top beam;
        # the foundation spans the wall, L = 4 l_u + 3 e, its centroid is at (L/2, -0.01 - 0.05)
        L = 4 * 0.21 + 3 * 0.01
        refused("pinned_foundation", wall_scene(tmp), [*WALL, "-supports_foundation_u1", 0, "-supports_foundation_u2", 0],
                ["not restrained", "blocks 0, 1, 2", "(20 blocks)", f"free motion: rotation about ({L / 2:g}, -0.06)"])


def unconnected():
    with tempfile.TemporaryDirectory() as tmp:
        blocks, _, _ = geomlib.two_blocks()
        apart = geomlib.transform(blocks, 0, (1.0, 0))
        geomlib.write_geometry(os.path.join(tmp, "g.h5"), blocks + apart, sets={"bottom": [0], "top": [1, 3]})
        scene = os.path.join(tmp, "s.yaml")
        geomlib.write_scene(scene, "g.h5", supports={"bottom": {"u1": 0, "u2": 0, "w": 0}}, loads={"top": (1000, -1000, 0)})
        refused("unconnected", scene, [], ["not restrained", "blocks 2, 3 (2 blocks) have no path of interfaces to a support",
                                           "free motion: rigid translation and rotation"])


def arch_m1():
    with tempfile.TemporaryDirectory() as tmp:
        blocks, _, sets = geomlib.arch()
        geomlib.write_geometry(os.path.join(tmp, "a.h5"), blocks, sets=sets)
        scene = os.path.join(tmp, "s.yaml")
        geomlib.write_scene(scene, "a.h5", supports={"springers": {"u1": 0, "u2": 0, "w": 0}}, loads={"crown": (0, -5e4, 0)}, m=1)
        refused("arch_m1", scene, [], ["mechanism", "blocks 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10 (11 blocks)",
                                       "27 free dofs against 20 hinge constraints", "at least 7 independent rotations"])


def four_bar():
    from bwrun import ENV, EXE, call
    R = geomlib.rect
    comb = [(1.5, 0.01), (1.6, 0.01), (1.6, 0.2), (1.8, 0.2), (1.8, 0.01), (1.9, 0.01), (1.9, 0.2), (2.1, 0.2),
            (2.1, 0.01), (2.2, 0.01), (2.2, 0.4), (1.5, 0.4)]
    blocks = [R(-1, -0.2, 3, 0), R(0, 0.01, 0.1, 1.0), R(0.9, 0.01, 1.0, 1.0), R(-0.05, 1.01, 1.05, 1.2), comb]
    with tempfile.TemporaryDirectory() as tmp:
        geomlib.write_geometry(os.path.join(tmp, "g.h5"), blocks, sets={"ground": [0], "beam": [3]})
        scene = os.path.join(tmp, "s.yaml")
        geomlib.write_scene(scene, "g.h5", supports={"ground": {"u1": 0, "u2": 0, "w": 0}}, loads={"beam": (0, -1000, 0)}, m=1)
        exe = os.path.join(os.path.dirname(EXE), "test_mechanism")
        for m, code_want in ((1, 1), (2, 0)):
            p = call([exe, "scene", "-scene", scene, "-discretization_m", str(m)], env=ENV)
            expect(p.returncode == code_want, f"four-bar, m = {m}: exit {p.returncode}, expected {code_want}\n{p.stdout}{p.stderr}")
            if m == 1:
                for w in ["mechanism", "blocks 1, 2, 3 (3 blocks)", "block 1 rotates about (0.05, 0.005)",
                          "block 2 rotates about (0.95, 0.005)", "block 3 translates along (1, 0)"]:
                    expect(w in p.stderr, f"four-bar: {w!r} not in {p.stderr!r}")
                print(f"four-bar, m = 1: {p.stderr.strip()}")
            else:
                print(f"four-bar, m = 2: {p.stdout.strip()}")
        # the executable itself refuses it (m = 1: S^ checked numerically
        # after assembly) and writes nothing
        out = os.path.join(tmp, "never.h5")
        p = call([EXE, "-scene", scene, "-output_file", out], env=ENV)
        lines = [l for l in p.stderr.splitlines() if l.strip()]
        expect(p.returncode != 0 and len(lines) == 1 and "mechanism" in lines[0] and "blocks 1, 2, 3" in lines[0],
               f"blockwall on the four-bar: exit {p.returncode}, stderr {p.stderr!r}")
        expect(not os.path.exists(out), "a result was written for a mechanism")
        print(f"blockwall, m = 1: {lines[0]}")


def balanced(res, what):
    e = res["solver"]["equilibrium_error"]
    expect(e < 1e-10 and res["solver"]["residual"] < 1e-10, f"{what}: equilibrium error {e:.1e}, residual {res['solver']['residual']:.1e}")
    expect(np.max(np.abs(res["blocks/displacement"])) > 0, f"{what}: nothing moved")


def sound():
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "s.yaml")
        with open(scene, "w") as f:
            f.write("geometry: {generator: two_blocks}\nsupports:\n  bottom: {u1: 0, u2: 0}\n  top: {w: 0}\n"
                    "loads: {top: [1000, -1000, 0]}\n")
        res = solve(scene)
        balanced(res, "two blocks on u1, u2 below and w above")
        expect(res["blocks/displacement"][1][2] == 0 and abs(res["blocks/reaction"][1][2]) > 0, "w of the top block not held")
        print(f"two blocks, u1 u2 below, w above: solved, equilibrium error {res['solver']['equilibrium_error']:.1e}")
        res = solve(wall_scene(tmp), [*WALL, "-supports_foundation_u1", 0, "-supports_foundation_u2", 0,
                                      "-supports_foundation_w", 0, "-discretization_m", 1])
        balanced(res, "wall with m = 1")
        print(f"running-bond wall with m = 1: solved, equilibrium error {res['solver']['equilibrium_error']:.1e}")


if __name__ == "__main__":
    try:
        globals()[sys.argv[1]]()
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
