"""README.md and docs/*.md as a user meets them (issue 28, item 3): the
links lead somewhere, the walkthroughs run as printed, and every other
snippet runs, parses, or is a fragment listed here with its reason.

    check_docs.py links              every relative link of README.md and docs/*.md reaches an
                                     existing file, every #anchor an existing heading; every
                                     docs page is linked from README; every code block is fenced
                                     and names its language (sh, python, yaml, text)
    check_docs.py walkthrough_2d     README's "Model your own wall in five steps": its commands
                                     and Python snippets, read from README's own text and run in
                                     order in a scratch copy of examples/ (nothing is written into
                                     the source tree), each command's output checked
    check_docs.py walkthrough_3d     the same for "Model your own 3D assembly in five steps",
                                     without step 4's picture (tools/plot --view needs pvpython)
    check_docs.py walkthrough_3d view  with it (registered where CMake finds pvpython and Xvfb)
    check_docs.py snippets           every other snippet: Python run, whole YAML scenes run,
                                     YAML fragments parsed, shell blocks run or listed

The numbers a snippet prints (each top-level expression, as the Python
prompt shows it) are checked against references that do not come from
that expression: the same datasets read with h5py, the loads of the scene
and the blocks' own areas and volumes (the reactions must balance them),
a joint's portions against its resultant.
"""
import ast
import os
import pickle
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from bwrun import ENV, EXE, MPIEXEC, Failure, expect  # noqa: E402

ROOT = os.path.realpath(os.path.join(HERE, "..", ".."))
README = os.path.join(ROOT, "README.md")
DOCS = os.path.join(ROOT, "docs")
LANGS = {"sh", "python", "yaml", "text"}
TIMEOUT = 300            # every subprocess: the slowest (pvpython's picture) takes ~25 s here
WALK_2D = "Model your own wall in five steps"
WALK_3D = "Model your own 3D assembly in five steps"

# Snippets that cannot run alone, keyed by (page, first line), with the reason.
FRAGMENTS = {
    ("docs/scene.md", "title: free text"):
        "the reference of every key: both joint laws' keys, every generator's section, placeholders ([[x0, y0, x1, y1], ...], {...})",
    ("docs/three-dimensions.md", "geometry:"):
        "the 3D keys alone, with placeholder loads [F1, F2, F3, M1, M2, M3] and box [x0, y0, z0, x1, y1, z1]",
    ("docs/three-dimensions.md", "analysis:"):
        "the analysis section of a 3D pushover alone (no geometry, joints or supports)",
}
# Shell blocks outside the walkthroughs that the test does not run, with the reason.
SHELL_NOT_RUN = {
    ("README.md", "tools/demo"):
        "installs packages and builds: the build and the suite are what run this test",
    ("docs/accuracy.md", "cmake --build build"):
        "measurements that take minutes to hours (stability, error against time)",
    ("docs/cluster.md", "#!/bin/bash"):
        "a Slurm job script: needs a Slurm cluster, and its capitals (NODES, CORES, MEM, HH:MM:SS) are placeholders",
    ("docs/command-line.md", "mpiexec -n 4 build/bin/blockwall -scene SCENE.yaml [scene options] [PETSc options]"):
        "a synopsis with placeholders",
    ("docs/hdf5.md", "tools/import_dxf DRAWING.dxf GEOMETRY.h5 [--layer-sets] [--unit mm|cm|m] [--depth S]"):
        "a synopsis with placeholders",
    ("docs/install.md", "module load gcc openmpi hdf5-mpi petsc"):
        "a site's modules and paths",
    ("docs/install.md", "cmake --install build --prefix $HOME/opt/blockwall"):
        "installs outside the build tree",
    ("docs/install.md", "./configure --with-debugging=0 COPTFLAGS=-O2 FOPTFLAGS=-O2 \\"):
        "builds a PETSc (needs its source and the network)",
    ("docs/install.md", "./configure --prefix=/work/petsc-alt --with-cc=mpicc --with-cxx=mpicxx --with-fc=mpif90 \\"):
        "builds a PETSc (needs its source)",
}
# Lines of README's "By hand" block of the Quick start that the test leaves out.
BY_HAND_NOT_RUN = {
    "cmake": "the build itself, which this test runs on",
    "cd": "the test suite, of which this test is part",
}


