"""The static theorem against the 3D pushover (issue "Out-of-plane
collapse"): python/blockwall/limit.py, a linear programme in scipy over the
stresses of the same portions (the friction cone bracketed by the pyramids
of K faces inscribed in it and circumscribed about it), independent of
blockwall's solver: its own equilibrium rows, its own volumes and
centroids (scipy's ConvexHull).

  block     the limit analysis itself against closed forms, on the block of
            tests/dim3/check_nonlinear3d.py tilted along X3: rocking
            (tan(phi) = 2) at (t/2)(1 - 1/m_b)/y from both pyramids (1e-9);
            sliding (tan(phi) = 0.3) at tan(phi) inside the bracket, whose
            width is 1 - cos(pi/K) or less.
  u_wall    examples/u_wall_tilt.yaml (the U-shaped wall with interlocked
            returns on a tilting table, associative joints psi = phi, no
            tension or cohesion), m = 4, m_b = 2, K = 16: the pushover's
            load factor at 5 mm for kn = 1e10, 1e11, 1e12 (kt = kn/2.5)
            grows with kn and never exceeds the circumscribed pyramid's
            multiplier (every converged pushover state is statically
            admissible, so it is a lower bound: 1e-9), and the stiffest
            lands inside the bracket [inscribed, circumscribed].

usage: check_limit3d.py block|u_wall
"""
import math
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))
from bwrun import Failure, expect, read, run  # noqa: E402
from blockwall import limit  # noqa: E402

EXAMPLES = os.path.join(HERE, "..", "..", "examples")
K = 32
# The U-wall's programme: each of K = 32's two took 50 s (scipy's HiGHS
# simplex); K = 16's pyramids, bracketing those of 32 (the 16-gon's edges
# are among the 32-gon's), 11-16 s (7 s since limit.py equilibrates the
# programme and uses HiGHS's interior point), the bracket [0.3309, 0.3339]
# around [0.3321, 0.3328].
K_U_WALL = 16


def bracket(path, tphi, direction, density, K=K):
    a = limit.read_assembly(path)
    F0, P = limit.gravity_loads(a, density, direction)
    lo, _ = limit.collapse_multiplier(a, F0, P, tanphi=tphi, K=K, inscribed=True)
    hi, _ = limit.collapse_multiplier(a, F0, P, tanphi=tphi, K=K, inscribed=False)
    expect(lo <= hi * (1 + 1e-12), f"inscribed pyramid {lo} above the circumscribed {hi}")
    return lo, hi


def block():
    sys.path.insert(0, HERE)
    import check_nonlinear3d as n3
    with tempfile.TemporaryDirectory() as tmp:
        res = n3.tilt(tmp, 2.0, math.pi / 2, 1e11, target=2e-6, steps=2)
        lo, hi = bracket(os.path.join(tmp, "out.h5"), 2.0, (0, 0, 1), 2000)
        want = (n3.S / 2) * (1 - 1 / 4) / n3.Y
        expect(abs(lo - want) <= 1e-9 * want and abs(hi - want) <= 1e-9 * want, f"rocking: bracket [{lo}, {hi}], closed form {want}")
        print(f"rocking along X3: limit analysis [{lo:.12g}, {hi:.12g}], (t/2)(1 - 1/m_b)/y = {want:.12g}")
        res = n3.tilt(tmp, 0.3, math.pi / 2, 1e11, target=2e-6, steps=2)
        lo, hi = bracket(os.path.join(tmp, "out.h5"), 0.3, (0, 0, 1), 2000)
        expect(lo <= 0.3 * (1 + 1e-9) and hi >= 0.3 * (1 - 1e-9) and hi / lo - 1 <= 1 / math.cos(math.pi / K) - 1 + 1e-9,
               f"sliding: bracket [{lo}, {hi}] should hold tan(phi) = 0.3 within 1 - cos(pi/K)")
        print(f"sliding along X3: limit analysis [{lo:.12g}, {hi:.12g}] holds tan(phi) = 0.3")
        del res


def u_wall():
    scene = os.path.join(EXAMPLES, "u_wall_tilt.yaml")
    expect(os.path.exists(os.path.join(EXAMPLES, "u_wall.h5")), "examples/u_wall.h5 missing (written by the build)")
    lams = []
    with tempfile.TemporaryDirectory() as tmp:
        for kn in (1e10, 1e11, 1e12):
            out = os.path.join(tmp, f"u_{kn:.0e}.h5")
            run(scene, ["-discretization_m", 4, "-discretization_m_b", 2, "-joints_kn", kn, "-joints_kt", kn / 2.5,
                        "-output_file", out, "-output_xdmf", "false", "-output_steps", "last"])
            r = read(out)
            lams.append(float(r["history/load_factor"][-1]))
            stop = r["solver"]["stop_reason"]
            expect((stop.decode() if isinstance(stop, bytes) else stop) == "target reached", f"kn {kn:g}: stop {stop}")
        lo, hi = bracket(out, 0.6, (0, 0, -1), 1800, K_U_WALL)
    for kn, lam in zip((1e10, 1e11, 1e12), lams):
        print(f"kn {kn:.0e}: pushover load factor at 5 mm {lam:.6f} ({lam / hi:.5f} of the circumscribed pyramid)")
    print(f"limit analysis (K = {K_U_WALL}): collapse multiplier in [{lo:.6f}, {hi:.6f}]")
    expect(all(lam <= hi * (1 + 1e-9) for lam in lams), f"a pushover load factor {max(lams):.9g} above the static theorem's bound {hi:.9g}")
    expect(lams[0] < lams[1] < lams[2], f"the load factor at 5 mm does not grow with kn: {lams}")
    expect(lo <= lams[2] <= hi * (1 + 1e-9), f"the stiffest pushover {lams[2]:.6f} outside the limit analysis' bracket [{lo:.6f}, {hi:.6f}]")


if __name__ == "__main__":
    try:
        {"block": block, "u_wall": u_wall}[sys.argv[1]]()
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
    print("ok")
