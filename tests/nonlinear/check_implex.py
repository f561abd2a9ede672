"""The IMPL-EX scheme (analysis.pushover.scheme: implex; issue 30) against
closed forms and invariants. Every IMPL-EX step is one linear solve on the
elastic matrix with the plastic jumps extrapolated from the last step, so
its path is a continuous function of the data: these references hold on any
CPU and BLAS to their stated tolerances.

  sliding   a block on a cohesive-frictional joint (check_nonlinear.py's
            `sliding` scene), displacement control: once it slides at a
            steady rate the extrapolation is exact, so the plateau is
            c A + N tan(phi) to 1e-9 (m = 2, 8, 32); the first sliding step
            overshoots (the extrapolation starts from no flow) by at most
            twice the tolerance (0.05: its error is measured on the
            portion's own stress, and a step cut twice is kept whatever its
            error; 0.048 measured); scheme "implex" in /solver, one linear
            solve per step tried, cut ones included, on one factorisation.
  softening a joint pulled open through its exponential softening
            (check_nonlinear.py's `softening`): the curve against the closed
            form within the tolerance of ft A (0.2 and 0.05: the crack's
            first step overshoots ft by what the tolerance allows, measured
            on ft), the work of the pull against GfI A (1 - exp(-ft k1/GfI))
            + the elastic energy to 1 %.
  reversal  the stack under a held pull (check_past_peak.py's `exhausted`):
            past its peak the pattern's load falls through zero where the
            softened joint's stress is ft/2; by default the IMPL-EX run
            stops at the first step with lambda <= 0 and says so, its peak
            at ft A_w - P0 or above it by at most twice the tolerance of
            ft A_w (the crack's overshoot, measured on ft; 0.025 ft A_w
            measured).
  handover  `scheme: auto` under dissipation control where Newton cannot
            go on: the sliding block with analysis.pushover.max_iterations
            1, so that no step in which the joint starts to slide converges
            (elastic steps take one correction). auto hands over to IMPL-EX
            (/solver scheme "newton+implex", implex_from_step past the
            elastic steps) at Newton's first exhaustion, without stepping
            over it (no "stepping over" among its progress lines, where
            scheme newton's run of the same scene has them), and IMPL-EX
            reaches the target on the plateau
            c A + N tan(phi) to 1e-9; Newton's steps before it lie on or
            below the capacity, IMPL-EX's first sliding step above it by at
            most twice the tolerance.
  ranks R   the 10-course wall of check_nonlinear.py's `ranks` on 1 and R
            ranks: the same steps to 1e-10 up to half the peak; past it the
            curves at the same monitor values within 2 % of the peak (a
            softening wall's path amplifies round-off where its cracks
            localise, whatever the scheme: measured 8e-10 at tolerance 0.2,
            1e-2 at 0.05).
"""
import math
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from bwrun import Failure, expect, run  # noqa: E402
import check_nonlinear as cn  # noqa: E402
import check_past_peak as cp  # noqa: E402

IMPLEX = ["-analysis_pushover_scheme", "implex"]
TOL = 0.05  # analysis.pushover.implex_tolerance's default, which these runs use


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def sliding():
    c, tphi, N, A = 1.0e4, 0.75, 1000.0, 0.2 * 0.1
    cap = c * A + N * tphi
    with tempfile.TemporaryDirectory() as tmp:
        for m in (2, 8, 32):
            res, r = cn.pushover_block(tmp, m, 20, f"tension: 1.0e5, cohesion: {c}, friction: {tphi}", (1, 0, 0.055), "u1", 1e-4, extra_args=IMPLEX)
            lam = r.history["load_factor"]
            sol = res["solver"]
            e = abs(lam[-1] - cap) / cap
            expect(e <= 1e-9, f"m = {m}: plateau {lam[-1]:.12g}, c A + N tan(phi) = {cap:.12g} (relative {e:.2e})")
            expect(text(sol["scheme"]) == "implex", f"m = {m}: /solver scheme {sol['scheme']!r}")
            expect(text(sol["stop_reason"]) == "target reached", f"m = {m}: stop {sol['stop_reason']}")
            tried = len(lam) - 1 + int(sol["implex_cut_steps"])
            expect(int(sol["newton_iterations"]) == tried + int(r.history["iterations"][0]),
                   f"m = {m}: {sol['newton_iterations']} Newton iterations for {tried} IMPL-EX solves (one each, cut ones included) and step 0")
            over = (lam.max() - cap) / cap
            expect(over <= 2 * TOL, f"m = {m}: the first sliding step overshoots the capacity by {over:.3f} (tolerance {TOL})")
            expect((r.state[0] >= 2).all(), f"m = {m}: not every portion is sliding at the end: {r.state[0]}")
            print(f"m = {m:2d}: plateau {lam[-1]:.12g} = c A + N tan(phi) {cap:.12g} ({e:.1e}); first sliding step {over:.3f} above it; "
                  f"{len(lam) - 1} steps, largest error {float(sol['implex_error_max']):.3f}")


