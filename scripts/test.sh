#!/usr/bin/env bash
# All tests: installs the dependencies, then builds and runs the whole suite three times,
#  1. build/       Release, warnings as errors, with clang++ (the compiler the scripts build
#                  the executable and the benchmarks with: its kernel is faster);
#  2. build-gcc/   the same with g++, Debian's default compiler, which a plain `cmake` uses;
#  3. build-asan/  AddressSanitizer + UndefinedBehaviorSanitizer (clang++) at -O1 with line
#                  tables (-g1), the kernels' baseline only (-DTETIA_KERNEL_VARIANTS=OFF; the fuzz
#                  step covers both);
# after 1., scripts/test-consumer.sh installs build/ and builds and runs a program against the
# installed package (CMake and pkg-config, g++ and clang++); then 4. build-fuzz/: the kernels'
# libFuzzer targets (clang++, ASan + UBSan), each run from its seed corpus on a fixed number of
# inputs with a fixed seed (scripts/fuzz.sh); a violation of the kernels' contract fails the run.
# The kernel's portable scalar code (the other side of its SSE2 branches) is compiled into
# test_kernel_variants in builds 1. and 2. and compared there with the baseline bit for bit
# (tests/CMakeLists.txt, TETIA_TEST_PORTABLE_KERNEL).
# Stops at the first failure. TETIA_JOBS sets the parallelism (default 2); TETIA_CXX the
# compiler of build/ (default clang++). bench_cgal (CGAL's kernel, timed by
# scripts/reproduce-paper.sh) is left out here: its one file took 88 s of compiling, a tenth of
# build/, and no test runs it.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

jobs="${TETIA_JOBS:-2}"
cxx="${TETIA_CXX:-clang++}"

# Each step with the time it starts (UTC), so that a slow step shows in the log.
step() { printf '\n==> %s (%s)\n' "$*" "$(date -u +%H:%M:%S)"; }

step "dependencies"
bash scripts/install-deps.sh

step "build ($cxx, Release, -DTETIA_WERROR=ON)"
cmake -S . -B build -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=Release -DTETIA_WERROR=ON \
  -DTETIA_BENCH_CGAL=OFF
cmake --build build -j"$jobs"

step "tests (build)"
ctest --test-dir build --output-on-failure -j"$jobs"

step "consumer of the installed package (g++ and clang++)"
bash scripts/test-consumer.sh build

step "build-gcc (g++, Release, -DTETIA_WERROR=ON)"
cmake -S . -B build-gcc -DCMAKE_CXX_COMPILER=g++ -DCMAKE_BUILD_TYPE=Release -DTETIA_WERROR=ON \
  -DTETIA_BUILD_BENCH=OFF
cmake --build build-gcc -j"$jobs"

step "tests (build-gcc)"
ctest --test-dir build-gcc --output-on-failure -j"$jobs"

step "build-asan (clang++, -O1 -g1, -DTETIA_SANITIZE=ON)"
# The kernels' x86-64-v3 variant is left out here: this build runs the baseline sanitized, the
# fuzz step below the variant chosen on CI's machines (x86-64-v3), both from the same sources;
# the variant here would add minutes of sanitized compiling to CI.
# -O1 -g1 rather than RelWithDebInfo's -O2 -g: the sanitizers report the same errors with file
# and line (-g1 keeps the line tables), and the build takes half the time (measured with g++:
# 5.9 min against 12.3 on the 2-core VM). clang++ rather than g++: its sanitized compiles are
# faster (the slowest files, 2026-12-05: src/remap/linear_reconstruction.cpp 28 s against 35,
# tests/test_tri_properties.cpp 16 s against 30).
cmake -S . -B build-asan -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DTETIA_SANITIZE=ON \
  -DTETIA_WERROR=ON -DTETIA_BUILD_BENCH=OFF -DTETIA_KERNEL_VARIANTS=OFF
cmake --build build-asan -j"$jobs"

step "tests (build-asan)"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
ctest --test-dir build-asan --output-on-failure -j"$jobs"

step "fuzz (clang++, libFuzzer + ASan/UBSan, a fixed seed and number of inputs per target)"
# A fixed seed and a fixed number of inputs (not a time): every machine explores the same
# inputs, so that the suite's verdict does not depend on chance or on the machine's speed.
# About 10 s for the 3D kernel (its exact checks are slow), 20 s for the 2D one, 10 s for the
# .msh reader, 5 s for meshes from arrays and a few for the operator reader here; longer or other runs: scripts/fuzz.sh. The
# time only caps a runaway run.
TETIA_FUZZ_SECONDS="${TETIA_FUZZ_SECONDS:-600}" TETIA_FUZZ_RUNS_TET="${TETIA_FUZZ_RUNS_TET:-1500}" \
  TETIA_FUZZ_RUNS_TRI="${TETIA_FUZZ_RUNS_TRI:-10000}" TETIA_FUZZ_RUNS_MSH="${TETIA_FUZZ_RUNS_MSH:-200000}" \
  TETIA_FUZZ_RUNS_ARRAYS="${TETIA_FUZZ_RUNS_ARRAYS:-100000}" TETIA_FUZZ_RUNS_OPERATOR="${TETIA_FUZZ_RUNS_OPERATOR:-100000}" \
  TETIA_FUZZ_ARGS="${TETIA_FUZZ_ARGS:--seed=1}" bash scripts/fuzz.sh

step "all tests passed"
