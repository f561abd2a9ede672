"""Large inputs are read in linear time, or refused at once with a clear
limit; none hangs.

  polygon  a geometry file with one block of 1e6 vertices (a dome on a
           foundation): self-intersection, overlap and interface detection
           once took 2.2 s at 1e4 vertices and did not end at 1e5
  keys     a scene of 1e5 keys (1e5 sets of a file, each loaded): parsing
           and set matching once took 3.3 s at 1e4 keys and 31 s at 3e4
  memory   a running-bond wall too large for this machine is refused before
           anything is allocated, saying what it needs and what there is

Each case is run under a timeout generous for linear work (a quadratic run
would take hours); the answers are checked against closed forms: the dome's
weight carried by the foundation, the sum of 1e5 loads."""
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import ENV, EXE, Failure, expect, read  # noqa: E402


def run(tmp, scene_text, timeout):
    scene = os.path.join(tmp, "scene.yaml")
    with open(scene, "w") as f:
        f.write(scene_text)
    return subprocess.run([EXE, "-scene", scene], capture_output=True, text=True, env=ENV, timeout=timeout, cwd=tmp)


def polygon():
    n = 1_000_000
    t = np.linspace(0.0, np.pi, n)
    arc = np.column_stack([np.cos(t), 0.05 + 0.5 * np.sin(t)])  # from (1, 0.05) to (-1, 0.05)
    dome = np.vstack([[[-1.0, 0.0], [1.0, 0.0]], arc])
    found = np.array([[-1.2, -0.3], [1.2, -0.3], [1.2, -0.01], [-1.2, -0.01]])
    with tempfile.TemporaryDirectory() as tmp:
        with h5py.File(os.path.join(tmp, "dome.h5"), "w") as f:
            f["blocks/vertices"] = np.vstack([found, dome])
            f["blocks/offsets"] = np.array([0, 4, 4 + len(dome)], np.int64)
            f["sets/foundation"] = np.array([0], np.int64)
            f["sets/dome"] = np.array([1], np.int64)
        p = run(tmp, "geometry: {generator: file, file: dome.h5}\n"
                "supports: {foundation: {u1: 0, u2: 0, w: 0}}\n"
                "gravity: {density: 2000}\noutput: {file: out.h5, xdmf: false}\n", timeout=120)
        expect(p.returncode == 0, f"1e6-vertex polygon: exit {p.returncode}\n{p.stderr}")
        res = read(os.path.join(tmp, "out.h5"))
        # the dome's area: rectangle 2 x 0.05 plus half an ellipse (semi-axes
        # 1 and 0.5) less the chords' sagitta, which 1e6 vertices make 4e-13
        area = 2 * 0.05 + 0.5 * np.pi * 1.0 * 0.5
        weight = 2000 * 9.81 * area * 0.1
        found_weight = 2000 * 9.81 * 2.4 * 0.29 * 0.1
        r = res["blocks/reaction"][0]
        expect(abs(r[1] - weight - found_weight) <= 1e-9 * weight, f"foundation reaction {r[1]} vs the weights {weight + found_weight}")
        expect(len(res["interfaces/blocks"]) == 1, f"interfaces: {res['interfaces/blocks']}")
        print(f"1e6-vertex polygon: {res['solver']['seconds_generate']:.2f} s to read and check, one interface, reaction {r[1]:.4f} N = the weights")


def keys():
    n = 100_000
    with tempfile.TemporaryDirectory() as tmp:
        blocks = [np.array([[0, -0.2], [1, -0.2], [1, -0.01], [0, -0.01]]), np.array([[0, 0], [1, 0], [1, 0.1], [0, 0.1]])]
        with h5py.File(os.path.join(tmp, "two.h5"), "w") as f:
            f["blocks/vertices"] = np.concatenate(blocks)
            f["blocks/offsets"] = np.array([0, 4, 8], np.int64)
            f["sets/foundation"] = np.array([0], np.int64)
            for k in range(n):  # sets may share blocks: 1e5 names for block 1
                f[f"sets/s{k}"] = np.array([1], np.int64)
        lines = ["geometry: {generator: file, file: two.h5}", "supports: {foundation: {u1: 0, u2: 0, w: 0}}", "loads:"]
        lines += [f"  s{k}: [0.001, -0.01, 0]" for k in range(n)]
        lines += ["output: {file: out.h5, xdmf: false}"]
        p = run(tmp, "\n".join(lines) + "\n", timeout=300)
        expect(p.returncode == 0, f"1e5 keys: exit {p.returncode}\n{p.stderr}")
        with h5py.File(os.path.join(tmp, "out.h5")) as f:  # not read(): it would load 1e5 sets
            res = {"blocks/load": f["blocks/load"][()], "blocks/reaction": f["blocks/reaction"][()],
                   "solver": dict(f["solver"].attrs)}
        load = res["blocks/load"][1]
        expect(abs(load[0] - 0.001 * n) <= 1e-9 * 0.001 * n and abs(load[1] + 0.01 * n) <= 1e-9 * 0.01 * n, f"1e5 loads summed to {load}")
        r = res["blocks/reaction"][0]
        expect(abs(r[0] + load[0]) <= 1e-9 * abs(load[0]) and abs(r[1] + load[1]) <= 1e-9 * abs(load[1]), f"reaction {r} vs load {load}")
        print(f"1e5 keys: {res['solver']['seconds_total']:.2f} s in all, loads summed to {load[0]:.6g}, {load[1]:.6g} N and balanced")


def memory():
    with tempfile.TemporaryDirectory() as tmp:
        p = run(tmp, "geometry: {generator: running_bond, running_bond: {courses: 20000, units_per_course: 5000}}\n"
                "supports: {foundation: {u1: 0, u2: 0, w: 0}}\noutput: {file: out.h5}\n", timeout=60)
        lines = [l for l in p.stderr.splitlines() if l.strip()]
        expect(p.returncode == 1 and len(lines) == 1, f"huge wall: exit {p.returncode}, stderr:\n{p.stderr}")
        for want in ("geometry.running_bond: 20000 courses of 5000 units", "needs about", "GB of memory", "this machine has available"):
            expect(want in lines[0], f"huge wall: {want!r} not in {lines[0]!r}")
        expect(os.listdir(tmp) == ["scene.yaml"], f"huge wall: files left: {os.listdir(tmp)}")
        print(lines[0])


if __name__ == "__main__":
    try:
        {"polygon": polygon, "keys": keys, "memory": memory}[sys.argv[1]]()
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
