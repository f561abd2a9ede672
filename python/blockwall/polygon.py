"""Plane polygons as blockwall reads them: the checks the geometry writer
and the DXF importer make before a file is written, with the tolerance
blockwall itself uses (docs/hdf5.md, "HDF5 geometry input"), so that what passes
here passes there.

    delta = 1e-6 x (median edge length) + 1e-12 x (largest |coordinate|)

A polygon is an (n, 2) array of its corners, each listed once (the last is
not the first again). It is *valid* when it has at least 3 corners,
consecutive corners more than delta apart, non-adjacent edges more than
delta apart (else it crosses or touches itself, or an edge folds back onto
its neighbour), and |area| > delta x perimeter / 2 (else its corners are
collinear). Two blocks *overlap* when their interiors share more than
delta x (the smaller perimeter) of area: faces pressed into each other by
less than delta are touching, not overlapping.

Overlap areas: clipping any polygon A by a convex polygon C
(Sutherland-Hodgman) gives exactly area(A n C), since the chords the
clipping adds along each clip line cancel in the shoelace sum; a
non-convex B is cut into triangles by ear clipping and
area(A n B) = sum over its triangles C of area(A n C). Candidate pairs come
from a uniform grid over the bounding boxes, so checking N blocks costs
O(N) for walls of similar blocks."""
from __future__ import annotations

import math

import numpy as np


class PolygonError(ValueError):
    """A defect of one polygon; `what` is the sentence naming it."""


