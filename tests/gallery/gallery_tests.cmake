# ctest label gallery: every example of examples/ run as shipped (their
# geometry made by their own scripts, or by tools/import_dxf from the
# shipped drawing) and checked against references that do not come from
# blockwall (tests/gallery/check_gallery.py says which, and why each
# tolerance). Included from tests/CMakeLists.txt, after bw_py_test.
foreach(case two_blocks demo openings arch stones facade)
  bw_py_test(gallery.${case} gallery gallery/check_gallery.py ${case})
endforeach()
set_tests_properties(gallery.demo gallery.facade PROPERTIES LABELS "gallery;mpi")
