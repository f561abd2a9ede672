"""Running-bond walls with half-integer units per course and split units,
and sets defined in the scene (interface.md, "running_bond additions" and
"Sets defined in the scene").

Every geometric claim is checked against the closed-form layout of
interface.md and against interfaces found again here, independently, from
the blocks' own coordinates (head joint: neighbours in a course across a gap
e; unit crack: across no gap; bed joint: rows that overlap in x).

  half        n = 1.5, 4.5, 7.5 and a whole n: course lengths, piece order, wall
              length L = N (l_u + e) + (l_u - e)/2, every head joint over the
              middle of a unit below, the interface list
  split       split_units on whole and half n: two l_u/2 blocks per full unit,
              half units whole, one zero-thickness crack per unit, sets hold halves
  stiff       a split wall whose cracks are 1e6 times stiffer than the joints
              deforms as the unsplit wall (to 1e-5 at m = 64), a softer one more
  sets        box and blocks sets against a selection of centroids made here;
              a load on a scene set reaches exactly its blocks
  errors      each bad set or units_per_course: one line naming the key
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import Failure, expect, rel_err, run, solve  # noqa: E402

LU, HU, E = 0.21, 0.052, 0.01
HALF = (LU - E) / 2


def scene(tmp, courses, n, split=False, extra="", unit="{law: dry, kn: 1.0e14, kt: 4.0e13}", loads="top_beam: [2.0e3, -5.0e3, 0]", m=4):
    path = os.path.join(tmp, "scene.yaml")
    with open(path, "w") as f:
        f.write(f"""title: running bond {n}
geometry:
  generator: running_bond
  depth: 0.1
  running_bond: {{courses: {courses}, units_per_course: {n}, unit_length: {LU}, unit_height: {HU}, split_units: {str(split).lower()}}}
joints:
  law: mortar
  E: 1.0e9
  nu: 0.2
  thickness: {E}
""" + (f"  unit: {unit}\n" if split else "") + f"""discretization: {{m: {m}}}
supports:
  foundation: {{u1: 0, u2: 0, w: 0}}
