// tests/consumer/main.cpp -- a program built against an installed tetia, by CMake
// (find_package(tetia CONFIG), CMakeLists.txt here) and by a plain compiler command with
// `pkg-config --cflags --libs tetia-reference` (scripts/test-consumer.sh). It uses the library's
// main entry points and the two headers that need more than the library itself (tetia/exact.hpp:
// GMP; tetia/baselines.hpp: tetia_reference), and exits with 1 on a wrong result.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "tetia/baselines.hpp"
#include "tetia/exact.hpp"
#include "tetia/mesh.hpp"
#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"

namespace {

int failures = 0;

void check(bool ok, const char* what, double got, double want) {
  if (!ok) {
    std::fprintf(stderr, "tetia_consumer: %s: got %.17g, want %.17g\n", what, got, want);
    ++failures;
  }
}

bool near(double a, double b, double tol) { return std::abs(a - b) <= tol * std::max(1.0, std::abs(b)); }

}  // namespace

int main() {
  // Two non-matching structured meshes: [0, 1]^3 in 3^3 cubes, [0.25, 1.25]^3 in 2^3 cubes.
  const tetia::TetMesh source = tetia::make_kuhn_mesh({3, 3, 3}, {0.0, 0.0, 0.0}, {1.0 / 3, 1.0 / 3, 1.0 / 3});
  const tetia::TetMesh target = tetia::make_kuhn_mesh({2, 2, 2}, {0.25, 0.25, 0.25}, {0.5, 0.5, 0.5});
  const double overlap = 0.75 * 0.75 * 0.75;  // [0.25, 1]^3

  const tetia::Supermesh s = tetia::supermesh(source, target);
  check(!s.pieces.empty(), "supermesh pieces", static_cast<double>(s.pieces.size()), 1.0);
  check(near(s.intersection_volume(), overlap, 1e-12), "intersection volume", s.intersection_volume(), overlap);

  // P0 remap of a constant: conserved over the overlap (cell_volume normalization).
  const std::vector<double> u(source.num_cells(), 2.0);
  const std::vector<double> v = tetia::remap_p0(s, u);
  check(v.size() == target.num_cells(), "remapped values", static_cast<double>(v.size()),
        static_cast<double>(target.num_cells()));
  double integral = 0.0;
  for (std::size_t t = 0; t < v.size() && t < target.num_cells(); ++t) integral += v[t] * target.volumes[t];
  check(near(integral, 2.0 * overlap, 1e-12), "remapped integral", integral, 2.0 * overlap);

  // The corner tetrahedron and its half-size copy: their intersection is the copy, 1/48.
  const tetia::Tet U{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  const tetia::Tet V{{{0, 0, 0}, {0.5, 0, 0}, {0, 0.5, 0}, {0, 0, 0.5}}};
  const mpq_class exact = tetia::exact::intersection_volume(U, V);
  check(exact == mpq_class(1, 48), "exact intersection volume", exact.get_d(), 1.0 / 48);
  const double clip = tetia::baselines::clip_volume(U, V);
  check(near(clip, 1.0 / 48, 1e-14), "clip_volume", clip, 1.0 / 48);

  if (failures != 0) return 1;
  std::printf("tetia_consumer: %zu pieces, intersection volume %.17g, remapped integral %.17g, exact %s: ok\n",
              s.pieces.size(), s.intersection_volume(), integral, exact.get_str().c_str());
  return 0;
}
