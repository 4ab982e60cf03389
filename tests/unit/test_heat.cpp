// SPDX-License-Identifier: GPL-3.0-or-later
// Heat conduction through contacts (contact/conduction.hpp): the conductance models against
// their formulas, the pair and wall passes against a brute force over all pairs, conservation
// and bounds of the grains' temperatures in a settling bed of spheres and of rods, restarts,
// the series quantities, and the instability and back-end refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <vector>

#include "boundaries/wall.hpp"
#include "case_builder.hpp"
#include "contact/conduction.hpp"
#include "contact/pair_forces.hpp"
#include "core/error.hpp"
#include "input_error.hpp"
#include "io/input/echo.hpp"
#include "io/input/parse_case.hpp"
#include "simulation/simulation.hpp"
#include "state_compare.hpp"
#include "temp_dir.hpp"

using namespace gf;

namespace {

constexpr double pi = std::numbers::pi;

/// 3D box 20 x 20 x 40 mm with adiabatic walls; 4 x 4 x 4 spheres (r 1.5 mm) of glass, the
/// lower half at 400 K and the upper at 300 K, fall onto the floor and settle.
config::Case bed_case(double end = 0.05) {
  auto c = test::base_case(2e-6, end, {0, 0, 0}, {0.02, 0.02, 0.04});
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  c.materials.back().thermal_conductivity = 1.0;
  c.materials.back().heat_capacity = 0.5;  // (small: the temperatures move within the test)
  test::add_contact(c, "glass", "glass", "hertz_mindlin", {{"restitution", 0.5}});
  for (int layer = 0; layer < 2; ++layer) {
    std::vector<Vec3> x;
    for (int k = 0; k < 2; ++k)
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
          x.push_back({0.0025 + 0.005 * i, 0.0025 + 0.005 * j,
                       0.0016 + 0.0031 * (2 * layer + k) + 0.0001 * ((i + j) % 2)});
    test::add_spheres(c, "glass", 0.0015, x);
    c.particles.back().temperature = layer == 0 ? 400 : 300;
  }
  config::Wall box;
  box.name = "box";
  box.kind = config::Wall::Kind::Box;
  box.min = {0, 0, 0};
  box.max = {0.02, 0.02, 0.04};
  box.material = "glass";
  c.walls.push_back(box);
  config::Heat h;
  h.temperature = 350;
  c.heat = h;
  c.output.quantities = {"temperature_mean", "temperature_min", "temperature_max",
                         "thermal_energy"};
  return c;
}

}  // namespace

TEST(HeatConduction, ConductanceModelsFollowTheirFormulas) {
  const double delta = 2e-6, r_eff = 5e-4, ki = 1.0, kj = 3.0;
  const double a = std::sqrt(r_eff * delta);
  const double bob =
      contact::contact_conductance(contact::conduction_index("batchelor_obrien"), delta, r_eff,
                                   contact::series_conductivity(ki, kj));
  EXPECT_NEAR(bob, 4 * a * ki * kj / (ki + kj), 1e-15);
  EXPECT_NEAR(contact::contact_conductance(0, delta, r_eff, contact::series_conductivity(2, 2)),
              2 * 2.0 * a, 1e-15);
  // LIGGGHTS' form: 4 k_i k_j / (k_i + k_j) sqrt(A), A = pi a_g^2 with a_g^2 = 2 R* delta.
  const double ia =
      contact::contact_conductance(contact::conduction_index("intersection_area"), delta, r_eff,
                                   contact::series_conductivity(ki, kj));
  EXPECT_NEAR(ia, 4 * ki * kj / (ki + kj) * std::sqrt(pi * 2 * r_eff * delta), 1e-15);
  EXPECT_EQ(contact::conduction_index("none"), -1);
  EXPECT_EQ(contact::find_conduction("none"), nullptr);
  ASSERT_NE(contact::find_conduction("intersection_area"), nullptr);
  EXPECT_EQ(contact::conduction_infos().size(), 2u);
}

