"""The XDMF of a 3D result, opened by ParaView itself (pvpython, data only:
no rendering, so no display is needed), with every reader it has for XDMF
3 (the one OpenDataFile picks, Xdmf3ReaderS, Xdmf3ReaderT), against numpy
computed from the HDF5 datasets, not from /xdmf:

  blocks      one VTK polyhedron (type 42) per block; ParaView's Cell Size
              gives every block's volume, the convex hull of its vertices
              (scipy), 1e-12; the cell fields displacement, reaction, load
              (6 components) equal to /blocks/*; the point field
              vertex_displacement equal to u + w x (x - c) at every vertex
              (numpy from /blocks/displacement), 1e-13 of the largest
  interfaces  one polygon per interface, Cell Size areas equal to
              /interfaces/area (1e-12), resultant and relative_displacement
              (6 components) equal to /interfaces/*; the point field
              vertex_displacement at every vertex of /interfaces/vertices
              equal to the mean of the two blocks' u + w x (x - c), 1e-13
  portions    one polygon per portion (P cells, /interfaces/portion_offsets
              telling the interface of each): its Cell Size area equal to
              /portions/area (1e-12) and per interface summing to
              /interfaces/area (1e-12); every point on its interface's
              plane and inside its polygon (1e-12 of the wall's size), the
              polygon's centroid (shoelace in the interface's (t, b)) at
              /portions/center (1e-12); stress equal to /portions/stress
              and area to /portions/area (1e-15); vertex_displacement at
              every point ParaView reads equal to the mean of the two
              blocks' rigid motions there (1e-13 of the largest)
              (measured: areas 6.7e-15, sums 5.8e-15, off the plane 4e-16,
              outside 5.5e-15, centroids 6e-16, fields exact, point
              displacements 3e-16; 420 portions of 3 to 6 vertices)

The wall is tests/dim3/wall.yaml's, written as a geometry file rotated by
40 degrees about (1, 2, 3) and moved: the grid of portions follows X3, so
the interfaces' bounding-box cells cut them into triangles to hexagons,
and interfaces of one shape share a layout whose polygon is another
interface's (35 interfaces, 27 layouts). On several ranks the portions' points and Mixed list
and the XDMF text are those of 1 rank, byte for byte. Without
output.stresses (a linear run writes no /portions) the XDMF has the
blocks and interfaces grids only and /xdmf no portion datasets. With
joints of strength and no stresses (tension 2e4, cohesion 5e4, friction
0.6: every mode occurs) the portions carry state and plastic_jump, and no
stress field.

A 3D pushover (check_xdmf.py pushover: the tilted wall of
check_nonlinear3d.py, every 10th step written) is a temporal collection:
with each reader the times are the written steps, and at every time the
blocks' displacement and vertex_displacement, the interfaces' resultant
and vertex_displacement and the portions' stress, state and
vertex_displacement are that step's (/steps/NNNNNN datasets; 1e-15 for
the fields, 1e-13 for the point displacements), and the portions' geometry
passes the checks above (measured over 6 steps: fields exact, point
displacements 3e-16, states 0, 2 and 3 seen).

usage: check_xdmf.py [RANKS]            (outside: runs blockwall, then pvpython)
       check_xdmf.py pushover
       pvpython check_xdmf.py --inside REF.npz XDMF
       pvpython check_xdmf.py --inside-steps REF.npz XDMF
"""
import os
import sys
import tempfile
import xml.etree.ElementTree as ET

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
WALL3 = os.path.join(HERE, "wall.yaml")


PORTION_FIELDS = ("stress", "state", "plastic_jump")  # as /portions has them


