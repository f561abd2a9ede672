"""Accuracy against run time (issue 5): one scene over m and over solver
paths and tolerances, each run's error against the converged limit, and
the work-precision diagram. tools/error_vs_time is the command line.

The converged limit, and why it is trusted
  m -> infinity. The discrete stiffness of an interface is exactly
      K_G(m) = diag(kt A, kn A, kn I (1 - 1/m^2))   (model.md),
  so the m -> infinity model is the one with the exact interface stiffness
  diag(kt A, kn A, kn I); its displacements are the limit of the
  displacements, and its linear stress field sigma(x) = (kt dt, kn (dn +
  phi x)) the limit of the piecewise-constant stresses. bw_reference -exact
  solves that model in real128 (the interface integral by two-point Gauss,
  exact for the quadratic integrand), with no code shared with blockwall.
  Two independent checks are recorded with every sweep: K(m) = K_inf - B/m^2
  gives q(m) = q_inf + c1/m^2 + c2/m^4 + ..., so Richardson extrapolation of
  the two finest runs, (m2^2 q(m2) - m1^2 q(m1)) / (m2^2 - m1^2), must agree
  with q_inf to O(1/m^4) (column `richardson` of the summary); and for two
  blocks q_inf is model.md's closed form with 1 - 1/m^2 = 1.
  Solver tolerance. For a given m the algebraic limit is the exact solution
  of that m's system: bw_reference without -exact (real128), not the
  tightest double-precision solve, which carries its own cond x eps.

Errors (max norms, relative to the largest limit value of their kind)
  displacement   max(|du1|, |du2|, L |dw|) / max(|u1|, |u2|, L |w|), L the
                 diagonal of the assembly's bounding box
  stress         sup over every interface and x of |sigma_h(x) - sigma(x)|
                 / max |sigma|: the piecewise-constant field against the
                 linear limit, i.e. what a user reading the stress at an
                 interface's edge gets wrong (order 1/m)
  stress_mid     the same at the portion midpoints only (order 1/m^2)
  (in the rtol sweep, against the real128 solution of the same m, stress
  and stress_mid are both the error of the portion values)
Time: blockwall's own seconds_total minus seconds_write (generate,
partition, assemble, set-up, solve, recover: the computation, without the
process start and the HDF5 write, which depend on the disk and on
output.stresses)."""
from __future__ import annotations

import csv
import os
import subprocess
import tempfile
import time

import numpy as np

from .launch import run
from .results import read_datasets

PATHS = {
    "fieldsplit": ["-solver_method", "fieldsplit"],
    "fieldsplit_gamg": ["-solver_method", "fieldsplit", "-solver_schur", "gamg"],
    "direct": ["-solver_method", "direct"],
    "condensed": ["-solver_method", "condensed"],
}
FIELDS = ["scene", "sweep", "m", "path", "rtol", "status", "seconds", "seconds_total", "seconds_process", "iterations",
          "residual", "method_used", "fallback", "err_displacement", "err_stress", "err_stress_mid", "note"]


def run_blockwall(exe, scene, args, out, ranks=1, timeout=3600, repeat=1):
    """One configuration, run `repeat` times (the fastest counts: timings of
    millisecond runs are noise); its /solver attributes, or {"status":
    "failed", "note": stderr}."""
    best = None
    for _ in range(max(1, repeat)):
        s = run_once(exe, scene, args, out, ranks, timeout)
        if s["status"] != "ok":
            return s
        if best is None or s["seconds"] < best["seconds"]:
            best = s
    return best


def run_once(exe, scene, args, out, ranks, timeout):
    t0 = time.perf_counter()
    try:
        p = run(scene, [*args, "-output_file", out, "-output_xdmf", "0", "-output_stresses", "1"], ranks,
                exe=exe, check=False, timeout=timeout, diagnose=False)  # a timeout is a result here, not a hang
    except subprocess.TimeoutExpired:
        return {"status": "timeout", "note": f"over {timeout} s", "seconds_process": timeout}
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        return {"status": "failed", "note": p.stderr.strip().replace("\n", " ")[:300], "seconds_process": wall}
    s = read_datasets(out)["solver"]
    s["status"] = "ok"
    s["seconds_process"] = wall
    s["seconds"] = s["seconds_total"] - s["seconds_write"]
    return s


