// SPDX-License-Identifier: GPL-3.0-or-later
// DEM physics against analytic and published references (Chung & Ooi 2011, restitution,
// energy conservation, static floor load, sliding-to-rolling). Each tolerance is argued.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>

#include "case_builder.hpp"
#include "dump.hpp"
#include "simulation/simulation.hpp"

using namespace gf;
using gf::test::Dump;

namespace {

/// Outcome of a head-on binary collision (sphere-sphere or sphere-wall).
struct Collision {
  double f_max = 0;        ///< N
  double overlap_max = 0;  ///< m
  double duration = 0;     ///< s
  double restitution = 0;
};

/// Runs until the pair separates; particle 0 moves with +v0 along z towards particle 1 (or the
/// wall).
Collision collide(Simulation& sim, bool wall, double v0, Dump* trace = nullptr) {
  Collision out;
  auto& p = sim.particles();
  const double dt = sim.dt();
  int in_contact = 0;
  bool touched = false;
  for (int s = 0; s < 10000000; ++s) {
    sim.step();
    double overlap;
    if (wall)
      overlap = p.radius()[0] - (sim.walls()[0].point.z - p.x()[0].z);
    else
      overlap = p.radius()[0] + p.radius()[1] - norm(p.x()[1] - p.x()[0]);
    if (overlap > 0) {
      touched = true;
      ++in_contact;
      out.overlap_max = std::max(out.overlap_max, overlap);
      out.f_max = std::max(out.f_max, std::abs(p.f()[0].z));
      if (trace) trace->row(sim.time(), overlap, std::abs(p.f()[0].z));
    } else if (touched) {
      break;
    }
  }
  out.duration = in_contact * dt;
  const double v_after = wall ? -p.v()[0].z : p.v()[1].z - p.v()[0].z;
  out.restitution = v_after / v0;
  return out;
}

}  // namespace

// Chung & Ooi, Granular Matter 13 (2011) 643, test 1: two glass spheres (R = 10 mm, E = 48 GPa,
// nu = 0.2, rho = 2800 kg/m^3) meeting head-on at 10 m/s each. References: F_max = 10.70 kN,
// delta_max = 274.1 um, t_c = 40.3 us (Hertz theory, which the paper's codes match). With
// dt = t_c / 4000, velocity Verlet resolves the peak to ~1e-6 relative, and the duration counts
// whole steps (+-1 step = 2.5e-4): 1 % is the requirement and leaves room only for a
// wrong law, never for discretisation error.
TEST(ValidationChungOoi, HertzNormalImpactTest1) {
  auto c = test::base_case(1e-8, 1.0, {-0.1, -0.1, -0.1}, {0.1, 0.1, 0.1});
  test::add_material(c, "glass", 2800, 48e9, 0.2);
  test::add_contact(c, "glass", "glass", "hertz_mindlin",
                    {{"restitution", 1.0}, {"friction", 0.0}});
  test::add_spheres(c, "glass", 0.010, {{0, 0, -0.0101}, {0, 0, 0.0101}},
                    {{0, 0, 10}, {0, 0, -10}});
  Simulation sim(c);
  Dump trace("chung_ooi_test1", "t,overlap,force");
  const Collision r = collide(sim, false, 20.0, &trace);
  EXPECT_NEAR(r.f_max, 10.70e3, 0.01 * 10.70e3);
  EXPECT_NEAR(r.overlap_max, 274.1e-6, 0.01 * 274.1e-6);
  EXPECT_NEAR(r.duration, 40.3e-6, 0.01 * 40.3e-6);
  RecordProperty("F_max_N", std::to_string(r.f_max));
  RecordProperty("delta_max_um", std::to_string(r.overlap_max * 1e6));
  RecordProperty("t_c_us", std::to_string(r.duration * 1e6));
}

// Realised restitution equals the requested one. The damping ratio comes from a numerical
// inversion of the continuous collision (restitution_map.cpp), so the remaining error is the
// time discretisation: with dt = t_c / 400 the velocity Verlet error in e is ~0.1 %, well inside
// the 1 % required; the clamped, non-attractive force is what the map models.
struct RestitutionCase {
  const char* model;
  bool wall;
  double e;
};

class ValidationRestitution : public ::testing::TestWithParam<RestitutionCase> {};

