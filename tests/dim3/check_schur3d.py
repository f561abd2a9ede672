"""The iterative 3D Schur solve (CG + GAMG with the long blocks eliminated,
src/solver/amg.c) against the factored one (S^ by Cholesky), on a thin
running-bond wall whose top beam touches all 40 units of its top course
(tests/dim3/schur3d.yaml), loaded in its plane and out of it, on RANKS
ranks. Both runs use solver.method fieldsplit, so that neither can fall
back to the other.

  in   the top beam pushed along and down its plane: the displacements agree
       to 1e-8 of the largest (rotations times the wall's size);
  out  the top beam pushed across the plane (the wall bends as a plate,
       S^'s conditioning is the worse one): they agree to 10 x the sum of
       the two answers' own forward-error estimates (/solver
       forward_error_estimate: the factored one is the factor's round-off
       bound with S^'s condition estimate, 1e6 here, ~7e-12; the iterative
       one its refinement's last correction): if each answer is within its
       estimate of the exact one, they are within the sum of each other; 10
       for the norms (the estimates' max norm against the 1-norm condition).

Each also checks that the iterative run ran as meant: no fallback,
schur_solve gamg, accuracy_met 1, true residual <= solver.rtol, and the
beam eliminated (its six solves for Z reported, -schur_long_ksp_*).

usage: check_schur3d.py in|out [RANKS]
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import Failure, expect, read, run  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "schur3d.yaml")
LOADS = {"in": "1.0e4,-1.0e5,0,0,0,0", "out": "0,0,2.0e3,0,0,0"}
TOL_IN = 1e-8
RTOL = 1e-10


def solve(schur, load, ranks, tmp, extra=()):
    out = os.path.join(tmp, f"{schur}.h5")
    _, stdout, _ = run(SCENE, ["-loads_top_beam", LOADS[load], "-solver_method", "fieldsplit", "-solver_schur", schur,
                               "-solver_rtol", str(RTOL), "-solver_condition_estimate", "always", "-output_file", out, *extra], ranks)
    return read(out), stdout


def main():
    import tempfile
    load, ranks = sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 1
    with tempfile.TemporaryDirectory() as tmp:
        fact, _ = solve("cholesky", load, ranks, tmp)
        it, stdout = solve("gamg", load, ranks, tmp, ["-schur_long_ksp_converged_reason"])
    s = it["solver"]
    expect(s["method_used"] == "fieldsplit" and s["schur_solve"] == "gamg" and int(s["fallback"]) == 0,
           f"the iterative run used {s['method_used']} / {s['schur_solve']} (fallback {s['fallback']})")
    expect(int(s["accuracy_met"]) == 1 and float(s["residual"]) <= RTOL,
           f"the iterative run: accuracy_met {s['accuracy_met']}, true residual {float(s['residual']):.2e} (rtol {RTOL:g})")
    zsolves = re.findall(r"Linear schur_long_ solve converged", stdout)
    expect(len(zsolves) == 6, f"the top beam was not eliminated: {len(zsolves)} solves for Z reported, not 6")
    expect(fact["solver"]["schur_solve"] == "cholesky", f"the factored run used {fact['solver']['schur_solve']}")
    v = fact["blocks/vertices"]
    L = float(np.linalg.norm(v.max(axis=0) - v.min(axis=0)))
    w = np.array([1, 1, 1, L, L, L])
    qf, qi = fact["blocks/displacement"] * w, it["blocks/displacement"] * w
    diff = float(np.max(np.abs(qi - qf)) / np.max(np.abs(qf)))
    if load == "in":
        tol = TOL_IN
        # nothing out of the plane: the two dof groups of S^ are independent
        expect(np.max(np.abs(qi[:, 2:5])) <= 1e-12 * np.max(np.abs(qf)), "the in-plane load moved the wall out of its plane")
    else:
        fe_f, fe_i = float(fact["solver"]["forward_error_estimate"]), float(s["forward_error_estimate"])
        expect(fe_f > 0 and fe_i >= 0, f"forward-error estimates missing: factored {fe_f}, iterative {fe_i}")
        tol = 10 * (fe_f + fe_i)
        print(f"condition estimate of S^ {float(fact['solver']['condition_estimate']):.2e}; forward-error estimates: "
              f"factored {fe_f:.2e}, iterative {fe_i:.2e}; tolerance {tol:.2e}")
    print(f"{load}, {ranks} rank(s): iterative against factored {diff:.2e} (tolerance {tol:.1e})")
    expect(diff <= tol, f"the iterative and factored displacements differ by {diff:.2e} > {tol:.1e}")


if __name__ == "__main__":
    try:
        main()
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
