"""tools/plot on a 3D pushover: the capacity curve and the crack pattern at
the peak and at the end, the blocks warped by their displacement with the
failed portions coloured on the joints. Two tilted running-bond walls of
check_nonlinear3d.py, every 4th step written: A (no tension, no cohesion:
sliding and open-and-sliding portions) and B (a little tension and
cohesion, Lourenco's cap at fc = 15 kPa: open, open-and-sliding and
crushed portions, state bit 4), so that the states 1 to 4 are all drawn.

  matplotlib   the fallback renderer (no ParaView).
  pvpython     ParaView's pvpython, off-screen (registered where it is).

Checked against the HDF5 file, by this script's own arithmetic:
- the portions rebuilt from the interface polygons: their number per
  interface is /interfaces/portion_offsets, their areas and centroids
  /portions/area and /portions/center (1e-12 of the interface's area and
  1e-9 of the wall's size);
- the states drawn are /portions/state of the step drawn (the end, or
  /steps/NNNNNN at the written step nearest to the peak), the legend
  counts them ("NAME: COUNT" for every state 0..3, and the cap's where they
  occur), and the portions given to the renderer are exactly the failed
  ones (state != 0), each at its joint's centre G + xi t + eta b moved by
  the mean of its two blocks' rigid motions times the scale (1e-9 of the
  wall's size);
- every block is drawn: its faces given to the renderer are at its
  vertices x + s (u + w x (x - c)) of the step drawn (1e-12 of the size),
  and their areas add up to the area of the convex hull of those points
  (1e-9), each block as many faces as its hull has planes;
- what the renderer drew: matplotlib, its collection's polygons counted by
  colour (the legend's colour of a state: exactly the portions of that
  state; the blocks' face colour: every face) and its edges (every hull
  edge, V + F - 2 per block); pvpython, the two VTK files it was given read
  back here (the block of each face, the portion, state and colour of each
  failed portion) and its own report of what it loaded and showed, counted
  by colour and state, with the colours given directly (not through a
  colour map), and the grey of the blocks' faces and edges on more than
  15 % of its picture (35-39 % measured; 0.1 % with the blocks hidden);
- the picture: the PNG written, the wall covering a good part of it, and
  in the part where the wall is drawn the hue of every state present
  (and none of a state absent among red, blue, purple and orange), the
  pushover's largest displacement (end and written steps: one factor for
  the peak and the end) drawn 3-8 % of the wall's size and the factor in
  the picture's caption;
- tools/plot, by default, writes the three PNGs and says who drew them
  (matplotlib where pvpython is not found, pvpython where it is) and the
  factor (--scale's, or the one drawn above); in the matplotlib run with
  --view iso,front, a crack picture per view named with it
  (wallA_cracks_peak_iso.png ...), each line naming its view and file, and
  the end's two views different pictures.

usage: check_cracks3d.py matplotlib|pvpython"""
import os
import re
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(ROOT, "python"))
sys.path.insert(0, HERE)
from bwrun import Failure, call, expect, read, run  # noqa: E402
import blockwall as bw  # noqa: E402
from blockwall.cracks3d import _area_centroid, plot_cracks3d, portion_polygons  # noqa: E402
import check_nonlinear3d as n3  # noqa: E402

# the legend's names (plots.STATES, CAP_STATES) -> the state bits they stand for
NAMES = {"elastic": 0, "open": 1, "sliding": 2, "open and sliding": 3, "crushed": 4, "crushed and open": 5,
         "crushed and sliding": 6, "crushed, open and sliding": 7}
# hues of the states' colours that the picture is searched for (tab:red, tab:blue, tab:purple, tab:orange)
HUES = {1: 0.999, 2: 0.568, 3: 0.754, 4: 0.078}
WALL_B = ("strength: {tension: 500, cohesion: 1000, friction: 0.6, tension_energy: 1, shear_energy: 5, "
          "compression: 1.5e4, compression_shear: 9}")
TIMEOUT = 300  # each blockwall run, tools/plot and pvpython render
# pvpython's two pictures drawn here (tools/plot's keep its default, 1600 x
# 1000): a quarter of the pixels, 4.8 s a render instead of 7.1 on llvmpipe.
# The pixel counts of check_hues are of a 1600 x 1000 picture; a state absent
# may leave no more pixels of its hue than it would there, scaled by the area
# (20 -> 5), and one present at least as many as there (200, of a quarter
# of the pixels).
PV_SIZE = (800, 500)


