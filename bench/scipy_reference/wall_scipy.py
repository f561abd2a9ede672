#!/usr/bin/env python3
"""A running-bond masonry wall of rigid blocks and elastic mortar joints,
solved with numpy/scipy and CHOLMOD (scikit-sparse): the script a masonry
researcher would write instead of using blockwall, kept as the yardstick for
blockwall's speed.

The model is blockwall's (shared spec model.md): 3 dofs (u1, u2, w) per block
at its centroid, interfaces cut into m portions of uniform stress. Since the
compliance G of the mixed form is diagonal, eliminating the stresses is exact
and leaves the classical stiffness system K q = F with

    K = sum_k (R B)_k^T diag(kt A, kn A, kn I (1 - 1/m^2)) (R B)_k,

3 unknowns per block. The stresses follow from q afterwards:
rt_p = kt dt, rn_p = kn (dn + x_p phi).

The geometry, block order and interface order are those of blockwall's
running_bond generator (interface.md), so both outputs compare entry by
entry. Only what the benchmark needs is here: integer units_per_course,
foundation and top beam, one mortar law for every joint, the foundation
fixed, loads on the top beam and optional self-weight.

    python3 wall_scipy.py --courses 316 --units 316 --m 16 --out /tmp/wall.h5

prints one line per phase (generate, assemble, factor+solve, recover, write,
total) and a last line starting with "JSON " holding the same numbers.
"""
import time

T_IMPORT = time.perf_counter()
import argparse
import json
import os
import sys

import h5py
import numpy as np
import scipy.sparse as sp
from sksparse.cholmod import cholesky

T_IMPORT = time.perf_counter() - T_IMPORT  # seconds to import numpy, scipy, h5py, sksparse

GRAVITY = 9.81  # m/s^2, as blockwall


# --------------------------------------------------------------------------
# 1. geometry
# --------------------------------------------------------------------------
def overlaps(x0a, x1a, x0b, x1b, tol):
    """Pairs (a, b) of two rows of sorted, disjoint intervals that overlap by
    more than tol, with the x-centre and length of each overlap."""
    # for each lower interval a: the upper intervals b with x1b > x0a and x0b < x1a
    lo = np.searchsorted(x1b, x0a, side="right")
    hi = np.searchsorted(x0b, x1a, side="left")
    count = np.maximum(hi - lo, 0)
    a = np.repeat(np.arange(len(x0a)), count)
    b = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count) + np.repeat(lo, count)
    x0 = np.maximum(x0a[a], x0b[b])
    x1 = np.minimum(x1a[a], x1b[b])
    keep = x1 - x0 > tol
    return a[keep], b[keep], 0.5 * (x0 + x1)[keep], (x1 - x0)[keep]


