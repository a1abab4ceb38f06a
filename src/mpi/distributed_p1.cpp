// The distributed P1 (Galerkin) remap of tetia/mpi.hpp: M_t u_t = M_ts u_s, both matrices
// assembled by rows of target nodes on the rank that owns each node, solved by a conjugate
// gradient over MPI.
//
// Ownership. A target node (a global node id) is owned by the lowest rank whose target part has
// it; found by rendezvous: each rank sends its nodes' ids to rank id mod P, which answers with
// the lowest rank it heard each id from (O(nodes) messages, no rank holds more than its share).
// Assembly. The rank that holds a target cell sends its consistent mass matrix's rows (|T| / 20
// times (1 + delta_ij)) to the owners of its nodes; the rank that computed a piece (the target
// cell's rank) sends the piece's rows of M_ts (its local mixed mass matrix, columns the source
// cell's node ids, which travelled with the cell) and of M_ts u_s (the source cell's nodal values
// travelled too). Owners add what they receive in the order received.
// Solve. The Jacobi-preconditioned conjugate gradient that tetia::remap_p1 uses (Eigen's), with
// the same start (the lumped-mass solution b_i / sum_j (M_t)_ij) and the same test (residual
// norm below 1e-14 of b's), on the owned rows: each product gathers the values of the ghost
// columns (nodes of owned rows' cells that another rank owns) from their owners, and each dot
// product is an MPI_Allreduce. Sums are in another order than one process's, so results agree
// with tetia::remap_p1 to rounding amplified by the mass matrix's condition (1e-14 of the
// field's size in the tests), not bit for bit. A node whose cells all have zero volume gets a
// unit diagonal (and so 0), as in one process.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

#include "exchange.hpp"
#include "tetia/mpi.hpp"