def handover():
    c, tphi, N, A = 1.0e4, 0.75, 1000.0, 0.2 * 0.1
    cap = c * A + N * tphi
    args = ["-analysis_pushover_control", "dissipation", "-analysis_pushover_max_iterations", "1", "-progress", "true"]

    def block(tmp, more=()):
        return cn.pushover_block(tmp, 8, 20, f"tension: 1.0e5, cohesion: {c}, friction: {tphi}", (1, 0, 0.055), "u1", 1e-4,
                                 extra_args=args + list(more), stdout=True)
    with tempfile.TemporaryDirectory() as tmp:
        res, r, printed = block(tmp)
        # scheme newton tries the step over where auto hands over
        _, _, printed_newton = block(tmp, ["-analysis_pushover_scheme", "newton"])
    overs = printed.count("stepping over")
    expect(overs == 0, f"auto stepped over Newton's exhaustion {overs} times before handing over (its progress lines)")
    expect(printed_newton.count("stepping over") > 0, "scheme newton did not step over where Newton was exhausted (its progress lines)")
    sol = res["solver"]
    lam = r.history["load_factor"]
    k = int(sol["implex_from_step"])
    expect(text(sol["scheme"]) == "newton+implex", f"/solver scheme {sol['scheme']!r}, want newton+implex")
    expect(text(sol["stop_reason"]) == "target reached", f"stop {sol['stop_reason']}")
    expect(1 <= k < len(lam), f"implex_from_step {k} of {len(lam) - 1} steps")
    expect(lam[:k].max() <= cap * (1 + 1e-10), f"Newton's steps before the handover reach {lam[:k].max():.12g} above the capacity {cap}")
    e = abs(lam[-1] - cap) / cap
    expect(e <= 1e-9, f"plateau {lam[-1]:.12g}, c A + N tan(phi) = {cap:.12g} (relative {e:.2e})")
    over = (lam.max() - cap) / cap
    expect(over <= 2 * TOL, f"IMPL-EX's first sliding step overshoots the capacity by {over:.3f} (tolerance {TOL})")
    print(f"Newton to step {k - 1} (largest load {lam[:k].max():.6g}), IMPL-EX from step {k}: plateau {lam[-1]:.12g} = c A + N tan(phi) "
          f"{cap:.12g} ({e:.1e}); first sliding step {over:.3f} above it; {len(lam) - 1} steps")


def softening():
    ft, GfI, A, kn = 0.25e6, 18.0, 0.2 * 0.1, 1e11
    u_end = 10 * GfI / ft
    with tempfile.TemporaryDirectory() as tmp:
        for tol in (0.2, 0.05):
            res, r = cn.pushover_block(tmp, 4, 500, f"tension: {ft}, cohesion: 1.0e7, friction: 0.75, tension_energy: {GfI}", (0, 1, 0), "u2", u_end, N=0.0,
                                       extra_args=IMPLEX + ["-analysis_pushover_implex_tolerance", str(tol)])
            lam, u = r.history["load_factor"], r.history["monitor"]
            work = float(np.sum(0.5 * (lam[1:] + lam[:-1]) * np.diff(u)))
            k1 = u[-1] - lam[-1] / (kn * A)
            want = GfI * A * (1 - math.exp(-ft * k1 / GfI)) + 0.5 * lam[-1] ** 2 / (kn * A)
            ew = abs(work - want) / want
            worst = max(abs(lk - cn.softening_stress(uk, ft, GfI, kn) * A) / (ft * A) for lk, uk in zip(lam, u))
            expect(text(res["solver"]["stop_reason"]) == "target reached", f"tolerance {tol}: stop {res['solver']['stop_reason']}")
            # the crack's first step overshoots ft by at most the tolerance
            # (its error is measured on ft); past it the extrapolation
            # follows the softening closely
            expect(worst <= 1.05 * tol, f"tolerance {tol}: curve off the closed form by {worst:.3f} of ft A")
            expect(ew <= 0.01, f"tolerance {tol}: work of the pull {work:.6g} J off GfI A (1 - exp(..)) + elastic {want:.6g} J by {ew:.2e}")
            print(f"tolerance {tol}: {len(lam) - 1} steps; work {work:.6f} J against {want:.6f} J ({ew:.2e}); curve off the closed form by {worst:.3f} of ft A")


