// SPDX-License-Identifier: GPL-3.0-or-later
// Unit quaternions for the orientation of rigid bodies (body frame -> world frame).
//
// q = (w, x, y, z) = (cos(phi/2), sin(phi/2) e) rotates by the angle phi about the unit axis e;
// a body-frame vector b has the world image R(q) b = q (0, b) q^*. Kinematics:
// dq/dt = 1/2 q (0, omega_body) = 1/2 (0, omega_world) q  (e.g. Evans, Mol. Phys. 34 (1977) 317).
#pragma once

#include <cmath>

#include "core/host_device.hpp"
#include "core/mat3.hpp"
#include "core/vec3.hpp"

namespace gf {

struct Quat {
  real w = 1, x = 0, y = 0, z = 0;
  GF_HOST_DEVICE constexpr Vec3 vec() const { return {x, y, z}; }
};

GF_HOST_DEVICE constexpr Quat operator*(const Quat& a, const Quat& b) {
  return {
      a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
      a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
GF_HOST_DEVICE constexpr Quat operator*(real s, const Quat& q) {
  return {s * q.w, s * q.x, s * q.y, s * q.z};
}
GF_HOST_DEVICE constexpr Quat operator+(const Quat& a, const Quat& b) {
  return {a.w + b.w, a.x + b.x, a.y + b.y, a.z + b.z};
}
GF_HOST_DEVICE constexpr Quat conjugate(const Quat& q) {
  return {q.w, -q.x, -q.y, -q.z};
}
GF_HOST_DEVICE constexpr real norm2(const Quat& q) {
  return q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
}
GF_HOST_DEVICE inline Quat normalized(const Quat& q) {
  return (1.0 / std::sqrt(norm2(q))) * q;
}

/// c = cos(x), s = sin(x) (x in rad). The rotations of a time step are small angles, where
/// the Taylor polynomials through x^7 (sin) and x^8 (cos) are exact to round-off: for
/// |x| < 0.02 the first omitted terms, x^9/9! and x^10/10!, are below 1e-19 of the result (half
/// an ulp is 1.1e-16 of it), and the Horner evaluation adds a few ulps at most, as the library's
/// does. Ten times cheaper than a library call; larger angles take the library's.
GF_HOST_DEVICE inline void cos_sin(real x, real& c, real& s) {
  if (std::abs(x) < 0.02) {
    // (Horner form in x^2 with the reciprocal factorials as constants: multiplications only)
    const real x2 = x * x;
    s = x + x * x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040)));
    c = 1 + x2 * (-0.5 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320))));
  } else {
    c = std::cos(x);
    s = std::sin(x);
  }
}

/// Rotation by `angle` (rad) about the unit vector `axis`.
GF_HOST_DEVICE inline Quat quat_from_axis_angle(const Vec3& axis, real angle) {
  const real s = std::sin(0.5 * angle);
  return {std::cos(0.5 * angle), s * axis.x, s * axis.y, s * axis.z};
}

/// World image R(q) b of a body-frame vector b (q a unit quaternion).
GF_HOST_DEVICE constexpr Vec3 rotate(const Quat& q, const Vec3& b) {
  // R b = b + 2 w (u x b) + 2 u x (u x b), u = vector part.
  const Vec3 u = q.vec();
  const Vec3 t = 2.0 * cross(u, b);
  return b + q.w * t + cross(u, t);
}
/// R(q) e_z, the world image of the body's z axis (the third column of R(q)): rotate(q, {0, 0, 1})
/// in a third of the operations (a multiplication by zero is not dropped by the compiler).
GF_HOST_DEVICE constexpr Vec3 rotate_z(const Quat& q) {
  return {2 * (q.x * q.z + q.w * q.y), 2 * (q.y * q.z - q.w * q.x),
          1 - 2 * (q.x * q.x + q.y * q.y)};
}
/// Body-frame image R(q)^T v of a world vector v.
GF_HOST_DEVICE constexpr Vec3 rotate_inverse(const Quat& q, const Vec3& v) {
  return rotate(conjugate(q), v);
}

/// Rotation matrix R(q) (body -> world) of a unit quaternion.
GF_HOST_DEVICE constexpr Mat3 to_matrix(const Quat& q) {
  return Mat3::from_columns(rotate(q, {1, 0, 0}), rotate(q, {0, 1, 0}), rotate(q, {0, 0, 1}));
}

/// dq/dt = 1/2 q (0, omega_body), omega_body in rad/s (body frame).
GF_HOST_DEVICE constexpr Quat quat_derivative(const Quat& q, const Vec3& omega_body) {
  return 0.5 * (q * Quat{0, omega_body.x, omega_body.y, omega_body.z});
}

/// q turned by `angle` (rad) about the world z axis (2D grains), renormalised. A unit q turned by
/// a unit rotation has |q'|^2 = 1 + e with e of a few ulps; one Newton step for 1/|q'|,
/// q' (3 - |q'|^2) / 2, leaves an error of O(e^2), below rounding, without the square root and
/// division of a full normalisation (which took 15 % of a polygon run's time). Far from unit
/// (not the case for the turns of a run), the full one.
GF_HOST_DEVICE inline Quat turn_about_z(const Quat& q, real angle) {
  real c = 1, s = 0;
  cos_sin(0.5 * angle, c, s);
  const Quat t = Quat{c, 0, 0, s} * q;
  const real n2 = norm2(t);
  if (!(std::abs(n2 - 1) < 1e-6)) return normalized(t);
  const real f = 0.5 * (3 - n2);
  return Quat{f * t.w, f * t.x, f * t.y, f * t.z};
}

}  // namespace gf