def running_bond(courses, n, lu, hu, e, hf, hb):
    """Blocks (rectangles x0, y0, x1, y1) and interfaces (i, j, G, angle,
    length), in blockwall's order."""
    L = n * lu + (n - 1) * e
    half = 0.5 * (lu - e)
    tol = 1e-9 * lu

    # x-extents of the two kinds of course
    p = np.arange(n)
    even_x0 = p * (lu + e)
    even_x1 = even_x0 + lu
    q = np.arange(1, n)
    odd_x0 = np.concatenate(([0.0], half + e + (q - 1) * (lu + e), [L - half]))
    odd_x1 = np.concatenate(([half], half + e + (q - 1) * (lu + e) + lu, [L]))

    # rows bottom to top: foundation, courses, top beam
    rows = [(np.array([0.0]), np.array([L]), -e - hf, -e)]
    for k in range(courses):
        y0 = k * (hu + e)
        if k % 2 == 0:
            rows.append((even_x0, even_x1, y0, y0 + hu))
        else:
            rows.append((odd_x0, odd_x1, y0, y0 + hu))
    ytop = (courses - 1) * (hu + e) + hu
    rows.append((np.array([0.0]), np.array([L]), ytop + e, ytop + e + hb))

    sizes = np.array([len(r[0]) for r in rows])
    first = np.concatenate(([0], np.cumsum(sizes)[:-1]))
    nblocks = int(sizes.sum())
    x0 = np.concatenate([r[0] for r in rows])
    x1 = np.concatenate([r[1] for r in rows])
    y0 = np.repeat([r[2] for r in rows], sizes)
    y1 = np.repeat([r[3] for r in rows], sizes)

    ii, jj, gx, gy, ang, length = [], [], [], [], [], []
    # head joints: neighbours within a course (rows 1..courses)
    rowid = np.repeat(np.arange(len(rows)), sizes)
    b = np.arange(nblocks - 1)
    head = (rowid[b] == rowid[b + 1]) & (rowid[b] >= 1) & (rowid[b] <= courses)
    head &= np.abs(x0[b + 1] - x1[b] - e) <= tol
    b = b[head]
    ii.append(b)
    jj.append(b + 1)
    gx.append(x1[b] + 0.5 * e)
    gy.append(0.5 * (y0[b] + y1[b]))
    ang.append(np.full(len(b), -0.5 * np.pi))
    length.append(np.full(len(b), hu))
    # bed joints: overlaps of each row with the row above
    for r in range(len(rows) - 1):
        lo, up = rows[r], rows[r + 1]
        a, c, xc, ln = overlaps(lo[0], lo[1], up[0], up[1], tol)
        ii.append(first[r] + a)
        jj.append(first[r + 1] + c)
        gx.append(xc)
        gy.append(np.full(len(a), 0.5 * (lo[3] + up[2])))
        ang.append(np.zeros(len(a)))
        length.append(ln)
    ii, jj, gx, gy, ang, length = (np.concatenate(v) for v in (ii, jj, gx, gy, ang, length))
    order = np.lexsort((gx, jj, ii))  # by i, then j, then G's x

    blocks = dict(x0=x0, y0=y0, x1=x1, y1=y1)
    interfaces = dict(i=ii[order], j=jj[order], G=np.column_stack((gx, gy))[order],
                      angle=ang[order], length=length[order])
    sets = dict(foundation=np.array([0]), top_beam=np.array([nblocks - 1]),
                bottom_course=np.arange(first[1], first[1] + sizes[1]),
                top_course=np.arange(first[courses], first[courses] + sizes[courses]),
                units=np.arange(1, nblocks - 1), all=np.arange(nblocks))
    return blocks, interfaces, sets


def compatibility(centroid, itf):
    """R B of every interface, (I, 3, 6): (dt, dn, phi) at G per unit dof of
    blocks i (columns 0-2) and j (columns 3-5)."""
    th = itf["angle"]
    t1, t2 = np.cos(th), np.sin(th)
    n1, n2 = -np.sin(th), np.cos(th)
    G = itf["G"]
    rb = np.zeros((len(th), 3, 6))
    for side, blk, sign in ((0, itf["i"], -1.0), (3, itf["j"], 1.0)):
        d = G - centroid[blk]  # lever arm G - c
        # R P_b with P_b = [[1,0,-d2],[0,1,d1],[0,0,1]]
        rb[:, 0, side + 0] = sign * t1
        rb[:, 0, side + 1] = sign * t2
        rb[:, 0, side + 2] = sign * (-t1 * d[:, 1] + t2 * d[:, 0])
        rb[:, 1, side + 0] = sign * n1
        rb[:, 1, side + 1] = sign * n2
        rb[:, 1, side + 2] = sign * (-n1 * d[:, 1] + n2 * d[:, 0])
        rb[:, 2, side + 2] = sign
    return rb


def loaded_blas():
    """The BLAS/LAPACK shared libraries this process has mapped (Linux): CHOLMOD's
    come through libblas.so.3 / liblapack.so.3; numpy's and scipy's wheels bring
    their own (scipy_openblas)."""
    libs = set()
    try:
        with open("/proc/self/maps") as f:
            for line in f:
                path = line.split()[-1]
                name = os.path.basename(path)
                if path.startswith("/") and ("blas" in name or "lapack" in name):
                    libs.add(os.path.realpath(path))
    except OSError:
        pass
    return sorted(libs)


