// fuzz/fuzz_mesh_from_arrays.cpp -- libFuzzer target for meshes from arrays
// (tetia/mesh_from_arrays.hpp, what bindings hand user arrays to): for any points and cell
// blocks, make_tet_mesh / make_tri_mesh either give a finalized mesh with one file cell per
// cell given, each of finite non-negative measure, or throw std::invalid_argument or
// std::runtime_error with a message "tetia: fuzz: ..."; anything else is a finding.
//
// Input bytes: [0] dimension (even: 3D; odd: 2D) and, in 2D, the points' dimension (2 or 3);
// [1] the number of nodes (1-32); then per node its coordinates, each a byte (a small integer,
// so that cells touch, share faces and collapse) or, with the top bit of [0], 8 bytes (any
// double: subnormal, huge, not finite); then blocks: a type byte (0-7: types of both
// dimensions and unknown ones), a count byte (cells, 0-15), and that many cells of one signed
// byte per node index (negative and out of range ones included).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "tetia/file_cells.hpp"
#include "tetia/mesh.hpp"
#include "tetia/mesh_from_arrays.hpp"

namespace {

struct Reader {
  const std::uint8_t* data;
  std::size_t size, at = 0;
  bool more() const { return at < size; }
  std::uint8_t byte() { return at < size ? data[at++] : 0; }
  double real(bool raw) {
    if (!raw) return static_cast<double>(static_cast<std::int8_t>(byte()));
    std::uint8_t b[8] = {};
    for (auto& x : b) x = byte();
    double v;
    std::memcpy(&v, b, 8);
    return v;
  }
};

[[noreturn]] void finding(const char* what) {
  std::fprintf(stderr, "fuzz_mesh_from_arrays: %s\n", what);
  std::abort();
}

template <class Mesh>
void check(const Mesh& m, std::size_t cells_given) {
  if (m.num_file_cells() != cells_given) finding("file cells differ from the cells given");
  for (const double v : tetia::file_cell_measures(m))
    if (!(v >= 0.0) || !std::isfinite(v)) finding("a file cell of negative or non-finite measure");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Reader in{data, size};
  const std::uint8_t head = in.byte();
  const bool three = (head & 1) == 0, raw = (head & 0x80) != 0;
  const int coordinate_dim = three ? 3 : ((head & 2) ? 3 : 2);
  const std::size_t nodes = 1 + in.byte() % 32;
  std::vector<double> xyz(nodes * static_cast<std::size_t>(coordinate_dim));
  for (double& x : xyz) x = in.real(raw);
  std::vector<std::vector<std::int64_t>> indices;
  std::vector<int> types;
  std::size_t cells = 0;
  while (in.more() && types.size() < 8) {
    const int type = in.byte() % 8;
    const int count = in.byte() % 16;
    const int n = tetia::file_cell_nodes(type) > 0 ? tetia::file_cell_nodes(type) : 1 + type % 4;
    std::vector<std::int64_t> block;
    for (int c = 0; c < count * n; ++c) block.push_back(static_cast<std::int8_t>(in.byte()));
    types.push_back(type);
    indices.push_back(std::move(block));
    cells += static_cast<std::size_t>(count);
  }
  std::vector<tetia::CellBlock> blocks;
  for (std::size_t b = 0; b < types.size(); ++b) blocks.push_back({types[b], indices[b]});
  try {
    if (three) check(tetia::make_tet_mesh(xyz, blocks, "fuzz"), cells);
    else check(tetia::make_tri_mesh(xyz, coordinate_dim, blocks, "fuzz"), cells);
  } catch (const std::exception& e) {  // invalid_argument (arrays) or runtime_error (finalize)
    if (std::string_view(e.what()).rfind("tetia: fuzz: ", 0) != 0) finding(e.what());
  }
  return 0;
}