def scene_text(wall):
    text = n3.WALL3.format(mb=3).replace("stresses: true, xdmf: false", "stresses: true, xdmf: false, steps: every_4")
    if wall == "B":
        text = text.replace("strength: {tension: 0, cohesion: 0, friction: 0.6}", WALL_B)
        expect("compression:" in text, "wall B: the strength line was not replaced")
    return text


def solve(tmp, wall):
    scene = os.path.join(tmp, f"wall{wall}.yaml")
    with open(scene, "w") as f:
        f.write(scene_text(wall))
    out = os.path.join(tmp, f"wall{wall}.h5")
    run(scene, ["-output_file", out], timeout=TIMEOUT)
    return out, bw.read(out), read(out)


def check_rebuilt(res, raw):
    polys = portion_polygons(res)
    expect(len(polys) == len(raw["portions/area"]), f"{len(polys)} portions rebuilt, {len(raw['portions/area'])} in the file")
    worst_a = worst_c = 0.0
    size = float(np.ptp(res.vertices, axis=0).max())
    off = raw["interfaces/portion_offsets"]
    for k in range(res.ninterfaces):
        t, b, G = res.frame[k][0], res.frame[k][2], res.center[k]
        for p in range(off[k], off[k + 1]):
            uv = np.column_stack([(polys[p] - G) @ t, (polys[p] - G) @ b])
            a, c = _area_centroid(uv)
            worst_a = max(worst_a, abs(a - raw["portions/area"][p]) / res.area[k])
            worst_c = max(worst_c, float(np.max(np.abs(c - raw["portions/center"][p]))) / size)
    expect(worst_a <= 1e-12 and worst_c <= 1e-9, f"rebuilt portions: areas {worst_a:.2e}, centroids {worst_c:.2e}")
    return f"{len(polys)} portions rebuilt, areas to {worst_a:.1e}, centroids to {worst_c:.1e}"


def polygon_area(p):
    p = np.asarray(p, float)
    return 0.5 * float(np.linalg.norm(np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)))


def polygon_centroid(p):
    """Area centroid of a planar polygon in space (a fan of triangles)."""
    p = np.asarray(p, float)
    a, c = 0.0, np.zeros(3)
    for i in range(1, len(p) - 1):
        t = 0.5 * np.linalg.norm(np.cross(p[i] - p[0], p[i + 1] - p[0]))
        a += t
        c += t * (p[0] + p[i] + p[i + 1]) / 3
    return c / a


class Reference:
    """What the picture of the step drawn must show, from the file alone."""

    def __init__(self, raw, c):
        self.step = c.step
        end = c.at == "end"
        self.state = raw["portions/state"] if end else raw[f"steps/{c.step:06d}/portions/state"]
        d = raw["blocks/displacement"] if end else raw[f"steps/{c.step:06d}/blocks/displacement"]
        v, off, cen = raw["blocks/vertices"], raw["blocks/offsets"], raw["blocks/centroid"]
        s = c.scene.scale
        self.size = float(np.ptp(v, axis=0).max())
        self.nblocks = len(off) - 1
        self.points = np.concatenate([v[off[b]:off[b + 1]] + s * (d[b, :3] + np.cross(d[b, 3:], v[off[b]:off[b + 1]] - cen[b]))
                                      for b in range(self.nblocks)])
        # the largest vertex displacement of the pushover (the end and every written step): the
        # peak and the end are drawn with one factor
        disps = [raw["blocks/displacement"]] + [raw[k] for k in raw if re.fullmatch(r"steps/\d+/blocks/displacement", k)]
        self.umax = max(float(np.max(np.linalg.norm(e[b, :3] + np.cross(e[b, 3:], v[off[b]:off[b + 1]] - cen[b]), axis=1)))
                        for e in disps for b in range(self.nblocks))
        from scipy.spatial import ConvexHull
        self.hull_area, self.hull_planes, self.hull_edges = [], [], []
        for b in range(self.nblocks):
            h = ConvexHull(self.points[off[b]:off[b + 1]])
            planes = len(np.unique(np.round(h.equations[:, :3], 6), axis=0))
            self.hull_area.append(h.area)
            self.hull_planes.append(planes)
            self.hull_edges.append(len(h.vertices) + planes - 2)  # Euler, a convex polyhedron
        # each failed portion's centre on its joint, moved by the mean motion of its two blocks
        self.failed = np.nonzero(self.state != 0)[0]
        pairs, G, frame = raw["interfaces/blocks"], raw["interfaces/center"], raw["interfaces/frame"]
        owner = np.repeat(np.arange(len(pairs)), np.diff(raw["interfaces/portion_offsets"]))
        self.centres = []
        for p in self.failed:
            k = owner[p]
            x = G[k] + raw["portions/center"][p][0] * frame[k][0] + raw["portions/center"][p][1] * frame[k][2]
            u = sum(d[b, :3] + np.cross(d[b, 3:], x - cen[b]) for b in pairs[k]) / 2
            self.centres.append(x + s * u)
        self.counts = np.bincount(self.state, minlength=4)


