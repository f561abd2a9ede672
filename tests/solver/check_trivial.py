"""Zero-size corners: scenes where a rank, or the whole assembly, has no
block unknown. Each must run like any other scene: exit 0, nothing on
stderr, the answer of a closed form.

  linear NP        two blocks, every dof prescribed (the top block moved by
                   u1, u2, w), no loads, on NP ranks: no system is solved
                   (/solver method_used "none"), the stresses are the
                   prescribed motion's, per portion (model.md: dt = u1 +
                   w (a + e)/2, dn = u2, rt = kt dt, rn = kn (dn + w x_p),
                   exact for every m), the reactions are D^T r of those
                   stresses (the resultants T, N, M of the closed form moved
                   to each centroid), the residual is zero. Before: CHOLMOD
                   was handed a Schur complement of no rows and printed
                   "CHOLMOD error: invalid xtype" on a good run.
  linear3d NP      the same wall extruded (dimension 3): every b-portion
                   carries the 2D stresses, rb = 0 (model.md's invariant 1).
  pushover NP      every dof prescribed, joints with strengths the motion
                   stays below (so the laws run, elastic), load control to
                   lambda = 1 with the pattern on the top block: every step
                   has the stresses of the prescribed motion, the monitor
                   reads its prescribed value, lambda reaches the target,
                   and each step's reactions balance lambda P plus the
                   self-weight.
  support_pattern NP  the top block free under its weight on a Coulomb
                   joint, the pattern on the fixed bottom block only: every
                   step's displacements and stresses are step 0's (1e-12),
                   the bottom's reaction takes lambda P.
  empty_rank NP    two blocks on NP ranks, where one rank owns only the
                   fixed block (no block unknown) and, on 3 ranks, one owns
                   nothing: a linear case and a sliding pushover (plateau c A
                   + N tan(phi), exact for every m) equal to one rank's to
                   1e-10."""
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from bwrun import each, expect, read, rel_err, run  # noqa: E402

L, A, S, E_JOINT, KN, KT = 0.2, 0.1, 0.1, 0.01, 1.0e11, 4.0e10
U1, U2, W = 1.0e-5, -2.0e-6, 1.0e-4

SCENE = """title: zero-size corner
geometry: {{generator: two_blocks, depth: {s}, two_blocks: {{length: {l}, height: {a}}}{dim}}}
joints: {{law: dry, kn: {kn}, kt: {kt}, thickness: {e}{strength}}}
discretization: {{m: {m}{mb}}}
gravity: {{density: {rho}}}
supports:
  bottom: {bottom}
{top}{loads}{analysis}output: {{file: out.h5, stresses: true, xdmf: true{steps}}}
"""


def scene(dim=2, m=8, top=True, strength="", rho=0, loads="", analysis="", steps=""):
    names = ["u1", "u2", "w"] if dim == 2 else ["u1", "u2", "u3", "w1", "w2", "w3"]
    fixed = "{" + ", ".join(f"{n}: 0" for n in names) + "}"
    moved = {"u1": U1, "u2": U2, "w": W, "w3": W}
    topline = ""
    if top:
        topline = "  top: {" + ", ".join(f"{n}: {moved.get(n, 0)}" for n in names) + "}\n"
    return SCENE.format(s=S, l=L, a=A, e=E_JOINT, kn=KN, kt=KT, m=m, rho=rho,
                        dim=", dimension: 3" if dim == 3 else "", mb=", m_b: 2" if dim == 3 else "",
                        strength=f", strength: {{{strength}}}" if strength else "",
                        bottom=fixed, top=topline, loads=loads, analysis=analysis,
                        steps=", steps: all" if steps else "")


def go(tmp, text, ranks, name="scene.yaml"):
    path = os.path.join(tmp, name)
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(tmp, "out.h5")
    _, stdout, stderr = run(path, ["-output_file", out], ranks)
    expect(stderr.strip() == "", f"{ranks} rank(s): a good run printed on stderr:\n{stderr}")
    return read(out), stdout


def closed_form(m):
    """Per-portion (rt, rn), the resultants (T, N, M) and the reactions
    (bottom, top) of the prescribed motion, from model.md alone."""
    dt, dn, phi = U1 + W * (A + E_JOINT) / 2, U2, W
    x = -L / 2 + (np.arange(m) + 0.5) * L / m
    area = S * L / m
    rt = np.full(m, KT * dt)
    rn = KN * (dn + phi * x)
    f = np.array([area * rt.sum(), area * rn.sum(), area * (x * rn).sum()])
    G = np.array([L / 2, A + E_JOINT / 2])
    ci, cj = np.array([L / 2, A / 2]), np.array([L / 2, 1.5 * A + E_JOINT])

    def P(c):
        return np.array([[1, 0, -(G[1] - c[1])], [0, 1, G[0] - c[0]], [0, 0, 1]])
    # D^T r = B^T R^T H r with B = [-P_i, P_j], R = I (theta = 0)
    return np.column_stack([rt, rn]), f, -P(ci).T @ f, P(cj).T @ f


