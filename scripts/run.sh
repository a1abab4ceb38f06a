#!/usr/bin/env bash
# The main job: builds the `tetia` executable, then
#  1. `tetia pairs` on the example pairs in examples/pairs.txt (or the file given as $1), next to
#     the exact volume (GMP rationals), with the relative error of each; fails if tetia
#     disagrees with the exact volume by more than 1e-10, relative (absolute where it is 0);
#     then the same in 2D, `tetia pairs --dim 2` on examples/triangle_pairs.txt (or $2);
#  2. `tetia demo`: two non-matching Gmsh meshes of a box and a ball against a box, their
#     supermesh, P0 and P1 remap of sin(x) cos(y) exp(z) both ways, a table, VTU files in
#     tetia-demo/; then `tetia demo --dim 2` (rectangle, disk and annulus meshes) into
#     tetia-demo-2d/;
#  3. installs tetia (`cmake --install build`: the library, headers, CMake and pkg-config files,
#     the CLI, and the Python package into Debian's /usr/local/lib/python3.X/dist-packages, so
#     that /usr/bin/python3 imports it from anywhere; with sudo when not root; TETIA_PREFIX
#     chooses another prefix), then runs the Python examples with the installed package from
#     another directory: examples/python/mortar_coupling.py, and examples/python/remap_meshio.py,
#     which writes tetia-demo/remap_slice.png.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

input="${1:-examples/pairs.txt}"
input2d="${2:-examples/triangle_pairs.txt}"
jobs="${TETIA_JOBS:-2}"

bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_CXX_COMPILER="${TETIA_CXX:-clang++}" -DCMAKE_BUILD_TYPE=Release -DTETIA_WERROR=ON
cmake --build build --target tetia_cli tetia_python -j"$jobs"

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# Runs `tetia pairs` (with extra options $3...) on file $1 with tetia and exact and prints a
# table; $2 says what is measured. Names: the last "# pair: NAME" comment before each data line.
compare_pairs() {
  local file="$1" what="$2"
  shift 2
  awk '/^[ \t]*# pair:/ { sub(/^[ \t]*# pair:[ \t]*/, ""); name = $0; next }
       /^[ \t]*(#|$)/ { next }
       { print (name != "" ? name : "line " NR); name = "" }' "$file" > "$tmp/names"
  ./build/tetia pairs "$@" --algorithm tetia < "$file" > "$tmp/tetia"
  ./build/tetia pairs "$@" --algorithm exact < "$file" > "$tmp/exact"

  echo
  echo "tetia pairs${*:+ $*} on $file ($what):"
  paste "$tmp/names" "$tmp/tetia" "$tmp/exact" | awk -F'\t' -v what="$what" '
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
      if (bad) { printf "\n%d pair(s) disagree with the exact value\n", bad; exit 1 }
      printf "\nall %d pairs agree with the exact value\n", NR
    }'
}

compare_pairs "$input" "volume of U intersected with V"
compare_pairs "$input2d" "area of A intersected with B" --dim 2

echo
echo "tetia demo (meshes, supermesh, conservative remap; VTU files in tetia-demo/):"
./build/tetia demo -o tetia-demo

echo
echo "tetia demo --dim 2 (2D meshes; VTU files in tetia-demo-2d/):"
./build/tetia demo --dim 2 -o tetia-demo-2d

echo
prefix="${TETIA_PREFIX:-/usr/local}"
install=(cmake --install build --prefix "$prefix")
if [[ $(id -u) -ne 0 && ! -w "$prefix" ]] && command -v sudo > /dev/null 2>&1; then install=(sudo "${install[@]}"); fi
echo "installing tetia into $prefix: ${install[*]}"
"${install[@]}" > "$tmp/install.log"
python_dir="$(sed -n 's/^TETIA_PYTHON_INSTALL_DIR:[A-Z]*=//p' build/CMakeCache.txt)"
[[ "$python_dir" = /* ]] || python_dir="$prefix/$python_dir"
python="$(sed -n 's/^Python_EXECUTABLE:[A-Z]*=//p' build/CMakeCache.txt)"
# Only a prefix whose site packages the interpreter does not search needs PYTHONPATH.
if ! "$python" -c "import sys; sys.exit(0 if '$python_dir' in sys.path else 1)"; then
  export PYTHONPATH="$python_dir${PYTHONPATH:+:$PYTHONPATH}"
fi
repo="$PWD"
(cd "$tmp" && "$python" -c "import tetia; print('python: import tetia', tetia.__version__, 'from', tetia.__file__)")

echo
echo "examples/python/mortar_coupling.py (mortar coupling matrix between non-matching 2D meshes):"
(cd "$tmp" && "$python" "$repo/examples/python/mortar_coupling.py")

echo
echo "examples/python/remap_meshio.py (P0 remap between meshio files; slice in tetia-demo/remap_slice.png):"
(cd "$tmp" && "$python" "$repo/examples/python/remap_meshio.py" -o "$repo/tetia-demo/remap_slice.png")
