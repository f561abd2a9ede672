"""tools/import_dxf on drawings written here with ezdxf.

Drawings imported, run, and compared with the same blocks written
directly with the Python package (every result of check_file.same equal to
SAME_TOL):
  wall      a running-bond wall with an opening, drawn block by block as
            LWPOLYLINEs in millimetres ($INSUNITS 4) on layers foundation,
            units, top_beam (--layer-sets), the units laid out here by
            interface.md's rule; also equal to the running_bond generator
            with the same opening (its own arithmetic: GEN_TOL)
  arch      examples/arch.py's arch: the voussoirs as the boundary paths of
            one HATCH (line edges), the springers as 2D POLYLINEs, metres
            ($INSUNITS 6); the joints' G, theta, l as constructed (1e-12)
  stones    examples/stones.py's wall (depth 0.4 by --depth) in centimetres without $INSUNITS
            (--unit cm), every stone clockwise, half of them as INSERTs of
            a block definition drawn about the stone's centroid and turned
            by 90 deg, placed back with rotation -90 deg
  units     the unit rule on one 2 x 1 rectangle: $INSUNITS 4 -> mm;
            --unit overrides it; $INSUNITS 0 -> metres; $INSUNITS 1 -> inches;
            $INSUNITS 3 (miles) is an error asking for --unit; vertices
            exact to 1e-15
Defects (DEFECTS below; `defects K` runs the K-th half of them, K = 1, 2,
`defect.NAME` one), one drawing each: exit code 1, exactly one line on
stderr, naming the entity's handle and layer and the defect, no file
created (the directory holds the drawing only), and a file already at the
target left byte for byte as it was (that second refusal by
tools/import_dxf's main() in this process: the same line, exit code 1).

SAME_TOL = 1e-12: the drawing's coordinates (mm x 1e-3, or turned by 90 deg
and back) differ from the directly written metres by round-off, 1e-16
relative; the solves amplify that by their condition (measured 1e-15 ..
1e-13). GEN_TOL = 1e-10: the generator computes the same layout with other
sums (k (h_u + e) against coordinates typed in mm), which changes the
round-off of the geometry in the same way (measured below 1e-12)."""
import math
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(HERE, "..", "geometry"))
sys.path.insert(0, os.path.join(ROOT, "examples"))
from bwrun import Failure, call, each, expect, rel_err, share, solve  # noqa: E402
from check_file import same  # noqa: E402
import geomlib  # noqa: E402
import blockwall as bw  # noqa: E402
import ezdxf  # noqa: E402

IMPORT = os.path.join(ROOT, "tools", "import_dxf")
SAME_TOL, GEN_TOL = 1e-12, 1e-10


def import_dxf(drawing, target, *args):
    p = call([sys.executable, IMPORT, drawing, target, *args], what="tools/import_dxf")
    return p.returncode, p.stdout, p.stderr


def import_dxf_here(drawing, target, *args):
    """tools/import_dxf's main() in this process: (exit code, stdout,
    stderr). For a drawing whose refusal a run of tools/import_dxf itself
    has just shown: the run again, here, costs 0.05 s where a new Python
    importing ezdxf took 0.9 s (dxf.defects_*: 16 such runs each)."""
    import contextlib
    import io
    from blockwall.dxf import main
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main([drawing, target, *args])
        except SystemExit as e:
            rc = e.code
    return rc, out.getvalue(), err.getvalue()


def run_file(tmp, name, geometry, supports, loads, extra=""):
    scene = os.path.join(tmp, f"{name}.yaml")
    geomlib.write_scene(scene, geometry, supports=supports, loads=loads, m=8, extra=extra)
    return solve(scene)


# ----------------------------------------------------------------- wall
LU, HU, E, HF, HB, N, COURSES = 210.0, 52.0, 10.0, 100.0, 100.0, 6, 10
OPENING_MM = (450.0, 180.0, 900.0, 420.0)  # [x0, y0, x1, y1]: units whose centroid lies inside are left out


