"""Pictures of a 3D result (tools/plot on a file with dimension = 3), drawn
by ParaView's pvpython off-screen from the XDMF file blockwall writes
beside the result (output.xdmf): the deformed assembly (every block's
polyhedron warped by its rigid motion, amplified) coloured by the size of
the displacement, and the interfaces coloured by their mean normal stress
N/A, from a chosen view; and the blocks and failed joint portions of a
3D pushover's crack pattern (render_cracks3d, for cracks3d.py).

Why pvpython and not PyVista: the XDMF (polyhedra, interface polygons, the
vertex displacement field) is the file a user opens in ParaView anyway, so
the picture is what ParaView shows and is tested with ParaView's readers
(tests/dim3/check_xdmf.py); Debian ships it (python3-paraview), where
PyVista would be one more pip package with its own VTK. Debian's pvpython
renders through X: without a display it runs on an Xvfb of its own
(blockwall.display)."""
import json
import os
import shutil
import sys
import tempfile

from .display import run_with_display

VIEWS = {  # camera direction (from the focal point to the camera) and up
    "iso": ([1.0, 0.8, 1.6], [0, 1, 0]),
    "front": ([0, 0, 1.0], [0, 1, 0]),
    "back": ([0, 0, -1.0], [0, 1, 0]),
    "side": ([1.0, 0, 0], [0, 1, 0]),
    "top": ([0, 1.0, 0], [0, 0, -1]),
}

_SCRIPT = r'''
import json, sys
from paraview import simple
a = json.load(open(sys.argv[1]))
blocks = simple.MergeBlocks(Input=simple.Xdmf3ReaderS(FileName=[a["blocks"]]))
joints = simple.MergeBlocks(Input=simple.Xdmf3ReaderS(FileName=[a["interfaces"]]))
warp = simple.WarpByVector(Input=blocks, Vectors=["POINTS", "vertex_displacement"], ScaleFactor=a["scale"])
umag = simple.Calculator(Input=warp, AttributeType="Point Data", ResultArrayName="|u| [m]", Function="mag(vertex_displacement)")
sig = simple.Calculator(Input=joints, AttributeType="Cell Data", ResultArrayName="N/A [Pa]", Function="resultant_1/area")
view = simple.CreateView("RenderView")
view.ViewSize = a["size"]
view.Background = [1, 1, 1]
view.OrientationAxesVisibility = 1
try:
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass
d1 = simple.Show(umag, view)
simple.ColorBy(d1, ("POINTS", "|u| [m]"))
d1.RescaleTransferFunctionToDataRange(True, False)
d1.LookupTable.ApplyPreset("Viridis (matplotlib)", True)
d1.SetScalarBarVisibility(view, True)
d1.Opacity = a["opacity"]
d2 = simple.Show(sig, view)
simple.ColorBy(d2, ("CELLS", "N/A [Pa]"))
d2.RescaleTransferFunctionToDataRange(True, False)
d2.LookupTable.ApplyPreset("Cool to Warm", True)
d2.SetScalarBarVisibility(view, True)
for lut, title in ((d1.LookupTable, "|u| [m] (blocks)"), (d2.LookupTable, "N/A [Pa] (joints)")):
    bar = simple.GetScalarBar(lut, view)
    bar.Title, bar.ComponentTitle = title, ""
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
view.OrientationAxesLabelColor = [0, 0, 0]
# one picture per view, the scene built once: ParaView's import and the
# first render are most of a picture's time
for job in a["views"]:
    view.ResetCamera()
    cam = view.GetActiveCamera()
    fp = cam.GetFocalPoint()
    dist = cam.GetDistance()
    d = job["direction"]
    n = sum(x * x for x in d) ** 0.5
    cam.SetPosition(*[fp[i] + dist * d[i] / n for i in range(3)])
    cam.SetViewUp(*job["up"])
    view.ResetCamera()
    simple.Render(view)
    simple.SaveScreenshot(job["png"], view, ImageResolution=a["size"], TransparentBackground=0)
print("ok")
'''


def _split_grids(xdmf, tmp):
    """One XDMF file per grid of `xdmf` (blocks, interfaces), its HDF5
    references made absolute: ParaView's readers give the two grids as
    unnamed pieces of one data set, which no filter selects by name."""
    import xml.etree.ElementTree as ET
    folder = os.path.dirname(os.path.abspath(xdmf))
    tree = ET.parse(xdmf)
    domain = tree.getroot().find("Domain")
    out = {}
    for grid in domain.findall("Grid"):
        for item in grid.iter("DataItem"):
            if item.get("Format") == "HDF" and not os.path.isabs(item.text.strip()):
                item.text = os.path.join(folder, item.text.strip())
        root = ET.Element("Xdmf", Version="3.0")
        ET.SubElement(root, "Domain").append(grid)
        path = os.path.join(tmp, grid.get("Name") + ".xdmf")
        ET.ElementTree(root).write(path)
        out[grid.get("Name")] = path
    if "blocks" not in out or "interfaces" not in out:
        raise RuntimeError(f"{xdmf}: no 'blocks' and 'interfaces' grids (a pushover's temporal collection is not drawn in 3D yet)")
    return out