def reference(ref_exe, path, exact, tmp):
    """bw_reference on an output file: q (B, 3), s (I, m, 2), relative (I, 3) and its measures."""
    out = os.path.join(tmp, f"ref_{'exact' if exact else 'm'}_{os.getpid()}.h5")
    p = subprocess.run([ref_exe, path, "-o", out] + (["-exact"] if exact else []), capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"bw_reference failed: {p.stderr.strip()}")
    stats = {k: float(v) for k, v in (line.split() for line in p.stdout.splitlines())}
    d = read_datasets(out)
    stats.update(q=d["reference/displacement"], s=d["reference/stress"], relative=d["reference/relative"])
    os.remove(out)
    return stats


def read_result(path):
    d = read_datasets(path)
    r = {k: d[k] for k in ("blocks/displacement", "blocks/vertices", "interfaces/stress", "interfaces/length",
                           "interfaces/kn", "interfaces/kt")}
    v = r["blocks/vertices"] - r["blocks/vertices"].min(axis=0)
    r["size"] = float(np.hypot(*v.max(axis=0)))
    return r


def displacement_error(q, q_ref, size):
    w = np.array([1.0, 1.0, size])
    scale = np.max(np.abs(q_ref * w))
    return float(np.max(np.abs((q - q_ref) * w)) / scale) if scale > 0 else float(np.max(np.abs(q - q_ref)))


def relative_error(a, b):
    scale = np.max(np.abs(b), initial=0.0)
    d = np.max(np.abs(np.asarray(a) - np.asarray(b)), initial=0.0)
    return float(d / scale) if scale > 0 else float(d)


def stress_errors(res, relative):
    """(sup-norm error of the piecewise-constant field, error at the portion
    midpoints) against the linear field of the relative displacements
    `relative` (dt, dn, phi at G), both relative to the largest |sigma|."""
    s, l, kn, kt = res["interfaces/stress"], res["interfaces/length"], res["interfaces/kn"], res["interfaces/kt"]
    m = s.shape[1]
    t = (np.arange(m) + 0.5) / m - 0.5                       # x_p / l
    lo, hi = t - 0.5 / m, t + 0.5 / m                        # portion ends / l
    dt, dn, phi = relative[:, 0:1], relative[:, 1:2], relative[:, 2:3]
    sn = lambda x: kn[:, None] * (dn + phi * x * l[:, None])  # noqa: E731
    st = kt[:, None] * dt
    scale = max(np.max(np.abs(st), initial=0), np.max(np.abs(sn(np.array([-0.5, 0.5]))), initial=0))
    e_shear = np.max(np.abs(s[:, :, 0] - st), initial=0)
    e_field = max(e_shear, np.max(np.abs(s[:, :, 1] - sn(lo)), initial=0), np.max(np.abs(s[:, :, 1] - sn(hi)), initial=0))
    e_mid = max(e_shear, np.max(np.abs(s[:, :, 1] - sn(t)), initial=0))
    return float(e_field / scale), float(e_mid / scale)


