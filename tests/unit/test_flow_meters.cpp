// SPDX-License-Identifier: GPL-3.0-or-later
// Flow meters: the net number and mass of grains whose centres cross a plane (within a radius),
// against trajectories known in closed form; periodic wraps, outlets that put grains back,
// restarts and the series quantities. Regions: the grains in them, against a brute force.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "case_builder.hpp"
#include "simulation/simulation.hpp"
#include "state_compare.hpp"
#include "temp_dir.hpp"

using namespace gf;

namespace {

config::FlowMeter& add_meter(config::Case& c, const std::string& name, Vec3 point, Vec3 normal,
                             std::optional<double> radius = std::nullopt) {
  config::FlowMeter f;
  f.name = name;
  f.point = point;
  f.normal = normal;
  f.radius = radius;
  c.flow_meters.push_back(f);
  return c.flow_meters.back();
}

double sphere_mass(double r, double rho) {
  return rho * 4.0 / 3.0 * M_PI * r * r * r;
}

/// 3D, no walls: a 5 x 5 square of spheres (r 1 mm, 10 mm apart, never touching) at z = 0.05
/// falls freely through the horizontal planes of the meters.
config::Case rain_case() {
  auto c = test::base_case(1e-4, 1.0, {-0.05, -0.05, -0.2}, {0.05, 0.05, 0.1});
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin", {{"restitution", 0.5}});
  std::vector<Vec3> x;
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j) x.push_back({0.01 * i, 0.01 * j, 0.05});
  test::add_spheres(c, "glass", 0.001, x);
  return c;
}

}  // namespace

// Every falling grain crosses a plane below it once: the meter along the fall counts them all
// (+25), one facing up counts them negatively, one with a radius counts only the grains within
// it (a disk of 15 mm about the axis: the central 3 x 3, whose corners are 14.1 mm out), and a
// plane the grains never reach counts none.
TEST(FlowMeters, CountEveryGrainThatFallsThroughOnce) {
  auto c = rain_case();
  add_meter(c, "down", {0, 0, 0}, {0, 0, -1});
  add_meter(c, "up", {0, 0, 0}, {0, 0, 1});
  add_meter(c, "disk", {0, 0, -0.02}, {0, 0, -1}, 0.015);
  add_meter(c, "deep", {0, 0, -0.19}, {0, 0, -1});
  Simulation sim(c);
  // z(t) = 0.05 - g t^2 / 2 reaches -0.02 at t = 0.119 s and -0.19 at 0.221 s: run to 0.15 s.
  for (int s = 0; s < 1500; ++s) sim.step();
  const auto t = sim.flow_meter_tallies();
  ASSERT_EQ(t.size(), 4u);
  const double m = sphere_mass(0.001, 2500);
  EXPECT_EQ(t[0].count, 25);
  EXPECT_NEAR(t[0].mass, 25 * m, 1e-12 * m);
  EXPECT_EQ(t[1].count, -25);
  EXPECT_NEAR(t[1].mass, -25 * m, 1e-12 * m);
  int inside = 0;  // brute force: the grains falling straight down within the disk's radius
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j)
      if (std::hypot(0.01 * i, 0.01 * j) <= 0.015) ++inside;
  EXPECT_EQ(inside, 9);
  EXPECT_EQ(t[2].count, inside);
  EXPECT_EQ(t[3].count, 0);
}

