"""Every scene key of blockwall's, given a value of the wrong type,
non-finite or out of the type's range, in the file or on the command line:
one error line that names where it was written and what was expected, exit
code 1 (bad input; 2 means a failed solve), the earlier output untouched and
no temporary file. Before these checks a wrong type escaped as PETSc's
"Input string sixteen has no integer value" with exit 2 and no key,
integers wrapped (m: 4294967297 ran as m = 1), and lists or empty strings
were accepted silently.

  check_types.py file KIND      every key of KIND (real, int, enum, bool, string, array, mapping)
  check_types.py cmdline        the same mistakes on the command line
  check_types.py early          typos are reported before any work
  check_types.py sets600        a scene with 600 loaded sets (more keys than PETSc's database holds) runs

The reference for each case is the key's type in interface.md, written out
below, not read from blockwall."""
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "geometry"))
from bwrun import ENV, EXE, call, each, expect, read  # noqa: E402

# A running-bond scene (every generator key has a place) as (path, value) leaves.
BASE_WALL = [
    (("title",), "type checks"),
    (("geometry", "generator"), "running_bond"),
    (("geometry", "depth"), "0.1"),
    (("geometry", "running_bond", "courses"), "3"),
    (("geometry", "running_bond", "units_per_course"), "2"),
    (("geometry", "running_bond", "unit_length"), "0.21"),
    (("geometry", "running_bond", "unit_height"), "0.052"),
    (("geometry", "running_bond", "foundation"), "true"),
    (("geometry", "running_bond", "foundation_height"), "0.1"),
    (("geometry", "running_bond", "top_beam"), "true"),
    (("geometry", "running_bond", "top_beam_height"), "0.1"),
    (("geometry", "running_bond", "split_units"), "false"),
    (("geometry", "running_bond", "openings"), "[]"),
    (("joints", "law"), "mortar"),
    (("joints", "thickness"), "0.01"),
    (("joints", "E"), "1.0e9"),
    (("joints", "nu"), "0.2"),
    (("joints", "head", "law"), "dry"),
    (("joints", "head", "kn"), "1.0e11"),
    (("joints", "head", "kt"), "4.0e10"),
    (("discretization", "m"), "4"),
    (("supports", "foundation", "u1"), "0"),
    (("supports", "foundation", "u2"), "0"),
    (("supports", "foundation", "w"), "0"),
    (("loads", "top_beam"), "[1000, -2000, 0]"),
    (("gravity", "density"), "0"),
    (("solver", "method"), "auto"),
    (("solver", "rtol"), "1.0e-10"),
    (("solver", "forward_rtol"), "1.0e-10"),
    (("solver", "schur"), "auto"),
    (("solver", "storage"), "shell"),
    (("solver", "condition_estimate"), "auto"),
    (("output", "stresses"), "true"),
    (("output", "xdmf"), "false"),
    (("progress",), "false"),
]
BASE_TWO = [
    (("geometry", "generator"), "two_blocks"),
    (("geometry", "two_blocks", "length"), "0.2"),
    (("geometry", "two_blocks", "height"), "0.1"),
    (("supports", "bottom", "u1"), "0"),
    (("supports", "bottom", "u2"), "0"),
    (("supports", "bottom", "w"), "0"),
    (("loads", "top"), "[1000, -1000, 0]"),
]
BASE_DRY = [
    (("geometry", "generator"), "two_blocks"),
    (("joints", "law"), "dry"),
    (("joints", "kn"), "1.0e11"),
    (("joints", "kt"), "4.0e10"),
    (("supports", "bottom", "u1"), "0"),
    (("supports", "bottom", "u2"), "0"),
    (("supports", "bottom", "w"), "0"),
    (("loads", "top"), "[1000, -1000, 0]"),
]
BASES = {"wall": BASE_WALL, "two": BASE_TWO, "dry": BASE_DRY}

