#!/usr/bin/env python3
"""The drawing examples/facade.dxf, made with ezdxf the way a CAD user would
draw it: a running-bond wall with a door and a window, block by block, in
millimetres, on layers foundation, masonry, lintels and top_beam.

    python3 examples/facade_dxf.py [DRAWING.dxf]        # default: facade.dxf beside this script
    tools/import_dxf examples/facade.dxf examples/facade.h5 --layer-sets
    mpiexec -n 2 build/bin/blockwall -scene examples/facade.yaml

The wall: 20 courses of 210 x 52 mm units with 10 mm joints, 11 units in
the even courses (half units at both ends of the odd ones), L = 2410 mm.
The door and the window jambs fall on head joints of the even courses, so
the odd courses end at the jambs with half units (100 mm). Over each
opening a lintel replaces the units of course 12 across it and one unit
beyond each jamb. The full units are INSERTs of one block definition
("UNIT"), the half units LWPOLYLINEs, the lintels HATCHes, the foundation
and the top beam 2D POLYLINEs: every entity kind import_dxf reads.

facade() gives the same blocks as a list of (layer, corners in mm), in the
drawing's order, for whoever wants to write them directly (the tests do)."""
import os
import sys

import numpy as np

LU, HU, E = 210.0, 52.0, 10.0            # unit length, height, joint [mm]
UNITS, COURSES = 11, 20
PITCH = LU + E
L = UNITS * PITCH - E                    # 2410 mm
HALF = (LU - E) / 2                      # 100 mm
DOOR = (1, 3, 0, 12)                     # jambs at x = 1*220-10 and 3*220; courses 0..11
WINDOW = (6, 9, 5, 12)                   # jambs at x = 6*220-10 and 9*220; courses 5..11
LINTEL_COURSE = 12
FOUNDATION_H, TOP_BEAM_H = 150.0, 150.0


def rect(x0, y0, x1, y1):
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], float)


def facade():
    """[(layer, kind, corners in mm)] in drawing order; kind is unit, half, lintel, foundation, top_beam."""
    openings = [(a * PITCH - E, b * PITCH, c0, c1) for a, b, c0, c1 in (DOOR, WINDOW)]
    lintels = [(a - 1, b, (a * PITCH - E) - PITCH, b * PITCH + LU + E) for a, b, *_ in (DOOR, WINDOW)]
    out = [("foundation", "foundation", rect(0, -E - FOUNDATION_H, L, -E))]
    for k in range(COURSES):
        y0 = k * (HU + E)
        if k % 2 == 0:
            pieces = [(i * PITCH, i * PITCH + LU, "unit", i) for i in range(UNITS)]
        else:
            pieces = [(0.0, HALF, "half", -1)] + [(HALF + E + i * PITCH, HALF + E + i * PITCH + LU, "unit", i)
                                                   for i in range(UNITS - 1)] + [(L - HALF, L, "half", -1)]
        if k == LINTEL_COURSE:
            # the even course's units a-1 .. b are replaced by one lintel [(a-1) pitch, b pitch + LU]
            keep = [p for p in pieces if not any(a <= p[3] <= b for a, b, *_ in lintels)]
            pieces = sorted(keep + [(a * PITCH, b * PITCH + LU, "lintel", -1) for a, b, *_ in lintels])
        for x0, x1, kind, _ in pieces:
            for ox0, ox1, c0, c1 in openings:
                if c0 <= k < c1 and x0 < ox1 and x1 > ox0:  # the piece meets the opening: keep what is outside
                    if x0 < ox0:
                        out.append(("masonry", "half" if ox0 - x0 < LU else kind, rect(x0, y0, ox0, y0 + HU)))
                    if x1 > ox1:
                        out.append(("masonry", "half" if x1 - ox1 < LU else kind, rect(ox1, y0, x1, y0 + HU)))
                    break
            else:
                out.append(("lintels" if kind == "lintel" else "masonry", kind, rect(x0, y0, x1, y0 + HU)))
    ytop = (COURSES - 1) * (HU + E) + HU
    out.append(("top_beam", "top_beam", rect(0, ytop + E, L, ytop + E + TOP_BEAM_H)))
    return out


def draw(path):
    import ezdxf
    doc = ezdxf.new("R2010", units=4)    # $INSUNITS 4: millimetres
    for name in ("foundation", "masonry", "lintels", "top_beam"):
        doc.layers.add(name)
    unit = doc.blocks.new("UNIT")        # a full unit, base point at its lower left corner, on layer 0
    unit.add_lwpolyline(rect(0, 0, LU, HU).tolist(), close=True)
    msp = doc.modelspace()
    for layer, kind, p in facade():
        attribs = {"layer": layer}
        if kind == "unit":
            msp.add_blockref("UNIT", tuple(p[0]), dxfattribs=attribs)
        elif kind == "half":
            msp.add_lwpolyline(p.tolist(), close=True, dxfattribs=attribs)
        elif kind == "lintel":
            hatch = msp.add_hatch(color=8, dxfattribs=attribs)
            edges = hatch.paths.add_edge_path()
            for a, b in zip(p, np.roll(p, -1, axis=0)):
                edges.add_line(tuple(a), tuple(b))
        else:
            msp.add_polyline2d(p.tolist(), close=True, dxfattribs=attribs)
    msp.add_text("door", height=40, dxfattribs={"layer": "masonry"}).set_placement((300, 300))
    doc.saveas(path)


if __name__ == "__main__":
    here = os.path.dirname(os.path.realpath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "facade.dxf")
    draw(out)
    blocks = facade()
    print(f"{out}: {len(blocks)} blocks, L = {L:g} mm, {COURSES} courses, a door and a window")
