#!/usr/bin/env python3
"""A dry-stone wall of irregular stones, written as blockwall geometry with
the Python package: examples/stones.yaml runs it.

    python3 examples/stones.py [GEOMETRY.h5] [--seed N]   # default: stones.h5 beside this script
    mpiexec -n 2 build/bin/blockwall -scene examples/stones.yaml

How the stones are drawn (so that blockwall finds every contact): the
courses are separated by bed lines, each a polyline over the same kinks
x_0 = 0 < x_1 < ... < x_K = L with random heights; the head joints of a
course are straight, slanted segments from its lower bed line to its upper
one, staggered from course to course. A stone is the region between two
bed lines and two head joints: its bottom runs along the lower bed line
through every kink in its span, its top back along the upper one, so two
stones on either side of a bed line face each other along collinear pieces
of it and two neighbours in a course along their common head joint. The
joints are dry (thickness 0): faces touch, and blockwall's interfaces are
the overlaps of facing edges. A foundation under the flat first bed line
and a capping beam over the flat last one close the wall.

Sets: foundation, stones, cap."""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "python"))
import blockwall as bw  # noqa: E402


def stone_wall(length=2.0, courses=6, course_height=0.25, stones_per_course=5, kinks=8, bed_jitter=0.04,
               head_jitter=0.06, slant=0.05, foundation_height=0.3, cap_height=0.15, depth=0.4, seed=7):
    """The wall as a bw.Geometry (stones in courses from the bottom, each from the left)."""
    rng = np.random.default_rng(seed)
    xk = np.linspace(0.0, length, kinks + 1)
    beds = [np.full(kinks + 1, k * course_height) for k in range(courses + 1)]
    for k in range(1, courses):  # inner bed lines wander; the first and the last stay flat
        beds[k] = beds[k] + rng.uniform(-bed_jitter, bed_jitter, kinks + 1)

    def on_bed(k, x):
        return float(np.interp(x, xk, beds[k]))

    def away_from_kinks(x):  # no head joint within 3 cm of a kink: no sliver edges
        near = xk[np.argmin(np.abs(xk - x))]
        return x if abs(x - near) >= 0.03 else near + np.copysign(0.03, x - near if x != near else 1.0)

    g = bw.Geometry(depth=depth)
    g.add_block(bw.rectangle(0.0, -foundation_height, length, 0.0), sets=["foundation"])
    width = length / stones_per_course
    for k in range(courses):
        shift = 0.5 * width if k % 2 else 0.0
        inner = [shift + i * width for i in range(1, stones_per_course + 1) if 0 < shift + i * width < length - 0.5 * width]
        heads = [(0.0, 0.0)]
        for x in inner:
            xb = away_from_kinks(x + rng.uniform(-head_jitter, head_jitter))
            xt = away_from_kinks(xb + rng.uniform(-slant, slant))
            heads.append((xb, xt))
        heads.append((length, length))
        for (lb, lt), (rb, rt) in zip(heads[:-1], heads[1:]):
            bottom = [(lb, on_bed(k, lb))] + [(x, on_bed(k, x)) for x in xk if lb < x < rb] + [(rb, on_bed(k, rb))]
            top = [(rt, on_bed(k + 1, rt))] + [(x, on_bed(k + 1, x)) for x in xk[::-1] if lt < x < rt] + \
                  [(lt, on_bed(k + 1, lt))]
            g.add_block(bottom + top, sets=["stones"])
    top = courses * course_height
    g.add_block(bw.rectangle(0.0, top, length, top + cap_height), sets=["cap"])
    return g


if __name__ == "__main__":
    here = os.path.dirname(os.path.realpath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("geometry", nargs="?", default=os.path.join(here, "stones.h5"))
    ap.add_argument("--seed", type=int, default=7)
    a = ap.parse_args()
    g = stone_wall(seed=a.seed)
    g.write(a.geometry)
    print(f"{a.geometry}: {len(g.blocks)} blocks ({len(g.sets['stones'])} stones, foundation, cap)")