# key -> (base scene, type) from interface.md and docs/scene.md
KEYS = {
    "geometry.depth": ("wall", "real"),
    "geometry.running_bond.courses": ("wall", "int"),
    "geometry.running_bond.units_per_course": ("wall", "real"),
    "geometry.running_bond.split_units": ("wall", "bool"),
    "geometry.running_bond.unit_length": ("wall", "real"),
    "geometry.running_bond.unit_height": ("wall", "real"),
    "geometry.running_bond.foundation": ("wall", "bool"),
    "geometry.running_bond.foundation_height": ("wall", "real"),
    "geometry.running_bond.top_beam": ("wall", "bool"),
    "geometry.running_bond.top_beam_height": ("wall", "real"),
    "geometry.running_bond.openings": ("wall", "array"),
    "geometry.two_blocks.length": ("two", "real"),
    "geometry.two_blocks.height": ("two", "real"),
    "geometry.generator": ("wall", "string"),
    "joints.law": ("wall", "enum"),
    "joints.thickness": ("wall", "real"),
    "joints.E": ("wall", "real"),
    "joints.nu": ("wall", "real"),
    "joints.kn": ("dry", "real"),
    "joints.kt": ("dry", "real"),
    "joints.head.law": ("wall", "enum"),
    "joints.head.kn": ("wall", "real"),
    "joints.head.kt": ("wall", "real"),
    "discretization.m": ("wall", "int"),
    "supports.foundation.u1": ("wall", "real"),
    "supports.foundation.w": ("wall", "real"),
    "loads.top_beam": ("wall", "array"),
    "gravity.density": ("wall", "real"),
    "solver.method": ("wall", "enum"),
    "solver.rtol": ("wall", "real"),
    "solver.forward_rtol": ("wall", "real"),
    "solver.schur": ("wall", "enum"),
    "solver.storage": ("wall", "enum"),
    "solver.condition_estimate": ("wall", "enum"),
    "output.stresses": ("wall", "bool"),
    "output.xdmf": ("wall", "bool"),
    "progress": ("wall", "bool"),
    "title": ("wall", "string"),
}

# type -> [(bad value as YAML text, phrase the message must hold)]
BAD = {
    "real": [("sixteen", "must be a number, got 'sixteen'"), (".inf", "must be a finite number, got '.inf'"),
             ("-.inf", "must be a finite number, got '-.inf'"), (".nan", "must be a finite number, got '.nan'"),
             ("1e400", "must be a finite number, got '1e400'"), ('""', "must be a number, got an empty value"),
             ("[1.0e-10]", "must be a number, got a sequence"), ("{a: 1}", "must be a number, got a mapping")],
    "int": [("sixteen", "must be an integer, got 'sixteen'"), ("3.5", "must be an integer, got '3.5'"),
            ("1e400", "must be an integer, got '1e400'"), (".inf", "must be an integer, got '.inf'"),
            ("4294967297", "must be an integer from -2147483648 to 2147483647, got '4294967297'"),
            ("3000000000", "got '3000000000'"), ("[16]", "must be an integer, got a sequence")],
    "enum": [("1", "must be one of"), ("granite", "got 'granite'"), ("[mortar]", "got a sequence")],
    "bool": [("2", "must be true or false, got '2'"), ("maybe", "got 'maybe'"), ("[true]", "got a sequence")],
    "string": [("[two_blocks]", "must be a single value, got a sequence"), ("{a: b}", "got a mapping")],
    "array": [("[1, .nan, 0]", "must hold finite numbers, got '.nan' (element 2)"), ("[1, x, 0]", "got 'x' (element 2)"),
              ("{a: 1}", "got a mapping")],
}
# sections that must be mappings, with a value of another kind
MAPPINGS = [("supports", "[bottom]"), ("loads", "[1, 2, 3]"), ("joints", "5"), ("solver", "[auto]"),
            ("geometry.running_bond", "7"), ("supports.foundation", "[0, 0, 0]")]


def emit(leaves):
    """YAML text of nested (path, value) leaves; returns (text, line of each dotted key)."""
    lines, where, opened = [], {}, []
    for path, value in leaves:
        common = 0
        while common < len(opened) and common < len(path) - 1 and opened[common] == path[common]:
            common += 1
        opened = opened[:common]
        for d in range(common, len(path) - 1):
            lines.append("  " * d + path[d] + ":")
            opened.append(path[d])
            where[".".join(path[:d + 1])] = len(lines)
        lines.append("  " * (len(path) - 1) + f"{path[-1]}: {value}")
        where[".".join(path)] = len(lines)
    return "\n".join(lines) + "\n", where


def replaced(base, dotted, value):
    path = tuple(dotted.split("."))
    out, done = [], False
    for p, v in base:
        if p == path:
            out.append((p, value))
            done = True
        elif p[:len(path)] == path:  # a mapping replaced by a value
            if not done:
                out.append((path, value))
                done = True
        else:
            out.append((p, v))
    if not done:
        out.append((path, value))
    return out


