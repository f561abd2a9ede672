"""The same curve under dissipation control as under displacement control
(issue 20, "Past the peak"): the scenes of the 2D nonlinear tests
(check_nonlinear.py: sliding, dilatancy, softening, overturning,
stack_overturn, the running-bond wall of `ranks`), each run
with control: displacement and with control: dissipation, on R ranks.

How the steps are chosen, and so what can be compared. Under dissipation
control the run takes displacement steps (the scene's increments) until a
step dissipates more than 1 % of the loads' work on it; from there each
step prescribes the energy it dissipates (bordered Newton), so its steps
land at monitor values u_k that are not on the displacement run's grid
(the energy per step follows the path, pushover.c). The steps before the
switch are the same computation under both controls: comparing them would
be a tautology, and they are not what this test is about (only checked
equal, as the switch's own guard). Interpolating the displacement run's
lambda(u) onto u_k is exact only where the curve is linear (an O(h^2) error
on the softening branch, 1e-4 here), so it cannot show 1e-8.

The comparison at 1e-8. Each scene here but the wall has a path-
independent discrete curve: one joint whose portions all follow the same
radial stress path (sliding, dilatancy, softening: the backward-Euler
return map is exact whatever the step), or no-tension joints opening
monotonically (overturning, stack_overturn: nothing dissipates). The state
at a monitor value is then unique, so a displacement-controlled run with its own equal increments to
target u_k must end at lambda_k. For the first and the last energy-
controlled steps k of each run (on 2 ranks the last only: mpiexec's start
is most of the test's time) a displacement run to u_k is made, and |lambda_disp(u_k) - lambda_k| <= 1e-8 of the peak (Newton's
tolerance is 1e-8 of the residual; the agreement is 1e-16 to 5e-10). A scene whose
dissipation run never left displacement control (nothing dissipated more
than 1 %) would make this tautological: every scene is required to have
energy-controlled steps off the grid, but the two rocking cases, whose
joints dissipate nothing (ft = c = 0, no slip): there the switch must not
happen (the run is then the displacement run, to 1e-9), or, if the
trapezoid rule's O(h^2) error on the curved elastic path counts as
dissipated energy and it does, its steps must still land on the unique
curve (overturning, at 1e-8 as above). Before 2026-11-25 the switch
compared the dissipation with the loads' net work, in which the weight
lifted by the rocking stack cancels the push: the error alone passed 1 %,
and energy control drove the stack onto a branch with lambda < 0.

Left out: stack_slide. Its plateau is a multiple mechanism (all four
joints reach tan(phi) at once, the share of the slip among them is free):
the energy steps spread the slip over every joint, the tangent then has a
null space the monitor's spring does not remove, and the run stops after 4
steps (displacement control, which keeps the slip in fewer joints, follows
it to its target). Not a curve both controls follow. And j4d: path-
dependent like the wall below, which checks the same at a tenth of the
cost (J4D's runs take seconds, the budget of this test is 30 s for 1 and 2
ranks together).

The running-bond wall (`ranks`): softening joints cracking one after the
other make the discrete path depend on the steps (backward Euler of a
path-dependent law), so two controls that take different steps differ by
the step's error, not by 1e-8. Checked: the steps before the switch
equal (1e-9 of the peak: Newton's tolerance), and past it every
energy-controlled point, where the monitor increases, against the
displacement run with half the increment interpolated at u_k, within 3
times 4 times that curve's error estimate (its distance to the run with
the scene's increment, the largest at the point and its two neighbours on
each side: steps and interpolation, both O(h^2); the energy steps aim at
two increments of path, so their own error is up to 4 times that) plus
1e-8 of the peak. The displacement run follows this wall to its target, and so must
the other control (no stop before its most steps). At least 10 points, and
half of the energy-controlled steps, must be compared (27 are).

The same on the direct path (`direct`): the unique scenes under
dissipation control with `-solver_method direct` give their curve to 1e-8
as above, in the steps the default path takes (at most 20 % more: a
failed linear solve cuts a step).

usage: check_controls.py same_curve R | direct
"""
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, HERE)
from bwrun import Failure, expect, run  # noqa: E402
import check_nonlinear as cn  # noqa: E402  (the scenes of the nonlinear tests)

sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))
import blockwall as bw  # noqa: E402


