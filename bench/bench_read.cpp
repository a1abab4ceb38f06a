// bench_read: reading speed of .msh files, tetia's strict reader (read_any_mesh) against the
// Gmsh library's reader (through the Gmsh module, detail::gmsh_read_any_mesh), both including
// everything up to a finalized mesh (tag order, repeated cells, adjacency). A plain program.
//
// The file: a structured Kuhn mesh of 55^3 cubes (998,250 tetrahedra, 175,616 nodes), written
// by Gmsh itself in the four variants (2.2 and 4.1, ASCII and binary) to this build folder
// (cached). Each file is read by both readers in alternation, best of --repeat (default 3),
// and the two meshes are checked to be identical. Prints one line per variant: size, seconds
// and million cells per second of each reader, and their ratio. See docs/benchmarks.md.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "../src/io/gmsh_reader.hpp"
#include "../tests/support/gmsh_write.hpp"
#include "tetia/io.hpp"
#include "tetia/mesh.hpp"

namespace fs = std::filesystem;

namespace {

template <class F>
double seconds(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  int repeat = 3;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--repeat") repeat = std::max(1, std::atoi(argv[i + 1]));
  const int n = 55;
  const tetia::TetMesh mesh = tetia::make_kuhn_mesh({n, n, n}, {0, 0, 0}, {1.0 / n, 1.0 / n, 1.0 / n});
  std::printf("%-16s %10s %9s %12s %9s %12s %8s\n", "file", "MB", "tetia s", "tetia Mc/s", "gmsh s", "gmsh Mc/s",
              "ratio");
  for (const double version : {2.2, 4.1})
    for (const bool binary : {false, true}) {
      char name[64];
      std::snprintf(name, sizeof name, "read_%s_%s.msh", version == 2.2 ? "22" : "41", binary ? "bin" : "ascii");
      const fs::path file = fs::path("bench-read") / name;
      fs::create_directories(file.parent_path());
      if (!fs::exists(file)) tetia::testsupport::gmsh_write(mesh, file, version, binary);
      double best_tetia = 1e30, best_gmsh = 1e30;
      bool same = true;
      for (int r = 0; r < repeat; ++r) {
        tetia::AnyMesh a, b;
        best_tetia = std::min(best_tetia, seconds([&] { a = tetia::read_any_mesh(file); }));
        best_gmsh = std::min(best_gmsh, seconds([&] { b = tetia::detail::gmsh_read_any_mesh(file); }));
        same &= std::get<tetia::TetMesh>(a).cells == std::get<tetia::TetMesh>(b).cells &&
                std::get<tetia::TetMesh>(a).nodes.size() == std::get<tetia::TetMesh>(b).nodes.size();
      }
      const double cells = static_cast<double>(mesh.num_cells()) / 1e6;
      std::printf("%-16s %10.1f %9.3f %12.2f %9.3f %12.2f %8.2f%s\n", name,
                  static_cast<double>(fs::file_size(file)) / 1e6, best_tetia, cells / best_tetia, best_gmsh,
                  cells / best_gmsh, best_gmsh / best_tetia, same ? "" : "  MESHES DIFFER");
      if (!same) return 1;
    }
  return 0;
}
