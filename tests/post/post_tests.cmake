# ctest label post: the XDMF beside the HDF5 file read back by meshio, and
# tools/plot (PNGs, summary, plotted numbers) against the HDF5 datasets.
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
