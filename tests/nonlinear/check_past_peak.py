"""Past the peak (issue 20): dissipation control against closed forms, and
the capacity figures against an independent implementation of their
definitions (interface.md, "Additions of 2026-11-23 (past the peak)").

  snapback R     a stack of N = 40 rigid blocks on a fixed base, pulled
                 apart by a vertical force on the top block (rotations and
                 horizontal motion held), all joints alike (dry, J4D's kn,
                 ft = 0.25 MPa, GfI = 18 J/m^2) except the top one, 1 %
                 smaller in area (A_w = 0.99 A), which reaches ft first. On
                 the post-peak branch, sigma the weak joint's stress,
                     u = sigma (1 + (N-1) A_w/A)/kn + (GfI/ft) ln(ft/sigma),
                 which snaps back (1 + 39 x 0.99 = 39.6 > kn GfI/ft^2 = 23.6).
                 control: dissipation on R ranks: every converged step on the
                 closed form (1e-6 of u_peak; Newton's tolerance leaves ~1e-8),
                 lambda decreasing past the peak, u decreasing then
                 increasing, down to sigma <= 0.02 ft; /history/dissipation =
                 GfI A_w (1 - sigma/ft) to 1e-3 of GfI A_w (its quadrature:
                 the loads' work by the trapezoid rule minus the exact change
                 of stored elastic energy, step by step) and closer with
                 half the energy per step (the trapezoid's error, O(h^2));
                 control: displacement stops at the snap-back with its
                 stop_reason. The capacity attributes against capacity()
                 below: elastic-brittle, ductility 1.
  exhausted R    the same stack with a constant upward pull P0 = ft A_w / 2 on
                 the top block (top-level `loads`): the pattern's peak is
                 lambda = ft A_w - P0 and past it lambda = sigma A_w - P0, on
                 the closed form above with sigma = (lambda + P0)/A_w, falls
                 to zero where sigma = ft/2: the softened joint no longer
                 carries the pull. With on_reversal: continue, energy
                 control goes on with the pattern pulling down (an
                 equilibrium path): every step past the peak, below zero
                 too, on the closed form (1e-6 of u_peak); /solver
                 load_reversal_step the first step with lambda <= 0 (-1
                 for the stack without the pull: snapback above). By
                 default (on_reversal: stop) the same run ends at that
                 step (the collapse): the same path to it (1e-9 of the
                 peak), its state written as the last, stop_reason naming
                 the sign change.
  capacity       the definitions on curves with a known answer: a
                 hardening-softening history (yield, 0.8 F_max fall,
                 snap-back drop) through blockwall's own output of a J4D
                 pushover, checked against capacity() (1e-9).
"""
import math
import os
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))
from bwrun import Failure, expect, run  # noqa: E402
import blockwall as bw  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(HERE))
N, B, H, E, S = 40, 0.2, 0.05, 0.01, 0.1
KN, FT, GF = 82.0e9, 0.25e6, 18.0
A, AW = B * S, (B - 0.002) * S


