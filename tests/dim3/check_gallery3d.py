"""The 3D gallery (examples/walls3d.py and its scenes, as shipped), each
against a reference that does not come from blockwall's solver:

  cantilever  examples/cantilever3d.yaml: a wall of N rigid courses under a
              force F3 at the top course's centroid. Joint k (at height
              y_k, area A = L t, I_b = L t^3/12) carries Tb = F3 and
              Mt = F3 (y_top - y_k), so the top moves by
                u3 = sum_k F3/(kt A) + F3 (y_top - y_k)^2 / (kn I_b (1 - 1/m_b^2))
                w1 = sum_k F3 (y_top - y_k) / (kn I_b (1 - 1/m_b^2))
              (model.md's K_G), 1e-10; every course's u3 likewise
  u_wall      examples/u_wall.yaml, on 2 ranks; vault: examples/vault.yaml.
              A second solver written here in numpy: for every interface of
              the result (its pair and polygon), the frame by model.md's rule
              from the polygon's own normal (Newell), K_G summed over the
              m x m_b cells of the polygon's box clipped to it (Sutherland-
              Hodgman here), K = sum (R B)^T K_G (R B) with P_b from the
              centroids, the loads of the scene (self-weight: density g
              volume, the volume of every block by the divergence theorem
              over its faces here), solved densely: the displacements
              agree to 1e-8 of the largest (rotations times the assembly's
              size). The detected interfaces themselves are checked against
              the construction: every pair of blocks whose boxes share a
              face patch across a joint (computed from the boxes) is an
              interface, with the patch's area.

usage: check_gallery3d.py CASE
"""
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
EX = os.path.join(ROOT, "examples")
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from bwrun import Failure, call, expect, solve  # noqa: E402

E, NU, E_J = 1.0e9, 0.2, 0.01


def write_geometry(which, tmp):
    path = os.path.join(tmp, f"{which}.h5")
    p = call([sys.executable, os.path.join(EX, "walls3d.py"), which, path], what="examples/walls3d.py")
    expect(p.returncode == 0, f"examples/walls3d.py {which}: exit {p.returncode}\n{p.stderr}")
    return path


def run_example(scene_name, which, ranks=1):
    with tempfile.TemporaryDirectory() as tmp:
        geo = write_geometry(which, tmp)
        return solve(os.path.join(EX, scene_name), ["-geometry_file", geo], ranks)


def check_cantilever():
    r = run_example("cantilever3d.yaml", "cantilever")
    kn, kt = E / E_J, E / (2 * (1 + NU) * E_J)
    L, h, t, e, mb, F3 = 1.0, 0.1, 0.2, 0.01, 4, 2000.0
    c = r["blocks/centroid"]
    courses = np.arange(1, len(c))
    y_top = c[-1, 1]
    A, Ib = L * t, L * t**3 / 12
    joints_y = np.array([k * (h + e) - e / 2 for k in range(len(courses))])  # G of joint k under course k
    u3 = np.zeros(len(c))
    w1 = np.zeros(len(c))
    for k, yk in enumerate(joints_y):
        phi = F3 * (y_top - yk) / (kn * Ib * (1 - 1 / mb**2))
        # every course above joint k moves with it: translation db + the rotation's lever to its centroid
        for b in courses[k:]:
            u3[b] += F3 / (kt * A) + phi * (c[b, 1] - yk)
            w1[b] += phi
    q = r["blocks/displacement"]
    e_u = np.max(np.abs(q[:, 2] - u3)) / np.max(np.abs(u3))
    e_w = np.max(np.abs(q[:, 3] - w1)) / np.max(np.abs(w1))
    print(f"cantilever: top u3 {q[-1, 2]:.6e} m (closed form {u3[-1]:.6e}), u3 of every course {e_u:.1e}, w1 {e_w:.1e}")
    expect(e_u < 1e-10 and e_w < 1e-10, f"cantilever: u3 {e_u:.2e}, w1 {e_w:.2e} off the closed form")
    # a column of full courses (centroids above one another, bed joints only)
    # splits further: sway and bending in its plane, compression, sway and
    # bending out of it, torsion
    check_groups(r, "cantilever", 4, "u1 w3 | u2 | u3 w1 | w2")


