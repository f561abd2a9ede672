"""tools/plot and the blockwall package's plots against the HDF5 datasets.

The command must write non-empty PNGs (decoded back into pixels that are
not one flat colour) and print the root and /solver attributes; the numbers
the plot functions drew must be the file's: the stress diagrams' step lines
are the /interfaces/stress values over the m equal portions of [-l/2, l/2],
the deformed polygons are x + s u(x) with the rigid-body u of each block,
the interfaces are coloured by N/(l s), and the automatic amplification
makes the largest vertex displacement ~5 % of the wall's size.

For the paper's case 2 (two_blocks.yaml as it is: F1 = 1000 N, F2 = -1000
N, l = 0.2 m, s = 0.1 m) the shear diagram is also checked against the
closed form F1/(l s) = 50 kPa on every portion (check_paper.py), i.e. the
paper's Fig. 8 drawn right.

A pushover (a 4-course running-bond wall with softening mortar joints
pushed past its peak under displacement control, every step written):
the capacity curve drawn is /history/monitor against /history/load_factor,
exactly; the crack pattern at the end is the top-level /interfaces/state
(its counts per state np.bincount of it, each portion a segment of its
joint line G + x t over the m equal portions of [-l/2, l/2], in the
colour of its state), the one at the peak that of /steps/NNNNNN of the
step of largest /history/load_factor, which is /solver peak_load_factor;
the run again writing every (p+1)-th step only, p the peak step, so that
the peak's state is not in the file: the step drawn is the written one
nearest to p (the later of two as near) and the title says so.

Modes: case2 (one rank, default options; a linear result: no history, no
crack pattern, and the functions that need them refuse it), demo
(examples/demo.yaml on 2 ranks, --color w --scale 500 --interfaces 0,5,7),
pushover."""
import os
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
TOOLS = os.path.join(HERE, "..", "..", "tools")
from bwrun import ENV, Failure, call, expect, run  # noqa: E402

import blockwall as post  # noqa: E402  (this checkout's python/, put on sys.path by bwrun)
from matplotlib.image import imread  # noqa: E402

TWO_BLOCKS = os.path.join(HERE, "..", "paper", "two_blocks.yaml")
DEMO = os.path.join(TOOLS, "..", "examples", "demo.yaml")
# Small enough to run in a fraction of a second, big enough to crack: bed
# and head joints of softening mortar, pushed at the top beam to 1.5 mm.
PUSHOVER = """title: pushover for the crack pattern
geometry:
  generator: running_bond
  depth: 0.1
  running_bond: {courses: 4, units_per_course: 3, unit_length: 0.21, unit_height: 0.052, foundation: true, top_beam: true}
joints: {law: dry, kn: 82.0e9, kt: 36.0e9, thickness: 0.01, strength: {tension: 0.25e6, cohesion: 0.35e6, friction: 0.75, tension_energy: 18, shear_energy: 125}}
discretization: {m: 8}
supports: {foundation: {u1: 0, u2: 0, w: 0}, top_beam: {w: 0}}
loads: {top_beam: [0, -25000, 0]}
analysis:
  type: pushover
  pushover: {loads: {top_beam: [1, 0, 0]}, control: displacement, monitor: {set: top_beam, dof: u1}, target: 1.5e-3, steps: 15}
output: {stresses: true, xdmf: false, steps: all}
"""
STATE_NAMES = {0: "elastic", 1: "open", 2: "sliding", 3: "open and sliding"}
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"



def suptitle(fig):
    """The figure's title (Figure.get_suptitle is matplotlib 3.8's; Debian 12 has 3.6)."""
    if hasattr(fig, "get_suptitle"):
        return fig.get_suptitle()
    return fig._suptitle.get_text() if fig._suptitle is not None else ""

def png_ok(path):
    expect(os.path.isfile(path) and os.path.getsize(path) > 0, f"{path} missing or empty")
    with open(path, "rb") as f:
        expect(f.read(8) == PNG_SIGNATURE, f"{path} is not a PNG")
    pixels = imread(path)
    expect(pixels.ndim == 3 and pixels.shape[0] > 100 and pixels.shape[1] > 100, f"{path}: {pixels.shape}")
    expect(np.ptp(pixels[..., :3]) > 0.5, f"{path} is blank")


