"""Running blockwall from Python: one launcher for scripts, examples and tests.

    from blockwall import run, solve
    r = run("examples/demo.yaml", ["-discretization_m", 8], ranks=2)   # r.returncode, r.stdout, r.stderr
    res = solve("examples/demo.yaml", ranks=2)                          # Results of a temporary output

The executable: `exe`, else $BW_EXE, else `blockwall` on $PATH, else the
build tree's build/bin/blockwall beside this package's source checkout.
mpiexec: `mpiexec`, else $BW_MPIEXEC, else `mpiexec` on $PATH; it is used
only for ranks > 1. With Open MPI the launcher passes --oversubscribe
(more ranks than cores, as on a laptop or a 2-core CI machine) and sets
OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1, without which
Open MPI refuses to start as root (containers, CI).

A run with a `timeout` is watched: it runs in a session (process group) of
its own (killed with it if Python is interrupted or exits first), and if it
has not ended by then the watchdog prints what each of
its processes was doing -- the process tree, a backtrace of every rank
(`gdb -batch -p PID -ex 'thread apply all bt'`; $BW_GDB names gdb, Debian
package gdb) and the last lines of its stdout and stderr, the last
`-progress` phase line among them -- then kills the whole group and raises
RunTimeout with that report. `call` does the same for any command, `start`
returns the watched process for callers that talk to it (signals, reading
its output line by line) before they `wait` for it."""
from __future__ import annotations

import atexit
import functools
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass

from .results import read

ROOT_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
            "OMPI_MCA_rmaps_base_oversubscribe": "1"}


class RunError(RuntimeError):
    """blockwall exited non-zero; the message holds the command, stdout and stderr."""

    def __init__(self, message, result):
        super().__init__(message)
        self.result = result


class RunTimeout(RunError, subprocess.TimeoutExpired):
    """A watched run that had not ended within its timeout, killed; the
    message says which and when, `report` holds the watchdog's whole report
    (printed on stderr when it fired). A subprocess.TimeoutExpired too, for
    callers that catch that."""

    def __init__(self, message, result, timeout):
        RunError.__init__(self, message, result)
        self.cmd, self.timeout, self.output, self.stderr = result.cmd, timeout, result.stdout, result.stderr
        self.report = message

    def __str__(self):
        return self.args[0]


@dataclass
class RunResult:
    cmd: list
    returncode: int
    stdout: str
    stderr: str


def environment(base=None):
    """The environment blockwall runs in: `base` (default os.environ) plus Open MPI's root and oversubscribe variables."""
    return dict(os.environ if base is None else base, **ROOT_ENV)


def find_executable(exe=None):
    if exe:
        return os.fspath(exe)
    if os.environ.get("BW_EXE"):
        return os.environ["BW_EXE"]
    found = shutil.which("blockwall")
    if found:
        return found
    checkout = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    return os.path.join(checkout, "build", "bin", "blockwall")


def find_mpiexec(mpiexec=None):
    return os.fspath(mpiexec) if mpiexec else os.environ.get("BW_MPIEXEC") or shutil.which("mpiexec") or "mpiexec"


@functools.lru_cache(maxsize=8)
def is_open_mpi(mpiexec):
    try:
        p = subprocess.run([mpiexec, "--version"], capture_output=True, text=True, timeout=60, env=environment())
    except (OSError, subprocess.SubprocessError):
        return False
    text = p.stdout + p.stderr
    return "Open MPI" in text or "OpenRTE" in text


def command(scene, args=(), ranks=1, exe=None, mpiexec=None):
    """The command line that runs `scene` on `ranks` ranks."""
    cmd = [find_executable(exe), "-scene", os.fspath(scene), *map(str, args)]
    if ranks > 1:
        launcher = find_mpiexec(mpiexec)
        extra = ["--oversubscribe"] if is_open_mpi(launcher) else []
        cmd = [launcher, *extra, "-n", str(int(ranks)), *cmd]
    return cmd


# ---------------------------------------------------------------- watchdog

# MPI launchers and their daemons: not backtraced (the ranks below them are)
LAUNCHERS = {"mpiexec", "mpirun", "orterun", "prterun", "orted", "prted", "prte", "hydra_pmi_proxy",
             "mpiexec.hydra", "mpiexec.openmpi", "mpirun.openmpi"}