// A grain thrown up through a plane and falling back through it: +1 on the way up, -1 on the
// way down along an upward normal (net 0 at the end), with the crossing times of the parabola.
TEST(FlowMeters, CountNetCrossingsBothWays) {
  auto c = test::base_case(1e-4, 1.0, {-0.05, -0.05, -0.1}, {0.05, 0.05, 0.2});
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin", {{"restitution", 0.5}});
  test::add_spheres(c, "glass", 0.001, {{0, 0, 0}}, {{0, 0, 1.0}});
  add_meter(c, "level", {0, 0, 0.03}, {0, 0, 1});
  Simulation sim(c);
  // z = t - 4.905 t^2 crosses 0.03 going up at t = 0.0335 s and down at 0.1704 s.
  std::vector<std::int64_t> counts;
  for (int s = 0; s < 2000; ++s) {
    sim.step();
    counts.push_back(sim.flow_meter_tallies()[0].count);
  }
  const double g = 9.81, disc = std::sqrt(1.0 - 2 * g * 0.03);
  const double t_up = (1.0 - disc) / g, t_down = (1.0 + disc) / g;
  for (std::size_t s = 0; s < counts.size(); ++s) {
    const double t = 1e-4 * static_cast<double>(s + 1);
    if (std::abs(t - t_up) < 2e-4 || std::abs(t - t_down) < 2e-4) continue;  // the steps at them
    EXPECT_EQ(counts[s], (t > t_up && t < t_down) ? 1 : 0) << "t = " << t;
  }
}

// Periodic: a grain moving along x at 1 m/s through a periodic box 0.1 m long crosses a meter in
// the middle and one on the periodic boundary once per pass (10 per second), and a wrap is no
// crossing for a meter it does not pass.
TEST(FlowMeters, PeriodicWrapsAreShortSteps) {
  auto c = test::base_case(1e-4, 1.0, {0, 0, 0}, {0.1, 0.05, 0.05}, {true, false, false});
  c.gravity = {0, 0, 0};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin", {{"restitution", 0.5}});
  test::add_spheres(c, "glass", 0.001, {{0.0255, 0.025, 0.025}}, {{1.0, 0, 0}});
  add_meter(c, "middle", {0.05, 0, 0}, {1, 0, 0});
  add_meter(c, "boundary", {0.0, 0, 0}, {1, 0, 0});
  add_meter(c, "other_end", {0.1, 0, 0}, {-1, 0, 0});
  Simulation sim(c);
  for (int s = 0; s < 3500; ++s) sim.step();  // x from 0.0255 to 0.3755: 3 wraps, 4 middles
  const auto t = sim.flow_meter_tallies();
  EXPECT_EQ(t[0].count, 4);
  EXPECT_EQ(t[1].count, 3);
  EXPECT_EQ(t[2].count, -3);  // the same plane as "boundary", normal reversed
}

// An outlet that puts the grains back above the meter: the jump up is no crossing, so each grain
// has crossed the meter once per time it was taken, plus once if it is below the meter now.
TEST(FlowMeters, GrainsPutBackByAnOutletDoNotCountTheJump) {
  auto c = rain_case();
  add_meter(c, "mid", {0, 0, -0.05}, {0, 0, -1});
  auto& o = test::add_outlet(c, "pit", test::box_region({-0.05, -0.05, -0.2}, {0.05, 0.05, -0.15}));
  o.reinsert = test::box_region({-0.05, -0.05, 0.06}, {0.05, 0.05, 0.09});
  Simulation sim(c);
  for (int s = 0; s < 6000; ++s) sim.step();  // 0.6 s: each grain goes round about twice
  const auto& p = sim.particles();
  std::int64_t below = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.x()[i].z < -0.05) ++below;
  const auto taken = sim.outlet_tallies()[0].count;
  EXPECT_GT(taken, 30);
  EXPECT_EQ(sim.flow_meter_tallies()[0].count, taken + below);
}

