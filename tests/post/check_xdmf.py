"""The XDMF file beside a result file, read by a real reader (meshio).

Reference: the HDF5 datasets themselves (h5py), and closed forms of what
the XDMF adds: the vertices of block b are offsets[b]..offsets[b+1]-1 in
order; a vertex x of a block moving by (u1, u2, w) about its centroid c
moves by (u1 - w (x2 - c2), u2 + w (x1 - c1), 0); an interface is the line
from G - l/2 t to G + l/2 t, t = (cos theta, sin theta).

meshio (5.3) reads one grid per XDMF file, and our file holds two (blocks,
interfaces) as ParaView expects: each grid is read from a copy of the file
that holds only that grid, written beside the result so the relative HDF5
references resolve as they do for ParaView. Everything else is read as is.

Modes:
  two_blocks N  the paper's two blocks on N ranks (block 1 moves: rotation and
                translation; with N = 2 the blocks' vertex rows come from two ranks)
  demo          examples/demo.yaml on 2 ranks (a wall of 92 blocks)
  polygons      a file geometry of a rectangle, a pentagon and a triangle:
                meshio knows no Polygon in a Mixed topology, so the blocks'
                connectivity /xdmf/topology is compared with its closed form
                (Polygon 3, n, ids; Triangle 4, ids; Quadrilateral 5, ids) and
                the interfaces grid is read by meshio as above
  off           -output_xdmf false: no .xdmf, no /xdmf group
  failure       the .xdmf path is a directory: error, an existing result file
                untouched, no temporary left behind
"""
import copy
import os
import sys
import tempfile
import xml.etree.ElementTree as ET

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import Failure, expect, run  # noqa: E402

import meshio  # noqa: E402

TESTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
ROOT = os.path.join(TESTS, "..")
TWO_BLOCKS = os.path.join(TESTS, "paper", "two_blocks.yaml")
DEMO = os.path.join(ROOT, "examples", "demo.yaml")
TOL = 1e-13  # relative: the XDMF only re-labels the HDF5 numbers; computed ones are a few flops


def h5(path):
    with h5py.File(path, "r") as f:
        return {name: f[name][()] for name in
                ["blocks/vertices", "blocks/offsets", "blocks/centroid", "blocks/displacement",
                 "blocks/reaction", "blocks/load", "blocks/prescribed", "interfaces/blocks",
                 "interfaces/center", "interfaces/angle", "interfaces/length", "interfaces/kn",
                 "interfaces/kt", "interfaces/relative_displacement", "interfaces/resultant"]}


def close(got, want, what, scale=None):
    got, want = np.asarray(got, float), np.asarray(want, float)
    expect(got.shape == want.shape, f"{what}: shape {got.shape}, HDF5 {want.shape}")
    s = scale if scale is not None else max(np.max(np.abs(want), initial=0.0), 1e-300)
    err = np.max(np.abs(got - want), initial=0.0) / s
    expect(err <= TOL, f"{what}: differs from the reference by {err:.2e} (relative)")


def read_grids(xdmf, only=None):
    """{grid name: meshio.Mesh}, each grid read on its own (see the module doc);
    with `only`, that grid's Mesh."""
    tree = ET.parse(xdmf)
    root = tree.getroot()
    expect(root.tag == "Xdmf" and root.get("Version", "").startswith("3"), "not an XDMF 3 file")
    base = os.path.basename(xdmf)[: -len(".xdmf")] + ".h5"
    with h5py.File(os.path.join(os.path.dirname(xdmf), base), "r") as f:
        for item in root.iter("DataItem"):
            ref = item.text.strip()
            expect(item.get("Format") == "HDF" and ref.split(":")[0] == base,
                   f"DataItem {ref!r} does not reference the result file beside it by its name")
            dims = tuple(int(n) for n in item.get("Dimensions").split())
            expect(dims == f[ref.split(":")[1]].shape, f"{ref}: Dimensions {dims}, dataset {f[ref.split(':')[1]].shape}")
        counts = {"blocks": len(f["blocks/offsets"]) - 1, "interfaces": len(f["interfaces/length"])}
    for grid in root.find("Domain").findall("Grid"):
        n = int(grid.find("Topology").get("NumberOfElements"))
        expect(n == counts[grid.get("Name")], f"grid {grid.get('Name')}: NumberOfElements {n}")
    grids = {}
    for grid in root.find("Domain").findall("Grid"):
        if only and grid.get("Name") != only:
            continue
        single = ET.Element("Xdmf", Version=root.get("Version"))
        ET.SubElement(single, "Domain").append(copy.deepcopy(grid))
        one = os.path.join(os.path.dirname(xdmf), f"grid_{grid.get('Name')}.xdmf")
        ET.ElementTree(single).write(one)
        grids[grid.get("Name")] = meshio.read(one)
    if only:
        expect(only in grids, f"no grid {only}")
        return grids[only]
    return grids


