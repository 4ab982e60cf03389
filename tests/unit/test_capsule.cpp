// SPDX-License-Identifier: GPL-3.0-or-later
// Spherocylinder narrow phase against a dense-sampling brute-force oracle on random configurations.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "contact/geometry/capsule.hpp"

using namespace gf;
using namespace gf::contact;

namespace {

// ---- Oracle -------------------------------------------------------------------------------
// Distance from a point to a segment by clamped projection (independent of the kernel).
Vec3 point_on_segment(const Vec3& x, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double dd = dot(d, d);
  double t = dd > 0 ? dot(x - a, d) / dd : 0.0;
  t = t < 0 ? 0 : (t > 1 ? 1 : t);
  return a + t * d;
}

struct OracleResult {
  double dist2;
  Vec3 p, q;
};

// Minimises g(s) = dist^2(P(s), segment Q) over s in [0, 1]: N + 1 dense samples, then golden
// section between the neighbours of the best sample. g is convex in s (the distance to a convex
// set along a line), so the true minimum lies in that bracket: the oracle is exact up to the
// golden-section resolution (~1e-16 in s after 80 halvings of 0.618).
OracleResult oracle_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1,
                             int n = 2000) {
  auto g = [&](double s) {
    const Vec3 p = p0 + s * (p1 - p0);
    return norm2(p - point_on_segment(p, q0, q1));
  };
  int best = 0;
  double gbest = g(0);
  for (int k = 1; k <= n; ++k) {
    const double gk = g(static_cast<double>(k) / n);
    if (gk < gbest) {
      gbest = gk;
      best = k;
    }
  }
  double lo = std::max(0.0, (best - 1.0) / n), hi = std::min(1.0, (best + 1.0) / n);
  const double phi = 0.5 * (std::sqrt(5.0) - 1);
  double x1 = hi - phi * (hi - lo), x2 = lo + phi * (hi - lo), g1 = g(x1), g2 = g(x2);
  for (int it = 0; it < 80; ++it) {
    if (g1 <= g2) {
      hi = x2;
      x2 = x1;
      g2 = g1;
      x1 = hi - phi * (hi - lo);
      g1 = g(x1);
    } else {
      lo = x1;
      x1 = x2;
      g1 = g2;
      x2 = lo + phi * (hi - lo);
      g2 = g(x2);
    }
  }
  double s = 0.5 * (lo + hi);
  // The ends are candidates too (the golden section never evaluates them exactly).
  if (g(0) <= g(s)) s = 0;
  if (g(1) < g(s)) s = 1;
  const Vec3 p = p0 + s * (p1 - p0);
  return {g(s), p, point_on_segment(p, q0, q1)};
}

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vec3 v{n(rng), n(rng), n(rng)};
  return normalized(v);
}

double on_segment_param(const Vec3& x, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  return dot(d, d) > 0 ? dot(x - a, d) / dot(d, d) : 0.0;
}

}  // namespace

// Random segments in a unit box, lengths in [0, 1.5] (some zero): the kernel's squared distance
// equals the oracle's to 1e-12 (both are minima of the same convex function; the oracle is
// exact to round-off, the kernel's closed form to round-off over sin^2 >= 1e-12), and where the
// minimiser is well conditioned (sin^2 of the angle > 0.01) the points agree to 1e-6: an error
// d in the points costs ~ sin^2 d^2 in the distance, so 1e-15 / 0.01 -> 3e-7.
TEST(CapsuleSegments, RandomAgainstOracle) {
  std::mt19937_64 rng(20240401);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double max_d2 = 0, max_dp = 0;
  for (int trial = 0; trial < 1500; ++trial) {
    const Vec3 c1{u(rng), u(rng), u(rng)}, c2{u(rng), u(rng), u(rng)};
    const double l1 = trial % 50 == 0 ? 0.0 : 1.5 * u(rng),
                 l2 = trial % 70 == 0 ? 0.0 : 1.5 * u(rng);
    const Vec3 a1 = random_unit(rng), a2 = random_unit(rng);
    const Vec3 p0 = c1 - 0.5 * l1 * a1, p1 = c1 + 0.5 * l1 * a1, q0 = c2 - 0.5 * l2 * a2,
               q1 = c2 + 0.5 * l2 * a2;
    const SegmentClosest k = closest_points_segments(p0, p1, q0, q1);
    const OracleResult o = oracle_segments(p0, p1, q0, q1);
    ASSERT_NEAR(k.dist2, o.dist2, 1e-12) << "trial " << trial;
    ASSERT_NEAR(norm2(k.p - k.q), k.dist2, 1e-14);
    max_d2 = std::max(max_d2, std::abs(k.dist2 - o.dist2));
    const double sin2 = norm2(cross(a1, a2));
    if (sin2 > 0.01 && l1 > 0 && l2 > 0) {
      EXPECT_LT(norm(k.p - o.p), 1e-6) << "trial " << trial;
      EXPECT_LT(norm(k.q - o.q), 1e-6) << "trial " << trial;
      max_dp = std::max({max_dp, norm(k.p - o.p), norm(k.q - o.q)});
    }
  }
  std::printf("[ measured ] random segments: max |d2 - oracle| = %.2e, max |p - oracle| = %.2e\n",
              max_d2, max_dp);
}

