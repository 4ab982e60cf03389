// SPDX-License-Identifier: GPL-3.0-or-later
// Overlap of a convex polygon with a disk and with the outside of a circle, against an
// independent oracle: the overlap's area and first moments integrated over vertical slices
// (both shapes are convex, so each slice of either, and of their intersection, is one interval),
// by Gauss-Legendre quadrature between every abscissa where a slice's ends change formula.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "contact/geometry/disk_polygon.hpp"

using namespace gf::contact;

namespace {

constexpr double kPi = std::numbers::pi;

struct Slice {
  bool hit = false;
  double lo = 0, hi = 0;
};

/// The vertical slice of a convex polygon at abscissa x.
Slice polygon_slice(const ConvexPolygon& p, double x) {
  Slice s;
  s.lo = 1e300;
  s.hi = -1e300;
  for (int k = 0; k < p.n; ++k) {
    const Vec2 a = p.v[k], b = p.v[(k + 1) % p.n];
    if ((x < std::min(a.x, b.x)) || (x > std::max(a.x, b.x)) || a.x == b.x) continue;
    const double y = a.y + (b.y - a.y) * (x - a.x) / (b.x - a.x);
    s.lo = std::min(s.lo, y);
    s.hi = std::max(s.hi, y);
    s.hit = true;
  }
  return s;
}

struct Moments {
  double area = 0;
  Vec2 centroid;
};

/// Area and centroid of P ∩ D (outside = false) or P \ D (outside = true) by quadrature.
Moments oracle(const ConvexPolygon& p, const Vec2& c, double r, bool outside) {
  std::vector<double> xs;
  for (int k = 0; k < p.n; ++k) xs.push_back(p.v[k].x);
  xs.push_back(c.x - r);
  xs.push_back(c.x + r);
  // Where an edge crosses the circle (the slice's end switches between edge and arc).
  for (int k = 0; k < p.n; ++k) {
    const Vec2 a = p.v[k], b = p.v[(k + 1) % p.n];
    for (int s = 0; s <= 4000; ++s) {  // bracket sign changes of |x(t) - c| - r, then bisect
      const double t0 = s / 4000.0, t1 = (s + 1) / 4000.0;
      auto f = [&](double t) { return norm(a + t * (b - a) - c) - r; };
      if (s == 4000 || f(t0) * f(t1) > 0) continue;
      double lo = t0, hi = t1;
      for (int it = 0; it < 200; ++it) {
        const double mid = 0.5 * (lo + hi);
        (f(lo) * f(mid) <= 0 ? hi : lo) = mid;
      }
      xs.push_back((a + lo * (b - a)).x);
    }
  }
  std::sort(xs.begin(), xs.end());
  // 16-point Gauss-Legendre on [-1, 1] (nodes and weights from the Golub-Welsch recursion).
  static const std::vector<std::pair<double, double>> gl = [] {
    const int n = 16;
    std::vector<std::pair<double, double>> out;
    for (int i = 1; i <= n; ++i) {
      double x = std::cos(kPi * (i - 0.25) / (n + 0.5));
      double dp = 0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1, p1 = x;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (x * p1 - p0) / (x * x - 1);
        x -= p1 / dp;
      }
      out.emplace_back(x, 2 / ((1 - x * x) * dp * dp));
    }
    return out;
  }();
  double a = 0, mx = 0, my = 0;
  for (std::size_t s = 0; s + 1 < xs.size(); ++s) {
    const double x0 = xs[s], x1 = xs[s + 1];
    if (!(x1 > x0)) continue;
    // x = x0 + (x1 - x0) * (3u^2 - 2u^3): flat at both ends, so the square-root ends of the arc
    // integrate to full accuracy; 40 sub-pieces of 16 points.
    const int pieces = 40;
    for (int q = 0; q < pieces; ++q) {
      for (const auto& [node, w] : gl) {
        const double u = (q + 0.5 * (node + 1)) / pieces;
        const double x = x0 + (x1 - x0) * (3 * u * u - 2 * u * u * u);
        const double jac = (x1 - x0) * 6 * u * (1 - u) * (0.5 * w / pieces);
        const Slice ps = polygon_slice(p, x);
        if (!ps.hit) continue;
        const double h2 = r * r - (x - c.x) * (x - c.x);
        double len = 0, m2 = 0;  // length and integral of y over the slice of the region
        const double ilo = h2 > 0 ? std::max(ps.lo, c.y - std::sqrt(h2)) : 0;
        const double ihi = h2 > 0 ? std::min(ps.hi, c.y + std::sqrt(h2)) : 0;
        const bool inner = h2 > 0 && ihi > ilo;
        if (outside) {
          len = ps.hi - ps.lo;
          m2 = 0.5 * (ps.hi * ps.hi - ps.lo * ps.lo);
          if (inner) {
            len -= ihi - ilo;
            m2 -= 0.5 * (ihi * ihi - ilo * ilo);
          }
        } else if (inner) {
          len = ihi - ilo;
          m2 = 0.5 * (ihi * ihi - ilo * ilo);
        }
        a += jac * len;
        mx += jac * x * len;
        my += jac * m2;
      }
    }
  }
  Moments m;
  m.area = a;
  if (a > 0) m.centroid = {mx / a, my / a};
  return m;
}

