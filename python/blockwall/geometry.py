"""The HDF5 geometry input of `geometry.generator: file` (docs/hdf5.md, "HDF5
geometry input"), written from polygons and read back.

    from blockwall import Geometry
    g = Geometry(depth=0.1)
    base = g.add_block([[0, -0.1], [1, -0.1], [1, 0], [0, 0]], sets=["foundation"])
    top = g.add_block([[0, 0.01], [1, 0.01], [1, 0.2], [0, 0.2]], sets=["top"])
    g.write("wall.h5")        # interfaces are detected by blockwall

or in one call, `write_geometry("wall.h5", blocks, sets={...})`.

What is written:
    /blocks/vertices   float64 (V, 2)   every block's corners, counter-clockwise
                       float64 (V, 3)   3D: every block's vertices (the block is their convex hull)
    /blocks/offsets    int64   (B+1)    block b is rows offsets[b]..offsets[b+1]-1
    /interfaces/blocks int64   (I, 2)   only if pairs are given: (i, j), i < j
    /interfaces/kn, kt float64 (I)      only if given: per-interface stiffness [N/m^3]
    /sets/NAME         int64   (k)      named block sets
    root attribute depth (float64)      only if given

Each block is checked as blockwall will check it (polygon.check, with
blockwall's tolerance) and made counter-clockwise; pairs, stiffnesses and
sets are checked against the block count; overlapping blocks are an error.
A defect raises ValueError naming the block, pair or set, and no file is
written. The file is written to a temporary name beside the target and
renamed when complete, so a failed write never leaves half a file."""
from __future__ import annotations

import os
import re
import tempfile
from dataclasses import dataclass, field

import h5py
import numpy as np

from . import polygon

SET_NAME = re.compile(r"^[A-Za-z0-9_]+$")


def rectangle(x0, y0, x1, y1):
    """The counter-clockwise rectangle [x0, x1] x [y0, y1]."""
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], float)


def box(x0, y0, z0, x1, y1, z1):
    """The 8 corners of the box [x0, x1] x [y0, y1] x [z0, z1] (a 3D block)."""
    return np.array([[x, y, z] for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)], float)


def prism(outline, z0, z1):
    """A 3D block: the 2D outline (n, 2) in X1-X2 extruded over x3 in [z0, z1]."""
    p = np.asarray(outline, float)
    return np.concatenate([np.column_stack([p, np.full(len(p), z0)]), np.column_stack([p, np.full(len(p), z1)])])


def atomic_h5(path, fill):
    """Create `path` by writing a temporary HDF5 file beside it with
    fill(h5py.File) and renaming it; on any exception nothing is left."""
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=os.path.basename(path) + ".tmp-", dir=folder)
    os.close(fd)
    try:
        with h5py.File(tmp, "w") as f:
            fill(f)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


@dataclass
class Geometry:
    """Blocks (polygons (n, 2), or 3D vertex sets (n, 3) whose convex hull
    is the block: box(), prism() or any convex set), named sets, optional
    explicit interfaces with optional per-interface stiffness, optional
    depth (2D only)."""
    depth: float | None = None
    blocks: list = field(default_factory=list)
    sets: dict = field(default_factory=dict)
    pairs: list | None = None
    kn: list | None = None
    kt: list | None = None

    def add_block(self, corners, sets=()):
        """Append a polygon (n, 2) and put it in the named sets; returns its index."""
        self.blocks.append(np.asarray(corners, float))
        b = len(self.blocks) - 1
        for name in sets:
            self.sets.setdefault(name, []).append(b)
        return b

    def add_set(self, name, members):
        self.sets.setdefault(name, []).extend(int(b) for b in members)

    def add_interface(self, i, j, kn=None, kt=None):
        """An explicit interface between blocks i < j (n from i into j).
        Give kn and kt for every interface or for none."""
        if self.pairs is None:
            self.pairs = []
        self.pairs.append((int(i), int(j)))
        if kn is not None or kt is not None:
            if kn is None or kt is None:
                raise ValueError(f"interface ({i}, {j}): give both kn and kt, or neither")
            if self.kn is None:
                if len(self.pairs) > 1:
                    raise ValueError(f"interface ({i}, {j}): kn and kt given, but not for the interfaces before it")
                self.kn, self.kt = [], []
            self.kn.append(float(kn))
            self.kt.append(float(kt))
        elif self.kn is not None:
            raise ValueError(f"interface ({i}, {j}): kn and kt missing, but given for the interfaces before it")

    def write(self, path, check=True):
        write_geometry(path, self.blocks, sets=self.sets, pairs=self.pairs, kn=self.kn, kt=self.kt,
                       depth=self.depth, check=check)


def _checked_3d(polys, depth):
    """3D blocks: any vertex set of at least 4 finite points (blockwall
    takes the convex hull and checks that every vertex is a corner of it)."""
    for b, p in enumerate(polys):
        if p.ndim != 2 or p.shape[1] != 3:
            raise ValueError(f"block {b}: vertices must be an (n, 3) array like the other blocks, got shape {p.shape}")
        if len(p) < 4:
            raise ValueError(f"block {b}: {len(p)} vertices; a 3D block needs at least 4")
        if not np.all(np.isfinite(p)):
            raise ValueError(f"block {b}: non-finite coordinate")
    if depth is not None:
        raise ValueError("depth: a 3D geometry has no depth (its blocks have their own thickness)")
    return polys


