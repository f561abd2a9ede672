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

Modes: case2 (one rank, default options), demo (examples/demo.yaml on 2
ranks, --color w --scale 500 --interfaces 0,5,7)."""
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
TOOLS = os.path.join(HERE, "..", "..", "tools")
from bwrun import ENV, Failure, expect, run  # noqa: E402

import blockwall as post  # noqa: E402  (this checkout's python/, put on sys.path by bwrun)
from matplotlib.image import imread  # noqa: E402

TWO_BLOCKS = os.path.join(HERE, "..", "paper", "two_blocks.yaml")
DEMO = os.path.join(TOOLS, "..", "examples", "demo.yaml")
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


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


def plot_command(h5file, outdir, args=()):
    p = subprocess.run([sys.executable, os.path.join(TOOLS, "plot"), h5file, "--outdir", outdir, *args],
                       capture_output=True, text=True, env=ENV, timeout=600)
    expect(p.returncode == 0, f"tools/plot failed ({p.returncode}):\n{p.stdout}\n{p.stderr}")
    return p.stdout


def main(mode):
    with tempfile.TemporaryDirectory() as tmp:
        out, png = os.path.join(tmp, "result.h5"), os.path.join(tmp, "png")
        if mode == "case2":
            run(TWO_BLOCKS, ["-output_file", out])
            stdout = plot_command(out, png)
            shown, scale, color = [0], None, "umag"
        elif mode == "demo":
            expect(os.path.isfile(DEMO), f"{DEMO} does not exist")
            run(DEMO, ["-output_file", out], np_ranks=2)
            stdout = plot_command(out, png, ["--color", "w", "--scale", "500", "--interfaces", "0,5,7"])
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
    print(f"{mode}: PNGs, summary and plotted numbers match the HDF5 file")


if __name__ == "__main__":
    try:
        main(*sys.argv[1:])
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
    print("ok")
