// SPDX-License-Identifier: GPL-3.0-or-later
// 2D convex-polygon overlap against an independent exact construction and a fine raster.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "contact/geometry/polygon2d.hpp"

using namespace gf::contact;

namespace {

// ---- Independent oracle -----------------------------------------------------------------
// The overlap of two convex polygons is the convex hull of (vertices of i inside j) + (vertices
// of j inside i) + (edge-edge intersection points); the boundary intersection points are the
// edge-edge intersections. No clipping involved.
bool inside_convex(const ConvexPolygon& p, const Vec2& x) {
  for (int k = 0; k < p.n; ++k)
    if (cross(p.v[(k + 1) % p.n] - p.v[k], x - p.v[k]) < 0) return false;
  return true;
}

std::vector<Vec2> edge_intersections(const ConvexPolygon& a, const ConvexPolygon& b) {
  std::vector<Vec2> out;
  for (int i = 0; i < a.n; ++i) {
    const Vec2 p = a.v[i], r = a.v[(i + 1) % a.n] - p;
    for (int j = 0; j < b.n; ++j) {
      const Vec2 q = b.v[j], s = b.v[(j + 1) % b.n] - q;
      const double den = cross(r, s);
      if (den == 0) continue;
      const double t = cross(q - p, s) / den, u = cross(q - p, r) / den;
      if (t >= 0 && t <= 1 && u >= 0 && u <= 1) out.push_back(p + t * r);
    }
  }
  return out;
}

std::vector<Vec2> convex_hull(std::vector<Vec2> pts) {  // Andrew's monotone chain, CCW
  std::sort(pts.begin(), pts.end(),
            [](const Vec2& a, const Vec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  if (pts.size() < 3) return pts;
  std::vector<Vec2> h(2 * pts.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(h[k - 1] - h[k - 2], pts[i] - h[k - 2]) <= 0) --k;
    h[k++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 1] - h[k - 2], pts[i - 1] - h[k - 2]) <= 0) --k;
    h[k++] = pts[i - 1];
  }
  h.resize(k - 1);
  return h;
}

struct Oracle {
  double area = 0;
  Vec2 centroid;
  std::vector<Vec2> crossings;
};

Oracle oracle_overlap(const ConvexPolygon& a, const ConvexPolygon& b) {
  std::vector<Vec2> pts = edge_intersections(a, b);
  Oracle o;
  o.crossings = pts;
  for (int k = 0; k < a.n; ++k)
    if (inside_convex(b, a.v[k])) pts.push_back(a.v[k]);
  for (int k = 0; k < b.n; ++k)
    if (inside_convex(a, b.v[k])) pts.push_back(b.v[k]);
  const std::vector<Vec2> hull = convex_hull(pts);
  if (hull.size() < 3) return o;
  const PolygonProperties pr = polygon_properties(hull.data(), static_cast<int>(hull.size()));
  o.area = pr.area;
  o.centroid = pr.centroid;
  return o;
}

ConvexPolygon random_grain(std::mt19937_64& rng, Vec2 at) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int n = 3 + static_cast<int>(u(rng) * 10);
  const ConvexPolygon body = random_convex_polygon(rng, n, 0.5 + 0.5 * u(rng), 1.0 + 2.0 * u(rng));
  return polygon_to_world(body, at, 6.283185307179586 * u(rng));
}

}  // namespace

