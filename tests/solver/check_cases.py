"""Load cases: one set-up, one solve per case, one file per case.

  separate RANKS  the demo wall with three cases (wind from the left, wind
                  from the right with self-weight, a moment on the top beam)
                  against three separate runs, each with the case's loads as
                  the scene's: displacements, stresses, resultants and
                  reactions equal to 1e-12 relative (the same operator and
                  factor, so only the refinement's round-off may differ);
                  root attribute case, one file per case, the scene's own
                  output.file not written
  failed          a case whose loads cannot be solved (a forced solver
                  failure applies to all, so a case with a bad key is used
                  instead: refused before any work, naming the key) and a
                  command-line-only case
"""
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import ENV, EXE, Failure, call, expect, read, rel_err, run  # noqa: E402

DEMO = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "demo.yaml")
CASES = {
    "wind_left": ("top_beam: [10000, -32700, 0]", None),
    "wind_right": ("top_beam: [-10000, -32700, 0]", 1800),
    "moment": ("top_beam: [0, -32700, 2000]", None),
}
KEYS = ("blocks/displacement", "interfaces/stress", "interfaces/resultant", "blocks/reaction", "blocks/load")


def scene_with_cases(tmp):
    with open(DEMO) as f:
        base = f.read()
    lines = ["cases:"]
    for name, (loads, rho) in CASES.items():
        lines.append(f"  {name}:")
        lines.append(f"    loads: {{{loads}}}")
        if rho is not None:
            lines.append(f"    gravity: {{density: {rho}}}")
    path = os.path.join(tmp, "cases.yaml")
    with open(path, "w") as f:
        f.write(base + "\n" + "\n".join(lines) + "\n")
    return path


def separate(ranks):
    with tempfile.TemporaryDirectory() as tmp:
        scene = scene_with_cases(tmp)
        out = os.path.join(tmp, "wall.h5")
        code, stdout, err = run(scene, ["-output_file", out], ranks)
        files = sorted(os.listdir(tmp))
        want = sorted(["cases.yaml"] + [f"wall.{n}.h5" for n in CASES] + [f"wall.{n}.xdmf" for n in CASES])
        expect(files == want, f"files written: {files}, expected {want}")
        worst = 0.0
        for name, (loads, rho) in CASES.items():
            res = read(os.path.join(tmp, f"wall.{name}.h5"))
            case_attr = res["attrs"]["case"]
            case_attr = case_attr.decode() if isinstance(case_attr, bytes) else case_attr
            expect(case_attr == name, f"case attribute {case_attr!r}, expected {name!r}")
            f = [float(v) for v in loads.split("[")[1].rstrip("]").split(",")]
            one = os.path.join(tmp, f"one_{name}.h5")
            args = ["-output_file", one, "-loads_top_beam", ",".join(map(str, f))]
            if rho is not None:
                args += ["-gravity_density", rho]
            run(DEMO, args, ranks)
            ref = read(one)
            for key in KEYS:
                e = rel_err(res[key], ref[key])
                expect(e <= 1e-12, f"case {name} on {ranks} rank(s): {key} differs from a separate run by {e:.2e}")
                worst = max(worst, e)
            expect(res["solver"]["residual"] <= 1e-10 and res["solver"]["equilibrium_error"] <= 1e-10, f"case {name}: self-check {res['solver']}")
        expect(stdout.count("equilibrium error") == len(CASES), f"summary has {stdout.count('equilibrium error')} case lines:\n{stdout}")
        print(f"{len(CASES)} cases on {ranks} rank(s) equal separate runs to {worst:.1e}")


def failed():
    with tempfile.TemporaryDirectory() as tmp:
        scene = scene_with_cases(tmp)
        with open(scene, "a") as f:
            f.write("  typo:\n    loads: {top_beem: [1, 2, 3]}\n")
        target = os.path.join(tmp, "wall.h5")
        p = call([EXE, "-scene", scene, "-output_file", target], env=ENV)
        expect(p.returncode == 1 and "cases.typo.loads.top_beem does not name a block set" in p.stderr, f"typo in a case: {p.returncode} {p.stderr}")
        expect(sorted(os.listdir(tmp)) == ["cases.yaml"], f"a refused scene wrote {os.listdir(tmp)}")
        # a case given on the command line only
        code, out, err = run(DEMO, ["-output_file", target, "-cases_push_loads_top_beam", "5000,-32700,0"])
        res = read(os.path.join(tmp, "wall.push.h5"))
        expect(np.allclose(res["blocks/load"][-1], [5000, -32700, 0]), f"command-line case loads {res['blocks/load'][-1]}")
        print("a typo in a case is refused before any work; a command-line case runs")


if __name__ == "__main__":
    try:
        if sys.argv[1] == "separate":
            separate(int(sys.argv[2]))
        elif sys.argv[1] == "failed":
            failed()
        else:  # not another case's checks under a mistyped name
            sys.exit(f"check_cases.py: unknown case {sys.argv[1]!r} (separate R, failed)")
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
