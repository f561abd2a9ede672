# ctest label dxf: tools/import_dxf on drawings written by the test with
# ezdxf (tests/dxf/check_dxf.py): three assemblies imported, run and
# compared with the same blocks written directly; the unit rule; one test
# per class of defect (error line naming handle and layer, exit code 1, no
# file left, an existing file untouched). Included from tests/CMakeLists.txt.
foreach(case wall arch stones units)
  bw_py_test(dxf.${case} dxf dxf/check_dxf.py ${case})
endforeach()
foreach(case open open_hatch line self_intersecting fold_back bulge arc circle hatch_arc overlap zero_area
             repeated_vertex two_vertices hole polyline_3d layer_name)
  bw_py_test(dxf.defect.${case} "dxf;errors" dxf/check_dxf.py defect.${case})
endforeach()
