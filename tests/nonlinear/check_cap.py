"""The compressive cap (issue 20; model.md, "Compressive cap") through the
whole program, against its closed forms.

  crush D R   two blocks (0.2 x 0.1 m joint, J4D's kn = 82 N/mm^3, ks = 36
              N/mm^3, tension, cohesion and friction of J4D) with Lourenço's
              cap (fc = 10.5 MPa, Css = 9, Gfc = 5 N/mm, kappa_p = 0.093 mm),
              the top block pressed down under displacement control with its
              sliding and rotation held (a uniaxial state: every portion
              alike), in D = 2 or 3 dimensions on R ranks. Every converged step
              lies on the closed form written here from model.md's text:
              elastic to fc/3, then u = -(k + sbar(k)/kn) and N = sbar(k) A
              through hardening, the parabola, the exponential and into the
              residual fc/10 (1e-6 of fc A, the issue's tolerance; the kernel
              solves its scalar equation to 1e-14). /history/dissipation
              against the exact plastic work A int_0^k sbar (1e-3 of Gfc A:
              its quadrature is the trapezoid rule on the loads' work, whose
              error falls as the step squared, checked by halving the steps);
              the energy dissipated past the peak above the residual,
              A int_kp^k (sbar - sr), against Gfc A, which it approaches as k
              grows (to e^(-8) of the exponential's area here), and the
              identity int_kp^inf (sbar - sr) = Gfc of model.md's km.
  plastic     the cap without compression_energy: perfectly plastic at fc,
              the plateau N = fc A exactly.
  errors      bad cap keys: one line naming the key, exit 1, no file.
The 2D crush also draws its crack pattern: the 4 crushed portions (state 4,
the cap's bit) in the legend.
"""
import math
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))
from bwrun import ENV, EXE, Failure, call, expect, run  # noqa: E402
import blockwall as bw  # noqa: E402

KN, KT, L, S = 82.0e9, 36.0e9, 0.2, 0.1
A = L * S
FC, CSS, GFC, KP = 10.5e6, 9.0, 5000.0, 0.093e-3
SCENE = """geometry: {{generator: two_blocks, {dim}depth: {s}, two_blocks: {{length: {l}, height: 0.1}}}}
joints: {{law: dry, kn: {kn}, kt: {kt}, thickness: 0.01,
  strength: {{tension: 0.25e6, cohesion: 0.35e6, friction: 0.75, tension_energy: 18, shear_energy: 125,
             compression: {fc}, compression_shear: {css}{cap}}}}}
discretization: {{m: 4{mb}}}
supports: {{bottom: {{{fixed}}}, top: {{{held}}}}}
analysis:
  type: pushover
  pushover: {{loads: {{top: {pattern}}}, control: displacement, monitor: {{set: top, dof: u2}}, target: {target}, steps: {steps}}}
output: {{file: out.h5, stresses: true}}
"""


def scene(dim, target, steps, soft=True, extra_cap=""):
    if dim == 3:
        return SCENE.format(dim="dimension: 3, ", s=S, l=L, kn=KN, kt=KT, fc=FC, css=CSS,
                            cap=(f", compression_energy: {GFC}, compression_peak_plastic: {KP}" if soft else "") + extra_cap,
                            mb=", m_b: 2", fixed="u1: 0, u2: 0, u3: 0, w1: 0, w2: 0, w3: 0", held="u1: 0, u3: 0, w1: 0, w2: 0, w3: 0",
                            pattern="[0, -1, 0, 0, 0, 0]", target=target, steps=steps)
    return SCENE.format(dim="", s=S, l=L, kn=KN, kt=KT, fc=FC, css=CSS,
                        cap=(f", compression_energy: {GFC}, compression_peak_plastic: {KP}" if soft else "") + extra_cap,
                        mb="", fixed="u1: 0, u2: 0, w: 0", held="u1: 0, w: 0", pattern="[0, -1, 0]", target=target, steps=steps)


def sbar(k, soft=True):
    """model.md's sbar(k), written from its text."""
    sp, si, sm, sr = FC, FC / 3, FC / 2, FC / 10
    if not soft:
        return FC
    km = KP + 75 * GFC / (67 * FC)
    mm = 2 * (sm - sp) / (km - KP)
    if k <= KP:
        return si + (sp - si) * math.sqrt(2 * k / KP - k * k / KP ** 2)
    if k <= km:
        return sp + (sm - sp) * ((k - KP) / (km - KP)) ** 2
    return sr + (sm - sr) * math.exp(mm * (k - km) / (sm - sr))


