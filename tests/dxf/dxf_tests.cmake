# ctest label dxf: tools/import_dxf on drawings written by the test with
# ezdxf (tests/dxf/check_dxf.py): three assemblies imported, run and
# compared with the same blocks written directly; the unit rule; every
# class of defect (error line naming handle and layer, exit code 1, no
# file left, an existing file untouched). Included from tests/CMakeLists.txt.
foreach(case wall arch stones units)
  bw_py_test(dxf.${case} dxf dxf/check_dxf.py ${case})
endforeach()
# The defective drawings (check_dxf.DEFECTS), half of them per test, one
# Python process each (each defect also starts tools/import_dxf twice); it
# was one test per defect, a Python process importing ezdxf (0.65 s of CPU)
# for each. `check_dxf.py defect.NAME` checks one.
foreach(half 1 2)
  bw_py_test(dxf.defects_${half} "dxf;errors" dxf/check_dxf.py defects ${half})
endforeach()
