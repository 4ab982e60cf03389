// SPDX-License-Identifier: GPL-3.0-or-later
// Convective heat transfer between grains and the fluid of unresolved CFD-DEM
// (coupling.heat_transfer; coupling/cfd_dem/heat_transfer.hpp, fluid/fv/heat_transport.hpp),
// through the full coupled Simulation (case text -> parser -> Simulation):
//
// 1. A hot glass bead (d = 2 mm, 400 K) held fixed in a closed box of water at rest (300 K): no
//    slip, so both correlations give Nu = 2 (conduction into an infinite still fluid), and the
//    bead cools as T_f + (T_0 - T_f) exp(-t / tau), tau = m c / (2 pi k_f d). The water of the
//    bead's 2 cm cell holds 4000 times the bead's heat capacity, so the fluid it reads warms by
//    < 0.03 % of the difference; the run's energy (bead + water) is conserved.
// 2. The same bead in a stream of air (0.25, 1 and 4 m/s, 300 K, through an inlet and an
//    outlet): Re = 33, 133 and 533, Pr = 0.70; the bead's rate of cooling relative to the air it
//    reads gives back the Nu of the correlation at the air speed it reads, to 2e-5 (0.1 %
//    allowed, argued in the test). With GF_VALIDATION_OUT set both write their curves
//    (docs/validation/make_heat_plots.py).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "dump.hpp"
#include "io/input/parse_case.hpp"
#include "io/input/validate.hpp"
#include "simulation/cfd_dem_coupling.hpp"
#include "simulation/simulation.hpp"

using namespace gf;
using gf::test::Dump;

namespace {

constexpr double pi = std::numbers::pi;
constexpr double d = 0.002, rho_p = 2500, c_p = 800;
const double mc = rho_p * pi * d * d * d / 6 * c_p;  // J/K

/// A case with one fixed glass bead at 400 K in the middle of the box, the fluid block `fluid`
/// and the given heat transfer correlation.
config::Case bead_case(const std::string& box, const std::string& fluid, const std::string& law,
                       double t_end) {
  const std::string text = "time: {step: 1.0e-4, end: " + std::to_string(t_end) + "}\n" + box +
                           R"(gravity: [0, 0, 0]
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3, thermal_conductivity: 1,
          heat_capacity: 800}
contacts:
  - {between: [glass, glass], model: hertz_mindlin, restitution: 0.5}
heat: {temperature: 400}
particles:
  - {shape: sphere, radius: 0.001, material: glass, fixed: true, positions: [[0.05, 0.03, 0.03]]}
)" + fluid + "coupling: {drag: schiller_naumann, interval: 10, heat_transfer: " +
                           law + "}\n";
  auto cfg = input::load_case_text(text, "bead.yaml");
  input::validate(cfg);
  return cfg;
}

double bead_temperature(const Simulation& sim) {
  return sim.particles().get<double>(sim.particles().find_field("temperature"))[0];
}
double fluid_at_bead(const Simulation& sim) {
  return sim.particles().get<double>(sim.particles().find_field("fluid_temperature"))[0];
}

}  // namespace

TEST(CfdDemHeatValidation, BeadInStillWaterCoolsAtNusseltTwo) {
  for (const char* law : {"ranz_marshall", "gunn"}) {
    // Water: rho c = 4.18e6 J/(m^3 K), k = 0.6 W/(m K): tau = mc / (2 pi k d) = 1.11 s.
    const auto cfg =
        bead_case("domain: {min: [0, 0, 0], max: [0.1, 0.06, 0.06]}\n",
                  "fluid: {density: 1000, viscosity: 1.0e-3, cells: [5, 3, 3], heat_capacity: "
                  "4180, thermal_conductivity: 0.6, temperature: 300}\n",
                  law, 0.5);
    Simulation sim(cfg);
    const double tau = mc / (2 * pi * 0.6 * d);
    // Energy of bead and water, with the heat the water has given and the bead not yet taken.
    const auto energy = [&] {
      return mc * bead_temperature(sim) + sim.quantity("fluid_thermal_energy") +
             sim.cfd_dem()->heat_in_transit(sim.particles());
    };
    const double e0 = energy();
    Dump curve(std::string("cfd_dem_heat_bead_water_") + law, "t,temperature,exact");
    for (int k = 1; k <= 50; ++k) {
      while (sim.time() < 0.01 * k - 1e-9) sim.step();
      curve.row(sim.time(), bead_temperature(sim), 300 + 100 * std::exp(-sim.time() / tau));
    }
    const double t = sim.time();
    const double expect = 300 + 100 * std::exp(-t / tau);
    const double got = bead_temperature(sim);
    const double e1 = energy();
    std::printf(
        "%s: bead %.6f K after %.3f s, exact (T_f = 300 K) %.6f K (%+.3g K); fluid at "
        "the bead %.5f K; energy change %.3g J of %.3g J exchanged\n",
        law, got, t, expect, got - expect, fluid_at_bead(sim), e1 - e0, mc * (400 - got));
    // Tolerance 0.1 K of the 36 K drop: the water the bead reads warms by its heat over the
    // heat capacity of the water around it, 0.3 J over (at least) the bead's cell's 33 J/K,
    // < 0.01 K (the printed fluid temperature), and the explicit Euler steps err by dt / (2 tau)
    // = 5e-5 relative per tau.
    EXPECT_NEAR(got, expect, 0.1) << law;
    // Energy: the fluid takes its side implicitly over each fluid step at the bead's
    // temperature then, the bead gives h A (T_f - T_p) at its current one; the difference (1e-3
    // of the exchange per step here) returns to the fluid at the next step, so bead + water +
    // the heat in transit is conserved to round-off: the water's 4.5e5 J summed over 45 cells
    // (1e-16 relative, 5e-11 J per sum) and its temperature changes solved to 1e-12 of
    // themselves; 1e-6 of the 0.3 J exchanged leaves a wide margin and still catches a lost
    // correction (3e-4 of it after 0.5 s).
    EXPECT_NEAR(e1, e0, 1e-6 * mc * (400 - got)) << law;
  }
}

