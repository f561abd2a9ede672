"""The crack pattern of a 3D pushover (tools/plot on a file with dimension
= 3 and /portions/state): the blocks, warped by their displacement at the
step drawn (amplified, the factor in the picture), with translucent faces
and opaque edges, and on the joints the failed portions, each the polygon
it is, coloured by its state (open, sliding, both; crushed on the
compressive cap); elastic portions are not coloured, the joint shows as
the blocks' faces. From a chosen view; beside it the capacity curve with
the step drawn, and a legend counting the portions in every state.

The portions' shapes are not in the file (only their centroids and
areas): they are rebuilt here as model.md lays them, the cells of the
m x m_b grid of each interface polygon's bounding box in its (xi, eta)
coordinates, clipped to the polygon, numbered with the t index fastest,
kept when their area exceeds 1e-9 of the polygon's; each interface's count
and every centroid are checked against /interfaces/portion_offsets and
/portions/center, so a picture never shows portions other than blockwall's.

Drawn by ParaView's pvpython off-screen where it is installed (plot3d.py,
as the other 3D pictures; its picture is set in a matplotlib figure with
the legend and the curve), else with matplotlib's 3D axes (tools/demo
installs no ParaView). Both draw the same Crack3DScene, kept on the
returned Crack3DPlot with what the renderer reports it drew."""
from __future__ import annotations

import os
import sys
import tempfile
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from matplotlib.colors import to_rgb
from matplotlib.patches import Patch
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from .plots import CAP_STATES, STATES, crack_panel, crack_step, state_counts
from .results import rigid_displacement

# camera (elevation, azimuth) of matplotlib's 3D axes, whose x, y, z are X1, X3, X2
# (pvpython's cameras for the same names: plot3d.VIEWS)
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


def hull_faces(points):
    """The faces of the convex hull of `points` (n, 3) as polygons: arrays
    of indices into `points`, in order around the face. Qhull gives
    triangles; those of one plane (outward normals within 1e-9, offsets
    within 1e-9 of the block's size) are one face, so that a box has six
    faces and its edges are the box's, not the triangles'."""
    from scipy.spatial import ConvexHull
    points = np.asarray(points, float)
    h = ConvexHull(points)
    size = float(np.ptp(points, axis=0).max())
    eq = h.equations
    left = np.ones(len(eq), bool)
    faces = []
    for s in range(len(eq)):
        if not left[s]:
            continue
        same = left & (np.abs(eq[:, :3] @ eq[s, :3] - 1) <= 1e-9) & (np.abs(eq[:, 3] - eq[s, 3]) <= 1e-9 * size)
        left &= ~same
        idx = np.unique(h.simplices[same])
        c = points[idx].mean(axis=0)
        e1 = points[idx[0]] - c
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(eq[s, :3], e1)
        d = points[idx] - c
        faces.append(idx[np.argsort(np.arctan2(d @ e2, d @ e1))])
    return faces


# Colours of the picture besides the states' (plots.STATES, CAP_STATES):
# the blocks' faces (light, translucent) and edges (dark, mostly opaque).
FACE_COLOUR, FACE_OPACITY = (0.80, 0.77, 0.72), 0.18
MPL_FACE_OPACITY = 0.09  # matplotlib blends every face drawn over a pixel, ParaView peels depths
EDGE_COLOUR, EDGE_OPACITY = (0.25, 0.25, 0.25), 0.7


def state_colours():
    """state -> (r, g, b) in 0..1 for the failed states 1..7."""
    return {s: to_rgb(colour) for s, (_, colour, _) in {**STATES, **CAP_STATES}.items() if s}


@dataclass
class Crack3DScene:
    """What a crack pattern gives its renderer: the blocks' faces at their
    warped vertices and the failed portions at the joints' warped place."""
    scale: float                 # displacement amplification s
    displacement: np.ndarray     # (B, 6) the blocks' displacement at the step drawn
    points: np.ndarray           # (V, 3) every block's vertex x + s u_b(x), in /blocks/vertices order
    faces: list                  # F index arrays into `points`: the blocks' hull faces
    face_block: np.ndarray       # (F,) the block of each face
    portions: np.ndarray         # (Q,) the failed portions drawn, indices into /portions
    portion_state: np.ndarray    # (Q,) their states (1..7)
    portion_polygons: list       # Q arrays (n, 3): each at x + s (u_i(x) + u_j(x))/2, i, j its joint's blocks
    colours: dict = field(default_factory=state_colours)

    def portion_colours(self):
        """(Q, 3): the colour of every portion drawn."""
        return np.array([self.colours[int(s)] for s in self.portion_state]).reshape(-1, 3)