def check_summary(stdout, h5file):
    """Every root (but the scene text) and /solver attribute printed with its value."""
    printed = {}
    for line in stdout.splitlines():
        if line.startswith("  "):
            key, _, value = line.strip().partition("  ")
            printed[key] = value.strip()
    with h5py.File(h5file, "r") as f:
        attrs = list(f.attrs.items()) + list(f["solver"].attrs.items())
    for key, v in attrs:
        expect(key in printed, f"attribute {key} not in the summary")
        if key == "scene":
            continue
        v = v.decode() if isinstance(v, bytes) else v
        if isinstance(v, str):
            expect(printed[key] == (v or "-"), f"{key}: printed {printed[key]!r}, file {v!r}")
        else:
            got = float(printed[key])
            expect(abs(got - float(v)) <= 1e-5 * abs(float(v)), f"{key}: printed {got}, file {v}")


def check_stress_plot(res, k, f):
    sp = post.plot_interface_stress(res, k)
    stress = f["interfaces/stress"][k]
    l = f["interfaces/length"][k]
    m = stress.shape[0]
    edges = -l / 2 + l * np.arange(m + 1) / m
    for col, name in ((0, "shear"), (1, "normal")):
        line = sp.lines[name]
        x, y = np.asarray(line.get_xdata()), np.asarray(line.get_ydata())
        expect(len(x) == 2 * m and len(y) == 2 * m, f"interface {k} {name}: {len(x)} points drawn for m = {m}")
        # portion p is the segment x[2p] .. x[2p+1], drawn at height y[2p] = y[2p+1]
        expect(np.allclose(x[0::2], edges[:-1], rtol=0, atol=1e-14 * l)
               and np.allclose(x[1::2], edges[1:], rtol=0, atol=1e-14 * l),
               f"interface {k} {name}: portions drawn at {x}, expected the ends {edges}")
        expect(np.array_equal(y[0::2], stress[:, col]) and np.array_equal(y[1::2], stress[:, col]),
               f"interface {k} {name}: drawn {y[0::2]}, HDF5 {stress[:, col]}")
    return sp


def check_wall(res, f, scale=None, color="umag"):
    wp = post.plot_wall(res, color=color, scale=scale)
    x, off = f["blocks/vertices"][()], f["blocks/offsets"][()]
    disp, cen = f["blocks/displacement"][()], f["blocks/centroid"][()]
    size = np.max(x.max(axis=0) - x.min(axis=0))
    umax = 0.0
    for b in range(len(off) - 1):
        p = x[off[b]:off[b + 1]]
        u = np.column_stack([disp[b, 0] - disp[b, 2] * (p[:, 1] - cen[b, 1]), disp[b, 1] + disp[b, 2] * (p[:, 0] - cen[b, 0])])
        umax = max(umax, np.max(np.hypot(u[:, 0], u[:, 1])))
        expect(np.allclose(wp.polygons[b], p + wp.scale * u, rtol=0, atol=1e-12 * size), f"block {b}: deformed polygon")
    if scale is None:
        ratio = wp.scale * umax / size
        expect(0.035 <= ratio <= 0.067, f"amplification {wp.scale:g}: largest displacement {ratio:.3f} of the size, not ~0.05")
    else:
        expect(wp.scale == scale, f"--scale {scale} drawn as {wp.scale}")
    expect(f"×{wp.scale:g}" in wp.ax.get_title(), f"the title does not state the factor: {wp.ax.get_title()!r}")
    column = {"u1": 0, "u2": 1, "w": 2}
    want = np.hypot(disp[:, 0], disp[:, 1]) if color == "umag" else disp[:, column[color]]
    expect(np.array_equal(wp.block_values, want), f"blocks coloured by {wp.block_values}, expected {color} {want}")
    sigma = f["interfaces/resultant"][:, 1] / (f["interfaces/length"][()] * f.attrs["depth"])
    expect(np.allclose(wp.interface_values, sigma, rtol=1e-14, atol=0), "interfaces not coloured by N/(l s)")
    return wp


