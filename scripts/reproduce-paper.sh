#!/usr/bin/env bash
# Reproduces the paper's numerical results and compares tetia with the alternatives
# (docs/paper-reproduction.md): the Section 5.2 sweep (Figure 11), parsimony (Sections 4.1, 5.1),
# robustness on near-degenerate pairs (Theorem 6, Corollary 2) and speed on 10^6 random pairs
# (bench_pairs, and bench_cgal when CGAL is found).
#
#   bash scripts/reproduce-paper.sh            # full run, results in docs/figures/ (~6-10 min)
#   bash scripts/reproduce-paper.sh --quick    # smoke test, results in build-repro/figures-quick/
#
# Builds in build-repro (Release, -Werror; with clang++ when it is installed, as scripts/run.sh
# does). Before each timed step it waits, polling every 60 s, until the 1-minute load average
# is below REPRO_MAX_LOAD (1.2), for at most REPRO_MAX_WAIT seconds (300) over the whole run,
# and records the load each step started at in run-info.txt.
# (The load average includes the previous step for a minute or two after it ends.)
#
# Environment: REPRO_BUILD_DIR (build-repro), REPRO_OUT (docs/figures), TETIA_JOBS (2),
# REPRO_MAX_LOAD (1.2), REPRO_MAX_WAIT (300), REPRO_CGAL (1; 0 skips bench_cgal, whose build
# alone takes ~2.5 min on two cores), TETIA_WERROR (ON), TETIA_CXX (the compiler),
# PYTHON (a python3 with matplotlib).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

quick=0
if [[ "${1:-}" == "--quick" ]]; then
  quick=1