def linear(ranks, dim=2):
    m = 8
    with tempfile.TemporaryDirectory() as tmp:
        res, out = go(tmp, scene(dim=dim, m=m), ranks)
        sv = res["solver"]
        expect(sv["method_used"] == "none", f"method_used {sv['method_used']!r}, expected 'none' (no block unknown)")
        expect("method: none" in out, f"the summary does not say no system was solved:\n{out}")
        expect(sv["residual"] <= 1e-14, f"residual {sv['residual']:.3e}")
        stress, f, rb, rt = closed_form(m)
        disp = res["blocks/displacement"]
        if dim == 2:
            got = res["interfaces/stress"][0]
            want_disp = [U1, U2, W]
            react = res["blocks/reaction"]
        else:
            # portions t-fastest: m along t, then m_b = 2 rows along b
            got3 = res["portions/stress"]
            expect(np.max(np.abs(got3[:, 2])) <= 1e-9 * np.max(np.abs(stress)), f"rb is not zero: {np.max(np.abs(got3[:, 2])):.3e}")
            for row in range(2):
                e = rel_err(got3[row * m:(row + 1) * m, :2], stress)
                expect(e <= 1e-12, f"3D b-row {row}: stresses off the 2D closed form by {e:.2e}")
            got = got3[:m, :2]
            want_disp = [U1, U2, 0, 0, 0, W]
            # in-plane components of the 3D reactions: F1, F2, M3
            react = res["blocks/reaction"][:, [0, 1, 5]]
        expect(rel_err(disp[1], want_disp) == 0 and np.all(disp[0] == 0), f"displacements {disp}")
        e = rel_err(got, stress)
        expect(e <= 1e-12, f"stresses off the closed form by {e:.2e}")
        er = max(rel_err(react[0], rb), rel_err(react[1], rt))
        expect(er <= 1e-10, f"reactions {react} against the closed form {rb}, {rt}: {er:.2e}")
        print(f"{dim}D, {ranks} rank(s): method none, stresses to {e:.1e}, reactions to {er:.1e}; T, N, M = {f}")


def pushover(ranks):
    m, P1 = 8, 1000.0
    analysis = ("analysis:\n  type: pushover\n  pushover: {loads: {top: [%g, 0, 0]}, control: load, target: 1.0, steps: 4}\n" % P1)
    with tempfile.TemporaryDirectory() as tmp:
        # strengths the prescribed motion stays below (its portions reach
        # kn dn = 1e6 Pa in tension): the joint laws run, elastic
        res, out = go(tmp, scene(m=m, rho=2000, strength="tension: 1.0e7, cohesion: 1.0e8, friction: 0.6", analysis=analysis, steps=True), ranks)
        lam, mon = res["history/load_factor"], res["history/monitor"]
        expect(len(lam) == 5 and abs(lam[-1] - 1.0) <= 1e-12, f"load factors {lam}")
        # the default monitor: the pattern's largest component, u1 of the
        # top block, which reads its prescribed value
        sv = res["solver"]
        expect(sv["monitor_dof"] == "u1" and sv["monitor_set"] == "block 1", f"monitor {sv['monitor_dof']} of {sv['monitor_set']}, expected u1 of block 1")
        expect(np.all(mon == U1), f"monitor {mon}: the prescribed u1 = {U1} at every step")
        stress, _, _, _ = closed_form(m)
        weight = 2000 * 9.81 * L * A * S
        for k in range(5):
            g = f"steps/{k:06d}"
            e = rel_err(res[g + "/interfaces/stress"][0], stress)
            expect(e <= 1e-12, f"step {k}: stresses off the prescribed motion's by {e:.2e}")
            react = res[g + "/blocks/reaction"]
            total = react.sum(axis=0)[:2] + np.array([lam[k] * P1, -2 * weight])
            expect(np.max(np.abs(total)) <= 1e-9 * (P1 + weight + np.max(np.abs(react))), f"step {k}: reactions {react} do not balance lambda P and the weight")
        print(f"pushover, every dof prescribed, {ranks} rank(s): {len(lam)} steps to lambda {lam[-1]}, monitor {mon[0]}, stresses of the prescribed motion at every step")