def check_legend(c, ref, where):
    """The legend: 'NAME: COUNT' for 0..3 and the cap's states present; the count the file's; its colours."""
    leg = c.ax.get_legend()
    expect(leg is not None, f"{where}: no legend")
    colours = {}
    # legend_handles since matplotlib 3.7; Debian 12 has 3.6 (legendHandles)
    handles = getattr(leg, "legend_handles", None) or leg.legendHandles
    for handle, text in zip(handles, leg.get_texts()):
        m = re.fullmatch(r"(.+): (\d+)", text.get_text())
        expect(m and m.group(1) in NAMES, f"{where}: legend entry {text.get_text()!r}")
        s = NAMES[m.group(1)]
        expect(int(m.group(2)) == ref.counts[s], f"{where}: legend '{text.get_text()}', the file has {ref.counts[s]}")
        colours[s] = tuple(handle.get_facecolor())
    want = set(range(4)) | {s for s in range(4, len(ref.counts)) if ref.counts[s]}
    expect(set(colours) == want, f"{where}: legend lists states {sorted(colours)}, want {sorted(want)}")
    expect(np.array_equal(c.state, ref.state) and np.array_equal(c.counts, ref.counts),
           f"{where}: the states drawn are not the file's (counts {c.counts}, file {ref.counts})")
    expect(len(set(tuple(np.round(colours[s][:3], 3)) for s in colours if s)) == len([s for s in colours if s]),
           f"{where}: two failed states share a colour in the legend")
    return colours


def check_scene(c, ref, where):
    """The scene handed to the renderer, against the file."""
    sc = c.scene
    expect(np.array_equal(sc.portions, ref.failed), f"{where}: {len(sc.portions)} portions given to the renderer, "
           f"{len(ref.failed)} failed in the file (or not the same ones)")
    expect(np.array_equal(sc.portion_state, ref.state[ref.failed]), f"{where}: the portions' states given to the renderer")
    err = max((float(np.max(np.abs(polygon_centroid(p) - x))) for p, x in zip(sc.portion_polygons, ref.centres)), default=0.0)
    expect(err <= 1e-9 * ref.size, f"{where}: a portion drawn {err:.2e} m from its place on the warped joint")
    expect(np.max(np.abs(sc.points - ref.points)) <= 1e-12 * ref.size, f"{where}: the blocks' warped vertices")
    faces = np.bincount(sc.face_block, minlength=ref.nblocks)
    areas = np.zeros(ref.nblocks)
    for f, b in zip(sc.faces, sc.face_block):
        areas[b] += polygon_area(sc.points[f])
    bad = np.nonzero((np.abs(areas - ref.hull_area) > 1e-9 * np.asarray(ref.hull_area)) | (faces != ref.hull_planes))[0]
    expect(len(bad) == 0, f"{where}: blocks {bad[:10].tolist()} drawn with {faces[bad[:10]].tolist()} faces of area "
           f"{areas[bad[:10]].tolist()}, their hulls have {np.asarray(ref.hull_planes)[bad[:10]].tolist()} of "
           f"{np.asarray(ref.hull_area)[bad[:10]].tolist()}")
    drawn = ref.umax * sc.scale / ref.size
    expect(0.03 <= drawn <= 0.08, f"{where}: the pushover's largest displacement is drawn {drawn:.1%} of the wall's size")
    expect(f"× {sc.scale:g}" in c.ax.get_title(), f"{where}: the factor {sc.scale:g} not in the caption {c.ax.get_title()!r}")
    return len(sc.faces)


