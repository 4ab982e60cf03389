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
#include "fit.hpp"
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

// ---------------------------------------------------------------------------------------------
// Fixed groups with prescribed motion (fixed: {translate, rotate})

namespace {

config::Motion translation(const Vec3& velocity, double start = 0) {
  config::Motion m;
  m.velocity = velocity;
  m.start = start;
  return m;
}

}  // namespace

// A bounce seen from the moving grain. Grain 1 (fixed) moves up at v0 into grain 2 at rest
// above it: in the frame of grain 1, grain 2 comes down at v0 and leaves at e v0, so in the lab
// it leaves at (1 + e) v0 and the relative velocity after the bounce is e v0. Galilean
// invariance of the contact law (it sees v_2 - v_1 and the overlap only) and the infinite mass
// of the fixed grain give the requested e, as against a fixed grain at rest; the moving grain's
// velocity field must equal the motion's for the damping to see the right approach speed (a
// fixed grain with v = 0 moving under it would leave grain 2 at (1 + e') v0 with the damping
// acting on the wrong speed). Tolerance: 1 % as for the grain at rest (time discretisation,
// dt = t_c / 1000), and equal to the at-rest bounce within 1e-3 (the same discretisation, the
// positions shifted by the motion).
TEST_P(ValidationFixedBounce, MovingFixedGrainGivesTheRestitutionOfItsFrame) {
  const BounceCase bc = GetParam();
  const double v0 = 0.5;
  const int axis = std::string(bc.shape) == "square" ? 1 : 2;
  Simulation at_rest(bounce_case(bc, true, 1.0, v0));
  const Bounce still = bounce(at_rest, axis, v0);
  auto c = bounce_case(bc, true, 1.0, v0);
  // Grain 2 at rest; grain 1 moving towards it at v0.
  Vec3 up{};
  up[axis] = v0;
  c.particles[1].explicit_particles->velocities = {Vec3{}};
  c.particles[0].motion = translation(up);
  Simulation moving(c);
  const Bounce seen = bounce(moving, axis, v0);
  const auto& p = moving.particles();
  const std::size_t b = index_of(moving, 2);
  std::printf(
      "%s: requested e = %.3f; grain at rest %.5f, moving grain %.5f (%.3f %%), grain 2 "
      "leaves at %.5f v0 (1 + e = %.5f)\n",
      bc.name, bc.e, still.restitution, seen.restitution, 100 * (seen.restitution / bc.e - 1),
      p.v()[b][axis] / v0, 1 + seen.restitution);
  EXPECT_NEAR(seen.restitution, bc.e, 0.01 * bc.e);
  EXPECT_NEAR(seen.restitution, still.restitution, 1e-3);
  EXPECT_NEAR(p.v()[b][axis] / v0, 1 + bc.e, 0.01 * (1 + bc.e));
  EXPECT_NEAR(p.v()[b].x, 0.0, 1e-12);  // head-on: nothing sideways
}

