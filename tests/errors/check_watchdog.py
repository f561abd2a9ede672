"""The suite's watchdog (blockwall.launch.Watched, through tests/common/bwrun.py
and tests/common/watchdog.py) on a planted hang: a 2-rank run of a 9e4-block
wall whose rank 1 is stopped (SIGSTOP) once the first phase has ended, so
that rank 0 waits for it in a collective for ever -- the shape of the hang of
issue 28. The watchdog must end it within its timeout plus the report's
time, and its report must show what each rank was doing:

  hang      bwrun.start with a 5 s timeout: TimedOut (a test failure) and a
            report with the process tree (mpiexec and both ranks, rank 1
            stopped), a gdb backtrace of each rank reaching main(), the last
            -progress phase line the run printed, and every process of the
            run gone afterwards
  nogdb     the same with BW_GDB naming no program (a machine without gdb):
            the report says there is no backtrace and why, and still gives
            the last lines, and the run is still killed
  wrapper   tests/common/watchdog.py, the wrapper of the tests ctest starts
            as a direct mpiexec command, with BW_TEST_TIMEOUT = 35 s (its
            watchdog fires at 35 - 30 = 5 s): exit 1, FAIL and the report

usage: check_watchdog.py hang|nogdb|wrapper"""
import os
import re
import shutil
import signal
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from bwrun import ENV, EXE, MPIEXEC, Failure, TimedOut, expect, start  # noqa: E402
import blockwall  # noqa: E402  (this checkout's python/, put on sys.path by bwrun)

SCENE = os.path.join(HERE, "..", "..", "examples", "demo.yaml")
# 9e4 blocks: 2.4 s on 2 ranks here, from a start-up of 0.15 s. The wrapper
# stops rank 1 0.5 s after the start, blind: a 1e4-block wall (0.45 s in
# all once Open MPI started in 0.15 s instead of 0.37) had ended by then
# now and then, and the run it meant to hang was a rank in its exit.
BIG = ["-geometry_running_bond_courses", "300", "-geometry_running_bond_units_per_course", "300", "-progress"]
TIMEOUT = 5.0  # the planted hang's watchdog
# what the report may take beyond TIMEOUT: two gdb runs side by side (each
# at most blockwall.launch.GDB_SECONDS, measured 10 s on 2 busy cores) and the kill
REPORT_SECONDS = blockwall.launch.GDB_SECONDS + 15


def ranks_of(pid):
    """The blockwall processes below pid (mpiexec's ranks), waited for until both have started."""
    t0 = time.monotonic()
    while time.monotonic() - t0 < 60:
        ranks = [p for p, comm, _ in blockwall.launch.descendants(pid) if comm == "blockwall"]
        if len(ranks) == 2:
            return sorted(ranks)
        time.sleep(0.05)
    raise Failure(f"the 2 ranks below {pid} did not start within 60 s")


def alive(pids):
    """Those of pids still running (a zombie has ended)."""
    table = blockwall.launch.process_table()
    return [p for p in pids if p in table and table[p][2] != "Z"]


def gone(pids, seconds=10):
    """Whether every pid has ended within `seconds`."""
    t0 = time.monotonic()
    while alive(pids) and time.monotonic() - t0 < seconds:
        time.sleep(0.1)
    return not alive(pids)


def check_report(report, ranks, first, gdb):
    """The report of the hang of `ranks` (rank 1 stopped); `first`: a
    progress line the run printed before the hang, or None (not known)."""
    expect(report.startswith("WATCHDOG: ") and "did not end within" in report and "killed" in report,
           f"the report does not say what happened:\n{report[:500]}")
    expect(re.search(r"\n  machine: (load average [0-9. ]+; )?(no stall of this machine seen|the machine stood still)", report),
           f"the report does not say whether the machine stalled:\n{report[:800]}")
    tree = re.search(r"processes: (.*)", report)
    expect(tree and "mpiexec" in tree.group(1) and all(f"{r} blockwall" in tree.group(1) for r in ranks)
           and f"{ranks[1]} blockwall (T)" in tree.group(1), f"the process tree does not show both ranks, rank 1 stopped: "
                                                             f"{tree.group(1) if tree else report[:500]}")
    for r in ranks:
        m = re.search(rf"--- backtrace of blockwall pid {r}:\n(.*?)(?=\n--- )", report, re.S)
        expect(m, f"no backtrace section for rank pid {r}")
        if gdb:
            frames = [l for l in m.group(1).splitlines() if l.startswith("#")]
            expect(len(frames) >= 3 and any(" main ()" in l or " in main " in l for l in frames),
                   f"rank pid {r}: not a backtrace down to main():\n{m.group(1)[:1500]}")
        else:
            expect("no backtrace" in m.group(1) and "not found" in m.group(1), f"rank pid {r}: {m.group(1)[:300]}")
    tail = report.split("lines of stdout:\n")[1].split("\n--- last")[0].splitlines()
    phases = [l for l in tail if l.startswith("[blockwall]")]
    expect(first is None or first.rstrip() in tail, f"the last lines of stdout lack {first!r}: {tail}")
    expect(f"--- last phase line: {phases[-1] if phases else '(none'}" in report,
           f"the last phase line is not the last progress line of stdout {phases[-1:]}")
    return phases[-1] if phases else None