def check_hues(img, ref, where, area=1.0):
    """The hue of every state present among 1..4 in the picture, none of a
    state absent; `area`: the picture's pixels over 1600 x 1000's."""
    from matplotlib.colors import rgb_to_hsv
    hsv = rgb_to_hsv(np.clip(img[..., :3], 0, 1))
    vivid = hsv[..., 1] > 0.25
    found = {}
    for s, h in HUES.items():
        dist = np.abs(hsv[..., 0] - h)
        found[s] = int(np.sum(vivid & (np.minimum(dist, 1 - dist) < 0.03)))
    for s in HUES:
        present = ref.counts[s] > 0 if s < len(ref.counts) else False
        expect(found[s] >= 200 if present else found[s] <= 20 * area,
               f"{where}: {found[s]} pixels of the hue of state {s}, which has {ref.counts[s] if s < len(ref.counts) else 0} portions")
    return found


def ink(img):
    return float(np.mean(np.any(img[..., :3] < 0.95, axis=-1)))


def check_matplotlib(c, ref, where, colours):
    col, edges = c.rendered["collection"], c.rendered["edges"]
    expect(col in c.ax.collections and edges in c.ax.collections, f"{where}: the faces or the edges are not in the wall's axes")
    c.figure.canvas.draw()
    fc = np.round(np.asarray(col.get_facecolor()), 4)
    expect(len(fc) == len(c.scene.faces) + len(ref.failed), f"{where}: {len(fc)} polygons drawn")
    for s, colour in colours.items():
        n = int(np.sum(np.all(fc == np.round(colour, 4), axis=1)))
        want = sum(ref.hull_planes) if s == 0 else ref.counts[s]
        expect(n == want, f"{where}: {n} polygons drawn in the colour of state {s} in the legend, want {want}"
                          + (" (every block face)" if s == 0 else ""))
    nlines = len(edges.get_segments())
    expect(nlines == sum(ref.hull_edges), f"{where}: {nlines} block edges drawn, the hulls have {sum(ref.hull_edges)}")
    # the wall's axes only: the legend is beside them, the curve in its own axes
    bbox = c.ax.get_window_extent()
    img = np.asarray(c.figure.canvas.buffer_rgba(), float)[..., :3] / 255
    h = img.shape[0]
    crop = img[int(h - bbox.y1):int(h - bbox.y0), int(bbox.x0):int(bbox.x1)]
    return check_hues(crop, ref, where), ink(crop)


def read_vtk(path):
    """(points, polygons, cell arrays) of a legacy ASCII POLYDATA file, read here."""
    with open(path) as f:
        lines = f.read().split("\n")
    expect(lines[2] == "ASCII" and lines[3] == "DATASET POLYDATA", f"{path}: not ASCII polydata")
    words = " ".join(lines[4:]).split()
    i = 0
    expect(words[i] == "POINTS", f"{path}: no POINTS")
    n = int(words[i + 1])
    points = np.array(words[i + 3:i + 3 + 3 * n], float).reshape(n, 3)
    i += 3 + 3 * n
    expect(words[i] == "POLYGONS", f"{path}: no POLYGONS")
    n, i = int(words[i + 1]), i + 3
    polygons = []
    for _ in range(n):
        k = int(words[i])
        polygons.append(np.array(words[i + 1:i + 1 + k], int))
        i += 1 + k
    expect(words[i] == "CELL_DATA" and int(words[i + 1]) == n, f"{path}: CELL_DATA")
    i += 2
    arrays = {}
    while i < len(words):
        expect(words[i] == "SCALARS" and words[i + 4] == "LOOKUP_TABLE", f"{path}: at word {i}: {words[i:i + 6]}")
        name, k = words[i + 1], int(words[i + 3])
        arrays[name] = np.array(words[i + 6:i + 6 + n * k], int).reshape(n, k)
        i += 6 + n * k
    return points, polygons, arrays