namespace tetia::mpi {

namespace {

using detail::all_to_all;
using detail::rank_of;
using detail::size_of;

std::size_t home_of(std::int64_t id, std::size_t ranks) { return static_cast<std::size_t>(id) % ranks; }

/// For each local target node: the rank that owns it (the lowest rank holding its id).
std::vector<int> owners_of(std::span<const std::int64_t> node_ids, MPI_Comm comm) {
  const auto ranks = static_cast<std::size_t>(size_of(comm));
  std::vector<std::vector<std::int64_t>> ask(ranks);
  for (const std::int64_t id : node_ids) ask[home_of(id, ranks)].push_back(id);
  std::vector<int> from;
  const std::vector<std::int64_t> asked = all_to_all(comm, ask, "node ownership", &from);
  std::unordered_map<std::int64_t, int> lowest;
  lowest.reserve(asked.size());
  for (std::size_t q = 0, k = 0; q < ranks; ++q)
    for (int i = 0; i < from[q]; ++i, ++k) lowest.try_emplace(asked[k], static_cast<int>(q));  // q ascending
  std::vector<std::vector<std::int64_t>> answer(ranks);
  for (std::size_t q = 0, k = 0; q < ranks; ++q)
    for (int i = 0; i < from[q]; ++i, ++k) answer[q].push_back(lowest.at(asked[k]));
  const std::vector<std::int64_t> answers = all_to_all(comm, answer, "node ownership");
  // The answers come back home by home, each home's in the order asked.
  std::vector<std::size_t> next(ranks, 0), start(ranks, 0);
  std::vector<std::size_t> count(ranks, 0);
  for (const std::int64_t id : node_ids) ++count[home_of(id, ranks)];
  for (std::size_t q = 1; q < ranks; ++q) start[q] = start[q - 1] + count[q - 1];
  std::vector<int> owner(node_ids.size());
  for (std::size_t n = 0; n < node_ids.size(); ++n) {
    const std::size_t h = home_of(node_ids[n], ranks);
    owner[n] = static_cast<int>(answers[start[h] + next[h]++]);
  }
  return owner;
}

/// Rows owned by this rank: a sparse matrix (columns by global id), right-hand sides.
struct OwnedRows {
  std::vector<std::int64_t> ids;                  ///< owned node ids, ascending
  std::unordered_map<std::int64_t, std::size_t> row_of;
  std::vector<std::vector<std::pair<std::int64_t, double>>> mass;  ///< M_t's rows, summed
  std::vector<std::vector<std::pair<std::int64_t, double>>> mixed; ///< M_ts's rows, summed
  std::vector<double> rhs;                        ///< components per row: M_ts u_s
};

void add(std::vector<std::pair<std::int64_t, double>>& row, std::int64_t column, double value) {
  for (auto& [c, v] : row)
    if (c == column) {
      v += value;
      return;
    }
  row.emplace_back(column, value);
}

/// The conjugate gradient over the ranks, for one right-hand side (Eigen's algorithm).
class DistributedCg {
 public:
  DistributedCg(const OwnedRows& rows, const std::unordered_map<std::int64_t, int>& ghost_owner, MPI_Comm comm)
      : comm_(comm) {
    const auto ranks = static_cast<std::size_t>(size_of(comm));
    // Columns: owned rows first (their row index), then ghosts (after them).
    std::unordered_map<std::int64_t, std::size_t> column;
    for (std::size_t r = 0; r < rows.ids.size(); ++r) column.emplace(rows.ids[r], r);
    std::vector<std::vector<std::int64_t>> need(ranks);
    for (const auto& row : rows.mass)
      for (const auto& [c, v] : row)
        if (!column.count(c)) {
          column.emplace(c, rows.ids.size() + ghosts_);
          ++ghosts_;
          need[static_cast<std::size_t>(ghost_owner.at(c))].push_back(c);
        }
    // Ghost values arrive rank after rank, each rank's in the order asked.
    ghost_slot_.reserve(ghosts_);
    for (std::size_t q = 0; q < ranks; ++q)
      for (const std::int64_t c : need[q]) ghost_slot_.push_back(column.at(c));
    std::vector<int> from;
    const std::vector<std::int64_t> asked = all_to_all(comm, need, "ghost nodes", &from);
    send_rows_.resize(ranks);
    for (std::size_t q = 0, k = 0; q < ranks; ++q)
      for (int i = 0; i < from[q]; ++i, ++k) send_rows_[q].push_back(rows.row_of.at(asked[k]));
    // The matrix with local column indices; the diagonal for the preconditioner.
    matrix_.resize(rows.ids.size());
    diagonal_.assign(rows.ids.size(), 0.0);
    for (std::size_t r = 0; r < rows.ids.size(); ++r)
      for (const auto& [c, v] : rows.mass[r]) {
        matrix_[r].emplace_back(column.at(c), v);
        if (c == rows.ids[r]) diagonal_[r] += v;
      }
  }

  std::vector<double> solve(const std::vector<double>& b, P1RemapReport& report) const {
    const std::size_t n = b.size();
    // The lumped-mass start, as one process.
    std::vector<double> x(n), ones_full(n + ghosts_, 1.0), lumped(n);
    multiply_local(ones_full, lumped);
    for (std::size_t i = 0; i < n; ++i) x[i] = lumped[i] > 0.0 ? b[i] / lumped[i] : 0.0;
    std::vector<double> r(n), z(n), p(n), ap(n);
    multiply(x, ap);
    for (std::size_t i = 0; i < n; ++i) r[i] = b[i] - ap[i];
    const double rhs_norm2 = dot(b, b);
    report = {};
    if (rhs_norm2 == 0.0) return std::vector<double>(n, 0.0);
    const double threshold = 1e-14 * 1e-14 * rhs_norm2;
    double residual_norm2 = dot(r, r);
    long max_iterations = 0;
    const long local_rows = static_cast<long>(n);
    MPI_Allreduce(&local_rows, &max_iterations, 1, MPI_LONG, MPI_SUM, comm_);
    max_iterations = std::max(1000L, 4 * max_iterations);
    if (residual_norm2 < threshold) {
      report.residual = std::sqrt(residual_norm2 / rhs_norm2);
      return x;
    }
    for (std::size_t i = 0; i < n; ++i) p[i] = precondition(i, r[i]);
    double abs_new = dot(r, p);
    long it = 0;
    while (it < max_iterations) {
      multiply(p, ap);
      const double alpha = abs_new / dot(p, ap);
      for (std::size_t i = 0; i < n; ++i) x[i] += alpha * p[i];
      for (std::size_t i = 0; i < n; ++i) r[i] -= alpha * ap[i];
      residual_norm2 = dot(r, r);
      ++it;
      if (residual_norm2 < threshold) break;
      for (std::size_t i = 0; i < n; ++i) z[i] = precondition(i, r[i]);
      const double abs_old = abs_new;
      abs_new = dot(r, z);
      const double beta = abs_new / abs_old;
      for (std::size_t i = 0; i < n; ++i) p[i] = z[i] + beta * p[i];
    }
    report.iterations = static_cast<int>(it);
    report.residual = std::sqrt(residual_norm2 / rhs_norm2);
    return x;
  }

