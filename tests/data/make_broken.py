"""The corpus of broken geometry files, tests/data/broken_<case>.h5, one
defect each, and what blockwall's one error line must say about it.

    python3 tests/data/make_broken.py [DIR]      (DIR: tests/data)

rewrites the files; tests/geometry/check_broken.py runs blockwall on each
(scene: geometry.generator file, mortar joints e = 0.01) and checks the exit
code, the single stderr line (it must hold every string of WANT, and the
file's name), and that no output appeared. Each file starts from the
paper's two blocks (l = 0.2, a = 0.1, e = 0.01, sets bottom and top) and
breaks one thing."""
import os
import sys

import h5py
import numpy as np

L, A, E = 0.2, 0.1, 0.01
BOTTOM = [[0, 0], [L, 0], [L, A], [0, A]]
TOP = [[0, A + E], [L, A + E], [L, 2 * A + E], [0, 2 * A + E]]


def base(blocks=None, pairs=None, sets=None):
    """Datasets of a geometry file: name -> array (None: left out)."""
    blocks = blocks if blocks is not None else [BOTTOM, TOP]
    d = {"blocks/vertices": np.array([v for b in blocks for v in b], float),
         "blocks/offsets": np.concatenate([[0], np.cumsum([len(b) for b in blocks])]).astype(np.int64)}
    if pairs is not None:
        d["interfaces/blocks"] = np.array(pairs, np.int64).reshape(-1, 2)
    for name, members in (sets if sets is not None else {"bottom": [0], "top": [1]}).items():
        d[f"sets/{name}"] = np.array(members, np.int64)
    return d


def with_(d, **changes):
    d = dict(d)
    for k, v in changes.items():
        d[k.replace("__", "/")] = v
    return d


def vertex(i, value):
    d = base()
    d["blocks/vertices"][i] = value
    return d


NAN, INF = float("nan"), float("inf")
NOTCHED = [[0, 0], [1, 0], [1, 0.5], [0.6, 0.5], [0.6, 0.3], [0.4, 0.3], [0.4, 0.5], [0, 0.5]]

