#!/usr/bin/env bash
# Uses an installed tetia as a user would. Installs the build folder given (default: build) into
# a fresh temporary prefix with `cmake --install`, then, for g++ and for clang++:
#  - configures and builds tests/consumer/ with find_package(tetia CONFIG), given nothing but
#    -DCMAKE_PREFIX_PATH, and runs it;
#  - builds tests/consumer/main.cpp with one compiler command from
#    `pkg-config --cflags --libs tetia-reference` and runs it;
# then runs the installed CLI's `tetia demo`, which generates meshes with Gmsh, checking that the
# library loaded the installed Gmsh module (not the build folder's); and, if the build has the
# Python package, imports the installed one from elsewhere and checks that it uses the installed
# libtetia. Stops at the first failure; removes its temporary folder.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

build="${1:-build}"
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  echo "test-consumer: $build is not a configured build folder of tetia" >&2
  exit 2
fi
tmp="$(mktemp -d /tmp/tetia-consumer.XXXXXX)"
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"

echo "-- install $build into $prefix"
cmake --install "$build" --prefix "$prefix" > "$tmp/install.log"

# GNUInstallDirs may have chosen lib/ or lib/<multiarch>/: take the pkgconfig folder installed.
pc="$(find "$prefix" -path '*/pkgconfig/tetia.pc' -print -quit)"
if [[ -z "$pc" ]]; then
  echo "test-consumer: no pkgconfig/tetia.pc under $prefix" >&2
  exit 1
fi
pcdir="$(dirname "$pc")"
libdir="$(dirname "$pcdir")"
# A static libtetia needs its private dependencies too: pkg-config --static.
pc_static=()
if ! compgen -G "$libdir/libtetia.so*" > /dev/null; then pc_static=(--static); fi

for cxx in g++ clang++; do
  echo "-- $cxx: CMake consumer (find_package(tetia CONFIG))"
  CXX="$cxx" cmake -S tests/consumer -B "$tmp/cmake-$cxx" -DCMAKE_PREFIX_PATH="$prefix" > "$tmp/cmake-$cxx.log" \
    || { cat "$tmp/cmake-$cxx.log"; exit 1; }
  cmake --build "$tmp/cmake-$cxx" > "$tmp/build-$cxx.log" || { cat "$tmp/build-$cxx.log"; exit 1; }
  "$tmp/cmake-$cxx/tetia_consumer"

  echo "-- $cxx: pkg-config consumer"
  flags="$(PKG_CONFIG_PATH="$pcdir" pkg-config "${pc_static[@]}" --cflags --libs tetia-reference)"
  echo "   $cxx -std=c++20 tests/consumer/main.cpp $flags"
  # shellcheck disable=SC2086  # the flags are words
  "$cxx" -std=c++20 tests/consumer/main.cpp $flags -o "$tmp/pkgconfig-$cxx"
  "$tmp/pkgconfig-$cxx"
done

echo "-- installed CLI: $prefix/bin/tetia demo (Gmsh meshes, through the installed module)"
LD_DEBUG=files LD_DEBUG_OUTPUT="$tmp/ld" "$prefix/bin/tetia" demo -o "$tmp/demo" --size 0.4 > "$tmp/demo.log" \
  || { cat "$tmp/demo.log"; exit 1; }
tail -n 3 "$tmp/demo.log"
module="$(cat "$tmp"/ld.* | sed -n 's/.*file=\([^ ]*libtetia_gmsh\.so\).*/\1/p' | head -n 1)"
if [[ -z "$module" ]]; then
  echo "test-consumer: the CLI loaded no Gmsh module" >&2
  exit 1
fi
module="$(realpath -m "$module")"
echo "   loaded $module"
if [[ "$module" != "$(realpath "$prefix")"/* ]]; then
  if [[ ${#pc_static[@]} -eq 0 ]]; then
    echo "test-consumer: the installed library loaded a Gmsh module outside its prefix" >&2
    exit 1
  fi
  # A static libtetia cannot know where it is installed: the configured prefix or the build's.
  echo "   (static library: the module of the configured prefix or of the build folder)"
fi
# The Python package, if this build has it: imported from another directory, with nothing but
# PYTHONPATH pointing into the prefix; it must load the prefix's libtetia, not the build's.
python_dir="$(sed -n 's/^TETIA_PYTHON_INSTALL_DIR:[A-Z]*=//p' "$build/CMakeCache.txt")"
python="$(sed -n 's/^Python_EXECUTABLE:[A-Z]*=//p' "$build/CMakeCache.txt")"
if [[ -n "$python_dir" && -n "$python" ]]; then
  [[ "$python_dir" = /* ]] || python_dir="$prefix/$python_dir"
  echo "-- installed Python package: PYTHONPATH=$python_dir $python -c 'import tetia' (from $tmp)"
  (cd "$tmp" && PYTHONPATH="$python_dir" "$python" - "$prefix" <<'PY'
import os
import sys

import numpy as np

import tetia

prefix = os.path.realpath(sys.argv[1])
assert os.path.realpath(tetia.__file__).startswith(prefix + os.sep), tetia.__file__
libraries = {line.split()[-1] for line in open("/proc/self/maps") if "libtetia" in line}
assert libraries and all(os.path.realpath(p).startswith(prefix + os.sep) for p in libraries), libraries
U = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
assert tetia.intersection_volume(U, U) == 1 / 6
m = tetia.Mesh(np.vstack([U, [[1, 1, 1]]]), [[0, 1, 2, 3], [1, 2, 3, 4]])
assert abs(tetia.Remap(m, m)(np.array([1.0, 2.0])) - [1.0, 2.0]).max() < 1e-15
print("   tetia", tetia.__version__, "from", os.path.dirname(tetia.__file__), "with", ", ".join(sorted(libraries)))
PY
  )
fi
echo "-- consumer tests passed"
