"""The XDMF file beside a result, opened by ParaView itself (pvpython).

Two halves in one file, because Debian's pvpython runs its own Python
(/usr/bin/python3, no h5py):

  python3 check_paraview.py MODE        the driver: runs blockwall, reads the
                                        reference numbers from the HDF5 file
                                        with h5py and the time values from
                                        the XDMF's XML, writes them to a JSON
                                        file, then runs
  Xvfb (on a free display) + pvpython check_paraview.py --inside REF.json
                                        which opens the .xdmf with ParaView's
                                        readers and compares what they give
                                        with the JSON, and renders the last
                                        step to a PNG that the driver checks
                                        is not blank.

Reading needs no display, but rendering does: Debian's ParaView 5.11 is
built for X, and pvpython without one (even --force-offscreen-rendering)
dies in SaveScreenshot; hence an Xvfb, started and waited for by
blockwall.display (python/blockwall/display.py).

What ParaView must give, with every reader it has for XDMF (the one
OpenDataFile picks, the legacy XDMFReader, Xdmf3ReaderS, Xdmf3ReaderT):
  - timesteps: the written steps (/steps/NNNNNN, as many and the same
    numbers), which are the XDMF's <Time Value=...>; none for a linear result;
  - at every timestep, the blocks grid: points /blocks/vertices, cell b the
    vertices offsets[b]..offsets[b+1]-1, cell data displacement and reaction
    of that step, centroid; the point field vertex_displacement the rigid
    motion u1 - w (x2 - c2), u2 + w (x1 - c1), 0 of each vertex;
  - the interfaces grid: points G -/+ l/2 t, cell data resultant,
    relative_displacement and state (m components) of that step, kn, kt,
    blocks.
A reader may pad a 2-component Vector to 3 (the legacy one does): the extra
component must then be 0.

Modes: pushover (a running-bond wall past its peak, every 4th step written,
so times are not 0, 1, 2, ...), linear (the paper's two blocks: rotation
and translation, a non-temporal file)."""
import json
import os
import sys
import tempfile
import time

TOL = 1e-13  # relative: the readers only copy the HDF5 numbers; the vertex field is a few flops


# ------------------------------------------------------------------ inside pvpython

