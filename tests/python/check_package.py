"""The blockwall Python package (python/blockwall) on its own.

  writer     Geometry -> file -> read_geometry gives the blocks back (exact),
             clockwise blocks made counter-clockwise with corner 0 kept,
             depth, pairs, kn, kt, sets as given; every rejected input
             (BAD_INPUT) raises ValueError naming it and leaves no file
  corpus     the polygon and overlap checks are blockwall's: every file of
             tests/data whose defect is a polygon's or an overlap
             (CORPUS) is refused by the writer with a ValueError naming the
             block(s) and the defect, and the generators' walls
             (two_blocks, a running bond with an opening) are accepted and
             run
  reader     a two-block result read into Results: every field equal to the
             HDF5 dataset read with h5py; the pushover additions (/history,
             /steps/NNNNNN, /interfaces/state, /interfaces/plastic_jump)
             read when present (and drawn: plot_history, plot_cracks) (added here to a copy) and None / {} when
             absent; a geometry file is "not a blockwall result file"
  launcher   the command for 1 rank is blockwall alone, for 3 ranks mpiexec
             -n 3 with --oversubscribe (Open MPI); the environment carries
             OMPI_ALLOW_RUN_AS_ROOT(_CONFIRM); a bad scene raises RunError with
             blockwall's exit code and error line; solve() on 2 ranks gives
             the result of 1 rank (1e-12)
"""
import os
import shutil
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(HERE, "..", "geometry"))
from bwrun import EXE, MPIEXEC, Failure, budget, expect, rel_err  # noqa: E402
import blockwall as bw  # noqa: E402
import geomlib  # noqa: E402

SQUARE = bw.rectangle(0, 0, 1, 1)
BAD_INPUT = {
    "bow-tie": (dict(blocks=[[[0, 0], [1, 1], [1, 0], [0, 1]]]), "self-intersecting"),
    "two corners": (dict(blocks=[[[0, 0], [1, 0]]]), "at least 3"),
    "collinear": (dict(blocks=[[[0, 0], [1, 0], [2, 0]]]), "zero area"),
    "repeated corner": (dict(blocks=[[[0, 0], [1, 0], [1, 0], [1, 1]]]), "coincide"),
    "nan": (dict(blocks=[[[0, 0], [1, np.nan], [1, 1]]]), "non-finite"),
    "overlap": (dict(blocks=[SQUARE, SQUARE + 0.5]), "overlap"),
    "set out of range": (dict(blocks=[SQUARE], sets={"a": [1]}), "out of range"),
    "set name": (dict(blocks=[SQUARE], sets={"top beam": [0]}), "letters, digits"),
    "empty set": (dict(blocks=[SQUARE], sets={"a": []}), "empty"),
    "pair order": (dict(blocks=[SQUARE, SQUARE + [0, 1.01]], pairs=[(1, 0)]), "i < j"),
    "pair range": (dict(blocks=[SQUARE, SQUARE + [0, 1.01]], pairs=[(0, 2)]), "out of range"),
    "kn without pairs": (dict(blocks=[SQUARE], kn=[1.0], kt=[1.0]), "without interface pairs"),
    "kn length": (dict(blocks=[SQUARE, SQUARE + [0, 1.01]], pairs=[(0, 1)], kn=[1, 2], kt=[1]), "2 values for 1"),
    "kt zero": (dict(blocks=[SQUARE, SQUARE + [0, 1.01]], pairs=[(0, 1)], kn=[1.0], kt=[0.0]), "kt of interface 0"),
    "depth": (dict(blocks=[SQUARE], depth=-1.0), "depth must be > 0"),
}
# file of tests/data/broken_<name>.h5: what the writer's ValueError must name
# (the block or blocks at fault and the defect, as blockwall's own error line
# does: tests/data/make_broken.py), so that a refusal for another reason
# (a defect the file does not have, an error in the writer) does not pass
CORPUS = {"bowtie": ["block 1 ", "self-intersecting"], "spike": ["block 1 ", "self-intersecting"],
          "fold_back": ["block 1 ", "self-intersecting"], "zero_area": ["block 1 ", "zero area"],
          "overlap": ["blocks 0 and 1 overlap"], "contained": ["blocks 0 and 1 overlap"],
          "duplicate_block": ["blocks 1 and 2 overlap"], "duplicate_vertex": ["block 0 ", "corners 1 and 2 coincide"],
          "closed_polygon": ["block 1 ", "last corner repeats its first"], "two_vertices": ["block 1 ", "2 corners", "at least 3"],
          "vertex_nan": ["block 1", "non-finite"], "vertex_inf": ["block 0", "non-finite"]}


