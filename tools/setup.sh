# Sourced by tools/demo and tools/test: install what is missing, then
# configure and build blockwall in build/ (Release). Safe to run again.
set -euo pipefail
BW_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

# Debian 12 packages. libopenblas0-pthread gives an optimised BLAS/LAPACK
# that Debian's alternatives pick over the reference libblas.so.3.
BW_DEBS=(build-essential gfortran cmake ninja-build pkg-config
         petsc-dev libhdf5-openmpi-dev hdf5-tools libmetis-dev libyaml-dev
         openmpi-bin libopenmpi-dev libopenblas0-pthread libblas3 liblapack3 python3 python3-pip)

# For tools/test only (it sets BW_SETUP_TESTS=1): ParaView's pvpython
# (python3-paraview, which brings paraview) and xvfb, the display its
# rendering needs, for the ParaView check of the XDMF files
# (tests/post/check_paraview.py; CMake leaves it out without them). About
# 200 MB to download and 1.2 GB installed, so tools/demo does not pay for them.
# gdb: the suite's watchdog (python/blockwall/launch.py) prints a backtrace of
# every rank of a run that hangs before it kills it (without gdb, only the
# run's last lines).
# libmumps-ptscotch-5.5: Debian's MUMPS built with PT-Scotch, the same
# version as petsc-dev's, which tests/solver/check_paths.py (analysis)
# preloads to check that blockwall orders in parallel where MUMPS can.
BW_TEST_DEBS=(python3-paraview xvfb gdb libmumps-ptscotch-5.5)

bw_install_debs() {
  local missing=() wanted=("${BW_DEBS[@]}")
  [ "${BW_SETUP_TESTS:-0}" = 1 ] && wanted+=("${BW_TEST_DEBS[@]}")
  for p in "${wanted[@]}"; do
    [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null)" = "install ok installed" ] || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "setup: installing ${missing[*]}"
    local sudo=""
    [ "$(id -u)" -ne 0 ] && sudo=sudo
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
}

# Python: numpy and h5py for the package python/blockwall (geometry files,
# results, launching), matplotlib for its plots, ezdxf for tools/import_dxf,
# meshio for the XDMF test, scipy for the limit analysis and the 3D crack
# pattern (blockwall.limit, blockwall.cracks3d), PyYAML for the test of the docs' YAML snippets
# (tests/docs); then the package itself, editable, so that
# `import blockwall` and blockwall-plot / blockwall-import-dxf use this checkout.
bw_pip() {
  python3 -m pip install -q "$@" 2>/dev/null || python3 -m pip install -q --break-system-packages "$@"
}

bw_install_python() {
  local need=()
  python3 -c 'import numpy' 2>/dev/null || need+=(numpy)
  python3 -c 'import h5py' 2>/dev/null || need+=(h5py)
  python3 -c 'import matplotlib' 2>/dev/null || need+=(matplotlib)
  python3 -c 'import meshio' 2>/dev/null || need+=(meshio)
  python3 -c 'import ezdxf' 2>/dev/null || need+=(ezdxf)
  python3 -c 'import scipy.optimize, scipy.spatial' 2>/dev/null || need+=(scipy)
  python3 -c 'import yaml' 2>/dev/null || need+=(pyyaml)
  if [ ${#need[@]} -gt 0 ]; then
    echo "setup: pip installing ${need[*]}"
    bw_pip "${need[@]}"
  fi
  if ! (cd / && python3 -c 'import blockwall, os, sys; sys.exit(os.path.realpath(blockwall.__file__) != os.path.realpath(sys.argv[1]))' \
          "$BW_ROOT/python/blockwall/__init__.py") 2>/dev/null; then
    echo "setup: pip installing the blockwall Python package (editable, $BW_ROOT/python)"
    bw_pip -e "$BW_ROOT/python"
  fi
}

bw_build() {
  # The interpreter itself, not a launcher in front of it (pyenv's shim, a
  # bash script, took 0.36 s of every test's start: 3 minutes of the suite)
  cmake -S "$BW_ROOT" -B "$BW_ROOT/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
        -DPython3_EXECUTABLE="$(python3 -c 'import sys; print(sys.executable)')" >/dev/null
  cmake --build "$BW_ROOT/build"
}

bw_install_debs
bw_install_python
bw_build
