"""The XDMF of a 3D result, opened by ParaView itself (pvpython, data only:
no rendering, so no display is needed), with every reader it has for XDMF
3 (the one OpenDataFile picks, Xdmf3ReaderS, Xdmf3ReaderT):

  blocks      one VTK polyhedron (type 42) per block; ParaView's Cell Size
              gives every block's volume as the HDF5 geometry says it
              (polygon area x depth of the extruded blocks, shoelace in
              numpy), 1e-12; the cell fields displacement, reaction, load
              (6 components) equal to /blocks/*; the point field
              vertex_displacement equal to u + w x (x - c) at every vertex
              (numpy from /blocks/displacement), 1e-13 of the largest
  interfaces  one quadrilateral per interface, Cell Size areas equal to
              /interfaces/area (1e-12), resultant and relative_displacement
              (6 components) equal to /interfaces/*

A 3D pushover (check_xdmf.py pushover: the tilted wall of
check_nonlinear3d.py, every 10th step written) is a temporal collection:
with each reader the times are the written steps, and at every time the
blocks' displacement and vertex_displacement and the interfaces'
resultant are that step's /steps/NNNNNN datasets (1e-15, 1e-13).

usage: check_xdmf.py [RANKS]            (outside: runs blockwall, then pvpython)
       check_xdmf.py pushover
       pvpython check_xdmf.py --inside REF.npz XDMF
       pvpython check_xdmf.py --inside-steps REF.npz XDMF
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

WALL3 = os.path.join(os.path.dirname(os.path.abspath(__file__)), "wall.yaml")


def inside(ref_path, xdmf):
    from paraview import servermanager as sm
    from paraview import simple
    from vtkmodules.util.numpy_support import vtk_to_numpy

    ref = np.load(ref_path)
    failures = []

    def leaves(data):
        out, it = [], data.NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            out.append(it.GetCurrentDataObject())
            it.GoToNextItem()
        return out

    def rel(a, b):
        return float(np.max(np.abs(np.asarray(a, float) - np.asarray(b, float))) / max(np.max(np.abs(b)), 1e-300))

    readers = {"OpenDataFile": lambda: simple.OpenDataFile(xdmf),
               "Xdmf3ReaderS": lambda: simple.Xdmf3ReaderS(FileName=[xdmf]),
               "Xdmf3ReaderT": lambda: simple.Xdmf3ReaderT(FileName=[xdmf])}
    for name, make in readers.items():
        r = make()
        r.UpdatePipeline()
        grids = leaves(sm.Fetch(r))
        size = simple.CellSize(Input=r)
        size.UpdatePipeline()
        sizes = leaves(sm.Fetch(size))
        if len(grids) != 2:
            failures.append(f"{name}: {len(grids)} grids, not 2 (blocks, interfaces)")
            continue
        b, i = grids
        nb, ni = len(ref["volume"]), len(ref["area"])
        if b.GetNumberOfCells() != nb or {b.GetCellType(c) for c in range(nb)} != {42}:
            failures.append(f"{name}: blocks grid has {b.GetNumberOfCells()} cells of types {sorted({b.GetCellType(c) for c in range(b.GetNumberOfCells())})}, not {nb} polyhedra (42)")
            continue
        if i.GetNumberOfCells() != ni:
            failures.append(f"{name}: interfaces grid has {i.GetNumberOfCells()} cells, not {ni}")
            continue
        checks = [("block volumes (Cell Size)", vtk_to_numpy(sizes[0].GetCellData().GetArray("Volume")), ref["volume"], 1e-12),
                  ("interface areas (Cell Size)", vtk_to_numpy(sizes[1].GetCellData().GetArray("Area")), ref["area"], 1e-12),
                  ("vertex_displacement", vtk_to_numpy(b.GetPointData().GetArray("vertex_displacement")), ref["vertex_displacement"], 1e-13)]
        for field in ("displacement", "reaction", "load"):
            checks.append((field, vtk_to_numpy(b.GetCellData().GetArray(field)), ref[field], 1e-15))
        for field in ("resultant", "relative_displacement"):
            checks.append((field, vtk_to_numpy(i.GetCellData().GetArray(field)), ref[field], 1e-15))
        for what, got, want, tol in checks:
            got = np.asarray(got).reshape(np.shape(want))
            e = rel(got, want)
            print(f"{name}: {what} {e:.1e}")
            if not e <= tol:
                failures.append(f"{name}: {what} differ by {e:.2e} (> {tol})")
        simple.Delete(size)
        simple.Delete(r)
    if failures:
        print("FAIL: " + "; ".join(failures))
        sys.exit(1)


def inside_steps(ref_path, xdmf):
    from paraview import servermanager as sm
    from paraview import simple
    from vtkmodules.util.numpy_support import vtk_to_numpy

    ref = np.load(ref_path)
    steps, failures = [int(t) for t in ref["steps"]], []
    readers = {"OpenDataFile": lambda: simple.OpenDataFile(xdmf),
               "Xdmf3ReaderT": lambda: simple.Xdmf3ReaderT(FileName=[xdmf])}
    for name, make in readers.items():
        r = make()
        r.UpdatePipelineInformation()
        times = [int(round(t)) for t in r.TimestepValues]
        if times != steps:
            failures.append(f"{name}: times {times}, written steps {steps}")
            continue
        worst = 0.0
        for k, t in enumerate(steps):
            r.UpdatePipeline(float(t))
            d = sm.Fetch(r)
            it, grids = d.NewIterator(), []
            it.InitTraversal()
            while not it.IsDoneWithTraversal():
                grids.append(it.GetCurrentDataObject())
                it.GoToNextItem()
            b, i = grids
            for got, want, tol in ((b.GetCellData().GetArray("displacement"), ref["displacement"][k], 1e-15),
                                   (b.GetPointData().GetArray("vertex_displacement"), ref["vertex_displacement"][k], 1e-13),
                                   (i.GetCellData().GetArray("resultant"), ref["resultant"][k], 1e-15)):
                got = np.asarray(vtk_to_numpy(got)).reshape(np.shape(want))
                e = float(np.max(np.abs(got - want)) / max(np.max(np.abs(want)), 1e-300))
                worst = max(worst, e)
                if not e <= tol:
                    failures.append(f"{name}: step {t}: a field differs by {e:.2e}")
        print(f"{name}: {len(steps)} timesteps, fields equal to {worst:.1e}")
        simple.Delete(r)
    if failures:
        print("FAIL: " + "; ".join(failures))
        sys.exit(1)


def pvpython(expect, mode, ref, xdmf):
    """This file's inside half under pvpython, without a display (data only)."""
    env = {k: val for k, val in os.environ.items() if k != "DISPLAY"}
    p = subprocess.run([os.environ.get("BW_PVPYTHON", "pvpython"), os.path.abspath(__file__), mode, ref, xdmf],
                       capture_output=True, text=True, env=env, timeout=300)
    print(p.stdout)
    expect(p.returncode == 0, f"pvpython: exit {p.returncode}\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")