def check_history(res, f):
    """The capacity curve holds and draws /history exactly."""
    hp = post.plot_history(res)
    mon, lam = f["history/monitor"][()], f["history/load_factor"][()]
    expect(np.array_equal(hp.monitor, mon) and np.array_equal(hp.load_factor, lam),
           f"capacity curve holds {hp.monitor}, {hp.load_factor}; /history {mon}, {lam}")
    line = hp.ax.lines[0]
    xs, _, ys, _ = post.curve_axes(res)
    expect(np.array_equal(line.get_xdata(), mon * xs) and np.array_equal(line.get_ydata(), lam * ys),
           "the curve drawn is not /history/monitor against /history/load_factor (in the axes' units)")
    # the axes as a test report reads them (issue 17): the monitor named, in
    # mm; the load in the pattern's unit (1 N on top_beam: lambda N, in kN)
    sv = f["solver"].attrs
    expect(sv["monitor_set"] == b"top_beam" or sv["monitor_set"] == "top_beam", f"monitor_set {sv['monitor_set']!r}")
    expect(float(sv["pattern_resultant"]) == 1.0, f"pattern_resultant {sv['pattern_resultant']!r} for a pattern of 1 N")
    expect(hp.ax.get_xlabel() == "u1 of top_beam [mm]" and xs == 1e3, f"x label {hp.ax.get_xlabel()!r}")
    expect(hp.ax.get_ylabel().startswith("load [kN]") and ys == 1e-3, f"y label {hp.ax.get_ylabel()!r}")
    # the envelope (its largest load the peak, its reach the monitor's) and the
    # bilinearisation of /solver: (0, 0) -> (d_y, F_y) -> (d_u, F_y) from step 0
    lines = {l.get_label(): l for l in hp.ax.lines}
    env = lines.get("envelope")
    sign = 1.0 if mon[-1] >= mon[0] else -1.0
    expect(env is not None and abs(env.get_ydata().max() - float(sv["peak_load_factor"]) * ys) <= 1e-12 * abs(env.get_ydata().max())
           and abs(env.get_xdata()[-1] - (mon[0] + sign * np.max(sign * (mon - mon[0]))) * xs) <= 1e-12 * abs(env.get_xdata()[-1]),
           "the envelope drawn does not reach the peak load and the monitor's reach")
    fy, dy, du = (float(sv[k]) for k in ("bilinear_yield_force", "bilinear_yield_displacement", "ultimate_displacement"))
    bil = [l for name, l in lines.items() if name.startswith("bilinear")]
    if np.isfinite(fy):
        want_x = (mon[0] + sign * np.array([0, dy, du])) * xs
        expect(len(bil) == 1 and np.allclose(bil[0].get_xdata(), want_x, rtol=1e-12, atol=0)
               and np.allclose(bil[0].get_ydata(), np.array([lam[0], fy, fy]) * ys, rtol=1e-12, atol=1e-300),
               f"bilinear line drawn {[(l.get_xdata(), l.get_ydata()) for l in bil]}, /solver gives d_y {dy}, d_u {du}, F_y {fy}")
    else:
        expect(not bil, "a bilinear line drawn where /solver has none")


def portion_ends(f):
    """(I, m, 2, 2) from the datasets: portion p of interface k runs from
    G + x_p t to G + x_(p+1) t, x_p = -l/2 + p l/m, t = (cos θ, sin θ)."""
    G, theta, l = f["interfaces/center"][()], f["interfaces/angle"][()], f["interfaces/length"][()]
    m = f.attrs["m"]
    t = np.column_stack([np.cos(theta), np.sin(theta)])
    x = -l[:, None] / 2 + l[:, None] * np.arange(m + 1)[None, :] / m
    pts = G[:, None, :] + x[:, :, None] * t[:, None, :]
    return np.stack([pts[:, :-1], pts[:, 1:]], axis=2)


def check_cracks(res, f, at, state, step):
    """The crack pattern drawn `at` ("peak", "end") is `state` (the file's
    dataset of step `step`): counts, legend, every portion where it is, in
    the colour of its state."""
    cp = post.plot_cracks(res, at)
    expect(cp.step == step, f"{at}: step {cp.step} drawn, expected {step}")
    expect(np.array_equal(cp.state, state), f"{at}: the states drawn are not those of step {step}")
    want = np.bincount(state.ravel().astype(np.int64), minlength=4)
    expect(np.array_equal(cp.counts, want), f"{at}: counts {cp.counts}, np.bincount of the file's state {want}")
    legend = [t.get_text() for t in cp.ax.get_legend().get_texts()]
    expect(legend == [f"{STATE_NAMES[s]}: {want[s]}" for s in range(4)], f"{at}: legend {legend}, counts {want}")
    ends = portion_ends(f)
    size = np.max(np.abs(f["blocks/vertices"][()]))
    for s in range(4):
        drawn = np.asarray(cp.lines[s].get_segments()).reshape(-1, 2, 2)
        expect(len(drawn) == want[s], f"{at}: {len(drawn)} segments drawn in state {s}, the file has {want[s]}")
        expect(np.allclose(drawn, ends[state == s], rtol=0, atol=1e-14 * size),
               f"{at}: the state-{s} segments are not the portions of the joints in that state")
    # red open, blue sliding, purple both: the dominant channels of each colour
    (r1, g1, b1), (r2, g2, b2), (r3, g3, b3) = (cp.lines[s].get_colors()[0][:3] for s in (1, 2, 3))
    expect(r1 > max(g1, b1) and b2 > max(r2, g2) and min(r3, b3) > g3, "the states' colours are not red, blue, purple")
    expect(f"step {step}" in suptitle(cp.figure), f"{at}: the title does not name step {step}: {suptitle(cp.figure)!r}")
    # every text of the figure inside it once drawn (the title once ran off
    # its left edge, issue 17)
    fig = cp.figure
    fig.canvas.draw()
    box = fig.bbox
    for t in [fig._suptitle, cp.ax.xaxis.label, cp.ax.yaxis.label] + ([cp.ax_history.xaxis.label, cp.ax_history.yaxis.label] if cp.ax_history else []):
        e = t.get_window_extent(fig.canvas.get_renderer())
        expect(e.x0 >= box.x0 - 0.5 and e.x1 <= box.x1 + 0.5 and e.y0 >= box.y0 - 0.5 and e.y1 <= box.y1 + 0.5,
               f"{at}: {t.get_text()!r} drawn at {e} outside the figure {box}")
    return cp