// The passes over the Verlet list and the wall list against a brute force over every pair of a
// settled bed with a hot floor: each grain's heat flow and conductance sum, to round-off.
TEST(HeatConduction, PairAndWallFlowsMatchABruteForce) {
  auto c = bed_case();
  Simulation sim(c);
  for (int s = 0; s < 15000; ++s) sim.step();
  const auto& p = sim.particles();
  const std::size_t n = p.size();
  const auto& temp = p.get<double>(p.find_field("temperature"));
  std::vector<double> q(n), h(n), entry_h;
  PairTable<double> k(1);
  k(0, 0) = contact::series_conductivity(1.0, 1.0);
  contact::pair_heat_flows(p, sim.domain(), sim.neighbor_list(), 0, k, temp.data(), q.data(),
                           h.data(), entry_h);
  EXPECT_EQ(entry_h.size(), sim.neighbor_list().neighbors().size());
  std::vector<double> q_ref(n), h_ref(n);
  int touching = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      if (i == j) continue;
      const double d = norm(p.x()[i] - p.x()[j]);
      const double ri = p.radius()[i], rj = p.radius()[j];
      if (d >= ri + rj) continue;
      touching += i < j;
      const double hc = 2 * 1.0 * std::sqrt(ri * rj / (ri + rj) * (ri + rj - d));
      q_ref[i] += hc * (temp[j] - temp[i]);
      h_ref[i] += hc;
    }
  ASSERT_GT(touching, 40);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_NEAR(q[i], q_ref[i], 1e-12 * h_ref[i] * 100) << i;
    EXPECT_NEAR(h[i], h_ref[i], 1e-12 * h_ref[i]) << i;
  }
  // The time loop's path: the force loop (its AVX2 and its baseline batch kernel) records each
  // contact's overlap, and the flows from those are the same bits as the pass above.
  for (const bool baseline : {false, true}) {
    contact::use_baseline_kernels(baseline);
    ParticleStore pc = p;
    VerletList lc = sim.neighbor_list();
    std::vector<double> overlaps(lc.neighbors().size(), 0.0);
    contact::ContactSink sink;
    sink.overlaps = overlaps.data();
    contact::compute_pair_forces(pc, sim.domain(), lc, sim.pairs(), 1e-6, &sink);
    contact::use_baseline_kernels(false);
    std::vector<double> q2(n), h2(n);
    contact::pair_heat_flows_from_overlaps(p, sim.neighbor_list(), 0, k, temp.data(),
                                           overlaps.data(), q2.data(), h2.data());
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_EQ(q2[i], q[i]) << i << (baseline ? " (baseline kernel)" : " (AVX2 kernel)");
      EXPECT_EQ(h2[i], h[i]) << i;
    }
  }
  // A floor at 500 K: each grain on it gets 2 k sqrt(r delta) (500 - T).
  std::vector<Wall> walls(sim.walls().begin(), sim.walls().end());
  std::size_t floor = walls.size();
  for (std::size_t w = 0; w < walls.size(); ++w)
    if (walls[w].name == "box.zmin") floor = w;
  ASSERT_LT(floor, walls.size());
  walls[floor].temperature = 500;
  std::vector<double> qw(n), hw(n);
  wall_heat_flows(p, walls, sim.wall_list(), 0, k, temp.data(), qw.data(), hw.data());
  double into_floor = 0;
  int on_floor = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double delta = p.radius()[i] - p.x()[i].z;
    const double hc = delta > 0 ? 2 * std::sqrt(p.radius()[i] * delta) : 0.0;
    on_floor += delta > 0;
    EXPECT_NEAR(qw[i], hc * (500 - temp[i]), 1e-12 * (hc * 200 + 1e-30)) << i;
    into_floor -= hc * (500 - temp[i]);
  }
  EXPECT_EQ(on_floor, 16);
  EXPECT_NEAR(walls[floor].heat_flow, into_floor, 1e-12 * std::abs(into_floor));
  for (std::size_t w = 0; w < walls.size(); ++w)
    if (w != floor) {
      EXPECT_EQ(walls[w].heat_flow, 0.0) << walls[w].name << " is adiabatic";
    }
}