def wall_layout():
    """[(layer, rectangle in mm)] in the generator's block order."""
    L = N * LU + (N - 1) * E
    half = (LU - E) / 2
    x0, y0, x1, y1 = OPENING_MM
    out = [("foundation", geomlib.rect(0, -E - HF, L, -E))]
    for k in range(COURSES):
        yb = k * (HU + E)
        if k % 2 == 0:
            xs = [(i * (LU + E), i * (LU + E) + LU) for i in range(N)]
        else:
            xs = [(0.0, half)] + [(half + E + i * (LU + E), half + E + i * (LU + E) + LU) for i in range(N - 1)] + \
                 [(L - half, L)]
        for a, b in xs:
            cx, cy = (a + b) / 2, yb + HU / 2
            if not (x0 <= cx <= x1 and y0 <= cy <= y1):
                out.append(("units", geomlib.rect(a, yb, b, yb + HU)))
    ytop = (COURSES - 1) * (HU + E) + HU
    out.append(("top_beam", geomlib.rect(0, ytop + E, L, ytop + E + HB)))
    return out


def wall():
    layout = wall_layout()
    doc = ezdxf.new(units=4)
    for layer, p in layout:
        doc.modelspace().add_lwpolyline(p.tolist(), close=True, dxfattribs={"layer": layer})
    sup, loads = {"foundation": {"u1": 0, "u2": 0, "w": 0}}, {"top_beam": (8e3, -2e4, 0)}
    with tempfile.TemporaryDirectory() as tmp:
        drawing, imported, direct = (os.path.join(tmp, n) for n in ("wall.dxf", "imported.h5", "direct.h5"))
        doc.saveas(drawing)
        code, out, err = import_dxf(drawing, imported, "--layer-sets")
        expect(code == 0, f"import failed: {err}")
        sets = {}
        for k, (layer, _) in enumerate(layout):
            sets.setdefault(layer, []).append(k)
        bw.write_geometry(direct, [p * 1e-3 for _, p in layout], sets=sets)
        got = run_file(tmp, "imported", imported, sup, loads)
        ref = run_file(tmp, "direct", direct, sup, loads)
        gen_scene = os.path.join(tmp, "gen.yaml")
        with open(gen_scene, "w") as f:
            f.write(f"""title: generator
geometry: {{generator: running_bond, depth: 0.1, running_bond: {{courses: {COURSES}, units_per_course: {N},
  unit_length: 0.21, unit_height: 0.052, foundation: true, foundation_height: 0.1, top_beam: true, top_beam_height: 0.1,
  openings: [[{', '.join(str(v * 1e-3) for v in OPENING_MM)}]]}}}}
joints: {{law: mortar, thickness: 0.01, E: 1.0e9, nu: 0.2}}
discretization: {{m: 8}}
supports: {{foundation: {{u1: 0, u2: 0, w: 0}}}}
loads: {{top_beam: [8000.0, -20000.0, 0.0]}}
solver: {{method: auto, rtol: 1.0e-10}}
output: {{stresses: true, xdmf: false}}
""")
        gen = solve(gen_scene)
    expect(got["blocks/vertices"].shape[0] == 4 * len(layout), "not every block imported")
    expect(sorted(k for k in got if k.startswith("sets/")) == ["sets/foundation", "sets/top_beam", "sets/units"],
           f"sets {[k for k in got if k.startswith('sets/')]}")
    same(got, ref, SAME_TOL, "wall: DXF vs written directly")
    same(got, gen, GEN_TOL, "wall: DXF vs running_bond generator")
    print(f"wall: {len(layout)} blocks ({COURSES * N + COURSES // 2 + 2 - len(layout)} left out for the opening), "
          f"{len(got['interfaces/blocks'])} interfaces; DXF vs direct "
          f"{rel_err(got['blocks/displacement'], ref['blocks/displacement']):.1e}, "
          f"vs generator {rel_err(got['blocks/displacement'], gen['blocks/displacement']):.1e}")