// A grain on a turning arm. A fixed sphere (r = 5 mm) on a rotating arm of length R = 1 m
// (Omega = 0.5 rad/s about z: speed Omega R = 0.5 m/s) hits a free sphere at rest in its path,
// frictionless, Hooke e = 0.5 and Hertz e = 0.8. The moving grain's velocity is the rigid
// motion's Omega x (x - c); the free grain leaves along the arm's path at (1 + e) Omega R.
// Tolerance 1 %: the discretisation as above, plus the turn of the arm during the contact
// (Omega t_c ~ 1e-3 rad: the normal turns by that, changing the normal speed by ~1e-6 and the
// direction of departure by 1e-3 rad) and the centripetal acceleration of the arm
// (Omega^2 R t_c / (Omega R) = Omega t_c ~ 1e-3).
TEST(ValidationFixedMotion, GrainOnATurningArmGivesTheRequestedRestitution) {
  for (const auto& [model, e] : {std::pair{"hooke", 0.5}, std::pair{"hertz_mindlin", 0.8}}) {
    const bool hertz = std::string(model) == "hertz_mindlin";
    const double r = 0.005, rho = 2500, E = 1e7, nu = 0.3, k = 1e4, R = 1.0, omega = 0.5;
    const double v0 = omega * R;
    const double m = rho * 4.0 / 3.0 * std::numbers::pi * r * r * r;
    const double e_star = E / (2 * (1 - nu * nu));
    const double tc = hertz ? 2.868 * std::pow(m * m / (0.5 * r * e_star * e_star * v0), 0.2)
                            : std::numbers::pi * std::sqrt(m / k);
    auto c = test::base_case(tc / 1000, 1.0, {-1.2, -1.2, -0.05}, {1.2, 1.2, 0.05});
    test::add_material(c, "grain", rho, E, nu);
    std::map<std::string, double> prm{{"restitution", e}, {"friction", 0.0}};
    if (!hertz) prm["stiffness"] = k;
    test::add_contact(c, "grain", "grain", model, prm);
    test::add_spheres(c, "grain", r, {{R, 0, 0}});
    c.particles[0].fixed = true;
    config::Motion turn;
    turn.rotates = true;
    turn.axis = {0, 0, 1};
    turn.center = {0, 0, 0};
    turn.rate = omega;
    c.particles[0].motion = turn;
    test::add_spheres(c, "grain", r, {{R, 2 * r + 1e-4, 0}});
    Simulation sim(c);
    bool touched = false;
    int steps = 0;
    for (; steps < 10000000; ++steps) {
      sim.step();
      if (sim.n_contacts() > 0)
        touched = true;
      else if (touched)
        break;
    }
    ASSERT_TRUE(touched);
    const auto& p = sim.particles();
    const std::size_t a = index_of(sim, 1), b = index_of(sim, 2);
    // The arm's point under the free grain moves at Omega R along the arm's normal (y at the
    // moment of contact, turned by Omega t since): the relative normal velocity after.
    const Vec3 arm_dir = normalized(p.x()[a]);
    const Vec3 path = cross(Vec3{0, 0, 1}, arm_dir);
    const double v_after = dot(p.v()[b], path);
    const double e_seen = (v_after - dot(p.v()[a], path)) / v0;
    std::printf(
        "turning arm (%s): requested e = %.3f, realised %.5f (%.3f %%), free grain "
        "leaves at %.5f Omega R; the fixed grain moved %.3e m, at %.5f m/s\n",
        model, e, e_seen, 100 * (e_seen / e - 1), v_after / v0, norm(p.x()[a] - Vec3{R, 0, 0}),
        norm(p.v()[a]));
    EXPECT_NEAR(e_seen, e, 0.01 * e);
    EXPECT_NEAR(v_after / v0, 1 + e, 0.01 * (1 + e));
    EXPECT_NEAR(norm(p.v()[a]), v0, 1e-12);
    EXPECT_NEAR(norm(p.x()[a]), R, 1e-12);
  }
}

