#!/usr/bin/env bash
# Fuzzes the kernels' contract (fuzz/kernel_contract.hpp), the strict .msh reader
# (fuzz/fuzz_msh_reader.cpp), meshes from arrays (fuzz/fuzz_mesh_from_arrays.cpp) and the reader
# of saved operators (fuzz/fuzz_operator_mtx.cpp): builds the libFuzzer targets fuzz_tet_kernel,
# fuzz_tri_kernel, fuzz_msh_reader, fuzz_mesh_from_arrays and fuzz_operator_mtx
# (and fuzz_replay) in build-fuzz/ with clang++, then runs each for
# TETIA_FUZZ_SECONDS seconds (default 30) on a temporary copy of its seed corpus
# fuzz/corpus/<target>/, so the repository's corpus never grows. A violation of the contract
# (or an ASan/UBSan report, a timeout, an allocation beyond the limit) stops that target; its
# input is kept in build-fuzz/artifacts/ and printed: a kernel input as a text line
# (fuzz_replay --decode) ready for fuzz/regressions/<target>/*.txt or `tetia pairs`, a file in
# base64 (for fuzz/regressions/fuzz_msh_reader/, or a unit test). Exits non-zero on any finding.
#
# Environment: TETIA_FUZZ_SECONDS (per target), TETIA_FUZZ_RUNS_TET, TETIA_FUZZ_RUNS_TRI and
# TETIA_FUZZ_RUNS_MSH, TETIA_FUZZ_RUNS_ARRAYS, TETIA_FUZZ_RUNS_OPERATOR (a fixed number of inputs per target instead of a time, so that with a
# fixed -seed every machine explores the same inputs; the time then only caps a run far slower
# than expected), TETIA_JOBS (build parallelism, default 2), TETIA_FUZZ_ARGS (extra libFuzzer
# flags, e.g. "-seed=1"), TETIA_FUZZ_IGNORE (kinds of kernel violation to let pass, e.g.
# "moments-overflow,vanished-overflow"; see fuzz/fuzz_target.hpp).
set -euo pipefail
export LC_ALL=C  # one collation for ls and comm below
cd "$(dirname "${BASH_SOURCE[0]}")/.."

seconds="${TETIA_FUZZ_SECONDS:-30}"
jobs="${TETIA_JOBS:-2}"
build=build-fuzz
artifacts="$build/artifacts"
targets=(fuzz_tet_kernel fuzz_tri_kernel fuzz_msh_reader fuzz_mesh_from_arrays fuzz_operator_mtx)

cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DTETIA_BUILD_FUZZERS=ON -DTETIA_BUILD_TESTS=OFF -DTETIA_BUILD_BENCH=OFF -DTETIA_BUILD_PYTHON=OFF
cmake --build "$build" -j"$jobs" --target "${targets[@]}" fuzz_replay

mkdir -p "$artifacts"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# The survey mode of fuzz/fuzz_target.hpp would let violations pass: not here.
unset TETIA_FUZZ_LOG
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"

status=0
for target in "${targets[@]}"; do
  dim=3
  [[ $target == fuzz_tri_kernel ]] && dim=2
  corpus="$work/$target"
  mkdir -p "$corpus"
  cp fuzz/corpus/"$target"/* "$corpus"/
  runs="${TETIA_FUZZ_RUNS_TET:-}"
  [[ $target == fuzz_tri_kernel ]] && runs="${TETIA_FUZZ_RUNS_TRI:-}"
  [[ $target == fuzz_msh_reader ]] && runs="${TETIA_FUZZ_RUNS_MSH:-}"
  [[ $target == fuzz_mesh_from_arrays ]] && runs="${TETIA_FUZZ_RUNS_ARRAYS:-}"
  [[ $target == fuzz_operator_mtx ]] && runs="${TETIA_FUZZ_RUNS_OPERATOR:-}"
  # Kernel inputs are a few doubles; files need room (the seeds are about 2 KB). The reader's
  # memory must stay proportional to its input: 256 MB is hundreds of times what 8 KB justify.
  limits=(-max_total_time="$seconds" -max_len=256)
  [[ $target == fuzz_msh_reader ]] && limits=(-max_total_time="$seconds" -max_len=8192 -malloc_limit_mb=256)
  [[ $target == fuzz_mesh_from_arrays ]] && limits=(-max_total_time="$seconds" -max_len=2048 -malloc_limit_mb=256)
  [[ $target == fuzz_operator_mtx ]] && limits=(-max_total_time="$seconds" -max_len=4096 -malloc_limit_mb=256)
  [[ -n $runs ]] && limits+=(-runs="$runs")
  printf '\n==> %s, %s\n' "$target" "${runs:+$runs inputs, at most }$seconds s"
  ls "$artifacts" > "$work/before"
  # shellcheck disable=SC2086  # TETIA_FUZZ_ARGS is a list of flags
  if ! "$build/$target" "${limits[@]}" -timeout=10 -print_final_stats=1 \
      -artifact_prefix="$artifacts/$target-" ${TETIA_FUZZ_ARGS:-} "$corpus"; then
    status=1
  fi
  # Every artifact this run wrote is a finding (contract violation, sanitizer report, timeout,
  # out of memory): show each as a text line.
  ls "$artifacts" > "$work/after"
  while read -r found; do
    status=1
    printf '\n%s:\n' "$artifacts/$found"
    if [[ $target == fuzz_msh_reader || $target == fuzz_mesh_from_arrays || $target == fuzz_operator_mtx ]]; then
      base64 -w 76 "$artifacts/$found" || true  # a file: keep it as fuzz/regressions/fuzz_msh_reader/*.msh
    else
      "$build/fuzz_replay" --dim "$dim" --decode "$artifacts/$found" || true
    fi
  done < <(comm -13 "$work/before" "$work/after")
done

if [[ $status -ne 0 ]]; then
  printf '\nfuzz: findings (inputs in %s/)\n' "$artifacts"
else
  printf '\nfuzz: no findings\n'
fi
exit "$status"
