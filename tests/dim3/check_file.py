"""3D geometry files (geometry.generator: file with (V, 3) vertices): the
convex hulls, the detected interfaces, and frame independence.

  generator  a 3D running-bond wall written by the generator, its blocks
             written back as a 3D file (bw.Geometry, vertex sets whose hull
             is the block): the file run gives the generator run's
             displacements, resultants and portion stresses (1e-12), with
             the same interfaces (pairs, centres, frames, areas)
  rotated    model.md invariant 2: the same wall file rotated about X3 by
             30 degrees and moved to (1000, -2000, 500), its loads rotated
             with it (no gravity: gravity does not rotate): displacement
             and rotation vectors, every interface's force T t + N n + Tb b
             and moment Mt t + Mn n + Mb b, every portion's traction
             vector are the rotated ones, 1e-10
  general    a rotation about the axis (1, 2, 3) by 40 degrees moves the
             grid of portions (it follows X3): two blocks under six loads,
             the frame-independent quantities against the unrotated run
             converge as m = m_b grows (4, 8, 16: each error at most 0.3 of
             the one before, as 1/m^2 gives 0.25; measured 6.7e-2, 1.9e-2,
             5.2e-3) and are below 1e-2 at 16
  errors     broken 3D files and scenes, one line each naming the file,
             block, vertex row or interface, exit 1, the previous output
             file untouched: fewer than 4 vertices, all on one plane, a
             vertex inside the hull, a repeated vertex, a non-finite
             coordinate, overlapping blocks, a listed interface without
             facing faces, a listed pair twice, geometry.dimension: 2 with
             a 3D file, geometry.depth with a 3D file
  twoboxes   the paper's two blocks as a file of two boxes give the
             two_blocks generator's answer exactly (1e-14)

usage: check_file.py CASE [RANKS]
"""
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import Failure, expect, rel_err, solve  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "python"))
import blockwall as bw  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
WALL3, TWO3 = os.path.join(HERE, "wall.yaml"), os.path.join(HERE, "two_blocks.yaml")
FILE_SCENE = """geometry: {{generator: file, file: {file}}}
joints: {{law: mortar, thickness: 0.01, E: 1.0e9, nu: 0.2}}
discretization: {{m: {m}, m_b: {mb}}}
supports:
  {support}: {{u1: 0, u2: 0, u3: 0, w1: 0, w2: 0, w3: 0}}
loads:
  {loaded}: [{load}]
output: {{stresses: true, xdmf: false}}
"""


def write_file(tmp, name, res, R=np.eye(3), shift=np.zeros(3)):
    """The blocks of result `res`, rotated by R and moved by shift, as a 3D geometry file."""
    v, off = res["blocks/vertices"], res["blocks/offsets"]
    g = bw.Geometry()
    for b in range(len(off) - 1):
        g.add_block(v[off[b]:off[b + 1]] @ R.T + shift)
    for k, members in res.items():
        if k.startswith("sets/"):
            g.add_set(k[5:], members)
    path = os.path.join(tmp, name + ".h5")
    g.write(path)
    return path


def scene(tmp, name, file, m, mb, support, loaded, load):
    path = os.path.join(tmp, name + ".yaml")
    with open(path, "w") as f:
        f.write(FILE_SCENE.format(file=file, m=m, mb=mb, support=support, loaded=loaded, load=", ".join(f"{x:.17g}" for x in load)))
    return path


def rotation(axis, deg):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    t = np.radians(deg)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(t) * K + (1 - np.cos(t)) * K @ K


def global_quantities(res):
    """Per interface the force and moment vectors (global axes), per portion the traction vector."""
    Q = res["interfaces/frame"]  # rows t, n, b
    f = res["interfaces/resultant"]
    force = np.einsum("kij,ki->kj", Q, f[:, :3])
    moment = np.einsum("kij,ki->kj", Q, f[:, 3:])
    off = res["interfaces/portion_offsets"]
    k_of = np.repeat(np.arange(len(off) - 1), np.diff(off))
    traction = np.einsum("pij,pi->pj", Q[k_of], res["portions/stress"])
    return force, moment, traction


def check_generator(ranks):
    load = [3000, -1.0e4, 800, 20, -30, 40]
    r_gen = solve(WALL3, ["-loads_top_beam", ",".join(map(str, load))], ranks)
    with tempfile.TemporaryDirectory() as tmp:
        f = write_file(tmp, "wall", r_gen)
        r_file = solve(scene(tmp, "wall", f, 4, 3, "foundation", "top_beam", load), [], ranks)
    expect(np.array_equal(r_file["interfaces/blocks"], r_gen["interfaces/blocks"]),
           f"detected pairs differ from the generator's: {len(r_file['interfaces/blocks'])} vs {len(r_gen['interfaces/blocks'])}")
    for key in ("interfaces/center", "interfaces/frame", "interfaces/area", "blocks/centroid",
                "blocks/displacement", "interfaces/resultant", "portions/stress"):
        e = rel_err(r_file[key], r_gen[key])
        print(f"{key}: {e:.1e}")
        expect(e < 1e-12, f"{key}: file and generator differ by {e:.2e}")


