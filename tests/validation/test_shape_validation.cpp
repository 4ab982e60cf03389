// SPDX-License-Identifier: GPL-3.0-or-later
// Non-spherical grains and the Gear integrator against analytic expectations: restitution of
// flat and crossed spherocylinder impacts, the sense of rotation of a tilted impact, free
// rotation, polygon impacts in 2D, a static pile of disks, Gear in collisions. Each tolerance
// is argued next to its check.
#include <gtest/gtest.h>

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

/// Rotation taking e_z to the unit vector u.
Quat rotation_to(const Vec3& u) {
  const Vec3 ez{0, 0, 1};
  const Vec3 axis = cross(ez, u);
  const double s = norm(axis);
  if (s < 1e-15) return dot(ez, u) > 0 ? Quat{} : Quat{0, 1, 0, 0};
  return quat_from_axis_angle(axis / s, std::atan2(s, dot(ez, u)));
}

config::Case capsule_wall_case(const std::string& model, double e, double mu, double dt) {
  auto c = test::base_case(dt, 1.0, {-0.1, -0.1, -0.01}, {0.1, 0.1, 0.1});
  test::add_material(c, "pom", 1400, 1e7, 0.3);
  std::map<std::string, double> prm{{"restitution", e}, {"friction", mu}};
  if (model == "hooke") prm["stiffness"] = 1e4;
  test::add_contact(c, "pom", "pom", model, prm);
  test::add_plane(c, "floor", {0, 0, 0}, {0, 0, 1}, "pom");
  return c;
}

/// Steps until the grains have touched (each other or a wall) and come apart again, calling
/// observe(step, contacts) after every step; returns the steps taken, -1 when no contact ended
/// within max_steps.
template <class Observe>
int run_through_contact(Simulation& sim, int max_steps, Observe&& observe) {
  bool touched = false;
  for (int s = 0; s < max_steps; ++s) {
    sim.step();
    const auto n = sim.n_contacts() + sim.n_wall_contacts();
    observe(s, n);
    if (n > 0)
      touched = true;
    else if (touched)
      return s + 1;
  }
  return -1;
}
int run_through_contact(Simulation& sim, int max_steps = 2000000) {
  return run_through_contact(sim, max_steps, [](int, std::int64_t) {});
}

struct LawAndRestitution {
  const char* model;
  double e;
};

}  // namespace

// A spherocylinder (r = 5 mm, L = 20 mm) falls flat onto a plane at 1 m/s. Both end spheres
// touch at once and share the mass (each carries m/2), so the pair of contacts is exactly one
// contact of mass m/2, stiffness and damping per contact as for a sphere: the realised
// restitution is then that of a single sphere-wall contact, within 0.7 % of the request at
// dt = t_c/1000 (ValidationRestitution). The issue asks for 2 %; we check 1 %. By symmetry the
// capsule must not start to rotate (|omega| < 1e-9 rad/s, round-off only).
class ValidationCapsuleFlat : public ::testing::TestWithParam<LawAndRestitution> {};

TEST_P(ValidationCapsuleFlat, ReboundsWithRequestedRestitution) {
  const auto prm = GetParam();
  auto c = capsule_wall_case(prm.model, prm.e, 0.0, 5e-7);
  const double r = 0.005, len = 0.02;
  test::add_capsules(c, "pom", r, len, {{0, 0, r + 1e-4}}, {rotation_to({1, 0, 0})},
                     {{0, 0, -1.0}});
  Simulation sim(c);
  ASSERT_GT(run_through_contact(sim), 0);
  const auto& p = sim.particles();
  const double e = p.v()[0].z / 1.0;
  std::printf("capsule flat drop %s: requested %.3f realised %.5f (%.3f %%)\n", prm.model, prm.e, e,
              100 * (e / prm.e - 1));
  EXPECT_NEAR(e, prm.e, 0.01 * prm.e);
  EXPECT_LT(norm(p.omega()[0]), 1e-9);
  Dump d(std::string("shape_restitution_capsule_flat_") + prm.model + "_" +
             std::to_string(static_cast<int>(100 * prm.e)),
         "requested,realised");
  d.row(prm.e, e);
}

INSTANTIATE_TEST_SUITE_P(Laws, ValidationCapsuleFlat,
                         ::testing::Values(LawAndRestitution{"hooke", 0.3},
                                           LawAndRestitution{"hooke", 0.8},
                                           LawAndRestitution{"hertz_mindlin", 0.3},
                                           LawAndRestitution{"hertz_mindlin", 0.8}),
                         [](const auto& tp) {
                           return std::string(tp.param.model) + "_e" +
                                  std::to_string(static_cast<int>(100 * tp.param.e));
                         });