// Near-parallel and parallel segments side by side (angles 0 to 1e-2 rad, overlapping or
// disjoint projections, crossing the parallel threshold sin^2 = 1e-12 of the kernel): the
// distance agrees with the oracle, the points lie on their segments at that distance, and for
// exactly parallel overlapping segments the pair is in the middle of the common part.
TEST(CapsuleSegments, NearParallelAgainstOracle) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double eps[] = {0.0, 1e-13, 1e-9, 1e-7, 1e-6, 1e-5, 1e-3, 1e-2};
  double max_d2 = 0;
  for (int trial = 0; trial < 800; ++trial) {
    const Vec3 a1 = random_unit(rng);
    const Vec3 w = normalized(cross(a1, random_unit(rng)));
    // Tilt in a random direction perpendicular to a1 (towards w changes the distance at first
    // order along the common part, the hardest case).
    const Vec3 tilt = normalized(cross(a1, random_unit(rng)));
    const Vec3 a2 = normalized(a1 + eps[trial % 8] * tilt);
    const double l1 = 0.5 + u(rng), l2 = 0.5 + u(rng);
    const Vec3 c1{u(rng), u(rng), u(rng)};
    const Vec3 c2 =
        c1 + (0.3 * u(rng)) * w + (2.2 * (u(rng) - 0.5)) * a1;  // side by side, shifted along
    const Vec3 p0 = c1 - 0.5 * l1 * a1, p1 = c1 + 0.5 * l1 * a1, q0 = c2 - 0.5 * l2 * a2,
               q1 = c2 + 0.5 * l2 * a2;
    const SegmentClosest k = closest_points_segments(p0, p1, q0, q1);
    const OracleResult o = oracle_segments(p0, p1, q0, q1, 4000);
    ASSERT_NEAR(k.dist2, o.dist2, 1e-12) << "trial " << trial << " eps " << eps[trial % 8];
    max_d2 = std::max(max_d2, std::abs(k.dist2 - o.dist2));
    EXPECT_GE(k.s, 0.0);
    EXPECT_LE(k.s, 1.0);
    EXPECT_GE(k.t, 0.0);
    EXPECT_LE(k.t, 1.0);
    EXPECT_NEAR(norm2(k.p - k.q), k.dist2, 1e-14);
    if (eps[trial % 8] == 0.0) {
      const double sq0 = on_segment_param(q0, p0, p1), sq1 = on_segment_param(q1, p0, p1);
      const double lo = std::max(0.0, std::min(sq0, sq1)), hi = std::min(1.0, std::max(sq0, sq1));
      if (lo < hi) {
        EXPECT_NEAR(k.s, 0.5 * (lo + hi), 1e-9) << "trial " << trial;
      }
    }
  }
  std::printf("[ measured ] near-parallel segments: max |d2 - oracle| = %.2e\n", max_d2);
}