def closing_at(u):
    """k >= 0 with u = -(k + sbar(k)/kn) on the cap (bisection: u is monotone in k
    because the softening is less steep than kn)."""
    lo, hi = 0.0, -u
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if -(mid + sbar(mid) / KN) > u:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def integral(f, a, b, n=200001):
    x = np.linspace(a, b, n)
    y = np.array([f(t) for t in x])
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))


def solve(tmp, text, ranks=1):
    path = os.path.join(tmp, "scene.yaml")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(tmp, "out.h5")
    run(path, ["-output_file", out], ranks)
    return bw.read(out)


def crush(dim, ranks):
    km = KP + 75 * GFC / (67 * FC)
    tail = (FC / 2 - FC / 10) / (FC / (km - KP))  # the exponential's length (sm - sr)/|mm|
    k_end = km + 8 * tail
    u_end = -(k_end + FC / 10 / KN)
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for steps in (150, 300):
            r = solve(tmp, scene(dim, u_end, steps), ranks)
            lam, u, diss = r.history["load_factor"], r.history["monitor"], r.history["dissipation"]
            expect(abs(u[-1] - u_end) <= 1e-12, f"{dim}D: ended at u = {u[-1]} before the target {u_end}")
            worst, kk = 0.0, []
            for lk, uk in zip(lam, u):
                k = 0.0 if -uk * KN <= FC / 3 else closing_at(uk)
                want = -uk * KN * A if k == 0 else sbar(k) * A
                worst = max(worst, abs(lk - want) / (FC * A))
                kk.append(k)
            expect(worst <= 1e-6, f"{dim}D, {steps} steps: a step off the cap's closed form by {worst:.2e} of fc A")
            kk = np.array(kk)
            exact = np.array([A * integral(sbar, 0, k, 2001) if k > 0 else 0.0 for k in kk])
            derr = np.max(np.abs(diss - exact)) / (GFC * A)
            results[steps] = (worst, derr, lam, kk, diss)
            print(f"{dim}D on {ranks} rank(s), {steps} steps: every step on rn = -sbar(k3) to {worst:.1e} of fc A; "
                  f"dissipation against A int sbar dk to {derr:.2e} of Gfc A; states at the end {np.unique(r.state[0])}")
            if dim == 2 and steps == 300:
                # the crack pattern names the crushed portions (state 4: the cap's bit)
                from blockwall import plots
                cp = plots.plot_cracks(r, "end")
                labels = [t.get_text() for t in cp.ax.get_legend().get_texts()]
                expect(cp.counts[4] == 4 and "crushed: 4" in labels, f"crack pattern: counts {cp.counts}, legend {labels}")
        worst, derr, lam, kk, diss = results[300]
        expect(derr <= 1e-3, f"dissipation off the exact plastic work by {derr:.2e} of Gfc A")
        expect(derr < results[150][1], f"the dissipation's error does not fall with the step ({results[150][1]:.2e} -> {derr:.2e})")
        # visited: hardening, the parabola, the exponential
        expect((kk < KP).sum() > 3 and ((kk > KP) & (kk < km)).sum() > 3 and (kk > km).sum() > 3, "a branch of sbar not visited")
        # the steps straddle the peak: below fc A, within the curve's drop over a step
        expect(FC * A * (1 - 1e-3) <= lam.max() <= FC * A * (1 + 1e-12), f"peak {lam.max():.9g} N, fc A = {FC * A:.9g} N")
        # past the peak above the residual: blockwall's dissipation and the closed form's
        i_peak = int(np.argmax(lam))
        d_past = diss[-1] - diss[i_peak] - A * FC / 10 * (kk[-1] - kk[i_peak]) - A * integral(lambda k: sbar(k) - FC / 10, kk[i_peak], KP, 2001)
        want = A * integral(lambda k: sbar(k) - FC / 10, KP, kk[-1])
        whole = integral(lambda k: sbar(k) - FC / 10, KP, km) + (FC / 2 - FC / 10) * tail
        expect(abs(whole - GFC) <= 1e-9 * GFC, f"int_kp^inf (sbar - sr) = {whole:.12g}, Gfc = {GFC}: km does not make the energy Gfc")
        e_past = abs(d_past - want) / (GFC * A)
        expect(e_past <= 1e-3, f"energy past the peak above the residual {d_past:.6g} J, closed form {want:.6g} J ({e_past:.1e} of Gfc A)")
        expect(abs(want - GFC * A) <= 1e-3 * GFC * A, f"closed form past the peak {want:.6g} J not within 1e-3 of Gfc A = {GFC * A}")
        print(f"past the peak above the residual: {d_past:.6f} J (closed form {want:.6f} J, Gfc A = {GFC * A:.6f} J: "
              f"{abs(d_past - GFC * A) / (GFC * A):.1e} of it at k3 = {kk[-1]:.3e} m); int_kp^inf (sbar - sr) = Gfc to {abs(whole - GFC) / GFC:.0e}")