// Adiabatic walls: the grains' thermal energy sum m c T stays (each contact's two flows are one
// number of opposite signs) to round-off of the sums, and no temperature leaves [300, 400]
// (each explicit step makes a grain's new temperature a convex combination of its own and its
// neighbours' while dt sum(H) <= m c, which the run checks).
TEST(HeatConduction, ASettlingBedConservesItsHeatWithinTheInitialBounds) {
  auto c = bed_case();
  Simulation sim(c);
  const double e0 = sim.quantity("thermal_energy");
  EXPECT_NEAR(e0, 0.5 * (32 * 400 + 32 * 300) * sim.particles().mass()[0], 1e-12 * e0);
  EXPECT_NEAR(sim.quantity("temperature_mean"), 350, 1e-12 * 350);
  for (int s = 0; s < 25000; ++s) sim.step();
  EXPECT_NEAR(sim.quantity("thermal_energy"), e0, 1e-12 * e0);
  const double lo = sim.quantity("temperature_min"), hi = sim.quantity("temperature_max");
  EXPECT_GE(lo, 300.0);
  EXPECT_LE(hi, 400.0);
  EXPECT_GT(lo, 300.5) << "heat reached the cold half";
  EXPECT_LT(hi, 399.5) << "the hot half lost heat";
}

// A floor at 500 K: the grains' thermal energy grows by exactly the heat the floor gave, the sum
// over the steps of dt times minus its heat flow (wall_heat_flow), to round-off.
TEST(HeatConduction, TheHeatAHotFloorGivesIsTheHeatTheGrainsGain) {
  auto c = bed_case();
  for (auto& w : c.walls) w.temperature = 500;  // (the box: its floor touches; walls too, few)
  c.output.quantities.push_back("wall_heat_flow.box");
  Simulation sim(c);
  const double e0 = sim.quantity("thermal_energy");
  double given = 0;
  for (int s = 0; s < 25000; ++s) {
    sim.step();
    given -= c.time.step * sim.quantity("wall_heat_flow.box");
  }
  EXPECT_GT(given, 0.01 * e0);
  // (round-off: 25000 sums of 64 terms, each step 1e-16 of E, against a gain > 1 % of E)
  EXPECT_NEAR(sim.quantity("thermal_energy") - e0, given, 1e-10 * given);
  EXPECT_LE(sim.quantity("temperature_max"), 500.0);
}

// A heat source heats an isolated grain linearly, m c dT/dt = P, which the explicit steps give
// exactly (to the rounding of the sums); the field heat_flow shows each grain's net flow.
TEST(HeatConduction, AHeatSourceHeatsAnIsolatedGrainLinearly) {
  auto c = test::base_case(1e-5, 1.0, {-0.01, -0.01, -0.01}, {0.01, 0.01, 0.01});
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  c.materials.back().thermal_conductivity = 1.0;
  c.materials.back().heat_capacity = 840;
  test::add_contact(c, "glass", "glass", "hertz_mindlin", {{"restitution", 0.5}});
  test::add_spheres(c, "glass", 0.001, {{-0.005, 0, 0}});
  c.particles.back().heat_source = 2e-3;
  test::add_spheres(c, "glass", 0.001, {{0.005, 0, 0}});  // (no source: stays)
  config::Heat h;
  h.temperature = 300;
  c.heat = h;
  Simulation sim(c);
  const auto& p = sim.particles();
  const double cap = p.mass()[0] * 840;
  for (int s = 0; s < 1000; ++s) sim.step();
  const auto& temp = p.get<double>(p.find_field("temperature"));
  const auto& flow = p.get<double>(p.find_field("heat_flow"));
  for (std::size_t i = 0; i < p.size(); ++i) {
    const bool source = p.id()[i] == 1;
    EXPECT_NEAR(temp[i], source ? 300 + 2e-3 * 0.01 / cap : 300.0, 1e-12 * 300) << i;
    EXPECT_EQ(flow[i], source ? 2e-3 : 0.0) << i;
  }
  EXPECT_NEAR(sim.quantity("thermal_energy"), 2 * cap * 300 + 2e-3 * 0.01, 1e-12 * 600 * cap);
}

