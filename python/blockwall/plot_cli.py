"""tools/plot (blockwall-plot when installed): PNGs of a blockwall result
file, and its summary on stdout."""
import argparse
import os
import sys

from .plots import COLORS, plot_cracks, plot_history, plot_interface_stress, plot_wall
from .results import read
from .summary import summary

DEFAULT_ALL = 8    # up to this many interfaces, draw every stress diagram ...
DEFAULT_FIRST = 4  # ... else the first few


def _interfaces(text, n):
    if text is None:
        return list(range(n if n <= DEFAULT_ALL else DEFAULT_FIRST))
    try:
        chosen = [int(t) for t in text.split(",") if t.strip()]
    except ValueError:
        raise ValueError(f"--interfaces: comma-separated integers expected, got {text!r}") from None
    bad = [k for k in chosen if not 0 <= k < n]
    if bad:
        raise ValueError(f"--interfaces: {', '.join(map(str, bad))} out of range (the file has {n} interfaces)")
    return chosen


def _pushover_pictures(res, draw, outdir, stem, dpi, views=(None,)):
    """A pushover's capacity curve and its crack pattern at the peak and at
    the end (draw([(at, view), ...]): the pictures, plot_cracks in 2D,
    plot_cracks3d_many in 3D, where views are the --view list; with more
    than one view each picture's name ends in its view)."""
    path = os.path.join(outdir, f"{stem}_history.png")
    plot_history(res).figure.savefig(path, dpi=dpi)
    print(f"pushover history (load factor against the monitor dof): {path}")
    if res.state is None:
        print(f"no crack pattern: the file has no {'/portions/state' if res.dimension == 3 else '/interfaces/state'}")
        return
    pictures = [(at, view) for at in ("peak", "end") for view in views]
    for (at, view), cracks in zip(pictures, draw(pictures)):
        path = os.path.join(outdir, f"{stem}_cracks_{at}{'' if len(views) == 1 else '_' + view}.png")
        cracks.figure.savefig(path, dpi=dpi)
        which = (f"step {cracks.step}, the written step nearest to the peak, step {cracks.requested}" if cracks.nearest
                 else f"step {cracks.step}")
        how = f", {view} view" if view else ""
        drawn = (f", blocks warped x{cracks.scene.scale:g}, drawn by {cracks.renderer}"
                 if getattr(cracks, "scene", None) is not None else "")
        print(f"crack pattern at the {at} ({which}){how}{drawn}: {path}")


def _views(text):
    """--view: one view or several, comma-separated (drawn in one pvpython session)."""
    views = [v.strip() for v in text.split(",") if v.strip()]
    if not views or len(set(views)) != len(views):
        raise ValueError(f"--view: one or more distinct views, comma-separated, expected, got {text!r}")
    return views


def main(argv=None, prog="tools/plot"):
    p = argparse.ArgumentParser(
        prog=prog,
        description="Draw a blockwall result: the deformed wall (STEM_wall.png) and the normal and shear "
                    "stress diagrams along interfaces (STEM_stress_K.png); for a pushover also the capacity "
                    "curve (STEM_history.png) and the crack pattern at the peak and at the end "
                    "(STEM_cracks_peak.png, STEM_cracks_end.png; in 3D the warped blocks and the failed joint portions from "
                    "--view, STEM_cracks_peak_VIEW.png for each of several views); for a 3D result the deformed assembly from --view (STEM_3d_VIEW.png, drawn by "
                    "pvpython); print the file's attributes.")
    p.add_argument("file", help="HDF5 result file written by blockwall")
    p.add_argument("--outdir", help="directory for the PNGs (default: beside the file)")
    p.add_argument("--color", choices=list(COLORS), default="umag", help="block colour (default: umag)")
    p.add_argument("--scale", type=float,
                   help="displacement amplification (default: largest displacement ~5%% of the wall's size)")
    p.add_argument("--interfaces", help=f"comma-separated interface indices for the stress diagrams "
                                        f"(default: all if at most {DEFAULT_ALL}, else the first {DEFAULT_FIRST})")
    p.add_argument("--dpi", type=int, default=150)
    p.add_argument("--view", help="3D results: iso, front, back, side or top, or several of them "
                                  "comma-separated (iso,front,top), drawn in one pvpython session "
                                  "(default: iso)")
    p.add_argument("--renderer", choices=["auto", "pvpython", "matplotlib"], default="auto",
                   help="3D pushovers: who draws the crack pattern (default: pvpython where it and a display "
                        "for it, or Xvfb, are found, else matplotlib)")
    args = p.parse_args(argv)
    try:
        if args.scale is not None and not args.scale > 0:
            raise ValueError(f"--scale must be > 0, got {args.scale:g}")
        views = _views(args.view or "iso")
        res = read(args.file)
        chosen = _interfaces(args.interfaces, res.ninterfaces)
    except (OSError, ValueError) as e:
        print(f"plot: error: {e}", file=sys.stderr)
        return 1

    print(summary(res))
    outdir = args.outdir or os.path.dirname(args.file) or "."
    os.makedirs(outdir, exist_ok=True)
    stem = os.path.splitext(os.path.basename(args.file))[0]
    if res.dimension == 3:
        if res.history:
            # a 3D pushover: the capacity curve and the crack pattern (pvpython or matplotlib)
            from .cracks3d import plot_cracks3d_many
            try:
                _pushover_pictures(res, lambda pictures: plot_cracks3d_many(res, pictures, args.renderer, args.scale),
                                   outdir, stem, args.dpi, views)
            except (RuntimeError, ValueError) as e:
                print(f"plot: error: {e}", file=sys.stderr)
                return 1
            return 0
        from .plot3d import render3d_views
        paths = {view: os.path.join(outdir, f"{stem}_3d_{view}.png") for view in views}
        try:
            scale = render3d_views(args.file, paths, scale=args.scale, res=res)
        except (RuntimeError, ValueError) as e:
            print(f"plot: error: {e}", file=sys.stderr)
            return 1
        for view, path in paths.items():
            print(f"3D assembly from the {view} view, displacements x{scale:g}, coloured by |u|; joints by N/A: {path}")
        return 0
    if args.view is not None:
        print(f"plot: --view {args.view} left aside: it chooses the camera of a 3D result, and this 2D result "
              f"is drawn in its plane", file=sys.stderr)
    wall = plot_wall(res, args.color, args.scale)
    path = os.path.join(outdir, f"{stem}_wall.png")
    wall.figure.savefig(path, dpi=args.dpi)
    print(f"wall, displacements x{wall.scale:g}: {path}")
    if res.history:
        _pushover_pictures(res, lambda pictures: [plot_cracks(res, at) for at, _ in pictures], outdir, stem, args.dpi)
    if res.stress is None:
        print("no stress diagrams: the file has no /interfaces/stress (output.stresses false)")
        return 0
    for k in chosen:
        path = os.path.join(outdir, f"{stem}_stress_{k}.png")
        plot_interface_stress(res, k).figure.savefig(path, dpi=args.dpi)
        print(f"stresses along interface {k}: {path}")
    return 0