def pvpython_command():
    pv = os.environ.get("BW_PVPYTHON") or shutil.which("pvpython")
    if not pv:
        raise RuntimeError("pictures of a 3D result need ParaView's pvpython (Debian: apt-get install python3-paraview xvfb)")
    return [pv, "--force-offscreen-rendering"]


def _check_views(views):
    for view in views:
        if view not in VIEWS:
            raise ValueError(f"--view must be one of {', '.join(VIEWS)}, got {view!r}")


def render3d(h5path, png, view="iso", scale=None, size=(1600, 1000), opacity=1.0, res=None):
    """Draw the 3D result `h5path` into `png`; returns the amplification used."""
    return render3d_views(h5path, {view: png}, scale, size, opacity, res)


def render3d_views(h5path, pngs, scale=None, size=(1600, 1000), opacity=1.0, res=None):
    """Draw the 3D result `h5path` from several views ({view: png}) in one
    pvpython session; returns the amplification used."""
    stem = os.path.splitext(h5path)[0]
    xdmf = stem + ".xdmf"
    if not os.path.exists(xdmf):
        raise RuntimeError(f"{xdmf}: the 3D pictures are drawn from the XDMF file beside the result; run with output.xdmf: true")
    _check_views(pngs)
    if scale is None and res is not None:
        import numpy as np
        size_m = float(np.ptp(res.vertices, axis=0).max())
        umax = max(float(np.max(np.linalg.norm(res.vertex_displacement(b), axis=1))) for b in range(res.nblocks))
        scale = 0.05 * size_m / umax if umax > 0 else 1.0
    views = [dict(png=os.path.abspath(png), direction=VIEWS[view][0], up=VIEWS[view][1]) for view, png in pngs.items()]
    with tempfile.TemporaryDirectory() as tmp:
        script, args = os.path.join(tmp, "draw.py"), os.path.join(tmp, "args.json")
        grids = _split_grids(xdmf, tmp)
        with open(script, "w") as f:
            f.write(_SCRIPT)
        with open(args, "w") as f:
            json.dump(dict(blocks=grids["blocks"], interfaces=grids["interfaces"], views=views,
                           scale=float(scale or 1.0), size=list(size), opacity=opacity), f)
        p = run_with_display([*pvpython_command(), script, args])
        if p.returncode != 0 or not all(os.path.exists(v["png"]) for v in views):
            raise RuntimeError(f"pvpython failed ({p.returncode}): {p.stderr.strip()[-1500:]}")
    return scale


