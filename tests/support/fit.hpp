// SPDX-License-Identifier: GPL-3.0-or-later
// Least-squares fits for the validation tests.
#pragma once

#include <cstddef>
#include <vector>

namespace gf::test {

/// Slope of the least-squares line through the points (x[i], y[i]).
inline double least_squares_slope(const std::vector<double>& x, const std::vector<double>& y) {
  const auto n = static_cast<double>(x.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace gf::test
