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


# Files with two or more defects, far apart in the file: read on several
# ranks each defect is found by another rank (blocks, rows and set members
# are read in ranges, pairs are decided by the ranks of their regions), and
# the line must name the one the serial reader finds first, which is not
# always the lowest block: offsets before the last offset, pair indices of
# every row before any kn, kn before kt, the sets in name order (a set's
# members in range before its repeats), 2D listed pairs by (i, j), 3D
# listed pairs by row.
def column(n, x0=0.0):
    """n blocks L x A stacked with joints E: block k at level k."""
    return [[[x0, k * (A + E)], [x0 + L, k * (A + E)], [x0 + L, k * (A + E) + A], [x0, k * (A + E) + A]] for k in range(n)]


def columns2(levels):
    """Two columns side by side (joint E between them): block 2 m + c at level m, column c."""
    return [[[c * (L + E), m * (A + E)], [c * (L + E) + L, m * (A + E)], [c * (L + E) + L, m * (A + E) + A], [c * (L + E), m * (A + E) + A]]
            for m in range(levels) for c in range(2)]


def box3(x0, y0, z0, x1, y1, z1):
    return [[x, y, z] for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)]


def column3(n):
    """n boxes L x A x L stacked along X2 with joints E."""
    return [box3(0, k * (A + E), 0, L, k * (A + E) + A, L) for k in range(n)]


def moved(blocks, k, dy):
    return [[[x, y + dy] for x, y in b] if i == k else b for i, b in enumerate(blocks)]


def with_block(blocks, k, block):
    return [block if i == k else b for i, b in enumerate(blocks)]


def offsets_twice():
    d = base(column(6), sets={"bottom": [0]})
    o = d["blocks/offsets"].copy()
    o[2], o[6] = 3, 23  # decreasing at block 1 (rank 0 of 3), the last wrong (rank 2)
    d["blocks/offsets"] = o
    return d


def vertex_nan_twice():
    d = base(column(6), sets={"bottom": [0]})
    d["blocks/vertices"][17] = [NAN, 0.0]  # block 4
    d["blocks/vertices"][6] = [0.0, INF]  # block 1
    return d


UNIT_X = [[0, 0], [L, 0], [L, A], [0, A]]
BOWTIE = [[0, 0], [L, A], [L, 0], [0, A]]
ISOLATED = [2, 3, 4, 5, 6, 8, 9, 10, 11, 12, 13, 15, 16, 17]  # 14 blocks far apart, on every rank of 3
CONNECTED = [0, 1, 7, 14, 18, 19]


def unconnected_many():
    blocks, level = [], 0
    for b in range(20):
        if b in CONNECTED:
            blocks.append([[x, y + level * (A + E)] for x, y in UNIT_X])
            level += 1
        else:
            blocks.append([[x + 1 + b, y] for x, y in UNIT_X])
    return base(blocks, sets={"bottom": [0]})


def pairs_and_kn():
    d = base(column(6), pairs=[[0, 1], [1, 2], [2, 3], [3, 4], [4, 5], [2, 9]], sets={"bottom": [0]})
    d["interfaces/kn"] = np.array([-1.0, 1e11, 1e11, 1e11, 1e11, 1e11])  # row 0: read by rank 0; the index fault of row 5 comes first
    return d


def kn_before_kt():
    d = base(column(6), pairs=[[0, 1], [1, 2], [2, 3], [3, 4], [4, 5]], sets={"bottom": [0]})
    d["interfaces/kn"] = np.array([1e11, 1e11, 1e11, 1e11, 0.0])
    d["interfaces/kt"] = np.array([1e11, -5.0, 1e11, 1e11, 1e11])
    return d


# two columns: listed vertical and horizontal neighbours, and two pairs
# that do not face: (1, 7) far apart (row 0), (0, 3) diagonal neighbours
# (last row): the serial reader takes 2D pairs in (i, j) order
NEIGHBOURS2 = [[2 * m + c, 2 * m + c + 2] for m in range(3) for c in range(2)] + [[2 * m, 2 * m + 1] for m in range(4)]