_CRACK_SCRIPT = r"""
import json, sys
from paraview import servermanager, simple
a = json.load(open(sys.argv[1]))
view = simple.CreateView("RenderView")
view.ViewSize = a["size"]
view.Background = [1, 1, 1]
view.OrientationAxesVisibility = 1
view.OrientationAxesLabelColor = [0, 0, 0]
try:
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass
# paraview.simple's first Render of a session renders, resets the camera and
# renders again: done here, on the empty view, it costs nothing, and the
# picture is rendered once, by SaveScreenshot, with the camera set below
# (each translucent render of 1600 x 1000 took ~1.3 s on llvmpipe)
simple.Render(view)


# one picture: the job's blocks and failed portions, from its view; returns
# what was loaded and shown, and the sources to delete
def draw(job):
    # the blocks: translucent faces, their edges opaque, so that the joints
    # inside the wall show through and every block's outline is still seen
    blocks = simple.LegacyVTKReader(FileNames=[job["blocks"]])
    faces = simple.Show(blocks, view)
    simple.ColorBy(faces, None)
    faces.DiffuseColor = faces.AmbientColor = a["face_colour"]
    faces.Opacity = a["face_opacity"]
    outline = simple.ExtractEdges(Input=blocks)
    edges = simple.Show(outline, view)
    simple.ColorBy(edges, None)
    edges.DiffuseColor = edges.AmbientColor = a["edge_colour"]
    edges.LineWidth = a["edge_width"]
    edges.Opacity = a["edge_opacity"]
    report = {"block_faces": {}, "portions": {}}
    data_blocks = data = servermanager.Fetch(blocks)
    ids = data.GetCellData().GetArray("block")
    for c in range(data.GetNumberOfCells()):
        b = str(int(ids.GetValue(c)))
        report["block_faces"][b] = report["block_faces"].get(b, 0) + 1
    portions = None
    if job["portions"]:
        # the failed portions in their own colours (rgb, not mapped through a
        # colour table: MapScalars off), opaque
        portions = simple.LegacyVTKReader(FileNames=[job["portions"]])
        shown = simple.Show(portions, view)
        simple.ColorBy(shown, ("CELLS", "rgb"))
        shown.MapScalars = 0
        # seen through the blocks' faces and often at a grazing angle: more
        # ambient light keeps them near the legend's colours
        shown.Ambient, shown.Diffuse = 0.45, 0.65
        shown.SetScalarBarVisibility(view, False)
        report["map_scalars"] = int(shown.MapScalars)
        report["colour_array"] = list(shown.ColorArrayName)
        data = servermanager.Fetch(portions)
        rgb, state = data.GetCellData().GetArray("rgb"), data.GetCellData().GetArray("state")
        for c in range(data.GetNumberOfCells()):
            key = "%d,%d,%d;%d" % (*(int(rgb.GetComponent(c, i)) for i in range(3)), int(state.GetValue(c)))
            report["portions"][key] = report["portions"].get(key, 0) + 1
    # a parallel projection fitted to the blocks as they are seen: ParaView's
    # camera reset fits the bounding sphere, which left a flat wall small in
    # the middle of the picture
    d, up = job["direction"], job["up"]
    n = sum(x * x for x in d) ** 0.5
    d = [x / n for x in d]
    right = [up[1] * d[2] - up[2] * d[1], up[2] * d[0] - up[0] * d[2], up[0] * d[1] - up[1] * d[0]]
    n = sum(x * x for x in right) ** 0.5
    right = [x / n for x in right]
    up = [d[1] * right[2] - d[2] * right[1], d[2] * right[0] - d[0] * right[2], d[0] * right[1] - d[1] * right[0]]
    pts = data_blocks.GetPoints()
    proj = [[sum(pts.GetPoint(i)[k] * e[k] for k in range(3)) for e in (right, up, d)] for i in range(pts.GetNumberOfPoints())]
    lo = [min(p[k] for p in proj) for k in range(3)]
    hi = [max(p[k] for p in proj) for k in range(3)]
    mid = [(lo[k] + hi[k]) / 2 for k in range(3)]
    fp = [mid[0] * right[k] + mid[1] * up[k] + mid[2] * d[k] for k in range(3)]
    depth = max(hi[k] - lo[k] for k in range(3))
    view.CameraParallelProjection = 1
    view.CameraFocalPoint = fp
    view.CameraPosition = [fp[k] + 4 * depth * d[k] for k in range(3)]
    view.CameraViewUp = up
    view.CameraParallelScale = 0.53 * max(hi[1] - lo[1], (hi[0] - lo[0]) * a["size"][1] / a["size"][0])
    simple.SaveScreenshot(job["png"], view, ImageResolution=a["size"], TransparentBackground=0)
    return report, [s for s in (portions, outline, blocks) if s is not None]


# one session for every picture (the import and the first render are most
# of a picture's time); each job's sources deleted before the next
for job in a["jobs"]:
    report, sources = draw(job)
    print("REPORT " + json.dumps(report))
    for src in sources:
        simple.Delete(src)
"""


def render_cracks3d(blocks_vtk, portions_vtk, png, view="iso", size=(1600, 1000), style=None, timeout=600):
    """Draw a crack pattern's blocks (legacy VTK polygons with the cell
    array `block`) and failed portions (cell arrays `rgb`, `state`; None if
    no portion failed) into `png` with pvpython. Returns what pvpython
    loaded and showed: {"block_faces": {block: faces}, "portions":
    {"r,g,b;state": count}, "map_scalars", "colour_array"}."""
    return render_cracks3d_many([(blocks_vtk, portions_vtk, png, view)], size, style, timeout)[0]


def render_cracks3d_many(pictures, size=(1600, 1000), style=None, timeout=600):
    """render_cracks3d for several pictures [(blocks_vtk, portions_vtk, png,
    view), ...] in one pvpython session; their reports in the same order."""
    _check_views(view for *_, view in pictures)
    jobs = [dict(blocks=os.path.abspath(b), portions=q and os.path.abspath(q), png=os.path.abspath(png),
                 direction=VIEWS[view][0], up=VIEWS[view][1]) for b, q, png, view in pictures]
    with tempfile.TemporaryDirectory() as tmp:
        script, args = os.path.join(tmp, "cracks.py"), os.path.join(tmp, "args.json")
        with open(script, "w") as f:
            f.write(_CRACK_SCRIPT)
        with open(args, "w") as f:
            json.dump(dict(jobs=jobs, size=list(size), **(style or {})), f)
        p = run_with_display([*pvpython_command(), script, args], timeout=timeout)
        lines = [line for line in p.stdout.splitlines() if line.startswith("REPORT ")]
        if p.returncode != 0 or not all(os.path.exists(j["png"]) for j in jobs) or len(lines) != len(jobs):
            raise RuntimeError(f"pvpython failed ({p.returncode}): {p.stderr.strip()[-1500:]}")
    return [json.loads(line[len("REPORT "):]) for line in lines]