def check_pvpython(c, ref, where, colours):
    expect(c.renderer == "pvpython", f"{where}: drawn by {c.renderer}")
    points, polygons, arrays = read_vtk(c.files["blocks"])
    block = arrays["block"][:, 0]
    expect(np.max(np.abs(points - ref.points)) <= 1e-12 * ref.size, f"{where}: blocks.vtk's points are not the warped vertices")
    areas = np.bincount(block, weights=[polygon_area(points[f]) for f in polygons], minlength=ref.nblocks)
    faces = np.bincount(block, minlength=ref.nblocks)
    bad = np.nonzero((np.abs(areas - ref.hull_area) > 1e-9 * np.asarray(ref.hull_area)) | (faces != ref.hull_planes))[0]
    expect(len(bad) == 0, f"{where}: blocks.vtk: blocks {bad[:10].tolist()} with {faces[bad[:10]].tolist()} faces, "
           f"their hulls {np.asarray(ref.hull_planes)[bad[:10]].tolist()}")
    shown = {int(b): n for b, n in c.rendered["block_faces"].items()}
    expect(shown == {b: ref.hull_planes[b] for b in range(ref.nblocks)},
           f"{where}: pvpython showed faces per block {shown}, the hulls have {ref.hull_planes}")
    ppts, ppolys, parr = read_vtk(c.files["portions"])
    expect(np.array_equal(parr["portion"][:, 0], ref.failed), f"{where}: portions.vtk holds other portions than the failed ones")
    expect(np.array_equal(parr["state"][:, 0], ref.state[ref.failed]), f"{where}: portions.vtk's states")
    err = max(float(np.max(np.abs(polygon_centroid(ppts[f]) - x))) for f, x in zip(ppolys, ref.centres))
    expect(err <= 1e-9 * ref.size, f"{where}: portions.vtk: a portion {err:.2e} m from its place")
    expect(c.rendered.get("map_scalars") == 0 and c.rendered.get("colour_array") == ["CELLS", "rgb"],
           f"{where}: pvpython coloured the portions by {c.rendered.get('colour_array')}, MapScalars {c.rendered.get('map_scalars')}")
    by_colour = {}
    for key, n in c.rendered["portions"].items():
        rgb, s = key.split(";")
        by_colour.setdefault(tuple(int(x) for x in rgb.split(",")), {})[int(s)] = n
    for s, colour in colours.items():
        if s == 0:
            continue
        rgb = tuple(int(round(255 * x)) for x in colour[:3])
        got = by_colour.get(rgb, {})
        want = {s: int(ref.counts[s])} if ref.counts[s] else {}
        expect(got == want, f"{where}: pvpython showed {got} (state: portions) in the legend's colour of state {s}, want {want}")
    expect(sum(sum(v.values()) for v in by_colour.values()) == len(ref.failed), f"{where}: pvpython showed {by_colour}")
    import matplotlib.image as mpimg
    img = mpimg.imread(c.files["png"])
    expect(img.shape[:2] == (PV_SIZE[1], PV_SIZE[0]), f"{where}: pvpython's picture {img.shape}, asked for {PV_SIZE}")
    # without the orientation axes (red, yellow, green) in its lower left
    # corner (250 x 250 of a 1600 x 1000 picture)
    crop = img.copy()
    corner = 250 * PV_SIZE[1] // 1000
    crop[-corner:, :corner] = 1.0
    # the blocks shown: grey of their faces over one another and of their edges
    from matplotlib.colors import rgb_to_hsv
    hsv = rgb_to_hsv(np.clip(crop[..., :3], 0, 1))
    grey = float(np.mean((hsv[..., 1] < 0.15) & (hsv[..., 2] < 0.9)))
    print(f"{where}: {grey:.1%} of pvpython's picture the blocks' grey")
    expect(grey > 0.15, f"{where}: {grey:.1%} of pvpython's picture in the blocks' grey: are the blocks shown?")
    return check_hues(crop, ref, where, PV_SIZE[0] * PV_SIZE[1] / (1600 * 1000)), ink(img)


