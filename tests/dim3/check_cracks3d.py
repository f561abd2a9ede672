"""tools/plot on a 3D pushover (the tilted running-bond wall of
check_nonlinear3d.py, every step written): the capacity curve and the
crack pattern at the peak and at the end. The portions drawn are rebuilt
from the interface polygons (python/blockwall/cracks3d.py): their number
per interface equals /interfaces/portion_offsets, their areas and
centroids /portions/area and /portions/center (1e-12 of the interface's
area and 1e-9 of the wall's size), the states drawn and the legend's
counts are the file's (/portions/state at the end, /steps/NNNNNN at the
peak's step), and the PNGs are written, of which the wall covers a good
part.

usage: check_cracks3d.py"""
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(ROOT, "python"))
sys.path.insert(0, HERE)
from bwrun import Failure, call, expect, read, run  # noqa: E402
import blockwall as bw  # noqa: E402
from blockwall.cracks3d import _area_centroid, plot_cracks3d, portion_polygons  # noqa: E402
import check_nonlinear3d as n3  # noqa: E402


def main():
    import matplotlib.image as mpimg
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "tilt.yaml")
        with open(scene, "w") as f:
            f.write(n3.WALL3.format(mb=3).replace("stresses: true, xdmf: false", "stresses: true, xdmf: false, steps: every_4"))
        out = os.path.join(tmp, "tilt.h5")
        run(scene, ["-output_file", out])
        res, raw = bw.read(out), read(out)
        polys = portion_polygons(res)
        expect(len(polys) == len(raw["portions/area"]), f"{len(polys)} portions rebuilt, {len(raw['portions/area'])} in the file")
        worst_a = worst_c = 0.0
        size = float(np.ptp(res.vertices, axis=0).max())
        off = raw["interfaces/portion_offsets"]
        for k in range(res.ninterfaces):
            t, b, G = res.frame[k][0], res.frame[k][2], res.center[k]
            for p in range(off[k], off[k + 1]):
                uv = np.column_stack([(polys[p] - G) @ t, (polys[p] - G) @ b])
                a, c = _area_centroid(uv)
                worst_a = max(worst_a, abs(a - raw["portions/area"][p]) / res.area[k])
                worst_c = max(worst_c, float(np.max(np.abs(c - raw["portions/center"][p]))) / size)
        expect(worst_a <= 1e-12 and worst_c <= 1e-9, f"rebuilt portions: areas {worst_a:.2e}, centroids {worst_c:.2e}")
        for at in ("end", "peak"):
            c = plot_cracks3d(res, at)
            want = raw["portions/state"] if at == "end" else raw[f"steps/{c.step:06d}/portions/state"]
            expect(np.array_equal(c.state, want), f"{at}: the states drawn are not the file's")
            expect(np.array_equal(c.counts, np.bincount(want, minlength=4)), f"{at}: legend counts {c.counts}")
            expect(c.counts[1:].sum() > 0, f"{at}: no portion cracked")
        p = call([sys.executable, os.path.join(ROOT, "tools", "plot"), out], what="tools/plot")
        expect(p.returncode == 0, f"tools/plot: exit {p.returncode}\n{p.stdout}\n{p.stderr}")
        for name in ("tilt_history.png", "tilt_cracks_peak.png", "tilt_cracks_end.png"):
            path = os.path.join(tmp, name)
            expect(os.path.exists(path), f"tools/plot did not write {name}:\n{p.stdout}")
            img = mpimg.imread(path)[..., :3]
            drawn = float(np.mean(np.any(img < 0.95, axis=-1)))
            expect(drawn > 0.03, f"{name}: {drawn:.1%} of the pixels drawn")
            print(f"{name}: {drawn:.0%} of the pixels drawn")
        print(f"portions rebuilt: {len(polys)}, areas to {worst_a:.1e}, centroids to {worst_c:.1e}; "
              f"states at the end {np.bincount(raw['portions/state'], minlength=4).tolist()}")


if __name__ == "__main__":
    try:
        main()
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
    print("ok")
