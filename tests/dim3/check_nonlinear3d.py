"""Nonlinear joints and pushover in three dimensions (model.md, "Three
dimensions", last item; issue "Out-of-plane collapse") against closed forms
and invariants. Each case says its reference and its tolerance's reason.

  sliding8      a block (0.2 x 0.1 x 0.1) under N = 1000 N with cohesion c and
                tan(phi), pushed in 8 horizontal directions of the X1-X3 plane
                (moment-free at the joint) under displacement control: the
                plateau is c A + N tan(phi) in every direction to 1e-10 (exact
                in the law: the circular cone is linear in rn, whose portions
                sum to -N), and the block slides along the push (u3/u1 =
                tan(theta) to 1e-10 of the slip).
  tilt_slide    the block on a fixed plane under its weight and the tilting
                table's load lambda * weight along (cos a, 0, sin a), a = 8
                azimuths, tan(phi) = 0.3 below every overturning limit: the
                collapse multiplier is tan(phi) in every azimuth (1e-10).
  tilt_rock     the same with tan(phi) = 2: the block overturns about its far
                edge, at the closed form of the portions,
                lambda = (b/2)(1 - 1/n)/y (b the base's width along the tilt,
                n its portions along it, y the centroid's height above the
                joint's plane): along X3 (b = 0.1, n = m_b) and along X1
                (b = 0.2, n = m), for three kn: never above the limit
                (1e-9), and reaching it (1e-9) once the joint's compressed
                row is the last one, at a displacement that falls like 1/kn.
  torsion       the block under uniform pressure p = N/A twisted about the
                joint's normal (rotation w2 prescribed), c = 0, psi = 0: the
                elastic torsion stiffness kt sum A_p rho_p^2 (1e-10, model.md's
                kt (I_t (1 - 1/m^2) + I_b (1 - 1/m_b^2)) for the rectangle) and
                the limit torque tan(phi) p sum A_p rho_p (1e-10), rho_p the
                distance of portion p's centroid from G, computed here from
                the grid (not from blockwall's output).
  wall_tilt     a free-standing running-bond wall (8 courses of 4 units,
                depth t = 0.1, no-tension dry joints) tilted along X3 to
                collapse: it overturns as a monolith about the far edge of
                its base joint, lambda = (t/2)(1 - 1/m_b) / (y_c - y_0), y_c
                the height of the centroid of every block above the base
                joint (from the blocks' boxes), y_0 the joint's plane: to
                1e-9, never above it.
  extrusion C   a 2D pushover of tests/nonlinear (C: sliding, dilatancy,
                overturning, softening; wall: a softening running-bond
                wall past its peak; j4d: examples/j4d.yaml, the TU
                Eindhoven wall; snapback: the stack of check_past_peak.py
                pulled apart under dissipation control through its
                snap-back) and its extrusion along X3 with in-plane loads (m_b =
                2): the same steps, load factor and monitor at every step
                (1e-8 of their largest value), the same final (u1, u2, w3)
                as (u1, u2, w), u3 = w1 = w2 = 0, and every row of b-portions
                in the 2D portions' states.
  ranks N       the tilted wall on 1 and N ranks: the same history (1e-8).
  errors        3D pushover keys: body_force with 2 numbers, monitor dof w,
                a 3-number pattern: one line naming the key, exit 1, no file.

usage: check_nonlinear3d.py CASE [ARG]
"""
import math
import os
import re
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(HERE, "..", "nonlinear"))
from bwrun import Failure, each, expect, read, rel_err, run  # noqa: E402

BLOCK = """geometry: {{generator: two_blocks, dimension: 3, depth: {s}, two_blocks: {{length: {l}, height: {a}}}}}
joints: {{law: dry, kn: {kn}, kt: {kt}, thickness: 0.01, strength: {{{strength}}}}}
discretization: {{m: {m}, m_b: {mb}}}
supports: {{bottom: {{u1: 0, u2: 0, u3: 0, w1: 0, w2: 0, w3: 0}}}}
loads: {{top: [0, {F2}, 0, 0, 0, 0]}}
{gravity}
analysis:
  type: pushover
  pushover: {{{pushover}}}
output: {{file: out.h5, stresses: true, xdmf: false}}
"""
L, S, A_H, E = 0.2, 0.1, 0.1, 0.01  # block length (X1), depth (X3), height, joint thickness
Y = A_H / 2 + E / 2                   # the top block's centroid above the joint's plane


