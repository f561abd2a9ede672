"""Large inputs are read in linear time, or refused at once with a clear
limit; none hangs.

  polygon  a geometry file with one block of 1e6 vertices (a dome on a
           foundation): self-intersection, overlap and interface detection
           once took 2.2 s at 1e4 vertices and did not end at 1e5
  zigzag   a block whose top edge zigzags with 1e5 steep teeth (a grid of
           the edges put thousands in a cell: N^1.75, 1.7 s at 1e5 and
           over a minute at 1e6): the work of the crossing-edge check, as
           PETSc's -info reports it, stays below 8 N log2 N at 1e4 and 1e5
           (it is about 4 N log2 N; quadratic work would be 1e3 N log2 N at
           1e5); a crossing and a near touch (0.3 delta, no crossing) put in
           the middle of the teeth are found and named by their rows
  sweep    random polygons of 65-400 vertices (above the all-pairs size),
           valid or with one vertex moved, accepted or refused exactly as a
           brute-force check of every pair of edges says
  keys     a scene of 1e5 keys (1e5 sets of a file, each loaded): parsing
           and set matching once took 3.3 s at 1e4 keys and 31 s at 3e4
  memory   a running-bond wall too large for this machine is refused before
           anything is allocated, saying what it needs and what there is

Each case is run under a timeout generous for linear work (a quadratic run
would take hours); the answers are checked against closed forms: the dome's
weight carried by the foundation, the sum of 1e5 loads."""
import os
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import ENV, EXE, Failure, call, expect, read  # noqa: E402


def run(tmp, scene_text, timeout):
    scene = os.path.join(tmp, "scene.yaml")
    with open(scene, "w") as f:
        f.write(scene_text)
    return call([EXE, "-scene", scene], timeout, env=ENV, cwd=tmp)


def polygon():
    n = 1_000_000
    t = np.linspace(0.0, np.pi, n)
    arc = np.column_stack([np.cos(t), 0.05 + 0.5 * np.sin(t)])  # from (1, 0.05) to (-1, 0.05)
    dome = np.vstack([[[-1.0, 0.0], [1.0, 0.0]], arc])
    found = np.array([[-1.2, -0.3], [1.2, -0.3], [1.2, -0.01], [-1.2, -0.01]])
    with tempfile.TemporaryDirectory() as tmp:
        with h5py.File(os.path.join(tmp, "dome.h5"), "w") as f:
            f["blocks/vertices"] = np.vstack([found, dome])
            f["blocks/offsets"] = np.array([0, 4, 4 + len(dome)], np.int64)
            f["sets/foundation"] = np.array([0], np.int64)
            f["sets/dome"] = np.array([1], np.int64)
        p = run(tmp, "geometry: {generator: file, file: dome.h5}\n"
                "supports: {foundation: {u1: 0, u2: 0, w: 0}}\n"
                "gravity: {density: 2000}\noutput: {file: out.h5, xdmf: false}\n", timeout=120)
        expect(p.returncode == 0, f"1e6-vertex polygon: exit {p.returncode}\n{p.stderr}")
        res = read(os.path.join(tmp, "out.h5"))
        # the dome's area: rectangle 2 x 0.05 plus half an ellipse (semi-axes
        # 1 and 0.5) less the chords' sagitta, which 1e6 vertices make 4e-13
        area = 2 * 0.05 + 0.5 * np.pi * 1.0 * 0.5
        weight = 2000 * 9.81 * area * 0.1
        found_weight = 2000 * 9.81 * 2.4 * 0.29 * 0.1
        r = res["blocks/reaction"][0]
        expect(abs(r[1] - weight - found_weight) <= 1e-9 * weight, f"foundation reaction {r[1]} vs the weights {weight + found_weight}")
        expect(len(res["interfaces/blocks"]) == 1, f"interfaces: {res['interfaces/blocks']}")
        print(f"1e6-vertex polygon: {res['solver']['seconds_generate']:.2f} s to read and check, one interface, reaction {r[1]:.4f} N = the weights")


FOUNDATION = np.array([[-1.2, -0.3], [1.2, -0.3], [1.2, -0.01], [-1.2, -0.01]])
SCENE = ("geometry: {generator: file, file: b.h5}\nsupports: {foundation: {u1: 0, u2: 0, w: 0}}\n"
         "gravity: {density: 2000}\noutput: {file: out.h5, xdmf: false}\n")


def one_block(tmp, block, extra=(), timeout=120):
    """The block on a foundation; blockwall's exit, stderr and stdout."""
    with h5py.File(os.path.join(tmp, "b.h5"), "w") as f:
        f["blocks/vertices"] = np.vstack([FOUNDATION, block])
        f["blocks/offsets"] = np.array([0, 4, 4 + len(block)], np.int64)
        f["sets/foundation"] = np.array([0], np.int64)
        f["sets/block"] = np.array([1], np.int64)
    with open(os.path.join(tmp, "scene.yaml"), "w") as f:
        f.write(SCENE)
    p = call([EXE, "-scene", "scene.yaml", *extra], timeout, env=ENV, cwd=tmp)
    return p.returncode, p.stderr, p.stdout


