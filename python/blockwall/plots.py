"""Pictures of a result: the deformed wall, and the stress diagrams along
interfaces (for the paper's two-block cases, its Fig. 8).

Figures are drawn on matplotlib's Agg canvas directly (no pyplot, no
display, no global backend switch), and every function returns the arrays
it drew, so that a test can compare them with the HDF5 datasets.

Deformed shape: each vertex x of block b is drawn at x + s u_b(x), u_b the
block's rigid motion (results.py), s the amplification factor. Left to
itself, s makes the largest vertex displacement about 5 % of the wall's
size, rounded to one significant digit so the title states a plain number.

Stresses: the model's stresses are constant on each of the m equal portions
of an interface, so the diagram is a step function over the portions,
x measured along t from the interface's centre G (the model's x_p).

Crack pattern (a pushover's, or any result with joint strength): every
portion of every interface drawn as its own segment of the undeformed joint
line, coloured by its state in /interfaces/state, at the end or at the
peak of the capacity curve (the written step nearest to it if the peak's
was not written)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.colors import Normalize
from matplotlib.figure import Figure

from .results import rigid_displacement

# --color: label and value per block (at the centroid)
COLORS = {
    "u1": ("u1 [m]", lambda d: d[:, 0]),
    "u2": ("u2 [m]", lambda d: d[:, 1]),
    "w": ("w [rad]", lambda d: d[:, 2]),
    "umag": ("|u| = sqrt(u1² + u2²) [m]", lambda d: np.hypot(d[:, 0], d[:, 1])),
}


@dataclass
class WallPlot:
    figure: Figure
    ax: object
    scale: float                    # amplification factor s
    size: float                     # the larger side of the undeformed bounding box [m]
    max_displacement: float         # largest |u(x)| over all vertices [m]
    color: str
    block_values: np.ndarray        # (B,) the colour of each block
    polygons: list                  # B arrays (n_b, 2): the deformed polygons drawn
    interface_segments: np.ndarray  # (I, 2, 2): the deformed interface lines drawn
    interface_values: np.ndarray    # (I,) their colour: mean normal stress N/(l s) [Pa]


@dataclass
class StressPlot:
    figure: Figure
    axes: dict                      # "normal", "shear"
    index: int
    edges: np.ndarray               # (m+1,) portion ends along t from G [m]
    normal: np.ndarray              # (m,) [Pa]
    shear: np.ndarray               # (m,) [Pa]
    lines: dict                     # "normal", "shear": the step lines (Line2D)
    mean: dict                      # "normal": N/(l s), "shear": T/(l s)


def _vertex_displacements(res):
    """(V, 2): u(x) at every vertex, block by block."""
    return np.concatenate([res.vertex_displacement(b) for b in range(res.nblocks)]) if res.nblocks else np.zeros((0, 2))


def _size(res):
    span = res.vertices.max(axis=0) - res.vertices.min(axis=0)
    return float(max(span.max(), 0.0))


def auto_scale(res, fraction=0.05):
    """Amplification making the largest vertex displacement ~`fraction` of the wall's size."""
    umax = float(np.max(np.hypot(*_vertex_displacements(res).T), initial=0.0))
    size = _size(res)
    if umax == 0 or size == 0 or not np.isfinite(umax):
        return 1.0
    raw = fraction * size / umax
    exponent = np.floor(np.log10(raw))
    return float(round(raw / 10**exponent) * 10**exponent)


def _symmetric(values):
    a = float(np.max(np.abs(values), initial=0.0))
    return Normalize(-a, a) if a > 0 else Normalize(-1, 1)


def _canvas(figsize, layout="constrained"):
    fig = Figure(figsize=figsize, layout=layout)
    FigureCanvasAgg(fig)
    return fig