// A capsule tilted 30 degrees from the vertical (upper end towards +x) falls onto a plane: the
// lower end touches first, on the -x side of the centre, and the upward contact force there
// turns the capsule about +y, towards lying flat: omega_y > 0 and the axis' z component falls.
// Without damping and friction (hooke, e = 1) the total energy (translation, rotation,
// contact) is conserved through the impact: velocity Verlet's energy error is O(dt^2), and at
// t_c/800 the relative error after the contact is below 1e-4.
TEST(ValidationCapsuleTilted, RotatesTowardsFlatAndConservesEnergy) {
  auto c = capsule_wall_case("hooke", 1.0, 0.0, 5e-7);
  const double r = 0.005, len = 0.02, tilt = 30.0 * kPi / 180;
  const Vec3 u{std::sin(tilt), 0, std::cos(tilt)};
  const double z0 = 0.5 * len * std::cos(tilt) + r + 1e-4;
  test::add_capsules(c, "pom", r, len, {{0, 0, z0}}, {rotation_to(u)}, {{0, 0, -1.0}});
  Simulation sim(c);
  const double e0 = sim.total_energy();
  Dump trace("shape_capsule_tilted", "t,omega_y,axis_z,energy_ratio,wall_contacts");
  double worst = 0;  // largest |E/E0 - 1| during the contact (wall contacts' elastic energy in E)
  ASSERT_GT(run_through_contact(sim, 2000000,
                                [&](int s, std::int64_t n) {
                                  if (n > 0)
                                    worst = std::max(worst, std::abs(sim.total_energy() / e0 - 1));
                                  if (s % 20 == 0)
                                    trace.row(
                                        sim.time(), sim.particles().omega()[0].y,
                                        rotate(sim.particles().orientation()[0], Vec3{0, 0, 1}).z,
                                        sim.total_energy() / e0, n);
                                }),
            0);
  const auto& p = sim.particles();
  const Vec3 axis = rotate(p.orientation()[0], Vec3{0, 0, 1});
  std::printf("tilted capsule: omega_y %.4f rad/s, axis z %.5f -> %.5f, energy %.3e relative\n",
              p.omega()[0].y, u.z, axis.z, sim.total_energy() / e0 - 1);
  EXPECT_GT(p.omega()[0].y, 1.0);
  EXPECT_LT(axis.z, u.z);
  EXPECT_NEAR(p.omega()[0].x, 0.0, 1e-9);
  EXPECT_NEAR(sim.total_energy() / e0, 1.0, 1e-4);
  std::printf("tilted capsule: largest energy error during the contact %.2e\n", worst);
  EXPECT_LT(worst, 1e-3);
}

// Two capsules with crossed axes (x and y) meet head-on along z: one side-side contact through
// both centres, so no torque, and m_eff = m/2 as for two equal spheres: the relative velocity
// is reversed by the requested restitution (within 1 %, as for spheres at this resolution).
// The same for two parallel capsules meeting side by side (a line contact that the narrow
// phase reduces to one contact at the middle of the overlap of the axes).
TEST(ValidationCapsulePair, CrossedAndParallelRestitution) {
  for (const bool parallel : {false, true}) {
    auto c = capsule_wall_case("hooke", 0.5, 0.3, 5e-7);
    c.walls.clear();
    const double r = 0.005, len = 0.02;
    test::add_capsules(
        c, "pom", r, len, {{0, 0, 0.02}, {0, 0, 0.02 + 2 * r + 1e-4}},
        {rotation_to({1, 0, 0}), rotation_to(parallel ? Vec3{1, 0, 0} : Vec3{0, 1, 0})},
        {{0, 0, 0.5}, {0, 0, -0.5}});
    Simulation sim(c);
    ASSERT_GT(run_through_contact(sim, 1000000), 0);
    const auto& p = sim.particles();
    const double e = (p.v()[1].z - p.v()[0].z) / 1.0;
    std::printf("capsule pair (%s): restitution %.5f\n", parallel ? "parallel" : "crossed", e);
    Dump d(std::string("shape_restitution_capsule_pair_") + (parallel ? "parallel" : "crossed"),
           "requested,realised");
    d.row(0.5, e);
    EXPECT_NEAR(e, 0.5, 0.005);
    EXPECT_LT(norm(p.omega()[0]) + norm(p.omega()[1]), 1e-6);
  }
}

