# ctest label post: the XDMF beside the HDF5 file read back by meshio (and by
# ParaView, below), and tools/plot (PNGs, summary, plotted numbers, the
# crack pattern of a pushover) against the HDF5 datasets.
# Included from tests/CMakeLists.txt, which defines bw_py_test.
foreach(ranks 1 2)
  bw_py_test(post.xdmf.two_blocks_np${ranks} post post/check_xdmf.py two_blocks ${ranks})
endforeach()
bw_py_test(post.xdmf.demo "post;mpi" post/check_xdmf.py demo)
bw_py_test(post.xdmf.polygons post post/check_xdmf.py polygons)
bw_py_test(post.xdmf.off post post/check_xdmf.py off)
bw_py_test(post.xdmf.failure "post;errors" post/check_xdmf.py failure)
bw_py_test(post.plot.case2 "post;paper" post/check_plot.py case2)
bw_py_test(post.plot.demo "post;mpi" post/check_plot.py demo)
bw_py_test(post.plot.pushover "post;nonlinear" post/check_plot.py pushover)
# ParaView itself (Debian: paraview, python3-paraview for pvpython, xvfb for
# the display its rendering needs) opens the XDMF files: a pushover's
# temporal collection and a linear result's single state, with all four of
# its XDMF readers, against the HDF5 datasets. Left out without them, like
# the tests of what a PETSc lacks.
find_program(BW_PVPYTHON pvpython)
find_program(BW_XVFB_RUN xvfb-run)
if(BW_PVPYTHON AND BW_XVFB_RUN)
  foreach(mode pushover linear)
    bw_py_test(post.paraview.${mode} "post;paraview" post/check_paraview.py ${mode})
    set_property(TEST post.paraview.${mode} APPEND PROPERTY ENVIRONMENT "BW_PVPYTHON=${BW_PVPYTHON};BW_XVFB_RUN=${BW_XVFB_RUN}")
    # two `xvfb-run -a` starting together can race for a display number
    set_tests_properties(post.paraview.${mode} PROPERTIES RESOURCE_LOCK xvfb)
  endforeach()
  message(STATUS "blockwall: ParaView check of the XDMF files with ${BW_PVPYTHON} under ${BW_XVFB_RUN}")
else()
  message(STATUS "blockwall: pvpython or xvfb-run not found (Debian packages python3-paraview, xvfb): "
                 "the ParaView check of the XDMF files is left out")
endif()
