"""The gallery's examples are tests (examples/*.yaml as shipped, their
geometry made by their own scripts or tools/import_dxf), each against a
reference that does not come from blockwall:

  two_blocks  examples/paper_case2.yaml: block 1's displacement and the 16
              portion stresses against model.md's closed form (tests/paper),
              1e-10
  demo        examples/demo.yaml on 2 ranks: the invariants below
  openings    examples/openings.yaml: the blocks left are exactly the units
              whose centroid lies outside both openings, by interface.md's
              layout computed here (centroids to 1e-12); the invariants
  arch        examples/arch.py + arch.yaml: the 16 joints at phi = pi k/15
              with G, theta, l of the construction (1e-12); the arch and its
              loads are symmetric about x = 0, so block k and its mirror
              have u1, w opposite and u2 equal (1e-9 of the largest), and
              the springers' horizontal reactions (the thrust) are opposite
              (1e-9); the invariants
  stones      examples/stones.py + stones.yaml (dry joints): every stone has
              an interface above and below it; the invariants
  facade      examples/facade.dxf as shipped is what examples/facade_dxf.py
              draws (imported vertices equal); imported with
              tools/import_dxf and run on 2 ranks, it gives the results of
              the same blocks written directly with the package on 1 rank
              (1e-12, see DIRECT_TOL); the invariants

The invariants (every example):
  loads     /blocks/load is -density g A s on F2 plus the scene's set
            loads, with A the polygon's area computed here (shoelace), 1e-12
  balance   the reactions balance the loads so computed: force and moment
            about the origin, relative to the total load, 1e-9
  statics   every free block is in equilibrium under its load and the forces
            its joints exert (T t + N n and M about G on block i, the opposite
            on j), from /interfaces/resultant alone, relative to the largest
            load on a block, 1e-9
Why 1e-9: each run meets a relative residual of 1e-10 on the scaled mixed
system (solver.rtol); a block's imbalance is a few rows of that residual,
measured 1e-14 .. 1e-12, so 1e-9 leaves two orders of margin and still
catches any wrong sign, lever arm or missing joint (those give O(1))."""
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
EXAMPLES = os.path.join(ROOT, "examples")
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(HERE, "..", "paper"))
sys.path.insert(0, os.path.join(HERE, "..", "geometry"))
sys.path.insert(0, EXAMPLES)
from bwrun import Failure, call, expect, rel_err, solve  # noqa: E402
import blockwall as bw  # noqa: E402

G = 9.81
TOL_STATICS = 1e-9
DIRECT_TOL = 1e-12  # DXF (mm x 1e-3) against metres written directly: coordinates differ by round-off (1e-16
#                     relative), which the solve amplifies by its condition (measured 1e-15 on the facade)