def writer():
    g = bw.Geometry(depth=0.25)
    base = g.add_block(bw.rectangle(0, -0.1, 1, 0), sets=["base"])
    cw = np.array([[0, 0.01], [0, 0.3], [1, 0.3], [1, 0.01]])  # clockwise
    top = g.add_block(cw, sets=["top", "all"])
    g.add_set("all", [base])
    g.add_interface(base, top, kn=2e9, kt=1e9)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "g.h5")
        g.write(path)
        back = bw.read_geometry(path)
        expect(os.listdir(tmp) == ["g.h5"], f"files left: {os.listdir(tmp)}")
        with h5py.File(path) as f:
            expect(f["blocks/offsets"].dtype == np.int64 and f["blocks/vertices"].dtype == np.float64,
                   "dataset types")
    expect(np.array_equal(back.blocks[0], g.blocks[0]), "block 0 changed")
    expect(np.array_equal(back.blocks[1], cw[[0, 3, 2, 1]]), f"clockwise block not reoriented from corner 0: {back.blocks[1]}")
    expect(back.depth == 0.25 and back.pairs == [(0, 1)] and back.kn == [2e9] and back.kt == [1e9], "attributes")
    expect(back.sets == {"base": [0], "top": [1], "all": [1, 0]}, f"sets {back.sets}")
    for name, (kw, words) in BAD_INPUT.items():
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "g.h5")
            blocks = kw.pop("blocks")
            try:
                bw.write_geometry(path, blocks, **kw)
                raise Failure(f"{name}: accepted")
            except ValueError as e:
                expect(words in str(e), f"{name}: {words!r} not in {e}")
                print(f"{name}: {e}")
            expect(os.listdir(tmp) == [], f"{name}: files left {os.listdir(tmp)}")


def corpus():
    data = os.path.join(ROOT, "tests", "data")
    for name, words in CORPUS.items():
        with h5py.File(os.path.join(data, f"broken_{name}.h5")) as f:
            v, off = f["blocks/vertices"][()], f["blocks/offsets"][()]
        blocks = [v[off[b]:off[b + 1]] for b in range(len(off) - 1)]
        with tempfile.TemporaryDirectory() as tmp:
            try:
                bw.write_geometry(os.path.join(tmp, "g.h5"), blocks)
                raise Failure(f"broken_{name}.h5 accepted by the writer")
            except ValueError as e:
                missing = [w for w in words if w not in str(e)]
                expect(not missing, f"broken_{name}.h5 refused, but the message does not name {missing}: {e}")
                print(f"broken_{name}.h5 refused: {e}")
    for what, (blocks, _, sets) in (("two blocks", geomlib.two_blocks()), ("running bond", geomlib.running_bond(6, 4))):
        with tempfile.TemporaryDirectory() as tmp:
            bw.write_geometry(os.path.join(tmp, "g.h5"), blocks, sets=sets)
            print(f"{what}: {len(blocks)} blocks accepted")