# ----------------------------------------------------------------- arch
def arch():
    import arch as example
    g, joints = example.arch(**example.SPAN)
    n = example.SPAN["n"]
    doc = ezdxf.new(units=6)
    msp = doc.modelspace()
    msp.add_polyline2d(g.blocks[0].tolist(), close=True, dxfattribs={"layer": "springers"})
    hatch = msp.add_hatch(dxfattribs={"layer": "voussoirs"})
    for p in g.blocks[1:n + 1]:
        path = hatch.paths.add_edge_path()
        for a, b in zip(p, np.roll(p, -1, axis=0)):
            path.add_line(tuple(a), tuple(b))
    msp.add_polyline2d(g.blocks[n + 1].tolist(), close=True, dxfattribs={"layer": "springers"})
    sup, loads = {"springers": {"u1": 0, "u2": 0, "w": 0}}, {"voussoirs": (0, -3e3, 0)}
    with tempfile.TemporaryDirectory() as tmp:
        drawing, imported, direct = (os.path.join(tmp, n) for n in ("arch.dxf", "imported.h5", "direct.h5"))
        doc.saveas(drawing)
        code, out, err = import_dxf(drawing, imported, "--layer-sets")
        expect(code == 0, f"import failed: {err}")
        bw.write_geometry(direct, g.blocks, sets={"springers": [0, n + 1], "voussoirs": list(range(1, n + 1))})
        got = run_file(tmp, "imported", imported, sup, loads)
        ref = run_file(tmp, "direct", direct, sup, loads)
    same(got, ref, SAME_TOL, "arch: DXF vs written directly")
    e_g = rel_err(got["interfaces/center"], np.array([c for _, _, c, _, _ in joints]))
    e_t = np.max(np.abs(geomlib.angle_diff(got["interfaces/angle"], [t for *_, t, _ in joints])))
    e_l = rel_err(got["interfaces/length"], np.array([l for *_, l in joints]))
    expect(max(e_g, e_t, e_l) < 1e-12, f"arch joints vs construction: G {e_g:.1e}, theta {e_t:.1e}, l {e_l:.1e}")
    print(f"arch: {n} voussoirs from one hatch, 2 springers; DXF vs direct "
          f"{rel_err(got['blocks/displacement'], ref['blocks/displacement']):.1e}; joints as constructed "
          f"(G {e_g:.1e}, theta {e_t:.1e}, l {e_l:.1e})")


# ----------------------------------------------------------------- stones
def stones():
    import stones as example
    g = example.stone_wall()
    doc = ezdxf.new()  # no $INSUNITS: --unit cm says what the numbers mean
    doc.header["$INSUNITS"] = 0
    msp = doc.modelspace()
    layer = {b: name for name, members in g.sets.items() for b in members}
    inserted = 0
    for b, p in enumerate(g.blocks):
        cm = p[::-1] * 100.0  # clockwise, centimetres
        if layer[b] == "stones" and b % 2 == 0:
            c = cm.mean(axis=0)
            turned = (cm - c) @ np.array([[0.0, -1.0], [1.0, 0.0]]).T  # turned by +90 deg about c
            block = doc.blocks.new(f"STONE{b}")
            block.add_lwpolyline(turned.tolist(), close=True)
            msp.add_blockref(f"STONE{b}", tuple(c), dxfattribs={"layer": layer[b], "rotation": -90.0})
            inserted += 1
        else:
            msp.add_lwpolyline(cm.tolist(), close=True, dxfattribs={"layer": layer[b]})
    sup, loads = {"foundation": {"u1": 0, "u2": 0, "w": 0}}, {"cap": (3e3, -2e4, 0)}
    joints = {"law": "dry", "kn": 1.0e9, "kt": 4.0e8}
    with tempfile.TemporaryDirectory() as tmp:
        drawing, imported, direct = (os.path.join(tmp, n) for n in ("stones.dxf", "imported.h5", "direct.h5"))
        doc.saveas(drawing)
        code, out, err = import_dxf(drawing, imported, "--layer-sets", "--unit", "cm", "--depth", "0.4")
        expect(code == 0, f"import failed: {err}")
        g.write(direct)
        for name, geo in (("imported", imported), ("direct", direct)):
            scene = os.path.join(tmp, f"{name}.yaml")
            geomlib.write_scene(scene, geo, joints=joints, supports=sup, loads=loads, m=8,
                                extra="gravity: {density: 2400}\n")
        got, ref = solve(os.path.join(tmp, "imported.yaml")), solve(os.path.join(tmp, "direct.yaml"))
    same(got, ref, SAME_TOL, "stones: DXF vs written directly")
    print(f"stones: {len(g.blocks)} blocks, {inserted} of them INSERTs turned by -90 deg, all clockwise in cm; "
          f"{len(got['interfaces/blocks'])} interfaces; DXF vs direct "
          f"{rel_err(got['blocks/displacement'], ref['blocks/displacement']):.1e}")