def sweep(exe, ref_exe, scene, ms, paths, rtols, m_rtol=16, args=(), ranks=1, timeout=3600, log=print, repeat=1,
          max_m=None):
    """Run the sweeps and return the rows of the CSV and a summary dict.

    sweep "m":    every path at solver.rtol 1e-10 (the default) for each m,
                  errors against the m -> infinity limit (discretisation +
                  algebra);
    sweep "rtol": every path at m = m_rtol for each rtol, errors against
                  the real128 solution of that m (algebra alone).
    max_m: {path: largest m to run it at} (the direct path's LU of the
    whole saddle matrix grows fast with m)."""
    max_m = max_m or {}
    rows, summary = [], {"scene": scene, "options": " ".join(map(str, args))}
    name = os.path.splitext(os.path.basename(scene))[0]
    with tempfile.TemporaryDirectory() as tmp:
        limit, finest = None, {}
        for m in ms:
            for path in paths:
                if m > max_m.get(path, m):
                    continue
                out = os.path.join(tmp, "run.h5")
                s = run_blockwall(exe, scene, [*args, "-discretization_m", m, *PATHS[path]], out, ranks, timeout, repeat)
                row = {"scene": name, "sweep": "m", "m": m, "path": path, "rtol": s.get("rtol", 1e-10), **s}
                if s["status"] == "ok":
                    res = read_result(out)
                    if limit is None:
                        limit = reference(ref_exe, out, True, tmp)
                        summary["cond_limit"] = limit["cond_mixed"]
                    row["err_displacement"] = displacement_error(res["blocks/displacement"], limit["q"], res["size"])
                    row["err_stress"], row["err_stress_mid"] = stress_errors(res, limit["relative"])
                    if path == "fieldsplit":
                        finest[m] = res["blocks/displacement"]
                        summary["size"] = res["size"]
                rows.append(row)
                log(format_row(row))
        if len(finest) >= 2 and limit is not None:
            m1, m2 = sorted(finest)[-2:]
            extrapolated = (m2**2 * finest[m2] - m1**2 * finest[m1]) / (m2**2 - m1**2)
            summary["richardson"] = displacement_error(extrapolated, limit["q"], summary["size"])
            summary["richardson_m"] = (m1, m2)
        algebraic = None
        for rtol in rtols:
            for path in paths:
                out = os.path.join(tmp, "run.h5")
                s = run_blockwall(exe, scene, [*args, "-discretization_m", m_rtol, "-solver_rtol", rtol, *PATHS[path]],
                                  out, ranks, timeout, repeat)
                row = {"scene": name, "sweep": "rtol", "m": m_rtol, "path": path, **s, "rtol": rtol}
                if s["status"] == "ok":
                    res = read_result(out)
                    if algebraic is None:
                        algebraic = reference(ref_exe, out, False, tmp)
                        summary["cond_m"] = algebraic["cond_mixed"]
                    row["err_displacement"] = displacement_error(res["blocks/displacement"], algebraic["q"], res["size"])
                    # same m: the portion values themselves are compared
                    row["err_stress"] = row["err_stress_mid"] = relative_error(res["interfaces/stress"], algebraic["s"])
                rows.append(row)
                log(format_row(row))
    return rows, summary


def format_row(r):
    if r["status"] != "ok":
        return f"{r['sweep']:4s} m {r['m']:4d} {r['path']:16s} rtol {r['rtol']:.0e}: {r['status']} {r.get('note', '')}"
    return (f"{r['sweep']:4s} m {r['m']:4d} {r['path']:16s} rtol {r['rtol']:.0e}: {r['seconds']:8.3f} s, it "
            f"{r['iterations']}, residual {r['residual']:.1e}, error displacement {r['err_displacement']:.2e}, "
            f"stress {r['err_stress']:.2e} (midpoints {r['err_stress_mid']:.2e})")


def write_csv(rows, path):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: r.get(k, "") for k in FIELDS})


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in ("m", "iterations", "fallback"):
            r[k] = int(r[k]) if r[k] not in ("", None) else None
        for k in ("rtol", "seconds", "seconds_total", "seconds_process", "residual", "err_displacement", "err_stress",
                  "err_stress_mid"):
            r[k] = float(r[k]) if r[k] not in ("", None) else None
    return rows


def plot(rows, png, title=""):
    """The work-precision diagram: error against seconds, log-log, one line
    per path: (a) displacements and (b) stresses over m (labels at the
    points), (c) displacements over solver.rtol at fixed m."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(15, 4.8))
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, 3)
    markers = dict(zip(PATHS, "osD^"))
    floor = 1e-17  # an exact zero drawn at the bottom of the axis
    for ax, sweep_name, key, what in ((axes[0], "m", "err_displacement", "displacements vs m -> inf"),
                                      (axes[1], "m", "err_stress", "stress field vs m -> inf"),
                                      (axes[2], "rtol", "err_displacement", "displacements vs real128, over rtol")):
        for path in PATHS:
            pts = [r for r in rows if r["sweep"] == sweep_name and r["path"] == path and r["status"] == "ok"]
            if not pts:
                continue
            pts.sort(key=lambda r: r["m"] if sweep_name == "m" else -r["rtol"])
            x = [r["seconds"] for r in pts]
            y = [max(r[key], floor) for r in pts]
            ax.loglog(x, y, marker=markers[path], label=path, alpha=0.85)
            # labels on one line: m along the default path; rtol where it matters (CG+GAMG)
            if path == ("fieldsplit" if sweep_name == "m" else "fieldsplit_gamg"):
                for r, xi, yi in zip(pts, x, y):
                    label = f"m={r['m']}" if sweep_name == "m" else f"{r['rtol']:.0e}"
                    ax.annotate(label, (xi, yi), textcoords="offset points", xytext=(4, 4), fontsize=7)
        ax.set_xlabel("seconds (computation, 1 rank)")
        ax.set_ylabel("relative error (max norm)")
        ax.set_title(what, fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    return fig
