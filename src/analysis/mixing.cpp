// SPDX-License-Identifier: GPL-3.0-or-later
#include "analysis/mixing.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace gf::analysis {

LaceyIndex lacey_index(const Vec3* x, const std::int32_t* kind, std::size_t n, const Vec3& lo,
                       const Vec3& hi, double cell, int dimension, int min_grains) {
  LaceyIndex out;
  // The cell of each counted grain as one key, with its kind; sorted, a cell's grains are a run.
  std::int64_t cells[3] = {1, 1, 1};
  for (int k = 0; k < dimension; ++k)
    cells[k] =
        std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil((hi[k] - lo[k]) / cell)));
  std::vector<std::pair<std::int64_t, std::int32_t>> keyed;
  keyed.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (kind[i] != 0 && kind[i] != 1) continue;
    std::int64_t key = 0;
    for (int k = dimension - 1; k >= 0; --k) {
      const auto c = std::clamp<std::int64_t>(
          static_cast<std::int64_t>(std::floor((x[i][k] - lo[k]) / cell)), 0, cells[k] - 1);
      key = key * cells[k] + c;
    }
    keyed.emplace_back(key, kind[i]);
  }
  std::sort(keyed.begin(), keyed.end());
  // Per cell counted: grains and grains of kind A.
  std::vector<std::pair<double, double>> counts;
  for (std::size_t s = 0; s < keyed.size();) {
    std::size_t e = s;
    double a = 0;
    while (e < keyed.size() && keyed[e].first == keyed[s].first) a += keyed[e++].second == 0;
    if (static_cast<int>(e - s) >= min_grains) counts.emplace_back(static_cast<double>(e - s), a);
    s = e;
  }
  double total = 0, total_a = 0;
  for (const auto& [m, a] : counts) {
    total += m;
    total_a += a;
  }
  out.cells = counts.size();
  if (counts.empty() || total_a == 0 || total_a == total) return out;
  out.fraction = total_a / total;
  out.per_cell = total / static_cast<double>(counts.size());
  double s2 = 0;
  for (const auto& [m, a] : counts) {
    const double d = a / m - out.fraction;
    s2 += m * d * d;
  }
  out.variance = s2 / total;
  out.segregated = out.fraction * (1 - out.fraction);
  out.random = out.segregated / out.per_cell;
  if (out.segregated > out.random)
    out.index = (out.segregated - out.variance) / (out.segregated - out.random);
  return out;
}

}  // namespace gf::analysis
