"""Which BLAS a run loaded, as blockwall reports it (summary line and
/solver blas). tools/test runs the whole suite twice, selecting OpenBLAS
and then the reference BLAS through LD_LIBRARY_PATH, and sets
BW_EXPECT_BLAS to the selected directory: this test then fails unless the
run really loaded it, so neither pass can silently test the other's BLAS
(whatever the system's alternatives point at). It runs once without mpiexec
and once on 2 ranks under mpiexec (as most of the suite's runs start: the
selection must reach them through the launcher). Without BW_EXPECT_BLAS it
checks that some BLAS library was found and reported."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import Failure, expect, solve  # noqa: E402

SCENE = os.path.join(os.path.dirname(__file__), "..", "paper", "two_blocks.yaml")

if __name__ == "__main__":
    try:
        want = os.environ.get("BW_EXPECT_BLAS")
        for ranks in (1, 2):
            blas = solve(SCENE, np_ranks=ranks)["solver"]["blas"]
            expect(blas != "unknown" and os.path.exists(blas), f"{ranks} rank(s): no BLAS library reported: {blas!r}")
            if want:
                expect(os.path.realpath(blas).startswith(os.path.realpath(want)), f"{ranks} rank(s): expected the BLAS from {want}, the run loaded {blas}")
            print(f"{ranks} rank(s): BLAS loaded: {blas}" + (f" (expected under {want})" if want else ""))
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