// A run continued from a checkpoint counts as the uninterrupted one: the tallies, and
// flow_rate (the net mass per time since the previous series row, whose mark the checkpoint
// keeps); the rate is the difference quotient of flow_mass between rows.
TEST(FlowMeters, RestartContinuesTheTalliesAndTheRate) {
  auto c = rain_case();
  add_meter(c, "mid", {0, 0, -0.05}, {0, 0, -1});
  auto& o = test::add_outlet(c, "pit", test::box_region({-0.05, -0.05, -0.2}, {0.05, 0.05, -0.15}));
  o.reinsert = test::box_region({-0.05, -0.05, 0.06}, {0.05, 0.05, 0.09});
  test::TempDir dir;
  const auto file = dir.path() / "meters.h5";
  // Rows every 300 steps; the checkpoint at step 1500, right after its row (as run() saves it),
  // in which the first grains have crossed (at t = 0.143 s).
  const auto rows = [](Simulation& sim, int from, int to, std::vector<std::vector<double>>& out) {
    for (int s = from; s < to; ++s) {
      sim.step();
      if ((s + 1) % 300 == 0) {
        out.push_back({sim.quantity("flow_mass.mid"), sim.quantity("flow_count.mid"),
                       sim.quantity("flow_rate.mid"), sim.time()});
        sim.series_row_written();
      }
    }
  };
  std::vector<std::vector<double>> a_rows, b_rows;
  Simulation a(c);
  rows(a, 0, 1500, a_rows);
  a.save_checkpoint(file);
  rows(a, 1500, 6000, a_rows);
  Simulation b(c);
  b.load_checkpoint(file);
  // The checkpoint's step had a row: a continued run writes it again, with the same rate.
  EXPECT_EQ(b.quantity("flow_rate.mid"), a_rows[4][2]);
  EXPECT_GT(a_rows[4][2], 0);
  rows(b, 1500, 6000, b_rows);
  ASSERT_EQ(a_rows.size(), 20u);
  ASSERT_EQ(b_rows.size(), 15u);
  for (std::size_t r = 0; r < b_rows.size(); ++r)
    for (std::size_t q = 0; q < 3; ++q) EXPECT_EQ(b_rows[r][q], a_rows[5 + r][q]) << r << " " << q;
  test::expect_same_state(a, b);
  double grew = 0;
  for (std::size_t r = 1; r < a_rows.size(); ++r) {
    const double dm = a_rows[r][0] - a_rows[r - 1][0], dt = a_rows[r][3] - a_rows[r - 1][3];
    EXPECT_NEAR(a_rows[r][2], dm / dt, 1e-9 * std::abs(dm / dt) + 1e-15) << r;
    grew += dm;
  }
  EXPECT_GT(grew, 0);
  EXPECT_GT(a_rows.back()[1], 30);
}

TEST(FlowMeters, TheCudaBackEndRefusesThem) {
  auto c = rain_case();
  add_meter(c, "mid", {0, 0, -0.05}, {0, 0, -1});
  const Simulation sim(c);
  EXPECT_NE(sim.device_unsupported().find("flow meters ('mid'"), std::string::npos);
}

// region_count / region_mass: the free grains whose centres lie in a box or a cylinder, against
// a count over the store; the falling square of grains leaves a low box as it enters a lower one.
TEST(Regions, CountAndMassOfTheGrainsInside) {
  auto c = rain_case();
  config::NamedRegion low, core;
  low.name = "low";
  low.region = test::box_region({-0.05, -0.05, -0.2}, {0.05, 0.05, -0.05});
  core.name = "core";
  core.region.kind = config::Region::Kind::Cylinder;
  core.region.center = {0, 0, -0.2};
  core.region.axis = {0, 0, 1};
  core.region.radius = 0.012;
  core.region.height = 0.3;
  c.regions = {low, core};
  Simulation sim(c);
  const double m = sphere_mass(0.001, 2500);
  EXPECT_EQ(sim.quantity("region_count.low"), 0);
  EXPECT_EQ(sim.quantity("region_count.core"), 5);  // (0, 0), (+-10, 0), (0, +-10) mm
  EXPECT_NEAR(sim.quantity("region_mass.core"), 5 * m, 1e-15);
  for (int s = 0; s < 1500; ++s) sim.step();  // 0.15 s: z = 0.05 - 0.11 = -0.06 m, all in "low"
  const auto& p = sim.particles();
  double n_low = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.x()[i].z < -0.05) n_low += 1;
  EXPECT_EQ(n_low, 25);
  EXPECT_EQ(sim.quantity("region_count.low"), n_low);
  EXPECT_NEAR(sim.quantity("region_mass.low"), 25 * m, 1e-12 * m);
  EXPECT_EQ(sim.quantity("region_count.core"), 5);
}