# --------------------------------------------------------------------------
# driver
# --------------------------------------------------------------------------
def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--courses", type=int, default=400)
    ap.add_argument("--units", type=int, default=250, help="full units per course (integer)")
    ap.add_argument("--m", type=int, default=16, help="portions per interface")
    ap.add_argument("--unit-length", type=float, default=0.21)
    ap.add_argument("--unit-height", type=float, default=0.052)
    ap.add_argument("--foundation-height", type=float, default=0.1)
    ap.add_argument("--top-beam-height", type=float, default=0.1)
    ap.add_argument("--depth", type=float, default=0.1)
    ap.add_argument("--E", type=float, default=0.82e9, help="mortar Young's modulus [Pa]")
    ap.add_argument("--nu", type=float, default=0.14, help="mortar Poisson's ratio")
    ap.add_argument("--thickness", type=float, default=0.01, help="joint thickness e [m]")
    ap.add_argument("--load", default="1.0e5,-1.6e6,0", help="F1,F2,M3 on the top beam [N, N, N m]")
    ap.add_argument("--density", type=float, default=0.0, help="self-weight density [kg/m^3]")
    ap.add_argument("--out", default=None, help="HDF5 output file (none: no write phase)")
    ap.add_argument("--no-stresses", action="store_true", help="skip the per-portion stresses")
    a = ap.parse_args(argv)
    load = [float(v) for v in a.load.split(",")]
    if len(load) != 3:
        ap.error("--load needs 3 numbers F1,F2,M3, got %r" % a.load)
    a.load = np.array(load)
    if a.courses < 1 or a.units < 1 or a.m < 1:
        ap.error("--courses, --units and --m must be >= 1")
    if not (a.E > 0 and -1 < a.nu < 0.5 and a.thickness > 0):
        ap.error("need E > 0, -1 < nu < 0.5, thickness > 0")
    if not a.unit_length > a.thickness:
        ap.error("--unit-length must exceed --thickness")
    return a


