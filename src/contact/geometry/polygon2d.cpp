// SPDX-License-Identifier: GPL-3.0-or-later
// Generation helpers for 2D convex polygons (regular and random irregular grains).
#include "contact/geometry/polygon2d.hpp"

#include <algorithm>
#include <array>

#include "core/error.hpp"

namespace gf::contact {

namespace {
constexpr double kPi = 3.141592653589793;
}

ConvexPolygon regular_polygon(int n, double circumradius, double phase) {
  REQUIRE(n >= 3 && n <= kMaxPolygonVertices, "regular_polygon: vertex count {} not in [3, {}]", n,
          kMaxPolygonVertices);
  REQUIRE(circumradius > 0, "regular_polygon: circumradius {} must be > 0", circumradius);
  ConvexPolygon p;
  p.n = n;
  for (int k = 0; k < n; ++k) {
    const double a = phase + 2 * kPi * k / n;
    p.v[k] = {circumradius * std::cos(a), circumradius * std::sin(a)};
  }
  return p;
}

ConvexPolygon random_convex_polygon(std::mt19937_64& rng, int n, double mean_radius,
                                    double elongation) {
  REQUIRE(n >= 3 && n <= kMaxPolygonVertices,
          "random_convex_polygon: vertex count {} not in [3, {}]", n, kMaxPolygonVertices);
  REQUIRE(mean_radius > 0, "random_convex_polygon: mean radius {} must be > 0", mean_radius);
  REQUIRE(elongation >= 1, "random_convex_polygon: elongation {} must be >= 1", elongation);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // Stratified angles: one per sector of 2 pi / n, jittered within the middle 80 % of it, so that
  // no two vertices coincide; points on an ellipse are always in convex position.
  const double offset = 2 * kPi * u(rng);
  const double ax = std::sqrt(elongation), ay = 1.0 / std::sqrt(elongation);
  ConvexPolygon p;
  p.n = n;
  for (int k = 0; k < n; ++k) {
    const double a = offset + 2 * kPi * (k + 0.1 + 0.8 * u(rng)) / n;
    p.v[k] = {ax * std::cos(a), ay * std::sin(a)};
  }
  const PolygonProperties pr = polygon_properties(p);
  const double s = mean_radius / pr.equivalent_radius;
  for (int k = 0; k < n; ++k) p.v[k] = s * (p.v[k] - pr.centroid);
  return p;
}

bool is_convex_ccw(const ConvexPolygon& poly) {
  if (poly.n < 3) return false;
  for (int k = 0; k < poly.n; ++k) {
    const Vec2 a = poly.v[k], b = poly.v[(k + 1) % poly.n], c = poly.v[(k + 2) % poly.n];
    if (!(cross(b - a, c - b) > 0)) return false;
  }
  return polygon_properties(poly).area > 0;
}

}  // namespace gf::contact
