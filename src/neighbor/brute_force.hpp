// SPDX-License-Identifier: GPL-3.0-or-later
// Brute-force O(N^2) pair search: the oracle the neighbour-list tests compare against.
#pragma once

#include <utility>
#include <vector>

#include "core/domain.hpp"

namespace gf {

/// All pairs i < j with |x_i - x_j| < r_i + r_j + skin under the minimum image, sorted.
inline std::vector<std::pair<int, int>> brute_force_pairs(const Domain& domain, const Vec3* x,
                                                          const double* r, std::size_t n,
                                                          double skin) {
  std::vector<std::pair<int, int>> out;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const double cut = r[i] + r[j] + skin;
      if (norm2(domain.delta(x[i], x[j])) < cut * cut)
        out.emplace_back(static_cast<int>(i), static_cast<int>(j));
    }
  return out;
}

}  // namespace gf
