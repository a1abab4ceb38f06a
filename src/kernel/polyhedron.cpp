#include "tetia/polyhedron.hpp"

namespace tetia {

std::vector<Tet> Polyhedron::tetrahedra() const {
  std::vector<Tet> out;
  if (num_corners_ == 0) return out;
  const Vec3 apex = corners_[0].point;
  for (int f = 0; f < num_facets_; ++f) {
    const auto idx = facet(f);
    bool has_apex = false;
    for (auto c : idx) has_apex |= c == 0;
    if (has_apex) continue;
    // Facets are counter-clockwise seen from outside, so (apex, p0, pk, pk+1) is positive.
    for (std::size_t k = 1; k + 1 < idx.size(); ++k)
      out.push_back({apex, corners_[idx[0]].point, corners_[idx[k]].point, corners_[idx[k + 1]].point});
  }
  return out;
}

}  // namespace tetia
