#!/usr/bin/env python3
"""A semicircular arch of voussoirs on two springers, written as blockwall
geometry with the Python package: examples/arch.yaml runs it.

    python3 examples/arch.py [GEOMETRY.h5]     # default: arch.h5 beside this script
    mpiexec -n 2 build/bin/blockwall -scene examples/arch.yaml

The arch: intrados radius r_in, extrados r_out, centred at the origin,
n voussoirs between n+1 radial joints at phi_k = pi k / n, each joint a
mortar layer of thickness e. The faces on either side of joint k are
parallel to its radial line, e/2 off it, so the two faces overlap along
the line from rho0 = sqrt(r_in^2 - e^2/4) to rho1 = sqrt(r_out^2 - e^2/4):
blockwall finds the interface with G = (rho0 + rho1)/2 (cos phi_k,
sin phi_k), l = rho1 - rho0, and its n pointing from the lower-phi block
into the next (theta = phi_k). Joints 0 and n sit on the springers, whose
tops are the horizontal faces y = -e/2 under the first and last voussoir.

Blocks: 0 the right springer, 1..n the voussoirs (from the right), n+1 the
left springer. Sets: springers, voussoirs, crown (the middle voussoir, n odd)."""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "python"))
import blockwall as bw  # noqa: E402

SPAN = dict(n=15, r_in=1.0, r_out=1.3, e=0.01, springer_height=0.5, springer_width=0.6, depth=0.5)


def arch(n=15, r_in=1.0, r_out=1.3, e=0.01, springer_height=0.5, springer_width=0.6, depth=0.5):
    """The arch as a bw.Geometry, and its joints [(i, j, G, theta, l)] in closed form."""
    rho0, rho1 = math.sqrt(r_in**2 - e**2 / 4), math.sqrt(r_out**2 - e**2 / 4)

    def face(phi, side):  # the face on joint phi, offset side * e/2 along the joint's normal
        d, nrm = np.array([math.cos(phi), math.sin(phi)]), np.array([-math.sin(phi), math.cos(phi)])
        return rho0 * d + side * e / 2 * nrm, rho1 * d + side * e / 2 * nrm

    g = bw.Geometry(depth=depth)
    y = -e / 2
    g.add_block(bw.rectangle(rho0, y - springer_height, rho0 + springer_width, y), sets=["springers"])
    phis = [math.pi * k / n for k in range(n + 1)]
    for k in range(n):
        a_in, a_out = face(phis[k], +1)
        b_in, b_out = face(phis[k + 1], -1)
        g.add_block([a_in, a_out, b_out, b_in], sets=["voussoirs"] + (["crown"] if k == n // 2 else []))
    g.add_block(bw.rectangle(-rho0 - springer_width, y - springer_height, -rho0, y), sets=["springers"])
    joints = [(k, k + 1, (rho0 + rho1) / 2 * np.array([math.cos(p), math.sin(p)]), p, rho1 - rho0)
              for k, p in enumerate(phis)]
    return g, joints


if __name__ == "__main__":
    here = os.path.dirname(os.path.realpath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "arch.h5")
    g, joints = arch(**SPAN)
    g.write(out)
    print(f"{out}: {len(g.blocks)} blocks ({SPAN['n']} voussoirs, 2 springers), {len(joints)} joints for blockwall to find")
