#!/usr/bin/env python3
"""Run blockwall and wall_scipy.py (2D) or wall3d_scipy.py (3D, --dim 3) on the
same small running-bond walls and check that they agree.

    python3 bench/scipy_reference/check_against_blockwall.py [--dim 2|3] [--blockwall build/bin/blockwall]

For every wall both programs write an HDF5 file; the geometry datasets must be
identical (integers exactly, coordinates to 1e-12 relative) and every result
dataset must agree to TOL relative, measured per component (last axis: u1,
u2, w; T, N, M; shear, normal) as max|scipy - blockwall| / max|blockwall|,
so a rotation is compared with rotations and a moment with moments.
Both solve the same linear model, blockwall in the mixed form (q, r) and the
script through the condensed stiffness K = D^T G^-1 D, so the differences are
those of two solvers in floating point. Not part of ctest.

--dim 3 (bench/large_wall3d.yaml, output.stresses true, xdmf false) also
checks that the script writes everything blockwall writes: every dataset of
blockwall's file must be in the script's, with its shape and dtype (a missing
one is a failure naming it), and every attribute, except those the script
lists in wall3d_scipy.LEFT_OUT with a reason (attributes of blockwall's
solver only; a dataset can never be left out). Datasets: integers exactly,
other geometry (everything but the results) to 1e-12 of the dataset's largest
entry, results to TOL per component, rotations taken times the wall's size L
and moments over L, each component against its own largest value but never
against less than 1e-3 of the dataset's largest (flagged *): a small
component carries the error of the whole solve (both solvers' errors are
normwise), so measured against itself alone it reads the conditioning, not a
defect (w2, the twist about X2, is 1e-5 of the largest displacement on the
20 x 15 wall and differs by 1e-13 of the largest, 1e-8 of its own; M2 of the
foundation's reaction is zero up to round-off). Attributes: the
scene's (units, dimension, m, m_b) and analysis, ranks, unknowns_q equal;
equilibrium_error below 1e-10 in both; what each program measures of itself
(memory_peak_bytes, blas, seconds_*) present with the same type.
"""
import argparse
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
TOL = 1e-8  # relative, per component of each result dataset
GEOMETRY_TOL = 1e-12

# (name, courses, units, m, load on the top beam F1,F2,M3, density)
WALLS = [
    ("20x20 m16", 20, 20, 16, "1.0e5,-1.6e6,0", 0.0),
    ("1 course m16", 1, 6, 16, "5.0e4,-3.0e4,0", 0.0),
    ("9x5 m1", 9, 5, 1, "5.0e4,-3.0e4,0", 0.0),
    ("8x7 m2 self-weight", 8, 7, 2, "5.0e4,-3.0e4,2.0e3", 1800.0),
    ("15x1 m3 pier", 15, 1, 3, "2.0e3,-1.0e4,0", 1800.0),
]

GEOMETRY = ["blocks/vertices", "blocks/offsets", "blocks/centroid", "blocks/prescribed", "blocks/load",
            "interfaces/blocks", "interfaces/center", "interfaces/angle", "interfaces/length",
            "interfaces/kn", "interfaces/kt"]
RESULTS = ["blocks/displacement", "blocks/reaction", "interfaces/relative_displacement",
           "interfaces/resultant", "interfaces/stress"]


# 3D: (name, courses, units, m, m_b, load on the top beam F1,F2,F3,M1,M2,M3, density)
WALLS3D = [
    ("10x10 m8 mb4", 10, 10, 8, 4, "1.0e5,-1.6e6,2.0e3,0,0,0", 1800.0),
    ("20x15 m8 mb4", 20, 15, 8, 4, "1.0e5,-1.6e6,2.0e3,0,0,0", 1800.0),
    ("12x7 m4 mb2, moments on the beam", 12, 7, 4, 2, "5.0e4,-3.0e5,4.0e3,3.0e2,-2.0e2,5.0e2", 1800.0),
]
# result datasets, with the weights of their components: rotations times L, moments over L
RESULTS3D = {
    "blocks/displacement": lambda L: np.array([1, 1, 1, L, L, L]),
    "interfaces/relative_displacement": lambda L: np.array([1, 1, 1, L, L, L]),
    "blocks/reaction": lambda L: np.array([1, 1, 1, 1 / L, 1 / L, 1 / L]),
    "interfaces/resultant": lambda L: np.array([1, 1, 1, 1 / L, 1 / L, 1 / L]),
    "portions/stress": lambda L: np.array([1.0, 1.0, 1.0]),
}
SMALL = 1e-3  # a result component is measured against at least this of its dataset's largest
ATTR_EQUAL = {"/:units", "/:dimension", "/:m", "/:m_b", "/solver:analysis", "/solver:ranks", "/solver:unknowns_q"}
ATTR_SMALL = {"/solver:equilibrium_error": 1e-10}
ATTR_OWN = {"/solver:memory_peak_bytes", "/solver:blas"}  # and /solver:seconds_*: what each program measures of itself

