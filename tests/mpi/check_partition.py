"""The partition's figures (interface.md, additions of 2026-11-26):
/solver partition_edge_cut (interfaces whose two blocks live on different
ranks) and partition_imbalance (the largest rank's blocks over the mean),
in the summary and the file.

  figures SCENE NP...   on 1 rank exactly 0 and 1.0; on NP ranks an edge
                        cut above 0 (the wall is connected, so some
                        interface crosses) and below a quarter of the
                        interfaces, an imbalance in [1, 1.3] (the issue's
                        bound for a rank's share), the summary's line equal
                        to the file's attributes, and the answer equal to 1
                        rank's to 1e-10 (whatever the partition).
  options SCENE         the partitioner's own options (-partition_, PETSc's
                        MatPartitioning) are taken on 2 ranks and, unused,
                        on 1 rank and with partition.method natural; a
                        misspelt one is refused on 2 ranks with the line
                        naming it (before: refused as unknown everywhere)."""
import os
import re
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
from bwrun import Failure, expect, read, rel_err, run  # noqa: E402


def figures(scene, ranks):
    with tempfile.TemporaryDirectory() as tmp:
        ref = None
        for np_ in [1, *ranks]:
            out = os.path.join(tmp, f"out{np_}.h5")
            _, stdout, _ = run(scene, ["-output_file", out], np_)
            res = read(out)
            sv = res["solver"]
            cut, imb = int(sv["partition_edge_cut"]), float(sv["partition_imbalance"])
            m = re.search(r"partition: edge cut (\d+) interfaces, imbalance ([0-9.]+)", stdout)
            expect(m is not None, f"{np_} ranks: no partition line in the summary:\n{stdout}")
            expect(int(m.group(1)) == cut and abs(float(m.group(2)) - imb) <= 5e-4, f"{np_} ranks: summary {m.group(0)!r}, file {cut}, {imb}")
            ni = len(res["interfaces/blocks"])
            if np_ == 1:
                expect(cut == 0 and imb == 1.0, f"1 rank: edge cut {cut}, imbalance {imb}; expected 0 and 1.0")
                ref = res
            else:
                expect(0 < cut < ni / 4, f"{np_} ranks: edge cut {cut} of {ni} interfaces")
                expect(1.0 <= imb <= 1.3, f"{np_} ranks: imbalance {imb}")
                for key in ("blocks/displacement", "interfaces/stress"):
                    e = rel_err(res[key], ref[key])
                    expect(e <= 1e-10, f"{np_} ranks: {key} differs from 1 rank's by {e:.2e}")
            print(f"{np_} rank(s): edge cut {cut} of {ni} interfaces, imbalance {imb:.3f}")


def options(scene):
    good = ["-partition_mat_partitioning_type", "ptscotch"]
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.h5")
        for np_, extra in ((2, []), (1, []), (2, ["-partition_method", "natural"])):
            run(scene, ["-output_file", out, *good, *extra], np_)
            print(f"{np_} rank(s) {' '.join(extra)}: {' '.join(good)} taken")
        bad = "-partition_mat_partitioning_typo"
        code, _, err = run(scene, ["-output_file", out, bad, "ptscotch"], 2, expect_ok=False)
        lines = [l for l in err.splitlines() if l.startswith("blockwall:")]
        expect(code == 1 and len(lines) == 1 and bad in lines[0], f"{bad} on 2 ranks: exit {code}, {err.strip()}")
        print(f"2 ranks, {bad}: exit 1, {lines[0]}")


if __name__ == "__main__":
    try:
        if len(sys.argv) >= 4 and sys.argv[1] == "figures":
            figures(sys.argv[2], [int(n) for n in sys.argv[3:]])
        elif len(sys.argv) == 3 and sys.argv[1] == "options":
            options(sys.argv[2])
        else:
            raise Failure(f"usage: check_partition.py figures SCENE NP... | options SCENE (got {sys.argv[1:]})")
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
