#!/usr/bin/env python3
"""The 3D running-bond wall (examples/large_wall.yaml with
geometry.dimension: 3) in numpy/scipy + CHOLMOD: what a researcher would
write instead of blockwall for the same linear model (model.md, "Three
dimensions"), as wall_scipy.py is for 2D.

    python3 bench/scipy_reference/wall3d_scipy.py --courses 316 --units 316 --m 8 --mb 4 --out w.h5

1. generate: wall_scipy.running_bond's blocks and interfaces (blockwall's
   order), extruded along X3 over [0, depth]: centroids at depth/2, every
   interface the l x depth rectangle with t = (cos, sin, 0), n = (-sin,
   cos, 0), b = X3.
2. assemble: per interface K_G = diag(kt A, kn A, kt A, kn I_b (1 - 1/m_b^2),
   kt (I_t (1 - 1/m^2) + I_b (1 - 1/m_b^2)), kn I_t (1 - 1/m^2)) (the
   discrete stiffness of the m x m_b portions of a rectangle, exact), the
   12 x 12 (R B)^T K_G (R B) by einsum, the foundation's dofs dropped, COO
   to CSC. Loads: --load (6 numbers) on the top beam, self-weight on F2.
3. factor+solve: sksparse.cholmod.cholesky(K), one solve.
4. recover: dG = R B q, resultants K_G dG, per-portion stresses
   (rt, rn, rb) = (kt (dt + phin eta), kn (dn + phib xi - phit eta),
   kt (db - phin xi)) unless --no-stresses, reactions, residual and balance.
5. write: blockwall's 3D dataset names (/blocks/displacement (B, 6),
   /interfaces/resultant (I, 6), /portions/stress (P, 3) with
   /interfaces/portion_offsets)."""
import argparse
import json
import os
import sys
import time

T0 = time.perf_counter()
import h5py  # noqa: E402
import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402
from sksparse.cholmod import cholesky  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from wall_scipy import loaded_blas, running_bond  # noqa: E402

T_IMPORT = time.perf_counter() - T0
GRAVITY = 9.81


def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--courses", type=int, default=316)
    ap.add_argument("--units", type=int, default=316)
    ap.add_argument("--m", type=int, default=8)
    ap.add_argument("--mb", type=int, default=4)
    ap.add_argument("--unit-length", type=float, default=0.21)
    ap.add_argument("--unit-height", type=float, default=0.052)
    ap.add_argument("--foundation-height", type=float, default=0.1)
    ap.add_argument("--top-beam-height", type=float, default=0.1)
    ap.add_argument("--depth", type=float, default=0.1)
    ap.add_argument("--E", type=float, default=0.82e9)
    ap.add_argument("--nu", type=float, default=0.14)
    ap.add_argument("--thickness", type=float, default=0.01)
    ap.add_argument("--load", default="1.0e5,-1.6e6,2.0e3,0,0,0", help="F1,F2,F3,M1,M2,M3 on the top beam")
    ap.add_argument("--density", type=float, default=1800.0)
    ap.add_argument("--out", default=None)
    ap.add_argument("--no-stresses", action="store_true")
    a = ap.parse_args(argv)
    a.load = np.array([float(x) for x in a.load.split(",")])
    return a


def cross_matrix(d):
    """[d]x for every row of d: (I, 3, 3)."""
    z = np.zeros(len(d))
    return np.stack([np.stack([z, -d[:, 2], d[:, 1]], 1), np.stack([d[:, 2], z, -d[:, 0]], 1),
                     np.stack([-d[:, 1], d[:, 0], z], 1)], 1)