def run(cmd, env=None):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)
    if p.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (p.returncode, " ".join(cmd), p.stdout))
    return p.stdout


def rel_per_component(x, y):
    """max over entries of |x - y| / max|y|, per component of the last axis."""
    x = x.reshape(-1, x.shape[-1]) if x.ndim > 1 else x.reshape(-1, 1)
    y = y.reshape(-1, y.shape[-1]) if y.ndim > 1 else y.reshape(-1, 1)
    scale = np.abs(y).max(axis=0)
    diff = np.abs(x - y).max(axis=0)
    return np.where(scale > 0, diff / np.where(scale > 0, scale, 1), diff)


def check2d(a, env, tmp):
    """The 2D walls (WALLS): geometry identical, results to TOL. Returns (passed, failed, worst)."""
    passed = failed = 0
    worst = 0.0
    for name, courses, units, m, load, density in WALLS:
        bw = os.path.join(tmp, "bw_%d_%d_%d.h5" % (courses, units, m))
        py = os.path.join(tmp, "py_%d_%d_%d.h5" % (courses, units, m))
        # the scene's joints (mortar E 0.82e9, nu 0.14, e 0.01), units 0.21 x 0.052, depth 0.1 are
        # wall_scipy.py's defaults; everything that differs is given to both
        run([a.blockwall, "-scene", a.scene,
             "-geometry_running_bond_courses", str(courses), "-geometry_running_bond_units_per_course", str(units),
             "-discretization_m", str(m), "-loads_top_beam", load, "-gravity_density", str(density),
             "-solver_method", a.method, "-output_file", bw, "-output_stresses", "true", "-output_xdmf", "false"],
            env=env)
        run([sys.executable, os.path.join(HERE, "wall_scipy.py"), "--courses", str(courses), "--units", str(units),
             "--m", str(m), "--load", load, "--density", str(density), "--out", py])
        ok = True
        with h5py.File(bw, "r") as fb, h5py.File(py, "r") as fp:
            method = fb["solver"].attrs["method_used"].decode()
            print("%s: %d blocks, %d interfaces, blockwall method %s, residual %.1e"
                  % (name, fb["blocks/offsets"].shape[0] - 1, fb["interfaces/blocks"].shape[0], method,
                     fb["solver"].attrs["residual"]))
            for key in GEOMETRY:
                x, y = fp[key][()], fb[key][()]
                if x.shape != y.shape:
                    print("  FAIL %s: shape %s vs blockwall %s" % (key, x.shape, y.shape))
                    ok = False
                    continue
                if np.issubdtype(y.dtype, np.integer):
                    good = np.array_equal(x, y)
                else:
                    good = np.abs(x - y).max() <= GEOMETRY_TOL * max(np.abs(y).max(), 1.0)
                if not good:
                    print("  FAIL %s differs" % key)
                    ok = False
            for s in fb["sets"]:
                if s not in fp["sets"] or not np.array_equal(fp["sets"][s][()], fb["sets"][s][()]):
                    print("  FAIL set %s differs" % s)
                    ok = False
            for key in RESULTS:
                x, y = fp[key][()], fb[key][()]
                if x.shape != y.shape:
                    print("  FAIL %s: shape %s vs blockwall %s" % (key, x.shape, y.shape))
                    ok = False
                    continue
                r = rel_per_component(x, y)
                worst = max(worst, r.max())
                bad = r.max() > TOL
                ok &= not bad
                print("  %-4s %-34s %s" % ("FAIL" if bad else "ok", key, "  ".join("%.1e" % v for v in r)))
        if ok:
            passed += 1
        else:
            failed += 1
    return passed, failed, worst