def reversal():
    p0 = 0.5 * cp.FT * cp.AW
    with tempfile.TemporaryDirectory() as tmp:
        scene = cp.stack_scene(tmp, "displacement", None, target=1.0e-3, steps=400, pull=p0)
        out = os.path.join(tmp, "out.h5")
        run(scene, ["-output_file", out, *IMPLEX], 1)
        hist, solver = cp.read_run(out)
    lam = hist["load_factor"]
    k = int(np.argmax(lam))
    peak = cp.FT * cp.AW - p0
    # the crack's first step overshoots ft by about the tolerance, twice it at most
    expect(-0.01 * peak <= lam[k] - peak <= 2 * TOL * cp.FT * cp.AW, f"peak lambda {lam[k]:.6e}, ft A_w - P0 = {peak:.6e}")
    expect(len(lam) > 2 and lam[-1] <= 0 and (lam[1:-1] > 0).all(), f"the run did not end at the first lambda <= 0: last {lam[-2:]}")
    expect("changed sign" in solver["stop_reason"], f"stop_reason {solver['stop_reason']!r} does not name the sign change")
    expect(int(solver["load_reversal_step"]) == len(lam) - 1, f"load_reversal_step {solver['load_reversal_step']}, last step {len(lam) - 1}")
    print(f"peak {lam[k]:.6e} (ft A_w - P0 = {peak:.6e}); lambda <= 0 at step {len(lam) - 1}, monitor {hist['monitor'][-1]:.4e}: {solver['stop_reason'][:60]}")


def ranks(n):
    hist = []
    with tempfile.TemporaryDirectory() as tmp:
        for p in (1, n):
            res, r = cn.solve(tmp, cn.WALL, IMPLEX, ranks=p)
            hist.append(r.history)
            expect(text(res["solver"]["scheme"]) == "implex", f"{p} ranks: scheme {res['solver']['scheme']!r}")
            expect(text(res["solver"]["stop_reason"]) == "target reached", f"{p} ranks: stop {res['solver']['stop_reason']}")
    a, b = hist
    peak = a["load_factor"].max()
    expect(a["load_factor"][-1] < peak, "the wall did not pass its peak")
    # up to half the peak the two runs make the same steps (the first
    # cracks' cuts included) to round-off
    m = min(len(a["load_factor"]), len(b["load_factor"]))
    early = np.nonzero((a["load_factor"][:m] <= 0.5 * peak) & (b["load_factor"][:m] <= 0.5 * peak))[0]
    early = early[early == np.arange(len(early))]
    e0 = max(cn.rel_err(a[k][:len(early)], b[k][:len(early)]) for k in ("load_factor", "monitor"))
    expect(len(early) >= 3 and e0 <= 1e-10, f"the first {len(early)} steps on 1 and {n} ranks differ by {e0:.2e}")
    # past the first cracks the path of a softening wall amplifies
    # round-off (where cracks localise, a perturbation grows from step to
    # step: measured 8e-10 at tolerance 0.2 and 1e-2 at 0.05 between 1 and
    # 2 ranks, whose sums differ in order), and a cut decided the other way
    # shifts the steps: the curves are compared at the same monitor values,
    # against the peak
    pts = np.linspace(0.1, 1.0, 10) * a["monitor"][-1]
    la = np.interp(pts, a["monitor"], a["load_factor"])
    lb = np.interp(pts, b["monitor"], b["load_factor"])
    e1 = np.max(np.abs(la - lb)) / peak
    expect(e1 <= 0.02, f"the curves on 1 and {n} ranks differ by {e1:.2e} of the peak")
    print(f"1 and {n} ranks: {len(a['load_factor'])} and {len(b['load_factor'])} steps; the first {len(early)} equal to {e0:.1e}; "
          f"curves at the same monitor within {e1:.1e} of the peak {peak:.1f} N")


if __name__ == "__main__":
    try:
        case = sys.argv[1]
        if case == "ranks":
            ranks(int(sys.argv[2]))
        else:
            globals()[case]()
    except Failure as e:
        print(f"FAILED: {e}")
        sys.exit(1)
