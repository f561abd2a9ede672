"""The crack pattern of a 3D pushover (tools/plot on a file with dimension
= 3 and /portions/state): every portion of every joint as the polygon it
is, coloured by its state, inside the assembly's translucent blocks, from
a chosen view; beside it the capacity curve with the step drawn.

The portions' shapes are not in the file (only their centroids and
areas): they are rebuilt here as model.md lays them, the cells of the
m x m_b grid of each interface polygon's bounding box in its (xi, eta)
coordinates, clipped to the polygon, numbered with the t index fastest,
kept when their area exceeds 1e-9 of the polygon's; each interface's count
and every centroid are checked against /interfaces/portion_offsets and
/portions/center, so a picture never shows portions other than blockwall's.
Drawn with matplotlib's 3D axes (no display, no ParaView needed)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from .plots import crack_panel, crack_step, state_counts

# camera (elevation, azimuth) of matplotlib's 3D axes, whose x, y, z are X1, X3, X2
VIEWS3D = {"iso": (22, -60), "front": (5, -90), "back": (5, 90), "side": (5, 0), "top": (88, -90)}


def _clip(poly, axis, value, keep_below):
    """Sutherland-Hodgman: the part of the convex polygon (n, 2) on one side
    of the line coordinate[axis] = value."""
    out = []
    n = len(poly)
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        ina = a[axis] <= value if keep_below else a[axis] >= value
        inb = b[axis] <= value if keep_below else b[axis] >= value
        if ina:
            out.append(a)
        if ina != inb:
            s = (value - a[axis]) / (b[axis] - a[axis])
            out.append(a + s * (b - a))
    return np.array(out) if out else np.zeros((0, 2))


def _area_centroid(p):
    if len(p) < 3:
        return 0.0, np.zeros(2)
    x, y = p[:, 0], p[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cr = x * yn - xn * y
    a = cr.sum() / 2
    if abs(a) == 0:
        return 0.0, np.zeros(2)
    return abs(a), np.array([((x + xn) * cr).sum(), ((y + yn) * cr).sum()]) / (6 * a)


def portion_polygons(res, check=True):
    """The portions of every interface of a 3D result as polygons in space:
    a list (P) of (n, 3) arrays in /portions order. With `check`, each
    interface's count and each centroid are compared with the file's."""
    if res.dimension != 3:
        raise ValueError(f"{res.path}: not a 3D result")
    m, mb = res.m, res.mb
    polys, centers, counts = [], [], []
    for k in range(res.ninterfaces):
        t, n, b = res.frame[k]
        G = res.center[k]
        w = res.interface_vertices[res.interface_offsets[k]:res.interface_offsets[k + 1]] - G
        uv = np.column_stack([w @ t, w @ b])
        area, _ = _area_centroid(uv)
        lo, hi = uv.min(axis=0), uv.max(axis=0)
        xs, ys = np.linspace(lo[0], hi[0], m + 1), np.linspace(lo[1], hi[1], mb + 1)
        count = 0
        for j in range(mb):
            strip = _clip(_clip(uv, 1, ys[j], False), 1, ys[j + 1], True)
            for i in range(m):
                cell = _clip(_clip(strip, 0, xs[i], False), 0, xs[i + 1], True) if len(strip) else strip
                a, c = _area_centroid(cell)
                if a > 1e-9 * area:
                    polys.append(G + cell[:, :1] * t + cell[:, 1:] * b)
                    centers.append(c)
                    count += 1
        counts.append(count)
    if check and res.portion_offsets is not None:
        want = np.diff(res.portion_offsets)
        bad = np.nonzero(np.asarray(counts) != want)[0]
        if len(bad):
            k = int(bad[0])
            raise ValueError(f"{res.path}: interface {k} has {want[k]} portions in the file, {counts[k]} rebuilt here")
        if res.portion_center is not None and len(centers):
            size = float(np.ptp(res.vertices, axis=0).max())
            err = float(np.max(np.abs(np.asarray(centers) - res.portion_center)))
            if err > 1e-9 * size:
                raise ValueError(f"{res.path}: rebuilt portions' centroids differ from /portions/center by {err:.3g} m")
    return polys


def _block_faces(res):
    """Every block's hull faces (triangles) for a translucent drawing."""
    from scipy.spatial import ConvexHull
    faces = []
    for b in range(res.nblocks):
        v = res.polygon(b)
        h = ConvexHull(v)
        faces.extend(v[s] for s in h.simplices)
    return faces


