#!/usr/bin/env python3
"""The 3D running-bond wall (examples/large_wall.yaml with
geometry.dimension: 3) in numpy/scipy + CHOLMOD: what a researcher would
write instead of blockwall for the same linear model (model.md, "Three
dimensions"), as wall_scipy.py is for 2D. It writes every dataset blockwall
writes for bench/large_wall3d.yaml (output.stresses: true, xdmf: false),
with blockwall's names, shapes, dtypes and values, so that a benchmark of
the two compares the same work.

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
   kt (db - phin xi)) unless --no-stresses, reactions; the script's own
   checks: |K q - F| / |F| and blockwall's equilibrium_error (the wrench of
   reactions + loads about the mean centroid, moments over the size).
5. write: blockwall's 3D output (docs/three-dimensions.md, "The 3D output"):

   /blocks/vertices (8B, 3)       the boxes: each block's bottom ring (x3 = 0),
                                  then its top ring (x3 = depth), counter-clockwise
   /blocks/offsets (B+1) int64, /blocks/centroid (B, 3), /blocks/prescribed (B, 6) int8
   /blocks/load, /blocks/displacement, /blocks/reaction (B, 6)
   /interfaces/blocks (I, 2) int64, /interfaces/center (I, 3), /interfaces/frame (I, 3, 3)
   /interfaces/area (I), /interfaces/kn, /interfaces/kt (I)
   /interfaces/vertices (4I, 3), /interfaces/offsets (I+1) int64: the rectangles,
                                  corners (xi, eta) = (-l/2, -s/2), (-l/2, s/2), (l/2, s/2), (l/2, -s/2)
   /interfaces/relative_displacement, /interfaces/resultant (I, 6)
   /interfaces/portion_offsets (I+1) int64, /portions/center (P, 2) (xi, eta),
   /portions/area (P), /portions/stress (P, 3)   (these four unless --no-stresses)
   /sets/{all,bottom_course,foundation,top_beam,top_course,units} int64
   root attributes units, dimension, m, m_b (and generator: this script)
   /solver attributes: analysis, ranks, unknowns_q, equilibrium_error, blas,
   memory_peak_bytes, seconds_{generate,assemble,setup,solve,recover,write,total}
   (setup the factorisation, solve the one triangular solve); and the script's
   own residual_stiffness |K q - F| / |F|.

   Before this version the script wrote only /blocks/{centroid,load,
   displacement,reaction}, /interfaces/{blocks,center,frame,
   relative_displacement,resultant,portion_offsets}, /portions/stress and
   root attributes dimension, m, m_b, residual, force_balance.

   Left out, each a blockwall-only notion (LEFT_OUT below, which
   check_against_blockwall.py --dim 3 reads; no dataset is left out):
   the root attributes version and scene (blockwall's version and its scene
   file as run: the script has neither), and the /solver attributes of
   blockwall's solver: method_requested, method_used, fallback,
   fallback_reason, iterations, setups, schur_solve, schur_groups,
   schur_group_dofs (its solver paths and Krylov iterations), rtol, residual,
   residual_equilibrium, residual_compatibility (the residual norms of the
   scaled mixed system; the script solves the condensed K q = F and writes
   residual_stiffness instead), forward_rtol, forward_error_estimate,
   condition_estimate, accuracy_met, warning (its accuracy machinery),
   unknowns_r (the stresses are unknowns of the mixed form only; the script
   eliminates them), partition_edge_cut, partition_imbalance,
   seconds_partition (the partition over MPI ranks: one process here).
   blockwall writes no /blocks/faces: its faces go only into /xdmf, which
   the benchmark's xdmf: false leaves out, and so does the script."""
import argparse
import json
import os
import resource
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