TEST(PolygonGeometry, PropertiesAndGenerators) {
  // Unit square: area 1, centroid (0.5, 0.5), J = 1/6.
  ConvexPolygon sq;
  sq.n = 4;
  sq.v[0] = {0, 0};
  sq.v[1] = {1, 0};
  sq.v[2] = {1, 1};
  sq.v[3] = {0, 1};
  PolygonProperties p = polygon_properties(sq);
  EXPECT_NEAR(p.area, 1.0, 1e-15);
  EXPECT_NEAR(p.centroid.x, 0.5, 1e-15);
  EXPECT_NEAR(p.centroid.y, 0.5, 1e-15);
  EXPECT_NEAR(p.polar_moment, 1.0 / 6.0, 1e-15);
  // Regular n-gon: area n/2 R^2 sin(2 pi/n), J = A R^2 (2 + cos(2 pi / n)) / 6.
  const ConvexPolygon hex = regular_polygon(6, 2.0, 0.3);
  p = polygon_properties(hex);
  const double a6 = 3.0 * 4.0 * std::sin(2 * 3.141592653589793 / 6);
  EXPECT_NEAR(p.area, a6, 1e-12);
  EXPECT_NEAR(p.polar_moment, a6 * 4.0 * (2 + std::cos(2 * 3.141592653589793 / 6)) / 6.0, 1e-12);
  EXPECT_TRUE(is_convex_ccw(hex));
  // Random grains: convex, CCW, centred, of the requested equal-area radius; deterministic.
  std::mt19937_64 rng(3), rng2(3);
  for (int t = 0; t < 200; ++t) {
    const int n = 3 + t % 14;
    const ConvexPolygon g = random_convex_polygon(rng, n, 0.7, 1.0 + 0.02 * t);
    EXPECT_TRUE(is_convex_ccw(g));
    const PolygonProperties pg = polygon_properties(g);
    EXPECT_NEAR(pg.equivalent_radius, 0.7, 1e-12);
    EXPECT_NEAR(std::hypot(pg.centroid.x, pg.centroid.y), 0.0, 1e-12);
    const ConvexPolygon g2 = random_convex_polygon(rng2, n, 0.7, 1.0 + 0.02 * t);
    EXPECT_EQ(g.v[1].x, g2.v[1].x);
  }
}

// Random pairs of grains (3 to 12 vertices, aspect ratio 1 to 3, random placement and angle):
// area, centroid and the two boundary intersection points agree with the independent oracle to
// round-off (1e-12 relative: both are exact constructions), and the normal is perpendicular to
// p2 - p1 and points from j to i (the part of the overlap on i's boundary lies behind it).
TEST(PolygonOverlap, RandomPairsAgainstExactOracle) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int n_overlaps = 0;
  double max_area = 0, max_c = 0, max_p = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const ConvexPolygon pi = random_grain(rng, {0, 0});
    const ConvexPolygon pj = random_grain(rng, {2.5 * (u(rng) - 0.5), 2.5 * (u(rng) - 0.5)});
    const Oracle o = oracle_overlap(pi, pj);
    PolygonOverlap k;
    const bool hit = polygon_overlap(pi, pj, k);
    if (o.area < 1e-10) {
      EXPECT_LT(hit ? k.area : 0.0, 1e-10);
      continue;
    }
    ASSERT_TRUE(hit) << "trial " << trial;
    ++n_overlaps;
    EXPECT_NEAR(k.area, o.area, 1e-12 * (1 + o.area)) << "trial " << trial;
    EXPECT_NEAR(k.centroid.x, o.centroid.x, 1e-10) << "trial " << trial;
    EXPECT_NEAR(k.centroid.y, o.centroid.y, 1e-10) << "trial " << trial;
    max_area = std::max(max_area, std::abs(k.area - o.area));
    max_c = std::max(max_c, norm(k.centroid - o.centroid));
    EXPECT_NEAR(norm(k.normal), 1.0, 1e-12);
    if (o.crossings.size() == 2 && norm(o.crossings[0] - o.crossings[1]) > 1e-6) {
      ASSERT_TRUE(k.chord);
      // The same two points (in either order).
      const double d1 = std::max(norm(k.p1 - o.crossings[0]), norm(k.p2 - o.crossings[1]));
      const double d2 = std::max(norm(k.p1 - o.crossings[1]), norm(k.p2 - o.crossings[0]));
      EXPECT_LT(std::min(d1, d2), 1e-10) << "trial " << trial;
      max_p = std::max(max_p, std::min(d1, d2));
      EXPECT_NEAR(dot(k.normal, k.p2 - k.p1), 0.0, 1e-12);
      // Orientation: vertices of i inside j lie on the far side of the chord (against n).
      for (int v = 0; v < pi.n; ++v)
        if (inside_convex(pj, pi.v[v])) {
          EXPECT_LE(dot(pi.v[v] - k.p1, k.normal), 1e-12) << "trial " << trial;
        }
      for (int v = 0; v < pj.n; ++v)
        if (inside_convex(pi, pj.v[v])) {
          EXPECT_GE(dot(pj.v[v] - k.p1, k.normal), -1e-12) << "trial " << trial;
        }
    }
  }
  EXPECT_GT(n_overlaps, 1000);
  std::printf(
      "[ measured ] polygon overlaps: %d, max |area - oracle| %.2e, max |centroid - oracle| %.2e, "
      "max |p1,p2 - oracle| %.2e\n",
      n_overlaps, max_area, max_c, max_p);
}