def pushover(tmp):
    scene = os.path.join(tmp, "pushover.yaml")
    with open(scene, "w") as fh:
        fh.write(PUSHOVER)
    out, png = os.path.join(tmp, "push.h5"), os.path.join(tmp, "png")
    run(scene, ["-output_file", out])
    stdout, _ = plot_command(out, png)
    res = post.load(out)
    with h5py.File(out, "r") as f:
        lam = f["history/load_factor"][()]
        n = len(f["interfaces/length"])
        shown = range(n if n <= 8 else 4)  # tools/plot's default choice of stress diagrams
        want_png = ["push_wall.png", "push_history.png", "push_cracks_peak.png", "push_cracks_end.png",
                    *(f"push_stress_{k}.png" for k in shown)]
        expect(sorted(os.listdir(png)) == sorted(want_png), f"PNGs written: {sorted(os.listdir(png))}")
        for name in want_png:
            png_ok(os.path.join(png, name))
        check_history(res, f)
        peak, last = int(np.argmax(lam)), len(lam) - 1
        expect(lam[peak] == f["solver"].attrs["peak_load_factor"],
               f"largest load factor {lam[peak]!r} of /history is not peak_load_factor {f['solver'].attrs['peak_load_factor']!r}")
        expect(0 < peak < last and lam[last] < lam[peak], f"the wall is not pushed past its peak: λ {lam}")
        written = sorted(int(k) for k in f["steps"])
        expect(written == list(range(last + 1)), f"output.steps all wrote steps {written} of 0..{last}")
        cp = check_cracks(res, f, "peak", f[f"steps/{peak:06d}/interfaces/state"][()], peak)
        expect(cp.requested == peak and not cp.nearest and "nearest" not in suptitle(cp.figure),
               f"the peak's own step {peak} was written, yet {cp.step} drawn as the nearest")
        end_state = f["interfaces/state"][()]
        expect(np.array_equal(end_state, f[f"steps/{last:06d}/interfaces/state"][()]),
               "the top-level state is not the last step's")
        cp = check_cracks(res, f, "end", end_state, last)
        expect(cp.counts[1:].sum() > 0, f"nothing cracked past the peak: counts {cp.counts}")
        expect(cp.load_factor == lam[last] and cp.monitor == f["history/monitor"][last], "end: λ and monitor marked")
    for at, step in (("peak", peak), ("end", last)):
        line = f"crack pattern at the {at} (step {step}): {os.path.join(png, f'push_cracks_{at}.png')}"
        expect(line in stdout, f"tools/plot did not print {line!r}:\n{stdout}")

    # the peak's step not written: the nearest written one is drawn, and said to be
    every = peak + 1
    out2, png2 = os.path.join(tmp, "every.h5"), os.path.join(tmp, "png2")
    run(scene, ["-output_file", out2, "-output_steps", f"every_{every}"])
    stdout, _ = plot_command(out2, png2)
    res = post.load(out2)
    with h5py.File(out2, "r") as f:
        expect(np.array_equal(f["history/load_factor"][()], lam), "every_N changed the analysis")
        check_history(res, f)
        written = sorted(int(k) for k in f["steps"])
        expect(peak not in written, f"every_{every} wrote the peak step {peak}: {written}")
        near = min(written, key=lambda s: (abs(s - peak), -s))
        cp = check_cracks(res, f, "peak", f[f"steps/{near:06d}/interfaces/state"][()], near)
        expect(cp.nearest and cp.requested == peak and f"nearest to step {peak}" in suptitle(cp.figure),
               f"the title does not say step {near} is the nearest to the peak {peak}: {suptitle(cp.figure)!r}")
        end = check_cracks(res, f, "end", f["interfaces/state"][()], last)
        line = (f"crack pattern at the peak (step {near}, the written step nearest to the peak, step {peak}): "
                f"{os.path.join(png2, 'every_cracks_peak.png')}")
        expect(line in stdout, f"tools/plot did not print {line!r}:\n{stdout}")
    for name in ("every_cracks_peak.png", "every_cracks_end.png"):
        png_ok(os.path.join(png2, name))
    print(f"pushover: {last + 1} steps, peak λ = {lam[peak]:.6g} at step {peak}; cracks at the peak "
          f"{np.bincount(res.steps[near].state.ravel(), minlength=4)} (every_{every}: step {near}), "
          f"at the end {end.counts}")