def plot_wall(res, color="umag", scale=None):
    """The deformed wall: blocks coloured by `color` (u1, u2, w, umag), the
    interfaces by their mean normal stress N/(l s), the undeformed outline
    dashed. `scale` None chooses the amplification (auto_scale)."""
    if color not in COLORS:
        raise ValueError(f"color must be one of {', '.join(COLORS)}, got {color!r}")
    s = auto_scale(res) if scale is None else float(scale)
    label, quantity = COLORS[color]
    values = quantity(res.displacement)
    polygons = [res.polygon(b) + s * res.vertex_displacement(b) for b in range(res.nblocks)]

    ends = res.interface_ends()
    segments = ends.copy()
    for k, (i, j) in enumerate(res.pairs):
        # the joint's mid-line moves with the mean of its two blocks
        u = 0.5 * (rigid_displacement(ends[k], res.displacement[i], res.centroid[i])
                   + rigid_displacement(ends[k], res.displacement[j], res.centroid[j]))
        segments[k] += s * u
    stress = res.mean_stress()[:, 1] if res.ninterfaces else np.zeros(0)

    lo, hi = res.vertices.min(axis=0), res.vertices.max(axis=0)
    aspect = (hi[1] - lo[1]) / max(hi[0] - lo[0], 1e-300)
    # "compressed" is the constrained layout for equal-aspect axes
    fig = _canvas((10, float(np.clip(6.5 * aspect, 2.5, 12)) + 1.2), layout="compressed")
    ax = fig.add_subplot()
    ax.add_collection(PolyCollection([res.polygon(b) for b in range(res.nblocks)], facecolors="none",
                                     edgecolors="0.6", linewidths=0.5, linestyles="--"))
    blocks = PolyCollection(polygons, array=values, cmap="viridis" if color == "umag" else "PuOr_r",
                            norm=None if color == "umag" else _symmetric(values), edgecolors="k", linewidths=0.4)
    ax.add_collection(blocks)
    fig.colorbar(blocks, ax=ax, label=f"blocks: {label}", fraction=0.05, pad=0.02)
    if res.ninterfaces:
        joints = LineCollection(segments, array=stress, cmap="RdBu_r", norm=_symmetric(stress), linewidths=2.5)
        ax.add_collection(joints)
        fig.colorbar(joints, ax=ax, label="interfaces: mean normal stress N/(l s) [Pa]", fraction=0.05, pad=0.02)
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("x1 [m]")
    ax.set_ylabel("x2 [m]")
    title = res.title or "blockwall"
    ax.set_title(f"{title}\ndeformed shape, displacements ×{s:g}")
    umax = float(np.max(np.hypot(*_vertex_displacements(res).T), initial=0.0))
    return WallPlot(fig, ax, s, _size(res), umax, color, values, polygons, segments, stress)


def _steps(edges, values):
    """The polyline of a piecewise-constant function: x = e0 e1 e1 e2 ... em, y = v0 v0 v1 v1 ..."""
    return np.repeat(edges, 2)[1:-1], np.repeat(values, 2)


def plot_interface_stress(res, k):
    """Normal (top) and shear (bottom) stress along interface k, per portion."""
    if res.stress is None:
        raise ValueError(f"{res.path} has no /interfaces/stress (written with output.stresses false)")
    if not 0 <= k < res.ninterfaces:
        raise ValueError(f"interface {k} does not exist (0..{res.ninterfaces - 1})")
    edges = res.portion_edges(k)
    shear, normal = res.stress[k, :, 0], res.stress[k, :, 1]
    mean_shear, mean_normal = res.mean_stress()[k]
    fig = _canvas((7, 6))
    ax_n = fig.add_subplot(2, 1, 1)
    ax_t = fig.add_subplot(2, 1, 2, sharex=ax_n)
    lines = {}
    for name, ax, values, mean, colour in (("normal", ax_n, normal, mean_normal, "tab:blue"),
                                           ("shear", ax_t, shear, mean_shear, "tab:red")):
        x, y = _steps(edges, values)
        ax.fill_between(x, y, 0, color=colour, alpha=0.25, linewidth=0)
        lines[name] = ax.plot(x, y, color=colour, linewidth=1.5, label=f"{name} stress per portion")[0]
        ax.axhline(mean, color="0.3", linestyle="--", linewidth=1,
                   label=f"mean {'N' if name == 'normal' else 'T'}/(l s) = {mean:.6g} Pa")
        ax.axhline(0, color="k", linewidth=0.6)
        ax.set_ylabel(f"{name} stress [Pa]")
        ax.legend(loc="best", fontsize="small")
        ax.grid(True, alpha=0.3)
    ax_t.set_xlabel("position along the interface from its centre G, along t [m]")
    i, j = res.pairs[k]
    T, N, M = res.resultant[k]
    fig.suptitle(f"interface {k} (blocks {i}-{j}): l = {res.length[k]:.4g} m, θ = {np.degrees(res.angle[k]):.4g}°, "
                 f"m = {res.m}\nT = {T:.4g} N, N = {N:.4g} N, M = {M:.4g} N·m")
    return StressPlot(fig, {"normal": ax_n, "shear": ax_t}, k, edges, normal, shear, lines,
                      {"normal": mean_normal, "shear": mean_shear})


