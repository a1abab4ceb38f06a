#!/usr/bin/env bash
# The main job: builds the `tetia` executable, then
#  1. `tetia pairs` on the example pairs in examples/pairs.txt (or the file given as $1), next to
#     the exact volume (GMP rationals), with the relative error of each; fails if tetia
#     disagrees with the exact volume by more than 1e-10, relative (absolute where it is 0);
#  2. `tetia demo`: two non-matching Gmsh meshes of a box and a ball against a box, their
#     supermesh, P0 and P1 remap of sin(x) cos(y) exp(z) both ways, a table, VTU files in
#     tetia-demo/.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

input="${1:-examples/pairs.txt}"
jobs="${TETIA_JOBS:-2}"

bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DTETIA_WERROR=ON
cmake --build build --target tetia_cli -j"$jobs"

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# Names: the last "# pair: NAME" comment before each data line (else "line N").
awk '/^[ \t]*# pair:/ { sub(/^[ \t]*# pair:[ \t]*/, ""); name = $0; next }
     /^[ \t]*(#|$)/ { next }
     { print (name != "" ? name : "line " NR); name = "" }' "$input" > "$tmp/names"
./build/tetia pairs --algorithm tetia < "$input" > "$tmp/tetia"
./build/tetia pairs --algorithm exact < "$input" > "$tmp/exact"

echo
echo "tetia pairs on $input (volume of U intersected with V):"
paste "$tmp/names" "$tmp/tetia" "$tmp/exact" | awk -F'\t' '
  BEGIN { printf "%-24s %-24s %-24s %s\n", "pair", "tetia", "exact", "relative error"; bad = 0 }
  {
    t = $2 + 0; e = $3 + 0
    err = (e != 0) ? (t - e) / e : t
    if (err < 0) err = -err
    flag = (err > 1e-10) ? "  <-- MISMATCH" : ""
    if (flag != "") bad++
    printf "%-24s %-24s %-24s %.3g%s\n", $1, $2, $3, err, flag
  }
  END {
    if (bad) { printf "\n%d pair(s) disagree with the exact volume\n", bad; exit 1 }
    printf "\nall %d pairs agree with the exact volume\n", NR
  }'

echo
echo "tetia demo (meshes, supermesh, conservative remap; VTU files in tetia-demo/):"
./build/tetia demo -o tetia-demo