def signed_area(p):
    """Shoelace area, > 0 for counter-clockwise corners."""
    p = np.asarray(p, float)
    x, y = p[:, 0] - p[0, 0], p[:, 1] - p[0, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def perimeter(p):
    p = np.asarray(p, float)
    return float(np.sum(np.hypot(*(np.roll(p, -1, axis=0) - p).T)))


def centroid(p):
    """Area centroid of a simple polygon."""
    p = np.asarray(p, float)
    o = p[0]
    q = p - o
    c = q[:, 0] * np.roll(q[:, 1], -1) - np.roll(q[:, 0], -1) * q[:, 1]
    a = 0.5 * c.sum()
    cx = np.sum((q[:, 0] + np.roll(q[:, 0], -1)) * c) / (6 * a)
    cy = np.sum((q[:, 1] + np.roll(q[:, 1], -1)) * c) / (6 * a)
    return o + np.array([cx, cy])


def counter_clockwise(p):
    """The polygon with counter-clockwise corners (reversed if clockwise, corner 0 kept first)."""
    p = np.asarray(p, float)
    if signed_area(p) < 0:
        p = np.concatenate([p[:1], p[:0:-1]])
    return p


def tolerance(polygons):
    """blockwall's delta for an assembly: 1e-6 x median edge + 1e-12 x max |coordinate|."""
    if not polygons:
        return 0.0
    edges = np.concatenate([np.hypot(*(np.roll(p, -1, axis=0) - p).T) for p in polygons])
    biggest = max(float(np.max(np.abs(p))) for p in polygons)
    return 1e-6 * float(np.median(edges)) + 1e-12 * biggest


def _point_segment(p, a, b):
    d, w = b - a, p - a
    l2 = float(d @ d)
    s = 0.0 if l2 == 0 else min(1.0, max(0.0, float(w @ d) / l2))
    return math.hypot(*(w - s * d))


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def segment_distance(a0, a1, b0, b1):
    """Distance between segments a0-a1 and b0-b1 (0 when they cross)."""
    o1, o2 = _cross(a1 - a0, b0 - a0), _cross(a1 - a0, b1 - a0)
    o3, o4 = _cross(b1 - b0, a0 - b0), _cross(b1 - b0, a1 - b0)
    if o1 * o2 < 0 and o3 * o4 < 0:
        return 0.0
    return min(_point_segment(a0, b0, b1), _point_segment(a1, b0, b1),
               _point_segment(b0, a0, a1), _point_segment(b1, a0, a1))


def check(p, delta):
    """Raise PolygonError naming the first defect of polygon p (corners
    numbered from 0 as given); returns nothing when p is valid."""
    p = np.asarray(p, float)
    if p.ndim != 2 or p.shape[1] != 2:
        raise PolygonError(f"corners must be an (n, 2) array, got shape {p.shape}")
    n = len(p)
    if not np.all(np.isfinite(p)):
        raise PolygonError("has a non-finite coordinate")
    if n < 3:
        raise PolygonError(f"has {n} corner{'s' if n != 1 else ''}; a block needs at least 3")
    for k in range(n):
        k1 = (k + 1) % n
        if math.hypot(*(p[k1] - p[k])) <= delta:
            if k1 == 0:
                raise PolygonError(f"is degenerate: its last corner repeats its first at ({p[0][0]:.6g}, {p[0][1]:.6g})")
            raise PolygonError(f"is degenerate: corners {k} and {k1} coincide at ({p[k][0]:.6g}, {p[k][1]:.6g})")
    for k in range(n):
        for m in range(k + 2, n):
            m1 = (m + 1) % n
            if m1 == k:
                continue
            if segment_distance(p[k], p[k + 1], p[m], p[m1]) <= delta:
                raise PolygonError(f"is self-intersecting: its edges {k}-{k + 1} and {m}-{m1} cross or touch "
                                   f"near ({p[k][0]:.6g}, {p[k][1]:.6g})")
    area, per = signed_area(p), perimeter(p)
    if abs(area) <= 0.5 * delta * per:
        raise PolygonError(f"is degenerate: zero area ({area:.3g} m^2 for a perimeter of {per:.6g} m), "
                           f"its corners are collinear")


def is_convex(p):
    """True for a counter-clockwise convex polygon."""
    d = np.roll(p, -1, axis=0) - p
    turn = d[:, 0] * np.roll(d[:, 1], -1) - d[:, 1] * np.roll(d[:, 0], -1)
    return bool(np.all(turn >= 0))


def triangles(p):
    """Ear clipping of a simple counter-clockwise polygon: a list of (3, 2) arrays."""
    idx = list(range(len(p)))
    out = []
    guard = 0
    while len(idx) > 3 and guard < 10 * len(p) ** 2:
        guard += 1
        n = len(idx)
        for k in range(n):
            a, b, c = p[idx[k - 1]], p[idx[k]], p[idx[(k + 1) % n]]
            if _cross(b - a, c - b) <= 0:  # reflex or flat corner: not an ear
                continue
            inside = False
            for m in idx:
                if m in (idx[k - 1], idx[k], idx[(k + 1) % n]):
                    continue
                q = p[m]
                if _cross(b - a, q - a) >= 0 and _cross(c - b, q - b) >= 0 and _cross(a - c, q - c) >= 0:
                    inside = True
                    break
            if not inside:
                out.append(np.array([a, b, c]))
                del idx[k]
                break
        else:  # no ear (round-off on a nearly flat corner): cut a fan from here
            break
    if len(idx) >= 3:
        for k in range(1, len(idx) - 1):
            out.append(np.array([p[idx[0]], p[idx[k]], p[idx[k + 1]]]))
    return out


def _clip_area(subject, clip):
    """Area of `subject` inside the convex counter-clockwise polygon `clip`."""
    poly = [np.asarray(v, float) for v in subject]
    nc = len(clip)
    for k in range(nc):
        if not poly:
            return 0.0
        c0, c1 = clip[k], clip[(k + 1) % nc]
        e = c1 - c0
        out = []
        for i in range(len(poly)):
            P, Q = poly[i], poly[(i + 1) % len(poly)]
            sp, sq = _cross(e, P - c0), _cross(e, Q - c0)
            if sp >= 0:
                out.append(P)
            if (sp >= 0) != (sq >= 0):
                out.append(P + sp / (sp - sq) * (Q - P))
        poly = out
    return abs(signed_area(np.array(poly))) if len(poly) >= 3 else 0.0


def overlap_area(a, b):
    """Area shared by the interiors of two simple counter-clockwise polygons."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    o = np.minimum(a.min(axis=0), b.min(axis=0))  # shift: fewer lost digits far from the origin
    a, b = a - o, b - o
    if is_convex(b):
        return _clip_area(a, b)
    if is_convex(a):
        return _clip_area(b, a)
    return sum(_clip_area(a, t) for t in triangles(b))


def overlaps(polygons, delta):
    """Pairs (i, j, area) of counter-clockwise polygons whose interiors
    share more than delta x (the smaller perimeter), i < j, in order."""
    n = len(polygons)
    if n < 2:
        return []
    lo = np.array([p.min(axis=0) for p in polygons])
    hi = np.array([p.max(axis=0) for p in polygons])
    cell = float(np.median(np.max(hi - lo, axis=1))) or 1.0
    grid = {}
    for b in range(n):
        i0, j0 = np.floor(lo[b] / cell).astype(int)
        i1, j1 = np.floor(hi[b] / cell).astype(int)
        if (i1 - i0 + 1) * (j1 - j0 + 1) > 4 * n:  # a block much larger than the cell: one coarse entry
            grid.setdefault(("big",), []).append(b)
            continue
        for i in range(i0, i1 + 1):
            for j in range(j0, j1 + 1):
                grid.setdefault((i, j), []).append(b)
    big = grid.pop(("big",), [])
    candidates = set()
    for members in grid.values():
        for x in range(len(members)):
            for y in range(x + 1, len(members)):
                candidates.add((min(members[x], members[y]), max(members[x], members[y])))
    for b in big:
        for c in range(n):
            if c != b:
                candidates.add((min(b, c), max(b, c)))
    found = []
    for i, j in sorted(candidates):
        if np.any(np.minimum(hi[i], hi[j]) - np.maximum(lo[i], lo[j]) <= delta):
            continue
        area = overlap_area(polygons[i], polygons[j])
        if area > delta * min(perimeter(polygons[i]), perimeter(polygons[j])):
            found.append((i, j, area))
    return found


def inside(a, b, delta):
    """True when polygon a lies inside polygon b (a hole of b): every corner
    of a off b's boundary is inside b, and there is one."""
    off = [q for q in np.asarray(a, float)
           if min(_point_segment(q, b[k], b[(k + 1) % len(b)]) for k in range(len(b))) > delta]
    return bool(off) and all(contains(b, q) for q in off)


def contains(p, q):
    """True when point q lies inside polygon p (even-odd rule)."""
    x, y = q
    inside = False
    n = len(p)
    for k in range(n):
        (x0, y0), (x1, y1) = p[k], p[(k + 1) % n]
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            inside = not inside
    return inside


def same_outline(a, b, delta):
    """True when two polygons have the same corners, whatever the first
    corner and the direction (a hatch drawn over its boundary polyline)."""
    if len(a) != len(b):
        return False
    a, b = counter_clockwise(a), counter_clockwise(b)
    d = np.hypot(*(b - a[0]).T)
    k = int(np.argmin(d))
    if d[k] > delta:
        return False
    return bool(np.all(np.hypot(*(np.roll(b, -k, axis=0) - a).T) <= delta))
