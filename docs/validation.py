#!/usr/bin/env python3
"""The figures and numbers of docs/validation.md: the TU Eindhoven wall J4D
(examples/j4d.yaml) pushed to 4 mm, confined as tested, and the same wall
with the precompression held as a force (the top beam free to rise).

usage: docs/validation.py [--exe build/bin/blockwall] [--outdir docs/img/validation]
Prints the table of docs/validation.md; writes j4d_curve.png and
j4d_cracks.png."""
import argparse
import os
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "python"))
import blockwall as bw  # noqa: E402

SCENE = os.path.join(ROOT, "examples", "j4d.yaml")
FIXED = "  top_beam: {u2: -7.61237249e-05, w: 0}\n"


def first_peak(res, upto=2.0e-3):
    lam, mon = res.history["load_factor"], res.history["monitor"]
    k = int(np.argmax(np.where(mon <= upto, lam, -np.inf)))
    return k, lam[k], mon[k]


def run_both(exe, tmp):
    out = {}
    for name, text in (("confined", None), ("force held", "held")):
        scene = SCENE
        if text:
            with open(SCENE) as f:
                t = f.read().replace(FIXED, "  top_beam: {w: 0}\nloads:\n  top_beam: [0, -29700, 0]\n")
            scene = os.path.join(tmp, "held.yaml")
            with open(scene, "w") as f:
                f.write(t)
        h5 = os.path.join(tmp, name.replace(" ", "_") + ".h5")
        bw.run(scene, ["-output_file", h5, "-output_steps", "all"], 1, exe=exe)
        out[name] = bw.read(h5)
    return out


def crack_segments(res, jump, threshold):
    """Line segments of the portions whose plastic opening (or slip) exceeds
    the threshold: (segments, values)."""
    t = np.column_stack([np.cos(res.angle), np.sin(res.angle)])
    segs, vals = [], []
    m = jump.shape[1]
    for k in range(res.ninterfaces):
        a = res.center[k] - 0.5 * res.length[k] * t[k]
        for p in range(m):
            if jump[k, p] > threshold:
                segs.append([a + res.length[k] * p / m * t[k], a + res.length[k] * (p + 1) / m * t[k]])
                vals.append(jump[k, p])
    return segs, np.array(vals)


def figures(runs, outdir):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection, PolyCollection

    os.makedirs(outdir, exist_ok=True)
    fig, ax = plt.subplots(figsize=(7, 4.5), layout="constrained")
    ax.axhspan(50, 57, xmin=0, xmax=1, color="0.85", zorder=0, label="test J4D: peak 50–57 kN (published range)")
    for name, style in (("confined", "-"), ("force held", "--")):
        r = runs[name]
        k, lam, mon = first_peak(r)
        ax.plot(1e3 * r.history["monitor"], 1e-3 * r.history["load_factor"], style, label=f"blockwall, {name}")
        ax.plot([1e3 * mon], [1e-3 * lam], "ko", markersize=4)
    ax.set_xlabel("horizontal displacement of the top beam [mm]")
    ax.set_ylabel("horizontal force [kN]")
    ax.set_xlim(0, 4)
    ax.set_ylim(0, None)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="lower right", fontsize="small")
    ax.set_title("TU Eindhoven wall J4D (0.30 MPa): capacity curve")
    fig.savefig(os.path.join(outdir, "j4d_curve.png"), dpi=120)
    plt.close(fig)

    r = runs["confined"]
    fig, ax = plt.subplots(figsize=(6, 6.2), layout="constrained")
    polys = [r.vertices[r.offsets[b]:r.offsets[b + 1]] for b in range(r.nblocks)]
    ax.add_collection(PolyCollection(polys, facecolors="0.93", edgecolors="0.6", linewidths=0.4))
    for comp, color, label in ((1, "tab:red", "plastic opening"), (0, "tab:blue", "plastic slip")):
        segs, vals = crack_segments(r, np.abs(r.plastic_jump[:, :, comp]), 2e-5)
        if segs:
            w = 0.8 + 3.0 * np.sqrt(vals / vals.max())
            ax.add_collection(LineCollection(segs, colors=color, linewidths=w, label=f"{label} > 0.02 mm (max {1e3 * vals.max():.2f} mm)"))
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.08), fontsize="small", ncol=1)
    ax.set_title("J4D at 4 mm: permanent joint openings and slips")
    fig.savefig(os.path.join(outdir, "j4d_cracks.png"), dpi=120)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "bin", "blockwall"))
    ap.add_argument("--outdir", default=os.path.join(ROOT, "docs", "img", "validation"))
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        runs = run_both(args.exe, tmp)
        print("| set-up | first peak [kN] | at [mm] | force at 1 mm [kN] | at 4 mm [kN] | steps | Newton its | stop |")
        print("|---|---:|---:|---:|---:|---:|---:|---|")
        for name, r in runs.items():
            k, lam, mon = first_peak(r)
            h = r.history
            at1 = np.interp(1e-3, h["monitor"], h["load_factor"])
            print(f"| {name} | {lam / 1e3:.1f} | {mon * 1e3:.2f} | {at1 / 1e3:.1f} | {h['load_factor'][-1] / 1e3:.1f} | "
                  f"{len(h['load_factor']) - 1} | {r.solver['newton_iterations']} | {r.solver['stop_reason'][:60]} |")
        # where the joints have cracked at the end, by interface kind
        r = runs["confined"]
        opening = np.abs(r.plastic_jump[:, :, 1]).max(1)
        slip = np.abs(r.plastic_jump[:, :, 0]).max(1)
        print(f"interfaces with a plastic opening > 0.02 mm: {(opening > 2e-5).sum()}, with a plastic slip > 0.02 mm: {(slip > 2e-5).sum()} of {r.ninterfaces}")
        figures(runs, args.outdir)
    print(f"figures in {args.outdir}")


if __name__ == "__main__":
    main()
