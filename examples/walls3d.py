#!/usr/bin/env python3
"""The 3D gallery's geometry, written with the Python package (bw.box,
bw.prism, bw.Geometry): a free-standing wall of courses, a U-shaped wall
with interlocked corners, and a barrel vault. Their scenes are
examples/cantilever3d.yaml, u_wall.yaml and vault.yaml.

    python3 examples/walls3d.py [cantilever|u_wall|vault] [GEOMETRY.h5]
    mpiexec -n 2 build/bin/blockwall -scene examples/u_wall.yaml

Axes: X2 up, a wall's length along X1 and its thickness along X3.

cantilever  N courses of one block each, L x h x t (length along X1,
            thickness along X3), on a foundation; joints of thickness e.
            Sets: foundation, courses, top.
u_wall      a facade along X1 (length L) and two return walls along X3
            (length R) at its ends, all of thickness t, in courses of height
            h: a running bond of units l_u long in every wall, and at the
            corners the courses alternate which wall runs through (the
            facade's end unit covers the return's end on even courses, the
            return's end unit covers the facade's on odd ones), so that
            every corner is interlocked. Sets: foundation, facade, returns,
            top_facade (the facade's top course), units.
vault       examples/arch.py's arch extruded along X3 in `rings` rings of
            depth d, the voussoirs of adjacent rings joined by joints
            normal to X3 (their frame: b = X2 projected, model.md). Sets:
            springers, voussoirs, crown (the middle voussoirs of every
            ring), crown_mid (the crown voussoir of the middle ring)."""
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.realpath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "python"))
import blockwall as bw  # noqa: E402
sys.path.insert(0, HERE)
import arch as arch2d  # noqa: E402

CANTILEVER = dict(courses=10, length=1.0, height=0.1, thickness=0.2, e=0.01, foundation_height=0.2)
U_WALL = dict(facade_units=6, return_units=3, courses=8, lu=0.25, hu=0.06, t=0.12, e=0.01)
VAULT = dict(rings=3, ring_depth=0.4)


def cantilever(courses=10, length=1.0, height=0.1, thickness=0.2, e=0.01, foundation_height=0.2):
    g = bw.Geometry()
    g.add_block(bw.box(0, -e - foundation_height, 0, length, -e, thickness), sets=["foundation"])
    for k in range(courses):
        y0 = k * (height + e)
        g.add_block(bw.box(0, y0, 0, length, y0 + height, thickness), sets=["courses"] + (["top"] if k == courses - 1 else []))
    return g


def u_wall(facade_units=6, return_units=3, courses=8, lu=0.25, hu=0.06, t=0.12, e=0.01):
    """Facade along X1 at x3 in [0, t]; returns along X3 at x1 in [0, t] and
    [L - t, L], from x3 = 0 to x3 = R. Units of length lu (the end units of a
    wall cut to fit), joints e."""
    L = facade_units * lu + (facade_units - 1) * e
    R = return_units * lu + (return_units - 1) * e
    g = bw.Geometry()
    g.add_block(bw.box(-0.1, -e - 0.15, -0.1, L + 0.1, -e, R + 0.1), sets=["foundation"])

    def row(a, b, n_cut):
        """Cut [a, b] into units of length ~lu with joints e (n_cut units)."""
        n = max(1, n_cut)
        w = (b - a - (n - 1) * e) / n
        return [(a + k * (w + e), a + k * (w + e) + w) for k in range(n)]

    for c in range(courses):
        y0, y1 = c * (hu + e), c * (hu + e) + hu
        top = c == courses - 1
        if c % 2 == 0:
            # the facade runs through both corners: x1 in [0, L], x3 in [0, t]
            for k, (a, b) in enumerate(row(0, L, facade_units)):
                g.add_block(bw.box(a, y0, 0, b, y1, t), sets=["facade", "units"] + (["top_facade"] if top else []))
            # returns start behind the facade: x3 in [t + e, R]
            for x0 in (0.0, L - t):
                for a, b in row(t + e, R, return_units):
                    g.add_block(bw.box(x0, y0, a, x0 + t, y1, b), sets=["returns", "units"])
        else:
            # the returns run through: x3 in [0, R]; the facade between them
            for x0 in (0.0, L - t):
                for a, b in row(0, R, return_units):
                    g.add_block(bw.box(x0, y0, a, x0 + t, y1, b), sets=["returns", "units"])
            for a, b in row(t + e, L - t - e, facade_units - 1):
                g.add_block(bw.box(a, y0, 0, b, y1, t), sets=["facade", "units"] + (["top_facade"] if top else []))
    return g


def vault(rings=3, ring_depth=0.4):
    g2, _ = arch2d.arch(**{**arch2d.SPAN, "depth": ring_depth})
    e = arch2d.SPAN["e"]
    n = arch2d.SPAN["n"]
    g = bw.Geometry()
    for r in range(rings):
        z0 = r * (ring_depth + e)
        for b, poly in enumerate(g2.blocks):
            sets = ["springers"] if b in (0, len(g2.blocks) - 1) else ["voussoirs"]
            if b == 1 + n // 2:
                sets += ["crown"] + (["crown_mid"] if r == rings // 2 else [])
            g.add_block(bw.prism(poly, z0, z0 + ring_depth), sets=sets)
    return g


MAKERS = {"cantilever": (cantilever, CANTILEVER), "u_wall": (u_wall, U_WALL), "vault": (vault, VAULT)}

if __name__ == "__main__":
    which = sys.argv[1] if len(sys.argv) > 1 else "u_wall"
    out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(HERE, f"{which}.h5")
    make, params = MAKERS[which]
    g = make(**params)
    g.write(out)
    print(f"{out}: {len(g.blocks)} blocks")