def cell_field(mesh, name):
    return np.concatenate(mesh.cell_data[name])


def check(h5file, expect_quads=True):
    xdmf = os.path.splitext(h5file)[0] + ".xdmf"
    expect(os.path.isfile(xdmf), f"no {xdmf} beside {h5file}")
    d = h5(h5file)
    grids = read_grids(xdmf)
    expect(sorted(grids) == ["blocks", "interfaces"], f"grids {sorted(grids)}")
    size = np.max(np.abs(d["blocks/vertices"]))

    # blocks: polygons in input order, fields at their datasets
    b = grids["blocks"]
    off = d["blocks/offsets"]
    nb = len(off) - 1
    close(b.points, d["blocks/vertices"], "block points")
    cells = [list(c) for block in b.cells for c in block.data]
    expect(cells == [list(range(off[k], off[k + 1])) for k in range(nb)],
           "block cells are not the polygons offsets[b]..offsets[b+1]-1 in block order")
    if expect_quads:  # every generator makes rectangles: quadrilateral cells
        expect([c.type for c in b.cells] == ["quad"], f"cell types {[c.type for c in b.cells]}")
    for name in ["displacement", "reaction", "load", "prescribed", "centroid"]:
        close(cell_field(b, name), d[f"blocks/{name}"], f"block field {name}")
    owner = np.repeat(np.arange(nb), np.diff(off))
    x = d["blocks/vertices"]
    u, c = d["blocks/displacement"][owner], d["blocks/centroid"][owner]
    want = np.column_stack([u[:, 0] - u[:, 2] * (x[:, 1] - c[:, 1]), u[:, 1] + u[:, 2] * (x[:, 0] - c[:, 0]),
                            np.zeros(len(x))])
    expect(np.max(np.abs(want)) > 0, "nothing moves: the vertex displacement check would be empty")
    close(b.point_data["vertex_displacement"], want, "vertex_displacement",
          scale=np.max(np.abs(u[:, :2])) + np.max(np.abs(u[:, 2])) * size)

    # interfaces: lines G -/+ l/2 t
    g = grids["interfaces"]
    ni = len(d["interfaces/length"])
    t = np.column_stack([np.cos(d["interfaces/angle"]), np.sin(d["interfaces/angle"])])
    h = 0.5 * d["interfaces/length"][:, None] * t
    ends = np.stack([d["interfaces/center"] - h, d["interfaces/center"] + h], axis=1).reshape(-1, 2)
    expect([c.type for c in g.cells] == ["line"], f"interface cell types {[c.type for c in g.cells]}")
    pts = g.points[g.cells[0].data]  # (I, 2, 2) the two ends of every line cell
    close(pts.reshape(-1, 2), ends, "interface ends", scale=size)
    for name in ["resultant", "relative_displacement", "kn", "kt", "blocks"]:
        close(cell_field(g, name), d[f"interfaces/{name}"], f"interface field {name}")
    print(f"{os.path.basename(xdmf)}: {nb} blocks, {len(x)} vertices, {ni} interfaces match the HDF5 datasets")


