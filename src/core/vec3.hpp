// SPDX-License-Identifier: GPL-3.0-or-later
// Small 3-vector of doubles with the arithmetic the physics kernels need.
#pragma once

#include <cmath>

#include "core/host_device.hpp"

namespace gf {

using real = double;

struct Vec3 {
  real x = 0, y = 0, z = 0;

  GF_HOST_DEVICE constexpr real& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  GF_HOST_DEVICE constexpr real operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  GF_HOST_DEVICE constexpr Vec3& operator+=(const Vec3& o) {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
  GF_HOST_DEVICE constexpr Vec3& operator-=(const Vec3& o) {
    x -= o.x;
    y -= o.y;
    z -= o.z;
    return *this;
  }
  GF_HOST_DEVICE constexpr Vec3& operator*=(real s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
  friend constexpr bool operator==(const Vec3&, const Vec3&) = default;
};

GF_HOST_DEVICE constexpr Vec3 operator+(const Vec3& a, const Vec3& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
GF_HOST_DEVICE constexpr Vec3 operator-(const Vec3& a, const Vec3& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
GF_HOST_DEVICE constexpr Vec3 operator-(const Vec3& a) {
  return {-a.x, -a.y, -a.z};
}
GF_HOST_DEVICE constexpr Vec3 operator*(real s, const Vec3& a) {
  return {s * a.x, s * a.y, s * a.z};
}
GF_HOST_DEVICE constexpr Vec3 operator*(const Vec3& a, real s) {
  return {s * a.x, s * a.y, s * a.z};
}
GF_HOST_DEVICE constexpr Vec3 operator/(const Vec3& a, real s) {
  return {a.x / s, a.y / s, a.z / s};
}
GF_HOST_DEVICE constexpr real dot(const Vec3& a, const Vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
GF_HOST_DEVICE constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
GF_HOST_DEVICE constexpr real norm2(const Vec3& a) {
  return dot(a, a);
}
GF_HOST_DEVICE inline real norm(const Vec3& a) {
  return std::sqrt(dot(a, a));
}
GF_HOST_DEVICE inline Vec3 normalized(const Vec3& a) {
  return a / norm(a);
}

}  // namespace gf