// Torque-free rotation of an elongated capsule (I_perp / I_axis = 12.6) spinning about a
// general axis: the world angular momentum is conserved to round-off by NO_SQUISH (every
// sub-step maps L exactly; 1e-12 relative over 2e4 steps leaves room for accumulated
// rounding), and the kinetic energy, which the splitting does not conserve exactly, stays
// within 1e-6 relative (its error is O(dt^2 |omega|^2) = 2.5e-7 here, bounded, no drift).
TEST(ValidationCapsuleFreeRotation, ConservesAngularMomentumAndEnergy) {
  auto c = capsule_wall_case("hooke", 0.5, 0.3, 1e-4);
  c.walls.clear();
  test::add_capsules(c, "pom", 0.005, 0.03, {{0, 0, 0.05}},
                     {rotation_to(normalized(Vec3{0.3, 0.2, 0.9}))}, {}, {{2.0, 0.5, 5.0}});
  Simulation sim(c);
  const Vec3 L0 = sim.particles().angular_momentum()[0];
  const double e0 = sim.total_energy();
  double worst_e = 0;
  Dump trace("shape_free_rotation", "t,energy_error,momentum_error");
  for (int s = 0; s < 20000; ++s) {
    sim.step();
    worst_e = std::max(worst_e, std::abs(sim.total_energy() / e0 - 1));
    if (s % 50 == 0)
      trace.row(sim.time(), sim.total_energy() / e0 - 1,
                norm(sim.particles().angular_momentum()[0] - L0) / norm(L0));
  }
  const Vec3 L = sim.particles().angular_momentum()[0];
  std::printf("free rotation: |dL|/|L| %.2e, max |dE/E| %.2e\n", norm(L - L0) / norm(L0), worst_e);
  EXPECT_LT(norm(L - L0) / norm(L0), 1e-12);
  EXPECT_LT(worst_e, 1e-6);
  // The motion is not trivial: omega precesses (it is not parallel to L).
  EXPECT_GT(
      norm(cross(sim.particles().omega()[0], L)) / (norm(L) * norm(sim.particles().omega()[0])),
      0.05);
}

namespace {

config::Case polygon_case(double e, double dt) {
  auto c = test::base_case(dt, 1.0, {-0.1, -0.01, 0}, {0.1, 0.2, 0});
  c.dimension = 2;
  c.domain.thickness = 0.01;
  test::add_material(c, "pom", 1400, 1e7, 0.3);
  test::add_contact(c, "pom", "pom", "hooke",
                    {{"restitution", e}, {"friction", 0.0}, {"stiffness", 1e5}});
  return c;
}

}  // namespace

// 2D polygons. A square (regular 4-gon turned by 45 degrees so that its faces are horizontal)
// falls flat onto a floor, and two squares meet face to face: the overlap is a rectangle of
// constant width w, so the contact is a linear spring of stiffness k w / l_c, and the damping
// is that of this stiffness (shape_forces.hpp): the realised restitution must match the request
// as for spheres (1 %), and the squares must not rotate.
TEST(ValidationPolygon, FlatImpactsRealiseRestitution) {
  const double R = 0.005, e = 0.5;
  for (const bool wall : {true, false}) {
    auto c = polygon_case(e, 2e-7);
    const double half = 0.5 * std::sqrt(kPi) * R;  // half side of the square of area pi R^2
    const Quat flat = turn_about_z(Quat{}, kPi / 4);
    if (wall) {
      test::add_plane(c, "floor", {0, 0, 0}, {0, 1, 0}, "pom");
      test::add_polygons(c, "pom", R, 4, {{0, half + 1e-5, 0}}, {flat}, {{0, -1.0, 0}});
    } else {
      test::add_polygons(c, "pom", R, 4, {{0, 0.05, 0}, {0, 0.05 + 2 * half + 1e-5, 0}},
                         {flat, flat}, {{0, 0.5, 0}, {0, -0.5, 0}});
    }
    Simulation sim(c);
    ASSERT_GT(run_through_contact(sim, 1000000), 0);
    const auto& p = sim.particles();
    const double realised = wall ? p.v()[0].y : p.v()[1].y - p.v()[0].y;
    std::printf("square %s: restitution %.5f (requested %.2f)\n", wall ? "on floor" : "pair",
                realised, e);
    EXPECT_NEAR(realised, e, 0.01 * e);
    Dump d(std::string("shape_restitution_square_") + (wall ? "wall" : "pair"),
           "requested,realised");
    d.row(e, realised);
    EXPECT_LT(std::abs(p.omega()[0].z), 1e-6);
    EXPECT_EQ(p.x()[0].z, 0.0);
  }
}