loads:
  {loads}
{extra}""")
    return path


def blocks_of(out):
    off, v = out["blocks/offsets"], out["blocks/vertices"]
    lo = np.array([v[off[b]:off[b + 1]].min(0) for b in range(len(off) - 1)])
    hi = np.array([v[off[b]:off[b + 1]].max(0) for b in range(len(off) - 1)])
    return lo, hi


def rows_of(lo, hi):
    """Courses (foundation and top beam excluded) as lists of block indices, bottom up, left to right."""
    ys = sorted(set(np.round(lo[1:-1, 1], 12)))
    return [sorted((b for b in range(1, len(lo) - 1) if abs(lo[b, 1] - y) < 1e-12), key=lambda b: lo[b, 0]) for y in ys]


def expected_interfaces(lo, hi, split_pairs):
    """(i, j) -> kind of every interface, found from the blocks: neighbours in a
    row across e (head) or across nothing (unit), rows that overlap (bed)."""
    want = {}
    nb = len(lo)
    for i in range(nb):
        for j in range(i + 1, nb):
            same_row = abs(lo[i, 1] - lo[j, 1]) < 1e-12 and abs(hi[i, 1] - hi[j, 1]) < 1e-12
            if same_row:
                gap = lo[j, 0] - hi[i, 0] if lo[j, 0] > lo[i, 0] else lo[i, 0] - hi[j, 0]
                if (i, j) in split_pairs:
                    expect(abs(gap) < 1e-12, f"the halves {i}, {j} of a unit are {gap} apart")
                    want[(i, j)] = "unit"
                elif abs(gap - E) < 1e-12:
                    want[(i, j)] = "head"
            elif abs(lo[j, 1] - hi[i, 1] - E) < 1e-12 or abs(lo[i, 1] - hi[j, 1] - E) < 1e-12:
                if min(hi[i, 0], hi[j, 0]) - max(lo[i, 0], lo[j, 0]) > 1e-12:
                    want[(i, j)] = "bed"
    return want


def check_layout(out, courses, n, split):
    N, halfn = int(np.floor(n)), n != int(n)
    L = N * (LU + E) + HALF if halfn else N * LU + (N - 1) * E
    lo, hi = blocks_of(out)
    expect(abs(hi[0, 0] - L) < 1e-12 and abs(hi[-1, 0] - L) < 1e-12, f"n = {n}: foundation and top beam end at {hi[0, 0]}, {hi[-1, 0]}, not L = {L}")
    rows = rows_of(lo, hi)
    expect(len(rows) == courses, f"n = {n}: {len(rows)} courses, not {courses}")
    split_pairs, unit_mid = set(), {}
    for k, row in enumerate(rows):
        lengths = hi[row, 0] - lo[row, 0]
        # pieces of the course as interface.md lays them out, before splitting
        if halfn:
            pieces = [LU] * N + [HALF] if k % 2 == 0 else [HALF] + [LU] * N
        else:
            pieces = [LU] * N if k % 2 == 0 else [HALF] + [LU] * (N - 1) + [HALF]
        want = [p for piece in pieces for p in ([LU / 2, LU / 2] if split and piece == LU else [piece])]
        expect(len(lengths) == len(want) and np.allclose(lengths, want, rtol=0, atol=1e-12),
               f"n = {n}, course {k}: block lengths {np.round(lengths, 6).tolist()}, expected {np.round(want, 6).tolist()}")
        expect(abs(lo[row[0], 0]) < 1e-12 and abs(hi[row[-1], 0] - L) < 1e-12, f"n = {n}, course {k}: spans [{lo[row[0], 0]}, {hi[row[-1], 0]}], not [0, {L}]")
        # the units of the course, with the middles a head joint above must sit over
        mids, p = [], 0
        for piece in pieces:
            if split and piece == LU:
                split_pairs.add((row[p], row[p + 1]))
                mids.append(hi[row[p], 0])
                p += 2
            else:
                if piece == LU:
                    mids.append(0.5 * (lo[row[p], 0] + hi[row[p], 0]))
                p += 1
        unit_mid[k] = np.array(mids)
    want = expected_interfaces(lo, hi, split_pairs)
    got = {tuple(int(x) for x in p): k for k, p in enumerate(out["interfaces/blocks"])}
    expect(set(got) == set(want), f"n = {n}: interfaces {sorted(set(got) ^ set(want))[:6]} differ from the ones found from the blocks")
    center, length = out["interfaces/center"], out["interfaces/length"]
    for (i, j), kind in want.items():
        k = got[(i, j)]
        if kind in ("head", "unit"):
            x = center[k, 0]
            expect(abs(x - (hi[i, 0] + (E / 2 if kind == "head" else 0))) < 1e-12 and abs(length[k] - HU) < 1e-12,
                   f"n = {n}: {kind} interface ({i}, {j}) at x = {x}, length {length[k]}")
        if kind == "head":
            # running bond: over the middle of a unit of the course below
            course = next(c for c, row in enumerate(rows) if i in row)
            if course > 0:
                d = np.min(np.abs(unit_mid[course - 1] - center[k, 0]))
                expect(d < 1e-12, f"n = {n}: head joint ({i}, {j}) of course {course} is {d} m from the middle of a unit below")
    kinds = [want[p] for p in want]
    return {kind: kinds.count(kind) for kind in ("bed", "head", "unit")}, lo, hi, split_pairs


def case_half(tmp):
    for n in (1.5, 4.5, 7.5, 4):
        out = solve(scene(tmp, 5, n))
        counts, lo, hi, _ = check_layout(out, 5, n, False)
        N = int(np.floor(n))
        per_course = [N + 1] * 5 if n != N else [N if k % 2 == 0 else N + 1 for k in range(5)]
        expect(len(lo) == sum(per_course) + 2, f"n = {n}: {len(lo)} blocks, expected {sum(per_course) + 2}")
        expect(counts["unit"] == 0, f"n = {n}: unit cracks without split_units")
        print(f"n = {n}: L = {hi[0, 0]:.4f} m, {len(lo)} blocks, {counts}")


def case_split(tmp):
    for n in (4.5, 3):
        out = solve(scene(tmp, 4, n, split=True))
        counts, lo, hi, pairs = check_layout(out, 4, n, True)
        N = int(np.floor(n))
        full = [N] * 4 if n != N else [N if k % 2 == 0 else N - 1 for k in range(4)]
        expect(counts["unit"] == sum(full), f"n = {n}: {counts['unit']} unit cracks, one per full unit = {sum(full)}")
        units = set(int(b) for b in out["sets/units"])
        halves = set(b for p in pairs for b in p)
        expect(halves <= units and len(units) == len(lo) - 2, f"n = {n}: the set units does not hold every block between foundation and top beam")
        bottom = set(int(b) for b in out["sets/bottom_course"])
        expect(bottom == set(rows_of(lo, hi)[0]), f"n = {n}: bottom_course {sorted(bottom)} is not the first course")
        print(f"n = {n}, split: {len(lo)} blocks, {counts}")


def top_beam(out):
    return out["blocks/displacement"][-1]


def case_stiff(tmp):
    # m = 64: a split unit's bed joints are two interfaces with m portions
    # each where the whole unit has one, so the two walls differ by the
    # stress discretisation too, O(1/m^2): measured 9.6e-4, 5.8e-5, 3.1e-6,
    # 3.5e-7 at m = 4, 16, 64, 256 with cracks 1e6 times stiffer than a
    # 10 mm joint of E = 1 GPa (kn 1e11), whose own compliance adds ~1e-6
    whole = top_beam(solve(scene(tmp, 6, 4.5, m=64)))
    stiff = top_beam(solve(scene(tmp, 6, 4.5, split=True, unit="{law: dry, kn: 1.0e17, kt: 4.0e16}", m=64)))
    soft = top_beam(solve(scene(tmp, 6, 4.5, split=True, unit="{law: dry, kn: 1.0e11, kt: 4.0e10}", m=64)))
    err = rel_err(stiff, whole)
    expect(err < 1e-5, f"split wall with stiff cracks: top beam {stiff} differs from the whole wall's {whole} by {err:.2e}")
    # cracks as stiff as the joints (kn 1e11): 24 more compliant vertical
    # interfaces in every unit, u1 grows far beyond the 1e-5 above (+28 %)
    expect(soft[0] > whole[0] * (1 + 1e-3), f"split wall with soft cracks: top beam u1 {soft[0]} not larger than the whole wall's {whole[0]}")
    print(f"top beam u1: whole {whole[0]:.6e}, stiff cracks {stiff[0]:.6e} (rel. diff {err:.1e}), soft cracks {soft[0]:.6e}")


def case_sets(tmp):
    box = [0.0, 0.0, 0.5, 0.2]
    sets = f"sets:\n  left: {{box: [{', '.join(map(str, box))}]}}\n  picked: {{blocks: [7, 3, 12]}}\n"
    out = solve(scene(tmp, 6, 4.5, extra=sets, loads="top_beam: [2.0e3, -5.0e3, 0]\n  left: [100, -300, 0]\n  picked: [0, 0, 7]"))
    c = out["blocks/centroid"]
    inside = np.flatnonzero((c[:, 0] >= box[0]) & (c[:, 0] <= box[2]) & (c[:, 1] >= box[1]) & (c[:, 1] <= box[3]))
    left = np.asarray(out["sets/left"])
    expect(np.array_equal(np.sort(left), inside) and len(inside) > 3, f"box set {left.tolist()} is not the blocks with centroid in the box {inside.tolist()}")
    expect(np.array_equal(np.sort(out["sets/picked"]), [3, 7, 12]), f"blocks set {out['sets/picked'].tolist()}")
    want = np.zeros((len(c), 3))
    want[-1] += [2.0e3, -5.0e3, 0]
    want[inside] += [100, -300, 0]
    want[[3, 7, 12]] += [0, 0, 7]
    expect(np.array_equal(out["blocks/load"], want), "the loads on scene sets do not reach exactly their blocks")
    # the run's own self-check holds equilibrium to 1e-10 of the forces
    # involved; 1e-8 of the loads leaves room for the reactions' round-off
    total = out["blocks/reaction"].sum(0)
    F = want.sum(0)
    expect(abs(total[0] + F[0]) < 1e-8 * np.abs(F).sum() and abs(total[1] + F[1]) < 1e-8 * np.abs(F).sum(),
           f"reactions {total[:2]} do not balance the loads {F[:2]}")
    print(f"box set: {len(inside)} blocks; loads balanced by the reactions to {abs(total[1] + F[1]):.1e} N")


def case_errors(tmp):
    cases = [
        ("sets:\n  left: {box: [5, 5, 6, 6]}\n", "sets.left.box set 'left' is empty: no block's centroid lies in the box [5, 5, 6, 6]"),
        ("sets:\n  one: {blocks: [500]}\n", "sets.one.blocks lists block 500 (element 1), but the geometry has"),
        ("sets:\n  one: {blocks: [1, 2, 1]}\n", "sets.one.blocks lists block 1 twice"),
        ("sets:\n  one: {blocks: [-1]}\n", "sets.one.blocks lists block -1"),
        ("sets:\n  top_beam: {blocks: [1]}\n", "sets.top_beam set 'top_beam' is already a set of the geometry"),
        ("sets:\n  x: {box: [0, 0, 1]}\n", "sets.x.box must hold 4 numbers"),
        ("sets:\n  x: {box: [1, 0, 0, 1]}\n", "sets.x.box needs x0 <= x1"),
        ("sets:\n  x: {boxx: [0, 0, 1, 1]}\n", "sets.x.boxx is not a key of a set"),
        ("sets:\n  x: {box: [0, 0, 1, 1], blocks: [1]}\n", "sets.x.blocks and box both define set 'x'"),
        ("sets:\n  x: 5\n", "sets.x is not a set definition"),
        ("sets: [a, b]\n", "sets must be a mapping (NAME: {box: [x0, y0, x1, y1]} or NAME: {blocks: [b, ...]}), got a sequence"),
    ]
    for extra, phrase in cases:
        code, out, err = run(scene(tmp, 3, 2.5, extra=extra), expect_ok=False)
        lines = err.strip().splitlines()
        expect(code == 1 and len(lines) == 1 and phrase in lines[0] and "scene.yaml:" in lines[0],
               f"{extra.strip()!r}: exit {code}, stderr {err.strip()!r}; expected one line with {phrase!r}")
    for n, phrase in ((2.25, "must be a whole or half number >= 1 (e.g. 10 or 4.5), got 2.25"), (0.5, "got 0.5"), (-3, "got -3")):
        code, out, err = run(scene(tmp, 3, n), expect_ok=False)
        expect(code == 1 and phrase in err and "geometry.running_bond.units_per_course" in err, f"units_per_course {n}: exit {code}, {err.strip()!r}")
    code, out, err = run(scene(tmp, 3, 2.5, split=True), ["-joints_unit_kn", "-1"], expect_ok=False)
    expect(code == 1 and "joints_unit_kn" in err, f"a negative unit crack stiffness: exit {code}, {err.strip()!r}")
    print(f"{len(cases) + 4} bad inputs, each one line naming the key")


if __name__ == "__main__":
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        try:
            globals()["case_" + sys.argv[1]](tmp)
        except Failure as e:
            print("FAIL", e)
            sys.exit(1)
    print("ok")