def curve_axes(res):
    """How a capacity curve's axes read (issue 17): the monitor by name
    and unit ("u1 of top_beam [mm]", rotations in mrad) and the load in the
    pattern's unit: lambda times the pattern's resultant |sum F| (N), in kN
    from 1 kN up. Returns (x scale, x label, y scale, y label): plot
    monitor * x scale against lambda * y scale. Files written before the
    attributes existed keep the generic labels."""
    sv = res.solver or {}
    dof, where = sv.get("monitor_dof"), sv.get("monitor_set")
    if dof and where:
        xs, xl = (1e3, f"{dof} of {where} [mrad]") if dof.startswith("w") else (1e3, f"{dof} of {where} [mm]")
    else:
        xs, xl = 1.0, "monitor dof [m or rad]"
    pr = sv.get("pattern_resultant")
    if isinstance(pr, (int, float, np.floating)) and pr > 0:
        lam = np.asarray(res.history["load_factor"]) if res.history and "load_factor" in res.history else np.ones(1)
        big = np.max(np.abs(lam)) * pr >= 1e3
        ys, yl = (pr / 1e3, "load [kN]") if big else (pr, "load [N]")
        yl += f" (λ × pattern, |ΣF| = {pr:.4g} N)"
    else:
        ys, yl = 1.0, "load factor λ"
    return xs, xl, ys, yl


@dataclass
class HistoryPlot:
    figure: Figure
    ax: object
    monitor: np.ndarray             # (S,) the monitor dof at each converged step
    load_factor: np.ndarray         # (S,) lambda


def capacity_envelope(lam, mon):
    """The displacement-controlled envelope of a capacity curve
    (interface.md, "past the peak"): the monitor measured from step 0
    along the direction it moved, the steps where it reaches a new
    maximum, and where the path comes back past that maximum after a
    snap-back, the point at it (a vertical drop). Returns (d, lambda, sign)
    with d >= 0 the displacement magnitudes."""
    lam, mon = np.asarray(lam, float), np.asarray(mon, float)
    sign = 1.0 if mon[-1] >= mon[0] else -1.0
    d = sign * (mon - mon[0])
    env_d, env_f, dmax, behind = [0.0], [lam[0]], 0.0, False
    for i in range(1, len(lam)):
        if d[i] <= dmax:
            behind = True
            continue
        if behind and d[i] > d[i - 1]:
            a = (dmax - d[i - 1]) / (d[i] - d[i - 1])
            env_d.append(dmax)
            env_f.append(lam[i - 1] + a * (lam[i] - lam[i - 1]))
        env_d.append(d[i])
        env_f.append(lam[i])
        dmax, behind = d[i], False
    return np.array(env_d), np.array(env_f), sign


def plot_history(res):
    """A pushover's capacity curve: the load factor against the monitor
    dof, one marker per converged step (/history), with its envelope and
    the bilinearisation of /solver (where it exists)."""
    if not res.history or "load_factor" not in res.history or "monitor" not in res.history:
        raise ValueError(f"{res.path} has no /history (not a pushover result)")
    lam, mon = np.asarray(res.history["load_factor"]), np.asarray(res.history["monitor"])
    xs, xl, ys, yl = curve_axes(res)
    fig = _canvas((7, 5))
    ax = fig.add_subplot()
    ax.plot(mon * xs, lam * ys, "-o", markersize=3, color="tab:blue")
    ax.axhline(0, color="k", linewidth=0.6)
    peak = res.solver.get("peak_load_factor")
    if isinstance(peak, (int, float, np.floating)):
        ax.axhline(peak * ys, color="0.4", linestyle="--", linewidth=1, label=f"peak λ = {peak:.6g}")
    # the envelope (a snap-back drawn as a vertical drop) and its NTC 2018
    # bilinearisation from /solver: up to (d_y, F_y), flat to d_u
    env_d, env_f, sign = capacity_envelope(lam, mon)
    if len(lam) > 1:
        ax.plot((mon[0] + sign * env_d) * xs, env_f * ys, "-", color="tab:orange", linewidth=1.5, label="envelope")
    fy, dy, du = (res.solver.get(k) for k in ("bilinear_yield_force", "bilinear_yield_displacement", "ultimate_displacement"))
    if all(isinstance(v, (int, float, np.floating)) and np.isfinite(v) for v in (fy, dy, du)):
        duct = res.solver.get("ductility")
        ax.plot((mon[0] + sign * np.array([0.0, dy, du])) * xs, np.array([lam[0], fy, fy]) * ys, "-", color="k",
                linewidth=1.2, label=f"bilinear: F_y λ = {fy:.4g} at d_y = {dy * xs:.3g}, d_u = {du * xs:.3g}"
                + (f", ductility {duct:.3g}" if isinstance(duct, (int, float, np.floating)) else ""))
    ax.legend(loc="best", fontsize="small")
    ax.set_xlabel(xl)
    ax.set_ylabel(yl)
    ax.grid(True, alpha=0.3)
    stop = res.solver.get("stop_reason", "")
    ax.set_title(f"{res.title or 'blockwall'}: pushover, {len(lam)} steps" + (f"\n{stop}" if stop else ""), wrap=True, fontsize="medium")
    return HistoryPlot(fig, ax, mon, lam)


