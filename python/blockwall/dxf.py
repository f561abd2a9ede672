"""A DXF drawing -> blockwall's HDF5 geometry input (tools/import_dxf).

    tools/import_dxf DRAWING.dxf GEOMETRY.h5 [--layer-sets] [--unit mm|cm|m] [--depth S]

What becomes a block (the model space of the drawing, in drawing order):
  LWPOLYLINE, 2D POLYLINE   closed (the closed flag, or a last vertex on the
                            first), straight segments only
  HATCH                     each boundary path, straight segments only; a
                            path that repeats a polyline of the drawing is
                            that polyline's fill, not a second block
  INSERT                    the entities of the block it references, moved,
                            scaled and rotated as placed (an entity on layer
                            0 takes the INSERT's layer, as CAD draws it)
Annotation (TEXT, MTEXT, DIMENSION, POINT, LEADER, ...) is skipped and
counted in the report. Every other case is a defect.

Units: --unit when given; else the drawing's $INSUNITS (in, ft, mm, cm, dm,
m), unless it is 0 (unitless); else metres. Coordinates are multiplied by
the factor to metres; corners are made counter-clockwise.

Sets: with --layer-sets, the blocks of each layer form the set named after
the layer (a set name holds letters, digits and '_' only: it becomes a
scene key, loads.NAME). Interfaces are not written: blockwall finds them
(edges facing each other across a gap of at most the joint thickness), so
draw the blocks with the mortar gap between them, or touching for a dry
joint of thickness 0.

Defects, each one error line naming the entity's handle and layer, exit
code 1, no file created or changed (the file is written beside the target
and renamed when complete):
  open outline              not closed, or a LINE (join lines into one closed polyline)
  arc                       a bulge in a polyline or hatch path, an ARC, CIRCLE, ELLIPSE
                            or SPLINE: replace it by straight segments first
  self-intersecting         edges that cross or touch (a bow-tie, an edge folding back)
  degenerate                fewer than 3 distinct corners, repeated corners, zero area
  overlap                   two blocks whose interiors share more than delta x perimeter
  not plane                 a 3D polyline, a mesh, or an outline not in the x-y plane
  hole                      a hatch path inside another path of the same hatch
  bad layer name            with --layer-sets, a layer name that cannot be a set name
with blockwall's tolerance delta (python/blockwall/polygon.py)."""
from __future__ import annotations

import argparse
import math
import os
import sys
from collections import Counter
from dataclasses import dataclass

import numpy as np

from . import polygon
from .geometry import SET_NAME, write_geometry

UNITS = {"in": 0.0254, "ft": 0.3048, "mm": 1e-3, "cm": 1e-2, "dm": 0.1, "m": 1.0}
INSUNITS = {1: "in", 2: "ft", 4: "mm", 5: "cm", 6: "m", 14: "dm"}
INSUNITS_NAMES = {0: "unitless", 3: "miles", 7: "km", 8: "microinches", 9: "mils", 10: "yards", 11: "angstroms",
                  12: "nanometers", 13: "microns", 15: "decameters", 16: "hectometers", 17: "gigameters",
                  18: "astronomical units", 19: "light years", 20: "parsecs"}
OUTLINES = {"LWPOLYLINE", "POLYLINE", "HATCH", "INSERT"}
CURVES = {"ARC", "CIRCLE", "ELLIPSE", "SPLINE", "HELIX"}
ANNOTATION = {"TEXT", "MTEXT", "DIMENSION", "ARC_DIMENSION", "LARGE_RADIAL_DIMENSION", "POINT", "LEADER",
              "MULTILEADER", "MLEADER", "ATTDEF", "ATTRIB", "TOLERANCE", "IMAGE", "WIPEOUT", "VIEWPORT",
              "XLINE", "RAY", "UNDERLAY", "PDFUNDERLAY", "DWFUNDERLAY", "DGNUNDERLAY", "TABLE", "ACAD_TABLE"}


class DxfError(ValueError):
    """One defect of the drawing: the message is the whole error line."""


@dataclass
class Outline:
    """One block-to-be: its corners in metres and where it came from."""
    points: np.ndarray
    kind: str          # LWPOLYLINE, POLYLINE, HATCH
    handle: str
    layer: str
    where: str         # "LWPOLYLINE #2F on layer 'units'" (with the INSERT and hatch path when there is one)
    group: str = ""    # the hatch a boundary path belongs to
    path: int = -1     # its boundary path number