// Fine-grid rasterisation (1000 x 1000 cell centres over the bounding box of the overlap) as a
// second, cruder check: area within 2 cells' worth of boundary error (relative ~1e-3), centroid
// within 1e-3 of the size.
TEST(PolygonOverlap, RandomPairsAgainstRaster) {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 40 && checked < 8; ++trial) {
    const ConvexPolygon pi = random_grain(rng, {0, 0});
    const ConvexPolygon pj = random_grain(rng, {1.5 * (u(rng) - 0.5), 1.5 * (u(rng) - 0.5)});
    PolygonOverlap k;
    if (!polygon_overlap(pi, pj, k) || k.area < 0.05) continue;
    ++checked;
    double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
    for (int v = 0; v < pi.n; ++v) {
      x0 = std::min(x0, pi.v[v].x), x1 = std::max(x1, pi.v[v].x);
      y0 = std::min(y0, pi.v[v].y), y1 = std::max(y1, pi.v[v].y);
    }
    const int m = 1000;
    const double hx = (x1 - x0) / m, hy = (y1 - y0) / m;
    double area = 0, cx = 0, cy = 0;
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b) {
        const Vec2 x{x0 + (a + 0.5) * hx, y0 + (b + 0.5) * hy};
        if (inside_convex(pi, x) && inside_convex(pj, x)) {
          area += hx * hy;
          cx += x.x * hx * hy;
          cy += x.y * hx * hy;
        }
      }
    EXPECT_NEAR(area, k.area, 2e-3 * k.area + 4 * (hx + hy) * std::sqrt(k.area) * 0.5);
    EXPECT_NEAR(cx / area, k.centroid.x, 1e-3 * (x1 - x0));
    EXPECT_NEAR(cy / area, k.centroid.y, 1e-3 * (y1 - y0));
  }
  EXPECT_EQ(checked, 8);
}