// A pile of 300 polydisperse disks (2D) settles in a box with periodic sides: the floor carries
// the weight of the pile. Residual motion after settling (kinetic energy < 1e-8 of the potential
// energy scale) leaves the force balance exact to the inertia of what still moves: 1 %.
TEST(ValidationDisks, FloorCarriesPileWeight) {
  auto c = test::base_case(2e-5, 1.0, {0, 0, 0}, {0.1, 0.3, 0}, {true, false, false});
  c.dimension = 2;
  c.domain.thickness = 0.01;
  c.gravity = {0, -9.81, 0};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hooke",
                    {{"restitution", 0.3}, {"friction", 0.5}, {"stiffness", 2e4}});
  auto& f = test::add_box_fill(c, "glass", 0.0015, 0.0025, {0, 0, 0}, {0.1, 0.25, 0},
                               config::Fill::Lattice::Random);
  c.particles.back().kind = config::Shape::Disk;
  c.particles.back().shape = "disk";
  f.count = 300;
  f.seed = 4;
  test::add_plane(c, "floor", {0, 0, 0}, {0, 1, 0}, "glass");
  Simulation sim(c);
  double weight = 0;
  for (std::size_t i = 0; i < sim.particles().size(); ++i)
    weight += 9.81 * sim.particles().mass()[i];
  for (int s = 0; s < 40000; ++s) sim.step();
  const double ratio = sim.walls()[0].force.y / -weight;
  std::printf("disk pile: floor force / weight = %.5f, kinetic %.3e J\n", ratio,
              sim.quantity("kinetic_energy"));
  EXPECT_NEAR(ratio, 1.0, 0.01);
  for (std::size_t i = 0; i < sim.particles().size(); ++i) ASSERT_EQ(sim.particles().x()[i].z, 0.0);
}

// `integrator: gear5` through the whole simulation: two spheres (hooke, e = 0.7) meet head-on
// at dt = t_c/10 and t_c/20, with Gear and with velocity Verlet at the same dt (same cost: one
// force evaluation per step). The design document expects Gear to be accurate at t_c/10. The
// kernel study (tests/unit/test_gear.cpp) confirms it for an unclipped, weakly damped dashpot
// (restitution error 1e-3 against Verlet's 2.7e-2), but grainflow's laws clip the dashpot so
// that the normal force never pulls (and the requested e is that of the clipped collision),
// which puts a kink into the force at the end of the contact and a jump at its start. Gear's
// fifth-order extrapolation then loses its advantage. Measured here: t_c/10 Gear 3.6e-2,
// Verlet 2.4e-2; t_c/20 Gear 8.1e-3, Verlet 6.2e-3 (a scan of the kernel with e = 0.37 gives
// Gear errors up to 50 % at t_c/10: docs/models/gear5.md). Asserted: Gear stays stable, within
// 5 % at t_c/10 and 1.5 % at t_c/20 (of the same order as Verlet, not better).
TEST(ValidationGear, CollisionAtATenthOfTheContactTime) {
  const double r = 0.005, rho = 2500, k = 1e4, e = 0.7;
  const double m = rho * 4.0 / 3.0 * kPi * r * r * r, m_eff = 0.5 * m;
  const double zeta = -std::log(e) / std::sqrt(kPi * kPi + std::log(e) * std::log(e));
  const double tc = kPi / (std::sqrt(k / m_eff) * std::sqrt(1 - zeta * zeta));
  for (const double per_contact : {10.0, 20.0, 40.0}) {
    for (const char* integrator : {"gear5", "velocity_verlet"}) {
      auto c = test::base_case(tc / per_contact, 1.0, {-0.05, -0.05, -0.05}, {0.05, 0.05, 0.05});
      c.integrator = integrator;
      test::add_material(c, "glass", rho, 1e7, 0.3);
      test::add_contact(c, "glass", "glass", "hooke",
                        {{"restitution", e}, {"friction", 0.3}, {"stiffness", k}});
      test::add_spheres(c, "glass", r, {{0, 0, -r - 0.0013}, {0, 0, r + 0.0013}},
                        {{0, 0, 0.5}, {0, 0, -0.5}});
      Simulation sim(c);
      ASSERT_GT(run_through_contact(sim, 100000), 0);
      // Gear's higher derivatives still carry the contact for a few steps after separation
      // (the corrector removes them): read the velocity 2 t_c later, as the kernel study does.
      for (int s = 0; s < 2 * static_cast<int>(per_contact); ++s) sim.step();
      const auto& p = sim.particles();
      const double realised = p.v()[1].z - p.v()[0].z;
      const double err = std::abs(realised / e - 1);
      std::printf("%s at dt = t_c/%g: restitution %.5f (error %.2e)\n", integrator, per_contact,
                  realised, err);
      if (std::string(integrator) == "gear5") {
        EXPECT_LT(err, per_contact == 10 ? 0.05 : 0.015);
      }
      Dump d(std::string("gear_collision_") + integrator + "_" +
                 std::to_string(static_cast<int>(per_contact)),
             "steps_per_contact,restitution_error");
      d.row(per_contact, err);
    }
  }
}