def solve(tmp, text, args=(), ranks=1, name="scene.yaml"):
    path = os.path.join(tmp, name)
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(tmp, "out.h5")
    run(path, ["-output_file", out, *args], ranks)
    return read(out)


def block(tmp, strength, pushover, m=8, mb=4, kn=1e11, kt=4e10, F2=-1000.0, gravity=""):
    return solve(tmp, BLOCK.format(s=S, l=L, a=A_H, kn=kn, kt=kt, strength=strength, m=m, mb=mb, F2=F2,
                                   gravity=gravity, pushover=pushover))


def stop_reason(res):
    s = res["solver"]["stop_reason"]
    return s.decode() if isinstance(s, bytes) else str(s)


def sliding8():
    c, tphi, N, A = 1.0e4, 0.75, 1000.0, L * S
    cap = c * A + N * tphi
    with tempfile.TemporaryDirectory() as tmp:
        for d in range(8):
            th = d * math.pi / 4
            e1, e3 = math.cos(th), math.sin(th)
            # the push at the top block's centroid, its moment about the joint's G removed
            pattern = [e1, 0, e3, -Y * e3, 0, Y * e1]
            dof, comp = ("u1", e1) if abs(e1) >= abs(e3) else ("u3", e3)
            push = (f"loads: {{top: [{', '.join(f'{v:.17g}' for v in pattern)}]}}, control: displacement, "
                    f"monitor: {{set: top, dof: {dof}}}, target: {1e-4 * math.copysign(1, comp):.17g}, steps: 10")
            res = block(tmp, f"tension: 1.0e5, cohesion: {c}, friction: {tphi}", push)
            lam = res["history/load_factor"]
            e = abs(lam[-1] - cap) / cap
            expect(stop_reason(res) == "target reached", f"direction {d}: stop {stop_reason(res)}")
            expect(e <= 1e-10, f"direction {d} ({th:.3f} rad): plateau {lam[-1]:.12g}, c A + N tan(phi) = {cap:.12g} ({e:.2e})")
            expect(lam.max() <= cap * (1 + 1e-10), f"direction {d}: load factor {lam.max():.12g} above the capacity")
            u = res["blocks/displacement"][1]
            slip = math.hypot(u[0], u[2])
            ed = abs(u[0] * e3 - u[2] * e1) / slip
            expect(ed <= 1e-10 and u[0] * e1 + u[2] * e3 > 0, f"direction {d}: the block moved along ({u[0]:.6g}, {u[2]:.6g}), not the push")
            expect((res["portions/state"] >= 2).all(), f"direction {d}: not every portion slides: {res['portions/state']}")
            print(f"direction {d} ({math.degrees(th):5.1f} deg): plateau {lam[-1]:.12g} = c A + N tan(phi) ({e:.1e}), "
                  f"motion off the push {ed:.1e}")


def tilt(tmp, tphi, a, kn, mb=4, m=4, target=None, steps=20):
    """The block on the table tilted along azimuth a: its weight (density 2000) held,
    lambda times it along (cos a, 0, sin a); displacement control on the larger component."""
    e1, e3 = math.cos(a), math.sin(a)
    dof, comp = ("u1", e1) if abs(e1) >= abs(e3) else ("u3", e3)
    target = target or 2e-5
    push = (f"body_force: [{e1:.17g}, 0, {e3:.17g}], control: displacement, monitor: {{set: top, dof: {dof}}}, "
            f"target: {target * math.copysign(1, comp):.17g}, steps: {steps}")
    return block(tmp, f"tension: 0, cohesion: 0, friction: {tphi}", push, m=m, mb=mb, kn=kn, kt=kn / 2.5, F2=0.0,
                 gravity="gravity: {density: 2000}")


def tilt_slide():
    tphi = 0.3
    with tempfile.TemporaryDirectory() as tmp:
        for d in range(8):
            a = d * math.pi / 4 + 0.1  # off the axes too
            res = tilt(tmp, tphi, a, 1e11, target=1e-4)
            lam = res["history/load_factor"]
            e = abs(lam[-1] - tphi) / tphi
            expect(e <= 1e-10 and lam.max() <= tphi * (1 + 1e-10), f"azimuth {a:.3f}: plateau {lam[-1]:.12g}, tan(phi) {tphi} ({e:.2e})")
            print(f"azimuth {math.degrees(a):6.1f} deg: collapse multiplier {lam[-1]:.12g} = tan(phi) ({e:.1e})")


