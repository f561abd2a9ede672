"""A command that ctest starts itself (mpiexec ... test_system, test_newton,
test_scene on two ranks), run under the watchdog every Python check has
(bwrun.start, blockwall.launch.Watched): if it has not ended when the
test's time is nearly up (BW_TEST_TIMEOUT, ctest's TIMEOUT of the test,
less the watchdog's margin), its process tree, a gdb backtrace of every
rank and its last output lines are printed, the process group is killed
and the test fails; otherwise its output and exit code are passed on.

usage: watchdog.py COMMAND [ARG ...]"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bwrun import Failure, start  # noqa: E402

if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    try:
        r = start(sys.argv[1:]).wait()
    except Failure as e:
        print(f"FAIL: {e}")
        sys.exit(1)
    sys.stdout.write(r.stdout)
    sys.stderr.write(r.stderr)
    # a rank killed by a signal: the shell's 128 + signal, not a negative code
    sys.exit(r.returncode if r.returncode >= 0 else 128 - r.returncode)