def main(mode):
    import matplotlib.image as mpimg
    with tempfile.TemporaryDirectory() as tmp:
        walls = {w: solve(tmp, w) for w in "AB"}
        print(check_rebuilt(*walls["A"][1:]))
        seen, scales = set(), {}
        pictures = (("A", "end"), ("A", "peak"), ("B", "end"), ("B", "peak")) if mode == "matplotlib" else (("A", "peak"), ("B", "end"))
        for wall, at in pictures:
            out, res, raw = walls[wall]
            where = f"wall {wall} at the {at}"
            work = os.path.join(tmp, f"{wall}_{at}")
            os.makedirs(work)
            size = PV_SIZE if mode == "pvpython" else (1600, 1000)  # matplotlib: the argument is pvpython's only
            c = plot_cracks3d(res, at, renderer=mode, workdir=work, size=size, timeout=TIMEOUT)
            ref = Reference(raw, c)
            colours = check_legend(c, ref, where)
            nfaces = check_scene(c, ref, where)
            hues, covered = (check_matplotlib if mode == "matplotlib" else check_pvpython)(c, ref, where, colours)
            expect(covered > 0.08, f"{where}: the wall covers {covered:.1%} of its picture")
            png = os.path.join(work, "figure.png")
            c.figure.savefig(png, dpi=100)
            drawn = ink(mpimg.imread(png))
            expect(drawn > 0.05, f"{where}: {drawn:.1%} of the figure's pixels drawn")
            seen |= {s for s in range(1, len(ref.counts)) if ref.counts[s]}
            scales[wall] = c.scene.scale
            print(f"{where} (step {c.step}, {mode}): states {dict(enumerate(ref.counts.tolist()))}; {len(ref.failed)} failed "
                  f"portions given and drawn, each in its state's colour; {nfaces} faces of {ref.nblocks} blocks "
                  f"(hull areas to 1e-9), x{c.scene.scale:g} (the largest displacement {ref.umax * c.scene.scale / ref.size:.1%} "
                  f"of the size); hue pixels {hues}; the wall covers {covered:.0%} of its picture, {drawn:.0%} of the figure")
        expect(seen >= {1, 2, 3, 4}, f"states drawn {sorted(seen)}: not every one of 1..4")

        wall = "A" if mode == "matplotlib" else "B"
        out = walls[wall][0]
        outdir = os.path.join(tmp, f"plot_{wall}")
        # by default: matplotlib on a machine without pvpython (no BW_PVPYTHON, a PATH without it), with
        # a factor asked for; pvpython where it is, with the factor drawn above
        env = dict(os.environ)
        if mode == "matplotlib":
            env.pop("BW_PVPYTHON", None)
            env["PATH"] = os.path.join(tmp, "empty")
            os.makedirs(env["PATH"])
        # matplotlib: two views in one call (each picture named with its view); pvpython: the default view
        extra, factor = (["--scale", "50", "--view", "iso,front"], 50.0) if mode == "matplotlib" else ([], scales[wall])
        views = ("iso", "front") if mode == "matplotlib" else ("iso",)
        p = call([sys.executable, os.path.join(ROOT, "tools", "plot"), out, "--outdir", outdir, *extra],
                 timeout=2 * TIMEOUT, env=env, what="tools/plot")
        expect(p.returncode == 0, f"tools/plot: exit {p.returncode}\n{p.stdout}\n{p.stderr}")
        names = [f"wall{wall}_history.png"]
        for at in ("peak", "end"):
            for view in views:
                name = f"wall{wall}_cracks_{at}{'_' + view if len(views) > 1 else ''}.png"
                names.append(name)
                line = re.search(rf"^crack pattern at the {at} .*, {view} view, blocks warped x([0-9.e+-]+), drawn by (\w+): (.*)$",
                                 p.stdout, re.M)
                expect(line and line.group(2) == mode and line.group(3) == os.path.join(outdir, name),
                       f"tools/plot: no line 'crack pattern at the {at} ... {view} view ... drawn by {mode}: ...{name}':\n{p.stdout}")
                expect(float(line.group(1)) == factor, f"tools/plot: the {at}'s blocks warped x{line.group(1)}, want x{factor:g}")
        for name in names:
            path = os.path.join(outdir, name)
            expect(os.path.exists(path), f"tools/plot did not write {name}:\n{p.stdout}")
            drawn = ink(mpimg.imread(path))
            expect(drawn > 0.05, f"{name}: {drawn:.1%} of the pixels drawn")
            print(f"tools/plot: {name}: {drawn:.0%} of the pixels drawn")
        if len(views) > 1:
            a, b = (mpimg.imread(os.path.join(outdir, f"wall{wall}_cracks_end_{v}.png"))[:, :, :3] for v in views)
            differ = float(np.mean(np.any(np.abs(a - b) > 0.02, axis=2)))
            expect(differ > 0.05, f"tools/plot: the end's {views[0]} and {views[1]} pictures differ in {differ:.1%} of their pixels")
            print(f"tools/plot: the end's {views[0]} and {views[1]} pictures differ in {differ:.0%} of their pixels")

if __name__ == "__main__":
    if len(sys.argv) != 2 or sys.argv[1] not in ("matplotlib", "pvpython"):
        print(__doc__.rsplit("usage: ", 1)[1])
        sys.exit(2)
    try:
        main(sys.argv[1])
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
    print("ok")