def run_bad(tmp, scene_text, args, what):
    """Runs blockwall expecting a bad-input failure; returns its one error line."""
    scene = os.path.join(tmp, "scene.yaml")
    with open(scene, "w") as f:
        f.write(scene_text)
    target = os.path.join(tmp, "result.h5")
    before = b"an earlier result that must survive\n"
    with open(target, "wb") as f:
        f.write(before)
    cmd = [EXE, "-scene", "scene.yaml", "-output_file", target, *args]
    p = call(cmd, 120, env=ENV, cwd=tmp)
    lines = [l for l in p.stderr.splitlines() if l.strip()]
    expect(p.returncode == 1, f"{what}: exit code {p.returncode}, expected 1 (bad input)\n{p.stderr}")
    expect(len(lines) == 1, f"{what}: expected one line on stderr, got {len(lines)}:\n{p.stderr}")
    with open(target, "rb") as f:
        expect(f.read() == before, f"{what}: the existing output file was changed")
    expect(sorted(os.listdir(tmp)) == ["result.h5", "scene.yaml"], f"{what}: files left behind: {os.listdir(tmp)}")
    return lines[0]


def check_file(kind):
    count = 0
    keys = [k for k, (_, t) in KEYS.items() if t == kind]
    expect(keys or kind == "mapping", f"no keys of type {kind}")
    if kind == "mapping":
        cases = [(k, "wall", v, "must be a mapping") for k, v in MAPPINGS]
    else:
        # every bad value on the first key of the type, then one per key in turn
        bad = BAD[kind]
        cases = [(keys[0], KEYS[keys[0]][0], v, want) for v, want in bad]
        cases += [(k, KEYS[k][0], *bad[i % len(bad)]) for i, k in enumerate(keys[1:])]
    for key, base, value, want in cases:
        text, where = emit(replaced(BASES[base], key, value))
        with tempfile.TemporaryDirectory() as tmp:
            line = run_bad(tmp, text, [], f"{key}: {value}")
        prefix = f"blockwall: error: scene.yaml:{where[key]}: {key} "
        expect(line.startswith(prefix), f"{key}: {value}: the message does not start with {prefix!r}: {line!r}")
        expect(want in line, f"{key}: {value}: {want!r} not in {line!r}")
        count += 1
    print(f"{kind}: {count} cases, each one line naming scene.yaml:LINE and the key, exit 1, nothing written")


def check_cmdline():
    text, _ = emit(BASE_WALL)
    cases = [
        (["-discretization_m", "sixteen"], "command line: -discretization_m must be an integer, got 'sixteen'"),
        (["-discretization_m", "4x"], "command line: -discretization_m must be an integer, got '4x'"),
        (["-discretization_m", "4294967297"], "command line: -discretization_m must be an integer from"),
        (["-joints_E", ".inf"], "command line: -joints_E must be a finite number, got '.inf'"),
        (["-joints_E", "nan"], "command line: -joints_E must be a finite number, got 'nan'"),
        (["-solver_method", "granite"], "command line: -solver_method must be one of auto, fieldsplit, direct or condensed, got 'granite'"),
        (["-output_xdmf", "2"], "command line: -output_xdmf must be true or false, got '2'"),
        (["-loads_top_beam", "1,x,0"], "command line: -loads_top_beam must hold finite numbers, got 'x' (element 2)"),
        # an option without its value: last, or followed by another option
        (["-discretization_m"], "command line: -discretization_m needs a value (an integer)"),
        (["-joints_E", "-discretization_m", "8"], "command line: -joints_E needs a value (a number)"),
        (["-loads_top_beam"], "command line: -loads_top_beam needs a value"),
        # given twice: which would win is not for the user to guess
        (["-discretization_m", "8", "-discretization_m", "4"], "command line: -discretization_m is given twice"),
        (["-scene", "other.yaml"], "command line: -scene is given twice"),
    ]
    for args, want in cases:
        with tempfile.TemporaryDirectory() as tmp:
            line = run_bad(tmp, text, args, " ".join(args))
        expect(want in line, f"{' '.join(args)}: {want!r} not in {line!r}")
    print(f"command line: {len(cases)} cases, each one line naming the option, exit 1, nothing written")