TEST(PolygonOverlap, VertexContactsAndContainment) {
  // A square i whose corner pokes depth h into the flat top edge of a big square j below it:
  // the chord lies on j's edge, so n = +y (from j up to i) exactly, and the overlap is the
  // triangle of area h^2 (45-degree corner).
  const double h = 1e-3;
  const ConvexPolygon j =
      polygon_to_world(regular_polygon(4, 10.0 * std::sqrt(2.0), 0.25 * 3.141592653589793),
                       {0, -10.0}, 0.0);  // top edge at y = 0
  const ConvexPolygon i =
      polygon_to_world(regular_polygon(4, 1.0, -0.5 * 3.141592653589793), {0.3, 1.0 - h}, 0.0);
  PolygonOverlap k;
  ASSERT_TRUE(polygon_overlap(i, j, k));
  EXPECT_NEAR(k.area, h * h, 1e-12);
  EXPECT_NEAR(k.normal.x, 0.0, 1e-12);
  EXPECT_NEAR(k.normal.y, 1.0, 1e-12);
  EXPECT_NEAR(k.centroid.y, -h / 3, 1e-12);
  // Swapped roles: the normal flips.
  ASSERT_TRUE(polygon_overlap(j, i, k));
  EXPECT_NEAR(k.normal.y, -1.0, 1e-12);
  // Exactly touching at a vertex (zero area): no contact, no NaN.
  const ConvexPolygon i0 =
      polygon_to_world(regular_polygon(4, 1.0, -0.5 * 3.141592653589793), {0.3, 1.0}, 0.0);
  EXPECT_FALSE(polygon_overlap(i0, j, k));
  // Vertex on vertex: two diamonds touching tip to tip, then pushed by h.
  const ConvexPolygon d1 = polygon_to_world(regular_polygon(4, 1.0, 0.0), {-1.0 + 0.5 * h, 0}, 0.0);
  const ConvexPolygon d2 = polygon_to_world(regular_polygon(4, 1.0, 0.0), {1.0 - 0.5 * h, 0}, 0.0);
  ASSERT_TRUE(polygon_overlap(d1, d2, k));
  EXPECT_NEAR(k.area, 0.5 * h * h, 1e-12);
  EXPECT_NEAR(k.normal.x, -1.0, 1e-9);
  // Containment: a small grain inside a big one; no crossing, normal along c_i - c_j.
  const ConvexPolygon small = polygon_to_world(regular_polygon(5, 0.1, 0.0), {0.2, 0.1}, 0.0);
  const ConvexPolygon big = regular_polygon(7, 2.0, 0.0);
  ASSERT_TRUE(polygon_overlap(small, big, k));
  EXPECT_FALSE(k.chord);
  EXPECT_NEAR(k.area, polygon_properties(small).area, 1e-14);
  EXPECT_GT(k.normal.x, 0.0);
}

// Polygon against a wall half-plane: area and centroid against the exact oracle with the wall as
// a huge polygon; the normal is the wall normal.
TEST(PolygonOverlap, HalfPlaneAgainstOracle) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int n = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const ConvexPolygon pi = random_grain(rng, {0, 0});
    const double ang = 6.283185307179586 * u(rng);
    const Vec2 nrm{std::cos(ang), std::sin(ang)};
    const Vec2 pt = (u(rng) - 0.8) * nrm;
    // The solid side as a big square behind the wall line.
    const double big = 100;
    const Vec2 t = perp(nrm);
    ConvexPolygon wall;
    wall.n = 4;
    wall.v[0] = pt + big * t;
    wall.v[1] = pt + big * t - (2 * big) * nrm;
    wall.v[2] = pt - big * t - (2 * big) * nrm;
    wall.v[3] = pt - big * t;
    std::reverse(wall.v, wall.v + 4);
    if (polygon_properties(wall).area < 0) std::reverse(wall.v, wall.v + 4);
    const Oracle o = oracle_overlap(pi, wall);
    PolygonOverlap k;
    const bool hit = polygon_halfplane_overlap(pi, pt, nrm, k);
    if (o.area < 1e-10) continue;
    ASSERT_TRUE(hit);
    ++n;
    EXPECT_NEAR(k.area, o.area, 1e-11);
    EXPECT_NEAR(norm(k.centroid - o.centroid), 0.0, 1e-9);
    EXPECT_EQ(k.normal.x, nrm.x);
    EXPECT_NEAR(dot(k.p1 - pt, nrm), 0.0, 1e-12);
    EXPECT_NEAR(dot(k.p2 - pt, nrm), 0.0, 1e-12);
  }
  EXPECT_GT(n, 100);
  EXPECT_DOUBLE_EQ(polygon_characteristic_length(0.5, 0.0), 0.5);
  EXPECT_DOUBLE_EQ(polygon_normal_force(1e6, 1e-4, 0.5), 200.0);
}
