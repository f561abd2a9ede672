"""Block assemblies for the geometry tests, written as blockwall HDF5
geometry files (interface.md), with the interfaces each should have
computed here, independently of blockwall, from the construction.

Every builder returns (blocks, interfaces, sets): blocks a list of (n, 2)
vertex arrays; interfaces a list of (i, j, G, theta, length) with n from i
into j, t = (n2, -n1), theta = atan2(t2, t1), as model.md fixes them."""
import math
import os

import numpy as np

from bwrun import EXE, FAILING_ENV, call
import blockwall  # noqa: E402  (bwrun put this checkout's python/ on sys.path)

TEST_GEOMETRY = os.environ.get("BW_TEST_GEOMETRY", os.path.join(os.path.dirname(EXE), "test_geometry"))


def write_geometry(path, blocks, pairs=None, kn=None, kt=None, sets=None, depth=None):
    """The arrays exactly as given (unchecked: the tests feed blockwall broken
    and extreme geometry on purpose), with the package's writer."""
    blockwall.write_geometry(path, blocks, sets=sets, pairs=pairs, kn=kn, kt=kt, depth=depth, check=False)


def write_scene(path, geometry_file, joints=None, supports=None, loads=None, m=16, extra=""):
    """A scene for the file generator. supports: set -> dict of dof -> value;
    loads: set -> (F1, F2, M3)."""
    joints = joints or {"law": "mortar", "thickness": 0.01, "E": 1.0e9, "nu": 0.2}
    lines = ["title: geometry test",
             f"geometry: {{generator: file, file: {geometry_file}}}",
             "joints: {" + ", ".join(f"{k}: {v}" for k, v in joints.items()) + "}",
             f"discretization: {{m: {m}}}",
             "solver: {method: auto, rtol: 1.0e-10}",
             "output: {stresses: true, xdmf: false}"]
    if supports:
        lines.append("supports:")
        lines += [f"  {s}: {{" + ", ".join(f"{d}: {v}" for d, v in dofs.items()) + "}" for s, dofs in supports.items()]
    if loads:
        lines.append("loads:")
        lines += [f"  {s}: [{', '.join(repr(float(x)) for x in f)}]" for s, f in loads.items()]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n" + extra)


def rotation(deg):
    a = math.radians(deg)
    return np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])


def transform(blocks, deg, shift):
    R = rotation(deg)
    return [np.asarray(b, float) @ R.T + np.asarray(shift, float) for b in blocks]


def rect(x0, y0, x1, y1):
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], float)


def two_blocks(l=0.2, a=0.1, e=0.01):
    """The paper's section 3 pair, as the two_blocks generator makes it."""
    blocks = [rect(0, 0, l, a), rect(0, a + e, l, 2 * a + e)]
    return blocks, [(0, 1, (l / 2, a + e / 2), 0.0, l)], {"bottom": [0], "top": [1]}


def running_bond(courses, n, lu=0.21, hu=0.052, e=0.01, hf=0.1, hb=0.1):
    """interface.md's running bond: foundation, courses bottom-up (even:
    n full units; odd: half, n-1 full, half), top beam. Interfaces sorted by
    (i, j): bed joints over each x-overlap (theta = 0), head joints between
    neighbours in a course (n = +x, theta = -pi/2)."""
    L = n * lu + (n - 1) * e
    half = (lu - e) / 2
    blocks, rows = [rect(0, -e - hf, L, -e)], [[(0, 0.0, L)]]
    for k in range(courses):
        y0 = k * (hu + e)
        if k % 2 == 0:
            xs = [(i * (lu + e), i * (lu + e) + lu) for i in range(n)]
        else:
            xs = [(0.0, half)] + [(half + e + i * (lu + e), half + e + i * (lu + e) + lu) for i in range(n - 1)] + [(L - half, L)]
        row = []
        for x0, x1 in xs:
            row.append((len(blocks), x0, x1))
            blocks.append(rect(x0, y0, x1, y0 + hu))
        rows.append(row)
    ytop = (courses - 1) * (hu + e) + hu
    rows.append([(len(blocks), 0.0, L)])
    blocks.append(rect(0, ytop + e, L, ytop + e + hb))
    ybed = [-e / 2] + [k * (hu + e) + hu + e / 2 for k in range(courses)]
    inter = []
    for r in range(len(rows) - 1):  # bed joints: one merge sweep of two rows sorted by x
        lo, hi, a, b = rows[r], rows[r + 1], 0, 0
        while a < len(lo) and b < len(hi):
            (i, a0, a1), (j, b0, b1) = lo[a], hi[b]
            x0, x1 = max(a0, b0), min(a1, b1)
            if x1 - x0 > 1e-9:
                inter.append((i, j, ((x0 + x1) / 2, ybed[r]), 0.0, x1 - x0))
            if a1 < b1:
                a += 1
            else:
                b += 1
    for r in range(1, len(rows) - 1):
        yc = (r - 1) * (hu + e) + hu / 2
        for (i, _, a1), (j, b0, _) in zip(rows[r][:-1], rows[r][1:]):
            inter.append((i, j, ((a1 + b0) / 2, yc), -math.pi / 2, hu))
    inter.sort(key=lambda t: (t[0], t[1]))
    units = [b for row in rows[1:-1] for (b, _, _) in row]
    sets = {"foundation": [0], "top_beam": [len(blocks) - 1], "units": units,
            "bottom_course": [b for (b, _, _) in rows[1]], "all": list(range(len(blocks)))}
    return blocks, inter, sets