def auto_scale3d(res, fraction=0.05):
    """The amplification making the largest vertex displacement of the
    pushover (at the end or at any written step) ~`fraction` of the
    assembly's size, to one significant digit: the same for the peak and
    the end, so that the two pictures compare."""
    disps = [res.displacement] + [st.displacement for st in res.steps.values() if st.displacement is not None]
    umax = max(float(np.max(np.linalg.norm(res.vertex_displacement(b, d), axis=1)))
               for d in disps for b in range(res.nblocks))
    size = float(np.ptp(res.vertices, axis=0).max())
    if not umax > 0 or not np.isfinite(umax) or size == 0:
        return 1.0
    raw = fraction * size / umax
    e = np.floor(np.log10(raw))
    return float(round(raw / 10**e) * 10**e)


def crack_scene(res, state, displacement, scale, polys=None):
    """The Crack3DScene of `state` (P,) with the blocks at `displacement`
    (B, 6) amplified by `scale`."""
    points = np.concatenate([res.polygon(b) + scale * res.vertex_displacement(b, displacement) for b in range(res.nblocks)])
    faces, face_block = [], []
    for b in range(res.nblocks):
        lo = res.offsets[b]
        for f in hull_faces(res.polygon(b)):
            faces.append(f + lo)
            face_block.append(b)
    polys = portion_polygons(res) if polys is None else polys
    failed = np.nonzero(np.asarray(state) != 0)[0]
    owner = np.repeat(np.arange(res.ninterfaces), np.diff(res.portion_offsets))
    moved = []
    for p in failed:
        i, j = res.pairs[owner[p]]
        x = polys[p]
        u = 0.5 * (rigid_displacement(x, displacement[i], res.centroid[i]) + rigid_displacement(x, displacement[j], res.centroid[j]))
        moved.append(x + scale * u)
    return Crack3DScene(scale, np.asarray(displacement), points, faces, np.array(face_block, dtype=np.int64),
                        failed, np.asarray(state)[failed].astype(np.int64), moved)


def write_vtk(path, points, polygons, cell_data):
    """A legacy VTK file (ASCII POLYDATA) of `polygons` (index arrays into
    `points`) with integer cell arrays: cell_data name -> (VTK type, (F,) or
    (F, k) values), which ParaView's legacy reader reads."""
    with open(path, "w") as f:
        f.write("# vtk DataFile Version 3.0\nblockwall crack pattern\nASCII\nDATASET POLYDATA\n")
        f.write(f"POINTS {len(points)} double\n")
        np.savetxt(f, np.asarray(points, float).reshape(-1, 3), fmt="%.17g")
        f.write(f"POLYGONS {len(polygons)} {sum(len(p) + 1 for p in polygons)}\n")
        for p in polygons:
            f.write(f"{len(p)} {' '.join(str(int(i)) for i in p)}\n")
        f.write(f"CELL_DATA {len(polygons)}\n")
        for name, (kind, values) in cell_data.items():
            values = np.asarray(values).reshape(len(polygons), -1)
            f.write(f"SCALARS {name} {kind} {values.shape[1]}\nLOOKUP_TABLE default\n")
            np.savetxt(f, values, fmt="%d")


def pvpython_available():
    """Whether pvpython and a display for it (DISPLAY, or an Xvfb) are there."""
    from .display import find_xvfb
    from .plot3d import pvpython_command
    try:
        pvpython_command()
        if not os.environ.get("DISPLAY"):
            find_xvfb()
    except RuntimeError:
        return False
    return True


@dataclass
class Crack3DPlot:
    figure: Figure
    ax: object                   # the picture of the wall (the rendered image's axes for pvpython)
    ax_history: object | None
    at: str
    requested: int | None
    step: int | None
    nearest: bool
    state: np.ndarray            # (P,) the states drawn
    counts: np.ndarray           # portions in each state (0..3, and the cap's 4..7 where present)
    load_factor: float | None
    monitor: float | None
    renderer: str = "matplotlib"  # "pvpython" or "matplotlib"
    scene: Crack3DScene | None = None
    legend: dict = field(default_factory=dict)     # state -> the legend's Patch
    rendered: dict = field(default_factory=dict)   # pvpython: its report (plot3d.render_cracks3d); matplotlib:
    #                                                the "collection" of faces and portions, the "edges", the "faces" count
    files: dict = field(default_factory=dict)      # pvpython: "blocks", "portions" (VTK), "png", where kept


