// SPDX-License-Identifier: GPL-3.0-or-later
// The simulation box: bounds in m, periodic flags, minimum-image displacement and wrapping, and
// Lees-Edwards (sliding) periodic images for homogeneous simple shear.
//
// Lees-Edwards (Lees & Edwards 1972): along the gradient axis g the box is periodic, but its
// images slide along the flow axis f: the image one box above (x_g + L_g) is displaced by
// `shear_offset` along f and moves with `shear_velocity` = gamma_dot L_g relative to the box.
// The mean flow is u_f = gamma_dot x_g. A particle leaving through the top re-enters at the bottom
// shifted by -offset and with its flow velocity reduced by gamma_dot L_g (wrap); the
// displacement between two particles uses the nearest image, shifted (delta), and their relative
// velocity the image's velocity (image_velocity). Velocities in the store are lab-frame.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "core/host_device.hpp"
#include "core/vec3.hpp"

namespace gf {

struct Domain {
  Vec3 lo, hi;  ///< box corners, m
  std::array<bool, 3> periodic{false, false, false};
  int shear_gradient = -1;    ///< Lees-Edwards gradient axis (0..2), -1 = none
  int shear_flow = 0;         ///< Lees-Edwards flow axis
  double shear_offset = 0;    ///< m, flow-axis shift of the upper image, in [-L_f/2, L_f/2)
  double shear_velocity = 0;  ///< m/s, flow velocity of the upper image, gamma_dot L_g

  GF_HOST_DEVICE Vec3 length() const { return hi - lo; }
  GF_HOST_DEVICE bool sheared() const { return shear_gradient >= 0; }
  GF_HOST_DEVICE bool any_periodic() const { return periodic[0] || periodic[1] || periodic[2]; }

  /// Which image of b along the gradient axis is nearest to a: +1 the upper one (b + L_g), -1
  /// the lower one, 0 b itself. Always 0 without Lees-Edwards.
  GF_HOST_DEVICE int shear_image(const Vec3& a, const Vec3& b) const {
    if (shear_gradient < 0) return 0;
    const double d = a[shear_gradient] - b[shear_gradient];
    const double half = 0.5 * (hi[shear_gradient] - lo[shear_gradient]);
    return d > half ? 1 : (d < -half ? -1 : 0);
  }

  /// Velocity of the image of b nearest to a relative to b itself (zero without Lees-Edwards):
  /// the relative velocity of a and b's image is v_a - v_b - image_velocity(a, b).
  GF_HOST_DEVICE Vec3 image_velocity(const Vec3& a, const Vec3& b) const {
    Vec3 u{};
    if (shear_gradient >= 0) u[shear_flow] = shear_image(a, b) * shear_velocity;
    return u;
  }

  /// Minimum image of a displacement along the periodic directions (no Lees-Edwards shift).
  GF_HOST_DEVICE Vec3 min_image(Vec3 d) const {
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

  /// Displacement a - b to the nearest image of b (minimum image in periodic directions, the
  /// image shifted by the Lees-Edwards offset when it lies across the gradient boundary).
  GF_HOST_DEVICE Vec3 delta(const Vec3& a, const Vec3& b) const {
    Vec3 d = a - b;
    if (shear_gradient >= 0) {
      const int s = shear_image(a, b);
      if (s != 0) {
        // Per component, not d[shear_gradient] (a runtime index puts d in memory, a store-load
        // stall in the hottest loops); x - (0 + y) is x - y exactly, x - 0 is x.
        const double dg = s * (hi[shear_gradient] - lo[shear_gradient]), df = s * shear_offset;
        d.x -= (shear_gradient == 0 ? dg : 0.0) + (shear_flow == 0 ? df : 0.0);
        d.y -= (shear_gradient == 1 ? dg : 0.0) + (shear_flow == 1 ? df : 0.0);
        d.z -= (shear_gradient == 2 ? dg : 0.0) + (shear_flow == 2 ? df : 0.0);
      }
    }
    return min_image(d);
  }

  /// Brings a position back into the box along periodic directions. With Lees-Edwards, a
  /// crossing of the gradient boundary also shifts the position (and the velocity, when given)
  /// along the flow axis.
  GF_HOST_DEVICE void wrap(Vec3& p, Vec3* v = nullptr) const {
    const Vec3 L = length();
    if (shear_gradient >= 0 &&
        (p[shear_gradient] < lo[shear_gradient] || p[shear_gradient] >= hi[shear_gradient])) {
      const int g = shear_gradient;
      const double n = std::floor((p[g] - lo[g]) / L[g]);  // images crossed upwards
      if (n != 0) {
        p[g] -= n * L[g];
        if (p[g] >= hi[g]) p[g] = lo[g];
        p[shear_flow] -= n * shear_offset;
        if (v) (*v)[shear_flow] -= n * shear_velocity;
      }
    }
    for (int k = 0; k < 3; ++k) {
      if (!periodic[k]) continue;
      if (p[k] >= hi[k])
        p[k] -= L[k] * std::floor((p[k] - lo[k]) / L[k]);
      else if (p[k] < lo[k])
        p[k] += L[k] * std::ceil((lo[k] - p[k]) / L[k]);
      if (p[k] >= hi[k]) p[k] = lo[k];  // guard rounding at the upper face
    }
  }

  /// Sets the Lees-Edwards offset for time t: gamma_dot L_g t, reduced to [-L_f/2, L_f/2) (the
  /// images repeat every L_f; in that range one minimum-image step along f after the shift
  /// finds the nearest image in delta()).
  void set_shear_time(double t) {
    if (shear_gradient < 0) return;
    const double lf = hi[shear_flow] - lo[shear_flow];
    shear_offset = shear_velocity * t;
    shear_offset -= lf * std::floor(shear_offset / lf + 0.5);
  }

  /// Smallest flow-axis distance between two offsets, modulo L_f (images repeat every L_f).
  double offset_change(double from) const {
    if (shear_gradient < 0) return 0;
    const double lf = hi[shear_flow] - lo[shear_flow];
    double d = std::fmod(std::fabs(shear_offset - from), lf);
    return std::min(d, lf - d);
  }
};

}  // namespace gf