def tilt_rock():
    with tempfile.TemporaryDirectory() as tmp:
        for axis, a, b, n in (("X3", math.pi / 2, S, 4), ("X1", 0.0, L, 4)):
            limit = (b / 2) * (1 - 1 / n) / Y
            gaps = []
            for kn in (1e10, 1e11, 1e12):
                # the rotation at which the joint is down to its last row scales as 1/kn
                res = tilt(tmp, 2.0, a, kn, target=2e-5 * 1e10 / kn, steps=40)
                lam = res["history/load_factor"]
                expect(lam.max() <= limit * (1 + 1e-9), f"along {axis}, kn {kn:g}: lambda {lam.max():.12g} above the limit {limit:.12g}")
                # the first step at the limit: how far the top had to move
                at = np.nonzero(np.abs(lam - limit) <= 1e-9 * limit)[0]
                gaps.append((kn, abs(lam[-1] - limit) / limit, abs(res["history/monitor"][at[0]]) if len(at) else float("inf")))
                print(f"along {axis} (b = {b}, n = {n}), kn {kn:.0e}: last lambda {lam[-1]:.12g}, limit {limit:.12g}, "
                      f"reached at displacement {gaps[-1][2]:.3e}")
            expect(gaps[-1][1] <= 1e-9, f"along {axis}: the stiffest joint ends {gaps[-1][1]:.2e} from the limit")
            d = [g[2] for g in gaps]
            expect(d[0] > 5 * d[1] > 25 * d[2], f"along {axis}: the displacement at which the limit is reached does not fall like 1/kn: {d}")


def torsion():
    tphi, N, m, mb, kt = 0.6, 1000.0, 8, 4, 4e10
    xi = (np.arange(m) + 0.5) * L / m - L / 2
    eta = (np.arange(mb) + 0.5) * S / mb - S / 2
    X, Z = np.meshgrid(xi, eta)
    Ap, p = L * S / (m * mb), N / (L * S)
    limit = tphi * p * Ap * np.sum(np.hypot(X, Z))
    stiff = kt * Ap * np.sum(X ** 2 + Z ** 2)
    closed = kt * (S * L ** 3 / 12 * (1 - 1 / m ** 2) + L * S ** 3 / 12 * (1 - 1 / mb ** 2))
    expect(abs(stiff - closed) <= 1e-12 * closed, f"the grid's sum {stiff} against model.md's K_G term {closed}")
    with tempfile.TemporaryDirectory() as tmp:
        strength = f"tension: 0, cohesion: 0, friction: {tphi}"
        th_el = 0.5 * limit / stiff  # half way to the first slip of the outermost portion... well inside
        el = block(tmp, strength, f"loads: {{top: [0, 0, 0, 0, 1, 0]}}, control: displacement, monitor: {{set: top, dof: w2}}, "
                   f"target: {th_el:.17g}, steps: 2", m=m, mb=mb, kt=kt)
        lam, th = el["history/load_factor"], el["history/monitor"]
        expect((el["portions/state"] == 0).all(), "the elastic twist made a portion slide")
        e_el = abs(lam[-1] / th[-1] - stiff) / stiff
        expect(e_el <= 1e-10, f"torsion stiffness {lam[-1] / th[-1]:.12g}, kt sum A_p rho_p^2 = {stiff:.12g} ({e_el:.2e})")
        res = block(tmp, strength, "loads: {top: [0, 0, 0, 0, 1, 0]}, control: displacement, monitor: {set: top, dof: w2}, "
                    "target: 1.0e-3, steps: 20", m=m, mb=mb, kt=kt)
        lam = res["history/load_factor"]
        e = abs(lam[-1] - limit) / limit
        expect(e <= 1e-10 and lam.max() <= limit * (1 + 1e-10), f"limit torque {lam[-1]:.12g}, tan(phi) p sum A_p rho_p = {limit:.12g} ({e:.2e})")
        expect((res["portions/state"] == 2).all(), f"not every portion slides: {res['portions/state']}")
        rn = res["portions/stress"][:, 1]
        expect(np.max(np.abs(rn + p)) <= 1e-10 * p, "the pressure is not uniform under the twist")
    print(f"torsion: stiffness {e_el:.1e} from kt sum A_p rho_p^2 = {stiff:.6g} N m/rad; limit torque {lam[-1]:.10g} N m "
          f"= tan(phi) p sum A_p rho_p ({e:.1e})")


