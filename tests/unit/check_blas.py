"""Which BLAS a run loaded, as blockwall reports it (summary line and
/solver blas). tools/test runs the whole suite twice, selecting OpenBLAS
and then the reference BLAS through LD_LIBRARY_PATH, and sets
BW_EXPECT_BLAS to the selected directory: this test then fails unless the
run really loaded it, so neither pass can silently test the other's BLAS
(whatever the system's alternatives point at). It runs once without mpiexec
and once on 2 ranks under mpiexec (as most of the suite's runs start: the
selection must reach them through the launcher). Without BW_EXPECT_BLAS it
checks that some BLAS library was found and reported.

With OpenBLAS, the kernels it computes with (/solver blas_kernels) are
not its generic Prescott fallback on a CPU that has AVX2 and FMA: Debian
12's OpenBLAS falls back to them on Intel CPUs newer than it (Sapphire and
Emerald Rapids), and blockwall then starts again with OPENBLAS_CORETYPE set
(src/util/process.c). Checked with OPENBLAS_CORETYPE unset, as a user's
shell has it; with OPENBLAS_CORETYPE=Prescott given, the user's choice is
kept."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
import bwrun  # noqa: E402
from bwrun import Failure, expect, solve  # noqa: E402

SCENE = os.path.join(os.path.dirname(__file__), "..", "paper", "two_blocks.yaml")

def cpu_flags():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("flags"):
                    return set(line.split(":", 1)[1].split())
    except OSError:
        pass
    return set()


if __name__ == "__main__":
    try:
        want = os.environ.get("BW_EXPECT_BLAS")
        bwrun.ENV.pop("OPENBLAS_CORETYPE", None)
        vector = {"avx2", "fma"} <= cpu_flags()
        for ranks in (1, 2):
            solver = solve(SCENE, np_ranks=ranks)["solver"]
            blas, kernels = solver["blas"], solver["blas_kernels"]
            if "openblas" in blas.lower():
                expect(kernels != "", f"{ranks} rank(s): OpenBLAS loaded ({blas}) but no kernels reported")
                if vector:
                    expect(kernels != "Prescott", f"{ranks} rank(s): OpenBLAS computes with its Prescott (SSE3) kernels on a CPU with AVX2 and FMA")
            else:
                expect(kernels == "", f"{ranks} rank(s): kernels {kernels!r} reported for a BLAS that is not OpenBLAS ({blas})")
            print(f"{ranks} rank(s): kernels {kernels or '(not OpenBLAS)'}; CPU with AVX2 and FMA: {vector}")
            expect(blas != "unknown" and os.path.exists(blas), f"{ranks} rank(s): no BLAS library reported: {blas!r}")
            if want:
                expect(os.path.realpath(blas).startswith(os.path.realpath(want)), f"{ranks} rank(s): expected the BLAS from {want}, the run loaded {blas}")
            print(f"{ranks} rank(s): BLAS loaded: {blas}" + (f" (expected under {want})" if want else ""))
        bwrun.ENV["OPENBLAS_CORETYPE"] = "Prescott"
        kernels = solve(SCENE)["solver"]["blas_kernels"]
        expect(kernels in ("", "Prescott"), f"OPENBLAS_CORETYPE=Prescott given, the run computed with {kernels!r}")
        print(f"OPENBLAS_CORETYPE=Prescott given: kernels {kernels or '(not OpenBLAS)'}")
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