def capacity(lam, mon, sign):
    """interface.md's definitions, written from its text (not from blockwall's C)."""
    lam, d = np.asarray(lam, float), sign * (np.asarray(mon, float) - mon[0])
    first = next((k for k in range(len(lam) - 1) if lam[k + 1] < lam[k]), int(np.argmax(lam)))
    env_d, env_f, dmax, behind = [0.0], [lam[0]], 0.0, False
    for i in range(1, len(lam)):
        if d[i] > dmax:
            if behind and d[i] > d[i - 1]:
                a = (dmax - d[i - 1]) / (d[i] - d[i - 1])
                env_d.append(dmax)
                env_f.append(lam[i - 1] + a * (lam[i] - lam[i - 1]))
            env_d.append(d[i])
            env_f.append(lam[i])
            dmax, behind = d[i], False
        else:
            behind = True
    env_d, env_f = np.array(env_d), np.array(env_f)
    fmax = env_f.max()
    imax = int(np.argmax(env_f))
    i7 = next(i for i in range(1, len(env_f)) if env_f[i] >= 0.7 * fmax)
    d7 = env_d[i7 - 1] + (0.7 * fmax - env_f[i7 - 1]) / (env_f[i7] - env_f[i7 - 1]) * (env_d[i7] - env_d[i7 - 1])
    k = 0.7 * fmax / d7
    du, pts_d, pts_f = env_d[-1], list(env_d), list(env_f)
    for i in range(imax + 1, len(env_f)):
        if env_f[i] <= 0.8 * fmax:
            a = (env_f[i - 1] - 0.8 * fmax) / (env_f[i - 1] - env_f[i]) if env_f[i - 1] > env_f[i] else 1.0
            du = env_d[i - 1] + a * (env_d[i] - env_d[i - 1])
            pts_d, pts_f = list(env_d[:i]) + [du], list(env_f[:i]) + [0.8 * fmax]
            break
    pts_d, pts_f = np.asarray(pts_d), np.asarray(pts_f)
    e = float(np.sum(0.5 * (pts_f[1:] + pts_f[:-1]) * np.diff(pts_d)))
    disc = du * du - 2 * e / k
    if -1e-9 * du * du < disc < 0:
        disc = 0.0
    fy = k * (du - math.sqrt(disc)) if disc >= 0 else float("nan")
    return dict(first_peak_load_factor=lam[first], first_peak_monitor=mon[first], residual_load_factor=lam[-1],
                ultimate_displacement=du, bilinear_yield_force=fy, bilinear_yield_displacement=fy / k,
                ductility=du / (fy / k))


def check_capacity(solver, hist, sign, tol, what):
    want = capacity(hist["load_factor"], hist["monitor"], sign)
    for key, v in want.items():
        got = float(solver[key])
        ok = (math.isnan(v) and math.isnan(got)) or abs(got - v) <= tol * max(abs(v), 1e-300)
        expect(ok, f"{what}: /solver {key} = {got!r}, the definitions give {v!r}")
    expect(abs(float(solver["dissipated_energy"]) - hist["dissipation"][-1]) <= 1e-12 * abs(hist["dissipation"][-1]) + 1e-300,
           f"{what}: dissipated_energy is not the last /history/dissipation")
    return want


def stack_scene(tmp, control, energy, target=3.0e-4, steps=1000, pull=0.0):
    g = bw.Geometry(depth=S)
    g.add_block(bw.rectangle(0, -0.1, B, 0.0), sets=["base"])
    for k in range(N):
        y0 = E + k * (H + E)
        x0, x1 = (0.001, B - 0.001) if k == N - 1 else (0.0, B)
        g.add_block(bw.rectangle(x0, y0, x1, y0 + H), sets=["top", "column"] if k == N - 1 else ["column"])
    g.write(os.path.join(tmp, "stack.h5"))
    extra = f", dissipation_step: {energy}" if energy else ""
    text = f"""geometry: {{generator: file, file: stack.h5}}
joints: {{law: dry, kn: {KN}, kt: 36.0e9, thickness: {E}, strength: {{tension: {FT}, cohesion: 1.0e7, friction: 0.75, tension_energy: {GF}}}}}
discretization: {{m: 2}}
supports: {{base: {{u1: 0, u2: 0, w: 0}}, column: {{u1: 0, w: 0}}}}
{f"loads: {{top: [0, {pull!r}, 0]}}" if pull else ""}
analysis:
  type: pushover
  pushover: {{loads: {{top: [0, 1, 0]}}, control: {control}, monitor: {{set: top, dof: u2}}, target: {target}, steps: {steps}{extra}}}
output: {{file: out.h5, stresses: false, xdmf: false}}
"""
    path = os.path.join(tmp, "stack.yaml")
    with open(path, "w") as f:
        f.write(text)
    return path


def read_run(out):
    with h5py.File(out, "r") as f:
        hist = {k: f["history"][k][()] for k in f["history"]}
        solver = dict(f["solver"].attrs)
    solver = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in solver.items()}
    return hist, solver


