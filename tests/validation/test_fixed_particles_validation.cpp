// SPDX-License-Identifier: GPL-3.0-or-later
// Fixed (frozen) grains against physics: a pile at rest on a bed of fixed spheres loads the bed
// with exactly its weight (fixed_force), and a grain bouncing on a fixed grain rebounds with the
// requested restitution, as against an immobile partner of infinite mass (the limit of a very
// heavy free partner, as LAMMPS's granular pair styles treat `fix freeze` groups), not with the
// restitution a damping with the fixed grain's real mass would give. Each tolerance is argued.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <ostream>
#include <string>

#include "case_builder.hpp"
#include "dump.hpp"
#include "simulation/simulation.hpp"

using namespace gf;
using gf::test::Dump;

namespace {

/// Index of the particle with id `id` (the store re-orders its particles at list builds).
std::size_t index_of(const Simulation& sim, std::int64_t id) {
  const auto& p = sim.particles();
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.id()[i] == id) return i;
  ADD_FAILURE() << "no particle " << id;
  return 0;
}

}  // namespace

// A pile of 150 free glass spheres (r = 0.9-1.1 mm) poured onto a rough base of 100 fixed
// spheres (r = 1 mm, square lattice of spacing 1.95 mm: the base's grains overlap, which they
// may, since fixed grains never touch one another) in a box periodic in x and y: no wall, no
// side friction, so the base carries the whole weight W = M g of the free grains.
//
// Tolerance: the free grains' momentum balance is M g - fixed_force = dP/dt (free-free forces
// cancel pair by pair, the base is the only other body), so the mean of fixed_force over a
// window T differs from M g by Delta P / T, |Delta P| <= 2 max |P| <= 2 sqrt(2 M E_k,max). The
// test measures E_k over the window and checks the mean against M g within that bound plus
// 1e-9 W for the rounding of the sums of ~600 contact forces (1e-16 each, relative); it also
// asks that bound to be below 1e-4 W, i.e. that the pile has come to rest, and that the
// instantaneous load at the end is within 1e-3 W (elastic ringing of a pile at rest).
TEST(ValidationFixedParticles, PileOnAFixedBedLoadsItWithItsWeight) {
  const double g = 9.81, dt = 5e-6;
  auto c = test::base_case(dt, 1.0, {0, 0, 0}, {0.0195, 0.0195, 0.03}, {true, true, false});
  c.gravity = {0, 0, -g};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin",
                    {{"restitution", 0.3}, {"friction", 0.5}, {"rolling_friction", 0.1}});
  test::add_fixed_sphere_layer(c, "glass", 0.001, 0.00195, 0, 0.0195, 0, 0.0195, 0.001);
  auto& f = test::add_box_fill(c, "glass", 0.0009, 0.0011, {0, 0, 0.0025}, {0.0195, 0.0195, 0.02},
                               config::Fill::Lattice::Random);
  f.count = 150;
  f.seed = 7;
  c.output.quantities = {"fixed_force"};
  Simulation sim(c);
  const auto& p = sim.particles();
  double mass = 0;
  std::size_t n_fixed = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.fixed()[i] != 0)
      ++n_fixed;
    else
      mass += p.mass()[i];
  }
  ASSERT_EQ(n_fixed, 100u);
  const double weight = mass * g;
  Dump trace("fixed_bed_load", "t,fixed_force_z_over_weight,kinetic_energy");
  const int settle = 70000, window = 10000;  // 0.35 s to settle, 0.05 s measured
  for (int s = 0; s < settle; ++s) {
    sim.step(true);
    if (s % 500 == 0) {
      sim.complete_step();
      trace.row(sim.time(), -sim.quantity("fixed_force.z") / weight,
                sim.quantity("kinetic_energy"));
    }
  }
  sim.complete_step();
  double sum_z = 0, sum_x = 0, sum_y = 0, ek_max = 0;
  for (int s = 0; s < window; ++s) {
    sim.step();
    sum_x += sim.quantity("fixed_force.x");
    sum_y += sim.quantity("fixed_force.y");
    sum_z += sim.quantity("fixed_force.z");
    ek_max = std::max(ek_max, sim.quantity("kinetic_energy"));
  }
  const double T = window * dt;
  const double bound = 2 * std::sqrt(2 * mass * ek_max) / T + 1e-9 * weight;
  const double mean_z = sum_z / window;
  std::printf(
      "fixed bed: W = %.6e N, mean fixed_force.z = %.6e N (rel. error %.2e, bound %.2e), "
      "E_k max %.2e J\n",
      weight, mean_z, std::abs(mean_z + weight) / weight, bound / weight, ek_max);
  RecordProperty("relative_error", std::to_string(std::abs(mean_z + weight) / weight));
  EXPECT_LT(bound, 1e-4 * weight) << "the pile has not come to rest";
  EXPECT_NEAR(mean_z, -weight, bound);
  EXPECT_NEAR(sum_x / window, 0.0, bound);
  EXPECT_NEAR(sum_y / window, 0.0, bound);
  EXPECT_NEAR(sim.quantity("fixed_force.z"), -weight, 1e-3 * weight);
  // The free grains rest on the base, not in it: every one above its top.
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.fixed()[i] == 0) {
      EXPECT_GT(p.x()[i].z, 0.001) << p.id()[i];
    }
  }
}