def rel_weighted(x, y, w):
    """Per component of the last axis: max|x - y| / max|y| with every component c taken times
    w[c], the scale never below SMALL of the dataset's largest (those components flagged).
    Returns (rel, flagged)."""
    X = x.reshape(-1, x.shape[-1]) * w
    Y = y.reshape(-1, y.shape[-1]) * w
    own = np.abs(Y).max(axis=0)
    big = own.max()
    flagged = own < SMALL * big
    scale = np.where(flagged, SMALL * big, own)
    diff = np.abs(X - Y).max(axis=0)
    return np.where(scale > 0, diff / np.where(scale > 0, scale, 1), diff), flagged


def attributes(f):
    """Every attribute of the file as "path:name" -> value (root "/")."""
    out = {"/:" + k: v for k, v in f.attrs.items()}

    def visit(name, obj):
        for k, v in obj.attrs.items():
            out["/%s:%s" % (name, k)] = v
    f.visititems(visit)
    return out


def datasets(f):
    out = []
    f.visititems(lambda name, obj: out.append(name) if isinstance(obj, h5py.Dataset) else None)
    return out


def kind(v):
    """int, float or str, as the attribute was stored."""
    v = np.asarray(v)
    if v.dtype.kind in "SUO":
        return "str"
    return "int" if np.issubdtype(v.dtype, np.integer) else "float"


def compare3d(bw, py, left_out):
    """Everything of blockwall's file bw against the script's py: printed; returns (ok, worst)."""
    ok, worst = True, 0.0
    with h5py.File(bw, "r") as fb, h5py.File(py, "r") as fp:
        L = float(np.ptp(fb["blocks/vertices"][()], axis=0).max())
        method = "/".join(filter(None, (fb["solver"].attrs[k].decode() for k in ("method_used", "schur_solve"))))
        print("  %d blocks, %d interfaces, %d portions, blockwall method %s, residual %.1e, L = %.2f m"
              % (fb["blocks/offsets"].shape[0] - 1, fb["interfaces/blocks"].shape[0], fb["portions/stress"].shape[0],
                 method, fb["solver"].attrs["residual"], L))
        names = datasets(fb)
        exact = close = 0
        gworst = 0.0
        for key in names:
            if key not in fp:
                print("  FAIL missing dataset /%s" % key)
                ok = False
                continue
            x, y = fp[key][()], fb[key][()]
            if x.shape != y.shape or x.dtype != y.dtype:
                print("  FAIL /%s: %s %s, blockwall %s %s" % (key, x.shape, x.dtype, y.shape, y.dtype))
                ok = False
                continue
            if key in RESULTS3D:
                r, flagged = rel_weighted(x, y, RESULTS3D[key](L))
                worst = max(worst, r.max())
                bad = r.max() > TOL
                ok &= not bad
                print("  %-4s %-34s %s" % ("FAIL" if bad else "ok", "/" + key,
                                           "  ".join("%.1e%s" % (v, "*" if f else "") for v, f in zip(r, flagged))))
            elif np.issubdtype(y.dtype, np.integer):
                if not np.array_equal(x, y):
                    print("  FAIL /%s: integers differ at %d entries" % (key, int((x != y).sum())))
                    ok = False
                exact += 1
            else:
                scale = np.abs(y).max()
                d = np.abs(x - y).max() / (scale if scale > 0 else 1.0)
                gworst = max(gworst, d)
                if not d <= GEOMETRY_TOL:
                    print("  FAIL /%s: differs by %.1e of its largest entry (tolerance %.0e)" % (key, d, GEOMETRY_TOL))
                    ok = False
                close += 1
        extra = sorted(set(datasets(fp)) - set(names))
        print("  datasets: %d in blockwall's file: %d integer (exact), %d other geometry (largest difference %.1e of the dataset's"
              " largest), %d results; %d more in the script's: %s"
              % (len(names), exact, close, gworst, len(RESULTS3D), len(extra), ", ".join(extra) or "none"))
        ab, ap = attributes(fb), attributes(fp)
        skipped = []
        for key, v in sorted(ab.items()):
            if key in left_out:
                skipped.append(key)
                continue
            if key not in ap:
                print("  FAIL missing attribute %s" % key)
                ok = False
                continue
            w = ap[key]
            if kind(v) != kind(w):
                print("  FAIL attribute %s: %s, blockwall %s" % (key, kind(w), kind(v)))
                ok = False
            elif key in ATTR_EQUAL:
                if not np.array_equal(np.asarray(v), np.asarray(w)):
                    print("  FAIL attribute %s: %r, blockwall %r" % (key, w, v))
                    ok = False
            elif key in ATTR_SMALL:
                if not (0 <= v <= ATTR_SMALL[key] and 0 <= w <= ATTR_SMALL[key]):
                    print("  FAIL attribute %s: %.1e, blockwall %.1e (both must be in [0, %.0e])" % (key, w, v, ATTR_SMALL[key]))
                    ok = False
                else:
                    print("  ok   attribute %s: %.1e, blockwall %.1e" % (key, w, v))
            elif key in ATTR_OWN or key.startswith("/solver:seconds_"):
                if not (len(w) > 0 if kind(w) == "str" else np.isfinite(w) and w >= 0):
                    print("  FAIL attribute %s: %r" % (key, w))
                    ok = False
            else:
                print("  FAIL attribute %s of blockwall is neither compared here nor left out by the script" % key)
                ok = False
        print("  attributes: %d in blockwall's file, %d left out by the script (wall3d_scipy.LEFT_OUT)" % (len(ab), len(skipped)))
    return ok, worst