def rel(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


def mean_motion(q, c, pairs, k, x):
    """The mean of the rigid motions u + w x (x - c) of interface k's two
    blocks at points x (k an index, or an array of one per point)."""
    i, j = pairs[k].T  # k one interface, or one per row of x
    return 0.5 * (q[i, :3] + np.cross(q[i, 3:], x - c[i]) + q[j, :3] + np.cross(q[j, 3:], x - c[j]))


def interface_motion(r, q):
    """numpy: the mean motion at every row of /interfaces/vertices."""
    w, off = r["interfaces/vertices"], r["interfaces/offsets"]
    out = np.zeros_like(w)
    for k in range(len(off) - 1):
        out[off[k]:off[k + 1]] = mean_motion(q, r["blocks/centroid"], r["interfaces/blocks"], k, w[off[k]:off[k + 1]])
    return out


def leaves(data):
    out, it = [], data.NewIterator()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        out.append(it.GetCurrentDataObject())
        it.GoToNextItem()
    return out


def cells(grid):
    """Every cell's points of a VTK grid of polygons, flattened: the points'
    coordinates in cell order, each one's cell, and the index of the next
    point around its cell (numpy over VTK's connectivity and offsets, not a
    Python loop over the cells: ParaView hands over ~1e3 portions a step)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    pts = vtk_to_numpy(grid.GetPoints().GetData())
    ca = grid.GetCells()
    conn = vtk_to_numpy(ca.GetConnectivityArray()).astype(np.int64)
    offs = vtk_to_numpy(ca.GetOffsetsArray()).astype(np.int64)
    counts = np.diff(offs)
    cell = np.repeat(np.arange(len(counts)), counts)
    local = np.arange(len(conn)) - offs[:-1][cell]
    return conn, pts[conn], cell, offs[:-1][cell] + (local + 1) % counts[cell]


def portion_geometry(ref, grid, areas):
    """(what, error, tolerance) of the portions grid's geometry against the HDF5 file's."""
    off, G, Q, W, woff = ref["portion_offsets"], ref["center"], ref["frame"], ref["iverts"], ref["ioffsets"]
    k_of = np.repeat(np.arange(len(off) - 1), np.diff(off))
    L = np.max(np.ptp(ref["vertices"], axis=0))
    _, x, cell, nxt = cells(grid)
    k = k_of[cell]
    t, n, b = Q[k, 0], Q[k, 1], Q[k, 2]
    d = x - G[k]
    plane = float(np.max(np.abs(np.sum(d * n, axis=1))))
    # every point against every edge of its interface's polygon (counter-clockwise
    # about n: a point is inside where every edge turns left)
    m = np.diff(woff)[k]
    pair_point = np.repeat(np.arange(len(x)), m)
    local = np.arange(len(pair_point)) - np.repeat(np.cumsum(m) - m, m)
    first = woff[k][pair_point]
    a = W[first + local]
    e = W[first + (local + 1) % m[pair_point]] - a
    inside = float(np.max(-np.sum(np.cross(e, x[pair_point] - a) * n[pair_point], axis=1) / np.linalg.norm(e, axis=1)))
    xi, eta = np.sum(d * t, axis=1), np.sum(d * b, axis=1)
    cr = xi * eta[nxt] - xi[nxt] * eta
    starts = np.flatnonzero(np.r_[True, cell[1:] != cell[:-1]])
    twice_area = np.add.reduceat(cr, starts)
    cen = np.stack([np.add.reduceat((xi + xi[nxt]) * cr, starts), np.add.reduceat((eta + eta[nxt]) * cr, starts)], axis=1)
    centre = float(np.max(np.abs(cen / (3 * twice_area[:, None]) - ref["portion_center"])))
    per_interface = np.add.reduceat(areas, off[:-1])
    return [("portion areas (Cell Size)", rel(areas, ref["portion_area"]), 1e-12),
            ("portion areas summed per interface", rel(per_interface, ref["area"]), 1e-12),
            ("portion points off their interface's plane", plane / L, 1e-12),
            ("portion points outside their interface", max(inside, 0.0) / L, 1e-12),
            ("portion centroids against /portions/center", centre / L, 1e-12)]


def portion_motion(ref, grid, q):
    """(what, error, tolerance) of the portions' vertex_displacement at the points ParaView reads."""
    off = ref["portion_offsets"]
    k_of = np.repeat(np.arange(len(off) - 1), np.diff(off))
    got = array(grid, "point", "vertex_displacement")
    conn, x, cell, _ = cells(grid)
    want = np.full_like(got, np.nan)  # a point of no cell stays NaN and fails
    want[conn] = mean_motion(q, ref["centroid"], ref["pairs"], k_of[cell], x)
    return [("portion vertex_displacement", rel(got, want), 1e-13)]


def judge(name, checks, failures, quiet=False):
    for what, e, tol in checks:
        if not quiet:
            print(f"{name}: {what} {e:.1e}")
        if not e <= tol:
            failures.append(f"{name}: {what} differ by {e:.2e} (> {tol})")


def array(grid, where, name):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    a = (grid.GetCellData() if where == "cell" else grid.GetPointData()).GetArray(name)
    if a is None:
        raise KeyError(f"no {where} field {name}")
    return vtk_to_numpy(a)


def inside(ref_path, xdmf):
    from paraview import servermanager as sm
    from paraview import simple
    from vtkmodules.util.numpy_support import vtk_to_numpy

    ref = np.load(ref_path)
    failures = []
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
        if len(grids) != 3:
            failures.append(f"{name}: {len(grids)} grids, not 3 (blocks, interfaces, portions)")
            continue
        b, i, p = grids
        nb, ni, npor = len(ref["volume"]), len(ref["area"]), len(ref["portion_area"])
        if b.GetNumberOfCells() != nb or {b.GetCellType(c) for c in range(nb)} != {42}:
            failures.append(f"{name}: blocks grid has {b.GetNumberOfCells()} cells of types {sorted({b.GetCellType(c) for c in range(b.GetNumberOfCells())})}, not {nb} polyhedra (42)")
            continue
        if i.GetNumberOfCells() != ni or p.GetNumberOfCells() != npor:
            failures.append(f"{name}: {i.GetNumberOfCells()} interface and {p.GetNumberOfCells()} portion cells, not {ni} and {npor}")
            continue
        sides = sorted({p.GetCell(c).GetNumberOfPoints() for c in range(npor)})
        print(f"{name}: {npor} portions of {sides} vertices")
        checks = [("block volumes (Cell Size)", vtk_to_numpy(sizes[0].GetCellData().GetArray("Volume")), ref["volume"], 1e-12),
                  ("interface areas (Cell Size)", vtk_to_numpy(sizes[1].GetCellData().GetArray("Area")), ref["area"], 1e-12),
                  ("vertex_displacement", array(b, "point", "vertex_displacement"), ref["vertex_displacement"], 1e-13),
                  ("interface vertex_displacement", array(i, "point", "vertex_displacement"), ref["interface_motion"], 1e-13),
                  ("portion area field", array(p, "cell", "area"), ref["portion_area"], 1e-15)]
        for field in PORTION_FIELDS:
            if "portion_" + field in ref:
                checks.append((f"portion {field}", array(p, "cell", field), ref["portion_" + field], 1e-15))
            elif p.GetCellData().GetArray(field) is not None:
                failures.append(f"{name}: the portions have a field {field} the HDF5 file has not")
        for field in ("displacement", "reaction", "load"):
            checks.append((field, array(b, "cell", field), ref[field], 1e-15))
        for field in ("resultant", "relative_displacement"):
            checks.append((field, array(i, "cell", field), ref[field], 1e-15))
        judge(name, [(what, rel(np.asarray(got).reshape(np.shape(want)), want), tol) for what, got, want, tol in checks], failures)
        judge(name, portion_geometry(ref, p, vtk_to_numpy(sizes[2].GetCellData().GetArray("Area"))), failures)
        judge(name, portion_motion(ref, p, ref["displacement"]), failures)
        simple.Delete(size)
        simple.Delete(r)
    if failures:
        print("FAIL: " + "; ".join(failures))
        sys.exit(1)


def inside_steps(ref_path, xdmf):
    from paraview import servermanager as sm
    from paraview import simple

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
        size = simple.CellSize(Input=r)
        worst, states = {}, set()
        for k, t in enumerate(steps):
            r.UpdatePipeline(float(t))
            size.UpdatePipeline(float(t))
            grids = leaves(sm.Fetch(r))
            if len(grids) != 3:
                failures.append(f"{name}: step {t}: {len(grids)} grids, not 3")
                break
            b, i, p = grids
            q = ref["displacement"][k]
            state = array(p, "cell", "state")
            states |= set(np.unique(state).tolist())
            checks = [(what, rel(np.asarray(got).reshape(np.shape(want)), want), tol) for what, got, want, tol in (
                ("displacement", array(b, "cell", "displacement"), q, 1e-15),
                ("vertex_displacement", array(b, "point", "vertex_displacement"), ref["vertex_displacement"][k], 1e-13),
                ("resultant", array(i, "cell", "resultant"), ref["resultant"][k], 1e-15),
                ("interface vertex_displacement", array(i, "point", "vertex_displacement"), ref["interface_motion"][k], 1e-13),
                ("portion stress", array(p, "cell", "stress"), ref["portion_stress"][k], 1e-15),
                ("portion state", state, ref["portion_state"][k], 0.0))]
            checks += portion_motion(ref, p, q)
            checks += portion_geometry(ref, p, array(leaves(sm.Fetch(size))[2], "cell", "Area"))
            for what, e, tol in checks:
                worst[what] = max(worst.get(what, 0.0), e)
            judge(f"{name}: step {t}", checks, failures, quiet=True)
        print(f"{name}: {len(steps)} timesteps, portion states {sorted(states)}; worst over the steps: " + ", ".join(f"{w} {e:.1e}" for w, e in worst.items()))
        simple.Delete(size)
        simple.Delete(r)
    if failures:
        print("FAIL: " + "; ".join(failures[:20]))
        sys.exit(1)


def pvpython(expect, mode, ref, xdmf):
    """This file's inside half under pvpython, without a display (data only)."""
    from bwrun import call  # noqa: E402  (put on sys.path by the caller)
    from blockwall.display import isolated_mpi  # noqa: E402  (Open MPI's isolated singleton: no orted)
    env = {k: val for k, val in os.environ.items() if k != "DISPLAY"}
    with isolated_mpi(env) as env:
        p = call([os.environ.get("BW_PVPYTHON", "pvpython"), os.path.abspath(__file__), mode, ref, xdmf], env=env, what="pvpython")
    print(p.stdout)
    expect(p.returncode == 0, f"pvpython: exit {p.returncode}\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")


def geometry_reference(r):
    """What the inside half needs of the HDF5 file to check the portions grid."""
    return dict(vertices=r["blocks/vertices"], centroid=r["blocks/centroid"], pairs=r["interfaces/blocks"],
                center=r["interfaces/center"], frame=r["interfaces/frame"], area=r["interfaces/area"],
                iverts=r["interfaces/vertices"], ioffsets=r["interfaces/offsets"],
                portion_offsets=r["interfaces/portion_offsets"], portion_center=r["portions/center"],
                portion_area=r["portions/area"])


def grid_names(xdmf):
    return [g.get("Name") for g in ET.parse(xdmf).getroot().iter("Grid") if g.get("GridType") == "Uniform"]


def pushover():
    sys.path.insert(0, os.path.join(HERE, "..", "common"))
    sys.path.insert(0, HERE)
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
            ref = {k: [] for k in ("displacement", "vertex_displacement", "resultant", "interface_motion", "portion_stress", "portion_state")}
            for t in steps:
                s = f"steps/{t:06d}/"
                q = r[s + "blocks/displacement"]
                vd = np.zeros_like(v)
                for blk in range(len(off) - 1):
                    p = v[off[blk]:off[blk + 1]]
                    vd[off[blk]:off[blk + 1]] = q[blk, :3] + np.cross(q[blk, 3:], p - c[blk])
                for key, val in (("displacement", q), ("vertex_displacement", vd), ("resultant", r[s + "interfaces/resultant"]),
                                 ("interface_motion", interface_motion(r, q)), ("portion_stress", r[s + "portions/stress"]),
                                 ("portion_state", r[s + "portions/state"])):
                    ref[key].append(val)
            path = os.path.join(tmp, "ref.npz")
            np.savez(path, steps=np.array(steps), **{k: np.array(val) for k, val in ref.items()}, **geometry_reference(r))
            pvpython(expect, "--inside-steps", path, out[:-3] + ".xdmf")
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)


