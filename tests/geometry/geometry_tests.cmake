# Geometry from files (issue 4): HDF5 input, automatic interfaces,
# validation, mechanisms. Included from tests/CMakeLists.txt, after
# bw_py_test and BW_MPI_ENV are defined. Labels: geometry, plus errors /
# mpi / mechanism where they apply.
set(BW_GEOMETRY_DIR ${CMAKE_CURRENT_LIST_DIR})

# Geometry without a solve, to check and time detection on 1e5 blocks.
add_executable(test_geometry ${BW_GEOMETRY_DIR}/test_geometry.c)
target_link_libraries(test_geometry PRIVATE blockwall_core)
# The numerical mechanism check a solver calls on a singular matrix.
add_executable(test_mechanism ${BW_GEOMETRY_DIR}/test_mechanism.c)
target_link_libraries(test_mechanism PRIVATE blockwall_core)

foreach(case sway sound verdict)
  add_test(NAME geometry.mechanism.numeric_${case} COMMAND test_mechanism ${case})
  set_tests_properties(geometry.mechanism.numeric_${case} PROPERTIES LABELS "geometry;mechanism" ENVIRONMENT "${BW_MPI_ENV}")
endforeach()

foreach(case case2 roundtrip paths depth dry)
  bw_py_test(geometry.file.${case} geometry geometry/check_file.py ${case})
endforeach()
bw_py_test(geometry.file.ranks "geometry;mpi" geometry/check_file.py ranks)
foreach(case two_blocks wall)
  bw_py_test(geometry.frame.${case} geometry geometry/check_frame.py ${case})
endforeach()
bw_py_test(geometry.arch geometry geometry/check_arch.py)
bw_py_test(geometry.tenon geometry geometry/check_arch.py tenon)
foreach(case analytic generator)
  bw_py_test(geometry.detect.wall_1e5_${case} geometry geometry/check_detect.py ${case})
endforeach()

# The broken files of tests/data/broken (tests/data/make_broken.py):
# geometry.parallel_read.broken_1..4, below, run each file on 1 rank and on
# 3 with check_broken.py's checks. Here: no file, and the corpus current.
foreach(case missing_file current)
  bw_py_test(geometry.broken.${case} "geometry;errors" geometry/check_broken.py ${case})
endforeach()

foreach(case hinge u1_only pinned_foundation unconnected arch_m1 four_bar)
  bw_py_test(geometry.mechanism.${case} "geometry;errors;mechanism" geometry/check_mechanism.py ${case})
endforeach()
bw_py_test(geometry.mechanism.sound "geometry;mechanism" geometry/check_mechanism.py sound)

# running_bond additions and scene sets (interface.md of 2026-11-22)
foreach(case half split stiff sets errors)
  bw_py_test(geometry.running_bond.${case} geometry geometry/check_running_bond.py ${case})
endforeach()
set_tests_properties(geometry.running_bond.errors PROPERTIES LABELS "geometry;errors")

# Files read in parallel (issue 29): the serial reader's geometry, bit for
# bit, on 1, 2, 3 and 5 ranks; the serial reader's error line on 3 ranks;
# no rank holding the whole file (peak memory per rank, 2 against 8 ranks).
# Each took 5 to 40 s here (two cores shared with other builds): the
# suite's default TIMEOUT, which the end of tests/CMakeLists.txt sets for
# every test, is theirs.
set(bw_parallel_read)
foreach(case shuffled listed listed_kn bands arch)
  bw_py_test(geometry.parallel_read.walls2d_${case} "geometry;mpi" geometry/check_parallel_read.py walls2d ${case})
  list(APPEND bw_parallel_read geometry.parallel_read.walls2d_${case})
endforeach()
foreach(case detected listed)
  bw_py_test(geometry.parallel_read.walls3d_${case} "geometry;mpi;dim3" geometry/check_parallel_read.py walls3d ${case})
  list(APPEND bw_parallel_read geometry.parallel_read.walls3d_${case})
endforeach()
# Every broken file of tests/data, a quarter of make_broken.CASES per test,
# on 1 rank and on 3 (every rank reads a part: the error must reach, and
# stop, every rank), with check_broken.py's checks on both, and the 3
# ranks' line the 1-rank run's. One Python process per quarter: this was
# a test per file on 1 rank (geometry.broken.<case>), three of them again
# on 3 (<case>_3ranks), and these tests running every file on 1 rank again
# to compare. `check_broken.py CASE [RANKS]` runs one file.
foreach(part 1 2 3 4)
  bw_py_test(geometry.parallel_read.broken_${part} "geometry;mpi;errors" geometry/check_broken.py part ${part})
  list(APPEND bw_parallel_read geometry.parallel_read.broken_${part})
endforeach()
bw_py_test(geometry.parallel_read.memory "geometry;mpi" geometry/check_parallel_read.py memory)
bw_py_test(geometry.parallel_read.memory_distribute "geometry;mpi" geometry/check_parallel_read.py memory distribute)
list(APPEND bw_parallel_read geometry.parallel_read.memory geometry.parallel_read.memory_distribute)
set_tests_properties(${bw_parallel_read} PROPERTIES TIMEOUT 120)
