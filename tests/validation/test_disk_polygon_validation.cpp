// SPDX-License-Identifier: GPL-3.0-or-later
// Disks among polygons and polygons in circular vessels (2D), through the whole simulation,
// against statics worked out by hand: at rest, the overlap-area law F_n = k A / l_c must carry
// the weight with the overlap of the exact geometry (a circular segment under a disk; the part
// of a square beyond a drum's arc), and the floor or the drum must carry all the weight.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "case_builder.hpp"
#include "dump.hpp"
#include "simulation/simulation.hpp"

using namespace gf;
using gf::test::Dump;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.81;

config::Case plane_case(double dt, Vec3 lo, Vec3 hi) {
  auto c = test::base_case(dt, 1.0, lo, hi);
  c.dimension = 2;
  c.domain.thickness = 0.01;
  c.gravity = {0, -kG, 0};
  test::add_material(c, "pom", 1400, 1e7, 0.3);
  // e = 0.3: the grains come to rest within a few contact times (below).
  test::add_contact(c, "pom", "pom", "hooke",
                    {{"restitution", 0.3}, {"friction", 0.5}, {"stiffness", 1e5}});
  return c;
}

/// Area of the circular segment of depth h of a circle of radius r.
double segment_area(double r, double h) {
  return r * r * std::acos((r - h) / r) - (r - h) * std::sqrt(2 * r * h - h * h);
}

}  // namespace

// A disk (r = 4 mm) and a square (equal-area radius R = 5 mm, faces horizontal) stacked on the
// floor, the disk on top and then below (the square balanced on it: exactly centred, nothing
// turns it). The upper grain's weight m g is carried by the disk-square contact, so their overlap
// is the circular segment of depth δ (the gap between the disk's lowest or highest point and the
// square's face) with k A(δ) / l_c = m g, l_c = r + R (contact/shape_forces.hpp). With
// k = 1e5 N/m the segment is 3-4 µm deep, the contact's period ~3 ms; after 0.08 s (e = 0.3:
// ~25 periods, each damping the amplitude to ~0.3) the residual motion is far below 1e-4 of δ;
// the tolerance 1e-3 on A covers it and the settling of the lower grain on the floor. The grains
// are ordered by height in the store, so the stacking order makes the disk grain i of the pair
// once and grain j once (both branches of the narrow phase).
TEST(ValidationDiskPolygon, StackedDiskAndSquareOverlapByTheSegmentDepth) {
  const double r = 0.004, R = 0.005, k = 1e5;
  const double half = 0.5 * std::sqrt(kPi) * R;  // half side of the square of area pi R^2
  const Quat flat = turn_about_z(Quat{}, kPi / 4);
  for (const bool disk_below : {false, true}) {
    auto c = plane_case(2e-6, {-0.05, -0.01, 0}, {0.05, 0.1, 0});
    test::add_plane(c, "floor", {0, 0, 0}, {0, 1, 0}, "pom");
    if (disk_below) {
      test::add_disks(c, "pom", r, {{0, r + 1e-6, 0}});
      test::add_polygons(c, "pom", R, 4, {{0, 2 * r + half + 2e-5, 0}}, {flat});
    } else {
      test::add_polygons(c, "pom", R, 4, {{0, half + 1e-6, 0}}, {flat});
      test::add_disks(c, "pom", r, {{0, 2 * half + r + 2e-5, 0}});
    }
    Simulation sim(c);
    for (int s = 0; s < 40000; ++s) sim.step();
    const auto& p = sim.particles();
    const std::size_t d = p.shape()[0] == static_cast<std::int32_t>(ShapeCode::Disk) ? 0 : 1;
    const std::size_t q = 1 - d;
    const double m_top = p.mass()[disk_below ? q : d], weight = kG * (p.mass()[0] + p.mass()[1]);
    const double depth = disk_below ? (p.x()[d].y + r) - (p.x()[q].y - half)
                                    : (p.x()[q].y + half) - (p.x()[d].y - r);
    const double area = segment_area(r, depth), want = m_top * kG * (r + R) / k;
    std::printf(
        "disk %s square: depth %.4e m, k A / l_c = %.6e N, m g = %.6e N, floor / "
        "weight %.6f\n",
        disk_below ? "under" : "on", depth, k * area / (r + R), m_top * kG,
        -sim.walls()[0].force.y / weight);
    EXPECT_NEAR(area / want, 1.0, 1e-3);
    EXPECT_NEAR(-sim.walls()[0].force.y / weight, 1.0, 1e-4);  // (the force on the wall)
    EXPECT_LT(std::abs(p.x()[0].x) + std::abs(p.x()[1].x), 1e-12);
    EXPECT_LT(std::abs(p.omega()[q].z), 1e-9);
    Dump dump(std::string("disk_square_stack_") + (disk_below ? "disk_below" : "disk_on_top"),
              "depth,area,area_from_weight,relative_error");
    dump.row(depth, area, want, area / want - 1);
  }
}

