"""Limit analysis of a 3D block assembly by the static theorem, independent
of blockwall's solver: the largest load factor lambda for which the blocks
are in equilibrium under F0 + lambda P with interface stresses that every
portion's strength admits (no tension beyond ft, the Coulomb cone
|tau| <= c - rn tan(phi)). For associative joints (psi = phi, perfectly
plastic) that lambda is the collapse multiplier of the discrete model, the
limit a pushover approaches from below as the joints stiffen.

The unknowns are the stresses (rt, rn, rb) of the same portions as
blockwall's (read from a result file written with output.stresses: the
interfaces' frames and centres, the portions' centroids and areas): each
portion's traction acts at its centroid with force A_p (rt t + rn n + rb b)
on the interface's first block and the opposite on the second (model.md,
"Three dimensions"). Equilibrium of every block (forces and moments about
its centroid, from the convex hull of its vertices: scipy's ConvexHull,
not blockwall's) on its free dofs; prescribed dofs take any reaction.

The circular cone is not linear: it is replaced by the pyramid of K faces
circumscribed about it (a relaxation: an upper bound on the cone's lambda)
and by the one inscribed in it (a restriction: a lower bound). The two
linear programmes (scipy's HiGHS) bracket the second-order-cone answer to
a relative width of about 1 - cos(pi/K).

    python3 -m blockwall.limit RESULT.h5 --direction 0 0 -1 --density 1800 --friction 0.6
"""
import argparse
import math

import numpy as np


def _hulls(vertices, offsets):
    from scipy.spatial import ConvexHull
    vol, cen = [], []
    for b in range(len(offsets) - 1):
        h = ConvexHull(vertices[offsets[b]:offsets[b + 1]])
        # the centroid of the solid: tetrahedra from an interior point to every facet
        pts, o = h.points, h.points.mean(axis=0)
        v, c = 0.0, np.zeros(3)
        for s in h.simplices:
            a, bb, cc = pts[s]
            tv = abs(np.dot(a - o, np.cross(bb - o, cc - o))) / 6
            v += tv
            c += tv * (o + a + bb + cc) / 4
        vol.append(v)
        cen.append(c / v)
    return np.array(vol), np.array(cen)


def read_assembly(path):
    """What the limit analysis needs from a 3D blockwall result file."""
    import h5py
    with h5py.File(path, "r") as f:
        if int(f.attrs.get("dimension", 2)) != 3:
            raise ValueError(f"{path}: not a 3D result")
        if "portions/center" not in f:
            raise ValueError(f"{path}: no /portions (run with output.stresses: true)")
        a = {k: f[k][()] for k in ("blocks/vertices", "blocks/offsets", "blocks/prescribed", "interfaces/blocks",
                                   "interfaces/center", "interfaces/frame", "interfaces/portion_offsets",
                                   "portions/center", "portions/area")}
        a["sets"] = {k: f["sets"][k][()] for k in f["sets"]}
    a["volume"], a["centroid"] = _hulls(a["blocks/vertices"], a["blocks/offsets"])
    return a


