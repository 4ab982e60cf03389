// SPDX-License-Identifier: GPL-3.0-or-later
// Discharge of a 2D flat-bottomed silo through an orifice, against Hagen's and Beverloo's laws:
// the mass flow rate does not depend on the fill height, and W = C rho_b sqrt(g) (D - k d)^{3/2}
// (per depth t of the layer) with k ~ 1.5. The grains that fall through the orifice are taken by
// an outlet below the floor (Simulation's outlets), whose tally gives the rate.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "case_builder.hpp"
#include "dump.hpp"
#include "fit.hpp"
#include "simulation/simulation.hpp"

using namespace gf;
using gf::test::Dump;

namespace {

constexpr double kG = 9.81;
constexpr double kRho = 2500;     // glass, kg/m^3
constexpr double kDepth = 0.002;  // domain.thickness, m
constexpr double kD = 0.002;      // mean grain diameter (radii uniform in [0.8, 1.2] mm), m
constexpr double kHalf = 0.04;    // silo half width (silo width 40 d), m
constexpr double kOpen = 0.3;     // the gate under the floor opens at this time, s

/// The silo: a bed of disks (hexagonal fill of `count` sites at most, ~1700 grains for 2000) on
/// a floor of fixed disks (r = 1 mm, touching) with a gap of D between the two middle ones'
/// edges; a gate (plane) under the floor holds the grains until kOpen, then drops away; side
/// walls at +-kHalf. The outlet 1 cm under the floor puts the grains back at rest in a layer
/// above the bed, which keeps its height: a steady flow.
config::Case silo_case(double orifice, std::int64_t count) {
  const double r = 0.001, top = 0.12;
  auto c = test::base_case(1.5e-5, 2.0, {-kHalf - 0.01, -0.03, 0}, {kHalf + 0.01, top + 0.02, 0});
  c.dimension = 2;
  c.domain.thickness = kDepth;
  c.gravity = {0, -kG, 0};
  test::add_material(c, "glass", kRho, 1e8, 0.3);
  // Soft linear springs (contact time 0.22 ms, 15 steps): the overlap under the bed's weight
  // stays below 0.5 % of d, and the rate does not depend on the stiffness there.
  test::add_contact(c, "glass", "glass", "hooke",
                    {{"stiffness", 1e3}, {"restitution", 0.5}, {"friction", 0.5}});
  auto& f = test::add_box_fill(c, "glass", 0.0008, 0.0012, {-kHalf, 0.001, 0}, {kHalf, top, 0},
                               config::Fill::Lattice::Hcp);
  f.spacing = 0.0025;
  f.count = count;
  f.velocity_jitter = 0.05;
  f.seed = 2;
  c.particles.back().shape = "disk";
  c.particles.back().kind = config::Shape::Disk;
  std::vector<Vec3> floor;
  for (double x = 0.5 * orifice + r; x <= kHalf - r + 1e-12; x += 2 * r) {
    floor.push_back({-x, 0, 0});
    floor.push_back({x, 0, 0});
  }
  test::add_disks(c, "glass", r, floor).fixed = true;
  test::add_plane(c, "left", {-kHalf, 0, 0}, {1, 0, 0}, "glass");
  test::add_plane(c, "right", {kHalf, 0, 0}, {-1, 0, 0}, "glass");
  test::add_plane(c, "gate", {0, 0, 0}, {0, 1, 0}, "glass");
  c.walls.back().motion.velocity = {0, -2, 0};
  c.walls.back().motion.start = kOpen;
  test::add_outlet(c, "below",
                   test::box_region({-kHalf - 0.01, -0.03, 0}, {kHalf + 0.01, -0.01, 0}))
      .reinsert = test::box_region({-kHalf, top - 0.015, 0}, {kHalf, top + 0.015, 0});
  // A flow meter just under the floor, across the orifice and the floor grains beside it.
  config::FlowMeter meter;
  meter.name = "orifice";
  meter.point = {0, -0.002, 0};
  meter.normal = {0, -1, 0};
  meter.radius = 0.5 * orifice + 4 * r;
  c.flow_meters.push_back(meter);
  return c;
}

struct Discharge {
  double rate = 0;            // kg/s over the window
  double first = 0;           // ... over its first half
  double second = 0;          // ... and its second half
  double solid_fraction = 0;  // of the settled bed before the gate opens
  double height = 0;          // of the settled bed (its highest grain), m
  double meter_rate = 0;      // kg/s over the window, from the flow meter under the orifice
};

/// Runs the silo with orifice D; the rate is the slope of the outlet's mass against time from
/// 0.2 s after the gate opened (the flow has set in) to 1.2 s.
Discharge discharge(double orifice, std::int64_t count, Dump& curve) {
  Simulation sim(silo_case(orifice, count));
  const double dt = sim.dt();
  const auto steps_to = [dt](double t) { return static_cast<std::int64_t>(std::llround(t / dt)); };
  while (sim.step_count() < steps_to(kOpen)) sim.step();
  Discharge out;
  {
    // Solid fraction of the bed: disk areas of the grains whose centre lies in a window of the
    // bed's middle (away from the floor, the walls and the surface), over the window's area.
    const auto& p = sim.particles();
    const double x0 = -0.03, x1 = 0.03, y0 = 0.01, y1 = 0.03;
    double area = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vec3 x = p.x()[i];
      out.height = std::max(out.height, x.y);
      if (x.x > x0 && x.x < x1 && x.y > y0 && x.y < y1)
        area += std::numbers::pi * p.radius()[i] * p.radius()[i];
    }
    out.solid_fraction = area / ((x1 - x0) * (y1 - y0));
  }
  std::vector<double> t, m, mm;
  const std::int64_t every = steps_to(0.01);
  while (sim.step_count() < steps_to(1.2)) {
    sim.step();
    if (sim.step_count() % every != 0) continue;
    const double now = sim.time(), mass = sim.outlet_tallies()[0].mass;
    curve.row(orifice / kD, static_cast<double>(count), now, mass);
    if (now < kOpen + 0.2 - 1e-9) continue;
    t.push_back(now);
    m.push_back(mass);
    mm.push_back(sim.flow_meter_tallies()[0].mass);
  }
  const std::size_t h = t.size() / 2;
  out.rate = test::least_squares_slope(t, m);
  out.meter_rate = test::least_squares_slope(t, mm);
  out.first = test::least_squares_slope({t.begin(), t.begin() + h}, {m.begin(), m.begin() + h});
  out.second = test::least_squares_slope({t.begin() + h, t.end()}, {m.begin() + h, m.end()});
  return out;
}

}  // namespace