# What blockwall writes for bench/large_wall3d.yaml and this script does not, with why
# (check_against_blockwall.py --dim 3 accepts exactly these as missing; they are attributes only).
_SOLVER = "blockwall's solver diagnostic (paths, Krylov iterations, accuracy machinery), no counterpart in a CHOLMOD solve"
_MIXED = "a residual norm of blockwall's scaled mixed system; the script solves the condensed K q = F (its residual_stiffness)"
_RANKS = "blockwall's partition over MPI ranks; the script is one process"
LEFT_OUT = {
    "/:version": "blockwall's version",
    "/:scene": "blockwall's scene file as run; the script has command-line options only",
    **{"/solver:" + k: _SOLVER for k in ("method_requested", "method_used", "fallback", "fallback_reason", "iterations", "setups",
                                         "schur_solve", "schur_groups", "schur_group_dofs", "forward_rtol", "forward_error_estimate",
                                         "condition_estimate", "accuracy_met", "warning")},
    **{"/solver:" + k: _MIXED for k in ("rtol", "residual", "residual_equilibrium", "residual_compatibility")},
    "/solver:unknowns_r": "the stresses are unknowns of blockwall's mixed form only; the script eliminates them",
    **{"/solver:" + k: _RANKS for k in ("partition_edge_cut", "partition_imbalance", "seconds_partition")},
}


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
    load = [float(x) for x in a.load.split(",")]
    if len(load) != 6:
        ap.error("--load needs 6 numbers F1,F2,F3,M1,M2,M3, got %r" % a.load)
    a.load = np.array(load)
    return a


def cross_matrix(d):
    """[d]x for every row of d: (I, 3, 3)."""
    z = np.zeros(len(d))
    return np.stack([np.stack([z, -d[:, 2], d[:, 1]], 1), np.stack([d[:, 2], z, -d[:, 0]], 1),
                     np.stack([-d[:, 1], d[:, 0], z], 1)], 1)


def equilibrium_error(centroid, volume, load, reaction):
    """blockwall's /solver equilibrium_error (src/system/recover.c): |wrench of loads + reactions
    about the mean centroid| over the sum of the magnitudes of every block's contributions,
    moments divided by the assembly's size L (the centroids' box diagonal, at least block 0's
    cube root of volume)."""
    arm = centroid - centroid.mean(axis=0)
    L = max(np.linalg.norm(np.ptp(centroid, axis=0)), np.cbrt(volume[0]))
    w, scale = np.zeros(6), 0.0
    for F in (load, reaction):
        f = F[:, :3]
        w[:3] += f.sum(axis=0)
        w[3:] += (F[:, 3:] + np.cross(arm, f)).sum(axis=0) / L
        amom = np.column_stack((np.abs(arm[:, 1] * f[:, 2]) + np.abs(arm[:, 2] * f[:, 1]),
                                np.abs(arm[:, 2] * f[:, 0]) + np.abs(arm[:, 0] * f[:, 2]),
                                np.abs(arm[:, 0] * f[:, 1]) + np.abs(arm[:, 1] * f[:, 0])))
        scale += np.abs(f).sum() + (np.abs(F[:, 3:]) + amom).sum() / L
    return np.linalg.norm(w) / scale if scale > 0 else 0.0


