# ctest label stability (issue 5): extreme cases on blockwall's default
# settings against an independent reference (model.md's closed form, or
# bw_reference's real128 solve); see check_stability.py for the bound each
# case asserts and why. Cases where the suite found blockwall wrong are
# kept out of ctest (check_stability.py KNOWN_SILENT, KNOWN_REFUSED,
# KNOWN_MISDIAGNOSED; measure them with `check_stability.py --table NAME`,
# run the assertions with `check_stability.py NAME`). Included from tests/CMakeLists.txt,
# after bw_py_test is defined; the slow cases are in bench/stability_slow.py.
set(BW_STABILITY_CASES
  kn_1e3 kn_1e9 kn_1e15 kn_1e16 kn_1e18 wall_kn_1e3 wall_kn_1e16 wall_kn_1e18
  contrast_random_1e6 contrast_random_1e9 contrast_random_1e12
  contrast_layered_1e6 contrast_layered_1e9 contrast_layered_1e12 cluster_1e6
  cluster_1e9 cluster_1e12 wall_random_1e9_12x8 wall_layered_1e7_20x12
  contrast_random_1e13 contrast_layered_1e13
  kt_kn_1e-6 kt_kn_1e6
  m1_two_blocks m2_two_blocks m1024_two_blocks m1_wall m2_wall m1024_wall
  thickness_1e-6 thickness_1e-3
  block_1mm block_10m blocks_1mm_on_10m aspect_slab_1e3 aspect_column_1e3 aspect_wall_1e3
  translated_two_blocks_1e6 translated_wall_1e6
  load_1e-6 load_1e9 wall_load_1e9 load_minus_1N
  tenon_1e-3 tenon_1e-5 tenon_1e-5_vertical)
# A quarter of the cases per test, in one Python process (it was one test
# per case, each a Python process of 0.3 s of CPU around runs of a few
# tenths); every case of the quarter is run and reported, and
# `check_stability.py NAME` checks one.
list(LENGTH BW_STABILITY_CASES bw_n)
foreach(part 1 2 3 4)
  math(EXPR bw_first "(${part} - 1) * ${bw_n} / 4")
  math(EXPR bw_count "${part} * ${bw_n} / 4 - ${bw_first}")
  list(SUBLIST BW_STABILITY_CASES ${bw_first} ${bw_count} bw_cases)
  bw_py_test(stability.cases_${part} stability stability/check_stability.py ${bw_cases})
  set_property(TEST stability.cases_${part} APPEND PROPERTY ENVIRONMENT "BW_REFERENCE=$<TARGET_FILE:bw_reference>")
endforeach()
# The same asserts with the displacements' worst-case round-off bound
# taken through S^'s factor (-solver_forward_bound schur), on the cases
# whose fieldsplit refinement needs the bound: it must still hold the true
# error (point 5 of check_stability.py).
bw_py_test(stability.schur_bound stability stability/check_stability.py --options
           "-solver_forward_bound schur -solver_condition_estimate always"
           cluster_1e6 cluster_1e9 tenon_1e-3 tenon_1e-5 tenon_1e-5_vertical m1024_wall aspect_column_1e3 wall_kn_1e16)
set_property(TEST stability.schur_bound APPEND PROPERTY ENVIRONMENT "BW_REFERENCE=$<TARGET_FILE:bw_reference>")
# ... and with the estimate from one residual in double-double (auto's
# choice; the cases above run it where the refinement shows trouble) and
# the condition estimated in every run: no bound, so the true error is the
# judge of its factor 10.
bw_py_test(stability.extra_estimate stability stability/check_stability.py --options
           "-solver_forward_bound extra -solver_condition_estimate always"
           cluster_1e6 cluster_1e9 cluster_1e12 tenon_1e-3 tenon_1e-5 tenon_1e-5_vertical m1024_wall aspect_column_1e3
           wall_kn_1e16 m1024_two_blocks wall_random_1e9_12x8 wall_layered_1e7_20x12 contrast_layered_1e9 kt_kn_1e6)
set_property(TEST stability.extra_estimate APPEND PROPERTY ENVIRONMENT "BW_REFERENCE=$<TARGET_FILE:bw_reference>")