TEST(CapsuleSegments, DegenerateAndCrossing) {
  // Two points.
  auto k = closest_points_segments({0, 0, 0}, {0, 0, 0}, {1, 2, 2}, {1, 2, 2});
  EXPECT_DOUBLE_EQ(k.dist2, 9.0);
  // Point and segment: projection inside.
  k = closest_points_segments({0.5, 1, 0}, {0.5, 1, 0}, {0, 0, 0}, {1, 0, 0});
  EXPECT_DOUBLE_EQ(k.dist2, 1.0);
  EXPECT_DOUBLE_EQ(k.t, 0.5);
  // Crossing segments: distance zero at the crossing.
  k = closest_points_segments({-1, 0, 0}, {1, 0, 0}, {0.25, -1, 0}, {0.25, 1, 0});
  EXPECT_NEAR(k.dist2, 0.0, 1e-30);
  EXPECT_NEAR(k.p.x, 0.25, 1e-15);
  // Collinear overlapping: middle of the common part [0.5, 1].
  k = closest_points_segments({0, 0, 0}, {1, 0, 0}, {0.5, 0, 0}, {3, 0, 0});
  EXPECT_NEAR(k.dist2, 0.0, 1e-30);
  EXPECT_NEAR(k.p.x, 0.75, 1e-15);
}

// Capsule-capsule contacts: overlap = r_i + r_j - d_oracle; the normal joins the oracle's closest
// points (well-conditioned cases) and points towards i; the contact point is at depth
// delta/2 inside both capsules (its distance to segment i is r_i - delta/2, to j r_j - delta/2).
TEST(CapsuleContact, RandomAgainstOracle) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int n_contacts = 0;
  double max_overlap_err = 0, max_normal_err = 0;
  for (int trial = 0; trial < 1500; ++trial) {
    Capsule ci{{u(rng), u(rng), u(rng)}, random_unit(rng), 0.5 * u(rng), 0.05 + 0.2 * u(rng)};
    Capsule cj{{u(rng), u(rng), u(rng)}, random_unit(rng), 0.5 * u(rng), 0.05 + 0.2 * u(rng)};
    if (trial % 5 == 0) cj.axis = normalized(ci.axis + 1e-7 * random_unit(rng));  // near-parallel
    if (trial % 5 == 1) cj.axis = ci.axis;                                        // parallel
    const OracleResult o = oracle_segments(ci.end0(), ci.end1(), cj.end0(), cj.end1());
    const double d = std::sqrt(o.dist2);
    ShapeContact k;
    const bool touching = capsule_capsule(ci, cj, k);
    const double rs = ci.radius + cj.radius;
    if (std::abs(d - rs) < 1e-9) continue;  // grazing: either answer is right
    ASSERT_EQ(touching, d < rs) << "trial " << trial;
    if (!touching) continue;
    ++n_contacts;
    // Compared through the squared distance, which both compute to round-off (the square root
    // amplifies a 1e-16 error of d^2 to 1e-8 in d when the axes nearly cross).
    const double dk = rs - k.overlap;
    EXPECT_NEAR(dk * dk, o.dist2, 1e-12) << "trial " << trial;
    max_overlap_err = std::max(max_overlap_err, std::abs(dk * dk - o.dist2));
    EXPECT_NEAR(norm(k.normal), 1.0, 1e-12);
    EXPECT_NEAR(k.r_eff, ci.radius * cj.radius / rs, 1e-15);
    const double ri_depth = norm(k.point - point_on_segment(k.point, ci.end0(), ci.end1()));
    const double rj_depth = norm(k.point - point_on_segment(k.point, cj.end0(), cj.end1()));
    // The point is inside both capsules (depth <= r; equal to r - delta/2 along the normal).
    EXPECT_LE(ri_depth, std::abs(ci.radius - 0.5 * k.overlap) + 1e-12) << "trial " << trial;
    EXPECT_LE(rj_depth, std::abs(cj.radius - 0.5 * k.overlap) + 1e-12) << "trial " << trial;
    if (d > 1e-6 && norm2(cross(ci.axis, cj.axis)) > 0.01) {
      const Vec3 n_oracle = (o.p - o.q) / d;
      EXPECT_GT(dot(k.normal, n_oracle), 1 - 1e-9) << "trial " << trial;
      EXPECT_LT(norm(k.point - (o.q + (cj.radius - 0.5 * k.overlap) * n_oracle)), 1e-6)
          << "trial " << trial;
      max_normal_err = std::max(max_normal_err, norm(k.normal - n_oracle));
    }
  }
  EXPECT_GT(n_contacts, 200);
  std::printf(
      "[ measured ] capsule-capsule: %d contacts, max |d^2 - oracle| %.2e m^2, max normal error "
      "%.2e\n",
      n_contacts, max_overlap_err, max_normal_err);
}