WALL3 = """geometry:
  generator: running_bond
  dimension: 3
  depth: 0.1
  running_bond: {{courses: 8, units_per_course: 4, unit_length: 0.21, unit_height: 0.052}}
joints: {{law: dry, kn: 1.0e12, kt: 4.0e11, thickness: 0.01, strength: {{tension: 0, cohesion: 0, friction: 0.6}}}}
discretization: {{m: 4, m_b: {mb}}}
supports:
  foundation: {{u1: 0, u2: 0, u3: 0, w1: 0, w2: 0, w3: 0}}
gravity: {{density: 1800}}
analysis:
  type: pushover
  pushover: {{body_force: [0, 0, 1], control: displacement, monitor: {{set: top_beam, dof: u3}}, target: 2.0e-4, steps: 40}}
output: {{file: out.h5, stresses: true, xdmf: false}}
"""


def wall_limit(res, mb):
    """(t/2)(1 - 1/m_b) / (y_c - y_0) from the blocks' boxes and the base joint."""
    v, off, c = res["blocks/vertices"], res["blocks/offsets"], res["blocks/centroid"]
    vol = np.array([np.prod(np.ptp(v[off[b]:off[b + 1]], axis=0)) for b in range(len(c))])
    fnd = set(res["sets/foundation"].tolist())
    above = np.array([b not in fnd for b in range(len(c))])
    ib, G = res["interfaces/blocks"], res["interfaces/center"]
    base = [k for k in range(len(ib)) if ib[k, 0] in fnd or ib[k, 1] in fnd]
    y0 = G[base, 1]
    expect(np.ptp(y0) == 0, f"the base joints are not on one plane: {y0}")
    t = np.ptp(v[:, 2])
    yc = np.sum(vol[above] * c[above, 1]) / np.sum(vol[above])
    return (t / 2) * (1 - 1 / mb) / (yc - y0[0])


def wall_tilt():
    with tempfile.TemporaryDirectory() as tmp:
        for mb in (2, 4):
            res = solve(tmp, WALL3.format(mb=mb))
            lam = res["history/load_factor"]
            limit = wall_limit(res, mb)
            e = abs(lam[-1] - limit) / limit
            expect(lam.max() <= limit * (1 + 1e-9), f"m_b = {mb}: lambda {lam.max():.12g} above the monolith's limit {limit:.12g}")
            expect(e <= 1e-9, f"m_b = {mb}: collapse multiplier {lam[-1]:.12g}, monolith overturning {limit:.12g} ({e:.2e})")
            st = res["portions/state"]
            print(f"m_b = {mb}: collapse multiplier {lam[-1]:.12g} = (t/2)(1 - 1/m_b)/(y_c - y_0) ({e:.1e}); "
                  f"portions open {np.sum(st & 1 > 0)} of {len(st)}")


# ------------------------------------------------------------ the extrusion of 2D pushovers

def to3d(text, mb=2):
    """A 2D scene of tests/nonlinear extruded along X3: dimension 3, m_b, six dofs."""
    t = re.sub(r"generator: (\w+), ", r"generator: \1, dimension: 3, ", text)
    t = re.sub(r"generator: (\w+)\n", r"generator: \1\n  dimension: 3\n", t)
    t = re.sub(r"discretization: \{m: (\d+)\}", rf"discretization: {{m: \1, m_b: {mb}}}", t)
    t = re.sub(r"discretization:\n  m: (\d+)\n", rf"discretization:\n  m: \1\n  m_b: {mb}\n", t)
    t = t.replace("{u1: 0, u2: 0, w: 0}", "{u1: 0, u2: 0, u3: 0, w1: 0, w2: 0, w3: 0}").replace("{w: 0}", "{w3: 0}")
    t = t.replace(", w: 0}", ", w3: 0}")
    t = re.sub(r"\[([^,\[\]]+), ([^,\[\]]+), ([^,\[\]]+)\]", r"[\1, \2, 0, 0, 0, \3]", t)
    t = re.sub(r"body_force: \[([^,\]]+), ([^,\]]+)\]", r"body_force: [\1, \2, 0]", t)
    return t.replace("dof: w}", "dof: w3}")


