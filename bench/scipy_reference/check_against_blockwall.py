#!/usr/bin/env python3
"""Run blockwall and wall_scipy.py on the same small running-bond walls and
check that they agree.

    python3 bench/scipy_reference/check_against_blockwall.py [--blockwall build/bin/blockwall]

For every wall both programs write an HDF5 file; the geometry datasets must be
identical (integers exactly, coordinates to 1e-12 relative) and every result
dataset must agree to TOL relative, measured per component (last axis: u1,
u2, w; T, N, M; shear, normal) as max|scipy - blockwall| / max|blockwall|,
so a rotation is compared with rotations and a moment with moments.
Both solve the same linear model, blockwall in the mixed form (q, r) and the
script through the condensed stiffness K = D^T G^-1 D, so the differences are
those of two solvers in floating point. Not part of ctest.
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


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--blockwall", default=os.path.join(ROOT, "build", "bin", "blockwall"))
    ap.add_argument("--scene", default=os.path.join(ROOT, "examples", "large_wall.yaml"))
    ap.add_argument("--method", default="auto", help="blockwall's -solver_method (auto | fieldsplit | direct)")
    ap.add_argument("--keep", action="store_true", help="keep the HDF5 files")
    a = ap.parse_args()
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    tmp = tempfile.mkdtemp(prefix="scipyref_")
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
