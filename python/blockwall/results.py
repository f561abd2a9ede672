"""A blockwall result file in numpy arrays (docs/hdf5.md, "HDF5 output").

    res = read("out/wall.h5")
    res.displacement        # (B, 3) u1, u2, w
    res.resultant[:, 1]     # N of every interface
    res.solver["residual"]  # /solver attributes as str, int, float
    res.sets["top_beam"]    # block indices

Every dataset of the schema is a field; the optional ones are None when
the file has none (`stress` without output.stresses; `state`,
`plastic_jump`, `history` and `steps` unless the run was a pushover).
`datasets` holds every dataset of the file by its path, including any the
schema adds later, so nothing in a file is out of reach.

Blocks are rigid: a block with displacement (u1, u2, w) about its centroid
c moves a point x by

    u(x) = (u1 - w (x2 - c2),  u2 + w (x1 - c1))

(small rotations, as in the model), which is all the plots need to draw
the deformed wall."""
from __future__ import annotations

from dataclasses import dataclass, field

import h5py
import numpy as np

REQUIRED = ("blocks/vertices", "blocks/offsets", "blocks/displacement", "interfaces/resultant")
STEP_DATASETS = ("blocks/displacement", "blocks/reaction", "interfaces/resultant",
                 "interfaces/relative_displacement", "interfaces/state", "interfaces/stress")


def _value(v):
    """An HDF5 attribute as str, int, float (or an array, as stored)."""
    if isinstance(v, (bytes, np.bytes_)):
        return v.decode()
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, np.ndarray) and v.dtype.kind in "SO" and v.size == 1:
        return _value(v.reshape(-1)[0])
    return v


def attributes(obj):
    return {k: _value(v) for k, v in obj.attrs.items()}


def read_datasets(path):
    """{path: array} for every dataset of an HDF5 file, and the root and
    /solver attributes under "attrs" and "solver" ({} if absent)."""
    out = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: out.__setitem__(name, obj[()]) if isinstance(obj, h5py.Dataset) else None)
        out["attrs"] = attributes(f)
        out["solver"] = attributes(f["solver"]) if "solver" in f else {}
    return out


def rigid_displacement(points, displacement, centroid):
    """u(x) at `points` (n, 2) of a block moving rigidly by (u1, u2, w) about
    `centroid`; in 3D, points (n, 3) and (u1, u2, u3, w1, w2, w3): u + w x (x - c)."""
    p = np.asarray(points, float)
    if len(displacement) == 6:
        u, w = np.asarray(displacement[:3], float), np.asarray(displacement[3:], float)
        return u + np.cross(w, p - np.asarray(centroid, float))
    u1, u2, w = displacement
    return np.column_stack([u1 - w * (p[:, 1] - centroid[1]), u2 + w * (p[:, 0] - centroid[0])])


@dataclass
class Step:
    """One written step of a pushover (/steps/NNNNNN)."""
    number: int
    displacement: np.ndarray
    reaction: np.ndarray
    resultant: np.ndarray
    relative: np.ndarray
    state: np.ndarray | None        # (I, m); 3D: (P,) /steps/N/portions/state
    stress: np.ndarray | None       # (I, m, 2); 3D: (P, 3)
    attrs: dict = field(default_factory=dict)