// A frictionless disk falls onto the corner of a fixed square turned by 20°, 1.5 mm off the
// corner's vertical: the overlap is lopsided, and its centroid lies off the disk's vertical, but
// the contact force acts on the line through the disk's centre (contact/geometry/
// disk_polygon.hpp), as the radial pressure on a circle would: without friction the disk must
// not spin (at the centroid it would, by ~1 rad/s here). It bounces off sideways.
TEST(ValidationDiskPolygon, FrictionlessDiskOffACornerDoesNotSpin) {
  auto c = plane_case(1e-6, {-0.05, -0.05, 0}, {0.05, 0.05, 0});
  c.contacts[0].params["friction"] = 0.0;
  const double R = 0.005, r = 0.004;
  const double circum = R * std::sqrt(kPi / 2);  // circumradius of the square of area pi R^2
  // A regular 4-gon has its first vertex at angle 0; turned by 110° its top corner points at
  // 110°, 20° off the vertical, between faces sloping at 65° and -25°.
  const double turn = 110 * kPi / 180;
  test::add_polygons(c, "pom", R, 4, {{0, 0, 0}}, {turn_about_z(Quat{}, turn)}).fixed = true;
  const Vec3 top{circum * std::cos(turn), circum * std::sin(turn), 0};
  test::add_disks(c, "pom", r, {{top.x + 0.0015, top.y + r + 2e-4, 0}});
  Simulation sim(c);
  const std::size_t d =
      sim.particles().shape()[0] == static_cast<std::int32_t>(ShapeCode::Disk) ? 0 : 1;
  double spin = 0, vx = 0;
  int touching = 0;
  for (int s = 0; s < 40000; ++s) {
    sim.step();
    touching += sim.n_contacts() > 0;
    spin = std::max(spin, std::abs(sim.particles().omega()[d].z));
    vx = sim.particles().v()[d].x;
  }
  std::printf(
      "frictionless disk off a corner: %d steps in contact, largest spin %.3e rad/s, "
      "v_x after %.3f m/s\n",
      touching, spin, vx);
  EXPECT_GT(touching, 100);
  EXPECT_GT(vx, 0.01);    // pushed away from the corner, sideways
  EXPECT_LT(spin, 1e-9);  // (rounding only)
}