def attr_string(obj, name, text):
    """A string attribute as blockwall writes it: fixed length, null-terminated, UTF-8."""
    data = text.encode()
    tid = h5py.h5t.C_S1.copy()
    tid.set_size(len(data) + 1)
    tid.set_strpad(h5py.h5t.STR_NULLTERM)
    tid.set_cset(h5py.h5t.CSET_UTF8)
    obj.attrs.create(name, np.array(data, dtype="S%d" % (len(data) + 1)), dtype=h5py.Datatype(tid))


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
    Q = np.zeros((ni, 3, 3))  # rows t, n, b
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
    t_setup = time.perf_counter() - t
    qf = factor(F)
    t_solve = time.perf_counter() - t - t_setup
    t = phase("factor+solve", t)

    q = np.zeros(6 * nb)
    q[free] = qf
    q = q.reshape(nb, 6)
    qij = np.concatenate((q[itf["i"]], q[itf["j"]]), axis=1)
    dG = np.einsum("kab,kb->ka", rb, qij)
    resultant = kg * dG
    stress = XI = ETA = None
    if not a.no_stresses:
        xi = lt[:, None] * ((np.arange(m) + 0.5) / m - 0.5)  # (I, m)
        eta = lb[:, None] * ((np.arange(mb) + 0.5) / mb - 0.5)  # (I, mb)
        XI = np.repeat(xi[:, None, :], mb, axis=1)  # (I, mb, m): t index fastest, as blockwall's portions
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
    balance = equilibrium_error(centroid, volume, load, reaction)
    t = phase("recover", t)

    blas = loaded_blas()
    if a.out:
        bx0, by0, bx1, by1 = blocks["x0"], blocks["y0"], blocks["x1"], blocks["y1"]
        ring = np.stack((np.column_stack((bx0, by0)), np.column_stack((bx1, by0)), np.column_stack((bx1, by1)),
                         np.column_stack((bx0, by1))), axis=1)  # (B, 4, 2), counter-clockwise
        vertices = np.empty((nb, 8, 3))
        vertices[:, :4, :2], vertices[:, 4:, :2] = ring, ring
        vertices[:, :4, 2], vertices[:, 4:, 2] = 0.0, s
        # the interface rectangles on the mid-plane, counter-clockwise about n (t x b = -n)
        h_, cxi, ceta = 0.5 * lt, np.array([-1.0, -1.0, 1.0, 1.0]), np.array([-0.5, 0.5, 0.5, -0.5]) * s
        poly = (G[:, None, :] + (h_[:, None] * cxi)[:, :, None] * Q[:, None, 0, :]) + ceta[None, :, None] * Q[:, None, 2, :]
        with h5py.File(a.out, "w") as h:
            attr_string(h, "units", "SI")
            h.attrs["dimension"] = np.int64(3)
            h.attrs["m"], h.attrs["m_b"] = np.int64(m), np.int64(mb)
            attr_string(h, "generator", "bench/scipy_reference/wall3d_scipy.py")
            h["/blocks/vertices"] = vertices.reshape(-1, 3)
            h["/blocks/offsets"] = np.arange(0, 8 * nb + 1, 8, dtype=np.int64)
            h["/blocks/centroid"] = centroid
            h["/blocks/prescribed"] = prescribed.astype(np.int8)
            h["/blocks/load"] = load
            h["/blocks/displacement"] = q
            h["/blocks/reaction"] = reaction
            h["/interfaces/blocks"] = np.column_stack((itf["i"], itf["j"])).astype(np.int64)
            h["/interfaces/center"] = G
            h["/interfaces/frame"] = Q
            h["/interfaces/area"] = A
            h["/interfaces/kn"] = np.full(ni, kn)
            h["/interfaces/kt"] = np.full(ni, kt)
            h["/interfaces/offsets"] = np.arange(0, 4 * ni + 1, 4, dtype=np.int64)
            h["/interfaces/vertices"] = poly.reshape(-1, 3)
            h["/interfaces/relative_displacement"] = dG
            h["/interfaces/resultant"] = resultant
            if stress is not None:
                h["/interfaces/portion_offsets"] = np.arange(0, m * mb * ni + 1, m * mb, dtype=np.int64)
                h["/portions/center"] = np.stack((XI, ETA), axis=-1).reshape(-1, 2)
                h["/portions/area"] = np.repeat(A / (m * mb), m * mb)
                h["/portions/stress"] = stress
            for name, members in sets.items():
                h["/sets/" + name] = members.astype(np.int64)
            g = h.create_group("solver")
            attr_string(g, "analysis", "linear")
            g.attrs["ranks"] = np.int64(1)
            g.attrs["unknowns_q"] = np.int64(nq)
            g.attrs["equilibrium_error"] = balance
            g.attrs["residual_stiffness"] = residual
            attr_string(g, "blas", ", ".join(blas))
            g.attrs["memory_peak_bytes"] = float(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss) * 1024.0
            seconds = dict(generate=times["generate"], assemble=times["assemble"], setup=t_setup, solve=t_solve,
                           recover=times["recover"], write=time.perf_counter() - t)
            for name, v in seconds.items():
                g.attrs["seconds_" + name] = v
            g.attrs["seconds_total"] = time.perf_counter() - t_start
        t = phase("write", t)
    else:
        times["write"] = 0.0
    times["total"] = time.perf_counter() - t_start
    print("%-13s %9.3f s" % ("total", times["total"]))
    print("blocks %d, interfaces %d, m %d, m_b %d, unknowns %d, nnz(K) %d, residual %.3e, equilibrium error %.3e"
          % (nb, ni, m, mb, nq, K.nnz, residual, balance))
    print("JSON " + json.dumps(dict(blocks=nb, interfaces=ni, unknowns=nq, nnz_K=int(K.nnz), residual=residual, equilibrium_error=balance,
                                    seconds={k: round(v, 4) for k, v in times.items()}, seconds_imports=round(T_IMPORT, 4),
                                    blas=blas)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