def frame_rule(n):
    b = np.array([0.0, 0.0, 1.0]) - n[2] * n
    if np.linalg.norm(b) < 1e-6:
        b = np.array([0.0, 1.0, 0.0]) - n[1] * n
    b /= np.linalg.norm(b)
    return np.array([np.cross(n, b), n, b])


def cross_matrix(a):
    return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


def block_volumes(res):
    """Volume of every block from its vertices: the convex hull's faces found
    here by brute force (planes through 3 vertices with all on one side)."""
    v, off = res["blocks/vertices"], res["blocks/offsets"]
    vols = []
    for b in range(len(off) - 1):
        p = v[off[b]:off[b + 1]]
        c = p.mean(axis=0)
        vol, seen = 0.0, []
        n = len(p)
        for i in range(n):
            for j in range(i + 1, n):
                for k in range(j + 1, n):
                    nrm = np.cross(p[j] - p[i], p[k] - p[i])
                    if np.linalg.norm(nrm) < 1e-12:
                        continue
                    nrm /= np.linalg.norm(nrm)
                    s = (p - p[i]) @ nrm
                    if s.max() > 1e-9 and s.min() < -1e-9:
                        continue
                    if s.max() > 1e-9:
                        nrm, s = -nrm, -s
                    d = nrm @ p[i]
                    if any(np.allclose(nrm, m) and abs(d - dd) < 1e-9 for m, dd in seen):
                        continue
                    seen.append((nrm, d))
                    face = p[np.abs(s) < 1e-9]
                    fc = face.mean(axis=0)
                    u = np.cross(nrm, [1.0, 0, 0] if abs(nrm[0]) < 0.6 else [0, 1.0, 0])
                    u /= np.linalg.norm(u)
                    w = np.cross(nrm, u)
                    ang = np.arctan2((face - fc) @ w, (face - fc) @ u)
                    f = face[np.argsort(ang)]
                    area = 0.5 * np.sum(((f - fc) @ u) * np.roll((f - fc) @ w, -1) - np.roll((f - fc) @ u, -1) * ((f - fc) @ w))
                    vol += area * (d - nrm @ c) / 3
        vols.append(vol)
    return np.array(vols)


def clip(poly, axis, at, side):
    """Sutherland-Hodgman: the part of convex polygon poly (k, 2) with side * (x[axis] - at) >= 0."""
    out = []
    for a in range(len(poly)):
        p, q = poly[a], poly[(a + 1) % len(poly)]
        dp, dq = side * (p[axis] - at), side * (q[axis] - at)
        if dp >= 0:
            out.append(p)
        if (dp >= 0) != (dq >= 0):
            out.append(p + dp / (dp - dq) * (q - p))
    return np.array(out)


def area_centroid(p):
    x, y = p[:, 0], p[:, 1]
    cr = x * np.roll(y, -1) - np.roll(x, -1) * y
    a = cr.sum() / 2
    return a, np.array([((x + np.roll(x, -1)) * cr).sum(), ((y + np.roll(y, -1)) * cr).sum()]) / (6 * a)


def local_polygon(poly, Q):
    xy = np.stack([poly @ Q[0], poly @ Q[2]], axis=1)
    a, _ = area_centroid(xy)
    return xy if a > 0 else xy[::-1]


def polygon_centroid(poly, Q):
    xy = local_polygon(poly, Q)
    _, c = area_centroid(xy)
    return c[0] * Q[0] + c[1] * Q[2] + (poly[0] @ Q[1]) * Q[1]


