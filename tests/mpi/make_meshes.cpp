// tests/mpi/make_meshes.cpp -- writes the meshes tests/mpi/cli_mpi.sh runs the CLI on, as .msh
// files in the folder given: Kuhn meshes of the unit cube and one offset by half a cell
// (exactly coplanar faces), Gmsh meshes of a box and of a ball (different domains), and
// hexahedra with interior nodes moved (split into tetrahedra by the reader).
#include <cstdio>
#include <filesystem>
#include <random>
#include <vector>

#include "tetia/io.hpp"
#include "tetia/mesh.hpp"
#include "tetia/mesh_from_arrays.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_meshes FOLDER\n");
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  using tetia::Vec3;
  tetia::write_msh(dir / "kuhn_a.msh", tetia::make_kuhn_mesh({6, 6, 6}, {0, 0, 0}, {1.0 / 6, 1.0 / 6, 1.0 / 6}));
  tetia::write_msh(dir / "kuhn_b.msh", tetia::make_kuhn_mesh({5, 5, 5}, {1.0 / 12, 1.0 / 12, 1.0 / 12}, {0.2, 0.2, 0.2}));
  tetia::write_msh(dir / "box.msh", tetia::generate_box({0, 0, 0}, {1, 1, 1}, 0.15));
  tetia::write_msh(dir / "ball.msh", tetia::generate_ball({0.5, 0.5, 0.5}, 0.6, 0.2));
  const int n = 4;
  std::vector<double> xyz;
  std::mt19937 rng(3);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      for (int k = 0; k <= n; ++k) {
        const bool inner = i > 0 && i < n && j > 0 && j < n && k > 0 && k < n;
        const auto jitter = [&] { return inner ? std::uniform_real_distribution<double>(-0.08, 0.08)(rng) : 0.0; };
        xyz.insert(xyz.end(), {double(i) / n + jitter(), double(j) / n + jitter(), double(k) / n + jitter()});
      }
  const auto id = [&](int i, int j, int k) { return std::int64_t((i * (n + 1) + j) * (n + 1) + k); };
  std::vector<std::int64_t> hexes;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k)
        hexes.insert(hexes.end(), {id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                                   id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
  const tetia::CellBlock block{5, hexes};
  tetia::write_msh(dir / "hexes.msh", tetia::make_tet_mesh(xyz, {&block, 1}, "hexes"));
  return 0;
}
