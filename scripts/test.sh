#!/usr/bin/env bash
# All tests: installs the dependencies, then builds and runs the whole suite twice,
#  1. build/       Release, warnings as errors;
#  2. build-asan/  RelWithDebInfo with AddressSanitizer + UndefinedBehaviorSanitizer.
# Stops at the first failure. TETIA_JOBS sets the parallelism (default 2).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

jobs="${TETIA_JOBS:-2}"

step() { printf '\n==> %s\n' "$*"; }

step "dependencies"
bash scripts/install-deps.sh

step "build (Release, -DTETIA_WERROR=ON)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DTETIA_WERROR=ON
cmake --build build -j"$jobs"

step "tests (build)"
ctest --test-dir build --output-on-failure -j"$jobs"

step "build-asan (RelWithDebInfo, -DTETIA_SANITIZE=ON)"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTETIA_SANITIZE=ON -DTETIA_WERROR=ON \
  -DTETIA_BUILD_BENCH=OFF
cmake --build build-asan -j"$jobs"

step "tests (build-asan)"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
ctest --test-dir build-asan --output-on-failure -j"$jobs"

step "all tests passed"
