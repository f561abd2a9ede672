"""How the file generator scales: read, check and detect interfaces of
running-bond walls of 1e3 .. 1e6 blocks, written without /interfaces/blocks
(detection) and with it (each listed pair matched to its facing edges).

    python3 bench/detect_scaling.py [--build build] [--max 1e6] [--repeat 3]

Runs build/bin/test_geometry (geometry only, no assembly or solve) on one
rank and writes bench/detect_scaling.md: machine, date, load, and per size
the wall-clock and CPU seconds of BwGeometrySetFromOptions (best of
--repeat), which covers reading the HDF5 file, every validation (polygons,
overlaps through the spatial hash, connection), detection and the
broadcast. Linear time shows as a constant CPU time per block. CPU time is
reported beside wall time because a machine shared with other jobs
inflates the latter."""
import argparse
import datetime
import os
import platform
import subprocess
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
LU, HU, E = 0.21, 0.052, 0.01


def wall(units_per_course, courses):
    """Vertices and offsets of a running-bond wall (interface.md's layout:
    even courses n full units, odd ones half, n-1 full, half; foundation and
    top beam) and its interface pairs in blockwall's order, built with numpy."""
    n = units_per_course
    L, half, p = n * LU + (n - 1) * E, (LU - E) / 2, LU + E
    x0s, x1s, ys, rows = [np.array([0.0])], [np.array([L])], [np.array([-E - 0.1])], []
    heights = [0.1]
    for k in range(courses):
        if k % 2 == 0:
            x0 = np.arange(n) * p
            x1 = x0 + LU
        else:
            x0 = np.concatenate([[0.0], half + E + np.arange(n - 1) * p, [L - half]])
            x1 = np.concatenate([[half], half + E + np.arange(n - 1) * p + LU, [L]])
        x0s.append(x0)
        x1s.append(x1)
        ys.append(np.full(len(x0), k * (HU + E)))
        heights.append(HU)
    ytop = (courses - 1) * (HU + E) + HU + E
    x0s.append(np.array([0.0]))
    x1s.append(np.array([L]))
    ys.append(np.array([ytop]))
    x0, x1, y0 = np.concatenate(x0s), np.concatenate(x1s), np.concatenate(ys)
    h = np.concatenate([np.full(len(a), hh) for a, hh in zip(x0s, heights + [0.1])])
    v = np.stack([np.stack([x0, y0], 1), np.stack([x1, y0], 1), np.stack([x1, y0 + h], 1), np.stack([x0, y0 + h], 1)], 1)
    return v.reshape(-1, 2), np.arange(len(x0) + 1, dtype=np.int64) * 4


def pairs_of(path, test_geometry, scene):
    """The interfaces blockwall detects (to time the explicit path on them)."""
    dump = path + ".dump.h5"
    subprocess.run([test_geometry, "-scene", scene, "-dump", dump], check=True, capture_output=True)
    with h5py.File(dump, "r") as f:
        p = f["interfaces/blocks"][()]
    os.remove(dump)
    return p


def timed(test_geometry, scene, repeat):
    best = None
    for _ in range(repeat):
        out = subprocess.run([test_geometry, "-scene", scene], check=True, capture_output=True, text=True).stdout.split()
        r = {"blocks": int(out[1]), "interfaces": int(out[3]), "seconds": float(out[5]), "cpu": float(out[7])}
        best = r if best is None or r["cpu"] < best["cpu"] else best
    return best


def machine():
    cpu = "unknown"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return cpu, os.cpu_count(), os.getloadavg()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(HERE, "..", "build"))
    ap.add_argument("--max", type=float, default=1e6)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    test_geometry = os.path.join(args.build, "bin", "test_geometry")
    if not os.path.exists(test_geometry):
        sys.exit(f"{test_geometry} not found: build the tests first (cd build && ninja)")
    sizes = [n for n in (1e3, 1e4, 1e5, 1e6) if n <= args.max]
    cpu, ncpu, load0 = machine()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for target in sizes:
            n = int(round(np.sqrt(target)))  # n courses of about n units
            v, off = wall(n, n)
            res = {}
            for mode in ("detected", "explicit"):
                geo, scene = os.path.join(tmp, f"{mode}.h5"), os.path.join(tmp, f"{mode}.yaml")
                with h5py.File(geo, "w") as f:
                    f["blocks/vertices"] = v
                    f["blocks/offsets"] = off
                    if mode == "explicit":
                        f["interfaces/blocks"] = pairs_of(os.path.join(tmp, "detected.h5"), test_geometry, os.path.join(tmp, "detected.yaml"))
                with open(scene, "w") as f:
                    f.write(f"geometry: {{generator: file, file: {geo}}}\njoints: {{law: mortar, thickness: {E}, E: 1.0e9, nu: 0.2}}\n")
                res[mode] = timed(test_geometry, scene, args.repeat)
            d, x = res["detected"], res["explicit"]
            assert d["interfaces"] == x["interfaces"]
            rows.append((d["blocks"], d["interfaces"], d["seconds"], d["cpu"], 1e6 * d["cpu"] / d["blocks"], x["seconds"], x["cpu"]))
            print(f"{d['blocks']:>9} blocks {d['interfaces']:>9} interfaces: detected {d['seconds']:.3f} s (cpu {d['cpu']:.3f} s, "
                  f"{1e6 * d['cpu'] / d['blocks']:.2f} us/block); listed {x['seconds']:.3f} s (cpu {x['cpu']:.3f} s)", flush=True)
    load1 = os.getloadavg()
    md = ["# Interface detection: scaling with the number of blocks", "",
          "Made by `python3 bench/detect_scaling.py` (geometry only: `build/bin/test_geometry`, one rank).",
          "Each size is a running-bond wall (about sqrt(N) courses of sqrt(N) units of 0.21 x 0.052 m, joints",
          "e = 0.01 m, foundation and top beam) in an HDF5 file. Times are those of BwGeometrySetFromOptions:",
          "reading the file, checking every polygon, overlaps (spatial hash of bounding boxes), interfaces",
          "(detected through the spatial hash of edges, or, with `/interfaces/blocks`, each listed pair matched",
          "to its facing edges), connection, and the broadcast. Best of the repeats by CPU time.", "",
          f"- date: {datetime.datetime.now().strftime('%Y-%m-%d %H:%M')}",
          f"- machine: {platform.node()}, {cpu}, {ncpu} cores, {platform.system()} {platform.release()}",
          f"- load average before / after: {load0[0]:.1f} / {load1[0]:.1f} (other jobs share the machine: CPU time is the measure)",
          f"- repeats: {args.repeat}", "",
          "| blocks | interfaces | detected: wall s | detected: CPU s | CPU us / block | listed: wall s | listed: CPU s |",
          "|---:|---:|---:|---:|---:|---:|---:|"]
    md += [f"| {b} | {i} | {s:.3f} | {c:.3f} | {u:.2f} | {xs:.3f} | {xc:.3f} |" for b, i, s, c, u, xs, xc in rows]
    if len(rows) > 1:
        md += ["", f"CPU time per block from {rows[0][0]} to {rows[-1][0]} blocks: {rows[0][4]:.2f} -> {rows[-1][4]:.2f} us "
               "(constant per block means linear time; the smallest size is dominated by fixed costs)."]
    with open(os.path.join(HERE, "detect_scaling.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print(f"wrote {os.path.join(HERE, 'detect_scaling.md')}")


if __name__ == "__main__":
    main()