def main(argv=None):
    a = parse_args(argv)
    times = {}
    t_start = time.perf_counter()

    def phase(name, t0):
        times[name] = time.perf_counter() - t0
        print("%-13s %9.3f s" % (name, times[name]), flush=True)
        return time.perf_counter()

    t = time.perf_counter()
    e, s, m, mb = a.thickness, a.depth, a.m, a.mb
    blocks, itf, sets = running_bond(a.courses, a.units, a.unit_length, a.unit_height, e, a.foundation_height, a.top_beam_height)
    nb, ni = len(blocks["x0"]), len(itf["i"])
    centroid = np.column_stack((0.5 * (blocks["x0"] + blocks["x1"]), 0.5 * (blocks["y0"] + blocks["y1"]), np.full(nb, s / 2)))
    volume = (blocks["x1"] - blocks["x0"]) * (blocks["y1"] - blocks["y0"]) * s
    th = itf["angle"]
    Q = np.zeros((ni, 3, 3))
    Q[:, 0, 0], Q[:, 0, 1] = np.cos(th), np.sin(th)
    Q[:, 1, 0], Q[:, 1, 1] = -np.sin(th), np.cos(th)
    Q[:, 2, 2] = 1.0
    G = np.column_stack((itf["G"], np.full(ni, s / 2)))
    t = phase("generate", t)

    kn, kt = a.E / e, a.E / (2 * (1 + a.nu) * e)
    lt, lb = itf["length"], np.full(ni, s)
    A, It, Ib = lt * lb, lb * lt**3 / 12, lt * lb**3 / 12
    kg = np.column_stack((kt * A, kn * A, kt * A, kn * Ib * (1 - 1 / mb**2), kt * (It * (1 - 1 / m**2) + Ib * (1 - 1 / mb**2)),
                          kn * It * (1 - 1 / m**2)))
    # R B: (I, 6, 12), R = diag(Q, Q), B = [-P_i, P_j], P = [[I, -[G - c]x], [0, I]]
    rb = np.zeros((ni, 6, 12))
    for side, blk, sign in ((0, itf["i"], -1.0), (6, itf["j"], 1.0)):
        X = cross_matrix(G - centroid[blk])
        rb[:, :3, side:side + 3] = sign * Q
        rb[:, :3, side + 3:side + 6] = sign * -np.einsum("kab,kbc->kac", Q, X)
        rb[:, 3:, side + 3:side + 6] = sign * Q
    ke = np.einsum("kai,ka,kaj->kij", rb, kg, rb)
    prescribed = np.zeros((nb, 6), dtype=bool)
    prescribed[sets["foundation"]] = True
    free = ~prescribed.ravel()
    dof = np.full(6 * nb, -1)
    dof[free] = np.arange(free.sum())
    nq = int(free.sum())
    edofs = np.concatenate((6 * itf["i"][:, None] + np.arange(6), 6 * itf["j"][:, None] + np.arange(6)), axis=1)
    eq = dof[edofs]
    rows = np.repeat(eq, 12, axis=1).ravel()
    cols = np.tile(eq, (1, 12)).ravel()
    keep = (rows >= 0) & (cols >= 0)
    K = sp.coo_matrix((ke.ravel()[keep], (rows[keep], cols[keep])), shape=(nq, nq)).tocsc()
    del rows, cols, keep, ke
    load = np.zeros((nb, 6))
    load[sets["top_beam"]] += a.load
    load[:, 1] -= a.density * GRAVITY * volume
    F = load.ravel()[free]
    t = phase("assemble", t)

    factor = cholesky(K)
    qf = factor(F)
    t = phase("factor+solve", t)

    q = np.zeros(6 * nb)
    q[free] = qf
    q = q.reshape(nb, 6)
    qij = np.concatenate((q[itf["i"]], q[itf["j"]]), axis=1)
    dG = np.einsum("kab,kb->ka", rb, qij)
    resultant = kg * dG
    stress = None
    if not a.no_stresses:
        xi = lt[:, None] * ((np.arange(m) + 0.5) / m - 0.5)  # (I, m)
        eta = lb[:, None] * ((np.arange(mb) + 0.5) / mb - 0.5)  # (I, mb)
        XI = np.repeat(xi[:, None, :], mb, axis=1)  # (I, mb, m): t index fastest
        ETA = np.repeat(eta[:, :, None], m, axis=2)
        d = dG[:, :, None, None]
        stress = np.stack([kt * (d[:, 0] + d[:, 4] * ETA), kn * (d[:, 1] + d[:, 5] * XI - d[:, 3] * ETA),
                           kt * (d[:, 2] - d[:, 4] * XI)], axis=-1).reshape(-1, 3)
    fblk = np.einsum("kab,ka->kb", rb, resultant)
    internal = np.zeros((nb, 6))
    for c in range(6):
        internal[:, c] = np.bincount(itf["i"], fblk[:, c], minlength=nb) + np.bincount(itf["j"], fblk[:, 6 + c], minlength=nb)
    reaction = np.where(prescribed, internal - load, 0.0)
    residual = np.linalg.norm(K @ qf - F) / np.linalg.norm(F)
    sum_load = load[:, :3].sum(axis=0)
    balance = np.linalg.norm(reaction[:, :3].sum(axis=0) + sum_load) / max(np.linalg.norm(sum_load), 1e-300)
    t = phase("recover", t)

    if a.out:
        with h5py.File(a.out, "w") as h:
            h.attrs["dimension"] = 3
            h.attrs["m"], h.attrs["m_b"] = m, mb
            h["/blocks/centroid"] = centroid
            h["/blocks/load"] = load
            h["/blocks/displacement"] = q
            h["/blocks/reaction"] = reaction
            h["/interfaces/blocks"] = np.column_stack((itf["i"], itf["j"])).astype(np.int64)
            h["/interfaces/center"] = G
            h["/interfaces/frame"] = Q
            h["/interfaces/relative_displacement"] = dG
            h["/interfaces/resultant"] = resultant
            if stress is not None:
                h["/interfaces/portion_offsets"] = np.arange(0, m * mb * ni + 1, m * mb, dtype=np.int64)
                h["/portions/stress"] = stress
            h.attrs["residual"], h.attrs["force_balance"] = residual, balance
        t = phase("write", t)
    else:
        times["write"] = 0.0
    times["total"] = time.perf_counter() - t_start
    print("%-13s %9.3f s" % ("total", times["total"]))
    print("blocks %d, interfaces %d, m %d, m_b %d, unknowns %d, nnz(K) %d, residual %.3e, force balance %.3e"
          % (nb, ni, m, mb, nq, K.nnz, residual, balance))
    print("JSON " + json.dumps(dict(blocks=nb, interfaces=ni, unknowns=nq, nnz_K=int(K.nnz), residual=residual, force_balance=balance,
                                    seconds={k: round(v, 4) for k, v in times.items()}, seconds_imports=round(T_IMPORT, 4),
                                    blas=loaded_blas())))
    return 0


if __name__ == "__main__":
    sys.exit(main())
