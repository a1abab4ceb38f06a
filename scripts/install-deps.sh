#!/usr/bin/env bash
# Installs the Debian packages tetia needs to build, test, benchmark and plot (Debian 12).
# Idempotent and non-interactive: when every package is already installed it does nothing
# (set TETIA_FORCE_APT=1 to run apt-get anyway); otherwise it runs `apt-get update`, then
# `apt-get install -y --no-install-recommends` of the list below. Uses sudo when not root.
set -euo pipefail

packages=(
  build-essential   # make, libc headers
  g++               # C++20 compiler (the default one; tested in CI)
  clang             # C++20 compiler the scripts build with: a faster kernel (docs/benchmarks.md)
  libomp-dev        # OpenMP runtime for clang
  libclang-rt-14-dev  # libFuzzer and the sanitizer runtimes for clang (fuzz/, scripts/fuzz.sh)
  cmake             # >= 3.25
  ninja-build
  libgtest-dev      # GoogleTest (tests)
  libgmock-dev
  libbenchmark-dev  # Google Benchmark (bench/)
  libgmp-dev        # GMP rationals: exact reference (tetia_reference)
  libmpfr-dev       # needed by CGAL
  libcli11-dev      # command-line parsing (tetia executable)
  libcgal-dev       # CGAL: the comparison in bench/bench_cgal
  libboost-dev      # Boost.Geometry R-tree (the MPI layer's rank boxes); CGAL's headers need it too
  libeigen3-dev     # sparse matrices and conjugate gradients (P1 remap)
  libgmsh-dev       # generating meshes (Gmsh C++ API), and the reference reader of the tests
  zlib1g-dev        # compressed binary VTU output
  libmuparser-dev   # analytic fields in `tetia remap --expr`
  libnetcdf-dev     # ESMF weight files (`tetia remap --save-operator W.nc`, `tetia apply`)
  python3-netcdf4   # the tests read those files with another netCDF reader
  python3           # scripts and plots
  python3-matplotlib
  python3-numpy
  python3-vtk9      # VTK's own reader checks the VTU files in the tests (tests/vtu_dump.py)
  # the Python package (python/): bindings, and what it works with and is tested with
  python3-dev       # headers for extension modules
  pybind11-dev      # the bindings
  python3-scipy     # sparse matrices (Remap.matrix, ...); Delaunay meshes in the tests
  python3-meshio    # mesh files of every format (tetia.read_mesh, Mesh.from_meshio)
  python3-h5py      # meshio's XDMF files
  python3-pytest    # the package's tests (python/tests/)
  libopenmpi-dev    # MPI: the distributed supermesh and remap (tetia_mpi, tests/mpi/)
  openmpi-bin       # mpiexec for the MPI tests
)

names=("${packages[@]}")

missing=()
for p in "${names[@]}"; do
  status=$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null || true)
  if [[ "$status" != "installed" ]]; then missing+=("$p"); fi
done

if [[ ${#missing[@]} -eq 0 && "${TETIA_FORCE_APT:-0}" != "1" ]]; then
  echo "install-deps: all ${#names[@]} packages already installed: ${names[*]}"
  exit 0
fi

if [[ $(id -u) -eq 0 ]]; then
  SUDO=()
elif command -v sudo >/dev/null 2>&1; then
  SUDO=(sudo)
else
  echo "install-deps: not root and sudo is not available; run as root: $0" >&2
  echo "install-deps: missing packages: ${missing[*]}" >&2
  exit 1
fi

export DEBIAN_FRONTEND=noninteractive
echo "install-deps: missing: ${missing[*]:-none}"
echo "install-deps: + ${SUDO[*]:+${SUDO[*]} }apt-get update"
"${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
echo "install-deps: + ${SUDO[*]:+${SUDO[*]} }apt-get install -y --no-install-recommends ${names[*]}"
"${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${names[@]}"
echo "install-deps: done"