 private:
  double precondition(std::size_t i, double v) const { return diagonal_[i] != 0.0 ? v / diagonal_[i] : v; }

  double dot(const std::vector<double>& a, const std::vector<double>& b) const {
    double local = 0.0, total = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) local += a[i] * b[i];
    MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, comm_);
    return total;
  }

  void multiply_local(const std::vector<double>& full, std::vector<double>& y) const {
    for (std::size_t r = 0; r < matrix_.size(); ++r) {
      double sum = 0.0;
      for (const auto& [c, v] : matrix_[r]) sum += v * full[c];
      y[r] = sum;
    }
  }

  void multiply(const std::vector<double>& x, std::vector<double>& y) const {
    std::vector<std::vector<double>> send(send_rows_.size());
    for (std::size_t q = 0; q < send_rows_.size(); ++q)
      for (const std::size_t r : send_rows_[q]) send[q].push_back(x[r]);
    const std::vector<double> ghost = all_to_all(comm_, send, "ghost values");
    std::vector<double> full(x.size() + ghosts_);
    std::copy(x.begin(), x.end(), full.begin());
    for (std::size_t g = 0; g < ghost.size(); ++g) full[ghost_slot_[g]] = ghost[g];
    multiply_local(full, y);
  }

  MPI_Comm comm_;
  std::size_t ghosts_ = 0;
  std::vector<std::size_t> ghost_slot_;               ///< where each received ghost value goes
  std::vector<std::vector<std::size_t>> send_rows_;   ///< owned rows each rank needs, in its order
  std::vector<std::vector<std::pair<std::size_t, double>>> matrix_;
  std::vector<double> diagonal_;
};

}  // namespace