TEST_P(ValidationRestitution, RealisedEqualsRequested) {
  const auto prm = GetParam();
  const double r = 0.005, rho = 2500, E = 1e7, nu = 0.3, v = 1.0;
  const double m = rho * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double m_eff = prm.wall ? m : m / 2, r_eff = prm.wall ? r : r / 2;
  const double e_star =
      E / (2 * (1 - nu * nu)) * (prm.wall ? 2.0 : 1.0);  // wall of the same material
  const double k = 1e4;
  const double v_rel = prm.wall ? v : 2 * v;
  const bool hertz = std::string(prm.model) == "hertz_mindlin";
  const double tc = hertz ? 2.868 * std::pow(m_eff * m_eff / (r_eff * e_star * e_star * v_rel), 0.2)
                          : std::numbers::pi * std::sqrt(m_eff / k);
  auto c = test::base_case(tc / 1000, 1.0, {-0.1, -0.1, -0.1}, {0.1, 0.1, 0.1});
  test::add_material(c, "glass", rho, E, nu);
  std::map<std::string, double> params{{"restitution", prm.e}, {"friction", 0.0}};
  if (!hertz) params["stiffness"] = k;
  test::add_contact(c, "glass", "glass", prm.model, params);
  if (prm.wall) {
    test::add_spheres(c, "glass", r, {{0, 0, -0.0001 - r}}, {{0, 0, v}});
    test::add_plane(c, "lid", {0, 0, 0}, {0, 0, -1}, "glass");
  } else {
    test::add_spheres(c, "glass", r, {{0, 0, -r - 1e-4}, {0, 0, r + 1e-4}},
                      {{0, 0, v}, {0, 0, -v}});
  }
  Simulation sim(c);
  const Collision out = collide(sim, prm.wall, v_rel);
  EXPECT_NEAR(out.restitution, prm.e, 0.01 * prm.e) << prm.model << (prm.wall ? " wall" : " pair");
  RecordProperty("realised_restitution", std::to_string(out.restitution));
  Dump d(std::string("restitution_") + prm.model + (prm.wall ? "_wall_" : "_pair_") +
             std::to_string(std::lround(prm.e * 10)),
         "requested,realised");
  d.row(prm.e, out.restitution);
  std::printf("restitution %s %s requested %.3f realised %.5f (%.3f %%)\n", prm.model,
              prm.wall ? "wall" : "pair", prm.e, out.restitution,
              100 * (out.restitution / prm.e - 1));
}

static std::vector<RestitutionCase> restitution_cases() {
  std::vector<RestitutionCase> out;
  for (const char* model : {"hooke", "hertz_mindlin"})
    for (bool wall : {false, true})
      for (double e : {0.1, 0.3, 0.5, 0.7, 0.9}) out.push_back({model, wall, e});
  return out;
}

INSTANTIATE_TEST_SUITE_P(AllLaws, ValidationRestitution, ::testing::ValuesIn(restitution_cases()),
                         [](const auto& tp) {
                           return std::string(tp.param.model) +
                                  (tp.param.wall ? "_wall_e" : "_pair_e") +
                                  std::to_string(static_cast<int>(std::lround(tp.param.e * 10)));
                         });

// An elastic, frictionless gas of Hertz spheres in a periodic box conserves kinetic + elastic
// energy. Velocity Verlet is symplectic, so the error stays bounded (no drift); with
// dt ~ t_c / 60 at the largest impact speed the fluctuation per collision is ~1e-6 of the
// energy, and 1e5 steps must stay within the required 1e-4.
TEST(ValidationEnergy, ElasticGasConservesEnergy) {
  auto c = test::base_case(2e-6, 1.0, {0, 0, 0}, {0.06, 0.06, 0.06}, {true, true, true});
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin",
                    {{"restitution", 1.0}, {"friction", 0.0}});
  auto& f = test::add_box_fill(c, "glass", 0.002, 0.003, {0, 0, 0}, {0.06, 0.06, 0.06},
                               config::Fill::Lattice::Random);
  f.count = 300;
  f.seed = 3;
  f.velocity_jitter = 1.0;
  Simulation sim(c);
  const double e0 = sim.total_energy();
  double worst = 0;
  Dump d("energy_elastic_gas", "step,relative_error");
  for (int s = 0; s < 100000; ++s) {
    sim.step();
    if (s % 1000 == 999) {
      const double err = (sim.total_energy() - e0) / e0;
      worst = std::max(worst, std::abs(err));
      d.row(s + 1, err);
    }
  }
  EXPECT_LT(worst, 1e-4);
  EXPECT_GT(sim.neighbor_list().n_builds(), 10);  // the gas really moved and collided
  RecordProperty("max_relative_energy_error", std::to_string(worst * 1e6) + "e-6");
}

