"""The round-off part of the forward estimate where the mixed system is too
large to assemble (3D walls above 1e6 rows of K~; src/solver/estimates.c):
the bound through the factor of S^ (-solver_forward_bound schur) against the
same bound with K~ assembled (whole), and the estimate from one residual in
double-double (extra, auto's choice), on bench/large_wall3d.yaml
at 40 x 40 units (1 622 blocks, out-of-plane bending: S^'s condition ~1e8),
the condition estimated and the bound added in every run, solver.method
fieldsplit (the bounds exceed forward_rtol 1e-10 on this wall, and auto would
then try the direct path too):

  agree    the two bound the same quantity, LAPACK's FERR || W |K~^-1|
           (|r| + gamma |K~| |x| + |b|) ||_inf, with two differences: schur
           counts each row's own roundings, 18 for a stress row, ~80 for a
           unit's row, where the whole one takes LAPACK's count of the
           longest row for every row (the top beam's, 40 units x 96 stress
           terms: ~3 900), so it may be smaller by up to ~3 900 / 18; and it
           bounds |E_p W_k| by |E_p| |W_k| (larger; measured up to 2x on
           such walls, on 100 x 100 units 3.5e-9 against 6.0e-9). So
           between 1/250 and 10 times the whole one.
  ranks    on 3 ranks the schur bound is within a factor 2 of 1 rank's (the
           estimator's maximum is found along another partition's order; the
           quantity is the same).
Each compares the round-off part a run reports (-info), not /solver
forward_error_estimate, the larger of it and the refinement's last
correction, which the round-off of another BLAS or partition moves (2.1e-11
against 3.6e-11 on 1 and 3 ranks with the reference BLAS).
  honest   both at least the displacements' change when D^ is applied by
           another arithmetic (assembled, -solver_storage nest: other
           products and sums, other roundings): a sample of the error the
           bound bounds.
  extra    the extra-precise estimate (10 x the error S~^-1 r shows, r in
           double-double) between that sample of the error and the schur
           bound, a worst case (on this axis-parallel wall most products
           are by 0 or +-1 and exact, so far below it); on 3 ranks within
           10x of 1 rank's (the error itself, which another partition's
           round-off changes).
  auto     the default takes the extra-precise estimate: on 60 x 60 units
           (3 632 blocks, 1.04e6 rows of K~) equal to the forced one.
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import Failure, expect, read, run  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
SCENE = os.path.join(ROOT, "bench", "large_wall3d.yaml")


PARTS = {"whole": r"round-off bound from the factor ([0-9.eE+-]+)",
         "schur": r"round-off bound through the factor of S\^ ([0-9.eE+-]+)",
         "extra": r"round-off estimate from a residual in double-double ([0-9.eE+-]+)"}


def solve(tmp, name, n, how=None, extra=(), ranks=1):
    """The run's displacements and the round-off part it added to its
    forward estimate (from -info: the attribute is the larger of it and
    the refinement's own estimate, which the round-off of a BLAS or a
    partition moves)."""
    out = os.path.join(tmp, f"{name}.h5")
    _, stdout, _ = run(SCENE, ["-geometry_running_bond_courses", n, "-geometry_running_bond_units_per_course", n,
                               "-output_stresses", "false", "-output_xdmf", "false", "-solver_condition_estimate", "always",
                               "-solver_method", "fieldsplit", "-info", ":ksp", "-output_file", out,
                               *(["-solver_forward_bound", how] if how else []), *extra], ranks)
    m = re.search(PARTS[how or "extra"], stdout)
    expect(m is not None, f"{name}: no round-off part reported ({how or 'auto'})")
    return read(out), float(m.group(1))


def main():
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        whole, fw = solve(tmp, "whole", 40, "whole")
        schur, fs = solve(tmp, "schur", 40, "schur")
        _, fs3 = solve(tmp, "schur3", 40, "schur", ranks=3)
        _, fe = solve(tmp, "extra", 40, "extra")
        _, fe3 = solve(tmp, "extra3", 40, "extra", ranks=3)
        nest, _ = solve(tmp, "nest", 40, "whole", ["-solver_storage", "nest"])
        _, fa = solve(tmp, "auto60", 60)
        _, fe60 = solve(tmp, "extra60", 60, "extra")
    v = whole["blocks/vertices"]
    w = np.array([1, 1, 1, *[float(np.linalg.norm(v.max(axis=0) - v.min(axis=0)))] * 3])
    q, qn = schur["blocks/displacement"] * w, nest["blocks/displacement"] * w
    spread = float(np.max(np.abs(q - qn)) / np.max(np.abs(q)))
    print(f"40 x 40: bound whole {fw:.2e}, schur {fs:.2e} (ratio {fs / fw:.2f}), schur on 3 ranks {fs3:.2e}; "
          f"displacements with D^ assembled against by its structure {spread:.1e}")
    print(f"40 x 40: extra-precise estimate {fe:.2e}, on 3 ranks {fe3:.2e}")
    print(f"60 x 60: auto {fa:.2e}, extra {fe60:.2e}")
    expect(fw > 0 and fs > 0, f"no bound: whole {fw}, schur {fs}")
    expect(1 / 250 <= fs / fw <= 10, f"the schur bound {fs:.2e} against the whole one {fw:.2e}: not in [1/250, 10]")
    expect(0.5 <= fs3 / fs <= 2, f"the schur bound on 3 ranks {fs3:.2e} against 1 rank's {fs:.2e}")
    expect(spread <= min(fs, fw), f"the arithmetic moved the displacements by {spread:.1e}, above a bound ({fs:.1e}, {fw:.1e})")
    expect(spread <= fe <= fs, f"the extra-precise estimate {fe:.2e} is not between the sample {spread:.1e} and the bound {fs:.2e}")
    expect(0.1 <= fe3 / fe <= 10, f"the extra-precise estimate on 3 ranks {fe3:.2e} against 1 rank's {fe:.2e}")
    expect(fa == fe60, f"60 x 60: auto's round-off part {fa:.3e} is not the extra-precise one {fe60:.3e}")


if __name__ == "__main__":
    try:
        main()
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
