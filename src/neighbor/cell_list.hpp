// SPDX-License-Identifier: GPL-3.0-or-later
// Uniform cell grid over the domain, for finding all pairs closer than a cutoff in O(N).
#pragma once

#include <cstdint>
#include <array>
#include <vector>

#include "core/domain.hpp"

namespace gf {

class CellList {
 public:
  /// Bins n positions into cells of edge >= cutoff. Particles outside the domain in
  /// non-periodic directions go to the border cells (correct, just slower).
  void build(const Domain& domain, const Vec3* x, std::size_t n, double cutoff);

  int n_cells() const { return nc_[0] * nc_[1] * nc_[2]; }
  /// Particles of cell c are order()[begin(c) .. begin(c+1)).
  std::int64_t begin(int c) const { return start_[c]; }
  const std::vector<std::int32_t>& order() const { return order_; }
  int cell_of(const Vec3& p) const;
  /// Distinct neighbour cells of cell c (itself included), periodic images folded.
  int stencil(int c, int* out27) const;
  const std::array<int, 3>& dims() const { return nc_; }

 private:
  Domain domain_;
  std::array<int, 3> nc_{1, 1, 1};
  Vec3 inv_size_;
  std::vector<std::int64_t> start_;
  std::vector<std::int32_t> order_;
  std::vector<std::int32_t> cell_;
};

}  // namespace gf
