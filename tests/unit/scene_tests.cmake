# Unit tests of src/scene (BwScene), included from tests/CMakeLists.txt.
# Each test runs one case of test_scene in scene_cases/, whose files the
# messages name as given; options after the case play the user's command line.
add_executable(test_scene ${CMAKE_CURRENT_LIST_DIR}/test_scene.c)
target_link_libraries(test_scene PRIVATE blockwall_core)

set(BW_SCENE_CASES ${CMAKE_CURRENT_LIST_DIR}/scene_cases)
set(BW_SCENE_MPIEXEC ${BW_WATCHDOG} ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} 2 ${MPIEXEC_PREFLAGS})

# BW_MPI_ENV (from tests/CMakeLists.txt) lets Open MPI run as root and oversubscribe.
function(bw_scene_test name labels)
  add_test(NAME ${name} COMMAND ${ARGN} WORKING_DIRECTORY ${BW_SCENE_CASES})
  set_tests_properties(${name} PROPERTIES LABELS "${labels}" ENVIRONMENT "${BW_MPI_ENV}")
endfunction()

set(BW_SCENE_ROUNDTRIP_ARGS
  -discretization_m 8 -title "cmd: title" -loads_top_beam 1,2,3
  -solver_rtol 1e-9 -output_dir "a b" -ksp_rtol 1e-3)

bw_scene_test(unit.scene.values "unit" $<TARGET_FILE:test_scene> values)
bw_scene_test(unit.scene.directory "unit" $<TARGET_FILE:test_scene> directory)
bw_scene_test(unit.scene.override "unit;errors" $<TARGET_FILE:test_scene> override
  -discretization_m 8 -JOINTS_E 1e9 -solver_rtol 1e-9 -test_extra 1 -options_left no)
bw_scene_test(unit.scene.error_format "unit;errors" $<TARGET_FILE:test_scene> error_format -discretization_m 8)
bw_scene_test(unit.scene.unknown_key "unit;errors" $<TARGET_FILE:test_scene> unknown_key)
bw_scene_test(unit.scene.roundtrip "unit" $<TARGET_FILE:test_scene> roundtrip
  ${CMAKE_CURRENT_BINARY_DIR}/scene_roundtrip.yaml ${BW_SCENE_ROUNDTRIP_ARGS})
foreach(case err_syntax err_duplicate err_nested_dup err_novalue err_notmapping
             err_alias err_nonscalarkey err_collision err_empty err_missing)
  bw_scene_test(unit.scene.${case} "unit;errors" $<TARGET_FILE:test_scene> ${case})
endforeach()

# The same on two ranks: rank 0 reads, all parse, errors are raised everywhere.
bw_scene_test(unit.scene.mpi.values "unit;mpi" ${BW_SCENE_MPIEXEC} $<TARGET_FILE:test_scene> values)
bw_scene_test(unit.scene.mpi.roundtrip "unit;mpi" ${BW_SCENE_MPIEXEC} $<TARGET_FILE:test_scene> roundtrip
  ${CMAKE_CURRENT_BINARY_DIR}/scene_roundtrip_mpi.yaml ${BW_SCENE_ROUNDTRIP_ARGS})
foreach(case unknown_key err_syntax err_duplicate err_missing)
  bw_scene_test(unit.scene.mpi.${case} "unit;errors;mpi" ${BW_SCENE_MPIEXEC} $<TARGET_FILE:test_scene> ${case})
endforeach()