def condensed_stiffness(poly, Q, m, mb, kn, kt):
    """K_G = sum_p A_p E_p^T C E_p over the m x m_b cells of the polygon's
    box in (t, b) (model.md), written here independently of blockwall."""
    xy = local_polygon(poly, Q)
    A, c = area_centroid(xy)
    xy = xy - c
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    C = np.diag([kt, kn, kt])
    kg = np.zeros((6, 6))
    for jb in range(mb):
        for it in range(m):
            x0 = lo[0] + (hi[0] - lo[0]) * it / m if it else lo[0] - 1
            x1 = lo[0] + (hi[0] - lo[0]) * (it + 1) / m if it + 1 < m else hi[0] + 1
            y0 = lo[1] + (hi[1] - lo[1]) * jb / mb if jb else lo[1] - 1
            y1 = lo[1] + (hi[1] - lo[1]) * (jb + 1) / mb if jb + 1 < mb else hi[1] + 1
            cell = xy
            for axis, at, side in ((0, x0, 1), (0, x1, -1), (1, y0, 1), (1, y1, -1)):
                if len(cell) < 3:
                    break
                cell = clip(cell, axis, at, side)
            if len(cell) < 3:
                continue
            a, (xi, eta) = area_centroid(cell)
            if not a > 1e-9 * A:
                continue
            Ep = np.array([[1, 0, 0, 0, eta, 0], [0, 1, 0, -eta, 0, xi], [0, 0, 1, 0, -xi, 0.0]])
            kg += a * Ep.T @ C @ Ep
    return kg


def reference_solve(res, scene_loads, density, m, mb, kn, kt):
    c, off = res["blocks/centroid"], res["interfaces/offsets"]
    nb = len(c)
    K = np.zeros((6 * nb, 6 * nb))
    for k, (i, j) in enumerate(res["interfaces/blocks"]):
        poly = res["interfaces/vertices"][off[k]:off[k + 1]]
        nrm = np.zeros(3)
        for a in range(len(poly)):  # Newell
            p, q = poly[a], poly[(a + 1) % len(poly)]
            nrm += np.array([(p[1] - q[1]) * (p[2] + q[2]), (p[2] - q[2]) * (p[0] + q[0]), (p[0] - q[0]) * (p[1] + q[1])])
        nrm /= np.linalg.norm(nrm)
        if nrm @ (c[j] - c[i]) < 0:
            nrm = -nrm
        Q = frame_rule(nrm)
        kg = condensed_stiffness(poly, Q, m, mb, kn, kt)
        G = polygon_centroid(poly, Q)
        R = np.zeros((6, 6))
        R[:3, :3] = R[3:, 3:] = Q
        Bm = np.zeros((6, 12))
        for side, blk, sign in ((0, i, -1), (1, j, 1)):
            P = np.eye(6)
            P[:3, 3:] = -cross_matrix(G - c[blk])
            Bm[:, 6 * side:6 * side + 6] = sign * P
        kk = (R @ Bm).T @ kg @ (R @ Bm)
        idx = np.r_[6 * i:6 * i + 6, 6 * j:6 * j + 6]
        K[np.ix_(idx, idx)] += kk
    F = np.zeros(6 * nb)
    vol = block_volumes(res)
    F[1::6] -= density * 9.81 * vol
    for name, load in scene_loads.items():
        for b in res[f"sets/{name}"]:
            F[6 * b:6 * b + 6] += load
    free = ~res["blocks/prescribed"].reshape(-1).astype(bool)
    q = np.zeros(6 * nb)
    q[free] = np.linalg.solve(K[np.ix_(free, free)], F[free])
    return q.reshape(nb, 6), vol


def check_groups(r, which, groups, dofs=""):
    """S^'s independent groups of dofs (/solver schur_groups): an assembly
    symmetric about a plane normal to X3 has no coupling between its
    in-plane and out-of-plane dofs and is solved as independent problems;
    one without that symmetry (the U's returns, the vault's ring joints)
    as one. The accuracy of the
    split answer is the closed form's or the numpy solver's check."""
    got = int(r["solver"]["schur_groups"])
    desc = r["solver"]["schur_group_dofs"]
    desc = desc.decode() if isinstance(desc, bytes) else str(desc)
    print(f"{which}: S^ in {got} independent group(s) {desc}")
    expect(got == groups and desc == dofs, f"{which}: S^ split into {got} groups ({desc!r}), expected {groups} ({dofs!r})")


