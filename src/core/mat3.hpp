// SPDX-License-Identifier: GPL-3.0-or-later
// Small 3x3 matrix of doubles (inertia, rotations, velocity gradients) for the physics kernels.
#pragma once

#include "core/host_device.hpp"
#include "core/vec3.hpp"

namespace gf {

/// Row-major 3x3 matrix; a[r][c].
struct Mat3 {
  real a[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};

  GF_HOST_DEVICE static constexpr Mat3 identity() { return diagonal({1, 1, 1}); }
  /// diag(d.x, d.y, d.z), e.g. a principal-axis inertia tensor (kg m^2).
  GF_HOST_DEVICE static constexpr Mat3 diagonal(const Vec3& d) {
    Mat3 m;
    m.a[0][0] = d.x;
    m.a[1][1] = d.y;
    m.a[2][2] = d.z;
    return m;
  }
  /// The matrix whose columns are c0, c1, c2.
  GF_HOST_DEVICE static constexpr Mat3 from_columns(const Vec3& c0, const Vec3& c1,
                                                    const Vec3& c2) {
    Mat3 m;
    for (int r = 0; r < 3; ++r) {
      m.a[r][0] = c0[r];
      m.a[r][1] = c1[r];
      m.a[r][2] = c2[r];
    }
    return m;
  }
  GF_HOST_DEVICE constexpr Vec3 row(int r) const { return {a[r][0], a[r][1], a[r][2]}; }
  GF_HOST_DEVICE constexpr Vec3 col(int c) const { return {a[0][c], a[1][c], a[2][c]}; }
};

GF_HOST_DEVICE constexpr Vec3 operator*(const Mat3& m, const Vec3& v) {
  return {dot(m.row(0), v), dot(m.row(1), v), dot(m.row(2), v)};
}
GF_HOST_DEVICE constexpr Mat3 operator*(const Mat3& p, const Mat3& q) {
  Mat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      m.a[r][c] = p.a[r][0] * q.a[0][c] + p.a[r][1] * q.a[1][c] + p.a[r][2] * q.a[2][c];
  return m;
}
GF_HOST_DEVICE constexpr Mat3 operator+(const Mat3& p, const Mat3& q) {
  Mat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m.a[r][c] = p.a[r][c] + q.a[r][c];
  return m;
}
GF_HOST_DEVICE constexpr Mat3 operator*(real s, const Mat3& p) {
  Mat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m.a[r][c] = s * p.a[r][c];
  return m;
}
GF_HOST_DEVICE constexpr Mat3 transpose(const Mat3& p) {
  Mat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m.a[r][c] = p.a[c][r];
  return m;
}
GF_HOST_DEVICE constexpr real determinant(const Mat3& m) {
  return dot(m.row(0), cross(m.row(1), m.row(2)));
}
/// Outer product u v^T.
GF_HOST_DEVICE constexpr Mat3 outer(const Vec3& u, const Vec3& v) {
  return Mat3::from_columns(v.x * u, v.y * u, v.z * u);
}
/// Inverse of a symmetric matrix (e.g. an inertia tensor) by cofactors; the caller guarantees
/// that it is non-singular (det != 0).
GF_HOST_DEVICE constexpr Mat3 inverse_symmetric(const Mat3& m) {
  const real a = m.a[0][0], b = m.a[0][1], c = m.a[0][2], d = m.a[1][1], e = m.a[1][2],
             f = m.a[2][2];
  const real c00 = d * f - e * e, c01 = c * e - b * f, c02 = b * e - c * d;
  const real c11 = a * f - c * c, c12 = b * c - a * e, c22 = a * d - b * b;
  const real inv_det = 1.0 / (a * c00 + b * c01 + c * c02);
  Mat3 r;
  r.a[0][0] = c00 * inv_det;
  r.a[0][1] = r.a[1][0] = c01 * inv_det;
  r.a[0][2] = r.a[2][0] = c02 * inv_det;
  r.a[1][1] = c11 * inv_det;
  r.a[1][2] = r.a[2][1] = c12 * inv_det;
  r.a[2][2] = c22 * inv_det;
  return r;
}

/// Rotation rate curl(u) / 2 (rad/s) of a velocity gradient g, g.a[i][j] = d u_i / d x_j (1/s).
GF_HOST_DEVICE constexpr Vec3 rotation_rate(const Mat3& g) {
  return {0.5 * (g.a[2][1] - g.a[1][2]), 0.5 * (g.a[0][2] - g.a[2][0]),
          0.5 * (g.a[1][0] - g.a[0][1])};
}
/// Strain rate (g + g^T) / 2 (1/s) of a velocity gradient g.
GF_HOST_DEVICE constexpr Mat3 strain_rate(const Mat3& g) {
  return 0.5 * (g + transpose(g));
}

}  // namespace gf
