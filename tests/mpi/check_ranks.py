"""Rank-count invariance: the same scene on 1 and N ranks writes the same
results, in input order, datasets compared one by one.

usage: check_ranks.py SCENE NRANKS[,NRANKS...] TOL [blockwall options]
(several rank counts: the 1-rank run once, each compared with it)
TOL is the relative tolerance: 1e-12 where the partition cannot change the
order of floating-point sums (two blocks), 1e-10 for walls, whose partition
changes the order in which MUMPS eliminates.

Both files must hold the same datasets (one written on 1 rank and not on N,
or the other way, fails), and each of RESULTS must be in them: a result
left out of both would otherwise be compared by nobody."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
from bwrun import Failure, each, expect, rel_err, solve  # noqa: E402

RESULTS = ("blocks/displacement", "blocks/reaction", "interfaces/stress", "interfaces/resultant",
           "interfaces/relative_displacement", "blocks/centroid", "blocks/load", "blocks/prescribed",
           "interfaces/blocks", "interfaces/center", "interfaces/kn")

def compare(one, many, nranks, tol):
    expect(many["solver"]["ranks"] == nranks, "rank count not recorded")
    datasets = {k for k in one if k not in ("attrs", "solver")}, {k for k in many if k not in ("attrs", "solver")}
    expect(datasets[0] == datasets[1], f"datasets written on 1 rank only: {sorted(datasets[0] - datasets[1])}, "
                                       f"on {nranks} ranks only: {sorted(datasets[1] - datasets[0])}")
    missing = [key for key in RESULTS if key not in one]
    expect(not missing, f"results not written on 1 or on {nranks} ranks: {missing}")
    worst = 0.0
    for key in RESULTS:
        expect(one[key].shape == many[key].shape, f"{key}: shapes {one[key].shape} vs {many[key].shape}")
        e = rel_err(many[key], one[key])
        worst = max(worst, e)
        expect(e < tol, f"{key} differs by {e:.2e} between 1 and {nranks} ranks")
    print(f"1 vs {nranks} ranks: {len(datasets[0])} datasets in both, the {len(RESULTS)} results compared: "
          f"worst relative difference {worst:.2e}")


if __name__ == "__main__":
    scene, counts, tol, args = sys.argv[1], [int(n) for n in sys.argv[2].split(",")], float(sys.argv[3]), sys.argv[4:]
    try:
        one = solve(scene, args, 1)
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
    each(counts, lambda nranks: compare(one, solve(scene, args, nranks), nranks, tol), lambda n: f"{n} ranks")