def block_scene(m, steps, strength, pattern, dof, target, N=1000.0, kn=1e11, kt=4e10):
    """check_nonlinear.pushover_block's scene, the control a placeholder."""
    extra = f"""analysis:
  type: pushover
  pushover: {{loads: {{top: [{pattern[0]}, {pattern[1]}, {pattern[2]}]}}, control: CONTROL, monitor: {{set: top, dof: {dof}}}, target: {target}, steps: {steps}}}"""
    return cn.TWO.format(s=0.1, l=0.2, a=0.1, kn=kn, kt=kt, strength=strength, m=m, F1=0, F2=-N, M3=0, extra=extra)


def stack_scene(tmp, tphi, target):
    """check_nonlinear.stack's scene (four blocks, body force), the control a placeholder."""
    b, h, e, n = 0.2, 0.2, 0.002, 4
    cn.stack_geometry(tmp, b, h, e, n)
    return f"""geometry: {{generator: file, file: stack.h5}}
joints: {{law: dry, kn: 1.0e12, kt: 4.0e11, thickness: {e}, strength: {{tension: 0, cohesion: 0, friction: {tphi}}}}}
discretization: {{m: 64}}
supports: {{base: {{u1: 0, u2: 0, w: 0}}}}
gravity: {{density: 2000.0}}
analysis:
  type: pushover
  pushover: {{body_force: [1, 0], control: CONTROL, monitor: {{set: top, dof: u1}}, target: {target}, steps: 40}}
output: {{file: out.h5, stresses: false, xdmf: false}}
"""


# name: (scene text or a function of tmp, target); the scenes and targets of
# check_nonlinear.py (softening with 200 steps instead of 1000: the same
# curve, a fifth of the time)
SOFT = "tension: 0.25e6, cohesion: 1.0e7, friction: 0.75, tension_energy: 18.0"
UNIQUE = {
    "sliding": lambda tmp: (block_scene(8, 20, "tension: 1.0e5, cohesion: 1.0e4, friction: 0.75", (1, 0, 0.055), "u1", 1e-4), 1e-4),
    "dilatancy": lambda tmp: (block_scene(8, 20, "tension: 1.0e5, cohesion: 1.0e4, friction: 0.75, dilatancy: 0.3", (1, 0, 0.055), "u1", 1e-4), 1e-4),
    "softening": lambda tmp: (block_scene(4, 200, SOFT, (0, 1, 0), "u2", 10 * 18.0 / 0.25e6, N=0.0), 10 * 18.0 / 0.25e6),
    "overturning": lambda tmp: (block_scene(256, 40, "tension: 0, cohesion: 0, friction: 10", (1, 0, 0), "w", -3e-5, kn=1e13, kt=1e13 / 2.5), -3e-5),
    "stack_overturn": lambda tmp: (stack_scene(tmp, 0.6, 2e-3), 2e-3),
}


# the joints of these never dissipate (ft = c = 0 and no slip: rocking on
# no-tension joints); dissipation control may stay displacement control
ELASTIC = ("overturning", "stack_overturn")
# the pattern pushes the monitor's dof alone (bP = s e)
ON_MONITOR = ("softening",)


def pushover(tmp, text, control, ranks, args=()):
    path = os.path.join(tmp, "scene.yaml")
    with open(path, "w") as f:
        f.write(text.replace("CONTROL", control))
    out = os.path.join(tmp, "out.h5")
    run(path, ["-output_file", out, "-output_xdmf", "0", *args], ranks)
    r = bw.read(out)
    s = r.solver
    stop = s["stop_reason"].decode() if isinstance(s["stop_reason"], bytes) else s["stop_reason"]
    SOLVER[control] = s
    return r.history["monitor"], r.history["load_factor"], r.history["residual"], stop


# the solver's record of the last run under each control
SOLVER = {}


def solves_per_iteration(name):
    """Where the pattern pushes the monitor's dof alone (bP = s e), a
    dissipation-controlled iteration solves K' twice (-F and e; K'^-1 bP is
    s K'^-1 e), displacement and load control at most twice (-F and bP,
    the latter only where K' changed): at most two solves per Newton
    iteration over the run (2.00 and 1.98 measured here, either BLAS).
    Three per dissipation-controlled iteration before 2026-11-28 (2.98 on
    the softening scene). The bound allows 2.25: a linear solve that fails
    ends its attempt before the iteration is counted, which round-off of
    another CPU could make happen a few times; none happens here."""
    s = SOLVER["dissipation"]
    its, solves = int(s["newton_iterations"]), int(s["linear_solves"])
    expect(0 < solves <= 2.25 * its, f"{name}: {solves} linear solves for {its} Newton iterations under dissipation control "
                                     "(the pattern pushes the monitor alone: 2 per iteration, 2.25 allowed)")
    return solves / its


