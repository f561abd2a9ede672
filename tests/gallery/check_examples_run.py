"""Every scene in examples/ runs as README shows it on a fresh clone
(issue 17, item 4: the gallery's geometry files are written by scripts
that nothing ran, and `blockwall -scene examples/arch.yaml` said only
"cannot read 'examples/arch.h5'").

    check_examples_run.py build      the build wrote every geometry file a
                                     scene of examples/ reads, and each scene
                                     runs from the repository's root on 2 ranks
                                     (output to a temporary file; exit 0, its
                                     own checks passed: /solver accuracy_met;
                                     pushovers under control: dissipation for
                                     40 steps, to 0.5 mm under IMPL-EX, under
                                     displacement control 40 % of their steps;
                                     large_wall at 100 x 100 units)
    check_examples_run.py missing    on a copy of examples/ without the
                                     written files, the error line names what
                                     writes the missing file (the script or
                                     tools/import_dxf with the drawing)
"""
import glob
import os
import re
import shutil
import sys
import tempfile

import h5py

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from bwrun import EXE, ENV, MPIEXEC, Failure, call, expect  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(HERE))
EXAMPLES = os.path.join(ROOT, "examples")


def geometry_file(scene):
    """The geometry.file a scene names (None for generated geometry)."""
    m = re.search(r"^\s+file:\s*(\S+\.h5)\s*$", open(scene).read().split("\noutput:")[0], re.M)
    return m.group(1) if m else None


def blockwall(scene, out, ranks, cwd, extra=()):
    cmd = [MPIEXEC, "-n", str(ranks), "--oversubscribe", EXE] if ranks > 1 else [EXE]
    cmd += ["-scene", scene, "-output_file", out, "-output_xdmf", "0", *extra]
    return call(cmd, env=ENV, cwd=cwd, what="blockwall")


def check_build():
    scenes = sorted(glob.glob(os.path.join(EXAMPLES, "*.yaml")))
    expect(len(scenes) >= 8, f"examples/: only {len(scenes)} scenes")
    with tempfile.TemporaryDirectory() as tmp:
        for scene in scenes:
            rel = os.path.relpath(scene, ROOT)
            geo = geometry_file(scene)
            if geo:
                expect(os.path.exists(os.path.join(EXAMPLES, geo)), f"{rel}: the build did not write examples/{geo}")
            out = os.path.join(tmp, os.path.basename(scene) + ".h5")
            # the pushovers past the peak (control: dissipation, hundreds of
            # steps: docs/validation.md runs them whole) for their first 40
            # steps here, which cross their first cracks and switch controls
            text = open(scene).read()
            extra = ["-analysis_pushover_steps", "40"] if re.search(r"^\s+control:\s*dissipation\s*$", text, re.M) else []
            # the pushovers under displacement control (J4D, the tilting
            # U-wall) for their first 40 % of the scene's steps, at its step
            # size (target and steps scaled together): past their first
            # cracks (docs/validation.md runs them whole)
            if not extra and re.search(r"^\s+control:\s*displacement\s*$", text, re.M):
                target = float(re.search(r"^\s+target:\s*(\S+)\s*$", text, re.M).group(1))
                steps = int(re.search(r"^\s+steps:\s*([0-9]+)\s*$", text, re.M).group(1))
                first = round(0.4 * steps)
                extra = ["-analysis_pushover_steps", str(first), "-analysis_pushover_target", repr(target * first / steps)]
            # the 1e5-block wall at 1e4 blocks (its size comes from the command
            # line, as its header says; bench/ and docs/accuracy.md run it whole)
            if os.path.basename(scene) == "large_wall.yaml":
                extra = ["-geometry_running_bond_courses", "100", "-geometry_running_bond_units_per_course", "100"]
            # under IMPL-EX (analysis.pushover.scheme: implex) a step is a
            # fraction of an increment where cracks spread: 40 increments
            # of 0.5 mm cross the first cracks
            if extra and re.search(r"^\s+scheme:\s*implex\s*$", text, re.M):
                extra += ["-analysis_pushover_target", "0.0005"]
            p = blockwall(rel, out, 2, ROOT, extra)
            expect(p.returncode == 0, f"{rel} on 2 ranks: exit {p.returncode}: {p.stderr.strip()}")
            with h5py.File(out, "r") as f:
                met = int(f["solver"].attrs["accuracy_met"])
                nb = f["blocks/displacement"].shape[0]
            expect(met == 1, f"{rel}: accuracy_met = {met}")
            print(f"{rel}: {nb} blocks, exit 0, accuracy_met 1" + (f" (geometry examples/{geo})" if geo else ""))


def check_missing():
    with tempfile.TemporaryDirectory() as tmp:
        ex = os.path.join(tmp, "examples")
        shutil.copytree(EXAMPLES, ex, ignore=shutil.ignore_patterns("*.h5", "out", "*.xdmf"))
        want = {"arch.yaml": "python3 examples/arch.py", "stones.yaml": "python3 examples/stones.py",
                "facade.yaml": "tools/import_dxf examples/facade.dxf examples/facade.h5",
                "cantilever3d.yaml": "python3 examples/cantilever.py", "u_wall.yaml": "python3 examples/u_wall.py",
                "u_wall_tilt.yaml": "python3 examples/u_wall.py",
                "vault.yaml": "python3 examples/vault.py"}
        for scene, hint in want.items():
            p = blockwall(os.path.join("examples", scene), os.path.join(tmp, "out.h5"), 1, tmp)
            lines = [l for l in p.stderr.splitlines() if l.startswith("blockwall:")]
            expect(p.returncode == 1, f"{scene} without its geometry: exit {p.returncode}")
            expect(len(lines) == 1 and "cannot read" in lines[0] and hint in lines[0],
                   f"{scene} without its geometry: the line does not name '{hint}': {p.stderr.strip()}")
            expect(not os.path.exists(os.path.join(tmp, "out.h5")), f"{scene}: an output file was written")
            print(f"{scene} without its geometry: exit 1, {lines[0]}")


if __name__ == "__main__":
    try:
        {"build": check_build, "missing": check_missing}[sys.argv[1]]()
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
