// tests/mpi/test_mpi.cpp -- the distributed supermesh and P0 remap (tetia/mpi.hpp) against one
// process, run by ctest under `mpiexec -np 1, 2, 3`. Every rank builds the same whole meshes
// (deterministically), takes its part of each by a partition (random, blocks of the file
// order, or one that leaves a rank without cells), and the pieces and values are gathered on
// rank 0 and compared with tetia::supermesh / tetia::remap_p0 on the whole meshes: the same
// pieces bit for bit, the same P0 values bit for bit.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "tetia/io.hpp"
#include "tetia/mesh.hpp"
#include "tetia/mpi.hpp"
#include "tetia/remap.hpp"
#include "tetia/supermesh.hpp"

namespace {

using tetia::TetMesh;
using tetia::Vec3;

int rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int ranks() {
  int n = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

/// This rank's part of a mesh (tetia::mpi::parts_of: cell ids are the whole mesh's cell
/// indices, node ids its node indices).
using Part = tetia::mpi::OwnedMeshPart;

Part part_of(const TetMesh& m, const std::vector<int>& owner, int r) {
  return std::move(tetia::mpi::parts_of(m, owner, ranks())[static_cast<std::size_t>(r)]);
}

// random: cells scattered; blocks: runs of the file order; slabs: compact regions, slabs across
// x for the source and across y for the target (partitions that do not match: every rank's
// target region meets every rank's source region); leave_one_empty: random, but the source
// leaves rank 0 without cells and the target the last rank.
enum class Partition { random, blocks, slabs, leave_one_empty };

/// Which rank holds each cell of m; the same on every rank (fixed seed).
std::vector<int> partition(const TetMesh& m, Partition kind, unsigned seed, bool source) {
  const int n = ranks();
  const std::size_t cells = m.num_cells();
  std::vector<int> owner(cells);
  if (kind == Partition::slabs) {
    double lo = 1e300, hi = -1e300;
    const auto axis = [&](const Vec3& p) { return source ? p.x : p.y; };
    for (const Vec3& p : m.nodes) lo = std::min(lo, axis(p)), hi = std::max(hi, axis(p));
    for (std::size_t c = 0; c < cells; ++c) {
      double centre = 0.0;
      for (const std::int32_t v : m.cells[c]) centre += 0.25 * axis(m.nodes[static_cast<std::size_t>(v)]);
      owner[c] = std::min(n - 1, static_cast<int>((centre - lo) / (hi - lo) * n));
    }
    return owner;
  }
  std::mt19937 rng(seed);
  for (std::size_t c = 0; c < cells; ++c) {
    switch (kind) {
      case Partition::random: owner[c] = static_cast<int>(rng() % static_cast<unsigned>(n)); break;
      case Partition::blocks: owner[c] = static_cast<int>(c * static_cast<std::size_t>(n) / cells); break;
      case Partition::slabs: break;
      case Partition::leave_one_empty: {
        // The source leaves rank 0 empty, the target the last rank (with one rank: nothing).
        const int skip = source ? 0 : n - 1;
        const int pick = n == 1 ? 0 : static_cast<int>(rng() % static_cast<unsigned>(n - 1));
        owner[c] = n == 1 ? 0 : (pick >= skip ? pick + 1 : pick);
        break;
      }
    }
  }
  return owner;
}

using Key = std::tuple<std::int64_t, std::int64_t>;

/// Every rank's pieces, on rank 0 (empty elsewhere), sorted by (target, source).
std::vector<tetia::mpi::DistributedPiece> gather(const std::vector<tetia::mpi::DistributedPiece>& mine) {
  std::vector<double> packed;
  for (const auto& p : mine) {
    double ids[2];
    std::memcpy(&ids[0], &p.source, sizeof(double));
    std::memcpy(&ids[1], &p.target, sizeof(double));
    packed.insert(packed.end(), {ids[0], ids[1], p.volume, p.first.x, p.first.y, p.first.z});
  }
  const int count = static_cast<int>(packed.size());
  std::vector<int> counts(static_cast<std::size_t>(ranks())), offsets(counts.size(), 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  for (std::size_t i = 1; i < counts.size(); ++i) offsets[i] = offsets[i - 1] + counts[i - 1];
  std::vector<double> all(rank() == 0 ? static_cast<std::size_t>(offsets.back() + counts.back()) : 0);
  MPI_Gatherv(packed.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, 0,
              MPI_COMM_WORLD);
  std::vector<tetia::mpi::DistributedPiece> out;
  for (std::size_t i = 0; i + 6 <= all.size(); i += 6) {
    tetia::mpi::DistributedPiece p;
    std::memcpy(&p.source, &all[i], sizeof(double));
    std::memcpy(&p.target, &all[i + 1], sizeof(double));
    p.volume = all[i + 2];
    p.first = {all[i + 3], all[i + 4], all[i + 5]};
    out.push_back(p);
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return Key{a.target, a.source} < Key{b.target, b.source};
  });
  return out;
}

/// Distributed pieces equal the serial ones, bit for bit, for the partitions given.
void expect_same_pieces(const TetMesh& source, const TetMesh& target, Partition kind, unsigned seed) {
  const Part s = part_of(source, partition(source, kind, seed, true), rank());
  const Part t = part_of(target, partition(target, kind, seed + 1, false), rank());
  tetia::mpi::DistributedOptions options;
  options.boxes_per_rank = 8;
  const tetia::mpi::DistributedSupermesh d = tetia::mpi::supermesh(s.view(), t.view(), MPI_COMM_WORLD, options);
  // Without node ids the received cells are a soup (R-tree search): the same pieces.
  tetia::mpi::MeshPart bare_source = s.view(), bare_target = t.view();
  bare_source.node_ids = {};
  bare_target.node_ids = {};
  const tetia::mpi::DistributedSupermesh soup = tetia::mpi::supermesh(bare_source, bare_target, MPI_COMM_WORLD, options);
  ASSERT_EQ(soup.pieces.size(), d.pieces.size());
  for (std::size_t i = 0; i < d.pieces.size(); ++i) {
    EXPECT_EQ(soup.pieces[i].source, d.pieces[i].source);
    EXPECT_EQ(soup.pieces[i].target, d.pieces[i].target);
    EXPECT_EQ(soup.pieces[i].volume, d.pieces[i].volume);
  }
  // Each rank's pieces are its own target cells', sorted.
  for (std::size_t i = 0; i < d.pieces.size(); ++i) {
    EXPECT_TRUE(std::binary_search(t.cell_ids.begin(), t.cell_ids.end(), d.pieces[i].target));
    if (i > 0) {
      EXPECT_LT((Key{d.pieces[i - 1].target, d.pieces[i - 1].source}), (Key{d.pieces[i].target, d.pieces[i].source}));
    }
  }
  const auto all = gather(d.pieces);
  if (rank() != 0) return;
  const tetia::Supermesh serial = tetia::supermesh(source, target);
  ASSERT_EQ(all.size(), serial.pieces.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    const tetia::SupermeshPiece& p = serial.pieces[i];
    ASSERT_EQ(all[i].source, p.source) << i;
    ASSERT_EQ(all[i].target, p.target) << i;
    EXPECT_EQ(all[i].volume, p.volume) << i;  // bit for bit
    EXPECT_EQ(all[i].first.x, p.first.x) << i;
    EXPECT_EQ(all[i].first.y, p.first.y) << i;
    EXPECT_EQ(all[i].first.z, p.first.z) << i;
  }
}

TetMesh kuhn(int n, double offset) {
  return tetia::make_kuhn_mesh({n, n, n}, {offset, offset, offset}, {1.0 / n, 1.0 / n, 1.0 / n});
}

TEST(Mpi, KuhnMeshesOffsetByHalfACell) {
  const TetMesh a = kuhn(5, 0.0), b = kuhn(5, 0.1);
  for (const Partition kind : {Partition::random, Partition::blocks, Partition::slabs, Partition::leave_one_empty})
    expect_same_pieces(a, b, kind, 11);
}

TEST(Mpi, IdenticalMeshesExactlyCoplanarEverywhere) {
  const TetMesh a = kuhn(4, 0.0);
  for (const Partition kind : {Partition::slabs, Partition::leave_one_empty}) expect_same_pieces(a, a, kind, 12);
}

TEST(Mpi, BallAgainstBox) {
  const TetMesh ball = tetia::generate_ball({0.5, 0.5, 0.5}, 0.6, 0.25);
  const TetMesh box = tetia::generate_box({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}, 0.2);
  expect_same_pieces(ball, box, Partition::random, 13);
  expect_same_pieces(box, ball, Partition::slabs, 14);
}

TEST(Mpi, PyramidAgainstCubeFromExtData) {
  const std::filesystem::path dir = std::filesystem::path(TETIA_SHARED_DIR) / "extdata";
  if (!std::filesystem::exists(dir / "lsm_pyramid_0_05.msh")) GTEST_SKIP() << "no ../shared/extdata";
  const TetMesh pyramid = tetia::read_mesh(dir / "lsm_pyramid_0_05.msh");
  const TetMesh cube = tetia::read_mesh(dir / "lsm_cube_0_05.msh");
  expect_same_pieces(pyramid, cube, Partition::slabs, 15);
}

TEST(Mpi, P0RemapEqualsTheSerialOneAndConserves) {
  const TetMesh source = kuhn(6, 0.0), target = tetia::generate_box({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}, 0.2);
  std::vector<double> u(source.num_cells());
  std::mt19937 rng(5);
  for (double& x : u) x = std::uniform_real_distribution<double>(-1.0, 1.0)(rng);
  for (const auto normalization : {tetia::P0Normalization::cell_volume, tetia::P0Normalization::covered_volume}) {
    const Part s = part_of(source, partition(source, Partition::random, 21, true), rank());
    const Part t = part_of(target, partition(target, Partition::leave_one_empty, 22, false), rank());
    // Two components: u and 2u.
    std::vector<double> values;
    for (const std::int64_t id : s.cell_ids) values.insert(values.end(), {u[static_cast<std::size_t>(id)], 2.0 * u[static_cast<std::size_t>(id)]});
    const std::vector<double> v = tetia::mpi::remap_p0(s.view(), values, t.view(), MPI_COMM_WORLD, 2, normalization);
    ASSERT_EQ(v.size(), 2 * t.cell_ids.size());
    const std::vector<double> serial = tetia::remap_p0(tetia::supermesh(source, target), u, normalization);
    double local = 0.0;
    for (std::size_t i = 0; i < t.cell_ids.size(); ++i) {
      const auto id = static_cast<std::size_t>(t.cell_ids[i]);
      EXPECT_EQ(v[2 * i], serial[id]) << id;  // bit for bit
      EXPECT_EQ(v[2 * i + 1], 2.0 * serial[id]) << id;
      local += v[2 * i] * target.volumes[id];
    }
    double total = 0.0;
    MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    double integral = 0.0, scale = 0.0;
    for (std::size_t c = 0; c < source.num_cells(); ++c) {
      integral += u[c] * source.volumes[c];
      scale += std::abs(u[c]) * source.volumes[c];
    }
    EXPECT_LE(std::abs(total - integral), 1e-13 * scale);
  }
}

TEST(Mpi, P1RemapAgreesWithTheSerialOneReproducesLinearFieldsAndConserves) {
  const TetMesh source = tetia::generate_box({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}, 0.17);
  const TetMesh target = kuhn(5, 0.0);
  // Two components: a random field, and a linear one (reproduced exactly by the projection).
  std::vector<double> u(2 * source.num_nodes());
  std::mt19937 rng(6);
  for (std::size_t n = 0; n < source.num_nodes(); ++n) {
    const Vec3& p = source.nodes[n];
    u[2 * n] = std::uniform_real_distribution<double>(-1.0, 1.0)(rng);
    u[2 * n + 1] = 1.0 + 2.0 * p.x - 3.0 * p.y + 0.5 * p.z;
  }
  std::vector<double> first(source.num_nodes());
  for (std::size_t n = 0; n < first.size(); ++n) first[n] = u[2 * n];
  tetia::SupermeshOptions keep;
  keep.keep_mixed_mass = true;
  const tetia::Supermesh whole = tetia::supermesh(source, target, keep);
  const std::vector<double> serial = tetia::remap_p1(whole, first);
  const tetia::SparseMatrix serial_mixed = tetia::mixed_mass_matrix(whole);
  double size = 0.0;
  for (const double v : serial) size = std::max(size, std::abs(v));
  for (const Partition kind : {Partition::random, Partition::slabs, Partition::leave_one_empty}) {
    const Part s = part_of(source, partition(source, kind, 31, true), rank());
    const Part t = part_of(target, partition(target, kind, 32, false), rank());
    std::vector<double> values;
    for (const std::int64_t id : s.node_ids)
      values.insert(values.end(), {u[2 * static_cast<std::size_t>(id)], u[2 * static_cast<std::size_t>(id) + 1]});
    tetia::P1RemapReport report;
    tetia::mpi::DistributedMatrix mixed;
    const std::vector<double> v =
        tetia::mpi::remap_p1(s.view(), values, t.view(), MPI_COMM_WORLD, 2, {}, &report, &mixed);
    ASSERT_EQ(v.size(), 2 * t.node_ids.size());
    EXPECT_GT(report.iterations, 0);
    for (std::size_t n = 0; n < t.node_ids.size(); ++n) {
      const auto id = static_cast<std::size_t>(t.node_ids[n]);
      const Vec3& p = target.nodes[id];
      EXPECT_NEAR(v[2 * n], serial[id], 1e-14 * size) << id;
      EXPECT_NEAR(v[2 * n + 1], 1.0 + 2.0 * p.x - 3.0 * p.y + 0.5 * p.z, 1e-12) << id;
    }
    // M_ts's rows, owned once each over the ranks, equal one process's to rounding.
    std::size_t owned = mixed.row_ids.size(), total_rows = 0;
    MPI_Allreduce(&owned, &total_rows, 1, MPI_UNSIGNED_LONG, MPI_SUM, MPI_COMM_WORLD);
    EXPECT_EQ(total_rows, target.num_nodes());
    for (std::size_t r = 0; r < mixed.row_ids.size(); ++r)
      for (auto e = mixed.row_begin[r]; e < mixed.row_begin[r + 1]; ++e) {
        const double want = serial_mixed.coeff(mixed.row_ids[r], mixed.column_ids[static_cast<std::size_t>(e)]);
        EXPECT_NEAR(mixed.values[static_cast<std::size_t>(e)], want, 1e-14 * std::abs(want));  // terms >= 0, summed in another order
      }
    // Conservation: the integral of the result (1^T M_t u_t over owned rows = sum of M_ts u_s).
    double local = 0.0;
    for (std::size_t r = 0; r < mixed.row_ids.size(); ++r)
      for (auto e = mixed.row_begin[r]; e < mixed.row_begin[r + 1]; ++e)
        local += mixed.values[static_cast<std::size_t>(e)] * first[static_cast<std::size_t>(mixed.column_ids[static_cast<std::size_t>(e)])];
    double integral = 0.0;
    MPI_Allreduce(&local, &integral, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    double serial_integral = 0.0;
    const Eigen::VectorXd b = serial_mixed * Eigen::Map<const Eigen::VectorXd>(first.data(), static_cast<Eigen::Index>(first.size()));
    for (Eigen::Index i = 0; i < b.size(); ++i) serial_integral += b[i];
    EXPECT_NEAR(integral, serial_integral, 1e-13);
  }
}

TEST(Mpi, BadInputOnOneRankStopsEveryRank) {
  const TetMesh a = kuhn(2, 0.0);
  Part s = part_of(a, partition(a, Partition::blocks, 1, true), rank());
  const Part t = part_of(a, partition(a, Partition::blocks, 2, false), rank());
  if (rank() == 0 && !s.cells.empty()) s.cells[1] = 1000;  // out of range on rank 0 only
  try {
    tetia::mpi::supermesh(s.view(), t.view(), MPI_COMM_WORLD);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(rank(), 0);
    EXPECT_NE(std::string(e.what()).find("source part: cell 0: node index 1000 out of range"), std::string::npos)
        << e.what();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(rank(), 0);
    EXPECT_NE(std::string(e.what()).find("rank 0: tetia: mpi: source part: cell 0"), std::string::npos) << e.what();
  }
  // And the communicator still works (nobody is left waiting).
  int one = 1, sum = 0;
  MPI_Allreduce(&one, &sum, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(sum, ranks());
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  if (rank() != 0) {
    // Only rank 0 prints; every rank's failures count (below).
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int mine = RUN_ALL_TESTS();
  int failed = 0;
  MPI_Allreduce(&mine, &failed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  if (rank() == 0 && failed != 0 && mine == 0) std::fprintf(stderr, "test_mpi: a test failed on another rank\n");
  MPI_Finalize();
  return failed;
}