def on_grid(u, ud, du):
    """whether each u is one of the displacement run's monitor values ud
    (its grid u0 + j du and any cut-back it made)"""
    return np.array([np.min(np.abs(ud - v)) <= 1e-9 * abs(du) for v in u])


def unique_case(name, ranks, args=()):
    """args: options of the dissipation run alone (`direct`: its solves on
    the direct path), checked against displacement runs on the default one."""
    with tempfile.TemporaryDirectory() as tmp:
        text, target = UNIQUE[name](tmp)
        steps = int(text.split("steps: ")[1].split("}")[0])
        ud, ld, _, stop_d = pushover(tmp, text, "displacement", ranks)
        if args:
            # the same run on the default path: the steps it takes
            ua, _, _, stop_a = pushover(tmp, text, "dissipation", ranks)
        ue, le, rese, stop_e = pushover(tmp, text, "dissipation", ranks, args)
        if args:
            expect(stop_e == stop_a and len(ue) <= 1.2 * len(ua),
                   f"{name} with {' '.join(args)}: {len(ue) - 1} steps ({stop_e}) where the default path takes {len(ua) - 1} ({stop_a}): "
                   f"its Newton corrections failed and cut steps")
        peak = max(np.abs(ld).max(), np.abs(le).max())
        expect(stop_d == "target reached", f"{name}: displacement control stopped early: {stop_d}")
        expect("no converged state" not in stop_e, f"{name}: dissipation control stopped: {stop_e}")
        expect((rese <= 1e-8).all(), f"{name}: a written step of the dissipation run did not converge ({rese.max():.2e})")
        du = (target - ud[0]) / steps
        off = np.nonzero(~on_grid(ue, ud, du))[0]
        if len(off) == 0 and name in ELASTIC:
            # nothing dissipates: dissipation control must stay displacement control
            # (the same steps: `steps` is also the most a dissipation run
            # takes, so a cut-back leaves it one step short of the target;
            # its next goal starts from the monitor value reached, which is
            # its goal to Newton's tolerance: equal to 1e-9, not bit for bit)
            n = min(len(le), len(ld))
            e0 = max(np.max(np.abs(le[:n] - ld[:n])) / peak, np.max(np.abs(ue[:n] - ud[:n])) / abs(du))
            expect(n >= len(ld) - 2 and e0 <= 1e-9, f"{name}: nothing dissipates, yet the curves differ ({len(le)} and {len(ld)} steps, {e0:.2e})")
            print(f"{name:15s} {ranks} rank(s): {len(ue) - 1} steps, no energy-controlled step (nothing dissipates): "
                  f"the displacement run's curve to {e0:.1e} of the peak")
            return
        expect(len(off) > 0, f"{name}: every dissipation-control step is on the displacement grid: nothing to compare")
        rate = solves_per_iteration(name) if name in ON_MONITOR else None
        # the steps before the switch: the same computation (the switch's guard)
        first = off[0]
        e0 = np.max(np.abs(le[:first] - ld[:first])) / peak if first else 0.0
        expect(first <= len(ld) and e0 <= 1e-9, f"{name}: the steps before the switch differ by {e0:.2e} of the peak")
        picks = [int(off[0]), int(off[-1])] if ranks == 1 else [int(off[-1])]
        worst = 0.0
        for k in picks:
            # a displacement run of its own to u_k, in increments of about the scene's
            n = max(2, int(round(abs((ue[k] - ud[0]) / du))))
            ur, lr, _, stop_r = pushover(tmp, text, "displacement", ranks,
                                         ["-analysis_pushover_target", repr(float(ue[k])), "-analysis_pushover_steps", str(n)])
            expect(stop_r == "target reached" and abs(ur[-1] - ue[k]) <= 1e-12 * abs(ue[k]),
                   f"{name}: the displacement run to u = {ue[k]:.9e} ended at {ur[-1]:.9e} ({stop_r})")
            e = abs(lr[-1] - le[k]) / peak
            worst = max(worst, e)
            expect(e <= 1e-8, f"{name}: at u = {ue[k]:.9e} (step {k} under dissipation control) lambda {le[k]:.12g}, "
                              f"displacement control {lr[-1]:.12g}: {e:.2e} of the peak")
        print(f"{name:15s} {ranks} rank(s){' with ' + ' '.join(args) if args else ''}: {len(ue) - 1} steps, {len(off)} energy-controlled off the grid from step {first}; "
              f"at {len(picks)} of them a displacement run to u_k gives lambda_k to {worst:.1e} of the peak {peak:.6g}"
              + (f"; {rate:.2f} solves per Newton iteration" if rate else ""))