std::vector<double> remap_p1(const MeshPart& source, std::span<const double> source_node_values,
                             const MeshPart& target, MPI_Comm comm, int components, const DistributedOptions& options,
                             P1RemapReport* report, DistributedMatrix* mixed_mass) {
  if (components < 1) throw std::invalid_argument("tetia: mpi: remap_p1: components must be at least 1");
  const auto k = static_cast<std::size_t>(components);
  const auto ranks = static_cast<std::size_t>(size_of(comm));
  // Each source cell travels with its four nodes' values (vertex after vertex) and ids.
  std::string error;
  std::vector<double> cell_values;
  std::vector<std::int64_t> cell_nodes;
  try {
    detail::check_part(source, "source", true);
    if (source_node_values.size() != source.node_ids.size() * k)
      throw std::invalid_argument("tetia: mpi: remap_p1: " + std::to_string(source_node_values.size()) +
                                  " source values for " + std::to_string(source.node_ids.size()) + " source nodes of " +
                                  std::to_string(components) + " components");
    for (std::size_t c = 0; c < source.cell_ids.size(); ++c)
      for (std::size_t j = 0; j < 4; ++j) {
        const auto v = static_cast<std::size_t>(source.cells[4 * c + j]);
        cell_nodes.push_back(source.node_ids[v]);
        cell_values.insert(cell_values.end(), source_node_values.begin() + static_cast<std::ptrdiff_t>(v * k),
                           source_node_values.begin() + static_cast<std::ptrdiff_t>((v + 1) * k));
      }
  } catch (const std::exception& e) {
    error = e.what();
  }
  detail::agree_on_errors(comm, error);
  const detail::Exchanged x = detail::exchange_and_intersect(source, cell_values, 4 * components, cell_nodes, 4, target,
                                                             comm, options, true, true);

  // Owners of the target nodes, and what goes to them: M_t rows (row, column, value), M_ts rows
  // (row, column, value) and M_ts u rows (row, k values).
  const std::vector<int> owner = owners_of(target.node_ids, comm);
  std::vector<std::vector<std::int64_t>> mass_ids(ranks), mixed_ids(ranks), rhs_ids(ranks), ghost_owner_ids(ranks);
  std::vector<std::vector<double>> mass_values(ranks), mixed_values(ranks), rhs_values(ranks);
  for (std::size_t c = 0; c < target.cell_ids.size(); ++c) {
    const double w = x.target->volumes[c] / 20.0;
    if (!(w > 0.0)) continue;
    const auto& cell = x.target->cells[c];
    for (std::size_t i = 0; i < 4; ++i) {
      const auto ni = static_cast<std::size_t>(cell[i]);
      const auto q = static_cast<std::size_t>(owner[ni]);
      for (std::size_t j = 0; j < 4; ++j) {
        const auto nj = static_cast<std::size_t>(cell[j]);
        // The column's owner too: the row's owner needs it to fetch the column's values.
        mass_ids[q].insert(mass_ids[q].end(), {target.node_ids[ni], target.node_ids[nj], owner[nj]});
        mass_values[q].push_back(i == j ? 2.0 * w : w);
      }
    }
  }
  for (std::size_t p = 0; p < x.pieces.size(); ++p) {
    const auto& A = x.local_mass[p];
    const auto s = static_cast<std::size_t>(x.pieces[p].source);
    const auto& cell = x.target->cells[static_cast<std::size_t>(x.pieces[p].target)];
    for (std::size_t i = 0; i < 4; ++i) {
      const auto ni = static_cast<std::size_t>(cell[i]);
      const auto q = static_cast<std::size_t>(owner[ni]);
      rhs_ids[q].push_back(target.node_ids[ni]);
      for (std::size_t comp = 0; comp < k; ++comp) {
        double sum = 0.0;
        for (std::size_t j = 0; j < 4; ++j) sum += A[4 * i + j] * x.source_values[s * 4 * k + j * k + comp];
        rhs_values[q].push_back(sum);
      }
      for (std::size_t j = 0; j < 4; ++j) {
        mixed_ids[q].insert(mixed_ids[q].end(), {target.node_ids[ni], x.source_extra[4 * s + j]});
        mixed_values[q].push_back(A[4 * i + j]);
      }
    }
  }
  // Every owned node is a row, even one whose cells are all flat (it gets a unit diagonal).
  OwnedRows rows;
  for (std::size_t n = 0; n < target.node_ids.size(); ++n)
    if (owner[n] == rank_of(comm)) rows.ids.push_back(target.node_ids[n]);
  std::sort(rows.ids.begin(), rows.ids.end());
  rows.ids.erase(std::unique(rows.ids.begin(), rows.ids.end()), rows.ids.end());
  for (std::size_t r = 0; r < rows.ids.size(); ++r) rows.row_of.emplace(rows.ids[r], r);
  rows.mass.resize(rows.ids.size());
  rows.mixed.resize(rows.ids.size());
  rows.rhs.assign(rows.ids.size() * k, 0.0);
  std::unordered_map<std::int64_t, int> ghost_owner;
  {
    const std::vector<std::int64_t> ids = all_to_all(comm, mass_ids, "mass matrix");
    const std::vector<double> values = all_to_all(comm, mass_values, "mass matrix");
    for (std::size_t e = 0; e < values.size(); ++e) {
      add(rows.mass[rows.row_of.at(ids[3 * e])], ids[3 * e + 1], values[e]);
      ghost_owner.emplace(ids[3 * e + 1], static_cast<int>(ids[3 * e + 2]));
    }
  }
  {
    const std::vector<std::int64_t> ids = all_to_all(comm, mixed_ids, "mixed mass matrix");
    const std::vector<double> values = all_to_all(comm, mixed_values, "mixed mass matrix");
    for (std::size_t e = 0; e < values.size(); ++e) add(rows.mixed[rows.row_of.at(ids[2 * e])], ids[2 * e + 1], values[e]);
  }
  {
    const std::vector<std::int64_t> ids = all_to_all(comm, rhs_ids, "right-hand side");
    const std::vector<double> values = all_to_all(comm, rhs_values, "right-hand side");
    for (std::size_t e = 0; e < ids.size(); ++e)
      for (std::size_t comp = 0; comp < k; ++comp) rows.rhs[rows.row_of.at(ids[e]) * k + comp] += values[e * k + comp];
  }
  for (std::size_t r = 0; r < rows.ids.size(); ++r)
    if (rows.mass[r].empty()) rows.mass[r].emplace_back(rows.ids[r], 1.0);

  // The solves, one per component, on the owned rows.
  const DistributedCg cg(rows, ghost_owner, comm);
  std::vector<double> owned(rows.ids.size() * k);
  for (std::size_t comp = 0; comp < k; ++comp) {
    std::vector<double> b(rows.ids.size());
    for (std::size_t r = 0; r < rows.ids.size(); ++r) b[r] = rows.rhs[r * k + comp];
    P1RemapReport solved;
    const std::vector<double> u = cg.solve(b, solved);
    for (std::size_t r = 0; r < rows.ids.size(); ++r) owned[r * k + comp] = u[r];
    if (report != nullptr) *report = solved;
  }

  // Every local target node's values, from its owner.
  std::vector<std::vector<std::int64_t>> ask(ranks);
  for (std::size_t n = 0; n < target.node_ids.size(); ++n) ask[static_cast<std::size_t>(owner[n])].push_back(target.node_ids[n]);
  std::vector<int> from;
  const std::vector<std::int64_t> asked = all_to_all(comm, ask, "target values", &from);
  std::vector<std::vector<double>> answer(ranks);
  for (std::size_t q = 0, e = 0; q < ranks; ++q)
    for (int i = 0; i < from[q]; ++i, ++e) {
      const std::size_t r = rows.row_of.at(asked[e]);
      answer[q].insert(answer[q].end(), owned.begin() + static_cast<std::ptrdiff_t>(r * k),
                       owned.begin() + static_cast<std::ptrdiff_t>((r + 1) * k));
    }
  const std::vector<double> answers = all_to_all(comm, answer, "target values");
  std::vector<std::size_t> start(ranks, 0), next(ranks, 0);
  for (std::size_t q = 1; q < ranks; ++q) start[q] = start[q - 1] + ask[q - 1].size() * k;
  std::vector<double> out(target.node_ids.size() * k);
  for (std::size_t n = 0; n < target.node_ids.size(); ++n) {
    const auto q = static_cast<std::size_t>(owner[n]);
    std::copy_n(answers.begin() + static_cast<std::ptrdiff_t>(start[q] + next[q]), k,
                out.begin() + static_cast<std::ptrdiff_t>(n * k));
    next[q] += k;
  }

  if (mixed_mass != nullptr) {
    mixed_mass->row_ids = rows.ids;
    mixed_mass->row_begin.assign(1, 0);
    mixed_mass->column_ids.clear();
    mixed_mass->values.clear();
    for (auto& row : rows.mixed) {
      std::sort(row.begin(), row.end());
      for (const auto& [c, v] : row) {
        mixed_mass->column_ids.push_back(c);
        mixed_mass->values.push_back(v);
      }
      mixed_mass->row_begin.push_back(static_cast<std::int64_t>(mixed_mass->values.size()));
    }
  }
  return out;
}

}  // namespace tetia::mpi