@dataclass
class Results:
    path: str
    vertices: np.ndarray        # (V, 2), counter-clockwise per block
    offsets: np.ndarray         # (B+1,)
    centroid: np.ndarray        # (B, 2)
    displacement: np.ndarray    # (B, 3) u1, u2, w
    reaction: np.ndarray        # (B, 3) at prescribed dofs, 0 elsewhere
    load: np.ndarray            # (B, 3) F1, F2, M3 applied (self-weight included)
    prescribed: np.ndarray      # (B, 3) 0/1
    pairs: np.ndarray           # (I, 2) blocks i < j of each interface
    center: np.ndarray          # (I, 2) G
    angle: np.ndarray           # (I,) theta [rad] of the tangent t
    length: np.ndarray          # (I,) l
    kn: np.ndarray
    kt: np.ndarray
    relative: np.ndarray        # (I, 3) dt, dn, phi
    resultant: np.ndarray       # (I, 3) T, N, M
    stress: np.ndarray | None   # (I, m, 2) shear, normal per portion; None without output.stresses
    depth: float
    m: int
    sets: dict = field(default_factory=dict)        # name -> block indices
    attrs: dict = field(default_factory=dict)       # root attributes
    solver: dict = field(default_factory=dict)      # /solver attributes
    state: np.ndarray | None = None                 # (I, m) int8: 0 elastic, 1 open, 2 sliding, 3 both (3D: (P,))
    plastic_jump: np.ndarray | None = None          # (I, m, 2) plastic slip and opening [m] (3D: (P, 3), slip b last)
    history: dict | None = None                     # load_factor, monitor, iterations, residual: (S,)
    steps: dict = field(default_factory=dict)       # step number -> Step
    datasets: dict = field(default_factory=dict)    # every dataset of the file by path
    # 3D results (root attribute dimension = 3): the shapes above are then
    # vertices (V, 3), centroid (B, 3), displacement, reaction, load,
    # prescribed (B, 6), center (I, 3), relative and resultant (I, 6);
    # angle, length and stress are None, and these hold the rest
    dimension: int = 2
    mb: int = 1                                     # portions along b
    frame: np.ndarray | None = None                 # (I, 3, 3) rows t, n, b
    area: np.ndarray | None = None                  # (I,) interface areas
    interface_vertices: np.ndarray | None = None    # (W, 3) interface polygons ...
    interface_offsets: np.ndarray | None = None     # (I+1,) ... by interface
    portion_offsets: np.ndarray | None = None       # (I+1,) interface k: portions offsets[k]..offsets[k+1]-1
    portion_center: np.ndarray | None = None        # (P, 2) (xi, eta) from G along t, b
    portion_area: np.ndarray | None = None          # (P,)
    portion_stress: np.ndarray | None = None        # (P, 3) rt, rn, rb

    @property
    def nblocks(self):
        return len(self.offsets) - 1

    @property
    def ninterfaces(self):
        return len(self.pairs)

    @property
    def title(self):
        """The scene's title (the root attribute `scene` is the scene as run)."""
        for line in str(self.attrs.get("scene", "")).splitlines():
            if line.startswith("title:"):
                return line[len("title:"):].strip().strip('"')
        return ""

    def polygon(self, b):
        return self.vertices[self.offsets[b]:self.offsets[b + 1]]

    def polygons(self):
        return [self.polygon(b) for b in range(self.nblocks)]

    def vertex_displacement(self, b, displacement=None):
        """u(x) at the vertices of block b (of `displacement`, default the final one)."""
        d = self.displacement if displacement is None else displacement
        return rigid_displacement(self.polygon(b), d[b], self.centroid[b])

    def tangent(self):
        return np.column_stack([np.cos(self.angle), np.sin(self.angle)])

    def normal(self):
        return np.column_stack([-np.sin(self.angle), np.cos(self.angle)])

    def interface_ends(self):
        """(I, 2, 2): the ends G -/+ l/2 t of every interface."""
        h = 0.5 * self.length[:, None] * self.tangent()
        return np.stack([self.center - h, self.center + h], axis=1)

    def mean_stress(self):
        """(I, 2): mean shear T/(l s) and mean normal stress N/(l s) of every
        interface (3D: |(T, Tb)|/A and N/A)."""
        if self.dimension == 3:
            return np.column_stack([np.hypot(self.resultant[:, 0], self.resultant[:, 2]), self.resultant[:, 1]]) / self.area[:, None]
        area = self.length * self.depth
        return self.resultant[:, :2] / area[:, None]

    def portion_edges(self, k):
        """The m+1 ends of the equal portions of interface k, along t from G."""
        l = self.length[k]
        return np.linspace(-l / 2, l / 2, self.m + 1)

    def global_forces(self, k=None):
        """(I, 3) or (3,): the force (F1, F2) and moment about G that the
        joint exerts on block i, in global axes: T t + N n, M."""
        t, n = self.tangent(), self.normal()
        f = np.column_stack([self.resultant[:, 0:1] * t + self.resultant[:, 1:2] * n, self.resultant[:, 2]])
        return f if k is None else f[k]


def _opt(f, name):
    return f[name][()] if name in f else None