// Four orifices, D = 6, 8, 10, 12 grain diameters (D the gap between the floor grains' edges),
// in steady flow (the grains that leave are put back on top) over 0.7 s: 500-2500 grains.
//
// The noise: a 2D orifice flow is intermittent (arches form and break); the rate over windows of
// 0.35 s of one long run (cases/dem2d/silo, D = 8 d, 2 s) scatters by 2.3 % (standard
// deviation), so by ~1.6 % over the 0.7 s window; the tolerances below are ~3 standard
// deviations of what they compare.
//
// Steadiness: the window's two halves must agree within 10 % (their difference: 3.3 %).
//
// Hagen: the rate does not depend on the fill height once the bed is a few orifices high (the
// walls carry its weight, Janssen): the D = 8 d silo with half the grains (the bed 0.65 silo
// widths high instead of 1.05) must discharge at the same rate within 7 % (2.3 %).
//
// Beverloo, 2D: W = C rho_b sqrt(g) t (D - k d)^{3/2}. The exponent is dimensional analysis,
// once the rate depends on neither the height nor the width: W / (rho_b t) is an area per time,
// sqrt(g) L^{3/2}. So W^{2/3} must be linear in D: the four rates must lie within 5 % of the
// line fitted through them (1.6 %), and the "empty annulus" k of that line must lie in
// Beverloo's 1-2 (1.5 the usual value for round grains; the noise moves k by ~0.15). A rate
// scaling with another power of D than 3/2 shifts that line: (D - 1.5 d)^1 gives k = -2.0,
// (D - 1.5 d)^2 gives k = 3.2 over these orifices. (A free fit of the exponent is not asked for:
// over a factor 2 in D it trades n against k, n = 1.8 at k = 0.2 fitting these rates as well as 1.5
// at 1.57; with 3/2 fixed, a wrong scaling shows as k outside 1-2.) C is reported against the
// free-fall-arch estimate: grains falling freely from an arch of radius D/2 leave at
// sqrt(g D (1 - 4x^2/D^2)) across the orifice, so with the bed's density there C = pi/4 = 0.79,
// and 1 with a flat profile; the dilation at the orifice lowers it, the push of the grains above
// raises it, so the test bounds C to [0.6, 1.4] only.
TEST(ValidationSilo, DischargeRateFollowsHagenAndBeverloo) {
  Dump curve("silo_discharge", "D_over_d,count,t,mass");
  Dump table("silo_rates", "D_over_d,count,rate,first,second,solid_fraction,height,meter_rate");
  const std::vector<double> ratios{6, 8, 10, 12};
  std::vector<double> rate;
  double phi = 0;
  for (const double q : ratios) {
    const Discharge r = discharge(q * kD, 2000, curve);
    std::printf(
        "D = %2.0f d: W = %.4f g/s (halves %.4f, %.4f; flow meter %.4f), solid fraction %.4f, "
        "bed %.1f mm\n",
        q, 1e3 * r.rate, 1e3 * r.first, 1e3 * r.second, 1e3 * r.meter_rate, r.solid_fraction,
        1e3 * r.height);
    table.row(q, 2000, r.rate, r.first, r.second, r.solid_fraction, r.height, r.meter_rate);
    EXPECT_NEAR(r.second / r.first, 1.0, 0.10) << "D = " << q << " d";
    // The flow meter 2 mm under the floor counts the grains the outlet takes 8-28 mm lower,
    // a few milliseconds earlier: in steady flow the two slopes differ only by the change of
    // the grains in flight between them over the window (a few of ~1000-3000 grains: 0.3 %).
    EXPECT_NEAR(r.meter_rate / r.rate, 1.0, 0.01) << "D = " << q << " d";
    rate.push_back(r.rate);
    phi += r.solid_fraction / static_cast<double>(ratios.size());
  }
  const Discharge low = discharge(8 * kD, 1000, curve);
  std::printf("D =  8 d, half the grains: W = %.4f g/s (bed %.1f mm): %.4f of the full silo's\n",
              1e3 * low.rate, 1e3 * low.height, low.rate / rate[1]);
  table.row(8, 1000, low.rate, low.first, low.second, low.solid_fraction, low.height,
            low.meter_rate);
  EXPECT_NEAR(low.rate / rate[1], 1.0, 0.07);
  // W^{2/3} = a D + b: k = -b / (a d), C = a^{3/2} / (rho_b sqrt(g) t).
  const std::size_t n = ratios.size();
  std::vector<double> dd(n), w23(n);
  for (std::size_t i = 0; i < n; ++i) {
    dd[i] = ratios[i] * kD;
    w23[i] = std::pow(rate[i], 2.0 / 3.0);
  }
  const double a = test::least_squares_slope(dd, w23);
  double b = 0;
  for (std::size_t i = 0; i < n; ++i) b += (w23[i] - a * dd[i]) / static_cast<double>(n);
  const double k = -b / (a * kD);
  const double c = std::pow(a, 1.5) / (phi * kRho * std::sqrt(kG) * kDepth);
  for (std::size_t i = 0; i < n; ++i)
    EXPECT_NEAR(rate[i] / std::pow(a * dd[i] + b, 1.5), 1.0, 0.05) << "D = " << ratios[i] << " d";
  std::printf("Beverloo: k = %.3f, C = %.3f (solid fraction %.4f)\n", k, c, phi);
  EXPECT_GT(k, 1.0);
  EXPECT_LT(k, 2.0);
  EXPECT_GT(c, 0.6);
  EXPECT_LT(c, 1.4);
}
