// SPDX-License-Identifier: GPL-3.0-or-later
// Particle shapes: the shape codes stored per particle, and the 2D convex polygon type with the
// table of body-frame polygons that polygon grains refer to.
//
// Per-particle shape data lives in the ParticleStore's field table (see enable_shapes()):
//   shape        ShapeCode
//   half_length  spherocylinder: half the length of the cylindrical part, m (0 otherwise)
//   orientation  unit quaternion body -> world (spherocylinder: body axis e_z; polygon: about z)
//   angular_momentum, inertia_body   spherocylinders: world-frame L and principal moments
//   polygon      index into the store's polygon table (-1 for other shapes)
// The `radius` column is always the bounding radius used by the broad phase: the sphere or disk
// radius, r + half_length for a spherocylinder, the circumradius of a polygon about its centroid.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/host_device.hpp"

namespace gf {

enum class ShapeCode : std::int32_t { Sphere = 0, Spherocylinder = 1, Disk = 2, Polygon = 3 };

struct Vec2 {
  double x = 0, y = 0;
};
GF_HOST_DEVICE constexpr Vec2 operator+(const Vec2& a, const Vec2& b) {
  return {a.x + b.x, a.y + b.y};
}
GF_HOST_DEVICE constexpr Vec2 operator-(const Vec2& a, const Vec2& b) {
  return {a.x - b.x, a.y - b.y};
}
GF_HOST_DEVICE constexpr Vec2 operator-(const Vec2& a) {
  return {-a.x, -a.y};
}
GF_HOST_DEVICE constexpr Vec2 operator*(double s, const Vec2& a) {
  return {s * a.x, s * a.y};
}
GF_HOST_DEVICE constexpr double dot(const Vec2& a, const Vec2& b) {
  return a.x * b.x + a.y * b.y;
}
/// z-component of the 3D cross product.
GF_HOST_DEVICE constexpr double cross(const Vec2& a, const Vec2& b) {
  return a.x * b.y - a.y * b.x;
}
/// a rotated by +90 degrees.
GF_HOST_DEVICE constexpr Vec2 perp(const Vec2& a) {
  return {-a.y, a.x};
}
GF_HOST_DEVICE inline double norm(const Vec2& a) {
  return std::sqrt(dot(a, a));
}

inline constexpr int kMaxPolygonVertices = 16;

/// A convex polygon, vertices counter-clockwise (body frame: about its centroid; or world), m.
struct ConvexPolygon {
  int n = 0;
  Vec2 v[kMaxPolygonVertices];
};

/// One entry of the polygon table: the body-frame polygon (centroid at the origin) and the
/// constants derived from it once.
struct PolygonShape {
  ConvexPolygon body;
  double area = 0;               ///< m^2
  double equivalent_radius = 0;  ///< radius of the equal-area disk, m
  double circumradius = 0;       ///< largest vertex distance from the centroid, m
  double polar_moment = 0;       ///< integral of |x|^2 dA about the centroid, m^4
};

}  // namespace gf
