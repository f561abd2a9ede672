# Nonlinear joints and pushover (ctest -L nonlinear): closed forms and
# invariants, tests/nonlinear/check_nonlinear.py says each reference and
# tolerance.
# The short cases of check_nonlinear.py in two Python processes (each was a
# test: 0.3 s of Python for a second of work); `check_nonlinear.py CASE`
# runs one. nonlinear.j4d stays a test of its own (docs/validation.md
# names it).
bw_py_test(nonlinear.closed_forms nonlinear nonlinear/check_nonlinear.py
           eccentric sliding dilatancy overturning stack_overturn stack_slide)
bw_py_test(nonlinear.paths "nonlinear;errors" nonlinear/check_nonlinear.py
           collapse softening step_size elastic_limit errors)
bw_py_test(nonlinear.j4d nonlinear nonlinear/check_nonlinear.py j4d)
foreach(np 2 3)
  bw_py_test(nonlinear.ranks_${np} "nonlinear;mpi" nonlinear/check_nonlinear.py ranks ${np})
endforeach()

# Load, unload, reload through the Newton solver itself (the pushover
# contract has no cycles): unloading on the initial stiffness.
add_executable(test_newton ${CMAKE_CURRENT_LIST_DIR}/../unit/test_newton.c)
target_link_libraries(test_newton PRIVATE blockwall_core)
foreach(np 1 2)
  add_test(NAME nonlinear.unload_reload_${np}
           COMMAND ${BW_WATCHDOG} ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} ${np} $<TARGET_FILE:test_newton>
                   -scene ${CMAKE_CURRENT_LIST_DIR}/../unit/newton_block.yaml)
  set_tests_properties(nonlinear.unload_reload_${np} PROPERTIES LABELS "nonlinear;unit" ENVIRONMENT "${BW_MPI_ENV}")
endforeach()

# Past the peak (issue 20): dissipation control on a snap-back against its
# closed form, and where the pattern's load falls to zero under a held pull;
# the capacity figures against their definitions.
foreach(np 1 2)
  bw_py_test(nonlinear.snapback_${np} "nonlinear;mpi" nonlinear/check_past_peak.py snapback ${np})
  bw_py_test(nonlinear.exhausted_${np} "nonlinear;mpi" nonlinear/check_past_peak.py exhausted ${np})
endforeach()
bw_py_test(nonlinear.capacity nonlinear nonlinear/check_past_peak.py capacity)

# Past the peak (issue 20): the scenes of the nonlinear tests give the same
# curve under dissipation control as under displacement control
# (check_controls.py says what is compared and why), and a running-bond
# wall of 412 blocks with J4D's joints followed past its peak to below 0.8
# of it, every written step a converged equilibrium.
bw_py_test(nonlinear.same_curve_1 nonlinear nonlinear/check_controls.py same_curve 1)
bw_py_test(nonlinear.same_curve_2 "nonlinear;mpi" nonlinear/check_controls.py same_curve 2)
bw_py_test(nonlinear.same_curve_direct nonlinear nonlinear/check_controls.py direct)
bw_py_test(nonlinear.wall_past_peak_2 "nonlinear;mpi" nonlinear/check_wall_past_peak.py 2)
# The same wall twice on 2 ranks with solver.reproducible: bit for bit the
# same curve and last state (MUMPS's parallel factorisation alone is not).
bw_py_test(nonlinear.reproducible_2 "nonlinear;mpi" nonlinear/check_reproducible.py 2)

# The IMPL-EX scheme (issue 30): the sliding plateau exactly, a softening
# crack within its tolerance and with its energy, the held-pull stack to its
# reversal, auto's handover where Newton cannot go on, 1 and 2 ranks alike
# (check_implex.py says each reference).
foreach(case sliding softening reversal handover)
  bw_py_test(nonlinear.implex.${case} nonlinear nonlinear/check_implex.py ${case})
endforeach()
bw_py_test(nonlinear.implex.ranks_2 "nonlinear;mpi" nonlinear/check_implex.py ranks 2)