def check_rotated(ranks):
    load = np.array([3000, -1.0e4, 800, 20, -30, 40], float)
    R, shift = rotation([0, 0, 1], 30.0), np.array([1000.0, -2000.0, 500.0])
    with tempfile.TemporaryDirectory() as tmp:
        r_gen = solve(WALL3, [], 1)
        f0 = write_file(tmp, "wall0", r_gen)
        f1 = write_file(tmp, "wall1", r_gen, R, shift)
        r0 = solve(scene(tmp, "wall0", f0, 4, 3, "foundation", "top_beam", load), [], 1)
        load1 = np.concatenate([R @ load[:3], R @ load[3:]])
        r1 = solve(scene(tmp, "wall1", f1, 4, 3, "foundation", "top_beam", load1), [], ranks)
    L = np.ptp(r0["blocks/vertices"], axis=0).max()
    q0, q1 = r0["blocks/displacement"], r1["blocks/displacement"]
    u_rot = np.concatenate([q0[:, :3] @ R.T, L * q0[:, 3:] @ R.T], axis=1)
    e_q = rel_err(np.concatenate([q1[:, :3], L * q1[:, 3:]], axis=1), u_rot)
    f0, m0, t0 = global_quantities(r0)
    f1, m1, t1 = global_quantities(r1)
    e_f, e_m, e_t = rel_err(f1, f0 @ R.T), rel_err(m1, m0 @ R.T), rel_err(t1, t0 @ R.T)
    print(f"rotated 30 deg about X3 and moved: displacements {e_q:.1e}, forces {e_f:.1e}, moments {e_m:.1e}, tractions {e_t:.1e}")
    for what, e in (("displacements", e_q), ("interface forces", e_f), ("interface moments", e_m), ("portion tractions", e_t)):
        expect(e < 1e-10, f"{what} are not the rotated ones: {e:.2e}")


def check_general(ranks):
    load = np.array([700, -1500, 400, 30, -20, 45], float)
    R = rotation([1, 2, 3], 40.0)
    errors = []
    with tempfile.TemporaryDirectory() as tmp:
        base = solve(TWO3, [], 1)
        f0 = write_file(tmp, "two0", base)
        f1 = write_file(tmp, "two1", base, R, np.array([3.0, -1.0, 2.0]))
        load1 = np.concatenate([R @ load[:3], R @ load[3:]])
        for m in (4, 8, 16):
            r0 = solve(scene(tmp, f"a{m}", f0, m, m, "bottom", "top", load), [], 1)
            r1 = solve(scene(tmp, f"b{m}", f1, m, m, "bottom", "top", load1), [], ranks)
            L = 0.2
            q0, q1 = r0["blocks/displacement"][1], r1["blocks/displacement"][1]
            want = np.concatenate([R @ q0[:3], L * (R @ q0[3:])])
            e = rel_err(np.concatenate([q1[:3], L * q1[3:]]), want)
            errors.append(e)
            print(f"m = m_b = {m}: rotated displacement of block 1 differs by {e:.2e}")
    expect(errors[1] <= 0.3 * errors[0] and errors[2] <= 0.3 * errors[1], f"no convergence as m, m_b grow: {errors}")
    expect(errors[2] < 1e-2, f"at m = m_b = 16 the rotated answer still differs by {errors[2]:.2e}")


def check_twoboxes(ranks):
    load = [700, -1500, 400, 30, -20, 45]
    with tempfile.TemporaryDirectory() as tmp:
        g = bw.Geometry()
        g.add_block(bw.box(0, 0, 0, 0.2, 0.1, 0.1), sets=["bottom"])
        g.add_block(bw.box(0, 0.11, 0, 0.2, 0.21, 0.1), sets=["top"])
        path = os.path.join(tmp, "two.h5")
        g.write(path)
        r_file = solve(scene(tmp, "two", path, 16, 4, "bottom", "top", load), [], ranks)
    r_gen = solve(TWO3, ["-loads_top", ",".join(map(str, load))], 1)
    for key in ("blocks/displacement", "interfaces/resultant", "portions/stress", "interfaces/frame", "interfaces/center"):
        e = rel_err(r_file[key], r_gen[key])
        print(f"{key}: {e:.1e}")
        expect(e < 1e-14, f"{key}: the two-box file differs from two_blocks by {e:.2e}")
    vol = r_file["blocks/vertices"]  # the hull's volume: the centroid of a box is its middle
    expect(np.allclose(r_file["blocks/centroid"][1], [0.1, 0.16, 0.05], rtol=0, atol=1e-15), "centroid of block 1")
    del vol