# ----------------------------------------------------------------- units
def units():
    rect = [(0, 0), (2, 0), (2, 1), (0, 1)]
    cases = [(4, [], 1e-3), (4, ["--unit", "m"], 1.0), (0, [], 1.0), (1, [], 0.0254), (6, ["--unit", "mm"], 1e-3),
             (5, [], 1e-2)]
    with tempfile.TemporaryDirectory() as tmp:
        for code_, args, factor in cases:
            doc = ezdxf.new()
            doc.header["$INSUNITS"] = code_
            doc.modelspace().add_lwpolyline(rect, close=True)
            drawing, target = os.path.join(tmp, "u.dxf"), os.path.join(tmp, "u.h5")
            doc.saveas(drawing)
            rc, out, err = import_dxf(drawing, target, *args)
            expect(rc == 0, f"$INSUNITS {code_} {args}: {err}")
            v = bw.read_geometry(target).blocks[0]
            e = np.max(np.abs(v - np.array(rect, float) * factor))
            expect(e <= 1e-15 * factor * 2, f"$INSUNITS {code_} {args}: vertices {v.tolist()}, want x {factor}")
            print(f"$INSUNITS {code_} {' '.join(args) or '(no --unit)'}: x {factor:g} ({out.splitlines()[0].split('; ')[-1]})")
            os.remove(target)
        doc = ezdxf.new()
        doc.header["$INSUNITS"] = 3
        doc.modelspace().add_lwpolyline(rect, close=True)
        doc.saveas(drawing)
        rc, out, err = import_dxf(drawing, target)
        expect(rc == 1 and "$INSUNITS = 3" in err and "--unit" in err and not os.path.exists(target),
               f"miles: exit {rc}, {err!r}")
        print(f"$INSUNITS 3: {err.strip()}")


# ----------------------------------------------------------------- defects
def _bulge(m):
    return m.add_lwpolyline([(0, 0, 0), (1, 0, 0.4), (1, 1, 0), (0, 1, 0)], format="xyb", close=True,
                            dxfattribs={"layer": "units"})


def _hatch(m, kind):
    h = m.add_hatch(dxfattribs={"layer": "fills"})
    if kind == "arc":
        p = h.paths.add_edge_path()
        p.add_line((0, 0), (1, 0))
        p.add_arc((1, 0.5), 0.5, -90, 90)
        p.add_line((1, 1), (0, 1))
        p.add_line((0, 1), (0, 0))
    elif kind == "open":
        p = h.paths.add_edge_path()
        p.add_line((0, 0), (1, 0))
        p.add_line((1, 0), (1, 1))
        p.add_line((1, 1.2), (0, 0))
    else:  # a hole
        h.paths.add_polyline_path([(0, 0), (3, 0), (3, 3), (0, 3)])
        h.paths.add_polyline_path([(1, 1), (2, 1), (2, 2), (1, 2)])
    return h


def _pair(m):
    m.add_lwpolyline([(0, 0), (2, 0), (2, 1), (0, 1)], close=True, dxfattribs={"layer": "units"})
    return m.add_lwpolyline([(1.5, 0.5), (3, 0.5), (3, 2), (1.5, 2)], close=True, dxfattribs={"layer": "beam"})


def _ok_then(m, make):
    m.add_lwpolyline([(0, -2), (1, -2), (1, -1), (0, -1)], close=True, dxfattribs={"layer": "units"})
    return make(m)