def plot_cracks3d(res, at="end", view="iso", renderer="auto", scale=None, workdir=None, size=(1600, 1000), timeout=600):
    """The 3D crack pattern at the end, at the peak (the written step nearest
    to it) or at a step: the blocks warped by their displacement x `scale`
    (default auto_scale3d), translucent with their edges, and the failed
    portions coloured by state (red open, blue sliding, purple both; the
    cap's crushed states where present); elastic ones uncoloured.
    `renderer`: "pvpython", "matplotlib" or "auto" (pvpython where it and a
    display for it are found). `workdir`: where pvpython's input files and
    picture are written and kept (default a temporary directory); `timeout`
    [s] for pvpython."""
    return plot_cracks3d_many(res, [(at, view)], renderer, scale, workdir, size, timeout)[0]


def plot_cracks3d_many(res, pictures, renderer="auto", scale=None, workdir=None, size=(1600, 1000), timeout=600):
    """plot_cracks3d for several pictures [(at, view), ...] of one result, in
    that order; pvpython draws them all in one session. With a `workdir`
    and more than one picture, each picture's files go to its folder
    AT_VIEW in it."""
    if res.state is None:
        raise ValueError(f"{res.path} has no /portions/state (joints without strength): no crack pattern")
    for _, view in pictures:
        if view not in VIEWS3D:
            raise ValueError(f"--view must be one of {', '.join(VIEWS3D)}, got {view!r}")
    if renderer not in ("auto", "pvpython", "matplotlib"):
        raise ValueError(f"--renderer must be auto, pvpython or matplotlib, got {renderer!r}")
    if scale is not None and not scale > 0:
        raise ValueError(f"--scale must be > 0, got {scale:g}")
    polys = portion_polygons(res)
    scale = auto_scale3d(res) if scale is None else float(scale)
    chosen, moments = [], {}
    for at, view in pictures:
        if at not in moments:
            # a moment's step and scene once, whatever the views of it
            history, kind, requested, step, state = crack_step(res, at)
            if len(polys) != len(state):
                raise ValueError(f"{res.path}: {len(state)} portion states for {len(polys)} portions")
            displacement = res.displacement if kind == "end" or step is None else res.steps[step].displacement
            moments[at] = (history, kind, requested, step, state, *state_counts(res.path, state),
                           crack_scene(res, state, displacement, scale, polys))
        chosen.append(_Picture(view, *moments[at]))
    auto = renderer == "auto"
    if auto:
        renderer = "pvpython" if pvpython_available() else "matplotlib"
    drawn_by_pv = [None] * len(chosen)
    if renderer == "pvpython":
        try:
            folders = [workdir if workdir is None or len(pictures) == 1 else os.path.join(workdir, f"{at}_{view}")
                       for at, view in pictures]
            drawn_by_pv = _draw_pvpython([(c.scene, c.view) for c in chosen], folders, size, timeout)
        except RuntimeError as e:
            if not auto:
                raise
            # a picture rather than none; the reason on stderr
            print(f"plot: pvpython could not draw the crack pattern, drawn with matplotlib instead: {e}", file=sys.stderr)
            renderer = "matplotlib"
    return [_crack_figure(res, c, renderer, pv) for c, pv in zip(chosen, drawn_by_pv)]


class _Picture(NamedTuple):
    """One crack picture asked of plot_cracks3d_many, before it is drawn."""
    view: str
    history: object        # crack_step's: the capacity curve to draw beside, or None
    kind: str              # "end", "peak" or "step"
    requested: int | None
    step: int | None
    state: np.ndarray
    counts: np.ndarray     # state_counts's
    drawn: dict
    scene: Crack3DScene


