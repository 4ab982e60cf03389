// SPDX-License-Identifier: GPL-3.0-or-later
// Prescribed rigid motion of a wall: constant translation plus rotation about an axis.
#pragma once

#include <cmath>

#include "core/host_device.hpp"
#include "core/vec3.hpp"

namespace gf {

/// x(t) = c0 + V max(0, t - start) + R(Omega t)(x0 - c0), Omega = rate * axis.
struct RigidMotion {
  Vec3 velocity;       ///< m/s
  Vec3 axis{0, 0, 1};  ///< unit
  Vec3 center;         ///< point on the rotation axis at t = 0, m
  double rate = 0;     ///< rad/s
  double start = 0;    ///< s: the translation begins at this time

  GF_HOST_DEVICE Vec3 omega() const { return rate * axis; }
  GF_HOST_DEVICE Vec3 center_at(double t) const {
    return center + (t > start ? t - start : 0.0) * velocity;
  }
  GF_HOST_DEVICE Vec3 translation_velocity(double t) const {
    return t >= start ? velocity : Vec3{};
  }

  /// Rodrigues rotation of a direction by angle rate * t about axis.
  GF_HOST_DEVICE Vec3 rotate(const Vec3& d, double t) const {
    if (rate == 0) return d;
    const double a = rate * t, c = std::cos(a), s = std::sin(a);
    return c * d + s * cross(axis, d) + (1 - c) * dot(axis, d) * axis;
  }
  GF_HOST_DEVICE Vec3 point_at(const Vec3& p0, double t) const {
    return center_at(t) + rotate(p0 - center, t);
  }
  /// Velocity of the wall material at point p (world) at time t.
  GF_HOST_DEVICE Vec3 velocity_at(const Vec3& p, double t) const {
    return translation_velocity(t) + cross(omega(), p - center_at(t));
  }
};

}  // namespace gf