MAX_BACKTRACES = 8  # processes backtraced in one report
GDB_SECONDS = 20    # the most one gdb may take (it loads every library's symbols: 10 s on 2 busy cores)
TAIL_LINES = 20     # lines of stdout and of stderr shown

_running = set()    # watched processes not yet reaped: killed if Python exits first


class _Stalls:
    """How long this machine stopped running us: a thread that wakes every
    TICK seconds and keeps the gaps between its wake-ups longer than STALL
    (a virtual machine paused by its host, or starved of CPU by it: CI
    machines have shown both, every test on them slow or still for minutes
    at once). A watchdog report says so, with the CPU's steal time from
    /proc/stat over the same interval, so that a timeout on a stalled
    machine is not read as a hang of blockwall's."""
    TICK, STALL = 0.5, 5.0

    def __init__(self):
        self.gaps = []  # (monotonic time at the end of the gap, its length [s])
        self.steal0 = self.steal()
        t = threading.Thread(target=self._run, daemon=True)
        t.start()

    @staticmethod
    def steal():
        """Seconds of CPU time the host took from this machine (all CPUs), or None."""
        try:
            with open("/proc/stat") as f:
                fields = f.readline().split()
            return int(fields[8]) / os.sysconf("SC_CLK_TCK")
        except (OSError, IndexError, ValueError):
            return None

    def _run(self):
        last = time.monotonic()
        while True:
            time.sleep(self.TICK)
            now = time.monotonic()
            if now - last > self.STALL:
                self.gaps.append((now, now - last - self.TICK))
            last = now

    def summary(self, since):
        gaps = [g for t, g in self.gaps if t >= since]
        steal, s = self.steal(), self.steal0
        stolen = f"{steal - s:.0f} s of CPU time stolen by the host since the first watched run" if steal is not None and s is not None else "steal time unknown"
        load = ""
        try:
            with open("/proc/loadavg") as f:
                load = "load average " + " ".join(f.read().split()[:3]) + "; "
        except OSError:
            pass
        if gaps:
            return (f"{load}the machine stood still {len(gaps)} time(s) while this run was watched, "
                    f"{sum(gaps):.0f} s in all (longest {max(gaps):.0f} s): a paused or starved machine, not a slow run; {stolen}")
        return f"{load}no stall of this machine seen while the run was watched (ticks every {self.TICK} s); {stolen}"


@functools.lru_cache(maxsize=1)
def stalls():
    return _Stalls()


def process_table():
    """{pid: (ppid, comm, state)} of every process now visible in /proc."""
    table = {}
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            with open(f"/proc/{d}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        comm, rest = stat[stat.index("(") + 1:stat.rindex(")")], stat[stat.rindex(")") + 2:].split()
        table[int(d)] = (int(rest[1]), comm, rest[0])
    return table


def descendants(pid):
    """pid and every process below it, parents before children: [(pid, comm, state)]."""
    table = process_table()
    children = {}
    for p, (ppid, _, _) in table.items():
        children.setdefault(ppid, []).append(p)
    out, todo = [], [pid]
    while todo:
        p = todo.pop(0)
        if p in table:
            out.append((p, table[p][1], table[p][2]))
        todo += sorted(children.get(p, []))
    return out


def backtrace(pid, gdb=None):
    """`thread apply all bt` of a running process by gdb (a few seconds), or why there is none."""
    gdb = gdb or os.environ.get("BW_GDB", "gdb")
    exe = shutil.which(gdb)
    if not exe:
        return f"(no backtrace: {gdb} not found; Debian package gdb)"
    cmd = [exe, "-nx", "-batch", "-p", str(pid), "-iex", "set debuginfod enabled off", "-ex", "set pagination off",
           "-ex", "thread apply all bt"]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=GDB_SECONDS, stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        return f"(no backtrace: gdb did not finish within {GDB_SECONDS} s)"
    # gdb's own chatter (symbol loading, [New LWP ...]) is left out: the threads and frames are the point
    lines = [l for l in p.stdout.splitlines() if l.startswith(("Thread ", "#")) or l.strip().startswith("#")]
    if not lines:
        return f"(no backtrace: gdb exit {p.returncode}: {(p.stderr.strip() or p.stdout.strip())[-500:]})"
    return "\n".join(lines)


