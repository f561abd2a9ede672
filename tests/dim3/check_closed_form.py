"""The paper's two blocks in 3D under all six load components, against the
closed form of model.md ("Three dimensions"), for several portion grids.

Block 1 (top, l x a x s) on block 0 (fixed), bed joint of thickness e:
G = (l/2, a + e/2, s/2), frame t = X1, n = X2, b = X3, block 1's centroid
h = a/2 + e/2 above G. Equilibrium of block 1 about G gives the joint's
resultants (T, N, Tb, Mt, Mn, Mb) = (F1, F2, F3, M1 + h F3, M2, M3 - h F1);
the discrete joint stiffness of an l x s rectangle cut into m x m_b cells is
    K_G = diag(kt A, kn A, kt A, kn I_b (1 - 1/m_b^2),
               kt (I_t (1 - 1/m^2) + I_b (1 - 1/m_b^2)), kn I_t (1 - 1/m^2)),
I_t = s l^3/12, I_b = l s^3/12, so dG = K_G^-1 f, and block 1 moves by
    (u1, u2, u3, w1, w2, w3) = (dt - h phib, dn, db + h phit, phit, phin, phib).
Per portion (centroid xi along t, eta along b, t index fastest):
    rt = kt (dt + phin eta), rn = kn (dn + phib xi - phit eta), rb = kt (db - phin xi).
Asserted to 1e-10 relative (displacements, rotations times l, stresses,
resultants); the reactions of block 0 balance the loads.

usage: check_closed_form.py M M_B [RANKS]
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import Failure, expect, rel_err, solve  # noqa: E402

SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "two_blocks.yaml")
L, A, S, E_J, E, NU = 0.2, 0.1, 0.1, 0.01, 1.0e9, 0.2
LOAD = np.array([700.0, -1500.0, 400.0, 30.0, -20.0, 45.0])  # F1, F2, F3, M1, M2, M3


def closed_form(m, mb):
    kn, kt = E / E_J, E / (2 * (1 + NU) * E_J)
    area, it, ib, h = L * S, S * L**3 / 12, L * S**3 / 12, A / 2 + E_J / 2
    f1, f2, f3, m1, m2, m3 = LOAD
    f = np.array([f1, f2, f3, m1 + h * f3, m2, m3 - h * f1])
    kg = np.array([kt * area, kn * area, kt * area, kn * ib * (1 - 1 / mb**2),
                   kt * (it * (1 - 1 / m**2) + ib * (1 - 1 / mb**2)), kn * it * (1 - 1 / m**2)])
    dt, dn, db, pt, pn, pb = f / kg
    q = np.array([dt - h * pb, dn, db + h * pt, pt, pn, pb])
    xi = -L / 2 + (np.arange(m) + 0.5) * L / m
    eta = -S / 2 + (np.arange(mb) + 0.5) * S / mb
    X, Y = np.meshgrid(xi, eta)  # rows: eta (b index), columns: xi (t index fastest)
    X, Y = X.ravel(), Y.ravel()
    stress = np.stack([kt * (dt + pn * Y), kn * (dn + pb * X - pt * Y), kt * (db - pn * X)], axis=1)
    return q, f, stress


def main():
    m, mb = int(sys.argv[1]), int(sys.argv[2])
    ranks = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    res = solve(SCENE, ["-discretization_m", m, "-discretization_m_b", mb, "-loads_top", ",".join(map(str, LOAD))], ranks)
    q_ref, f_ref, s_ref = closed_form(m, mb)
    w = np.array([1, 1, 1, L, L, L])
    q = res["blocks/displacement"][1]
    e_q = np.max(np.abs((q - q_ref) * w)) / np.max(np.abs(q_ref * w))
    e_f = rel_err(res["interfaces/resultant"][0] / w, f_ref / w)
    e_s = rel_err(res["portions/stress"], s_ref)
    expect(res["interfaces/portion_offsets"][-1] == m * mb, f"{m * mb} portions expected, got {res['interfaces/portion_offsets'][-1]}")
    expect(e_q < 1e-10, f"m {m}, m_b {mb}: displacement {q} vs closed form {q_ref}: {e_q:.2e}")
    expect(e_f < 1e-10, f"m {m}, m_b {mb}: resultants {res['interfaces/resultant'][0]} vs {f_ref}: {e_f:.2e}")
    expect(e_s < 1e-10, f"m {m}, m_b {mb}: portion stresses vs closed form: {e_s:.2e}")
    expect(np.all(res["blocks/displacement"][0] == 0), "block 0 is fixed")
    reac = res["blocks/reaction"][0]
    # block 0's reaction balances the load moved to its centroid (arm 2h + ... = a + e along X2)
    arm = np.array([0.0, A + E_J, 0.0])
    f, mom = LOAD[:3], LOAD[3:] + np.cross(arm, LOAD[:3])
    e_r = rel_err(reac / w, -np.concatenate([f, mom]) / w)
    expect(e_r < 1e-10, f"reaction {reac} does not balance the load: {e_r:.2e}")
    print(f"m {m}, m_b {mb}, {ranks} rank(s): displacement {e_q:.1e}, resultants {e_f:.1e}, stresses {e_s:.1e}, reaction {e_r:.1e}")


if __name__ == "__main__":
    try:
        main()
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