def main(argv=None):
    a = parse_args(argv)
    times = {}
    print("%-13s %9.3f s (not in total)" % ("imports", T_IMPORT), flush=True)
    t_start = time.perf_counter()

    def phase(name, t0):
        times[name] = time.perf_counter() - t0
        print("%-13s %9.3f s" % (name, times[name]), flush=True)
        return time.perf_counter()

    # 1. generate --------------------------------------------------------
    t = time.perf_counter()
    e, s, m = a.thickness, a.depth, a.m
    blocks, itf, sets = running_bond(a.courses, a.units, a.unit_length, a.unit_height, e,
                                     a.foundation_height, a.top_beam_height)
    nb, ni = len(blocks["x0"]), len(itf["i"])
    centroid = np.column_stack((0.5 * (blocks["x0"] + blocks["x1"]), 0.5 * (blocks["y0"] + blocks["y1"])))
    area = (blocks["x1"] - blocks["x0"]) * (blocks["y1"] - blocks["y0"])
    t = phase("generate", t)

    # 2. assemble --------------------------------------------------------
    kn = a.E / e
    kt = a.E / (2 * (1 + a.nu) * e)
    l = itf["length"]
    A = s * l
    I = s * l**3 / 12
    kg = np.column_stack((np.full(ni, kt) * A, kn * A, kn * I * (1 - 1 / m**2)))  # (I, 3)
    rb = compatibility(centroid, itf)
    ke = np.einsum("kai,ka,kaj->kij", rb, kg, rb)  # (I, 6, 6) interface stiffness

    prescribed = np.zeros((nb, 3), dtype=bool)
    prescribed[sets["foundation"]] = True  # supports: foundation u1 = u2 = w = 0
    free = ~prescribed.ravel()
    dof = np.full(3 * nb, -1)
    dof[free] = np.arange(free.sum())  # full dof -> equation number, -1 if prescribed
    nq = int(free.sum())

    edofs = np.column_stack((3 * itf["i"], 3 * itf["i"] + 1, 3 * itf["i"] + 2,
                             3 * itf["j"], 3 * itf["j"] + 1, 3 * itf["j"] + 2))
    eq = dof[edofs]  # (I, 6)
    rows = np.repeat(eq, 6, axis=1).ravel()
    cols = np.tile(eq, (1, 6)).ravel()
    keep = (rows >= 0) & (cols >= 0)
    K = sp.coo_matrix((ke.ravel()[keep], (rows[keep], cols[keep])), shape=(nq, nq)).tocsc()
    del rows, cols, keep, ke

    load = np.zeros((nb, 3))
    load[sets["top_beam"]] += a.load
    load[:, 1] -= a.density * GRAVITY * area * s
    F = load.ravel()[free]
    t = phase("assemble", t)

    # 3. factor + solve --------------------------------------------------
    factor = cholesky(K)
    qf = factor(F)
    t = phase("factor+solve", t)

    # 4. recover ---------------------------------------------------------
    q = np.zeros(3 * nb)  # prescribed values are all 0
    q[free] = qf
    q = q.reshape(nb, 3)
    qij = np.concatenate((q[itf["i"]], q[itf["j"]]), axis=1)  # (I, 6)
    dG = np.einsum("kab,kb->ka", rb, qij)  # dt, dn, phi at G
    resultant = kg * dG  # T, N, M = diag(kt A, kn A, kn I (1-1/m^2)) dG
    stress = None
    if not a.no_stresses:
        xp = l[:, None] * ((np.arange(1, m + 1) - 0.5) / m - 0.5)  # (I, m) portion midpoints
        stress = np.empty((ni, m, 2))
        stress[:, :, 0] = kt * dG[:, 0:1]
        stress[:, :, 1] = kn * (dG[:, 1:2] + xp * dG[:, 2:3])
    # interface forces on the blocks D^T r = sum (R B)^T (T, N, M); reactions D^T r - F
    fblk = np.einsum("kab,ka->kb", rb, resultant)  # (I, 6)
    internal = np.zeros((nb, 3))
    for c in range(3):
        internal[:, c] = (np.bincount(itf["i"], fblk[:, c], minlength=nb)
                          + np.bincount(itf["j"], fblk[:, 3 + c], minlength=nb))
    reaction = np.where(prescribed, internal - load, 0.0)
    # self-checks: residual of K q = F, and the balance of applied forces and reactions
    residual = np.linalg.norm(K @ qf - F) / np.linalg.norm(F)
    sum_load = load[:, :2].sum(axis=0)
    balance = np.linalg.norm(reaction[:, :2].sum(axis=0) + sum_load) / max(np.linalg.norm(sum_load), 1e-300)
    t = phase("recover", t)

    # 5. write -----------------------------------------------------------
    if a.out:
        bx0, by0, bx1, by1 = blocks["x0"], blocks["y0"], blocks["x1"], blocks["y1"]
        vertices = np.stack((np.column_stack((bx0, by0)), np.column_stack((bx1, by0)),
                             np.column_stack((bx1, by1)), np.column_stack((bx0, by1))), axis=1).reshape(-1, 2)
        with h5py.File(a.out, "w") as h:
            h.attrs["units"] = "SI"
            h.attrs["m"] = m
            h.attrs["depth"] = s
            h.attrs["generator"] = "bench/scipy_reference/wall_scipy.py"
            h["/blocks/vertices"] = vertices
            h["/blocks/offsets"] = np.arange(0, 4 * nb + 1, 4, dtype=np.int64)
            h["/blocks/centroid"] = centroid
            h["/blocks/prescribed"] = prescribed.astype(np.int8)
            h["/blocks/load"] = load
            h["/blocks/displacement"] = q
            h["/blocks/reaction"] = reaction
            h["/interfaces/blocks"] = np.column_stack((itf["i"], itf["j"])).astype(np.int64)
            h["/interfaces/center"] = itf["G"]
            h["/interfaces/angle"] = itf["angle"]
            h["/interfaces/length"] = l
            h["/interfaces/kn"] = np.full(ni, kn)
            h["/interfaces/kt"] = np.full(ni, kt)
            h["/interfaces/relative_displacement"] = dG
            h["/interfaces/resultant"] = resultant
            if stress is not None:
                h["/interfaces/stress"] = stress
            for name, members in sets.items():
                h["/sets/" + name] = members.astype(np.int64)
            h.attrs["residual"] = residual
            h.attrs["force_balance"] = balance
        t = phase("write", t)
    else:
        times["write"] = 0.0
    times["total"] = time.perf_counter() - t_start
    print("%-13s %9.3f s" % ("total", times["total"]))
    print("blocks %d, interfaces %d, m %d, unknowns %d, nnz(K) %d, residual %.3e, force balance %.3e"
          % (nb, ni, m, nq, K.nnz, residual, balance))
    blas = loaded_blas()
    print("BLAS/LAPACK loaded: " + ", ".join(blas))
    print("JSON " + json.dumps(dict(blocks=nb, interfaces=ni, m=m, unknowns=nq, nnz_K=int(K.nnz),
                                    residual=residual, force_balance=balance,
                                    seconds={k: round(v, 4) for k, v in times.items()},
                                    seconds_imports=round(T_IMPORT, 4), blas=blas)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