TEST(CapsuleContact, SphereAndFeatures) {
  // Sphere above the side of a capsule along x: overlap 0.1; i is the capsule, below the sphere,
  // so the normal (towards i) is -z.
  const Capsule c{{0, 0, 0}, {1, 0, 0}, 1.0, 0.5};
  ShapeContact k;
  ASSERT_TRUE(capsule_sphere(c, {0.3, 0, 0.7}, 0.3, k));
  EXPECT_NEAR(k.overlap, 0.1, 1e-15);
  EXPECT_NEAR(k.normal.z, -1.0, 1e-15);
  EXPECT_NEAR(k.point.z, 0.45, 1e-15);
  EXPECT_EQ(k.feature_i, CapsuleFeature::Side);
  EXPECT_EQ(k.feature_j, CapsuleFeature::Cap);
  EXPECT_NEAR(k.r_eff, 0.15 / 0.8, 1e-15);
  // Beyond the end: cap contact along the axis.
  ASSERT_TRUE(capsule_sphere(c, {1.7, 0, 0}, 0.3, k));
  EXPECT_NEAR(k.overlap, 0.1, 1e-15);
  EXPECT_NEAR(k.normal.x, -1.0, 1e-15);
  EXPECT_EQ(k.feature_i, CapsuleFeature::Cap);
  EXPECT_FALSE(capsule_sphere(c, {1.81, 0, 0}, 0.3, k));
  // Crossing axes (distance 0): normal perpendicular to both, towards i's centre.
  const Capsule a{{0, 0, 0.01}, {1, 0, 0}, 1.0, 0.2}, b{{0, 0, 0}, {0, 1, 0}, 1.0, 0.2};
  Capsule a0 = a;
  a0.center = {0, 0, 0};
  ASSERT_TRUE(capsule_capsule(a0, b, k));
  EXPECT_NEAR(std::abs(k.normal.z), 1.0, 1e-15);
  EXPECT_NEAR(k.overlap, 0.4, 1e-15);
  ASSERT_TRUE(capsule_capsule(a, b, k));
  EXPECT_NEAR(k.normal.z, 1.0, 1e-15);
  // Coaxial capsules (parallel, distance 0): a normal perpendicular to the axis, no NaN.
  ASSERT_TRUE(capsule_capsule(Capsule{{0, 0, 0}, {1, 0, 0}, 1.0, 0.2},
                              Capsule{{0.5, 0, 0}, {1, 0, 0}, 1.0, 0.2}, k));
  EXPECT_NEAR(norm(k.normal), 1.0, 1e-12);
  EXPECT_NEAR(k.normal.x, 0.0, 1e-12);
}