def snapback(ranks):
    errs = []
    with tempfile.TemporaryDirectory() as tmp:
        for energy in (GF * AW / 120, GF * AW / 240):
            scene = stack_scene(tmp, "dissipation", energy)
            out = os.path.join(tmp, "out.h5")
            run(scene, ["-output_file", out], ranks)
            hist, solver = read_run(out)
            lam, u, dis = hist["load_factor"], hist["monitor"], hist["dissipation"]
            k = int(np.argmax(lam))
            sig = lam / AW
            upk = sig[k] * (1 + (N - 1) * AW / A) / KN
            # the peak: the last elastic step, within the smallest cut-back of ft
            expect(0.99 * FT <= sig[k] <= FT * (1 + 1e-9), f"peak stress {sig[k]:.6e}, ft {FT}")
            post = np.arange(k + 1, len(lam))
            expect(len(post) >= 50, f"only {len(post)} steps past the peak")
            ucf = sig[post] * (1 + (N - 1) * AW / A) / KN + GF / FT * np.log(FT / sig[post])
            eu = np.max(np.abs(u[post] - ucf)) / upk
            expect(eu <= 1e-6, f"a post-peak step off the closed form by {eu:.2e} of u_peak")
            expect(np.all(np.diff(lam[post]) < 0), "lambda does not decrease past the peak")
            i_min = int(np.argmin(u[post]))
            expect(u[post][i_min] < upk * 0.99 and u[-1] > u[post][i_min], "u does not first decrease then increase (no snap-back followed)")
            expect(sig[post].min() <= 0.02 * FT, f"followed only down to sigma = {sig[post].min() / FT:.3f} ft")
            ed = np.max(np.abs(dis[post] - GF * AW * (1 - sig[post] / FT))) / (GF * AW)
            expect(ed <= 1e-3, f"dissipation off GfI A_w (1 - sigma/ft) by {ed:.2e} of GfI A_w")
            expect(np.max(np.abs(dis[:k + 1])) <= 1e-9 * GF * AW, "energy dissipated before the peak")
            # F_y = k (d_u - sqrt(d_u^2 - 2E/k)) with d_u^2 = 2E/k up to round-off here:
            # the square root of a cancellation, good to ~sqrt(eps)
            expect(int(solver["load_reversal_step"]) == -1, f"load_reversal_step {solver['load_reversal_step']} where lambda stays > 0")
            cap = check_capacity(solver, hist, 1.0, 1e-6, "snap-back")
            expect(abs(cap["ductility"] - 1) <= 1e-6, f"an elastic-brittle envelope has ductility 1, got {cap['ductility']}")
            errs.append(ed)
            print(f"{ranks} rank(s), energy per step {energy:.3e} J: {len(post)} steps past the peak, down to sigma = "
                  f"{sig[post].min() / FT:.4f} ft; off the closed form by {eu:.1e} u_peak; dissipation off by {ed:.2e} GfI A_w; "
                  f"u min {u[post][i_min] / upk:.4f} u_peak; {solver['stop_reason']}")
        expect(errs[1] < 0.5 * errs[0], f"the dissipation's quadrature error does not fall with the step: {errs}")
        # displacement control stops at the snap-back
        scene = stack_scene(tmp, "displacement", None, steps=100)
        out = os.path.join(tmp, "out.h5")
        run(scene, ["-output_file", out], ranks)
        hist, solver = read_run(out)
        expect("the end of what displacement control can follow" in solver["stop_reason"], f"displacement control: {solver['stop_reason']}")
        expect(hist["load_factor"].max() / AW >= 0.99 * FT, "displacement control stopped before the peak")
        print(f"displacement control: stops at monitor {hist['monitor'][-1]:.4e} ({solver['stop_reason'][:60]}...)")