def plastic():
    with tempfile.TemporaryDirectory() as tmp:
        r = solve(tmp, scene(2, -3 * FC / KN, 30, soft=False))
        lam, u = r.history["load_factor"], r.history["monitor"]
        plateau = lam[-u * KN > FC * (1 + 1e-9)]
        expect(len(plateau) > 5 and np.max(np.abs(plateau - FC * A)) <= 1e-9 * FC * A, f"perfectly plastic cap: plateau {plateau}, fc A = {FC * A}")
        elastic = lam[-u * KN < FC * (1 - 1e-9)]
        expect(np.max(np.abs(elastic + u[: len(elastic)] * KN * A)) <= 1e-9 * FC * A, "perfectly plastic cap: not elastic below fc")
        print(f"perfectly plastic cap: {len(plateau)} steps on the plateau fc A = {FC * A:.6g} N to 1e-9")


def errors():
    cases = [
        (2, ", compression: -1", "compression"),
        (2, ", compression_energy: 0", "compression_energy"),
        (2, ", compression_peak_plastic: -1e-4", "compression_peak_plastic"),
        (3, ", compression_energy: 100", "compression_energy"),  # 67 fc^2/(75 Gfc) > kn: a portion would snap back
    ]
    with tempfile.TemporaryDirectory() as tmp:
        for dim, cap, named in cases:
            text = scene(dim, -1e-4, 5, soft=False, extra_cap=cap)
            if "-1\n" in cap or cap.startswith(", compression: "):
                text = text.replace(f"compression: {FC}, ", "")
            if "compression_energy" in cap and "peak" not in cap:
                text = text.replace(cap, cap + ", compression_peak_plastic: 1e-4")
            path = os.path.join(tmp, "bad.yaml")
            with open(path, "w") as f:
                f.write(text)
            out = os.path.join(tmp, "bad.h5")
            p = call([EXE, "-scene", path, "-output_file", out], env=ENV)
            err = p.stderr.strip().splitlines()
            expect(p.returncode == 1 and len(err) == 1 and f"joints.strength.{named}" in err[0],
                   f"{cap}: exit {p.returncode}, stderr {p.stderr!r}, expected one line naming joints.strength.{named}")
            expect(not os.path.exists(out), f"{cap}: an output file was written")
            print(f"{dim}D {cap[2:]}: {err[0]}")
        # Css = 0, a cap key without the cap, and the energy without kappa_p (named on the energy's line)
        for text, named in ((scene(2, -1e-4, 5).replace(f"compression_shear: {CSS}", "compression_shear: 0"), "compression_shear"),
                            (scene(2, -1e-4, 5, soft=False).replace(f"compression: {FC}, ", ""), "compression_shear"),
                            (scene(2, -1e-4, 5).replace(f", compression_peak_plastic: {KP}", ""), "compression_energy")):
            path = os.path.join(tmp, "bad.yaml")
            with open(path, "w") as f:
                f.write(text)
            p = call([EXE, "-scene", path, "-output_file", os.path.join(tmp, "bad.h5")], env=ENV)
            err = p.stderr.strip().splitlines()
            expect(p.returncode == 1 and len(err) == 1 and f"joints.strength.{named}" in err[0], f"expected one line naming {named}: {p.stderr!r}")
            print(err[0])


if __name__ == "__main__":
    try:
        what = sys.argv[1]
        if what == "crush":
            crush(int(sys.argv[2]), int(sys.argv[3]))
        elif what == "plastic":
            plastic()
        elif what == "errors":
            errors()
        else:
            raise Failure(f"unknown case {what}")
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