def extrusion(case):
    import check_nonlinear as cn
    if case == "sliding":
        extra = ("analysis:\n  type: pushover\n  pushover: {loads: {top: [1, 0, 0.055]}, control: displacement, "
                 "monitor: {set: top, dof: u1}, target: 1e-4, steps: 20}")
        text = cn.TWO.format(s=0.1, l=0.2, a=0.1, kn=1e11, kt=4e10, strength="tension: 1.0e5, cohesion: 1.0e4, friction: 0.75",
                             m=8, F1=0, F2=-1000, M3=0, extra=extra)
    elif case == "dilatancy":
        extra = ("analysis:\n  type: pushover\n  pushover: {loads: {top: [1, 0, 0.055]}, control: displacement, "
                 "monitor: {set: top, dof: u1}, target: 1e-4, steps: 20}")
        text = cn.TWO.format(s=0.1, l=0.2, a=0.1, kn=1e11, kt=4e10,
                             strength="tension: 1.0e5, cohesion: 1.0e4, friction: 0.75, dilatancy: 0.3", m=8, F1=0, F2=-1000, M3=0, extra=extra)
    elif case == "overturning":
        extra = ("analysis:\n  type: pushover\n  pushover: {loads: {top: [1, 0, 0]}, control: displacement, "
                 "monitor: {set: top, dof: w}, target: -3e-5, steps: 40}")
        text = cn.TWO.format(s=0.1, l=0.2, a=0.1, kn=1e13, kt=4e12, strength="tension: 0, cohesion: 0, friction: 10",
                             m=64, F1=0, F2=-1000, M3=0, extra=extra)
    elif case == "softening":
        extra = ("analysis:\n  type: pushover\n  pushover: {loads: {top: [0, 1, 0]}, control: displacement, "
                 "monitor: {set: top, dof: u2}, target: 7.2e-4, steps: 200}")
        text = cn.TWO.format(s=0.1, l=0.2, a=0.1, kn=1e11, kt=4e10,
                             strength="tension: 0.25e6, cohesion: 1.0e7, friction: 0.75, tension_energy: 18", m=4, F1=0, F2=0, M3=0, extra=extra)
    elif case == "wall":
        text = cn.WALL
    elif case == "j4d":
        # examples/j4d.yaml: split units, confinement by a prescribed settlement, 100 steps to 4 mm
        with open(os.path.join(HERE, "..", "..", "examples", "j4d.yaml")) as f:
            text = f.read().replace("  steps: every_5\n  xdmf: true", "  steps: last\n  xdmf: false")
    elif case == "snapback":
        text = None  # a stack of blocks written as files, below
    else:
        raise SystemExit(f"unknown extrusion case {case}")
    mb = 2
    with tempfile.TemporaryDirectory() as tmp:
        if case == "snapback":
            # tests/nonlinear/check_past_peak.py's stack pulled apart under dissipation
            # control (a snap-back), its blocks extruded into boxes over [0, depth]
            import check_past_peak as cp
            import blockwall as bw
            scene = cp.stack_scene(tmp, "dissipation", cp.GF * cp.AW / 120)
            with open(scene) as f:
                text = f.read()
            g = bw.Geometry()
            g.add_block(bw.box(0, -0.1, 0, cp.B, 0.0, cp.S), sets=["base"])
            for k in range(cp.N):
                y0 = cp.E + k * (cp.H + cp.E)
                x0, x1 = (0.001, cp.B - 0.001) if k == cp.N - 1 else (0.0, cp.B)
                g.add_block(bw.box(x0, y0, 0, x1, y0 + cp.H, cp.S), sets=["top", "column"] if k == cp.N - 1 else ["column"])
            g.write(os.path.join(tmp, "stack3.h5"))
        r2 = solve(tmp, text, name="two.yaml")
        t3 = to3d(text, mb)
        if case == "snapback":
            t3 = t3.replace("file: stack.h5", "file: stack3.h5")  # a 3D file: its vertices say so
        r3 = solve(tmp, t3, name="three.yaml")
    h2, h3 = (r2["history/load_factor"], r2["history/monitor"]), (r3["history/load_factor"], r3["history/monitor"])
    expect(len(h2[0]) == len(h3[0]), f"{case}: 2D {len(h2[0])} steps, 3D {len(h3[0])}")
    e = max(rel_err(h3[0], h2[0]), rel_err(h3[1], h2[1]))
    expect(e <= 1e-8, f"{case}: the 3D curve differs from the 2D one by {e:.2e}")
    q2, q3 = r2["blocks/displacement"], r3["blocks/displacement"]
    size = float(np.ptp(r2["blocks/vertices"], axis=0).max())
    w = np.array([1, 1, size])
    scale = np.max(np.abs(q2 * w))
    e_in = np.max(np.abs((q3[:, [0, 1, 5]] - q2) * w)) / scale
    e_out = np.max(np.abs(q3[:, [2, 3, 4]] * np.array([1, size, size]))) / scale
    expect(e_in <= 1e-8 and e_out <= 1e-8, f"{case}: final (u1, u2, w3) differ by {e_in:.2e}, out of plane {e_out:.2e}")
    st2, st3, off = r2["interfaces/state"], r3["portions/state"], r3["interfaces/portion_offsets"]
    bad = [k for k in range(len(st2)) if not (st3[off[k]:off[k + 1]].reshape(mb, -1) == st2[k][None]).all()]
    expect(not bad, f"{case}: portion states differ from 2D at interfaces {bad[:10]}")
    print(f"{case}: {len(h2[0])} steps, curves equal to {e:.1e}, final (u1, u2, w3) {e_in:.1e}, out of plane {e_out:.1e}, "
          f"states equal; peak {h2[0].max():.6g}")


