# Nonlinear joints and pushover (ctest -L nonlinear): closed forms and
# invariants, tests/nonlinear/check_nonlinear.py says each reference and
# tolerance.
foreach(case eccentric sliding overturning stack_overturn stack_slide softening step_size elastic_limit)
  bw_py_test(nonlinear.${case} nonlinear nonlinear/check_nonlinear.py ${case})
endforeach()
bw_py_test(nonlinear.errors "nonlinear;errors" nonlinear/check_nonlinear.py errors)
foreach(np 2 3)
  bw_py_test(nonlinear.ranks_${np} "nonlinear;mpi" nonlinear/check_nonlinear.py ranks ${np})
endforeach()