def check_reference(scene_name, which, loads, density, E_mod, ranks):
    r = run_example(scene_name, which, ranks)
    kn, kt = E_mod / E_J, E_mod / (2 * (1 + NU) * E_J)
    q_ref, vol = reference_solve(r, loads, density, 8, 4, kn, kt)
    L = np.ptp(r["blocks/vertices"], axis=0).max()
    w = np.array([1, 1, 1, L, L, L])
    q = r["blocks/displacement"]
    err = np.max(np.abs((q - q_ref) * w)) / np.max(np.abs(q_ref * w))
    print(f"{which}: {len(q)} blocks, {len(r['interfaces/blocks'])} interfaces; displacements against the numpy solver {err:.1e} "
          f"(largest |u| {np.max(np.abs(q[:, :3])):.3e} m)")
    expect(err < 1e-8, f"{which}: displacements differ from the independent solver by {err:.2e}")
    e_w = np.max(np.abs(r["blocks/load"][:, 1] + density * 9.81 * vol - sum(np.isin(np.arange(len(vol)), r[f"sets/{n}"]) * l[1] for n, l in loads.items())))
    e_w /= np.max(np.abs(density * 9.81 * vol))
    print(f"{which}: self-weight against the volumes computed here {e_w:.1e}")
    expect(e_w < 1e-12, f"{which}: /blocks/load F2 is not -density g volume (+ set loads): {e_w:.2e}")
    check_groups(r, which, 1)
    return r


def box_contacts(res, e):
    """Pairs of boxes (blocks given as 8 vertices) with parallel faces e apart
    and a shared patch: the interfaces the construction has, with areas."""
    v, off = res["blocks/vertices"], res["blocks/offsets"]
    lo = np.array([v[off[b]:off[b + 1]].min(axis=0) for b in range(len(off) - 1)])
    hi = np.array([v[off[b]:off[b + 1]].max(axis=0) for b in range(len(off) - 1)])
    out = {}
    for i in range(len(lo)):
        for j in range(i + 1, len(lo)):
            for ax in range(3):
                gap = max(lo[j, ax] - hi[i, ax], lo[i, ax] - hi[j, ax])
                if abs(gap - e) > 1e-9:
                    continue
                others = [a for a in range(3) if a != ax]
                ext = [min(hi[i, a], hi[j, a]) - max(lo[i, a], lo[j, a]) for a in others]
                if min(ext) > 1e-9:
                    out[(i, j)] = ext[0] * ext[1]
    return out


def check_u_wall():
    r = check_reference("u_wall.yaml", "u_wall", {"top_facade": np.array([0, 0, -400, 0, 0, 0.0])}, 1800, E, 2)
    want = box_contacts(r, E_J)
    got = {tuple(p): a for p, a in zip(r["interfaces/blocks"].tolist(), r["interfaces/area"])}
    expect(set(got) == set(want), f"u_wall: detected pairs differ from the construction's: missing {sorted(set(want) - set(got))[:5]}, extra {sorted(set(got) - set(want))[:5]}")
    e_a = max(abs(got[p] - want[p]) / want[p] for p in want)
    print(f"u_wall: {len(want)} interfaces as the construction has them, areas {e_a:.1e}")
    expect(e_a < 1e-12, f"u_wall: interface areas differ from the construction's by {e_a:.2e}")


def check_vault():
    r = check_reference("vault.yaml", "vault", {"crown_mid": np.array([0, -20000, 0, 0, 0, 0.0])}, 2200, 0.5e9, 1)
    # 3 rings of 17 blocks: 16 radial joints in each ring, 17 between rings
    expect(len(r["interfaces/blocks"]) == 3 * 16 + 2 * 17, f"vault: {len(r['interfaces/blocks'])} interfaces, the construction has {3 * 16 + 2 * 17}")


if __name__ == "__main__":
    try:
        {"cantilever": check_cantilever, "u_wall": check_u_wall, "vault": check_vault}[sys.argv[1]]()
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