def exhausted(ranks):
    p0 = 0.5 * FT * AW
    with tempfile.TemporaryDirectory() as tmp:
        scene = stack_scene(tmp, "dissipation", GF * AW / 120, pull=p0)
        out = os.path.join(tmp, "out.h5")
        run(scene, ["-output_file", out, "-analysis_pushover_on_reversal", "continue", "-output_steps", "all"], ranks)
        hist, solver = read_run(out)
        lam, u = hist["load_factor"], hist["monitor"]
        k = int(np.argmax(lam))
        expect(abs(lam[k] - (FT * AW - p0)) <= 0.01 * FT * AW, f"peak lambda {lam[k]:.6e}, ft A_w - P0 = {FT * AW - p0:.6e}")
        post = np.arange(k + 1, len(lam))
        expect(len(post) >= 20, f"only {len(post)} steps past the peak")
        sig = (lam + p0) / AW
        upk = sig[k] * (1 + (N - 1) * AW / A) / KN
        ucf = sig[post] * (1 + (N - 1) * AW / A) / KN + GF / FT * np.log(FT / sig[post])
        eu = np.max(np.abs(u[post] - ucf)) / upk
        expect(eu <= 1e-6, f"a post-peak step off the closed form by {eu:.2e} of u_peak")
        below = np.nonzero(lam[k:] <= 0)[0]
        expect(len(below) > 0 and lam[-1] < -0.5 * p0, f"lambda did not fall through zero to below -P0/2 (last {lam[-1]:.3e})")
        first = k + int(below[0])
        expect(int(solver["load_reversal_step"]) == first, f"load_reversal_step {solver['load_reversal_step']}, the first step with lambda <= 0 is {first}")
        expect(abs(float(solver["residual_load_factor"]) - lam[-1]) <= 1e-12 * lam[k], "residual_load_factor is not the last lambda")
        # by default (on_reversal: stop) the same path ends at that step:
        # the stack no longer carries the held pull
        stopped = os.path.join(tmp, "stopped.h5")
        run(scene, ["-output_file", stopped], ranks)
        hs, ss = read_run(stopped)
        expect(len(hs["load_factor"]) == first + 1, f"on_reversal: stop ended after {len(hs['load_factor']) - 1} steps, the sign changed at step {first}")
        expect("changed sign" in ss["stop_reason"], f"stop_reason {ss['stop_reason']!r} does not name the sign change")
        expect(int(ss["load_reversal_step"]) == first, f"load_reversal_step {ss['load_reversal_step']} with on_reversal: stop, expected {first}")
        el = np.max(np.abs(hs["load_factor"] - lam[:first + 1])) / lam[k]
        expect(el <= 1e-9, f"the stopped run's path differs from the continued one's by {el:.2e} of the peak")
        with h5py.File(stopped, "r") as a, h5py.File(out, "r") as b:
            ed = np.max(np.abs(a["blocks/displacement"][()] - b[f"steps/{first:06d}/blocks/displacement"][()])) / upk
        expect(ed <= 1e-9, f"the stopped run's final state is not that of step {first} ({ed:.2e} of u_peak)")
        print(f"{ranks} rank(s): peak {lam[k]:.6e} (ft A_w - P0 = {FT * AW - p0:.6e}), {len(post)} steps past it on the closed form "
              f"to {eu:.1e} u_peak, lambda <= 0 from step {first} (load_reversal_step {solver['load_reversal_step']}) to {lam[-1] / p0:.3f} P0; "
              f"{solver['stop_reason'][:40]}; by default the run stops there: {ss['stop_reason'][:50]}")


def capacity_case():
    """J4D (examples/j4d.yaml) as shipped, shortened: a hardening curve;
    blockwall's attributes against the definitions."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.h5")
        run(os.path.join(ROOT, "examples", "j4d.yaml"), ["-output_file", out, "-output_xdmf", "0",
                                                         "-analysis_pushover_steps", "40"], 1)
        hist, solver = read_run(out)
        want = check_capacity(solver, hist, 1.0, 1e-9, "J4D")
        print("J4D, 40 steps: " + ", ".join(f"{k} {v:.6g}" for k, v in want.items()))


if __name__ == "__main__":
    try:
        if sys.argv[1] == "snapback":
            snapback(int(sys.argv[2]))
        elif sys.argv[1] == "exhausted":
            exhausted(int(sys.argv[2]))
        elif sys.argv[1] == "capacity":
            capacity_case()
        else:  # not another case's checks under a mistyped name
            sys.exit(f"check_past_peak.py: unknown case {sys.argv[1]!r} (snapback R, exhausted R, capacity)")
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
