# ctest label gallery: every example of examples/ run as shipped (their
# geometry made by their own scripts, or by tools/import_dxf from the
# shipped drawing) and checked against references that do not come from
# blockwall (tests/gallery/check_gallery.py says which, and why each
# tolerance). Included from tests/CMakeLists.txt, after bw_py_test.
foreach(case two_blocks demo openings arch stones facade)
  bw_py_test(gallery.${case} gallery gallery/check_gallery.py ${case})
endforeach()
set_tests_properties(gallery.demo gallery.facade PROPERTIES LABELS "gallery;mpi")
# every scene of examples/ as README runs it (the build writes the gallery's
# geometry: examples/CMakeLists.txt), and what the error names without it
bw_py_test(gallery.examples_run gallery gallery/check_examples_run.py build)
bw_py_test(gallery.examples_missing gallery gallery/check_examples_run.py missing)
set_tests_properties(gallery.examples_run PROPERTIES LABELS "gallery;mpi")