// Grains an inlet inserts take their group's temperature (here not the heat block's default).
TEST(HeatConduction, InletGrainsTakeTheirGroupsTemperature) {
  auto c = bed_case();
  config::ParticleGroup g;
  g.material = "glass";
  g.radius.value = 0.001;
  g.temperature = 450;
  config::Inlet in;
  in.region = test::box_region({0, 0, 0.03}, {0.02, 0.02, 0.04});
  in.rate = 2000;
  in.every = 0.01;
  g.inlet = in;
  c.particles.push_back(g);
  Simulation sim(c);
  for (int s = 0; s < 10; ++s) sim.step();
  const auto& p = sim.particles();
  const auto& temp = p.get<double>(p.find_field("temperature"));
  int inserted = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.id()[i] > 64) {
      ++inserted;
      EXPECT_EQ(temp[i], 450.0) << "grain " << p.id()[i];
    }
  EXPECT_GT(inserted, 10);
}

// Spherocylinders conduct through the contacts of their capsules (and with walls): a bed of
// rods conserves its heat too and its temperatures mix.
TEST(HeatConduction, RodsConductThroughTheirContacts) {
  auto c = bed_case();
  for (auto& g : c.particles) {
    g.kind = config::Shape::Spherocylinder;
    g.shape = "spherocylinder";
    g.radius.value = 0.001;
    g.length = 0.002;
  }
  c.time.step = 1e-6;
  Simulation sim(c);
  const double e0 = sim.quantity("thermal_energy");
  for (int s = 0; s < 30000; ++s) sim.step();
  EXPECT_NEAR(sim.quantity("thermal_energy"), e0, 1e-12 * e0);
  EXPECT_GE(sim.quantity("temperature_min"), 300.0);
  EXPECT_LE(sim.quantity("temperature_max"), 400.0);
  // (equal masses: the plain means of the two halves)
  const auto& p = sim.particles();
  const auto& temp = p.get<double>(p.find_field("temperature"));
  double hot = 0, cold = 0;
  for (std::size_t i = 0; i < p.size(); ++i) (p.id()[i] <= 32 ? hot : cold) += temp[i] / 32;
  std::printf("rods: mean of the hot half %.3f K, of the cold half %.3f K\n", hot, cold);
  EXPECT_LT(hot, 398.5);
  EXPECT_GT(cold, 301.5);
  EXPECT_NEAR(hot + cold, 700.0, 1e-9);
}

TEST(HeatConduction, RestartContinuesBitIdentically) {
  test::TempDir tmp;
  auto c = bed_case();
  Simulation a(c);
  for (int s = 0; s < 3000; ++s) a.step();
  a.save_checkpoint(tmp / "c.h5");
  Simulation b(c);
  b.load_checkpoint(tmp / "c.h5");
  for (int s = 0; s < 2000; ++s) {
    a.step();
    b.step();
  }
  test::expect_same_state(a, b);
  EXPECT_EQ(a.quantity("temperature_max"), b.quantity("temperature_max"));
  // A checkpoint of a case without heat lacks the temperatures: refused with the field's name.
  auto cold = bed_case();
  cold.heat.reset();
  for (auto& g : cold.particles) g.temperature.reset();
  Simulation d(cold);
  d.save_checkpoint(tmp / "cold.h5");
  Simulation e(c);
  try {
    e.load_checkpoint(tmp / "cold.h5");
    ADD_FAILURE() << "loaded a checkpoint without temperatures";
  } catch (const Error& err) {
    EXPECT_NE(std::string(err.what()).find("temperature"), std::string::npos) << err.what();
  }
}