def read(path):
    """Read a blockwall result file; raises ValueError if it is not one."""
    path = str(path)
    with h5py.File(path, "r") as f:
        missing = [d for d in REQUIRED if d not in f]
        if missing or "solver" not in f:
            raise ValueError(f"{path}: not a blockwall result file (missing {', '.join(missing) or '/solver'})")
        g = lambda name: f[name][()]  # noqa: E731
        datasets = {}
        f.visititems(lambda name, obj: datasets.__setitem__(name, obj[()]) if isinstance(obj, h5py.Dataset) else None)
        history = None
        if "history" in f:
            history = {k: f["history"][k][()] for k in f["history"] if isinstance(f["history"][k], h5py.Dataset)}
        steps = {}
        if "steps" in f:
            for name in sorted(f["steps"]):
                s = f["steps"][name]
                steps[int(name)] = Step(
                    number=int(name), displacement=_opt(s, "blocks/displacement"),
                    reaction=_opt(s, "blocks/reaction"), resultant=_opt(s, "interfaces/resultant"),
                    relative=_opt(s, "interfaces/relative_displacement"),
                    state=_opt(s, "interfaces/state") if "interfaces/state" in s else _opt(s, "portions/state"),
                    stress=_opt(s, "interfaces/stress") if "interfaces/stress" in s else _opt(s, "portions/stress"),
                    attrs=attributes(s))
        if int(f.attrs.get("dimension", 2)) == 3:
            return Results(
                path=path, dimension=3, mb=int(f.attrs.get("m_b", 1)),
                vertices=g("blocks/vertices"), offsets=g("blocks/offsets"), centroid=g("blocks/centroid"),
                displacement=g("blocks/displacement"), reaction=g("blocks/reaction"), load=g("blocks/load"),
                prescribed=g("blocks/prescribed"),
                pairs=g("interfaces/blocks").reshape(-1, 2), center=g("interfaces/center").reshape(-1, 3),
                angle=None, length=None, kn=g("interfaces/kn"), kt=g("interfaces/kt"),
                relative=g("interfaces/relative_displacement").reshape(-1, 6),
                resultant=g("interfaces/resultant").reshape(-1, 6), stress=None,
                depth=float(f.attrs.get("depth", 0.0)), m=int(f.attrs["m"]),
                sets={k: f["sets"][k][()] for k in f["sets"]} if "sets" in f else {},
                attrs=attributes(f), solver=attributes(f["solver"]),
                history=history, steps=steps, datasets=datasets,
                frame=g("interfaces/frame"), area=g("interfaces/area"),
                interface_vertices=g("interfaces/vertices"), interface_offsets=g("interfaces/offsets"),
                portion_offsets=_opt(f, "interfaces/portion_offsets"), portion_center=_opt(f, "portions/center"),
                portion_area=_opt(f, "portions/area"), portion_stress=_opt(f, "portions/stress"),
                state=_opt(f, "portions/state"), plastic_jump=_opt(f, "portions/plastic_jump"))
        return Results(
            path=path,
            vertices=g("blocks/vertices"), offsets=g("blocks/offsets"), centroid=g("blocks/centroid"),
            displacement=g("blocks/displacement"), reaction=g("blocks/reaction"), load=g("blocks/load"),
            prescribed=g("blocks/prescribed"),
            pairs=g("interfaces/blocks").reshape(-1, 2), center=g("interfaces/center").reshape(-1, 2),
            angle=g("interfaces/angle"), length=g("interfaces/length"), kn=g("interfaces/kn"), kt=g("interfaces/kt"),
            relative=g("interfaces/relative_displacement").reshape(-1, 3),
            resultant=g("interfaces/resultant").reshape(-1, 3),
            stress=_opt(f, "interfaces/stress"),
            depth=float(f.attrs["depth"]), m=int(f.attrs["m"]),
            sets={k: f["sets"][k][()] for k in f["sets"]} if "sets" in f else {},
            attrs=attributes(f), solver=attributes(f["solver"]),
            state=_opt(f, "interfaces/state"), plastic_jump=_opt(f, "interfaces/plastic_jump"),
            history=history, steps=steps, datasets=datasets)


load = read  # the name tools/blockwall_post used