/// Gradient of the oracle's area with respect to a translation of the polygon, by central
/// differences (step 1e-5 on shapes of size ~1: truncation ~1e-10, quadrature noise ~1e-8).
Vec2 area_gradient(const ConvexPolygon& p, const Vec2& c, double r, bool outside) {
  const double h = 1e-5;
  auto area = [&](Vec2 d) {
    ConvexPolygon q = p;
    for (int v = 0; v < q.n; ++v) q.v[v] = q.v[v] + d;
    return oracle(q, c, r, outside).area;
  };
  return {(area({h, 0}) - area({-h, 0})) / (2 * h), (area({0, h}) - area({0, -h})) / (2 * h)};
}

ConvexPolygon random_grain(std::mt19937_64& rng, Vec2 at, double size) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int n = 3 + static_cast<int>(u(rng) * 14);  // 3..16 vertices
  const ConvexPolygon body =
      random_convex_polygon(rng, n, size * (0.5 + 0.5 * u(rng)), 1.0 + 2.0 * u(rng));
  return polygon_to_world(body, at, 2 * kPi * u(rng));
}

bool on_boundary(const ConvexPolygon& p, const Vec2& x, double tol) {
  for (int k = 0; k < p.n; ++k) {
    const Vec2 a = p.v[k], b = p.v[(k + 1) % p.n];
    const double t = dot(x - a, b - a) / dot(b - a, b - a);
    if (t >= -1e-12 && t <= 1 + 1e-12 && norm(a + t * (b - a) - x) <= tol) return true;
  }
  return false;
}

/// Area of the circular segment of depth h of a circle of radius r.
double segment_area(double r, double h) {
  return r * r * std::acos((r - h) / r) - (r - h) * std::sqrt(2 * r * h - h * h);
}

}  // namespace