// A sphere on a conveyor. A free glass sphere (r = 2 mm) rests on top of a fixed sphere so large
// (R = 0.5 m) that its top is a flat plate for it; at t0 = 5 ms (the sphere settled) the plate
// starts translating at V = 0.05 m/s along x (translate.start). Friction mu = 0.4 (Hooke, no
// rolling resistance): the sphere slides with a = mu g, spins up with dw/dt = 5 mu g / (2 r)
// (the torque mu m g r over I = 2/5 m r^2) until its contact point moves with the plate,
// v + w r = V, at t* = 2 V / (7 mu g); from then it rolls at v = 2 V / 7, spinning at w r = 5 V / 7
// (rolling on the plate that moves at V under it: a free sphere on a
// moving plate never reaches the plate's speed: the friction that would accelerate it further
// would spin it faster than rolling allows). The plate's velocity field is what makes the
// friction act: were its grain's velocity left at zero, the sphere would see no sliding and stay.
// Tolerances: a and dw/dt within 1 % (fit over the middle of the sliding phase; the normal force
// is m g to the curvature of the plate, whose slope under the sphere stays below 1e-3, and the
// settling's ringing, damped to < 1e-4 m g; the tangential spring reaches the Coulomb bound
// within mu m g / (k_t V) ~ 2 us, one step), t* within 2 % (one part in ~600 steps and the
// tangential spring's transition from sliding to sticking), the rolling speed 2 V / 7 within
// 2 % over a window after t* (the elastic ringing of the tangential spring when it sticks,
// amplitude mu g / omega_t ~ 2.5 % of 2 V / 7, damped over a few of its 0.6 ms periods and
// averaged out over the 5 ms window).
TEST(ValidationFixedMotion, SphereOnAConveyorSlidesAtMuGThenRolls) {
  const double g = 9.81, mu = 0.4, V = 0.05, r = 0.002, R = 0.5, rho = 2500, k = 1e4;
  const double m = rho * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double tc = std::numbers::pi * std::sqrt(m / k);
  const double dt = tc / 50, t0 = 0.005;
  auto c = test::base_case(dt, 1.0, {-0.6, -0.6, -0.6}, {0.6, 0.6, 0.6});
  c.gravity = {0, 0, -g};
  test::add_material(c, "glass", rho, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hooke",
                    {{"restitution", 0.5}, {"friction", mu}, {"stiffness", k}});
  test::add_spheres(c, "glass", R, {{0, 0, 0}});
  c.particles[0].fixed = true;
  c.particles[0].motion = translation({V, 0, 0}, t0);
  const double overlap = m * g / k;  // resting on it from the start
  test::add_spheres(c, "glass", r, {{0, 0, R + r - overlap}});
  Simulation sim(c);
  const double t_star = 2 * V / (7 * mu * g);
  std::vector<double> ts, vs, ws;
  Dump trace("fixed_conveyor", "t_over_tstar,v_over_V,w_r_over_V");
  double roll_v = 0, roll_w = 0;
  int roll_n = 0;
  double t_lock = -1;
  const std::size_t b = index_of(sim, 2);
  while (sim.time() < t0 + 3 * t_star) {
    sim.step();
    const auto& p = sim.particles();
    const std::size_t i = p.id()[b] == 2 ? b : index_of(sim, 2);
    const double t = sim.time() - t0;
    const double v = p.v()[i].x, w = p.omega()[i].y;
    if (t < 0) continue;
    if (sim.step_count() % 20 == 0) trace.row(t / t_star, v / V, -w * r / V);
    if (t > 0.1 * t_star && t < 0.8 * t_star) {
      ts.push_back(t);
      vs.push_back(v);
      ws.push_back(w);
    }
    // The contact point's slip V - (v - w r) (w < 0: rolling along +x) falls to zero at t*.
    if (t_lock < 0 && V - (v - w * r) < 1e-3 * V) t_lock = t;
    if (t > 2 * t_star) {
      roll_v += v;
      roll_w += -w * r;
      ++roll_n;
    }
  }
  // Least-squares slopes over the sliding phase.
  auto slope = [&](const std::vector<double>& y) { return test::least_squares_slope(ts, y); };
  const double a = slope(vs), alpha = -slope(ws);
  roll_v /= roll_n;
  roll_w /= roll_n;
  std::printf(
      "conveyor: a = %.5f m/s^2 (mu g = %.5f, %.3f %%), dw/dt = %.4f rad/s^2 (5 mu g / "
      "2r = %.4f, %.3f %%), slip ends at %.4e s (t* = %.4e s, %.3f %%), rolls at %.5f "
      "m/s (2V/7 = %.5f, %.3f %%), w r = %.5f m/s (5V/7 = %.5f)\n",
      a, mu * g, 100 * (a / (mu * g) - 1), alpha, 5 * mu * g / (2 * r),
      100 * (alpha / (5 * mu * g / (2 * r)) - 1), t_lock, t_star, 100 * (t_lock / t_star - 1),
      roll_v, 2 * V / 7, 100 * (roll_v / (2 * V / 7) - 1), roll_w, 5 * V / 7);
  RecordProperty("acceleration_over_mu_g", std::to_string(a / (mu * g)));
  EXPECT_NEAR(a, mu * g, 0.01 * mu * g);
  EXPECT_NEAR(alpha, 5 * mu * g / (2 * r), 0.01 * 5 * mu * g / (2 * r));
  EXPECT_NEAR(t_lock, t_star, 0.02 * t_star);
  EXPECT_NEAR(roll_v, 2 * V / 7, 0.02 * 2 * V / 7);
  EXPECT_NEAR(roll_w, 5 * V / 7, 0.02 * 5 * V / 7);  // its contact point moves with the plate
}