def collapse_multiplier(a, F0, P, ft=0.0, c=0.0, tanphi=0.6, K=64, inscribed=False, method="highs-ipm"):
    """The largest lambda of the static theorem for the assembly `a`
    (read_assembly), constant loads F0 and pattern P ((B, 6) arrays: F1, F2,
    F3, M1, M2, M3 at the blocks' centroids), with the friction cone replaced
    by the pyramid of K faces inscribed in it (or circumscribed about it).
    Returns (lambda, the stresses (P, 3) of the optimum); (nan, None) when F0
    alone has no admissible equilibrium, (inf, None) when lambda is unbounded.

    Each portion's stress is the cone's apex r0 = (0, c/tan(phi), 0) plus a
    non-negative combination of the pyramid's K edges
    g_k = (R cos(th_k), -1, R sin(th_k)), R = tan(phi) (inscribed) or
    tan(phi)/cos(pi/K) (circumscribed): the strength is then the bounds
    mu >= 0, and the programme has only the blocks' equilibrium rows (6 per
    free block), which HiGHS solves in seconds where the
    cone's K inequalities per portion took it minutes. A tension cut-off
    below the apex (ft < c/tan(phi)) adds its rows rn <= ft."""
    from scipy.optimize import linprog
    from scipy.sparse import coo_matrix, csr_matrix, diags, hstack

    pairs, G, frame = a["interfaces/blocks"], a["interfaces/center"], a["interfaces/frame"]
    off, pc, pa = a["interfaces/portion_offsets"], a["portions/center"], a["portions/area"]
    cen, pres = a["centroid"], a["blocks/prescribed"].astype(bool)
    nb, npor = len(cen), len(pa)
    if not tanphi > 0:
        raise ValueError("the pyramid needs tan(phi) > 0")
    k_of = np.repeat(np.arange(len(pairs)), np.diff(off))
    t, n, b = frame[k_of, 0], frame[k_of, 1], frame[k_of, 2]
    x = G[k_of] + pc[:, :1] * t + pc[:, 1:] * b
    free = ~pres.reshape(-1)
    renum = -np.ones(6 * nb, int)
    renum[free] = np.arange(free.sum())
    nrow = int(free.sum())

    def equilibrium(vec):
        """Rows of the free dofs for a stress vec (P, 3 in local t, n, b) of
        every portion: the forces and moments on both blocks, as a sparse
        (nrow, P) matrix."""
        rows, cols, vals = [], [], []
        f = pa[:, None] * (vec[:, :1] * t + vec[:, 1:2] * n + vec[:, 2:] * b)
        for side, sign in ((0, 1.0), (1, -1.0)):
            blk = pairs[k_of, side]
            mom = np.cross(x - cen[blk], sign * f)
            for d in range(3):
                for r, v in ((6 * blk + d, sign * f[:, d]), (6 * blk + 3 + d, mom[:, d])):
                    keep = free[r]
                    rows.append(renum[r[keep]]), cols.append(np.arange(npor)[keep]), vals.append(v[keep])
        return coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(nrow, npor)).tocsr()

    R = tanphi if inscribed else tanphi / math.cos(math.pi / K)
    cols = []
    for k in range(K):
        th = 2 * math.pi * k / K
        cols.append(equilibrium(np.tile([R * math.cos(th), -1.0, R * math.sin(th)], (npor, 1))))
    apex = np.tile([0.0, c / tanphi, 0.0], (npor, 1))
    beq = -F0.reshape(-1)[free] - equilibrium(apex) @ np.ones(npor)
    Pcol = csr_matrix(P.reshape(-1)[free][:, None])
    Aeq = hstack(cols + [Pcol]).tocsr()
    nvar = K * npor + 1
    cost = np.zeros(nvar)
    cost[-1] = -1.0
    bounds = [(0, None)] * (K * npor) + [(None, None)]
    Aub = bub = None
    if ft < c / tanphi:
        # rn = c/tan(phi) - sum_k mu_k <= ft
        rr = np.repeat(np.arange(npor)[None], K, axis=0).reshape(-1)
        cc = np.arange(K * npor)
        Aub = coo_matrix((-np.ones(K * npor), (rr, cc)), shape=(npor, nvar)).tocsr()
        bub = np.full(npor, ft - c / tanphi)
    # Equilibrated: each column (a stress in Pa, lambda) and then each row (a
    # force in N, a moment in N m) scaled to unit length. Unscaled, HiGHS's
    # answers for the U-wall's pyramids (K = 16) lay 1e-6 apart from one
    # method to the other; equilibrated, its simplex and its interior point
    # (with crossover: a vertex) agree to 6e-9, and the interior point took
    # 7 s a pyramid where the simplex took 12-14 s.
    col = np.sqrt(np.asarray(Aeq.multiply(Aeq).sum(axis=0))).ravel()
    col[col == 0] = 1.0
    Aeq = Aeq @ diags(1.0 / col)
    row = np.sqrt(np.asarray(Aeq.multiply(Aeq).sum(axis=1))).ravel()
    row[row == 0] = 1.0
    Aeq = diags(1.0 / row) @ Aeq
    if Aub is not None:
        Aub = Aub @ diags(1.0 / col)
    res = linprog(cost / col, A_ub=Aub, b_ub=bub, A_eq=Aeq, b_eq=beq / row, bounds=bounds, method=method)
    if res.status == 2:
        return float("nan"), None
    if res.status == 3:
        return float("inf"), None
    if res.status != 0:
        raise RuntimeError(f"linprog: {res.message}")
    x = res.x / col
    mu = x[:-1].reshape(K, npor)
    th = 2 * math.pi * np.arange(K) / K
    stress = np.column_stack([R * (np.cos(th) @ mu), c / tanphi - mu.sum(axis=0), R * (np.sin(th) @ mu)])
    return float(x[-1]), stress


def gravity_loads(a, density, direction):
    """F0 = the weight (-density g V on F2) and P = the weight times `direction`
    (the tilting table's pattern), per block at its centroid."""
    w = density * 9.81 * a["volume"]
    F0 = np.zeros((len(w), 6))
    F0[:, 1] = -w
    P = np.zeros((len(w), 6))
    P[:, :3] = w[:, None] * np.asarray(direction, float)[None]
    return F0, P


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("result", help="a 3D blockwall result written with output.stresses: true (its portions)")
    ap.add_argument("--direction", type=float, nargs=3, default=(0, 0, 1), help="the body force's direction (a1 a2 a3)")
    ap.add_argument("--density", type=float, required=True)
    ap.add_argument("--friction", type=float, required=True, help="tan(phi)")
    ap.add_argument("--cohesion", type=float, default=0.0)
    ap.add_argument("--tension", type=float, default=0.0)
    ap.add_argument("--faces", type=int, default=64, help="K, the faces of the polygons that bracket the cone")
    args = ap.parse_args(argv)
    a = read_assembly(args.result)
    F0, P = gravity_loads(a, args.density, args.direction)
    kw = dict(ft=args.tension, c=args.cohesion, tanphi=args.friction, K=args.faces)
    lo, _ = collapse_multiplier(a, F0, P, inscribed=True, **kw)
    hi, _ = collapse_multiplier(a, F0, P, inscribed=False, **kw)
    print(f"collapse multiplier between {lo:.6g} (inscribed {args.faces}-gon) and {hi:.6g} (circumscribed)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