// A time step too long for the conductances stops the run before a temperature goes wrong.
TEST(HeatConduction, AnUnstableStepStopsTheRunWithTheNumbers) {
  auto c = bed_case();
  c.materials[0].heat_capacity = 1e-9;
  Simulation sim(c);
  try {
    for (int s = 0; s < 20000; ++s) sim.step();
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("heat conduction is unstable"), std::string::npos)
        << e.what();
  }
}

TEST(HeatConduction, CodeBuiltCasesAreCheckedAndTheCudaBackEndRefusesThem) {
  auto c = bed_case();
  c.materials[0].thermal_conductivity.reset();
  EXPECT_NE(test::input_error_of([&] { Simulation s(c); }).find("needs thermal_conductivity"),
            std::string::npos);
  auto bad_model = bed_case();
  bad_model.heat->model = "fourier";
  EXPECT_NE(test::input_error_of([&] { Simulation s(bad_model); }).find("unknown conduction"),
            std::string::npos);
  Simulation sim(bed_case());
  EXPECT_NE(sim.device_unsupported().find("heat"), std::string::npos);
}

// The resolved case (the echo every run writes) keeps every thermal key, and loads back to the
// same case: the heated bed (materials, heat block, walls' temperatures) and the heated
// fluidised bed (the fluid's properties, the inlet's temperature, the correlation).
TEST(HeatConduction, TheResolvedCaseKeepsTheTemperatures) {
  for (const char* name : {"dem/heated_bed", "cfd_dem/fluidized_bed_heating"}) {
    const auto file = std::filesystem::path(GF_SOURCE_DIR) / "cases" / name / "case.yaml";
    const auto c = input::load_case(file);
    ASSERT_TRUE(c.heat) << name;
    const std::string text = input::echo_yaml(c, "1");
    test::TempDir dir;
    const auto again = input::load_case(dir.write("echo.yaml", text));
    ASSERT_TRUE(again.heat) << text;
    EXPECT_EQ(again.heat->model, c.heat->model);
    EXPECT_EQ(again.heat->temperature, c.heat->temperature);
    ASSERT_EQ(again.materials.size(), c.materials.size());
    for (std::size_t m = 0; m < c.materials.size(); ++m) {
      EXPECT_EQ(again.materials[m].thermal_conductivity, c.materials[m].thermal_conductivity);
      EXPECT_EQ(again.materials[m].heat_capacity, c.materials[m].heat_capacity);
    }
    ASSERT_EQ(again.particles.size(), c.particles.size());
    for (std::size_t g = 0; g < c.particles.size(); ++g) {
      EXPECT_EQ(again.particles[g].temperature, c.particles[g].temperature);
      EXPECT_EQ(again.particles[g].heat_source, c.particles[g].heat_source);
    }
    ASSERT_EQ(again.walls.size(), c.walls.size());
    for (std::size_t w = 0; w < c.walls.size(); ++w)
      EXPECT_EQ(again.walls[w].temperature, c.walls[w].temperature) << c.walls[w].name;
    EXPECT_EQ(again.fluid.has_value(), c.fluid.has_value());
    if (c.fluid) {
      EXPECT_EQ(again.fluid->heat_capacity, c.fluid->heat_capacity);
      EXPECT_EQ(again.fluid->thermal_conductivity, c.fluid->thermal_conductivity);
      EXPECT_EQ(again.fluid->temperature, c.fluid->temperature);
      for (int face = 0; face < 6; ++face)
        EXPECT_EQ(again.fluid->boundary[face].temperature, c.fluid->boundary[face].temperature);
      EXPECT_EQ(again.coupling->heat_transfer, c.coupling->heat_transfer);
    }
    // Resolved once, the echo is a fixed point (but for its first line, naming the file read).
    const std::string second = input::echo_yaml(again, "1");
    const auto third = input::load_case(dir.write("echo2.yaml", second));
    const auto body = [](const std::string& e) { return e.substr(e.find('\n') + 1); };
    EXPECT_EQ(body(input::echo_yaml(third, "1")), body(second)) << name;
  }
}
