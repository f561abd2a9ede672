"""A cracking wall followed past its peak under dissipation control (issue
20, "Past the peak"): the scaled-down version of bench/pushover.py's 1e4-
block wall, 20 courses of 20 units (412 blocks, 4.39 m long) with J4D's
joints (ft 0.25 MPa, c 0.35 MPa, tan(phi) 0.75, GfI 18, GfII 125 J/m^2),
0.30 MPa held on the top beam, the top beam pushed sideways (kept
horizontal), control: dissipation, at most 100 steps, on R ranks.

What is checked, against what:
  - it is followed past its peak: at least 30 converged steps after the
    largest lambda and the last lambda below 0.8 of it (displacement control
    on this wall needs 40-iteration cut-backs at its peak; the capability is
    what issue 20 asks of the 1e4-block wall, bench/pushover.py);
  - every written step (output.steps: all) is a converged equilibrium, by
    two invariants that do not trust the Newton loop: /history/residual
    (the relative true residual of the full mixed system, recomputed on the
    committed state) below the tolerance 1e-8, and the balance of the
    reactions against the loads in each written step, sum over blocks of
    (reaction + load) = 0 for both forces and the moment about the origin
    (the joints' forces cancel pairwise: what is left is the equilibrium
    error of the free dofs), to 1e-9 of the loads; /solver
    equilibrium_error of the last state below 1e-10;
  - the energy: /history/dissipation never decreases by more than round-off
    (plastic work is >= 0) and the last value equals /solver
    dissipated_energy;
  - past the switch the steps are energy-controlled: lambda falls after the
    peak while the monitor does not need to grow (no step of the post-peak
    branch is on the displacement grid of the elastic steps).

usage: check_wall_past_peak.py R
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

COURSES, UNITS, SIGMA, DEPTH = 20, 20, 0.30e6, 0.1
LENGTH = UNITS * 0.22 - 0.01  # units of 0.21 m and 10 mm head joints, half units at the ends
N = -SIGMA * LENGTH * DEPTH
SCENE = f"""title: running-bond wall past its peak, 20 x 20 units
geometry:
  generator: running_bond
  depth: {DEPTH}
  running_bond: {{courses: {COURSES}, units_per_course: {UNITS}, unit_length: 0.21, unit_height: 0.052, foundation: true, top_beam: true}}
joints: {{law: dry, kn: 82.0e9, kt: 36.0e9, thickness: 0.01, strength: {{tension: 0.25e6, cohesion: 0.35e6, friction: 0.75, dilatancy: 0, tension_energy: 18, shear_energy: 125}}}}
discretization: {{m: 8}}
supports: {{foundation: {{u1: 0, u2: 0, w: 0}}, top_beam: {{w: 0}}}}
loads: {{top_beam: [0, {N!r}, 0]}}
analysis:
  type: pushover
  pushover: {{loads: {{top_beam: [1, 0, 0]}}, control: dissipation, monitor: {{set: top_beam, dof: u1}}, target: 4.0e-3, steps: 100}}
output: {{file: out.h5, stresses: false, xdmf: false, steps: all}}
"""


def main(ranks):
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "wall.yaml")
        with open(scene, "w") as f:
            f.write(SCENE)
        out = os.path.join(tmp, "out.h5")
        run(scene, ["-output_file", out, "-progress", "false"], ranks)
        r = bw.read(out)
    h, s = r.history, r.solver
    lam, mon, res, dis = h["load_factor"], h["monitor"], h["residual"], h["dissipation"]
    k = int(np.argmax(lam))
    past = len(lam) - 1 - k
    expect(past >= 30, f"{past} steps past the peak (step {k} of {len(lam) - 1}): stop {s['stop_reason']}")
    expect(lam[-1] < 0.8 * lam[k], f"the last lambda {lam[-1]:.6g} is {lam[-1] / lam[k]:.3f} of the peak {lam[k]:.6g}, not below 0.8")
    expect("no converged state" not in s["stop_reason"], f"stopped: {s['stop_reason']}")
    expect((res <= 1e-8).all(), f"a step's relative residual {res.max():.2e} is above the tolerance 1e-8 (step {int(np.argmax(res))})")
    expect(0 <= s["equilibrium_error"] <= 1e-10, f"/solver equilibrium_error {s['equilibrium_error']:.2e}")
    # the reactions against the loads, per written step: load0 + lambda P
    top = r.sets["top_beam"][0]
    c = r.centroid
    worst = 0.0
    expect(len(r.steps) == len(lam), f"{len(r.steps)} written steps, {len(lam)} in /history (output.steps: all)")
    for n, st in r.steps.items():
        load = np.zeros_like(st.reaction)
        load[top] = [lam[n], N, 0.0]
        f = st.reaction + load
        fx, fy = f[:, 0].sum(), f[:, 1].sum()
        m = (f[:, 2] + c[:, 0] * f[:, 1] - c[:, 1] * f[:, 0]).sum()
        scale = abs(N) + abs(lam[n])
        e = max(abs(fx), abs(fy), abs(m) / (LENGTH + c[:, 1].max())) / scale
        worst = max(worst, e)
        expect(e <= 1e-9, f"step {n}: reactions + loads = ({fx:.3e} N, {fy:.3e} N, {m:.3e} N m), {e:.2e} of the loads")
    dd = np.diff(dis)
    expect(dd.min() >= -1e-9 * dis[-1], f"the dissipated energy falls by {-dd.min():.3e} J in a step (of {dis[-1]:.4g} J)")
    expect(abs(s["dissipated_energy"] - dis[-1]) <= 1e-12 * dis[-1], "dissipated_energy is not the last /history/dissipation")
    du = mon[1] - mon[0]
    post = mon[k + 1:]
    on = np.abs(post - mon[0] - np.round((post - mon[0]) / du) * du) <= 1e-9 * du
    expect(not on.all(), "every post-peak step is on the displacement grid: no energy-controlled step")
    print(f"{ranks} rank(s): {len(r.displacement)} blocks, {len(lam) - 1} steps, peak {lam[k] / 1e3:.2f} kN at step {k} "
          f"(u {mon[k] * 1e3:.3f} mm), {past} steps past it down to {lam[-1] / lam[k]:.3f} of it; residuals <= {res.max():.1e}; "
          f"reactions + loads <= {worst:.1e} of the loads; dissipated {dis[-1]:.2f} J; "
          f"{s['newton_iterations'] / max(1, len(lam) - 1):.1f} Newton iterations per step; stop: {s['stop_reason'][:70]}")


if __name__ == "__main__":
    try:
        main(int(sys.argv[1]))
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