def pushover():
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from bwrun import Failure, expect, read, run  # noqa: E402
    import check_nonlinear3d as n3  # noqa: E402
    try:
        with tempfile.TemporaryDirectory() as tmp:
            scene = os.path.join(tmp, "tilt.yaml")
            with open(scene, "w") as f:
                f.write(n3.WALL3.format(mb=2).replace("xdmf: false", "xdmf: true, steps: every_10"))
            out = os.path.join(tmp, "tilt.h5")
            run(scene, ["-output_file", out])
            r = read(out)
            v, off, c = r["blocks/vertices"], r["blocks/offsets"], r["blocks/centroid"]
            steps = sorted({int(k.split("/")[1]) for k in r if k.startswith("steps/")})
            expect(len(steps) >= 3, f"written steps {steps}")
            disp, vds, res = [], [], []
            for t in steps:
                q = r[f"steps/{t:06d}/blocks/displacement"]
                vd = np.zeros_like(v)
                for blk in range(len(off) - 1):
                    p = v[off[blk]:off[blk + 1]]
                    vd[off[blk]:off[blk + 1]] = q[blk, :3] + np.cross(q[blk, 3:], p - c[blk])
                disp.append(q), vds.append(vd), res.append(r[f"steps/{t:06d}/interfaces/resultant"])
            ref = os.path.join(tmp, "ref.npz")
            np.savez(ref, steps=np.array(steps), displacement=np.array(disp), vertex_displacement=np.array(vds), resultant=np.array(res))
            pvpython(expect, "--inside-steps", ref, out[:-3] + ".xdmf")
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)


def outside(ranks):
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
    from bwrun import Failure, expect, read, run  # noqa: E402
    try:
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "wall3.h5")
            run(WALL3, ["-output_file", out, "-output_xdmf", "true", "-gravity_density", 1800,
                        "-loads_top_beam", "3000,-1.0e4,800,20,-30,40"], ranks)
            r = read(out)
            v, off, c, q = r["blocks/vertices"], r["blocks/offsets"], r["blocks/centroid"], r["blocks/displacement"]
            vol, vd = [], np.zeros_like(v)
            for blk in range(len(off) - 1):
                p = v[off[blk]:off[blk + 1]]
                ring = p[: len(p) // 2]  # the extruded prism: bottom ring, then top ring
                x, y = ring[:, 0], ring[:, 1]
                area = 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)
                vol.append(area * (p[len(p) // 2, 2] - p[0, 2]))
                vd[off[blk]:off[blk + 1]] = q[blk, :3] + np.cross(q[blk, 3:], p - c[blk])
            ref = os.path.join(tmp, "ref.npz")
            np.savez(ref, volume=np.array(vol), area=r["interfaces/area"], vertex_displacement=vd,
                     displacement=q, reaction=r["blocks/reaction"], load=r["blocks/load"],
                     resultant=r["interfaces/resultant"], relative_displacement=r["interfaces/relative_displacement"])
            pvpython(expect, "--inside", ref, out[:-3] + ".xdmf")
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--inside":
        inside(sys.argv[2], sys.argv[3])
    elif len(sys.argv) > 1 and sys.argv[1] == "--inside-steps":
        inside_steps(sys.argv[2], sys.argv[3])
    elif len(sys.argv) > 1 and sys.argv[1] == "pushover":
        pushover()
    else:
        outside(int(sys.argv[1]) if len(sys.argv) > 1 else 1)