def planted(gdb=True):
    """The hang through bwrun.start; returns what the report said."""
    old = os.environ.get("BW_GDB")
    if not gdb:
        os.environ["BW_GDB"] = "no-such-gdb-here"  # the watchdog reads it in this process
    try:
        with tempfile.TemporaryDirectory() as tmp:
            cmd = blockwall.command(SCENE, [*BIG, "-output_file", os.path.join(tmp, "r.h5")], 2, exe=EXE, mpiexec=MPIEXEC)
            w = start(cmd, TIMEOUT, env=ENV, what="blockwall")
            phase = w.readline()
            expect(phase.startswith("[blockwall]"), f"no progress line: {phase!r}")
            ranks = ranks_of(w.pid)
            os.kill(ranks[1], signal.SIGSTOP)
            try:
                w.wait()
                raise Failure("the run with a stopped rank ended by itself: nothing was planted")
            except TimedOut as e:
                took = time.monotonic() - w.started
                report = e.report
            expect(took <= TIMEOUT + REPORT_SECONDS, f"the watchdog took {took:.1f} s (timeout {TIMEOUT} s)")
            check_report(report, ranks, phase, gdb)
            expect(gone([w.pid, *ranks]), f"processes of the run left: {alive([w.pid, *ranks])}")
            print(f"stopped rank pid {ranks[1]} after {phase.split()[1]}: watchdog fired at {TIMEOUT:.0f} s, report and kill "
                  f"took {took - TIMEOUT:.1f} s more; {'backtraces of both ranks down to main()' if gdb else 'no gdb: said so'}; "
                  f"last phase line shown; every process gone")
    finally:
        if old is None:
            os.environ.pop("BW_GDB", None)
        else:
            os.environ["BW_GDB"] = old


def wrapper():
    """tests/common/watchdog.py on the same hang, its budget from BW_TEST_TIMEOUT."""
    with tempfile.TemporaryDirectory() as tmp:
        cmd = blockwall.command(SCENE, [*BIG, "-output_file", os.path.join(tmp, "r.h5")], 2, exe=EXE, mpiexec=MPIEXEC)
        env = dict(ENV, BW_TEST_TIMEOUT="35")  # fires at 35 - max(30, 3.5) = 5 s
        w = start([sys.executable, os.path.join(HERE, "..", "common", "watchdog.py"), *cmd], env=env, what="watchdog.py")
        ranks = ranks_of(w.pid)
        time.sleep(0.5)  # the wrapper's output comes at its end: where the ranks are when stopped is not known
        os.kill(ranks[1], signal.SIGSTOP)
        r = w.wait()
        took = time.monotonic() - w.started
        expect(r.returncode == 1 and "FAIL: WATCHDOG: " in r.stdout, f"the wrapper: exit {r.returncode}, stdout {r.stdout[-500:]!r}")
        expect(took <= 5 + REPORT_SECONDS + 5, f"the wrapper took {took:.1f} s")
        expect("WATCHDOG: " in r.stderr, f"no report on the wrapper's stderr: {r.stderr[-500:]!r}")
        last = check_report(r.stderr[r.stderr.index("WATCHDOG: "):], ranks, None, bool(shutil.which("gdb")))
        expect(gone(ranks), f"ranks of the wrapped run left: {alive(ranks)}")
        print(f"watchdog.py: exit 1 after {took:.1f} s, FAIL line, backtraces of both ranks, last phase line "
              f"{last.split()[1] if last else '(none yet)'}, every rank gone")


CASES = {"hang": planted, "nogdb": lambda: planted(gdb=False), "wrapper": wrapper}

if __name__ == "__main__":
    if len(sys.argv) != 2 or sys.argv[1] not in CASES:
        sys.exit(f"check_watchdog.py: unknown case {sys.argv[1:]} (cases: {', '.join(CASES)})")
    try:
        CASES[sys.argv[1]]()
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