// Disks of radius 0.3-1.5 against random polygons (3-16 vertices, aspect ratio 1-3, size ~1):
// area to 1e-11 absolute and centroid to 1e-9 (the quadrature is good to ~1e-13 on these
// sizes; the kernel's rounding is ~1e-15), the chord's ends on both boundaries, the normal
// perpendicular to the chord, pointing from the polygon into the disk.
TEST(DiskPolygonOverlap, RandomPairsAgainstQuadrature) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int hits = 0, chords = 0, single = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const ConvexPolygon p = random_grain(rng, {0, 0}, 1.0);
    const double r = 0.3 + 1.2 * u(rng);
    const double ang = 2 * kPi * u(rng), dist = (0.2 + 1.6 * u(rng)) * (0.5 + r);
    const Vec2 c{dist * std::cos(ang), dist * std::sin(ang)};
    const Moments o = oracle(p, c, r, false);
    PolygonOverlap k;
    const bool hit = disk_polygon_overlap(c, r, p, k);
    if (o.area < 1e-9) {
      EXPECT_TRUE(!hit || k.area < 1e-9);
      continue;
    }
    ASSERT_TRUE(hit) << trial;
    ++hits;
    EXPECT_NEAR(k.area, o.area, 1e-11) << trial;
    EXPECT_NEAR(norm(k.centroid - o.centroid), 0.0, 1e-9) << trial;
    EXPECT_NEAR(norm(k.normal), 1.0, 1e-14);
    // The normal and the chord's width are the direction and the rate of the overlap's growth:
    // moving the polygon along the normal (towards the disk) grows it at |p2 - p1| per metre.
    const Vec2 grad = area_gradient(p, c, r, false);
    if (!k.chord) {
      EXPECT_LT(norm(grad), 1e-6) << trial;  // one inside the other
      continue;
    }
    EXPECT_NEAR(norm(grad - norm(k.p2 - k.p1) * k.normal), 0.0, 1e-6) << trial;
    EXPECT_NEAR(dot(k.normal, k.p2 - k.p1), 0.0, 1e-12);
    ++chords;
    // One run of polygon boundary inside the disk (else the chord is an equivalent one through
    // the centroid): its ends on both boundaries, the shapes on the right sides of it.
    if (std::abs(norm(k.p1 - c) - r) > 1e-9 * r) continue;
    ++single;
    EXPECT_NEAR(norm(k.p1 - c), r, 1e-12 * r);
    EXPECT_NEAR(norm(k.p2 - c), r, 1e-12 * r);
    EXPECT_TRUE(on_boundary(p, k.p1, 1e-12) && on_boundary(p, k.p2, 1e-12)) << trial;
    // The deepest point of the disk inside the polygon lies behind the chord, the polygon's
    // vertices inside the disk in front of it.
    EXPECT_LT(dot(c - r * k.normal - k.p1, k.normal), 0.0) << trial;
    for (int v = 0; v < p.n; ++v) {
      if (norm(p.v[v] - c) < r) {
        EXPECT_GT(dot(p.v[v] - k.p1, k.normal), -1e-12) << trial;
      }
    }
  }
  std::printf("disks: %d overlaps, %d with a chord, %d of one run\n", hits, chords, single);
  EXPECT_GT(hits, 300);
  EXPECT_GT(single, 250);
  EXPECT_GT(chords - single, 0);  // some of several runs (a long polygon across the disk)
}

// Polygons near the wall of a circular vessel (grains inside, radius 4-8 times their size) and
// against a post (a solid disk): the part outside the circle, respectively inside it, against
// the quadrature; with one run of boundary beyond the circle the normal is radial through the
// chord's middle, inwards for the vessel and outwards for the post.
TEST(DiskPolygonOverlap, CircularWallsAgainstQuadrature) {
  std::mt19937_64 rng(22);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const bool inside : {true, false}) {
    int hits = 0, chords = 0, single = 0;
    for (int trial = 0; trial < 400; ++trial) {
      const double big = 4 + 4 * u(rng);
      const double ang = 2 * kPi * u(rng), dist = big + (u(rng) - 0.5) * 2.4;
      const ConvexPolygon p = random_grain(rng, {dist * std::cos(ang), dist * std::sin(ang)}, 1.0);
      const Vec2 c{0.3, -0.2};
      const Vec2 cc = c;
      ConvexPolygon pw = p;
      for (int v = 0; v < pw.n; ++v) pw.v[v] = pw.v[v] + cc;
      const Moments o = oracle(pw, c, big, inside);
      PolygonOverlap k;
      const bool hit = polygon_circle_wall_overlap(pw, c, big, inside, k);
      if (o.area < 1e-9) {
        EXPECT_TRUE(!hit || k.area < 1e-9);
        continue;
      }
      ASSERT_TRUE(hit) << trial;
      ++hits;
      EXPECT_NEAR(k.area, o.area, 2e-11) << inside << " " << trial;
      EXPECT_NEAR(norm(k.centroid - o.centroid), 0.0, 1e-9) << inside << " " << trial;
      // Moving the polygon along the normal (away from the wall) shrinks the overlap at the
      // rate |p2 - p1|.
      const Vec2 grad = area_gradient(pw, c, big, inside);
      if (!k.chord) {
        EXPECT_LT(norm(grad), 1e-6) << inside << " " << trial;
        continue;
      }
      ++chords;
      EXPECT_NEAR(norm(grad + norm(k.p2 - k.p1) * k.normal), 0.0, 1e-6) << inside << " " << trial;
      EXPECT_NEAR(dot(k.normal, k.p2 - k.p1), 0.0, 1e-12);
      // One run beyond the circle: the chord joins two points of the circle, and the normal is
      // radial through its middle, inwards for the vessel and outwards for the post.
      if (std::abs(norm(k.p1 - c) - big) > 1e-9 * big) continue;
      ++single;
      const Vec2 mid = 0.5 * (k.p1 + k.p2);
      const Vec2 radial = (1.0 / norm(mid - c)) * (mid - c);
      const Vec2 want = inside ? -radial : radial;
      EXPECT_NEAR(norm(k.normal - want), 0.0, 1e-9) << inside << " " << trial;
    }
    std::printf("%s: %d overlaps, %d with a chord, %d of one run\n", inside ? "vessel" : "post",
                hits, chords, single);
    EXPECT_GT(hits, 150) << inside;
    EXPECT_GT(single, 100) << inside;
  }
}