def arch(nv=9, rin=1.0, rout=1.3, e=0.01, springer=0.4, shapes=True):
    """A semicircular arch of nv voussoirs between two springers. Joint k
    (k = 0..nv) lies on the radial line at phi_k = pi k / nv; the faces on
    either side are parallel to it, e/2 off, so the interface runs along
    the line from rho0 = sqrt(rin^2 - e^2/4) to rho1 = sqrt(rout^2 - e^2/4):
    G = (rho0 + rho1)/2 (cos phi, sin phi), l = rho1 - rho0, and with n from
    the lower-phi block into the next, theta = phi_k. Block 0 is the right
    springer (below phi = 0), 1..nv the voussoirs, nv+1 the left springer
    (below phi = pi; n points down into it, theta = pi). With `shapes`, some
    voussoirs get extra vertices (pentagons, hexagons) and the springers are
    irregular pentagons, all faces unchanged."""
    r0, r1 = math.sqrt(rin**2 - e**2 / 4), math.sqrt(rout**2 - e**2 / 4)

    def face(phi, side):  # the two ends of a face on joint phi, offset side * e/2 along n_phi
        d, n = np.array([math.cos(phi), math.sin(phi)]), np.array([-math.sin(phi), math.cos(phi)])
        return r0 * d + side * e / 2 * n, r1 * d + side * e / 2 * n

    phis = [math.pi * k / nv for k in range(nv + 1)]
    y = -e / 2
    right = np.array([[r0, y - springer], [r1 + 0.1, y - springer], [r1 + 0.05, y - springer / 2], [r1, y], [r0, y]])
    left = np.array([[-r1 - 0.1, y - springer], [-r0, y - springer], [-r0, y], [-r1, y], [-r1 - 0.05, y - springer / 2]])
    blocks = [right]
    for k in range(nv):
        a_in, a_out = face(phis[k], +1)
        b_in, b_out = face(phis[k + 1], -1)
        poly = [a_in, a_out, b_out, b_in]  # counter-clockwise: out along the first face, back along the second
        if shapes and k % 3 == 1:  # pentagon: a vertex bulging out of the extrados
            mid = 0.5 * (a_out + b_out)
            poly = [a_in, a_out, mid * (1 + 0.04 / np.linalg.norm(mid)), b_out, b_in]
        elif shapes and k % 3 == 2:  # hexagon: the extrados and the intrados broken
            mo, mi = 0.5 * (a_out + b_out), 0.5 * (a_in + b_in)
            poly = [a_in, a_out, mo * (1 + 0.03 / np.linalg.norm(mo)), b_out, b_in, mi * (1 - 0.02 / np.linalg.norm(mi))]
        blocks.append(np.array(poly))
    blocks.append(left)
    inter = []
    for k in range(nv + 1):
        phi = phis[k]
        G = (r0 + r1) / 2 * np.array([math.cos(phi), math.sin(phi)])
        inter.append((k, k + 1, tuple(G), phi, r1 - r0))
    sets = {"springers": [0, nv + 1], "crown": [(nv + 1) // 2], "voussoirs": list(range(1, nv + 1))}
    return blocks, inter, sets


def geometry_only(scene, args=(), np_ranks=1, dump=None):
    """Run test_geometry: (returncode, stdout, stderr); with `dump`, the
    geometry blockwall built, as a dict of arrays."""
    cmd = [TEST_GEOMETRY, "-scene", scene, *map(str, args)]
    if dump:
        cmd += ["-dump", dump]
    if np_ranks > 1:
        cmd = [os.environ.get("BW_MPIEXEC", "mpiexec"), "--oversubscribe", "-n", str(np_ranks), *cmd]
    p = call(cmd, env=FAILING_ENV, what="test_geometry")  # bad geometry: no second's wait (bwrun.FAILING_ENV)
    out = None
    if dump and p.returncode == 0:
        d = blockwall.read_datasets(dump)
        out = {k: d[k] for k in ("blocks/centroid", "blocks/area", "interfaces/blocks", "interfaces/center",
                                 "interfaces/angle", "interfaces/length", "interfaces/kind")}
    return p.returncode, p.stdout, p.stderr, out


def angle_diff(a, b):
    """Difference of angles, wrapped to (-pi, pi] (pi and -pi are one direction)."""
    return np.angle(np.exp(1j * (np.asarray(a, float) - np.asarray(b, float))))