class Watched:
    """A command, its stdout and stderr read as they come (so that a report
    can show their last lines), and with a `timeout` a watchdog that reports
    and kills it after that many seconds; a watched command runs in a
    session of its own, so that the kill reaches every process it started.

        w = Watched(cmd, timeout=60, env=env)
        line = w.readline()        # stdout, line by line ("" at its end)
        w.proc.send_signal(...)    # the Popen, for signals and pids
        result = w.wait()          # RunResult; RunTimeout if the watchdog fired

    `error` is the exception class raised on a timeout (a RunTimeout), so
    that a caller can have its own."""

    def __init__(self, cmd, timeout=None, env=None, cwd=None, what=None, diagnose=True, error=RunTimeout):
        self.cmd, self.timeout, self.what, self.diagnose, self.error = list(map(str, cmd)), timeout, what, diagnose, error
        self.out, self.err = [], []
        self.report = None  # the watchdog's report, once it fired
        self._expiring, self._reported = False, threading.Event()
        self._lock = threading.Condition()
        self._out_done = False
        self._next = 0  # lines of stdout returned by readline
        self.started = time.monotonic()
        if timeout is not None:
            stalls()  # start measuring stalls of the machine with the first watched run
        self.proc = subprocess.Popen(self.cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     text=True, errors="replace", env=env, cwd=cwd,
                                     start_new_session=timeout is not None)
        _running.add(self)
        self._readers = [threading.Thread(target=self._read, args=(self.proc.stdout, self.out, True), daemon=True),
                         threading.Thread(target=self._read, args=(self.proc.stderr, self.err, False), daemon=True)]
        for t in self._readers:
            t.start()
        self._timer = None
        if timeout is not None:
            self._timer = threading.Timer(max(0.0, timeout), self.expire)
            self._timer.daemon = True
            self._timer.start()

    @property
    def pid(self):
        return self.proc.pid

    def _read(self, stream, lines, is_stdout):
        for line in stream:
            with self._lock:
                lines.append(line)
                self._lock.notify_all()
        with self._lock:
            if is_stdout:
                self._out_done = True
            self._lock.notify_all()

    def readline(self):
        """The next line of stdout not yet returned by readline ("" once
        stdout has ended). Raises the timeout error if the watchdog fired."""
        with self._lock:
            while self._next >= len(self.out) and not self._out_done and not self._expiring:
                self._lock.wait(1.0)
            if not self._expiring and self._next < len(self.out):
                self._next += 1
                return self.out[self._next - 1]
        if self._expiring:
            raise self._timeout_error()
        return ""

    def poll(self):
        return self.proc.poll()

    def expire(self, why=None):
        """The watchdog: report what the run was doing, kill its process
        group and every process below it. Called by the timer, or by wait()
        when its own timeout passes first."""
        with self._lock:
            if self._expiring or self.proc.poll() is not None:
                return
            self._expiring = True  # claimed: a second call returns at once
            self._lock.notify_all()
        waited = time.monotonic() - self.started
        tree = descendants(self.proc.pid)
        name = self.what or os.path.basename(self.cmd[0])
        lines = [f"WATCHDOG: {name} did not end within {why or f'{self.timeout:.0f} s'} "
                 f"({waited:.0f} s since it started); killed.",
                 f"  command: {' '.join(self.cmd)}",
                 "  processes: " + ", ".join(f"{p} {c} ({s})" for p, c, s in tree),
                 f"  machine: {stalls().summary(self.started)}"]
        # the head at once: if the test's own deadline (ctest's TIMEOUT)
        # comes while gdb runs, what the processes were doing is on record
        print("\n".join(lines) + "\n  (backtraces follow)", file=sys.stderr, flush=True)
        head = len(lines)
        if self.diagnose:
            ranks = [(p, c) for p, c, _ in tree if c not in LAUNCHERS][:MAX_BACKTRACES]
            traces = {}
            threads = [threading.Thread(target=lambda p=p: traces.__setitem__(p, backtrace(p))) for p, _ in ranks]
            for t in threads:
                t.start()
            for t in threads:
                t.join(GDB_SECONDS + 5)
            for p, c in ranks:
                lines += [f"--- backtrace of {c} pid {p}:", traces.get(p, "(no backtrace: gdb did not return)")]
        with self._lock:
            out, err = list(self.out), list(self.err)
        phase = [l.rstrip() for l in out if l.startswith("[blockwall]")]
        lines.append(f"--- last phase line: {phase[-1] if phase else '(none: no -progress line)'}")
        lines.append(f"--- last {TAIL_LINES} lines of stdout:")
        lines += [l.rstrip("\n") for l in out[-TAIL_LINES:]] or ["(none)"]
        lines.append(f"--- last {TAIL_LINES} lines of stderr:")
        lines += [l.rstrip("\n") for l in err[-TAIL_LINES:]] or ["(none)"]
        self._kill([p for p, _, _ in tree])
        report = "\n".join(lines)
        print("\n".join(lines[head:]), file=sys.stderr, flush=True)
        self.report = report
        self._reported.set()

    def _kill(self, pids):
        group = [lambda: os.killpg(self.proc.pid, signal.SIGKILL)] if self._timer is not None else []
        for kill in group + [lambda p=p: os.kill(p, signal.SIGKILL) for p in pids]:
            try:
                kill()
            except OSError:  # already gone
                pass

    def _timeout_error(self):
        """The error to raise once the watchdog fired (after its report is written)."""
        self._reported.wait()
        result = RunResult(self.cmd, self.proc.returncode if self.proc.returncode is not None else -9,
                           "".join(self.out), "".join(self.err))
        head = self.report.splitlines()[:2]
        e = self.error("\n".join(head) + "\n  (the watchdog's report, with the backtraces, is on stderr)", result, self.timeout)
        e.report = self.report
        return e

    def wait(self, timeout=None):
        """Wait for the end of the run and of its output; RunResult. With
        `timeout`, a run still going after that many seconds is treated as
        by the watchdog (report, kill). Raises the timeout error if the
        watchdog fired."""
        try:
            self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.expire(f"{timeout:.0f} s")
            self.proc.wait()
        except KeyboardInterrupt:  # a session of its own does not see the terminal's Ctrl-C
            self._kill([p for p, _, _ in descendants(self.proc.pid)])
            raise
        for t in self._readers:
            t.join(30)  # a grandchild that escaped the kill may hold the pipes: do not wait for ever
        if self._timer is not None:
            self._timer.cancel()
        _running.discard(self)
        if self._expiring:
            raise self._timeout_error()
        return RunResult(self.cmd, self.proc.returncode, "".join(self.out), "".join(self.err))