# The states of /interfaces/state: value -> (name in the legend, colour,
# line width). Elastic portions are drawn thin and light so that the
# cracks (open, sliding, both) stand out on them. A state is a set of
# bits (1 open, 2 sliding, 4 crushed on the compressive cap); the crushed
# ones are drawn and listed only where a file has them.
STATES = {0: ("elastic", "0.82", 0.6),
          1: ("open", "tab:red", 2.5),
          2: ("sliding", "tab:blue", 2.5),
          3: ("open and sliding", "tab:purple", 2.5)}
CAP_STATES = {4: ("crushed", "tab:orange", 3.0),
              5: ("crushed and open", "tab:brown", 3.0),
              6: ("crushed and sliding", "tab:olive", 3.0),
              7: ("crushed, open and sliding", "black", 3.0)}


def state_counts(path, state):
    """Portions per state (at least 0..3) and the states to draw: 0..3,
    and those of the cap that occur."""
    counts = np.bincount(np.asarray(state).ravel().astype(np.int64), minlength=len(STATES))
    if len(counts) > len(STATES) + len(CAP_STATES):
        raise ValueError(f"{path}: interface state {len(counts) - 1} is none of 0..{len(STATES) + len(CAP_STATES) - 1}")
    drawn = dict(STATES)
    drawn.update({s: v for s, v in CAP_STATES.items() if s < len(counts) and counts[s] > 0})
    return counts, drawn


@dataclass
class CrackPlot:
    figure: Figure
    ax: object                      # the wall
    ax_history: object              # the capacity curve beside it, the step drawn marked (None without /history)
    at: str                         # "end", "peak" or "step"
    requested: int | None           # the step asked for (the peak's); None: the file's final state
    step: int | None                # the step drawn; None only for a file without /history
    nearest: bool                   # True: `requested` was not written, the nearest written step was drawn
    state: np.ndarray               # (I, m) the states drawn
    segments: np.ndarray            # (I, m, 2, 2) each portion's ends on the undeformed joint line
    counts: np.ndarray              # portions drawn in each state 0..3 (and 4..7, crushed, where present)
    lines: dict                     # state -> the LineCollection of its portions
    load_factor: float | None       # lambda of the step drawn (None without /history)
    monitor: float | None           # the monitor dof at the step drawn


def portion_segments(res):
    """(I, m, 2, 2): the ends of the m equal portions of every interface,
    G + x t for x from -l/2 to l/2 (results.portion_edges), on the
    undeformed joint line (results.interface_ends)."""
    if not res.ninterfaces:
        return np.zeros((0, res.m, 2, 2))
    edges = np.stack([res.portion_edges(k) for k in range(res.ninterfaces)])     # (I, m+1)
    points = res.center[:, None, :] + edges[:, :, None] * res.tangent()[:, None, :]  # (I, m+1, 2)
    return np.stack([points[:, :-1], points[:, 1:]], axis=2)


def peak_step(res):
    """The step of /history with the largest load factor (the first of
    equals). /solver peak_load_factor is that value."""
    if not res.history or "load_factor" not in res.history:
        raise ValueError(f"{res.path} has no /history (not a pushover result): no peak to draw")
    return int(np.argmax(res.history["load_factor"]))


def nearest_written_step(res, step):
    """The written step (/steps/NNNNNN with interfaces/state) nearest to
    `step`; of two equally near, the later one (it has been through the
    state asked for, not short of it)."""
    written = [s for s, st in res.steps.items() if st.state is not None]
    if not written:
        raise ValueError(f"{res.path} has no /steps/NNNNNN/interfaces/state (output.steps wrote none)")
    return min(written, key=lambda s: (abs(s - step), -s))