def area(p):
    x, y = p[:, 0], p[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def polygons(res):
    v, off = res["blocks/vertices"], res["blocks/offsets"]
    return [v[off[b]:off[b + 1]] for b in range(len(off) - 1)]


def expected_loads(res, density, depth, set_loads):
    """(B, 3): self-weight from the polygons' areas plus the set loads."""
    load = np.zeros((len(res["blocks/offsets"]) - 1, 3))
    load[:, 1] = [-density * G * area(p) * depth for p in polygons(res)]
    for name, f in set_loads.items():
        load[res[f"sets/{name}"]] += np.asarray(f, float)
    return load


def wrench(force, at):
    """Total force and moment about the origin of forces (n, 3) = (F1, F2, M) applied at points `at` (n, 2)."""
    return np.array([force[:, 0].sum(), force[:, 1].sum(),
                     np.sum(force[:, 2] + at[:, 0] * force[:, 1] - at[:, 1] * force[:, 0])])


def statics(res, free):
    """Largest residual of force and moment on the free blocks, from the joints' resultants, over the largest load."""
    c, load = res["blocks/centroid"], res["blocks/load"]
    total = load.copy()
    for k, (i, j) in enumerate(res["interfaces/blocks"]):
        th, g = res["interfaces/angle"][k], res["interfaces/center"][k]
        t, n = np.array([np.cos(th), np.sin(th)]), np.array([-np.sin(th), np.cos(th)])
        T, N, M = res["interfaces/resultant"][k]
        F = T * t + N * n
        for b, sign in ((i, 1.0), (j, -1.0)):
            arm = g - c[b]
            total[b] += sign * np.array([F[0], F[1], M + arm[0] * F[1] - arm[1] * F[0]])
    return np.max(np.abs(total[free])) / np.max(np.abs(load[free]))


def invariants(res, density, depth, set_loads, what):
    want = expected_loads(res, density, depth, set_loads)
    e_load = rel_err(res["blocks/load"], want)
    expect(e_load < 1e-12, f"{what}: /blocks/load differs from self-weight + set loads by {e_load:.1e}")
    size = np.ptp(res["blocks/vertices"], axis=0).max()
    fixed = np.any(res["blocks/prescribed"] != 0, axis=1)
    loads = wrench(want, res["blocks/centroid"])
    reactions = wrench(res["blocks/reaction"][fixed], res["blocks/centroid"][fixed])
    scale = np.abs(loads) * np.array([1, 1, 1 / size])
    e_bal = np.max(np.abs(loads + reactions) * np.array([1, 1, 1 / size])) / scale.max()
    expect(e_bal < TOL_STATICS, f"{what}: reactions do not balance the loads: {e_bal:.1e}")
    e_st = statics(res, np.flatnonzero(~fixed))
    expect(e_st < TOL_STATICS, f"{what}: a free block is out of equilibrium by {e_st:.1e} of the largest load")
    print(f"{what}: loads as computed here {e_load:.1e}; reactions balance the loads {e_bal:.1e}; "
          f"every free block in equilibrium with its joints {e_st:.1e}")
    return e_bal, e_st


def scene_run(scene, tmp, args=(), ranks=1):
    return solve(os.path.join(EXAMPLES, scene), [*args, "-output_xdmf", "0"], ranks)


def two_blocks():
    from check_paper import closed_form
    res = scene_run("paper_case2.yaml", None)
    q_ref, s_ref = closed_form(0.2, 0.1, 1000.0, -1000.0)
    e_q, e_s = rel_err(res["blocks/displacement"][1], q_ref), rel_err(res["interfaces/stress"][0], s_ref)
    expect(e_q < 1e-10 and e_s < 1e-10, f"two blocks vs closed form: displacement {e_q:.1e}, stresses {e_s:.1e}")
    print(f"paper case 2 vs closed form: displacement {e_q:.1e}, stresses {e_s:.1e}")
    invariants(res, 0.0, 0.1, {"top": (1000, -1000, 0)}, "paper case 2")


def demo():
    res = scene_run("demo.yaml", None, ranks=2)
    expect(res["solver"]["ranks"] == 2, "not run on 2 ranks")
    invariants(res, 0.0, 0.1, {"top_beam": (10000, -29700, 0)}, "demo wall, 2 ranks")


def running_bond_centroids(courses, n, lu, hu, e, hf, hb, openings):
    """interface.md's layout: centroids of foundation, the units left, top beam."""
    L = n * lu + (n - 1) * e
    half = (lu - e) / 2
    out = [(L / 2, -e - hf / 2)]
    for k in range(courses):
        y = k * (hu + e) + hu / 2
        if k % 2 == 0:
            xs = [i * (lu + e) + lu / 2 for i in range(n)]
        else:
            xs = [half / 2] + [half + e + i * (lu + e) + lu / 2 for i in range(n - 1)] + [L - half / 2]
        out += [(x, y) for x in xs if not any(x0 <= x <= x1 and y0 <= y <= y1 for x0, y0, x1, y1 in openings)]
    ytop = (courses - 1) * (hu + e) + hu
    out.append((L / 2, ytop + e + hb / 2))
    return np.array(out)


def openings():
    res = scene_run("openings.yaml", None)
    boxes = [(0.3, 0.0, 0.75, 0.75), (1.3, 0.38, 1.85, 0.8)]
    want = running_bond_centroids(18, 10, 0.21, 0.052, 0.01, 0.1, 0.1, boxes)
    full = running_bond_centroids(18, 10, 0.21, 0.052, 0.01, 0.1, 0.1, [])
    got = res["blocks/centroid"]
    expect(got.shape == want.shape, f"{len(got)} blocks, the layout leaves {len(want)} ({len(full) - len(want)} in openings)")
    e_c = rel_err(got, want)
    expect(e_c < 1e-12, f"block centroids differ from the layout by {e_c:.1e}")
    print(f"openings: {len(full) - len(want)} units left out, the {len(want)} blocks where the layout puts them ({e_c:.1e})")
    invariants(res, 1800.0, 0.1, {"top_beam": (6000, -40000, 0)}, "wall with a door and a window")


def arch():
    import arch as example
    with tempfile.TemporaryDirectory() as tmp:
        geo = os.path.join(tmp, "arch.h5")
        p = call([sys.executable, os.path.join(EXAMPLES, "arch.py"), geo], what="examples/arch.py")
        expect(p.returncode == 0, f"examples/arch.py: exit {p.returncode}\n{p.stderr}")
        res = scene_run("arch.yaml", tmp, ["-geometry_file", geo])
    g, joints = example.arch(**example.SPAN)
    n = example.SPAN["n"]
    expect(res["interfaces/blocks"].tolist() == [[i, j] for i, j, *_ in joints], f"joints {res['interfaces/blocks'].tolist()}")
    e_g = rel_err(res["interfaces/center"], np.array([c for _, _, c, _, _ in joints]))
    e_t = np.max(np.abs(np.angle(np.exp(1j * (res["interfaces/angle"] - [t for *_, t, _ in joints])))))
    e_l = rel_err(res["interfaces/length"], np.array([l for *_, l in joints]))
    expect(max(e_g, e_t, e_l) < 1e-12, f"arch joints vs construction: G {e_g:.1e}, theta {e_t:.1e}, l {e_l:.1e}")
    u = res["blocks/displacement"]
    mirror = u[::-1]  # block k <-> n+1-k
    scale = np.max(np.abs(u))
    e_sym = max(np.max(np.abs(u[:, 0] + mirror[:, 0])), np.max(np.abs(u[:, 1] - mirror[:, 1])),
                np.max(np.abs(u[:, 2] + mirror[:, 2])) * 1.3) / scale
    expect(e_sym < 1e-9, f"arch not symmetric: {e_sym:.1e}")
    H = res["blocks/reaction"][[0, n + 1], 0]
    # the arch pushes its springers apart: the support holds the right one (x > 0) with a force towards -x
    expect(H[0] < 0 and abs(H[0] + H[1]) < 1e-9 * abs(H[0]), f"springer thrusts {H}")
    print(f"arch: {len(joints)} joints as constructed (G {e_g:.1e}, theta {e_t:.1e}, l {e_l:.1e}); symmetric to {e_sym:.1e}; "
          f"horizontal reactions (thrust) {H[0]:.6g} N on the right springer, {H[1]:.6g} N on the left")
    invariants(res, 2200.0, 0.5, {"crown": (0, -20000, 0)}, "arch")


def stones():
    with tempfile.TemporaryDirectory() as tmp:
        geo = os.path.join(tmp, "stones.h5")
        p = call([sys.executable, os.path.join(EXAMPLES, "stones.py"), geo], what="examples/stones.py")
        expect(p.returncode == 0, f"examples/stones.py: exit {p.returncode}\n{p.stderr}")
        res = scene_run("stones.yaml", tmp, ["-geometry_file", geo])
    stones_ = res["sets/stones"]
    c = res["blocks/centroid"]
    pairs = res["interfaces/blocks"]
    for b in stones_:
        others = np.concatenate([pairs[pairs[:, 0] == b, 1], pairs[pairs[:, 1] == b, 0]])
        expect(np.any(c[others, 1] > c[b, 1]) and np.any(c[others, 1] < c[b, 1]),
               f"stone {b} has no interface above or below it")
    print(f"stones: {len(stones_)} stones, {len(pairs)} interfaces, each stone held above and below")
    invariants(res, 2400.0, 0.4, {"cap": (5000, -30000, 0)}, "dry-stone wall")


def facade():
    import facade_dxf
    with tempfile.TemporaryDirectory() as tmp:
        shipped, fresh = os.path.join(tmp, "shipped.h5"), os.path.join(tmp, "fresh.h5")
        drawing = os.path.join(tmp, "facade.dxf")
        facade_dxf.draw(drawing)
        for src, dst in ((os.path.join(EXAMPLES, "facade.dxf"), shipped), (drawing, fresh)):
            p = call([sys.executable, os.path.join(ROOT, "tools", "import_dxf"), src, dst, "--layer-sets"], what="tools/import_dxf")
            expect(p.returncode == 0, f"import_dxf {src}: {p.stderr}")
        a, b = bw.read_geometry(shipped), bw.read_geometry(fresh)
        expect(len(a.blocks) == len(b.blocks) and all(np.array_equal(x, y) for x, y in zip(a.blocks, b.blocks))
               and a.sets == b.sets, "examples/facade.dxf is not what examples/facade_dxf.py draws: run it again")
        direct = os.path.join(tmp, "direct.h5")
        blocks = facade_dxf.facade()
        sets = {}
        for k, (layer, _, _) in enumerate(blocks):
            sets.setdefault(layer, []).append(k)
        bw.write_geometry(direct, [p * 1e-3 for _, _, p in blocks], sets=sets)
        res = scene_run("facade.yaml", tmp, ["-geometry_file", shipped], ranks=2)
        ref = scene_run("facade.yaml", tmp, ["-geometry_file", direct])
    from check_file import same
    same(res, ref, DIRECT_TOL, "facade from the DXF (2 ranks) vs written directly (1 rank)")
    e = rel_err(res["blocks/displacement"], ref["blocks/displacement"])
    print(f"facade: {len(blocks)} blocks, {len(res['interfaces/blocks'])} interfaces; DXF import on 2 ranks vs the "
          f"blocks written directly on 1: displacements {e:.1e}")
    invariants(res, 1800.0, 0.1, {"top_beam": (8000, -48200, 0)}, "facade")


if __name__ == "__main__":
    try:
        {"two_blocks": two_blocks, "demo": demo, "openings": openings, "arch": arch, "stones": stones,
         "facade": facade}[sys.argv[1]]()
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