namespace {

/// Outcome of a head-on collision of grain 2 (moving at -v0 along the y axis in 2D, z in 3D)
/// with grain 1 (fixed, or free and at rest): the realised restitution from the relative normal
/// velocity after separation.
struct Bounce {
  double restitution = 0;
  double contact_time = 0;  ///< s
};

Bounce bounce(Simulation& sim, int axis, double v0) {
  const double dt = sim.dt();
  bool touched = false;
  int in_contact = 0;
  for (int s = 0; s < 10000000; ++s) {
    sim.step();
    if (sim.n_contacts() > 0) {
      touched = true;
      ++in_contact;
    } else if (touched) {
      break;
    }
  }
  EXPECT_TRUE(touched);
  const auto& p = sim.particles();
  const std::size_t a = index_of(sim, 1), b = index_of(sim, 2);
  return {(p.v()[b][axis] - p.v()[a][axis]) / v0, in_contact * dt};
}

struct BounceCase {
  const char* name;
  const char* model;  ///< hooke | hertz_mindlin
  const char* shape;  ///< sphere | capsule (horizontal, on a sphere) | square (2D, face on face)
  double e;
};

/// Grain 1 at the origin (fixed, or free with `density_ratio` x the density), grain 2 above it
/// moving down at v0, a gap of 1e-4 m, no gravity. dt = t_c / 1000 (t_c of the pair, estimated
/// with m* = m_2: Hertz, Johnson eq. 4.24; linear: pi sqrt(m*/k)).
config::Case bounce_case(const BounceCase& bc, bool fixed, double density_ratio, double v0) {
  const bool two_d = std::string(bc.shape) == "square";
  const bool hertz = std::string(bc.model) == "hertz_mindlin";
  const double r = 0.005, rho = 2500, E = 1e7, nu = 0.3, k = 1e4;
  const double m2 = two_d ? rho * std::numbers::pi * r * r * 0.01
                          : rho * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double e_star = E / (2 * (1 - nu * nu));
  const double tc = hertz ? 2.868 * std::pow(m2 * m2 / (0.5 * r * e_star * e_star * v0), 0.2)
                          : std::numbers::pi * std::sqrt(m2 / k);
  auto c = test::base_case(tc / 1000, 1.0, {-0.05, -0.05, -0.05}, {0.05, 0.05, 0.05});
  test::add_material(c, "grain", rho, E, nu);
  test::add_material(c, "heavy", rho * density_ratio, E, nu);
  std::map<std::string, double> prm{{"restitution", bc.e}, {"friction", 0.5}};
  if (!hertz) prm["stiffness"] = k;
  for (const auto& [a, b] :
       {std::pair{"grain", "grain"}, std::pair{"grain", "heavy"}, std::pair{"heavy", "heavy"}})
    test::add_contact(c, a, b, bc.model, prm);
  const std::string base = density_ratio == 1 ? "grain" : "heavy";
  const Vec3 down = two_d ? Vec3{0, -v0, 0} : Vec3{0, 0, -v0};
  const Vec3 above = two_d ? Vec3{0, 2 * r + 1e-4, 0} : Vec3{0, 0, 2 * r + 1e-4};
  if (two_d) {
    c.dimension = 2;
    c.domain.min.z = c.domain.max.z = 0;
    c.domain.thickness = 0.01;
    // Squares of the area of a disk of radius r (side sqrt(pi) r), faces along x and y.
    const double half = 0.5 * std::sqrt(std::numbers::pi) * r;
    test::add_polygons(c, base, r, 4, {{0, 0, 0}},
                       {quat_from_axis_angle({0, 0, 1}, 0.25 * std::numbers::pi)});
    c.particles.back().fixed = fixed;
    test::add_polygons(c, "grain", r, 4, {{0, 2 * half + 1e-4, 0}},
                       {quat_from_axis_angle({0, 0, 1}, 0.25 * std::numbers::pi)}, {down});
  } else {
    test::add_spheres(c, base, r, {{0, 0, 0}});
    c.particles.back().fixed = fixed;
    if (std::string(bc.shape) == "capsule") {
      // A horizontal spherocylinder (cap radius r, L = 4 r) whose middle lies over the sphere:
      // a side contact whose normal passes through both centres (no torque).
      test::add_capsules(c, "grain", r, 4 * r, {above},
                         {quat_from_axis_angle({0, 1, 0}, 0.5 * std::numbers::pi)}, {down});
    } else {
      test::add_spheres(c, "grain", r, {above}, {down});
    }
  }
  return c;
}

void PrintTo(const BounceCase& bc, std::ostream* os) {
  *os << bc.name;
}

class ValidationFixedBounce : public ::testing::TestWithParam<BounceCase> {};

}  // namespace

