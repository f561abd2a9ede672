"""One blockwall result file in memory (schema: README "HDF5 output").

Blocks are rigid: a block with displacement (u1, u2, w) about its centroid
c moves a point x by

    u(x) = (u1 - w (x2 - c2),  u2 + w (x1 - c1))

(small rotations, as in the model), which is all the plots need to draw
the deformed wall."""
from __future__ import annotations

from dataclasses import dataclass, field

import h5py
import numpy as np


def _text(v):
    return v.decode() if isinstance(v, (bytes, np.bytes_)) else v


def _value(v):
    """HDF5 attribute -> str, int or float."""
    v = _text(v)
    if isinstance(v, np.generic):
        return v.item()
    return v


def rigid_displacement(points, displacement, centroid):
    """u(x) at `points` (n, 2) of a block moving rigidly by (u1, u2, w) about `centroid`."""
    p = np.asarray(points, float)
    u1, u2, w = displacement
    return np.column_stack([u1 - w * (p[:, 1] - centroid[1]), u2 + w * (p[:, 0] - centroid[0])])


@dataclass
class Results:
    path: str
    vertices: np.ndarray        # (V, 2)
    offsets: np.ndarray         # (B+1,)
    centroid: np.ndarray        # (B, 2)
    displacement: np.ndarray    # (B, 3) u1, u2, w
    reaction: np.ndarray        # (B, 3)
    load: np.ndarray            # (B, 3)
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
    attrs: dict = field(default_factory=dict)   # root attributes
    solver: dict = field(default_factory=dict)  # /solver attributes

    @property
    def nblocks(self):
        return len(self.offsets) - 1

    @property
    def ninterfaces(self):
        return len(self.length)

    @property
    def title(self):
        """The scene's title (the root attribute `scene` is the scene as run)."""
        for line in str(self.attrs.get("scene", "")).splitlines():
            if line.startswith("title:"):
                return line[len("title:"):].strip().strip('"')
        return ""

    def polygon(self, b):
        return self.vertices[self.offsets[b]:self.offsets[b + 1]]

    def vertex_displacement(self, b):
        """u(x) at the vertices of block b."""
        return rigid_displacement(self.polygon(b), self.displacement[b], self.centroid[b])

    def tangent(self):
        return np.column_stack([np.cos(self.angle), np.sin(self.angle)])

    def interface_ends(self):
        """(I, 2, 2): the ends G -/+ l/2 t of every interface."""
        h = 0.5 * self.length[:, None] * self.tangent()
        return np.stack([self.center - h, self.center + h], axis=1)

    def mean_stress(self):
        """(I, 2): mean shear T/(l s) and mean normal stress N/(l s) of every interface."""
        area = self.length * self.depth
        return self.resultant[:, :2] / area[:, None]

    def portion_edges(self, k):
        """The m+1 ends of the equal portions of interface k, along t from G."""
        l = self.length[k]
        return np.linspace(-l / 2, l / 2, self.m + 1)


def load(path):
    """Read a blockwall result file; raises ValueError if it is not one."""
    with h5py.File(path, "r") as f:
        missing = [d for d in ("blocks/vertices", "blocks/displacement", "interfaces/resultant") if d not in f]
        if missing or "solver" not in f:
            raise ValueError(f"{path}: not a blockwall result file (missing {', '.join(missing) or '/solver'})")
        g = lambda name: f[name][()]  # noqa: E731
        return Results(
            path=str(path),
            vertices=g("blocks/vertices"), offsets=g("blocks/offsets"), centroid=g("blocks/centroid"),
            displacement=g("blocks/displacement"), reaction=g("blocks/reaction"), load=g("blocks/load"),
            prescribed=g("blocks/prescribed"),
            pairs=g("interfaces/blocks").reshape(-1, 2), center=g("interfaces/center").reshape(-1, 2),
            angle=g("interfaces/angle"), length=g("interfaces/length"), kn=g("interfaces/kn"), kt=g("interfaces/kt"),
            relative=g("interfaces/relative_displacement").reshape(-1, 3),
            resultant=g("interfaces/resultant").reshape(-1, 3),
            stress=g("interfaces/stress") if "interfaces/stress" in f else None,
            depth=float(f.attrs["depth"]), m=int(f.attrs["m"]),
            attrs={k: _value(v) for k, v in f.attrs.items()},
            solver={k: _value(v) for k, v in f["solver"].attrs.items()},
        )
