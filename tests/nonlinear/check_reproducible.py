"""A pushover repeats itself bit for bit on several ranks with
solver.reproducible (-solver_reproducible): the cracking wall of
check_wall_past_peak.py (412 blocks, dissipation control well past its
peak; its first 75 steps), run twice on R ranks.

Why a test: a parallel factorisation is not the same from one run to the
next (of 10 factorisations of one matrix by MUMPS on 2 ranks, 9 gave
answers up to 4e-13 apart from the first's; SuperLU_DIST on 3, 5 of 6), and
past the peak such round-off chooses among the paths of the portions that
swap: this wall on 2 ranks with MUMPS, six runs, one 1.6e-6 apart from the
others, and of nine later runs none bit for bit with the first of its three
(docs/solvers.md). With the option every factorisation is a sequential one
of the whole matrix on each rank (PCREDUNDANT), which repeats itself, and
the rest of this run did.

Bit for bit is asserted of one machine against itself, not across
machines: it takes a sequential factorisation and a BLAS that do the same
sums in the same order at every run, as they did here with OpenBLAS and
with the reference BLAS (both passes of tools/test). Across CPUs and BLAS
only round-off agreement holds, which other tests check
(nonlinear.same_curve_*, wall_past_peak_2).

What is checked, against what (the first run is the reference, nothing
else is assumed):
  - the second run's /history (load factor, monitor, residual, Newton
    iterations per step, dissipation) and its last state's displacements,
    stresses and portion states are equal bit for bit to the first's;
  - the run went past its peak (at least 30 steps after the largest load
    factor), where the paths can part;
  - /solver schur_solve names the factorisation it used and the answer
    met its tolerance (accuracy_met).

usage: check_reproducible.py R
"""
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from bwrun import Failure, expect, run  # noqa: E402

sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))
import blockwall as bw  # noqa: E402

from check_wall_past_peak import SCENE  # noqa: E402


def once(tmp, ranks, k):
    scene = os.path.join(tmp, "wall.yaml")
    with open(scene, "w") as f:
        # 75 of the scene's 100 steps, at its step size: the peak at step 40
        # and 35 steps past it, where the paths part (the same iterations
        # per step as the first 75 of 100, loads within 5e-10 of them)
        text = SCENE.replace("steps: all", "steps: last").replace("stresses: false", "stresses: true")
        expect("target: 4.0e-3, steps: 100}" in text, "the wall's pushover line changed: adjust the 75 steps")
        f.write(text.replace("target: 4.0e-3, steps: 100}", "target: 3.0e-3, steps: 75}"))
    out = os.path.join(tmp, f"run{k}.h5")
    run(scene, ["-output_file", out, "-progress", "false", "-solver_reproducible"], ranks)
    return bw.read(out)


def main(ranks):
    with tempfile.TemporaryDirectory() as tmp:
        a, b = once(tmp, ranks, 0), once(tmp, ranks, 1)
    lam = np.asarray(a.history["load_factor"])
    k = int(np.argmax(lam))
    past = len(lam) - 1 - k
    expect(past >= 30, f"only {past} steps after the peak (step {k} of {len(lam) - 1}): not past the point where paths part")
    for key in ("load_factor", "monitor", "residual", "iterations", "dissipation"):
        x, y = np.asarray(a.history[key]), np.asarray(b.history[key])
        expect(x.shape == y.shape, f"/history/{key}: {x.shape} against {y.shape} in the second run")
        if not np.array_equal(x, y):
            i = int(np.nonzero(x != y)[0][0])
            raise Failure(f"/history/{key} differs from step {i} on: {x[i]!r} against {y[i]!r} in the second run")
    la, lb = a.steps[max(a.steps)], b.steps[max(b.steps)]
    expect(np.array_equal(la.displacement, lb.displacement), "the last state's displacements differ between the two runs")
    expect(la.stress is not None and lb.stress is not None, "no stresses written in the last step (output.stresses: true)")
    expect(np.array_equal(la.stress, lb.stress), "the last state's stresses differ between the two runs")
    expect(np.array_equal(la.state, lb.state), "the last state's portion states differ between the two runs")
    for r in (a, b):
        expect(r.solver["accuracy_met"] == 1, "accuracy_met is not 1")
        expect(r.solver["schur_solve"] in ("lu", "cholesky"), f"schur_solve {r.solver['schur_solve']!r}: not a factorisation")
    print(f"{ranks} ranks, two runs: {len(lam) - 1} steps, peak {lam[k] / 1e3:.3f} kN at step {k}, {past} steps past it, "
          f"{a.solver['newton_iterations']} Newton iterations, last lambda {lam[-1]!r}: bit for bit the same")


if __name__ == "__main__":
    try:
        main(int(sys.argv[1]))
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