def teeth(n, height=0.05):
    """Bottom edge (-1, 0) -> (1, 0), then n teeth from right to left."""
    x = np.linspace(1.0, -1.0, n)
    y = 0.5 + height * (np.arange(n) % 2)
    return np.vstack([[[-1.0, 0.0], [1.0, 0.0]], np.column_stack([x, y])])


def delta_of(block):
    """model of validate.h: 1e-6 median edge length + 1e-12 max |coordinate|"""
    edges = []
    for poly in (FOUNDATION, block):
        edges.append(np.linalg.norm(np.roll(poly, -1, axis=0) - poly, axis=1))
    edges = np.concatenate(edges)
    return 1e-6 * np.median(edges) + 1e-12 * np.abs(np.vstack([FOUNDATION, block])).max()


def zigzag():
    for n in (10_000, 100_000):
        with tempfile.TemporaryDirectory() as tmp:
            code, err, out = one_block(tmp, teeth(n), ["-info"])
            expect(code == 0, f"{n} teeth: exit {code}\n{err[-400:]}")
            steps = [int(l.split(" steps")[0].split()[-1]) for l in out.splitlines() if "checked for crossing edges" in l]
            nv = n + 2
            expect(len(steps) == 1, f"{n} teeth: no work line from -info")
            per = steps[0] / (nv * np.log2(nv))
            expect(per < 8, f"{n} teeth: {steps[0]} steps = {per:.1f} N log2 N (more than 8)")
            print(f"{nv} vertices: {steps[0]} steps of the crossing-edge check = {per:.2f} N log2 N")
    n = 100_000
    d = delta_of(teeth(n))
    mid = 2 + n // 2  # a tooth tip (odd position from the start of the teeth: y = 0.55)
    mid += (mid - 2) % 2 == 0
    cases = []
    crossing = teeth(n)
    crossing[mid, 0] = crossing[mid + 3, 0]  # the tip leans over two teeth
    cases.append(("crossing", crossing, mid))
    near = teeth(n)
    # the tip slides towards the next tip until it is 0.3 delta from the edge
    # that rises to that tip, without crossing it
    a, b = near[mid + 1], near[mid + 2]
    t = (b - a) / np.linalg.norm(b - a)
    normal = np.array([-t[1], t[0]])
    if np.dot(near[mid] - a, normal) < 0:
        normal = -normal
    foot = a + 0.5 * (b - a)
    near[mid] = foot + 0.3 * d * normal
    cases.append(("near touch", near, mid))
    for what, block, row in cases:
        with tempfile.TemporaryDirectory() as tmp:
            code, err, _ = one_block(tmp, block)
            lines = [l for l in err.splitlines() if l.strip()]
            expect(code == 1 and len(lines) == 1 and "self-intersecting" in lines[0],
                   f"{what} in {n} teeth: exit {code}, {lines}")
            rows = [int(w) for w in lines[0].replace(" to ", " ").split() if w.isdigit()]
            expect(any(abs(r - (4 + row)) <= 3 for r in rows), f"{what}: the rows named {rows} are not near row {4 + row}")
            print(f"{what} at row {4 + row} of {n} teeth: {lines[0]}")


def brute_force_min(poly):
    """The smallest distance between two edges that share no vertex."""
    n = len(poly)
    a0, a1 = poly, np.roll(poly, -1, axis=0)
    best = np.inf

    def point_seg(p, s0, s1):
        dd = s1 - s0
        l2 = (dd * dd).sum(-1)
        t = np.clip(((p - s0) * dd).sum(-1) / np.where(l2 > 0, l2, 1), 0, 1)
        return np.linalg.norm(p - (s0 + t[..., None] * dd), axis=-1)

    for k in range(n):
        ls = np.array([l for l in range(n) if l != k and (l + 1) % n != k and (k + 1) % n != l])
        b0, b1 = a0[ls], a1[ls]
        p0, p1 = a0[k], a1[k]
        cr = lambda o, e, q: (e[..., 0] - o[..., 0]) * (q[..., 1] - o[..., 1]) - (e[..., 1] - o[..., 1]) * (q[..., 0] - o[..., 0])
        o1, o2 = cr(p0, p1, b0), cr(p0, p1, b1)
        o3, o4 = cr(b0, b1, p0), cr(b0, b1, p1)
        crossing = (o1 * o2 < 0) & (o3 * o4 < 0)
        dist = np.minimum.reduce([point_seg(p0, b0, b1), point_seg(p1, b0, b1), point_seg(b0, p0, p1), point_seg(b1, p0, p1)])
        dist[crossing] = 0
        best = min(best, dist.min())
    return best