def linear_refused(res, stdout):
    """A linear result without strength: no capacity curve, no crack
    pattern, and the functions say why."""
    expect("pushover history" not in stdout and "crack pattern" not in stdout,
           f"tools/plot drew a pushover's pictures for a linear result:\n{stdout}")
    for draw, words in ((lambda: post.plot_history(res), "/history"), (lambda: post.peak_step(res), "/history"),
                        (lambda: post.plot_cracks(res, "end"), "/interfaces/state"),
                        (lambda: post.plot_cracks(res, "peak"), "/interfaces/state")):
        try:
            draw()
            raise Failure(f"a linear result drawn without {words}")
        except ValueError as e:
            expect(words in str(e), f"the error does not name {words}: {e}")


def plot_command(h5file, outdir, args=()):
    p = call([sys.executable, os.path.join(TOOLS, "plot"), h5file, "--outdir", outdir, *args], env=ENV, what="tools/plot")
    expect(p.returncode == 0, f"tools/plot failed ({p.returncode}):\n{p.stdout}\n{p.stderr}")
    return p.stdout, p.stderr


def main(mode):
    with tempfile.TemporaryDirectory() as tmp:
        if mode == "pushover":
            pushover(tmp)
            return
        out, png = os.path.join(tmp, "result.h5"), os.path.join(tmp, "png")
        if mode == "case2":
            run(TWO_BLOCKS, ["-output_file", out])
            # --view chooses a 3D result's camera: a 2D result says it is left aside, in one line
            stdout, stderr = plot_command(out, png, ["--view", "front"])
            lines = [line for line in stderr.splitlines() if line.strip()]
            expect(len(lines) == 1 and "--view front left aside" in lines[0] and "2D" in lines[0],
                   f"tools/plot --view on a 2D result: stderr {stderr!r}")
            shown, scale, color = [0], None, "umag"
        elif mode == "demo":
            expect(os.path.isfile(DEMO), f"{DEMO} does not exist")
            run(DEMO, ["-output_file", out], np_ranks=2)
            stdout, stderr = plot_command(out, png, ["--color", "w", "--scale", "500", "--interfaces", "0,5,7"])
            expect("--view" not in stderr, f"tools/plot without --view on a 2D result: stderr {stderr!r}")
            shown, scale, color = [0, 5, 7], 500.0, "w"
        else:
            raise SystemExit(f"unknown mode {mode}")
        expect(sorted(os.listdir(png)) == sorted(["result_wall.png"] + [f"result_stress_{k}.png" for k in shown]),
               f"PNGs written: {sorted(os.listdir(png))}")
        for name in os.listdir(png):
            png_ok(os.path.join(png, name))
        check_summary(stdout, out)

        res = post.load(out)
        with h5py.File(out, "r") as f:
            wp = check_wall(res, f, scale=scale, color=color)
            expect(f"x{wp.scale:g}:" in stdout, "the command does not print the amplification")
            for k in shown:
                sp = check_stress_plot(res, k, f)
            if mode == "case2":
                f1, l, s = 1000.0, 0.2, 0.1
                shear = sp.lines["shear"].get_ydata()
                expect(np.max(np.abs(shear - f1 / (l * s))) <= 1e-10 * f1 / (l * s),
                       f"case 2 shear diagram {shear[::2]} is not F1/(l s) = {f1 / (l * s)}")
                linear_refused(res, stdout)
    print(f"{mode}: PNGs, summary and plotted numbers match the HDF5 file")


if __name__ == "__main__":
    try:
        main(*sys.argv[1:])
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
    print("ok")
