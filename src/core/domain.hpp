// SPDX-License-Identifier: GPL-3.0-or-later
// The simulation box: bounds in m, periodic flags, minimum-image displacement and wrapping.
#pragma once

#include <array>
#include <cmath>

#include "core/host_device.hpp"
#include "core/vec3.hpp"

namespace gf {

struct Domain {
  Vec3 lo, hi;  ///< box corners, m
  std::array<bool, 3> periodic{false, false, false};

  GF_HOST_DEVICE Vec3 length() const { return hi - lo; }

  /// Displacement a - b under the minimum-image convention in periodic directions.
  GF_HOST_DEVICE Vec3 delta(const Vec3& a, const Vec3& b) const {
    Vec3 d = a - b;
    const Vec3 L = length();
    for (int k = 0; k < 3; ++k) {
      if (periodic[k]) {
        if (d[k] > 0.5 * L[k])
          d[k] -= L[k];
        else if (d[k] < -0.5 * L[k])
          d[k] += L[k];
      }
    }
    return d;
  }

  /// Brings a position back into the box along periodic directions.
  GF_HOST_DEVICE void wrap(Vec3& p) const {
    const Vec3 L = length();
    for (int k = 0; k < 3; ++k) {
      if (!periodic[k]) continue;
      if (p[k] >= hi[k])
        p[k] -= L[k] * std::floor((p[k] - lo[k]) / L[k]);
      else if (p[k] < lo[k])
        p[k] += L[k] * std::ceil((lo[k] - p[k]) / L[k]);
      if (p[k] >= hi[k]) p[k] = lo[k];  // guard rounding at the upper face
    }
  }
};

}  // namespace gf