# name: (datasets or a callable writing the file, root attributes, [strings the error line must hold])
CASES = {
    "vertex_nan": (vertex(5, [NAN, A + E]), {}, ["/blocks/vertices", "block 1", "vertex row 5", "not finite"]),
    "vertex_inf": (vertex(2, [L, INF]), {}, ["/blocks/vertices", "block 0", "vertex row 2", "not finite"]),
    "duplicate_vertex": (base([[BOTTOM[0], BOTTOM[1], BOTTOM[1], BOTTOM[2], BOTTOM[3]], TOP]), {},
                         ["/blocks/vertices", "block 0", "duplicate vertices", "rows 1 and 2"]),
    "closed_polygon": (base([BOTTOM, TOP + [TOP[0]]]), {}, ["/blocks/vertices", "block 1", "repeats its first", "duplicate vertices"]),
    "two_vertices": (base([BOTTOM, TOP[:2]]), {}, ["/blocks/offsets", "block 1 has 2 vertices", "at least 3"]),
    "one_vertex_block": (base([BOTTOM, TOP, [[5, 5]]]), {}, ["block 2 has 1 vertices", "at least 3"]),
    "bowtie": (base([BOTTOM, [TOP[0], TOP[2], TOP[1], TOP[3]]]), {}, ["/blocks/vertices", "block 1 is self-intersecting", "cross"]),
    "spike": (base([BOTTOM, [TOP[0], TOP[1], [L + 0.1, A + E], TOP[1], TOP[2], TOP[3]]]), {},
              ["/blocks/vertices", "block 1", "self-intersecting"]),
    "fold_back": (base([BOTTOM, [TOP[0], TOP[1], TOP[2], [L, A + E + 0.02], [L, 2 * A + E + 0.05], TOP[3]]]), {},
                  ["/blocks/vertices", "block 1 is self-intersecting", "cross or touch"]),
    "zero_area": (base([BOTTOM, [[0, 0.3], [0.1, 0.3], [0.2, 0.3]]]), {}, ["/blocks/vertices", "block 1", "zero area"]),
    "overlap": (base([BOTTOM, [[0.1, 0.05], [0.3, 0.05], [0.3, 0.2], [0.1, 0.2]]]), {},
                ["/blocks/vertices", "blocks 0 and 1 overlap", "m^2"]),
    "contained": (base([[[-1, -1], [1, -1], [1, 1], [-1, 1]], [[0, 0], [0.1, 0], [0.1, 0.1], [0, 0.1]]]), {},
                  ["blocks 0 and 1 overlap", "100% of block 1"]),
    "duplicate_block": (base([BOTTOM, TOP, TOP]), {}, ["blocks 1 and 2 overlap"]),
    "interface_out_of_range": (base(pairs=[[0, 2]]), {}, ["/interfaces/blocks", "interface 0 names block 2, out of range [0, 2)"]),
    "interface_negative": (base(pairs=[[-1, 1]]), {}, ["/interfaces/blocks", "interface 0 names block -1"]),
    "interface_self": (base(pairs=[[1, 1]]), {}, ["/interfaces/blocks", "interface 0 joins block 1 to itself"]),
    "interface_reversed": (base(pairs=[[1, 0]]), {}, ["/interfaces/blocks", "interface 0 is (1, 0) with i > j", "i < j"]),
    "interface_duplicate": (base(pairs=[[0, 1], [0, 1]]), {}, ["/interfaces/blocks", "interface 1 repeats the pair (0, 1) of interface 0", "duplicate pair"]),
    "interface_not_facing": (base([BOTTOM, TOP, [[0, 0.5], [L, 0.5], [L, 0.6], [0, 0.6]]], pairs=[[0, 1], [0, 2], [1, 2]]), {},
                             ["/interfaces/blocks", "interface 1 joins blocks 0 and 2", "no facing edges"]),
    "interface_listed_once": (base([NOTCHED, [[0, 0.51], [1, 0.51], [1, 0.8], [0, 0.8]]], pairs=[[0, 1]]), {},
                              ["/interfaces/blocks", "blocks 0 and 1 face each other along 2 separate segments", "listed 1 time", "interface 0"]),
    "interfaces_shape": (with_(base(), interfaces__blocks=np.array([[0, 1, 2]], np.int64)), {}, ["/interfaces/blocks has shape (1, 3)", "(I, 2)"]),
    "interfaces_float": (with_(base(), interfaces__blocks=np.array([[0.0, 1.0]])), {}, ["/interfaces/blocks holds floating-point values", "int64"]),
    "kn_negative": (with_(base(pairs=[[0, 1]]), interfaces__kn=np.array([-1.0])), {}, ["/interfaces/kn", "interface 0", "kn = -1", "> 0"]),
    "kt_zero": (with_(base(pairs=[[0, 1]]), interfaces__kt=np.array([0.0])), {}, ["/interfaces/kt", "interface 0", "kt = 0"]),
    "kn_nan": (with_(base(pairs=[[0, 1]]), interfaces__kn=np.array([NAN])), {}, ["/interfaces/kn", "interface 0", "kn = nan"]),
    "kn_length": (with_(base(pairs=[[0, 1]]), interfaces__kn=np.array([1e11, 1e11])), {},
                  ["/interfaces/kn has 2 values but /interfaces/blocks has 1 interfaces"]),
    "kn_without_blocks": (with_(base(), interfaces__kn=np.array([1e11])), {}, ["/interfaces/kn is given without /interfaces/blocks"]),
    "set_out_of_range": (base(sets={"bottom": [0], "top": [5]}), {}, ["/sets/top", "member 0 is block 5, out of range [0, 2)"]),
    "set_negative": (base(sets={"bottom": [0, -1], "top": [1]}), {}, ["/sets/bottom", "member 1 is block -1"]),
    "set_repeated": (base(sets={"bottom": [0], "top": [1, 1]}), {}, ["/sets/top lists block 1 more than once"]),
    "set_shape": (base(sets={"bottom": [0], "top": [[1, 0]]}), {}, ["/sets/top has shape (1, 2)"]),
    "set_name": (base(sets={"bottom": [0], "top beam": [1]}), {}, ["/sets/top beam", "letters, digits and '_'"]),
    "sets_not_group": (with_({k: v for k, v in base().items() if not k.startswith("sets")}, sets=np.array([0], np.int64)), {},
                       ["/sets is not a group"]),
    "vertices_shape": (with_(base(), blocks__vertices=np.zeros((8, 4))), {}, ["/blocks/vertices has shape (8, 4)", "(V, 2)", "(V, 3)"]),
    "vertices_1d": (with_(base(), blocks__vertices=np.zeros(16)), {}, ["/blocks/vertices has shape (16,)"]),
    "vertices_int": (with_(base(), blocks__vertices=np.zeros((8, 2), np.int64)), {}, ["/blocks/vertices holds integer values"]),
    "offsets_float": (with_(base(), blocks__offsets=np.array([0.0, 4.0, 8.0])), {}, ["/blocks/offsets holds floating-point values"]),
    "offsets_decreasing": (with_(base([BOTTOM, TOP, TOP]), blocks__offsets=np.array([0, 8, 4, 12], np.int64)), {},
                           ["/blocks/offsets is not increasing", "offsets[2] = 4 < offsets[1] = 8", "block 1"]),
    "offsets_end": (with_(base(), blocks__offsets=np.array([0, 4, 7], np.int64)), {},
                    ["/blocks/offsets[2] = 7 (the last) must equal the number of rows of /blocks/vertices, 8"]),
    "offsets_start": (with_(base(), blocks__offsets=np.array([1, 4, 8], np.int64)), {}, ["/blocks/offsets[0] = 1", "must be 0"]),
    "offsets_empty": (with_(base(), blocks__offsets=np.array([0], np.int64)), {}, ["/blocks/offsets has 1 entries", "at least one block"]),
    "no_vertices": ({k: v for k, v in base().items() if k != "blocks/vertices"}, {}, ["no dataset /blocks/vertices"]),
    "no_offsets": ({k: v for k, v in base().items() if k != "blocks/offsets"}, {}, ["no dataset /blocks/offsets"]),
    "unconnected_detected": (base([BOTTOM, TOP, [[1, 0], [1.2, 0], [1.2, 0.1], [1, 0.1]]], sets={"bottom": [0, 2]}), {},
                             ["/blocks", "block 2 (1 block) is unconnected", "detected", "e + tolerance"]),
    "unconnected_explicit": (base([BOTTOM, TOP, [[0, 2 * A + 2 * E], [L, 2 * A + 2 * E], [L, 0.4], [0, 0.4]]], pairs=[[0, 1]]), {},
                             ["/blocks", "block 2 (1 block) is unconnected", "/interfaces/blocks names no pair with it"]),
    "gap_too_wide": (base([BOTTOM, [[x, y + E] for x, y in TOP]]), {}, ["blocks 0, 1 (2 blocks) are unconnected", "e + tolerance"]),
    "depth_negative": (base(), {"depth": -0.1}, ["root attribute depth = -0.1", "> 0"]),
    "depth_string": (base(), {"depth": "0.1"}, ["root attribute depth must be one float64"]),
    "not_hdf5": ("this is not an HDF5 file\n", {}, ["is not an HDF5 file"]),
}


def write(path, datasets, attrs):
    if isinstance(datasets, str):
        with open(path, "w") as f:
            f.write(datasets)
        return
    with h5py.File(path, "w") as f:
        for name, value in datasets.items():
            f[name] = value
        for k, v in attrs.items():
            f.attrs[k] = v


def path(out, name):
    return os.path.join(out, f"broken_{name}.h5")


def main(out):
    os.makedirs(out, exist_ok=True)
    for name, (datasets, attrs, _) in CASES.items():
        write(path(out, name), datasets, attrs)
    print(f"{len(CASES)} files broken_*.h5 in {out}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__)))