def check3d(a, env, tmp):
    """The 3D walls (WALLS3D): everything blockwall writes, in the script's file. Returns (passed, failed, worst)."""
    sys.path.insert(0, HERE)
    from wall3d_scipy import LEFT_OUT
    bad = [k for k in LEFT_OUT if not (k.startswith("/:") or k.startswith("/solver:"))]
    if bad:
        sys.exit("wall3d_scipy.LEFT_OUT may name root and /solver attributes only, not %s" % ", ".join(bad))
    passed = failed = 0
    worst = 0.0
    for name, courses, units, m, mb, load, density in WALLS3D:
        bw = os.path.join(tmp, "bw3_%d_%d_%d_%d.h5" % (courses, units, m, mb))
        py = os.path.join(tmp, "py3_%d_%d_%d_%d.h5" % (courses, units, m, mb))
        # the scene's joints, unit sizes and depth are wall3d_scipy.py's defaults; everything that differs is given to both
        run([a.blockwall, "-scene", a.scene,
             "-geometry_running_bond_courses", str(courses), "-geometry_running_bond_units_per_course", str(units),
             "-discretization_m", str(m), "-discretization_m_b", str(mb), "-loads_top_beam", load,
             "-gravity_density", str(density), "-solver_method", a.method, "-output_file", bw,
             "-output_stresses", "true", "-output_xdmf", "false"], env=env)
        run([sys.executable, os.path.join(HERE, "wall3d_scipy.py"), "--courses", str(courses), "--units", str(units),
             "--m", str(m), "--mb", str(mb), "--load", load, "--density", str(density), "--out", py])
        print("%s:" % name)
        ok, w = compare3d(bw, py, LEFT_OUT)
        worst = max(worst, w)
        passed, failed = passed + ok, failed + (not ok)
    print("left out by the script, with its reasons:")
    for key, why in LEFT_OUT.items():
        print("  %s: %s" % (key, why))
    return passed, failed, worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--dim", type=int, choices=(2, 3), default=2)
    ap.add_argument("--blockwall", default=os.path.join(ROOT, "build", "bin", "blockwall"))
    ap.add_argument("--scene", default=None, help="default examples/large_wall.yaml (2D), bench/large_wall3d.yaml (3D)")
    ap.add_argument("--method", default="auto", help="blockwall's -solver_method (auto | fieldsplit | direct)")
    ap.add_argument("--keep", action="store_true", help="keep the HDF5 files")
    a = ap.parse_args()
    if a.scene is None:
        a.scene = os.path.join(ROOT, "examples", "large_wall.yaml") if a.dim == 2 else os.path.join(ROOT, "bench", "large_wall3d.yaml")
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    tmp = tempfile.mkdtemp(prefix="scipyref_")
    passed, failed, worst = (check2d if a.dim == 2 else check3d)(a, env, tmp)
    if not a.keep:
        for f in os.listdir(tmp):
            os.remove(os.path.join(tmp, f))
        os.rmdir(tmp)
    else:
        print("files kept in", tmp)
    print("largest relative difference %.2e (tolerance %.0e)" % (worst, TOL))
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