def check_early():
    """Typos are found before any work: on a 1e6-block wall the typo of a
    generator key (-running_bond_courses for -geometry_running_bond_courses)
    once ran generate, assemble, set-up and solve first. With -progress every
    phase prints a line on stdout when it ends: none may appear."""
    text, _ = emit(BASE_WALL)
    big = ["-geometry_running_bond_courses", "1000", "-geometry_running_bond_units_per_course", "1000", "-progress"]
    cases = [
        (["-running_bond_courses", "316"], "unknown option -running_bond_courses (nothing uses it; did you mean -geometry_running_bond_courses?)", []),
        # a key of blockwall's misspelt: after reading the keys (generate), before partition and assembly
        (["-geometry_running_bond_course", "5", "-geometry_running_bond_courses", "30", "-geometry_running_bond_units_per_course", "30", "-progress"],
         "unknown option -geometry_running_bond_course (nothing uses it; did you mean -geometry_running_bond_courses?)", ["generate"]),
        (["-solver_rtoll", "1e-8"], "unknown option -solver_rtoll (nothing uses it; did you mean -solver_rtol?)", None),
    ]
    for args, want, phases in cases:
        with tempfile.TemporaryDirectory() as tmp:
            scene = os.path.join(tmp, "scene.yaml")
            with open(scene, "w") as f:
                f.write(text)
            full = args if phases is not None else args
            if phases == []:
                full = [*big, *args]
            p = call([EXE, "-scene", scene, "-output_file", os.path.join(tmp, "r.h5"), *full], 120, env=ENV)
            expect(p.returncode == 1, f"{args}: exit {p.returncode}\n{p.stderr}")
            expect(want in p.stderr, f"{args}: {want!r} not in {p.stderr!r}")
            ran = [l.split()[1] for l in p.stdout.splitlines() if l.startswith("[blockwall]")]
            if phases is not None:
                expect(ran == phases, f"{args}: phases run before the error: {ran}, expected {phases}")
            expect(os.listdir(tmp) == ["scene.yaml"], f"{args}: files left: {os.listdir(tmp)}")
    print(f"early: {len(cases)} typos reported before any phase that builds or solves the system")


def check_sets600():
    """600 sets, each loaded: 600 + keys, more than PETSc 3.18's options
    database holds (512; it reported "out of memory"). A column of 600
    blocks on a foundation, block k in set b<k> loaded with (10, -100, 0):
    the foundation's reaction is minus the sum of the loads, exactly."""
    from geomlib import write_geometry
    n = 600
    blocks = [np.array([[0, -0.2], [1, -0.2], [1, -0.01], [0, -0.01]])]
    for k in range(n):
        y = k * 0.11
        blocks.append(np.array([[0, y], [1, y], [1, y + 0.1], [0, y + 0.1]]))
    sets = {"foundation": [0], **{f"b{k}": [k + 1] for k in range(n)}}
    with tempfile.TemporaryDirectory() as tmp:
        write_geometry(os.path.join(tmp, "column.h5"), blocks, sets=sets)
        lines = ["geometry: {generator: file, file: column.h5}", "joints: {law: mortar, thickness: 0.01, E: 1.0e9, nu: 0.2}",
                 "discretization: {m: 2}", "supports:", "  foundation: {u1: 0, u2: 0, w: 0}", "loads:"]
        lines += [f"  b{k}: [10, -100, 0]" for k in range(n)]
        lines += ["output: {xdmf: false, stresses: false}"]
        scene = os.path.join(tmp, "scene.yaml")
        with open(scene, "w") as f:
            f.write("\n".join(lines) + "\n")
        out = os.path.join(tmp, "r.h5")
        p = call([EXE, "-scene", scene, "-output_file", out], 300, env=ENV)
        expect(p.returncode == 0, f"600 loaded sets: exit {p.returncode}\n{p.stderr}")
        res = read(out)
        r = res["blocks/reaction"][0]
        expect(abs(r[0] + 10 * n) <= 1e-9 * 10 * n and abs(r[1] - 100 * n) <= 1e-9 * 100 * n, f"600 loaded sets: foundation reaction {r}")
        expect(np.allclose(res["blocks/load"][1:], [10, -100, 0]), "600 loaded sets: loads not applied to every block")
        print(f"600 loaded sets: ran, foundation reaction {r[0]:.6g}, {r[1]:.6g} N balances the loads")


def one(what, kind=None):
    if what == "file":
        check_file(kind)
    else:
        {"cmdline": check_cmdline, "early": check_early, "sets600": check_sets600}[what]()


if __name__ == "__main__":
    # file KIND | cmdline | early | sets600, or several specs (file:KIND,
    # cmdline, ...) in one process, every one run and reported
    args = sys.argv[1:]
    specs = [f"file:{args[1]}"] if args[:1] == ["file"] and len(args) == 2 else args
    each(specs, lambda spec: one(spec.partition(":")[0], spec.partition(":")[2] or None))