def sweep():
    rng = np.random.default_rng(20261124)
    tried = {"valid": 0, "refused": 0}
    for attempt in range(400):
        if min(tried.values()) >= 6:
            break
        n = int(rng.integers(65, 400))
        th = np.sort(rng.uniform(0.02, np.pi - 0.02, n))  # from the right end of the base round to its left
        r = rng.uniform(0.5, 1.0, n)
        arc = np.column_stack([r * np.cos(th), 0.05 + 0.5 * r * np.sin(th)])
        block = np.vstack([[[-1.0, 0.0], [1.0, 0.0]], arc])
        if rng.uniform() < 0.6:  # one vertex of the arc moved somewhere over the base
            k = int(rng.integers(2, len(block)))
            block[k] = [rng.uniform(-0.9, 0.9), rng.uniform(0.1, 0.5)]
        d = delta_of(block)
        dmin = brute_force_min(block)
        if 0.1 * d < dmin < 10 * d or np.linalg.norm(np.diff(block, axis=0), axis=1).min() < 10 * d:
            continue  # too close to the tolerance to call
        want = "valid" if dmin > d else "refused"
        if tried[want] >= 6:
            continue
        with tempfile.TemporaryDirectory() as tmp:
            code, err, _ = one_block(tmp, block)
        got = "valid" if "self-intersecting" not in err else "refused"
        expect(got == want, f"{len(block)}-vertex polygon, closest edges {dmin:.3g} (delta {d:.3g}): {got}, brute force says {want}\n{err}")
        tried[want] += 1
        print(f"{len(block)} vertices, closest non-adjacent edges {dmin:.3g} m (delta {d:.3g}): {got}, as the brute force says")
    expect(min(tried.values()) >= 6, f"only {tried} polygons far enough from the tolerance in 400 draws")


def keys():
    n = 100_000
    with tempfile.TemporaryDirectory() as tmp:
        blocks = [np.array([[0, -0.2], [1, -0.2], [1, -0.01], [0, -0.01]]), np.array([[0, 0], [1, 0], [1, 0.1], [0, 0.1]])]
        with h5py.File(os.path.join(tmp, "two.h5"), "w") as f:
            f["blocks/vertices"] = np.concatenate(blocks)
            f["blocks/offsets"] = np.array([0, 4, 8], np.int64)
            f["sets/foundation"] = np.array([0], np.int64)
            # sets may share blocks: 1e5 names for block 1, written with
            # h5py's low-level calls (3x faster than f[name] = ..., whose
            # object bookkeeping took 25 of this test's 46 s)
            sets, space, one = f["sets"].id, h5py.h5s.create_simple((1,)), np.array([1], np.int64)
            for k in range(n):
                h5py.h5d.create(sets, f"s{k}".encode(), h5py.h5t.STD_I64LE, space).write(h5py.h5s.ALL, h5py.h5s.ALL, one)
        lines = ["geometry: {generator: file, file: two.h5}", "supports: {foundation: {u1: 0, u2: 0, w: 0}}", "loads:"]
        lines += [f"  s{k}: [0.001, -0.01, 0]" for k in range(n)]
        lines += ["output: {file: out.h5, xdmf: false}"]
        p = run(tmp, "\n".join(lines) + "\n", timeout=300)
        expect(p.returncode == 0, f"1e5 keys: exit {p.returncode}\n{p.stderr}")
        with h5py.File(os.path.join(tmp, "out.h5")) as f:  # not read(): it would load 1e5 sets
            res = {"blocks/load": f["blocks/load"][()], "blocks/reaction": f["blocks/reaction"][()],
                   "solver": dict(f["solver"].attrs)}
        load = res["blocks/load"][1]
        expect(abs(load[0] - 0.001 * n) <= 1e-9 * 0.001 * n and abs(load[1] + 0.01 * n) <= 1e-9 * 0.01 * n, f"1e5 loads summed to {load}")
        r = res["blocks/reaction"][0]
        expect(abs(r[0] + load[0]) <= 1e-9 * abs(load[0]) and abs(r[1] + load[1]) <= 1e-9 * abs(load[1]), f"reaction {r} vs load {load}")
        print(f"1e5 keys: {res['solver']['seconds_total']:.2f} s in all, loads summed to {load[0]:.6g}, {load[1]:.6g} N and balanced")


def memory():
    with tempfile.TemporaryDirectory() as tmp:
        p = run(tmp, "geometry: {generator: running_bond, running_bond: {courses: 20000, units_per_course: 5000}}\n"
                "supports: {foundation: {u1: 0, u2: 0, w: 0}}\noutput: {file: out.h5}\n", timeout=60)
        lines = [l for l in p.stderr.splitlines() if l.strip()]
        expect(p.returncode == 1 and len(lines) == 1, f"huge wall: exit {p.returncode}, stderr:\n{p.stderr}")
        for want in ("geometry.running_bond: 20000 courses of 5000 units", "needs about", "GB of memory", "this machine has available"):
            expect(want in lines[0], f"huge wall: {want!r} not in {lines[0]!r}")
        expect(os.listdir(tmp) == ["scene.yaml"], f"huge wall: files left: {os.listdir(tmp)}")
        print(lines[0])


if __name__ == "__main__":
    try:
        {"polygon": polygon, "zigzag": zigzag, "sweep": sweep, "keys": keys, "memory": memory}[sys.argv[1]]()
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