@dataclass
class Report:
    blocks: int
    kinds: Counter
    sets: dict
    unit: str
    unit_rule: str
    ignored: Counter
    fills: int         # hatch paths that were the fill of a polyline


def _where(kind, handle, layer, via=None, path=None):
    s = f"{kind} #{handle} on layer '{layer}'"
    if path is not None:
        s += f", boundary path {path}"
    if via is not None:
        s += f" (in {via})"
    return s


def _plane(e, where):
    ext = getattr(e.dxf, "extrusion", None)
    if ext is not None and (abs(ext[0]) > 1e-12 or abs(ext[1]) > 1e-12):
        raise DxfError(f"{where}: not in the drawing's x-y plane (extrusion {tuple(round(c, 6) for c in ext)}); "
                       f"blocks are plane outlines in x-y")


def _closed(points, flagged, where, size_tol):
    """Drop a last corner that repeats the first; an unflagged outline must end on its first corner."""
    pts = np.asarray(points, float)
    if len(pts) >= 2 and math.hypot(*(pts[-1] - pts[0])) <= size_tol(pts):
        return pts[:-1]
    if not flagged:
        raise DxfError(f"{where}: open outline: not closed, and its last vertex ({pts[-1][0]:.6g}, {pts[-1][1]:.6g}) "
                       f"is not its first ({pts[0][0]:.6g}, {pts[0][1]:.6g}); close the polyline")
    return pts


def _size_tol(pts):
    return polygon.tolerance([np.asarray(pts, float)]) if len(pts) >= 2 else 0.0


def _no_bulge(bulges, where, what="vertex"):
    for k, b in enumerate(bulges):
        if b and abs(b) > 1e-12:
            raise DxfError(f"{where}: arc segment (bulge {b:.6g}) after {what} {k}, without a polyline "
                           f"approximation: replace arcs by straight segments")


def _lwpolyline(e, where):
    _plane(e, where)
    xyb = list(e.get_points("xyb"))
    _no_bulge([b for _, _, b in (xyb if e.closed else xyb[:-1])], where)
    pts = [(v.x, v.y) for v in e.vertices_in_wcs()]
    return _closed(pts, e.closed, where, _size_tol)


def _polyline(e, where):
    if not e.is_2d_polyline:
        raise DxfError(f"{where}: a 3D polyline or mesh, not a plane outline; draw blocks as 2D polylines")
    _plane(e, where)
    verts = list(e.vertices)
    _no_bulge([v.dxf.bulge for v in (verts if e.is_closed else verts[:-1])], where)
    pts = [(v.x, v.y) for v in e.points_in_wcs()]
    return _closed(pts, e.is_closed, where, _size_tol)


def _hatch_paths(e, where_of):
    """[(path index, points in WCS)] of a hatch's boundary paths."""
    from ezdxf.entities.boundary_paths import EdgePath, LineEdge, PolylinePath
    _plane(e, where_of(None))
    ocs, z = e.ocs(), e.dxf.elevation[2]
    out = []
    for k, path in enumerate(e.paths):
        where = where_of(k)
        if isinstance(path, PolylinePath):
            verts = list(path.vertices)
            _no_bulge([v[2] if len(v) > 2 else 0 for v in verts], where)
            pts = [(v[0], v[1]) for v in verts]
            flagged = True  # a polyline boundary path is closed by definition
        elif isinstance(path, EdgePath):
            pts = []
            for m, edge in enumerate(path.edges):
                if not isinstance(edge, LineEdge):
                    kind = type(edge).__name__.replace("Edge", "").lower()
                    raise DxfError(f"{where}: {kind} edge {m} without a polyline approximation: replace arcs and "
                                   f"curves by straight segments")
                a, b = (edge.start[0], edge.start[1]), (edge.end[0], edge.end[1])
                gap_tol = 1e-6 * math.hypot(b[0] - a[0], b[1] - a[1]) + 1e-12 * max(map(abs, a + b))
                if pts and math.hypot(a[0] - pts[-1][0], a[1] - pts[-1][1]) > gap_tol:
                    raise DxfError(f"{where}: open outline: edge {m} starts at ({a[0]:.6g}, {a[1]:.6g}), not where "
                                   f"edge {m - 1} ends ({pts[-1][0]:.6g}, {pts[-1][1]:.6g})")
                if not pts:
                    pts.append(a)
                pts.append(b)
            flagged = False
        else:
            raise DxfError(f"{where}: boundary path of an unknown kind ({type(path).__name__})")
        if len(pts) < 3:
            raise DxfError(f"{where}: degenerate outline: {len(pts)} vertices")
        wcs = [(p.x, p.y) for p in ocs.points_to_wcs([(x, y, z) for x, y in pts])]
        out.append((k, _closed(wcs, flagged, where, _size_tol)))
    return out