def blocks3(blocks, pairs=None, sets=None):
    d = {"blocks/vertices": np.array([v for b in blocks for v in b], float),
         "blocks/offsets": np.concatenate([[0], np.cumsum([len(b) for b in blocks])]).astype(np.int64)}
    if pairs is not None:
        d["interfaces/blocks"] = np.array(pairs, np.int64).reshape(-1, 2)
    for name, members in (sets or {"bottom": [0]}).items():
        d[f"sets/{name}"] = np.array(members, np.int64)
    return d


def planar3(k):
    b = box3(0, k * (A + E), 0, L, k * (A + E) + A, L)
    return [b[0], b[1], b[2], b[3]]  # the bottom face only


CASES.update({
    "offsets_twice": (offsets_twice(), {}, ["/blocks/offsets is not increasing", "offsets[2] = 3 < offsets[1] = 4", "block 1"]),
    "vertex_nan_twice": (vertex_nan_twice(), {}, ["/blocks/vertices", "block 1: vertex row 6 is not finite"]),
    "polygons_twice": (base(with_block(with_block(column(6), 4, [[0, 0.5], [0.1, 0.5], [0.2, 0.5]]), 1, [[0, 0.11], [L, 0.21], [L, 0.11], [0, 0.21]]),
                            sets={"bottom": [0]}), {}, ["/blocks/vertices", "block 1 is self-intersecting"]),
    "overlap_twice": (base(moved(moved(column(8), 6, 0.05), 2, 0.05), sets={"bottom": [0]}), {}, ["/blocks/vertices", "blocks 2 and 3 overlap"]),
    "pairs_before_kn": (pairs_and_kn(), {}, ["/interfaces/blocks", "interface 5 names block 9, out of range [0, 6)"]),
    "kn_before_kt": (kn_before_kt(), {}, ["/interfaces/kn", "interface 4 (blocks 4, 5) has kn = 0"]),
    "sets_range_first": (base(column(6), sets={"a": [0, 7], "b": [1, 1]}), {}, ["/sets/a: member 1 is block 7, out of range [0, 6)"]),
    "sets_repeat_first": (base(column(6), sets={"a": [2, 3, 2], "b": [9]}), {}, ["/sets/a lists block 2 more than once"]),
    "not_facing_twice": (base(columns2(4), pairs=[[1, 7]] + NEIGHBOURS2 + [[0, 3]], sets={"bottom": [0, 1]}), {},
                         ["/interfaces/blocks", "interface 11 joins blocks 0 and 3, which have no facing edges"]),
    "unconnected_many": (unconnected_many(), {}, ["/blocks", "blocks 2, 3, 4, 5, 6, 8, 9, 10, 11, 12, 13, 15, ... (14 blocks) are unconnected"]),
    "hulls_twice_3d": (blocks3(with_block(with_block(column3(6), 4, planar3(4)), 1, column3(6)[1][:3])), {},
                       ["/blocks/vertices", "block 1 has 3 vertices", "at least 4"]),
    "overlap_twice_3d": (blocks3([[[x, y + (0.05 if k in (2, 6) else 0), z] for x, y, z in b] for k, b in enumerate(column3(8))]), {},
                         ["/blocks/vertices", "blocks 2 and 3 overlap", "m^3"]),
    # rows by the serial order: row 5 repeats the pair (4, 5) of row 2 (its
    # first block on the last rank of 3), row 6 joins blocks 0 and 2, which
    # do not face (on rank 0)
    "listed_rows_3d": (blocks3(column3(6), pairs=[[0, 1], [1, 2], [4, 5], [2, 3], [3, 4], [4, 5], [0, 2]]), {},
                       ["/interfaces/blocks", "interface 5 repeats the pair (4, 5) of interface 2"]),
})


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
