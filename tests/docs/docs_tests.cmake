# ctest label docs: README.md and docs/*.md as a user meets them
# (tests/docs/check_docs.py): the links and anchors, the two five-step
# walkthroughs run as README prints them (in a scratch copy of examples/),
# every other snippet run, parsed or listed as a fragment with its reason.
# Included from tests/CMakeLists.txt, after bw_py_test. Timeouts: at least 4x
# what each took under ctest -j2 on a shared 2-core machine (links 3 s,
# walkthrough_2d 52 s, walkthrough_3d 22 s, with the picture 46 s, snippets 56 s).
bw_py_test(docs.links docs docs/check_docs.py links)
bw_py_test(docs.walkthrough_2d "docs;mpi;dxf" docs/check_docs.py walkthrough_2d)
bw_py_test(docs.walkthrough_3d "docs;mpi;dim3" docs/check_docs.py walkthrough_3d)
bw_py_test(docs.snippets "docs;mpi" docs/check_docs.py snippets)
set_tests_properties(docs.links PROPERTIES TIMEOUT 60)
set_tests_properties(docs.walkthrough_2d docs.walkthrough_3d docs.snippets PROPERTIES TIMEOUT 240)
# Step 4 of the 3D walkthrough draws with ParaView's pvpython on an Xvfb of
# its own: registered where CMake finds both, as post/post_tests.cmake does.
find_program(BW_PVPYTHON pvpython)
find_program(BW_XVFB_RUN xvfb-run)
if(BW_PVPYTHON AND BW_XVFB_RUN)
  bw_py_test(docs.walkthrough_3d_view "docs;mpi;dim3" docs/check_docs.py walkthrough_3d view)
  set_property(TEST docs.walkthrough_3d_view APPEND PROPERTY ENVIRONMENT "BW_PVPYTHON=${BW_PVPYTHON};BW_XVFB_RUN=${BW_XVFB_RUN}")
  set_tests_properties(docs.walkthrough_3d_view PROPERTIES TIMEOUT 300 RESOURCE_LOCK xvfb)
else()
  message(STATUS "blockwall: pvpython or xvfb-run not found: docs.walkthrough_3d_view (step 4 of README's 3D walkthrough) is left out")
endif()
