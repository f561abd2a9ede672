"""The running_bond generator and walls solved with it.

  counts       blocks and interfaces in closed form for several (courses, n),
               1 x 1 and odd/even included; every head joint over the middle
               of a unit below; total block area = wall area minus joints
  openings     exactly the units whose centroid lies in the rectangle go
  compression  dry joints of zero thickness, foundation fixed, top beam
               pressed by P: head joints carry no stress, every bed joint
               sigma = -P/(L s), the top beam moves (courses + 1) sigma / kn,
               to 1e-10; reactions balance the load to 1e-10
"""
import itertools
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import Failure, expect, rel_err, solve  # noqa: E402

SCENE = os.path.join(os.path.dirname(__file__), "wall.yaml")
SCENE_DRY = os.path.join(os.path.dirname(__file__), "wall_dry.yaml")
LU, HU, E_J, S = 0.21, 0.052, 0.01, 0.1


def wall(courses, n, *extra):
    return ["-geometry_running_bond_courses", courses, "-geometry_running_bond_units_per_course", n, *extra]


def areas(res):
    v, off = res["blocks/vertices"], res["blocks/offsets"]
    a = []
    for b in range(len(off) - 1):
        p = v[off[b]:off[b + 1]]
        x, y = p[:, 0], p[:, 1]
        a.append(0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    return np.array(a)


def counts():
    for courses, n in itertools.product((1, 2, 3, 6), (1, 2, 5)):
        res = solve(SCENE, wall(courses, n))
        even, odd = (courses + 1) // 2, courses // 2
        units = even * n + odd * (n + 1)
        head = even * (n - 1) + odd * n
        top_units = n if (courses - 1) % 2 == 0 else n + 1
        bed = n + (courses - 1) * 2 * n + top_units
        nb, ni = len(res["blocks/offsets"]) - 1, len(res["interfaces/blocks"])
        expect(nb == units + 2, f"{courses}x{n}: {nb} blocks, closed form {units + 2}")
        expect(ni == head + bed, f"{courses}x{n}: {ni} interfaces, closed form {head} head + {bed} bed")
        L = n * LU + (n - 1) * E_J
        a = areas(res)
        unit_area = np.sum(a[1:-1])
        want = courses * HU * L - head * E_J * HU
        expect(abs(unit_area - want) < 1e-12 * want, f"{courses}x{n}: unit area {unit_area} vs {want}")
        expect(np.all(a > 0), "counter-clockwise blocks")
        # head joints: vertical (theta = -pi/2), over the middle of a unit below
        ang, G, pairs = res["interfaces/angle"], res["interfaces/center"], res["interfaces/blocks"]
        cen = res["blocks/centroid"]
        is_head = np.isclose(ang, -np.pi / 2)
        expect(np.sum(is_head) == head, f"{courses}x{n}: head joints by angle")
        for k in np.nonzero(is_head)[0]:
            y = G[k, 1]
            if y < HU:  # bottom course: over the foundation
                continue
            below = [b for b in range(1, nb - 1) if abs(cen[b, 1] - (y - HU - E_J)) < 1e-9]
            expect(any(abs(cen[b, 0] - G[k, 0]) < 1e-12 for b in below),
                   f"{courses}x{n}: head joint {k} at x = {G[k, 0]} is not over the middle of a unit")
        expect(np.all(pairs[:, 0] < pairs[:, 1]), "pairs i < j")
        order = np.lexsort((G[:, 0], pairs[:, 1], pairs[:, 0]))
        expect(np.all(order == np.arange(ni)), "interfaces sorted by (i, j)")
        print(f"{courses} x {n}: {nb} blocks, {ni} interfaces ({head} head) as in closed form")


def openings():
    base = solve(SCENE, wall(6, 5))
    box = (0.3, 0.1, 0.8, 0.25)
    res = solve(SCENE, wall(6, 5, "-geometry_running_bond_openings", ",".join(map(str, box))))
    c = base["blocks/centroid"][1:-1]
    inside = (c[:, 0] >= box[0]) & (c[:, 0] <= box[2]) & (c[:, 1] >= box[1]) & (c[:, 1] <= box[3])
    kept = np.concatenate([[base["blocks/centroid"][0]], c[~inside], [base["blocks/centroid"][-1]]])
    expect(np.sum(inside) > 0, "the opening removes something")
    expect(res["blocks/centroid"].shape == kept.shape and np.allclose(res["blocks/centroid"], kept, rtol=0, atol=1e-15),
           "openings removed other units than those whose centroid is inside")
    print(f"opening removed {np.sum(inside)} units, exactly those inside")


def compression():
    P, kn, courses, n = 5.0e4, 2.0e11, 7, 4
    res = solve(SCENE_DRY, wall(courses, n, "-joints_kn", kn, "-loads_top_beam", f"0,{-P},0"))
    L = n * LU  # e = 0 for dry joints
    sigma = -P / (L * S)
    st, ang = res["interfaces/stress"], res["interfaces/angle"]
    head = np.isclose(ang, -np.pi / 2)
    expect(np.max(np.abs(st[head])) <= 1e-10 * abs(sigma), f"head joints carry stress {np.max(np.abs(st[head]))}")
    expect(np.max(np.abs(st[~head][:, :, 1] - sigma)) <= 1e-10 * abs(sigma), "bed joints not uniform -P/(L s)")
    expect(np.max(np.abs(st[~head][:, :, 0])) <= 1e-10 * abs(sigma), "bed joints carry shear")
    u_top = res["blocks/displacement"][-1]
    want = (courses + 1) * sigma / kn
    expect(abs(u_top[1] - want) <= 1e-10 * abs(want), f"top beam u2 {u_top[1]} vs (courses+1) sigma/kn = {want}")
    expect(abs(u_top[0]) <= 1e-10 * abs(want) and abs(u_top[2]) * L <= 1e-10 * abs(want), "top beam moves sideways")
    expect(res["solver"]["equilibrium_error"] < 1e-10, "reactions do not balance the load")
    r = res["blocks/reaction"][0]
    expect(abs(r[1] - P) < 1e-10 * P and abs(r[0]) < 1e-10 * P, f"foundation reaction {r}")
    print(f"compression: sigma {sigma:.6e} uniform, u_top {u_top[1]:.6e} = {want:.6e}, equilibrium error {res['solver']['equilibrium_error']:.1e}")


def balanced():
    """Loads that sum to zero, and a prescribed displacement without loads:
    correct answers whose balance must read as balanced. equilibrium_error
    is |sum of reactions + loads| relative to the forces involved (before:
    relative to the loads' resultant alone, it read 1.0 on both)."""
    # bottom and top course (both even: n units each) pushed apart
    res = solve(SCENE, wall(5, 4, "-loads_bottom_course", "0,-1000,0", "-loads_top_course", "0,1000,0", "-loads_top_beam", "0,0,0"))
    e1 = res["solver"]["equilibrium_error"]
    expect(e1 <= 1e-10, f"self-balanced loads: equilibrium error {e1:.3e}")
    r = res["blocks/reaction"][0]
    expect(np.max(np.abs(r)) <= 1e-9 * 1000 * 4, f"self-balanced loads: the foundation reacts {r}")
    # the top beam moved sideways by 1 mm, nothing loaded
    res = solve(SCENE, wall(5, 4, "-loads_top_beam", "0,0,0", "-supports_top_beam_u1", 1e-3))
    e2 = res["solver"]["equilibrium_error"]
    rr = res["blocks/reaction"]
    expect(e2 <= 1e-10, f"prescribed displacement: equilibrium error {e2:.3e}")
    expect(abs(rr[0][0] + rr[-1][0]) <= 1e-10 * abs(rr[-1][0]), f"prescribed displacement: x reactions {rr[0][0]} and {rr[-1][0]} do not balance")
    print(f"self-balanced loads: equilibrium error {e1:.1e}; prescribed displacement: {e2:.1e}, reaction {rr[-1][0]:.4e} N")


if __name__ == "__main__":
    try:
        {"counts": counts, "openings": openings, "compression": compression, "balanced": balanced}[sys.argv[1]]()
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
