"""Bad input: one line on stderr naming the key (file:line when it came from
the file), a non-zero exit, and no output file created or changed.

Each case runs with output.file pointing at a file that already exists with
known bytes; after the failed run those bytes must be unchanged and no
temporary file may remain beside it."""
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import each, expect, run, share  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
C = os.path.join(HERE, "cases")

# name: (scene, extra args, [substrings the error line must contain])
CASES = {
    "bad_yaml": ("bad_yaml.yaml", [], ["bad_yaml.yaml:"]),
    "unknown_key": ("unknown_key.yaml", [], ["unknown_key.yaml:6:", "joints.Emod"]),
    "negative_E": ("negative_E.yaml", [], ["negative_E.yaml:7: joints.E must be > 0, got -1"]),
    "bad_nu": ("bad_nu.yaml", [], ["bad_nu.yaml:2: joints.nu", "(-1, 0.5)", "0.5"]),
    "zero_m": ("zero_m.yaml", [], ["zero_m.yaml:3: discretization.m must be >= 1, got 0"]),
    "mortar_zero_thickness": ("mortar_zero_thickness.yaml", [], ["mortar_zero_thickness.yaml:4: joints.thickness", "> 0"]),
    "negative_thickness": ("negative_thickness.yaml", [], ["negative_thickness.yaml:4: joints.thickness must be >= 0"]),
    "unknown_set": ("unknown_set.yaml", [], ["unknown_set.yaml:5: loads.roof does not name a block set (sets: bottom, top)"]),
    "unknown_generator": ("unknown_generator.yaml", [], ["unknown_generator.yaml:2: geometry.generator must be one of ", "two_blocks", "running_bond", "got 'spiral'"]),
    "load_arity": ("load_arity.yaml", [], ["load_arity.yaml:4: loads.top must have 3 values"]),
    "unrestrained": ("unrestrained.yaml", [], ["not restrained", "blocks 0, 1"]),
    "command_line_value": ("ok.yaml", ["-joints_E", "0"], ["command line: -joints_E must be > 0, got 0"]),
    "command_line_typo": ("ok.yaml", ["-joints_Ee", "1e9"], ["-joints_Ee"]),
    "missing_file": ("does_not_exist.yaml", [], ["does_not_exist.yaml"]),
    "unwritable_output": ("ok.yaml", ["-output_file", os.path.join(C, "ok.yaml", "out.h5")], ["-output_file", "cannot be written", "not a directory"]),
    "no_scene": (None, [], ["-scene"]),
    # a PETSc option with a value PETSc refuses is bad input (exit 1, the
    # option named), not a failed solve (exit 2, as it was: issue 17)
    "petsc_ksp_type": ("ok.yaml", ["-ksp_type", "nonsense"], ["option -ksp_type", "nonsense"]),
    "petsc_schur_pc_type": ("ok.yaml", ["-schur_pc_type", "nonsense"], ["option -schur_pc_type", "nonsense"]),
    "petsc_number": ("ok.yaml", ["-ksp_rtol", "abc"], ["option -ksp_rtol", "abc"]),
    # keys of the other dimension (interface.md, additions of 2026-11-23)
    "dim3_m_b_in_2d": ("dim3_m_b_in_2d.yaml", [], ["dim3_m_b_in_2d.yaml:4: discretization.m_b has no meaning in 2D"]),
    "dim3_w_in_3d": ("dim3_w_in_3d.yaml", [], ["dim3_w_in_3d.yaml:3: supports.bottom.w names dof w, which has no meaning in 3D", "u1, u2, u3, w1, w2, w3"]),
    "dim3_u3_in_2d": ("dim3_u3_in_2d.yaml", [], ["dim3_u3_in_2d.yaml:4: supports.top.u3 names dof u3, which has no meaning in 2D"]),
    "dim3_load3_in_3d": ("dim3_load3_in_3d.yaml", [], ["dim3_load3_in_3d.yaml:4: loads.top has 3 values, a load of a 2D scene; this scene is 3D"]),
    "dim3_load6_in_2d": ("dim3_load6_in_2d.yaml", [], ["dim3_load6_in_2d.yaml:4: loads.top has 6 values, a load of a 3D scene; this scene is 2D"]),
    "dim3_dimension": ("dim3_dimension.yaml", [], ["dim3_dimension.yaml:3: geometry.dimension must be 2 or 3, got 4"]),
    "dim3_case_load": ("dim3_ok.yaml", ["-loads_top", "1,2,3"], ["command line: -loads_top has 3 values", "this scene is 3D"]),
    # 3D restraint: the free rigid motions by axis, and an m_b = 1 hinge
    "dim3_rotation_free": ("dim3_rotation_free.yaml", [], ["not restrained", "blocks 0, 1", "3 rigid motions free",
                                                           "rotation about X1 (the line x2 = 0.05, x3 = 0.05)",
                                                           "rotation about X2 (the line x1 = 0.1, x3 = 0.05)",
                                                           "rotation about X3 (the line x1 = 0.1, x2 = 0.05)"]),
    "dim3_translation_free": ("dim3_translation_free.yaml", [], ["not restrained", "1 rigid motion free", "free motion: translation along X3"]),
    "dim3_hinge": ("dim3_hinge.yaml", [], ["mechanism", "m_b = 1", "block 1", "rotation about X1 (the line x2 = 0.105, x3 = 0.05)"]),
}
# the exit code where it is fixed: 1 for what the user gave wrong
EXIT = {"petsc_ksp_type": 1, "petsc_schur_pc_type": 1, "petsc_number": 1, "unknown_key": 1, "negative_E": 1}


def check(name):
    scene, args, wants = CASES[name]
    with tempfile.TemporaryDirectory() as tmp:
        target = os.path.join(tmp, "result.h5")
        before = b"an earlier result that must survive\n"
        with open(target, "wb") as f:
            f.write(before)
        if not any(a == "-output_file" for a in map(str, args)):
            args = [*args, "-output_file", target]
        path = os.path.join(C, scene) if scene else None
        if path:
            code, out, err = run(path, args, expect_ok=False)
        else:  # no -scene at all
            from bwrun import ENV, EXE, call
            p = call([EXE, *map(str, args)], env=ENV)
            code, out, err = p.returncode, p.stdout, p.stderr
        lines = [l for l in err.splitlines() if l.strip()]
        expect(code != 0, f"{name}: exit code 0")
        expect(name not in EXIT or code == EXIT[name], f"{name}: exit code {code}, not {EXIT.get(name)}: {err.strip()}")
        expect(len(lines) == 1, f"{name}: expected one line on stderr, got {len(lines)}:\n{err}")
        for w in wants:
            expect(w in lines[0], f"{name}: {w!r} not in {lines[0]!r}")
        with open(target, "rb") as f:
            expect(f.read() == before, f"{name}: the existing output file was changed")
        expect(sorted(os.listdir(tmp)) == ["result.h5"], f"{name}: files left behind: {os.listdir(tmp)}")
        print(f"{name}: exit {code}: {lines[0]}")


if __name__ == "__main__":
    # check_errors.py [NAME ...] | part K: the cases named (default all), or
    # the K-th half of CASES (K = 1, 2); every case run and reported
    names = sys.argv[1:] or list(CASES)
    if sys.argv[1:2] == ["part"]:
        if sys.argv[2:] not in (["1"], ["2"]):
            sys.exit(f"check_errors.py part K: K is 1 or 2, got {sys.argv[2:]}")
        k = int(sys.argv[2])
        names = share(CASES, k, 2)
    each(names, check)
