"""Rank-count invariance: the same scene on 1 and N ranks writes the same
results, in input order, datasets compared one by one.

usage: check_ranks.py SCENE NRANKS TOL [blockwall options]
TOL is the relative tolerance: 1e-12 where the partition cannot change the
order of floating-point sums (two blocks), 1e-10 for walls, whose partition
changes the order in which MUMPS eliminates."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import Failure, expect, rel_err, solve  # noqa: E402

RESULTS = ("blocks/displacement", "blocks/reaction", "interfaces/stress", "interfaces/resultant",
           "interfaces/relative_displacement", "blocks/centroid", "blocks/load", "blocks/prescribed",
           "interfaces/blocks", "interfaces/center", "interfaces/kn")

if __name__ == "__main__":
    scene, nranks, tol, args = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), sys.argv[4:]
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
            expect(e < tol, f"{key} differs by {e:.2e} between 1 and {nranks} ranks")
        print(f"1 vs {nranks} ranks: worst relative difference {worst:.2e}")
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
