"""Broken geometry files (tests/data/broken_*.h5, made by tests/data/make_broken.py):
blockwall exits non-zero with one line on stderr that names the file and
says what is wrong where (make_broken.CASES), and no output file is created
or changed (as tests/errors/check_errors.py).

  check_broken.py CASE [RANKS]   one corpus file (on RANKS ranks: each
                                 reads a part, the error reaches every rank)
  check_broken.py part K         every corpus file of the K-th quarter of
                                 make_broken.CASES (K = 1..4), each on 1 rank
                                 and on 3 (as CASE 1 and CASE 3), and the 3
                                 ranks' line is the 1-rank run's (the serial
                                 reader's: a defect read by another rank
                                 than the first must still be the one the
                                 serial reader meets first, issue 29), exit
                                 1 on both; one Python process for the
                                 quarter, every case run and reported
  check_broken.py missing_file   geometry.file names no file
  check_broken.py current        the committed files are what make_broken.py
                                 writes, and every file has a case
"""
import os
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "data")
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, DATA)
sys.path.insert(0, HERE)
from bwrun import Failure, each, expect, run, share  # noqa: E402
import geomlib  # noqa: E402
import make_broken  # noqa: E402


def check(name, geometry, wants, ranks=1, tmp=None):
    """One run of the file on `ranks` ranks; returns (exit code, blockwall's
    lines). `tmp`: an empty directory for the scene and the target (default
    a new one; two runs in one directory name the same scene path)."""
    if tmp is None:
        with tempfile.TemporaryDirectory() as tmp:
            return check(name, geometry, wants, ranks, tmp)
    target = os.path.join(tmp, "result.h5")
    before = b"an earlier result that must survive\n"
    with open(target, "wb") as f:
        f.write(before)
    scene = os.path.join(tmp, "scene.yaml")
    geomlib.write_scene(scene, geometry)
    code, out, err = run(scene, ["-output_file", target], np_ranks=ranks, expect_ok=False)
    lines = [l for l in err.splitlines() if l.strip()]
    if ranks > 1:  # mpiexec adds its own report of the failed job; blockwall's line must appear once
        lines = [l for l in lines if l.startswith("blockwall")]
    expect(code != 0, f"{name}: exit code 0")
    expect(len(lines) == 1, f"{name}: expected one line on stderr, got {len(lines)}:\n{err}")
    for w in [os.path.basename(geometry), *wants]:
        expect(w in lines[0], f"{name}: {w!r} not in {lines[0]!r}")
    with open(target, "rb") as f:
        expect(f.read() == before, f"{name}: the existing output file was changed")
    expect(sorted(os.listdir(tmp)) == ["result.h5", "scene.yaml"], f"{name}: files left behind: {os.listdir(tmp)}")
    print(f"{name}{f' ({ranks} ranks)' if ranks > 1 else ''}: exit {code}: {lines[0]}")
    return code, [l for l in err.splitlines() if l.startswith("blockwall")]


def part(k):
    """The K-th quarter of the corpus, each file on 1 rank and on 3."""

    def alike(name):
        with tempfile.TemporaryDirectory() as tmp:
            c1, l1 = check(name, make_broken.path(DATA, name), make_broken.CASES[name][2], 1, tmp)
            for f in os.listdir(tmp):
                os.unlink(os.path.join(tmp, f))
            c3, l3 = check(name, make_broken.path(DATA, name), make_broken.CASES[name][2], 3, tmp)
        expect(c1 == 1 and c3 == 1 and len(l1) == 1 and l1 == l3,
               f"{name}: 1 rank exit {c1} {l1}, 3 ranks exit {c3} {l3}: not the serial reader's line")
        print(f"ok {name}: the same line on 1 and 3 ranks")

    names = share(make_broken.CASES, k, 4)
    each(names, alike)
    print(f"{len(names)} broken files (part {k} of 4): each refused alike on 1 and 3 ranks")


def same_file(a, b):
    """The same datasets, values and root attributes (NaN equal to NaN)."""
    try:
        fa, fb = h5py.File(a, "r"), h5py.File(b, "r")
    except OSError:
        with open(a, "rb") as x, open(b, "rb") as y:
            return x.read() == y.read()
    with fa, fb:
        na, nb = [], []
        fa.visit(na.append)
        fb.visit(nb.append)
        if sorted(na) != sorted(nb) or dict(fa.attrs) != dict(fb.attrs):
            return False
        for n in na:
            if isinstance(fa[n], h5py.Dataset):
                x, y = fa[n][()], fb[n][()]
                if x.dtype != y.dtype or x.shape != y.shape:
                    return False
                if not np.array_equal(x, y, equal_nan=x.dtype.kind == "f"):
                    return False
    return True


def current():
    with tempfile.TemporaryDirectory() as tmp:
        make_broken.main(tmp)
        fresh = sorted(os.listdir(tmp))
        committed = sorted(f for f in os.listdir(DATA) if f.startswith("broken_") and f.endswith(".h5"))
        expect(fresh == committed, f"tests/data/broken_*.h5 differ from make_broken.py: {set(fresh) ^ set(committed)}")
        for f in fresh:
            expect(same_file(os.path.join(tmp, f), os.path.join(DATA, f)), f"tests/data/{f} is not what make_broken.py writes")
    expect(len(committed) >= 25, f"only {len(committed)} broken files")
    print(f"{len(committed)} broken files, as make_broken.py writes them")


if __name__ == "__main__":
    try:
        case = sys.argv[1]
        if case == "current":
            current()
        elif case == "part" and sys.argv[2:] in (["1"], ["2"], ["3"], ["4"]):
            part(int(sys.argv[2]))
        elif case == "missing_file":
            check(case, make_broken.path(DATA, "does_not_exist"), ["geometry.file", "cannot read", "No such file"])
        else:
            check(case, make_broken.path(DATA, case), make_broken.CASES[case][2], int(sys.argv[2]) if len(sys.argv) > 2 else 1)
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