def reader():
    scene = os.path.join(ROOT, "tests", "paper", "two_blocks.yaml")
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "r.h5")
        bw.run(scene, ["-output_file", out], exe=EXE, timeout=budget())
        res = bw.read(out)
        fields = {"vertices": "blocks/vertices", "offsets": "blocks/offsets", "centroid": "blocks/centroid",
                  "displacement": "blocks/displacement", "reaction": "blocks/reaction", "load": "blocks/load",
                  "prescribed": "blocks/prescribed", "pairs": "interfaces/blocks", "center": "interfaces/center",
                  "angle": "interfaces/angle", "length": "interfaces/length", "kn": "interfaces/kn",
                  "kt": "interfaces/kt", "relative": "interfaces/relative_displacement",
                  "resultant": "interfaces/resultant", "stress": "interfaces/stress"}
        with h5py.File(out) as f:
            for field, name in fields.items():
                expect(np.array_equal(getattr(res, field), f[name][()].reshape(getattr(res, field).shape)),
                       f"{field} != /{name}")
            expect(res.sets["top"].tolist() == [1] and res.m == f.attrs["m"] and res.depth == f.attrs["depth"], "sets, m, depth")
            expect(res.solver["method_used"] == f["solver"].attrs["method_used"].decode()
                   if isinstance(f["solver"].attrs["method_used"], bytes) else f["solver"].attrs["method_used"], "solver")
        expect(res.state is None and res.plastic_jump is None and res.history is None and res.steps == {},
               "pushover fields present in a linear result")
        copy = os.path.join(tmp, "p.h5")
        shutil.copy(out, copy)
        I, m = res.ninterfaces, res.m
        rng = np.random.default_rng(1)
        hist = {"load_factor": np.linspace(0, 1, 4), "monitor": np.linspace(0, 1e-3, 4),
                "iterations": np.array([0, 3, 4, 5], np.int32), "residual": np.array([0, 1e-9, 2e-9, 1e-9])}
        step = {"blocks/displacement": rng.random((2, 3)), "blocks/reaction": rng.random((2, 3)),
                "interfaces/resultant": rng.random((I, 3)), "interfaces/relative_displacement": rng.random((I, 3)),
                "interfaces/state": rng.integers(0, 4, (I, m)).astype(np.int8), "interfaces/stress": rng.random((I, m, 2))}
        state, jump = rng.integers(0, 4, (I, m)).astype(np.int8), rng.random((I, m, 2))
        with h5py.File(copy, "r+") as f:
            for k, v in hist.items():
                f[f"history/{k}"] = v
            for k, v in step.items():
                f[f"steps/000003/{k}"] = v
            f["interfaces/state"], f["interfaces/plastic_jump"] = state, jump
            f["solver"].attrs["peak_load_factor"] = 1.0
            f["solver"].attrs["stop_reason"] = "target reached"
        p = bw.read(copy)
        expect(all(np.array_equal(p.history[k], v) for k, v in hist.items()), "history")
        s = p.steps[3]
        expect(np.array_equal(s.displacement, step["blocks/displacement"]) and np.array_equal(s.state, step["interfaces/state"])
               and np.array_equal(s.stress, step["interfaces/stress"]) and np.array_equal(s.relative, step["interfaces/relative_displacement"]),
               "step 3")
        expect(np.array_equal(p.state, state) and np.array_equal(p.plastic_jump, jump), "state, plastic_jump")
        hp = bw.plot_history(p)
        expect(np.array_equal(hp.load_factor, hist["load_factor"]) and np.array_equal(hp.monitor, hist["monitor"]),
               "plot_history drew other numbers")
        # the crack pattern: the peak (λ largest at step 3, written) and the end, counted as stored
        for at, want in (("peak", step["interfaces/state"]), ("end", state)):
            cp = bw.plot_cracks(p, at)
            expect(cp.step == 3 and np.array_equal(cp.state, want)
                   and np.array_equal(cp.counts, np.bincount(want.ravel(), minlength=4)),
                   f"plot_cracks {at}: step {cp.step}, counts {cp.counts}")
        expect(p.solver["stop_reason"] == "target reached", "new /solver attributes")
        geo = os.path.join(tmp, "g.h5")
        bw.write_geometry(geo, [SQUARE])
        try:
            bw.read(geo)
            raise Failure("a geometry file read as a result")
        except ValueError as e:
            expect("not a blockwall result file" in str(e), str(e))
    print(f"two blocks: {len(fields)} datasets as stored; pushover additions read when present, None when absent")


def launcher():
    scene = os.path.join(ROOT, "tests", "paper", "two_blocks.yaml")
    one = bw.command(scene, ["-discretization_m", 4], 1, exe=EXE)
    expect(one[:3] == [EXE, "-scene", scene] and one[3:] == ["-discretization_m", "4"], f"1 rank: {one}")
    three = bw.command(scene, [], 3, exe=EXE, mpiexec=MPIEXEC)
    expect(three[0] == MPIEXEC and three[-3:] == [EXE, "-scene", scene] and "-n" in three
           and three[three.index("-n") + 1] == "3", f"3 ranks: {three}")
    if bw.launch.is_open_mpi(MPIEXEC):
        expect("--oversubscribe" in three, f"Open MPI without --oversubscribe: {three}")
    env = bw.environment({})
    expect(env.get("OMPI_ALLOW_RUN_AS_ROOT") == "1" and env.get("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM") == "1", f"{env}")
    try:
        bw.run(scene, ["-joints_E", "-1"], exe=EXE, timeout=budget())
        raise Failure("a bad option did not raise")
    except bw.RunError as e:
        expect(e.result.returncode == 1 and "-joints_E must be > 0" in e.result.stderr, f"{e.result.returncode}: {e.result.stderr}")
    a = bw.solve(scene, exe=EXE, timeout=budget())
    b = bw.solve(scene, ranks=2, exe=EXE, mpiexec=MPIEXEC, timeout=budget())
    e = rel_err(b.displacement, a.displacement)
    expect(b.solver["ranks"] == 2 and e < 1e-12, f"2 ranks: {b.solver['ranks']}, {e:.1e}")
    print(f"commands {one[:3]}..., {three[:4]}...; RunError on a bad option; 2 ranks vs 1: {e:.1e}")


if __name__ == "__main__":
    try:
        {"writer": writer, "corpus": corpus, "reader": reader, "launcher": launcher}[sys.argv[1]]()
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