def inside(ref_path):
    import numpy as np
    from paraview import servermanager as sm
    from paraview import simple
    from vtkmodules.util.numpy_support import vtk_to_numpy

    with open(ref_path) as f:
        ref = json.load(f)
    failures = []

    def fail(msg):
        failures.append(msg)

    def compare(got, want, what, scale=None):
        got, want = np.asarray(got, float), np.asarray(want, float)
        if want.ndim == 1:
            want = want[:, None]
        if got.ndim == 1:
            got = got[:, None]
        if got.shape[1] == want.shape[1] + 1 and want.shape[1] == 2:
            if np.any(got[:, 2] != 0):
                return fail(f"{what}: the padded third component is not 0")
            got = got[:, :2]
        if got.shape != want.shape:
            return fail(f"{what}: shape {got.shape}, HDF5 {want.shape}")
        s = scale if scale is not None else max(float(np.max(np.abs(want), initial=0.0)), 1e-300)
        err = float(np.max(np.abs(got - want), initial=0.0)) / s
        if err > TOL:
            fail(f"{what}: differs from the HDF5 file by {err:.2e} (relative)")

    def leaves(data):
        """The unstructured grids of a (nested) multiblock data set."""
        out = []
        it = data.NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            out.append(it.GetCurrentDataObject())
            it.GoToNextItem()
        return out

    def cell_array(grid, name):
        a = grid.GetCellData().GetArray(name)
        return None if a is None else vtk_to_numpy(a)

    def check_state(grid_b, grid_i, state, what):
        """The grids of one state against its reference numbers."""
        nb = len(ref["offsets"]) - 1
        compare(vtk_to_numpy(grid_b.GetPoints().GetData()), np.column_stack(
            [np.asarray(ref["vertices"]), np.zeros(len(ref["vertices"]))]), f"{what} block points")
        cells = [[grid_b.GetCell(c).GetPointId(k) for k in range(grid_b.GetCell(c).GetNumberOfPoints())]
                 for c in range(grid_b.GetNumberOfCells())]
        if cells != [list(range(ref["offsets"][b], ref["offsets"][b + 1])) for b in range(nb)]:
            fail(f"{what}: block cells are not the polygons offsets[b]..offsets[b+1]-1")
        for name, want in (("displacement", state["displacement"]), ("reaction", state["reaction"]),
                           ("centroid", ref["centroid"])):
            got = cell_array(grid_b, name)
            if got is None:
                fail(f"{what}: no block cell array {name}")
            else:
                compare(got, want, f"{what} block {name}")
        vd = grid_b.GetPointData().GetArray("vertex_displacement")
        if vd is None:
            fail(f"{what}: no point array vertex_displacement")
        else:
            want = np.asarray(state["vertex_displacement"])
            compare(vtk_to_numpy(vd), want, f"{what} vertex_displacement", scale=max(np.max(np.abs(want)), 1e-300))
        if grid_i is None:
            return fail(f"{what}: no interfaces grid")
        ends = np.asarray(ref["interface_ends"])
        pts = vtk_to_numpy(grid_i.GetPoints().GetData())
        conn = [[grid_i.GetCell(c).GetPointId(k) for k in range(grid_i.GetCell(c).GetNumberOfPoints())]
                for c in range(grid_i.GetNumberOfCells())]
        if any(len(c) != 2 for c in conn) or len(conn) != len(ends):
            return fail(f"{what}: {len(conn)} interface cells, not {len(ends)} lines of 2 points")
        compare(pts[np.asarray(conn)].reshape(-1, 3)[:, :2], ends.reshape(-1, 2), f"{what} interface ends",
                scale=float(np.max(np.abs(ref["vertices"]))))
        for name in ("resultant", "relative_displacement", "state"):
            got = cell_array(grid_i, name)
            if name == "state" and state.get("state") is None:
                continue
            if got is None:
                fail(f"{what}: no interface cell array {name}")
            else:
                compare(got, state[name], f"{what} interface {name}")
        for name in ("kn", "kt", "blocks"):
            got = cell_array(grid_i, name)
            if got is None:
                fail(f"{what}: no interface cell array {name}")
            else:
                compare(got, ref[name], f"{what} interface {name}")

    readers = {"OpenDataFile": lambda: simple.OpenDataFile(ref["xdmf"]),
               "XDMFReader": lambda: simple.XDMFReader(FileNames=[ref["xdmf"]]),
               "Xdmf3ReaderS": lambda: simple.Xdmf3ReaderS(FileName=[ref["xdmf"]]),
               "Xdmf3ReaderT": lambda: simple.Xdmf3ReaderT(FileName=[ref["xdmf"]])}
    report = []
    for rname, make in readers.items():
        reader = make()
        if reader is None:
            fail(f"{rname}: ParaView opened nothing")
            continue
        label = f"{rname} ({reader.GetXMLName()})"
        times = [float(t) for t in reader.TimestepValues] if reader.TimestepValues else []
        if times != [float(t) for t in ref["times"]]:
            fail(f"{label}: timesteps {times}, the XDMF's {ref['times']}")
            continue
        for t, state in zip(times or [None], ref["states"]):
            reader.UpdatePipeline(t) if t is not None else reader.UpdatePipeline()
            grids = leaves(sm.Fetch(reader))
            # the blocks are the grid of polygons, the interfaces that of lines (VTK_LINE 3, VTK_POLY_LINE 4)
            lines = [g for g in grids if g.GetNumberOfCells() and g.GetCellType(0) in (3, 4)]
            polys = [g for g in grids if g.GetNumberOfCells() and g.GetCellType(0) not in (3, 4)]
            if len(polys) != 1 or len(lines) != 1:
                fail(f"{label} time {t}: {len(polys)} block grids and {len(lines)} interface grids")
                continue
            check_state(polys[0], lines[0], state, f"{label} time {t}")
        report.append(f"{label}: {len(times)} timesteps")
        simple.Delete(reader)

    # ParaView draws it: the last step, blocks coloured by |displacement|
    reader = simple.OpenDataFile(ref["xdmf"])
    view = simple.GetActiveViewOrCreate("RenderView")
    view.ViewSize = [480, 360]
    if ref["times"]:
        view.ViewTime = ref["times"][-1]
    shown = simple.Show(reader, view)
    simple.ColorBy(shown, ("CELLS", "displacement", "Magnitude"))
    simple.ResetCamera(view)
    simple.SaveScreenshot(ref["png"], view, ImageResolution=[480, 360])
    # freed while the X display is still there: left to the interpreter's
    # exit, the render window's teardown fails (GLXBadContext, exit 1)
    simple.Delete(shown)
    simple.Delete(view)
    simple.Delete(reader)
    del shown, view, reader

    for line in report:
        print(line)
    for msg in failures:
        print(f"FAIL: {msg}")
    return 1 if failures else 0


# ------------------------------------------------------------------ the driver (python3, h5py)