// A square (R = 5 mm) at the bottom of a drum of radius 5 cm (a 2D cylinder wall, inside:
// true): the flat bottom face cannot follow the arc, so the square rests on its two corners,
// which cross the circle (two runs of boundary beyond it; contact/geometry/disk_polygon.hpp).
// At rest k A / l_c = m g with l_c = R (a rigid wall) and A the part of the square below the
// arc y = -sqrt(Rd^2 - x^2), from the square's height alone. The drum carries the weight.
// Tolerances as above (1e-3 on A, the square's contact being ~1e-7 m deep and stiff).
// Then the drum turns at 0.5 rad/s: friction (μ = 0.5) carries the square up the wall until it
// slides back at the angle where tan θ = μ; it then rides there (the drum's speed, 2.5 cm/s, is
// slow against the contact's dynamics): θ within 1° of atan(0.5) = 26.57°.
TEST(ValidationDiskPolygon, SquareRestsInADrumAndRidesUpToTheFrictionAngle) {
  const double R = 0.005, Rd = 0.05, k = 1e5;
  const double half = 0.5 * std::sqrt(kPi) * R;
  auto c = plane_case(2e-6, {-0.06, -0.06, 0}, {0.06, 0.06, 0});
  test::add_polygons(c, "pom", R, 4, {{0, -Rd + half + 1e-3, 0}}, {turn_about_z(Quat{}, kPi / 4)});
  test::add_cylinder(c, "drum", {0, 0, 0}, {0, 0, 1}, Rd, true, "pom");
  {
    Simulation sim(c);
    for (int s = 0; s < 40000; ++s) sim.step();
    const auto& p = sim.particles();
    const double m = p.mass()[0];
    const double yb = p.x()[0].y - half;  // the bottom face, horizontal by symmetry
    const double xs = std::sqrt(Rd * Rd - yb * yb);
    auto F = [&](double x) {
      return 0.5 * (x * std::sqrt(Rd * Rd - x * x) + Rd * Rd * std::asin(x / Rd));
    };
    // Below the arc: both corners (x* < |x| < half) when the face is above the drum's bottom,
    // the whole face otherwise.
    const double x0 = yb > -Rd ? xs : 0.0;
    const double area = 2 * (-yb * (half - x0) - (F(half) - F(x0)));
    const double want = m * kG * R / k;
    std::printf(
        "square in drum: bottom face %.4e m above the drum's bottom, corners from x = "
        "%.4e, k A / R = %.6e N, m g = %.6e N, drum / weight %.6f\n",
        yb + Rd, x0, k * area / R, m * kG, -sim.walls()[0].force.y / (m * kG));
    Dump dump("square_in_drum_rest", "depth,area,area_from_weight,relative_error");
    dump.row(yb + Rd, area, want, area / want - 1);
    EXPECT_GT(yb, -Rd);  // resting on its corners
    EXPECT_NEAR(area / want, 1.0, 1e-3);
    EXPECT_NEAR(-sim.walls()[0].force.y / (m * kG), 1.0, 1e-4);
    EXPECT_LT(std::abs(p.x()[0].x), 1e-12);
  }
  // The turning drum: ten times larger (the shift of the load towards the downhill corner, by
  // μ h = 2.2 mm to balance the friction's torque about the centre of mass, then moves the
  // contact's normal by only μ h / Rd = 0.25° from the square's angular position).
  const double big = 10 * Rd;
  c.domain.min = {-1.1 * big, -1.1 * big, 0};
  c.domain.max = {1.1 * big, 1.1 * big, 0};
  c.particles[0].explicit_particles->positions = {{0, -big + half + 1e-4, 0}};
  c.walls[0].radius = big;
  c.walls[0].motion.rotates = true;
  c.walls[0].motion.axis = {0, 0, 1};
  c.walls[0].motion.center = {0, 0, 0};
  c.walls[0].motion.rate = 0.5;
  c.time.end = 3.0;
  Simulation sim(c);
  // Sample the square's angular position every millisecond; it turns with the drum (sticks,
  // 0.0286° per ms) until the friction gives way, where it falls behind (it still rises for a
  // while, decelerating): the angle where it first lags by more than 10 % of the drum's turn.
  const double per_ms = 0.5e-3 * 180 / kPi;
  double prev = 0, slip = -1;
  Dump path("square_in_drum_turning", "t,angle_deg,drum_deg");
  for (int ms = 1; ms <= 1500 && slip < 0; ++ms) {
    for (int s = 0; s < 500; ++s) sim.step();
    const Vec3 x = sim.particles().x()[0];
    const double a = std::atan2(x.x, -x.y) * 180 / kPi;
    path.row(1e-3 * ms, a, per_ms * ms);
    if (a > 5 && a - prev < 0.9 * per_ms) slip = prev;
    prev = a;
  }
  // Past the slip angle θ_s the square decelerates against the drum at g (sin θ - μ cos θ)
  // ≈ g c (θ - θ_s), c = cos θ_s + μ sin θ_s, with θ - θ_s ≈ ω t: it lags by ½ g c ω t², which
  // reaches 10 % of the drum's speed ω Rd after t = sqrt(0.2 Rd / (g c)), a turn of ω t later.
  const double mu = 0.5, omega = 0.5;
  const double slip_angle = std::atan(mu) + mu * half / big;
  const double c_s = std::cos(slip_angle) + mu * std::sin(slip_angle);
  const double late = omega * std::sqrt(0.2 * big / (kG * c_s));
  const double want = (slip_angle + late) * 180 / kPi;
  std::printf(
      "square in a turning drum: lags by 10 %% at %.3f deg (expected %.3f: tan = mu "
      "%.3f, load shift %.3f, lag %.3f deg)\n",
      slip, want, std::atan(mu) * 180 / kPi, mu * half / big * 180 / kPi, late * 180 / kPi);
  // 0.5°: the estimate of the load shift (0.25°) and of the lag (linearised) are approximate.
  EXPECT_NEAR(slip, want, 0.5);
  Dump dump("square_in_drum_slip", "lag_angle_deg,expected_deg,friction_angle_deg");
  dump.row(slip, want, std::atan(mu) * 180 / kPi);
}
