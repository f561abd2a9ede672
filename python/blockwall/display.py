"""An X display for ParaView's pvpython, which renders only through X.

Debian's ParaView 5.11 is built for X: pvpython without a display (even with
--force-offscreen-rendering) aborts when it opens its render window. Where
DISPLAY is unset, run_with_display starts an Xvfb of its own and waits until
the server accepts connections. xvfb-run is not used: with the CPUs busy it
let pvpython in before its server listened (SIGABRT in
vtkXOpenGLRenderWindow::CreateAWindow, "bad X server connection"); a fresh
CI machine met it in a 3D plot test. Even a listening server is now and then
refused by Xlib under load, so a run that died opening the display is tried
again on a new server, and the tries are reported on stderr."""
import contextlib
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time

from .launch import call

# What pvpython prints when it could not open or use the display, as opposed
# to failing in its own work (a bad file, an error in the script).
_DISPLAY_FAILURES = ("bad X server connection", "CreateAWindow", "XOpenDisplay", "Could not open display",
                     "cannot open display")


class XServer:
    """An Xvfb (24-bit screen) on a free display number, waited for until its
    socket accepts connections; terminated on exit."""

    def __init__(self, xvfb=None, screen="1600x1200x24"):
        self.exe = xvfb or find_xvfb()
        self.screen = screen
        self.proc, self.display = None, None

    def __enter__(self):
        for n in range(140, 400):
            if os.path.exists(f"/tmp/.X{n}-lock") or os.path.exists(f"/tmp/.X11-unix/X{n}"):
                continue
            proc = subprocess.Popen([self.exe, f":{n}", "-screen", "0", self.screen, "-nolisten", "tcp"],
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            t0 = time.monotonic()
            while proc.poll() is None and time.monotonic() - t0 < 60:
                try:
                    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as c:
                        c.connect(f"/tmp/.X11-unix/X{n}")
                    self.proc, self.display = proc, f":{n}"
                    return self
                except OSError:
                    time.sleep(0.05)
            proc.kill()
            proc.wait()
        raise RuntimeError("no display for Xvfb could be started (display numbers 140-399 all taken or failing)")

    def __exit__(self, *exc):
        self.proc.terminate()
        try:
            self.proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        return False


def find_xvfb():
    """The Xvfb executable: BW_XVFB (the server), or beside BW_XVFB_RUN or
    xvfb-run (Debian's package xvfb brings both), or on the PATH."""
    exe = os.environ.get("BW_XVFB")
    if exe:
        return exe
    run = os.environ.get("BW_XVFB_RUN") or shutil.which("xvfb-run")
    if run:
        beside = os.path.join(os.path.dirname(os.path.realpath(run)), "Xvfb")
        if os.path.exists(beside):
            return beside
    exe = shutil.which("Xvfb")
    if not exe:
        raise RuntimeError("pvpython needs a display: run with DISPLAY set, or install xvfb (Debian: apt-get install xvfb)")
    return exe


def display_failed(p):
    """Whether a finished pvpython died opening the display (worth a retry)."""
    return p.returncode != 0 and any(s in p.stdout + p.stderr for s in _DISPLAY_FAILURES)


@contextlib.contextmanager
def isolated_mpi(env):
    """`env` for a program built with Open MPI run as one process without
    mpiexec (ParaView's pvpython is): Open MPI's isolated singleton (no
    orted), in a session directory of its own, removed afterwards. Left to
    itself, Open MPI 4.1 forks an orted and can crash the process at its
    end (blockwall's src/util/process.c: the same in blockwall, two cores).
    A caller's own choice of either variable wins."""
    env, base = dict(env), None
    if "OMPI_MCA_ess_singleton_isolated" not in env:
        env["OMPI_MCA_ess_singleton_isolated"] = "1"
        if "OMPI_MCA_orte_tmpdir_base" not in env:
            base = env["OMPI_MCA_orte_tmpdir_base"] = tempfile.mkdtemp(prefix="blockwall-pvpython-")
    try:
        yield env
    finally:
        if base:
            shutil.rmtree(base, ignore_errors=True)


def run_with_display(cmd, timeout=600, tries=6, env=None):
    """Run cmd with a display: DISPLAY as it is when set, else an Xvfb of our
    own per try; a try that died opening the display is repeated on a new
    server, up to `tries` times. Each try is watched (launch.call: killed,
    with a backtrace, past `timeout`). Returns the RunResult (returncode,
    stdout, stderr)."""
    env = dict(os.environ if env is None else env)
    if env.get("DISPLAY"):
        with isolated_mpi(env) as e:
            return call(cmd, timeout, e, what=os.path.basename(cmd[0]))
    for attempt in range(tries):
        with XServer() as x, isolated_mpi(dict(env, DISPLAY=x.display)) as e:
            p = call(cmd, timeout, e, what=os.path.basename(cmd[0]))
        if not display_failed(p):
            break
        print(f"X: pvpython could not open the display (try {attempt + 1} of {tries}); again with a new server",
              file=sys.stderr)
    return p