// Plane: gap sampled densely along the axis (it is linear, so the ends are the minima); tilted
// capsules have one contact at the deepest end with the sampled overlap, flat ones two equal
// contacts whose torques about the centre cancel; a slightly tilted capsule is pushed back flat.
TEST(CapsuleWall, PlaneAgainstSampling) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 p0{0.1, -0.2, 0.05};
  for (int trial = 0; trial < 500; ++trial) {
    const Vec3 n = random_unit(rng);
    const Capsule c{p0 + (0.6 * u(rng) - 0.1) * n + Vec3{u(rng), u(rng), 0}, random_unit(rng),
                    0.5 * u(rng), 0.05 + 0.2 * u(rng)};
    double gmin = 1e300;
    for (int s = 0; s <= 1000; ++s) {
      const Vec3 x = c.end0() + (s / 1000.0) * (c.end1() - c.end0());
      gmin = std::min(gmin, dot(x - p0, n) - c.radius);
    }
    ShapeContact out[2];
    const int m = capsule_plane(c, p0, n, out);
    ShapeContact deep;
    const bool has_deep = capsule_plane_deepest(c, p0, n, deep);
    ASSERT_EQ(m > 0, gmin < 0);
    ASSERT_EQ(has_deep, gmin < 0);
    if (m == 0) continue;
    double omax = 0;
    for (int e = 0; e < m; ++e) {
      omax = std::max(omax, out[e].overlap);
      EXPECT_NEAR(dot(out[e].normal, n), 1.0, 1e-15);
      // Contact point midway: (point - p0).n = -overlap/2.
      EXPECT_NEAR(dot(out[e].point - p0, n), -0.5 * out[e].overlap, 1e-12);
    }
    EXPECT_NEAR(omax, -gmin, 1e-12);
    EXPECT_NEAR(deep.overlap, -gmin, 1e-12);
  }
  // Flat capsule: two contacts, equal overlap, zero net torque about the centre.
  const Capsule flat{{0, 0, 0.15}, {1, 0, 0}, 0.5, 0.2};
  ShapeContact out[2];
  ASSERT_EQ(capsule_plane(flat, {0, 0, 0}, {0, 0, 1}, out), 2);
  EXPECT_NEAR(out[0].overlap, 0.05, 1e-15);
  EXPECT_NEAR(out[1].overlap, 0.05, 1e-15);
  Vec3 torque = cross(out[0].point - flat.center, out[0].overlap * out[0].normal) +
                cross(out[1].point - flat.center, out[1].overlap * out[1].normal);
  EXPECT_NEAR(norm(torque), 0.0, 1e-15);
  ShapeContact deep;
  ASSERT_TRUE(capsule_plane_deepest(flat, {0, 0, 0}, {0, 0, 1}, deep));
  EXPECT_NEAR(deep.point.x, 0.0, 1e-15);
  // Slightly tilted, end1 (at +x) up: end0 is deeper and pushes harder.
  const double tilt = 0.01;
  const Capsule tilted{{0, 0, 0.15}, {std::cos(tilt), 0, std::sin(tilt)}, 0.5, 0.2};
  ASSERT_EQ(capsule_plane(tilted, {0, 0, 0}, {0, 0, 1}, out), 2);
  torque = cross(out[0].point - tilted.center, out[0].overlap * out[0].normal) +
           cross(out[1].point - tilted.center, out[1].overlap * out[1].normal);
  // The axis is turned by +tilt about -y; the restoring torque turns it back: about +y.
  EXPECT_GT(torque.y, 0.0);
  // A sphere gets one contact.
  EXPECT_EQ(capsule_plane(Capsule{{0, 0, 0.1}, {1, 0, 0}, 0.0, 0.2}, {0, 0, 0}, {0, 0, 1}, out), 1);
}

// Cylinder walls (inside: a drum; outside: a pillar) against the gap sampled densely along the
// axis with the exact point-to-axis distance: the largest returned overlap equals the sampled
// one to the sampling resolution (1e-6 relative with 2000 samples plus golden refinement).
TEST(CapsuleWall, CylinderAgainstSampling) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 a0{0.2, 0.1, -0.3};
  const double R = 1.0;
  int n_in = 0, n_out = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const bool inside = trial % 2 == 0;
    const Vec3 w = random_unit(rng);
    const Vec3 radial = normalized(cross(w, random_unit(rng)));
    const double rho_c = inside ? R - 0.6 * u(rng) : R + 0.6 * u(rng) - 0.05;
    Capsule c{a0 + rho_c * radial + (u(rng) - 0.5) * w, random_unit(rng), 0.4 * u(rng),
              0.05 + 0.15 * u(rng)};
    if (trial % 7 == 0) c.axis = w;  // parallel to the cylinder axis
    auto gap_at = [&](double s) {
      const Vec3 x = c.end0() + s * (c.end1() - c.end0());
      const Vec3 d = x - a0;
      const double rho = norm(d - dot(d, w) * w);
      return inside ? R - rho - c.radius : rho - R - c.radius;
    };
    double gmin = 1e300;
    for (int s = 0; s <= 2000; ++s) gmin = std::min(gmin, gap_at(s / 2000.0));
    ShapeContact out[2];
    const int m = capsule_cylinder_wall(c, a0, w, R, inside, out);
    if (std::abs(gmin) < 1e-6) continue;
    ASSERT_EQ(m > 0, gmin < 0) << "trial " << trial;
    if (m == 0) continue;
    (inside ? n_in : n_out)++;
    double omax = 0;
    for (int e = 0; e < m; ++e) {
      omax = std::max(omax, out[e].overlap);
      EXPECT_NEAR(norm(out[e].normal), 1.0, 1e-12);
      // The normal is radial (perpendicular to the axis) and points into the fluid side.
      EXPECT_NEAR(dot(out[e].normal, w), 0.0, 1e-9);
    }
    EXPECT_NEAR(omax, -gmin, 1e-6 * (1 + std::abs(gmin))) << "trial " << trial;
    EXPECT_GE(omax, -gmin - 1e-15);
  }
  EXPECT_GT(n_in, 50);
  EXPECT_GT(n_out, 30);
}
