"""Geometry files read in parallel (issue 29, item 1): each rank reads its
range of blocks, rows and set members, and the pairwise work is shared by
regions of space; the result must be the serial reader's, exactly.

  walls2d CASE   a 2D geometry file run on 1, 2, 3 and 5 ranks: the output
                 files' geometry (/blocks vertices, offsets, centroid, load,
                 prescribed; /interfaces blocks, center, angle, length, kn,
                 kt; every /sets/NAME) are identical, bit for bit, to the
                 1-rank run's, and the 1-rank run is the construction's
                 (geomlib: the pairs, the rows of a listed file, the sets as
                 written). Interfaces cross every rank's range boundary
                 (checked). CASE:
                   shuffled  a running-bond wall, its blocks in a random
                             order (each rank's range scattered over the
                             wall), interfaces detected; its top beam's
                             lower edge split by extra vertices (collinear
                             pieces merged into one interface) and notched
                             over one unit (two interfaces of one pair)
                   listed    the same wall with /interfaces/blocks in a
                             random row order, kn and kt per row
                   listed_kn the same with kn only (kt: the joint law's)
                   bands     the wall in its natural order: ranges are
                             bands of courses
                   arch      the arch of pentagons and hexagons, shuffled
  walls3d CASE   the same for 3D files (the wall's blocks extruded to
                 prisms, shuffled): /interfaces blocks, center, frame, area,
                 vertices, offsets, kn, kt; CASE detected | listed
  (the broken files of tests/data on 3 ranks give the 1-rank run's line:
                 tests/geometry/check_broken.py part K, the tests
                 geometry.parallel_read.broken_K)
  memory [distribute]
                 a rank does not hold the whole file: test_geometry on a
                 1e5-block running-bond file (8.8 MB), each rank's peak
                 resident memory measured from outside (/usr/bin/time, one
                 per rank), less M0, the largest rank's peak on a two-block
                 file on as many ranks: the largest rank's on 8 ranks must
                 be below 0.6 of the largest rank's on 2 (a reader that
                 splits the work gives about 2/8 = 0.25; rank 0 reading the
                 whole file, about 1). With `distribute`, the geometry is
                 also partitioned and moved (BwGeometryDistribute).
"""
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "data")
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, HERE)
sys.path.insert(0, DATA)
from bwrun import ENV, MPIEXEC, Failure, call, expect, read, run  # noqa: E402
import geomlib  # noqa: E402
import blockwall as bw  # noqa: E402  (bwrun put this checkout's python/ on sys.path)

RANKS = (1, 2, 3, 5)
GEOMETRY2 = ("blocks/vertices", "blocks/offsets", "blocks/centroid", "blocks/load", "blocks/prescribed",
             "interfaces/blocks", "interfaces/center", "interfaces/angle", "interfaces/length", "interfaces/kn", "interfaces/kt")
GEOMETRY3 = ("blocks/vertices", "blocks/offsets", "blocks/centroid", "blocks/load", "blocks/prescribed",
             "interfaces/blocks", "interfaces/center", "interfaces/frame", "interfaces/area", "interfaces/vertices",
             "interfaces/offsets", "interfaces/kn", "interfaces/kt")
LU, HU, E = 0.21, 0.052, 0.01
SCENE3 = """geometry: {{generator: file, file: {file}}}
joints: {{law: mortar, thickness: 0.01, E: 1.0e9, nu: 0.2}}
discretization: {{m: 2, m_b: 2}}
supports:
  foundation: {{u1: 0, u2: 0, u3: 0, w1: 0, w2: 0, w3: 0}}
loads:
  top_beam: [1000, -2000, 300, 0, 0, 0]
output: {{stresses: false, xdmf: false}}
"""


def shuffle(blocks, sets, seed):
    """The blocks in a random order: (blocks, new id of each old block, sets
    renamed and each list in a random order)."""
    rng = np.random.default_rng(seed)
    perm = rng.permutation(len(blocks))
    new_of = np.empty(len(blocks), int)
    new_of[perm] = np.arange(len(blocks))
    sets = {k: [int(new_of[b]) for b in v] for k, v in sets.items()}
    for k in sorted(sets):
        rng.shuffle(sets[k])
    return [blocks[o] for o in perm], new_of, sets