// Exact cases: a flat face pressed into a disk (the circular segment: area, centroid, chord);
// the same face on a drum's wall from inside; containment either way; a vertex exactly on the
// circle (no spurious crossing); a tangent face (no contact).
TEST(DiskPolygonOverlap, ExactCases) {
  const double r = 0.01, h = 2e-5;
  ConvexPolygon square;  // side 0.02, top face at y = 0
  square.n = 4;
  square.v[0] = {-0.01, -0.02};
  square.v[1] = {0.01, -0.02};
  square.v[2] = {0.01, 0.0};
  square.v[3] = {-0.01, 0.0};
  PolygonOverlap k;
  ASSERT_TRUE(disk_polygon_overlap({0.001, r - h}, r, square, k));
  EXPECT_NEAR(k.area / segment_area(r, h), 1.0, 1e-9);
  const double half = std::sqrt(2 * r * h - h * h);
  EXPECT_TRUE(k.chord);
  EXPECT_NEAR(norm(k.p2 - k.p1), 2 * half, 1e-15);
  EXPECT_NEAR(k.normal.x, 0.0, 1e-15);
  EXPECT_NEAR(k.normal.y, 1.0, 1e-15);
  // Centroid of a segment: distance 4 r sin^3(θ) / (3 (2θ - sin 2θ)) from the centre.
  const double th = std::acos((r - h) / r);
  const double cd = 4 * r * std::pow(std::sin(th), 3) / (3 * (2 * th - std::sin(2 * th)));
  EXPECT_NEAR(k.centroid.x, 0.001, 1e-15);
  EXPECT_NEAR(k.centroid.y, (r - h) - cd, 1e-13);

  // The square's bottom face just below the bottom of a drum of radius 0.5 (centre at the
  // origin): the overlap runs across the whole face, between it and the arc.
  const double R = 0.5, depth = 1e-4;
  ConvexPolygon sq2 = square;
  for (int v = 0; v < 4; ++v) sq2.v[v] = sq2.v[v] + Vec2{0, -R - depth + 0.02};
  ASSERT_TRUE(polygon_circle_wall_overlap(sq2, {0, 0}, R, true, k));
  // Area between y = -R - depth and the arc y = -sqrt(R^2 - x^2) over |x| <= 0.01.
  const double w = 0.01;
  const double under = w * std::sqrt(R * R - w * w) + R * R * std::asin(w / R);
  EXPECT_NEAR(k.area / (2 * w * (R + depth) - under), 1.0, 1e-8);
  EXPECT_NEAR(k.normal.x, 0.0, 1e-14);
  EXPECT_NEAR(k.normal.y, 1.0, 1e-14);
  EXPECT_NEAR(norm(k.p2 - k.p1), 2 * w, 1e-14);

  // The same face higher, above the drum's bottom but below the circle at its corners: the
  // corners poke out, the middle does not (two runs). Area beyond the arc for x* < |x| < w,
  // x* = sqrt(R^2 - y_b^2); the normal straight up; the width the rate dA/dy_b = 2 (w - x*).
  const double yb = -R + 0.5 * (R - std::sqrt(R * R - w * w));
  ConvexPolygon sq3 = square;
  for (int v = 0; v < 4; ++v) sq3.v[v] = sq3.v[v] + Vec2{0, yb + 0.02};
  ASSERT_TRUE(polygon_circle_wall_overlap(sq3, {0, 0}, R, true, k));
  const double xs = std::sqrt(R * R - yb * yb);
  auto F = [&](double x) {
    return 0.5 * (x * std::sqrt(R * R - x * x) + R * R * std::asin(x / R));
  };
  const double two_corners = 2 * (-yb * (w - xs) - (F(w) - F(xs)));
  EXPECT_NEAR(k.area / two_corners, 1.0, 1e-7);
  EXPECT_NEAR(k.normal.x, 0.0, 1e-12);
  EXPECT_NEAR(k.normal.y, 1.0, 1e-12);
  EXPECT_TRUE(k.chord);
  EXPECT_NEAR(norm(k.p2 - k.p1) / (2 * (w - xs)), 1.0, 1e-9);
  EXPECT_NEAR(k.centroid.x, 0.0, 1e-12);  // (the two corners cancel: rounding of ~1e-14)

  // Containment: a small disk inside the square, the square inside a large disk.
  ASSERT_TRUE(disk_polygon_overlap({0.002, -0.01}, 0.003, square, k));
  EXPECT_NEAR(k.area, kPi * 9e-6, 1e-18);
  EXPECT_FALSE(k.chord);
  EXPECT_NEAR(k.centroid.x, 0.002, 1e-15);
  ASSERT_TRUE(disk_polygon_overlap({0.0, -0.01}, 0.1, square, k));
  EXPECT_NEAR(k.area, 4e-4, 1e-18);
  EXPECT_FALSE(k.chord);
  // Apart, and a polygon wholly inside a drum: nothing.
  EXPECT_FALSE(disk_polygon_overlap({0.0, 0.02}, 0.01, square, k));  // tangent to the top face
  EXPECT_FALSE(disk_polygon_overlap({0.0, 0.03}, 0.01, square, k));
  EXPECT_FALSE(polygon_circle_wall_overlap(square, {0, 0}, 1.0, true, k));

  // A kite with its left corner exactly on the circle of a disk of radius 1.5 centred at
  // (0.5, 0) and its right corner outside: one run of boundary outside (the corner on the circle
  // leaves and enters at one point, which is no crossing).
  ConvexPolygon kite;
  kite.n = 4;
  kite.v[0] = {-1, 0};
  kite.v[1] = {1.5, -1};
  kite.v[2] = {2.5, 0};
  kite.v[3] = {1.5, 1};
  ASSERT_TRUE(disk_polygon_overlap({0.5, 0}, 1.5, kite, k));
  const Moments o = oracle(kite, {0.5, 0}, 1.5, false);
  EXPECT_NEAR(k.area, o.area, 1e-12);
  EXPECT_TRUE(k.chord);
  EXPECT_NEAR(k.p1.x, k.p2.x, 1e-14);  // the chord across the right corner is vertical
  EXPECT_NEAR(k.normal.x, -1.0, 1e-14);
  // A vertex inside the circle by one rounding step, its edge running radially out: the exit
  // lies at the vertex itself (where rounding may put the root just behind it) and must still be
  // found, or the entry of the other edge would have no exit and the chord would be wrong.
  ConvexPolygon tri;
  tri.n = 3;
  tri.v[0] = {std::nextafter(1.0, 0.0), 0};
  tri.v[1] = {2, 0};
  tri.v[2] = {0, 0.5};
  ASSERT_TRUE(disk_polygon_overlap({0, 0}, 1.0, tri, k));
  const Moments ot = oracle(tri, {0, 0}, 1.0, false);
  EXPECT_NEAR(k.area, ot.area, 1e-12);
  EXPECT_TRUE(k.chord);
  EXPECT_NEAR(norm(k.p1), 1.0, 1e-12);
  EXPECT_NEAR(norm(k.p2), 1.0, 1e-12);
  // (the vertex crosses the circle within the difference's step: a kink, an O(step) error)
  EXPECT_NEAR(norm(area_gradient(tri, {0, 0}, 1.0, false) - norm(k.p2 - k.p1) * k.normal), 0.0,
              1e-5);
  // The same kite inside a larger disk that touches only its left corner (centre (0.8, 0),
  // radius 1.8: the right corner is 1.7 from the centre): no crossing at all.
  ASSERT_TRUE(disk_polygon_overlap({0.8, 0}, 1.8, kite, k));
  EXPECT_NEAR(k.area, polygon_properties(kite).area, 1e-14);
  EXPECT_FALSE(k.chord);
}