def plot_cracks(res, at="end"):
    """The crack pattern: the wall's blocks (undeformed outline) and every
    portion of every interface as a segment along the joint, coloured by
    its state (0 elastic, 1 open, 2 sliding, 3 both; 4..7 crushed on the
    compressive cap, alone or with those); the legend counts
    the portions in each state. `at`: "end" (the top-level
    /interfaces/state, the last converged step), "peak" (the step of
    largest load factor, or the written step nearest to it), or a step
    number (that written step, or the nearest one). Beside it, for a
    pushover, the capacity curve with the step drawn marked."""
    if res.state is None:
        raise ValueError(f"{res.path} has no /interfaces/state (joints without strength): no crack pattern")
    history, kind, requested, step, state = crack_step(res, at)
    state = state.reshape(res.ninterfaces, res.m)
    segments = portion_segments(res)
    counts, drawn = state_counts(res.path, state)

    lo, hi = res.vertices.min(axis=0), res.vertices.max(axis=0)
    aspect = (hi[1] - lo[1]) / max(hi[0] - lo[0], 1e-300)
    fig = _canvas((13 if history else 10, float(np.clip(6.5 * aspect, 3.5, 12)) + 1.2), layout="compressed")
    if history:
        ax, ax_h = fig.subplots(1, 2, width_ratios=[3, 1.3])
    else:
        ax, ax_h = fig.add_subplot(), None
    ax.add_collection(PolyCollection(res.polygons(), facecolors="0.97", edgecolors="0.35", linewidths=0.5))
    lines = {}
    for s, (name, colour, width) in drawn.items():
        mask = state == s
        # elastic first, so that a crack is never hidden under a grey segment
        lines[s] = LineCollection(segments[mask], colors=colour, linewidths=width, zorder=2 + (s > 0),
                                  capstyle="butt", label=f"{name}: {counts[s]}")
        ax.add_collection(lines[s])
    ax.legend(handles=[lines[s] for s in drawn], loc="upper left", bbox_to_anchor=(1.0, 1.0),
              fontsize="small", title=f"portions ({state.size})", title_fontsize="small")
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("x1 [m]")
    ax.set_ylabel("x2 [m]")

    lam, mon, nearest = crack_panel(res, fig, ax_h, history, kind, requested, step)
    return CrackPlot(fig, ax, ax_h, kind, requested, step, nearest, state, segments, counts, lines, lam, mon)


def crack_step(res, at):
    """Which state a crack pattern draws (2D and 3D): (history or None, kind
    "end" | "peak" | "step", the step asked for, the step drawn, its state):
    the final state, the peak's step or a given one (the written step
    nearest to it)."""
    history = res.history if res.history and "load_factor" in res.history and "monitor" in res.history else None
    last = len(history["load_factor"]) - 1 if history else None
    if at == "end":
        return history, "end", last, last, np.asarray(res.state)
    if isinstance(at, str) and at != "peak":
        raise ValueError(f"at must be 'end', 'peak' or a step number, got {at!r}")
    requested = peak_step(res) if at == "peak" else int(at)
    step = nearest_written_step(res, requested)
    return history, at if isinstance(at, str) else "step", requested, step, np.asarray(res.steps[step].state)


def crack_panel(res, fig, ax_h, history, kind, requested, step):
    """A crack pattern's capacity curve beside it (the peak ringed, the step
    drawn in red) and its title. Returns (lambda, monitor, nearest)."""
    lam = mon = None
    if history:
        lam, mon = float(history["load_factor"][step]), float(history["monitor"][step])
        xs, xl, ys, yl = curve_axes(res)
        hm, hl = np.asarray(history["monitor"]) * xs, np.asarray(history["load_factor"]) * ys
        ax_h.plot(hm, hl, "-", color="0.5", linewidth=1)
        p = peak_step(res)
        ax_h.plot(hm[p], hl[p], "o", markersize=12, markerfacecolor="none",
                  markeredgecolor="k", label=f"peak, step {p}")
        ax_h.plot(mon * xs, lam * ys, "o", color="tab:red", markersize=6, label=f"drawn, step {step}")
        ax_h.set_xlabel(xl)
        ax_h.set_ylabel(yl.replace(" (λ", "\n(λ"))
        ax_h.grid(True, alpha=0.3)
        ax_h.legend(loc="best", fontsize="small")
    nearest = requested is not None and step != requested
    where = {"end": "at the end", "peak": "at the peak", "step": f"at step {requested}"}[kind]
    if step is None:
        what = "final state"
    elif nearest:
        what = (f"step {step}, the written step nearest to step {requested}" +
                (" (the peak)" if kind == "peak" else "") + f"; λ = {lam:.6g}")
    else:
        what = f"step {step}, λ = {lam:.6g}"
    # the figure's title, not the wall's: a title longer than the wall's
    # axes ran off the figure's left edge (issue 17); the layout makes room
    fig.suptitle(f"{res.title or 'blockwall'}: crack pattern {where}\n{what}", wrap=True)
    return lam, mon, nearest