def ranks(n):
    hist = []
    with tempfile.TemporaryDirectory() as tmp:
        for p in (1, n):
            res = solve(tmp, WALL3.format(mb=4), ranks=p)
            hist.append((res["history/load_factor"], res["history/monitor"]))
    (a1, m1), (a2, m2) = hist
    expect(len(a1) == len(a2), f"1 rank: {len(a1)} steps, {n} ranks: {len(a2)}")
    e = max(rel_err(a2, a1), rel_err(m2, m1))
    expect(e <= 1e-8, f"the tilted wall on 1 and {n} ranks differs by {e:.2e}")
    print(f"1 and {n} ranks: {len(a1)} steps, histories equal to {e:.1e}")


def errors():
    from bwrun import ENV, EXE, call
    cases = [
        ("body_force: [0, 1], control: load, target: 1", "analysis.pushover.body_force"),
        ("loads: {top: [1, 0, 0]}, control: load, target: 1", "analysis.pushover.loads"),
        ("loads: {top: [1, 0, 0, 0, 0, 0]}, control: displacement, monitor: {set: top, dof: w}, target: 1e-3",
         "analysis.pushover.monitor.dof"),
    ]
    with tempfile.TemporaryDirectory() as tmp:
        for push, key in cases:
            text = BLOCK.format(s=S, l=L, a=A_H, kn=1e11, kt=4e10, strength="tension: 0, cohesion: 0, friction: 0.6", m=4, mb=2,
                                F2=-1000, gravity="gravity: {density: 2000}", pushover=push)
            path = os.path.join(tmp, "bad.yaml")
            with open(path, "w") as f:
                f.write(text)
            out = os.path.join(tmp, "bad.h5")
            p = call([EXE, "-scene", path, "-output_file", out], env=ENV)
            lines = [s for s in p.stderr.splitlines() if s.strip()]
            expect(p.returncode == 1, f"{key}: exit {p.returncode}\n{p.stderr}")
            expect(len(lines) == 1 and key in lines[0] and "bad.yaml:" in lines[0], f"{key}: stderr is not one line naming it:\n{p.stderr}")
            expect(not os.path.exists(out), f"{key}: an output file was written")
            print(f"{key}: {lines[0]}")


def one(case, arg=None):
    if case == "extrusion":
        extrusion(arg)
    elif case == "ranks":
        ranks(int(arg))
    else:
        {"sliding8": sliding8, "tilt_slide": tilt_slide, "tilt_rock": tilt_rock, "torsion": torsion,
         "wall_tilt": wall_tilt, "errors": errors}[case]()


def main():
    """CASE [ARG] (extrusion NAME, ranks NP, or a case alone), or several
    specs CASE or CASE:ARG in one process, every one run and reported."""
    args = sys.argv[1:]
    if args[0] in ("extrusion", "ranks") and len(args) == 2:
        one(*args)
        return
    each(args, lambda spec: one(spec.partition(":")[0], spec.partition(":")[2] or None))


if __name__ == "__main__":
    try:
        main()
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
    print("ok")
