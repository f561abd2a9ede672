"""One rank started without mpiexec (util/process.c): Open MPI's isolated
singleton, each in a session directory of its own.

Left to itself, Open MPI 4.1 forks an orted for a singleton and talks to it
through PMIx; in MPI_Finalize it unloads its PMIx component before it stops
the progress thread that may still run that component's events, and such
a process died of SIGSEGV after its last line, about once in 650 runs on a
loaded machine (two cores dumped on 2026-11-27; that race cannot be
provoked on demand, so what removes it is checked). blockwall starts a
singleton isolated (no orted, no PMIx server). Isolated singletons all
name their session directory alike, and two at once failed when one
removed it as the other made it: each now has its own,
TMPDIR/blockwall-PID-XXXXXX, removed at exit, and by the next singleton
after a kill.

  check_singleton.py    three singletons at once, then one killed

Checked, with TMPDIR a directory of the test's: three runs started
together each have their own directory holding Open MPI's session tree
while they run, no child process (no orted); all three exit 0 with the
same displacements (to 1e-12, one binary and one input); nothing is left
in TMPDIR after them. A run killed by SIGKILL leaves its directory; the
next run removes it and leaves nothing."""
import os
import signal
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import ENV, EXE, expect, read, start  # noqa: E402

SCENE = """title: singleton check
geometry:
  generator: running_bond
  depth: 0.1
  running_bond:
    courses: 120
    units_per_course: 80
    unit_length: 0.21
    unit_height: 0.052
    foundation: true
    top_beam: true
joints: {law: mortar, thickness: 0.01, E: 0.82e9, nu: 0.14}
discretization: {m: 8}
supports:
  foundation: {u1: 0, u2: 0, w: 0}
loads:
  top_beam: [1.0e5, -1.6e6, 0]
output: {stresses: false, xdmf: false}
"""


def children(pid):
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as f:
            return f.read().split()
    except OSError:
        return None  # ended


def private_dirs(tmpdir):
    return {d: os.path.join(tmpdir, d) for d in os.listdir(tmpdir) if d.startswith("blockwall-")}


def main():
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "wall.yaml")
        with open(scene, "w") as f:
            f.write(SCENE)
        tmpdir = os.path.join(tmp, "tmpdir")
        os.makedirs(tmpdir)
        env = dict(ENV, TMPDIR=tmpdir)
        for k in ("OMPI_MCA_ess_singleton_isolated", "OMPI_MCA_orte_tmpdir_base"):
            env.pop(k, None)
        runs = [start([EXE, "-scene", scene, "-output_file", os.path.join(tmp, f"r{k}.h5")], 120, env=env,
                      what="blockwall") for k in range(3)]
        pids = [w.pid for w in runs]
        # while they run: a directory each, named by its pid, holding Open MPI's session tree; no orted
        seen, orteds = {}, []
        deadline = time.monotonic() + 60
        while len(seen) < 3 and time.monotonic() < deadline and any(w.proc.poll() is None for w in runs):
            for name, path in private_dirs(tmpdir).items():
                pid = int(name.split("-")[1])
                if pid in pids and pid not in seen and any(e.startswith("ompi.") for e in os.listdir(path)):
                    seen[pid] = name
                    kids = children(pid)
                    if kids:
                        orteds.append((pid, kids))
            time.sleep(0.01)
        results = [w.wait() for w in runs]
        for pid, p in zip(pids, results):
            expect(p.returncode == 0, f"singleton {pid}: exit {p.returncode}\n{p.stderr}")
        expect(len(seen) == 3, f"session directories seen while the runs ran: {seen} (pids {pids})")
        expect(len(set(seen.values())) == 3, f"the three runs shared a directory: {seen}")
        expect(not orteds, f"child processes of the singletons (an orted?): {orteds}")
        disp = [read(os.path.join(tmp, f"r{k}.h5"))["blocks/displacement"] for k in range(3)]
        scale = np.max(np.abs(disp[0]))
        spread = max(np.max(np.abs(d - disp[0])) for d in disp[1:]) / scale
        expect(scale > 0 and spread <= 1e-12, f"the three runs differ by {spread:.2e} of the largest displacement")
        left = os.listdir(tmpdir)
        expect(not left, f"left in TMPDIR after three runs: {left}")
        print(f"3 singletons at once: each its own session directory ({sorted(seen.values())}), no child process, "
              f"exit 0, displacements alike to {spread:.1e}, nothing left in TMPDIR")

        # a run killed outright keeps its directory; the next run removes it
        w = start([EXE, "-scene", scene, "-output_file", os.path.join(tmp, "k.h5")], 120, env=env, what="blockwall")
        deadline = time.monotonic() + 60
        while not private_dirs(tmpdir) and time.monotonic() < deadline and w.proc.poll() is None:
            time.sleep(0.01)
        expect(private_dirs(tmpdir), "the run to be killed made no directory")
        w.proc.send_signal(signal.SIGKILL)
        w.wait()
        stale = sorted(private_dirs(tmpdir))
        expect(len(stale) == 1 and stale[0].startswith(f"blockwall-{w.pid}-"), f"after SIGKILL: {stale}")
        p = start([EXE, "-scene", scene, "-output_file", os.path.join(tmp, "n.h5")], 120, env=env, what="blockwall").wait()
        expect(p.returncode == 0, f"the run after the kill: exit {p.returncode}\n{p.stderr}")
        left = os.listdir(tmpdir)
        expect(not left, f"left in TMPDIR after the next run: {left}")
        print(f"a singleton killed by SIGKILL left {stale[0]}; the next run removed it and left nothing")


if __name__ == "__main__":
    try:
        main()
    except Exception as e:  # noqa: BLE001  (one line, exit 1)
        print(f"FAIL {e}")
        sys.exit(1)