def outside(ranks):
    sys.path.insert(0, os.path.join(HERE, "..", "common"))
    sys.path.insert(0, HERE)
    from bwrun import Failure, expect, read, run, solve  # noqa: E402
    import check_file as cf  # noqa: E402
    from scipy.spatial import ConvexHull
    load = np.array([3000, -1.0e4, 800, 20, -30, 40], float)
    R = cf.rotation([1, 2, 3], 40.0)

    def check(tmp, out, args):
        """blockwall, then the inside half against numpy from the file; the file's datasets."""
        run(scene, ["-output_file", out, "-output_xdmf", "true", "-gravity_density", 1800, *args], ranks)
        r = read(out)
        v, off, c, q = r["blocks/vertices"], r["blocks/offsets"], r["blocks/centroid"], r["blocks/displacement"]
        vol, vd = [], np.zeros_like(v)
        for blk in range(len(off) - 1):
            p = v[off[blk]:off[blk + 1]]
            vol.append(ConvexHull(p).volume)
            vd[off[blk]:off[blk + 1]] = q[blk, :3] + np.cross(q[blk, 3:], p - c[blk])
        ref = os.path.join(tmp, "ref.npz")
        np.savez(ref, volume=np.array(vol), vertex_displacement=vd,
                 displacement=q, reaction=r["blocks/reaction"], load=r["blocks/load"],
                 resultant=r["interfaces/resultant"], relative_displacement=r["interfaces/relative_displacement"],
                 interface_motion=interface_motion(r, q), **geometry_reference(r),
                 **{"portion_" + f: r["portions/" + f] for f in PORTION_FIELDS if "portions/" + f in r})
        pvpython(expect, "--inside", ref, out[:-3] + ".xdmf")
        return r

    try:
        with tempfile.TemporaryDirectory() as tmp:
            geometry = cf.write_file(tmp, "wall", solve(WALL3, [], 1), R, np.array([3.0, -1.0, 2.0]))
            scene = cf.scene(tmp, "wall", geometry, 4, 3, "foundation", "top_beam", np.concatenate([R @ load[:3], R @ load[3:]]))
            out = os.path.join(tmp, "wall3.h5")
            r = check(tmp, out, [])
            if ranks > 1:
                one = os.path.join(tmp, "one.h5")
                run(scene, ["-output_file", one, "-output_xdmf", "true", "-gravity_density", 1800], 1)
                r1 = read(one)
                for key in ("xdmf/portion_points", "xdmf/portion_topology", "xdmf/interface_topology", "xdmf/topology"):
                    expect(r1[key].dtype == r[key].dtype and np.array_equal(r1[key], r[key]), f"{key} differs between 1 and {ranks} ranks")
                with open(out[:-3] + ".xdmf") as f, open(one[:-3] + ".xdmf") as g:
                    expect(f.read().replace("wall3.h5", "one.h5") == g.read(), f"the XDMF text differs between 1 and {ranks} ranks")
                print(f"{ranks} ranks: portion points, Mixed lists and XDMF text identical to 1 rank's")
            # joints with strength, without stresses: /portions holds the
            # states and plastic jumps, the portions grid those fields
            r = check(tmp, os.path.join(tmp, "joints.h5"), ["-output_stresses", "false", "-joints_strength_tension", "2e4",
                                                            "-joints_strength_cohesion", "5e4", "-joints_strength_friction", "0.6"])
            states = np.bincount(r["portions/state"], minlength=4)
            print(f"joints with strength: portions elastic, open, sliding, both {states.tolist()}")
            expect(np.all(states > 0), f"the joints' states do not show every mode: {states}")
            # a linear run without stresses writes no /portions: no portions grid
            bare = os.path.join(tmp, "bare.h5")
            run(scene, ["-output_file", bare, "-output_xdmf", "true", "-output_stresses", "false"], ranks)
            names, keys = grid_names(bare[:-3] + ".xdmf"), sorted(k for k in read(bare) if k.startswith("xdmf/"))
            print(f"without stresses: grids {names}, {keys}")
            expect(names == ["blocks", "interfaces"], f"without stresses the grids are {names}")
            expect(keys == ["xdmf/interface_displacement", "xdmf/interface_topology", "xdmf/topology", "xdmf/vertex_displacement"],
                   f"without stresses /xdmf holds {keys}")
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