@atexit.register
def _kill_leftovers():
    for w in list(_running):
        if w.proc.poll() is None:
            w._kill([p for p, _, _ in descendants(w.proc.pid)])


def start(cmd, timeout=None, env=None, cwd=None, what=None, diagnose=True, error=RunTimeout):
    """Start `cmd` watched (class Watched); env is used as given (None: this process's)."""
    return Watched(cmd, timeout, env, cwd, what, diagnose, error)


def call(cmd, timeout=None, env=None, cwd=None, what=None, diagnose=True, error=RunTimeout):
    """Run any command to its end under the watchdog: RunResult (returncode,
    stdout, stderr), or the timeout error with the watchdog's report."""
    return start(cmd, timeout, env, cwd, what, diagnose, error).wait()


def run(scene, args=(), ranks=1, exe=None, mpiexec=None, check=True, timeout=None, cwd=None, env=None, diagnose=True):
    """Run blockwall on `scene` with extra options `args` on `ranks` MPI ranks.
    Returns a RunResult; with check=True a non-zero exit raises RunError.
    With `timeout` the run is watched (module docstring): RunTimeout, with
    the ranks' backtraces (diagnose=False: without), if it has not ended."""
    cmd = command(scene, args, ranks, exe, mpiexec)
    result = call(cmd, timeout, environment(env), cwd, "blockwall", diagnose)
    if check and result.returncode != 0:
        raise RunError(f"blockwall failed ({result.returncode}): {' '.join(cmd)}\n{result.stdout}\n{result.stderr}", result)
    return result


def solve(scene, args=(), ranks=1, output=None, **kwargs):
    """Run blockwall and read its result: to `output` if given (kept), else
    to a temporary file (removed after reading). Returns Results."""
    if output is not None:
        run(scene, [*args, "-output_file", os.fspath(output)], ranks, **kwargs)
        return read(output)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.h5")
        run(scene, [*args, "-output_file", out], ranks, **kwargs)
        return read(out)