def beam_with_extras(blocks, inter):
    """The top beam's lower edge split by a vertex over the middle of every
    other unit below it (two collinear pieces: one interface) and notched
    0.02 deep over the middle third of the unit in the middle (two
    interfaces of that pair). Returns the pair that has two."""
    beam = len(blocks) - 1
    below = sorted(((i, g[0] - l / 2, g[0] + l / 2) for i, j, g, t, l in inter if j == beam), key=lambda u: u[1])
    x0, y0 = blocks[beam][0]
    x1, y1 = blocks[beam][2]
    notched = below[len(below) // 2]
    bottom = [(x0, y0)]
    for k, (i, a, b) in enumerate(below):
        if i == notched[0]:
            na, nb = a + (b - a) / 3, a + 2 * (b - a) / 3
            bottom += [(na, y0), (na, y0 + 0.02), (nb, y0 + 0.02), (nb, y0)]
        elif k % 2:
            bottom.append(((a + b) / 2, y0))
    bottom.append((x1, y0))
    blocks[beam] = np.array(bottom + [(x1, y1), (x0, y1)])
    return notched[0], beam


def crosses_every_boundary(pairs, nb, what):
    for np_ in RANKS[1:]:
        for r in range(1, np_):
            c = nb * r // np_
            expect(np.any((pairs[:, 0] < c) & (pairs[:, 1] >= c)), f"{what}: no interface crosses the boundary of rank {r} of {np_} (block {c})")


def same_everywhere(scene, keys, what, nsets, tmp):
    """The scene on every rank count; returns the 1-rank run's datasets."""
    ref = None
    for np_ in RANKS:
        out = os.path.join(tmp, f"out_{np_}.h5")
        run(scene, ["-output_file", out], np_)
        got = read(out)
        if ref is None:
            ref = got
            sets = [k for k in got if k.startswith("sets/")]
            expect(len(sets) == nsets, f"{what}: {len(sets)} sets written, expected {nsets}")
            continue
        for key in keys + tuple(k for k in ref if k.startswith("sets/")):
            a, b = ref[key], got[key]
            expect(a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b),
                   f"{what}, {np_} ranks: {key} differs from 1 rank's ({a.shape} vs {b.shape}, "
                   f"{np.count_nonzero(a != b) if a.shape == b.shape else 'all'} entries)")
        print(f"{what}: {np_} ranks: {len(got['interfaces/blocks'])} interfaces, {len(keys)} datasets and the sets as on 1 rank")
    return ref


def walls2d(case):
    supports, loads = {"foundation": {"u1": 0, "u2": 0, "w": 0}}, {"top_beam": (1000, -2000, 0)}
    if case == "arch":
        blocks, inter, sets = geomlib.arch(nv=13)
        supports, loads = {"springers": {"u1": 0, "u2": 0, "w": 0}}, {"crown": (0, -1000, 0)}
        extra = None
    else:
        blocks, inter, sets = geomlib.running_bond(12, 8, LU, HU, E)
        extra = beam_with_extras(blocks, inter) if case != "bands" else None
    pairs = [(i, j) for i, j, *_ in inter]
    new_of = np.arange(len(blocks))
    if case != "bands":
        blocks, new_of, sets = shuffle(blocks, sets, seed=29)
    want = sorted(tuple(sorted((int(new_of[i]), int(new_of[j])))) for i, j in pairs)
    if extra:  # the notched pair twice
        want = sorted(want + [tuple(sorted((int(new_of[extra[0]]), int(new_of[extra[1]]))))])
    kw = {}
    if case.startswith("listed"):
        rng = np.random.default_rng(7)
        rows = np.array(want)[rng.permutation(len(want))]
        kw = {"pairs": rows, "kn": rng.uniform(1e9, 2e9, len(rows)), "kt": rng.uniform(4e8, 8e8, len(rows))}
        if case == "listed_kn":
            del kw["kt"]
    with tempfile.TemporaryDirectory() as tmp:
        geo, scene = os.path.join(tmp, "wall.h5"), os.path.join(tmp, "wall.yaml")
        geomlib.write_geometry(geo, blocks, sets=sets, **kw)
        geomlib.write_scene(scene, geo, supports=supports, loads=loads, m=2)
        ref = same_everywhere(scene, GEOMETRY2, f"2D {case}", len(sets), tmp)
    got = ref["interfaces/blocks"]
    if case.startswith("listed"):
        expect(np.array_equal(got, kw["pairs"]), f"{case}: /interfaces/blocks are not the file's rows")
        expect(np.array_equal(ref["interfaces/kn"], kw["kn"]), f"{case}: kn are not the file's")
        # the law's kt (mortar: E / (2 (1 + nu)) / e) where the file gives none
        kt = kw["kt"] if "kt" in kw else np.full(len(got), 1.0e9 / (2 * 1.2) / 0.01)
        expect(np.allclose(ref["interfaces/kt"], kt, rtol=1e-14, atol=0), f"{case}: kt are not the file's or the law's")
    else:
        expect(np.array_equal(got, np.array(want)), f"{case}: the detected pairs are not the construction's ({len(got)} vs {len(want)})")
    for name, members in sets.items():
        expect(np.array_equal(ref[f"sets/{name}"], members), f"{case}: /sets/{name} is not the list as written")
    crosses_every_boundary(got, len(blocks), f"2D {case}")
    print(f"2D {case}: {len(blocks)} blocks, {len(got)} interfaces, the construction's, crossing every rank boundary")


