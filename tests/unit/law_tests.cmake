# Unit tests of the per-portion joint laws (src/kernels/joint_law_kernels.f90 through
# include/blockwall/laws.h), included from tests/CMakeLists.txt. Each case of test_laws
# checks a closed form or an invariant; the tolerances and their reasons are in the source.
add_executable(test_laws ${CMAKE_CURRENT_LIST_DIR}/test_laws.c)
target_link_libraries(test_laws PRIVATE blockwall_core)
foreach(case elastic cutoff coulomb corner apex notension soft_mode1 soft_mode2 unload tangent property bad)
  add_test(NAME unit.laws.${case} COMMAND test_laws ${case})
  set_tests_properties(unit.laws.${case} PROPERTIES LABELS "unit;nonlinear")
endforeach()
