// SPDX-License-Identifier: GPL-3.0-or-later
// Verlet (neighbour) list with skin: a half list in CSR form, the tangential contact history
// stored next to each entry and carried across rebuilds.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/domain.hpp"
#include "neighbor/cell_list.hpp"

namespace gf {

class VerletList {
 public:
  /// Builds the list of pairs i < j with |x_i - x_j| < r_i + r_j + skin (minimum image), and
  /// carries the contact history of pairs present in the previous list.
  void build(const Domain& domain, const Vec3* x, const double* r, std::size_t n, double skin);

  /// True when some particle moved more than skin/2 since the last build (or the count changed).
  bool needs_rebuild(const Domain& domain, const Vec3* x, std::size_t n) const;

  std::size_t n_particles() const { return offsets_.empty() ? 0 : offsets_.size() - 1; }
  std::size_t n_pairs() const { return neighbors_.size(); }
  std::int64_t n_builds() const { return n_builds_; }
  double skin() const { return skin_; }

  // CSR: the neighbours of i are neighbors()[offsets()[i] .. offsets()[i+1]).
  std::span<const std::int64_t> offsets() const { return offsets_; }
  std::span<const std::int32_t> neighbors() const { return neighbors_; }
  std::span<Vec3> history() { return history_; }
  std::span<const Vec3> history() const { return history_; }
  std::span<const Vec3> reference_positions() const { return x_ref_; }

  /// Replaces the whole state (restart).
  void restore(std::vector<std::int64_t> offsets, std::vector<std::int32_t> neighbors, std::vector<Vec3> history,
               std::vector<Vec3> x_ref, double skin, std::int64_t n_builds);

  std::size_t bytes() const;

 private:
  double skin_ = 0;
  std::int64_t n_builds_ = 0;
  std::vector<std::int64_t> offsets_;
  std::vector<std::int32_t> neighbors_;
  std::vector<Vec3> history_;
  std::vector<Vec3> x_ref_;
  CellList cells_;
  // Scratch for the history transfer (kept to avoid re-allocation).
  std::vector<std::int64_t> old_offsets_;
  std::vector<std::int32_t> old_neighbors_;
  std::vector<Vec3> old_history_;
};

}  // namespace gf