def walls3d(case):
    blocks, inter, sets = geomlib.running_bond(7, 6, LU, HU, E)
    depth = 0.1
    prisms = [np.vstack([np.c_[b, np.zeros(len(b))], np.c_[b, np.full(len(b), depth)]]) for b in blocks]
    prisms, new_of, sets = shuffle(prisms, sets, seed=30)
    want = sorted(tuple(sorted((int(new_of[i]), int(new_of[j])))) for i, j, *_ in inter)
    kw = {}
    if case == "listed":
        rng = np.random.default_rng(8)
        rows = np.array(want)[rng.permutation(len(want))]
        kw = {"pairs": rows, "kn": rng.uniform(1e9, 2e9, len(rows)), "kt": rng.uniform(4e8, 8e8, len(rows))}
    with tempfile.TemporaryDirectory() as tmp:
        geo, scene = os.path.join(tmp, "wall3.h5"), os.path.join(tmp, "wall3.yaml")
        bw.write_geometry(geo, prisms, sets=sets, check=False, **kw)
        with open(scene, "w") as f:
            f.write(SCENE3.format(file=geo))
        ref = same_everywhere(scene, GEOMETRY3, f"3D {case}", len(sets), tmp)
    got = ref["interfaces/blocks"]
    if case == "listed":
        expect(np.array_equal(got, kw["pairs"]), "listed: /interfaces/blocks are not the file's rows")
        expect(np.array_equal(ref["interfaces/kn"], kw["kn"]) and np.array_equal(ref["interfaces/kt"], kw["kt"]), "listed: kn, kt are not the file's")
    else:
        expect(np.array_equal(got, np.array(want)), f"3D {case}: the detected pairs are not the construction's ({len(got)} vs {len(want)})")
    crosses_every_boundary(got, len(prisms), f"3D {case}")
    print(f"3D {case}: {len(prisms)} blocks, {len(got)} interfaces, the construction's, crossing every rank boundary")


def peaks(scene, np_, tmp, extra):
    """Each rank's peak resident memory [kB], measured by /usr/bin/time around it."""
    d = tempfile.mkdtemp(dir=tmp)
    wrapper = os.path.join(d, "wrap.sh")
    with open(wrapper, "w") as f:
        f.write('#!/bin/sh\nd=$1; shift\nexec /usr/bin/time -f %M -o "$d/rss.${OMPI_COMM_WORLD_RANK:-0}" "$@"\n')
    os.chmod(wrapper, 0o755)
    p = call([MPIEXEC, "--oversubscribe", "-n", str(np_), wrapper, d, geomlib.TEST_GEOMETRY, "-scene", scene, *extra], env=ENV, what="test_geometry")
    expect(p.returncode == 0, f"test_geometry failed on {np_} ranks: {p.stderr}")
    files = sorted(f for f in os.listdir(d) if f.startswith("rss."))
    expect(len(files) == np_, f"{len(files)} measurements of {np_} ranks")
    return [int(open(os.path.join(d, f)).read().split()[-1]) for f in files]


def memory(extra):
    expect(os.access("/usr/bin/time", os.X_OK), "/usr/bin/time is needed to measure each rank from outside")
    with tempfile.TemporaryDirectory() as tmp:
        blocks, _, sets = geomlib.running_bond(316, 316, LU, HU, E)
        wall, two = os.path.join(tmp, "wall.yaml"), os.path.join(tmp, "two.yaml")
        geomlib.write_geometry(os.path.join(tmp, "wall.h5"), blocks, sets=sets)
        geomlib.write_scene(wall, "wall.h5")
        b2, _, s2 = geomlib.two_blocks()
        geomlib.write_geometry(os.path.join(tmp, "two.h5"), b2, sets=s2)
        geomlib.write_scene(two, "two.h5")
        above = {}
        for np_ in (2, 8):
            m0 = max(peaks(two, np_, tmp, extra))
            got = peaks(wall, np_, tmp, extra)
            above[np_] = max(got) - m0
            print(f"{len(blocks)} blocks on {np_} ranks: peaks {sorted(got)} kB, M0 {m0} kB: the largest {above[np_]} kB above M0")
    ratio = above[8] / above[2]
    expect(above[2] > 5000, f"the 1e5-block file adds only {above[2]} kB on 2 ranks: nothing to measure")
    expect(ratio < 0.6, f"the largest of 8 ranks holds {ratio:.2f} of what the largest of 2 holds (above M0): a rank holds the whole file")
    print(f"largest rank above M0: {above[8]} kB on 8 ranks, {ratio:.2f} of {above[2]} kB on 2")


if __name__ == "__main__":
    try:
        what, args = sys.argv[1], sys.argv[2:]
        if what == "walls2d" and args and args[0] in ("shuffled", "listed", "listed_kn", "bands", "arch"):
            walls2d(args[0])
        elif what == "walls3d" and args and args[0] in ("detected", "listed"):
            walls3d(args[0])
        elif what == "memory" and args in ([], ["distribute"]):
            memory(["-distribute"] if args else [])
        else:
            sys.exit(f"check_parallel_read.py: unknown case {sys.argv[1:]} (walls2d shuffled|listed|listed_kn|bands|arch, walls3d detected|listed, memory [distribute])")
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