# name: (draw: modelspace -> the offending entity, words the error line must hold)
DEFECTS = {
    "open": (lambda m: _ok_then(m, lambda m: m.add_lwpolyline([(0, 0), (1, 0), (1, 1), (0, 1)],
                                                              dxfattribs={"layer": "units"})), ["open outline"]),
    "open_hatch": (lambda m: _hatch(m, "open"), ["open outline", "edge 2"]),
    "line": (lambda m: m.add_line((0, 0), (1, 0), dxfattribs={"layer": "sketch"}), ["open outline", "LINE"]),
    "self_intersecting": (lambda m: m.add_lwpolyline([(0, 0), (1, 1), (1, 0), (0, 1)], close=True,
                                                     dxfattribs={"layer": "units"}), ["self-intersecting"]),
    "fold_back": (lambda m: m.add_lwpolyline([(0, 0), (2, 0), (2, 1), (1, 1), (3, 1), (3, 2), (0, 2)], close=True,
                                             dxfattribs={"layer": "units"}), ["self-intersecting"]),
    "bulge": (_bulge, ["arc", "bulge"]),
    "arc": (lambda m: m.add_arc((0, 0), 1, 0, 180, dxfattribs={"layer": "arches"}), ["arc", "polyline approximation"]),
    "circle": (lambda m: m.add_circle((0, 0), 1, dxfattribs={"layer": "stones"}), ["circle", "polyline approximation"]),
    "hatch_arc": (lambda m: _hatch(m, "arc"), ["arc edge", "polyline approximation"]),
    "overlap": (_pair, ["overlaps", "#", "layer 'units'", "0.25 m^2"]),
    "zero_area": (lambda m: m.add_lwpolyline([(0, 0), (1, 0), (2, 0)], close=True, dxfattribs={"layer": "units"}),
                  ["degenerate", "zero area"]),
    "repeated_vertex": (lambda m: m.add_lwpolyline([(0, 0), (1, 0), (1, 0), (1, 1), (0, 1)], close=True,
                                                   dxfattribs={"layer": "units"}), ["degenerate", "coincide"]),
    "two_vertices": (lambda m: m.add_lwpolyline([(0, 0), (1, 0)], close=True, dxfattribs={"layer": "units"}),
                     ["degenerate", "2 corners"]),
    "hole": (lambda m: _hatch(m, "hole"), ["hole"]),
    "polyline_3d": (lambda m: m.add_polyline3d([(0, 0, 0), (1, 0, 1), (1, 1, 0)], close=True,
                                               dxfattribs={"layer": "units"}), ["3D polyline"]),
    "layer_name": (lambda m: m.add_lwpolyline([(0, 0), (1, 0), (1, 1), (0, 1)], close=True,
                                              dxfattribs={"layer": "west wall"}), ["cannot be a set name"]),
}


def defect(name):
    draw, words = DEFECTS[name]
    doc = ezdxf.new()
    bad = draw(doc.modelspace())
    handle, layer = bad.dxf.handle, bad.dxf.layer
    with tempfile.TemporaryDirectory() as tmp:
        drawing = os.path.join(tmp, "bad.dxf")
        doc.saveas(drawing)
        target = os.path.join(tmp, "geometry.h5")
        rc, out, err = import_dxf(drawing, target, "--layer-sets")
        lines = err.strip().splitlines()
        expect(rc == 1, f"{name}: exit code {rc}, want 1 ({err!r})")
        expect(len(lines) == 1, f"{name}: {len(lines)} lines on stderr, want one:\n{err}")
        line = lines[0]
        expect(line.startswith(f"tools/import_dxf: error: {drawing}: "), f"{name}: {line!r}")
        expect(f"#{handle} " in line and f"layer '{layer}'" in line, f"{name}: handle #{handle} and layer "
                                                                     f"'{layer}' not named: {line!r}")
        for w in words:
            expect(w in line, f"{name}: {w!r} not in {line!r}")
        expect(sorted(os.listdir(tmp)) == ["bad.dxf"], f"{name}: files left: {sorted(os.listdir(tmp))}")
        with open(target, "wb") as f:  # an older file at the target stays as it was
            f.write(b"previous geometry")
        rc2, _, err2 = import_dxf_here(drawing, target, "--layer-sets")
        expect(err2.strip() == line, f"{name}: run again, the line {err2.strip()!r}, first {line!r}")
        with open(target, "rb") as f:
            kept = f.read()
        expect(rc2 == 1 and kept == b"previous geometry", f"{name}: the existing target was changed")
        expect(sorted(os.listdir(tmp)) == ["bad.dxf", "geometry.h5"], f"{name}: files left: {sorted(os.listdir(tmp))}")
    print(f"{name}: exit 1, {line}")


def defects(k):
    """The K-th half of DEFECTS (K = 1, 2), each checked as defect(name), in
    one Python process; every defect run and reported."""
    names = share(DEFECTS, k, 2)
    each(names, defect)
    print(f"{len(names)} defects (half {k} of 2) refused")


if __name__ == "__main__":
    try:
        what = sys.argv[1]
        if what.startswith("defect."):
            defect(what[len("defect."):])
        elif what == "defects" and sys.argv[2:] in (["1"], ["2"]):
            defects(int(sys.argv[2]))
        else:
            {"wall": wall, "arch": arch, "stones": stones, "units": units}[what]()
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