def wall_case(ranks):
    with tempfile.TemporaryDirectory() as tmp:
        text = cn.WALL.replace("control: displacement", "control: CONTROL")
        ud, ld, _, stop_d = pushover(tmp, text, "displacement", ranks)
        uh, lh, _, _ = pushover(tmp, text, "displacement", ranks, ["-analysis_pushover_steps", "60"])
        ue, le, rese, stop_e = pushover(tmp, text, "dissipation", ranks)
        peak = ld.max()
        expect(stop_d == "target reached", f"wall: displacement control stopped early: {stop_d}")
        expect("no converged state" not in stop_e, f"wall: dissipation control stopped: {stop_e}")
        expect(len(ue) == len(ud), f"wall: {len(ue) - 1} steps under dissipation control, {len(ud) - 1} asked for")
        expect((rese <= 1e-8).all(), f"wall: a written step of the dissipation run did not converge ({rese.max():.2e})")
        du = ud[1] - ud[0]
        off = np.nonzero(~on_grid(ue, ud, du))[0]
        expect(len(off) > 0, "wall: every dissipation-control step is on the displacement grid: nothing to compare")
        rate = solves_per_iteration("wall")
        first = off[0]
        e0 = np.max(np.abs(le[:first] - ld[:first])) / peak
        expect(e0 <= 1e-9, f"wall: the steps before the switch differ by {e0:.2e} of the peak")
        # the reference: the displacement run with half the increment,
        # interpolated at u_k; its error (steps and interpolation, both
        # O(h^2) where the curve is smooth) estimated by its distance to the
        # run with the scene's increment, times 3
        # The energy steps aim at two increments of path length (pushover.c),
        # so their own O(h^2) error is up to 4 times that of the run with the
        # scene's increment: the band is 3 x 4 times that run's estimated
        # error, the largest over the point and its two neighbours on each
        # side (a single point's estimate passes through zero where the
        # error changes sign).
        picks = [k for k in off if ue[k] > ue[k - 1] and ud[0] <= ue[k] <= min(ud[-1], uh[-1])]
        # the points compared: 27 of the 26 to 27 steps past the switch
        # (1 and 2 ranks); a filter or a run that leaves few of them would
        # check the softening branch at a handful of points, or none
        expect(len(picks) >= max(10, len(off) // 2),
               f"wall: {len(picks)} of the {len(off)} energy-controlled steps compared (too few to check the curve)")
        local = [abs(np.interp(ue[k], ud, ld) - np.interp(ue[k], uh, lh)) for k in picks]
        worst, band, est = 0.0, 0.0, 0.0
        for i, k in enumerate(picks):
            ref = np.interp(ue[k], uh, lh)
            near = max(local[max(0, i - 2):i + 3])
            est = max(est, near)
            tol = 3 * 4 * near + 1e-8 * peak
            e = abs(le[k] - ref)
            worst, band = max(worst, e / peak), max(band, tol / peak)
            expect(e <= tol, f"wall: at u = {ue[k]:.6e} lambda {le[k]:.9g}, the displacement curve {ref:.9g}: "
                             f"{e / peak:.2e} of the peak, outside 12x its error estimate {tol / peak:.2e}")
        print(f"wall {ranks} rank(s): {len(ue) - 1} steps, switch at step {first}; steps before it equal ({e0:.1e}); past it, "
              f"at {len(picks)} of its {len(off)} energy-controlled steps, within {worst:.1e} of the peak of the displacement curve (its error estimate {est / peak:.1e}, band {band:.1e}); {rate:.2f} solves per Newton iteration")


if __name__ == "__main__":
    try:
        if sys.argv[1] == "direct":
            # the direct path (LU of the whole saddle system) under
            # dissipation control: a Newton correction's tolerance there
            # once became a relative one >= 1 where the residual had
            # converged before the energy, which KSP refused (c782f06: the
            # sliding plateau in 25 steps instead of 12, the softening
            # scene 205 instead of 92; inexact Newton reverted since)
            for name in ("sliding", "dilatancy", "softening"):
                unique_case(name, 1, ("-solver_method", "direct"))
            sys.exit(0)
        if sys.argv[1] != "same_curve":
            raise SystemExit(__doc__)
        ranks = int(sys.argv[2])
        for name in UNIQUE:
            unique_case(name, ranks)
        wall_case(ranks)
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
