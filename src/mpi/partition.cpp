// Parts of a whole mesh and a Morton partition (tetia/mpi.hpp): what a code that reads a mesh on
// one rank, the command line and the tests hand to the distributed supermesh.
#include <algorithm>
#include <stdexcept>
#include <string>

#include "../morton.hpp"
#include "tetia/mpi.hpp"

namespace tetia::mpi {

std::vector<OwnedMeshPart> parts_of(const TetMesh& mesh, std::span<const int> owner, int parts) {
  if (owner.size() != mesh.num_cells())
    throw std::invalid_argument("tetia: mpi: parts_of: " + std::to_string(owner.size()) + " owners for " +
                                std::to_string(mesh.num_cells()) + " cells");
  if (parts < 1) throw std::invalid_argument("tetia: mpi: parts_of: parts must be at least 1");
  std::vector<OwnedMeshPart> out(static_cast<std::size_t>(parts));
  // local[c's part][node]: the node's index in that part, -1 until used there.
  std::vector<std::vector<std::int32_t>> local(static_cast<std::size_t>(parts));
  for (std::size_t c = 0; c < mesh.num_cells(); ++c) {
    if (owner[c] < 0 || owner[c] >= parts)
      throw std::invalid_argument("tetia: mpi: parts_of: cell " + std::to_string(c) + ": owner " +
                                  std::to_string(owner[c]) + " not in [0, " + std::to_string(parts) + ")");
    const auto q = static_cast<std::size_t>(owner[c]);
    if (local[q].empty()) local[q].assign(mesh.num_nodes(), -1);
    OwnedMeshPart& p = out[q];
    p.cell_ids.push_back(static_cast<std::int64_t>(c));
    for (const std::int32_t v : mesh.cells[c]) {
      std::int32_t& l = local[q][static_cast<std::size_t>(v)];
      if (l < 0) {
        l = static_cast<std::int32_t>(p.node_ids.size());
        p.node_ids.push_back(v);
        const Vec3& x = mesh.nodes[static_cast<std::size_t>(v)];
        p.coordinates.insert(p.coordinates.end(), {x.x, x.y, x.z});
      }
      p.cells.push_back(l);
    }
  }
  return out;
}

std::vector<int> morton_partition(const TetMesh& mesh, int parts) {
  if (parts < 1) throw std::invalid_argument("tetia: mpi: morton_partition: parts must be at least 1");
  const std::size_t n = mesh.num_cells();
  std::vector<int> owner(n, 0);
  if (n == 0) return owner;
  Vec3 lo = mesh.nodes[0], hi = mesh.nodes[0];
  for (const Vec3& p : mesh.nodes) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const double lo_xyz[3] = {lo.x, lo.y, lo.z}, hi_xyz[3] = {hi.x, hi.y, hi.z};
  std::vector<std::pair<std::uint64_t, std::size_t>> order(n);  // (code, cell), sorted stably
  for (std::size_t c = 0; c < n; ++c) {
    Vec3 g{0, 0, 0};
    for (const std::int32_t v : mesh.cells[c]) {
      const Vec3& p = mesh.nodes[static_cast<std::size_t>(v)];
      g = {g.x + 0.25 * p.x, g.y + 0.25 * p.y, g.z + 0.25 * p.z};
    }
    const double centre[3] = {g.x, g.y, g.z};
    order[c] = {tetia::detail::morton_code<3>(centre, lo_xyz, hi_xyz), c};
  }
  tetia::detail::sort_by_key(order);
  for (std::size_t i = 0; i < n; ++i) owner[order[i].second] = static_cast<int>(i * static_cast<std::size_t>(parts) / n);
  return owner;
}

}  // namespace tetia::mpi
