# cmake --install BUILD [--prefix PREFIX]:
#   bin/blockwall, bin/bw_reference                 the executables
#   include/blockwall/*.h                           the kernel headers
#   share/blockwall/python/                         the Python package (pip install PREFIX/share/blockwall/python)
#   share/blockwall/tools/{plot,import_dxf,error_vs_time}  its command-line front ends, which use that copy
#   bin/blockwall-plot, bin/blockwall-import-dxf    links to them
#   share/blockwall/examples/                       the gallery's scenes and scripts
include(GNUInstallDirs)
install(TARGETS blockwall bw_reference RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/blockwall DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h")
set(BW_SHARE ${CMAKE_INSTALL_DATADIR}/blockwall)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/python/ DESTINATION ${BW_SHARE}/python
        PATTERN "__pycache__" EXCLUDE PATTERN "*.egg-info" EXCLUDE PATTERN "build" EXCLUDE)
install(PROGRAMS ${PROJECT_SOURCE_DIR}/tools/plot ${PROJECT_SOURCE_DIR}/tools/import_dxf
                 ${PROJECT_SOURCE_DIR}/tools/error_vs_time DESTINATION ${BW_SHARE}/tools)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/ DESTINATION ${BW_SHARE}/examples
        PATTERN "*.h5" EXCLUDE PATTERN "__pycache__" EXCLUDE)
foreach(pair "plot;blockwall-plot" "import_dxf;blockwall-import-dxf")
  list(GET pair 0 tool)
  list(GET pair 1 link)
  install(CODE "
    set(bin \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_BINDIR}\")
    file(MAKE_DIRECTORY \"\${bin}\")
    file(CREATE_LINK \"../${BW_SHARE}/tools/${tool}\" \"\${bin}/${link}\" SYMBOLIC)
    message(STATUS \"Installing: \${bin}/${link} -> ../${BW_SHARE}/tools/${tool}\")")
endforeach()
