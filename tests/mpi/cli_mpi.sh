#!/usr/bin/env bash
# tests/mpi/cli_mpi.sh TETIA MAKE_MESHES SHARED_DIR NP MPIEXEC [MPIEXEC FLAGS...] -- the tetia
# executable under mpiexec -np NP against itself in one process: for pairs of meshes of
# tests/mpi/make_meshes.cpp (and ../shared/extdata's pyramid and cube where present), each with
# one --partition in turn, `tetia supermesh` and `tetia remap` (P0 and P1, with -o) print the same JSON
# (but for seconds, and candidates: the ranks search with R-trees) and write the same files,
# byte for byte. Then a bad file: every rank ends, exit status 2, one message.
set -euo pipefail
tetia="$1" make_meshes="$2" shared="$3" np="$4"
shift 4
mpiexec=("$@" -np "$np")
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$make_meshes" "$tmp"
export OMP_NUM_THREADS=1

strip() { sed -E 's/"(seconds|candidates)": [0-9.eE+-]+(, )?//g'; }

same() {  # same NAME ARGS...: serial and MPI runs of `tetia ARGS -o FILE` agree
  local name="$1"
  shift
  "$tetia" "$@" --quiet -o "$tmp/serial.vtu" | strip > "$tmp/serial.json"
  "${mpiexec[@]}" "$tetia" "$@" --quiet -o "$tmp/mpi.vtu" | strip > "$tmp/mpi.json"
  if ! diff "$tmp/serial.json" "$tmp/mpi.json" > /dev/null; then
    echo "cli_mpi: $name: the JSON differs"
    diff "$tmp/serial.json" "$tmp/mpi.json" || true
    exit 1
  fi
  if ! cmp -s "$tmp/serial.vtu" "$tmp/mpi.vtu"; then
    echo "cli_mpi: $name: the -o files differ"
    exit 1
  fi
  echo "ok: $name"
}

pairs=("kuhn_a kuhn_b" "kuhn_a kuhn_a" "ball box" "box ball" "hexes box")
extra=()
if [[ -f "$shared/extdata/lsm_pyramid_0_05.msh" ]]; then
  extra=("$shared/extdata/lsm_pyramid_0_05.msh $shared/extdata/lsm_cube_0_05.msh")
fi
# Each pair with one partition (in turn), so that every partition meets several pairs.
partitions=(reversed morton random)
i=0
for pair in "${pairs[@]}" "${extra[@]}"; do
  read -r a b <<< "$pair"
  [[ "$a" = /* ]] || a="$tmp/$a.msh"
  [[ "$b" = /* ]] || b="$tmp/$b.msh"
  partition="${partitions[$((i % 3))]}"
  i=$((i + 1))
  what="$(basename "$a") x $(basename "$b"), $partition, np $np"
  same "supermesh $what" supermesh "$a" "$b" --partition "$partition"
  same "remap P0 $what" remap "$a" "$b" --expr "sin(3*x)*y + z" --order 0 --partition "$partition"
  same "remap P1 $what" remap "$a" "$b" --expr "sin(3*x)*y + z" --order 1 --partition "$partition"
done

# A bad file read by rank 0: every rank stops with status 2, and one message is printed.
echo "not a mesh" > "$tmp/bad.msh"
set +e
"${mpiexec[@]}" "$tetia" supermesh "$tmp/bad.msh" "$tmp/box.msh" > "$tmp/bad.out" 2> "$tmp/bad.err"
status=$?
set -e
messages="$(grep -c '^tetia: ' "$tmp/bad.err" || true)"
if [[ $status -ne 2 || "$messages" -ne 1 || -s "$tmp/bad.out" ]]; then
  echo "cli_mpi: bad file: status $status (want 2), $messages messages (want 1), stdout: $(cat "$tmp/bad.out")"
  cat "$tmp/bad.err"
  exit 1
fi
echo "ok: a bad file ends every rank with status 2 and one message"