def _entities(msp):
    """(entity, handle, layer, via) in drawing order, INSERTs expanded recursively."""
    def walk(entities, via, via_handle, via_layer, depth):
        for e in entities:
            kind = e.dxftype()
            handle = e.dxf.handle if e.dxf.hasattr("handle") and e.dxf.handle else via_handle
            layer = e.dxf.layer if e.dxf.hasattr("layer") else "0"
            if via is not None and layer == "0":
                layer = via_layer
            if kind == "INSERT":
                if depth > 16:
                    raise DxfError(f"{_where(kind, handle, layer, via)}: block references nested more than 16 deep")
                name = f"INSERT #{handle} of block '{e.dxf.name}'" if via is None else f"{via}, block '{e.dxf.name}'"
                yield from walk(e.virtual_entities(), name, handle, layer, depth + 1)
            else:
                yield e, kind, handle, layer, via
    yield from walk(msp, None, None, None, 0)


def _unit(doc, unit):
    if unit is not None:
        if unit not in UNITS:
            raise DxfError(f"--unit must be one of {', '.join(UNITS)}, got {unit!r}")
        return unit, "--unit"
    code = doc.header.get("$INSUNITS", 0)
    if code in INSUNITS:
        return INSUNITS[code], f"the drawing's $INSUNITS = {code}"
    if code == 0:
        return "m", "no unit in the drawing ($INSUNITS 0 or unset): metres"
    raise DxfError(f"the drawing's unit ($INSUNITS = {code}, {INSUNITS_NAMES.get(code, 'unknown')}) is not one of "
                   f"{', '.join(UNITS)}: give --unit")


def read_outlines(drawing, unit=None):
    """The outlines of a DXF drawing in metres: ([Outline], unit, rule, ignored Counter, fills)."""
    import ezdxf
    try:
        doc = ezdxf.readfile(drawing)
    except IOError as e:
        raise DxfError(f"cannot read: {e.strerror or e}") from None
    except ezdxf.DXFStructureError as e:
        raise DxfError(f"not a valid DXF file: {e}") from None
    name, rule = _unit(doc, unit)
    factor = UNITS[name]
    outlines, hatches, ignored = [], [], Counter()
    for e, kind, handle, layer, via in _entities(doc.modelspace()):
        where = _where(kind, handle, layer, via)
        if kind == "LWPOLYLINE":
            outlines.append(Outline(_lwpolyline(e, where) * factor, kind, handle, layer, where))
        elif kind == "POLYLINE":
            outlines.append(Outline(_polyline(e, where) * factor, kind, handle, layer, where))
        elif kind == "HATCH":
            for k, pts in _hatch_paths(e, lambda k: _where(kind, handle, layer, via, k)):
                o = Outline(pts * factor, kind, handle, layer, _where(kind, handle, layer, via, k),
                            group=f"{handle}|{via}", path=k)
                hatches.append(o)
                outlines.append(o)
        elif kind == "LINE":
            raise DxfError(f"{where}: open outline: a LINE is not a block; join the lines of a block into one "
                           f"closed polyline")
        elif kind in CURVES:
            raise DxfError(f"{where}: {kind.lower()} without a polyline approximation: draw the block as a closed "
                           f"polyline of straight segments")
        elif kind in ANNOTATION:
            ignored[kind] += 1
        else:
            raise DxfError(f"{where}: a {kind} entity cannot be read as a block outline; draw blocks as closed "
                           f"polylines or hatches")
    # a block has no hole: no boundary path of a hatch lies inside another
    delta = polygon.tolerance([o.points for o in outlines]) if outlines else 0.0
    for a in hatches:
        for b in hatches:
            if b is not a and b.group == a.group and polygon.inside(a.points, b.points, delta):
                raise DxfError(f"{a.where}: a hole in boundary path {b.path} of the same hatch: a block cannot have "
                               f"a hole; draw the pieces around it as separate blocks")
    # a hatch drawn over its own boundary polyline is a fill, not a block
    lines = [o for o in outlines if o.kind != "HATCH"]
    fill = [h for h in hatches if any(polygon.same_outline(h.points, o.points, delta) for o in lines)]
    outlines = [o for o in outlines if not any(o is h for h in fill)]
    fills = len(fill)
    return outlines, name, rule, ignored, fills


