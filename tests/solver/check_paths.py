"""Solver paths against each other and against the closed form.

  agree     fieldsplit and direct (MUMPS LU + refinement) give the same
            displacements and stresses to 1e-10 on the paper's cases 3 and 8
  fallback  a fieldsplit forced to fail (one outer iteration with a Jacobi
            Schur solve) makes `auto` fall back to direct, records it in
            /solver, and the answer is still the closed form's
  strict    the same failure with solver.method: fieldsplit is an error
  gamg_fallback  on the demo wall, a CG+GAMG fieldsplit forced to fail (one
            outer step) falls back first to the fieldsplit with S^ factored
            by MUMPS, which answers: recorded in /solver, equal to the direct
            path's answer to 1e-10
  floor     a CG+GAMG fieldsplit asked for a residual below its round-off
            floor (rtol 1e-16 on the demo wall, whose residual stops near
            1e-14 on any CPU) with the displacements' forward_rtol 1e-8,
            which the first steps meet: it stops as stalled within a few
            steps (not at its 30-step limit), `auto` does not factor S^
            (two set-ups: GAMG and the direct path, which stops at its own
            floor), the reason names the floor, accuracy_met 0, and the
            answer equals the direct path's to 1e-10. The floor is measured:
            rounding the displacements to double alone leaves a residual up
            to eps |S~| |q| / |b| (solvers.md), which the residual reached
            is within (5-7x below it measured, 2D and 3D): the warning and
            /solver residual_floor give that floor, the same on 3 ranks
  warn      a tolerance below double precision's reach (rtol 1e-18) is missed
            by every path: the run still writes the best answer, says so on
            stdout (WARNING) and in /solver (accuracy_met 0, warning), and
            that answer equals the normal one to 1e-12
  wall      on the demo shear wall (92 blocks), every path
            and storage (fieldsplit with D^ as a shell, on the nest with D^
            assembled, on one AIJ,
            direct, condensed, fieldsplit with CG+GAMG) gives the same
            displacements, stresses and reactions: to 1e-10 for the exact
            paths, to 1e-8 for GAMG, whose residual is only asked to reach 1e-10
  ptap      GAMG's Galerkin products by another of PETSc's algorithms
            (-matptap_via allatonce, which holds less memory on several
            ranks: docs/cluster.md) on 2 ranks, a 3D wall (bench's
            large_wall3d at 24 x 24 units): the option is taken, and the
            displacements equal those of PETSc's default algorithm to 1e-8
            (the two products differ in their sums' order; CG is asked for
            a residual of 1e-10), both within 1e-8 of S^ factored (the direct
            path on the whole saddle matrix gives the same to 1e-14, in 15
            times the time)
  analysis  where MUMPS orders (analyses) S^ on several ranks, in /solver
            factor_analysis: "" on 1 rank; on 2 ranks "rank 0" or
            "parallel", as the MUMPS PETSc calls can (PT-Scotch or ParMETIS
            built in: its mumps_dgraphinit or mumps_parmetis); given the
            libraries of a MUMPS built with PT-Scotch (argument 2,
            LD_PRELOAD: Debian's libmumps-ptscotch-5.5, found by CMake), 2
            ranks order in parallel. The 3D wall of the bench at 24 x 24
            units (S^ factored by MUMPS under auto): every answer's
            displacements within 1e-10 of one rank's, accuracy_met
  compression  the same wall on 2 ranks, whose S^ splits into two groups of
            dofs (u1 u2 w3 | u3 w1 w2): MUMPS gets its graph uncompressed
            (ICNTL(15) = 0, schur.c), so the groups stay apart in the
            ordering: the factor has at most 0.6 x the entries (INFOG(20))
            of the factor of the graph compressed by blocks of 6 (PETSc's
            default, given as -schur_mat_mumps_icntl_15 -6: the user's
            option wins), 0.5 x when the groups are factored apart; the two
            answers within 1e-10 of each other
  memory    auto's Schur solve on a split 3D S^ is chosen by the run's
            memory estimate: the same wall on 2 ranks factors S^ when the
            estimate fits (the summary says so), takes CG + GAMG when
            solver.memory (GB, summed over the ranks) is below it, its
            answer within 1e-8 of the factored one (CG is asked for a
            residual of 1e-10); a 2D wall (S^ does not split) factors S^
            whatever solver.memory says; solver.memory < 0 is an error
            naming the key, with no file written
  low_rank  S^ factored by MUMPS in block low-rank form (solver.low_rank):
            the bench's 3D wall at 300 x 300 units (9e4 blocks, the smallest
            square wall whose fronts MUMPS compresses) on 2 ranks with
            `always`: the summary and /solver factor_low_rank_ratio say the
            factor holds fewer entries than in full rank (< 0.98; 0.90
            measured). The same with a compression too coarse for the
            refinement (-schur_mat_mumps_cntl_7 1e-3: the user's option
            wins): `auto` falls back to S^ factored again in full rank,
            recorded in /solver (fallback 1, its reason, ratio -1). The two
            answers, one refined from a low-rank factor and one from a
            full-rank factor, within 1e-9 of each other, the first's
            residual within 3x the second's (both at the floor of rounding
            the displacements). Under auto, the 24 x 24 wall has no
            low-rank factor (ratio -1: below 1e6 rows of S^); with `always`
            on 1 rank MUMPS factors it (not CHOLMOD), its fronts too small
            to compress (ratio 1); `always` with solver.reproducible is an
            error naming the key, with no file written
  alone     a path that stops at the round-off floor where no other path
            can run (the bench's 3D wall at 100 x 100 units on 2 ranks: S^
            factored, the saddle matrix too large for the direct path;
            rtol 1e-14, below the floor on any CPU): its answer is written
            with /solver fallback 0 and fallback_reason "" (nothing fell
            back), accuracy_met 0, and the warning says that no other path
            ran, why, and names the floor
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "common"))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "paper"))
from bwrun import Failure, expect, rel_err, run  # noqa: E402
from check_paper import SCENE, run_case  # noqa: E402

FORCE_FAIL = ["-ksp_max_it", 1, "-schur_pc_type", "jacobi"]
# the demo shear wall (2D, 92 blocks)
DEMO = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "demo.yaml")


def agree():
    for case in (3, 8):
        fs, (q_ref, _) = run_case(case, args=["-solver_method", "fieldsplit"])
        dr, _ = run_case(case, args=["-solver_method", "direct"])
        expect(fs["solver"]["method_used"] == "fieldsplit", "fieldsplit path not used")
        expect(dr["solver"]["method_used"] == "direct", "direct path not used")
        for key in ("blocks/displacement", "interfaces/stress", "interfaces/resultant", "blocks/reaction"):
            e = rel_err(dr[key], fs[key])
            expect(e < 1e-10, f"case {case}: {key} differs by {e:.2e} between fieldsplit and direct")
        e = rel_err(dr["blocks/displacement"][1], q_ref)
        expect(e < 1e-10, f"case {case}: direct vs closed form {e:.2e}")
        print(f"case {case}: fieldsplit vs direct {rel_err(dr['blocks/displacement'], fs['blocks/displacement']):.1e}; "
              f"residuals {fs['solver']['residual']:.1e} / {dr['solver']['residual']:.1e}")


def fallback():
    res, (q_ref, _) = run_case(2, args=FORCE_FAIL)
    s = res["solver"]
    expect(s["fallback"] == 1 and s["method_used"] == "direct" and s["method_requested"] == "auto",
           f"no fallback recorded: {s}")
    expect("fieldsplit" in s["fallback_reason"] and "DIVERGED_ITS" in s["fallback_reason"],
           f"fallback reason does not say why: {s['fallback_reason']!r}")
    e = rel_err(res["blocks/displacement"][1], q_ref)
    expect(e < 1e-10, f"fallback answer vs closed form {e:.2e}")
    print(f"fallback recorded: {s['fallback_reason']}; answer vs closed form {e:.1e}")


def strict():
    code, out, err = run(SCENE, ["-solver_method", "fieldsplit", *FORCE_FAIL, "-output_file", "/tmp/bw_strict_never.h5"],
                         expect_ok=False)
    expect(code != 0, "a failed fieldsplit with method fieldsplit must fail the run")
    expect("solver failed" in err and "DIVERGED_ITS" in err, f"message: {err!r}")
    expect(not os.path.exists("/tmp/bw_strict_never.h5"), "output written after a failed solve")
    print("strict fieldsplit failure:", err.strip().splitlines()[0])


def wall():
    from bwrun import solve
    scene = DEMO
    ref = solve(scene, ["-solver_method", "fieldsplit"])
    variants = {"aij storage": (["-solver_storage", "aij"], 1e-10), "nest storage": (["-solver_storage", "nest"], 1e-10), "direct": (["-solver_method", "direct"], 1e-10),
                "condensed": (["-solver_method", "condensed"], 1e-10), "gamg": (["-solver_schur", "gamg"], 1e-8)}
    for name, (args, tol) in variants.items():
        res = solve(scene, args)
        for key in ("blocks/displacement", "interfaces/stress", "blocks/reaction"):
            e = rel_err(res[key], ref[key])
            expect(e < tol, f"{name}: {key} differs from fieldsplit by {e:.2e}")
        expect(res["solver"]["residual"] < 1e-10, f"{name}: residual {res['solver']['residual']}")
        print(f"{name}: agrees with fieldsplit to {rel_err(res['blocks/displacement'], ref['blocks/displacement']):.1e} "
              f"({res['solver']['method_used']}, {res['solver']['iterations']} iterations, residual {res['solver']['residual']:.1e})")


def gamg_fallback():
    # on two blocks GAMG is a direct solve; the demo wall needs iterations
    from bwrun import solve
    scene = DEMO
    ref = solve(scene, ["-solver_method", "direct"])
    res = solve(scene, ["-solver_schur", "gamg", "-ksp_max_it", 1])
    s = res["solver"]
    expect(s["fallback"] == 1 and s["method_used"] == "fieldsplit", f"no Cholesky fallback: {s}")
    expect("DIVERGED_ITS" in s["fallback_reason"], f"reason {s['fallback_reason']!r}")
    e = rel_err(res["blocks/displacement"], ref["blocks/displacement"])
    expect(e < 1e-10, f"answer vs the direct path {e:.2e}")
    print(f"CG+GAMG failure caught by the Cholesky fieldsplit: {s['fallback_reason']}; error {e:.1e}")


def floor():
    from bwrun import solve
    scene = DEMO
    ref = solve(scene, ["-solver_method", "direct"])
    opts = ["-solver_schur", "gamg", "-solver_rtol", "1e-16", "-solver_forward_rtol", "1e-8"]
    res = solve(scene, opts)
    s = res["solver"]
    expect("round-off floor" in s["fallback_reason"], f"the reason does not name the floor: {s['fallback_reason']!r}")
    expect(s["setups"] == 2, f"{s['setups']} set-ups: S^ was factored after the floor (want GAMG and direct only)")
    expect(s["accuracy_met"] == 0 and "misses solver.rtol" in s["warning"], f"no warning recorded: {s}")
    fl, r = float(s["residual_floor"]), float(s["residual"])
    expect(1e-16 < r <= fl <= 1e3 * r and "leaves a residual up to" in s["warning"],
           f"residual {r:.2e}, its floor {fl:.2e} (want r <= floor <= 1e3 r), warning {s['warning']!r}")
    e = rel_err(res["blocks/displacement"], ref["blocks/displacement"])
    expect(e < 1e-10, f"answer vs the direct path {e:.2e}")
    # the floor is a property of the wall and its answer, not of the ranks
    s3 = solve(scene, opts, np_ranks=3)["solver"]
    fl3 = float(s3["residual_floor"])
    expect(abs(fl3 - fl) <= 1e-10 * fl and float(s3["residual"]) <= fl3, f"the floor on 3 ranks {fl3:.6e}, on 1 {fl:.6e}")
    print(f"stopped at the floor: {s['fallback_reason']}; {s['setups']} set-ups; floor {fl:.1e} (3 ranks: the same to "
          f"{abs(fl3 - fl) / fl:.0e}); error {e:.1e} against direct")


def warn():
    """On the demo wall the round-off of any double-precision solve leaves a
    true residual near 1e-14 (on the paper's two blocks the Schur solve is
    exact to the last bit: a residual of 0 meets any rtol)."""
    from bwrun import solve
    wall = DEMO
    ref = solve(wall)
    res = solve(wall, ["-solver_rtol", "1e-18"])
    sv = res["solver"]
    expect(sv["accuracy_met"] == 0 and "misses solver.rtol" in sv["warning"], f"no warning recorded: {sv}")
    expect(sv["fallback"] == 1, "auto should have tried the direct path too")
    e = rel_err(res["blocks/displacement"], ref["blocks/displacement"])
    expect(e < 1e-12, f"best-effort answer vs the normal one {e:.2e}")
    code, out, err = run(wall, ["-solver_rtol", "1e-18", "-output_file", "/tmp/bw_warn_test.h5"])
    expect(code == 0 and "WARNING: true residual" in out and not err.strip(), f"summary: {out!r} stderr {err!r}")
    os.remove("/tmp/bw_warn_test.h5")
    expect(ref["solver"]["accuracy_met"] == 1 and ref["solver"]["warning"] == "", "a met tolerance recorded as missed")
    print(f"warning recorded: {sv['warning']}")


# the bench's 3D wall at 24 x 24 units (its S^ splits into two groups of
# dofs), stresses and XDMF not written
WALL3D = os.path.join(os.path.dirname(__file__), "..", "..", "bench", "large_wall3d.yaml")
WALL3D_24 = ["-geometry_running_bond_courses", 24, "-geometry_running_bond_units_per_course", 24,
             "-output_stresses", "false", "-output_xdmf", "false"]


def ptap():
    from bwrun import solve
    # the reference: S^ factored (MUMPS on 2 ranks), 0.3 s; the direct path
    # on the whole saddle matrix gave the same to 1e-14 in 4.8 s
    ref = solve(WALL3D, [*WALL3D_24, "-solver_schur", "cholesky"], np_ranks=2)
    expect(ref["solver"]["schur_solve"] in ("lu", "cholesky"), f"reference: schur_solve {ref['solver']['schur_solve']!r}")
    dflt = solve(WALL3D, [*WALL3D_24, "-solver_schur", "gamg"], np_ranks=2)
    lean = solve(WALL3D, [*WALL3D_24, "-solver_schur", "gamg", "-matptap_via", "allatonce"], np_ranks=2)
    for name, res in (("default", dflt), ("allatonce", lean)):
        s = res["solver"]
        expect(s["accuracy_met"] == 1 and s["fallback"] == 0, f"{name}: {s}")
        e = rel_err(res["blocks/displacement"], ref["blocks/displacement"])
        expect(e < 1e-8, f"{name} vs S^ factored {e:.2e}")
    e = rel_err(lean["blocks/displacement"], dflt["blocks/displacement"])
    expect(e < 1e-8, f"allatonce vs PETSc's default product {e:.2e}")
    print(f"{ref['blocks/displacement'].shape[0]} blocks on 2 ranks, CG + GAMG with the Galerkin products all at once: "
          f"{e:.1e} from the default products, residual {lean['solver']['residual']:.1e}")


def analysis():
    from bwrun import EXE, solve
    preload = sys.argv[2] if len(sys.argv) > 2 else ""
    if preload:
        # only over the same MUMPS: PETSc's own a libdmumps of the version
        # the preloaded one has (Debian's petsc-dev: 5.5)
        import re
        import subprocess
        linked = re.findall(r"libdmumps-([0-9.]+)\.so", subprocess.run(["ldd", EXE], capture_output=True, text=True).stdout)
        version = re.findall(r"dmumps_ptscotch-([0-9.]+)\.so", preload)
        if not linked or linked[:1] != version[:1]:
            print(f"PETSc's MUMPS {linked or 'not a shared libdmumps'} is not the version of {preload}: not preloaded")
            preload = ""

    one = solve(WALL3D, WALL3D_24, 1)
    runs = [("2 ranks, PETSc's MUMPS", solve(WALL3D, WALL3D_24, 2), ("rank 0", "parallel"))]
    if preload:
        runs.append(("2 ranks, MUMPS with PT-Scotch", solve(WALL3D, WALL3D_24, 2, extra_env={"LD_PRELOAD": preload}), ("parallel",)))
    expect(one["solver"]["factor_analysis"] == "", f"1 rank: factor_analysis {one['solver']['factor_analysis']!r}, want ''")
    for name, res, want in runs:
        s = res["solver"]
        expect(s["schur_solve"] in ("cholesky", "lu") and s["accuracy_met"] == 1 and s["fallback"] == 0, f"{name}: {s}")
        expect(s["factor_analysis"] in want, f"{name}: factor_analysis {s['factor_analysis']!r}, want one of {want}")
        e = rel_err(res["blocks/displacement"], one["blocks/displacement"])
        expect(e < 1e-10, f"{name}: displacements {e:.2e} from 1 rank's")
        print(f"{name}: MUMPS ordered S^ {'in parallel' if s['factor_analysis'] == 'parallel' else 'on rank 0'}; "
              f"displacements {e:.1e} from 1 rank's")


def compression():
    import re
    from bwrun import solve
    got = {}
    for name, extra in (("uncompressed", []), ("compressed", ["-schur_mat_mumps_icntl_15", -6])):
        res, stdout = solve(WALL3D, [*WALL3D_24, "-schur_ksp_view", "::ascii_info_detail", *extra], 2, stdout=True)
        icntl = re.findall(r"ICNTL\(15\) \(compression of the input matrix\): *(-?[0-9]+)", stdout)
        entries = re.findall(r"INFOG\(20\) \(estimated number of entries in the factors\): *([0-9]+)", stdout)
        expect(icntl and entries, f"{name}: no MUMPS factor of S^ in -schur_ksp_view's output")
        expect(res["solver"]["schur_groups"] == 2, f"{name}: S^ in {res['solver']['schur_groups']} groups, want 2")
        got[name] = (int(icntl[0]), int(entries[0]), res)
    expect(got["uncompressed"][0] == 0 and got["compressed"][0] == -6, f"ICNTL(15) {got['uncompressed'][0]} and {got['compressed'][0]}, want 0 and -6")
    ratio = got["uncompressed"][1] / got["compressed"][1]
    expect(ratio <= 0.6, f"factor entries uncompressed {got['uncompressed'][1]} against compressed {got['compressed'][1]}: {ratio:.2f}, want <= 0.6")
    e = rel_err(got["uncompressed"][2]["blocks/displacement"], got["compressed"][2]["blocks/displacement"])
    expect(e < 1e-10, f"displacements {e:.2e} apart")
    print(f"S^ in 2 groups on 2 ranks: {got['uncompressed'][1]} entries in MUMPS's factor uncompressed, "
          f"{got['compressed'][1]} compressed by blocks of 6 ({ratio:.2f}); displacements {e:.1e} apart")


def memory():
    import re
    from bwrun import solve
    fac, out_fac = solve(WALL3D, WALL3D_24, 2, stdout=True)
    low, out_low = solve(WALL3D, [*WALL3D_24, "-solver_memory", 0.05], 2, stdout=True)
    for name, res, out, want in (("default", fac, out_fac, "cholesky"), ("solver.memory 0.05", low, out_low, "gamg")):
        s = res["solver"]
        expect(s["schur_groups"] == 2, f"{name}: S^ in {s['schur_groups']} groups, want 2")
        expect(s["schur_solve"] == want and s["fallback"] == 0 and s["accuracy_met"] == 1, f"{name}: {s}")
        line = re.findall(r"auto's Schur solve: (.*)", out)
        expect(line and line[0].startswith("S^ factored" if want == "cholesky" else "CG + GAMG"), f"{name}: summary {line}")
        print(f"{name}: {s['schur_solve']}: {line[0]}")
    e = rel_err(low["blocks/displacement"], fac["blocks/displacement"])
    expect(e < 1e-8, f"CG + GAMG vs the factored S^ {e:.2e}")
    two = solve(DEMO, ["-solver_memory", 1e-6, "-output_stresses", "false", "-output_xdmf", "false"], 1)
    expect(two["solver"]["schur_solve"] == "cholesky", f"2D wall, solver.memory 1e-6: {two['solver']['schur_solve']}, want cholesky")
    out = "/tmp/bw_memory_never.h5"
    if os.path.exists(out):
        os.remove(out)
    code, _, err = run(WALL3D, [*WALL3D_24, "-solver_memory", -1, "-output_file", out], expect_ok=False)
    expect(code != 0 and "solver_memory" in err and len(err.strip().splitlines()) == 1, f"solver.memory -1: exit {code}, {err!r}")
    expect(not os.path.exists(out), "output written after bad input")
    print(f"displacements of CG + GAMG {e:.1e} from the factored S^'s; 2D wall factored; {err.strip()}")


def low_rank():
    import re
    from bwrun import solve
    wall300 = [*WALL3D_24[4:], "-geometry_running_bond_courses", 300, "-geometry_running_bond_units_per_course", 300]
    blr, out_blr = solve(WALL3D, [*wall300, "-solver_low_rank", "always"], 2, stdout=True)
    s = blr["solver"]
    ratio = s["factor_low_rank_ratio"]
    expect(s["fallback"] == 0 and s["schur_solve"] == "cholesky", f"low rank: {s}")
    expect(0 < ratio < 0.98, f"low rank: factor_low_rank_ratio {ratio}, want in (0, 0.98)")
    line = re.findall(r"S\^'s factor in block low-rank form \(MUMPS BLR\): ([0-9]+) %", out_blr)
    expect(line and abs(int(line[0]) - 100 * ratio) <= 1, f"low rank: summary {line} against ratio {ratio}")
    full, out_full = solve(WALL3D, [*wall300, "-solver_low_rank", "always", "-schur_mat_mumps_cntl_7", 1e-3], 2, stdout=True)
    f = full["solver"]
    expect(f["fallback"] == 1 and "S^ factored again in full rank" in f["fallback_reason"] and f["factor_low_rank_ratio"] == -1,
           f"coarse low rank: fallback {f['fallback']}, reason {f['fallback_reason']!r}, ratio {f['factor_low_rank_ratio']}")
    expect("block low-rank form (MUMPS BLR)" not in out_full, "coarse low rank: the summary names a low-rank factor the answer did not use")
    e = rel_err(blr["blocks/displacement"], full["blocks/displacement"])
    expect(e < 1e-9, f"low-rank and full-rank answers {e:.2e} apart")
    expect(s["residual"] <= 3 * f["residual"], f"residual {s['residual']:.3e} with the low-rank factor, {f['residual']:.3e} in full rank")
    auto = solve(WALL3D, WALL3D_24, 2)["solver"]["factor_low_rank_ratio"]
    one = solve(WALL3D, [*WALL3D_24, "-solver_low_rank", "always"], 1)["solver"]["factor_low_rank_ratio"]
    expect(auto == -1 and one == 1, f"24 x 24: ratio {auto} under auto (want -1), {one} with always on 1 rank (want 1)")
    out = "/tmp/bw_low_rank_reproducible.h5"
    if os.path.exists(out):
        os.remove(out)
    code, _, err = run(WALL3D, [*WALL3D_24, "-solver_low_rank", "always", "-solver_reproducible", "true", "-output_file", out], 2, expect_ok=False)
    lines = [l for l in err.splitlines() if l.startswith("blockwall:")]
    expect(code != 0 and len(lines) == 1 and "solver_low_rank" in lines[0], f"low rank and reproducible: exit {code}, {err!r}")
    expect(not os.path.exists(out), "output written after bad input")
    print(f"300 x 300 on 2 ranks: low-rank factor {ratio:.3f} of the full rank's entries, residual {s['residual']:.2e}; "
          f"cntl_7 1e-3 fell back ({f['fallback_reason'][:80]}...), residual {f['residual']:.2e}; answers {e:.1e} apart; "
          f"24 x 24: ratio {auto} (auto), {one} (always, 1 rank); {lines[0]}")


def alone():
    from bwrun import solve
    args = [*WALL3D_24[4:], "-geometry_running_bond_courses", 100, "-geometry_running_bond_units_per_course", 100, "-solver_rtol", 1e-14]
    s = solve(WALL3D, args, 2)["solver"]
    expect(s["method_used"] == "fieldsplit" and s["fallback"] == 0 and s["fallback_reason"] == "" and s["accuracy_met"] == 0,
           f"floor, no other path: {s}")
    w = s["warning"]
    expect("no other path ran" in w and "direct path was not tried" in w and "round-off floor" in w, f"warning {w!r}")
    expect(s["residual"] > 1e-14 and s["residual_floor"] > 0, f"residual {s['residual']}, floor {s['residual_floor']}")
    print(f"fieldsplit alone at the floor: fallback 0, residual {s['residual']:.2e}, floor {s['residual_floor']:.1e}; {w[-200:]}")


if __name__ == "__main__":
    try:
        {"gamg_fallback": gamg_fallback, "floor": floor, "warn": warn, "agree": agree, "fallback": fallback, "strict": strict, "wall": wall,
         "ptap": ptap, "analysis": analysis, "compression": compression, "memory": memory,
         "low_rank": low_rank, "alone": alone}[sys.argv[1]]()
    except Failure as e:
        print("FAIL", e)
        sys.exit(1)
