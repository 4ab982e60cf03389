// SPDX-License-Identifier: GPL-3.0-or-later
// Prescribed rigid motion of a wall or of a fixed particle group: constant translation plus
// rotation about an axis.
#pragma once

#include <cmath>

#include "core/host_device.hpp"
#include "core/quaternion.hpp"
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
    const double a = rate * t;
    return rotate_by(d, std::cos(a), std::sin(a));
  }
  /// Rodrigues rotation about axis by the angle of cosine c and sine s (the device back end
  /// takes them from the host: the same bits as rotate()).
  GF_HOST_DEVICE Vec3 rotate_by(const Vec3& d, double c, double s) const {
    return c * d + s * cross(axis, d) + (1 - c) * dot(axis, d) * axis;
  }
  GF_HOST_DEVICE Vec3 point_at(const Vec3& p0, double t) const {
    return center_at(t) + rotate(p0 - center, t);
  }
  /// point_at(p0, t), the image at time t of the material point at p0 at t = 0, evaluated so
  /// that a translation alone carries p0 by exactly V max(0, t - start) (without the round-off
  /// of (p0 - center) + center): the grains of fixed groups (docs/models/fixed_particles.md).
  GF_HOST_DEVICE Vec3 carry(const Vec3& p0, double t) const {
    if (rate == 0) return carry_by(p0, t, 1, 0);
    const double a = rate * t;
    return carry_by(p0, t, std::cos(a), std::sin(a));
  }
  /// carry() with the rotation angle's cosine c and sine s given (the device back end takes
  /// them from the host: the same bits as carry()).
  GF_HOST_DEVICE Vec3 carry_by(const Vec3& p0, double t, double c, double s) const {
    if (rate == 0) return p0 + (t > start ? t - start : 0.0) * velocity;
    return center_at(t) + rotate_by(p0 - center, c, s);
  }
  /// Orientation (body -> world) at time t of a body whose orientation is q0 at t = 0: q0 turned
  /// by the angle rate * t about axis, as rotate() turns directions.
  GF_HOST_DEVICE Quat turn(const Quat& q0, double t) const {
    if (rate == 0) return q0;
    return quat_from_axis_angle(axis, rate * t) * q0;
  }
  /// Velocity of the wall material at point p (world) at time t.
  GF_HOST_DEVICE Vec3 velocity_at(const Vec3& p, double t) const {
    return translation_velocity(t) + cross(omega(), p - center_at(t));
  }
};

}  // namespace gf