def driver(mode):
    import xml.etree.ElementTree as ET

    import h5py
    import numpy as np

    here = os.path.dirname(os.path.abspath(__file__))
    sys.path.insert(0, os.path.join(here, "..", "common"))
    from bwrun import Failure, budget, expect, run  # noqa: E402
    sys.path.insert(0, os.path.join(here, "..", "..", "python"))
    from blockwall.display import run_with_display  # noqa: E402
    from matplotlib.image import imread  # noqa: E402

    pvpython = os.environ.get("BW_PVPYTHON", "pvpython")
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "result.h5")
        if mode == "pushover":
            sys.path.insert(0, here)
            from check_plot import PUSHOVER  # the wall of the crack-pattern test
            scene = os.path.join(tmp, "pushover.yaml")
            with open(scene, "w") as f:
                f.write(PUSHOVER.replace("xdmf: false, steps: all", "xdmf: true, steps: every_4"))
            run(scene, ["-output_file", out])
        elif mode == "linear":
            run(os.path.join(here, "..", "paper", "two_blocks.yaml"), ["-output_file", out, "-output_xdmf", "true"])
        else:
            raise SystemExit(f"unknown mode {mode}")
        xdmf = os.path.splitext(out)[0] + ".xdmf"
        times = [float(t.get("Value")) for t in ET.parse(xdmf).getroot().iter("Time")]

        def rigid(vertices, offsets, centroid, d):
            owner = np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))
            u, c = d[owner], centroid[owner]
            return np.column_stack([u[:, 0] - u[:, 2] * (vertices[:, 1] - c[:, 1]),
                                    u[:, 1] + u[:, 2] * (vertices[:, 0] - c[:, 0]), np.zeros(len(vertices))])

        with h5py.File(out, "r") as f:
            x, off, cen = f["blocks/vertices"][()], f["blocks/offsets"][()], f["blocks/centroid"][()]
            G, th, l = f["interfaces/center"][()], f["interfaces/angle"][()], f["interfaces/length"][()]
            h = 0.5 * l[:, None] * np.column_stack([np.cos(th), np.sin(th)])
            if mode == "pushover":
                written = sorted(int(k) for k in f["steps"])
                expect(times == [float(s) for s in written] and len(written) >= 3,
                       f"XDMF times {times}, written steps {written}")
                expect(written != list(range(len(written))), f"steps {written}: times would equal indices")
                groups = [f[f"steps/{s:06d}"] for s in written]
            else:
                expect(times == [] and "steps" not in f, f"a linear result with times {times}")
                groups = [f["/"]]

            def state_of(g):
                d = g["blocks/displacement"][()]
                expect(np.max(np.abs(d)) > 0 or g.name.endswith("000000"), f"{g.name}: nothing moves")
                return {"displacement": d.tolist(), "reaction": g["blocks/reaction"][()].tolist(),
                        "vertex_displacement": rigid(x, off, cen, d).tolist(),
                        "resultant": g["interfaces/resultant"][()].tolist(),
                        "relative_displacement": g["interfaces/relative_displacement"][()].tolist(),
                        "state": g["interfaces/state"][()].tolist() if "interfaces/state" in g else None}
            ref = {"xdmf": os.path.abspath(xdmf), "png": os.path.join(tmp, "paraview.png"), "times": times,
                   "vertices": x.tolist(), "offsets": off.tolist(), "centroid": cen.tolist(),
                   "interface_ends": np.stack([G - h, G + h], axis=1).tolist(),
                   "kn": f["interfaces/kn"][()].tolist(), "kt": f["interfaces/kt"][()].tolist(),
                   "blocks": f["interfaces/blocks"][()].tolist(), "states": [state_of(g) for g in groups]}
            if mode == "pushover":
                last = ref["states"][-1]["state"]
                expect(last is not None and np.any(np.asarray(last) > 0), "no portion cracked: state 0 everywhere")
        ref_path = os.path.join(tmp, "reference.json")
        with open(ref_path, "w") as f:
            json.dump(ref, f)
        cmd = [pvpython, os.path.abspath(__file__), "--inside", ref_path]
        t0 = time.monotonic()
        p = run_with_display(cmd, timeout=budget())
        seconds = time.monotonic() - t0
        print(p.stdout, end="")
        expect(p.returncode == 0, f"{' '.join(cmd)} exited {p.returncode}:\n{p.stdout}\n{p.stderr[-3000:]}")
        reports = [line for line in p.stdout.splitlines() if line.endswith(f": {len(times)} timesteps")]
        expect(len(reports) == 4 and "FAIL" not in p.stdout, f"pvpython did not pass its four readers:\n{p.stdout}")
        pixels = imread(ref["png"])[..., :3]
        background = pixels[0, 0]
        drawn = np.mean(np.any(np.abs(pixels - background) > 0.02, axis=-1))
        expect(drawn > 0.05, f"ParaView's picture of the last step is blank ({drawn:.1%} of the pixels drawn)")
        print(f"{mode}: {len(times)} timesteps, {len(ref['states'])} states checked by 4 readers; "
              f"picture {drawn:.0%} drawn; pvpython {seconds:.1f} s")


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--inside":
        sys.exit(inside(sys.argv[2]))
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
    from bwrun import Failure  # noqa: E402
    try:
        driver(*sys.argv[1:])
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
    print("ok")