// After settling, the floor carries the weight of the bed. Side boundaries are periodic, so no
// wall friction takes load (no Janssen effect); the residual kinetic motion makes the floor
// force oscillate by < 0.1 % once settled, and averaging over 0.05 s leaves the 1 % required
// for a wrong force balance only.
TEST(ValidationStatics, FloorForceEqualsBedWeight) {
  auto c = test::base_case(2e-5, 0.6, {0, 0, 0}, {0.06, 0.06, 0.2}, {true, true, false});
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin",
                    {{"restitution", 0.5}, {"friction", 0.5}});
  auto& f = test::add_box_fill(c, "glass", 0.005, 0.005, {0, 0, 0}, {0.06, 0.06, 0.06},
                               config::Fill::Lattice::Cubic);
  f.spacing = 0.0102;
  f.velocity_jitter = 0.05;
  test::add_plane(c, "floor", {0, 0, 0}, {0, 0, 1}, "glass");
  Simulation sim(c);
  double weight = 0;
  for (std::size_t i = 0; i < sim.particles().size(); ++i)
    weight += sim.particles().mass()[i] * 9.81;
  const int n_steps = static_cast<int>(std::lround(0.6 / 2e-5));
  const int avg_from = n_steps - static_cast<int>(std::lround(0.05 / 2e-5));
  double sum = 0;
  int count = 0;
  Dump d("floor_force", "t,floor_over_weight");
  for (int s = 0; s < n_steps; ++s) {
    sim.step();
    if (s % 50 == 0) d.row(sim.time(), -sim.walls()[0].force.z / weight);
    if (s >= avg_from) {
      sum += -sim.walls()[0].force.z;
      ++count;
    }
  }
  const double floor = sum / count;
  EXPECT_NEAR(floor, weight, 0.01 * weight);
  RecordProperty("floor_over_weight", std::to_string(floor / weight));
}

// A sphere launched sliding (v0, no spin) on a rough plane: friction mu m g decelerates it and
// spins it up until v = omega r, at t = 2 v0 / (7 mu g) with v = 5 v0 / 7 (rigid-body theory).
// The Mindlin spring needs a few microseconds to reach the Coulomb cap and the Hertz overlap
// (~1e-5 r) shifts the lever arm; both are below 1e-3 of the reference values, so 1 % holds.
TEST(ValidationFriction, SlidingToRolling) {
  const double r = 0.005, mu = 0.3, g = 9.81, v0 = 1.0, E = 1e7, nu = 0.3, rho = 2500;
  const double m = rho * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double e_star = E / (2 * (1 - nu * nu)) * 2;  // same-material half-space
  const double overlap_eq = std::pow(m * g / (4.0 / 3.0 * e_star * std::sqrt(r)), 2.0 / 3.0);
  auto c = test::base_case(1e-6, 1.0, {-1, -0.1, -0.1}, {1, 0.1, 0.1});
  c.gravity = {0, 0, -g};
  test::add_material(c, "glass", rho, E, nu);
  test::add_contact(c, "glass", "glass", "hertz_mindlin", {{"restitution", 0.5}, {"friction", mu}});
  test::add_spheres(c, "glass", r, {{0, 0, r - overlap_eq}}, {{v0, 0, 0}});
  test::add_plane(c, "floor", {0, 0, 0}, {0, 0, 1}, "glass");
  Simulation sim(c);
  auto& p = sim.particles();
  double t_roll = -1, v_roll = 0;
  double slip_prev = v0;
  Dump d("sliding_rolling", "t,v,omega_r");
  for (int s = 0; s < 200000; ++s) {
    sim.step();
    if (s % 200 == 0) d.row(sim.time(), p.v()[0].x, p.omega()[0].y * r);
    const double contact_speed =
        p.v()[0].x - p.omega()[0].y * r;  // slip speed of the contact point
    if (contact_speed <= 0 && slip_prev > 0) {
      const double w = slip_prev / (slip_prev - contact_speed);
      t_roll = sim.time() - (1 - w) * sim.dt();
      v_roll = p.v()[0].x;
      break;
    }
    slip_prev = contact_speed;
  }
  const double t_ref = 2 * v0 / (7 * mu * g), v_ref = 5 * v0 / 7;
  ASSERT_GT(t_roll, 0) << "never reached rolling";
  EXPECT_NEAR(t_roll, t_ref, 0.01 * t_ref);
  EXPECT_NEAR(v_roll, v_ref, 0.01 * v_ref);
  RecordProperty("t_roll_over_ref", std::to_string(t_roll / t_ref));
  RecordProperty("v_roll_over_ref", std::to_string(v_roll / v_ref));
}
