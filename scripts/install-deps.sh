#!/usr/bin/env bash
# Installs the Debian packages Horizon needs, skipping those already present.
# Runs as root on Debian 12 (the README's quick start); prints what it installs.
# libopenblas0-pthread replaces the reference BLAS under CHOLMOD (solver.linear_solver:
# cholesky): its supernodal factorisation is dense-block work, 4x faster with OpenBLAS.
# libexodusii-dev: Exodus II mesh input (about 32 MB with netCDF and HDF5).
# libgmsh-dev: Gmsh .msh meshes of every version and STL/PLY surfaces (body shapes), read
# by the Gmsh library rather than by parsers of Horizon's own (issue 32). It pulls
# OpenCASCADE, FLTK and friends: 23 packages, about 175 MB installed on top of the rest of
# this list. Horizon loads it only when a deck reads such a file (docs/design.md).
# libopenmpi-dev, openmpi-bin: the MPI program horizon-mpi (HORIZON_MPI; `make test` builds and tests it).
# pybind11-dev, python3-dev, python3-numpy, python3-pytest: the Python module and its tests
# (against /usr/bin/python3); python3-matplotlib: the examples in examples/python.
# python3-vtk9: VTK's own XML reader opens every frame in the output-fault tests
# (tests/python/test_vtk_frames.py; about 20 MB).
# libcairo2-dev, fonts-dejavu-core: `horizon plot` and `horizon render` draw with Cairo
# (PNG, SVG, PDF) and write their text in DejaVu Sans; libpng-dev stays for the tests,
# which read the pictures back.
# python3-netcdf4: reads Exodus files for the Peridigm suite runner's comparer
# (bench/peridigm/compare_exodus.py; exodiff is not packaged by Debian).
set -euo pipefail
pkgs=(g++ cmake ninja-build pkg-config libyaml-cpp-dev libeigen3-dev libmuparser-dev
      pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib python3-vtk9
      libcli11-dev libfmt-dev libgtest-dev libgmock-dev libbenchmark-dev libpng-dev zlib1g-dev nlohmann-json3-dev
      libsuitesparse-dev libspectra-dev libopenblas0-pthread libexodusii-dev libgmsh-dev libopenmpi-dev openmpi-bin
      libcairo2-dev fonts-dejavu-core
      python3-netcdf4)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  SUDO=sudo
else
  SUDO=
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