def _checked(blocks, sets, pairs, kn, kt, depth, check_overlaps):
    polys = [np.asarray(b, float) for b in blocks]
    if not polys:
        raise ValueError("no blocks")
    three_d = polys[0].ndim == 2 and polys[0].shape[1] == 3
    if three_d:
        polys = _checked_3d(polys, depth)
    for b, p in enumerate(polys if not three_d else []):
        if p.ndim != 2 or p.shape[1] != 2:
            raise ValueError(f"block {b}: corners must be an (n, 2) array, got shape {p.shape}")
        if not np.all(np.isfinite(p)):
            raise ValueError(f"block {b}: non-finite coordinate")
    if not three_d:
        delta = polygon.tolerance(polys)
        for b, p in enumerate(polys):
            try:
                polygon.check(p, delta)
            except polygon.PolygonError as e:
                raise ValueError(f"block {b} {e}") from None
        polys = [polygon.counter_clockwise(p) for p in polys]
    if check_overlaps and not three_d:
        found = polygon.overlaps(polys, delta)
        if found:
            i, j, area = found[0]
            raise ValueError(f"blocks {i} and {j} overlap: their interiors share {area:.4g} m^2")
    nb = len(polys)
    out_sets = {}
    for name, members in (sets or {}).items():
        if not SET_NAME.match(str(name)):
            raise ValueError(f"set {name!r}: set names may hold only letters, digits and '_' "
                             f"(they become scene keys loads.NAME, supports.NAME)")
        m = np.asarray(members, np.int64).reshape(-1)
        if m.size == 0:
            raise ValueError(f"set {name}: empty")
        bad = m[(m < 0) | (m >= nb)]
        if bad.size:
            raise ValueError(f"set {name}: block {bad[0]} out of range (0..{nb - 1})")
        if len(np.unique(m)) != len(m):
            raise ValueError(f"set {name}: a block is listed twice")
        out_sets[str(name)] = m
    P = None
    if pairs is not None:
        P = np.asarray(pairs, np.int64).reshape(-1, 2)
        for k, (i, j) in enumerate(P):
            if not (0 <= i < nb and 0 <= j < nb):
                raise ValueError(f"interface {k}: blocks ({i}, {j}) out of range (0..{nb - 1})")
            if i >= j:
                raise ValueError(f"interface {k}: blocks ({i}, {j}) must satisfy i < j (n points from i into j)")
    K = {}
    for name, v in (("kn", kn), ("kt", kt)):
        if v is None:
            continue
        if P is None:
            raise ValueError(f"{name} given without interface pairs: per-interface stiffness needs the pairs")
        a = np.asarray(v, float).reshape(-1)
        if len(a) != len(P):
            raise ValueError(f"{name}: {len(a)} values for {len(P)} interfaces")
        if not np.all(np.isfinite(a) & (a > 0)):
            k = int(np.argmin(np.isfinite(a) & (a > 0)))
            raise ValueError(f"{name} of interface {k} must be finite and > 0, got {a[k]:g}")
        K[name] = a
    if (kn is None) != (kt is None):
        raise ValueError("give both kn and kt per interface, or neither")
    if depth is not None and not (np.isfinite(depth) and depth > 0):
        raise ValueError(f"depth must be > 0, got {depth}")
    return polys, out_sets, P, K


def write_geometry(path, blocks, sets=None, pairs=None, kn=None, kt=None, depth=None, check=True,
                   check_overlaps=True):
    """Write the geometry file `path` (schema in this module's doc).
    check=False writes the arrays exactly as given, unchecked and in the
    given orientation: for tests of blockwall's own validation."""
    if check:
        polys, sets, P, K = _checked(blocks, sets, pairs, kn, kt, depth, check_overlaps)
    else:
        polys = [np.asarray(b, float) for b in blocks]
        sets = {k: np.asarray(m, np.int64) for k, m in (sets or {}).items()}
        P = None if pairs is None else np.asarray(pairs, np.int64).reshape(-1, 2)
        K = {k: np.asarray(v, float) for k, v in (("kn", kn), ("kt", kt)) if v is not None}

    def fill(f):
        f["blocks/vertices"] = np.concatenate(polys)
        f["blocks/offsets"] = np.concatenate([[0], np.cumsum([len(p) for p in polys])]).astype(np.int64)
        if P is not None:
            f["interfaces/blocks"] = P
        for name, a in K.items():
            f[f"interfaces/{name}"] = a
        for name, m in sets.items():
            f[f"sets/{name}"] = m
        if depth is not None:
            f.attrs["depth"] = float(depth)

    atomic_h5(path, fill)


def read_geometry(path):
    """A geometry (or result) file's input part, as a Geometry."""
    with h5py.File(path, "r") as f:
        v, off = f["blocks/vertices"][()], f["blocks/offsets"][()]
        g = Geometry(depth=float(f.attrs["depth"]) if "depth" in f.attrs else None)
        g.blocks = [v[off[b]:off[b + 1]] for b in range(len(off) - 1)]
        if "sets" in f:
            g.sets = {k: f["sets"][k][()].tolist() for k in f["sets"]}
        if "interfaces/blocks" in f:
            g.pairs = [tuple(p) for p in f["interfaces/blocks"][()].reshape(-1, 2).tolist()]
            if "interfaces/kn" in f and "interfaces/kt" in f:
                g.kn, g.kt = f["interfaces/kn"][()].tolist(), f["interfaces/kt"][()].tolist()
    return g
