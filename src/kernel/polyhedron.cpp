#include "tetia/polyhedron.hpp"

namespace tetia {

std::vector<std::array<std::uint8_t, 4>> Polyhedron::tetrahedra_corners() const {
  std::vector<std::array<std::uint8_t, 4>> out;
  for (int f = 0; f < num_facets_; ++f) {
    const auto idx = facet(f);
    bool has_apex = false;
    for (auto c : idx) has_apex |= c == 0;
    if (has_apex) continue;
    // Facets are counter-clockwise seen from outside, so (apex, p0, pk, pk+1) is positive.
    for (std::size_t k = 1; k + 1 < idx.size(); ++k) out.push_back({0, idx[0], idx[k], idx[k + 1]});
  }
  return out;
}

std::vector<Tet> Polyhedron::tetrahedra() const {
  std::vector<Tet> out;
  for (const auto& t : tetrahedra_corners())
    out.push_back({corners_[t[0]].point, corners_[t[1]].point, corners_[t[2]].point, corners_[t[3]].point});
  return out;
}

}  // namespace tetia