// Restitution against a fixed grain. The relative motion of two grains obeys m* x'' = F(x, x')
// with m* = m1 m2 / (m1 + m2), and the damping slot's coefficient 2 zeta sqrt(m* S_n) makes it
// realise e for that m* (restitution_map.cpp). A grain glued to an immobile base does not recoil:
// the relative motion is that of the free grain alone, m* = m2, the m1 -> infinity limit. The law
// is given exactly that (contact::reduced_mass), so the realised restitution equals the
// requested one to the map's accuracy, as for a free pair (ValidationRestitution: dt = t_c/1000,
// ~0.1 % from time discretisation, 1 % required), and equals that of a free partner 10^6 times
// heavier within 1e-3 (its m* differs by 1e-6, the rest is the same discretisation).
//
// Keeping the fixed grain's real mass in the damping coefficient instead: for equal grains
// c = 2 zeta sqrt(m2/2 S_n), i.e. a damping ratio zeta / sqrt(2) for the actual motion, and a
// restitution e' = exp(-pi zeta' / sqrt(1 - zeta'^2)) for a linear spring without the clamp of
// the normal force (0.616 where 0.5 is asked; 0.600 measured with the clamped law when this
// force loop is given the frozen grain's real mass). The test prints e' and checks that the
// measured value is far from it.
TEST_P(ValidationFixedBounce, RestitutionIsTheRequestedOneAsAgainstAnImmobileGrain) {
  const BounceCase bc = GetParam();
  const double v0 = 0.5;
  const int axis = std::string(bc.shape) == "square" ? 1 : 2;
  Simulation fixed_sim(bounce_case(bc, true, 1.0, v0));
  const Bounce on_fixed = bounce(fixed_sim, axis, v0);
  // The fixed grain did not move.
  const std::size_t a = index_of(fixed_sim, 1);
  EXPECT_EQ(fixed_sim.particles().x()[a], Vec3{});
  EXPECT_EQ(fixed_sim.particles().v()[a], Vec3{});
  Simulation heavy_sim(bounce_case(bc, false, 1e6, v0));
  const Bounce on_heavy = bounce(heavy_sim, axis, v0);

  // The damping with the real mass of the fixed grain (linear spring, equal masses).
  const double zeta = -std::log(bc.e) / std::sqrt(std::numbers::pi * std::numbers::pi +
                                                  std::log(bc.e) * std::log(bc.e));
  const double zeta_l = zeta / std::sqrt(2.0);
  const double e_real_mass = std::exp(-std::numbers::pi * zeta_l / std::sqrt(1 - zeta_l * zeta_l));
  std::printf(
      "%s: requested e = %.3f, on a fixed grain %.5f (%.3f %%), on a 1e6 x heavier free "
      "grain %.5f; with the frozen grain's real mass in the damping (linear law) %.3f\n",
      bc.name, bc.e, on_fixed.restitution, 100 * (on_fixed.restitution / bc.e - 1),
      on_heavy.restitution, e_real_mass);
  Dump d(std::string("fixed_bounce_") + bc.name, "requested,on_fixed,on_heavy,real_mass_linear");
  d.row(bc.e, on_fixed.restitution, on_heavy.restitution, e_real_mass);
  RecordProperty("realised_restitution", std::to_string(on_fixed.restitution));
  EXPECT_NEAR(on_fixed.restitution, bc.e, 0.01 * bc.e);
  EXPECT_NEAR(on_fixed.restitution, on_heavy.restitution, 1e-3);
  EXPECT_NEAR(on_fixed.contact_time, on_heavy.contact_time, 0.01 * on_heavy.contact_time);
  if (std::string(bc.model) == "hooke" && std::string(bc.shape) == "sphere") {
    EXPECT_GT(std::abs(on_fixed.restitution - e_real_mass), 0.05);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Shapes, ValidationFixedBounce,
    ::testing::Values(BounceCase{"hooke_sphere_e05", "hooke", "sphere", 0.5},
                      BounceCase{"hooke_sphere_e03", "hooke", "sphere", 0.3},
                      BounceCase{"hertz_sphere_e05", "hertz_mindlin", "sphere", 0.5},
                      BounceCase{"hertz_sphere_e08", "hertz_mindlin", "sphere", 0.8},
                      BounceCase{"hertz_capsule_e05", "hertz_mindlin", "capsule", 0.5},
                      BounceCase{"hooke_square_e05", "hooke", "square", 0.5}),
    [](const auto& param_info) { return std::string(param_info.param.name); });
