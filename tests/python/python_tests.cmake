# ctest label python: the blockwall Python package (python/blockwall) on
# its own: the geometry writer against blockwall's own validation corpus,
# the reader against h5py (pushover datasets present and absent), the
# launcher's commands and errors (tests/python/check_package.py).
foreach(case writer corpus reader launcher)
  bw_py_test(python.${case} python python/check_package.py ${case})
endforeach()