def _check(outlines):
    delta = polygon.tolerance([o.points for o in outlines])
    for o in outlines:
        try:
            polygon.check(o.points, delta)
        except polygon.PolygonError as e:
            text = str(e)
            text = text[3:] if text.startswith("is ") else f"degenerate outline: {text}"
            raise DxfError(f"{o.where}: {text}") from None
    polys = [polygon.counter_clockwise(o.points) for o in outlines]
    found = polygon.overlaps(polys, delta)
    if found:
        i, j, area = found[0]
        raise DxfError(f"{outlines[j].where}: overlaps {outlines[i].where}: their interiors share {area:.4g} m^2 "
                       f"({100 * area / min(abs(polygon.signed_area(polys[i])), abs(polygon.signed_area(polys[j]))):.3g}"
                       f" % of the smaller)")
    return polys


def import_dxf(drawing, geometry, layer_sets=False, unit=None, depth=None):
    """Read `drawing`, check it, write `geometry` (HDF5). Returns a Report;
    raises DxfError (the error line, without the program's name) on a defect,
    leaving `geometry` as it was."""
    outlines, name, rule, ignored, fills = read_outlines(drawing, unit)
    if not outlines:
        raise DxfError("no closed polylines or hatches in the model space: nothing to import")
    polys = _check(outlines)
    sets = {}
    if layer_sets:
        for b, o in enumerate(outlines):
            sets.setdefault(o.layer, []).append(b)
        for layer, members in sets.items():
            if not SET_NAME.match(layer):
                o = outlines[members[0]]
                raise DxfError(f"{o.where}: layer '{layer}' cannot be a set name (letters, digits and '_' only: it "
                               f"becomes the scene key loads.NAME); rename the layer or leave out --layer-sets")
    if depth is not None and not (math.isfinite(depth) and depth > 0):
        raise DxfError(f"--depth must be > 0, got {depth:g}")
    folder = os.path.dirname(os.path.abspath(geometry))
    if not os.path.isdir(folder):
        raise DxfError(f"{geometry}: cannot be written: {folder} is not a directory")
    try:
        write_geometry(geometry, polys, sets=sets, depth=depth, check=False)
    except OSError as e:
        raise DxfError(f"{geometry}: cannot be written: {e.strerror or e}") from None
    kinds = Counter(o.kind + (" of an INSERT" if "(in INSERT" in o.where else "") for o in outlines)
    return Report(len(polys), kinds, {k: len(v) for k, v in sets.items()}, name, rule,
                  ignored, fills)


def main(argv=None, prog="tools/import_dxf"):
    p = argparse.ArgumentParser(
        prog=prog, description="Turn the closed polylines and hatches of a DXF drawing into blockwall's HDF5 "
                               "geometry input (geometry.generator: file). Interfaces are left to blockwall.")
    p.add_argument("drawing", help="DXF file")
    p.add_argument("geometry", help="HDF5 geometry file to write")
    p.add_argument("--layer-sets", action="store_true", help="each layer's blocks become the set named after it")
    p.add_argument("--unit", choices=list(UNITS),
                   help="drawing unit (default: the drawing's $INSUNITS if set, else m)")
    p.add_argument("--depth", type=float, help="out-of-plane depth s [m], written as the root attribute depth")
    a = p.parse_args(argv)
    try:
        r = import_dxf(a.drawing, a.geometry, a.layer_sets, a.unit, a.depth)
    except DxfError as e:
        print(f"{prog}: error: {a.drawing}: {e}", file=sys.stderr)
        return 1
    kinds = ", ".join(f"{n} {k}" for k, n in sorted(r.kinds.items()))
    print(f"{a.geometry}: {r.blocks} blocks from {a.drawing} ({kinds}); unit {r.unit} ({r.unit_rule})")
    if r.sets:
        print("sets: " + ", ".join(f"{k} ({n})" for k, n in r.sets.items()))
    if r.fills:
        print(f"{r.fills} hatch path(s) filling a polyline of the drawing: not separate blocks")
    if r.ignored:
        print("skipped (annotation): " + ", ".join(f"{n} {k}" for k, n in sorted(r.ignored.items())))
    return 0


if __name__ == "__main__":
    sys.exit(main())