TEST(CfdDemHeatValidation, BeadInAnAirStreamCoolsAtTheCorrelationsRate) {
  const double rho_f = 1.2, mu = 1.8e-5, k_f = 0.026, cp_f = 1005, t_in = 300;
  const double pr = cp_f * mu / k_f;
  // The bead's cell: fluid fraction 1 - V_p / V_cell (the bead lies inside one 2 cm cell).
  const double eps = 1 - pi * d * d * d / 6 / (0.02 * 0.02 * 0.02);
  const auto ranz_marshall = [&](double re) { return 2 + 0.6 * std::sqrt(re) * std::cbrt(pr); };
  const auto gunn = [&](double re) {
    const double re_e = eps * re;
    return (7 - 10 * eps + 5 * eps * eps) * (1 + 0.7 * std::pow(re_e, 0.2) * std::cbrt(pr)) +
           (1.33 - 2.4 * eps + 1.2 * eps * eps) * std::pow(re_e, 0.7) * std::cbrt(pr);
  };
  Dump dump("cfd_dem_heat_bead_air", "law,speed,re,nu,correlation");
  for (const char* law : {"ranz_marshall", "gunn"})
    for (const double speed : {0.25, 1.0, 4.0}) {
      const std::string u = std::to_string(speed);
      const double window = std::max(0.2, 10 * 0.02 / speed);  // s
      const auto cfg = bead_case(
          "domain: {min: [0, 0, 0], max: [0.1, 0.06, 0.06], periodic: [false, true, true]}\n",
          "fluid:\n  density: 1.2\n  viscosity: 1.8e-5\n  cells: [5, 3, 3]\n  heat_capacity: "
          "1005\n  thermal_conductivity: 0.026\n  temperature: 300\n  initial_velocity: [" +
              u + ", 0, 0]\n  boundary: {xmin: {velocity_inlet: [" + u +
              ", 0, 0], temperature: 300}, xmax: "
              "{pressure_outlet: 0}}\n",
          law, 2 * window);
      Simulation sim(cfg);
      // The rate of T_p - T_f, T_f the air the bead reads, over the second half of the run, once
      // the air of the bead's cell has settled: it follows the bead in h / U (0.08 s at 0.25
      // m/s), and the window starts after 10 such times.
      while (sim.time() < window - 1e-9) sim.step();
      const double t1 = sim.time(), diff1 = bead_temperature(sim) - fluid_at_bead(sim);
      while (sim.time() < 2 * window - 1e-9) sim.step();
      const double t2 = sim.time(), diff2 = bead_temperature(sim) - fluid_at_bead(sim);
      // The bead warms the air of its cell by beta (T_p - T_f) (its heat over the air's heat flow
      // through the cell), and that air cools with the bead, so T_p - T_f decays at
      // h A / (m c) / (1 + beta): beta = 0.28 % here, taken from the run.
      const double beta = (fluid_at_bead(sim) - t_in) / diff2;
      const double rate = std::log(diff1 / diff2) / (t2 - t1) * (1 + beta);
      const double nu = rate * mc / (k_f * pi * d);
      // The correlation at the air speed the bead reads (0.18 % below the inflow's: the cell's
      // share of the bead's drag).
      const Vec3 u_seen =
          sim.particles().get<Vec3>(sim.particles().find_field("fluid_velocity"))[0];
      const double re = rho_f * norm(u_seen) * d / mu;
      const double expect = std::string(law) == "gunn" ? gunn(re) : ranz_marshall(re);
      std::printf(
          "%s: Re = %.5g (air at the bead %.5f m/s), Pr = %.4g, beta = %.3g: Nu from the "
          "cooling rate %.5f, correlation %.5f (%+.3f %%)\n",
          law, re, norm(u_seen), pr, beta, nu, expect, 100 * (nu / expect - 1));
      // Tolerance 0.1 %: Re is read after the run, and the air speed at the bead drifts by
      // < 1e-4 over it (its deficit is set up within a flow-through time, 0.1 s); beta is the
      // quasi-steady share, exact to its own change over the interval (< 1e-3 of 0.28 %); the
      // explicit Euler steps add dt / (2 tau) = 1e-5. A wrong surface (A = pi d^2 / 4) or
      // diameter in Nu would be off by factors, a Re without the slip by 70 %.
      EXPECT_NEAR(nu, expect, 1e-3 * expect) << law << " at " << speed << " m/s";
      dump.row(std::string(law) == "gunn" ? 1 : 0, speed, re, nu, expect);
    }
}
