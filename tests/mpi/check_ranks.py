"""Rank-count invariance: the same scene on 1 and N ranks writes the same
results, in input order, to 1e-12 relative (datasets compared one by one)."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import Failure, expect, rel_err, solve  # noqa: E402

RESULTS = ("blocks/displacement", "blocks/reaction", "interfaces/stress", "interfaces/resultant",
           "interfaces/relative_displacement", "blocks/centroid", "blocks/load", "blocks/prescribed",
           "interfaces/blocks", "interfaces/center", "interfaces/kn")

if __name__ == "__main__":
    scene, nranks, args = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
    try:
        one = solve(scene, args, 1)
        many = solve(scene, args, nranks)
        expect(many["solver"]["ranks"] == nranks, "rank count not recorded")
        worst = 0.0
        for key in RESULTS:
            if key not in one:
                continue
            expect(one[key].shape == many[key].shape, f"{key}: shapes {one[key].shape} vs {many[key].shape}")
            e = rel_err(many[key], one[key])
            worst = max(worst, e)
            expect(e < 1e-12, f"{key} differs by {e:.2e} between 1 and {nranks} ranks")
        print(f"1 vs {nranks} ranks: worst relative difference {worst:.2e}")
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