def _crack_figure(res, picture, renderer, drawn_by_pv):
    """The figure of one crack picture: the wall (pvpython's picture, or
    matplotlib's 3D axes), its legend and the capacity curve beside it."""
    view, history, kind, requested, step, state, counts, drawn, scene = picture
    fig = Figure(figsize=(14 if history else 10, 7.5), layout="constrained")
    FigureCanvasAgg(fig)
    gs = fig.add_gridspec(1, 2, width_ratios=[2.6, 1]) if history else None
    ax_h = fig.add_subplot(gs[1]) if history else None
    if renderer == "pvpython":
        rendered, files, image = drawn_by_pv
        ax = fig.add_subplot(gs[0]) if history else fig.add_subplot()
        ax.imshow(image, interpolation="antialiased")
        ax.set_axis_off()
    else:
        files = {}
        ax = fig.add_subplot(gs[0], projection="3d") if history else fig.add_subplot(projection="3d")
        rendered = _draw_matplotlib(ax, scene, view)
    # elastic portions look like the blocks' faces (they are not coloured)
    face = FACE_COLOUR + (FACE_OPACITY if renderer == "pvpython" else MPL_FACE_OPACITY,)
    legend = {s: Patch(facecolor=face if s == 0 else scene.colours[s], edgecolor=EDGE_COLOUR if s == 0 else "0.3",
                       linewidth=0.5, label=f"{name}: {counts[s]}")
              for s, (name, _, _) in drawn.items()}
    # beside the picture, as in 2D: over it, it hid a corner of the assembly
    ax.legend(handles=list(legend.values()), loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize="small",
              title=f"portions ({len(state)})", title_fontsize="small")
    ax.set_title(f"blocks warped by their displacement × {scene.scale:g} (translucent); failed portions coloured "
                 f"on the joints, elastic ones not", fontsize="small")

    lam, mon, nearest = crack_panel(res, fig, ax_h, history, kind, requested, step)
    return Crack3DPlot(fig, ax, ax_h, kind, requested, step, nearest, state, counts, lam, mon, renderer, scene,
                       legend, rendered, files)


def _draw_pvpython(scenes, workdirs, size, timeout):
    """Write each (scene, view) as two legacy VTK files and draw them all
    with one pvpython: for each, (its report, the files where kept, the
    picture as an array)."""
    import matplotlib.image as mpimg
    from .plot3d import render_cracks3d_many
    with tempfile.TemporaryDirectory() as tmp:
        pictures, kept = [], []
        for k, ((scene, view), workdir) in enumerate(zip(scenes, workdirs)):
            where = workdir or os.path.join(tmp, str(k))
            os.makedirs(where, exist_ok=True)
            files = {"blocks": os.path.join(where, "blocks.vtk"), "png": os.path.join(where, "cracks3d.png"),
                     "portions": os.path.join(where, "portions.vtk") if len(scene.portions) else None}
            write_vtk(files["blocks"], scene.points, scene.faces, {"block": ("int", scene.face_block)})
            if files["portions"]:
                pts = np.concatenate(scene.portion_polygons)
                ends = np.cumsum([0] + [len(p) for p in scene.portion_polygons])
                write_vtk(files["portions"], pts, [np.arange(ends[q], ends[q + 1]) for q in range(len(scene.portions))],
                          {"state": ("int", scene.portion_state), "portion": ("int", scene.portions),
                           "rgb": ("unsigned_char", np.rint(255 * scene.portion_colours()).astype(np.int64))})
            pictures.append((files["blocks"], files["portions"], files["png"], view))
            kept.append(files if workdir else {})
        style = dict(face_colour=FACE_COLOUR, face_opacity=FACE_OPACITY, edge_colour=EDGE_COLOUR,
                     edge_opacity=EDGE_OPACITY, edge_width=1.0)
        reports = render_cracks3d_many(pictures, size, style, timeout)
        images = [mpimg.imread(png) for _, _, png, _ in pictures]
    return list(zip(reports, kept, images))


def _draw_matplotlib(ax, scene, view):
    """The scene in matplotlib's 3D axes: one collection of the blocks'
    faces and the failed portions, so that they are sorted by depth together."""
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection
    swap = lambda p: np.asarray(p)[:, [0, 2, 1]]  # noqa: E731  (X1, X3, X2): X2 up
    verts = [swap(scene.points[f]) for f in scene.faces] + [swap(p) for p in scene.portion_polygons]
    nf = len(scene.faces)
    colours = np.zeros((len(verts), 4))
    colours[:nf] = FACE_COLOUR + (MPL_FACE_OPACITY,)
    colours[nf:, :3], colours[nf:, 3] = scene.portion_colours(), 1.0
    # faces and portions in one collection, sorted by depth together; the
    # blocks' edges over them (matplotlib sorts whole collections, and
    # edges sorted with the faces came out dim on one side of the wall)
    ax.computed_zorder = False
    col = Poly3DCollection(verts, facecolors=colours, edgecolors="none", zorder=1)
    ax.add_collection3d(col)
    edges = {tuple(sorted((int(f[i]), int(f[(i + 1) % len(f)])))) for f in scene.faces for i in range(len(f))}
    lines = Line3DCollection([swap(scene.points[list(e)]) for e in sorted(edges)], colors=[EDGE_COLOUR + (EDGE_OPACITY,)],
                             linewidths=0.5, zorder=2)
    ax.add_collection3d(lines)
    lo, hi = scene.points.min(axis=0), scene.points.max(axis=0)
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
    return {"collection": col, "edges": lines, "faces": nf}