def support_pattern(ranks):
    m, P1 = 8, 1000.0
    analysis = ("analysis:\n  type: pushover\n  pushover: {loads: {bottom: [%g, 0, 0]}, control: load, target: 1.0, steps: 4}\n" % P1)
    with tempfile.TemporaryDirectory() as tmp:
        res, out = go(tmp, scene(m=m, top=False, rho=2000, strength="tension: 0, cohesion: 0, friction: 0.6", analysis=analysis, steps=True), ranks)
        lam = res["history/load_factor"]
        expect(len(lam) == 5 and abs(lam[-1] - 1.0) <= 1e-12, f"load factors {lam}")
        d0, s0 = res["steps/000000/blocks/displacement"], res["steps/000000/interfaces/stress"]
        expect(np.max(np.abs(d0[1])) > 0, "the top block did not settle under its weight at step 0")
        for k in range(1, 5):
            g = f"steps/{k:06d}"
            ed = rel_err(res[g + "/blocks/displacement"], d0)
            es = rel_err(res[g + "/interfaces/stress"], s0)
            expect(ed <= 1e-12 and es <= 1e-12, f"step {k}: the free block moved ({ed:.2e}) or its joint changed ({es:.2e}) under a pattern on the support")
            rx = res[g + "/blocks/reaction"][0, 0]
            expect(abs(rx + lam[k] * P1) <= 1e-9 * P1, f"step {k}: the support's F1 reaction {rx}, expected {-lam[k] * P1}")
        print(f"pattern on the support, {ranks} rank(s): nothing moved over {len(lam)} steps, the support took lambda P")


def empty_rank(ranks):
    N, c, tanphi, m = 2000.0, 0.2e6, 0.6, 8
    cap = c * L * S + N * tanphi
    # pushed at the centroid, with the moment that makes the push
    # moment-free at the joint (its arm (a + e)/2 above G): no rocking
    analysis = ("analysis:\n  type: pushover\n  pushover: {loads: {top: [1, 0, %.17g]}, control: displacement,"
                " monitor: {set: top, dof: u1}, target: 2.0e-4, steps: 8}\n" % ((A + E_JOINT) / 2))
    linear_text = scene(m=m, top=False, loads=f"loads: {{top: [1000, {-N}, 5]}}\n")
    push_text = scene(m=m, top=False, strength=f"tension: 0, cohesion: {c}, friction: {tanphi}",
                      loads=f"loads: {{top: [0, {-N}, 0]}}\n", analysis=analysis)
    with tempfile.TemporaryDirectory() as tmp:
        one, _ = go(tmp, linear_text, 1)
        many, _ = go(tmp, linear_text, ranks)
        for key in ("blocks/displacement", "blocks/reaction", "interfaces/stress", "interfaces/resultant"):
            e = rel_err(many[key], one[key])
            expect(e <= 1e-10, f"linear: {key} on {ranks} ranks differs from 1 rank by {e:.2e}")
        one, _ = go(tmp, push_text, 1)
        many, _ = go(tmp, push_text, ranks)
        lam1, lamn = one["history/load_factor"], many["history/load_factor"]
        expect(len(lam1) == len(lamn) and rel_err(lamn, lam1) <= 1e-10, f"pushover histories differ: {lam1} / {lamn}")
        expect(abs(lamn[-1] - cap) <= 1e-9 * cap, f"sliding plateau {lamn[-1]:.10g}, closed form c A + N tan(phi) = {cap:.10g}")
        print(f"{ranks} ranks (one with no block unknown): linear and pushover equal to 1 rank's; plateau {lamn[-1]:.8g} = c A + N tan(phi)")


CASES = {"linear": lambda n: linear(n, 2), "linear3d": lambda n: linear(n, 3), "pushover": pushover,
         "support_pattern": support_pattern, "empty_rank": empty_rank}

if __name__ == "__main__":
    # CASE RANKS, or specs CASE:RANKS... in one process, every one run and reported
    args = sys.argv[1:]
    specs = [f"{args[0]}:{args[1]}"] if len(args) == 2 and ":" not in args[0] else args
    parsed = [spec.partition(":") for spec in specs]
    if not specs or any(c not in CASES or not n.isdigit() for c, _, n in parsed):
        print(f"FAIL usage: check_trivial.py {{{'|'.join(CASES)}}} RANKS, or CASE:RANKS... (got {args})")
        sys.exit(1)
    each(specs, lambda spec: CASES[spec.partition(":")[0]](int(spec.partition(":")[2])))