def corner_cube(depth, top=1.0):
    """A unit cube standing on a corner (its main diagonal along X2) above
    the middle of the face y = top, its lowest corner `depth` below it."""
    v = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
    a = np.array([1.0, 1.0, 1.0]) / np.sqrt(3)  # turned onto X2 about a x X2
    b = np.array([0.0, 1.0, 0.0])
    k = np.cross(a, b)
    s, c = np.linalg.norm(k), a @ b
    k /= s
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    w = v @ (np.eye(3) + s * K + (1 - c) * K @ K).T
    return w + [0.5, top - depth - w[:, 1].min(), 0.5]


def check_errors(ranks):
    from bwrun import run
    cube = bw.box(0, 0, 0, 1, 1, 1)
    top = bw.box(0, 1.01, 0, 1, 2.01, 1)
    cases = {
        "three_vertices": ([cube, cube[:3] + [0, 1.01, 0]], None, [], ["block 1 has 3 vertices", "at least 4"]),
        "planar": ([cube, np.array([[0, 1.01, 0], [1, 1.01, 0], [1, 1.01, 1], [0, 1.01, 1.0]])], None, [],
                   ["block 1: all its 4 vertices", "one plane"]),
        "inside": ([cube, np.vstack([top, [[0.5, 1.5, 0.5]]])], None, [], ["block 1: vertex row 16 (0.5, 1.5, 0.5) is not a corner"]),
        "repeated": ([cube, np.vstack([top, top[3:4]])], None, [], ["block 1: vertex row 16", "repeats vertex row 11"]),
        "on_edge": ([cube, np.vstack([top, [[0.5, 1.01, 0]]])], None, [], ["block 1: vertex row 16 (0.5, 1.01, 0", "is not a corner"]),
        "nan": ([cube, np.vstack([top[:7], [[np.nan, 2.01, 1]]])], None, [], ["block 1: vertex row 15 is not finite"]),
        "overlap": ([cube, cube + [0.5, 0.5, 0.5]], None, [], ["blocks 0 and 1 overlap", "share 0.125 m^3, 0.125 of the smaller"]),
        # listed interfaces are no excuse: the blocks are checked all the same
        "overlap_listed": ([cube, cube + [0.5, 0.5, 0.5]], [(0, 1)], [], ["blocks 0 and 1 overlap"]),
        # a cube standing on its corner, 0.2 m into the one below: the
        # corner tetrahedron (0.2 sqrt(3))^3 / 6 = 6.93e-3 m^3 is shared
        "overlap_corner": ([cube, corner_cube(0.2)], None, [], ["blocks 0 and 1 overlap", "share 0.00692"]),
        # 5 mm in: (0.005 sqrt(3))^3 / 6 = 1.1e-7 of the unit cube, below
        # the 1e-6 of interface.md's "relative tolerance of the smaller
        # volume" (the separating-axis depth alone, 5 mm, refused it): no
        # overlap, and the block, facing none, is held by nothing
        "corner_shallow": ([cube, top, corner_cube(0.005, 2.01)], None, [], ["block 2 (1 block) has no path of interfaces to a support"]),
        "not_facing": ([cube, top + [0, 0.5, 0]], [(0, 1)], [], ["interface 0 joins blocks 0 and 1, which have no facing faces"]),
        "pair_twice": ([cube, top], [(0, 1), (0, 1)], [], ["interface 1 repeats the pair (0, 1) of interface 0"]),
        "dimension_2": ([cube, top], None, ["-geometry_dimension", "2"], ["-geometry_dimension is 2, but the geometry file", "holds 3D blocks"]),
        "depth": ([cube, top], None, ["-geometry_depth", "0.2"], ["-geometry_depth has no meaning with a 3D geometry file"]),
    }
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, (blocks, pairs, args, wants) in cases.items():
            path = os.path.join(tmp, name + ".h5")
            bw.write_geometry(path, blocks, sets={"bottom": [0], "top": [1]}, pairs=pairs, check=False)
            sc = scene(tmp, name, path, 2, 2, "bottom", "top", [0, -1, 0, 0, 0, 0])
            out = os.path.join(tmp, name + "_out.h5")
            with open(out, "wb") as f:
                f.write(b"an earlier result")
            code, _, err = run(sc, [*args, "-output_file", out], ranks, expect_ok=False)
            lines = [ln for ln in err.strip().splitlines() if ln.strip()]
            if ranks > 1:  # mpiexec adds its own report of the failed job; blockwall's line must appear once
                lines = [ln for ln in lines if ln.startswith("blockwall")]
            ok = code == 1 and len(lines) == 1 and all(w in lines[0] for w in wants) and open(out, "rb").read() == b"an earlier result"
            print(f"{name}: exit {code}: {lines[0] if lines else '(nothing on stderr)'}")
            if not ok:
                failures.append(f"{name}: exit {code}, stderr {err!r}, wanted one line with {wants}")
    expect(not failures, "; ".join(failures))


def main():
    case = sys.argv[1]
    ranks = int(sys.argv[2]) if len(sys.argv) > 2 else 1
    {"generator": check_generator, "rotated": check_rotated, "general": check_general, "twoboxes": check_twoboxes,
     "errors": check_errors}[case](ranks)


if __name__ == "__main__":
    try:
        main()
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