# --------------------------------------------------------------- markdown

class Block:
    def __init__(self, page, line, lang, text, section):
        self.page, self.line, self.lang, self.text, self.section = page, line, lang, text, section

    @property
    def first(self):
        return next((ln.split("  #")[0].rstrip() for ln in self.text.split("\n") if ln.strip()), "")

    def where(self):
        return f"{self.page}:{self.line}"


def rel(path):
    return os.path.relpath(path, ROOT)


def slug(heading):
    """GitHub's anchor of a heading: link markup and punctuation dropped, spaces to hyphens."""
    h = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading).strip().lower()
    return re.sub(r"[^\w\- ]", "", h).replace(" ", "-")


def parse(path):
    """Code blocks, heading anchors, links (line, target) and problems of a markdown file."""
    lines = open(path, encoding="utf-8").read().split("\n")
    blocks, anchors, problems = [], [], []
    prose = []                  # the lines outside code blocks ("" for code), for the links
    section, list_ind, i = None, 0, 0
    while i < len(lines):
        ln = lines[i]
        m = re.match(r"^( *)```(\S*)\s*$", ln)
        if m:
            ind, lang = len(m.group(1)), m.group(2)
            j = i + 1
            while j < len(lines) and not re.match(r"^ *```\s*$", lines[j]):
                j += 1
            if j == len(lines):
                problems.append(f"{rel(path)}:{i + 1}: code block not closed")
                break
            body = "\n".join(x[ind:] if x.startswith(" " * ind) else x.strip() for x in lines[i + 1:j])
            if lang not in LANGS:
                problems.append(f"{rel(path)}:{i + 1}: code block without one of the languages {sorted(LANGS)}: '```{lang}'")
            blocks.append(Block(rel(path), i + 1, lang, body, section))
            prose += [""] * (j + 1 - i)
            i = j + 1
            continue
        h = re.match(r"^(#{1,6})\s+(.*?)\s*$", ln)
        if h:
            section, list_ind = h.group(2), 0
            a = slug(section)
            n = sum(1 for x in anchors if re.fullmatch(re.escape(a) + r"(-\d+)?", x))
            anchors.append(a if n == 0 else f"{a}-{n}")
        ind = len(ln) - len(ln.lstrip(" "))
        after_blank = i > 0 and not lines[i - 1].strip()
        if ln.strip() and after_blank and ind >= list_ind + 4 and not ln.lstrip().startswith("|"):
            problems.append(f"{rel(path)}:{i + 1}: indented code block: fence it and name its language")
        if ln.strip():
            li = re.match(r"^(\s*)([-*+]|\d+\.)\s+", ln)
            if li:
                list_ind = len(li.group(0))
            elif after_blank and ind < list_ind:
                list_ind = ind
        prose.append(ln)
        i += 1
    text = "\n".join(prose)
    # inline code spans (they may run over a line break) hold no links
    text = re.sub(r"(`+)(.+?)\1", lambda mm: re.sub(r"[^\n]", " ", mm.group(0)), text, flags=re.S)
    links = [(text.count("\n", 0, mm.start()) + 1, mm.group(1))
             for mm in re.finditer(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)", text)]
    return blocks, anchors, links, problems


def pages():
    return [README] + sorted(os.path.join(DOCS, f) for f in os.listdir(DOCS) if f.endswith(".md"))


def section_text(path, title):
    """The text of a level-2 section, up to the next level-2 heading."""
    text = open(path, encoding="utf-8").read()
    m = re.search(rf"^## {re.escape(title)}\s*$(.*?)(?=^## |\Z)", text, re.M | re.S)
    expect(m, f"{rel(path)} has no section '## {title}'")
    return m.group(1)


# ------------------------------------------------------------------- links

def check_links():
    problems, nlinks, nanchors = [], 0, 0
    parsed = {p: parse(p) for p in pages()}
    anchors_of = {p: v[1] for p, v in parsed.items()}
    for page, (blocks, _, links, probs) in parsed.items():
        problems += probs
        for line, target in links:
            if re.match(r"^[a-z][a-z0-9+.-]*:", target):          # http:, https:, mailto:
                continue
            nlinks += 1
            path, _, anchor = target.partition("#")
            dest = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
            if not os.path.exists(dest):
                problems.append(f"{rel(page)}:{line}: link to '{target}': {rel(dest)} does not exist")
                continue
            if anchor:
                nanchors += 1
                if not dest.endswith(".md"):
                    problems.append(f"{rel(page)}:{line}: link to '{target}': an anchor into a file that is not markdown")
                    continue
                if dest not in anchors_of:
                    anchors_of[dest] = parse(dest)[1]
                if anchor not in anchors_of[dest]:
                    problems.append(f"{rel(page)}:{line}: link to '{target}': {rel(dest)} has no heading '#{anchor}'")
    readme_targets = {os.path.normpath(os.path.join(ROOT, t.partition("#")[0])) for _, t in parsed[README][2]}
    for page in pages()[1:]:
        if page not in readme_targets:
            problems.append(f"{rel(page)} is not linked from README.md: a reader cannot find it")
    nblocks = sum(len(v[0]) for v in parsed.values())
    print(f"{len(parsed)} pages, {nlinks} relative links ({nanchors} with an anchor), {nblocks} code blocks")
    expect(not problems, "\n".join(problems))
    expect(nlinks >= 30 and nanchors >= 10, f"only {nlinks} links, {nanchors} anchors found: the parser lost them")


# ---------------------------------------------------------------- running

def workspace(tmp):
    """A scratch checkout: examples/ copied without what the build wrote,
    tools/ and python/ linked, build/bin/blockwall the executable under test."""
    shutil.copytree(os.path.join(ROOT, "examples"), os.path.join(tmp, "examples"),
                    ignore=shutil.ignore_patterns("*.h5", "*.xdmf", "out", "__pycache__"))
    for d in ("tools", "python"):
        os.symlink(os.path.join(ROOT, d), os.path.join(tmp, d))
    os.makedirs(os.path.join(tmp, "build", "bin"))
    os.symlink(os.path.realpath(EXE), os.path.join(tmp, "build", "bin", "blockwall"))
    env = dict(ENV, PYTHONPATH=os.path.join(ROOT, "python"), PYTHONDONTWRITEBYTECODE="1", MPLBACKEND="Agg",
               BW_EXE=os.path.realpath(EXE))
    return env


def source_state():
    """What a run could have written into the checkout: examples/ and out/."""
    state = {}
    for d in ("examples", "out"):
        for dirpath, _, files in os.walk(os.path.join(ROOT, d)):
            for f in files:
                p = os.path.join(dirpath, f)
                st = os.stat(p)
                state[rel(p)] = (st.st_size, st.st_mtime_ns)
    return state


def commands(block):
    """The command lines of a shell block (continuations joined, comments dropped)."""
    out, cur = [], ""
    for ln in block.text.split("\n"):
        cur += ln.rstrip()
        if cur.endswith("\\"):
            cur = cur[:-1] + " "
            continue
        if cur.strip():
            out.append(cur.strip())
        cur = ""
    return out


def run_command(line, cwd, env):
    """Run one command line as README prints it; python3 and mpiexec are the build's."""
    words = shlex.split(line, comments=True)
    expect(not any(w in ("&&", "||", "|", ";", ">") for w in words), f"'{line}': a shell construct the test cannot run")
    argv = {"mpiexec": [MPIEXEC], "python3": [sys.executable]}.get(words[0], [words[0]]) + words[1:]
    print(f"$ {line}", flush=True)
    p = subprocess.run(argv, cwd=cwd, env=env, capture_output=True, text=True, timeout=TIMEOUT)
    print(p.stdout.rstrip())
    expect(p.returncode == 0, f"'{line}' exited {p.returncode}:\n{p.stdout}\n{p.stderr}")
    return words, p.stdout


RUNNER = r"""
import ast, pickle, sys
import numpy as np
src = open(sys.argv[1]).read()
ns, values = {"__name__": "__main__"}, {}
for node in ast.parse(src).body:
    seg = ast.get_source_segment(src, node)
    if isinstance(node, ast.Expr):
        v = eval(compile(ast.Expression(node.value), "<snippet>", "eval"), ns)
        if v is not None:
            print(">>>", seg); print(repr(v)[:600])
        keep = lambda x: x if isinstance(x, (np.ndarray, np.generic, int, float, str, bytes, type(None), type(...))) else repr(x)[:200]
        values[seg] = tuple(keep(x) for x in v) if isinstance(v, tuple) else keep(v)
    else:
        exec(compile(ast.Module([node], []), "<snippet>", "exec"), ns)
print(">>> import blockwall:", ns["bw"].__file__ if "bw" in ns else "-")
pickle.dump(values, open(sys.argv[2], "wb"))
"""


def run_python(block, cwd, env):
    """Run a Python snippet as the prompt would: the value of every top-level expression kept."""
    path = os.path.join(cwd, f"snippet_{block.line}.py")
    with open(path, "w") as f:
        f.write(block.text + "\n")
    print(f"$ python3 <<'{block.where()}'", flush=True)
    p = subprocess.run([sys.executable, "-c", RUNNER, path, path + ".pickle"], cwd=cwd, env=env,
                       capture_output=True, text=True, timeout=TIMEOUT)
    print(p.stdout.rstrip())
    expect(p.returncode == 0, f"the snippet at {block.where()} failed ({p.returncode}):\n{block.text}\n{p.stderr}")
    expect(os.path.join(ROOT, "python") in p.stdout, f"the snippet at {block.where()} did not import this checkout's blockwall")
    with open(path + ".pickle", "rb") as f:
        return pickle.load(f)


def value(values, expr, block):
    expect(expr in values, f"README's snippet at {block.where()} no longer prints `{expr}`: "
                           f"update tests/docs/check_docs.py with it (it prints {list(values)})")
    return values[expr]


def close(got, want, tol, what):
    got, want = np.asarray(got, float), np.asarray(want, float)
    expect(got.shape == want.shape, f"{what}: shape {got.shape}, expected {want.shape}")
    scale = max(float(np.max(np.abs(want))) if want.size else 0.0, 1e-300)
    err = float(np.max(np.abs(got - want))) / scale if want.size else 0.0
    print(f"  {what}: relative difference {err:.1e}")
    expect(err <= tol, f"{what}: relative difference {err:.2e} > {tol:.0e}\n got {got}\nwant {want}")


def png_drawn(path, least):
    """A picture was drawn: a PNG of sensible size with some of it not background white."""
    import matplotlib.image as mpimg
    expect(os.path.exists(path), f"{path} not written")
    img = mpimg.imread(path)
    ink = float(np.mean(np.any(img[:, :, :3] < 0.95, axis=2)))
    print(f"  {os.path.basename(path)}: {img.shape[1]} x {img.shape[0]}, {ink:.0%} drawn")
    expect(img.shape[0] >= 200 and img.shape[1] >= 200 and ink > least, f"{path}: {img.shape}, {ink:.1%} drawn")


def pngs_printed(stdout, cwd):
    return [os.path.join(cwd, p) for p in re.findall(r":\s+(\S+\.png)\s*$", stdout, re.M)]


def scene_of(words, cwd):
    import yaml
    path = os.path.join(cwd, words[words.index("-scene") + 1])
    with open(path) as f:
        return path, yaml.safe_load(f)


def check_run_output(words, stdout, cwd):
    """A blockwall run as README prints it: its summary, its file, its ranks."""
    scene_path, scene = scene_of(words, cwd)
    out = os.path.join(cwd, scene["output"]["file"])
    expect(os.path.exists(out), f"{rel(scene_path)}: {scene['output']['file']} not written")
    ranks = int(words[words.index("-n") + 1]) if words[0] == "mpiexec" else 1
    with h5py.File(out, "r") as f:
        nb, ni = f["blocks/offsets"].shape[0] - 1, f["interfaces/blocks"].shape[0]
        s = f["solver"].attrs
        expect(int(s["ranks"]) == ranks and int(s["accuracy_met"]) == 1 and float(s["residual"]) <= float(s["rtol"]),
               f"{out}: ranks {s['ranks']} (want {ranks}), accuracy_met {s['accuracy_met']}, residual {s['residual']}")
    m = re.search(r"blocks (\d+), interfaces (\d+)", stdout)
    expect(m and (int(m.group(1)), int(m.group(2))) == (nb, ni), f"the summary does not say the file's {nb} blocks, {ni} interfaces")
    print(f"  {out}: {nb} blocks, {ni} interfaces, {ranks} ranks, accuracy met")
    return scene, out, nb, ni


def set_loads(scene, f, ndof):
    """The total force of the scene's loads on its sets, from the scene and the file's sets."""
    total = np.zeros(ndof)
    for name, load in (scene.get("loads") or {}).items():
        total += len(f["sets/" + name][()]) * np.asarray(load, float)
    return total


def shoelace(v):
    x, y = v[:, 0], v[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def check_geometry_script(block, cwd, before):
    """A snippet that writes a geometry file: the blocks and sets it adds are there."""
    tree = ast.parse(block.text)
    calls = [n for n in ast.walk(tree) if isinstance(n, ast.Call) and getattr(n.func, "attr", "") == "add_block"]
    sets = {s for c in calls for k in c.keywords if k.arg == "sets" for s in ast.literal_eval(k.value)}
    written = sorted(set(f for f in os.listdir(cwd) if f.endswith(".h5")) - before)
    expect(len(written) == 1, f"the snippet at {block.where()} wrote {written}, expected one geometry file")
    with h5py.File(os.path.join(cwd, written[0]), "r") as f:
        nb = f["blocks/offsets"].shape[0] - 1
        have = set(f["sets"]) if "sets" in f else set()
        dim = f["blocks/vertices"].shape[1]
    expect(nb == len(calls) and have == sets, f"{written[0]}: {nb} blocks, sets {sorted(have)}; the snippet adds {len(calls)}, {sorted(sets)}")
    print(f"  {written[0]}: {nb} blocks in {dim}D, sets {sorted(have)}")
    return written[0], dim


# ------------------------------------------------------------ walkthroughs

def walk_blocks(title):
    blocks = [b for b in parse(README)[0] if b.section == title]
    expect(blocks, f"README has no code blocks under '## {title}'")
    return blocks


def walkthrough_2d():
    blocks = walk_blocks(WALK_2D)
    steps = [(b, c) for b in blocks if b.lang == "sh" for c in commands(b)]
    pys = [b for b in blocks if b.lang == "python"]
    programs = [shlex.split(c)[0] for _, c in steps]
    expect(programs == ["tools/import_dxf", "mpiexec", "tools/plot"] and len(pys) == 2,
           f"README's 2D walkthrough: commands {programs} and {len(pys)} Python snippets; "
           "the test checks import_dxf, mpiexec, plot, the reading snippet and the geometry script")
    before = source_state()
    with tempfile.TemporaryDirectory() as tmp:
        env = workspace(tmp)
        # 2. the drawing imported: the geometry the scene reads, with the layers as sets
        words, out = run_command(steps[0][1], tmp, env)
        h5 = os.path.join(tmp, words[2])
        with h5py.File(h5, "r") as f:
            nb, layer_sets = f["blocks/offsets"].shape[0] - 1, set(f["sets"])
        expect(nb > 0 and {"foundation", "top_beam"} <= layer_sets, f"{words[2]}: {nb} blocks, sets {sorted(layer_sets)}")
        expect(f"{nb} blocks" in out, f"import_dxf does not report the {nb} blocks it wrote")
        # 4. the run
        words, out = run_command(steps[1][1], tmp, env)
        scene, res_path, nb_run, ni = check_run_output(words, out, tmp)
        expect(nb_run == nb and os.path.samefile(os.path.join(os.path.dirname(os.path.join(tmp, words[words.index("-scene") + 1])),
                                                              scene["geometry"]["file"]), h5),
               "the scene does not run the imported geometry")
        # 5. the pictures: the wall and one stress diagram per interface named
        words, out = run_command(steps[2][1], tmp, env)
        named = words[words.index("--interfaces") + 1].split(",")
        pngs = pngs_printed(out, tmp)
        expect(len(pngs) == 1 + len(named) and all(f"_stress_{k}.png" in " ".join(pngs) for k in named),
               f"tools/plot printed {pngs} for interfaces {named}")
        for p in pngs:
            png_drawn(p, 0.02)
        # 5. the numbers
        values = run_python(pys[0], tmp, env)
        N = value(values, "res.resultant[:, 1]", pys[0])
        R = value(values, 'res.reaction[res.sets["foundation"]]', pys[0])
        with h5py.File(res_path, "r") as f:
            close(N, f["interfaces/resultant"][:, 1], 0, "N of every interface against /interfaces/resultant")
            length, depth, m = f["interfaces/length"][()], float(f.attrs["depth"]), int(f.attrs["m"])
            rn = f["interfaces/stress"][:, :, 1]
            close(N, (length * depth / m) * rn.sum(axis=1), 1e-9, "N against the sum of its portions' normal stresses x areas")
            v, off = f["blocks/vertices"][()], f["blocks/offsets"][()]
            area = sum(shoelace(v[off[b]:off[b + 1]]) for b in range(len(off) - 1))
            loads = set_loads(scene, f, 3)
            foundation = f["sets/foundation"][()]
            close(R, f["blocks/reaction"][foundation], 0, "the foundation's reaction against /blocks/reaction")
        weight = scene["gravity"]["density"] * 9.81 * area * depth
        close(np.sum(R, axis=0)[:2], -(loads[:2] + [0.0, -weight]), 1e-9,
              "the foundation's reaction against the loads of the scene and the weight of the drawn blocks")
        expect(np.all(np.isfinite(N)) and np.sum(N < 0) > len(N) // 2, "the joints of a wall under its weight are not mostly compressed")
        # without a drawing: the geometry script
        before_h5 = {f for f in os.listdir(tmp) if f.endswith(".h5")}
        run_python(pys[1], tmp, env)
        geo, dim = check_geometry_script(pys[1], tmp, before_h5)
        expect(dim == 2, f"{geo}: {dim}D")
        # and blockwall accepts it, finding the joint between the two blocks
        with open(os.path.join(tmp, "my_scene.yaml"), "w") as f:
            f.write(f"geometry: {{generator: file, file: {geo}}}\njoints: {{law: mortar, thickness: 0.01, E: 1.0e9, nu: 0.2}}\n"
                    "supports: {foundation: {u1: 0, u2: 0, w: 0}}\nloads: {top: [0, -1000, 0]}\noutput: {file: out/my_wall.h5}\n")
        words, out = run_command("build/bin/blockwall -scene my_scene.yaml", tmp, env)
        _, _, nb2, ni2 = check_run_output(words, out, tmp)
        expect((nb2, ni2) == (2, 1), f"{geo}: blockwall found {nb2} blocks and {ni2} interfaces, expected 2 and 1")
    expect(source_state() == before, "the walkthrough wrote into the checkout's examples/ or out/")


def walkthrough_3d(view):
    from scipy.spatial import ConvexHull
    text = section_text(README, WALK_3D)
    blocks = walk_blocks(WALK_3D)
    pys = [b for b in blocks if b.lang == "python"]
    steps = [c for b in blocks if b.lang == "sh" for c in commands(b)]
    programs = [shlex.split(c)[0] for c in steps]
    inline = re.findall(r"`(python3 examples/\S+\.py)`", text)
    found = re.search(r"\((\d+) here\)", text)
    expect(programs == ["mpiexec", "tools/plot"] and len(pys) == 2 and len(inline) == 1 and found,
           f"README's 3D walkthrough: commands {programs}, {len(pys)} Python snippets, scripts {inline}, "
           f"interfaces 'here': {bool(found)}; the test checks the two snippets, the script, mpiexec and plot")
    before = source_state()
    with tempfile.TemporaryDirectory() as tmp:
        env = workspace(tmp)
        # 1. the blocks described in Python, then the whole wall by its script
        before_h5 = {f for f in os.listdir(tmp) if f.endswith(".h5")}
        run_python(pys[0], tmp, env)
        geo, dim = check_geometry_script(pys[0], tmp, before_h5)
        expect(dim == 3, f"{geo}: {dim}D")
        run_command(inline[0], tmp, env)
        # 3. the run: the number of interfaces README gives
        words, out = run_command(steps[0], tmp, env)
        scene, res_path, nb, ni = check_run_output(words, out, tmp)
        expect(ni == int(found.group(1)), f"README says {found.group(1)} interfaces, blockwall found {ni}")
        # 4. the picture (pvpython)
        if view:
            words, out = run_command(steps[1], tmp, env)
            pngs = pngs_printed(out, tmp)
            expect(len(pngs) == 1 and f"_3d_{words[words.index('--view') + 1]}.png" in pngs[0], f"tools/plot printed {pngs}")
            png_drawn(pngs[0], 0.08)
        else:
            print(f"step 4 ({steps[1]}) needs pvpython: run by docs.walkthrough_3d_view")
        # 5. the numbers
        values = run_python(pys[1], tmp, env)
        D = value(values, 'res.displacement[res.sets["top_facade"]]', pys[1])
        S = value(values, "res.resultant[:, 1] / res.area", pys[1])
        P = value(values, "res.portion_stress[res.portion_offsets[7]:res.portion_offsets[8]]", pys[1])
        with h5py.File(res_path, "r") as f:
            top = f["sets/top_facade"][()]
            close(D, f["blocks/displacement"][top], 0, "the top course's displacements against /blocks/displacement")
            N, A = f["interfaces/resultant"][:, 1], f["interfaces/area"][()]
            close(S, N / A, 0, "the joints' mean normal stress against /interfaces/resultant and area")
            po = f["interfaces/portion_offsets"][()]
            pa = f["portions/area"][po[7]:po[8]]
            close(P, f["portions/stress"][po[7]:po[8]], 0, "joint 7's portions against /portions/stress")
            close(pa.sum(), A[7], 1e-12, "joint 7's portions' areas against its area")
            close(np.dot(pa, P[:, 1]), N[7], 1e-9, "joint 7's portions' normal stresses x areas against its N")
            v, off = f["blocks/vertices"][()], f["blocks/offsets"][()]
            volume = sum(ConvexHull(v[off[b]:off[b + 1]]).volume for b in range(len(off) - 1))
            loads = set_loads(scene, f, 6)
            reaction = f["blocks/reaction"][()].sum(axis=0)
        weight = scene["gravity"]["density"] * 9.81 * volume
        close(reaction[:3], -(loads[:3] + [0.0, -weight, 0.0]), 1e-9,
              "the reactions against the loads of the scene and the weight of the blocks' hulls")
        load_dir = np.sign(loads[2])
        expect(load_dir != 0 and np.all(np.sign(D[:, 2]) == load_dir),
               f"the top course does not move along the out-of-plane load ({loads[2]} N): u3 = {D[:, 2]}")
    expect(source_state() == before, "the walkthrough wrote into the checkout's examples/ or out/")


# ---------------------------------------------------------------- snippets

def check_snippets():
    import yaml
    all_blocks = [b for p in pages() for b in parse(p)[0]]
    walk = {WALK_2D, WALK_3D}
    listed = set()
    counts = dict.fromkeys(("run", "scene", "fragment", "shell run", "shell listed", "text", "walkthrough"), 0)
    before = source_state()
    with tempfile.TemporaryDirectory() as tmp:
        env = workspace(tmp)
        by_hand = [b for b in all_blocks if b.page == "README.md" and b.section == "Quick start" and b.first.startswith("cmake")]
        expect(len(by_hand) == 1, "README's Quick start has no 'By hand' block starting with cmake")
        # the Quick start by hand first: its result is what the Python snippets of the docs read
        for line in commands(by_hand[0]):
            w = shlex.split(line, comments=True)[0]
            if w in BY_HAND_NOT_RUN:
                print(f"not run: {line}  ({BY_HAND_NOT_RUN[w]})")
                continue
            words, out = run_command(line, tmp, env)
            if words[0] == "mpiexec":
                check_run_output(words, out, tmp)
            else:
                pngs = pngs_printed(out, tmp)
                expect(pngs, f"'{line}' drew nothing")
                for p in pngs:
                    png_drawn(p, 0.02)
        counts["shell run"] += 1
        for b in all_blocks:
            key = (b.page, b.first)
            if b.page == "README.md" and b.section in walk:
                counts["walkthrough"] += 1
            elif b.lang == "text":
                counts["text"] += 1
            elif b is by_hand[0]:
                pass
            elif b.lang == "sh":
                expect(key in SHELL_NOT_RUN, f"{b.where()}: a shell block neither run nor listed in SHELL_NOT_RUN: {b.first}")
                listed.add(key)
                counts["shell listed"] += 1
            elif key in FRAGMENTS:
                listed.add(key)
                if b.lang == "yaml":
                    expect(isinstance(yaml.safe_load(b.text), dict), f"{b.where()}: the YAML fragment is not a mapping")
                else:
                    compile(b.text, b.where(), "exec")
                print(f"{b.where()}: {b.lang} fragment, parsed ({FRAGMENTS[key]})")
                counts["fragment"] += 1
            elif b.lang == "yaml":
                scene = yaml.safe_load(b.text)
                expect(isinstance(scene, dict) and "geometry" in scene,
                       f"{b.where()}: a YAML snippet that is not a whole scene: list it in FRAGMENTS with the reason")
                path = os.path.join(tmp, f"scene_{b.line}.yaml")
                with open(path, "w") as f:
                    f.write(b.text)
                words, out = run_command(f"build/bin/blockwall -scene {os.path.basename(path)}", tmp, env)
                scene, res_path, _, _ = check_run_output(words, out, tmp)
                with h5py.File(res_path, "r") as f:
                    close(f["blocks/reaction"][()].sum(axis=0)[:2], -set_loads(scene, f, 3)[:2], 1e-9,
                          f"{b.where()}: the reactions against the loads")
                counts["scene"] += 1
            elif b.lang == "python":
                values = run_python(b, tmp, env)
                check_python_values(b, values, tmp)
                counts["run"] += 1
            else:
                raise Failure(f"{b.where()}: a code block in '{b.lang}'")
    stale = sorted((set(FRAGMENTS) | set(SHELL_NOT_RUN)) - listed)
    expect(not stale, f"listed snippets no longer in the docs: {stale}")
    expect(source_state() == before, "the snippets wrote into the checkout's examples/ or out/")
    print(", ".join(f"{v} {k}" for k, v in counts.items()))
    expect(counts["run"] >= 1 and counts["scene"] >= 1, f"no Python snippet or scene was run: {counts}")


def check_python_values(block, values, cwd):
    """What a docs snippet prints, where the test knows what it must be."""
    if block.page == "docs/post-processing.md":
        shapes = value(values, "res.displacement, res.reaction, res.load, res.centroid", block)
        nb = len(shapes[0])
        expect([np.shape(x) for x in shapes] == [(nb, 3), (nb, 3), (nb, 3), (nb, 2)],
               f"{block.where()}: shapes {[np.shape(x) for x in shapes]}, its comment says (B, 3), (B, 3), (B, 3), (B, 2)")
        top, residual, scene = value(values, 'res.sets["top_beam"], res.solver["residual"], res.attrs["scene"]', block)
        expect(len(top) == 1 and 0 < residual <= 1e-10 and "top_beam" in scene, f"{block.where()}: {top}, {residual}")
        expect(os.path.exists(os.path.join(cwd, "wall.png")), f"{block.where()}: wall.png not drawn")
        png_drawn(os.path.join(cwd, "wall.png"), 0.02)
    else:
        raise Failure(f"{block.where()}: a Python snippet the test runs but does not check: add its checks")


def main():
    what = sys.argv[1:]
    if what == ["links"]:
        check_links()
    elif what == ["walkthrough_2d"]:
        walkthrough_2d()
    elif what in (["walkthrough_3d"], ["walkthrough_3d", "view"]):
        walkthrough_3d(view=len(what) == 2)
    elif what == ["snippets"]:
        check_snippets()
    else:
        raise SystemExit(f"usage: check_docs.py links | walkthrough_2d | walkthrough_3d [view] | snippets (got {what})")


if __name__ == "__main__":
    try:
        main()
    except (Failure, subprocess.TimeoutExpired) as e:
        print(f"FAIL: {e}")
        sys.exit(1)
