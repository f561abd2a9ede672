"""tools/plot on a 3D result: the summary (dimension 3, the blocks and
interfaces counted), and the picture drawn by pvpython from the XDMF: a PNG
of the requested size, of which the assembly covers a good part (more than
8 % of the pixels not background white; a blank render, colour bars
only, has about 1 %: measured 26 %, 28 % and 11 % for iso, front, top), for each view of
`--view iso,front,top` (the three drawn in one pvpython session, each from its own camera: any two differ in more
than 10 % of their pixels, 26-29 % measured); a 3D result without its XDMF is refused with one line.

usage: check_plot3d.py"""
import os
import re
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from bwrun import Failure, call, expect, run  # noqa: E402


def main():
    import matplotlib.image as mpimg
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "wall3.h5")
        run(os.path.join(HERE, "wall.yaml"), ["-output_file", out, "-output_xdmf", "true", "-loads_top_beam", "3000,-1.0e4,800,0,0,0"])
        views = ("iso", "front", "top")
        p = call([sys.executable, os.path.join(ROOT, "tools", "plot"), out, "--view", ",".join(views)], what="tools/plot")
        expect(p.returncode == 0, f"tools/plot --view {','.join(views)}: exit {p.returncode}\n{p.stdout}\n{p.stderr}")
        expect(re.search(r"^\s+dimension\s+3$", p.stdout, re.M) and re.search(r"^\s+blocks\s+16$", p.stdout, re.M),
               f"the summary does not give dimension 3 and 16 blocks:\n{p.stdout}")
        images = {}
        for view in views:
            png = os.path.join(tmp, f"wall3_3d_{view}.png")
            expect(os.path.exists(png) and re.search(rf"^3D assembly from the {view} view, .*: {re.escape(png)}$", p.stdout, re.M),
                   f"{png} not written or not named:\n{p.stdout}")
            img = images[view] = mpimg.imread(png)[:, :, :3]
            expect(img.shape[0] == 1000 and img.shape[1] == 1600, f"{view}: picture of {img.shape}")
            ink = float(np.mean(np.any(img < 0.95, axis=2)))
            print(f"--view {view}: {png}, {ink:.0%} of the pixels drawn")
            expect(ink > 0.08, f"--view {view}: only {ink:.1%} of the picture is drawn")
        for a, b in ((0, 1), (0, 2), (1, 2)):
            differ = float(np.mean(np.any(np.abs(images[views[a]] - images[views[b]]) > 0.02, axis=2)))
            print(f"{views[a]} and {views[b]}: {differ:.0%} of the pixels differ")
            expect(differ > 0.10, f"the {views[a]} and {views[b]} pictures differ in only {differ:.1%} of their pixels")
        os.unlink(out[:-3] + ".xdmf")
        p = call([sys.executable, os.path.join(ROOT, "tools", "plot"), out], what="tools/plot")
        lines = [l for l in p.stderr.splitlines() if l.strip()]
        expect(p.returncode == 1 and len(lines) == 1 and "output.xdmf: true" in lines[0], f"without the XDMF: exit {p.returncode}, {p.stderr!r}")
        print(f"without the XDMF: {lines[0]}")


if __name__ == "__main__":
    try:
        main()
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
