# blockwall's dependencies, found the way a cluster's installations allow
# (docs/install.md):
#
#   MPI      FindMPI (the C binding), MPI::MPI_C
#   PETSc    PETSC_DIR [+ PETSC_ARCH] (CMake variables or environment) ->
#            PETSc's own pkg-config file, $PETSC_DIR/$PETSC_ARCH/lib/pkgconfig/petsc.pc
#            (a build in the source tree) or $PETSC_DIR/lib/pkgconfig/petsc.pc
#            (a --prefix installation); without PETSC_DIR, the system's
#            PETSc.pc (Debian's). Target PkgConfig::PETSC. At least 3.18.
#   HDF5     FindHDF5, parallel preferred (HDF5_PREFER_PARALLEL) and required:
#            the output is written collectively. HDF5::HDF5, also known as
#            PkgConfig::HDF5 (the name src/ links).
#   libyaml  pkg-config yaml-0.1, PkgConfig::YAML
#   (METIS is not linked: the partition is PETSc's MatPartitioning, PT-Scotch
#   or ParMETIS; METIS orders MUMPS's factorisations inside PETSc.)
#
# PETSc's optional packages are read from its petscconf.h and reported in
# one configure message; BW_HAVE_MUMPS, BW_HAVE_SUITESPARSE and
# BW_HAVE_HYPRE (ON/OFF) tell tests/CMakeLists.txt which tests apply.

find_package(MPI REQUIRED COMPONENTS C)
find_package(PkgConfig REQUIRED)

# ---------------------------------------------------------------- PETSc
set(PETSC_DIR "$ENV{PETSC_DIR}" CACHE PATH "PETSc installation (empty: the system's PETSc.pc)")
set(PETSC_ARCH "$ENV{PETSC_ARCH}" CACHE STRING "PETSc configuration inside PETSC_DIR (empty for a --prefix installation)")
if(PETSC_DIR)
  set(_bw_pc_dirs "")
  if(PETSC_ARCH)
    list(APPEND _bw_pc_dirs "${PETSC_DIR}/${PETSC_ARCH}/lib/pkgconfig")
  endif()
  list(APPEND _bw_pc_dirs "${PETSC_DIR}/lib/pkgconfig")
  set(_bw_pc "")
  foreach(dir IN LISTS _bw_pc_dirs)
    if(EXISTS "${dir}/petsc.pc" AND NOT _bw_pc)
      set(_bw_pc "${dir}")
    endif()
  endforeach()
  if(NOT _bw_pc)
    string(REPLACE ";" " or " _bw_where "${_bw_pc_dirs}")
    message(FATAL_ERROR "PETSC_DIR=${PETSC_DIR} PETSC_ARCH=${PETSC_ARCH}: no petsc.pc in ${_bw_where}; "
                        "is PETSc built (and installed, for a --prefix build) there?")
  endif()
  # searched before the system's directories, so this PETSc wins
  set(ENV{PKG_CONFIG_PATH} "${_bw_pc}:$ENV{PKG_CONFIG_PATH}")
  pkg_check_modules(PETSC REQUIRED IMPORTED_TARGET petsc>=3.18)
  file(REAL_PATH "${PETSC_DIR}" _bw_dir)
  file(REAL_PATH "${PETSC_INCLUDEDIR}" _bw_inc)
  string(FIND "${_bw_inc}" "${_bw_dir}" _bw_at)
  if(NOT _bw_at EQUAL 0)
    message(FATAL_ERROR "${_bw_pc}/petsc.pc describes the PETSc of ${PETSC_INCLUDEDIR}, not one in PETSC_DIR=${PETSC_DIR} "
                        "(a PETSc configured with --prefix: set PETSC_DIR to that prefix and PETSC_ARCH empty)")
  endif()
else()
  pkg_check_modules(PETSC REQUIRED IMPORTED_TARGET PETSc>=3.18)
endif()
# A static libpetsc needs the libraries PETSc itself links (Libs.private).
find_library(_bw_petsc_shared NAMES petsc petsc_real PATHS ${PETSC_LIBRARY_DIRS} NO_DEFAULT_PATH)
if(_bw_petsc_shared MATCHES "\\.a$")
  target_link_libraries(PkgConfig::PETSC INTERFACE ${PETSC_STATIC_LDFLAGS})
endif()

# Optional packages of the PETSc found: petscconf.h says what it was built with.
find_file(BW_PETSCCONF petscconf.h PATHS ${PETSC_INCLUDE_DIRS} ${PETSC_INCLUDEDIR} NO_DEFAULT_PATH)
if(NOT BW_PETSCCONF)
  message(FATAL_ERROR "petscconf.h not found in PETSc's include directories (${PETSC_INCLUDE_DIRS})")
endif()
file(STRINGS "${BW_PETSCCONF}" _bw_have REGEX "^#define PETSC_HAVE_(MUMPS|SUITESPARSE|HYPRE) +1")
set(_bw_report "")
foreach(pkg MUMPS SUITESPARSE HYPRE)
  if(_bw_have MATCHES "PETSC_HAVE_${pkg} ")
    set(BW_HAVE_${pkg} ON)
    string(APPEND _bw_report " ${pkg}:yes")
  else()
    set(BW_HAVE_${pkg} OFF)
    string(APPEND _bw_report " ${pkg}:no")
  endif()
endforeach()
set(_bw_left_out "")
if(NOT BW_HAVE_MUMPS)
  set(_bw_left_out "; without MUMPS the tests of the direct path and of MUMPS factorisations are left out")
endif()
message(STATUS "blockwall: PETSc ${PETSC_VERSION} (${BW_PETSCCONF}):${_bw_report} "
               "(SUITESPARSE gives CHOLMOD)${_bw_left_out}")

# ---------------------------------------------------------------- HDF5
# A build directory configured before this file used pkg-config's HDF5_*
# variables, which FindHDF5 would take for its own: forget them once.
if(DEFINED CACHE{__pkg_config_checked_HDF5})
  get_cmake_property(_bw_cached CACHE_VARIABLES)
  foreach(v IN LISTS _bw_cached)
    if(v MATCHES "^(HDF5_|pkgcfg_lib_HDF5_|__pkg_config_checked_HDF5|__pkg_config_arguments_HDF5)")
      unset(${v} CACHE)
    endif()
  endforeach()
endif()
set(HDF5_PREFER_PARALLEL TRUE)
find_package(HDF5 REQUIRED COMPONENTS C)
if(NOT HDF5_IS_PARALLEL)
  message(FATAL_ERROR "HDF5 ${HDF5_VERSION} found (${HDF5_C_INCLUDE_DIRS}) is not parallel: blockwall writes its "
                      "output collectively. Point HDF5_ROOT (or PATH, for h5pcc) at a parallel HDF5.")
endif()
if(NOT TARGET HDF5::HDF5)
  add_library(HDF5::HDF5 INTERFACE IMPORTED)
  target_include_directories(HDF5::HDF5 INTERFACE ${HDF5_C_INCLUDE_DIRS})
  target_link_libraries(HDF5::HDF5 INTERFACE ${HDF5_C_LIBRARIES})
  target_compile_definitions(HDF5::HDF5 INTERFACE ${HDF5_C_DEFINITIONS})
endif()
# the name src/CMakeLists.txt links (it used Debian's hdf5-openmpi.pc before)
add_library(PkgConfig::HDF5 INTERFACE IMPORTED)
target_link_libraries(PkgConfig::HDF5 INTERFACE HDF5::HDF5 MPI::MPI_C)

# ---------------------------------------------------------------- libyaml
pkg_check_modules(YAML REQUIRED IMPORTED_TARGET yaml-0.1)