@dataclass
class Crack3DPlot:
    figure: Figure
    ax: object
    ax_history: object | None
    at: str
    requested: int | None
    step: int | None
    nearest: bool
    state: np.ndarray            # (P,) the states drawn
    counts: np.ndarray           # portions in each state (0..3, and the cap's 4..7 where present)
    load_factor: float | None
    monitor: float | None


def plot_cracks3d(res, at="end", view="iso"):
    """The 3D crack pattern at the end, at the peak (the written step nearest
    to it) or at a step: portions coloured by state (grey elastic, red open,
    blue sliding, purple both) in the translucent undeformed blocks."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection
    if res.state is None:
        raise ValueError(f"{res.path} has no /portions/state (joints without strength): no crack pattern")
    if view not in VIEWS3D:
        raise ValueError(f"--view must be one of {', '.join(VIEWS3D)}, got {view!r}")
    history, kind, requested, step, state = crack_step(res, at)
    polys = portion_polygons(res)
    if len(polys) != len(state):
        raise ValueError(f"{res.path}: {len(state)} portion states for {len(polys)} portions")
    counts, drawn = state_counts(res.path, state)

    fig = Figure(figsize=(14 if history else 10, 7.5), layout="constrained")
    FigureCanvasAgg(fig)
    if history:
        gs = fig.add_gridspec(1, 2, width_ratios=[2.6, 1])
        ax = fig.add_subplot(gs[0], projection="3d")
        ax_h = fig.add_subplot(gs[1])
    else:
        ax, ax_h = fig.add_subplot(projection="3d"), None
    swap = lambda p: np.asarray(p)[:, [0, 2, 1]]  # noqa: E731  (X1, X3, X2): X2 up
    ax.add_collection3d(Poly3DCollection([swap(f) for f in _block_faces(res)], facecolors=(0.6, 0.6, 0.6, 0.04),
                                         edgecolors="none"))
    handles = []
    for s, (name, colour, _) in drawn.items():
        sel = [swap(polys[i]) for i in np.nonzero(state == s)[0]]
        col = Poly3DCollection(sel, facecolors=colour, edgecolors="0.3" if s else "0.7", linewidths=0.2,
                               alpha=0.25 if s == 0 else 0.95, label=f"{name}: {counts[s]}")
        ax.add_collection3d(col)
        handles.append(col)
    lo, hi = res.vertices.min(axis=0), res.vertices.max(axis=0)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[2], hi[2])
    ax.set_zlim(lo[1], hi[1])
    ax.set_box_aspect((hi[0] - lo[0], hi[2] - lo[2], hi[1] - lo[1]))
    ax.view_init(*VIEWS3D[view])
    ax.set_xlabel("x1 [m]")
    ax.set_ylabel("x3 [m]")
    ax.set_zlabel("x2 [m]")
    # ticks in proportion to each side: a wall thin along X3 gets two, not ten overlapping
    for axis, c in ((ax.xaxis, 0), (ax.yaxis, 2), (ax.zaxis, 1)):
        axis.set_major_locator(MaxNLocator(nbins=max(2, int(8 * (hi[c] - lo[c]) / max(hi - lo)))))
    ax.legend(handles=handles, loc="upper left", fontsize="small", title=f"portions ({len(state)})", title_fontsize="small")

    lam, mon, nearest = crack_panel(res, fig, ax_h, history, kind, requested, step)
    return Crack3DPlot(fig, ax, ax_h, kind, requested, step, nearest, state, counts, lam, mon)