// A block on a conveyor (2D). A free square (side 3.5 mm) lies face down on a fixed square plate
// (side 0.18 m) that starts translating at V = 0.1 m/s at t0 = 10 ms: a block does not roll, so
// friction accelerates it at a = mu g until it moves with the plate, at t* = V / (mu g), and the
// plate then carries it along at V. mu = 0.4 (below 1: the friction couple cannot tip a square).
// Tolerances: a within 1 % (fit over the middle of the sliding phase; as above), t* within 2 %,
// the carried speed V within 1 % (averaged after 1.5 t*: the tangential spring's ringing when it
// sticks is mu g / omega_t ~ 0.3 % of V here and damped).
TEST(ValidationFixedMotion, BlockOnAConveyorIsCarriedAlongAfterSlidingAtMuG) {
  const double g = 9.81, mu = 0.4, V = 0.1, r = 0.002, R = 0.1, rho = 2500, k = 2e4;
  const double thickness = 0.01;
  const double m = rho * std::numbers::pi * r * r * thickness;
  const double tc = std::numbers::pi * std::sqrt(m / k);
  const double t0 = 0.01;
  auto c = test::base_case(tc / 50, 1.0, {-0.3, -0.3, 0}, {0.3, 0.3, 0});
  c.dimension = 2;
  c.domain.thickness = thickness;
  c.gravity = {0, -g, 0};
  test::add_material(c, "stone", rho, 1e7, 0.3);
  test::add_contact(c, "stone", "stone", "hooke",
                    {{"restitution", 0.5}, {"friction", mu}, {"stiffness", k}});
  const Quat faces = quat_from_axis_angle({0, 0, 1}, 0.25 * std::numbers::pi);
  const double half_plate = 0.5 * std::sqrt(std::numbers::pi) * R;
  const double half_block = 0.5 * std::sqrt(std::numbers::pi) * r;
  test::add_polygons(c, "stone", R, 4, {{0, 0, 0}}, {faces});
  c.particles[0].fixed = true;
  c.particles[0].motion = translation({V, 0, 0}, t0);
  test::add_polygons(c, "stone", r, 4, {{0, half_plate + half_block - 1e-6, 0}}, {faces});
  Simulation sim(c);
  const double t_star = V / (mu * g);
  std::vector<double> ts, vs;
  Dump trace("fixed_conveyor_block", "t_over_tstar,v_over_V");
  double carried = 0, turn = 0;
  int carried_n = 0;
  double t_lock = -1;
  while (sim.time() < t0 + 2.5 * t_star) {
    sim.step();
    const auto& p = sim.particles();
    const std::size_t i = index_of(sim, 2);
    const double t = sim.time() - t0, v = p.v()[i].x;
    if (t < 0) continue;
    if (sim.step_count() % 50 == 0) trace.row(t / t_star, v / V);
    if (t > 0.1 * t_star && t < 0.8 * t_star) {
      ts.push_back(t);
      vs.push_back(v);
    }
    if (t_lock < 0 && V - v < 1e-3 * V) t_lock = t;
    if (t > 1.5 * t_star) {
      carried += v;
      ++carried_n;
    }
    turn = std::max(turn, std::abs(p.omega()[i].z));
  }
  const double a = test::least_squares_slope(ts, vs);
  carried /= carried_n;
  std::printf(
      "block on conveyor: a = %.5f m/s^2 (mu g = %.5f, %.3f %%), carried from %.4e s "
      "(t* = %.4e s, %.3f %%) at %.6f m/s (V = %.3f, %.3f %%); largest spin %.3e rad/s\n",
      a, mu * g, 100 * (a / (mu * g) - 1), t_lock, t_star, 100 * (t_lock / t_star - 1), carried, V,
      100 * (carried / V - 1), turn);
  EXPECT_NEAR(a, mu * g, 0.01 * mu * g);
  EXPECT_NEAR(t_lock, t_star, 0.02 * t_star);
  EXPECT_NEAR(carried, V, 0.01 * V);
}