elif [[ $# -gt 0 ]]; then
  echo "usage: bash scripts/reproduce-paper.sh [--quick]" >&2
  exit 2
fi

build="${REPRO_BUILD_DIR:-build-repro}"
jobs="${TETIA_JOBS:-2}"
max_load="${REPRO_MAX_LOAD:-1.2}"
max_wait="${REPRO_MAX_WAIT:-300}"  # in all
waited=0
cgal="${REPRO_CGAL:-1}"
if [[ $quick == 1 ]]; then
  out="${REPRO_OUT:-$build/figures-quick}"
  cgal="${REPRO_CGAL:-0}"
else
  out="${REPRO_OUT:-docs/figures}"
fi

# A python3 that has matplotlib (Debian's python3-matplotlib lives in /usr/bin/python3).
python="${PYTHON:-}"
if [[ -z "$python" ]]; then
  for p in python3 /usr/bin/python3; do
    if "$p" -c 'import matplotlib' 2>/dev/null; then python="$p"; break; fi
  done
fi
if [[ -z "$python" ]]; then
  echo "no python3 with matplotlib found (apt-get install python3-matplotlib, or set PYTHON)" >&2
  exit 1
fi

# The compiler: clang++ as scripts/run.sh uses (docs/benchmarks.md, "Compiler"), else c++.
cxx="${TETIA_CXX:-}"
if [[ -z "$cxx" ]]; then
  if command -v clang++ >/dev/null 2>&1; then cxx=clang++; else cxx=c++; fi
fi

t_start=$(date +%s)
echo "== build ($build, Release, $cxx)"
mkdir -p "$build"
cmake -S . -B "$build" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=Release -DTETIA_BUILD_TESTS=OFF \
  -DTETIA_WERROR="${TETIA_WERROR:-ON}" -DTETIA_BENCH_CGAL="$([[ $cgal == 1 ]] && echo ON || echo OFF)" \
  > "$build/repro-cmake.log" 2>&1 || { cat "$build/repro-cmake.log"; exit 1; }
targets=(paper_repro bench_pairs)
if [[ $cgal == 1 ]]; then
  if [[ -d "$build/bench/CMakeFiles/bench_cgal.dir" ]]; then
    targets+=(bench_cgal)
  else
    echo "   CGAL not found: no bench_cgal"
    cgal=0
  fi
fi
for t in "${targets[@]}"; do
  echo "   building $t"
  cmake --build "$build" --target "$t" -j"$jobs" > "$build/repro-build.log" 2>&1 || { tail -40 "$build/repro-build.log"; exit 1; }
done

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

load1() { cut -d' ' -f1 /proc/loadavg; }
# Waits until the 1-minute load average is below max_load, or until the run has waited
# max_wait seconds in all. Not called in a subshell: it updates `waited`.
wait_quiet() {
  while awk -v l="$(load1)" -v m="$max_load" 'BEGIN { exit !(l >= m) }'; do
    if (( waited >= max_wait )); then
      echo "   load $(load1) still >= $max_load (waited ${waited} s in all): running anyway"
      return
    fi
    echo "   load $(load1) >= $max_load: waiting 60 s"
    sleep 60
    waited=$((waited + 60))
  done
}

{
  echo "date:     $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "machine:  $(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) cores, $(free -g | awk '/^Mem:/ { print $2 }') GB RAM"
  echo "compiler: $(c++ --version | head -1)"
  measured=(src/kernel src/baselines.cpp src/exact.cpp
            include/tetia/geometry.hpp include/tetia/polyhedron.hpp include/tetia/tet_intersection.hpp
            include/tetia/kernel_trace.hpp include/tetia/baselines.hpp include/tetia/exact.hpp
            bench/bench_pairs.cpp bench/bench_cgal.cpp bench/random_pairs.hpp)
  echo "code:     $(git rev-parse --short HEAD 2>/dev/null || echo '?')$(git diff --quiet HEAD -- "${measured[@]}" 2>/dev/null || echo ' + uncommitted changes to the kernel, baselines or benchmarks')"
  echo "flags:    Release (-O3 -DNDEBUG) -ffp-contract=off -fno-fast-math"
} > "$tmp/run-info.txt"

repro="$build/bench/paper_repro"
qflag=()
[[ $quick == 1 ]] && qflag=(--quick)

echo "== parsimony and robustness (untimed)"
"$repro" "${qflag[@]}" --parts=parsimony,robustness --out="$tmp" | tee "$tmp/paper_repro_counts.txt"

echo "== Section 5.2 sweep (timed)"
wait_quiet
echo "load at start of sweep timing:       $(load1) (1-minute average)" >> "$tmp/run-info.txt"
"$repro" "${qflag[@]}" --parts=sweep --out="$tmp" | tee "$tmp/paper_repro_sweep.txt"

echo "== bench_pairs (timed)"
bp_args=(--benchmark_repetitions=3 --benchmark_report_aggregates_only=true)
[[ $quick == 1 ]] && bp_args=(--pairs=100000 --benchmark_repetitions=1)
wait_quiet
echo "load at start of bench_pairs:        $(load1)" >> "$tmp/run-info.txt"
"$build/bench/bench_pairs" "${bp_args[@]}" --benchmark_out="$tmp/bench_pairs.json" \
  --benchmark_out_format=json | tee "$tmp/bench_pairs.txt"

if [[ $cgal == 1 ]]; then
  echo "== bench_cgal (timed)"
  wait_quiet
  echo "load at start of bench_cgal:         $(load1)" >> "$tmp/run-info.txt"
  "$build/bench/bench_cgal" --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
    --benchmark_out="$tmp/bench_cgal.json" --benchmark_out_format=json | tee "$tmp/bench_cgal.txt"
fi
echo "load at end:                         $(load1) (waited ${waited} s in all for load < $max_load)" >> "$tmp/run-info.txt"

mkdir -p "$out"
rm -f "$out/bench_cgal.json" "$out/bench_cgal.txt"
cp "$tmp"/*.csv "$tmp"/*.json "$tmp"/*.txt "$out/"
"$python" scripts/paper_plots.py "$out"
echo "== done in $(( $(date +%s) - t_start )) s: $out/ (tables in $out/tables.md)"