def polygons(tmp):
    """Blocks of 4, 5 and 3 vertices; the result file's path."""
    blocks = [[(0, 0), (0.4, 0), (0.4, 0.1), (0, 0.1)],
              [(0, 0.11), (0.2, 0.11), (0.2, 0.21), (0.1, 0.26), (0, 0.21)],
              [(0.21, 0.11), (0.4, 0.11), (0.21, 0.25)]]
    with h5py.File(os.path.join(tmp, "geometry.h5"), "w") as f:
        f["blocks/vertices"] = np.concatenate([np.asarray(b, float) for b in blocks])
        f["blocks/offsets"] = np.array([0, 4, 9, 12], np.int64)
        f["sets/base"] = np.array([0], np.int64)
        f["sets/top"] = np.array([1, 2], np.int64)
    scene = os.path.join(tmp, "scene.yaml")
    with open(scene, "w") as f:
        f.write("title: polygons\ngeometry: {generator: file, file: geometry.h5, depth: 0.1}\n"
                "joints: {law: mortar, thickness: 0.01, E: 1.0e9, nu: 0.2}\ndiscretization: {m: 4}\n"
                "supports:\n  base: {u1: 0, u2: 0, w: 0}\nloads:\n  top: [1000, -2000, 0]\n"
                "output: {stresses: true, xdmf: true}\n")
    out = os.path.join(tmp, "result.h5")
    run(scene, ["-output_file", out])
    return out


def main(mode, *args):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "result.h5")
        if mode == "two_blocks":
            run(TWO_BLOCKS, ["-output_file", out, "-output_xdmf", "true"], np_ranks=int(args[0]))
            check(out)
        elif mode == "demo":
            expect(os.path.isfile(DEMO), f"{DEMO} does not exist")
            run(DEMO, ["-output_file", out, "-output_xdmf", "true"], np_ranks=2)
            check(out)
        elif mode == "polygons":
            out = polygons(tmp)
            with h5py.File(out, "r") as f:
                topology = f["xdmf/topology"][()]
            want = [5, 0, 1, 2, 3, 3, 5, 4, 5, 6, 7, 8, 4, 9, 10, 11]
            expect(topology.tolist() == want, f"/xdmf/topology {topology.tolist()}, expected {want}")
            d = h5(out)
            expect(len(d["interfaces/length"]) == 3, f"{len(d['interfaces/length'])} interfaces found, expected 3")
            grid = read_grids(os.path.splitext(out)[0] + ".xdmf", only="interfaces")
            expect(grid.points.shape == (6, 2), f"interface points {grid.points.shape}")
            for name in ["resultant", "kn", "blocks"]:
                close(cell_field(grid, name), d[f"interfaces/{name}"], f"interface field {name}")
        elif mode == "off":
            run(TWO_BLOCKS, ["-output_file", out, "-output_xdmf", "false"])
            expect(sorted(os.listdir(tmp)) == ["result.h5"], f"files written: {sorted(os.listdir(tmp))}")
            with h5py.File(out, "r") as f:
                expect("xdmf" not in f, "/xdmf written without output.xdmf")
        elif mode == "failure":
            with open(out, "wb") as f:
                f.write(b"an earlier result")
            os.mkdir(os.path.join(tmp, "result.xdmf"))
            code, _, err = run(TWO_BLOCKS, ["-output_file", out, "-output_xdmf", "true"], expect_ok=False)
            expect(code != 0, "a directory in the way of the .xdmf was not an error")
            expect("result.xdmf" in err and len(err.strip().splitlines()) == 1,
                   f"the error is not one line naming the .xdmf: {err!r}")
            with open(out, "rb") as f:
                expect(f.read() == b"an earlier result", "the existing result file was changed")
            expect(sorted(os.listdir(tmp)) == ["result.h5", "result.xdmf"] and not os.listdir(os.path.join(tmp, "result.xdmf")),
                   f"left behind: {sorted(os.listdir(tmp))}")
        else:
            raise SystemExit(f"unknown mode {mode}")


if __name__ == "__main__":
    try:
        main(*sys.argv[1:])
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
    print("ok")
