// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of the continuum module: the SPH kernel, the rheologies and their registry, the
// solver's set-up checks, the `continuum:` block's reader.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <numbers>
#include <string>
#include <tuple>

#include "continuum/rheology_registry.hpp"
#include "continuum/sph.hpp"
#include "core/error.hpp"
#include "core/files.hpp"
#include "input_error.hpp"
#include "io/input/echo.hpp"
#include "io/input/parse_continuum.hpp"
#include "io/restart/h5.hpp"
#include "simulation/continuum_case.hpp"
#include "temp_dir.hpp"

namespace gf::continuum {
namespace {

TEST(SphKernel, NormalisedAndDerivativeMatchesDifferences) {
  for (int dim : {2, 3}) {
    const WendlandC2 w(dim, 0.7);
    // integral of W over its support by the midpoint rule in r
    const int n = 20000;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      const double r = (i + 0.5) * w.support() / n;
      const double shell = dim == 2 ? 2 * std::numbers::pi * r : 4 * std::numbers::pi * r * r;
      sum += w.value(r) * shell * w.support() / n;
    }
    EXPECT_NEAR(sum, 1.0, 1e-7) << dim << "D";
    for (double r : {0.05, 0.3, 0.9, 1.3}) {
      const double e = 1e-6;
      EXPECT_NEAR(w.derivative(r), (w.value(r + e) - w.value(r - e)) / (2 * e),
                  1e-6 * std::fabs(w.derivative(0.7)));
    }
    EXPECT_EQ(w.value(w.support()), 0.0);
    EXPECT_EQ(w.derivative(w.support() * 1.01), 0.0);
  }
}

TEST(ContinuumRheology, MuIFrictionViscosityAndCap) {
  const auto p = prepare_rheology(
      "mu_i", {{"grain_diameter", 1e-3}, {"grain_density", 2500}, {"max_viscosity", 100}});
  EXPECT_DOUBLE_EQ(p.mu_s, 0.382);  // Jop et al. (2006) defaults
  // I = gamma_dot d sqrt(rho_s / p): gamma_dot = 10, p = 25 -> I = 0.1
  const double mu = MuI::friction(0.1, p);
  EXPECT_NEAR(mu, 0.382 + (0.643 - 0.382) * 0.1 / (0.279 + 0.1), 1e-15);
  EXPECT_NEAR(apparent_viscosity(10.0, 25.0, p), mu * 25.0 / 10.0, 1e-12);
  EXPECT_NEAR(MuI::inertial_number_for(mu, p), 0.1, 1e-12);
  EXPECT_EQ(apparent_viscosity(1e-6, 250.0, p), 100.0);  // capped
  EXPECT_EQ(apparent_viscosity(0.0, 250.0, p), 100.0);
  EXPECT_EQ(apparent_viscosity(10.0, -5.0, p), 0.0);  // no pressure, no friction
  const auto n = prepare_rheology("newtonian", {{"viscosity", 1e-3}});
  EXPECT_EQ(apparent_viscosity(123.0, 4.0, n), 1e-3);
}

TEST(ContinuumRheology, RegistryRefusesBadParameters) {
  EXPECT_THROW(prepare_rheology("bingham", {}), Error);
  EXPECT_THROW(prepare_rheology("newtonian", {}), Error);  // viscosity is required
  EXPECT_THROW(prepare_rheology("newtonian", {{"viscosity", -1}}), Error);
  EXPECT_THROW(prepare_rheology("newtonian", {{"viscosity", 1}, {"mu_s", 1}}), Error);
  EXPECT_THROW(
      prepare_rheology(
          "mu_i",
          {{"grain_diameter", 1e-3}, {"grain_density", 2500}, {"max_viscosity", 1}, {"mu_s", 0.7}}),
      Error);  // mu_2 = 0.643 < mu_s
  EXPECT_NE(find_rheology("mu_i"), nullptr);
  EXPECT_EQ(rheology_infos().size(), Rheologies::size);
}

SphConfig small_tank() {
  SphConfig c;
  c.dimension = 2;
  c.domain.lo = {-0.03, -0.03, 0};
  c.domain.hi = {0.13, 0.2, 0};
  c.gravity = {0, -9.81, 0};
  c.spacing = 0.01;
  c.density = 1000;
  c.sound_speed = 20;
  c.rheology = prepare_rheology("newtonian", {{"viscosity", 1e-3}});
  c.blocks.push_back({{0, 0, 0}, {0.1, 0.1, 0}, {}, true});
  SphWall floor;
  floor.name = "floor";
  floor.lo = {-0.03, -0.03, 0};
  floor.hi = {0.13, 0, 0};
  c.walls.push_back(floor);
  return c;
}

TEST(SphSolver, BuildsLatticeWithHydrostaticStart) {
  const SphSolver s(small_tank());
  EXPECT_EQ(s.n_fluid(), 100u);
  EXPECT_EQ(s.particles().size() - s.n_fluid(), 16u * 3u);
  // bottom row (y = 0.005): p = rho g (0.1 - 0.005)
  const auto& p = s.particles();
  for (std::size_t i = 0; i < s.n_fluid(); ++i) {
    if (p.x[i].y < 0.01) {
      EXPECT_NEAR(p.p[i], 1000 * 9.81 * 0.095, 1e-9);
    }
  }
  EXPECT_NEAR(s.density_of(s.pressure_of(1003.0)), 1003.0, 1e-9);
}

TEST(SphSolver, RefusesOverlapsWallsOutsideAndShortPeriods) {
  auto c = small_tank();
  c.blocks.push_back({{0.05, 0.05, 0}, {0.1, 0.1, 0}, {}, false});
  EXPECT_THROW(SphSolver{c}, InputError);
  c = small_tank();
  c.walls[0].lo.y = -0.05;  // below domain.min
  EXPECT_THROW(SphSolver{c}, InputError);
  c = small_tank();
  c.domain.periodic[0] = true;
  c.domain.hi.x = c.domain.lo.x + 0.04;  // below 2 x 2h = 0.052
  EXPECT_THROW(SphSolver{c}, Error);
}

TEST(SphSolver, CylinderShellIsHollowAndParticlesLeavingAreRemoved) {
  auto c = small_tank();
  SphWall cyl;
  cyl.name = "post";
  cyl.shape = SphWall::Shape::Cylinder;
  cyl.center = {0.06, 0.16, 0};
  cyl.radius = 0.03;
  cyl.thickness = 0.015;
  c.walls.push_back(cyl);
  c.blocks[0].velocity = {3.0, 0, 0};  // the block runs out through x = 0.13
  SphSolver s(c);
  const auto& p = s.particles();
  std::size_t in_post = 0;
  for (std::size_t i = s.n_fluid(); i < p.size(); ++i)
    if (p.wall_index[i] == 1) {
      ++in_post;
      const double r = norm(p.x[i] - cyl.center);
      EXPECT_LE(r, 0.03 + 1e-12);
      EXPECT_GE(r, 0.015 - 1e-12);
    }
  EXPECT_GT(in_post, 10u);
  while (s.time() < 0.1) s.step();
  EXPECT_GT(s.n_removed(), 0u);
  EXPECT_EQ(s.n_fluid() + s.n_removed(), 100u);
  for (std::size_t i = 0; i < s.n_fluid(); ++i) EXPECT_LE(s.particles().x[i].x, 0.13);
}

// A wall that translates and rotates moves rigidly: after time t each particle is at
// c0 + V t + R(Omega t) (x(0) - c0), distances between its particles are kept, its velocity is
// V + Omega x (x - c(t)); the lattice was first turned by initial_angle about c0.
TEST(SphSolver, TranslatingRotatingWallMovesRigidly) {
  auto c = small_tank();
  SphWall blade;
  blade.name = "blade";
  blade.lo = {0.02, 0.13, 0};
  blade.hi = {0.08, 0.16, 0};
  blade.velocity = {0.2, -0.1, 0};
  blade.angular_velocity = {0, 0, 3.0};
  blade.rotation_center = Vec3{0.04, 0.15, 0};  // off the box's centre
  const Vec3 c0{0.04, 0.15, 0}, vel{0.2, -0.1, 0};
  auto straight = c;
  straight.walls.push_back(blade);
  blade.initial_angle = 0.4;
  c.walls.push_back(blade);
  const SphSolver s0(straight);
  SphSolver s(c);
  auto of_blade = [](const SphSolver& sv) {
    std::vector<Vec3> x, u;
    const auto& p = sv.particles();
    for (std::size_t i = sv.n_fluid(); i < p.size(); ++i)
      if (p.wall_index[i] == 1) {
        x.push_back(p.x[i]);
        u.push_back(p.u_wall[i]);
      }
    return std::make_pair(x, u);
  };
  const auto [lattice, u_lattice] = of_blade(s0);
  auto turned = [&](const Vec3& x, double angle) {
    const Vec3 d = x - c0;
    return Vec3{std::cos(angle) * d.x - std::sin(angle) * d.y,
                std::sin(angle) * d.x + std::cos(angle) * d.y, 0.0};
  };
  const auto [x0, u0] = of_blade(s);
  ASSERT_EQ(x0.size(), 18u);  // 6 x 3 lattice points
  ASSERT_EQ(x0.size(), lattice.size());
  for (std::size_t k = 0; k < x0.size(); ++k) {
    EXPECT_LT(norm(x0[k] - (c0 + turned(lattice[k], 0.4))), 1e-15);
    // u = V + Omega x (x - c0) at t = 0 (Omega along z: Omega x d = Omega (-d_y, d_x))
    const Vec3 d = x0[k] - c0;
    EXPECT_LT(norm(u0[k] - (vel + Vec3{-3.0 * d.y, 3.0 * d.x, 0})), 1e-14);
    EXPECT_LT(
        norm(u_lattice[k] - (vel + Vec3{-3.0 * (lattice[k] - c0).y, 3.0 * (lattice[k] - c0).x, 0})),
        1e-14);
  }
  while (s.time() < 0.05 - 1e-12) s.step(0.05);
  EXPECT_GT(s.steps(), 10);
  const double t = s.time();
  const Vec3 ct = c0 + t * vel;
  EXPECT_LT(norm(s.wall_center(1) - ct), 1e-15);
  EXPECT_EQ(s.wall_center(0), (Vec3{0.05, -0.015, 0}));  // a fixed box: its centre
  const auto [x, u] = of_blade(s);
  for (std::size_t k = 0; k < x.size(); ++k) {
    EXPECT_LT(norm(x[k] - (ct + turned(x0[k], 3.0 * t))), 1e-15) << k;
    const Vec3 d = x[k] - ct;
    EXPECT_LT(norm(u[k] - (vel + Vec3{-3.0 * d.y, 3.0 * d.x, 0})), 1e-14) << k;
    for (std::size_t q = 0; q < k; ++q) EXPECT_NEAR(norm(x[k] - x[q]), norm(x0[k] - x0[q]), 1e-15);
  }
  // the fixed floor has not moved
  for (std::size_t i = s.n_fluid(); i < s.particles().size(); ++i)
    if (s.particles().wall_index[i] == 0) {
      EXPECT_EQ(s.particles().x[i], s0.particles().x[i]);
      EXPECT_EQ(s.particles().u_wall[i], Vec3{});
    }
}

TEST(SphSolver, RefusesRotationsItCannotDefine) {
  auto message = [](const SphConfig& cfg) -> std::string {
    try {
      SphSolver s(cfg);
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  };
  auto c = small_tank();
  c.walls[0].angular_velocity = {1.0, 0, 0};  // 2D: about z only
  EXPECT_THAT(message(c), ::testing::HasSubstr("a 2D wall rotates about z only"));
  c = small_tank();
  c.dimension = 3;
  c.gravity = {0, -9.81, 0};
  c.domain.hi.z = 0.04;
  c.blocks[0].hi.z = 0.04;
  c.walls[0].hi.z = 0.04;
  EXPECT_EQ(message(c), "no error");
  c.walls[0].initial_angle = 0.5;  // 3D without an axis
  EXPECT_THAT(message(c), ::testing::HasSubstr("an initial angle in 3D needs a non-zero"));
  c.walls[0].angular_velocity = {0, 0.5, 0};
  c.walls[0].initial_angle = std::numbers::pi;  // about y through its centre: onto itself
  EXPECT_EQ(message(c), "no error");
}

/// A granular gas by kinetic theory (lun, e = 0.8, d = 1 mm, rho_s = 2500, dense packing 0.6)
/// at volume fraction a and Theta0 = 0.01 m^2/s^2 in a periodic square box, no gravity.
SphConfig kt_gas_box(double a, const char* dense, std::map<std::string, double> dense_params = {}) {
  SphConfig c;
  c.dimension = 2;
  c.domain.lo = {0, 0, 0};
  c.domain.hi = {0.06, 0.06, 0};
  c.domain.periodic = {true, true, false};
  c.spacing = 0.005;
  c.density = 0.6 * 2500;
  c.sound_speed = 10;
  c.rheology = prepare_rheology(
      "mu_i", {{"grain_diameter", 1e-3}, {"grain_density", 2500}, {"max_viscosity", 50}});
  SphKineticTheory kt;
  kt.closures = prepare_ktgf(
      "lun", {{"restitution", 0.8}, {"grain_diameter", 1e-3}, {"grain_density", 2500}});
  kt.dense = prepare_frictional(dense, dense_params);
  kt.initial_temperature = 0.01;
  c.kinetic_theory = kt;
  SphBlock b{{0, 0, 0}, {0.06, 0.06, 0}, {}, false};
  b.volume_fraction = a;
  c.blocks.push_back(b);
  return c;
}

// A granular gas sheared between moving Johnson-Jackson walls (slip, slip work and wall
// dissipation at play): a run continued from its state goes on bit-identically, explicit and
// implicit (the walls' heat and mirrored velocities are computed from the state alone).
TEST(SphSolver, JohnsonJacksonWallsContinueBitIdentically) {
  for (const bool implicit : {false, true}) {
    auto c = kt_gas_box(0.2, "mu_i_switch");
    c.domain.periodic = {true, false, false};
    c.domain.lo.y = -0.015;
    c.domain.hi.y = 0.075;
    c.implicit_viscosity = implicit;
    SphWall floor;
    floor.name = "floor";
    floor.lo = {0, -0.015, 0};
    floor.hi = {0.06, 0, 0};
    floor.velocity = {-1.0, 0, 0};
    floor.johnson_jackson = SphWall::JohnsonJackson{0.3, 0.8};
    SphWall lid = floor;
    lid.name = "lid";
    lid.lo = {0, 0.06, 0};
    lid.hi = {0.06, 0.075, 0};
    lid.velocity = {1.0, 0, 0};
    c.walls = {floor, lid};
    SphSolver a(c);
    for (int q = 0; q < 60; ++q) a.step();
    SphSolver b(c);
    b.restore(a.state());
    for (int q = 0; q < 60; ++q) {
      a.step();
      b.step();
    }
    for (std::size_t i = 0; i < a.n_fluid(); ++i) {
      ASSERT_EQ(a.particles().x[i], b.particles().x[i]) << i << " " << implicit;
      ASSERT_EQ(a.particles().v[i], b.particles().v[i]) << i << " " << implicit;
      ASSERT_EQ(a.particles().theta[i], b.particles().theta[i]) << i << " " << implicit;
    }
    EXPECT_GT(std::fabs(a.particles().v[0].x), 0.0);  // (sheared)
  }
}

// A Johnson-Jackson wall needs kinetic theory (an input error for a case built in code too) and
// is neither free-slip nor given a slip length.
TEST(SphSolver, RefusesJohnsonJacksonWallsItCannotUse) {
  auto c = small_tank();
  c.walls[0].johnson_jackson = SphWall::JohnsonJackson{0.5, 0.9};
  EXPECT_THROW(SphSolver{c}, InputError);
  auto k = kt_gas_box(0.2, "mu_i_switch");
  k.domain.periodic = {true, false, false};
  k.domain.lo.y = -0.02;
  SphWall floor;
  floor.name = "floor";
  floor.lo = {0, -0.02, 0};
  floor.hi = {0.06, 0, 0};
  floor.johnson_jackson = SphWall::JohnsonJackson{0.5, 0.9};
  k.walls.push_back(floor);
  EXPECT_NO_THROW(SphSolver{k});
  k.walls[0].slip_length = 0.01;
  EXPECT_THROW(SphSolver{k}, Error);
  k.walls[0].slip_length = 0.0;
  k.walls[0].johnson_jackson->specularity = 1.5;
  EXPECT_THROW(SphSolver{k}, Error);
}

// The solver evaluates the closures once per particle and step, at unit temperature, scaled by
// Theta (P_s ~ Theta, mu_s ~ sqrt(Theta)), and the dense model's viscosity from that mu_s: each
// particle's pressure and viscosity must be those of ktgf.hpp's functions at its state, in both
// dense models, below and above their limits. A gas at rest (div v and gamma_dot zero to
// round-off) cooling for a few steps.
TEST(SphSolver, KineticTheoryStateMatchesTheClosures) {
  struct Case {
    double a;
    const char* dense;
    std::map<std::string, double> params;
  };
  const Case cases[] = {{0.2, "mu_i_switch", {{"frictional_limit", 0.5}}},
                        {0.57, "mu_i_switch", {{"frictional_limit", 0.5}}},
                        {0.2, "schaeffer_johnson_jackson", {}},
                        {0.57, "schaeffer_johnson_jackson", {}}};
  for (const auto& k : cases) {
    const auto c = kt_gas_box(k.a, k.dense, k.params);
    SphSolver s(c);
    for (int q = 0; q < 5; ++q) s.step();
    const auto& kt = *c.kinetic_theory;
    const auto& p = s.particles();
    for (std::size_t i = 0; i < s.n_fluid(); ++i) {
      const double a = p.rho[i] / kt.closures.density, theta = p.theta[i];
      ASSERT_LT(p.gamma_dot[i], 1e-12);  // (round-off of a uniform state)
      EXPECT_LT(theta, 0.01);            // (it cools)
      double pressure = solids_pressure(a, theta, kt.closures) +
                        std::max(0.0, s.pressure_of(p.rho[i]) - c.background_pressure) +
                        c.background_pressure;
      if (std::string(k.dense) == "schaeffer_johnson_jackson")
        pressure += johnson_jackson_pressure(a, kt.dense);
      const double eta =
          effective_shear_viscosity(a, theta, p.gamma_dot[i], std::max(pressure, 0.0), kt.closures,
                                    kt.dense, c.rheology)
              .viscosity;
      EXPECT_NEAR(p.p[i], pressure, 1e-12 * pressure) << k.a << " " << k.dense;
      EXPECT_NEAR(p.eta[i], eta, 1e-12 * eta) << k.a << " " << k.dense;
    }
  }
}

// Granular gases leaving the domain: the solver carries each particle's closures and
// conductivity with it as particles are removed (no new evaluation), and a restore recomputes
// them from the state as a step does: a run continued from its state after removals must go on
// bit-identically, with more removals.
TEST(SphSolver, KineticTheoryContinuesBitIdenticallyAfterRemovals) {
  auto c = kt_gas_box(0.2, "mu_i_switch");
  c.domain.periodic = {false, true, false};
  c.domain.hi.x = 0.1;
  // two gases, a = 0.2 and 0.1 (different conductivities), out through x = 0.1
  c.blocks[0].hi.x = 0.03;
  c.blocks.push_back(c.blocks[0]);
  c.blocks[1].lo.x = 0.03;
  c.blocks[1].hi.x = 0.06;
  c.blocks[1].volume_fraction = 0.1;
  for (auto& b : c.blocks) b.velocity = {2.0, 0, 0};
  c.kinetic_theory->initial_temperature = 0.5;
  SphSolver a(c);
  while (a.n_removed() == 0) a.step();
  for (int q = 0; q < 20; ++q) a.step();
  const auto removed = a.n_removed();
  SphSolver b(c);
  b.restore(a.state());
  for (int q = 0; q < 200; ++q) {
    a.step();
    b.step();
  }
  EXPECT_GT(a.n_removed(), removed);  // more left after the restore
  EXPECT_EQ(a.n_removed(), b.n_removed());
  ASSERT_EQ(a.n_fluid(), b.n_fluid());
  for (std::size_t i = 0; i < a.n_fluid(); ++i) {
    ASSERT_EQ(a.particles().x[i], b.particles().x[i]) << i;
    ASSERT_EQ(a.particles().v[i], b.particles().v[i]) << i;
    ASSERT_EQ(a.particles().theta[i], b.particles().theta[i]) << i;
  }
  EXPECT_EQ(a.time(), b.time());
}

}  // namespace
}  // namespace gf::continuum

namespace gf::input {
namespace {

const char* kContinuumBlock = R"(continuum:
  method: sph
  dimension: 2
  domain: {min: [0, 0], max: [1, 1]}
  gravity: [0, -9.81]
  spacing: 0.05
  density: 1500
  rheology: {model: mu_i, grain_diameter: 1.0e-3, grain_density: 2500, max_viscosity: 100}
  time: {end: 0.1, viscous: implicit}
  blocks:
    - {box: {min: [0.1, 0.1], max: [0.3, 0.3]}, hydrostatic: true}
  walls:
    - {name: floor, box: {min: [0, 0], max: [1, 0.1]}}
)";

ContinuumCase parse_text(const std::string& text) {
  const auto root = YamlNode::parse_text(text, "case.yaml");
  return parse_continuum(YamlMap(root, {"continuum"}).at("continuum"));
}

std::string error_of(const std::string& text) {
  return test::input_error_of([&] { parse_text(text); }, "no error");
}

TEST(ContinuumInput, ReadsTheBlockWithDefaults) {
  const auto c = parse_text(kContinuumBlock);
  EXPECT_EQ(c.rheology, "mu_i");
  EXPECT_TRUE(c.sph.implicit_viscosity);
  EXPECT_DOUBLE_EQ(c.sph.smoothing_ratio, 1.3);
  EXPECT_DOUBLE_EQ(c.sph.rheology.mu_s, 0.382);
  // c0 = 10 sqrt(2 g H), H = 0.2 m the block's height along gravity
  EXPECT_NEAR(c.sph.sound_speed, 10 * std::sqrt(2 * 9.81 * 0.2), 1e-12);
  ASSERT_EQ(c.sph.walls.size(), 1u);
  EXPECT_EQ(c.sph.walls[0].name, "floor");
}

TEST(ContinuumInput, ReadsWallMotionAndCylinderBlocks) {
  std::string text = kContinuumBlock;
  text.replace(text.find("  walls:"), std::string::npos,
               R"(    - {cylinder: {center: [0.6, 0.6], radius: 0.2, thickness: 0.1}}
  walls:
    - {name: floor, box: {min: [0, 0], max: [1, 0.1]}}
    - {name: blade, box: {min: [0.5, 0.2], max: [0.7, 0.25]}, velocity: [0.1, 0],
       angular_velocity: -2.5, rotation_center: [0.6, 0.3], initial_angle: 0.25}
    - {name: drum, cylinder: {center: [0.6, 0.6], radius: 0.3, thickness: 0.1},
       angular_velocity: 1.5, slip: free_slip}
    - {name: chute, box: {min: [0, 0.9], max: [1, 1]}, slip: {slip_length: 0.002}}
)");
  const auto c = parse_text(text);
  ASSERT_EQ(c.sph.walls.size(), 4u);
  EXPECT_EQ(c.sph.walls[0].slip_length, 0.0);
  EXPECT_FALSE(c.sph.walls[3].free_slip);
  EXPECT_EQ(c.sph.walls[3].slip_length, 0.002);
  const auto& floor = c.sph.walls[0];
  EXPECT_EQ(floor.angular_velocity, Vec3{});
  EXPECT_FALSE(floor.rotation_center.has_value());
  EXPECT_EQ(floor.initial_angle, 0.0);
  const auto& blade = c.sph.walls[1];
  EXPECT_EQ(blade.velocity, (Vec3{0.1, 0, 0}));
  EXPECT_EQ(blade.angular_velocity, (Vec3{0, 0, -2.5}));
  ASSERT_TRUE(blade.rotation_center.has_value());
  EXPECT_EQ(*blade.rotation_center, (Vec3{0.6, 0.3, 0}));
  EXPECT_EQ(blade.initial_angle, 0.25);
  EXPECT_EQ(c.sph.walls[2].angular_velocity, (Vec3{0, 0, 1.5}));
  EXPECT_FALSE(c.sph.walls[2].rotation_center.has_value());  // the solver takes the centre
  EXPECT_FALSE(floor.free_slip);                             // no slip by default
  EXPECT_TRUE(c.sph.walls[2].free_slip);
  ASSERT_EQ(c.sph.blocks.size(), 2u);
  const auto& ring = c.sph.blocks[1];
  EXPECT_EQ(ring.shape, continuum::SphBlock::Shape::Cylinder);
  EXPECT_EQ(ring.center, (Vec3{0.6, 0.6, 0}));
  EXPECT_EQ(ring.radius, 0.2);
  EXPECT_EQ(ring.thickness, 0.1);
  // its bounding box, for the default sound speed
  EXPECT_LT(norm(ring.lo - Vec3{0.4, 0.4, 0}), 1e-15);
  EXPECT_LT(norm(ring.hi - Vec3{0.8, 0.8, 0}), 1e-15);
}

TEST(ContinuumInput, ErrorsNameLineKeyAndExpectation) {
  std::string text = kContinuumBlock;
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  EXPECT_THAT(error_of(with("spacing:", "spacng:")),
              ::testing::HasSubstr("case.yaml:6:3: error: continuum.spacng: unknown key"));
  EXPECT_THAT(error_of(with("max_viscosity: 100", "max_viscosity: -1")),
              ::testing::HasSubstr("continuum.rheology.max_viscosity: expected a number"));
  EXPECT_THAT(error_of(with(", max_viscosity: 100", "")),
              ::testing::HasSubstr("rheology 'mu_i' needs 'max_viscosity'"));
  EXPECT_THAT(error_of(with("model: mu_i", "model: bingham")),
              ::testing::HasSubstr("expected a rheology: newtonian, mu_i"));
  EXPECT_THAT(error_of(with("viscous: implicit", "viscous: sometimes")),
              ::testing::HasSubstr("continuum.time.viscous"));
  EXPECT_THAT(error_of(with("max: [1, 1]}", "max: [1, 1, 1]}")),
              ::testing::HasSubstr("expected 2 components in a 2D case"));
  // wall motion: a 2D rotation is a rate about z, not a vector
  EXPECT_THAT(error_of(with("max: [1, 0.1]}}", "max: [1, 0.1]}, angular_velocity: [0, 0, 1]}")),
              ::testing::HasSubstr("case.yaml:13:74: error: continuum.walls[0].angular_velocity: "
                                   "expected a number in a 2D case"));
  EXPECT_THAT(error_of(with("max: [1, 0.1]}}", "max: [1, 0.1]}, rotation_center: [0.5]}")),
              ::testing::HasSubstr("continuum.walls[0].rotation_center"));
  EXPECT_THAT(error_of(with("max: [1, 0.1]}}", "max: [1, 0.1]}, initial_angle: fast}")),
              ::testing::HasSubstr("continuum.walls[0].initial_angle: expected a number"));
  EXPECT_THAT(error_of(with("max: [1, 0.1]}}", "max: [1, 0.1]}, angular_velocty: 1}")),
              ::testing::HasSubstr("continuum.walls[0].angular_velocty: unknown key"));
  EXPECT_THAT(error_of(with("max: [1, 0.1]}}", "max: [1, 0.1]}, slip: partial}")),
              ::testing::HasSubstr("continuum.walls[0].slip: expected one of no_slip, free_slip"));
  EXPECT_THAT(error_of(with("max: [1, 0.1]}}", "max: [1, 0.1]}, slip: {slip_length: 0}}")),
              ::testing::HasSubstr("continuum.walls[0].slip.slip_length: expected a number > 0"));
  EXPECT_THAT(error_of(with("max: [1, 0.1]}}", "max: [1, 0.1]}, slip: {length: 0.1}}")),
              ::testing::HasSubstr("continuum.walls[0].slip.length: unknown key"));
  EXPECT_THAT(error_of(with("max: [1, 0.1]}}", "max: [1, 0.1]}, slip: [0.1]}")),
              ::testing::HasSubstr("continuum.walls[0].slip: expected no_slip, free_slip, "
                                   "{slip_length: b} (partial slip, m) or {specularity: phi', "
                                   "wall_restitution: e_w}"));
  // 3D: an initial angle needs the rotation's axis
  std::string three = R"(continuum:
  method: sph
  dimension: 3
  domain: {min: [0, 0, 0], max: [1, 1, 1]}
  gravity: [0, -9.81, 0]
  spacing: 0.05
  density: 1000
  rheology: {model: newtonian, viscosity: 1.0e-3}
  time: {end: 0.1}
  blocks:
    - {box: {min: [0.1, 0.1, 0.1], max: [0.3, 0.3, 0.3]}}
  walls:
    - {name: blade, box: {min: [0.5, 0, 0], max: [0.6, 0.5, 0.5]}, initial_angle: 0.3}
)";
  EXPECT_THAT(error_of(three),
              ::testing::HasSubstr("continuum.walls[0].initial_angle: in 3D an initial_angle "
                                   "turns the wall about its angular_velocity"));
  three.replace(three.find("initial_angle"), 0, "angular_velocity: [0, 0, 2], ");
  EXPECT_EQ(parse_text(three).sph.walls[0].angular_velocity, (Vec3{0, 0, 2}));
}

// The resolved case written into the output folder loads back to the same configuration: for
// every shipped continuum case, echo -> load -> echo gives the same text (every echoed key round
// trips) and the same derived numbers (the default sound speed, the rheology's constants).
TEST(ContinuumInput, ReadsKineticTheory) {
  std::string text = kContinuumBlock;
  const std::string kt = R"(  kinetic_theory:
    closures: gidaspow
    radial_distribution: lun_savage
    packing_limit: 0.63
    restitution: 0.8
    grain_diameter: 1.0e-3
    grain_density: 2500
    initial_temperature: 0.01
    dense: {model: mu_i_switch, frictional_limit: 0.5}
)";
  auto with_kt = [&](std::string t) {
    t.insert(t.find("  time:"), kt);
    return t;
  };
  text = with_kt(text);
  text.replace(text.find("hydrostatic: true}"), 18, "volume_fraction: 0.3}");
  const auto c = parse_text(text);
  ASSERT_TRUE(c.sph.kinetic_theory.has_value());
  const auto& k = *c.sph.kinetic_theory;
  EXPECT_EQ(k.closures.model, index_of_key(continuum::KtgfClosures{}, "gidaspow"));
  EXPECT_EQ(k.closures.radial, index_of_key(continuum::RadialDistributions{}, "lun_savage"));
  EXPECT_EQ(k.closures.packing_limit, 0.63);
  EXPECT_EQ(k.closures.restitution, 0.8);
  EXPECT_EQ(k.initial_temperature, 0.01);
  EXPECT_EQ(k.min_temperature, 1e-10);  // default
  EXPECT_EQ(k.dense.frictional_limit, 0.5);
  EXPECT_EQ(c.sph.blocks[0].volume_fraction, 0.3);
  EXPECT_EQ(c.ktgf_closures, "gidaspow");
  EXPECT_EQ(c.ktgf_dense, "mu_i_switch");
  // errors name the key and what was expected
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  EXPECT_THAT(error_of(with("closures: gidaspow", "closures: enskog")),
              ::testing::HasSubstr("continuum.kinetic_theory.closures: expected a KTGF closure "
                                   "set: lun, syamlal, gidaspow"));
  EXPECT_THAT(error_of(with("    restitution: 0.8\n", "")),
              ::testing::HasSubstr("[missing key] KTGF closure set 'gidaspow' needs "
                                   "'restitution'"));
  EXPECT_THAT(error_of(with("restitution: 0.8", "restitution: 1.5")),
              ::testing::HasSubstr("continuum.kinetic_theory.restitution: expected a number"));
  EXPECT_THAT(error_of(with("packing_limit: 0.63", "packing_limt: 0.63")),
              ::testing::HasSubstr("continuum.kinetic_theory.packing_limt: unknown key"));
  EXPECT_THAT(error_of(with("model: mu_i_switch", "model: plastic")),
              ::testing::HasSubstr("continuum.kinetic_theory.dense.model: expected a dense-regime "
                                   "model: schaeffer_johnson_jackson, mu_i_switch"));
  EXPECT_THAT(
      error_of(with("{model: mu_i_switch, frictional_limit: 0.5}",
                    "{model: schaeffer_johnson_jackson, min_fraction: 0.6, max_fraction: 0.55}")),
      ::testing::HasSubstr("min_fraction = 0.6 must be below max_fraction = 0.55"));
  // a volume fraction needs kinetic theory
  std::string plain = kContinuumBlock;
  plain.replace(plain.find("hydrostatic: true}"), 18, "volume_fraction: 0.3}");
  EXPECT_THAT(error_of(plain), ::testing::HasSubstr("continuum.blocks[0].volume_fraction: a "
                                                    "block's volume fraction needs "
                                                    "kinetic_theory"));
}

// Johnson-Jackson walls: `slip: {specularity: phi', wall_restitution: e_w}`, kinetic theory only;
// echoed into the resolved case and read back; bad input names file, line, column and key.
TEST(ContinuumInput, ReadsJohnsonJacksonWalls) {
  std::string text = kContinuumBlock;
  text.insert(text.find("  time:"), R"(  kinetic_theory:
    restitution: 0.8
    grain_diameter: 1.0e-3
    grain_density: 2500
)");
  text.replace(text.find("hydrostatic: true}"), 18, "volume_fraction: 0.3}");
  const std::string floor = "max: [1, 0.1]}}";
  text.replace(text.find(floor), floor.size(),
               "max: [1, 0.1]}, slip: {specularity: 0.25, wall_restitution: 0.9}}");
  const auto c = parse_text(text);
  ASSERT_TRUE(c.sph.walls[0].johnson_jackson.has_value());
  EXPECT_EQ(c.sph.walls[0].johnson_jackson->specularity, 0.25);
  EXPECT_EQ(c.sph.walls[0].johnson_jackson->wall_restitution, 0.9);
  EXPECT_FALSE(c.sph.walls[0].free_slip);
  EXPECT_EQ(c.sph.walls[0].slip_length, 0.0);
  // the resolved case holds it and loads back the same
  const std::string echoed = echo_continuum_yaml(c, "test");
  EXPECT_NE(echoed.find("slip: {specularity: 0.25, wall_restitution: 0.9}"), std::string::npos)
      << echoed;
  const auto root = YamlNode::parse_text(echoed, "resolved_case.yaml");
  const auto again = parse_continuum(YamlMap(root).at("continuum"));
  ASSERT_TRUE(again.sph.walls[0].johnson_jackson.has_value());
  EXPECT_EQ(again.sph.walls[0].johnson_jackson->specularity, 0.25);
  EXPECT_EQ(again.sph.walls[0].johnson_jackson->wall_restitution, 0.9);
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  EXPECT_THAT(error_of(with("specularity: 0.25", "specularity: 1.5")),
              ::testing::HasSubstr("continuum.walls[0].slip.specularity: expected a number in "
                                   "[0, 1]"));
  EXPECT_THAT(error_of(with("wall_restitution: 0.9", "wall_restitution: -0.1")),
              ::testing::HasSubstr("continuum.walls[0].slip.wall_restitution: expected a number "
                                   "in [0, 1]"));
  EXPECT_THAT(error_of(with(", wall_restitution: 0.9", "")),
              ::testing::HasSubstr("continuum.walls[0].slip.wall_restitution"));
  EXPECT_THAT(error_of(with("specularity: 0.25", "specularty: 0.25")),
              ::testing::HasSubstr("continuum.walls[0].slip.specularty: unknown key"));
  EXPECT_THAT(error_of(with("{specularity: 0.25", "{slip_length: 0.01, specularity: 0.25")),
              ::testing::HasSubstr("continuum.walls[0].slip: either {slip_length: b} (Navier "
                                   "slip) or {specularity: phi', wall_restitution: e_w}"));
  // without kinetic theory: an error at the value, line 13 column 76 of the block's text
  std::string plain = kContinuumBlock;
  plain.replace(plain.find(floor), floor.size(),
                "max: [1, 0.1]}, slip: {specularity: 0.25, wall_restitution: 0.9}}");
  EXPECT_THAT(error_of(plain),
              ::testing::HasSubstr("case.yaml:13:76: error: continuum.walls[0].slip.specularity: "
                                   "the Johnson-Jackson wall condition (specularity, "
                                   "wall_restitution) needs kinetic_theory"));
}

// The command line refuses a Johnson-Jackson wall without kinetic theory: exit code 2, the
// message (file:line:column, key) on stderr, nothing written.
TEST(ContinuumInput, JohnsonJacksonWallWithoutKineticTheoryExitsWithTwo) {
  std::string text = read_text_file(std::filesystem::path(GF_SOURCE_DIR) / "cases" / "continuum" /
                                    "paddle_mixer" / "case.yaml");
  const std::string navier = "slip: {slip_length: 0.006}";
  const auto at = text.find(navier);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, navier.size(), "slip: {specularity: 0.5, wall_restitution: 0.9}");
  const auto line =
      1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
  // (1-based, at the value of specularity)
  const auto column = at - text.rfind('\n', at) + std::string("slip: {specularity: ").size();
  test::TempDir dir;
  const auto bad = dir.write("bad.yaml", text);
  const std::string cmd = std::string(GF_BINARY) + " run " + bad.string() + " --output " +
                          (dir.path() / "out").string() + " > " + (dir.path() / "log").string() +
                          " 2>&1";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  const std::string log = read_text_file(dir.path() / "log");
  EXPECT_NE(log.find(fmt::format("bad.yaml:{}:{}: error: continuum.walls[", line, column)),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("].slip.specularity: the Johnson-Jackson wall condition"), std::string::npos)
      << log;
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "out"));
}

TEST(ContinuumInput, ResolvedCaseLoadsBackTheSame) {
  int n_cases = 0;
  for (const auto& e : std::filesystem::directory_iterator(GF_SOURCE_DIR "/cases/continuum")) {
    const auto file = e.path() / "case.yaml";
    if (!std::filesystem::exists(file)) continue;
    ++n_cases;
    std::filesystem::path dir;
    const auto a = load_continuum_case(file, dir, {});
    ASSERT_TRUE(a.has_value()) << file;
    const std::string text = echo_continuum_yaml(*a, "test");
    EXPECT_NE(text.find("sound_speed:"), std::string::npos);
    test::TempDir tmp;
    const auto echoed = tmp.path() / "resolved_case.yaml";
    write_atomically(echoed, [&](std::ostream& o) { o << text; });
    const auto b = load_continuum_case(echoed, dir, {});
    ASSERT_TRUE(b.has_value()) << file;
    const std::string again = echo_continuum_yaml(*b, "test");
    // (the first line names the file echoed; a default sound speed is given in the echo)
    std::string first = text.substr(text.find('\n'));
    const std::string note = " (default: 10 sqrt(2 |g| H))";
    if (const auto at = first.find(note); at != std::string::npos) first.erase(at, note.size());
    EXPECT_EQ(first, again.substr(again.find('\n'))) << file;
    EXPECT_EQ(a->sph.sound_speed, b->sph.sound_speed) << file;
    EXPECT_EQ(a->sph.rheology.model, b->sph.rheology.model) << file;
    EXPECT_EQ(a->sph.rheology.mu_s, b->sph.rheology.mu_s) << file;
    EXPECT_EQ(a->sph.rheology.max_viscosity, b->sph.rheology.max_viscosity) << file;
    EXPECT_EQ(a->sph.rheology.viscosity, b->sph.rheology.viscosity) << file;
    EXPECT_EQ(a->sph.walls.size(), b->sph.walls.size()) << file;
    EXPECT_EQ(a->sph.blocks.size(), b->sph.blocks.size()) << file;
  }
  EXPECT_GE(n_cases, 4);
}

}  // namespace
}  // namespace gf::input

namespace gf {
namespace {

// A run whose weakly compressible model breaks down stops with an error naming the time: here
// a block falls past ten times the sound speed it was given (c0 = 0.1 m/s: 1 m/s after 0.09 s
// of fall and of its own expansion).
TEST(ContinuumRun, StopsARunThatDiverges) {
  test::TempDir tmp;
  auto c = input::parse_text(R"(continuum:
  method: sph
  dimension: 2
  domain: {min: [0, -10], max: [0.1, 0.1]}
  gravity: [0, -9.81]
  spacing: 0.01
  density: 1000
  sound_speed: 0.1
  rheology: {model: newtonian, viscosity: 1.0e-3}
  time: {end: 1.0}
  blocks:
    - {box: {min: [0.02, 0.02], max: [0.08, 0.08]}}
)");
  c.name = "diverging";
  c.file = "case.yaml";
  RunOptions o;
  o.output = tmp.path() / "run";
  o.quiet = true;
  try {
    run_continuum_case(c, {}, o);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("SPH: the run diverged at t = 0.08"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("over ten times the sound speed 0.1 m/s"));
  }
}

// A continuum run continued from a checkpoint ends bit-identically to one that ran straight
// through, in a new folder and with --append in its own (series and ParaView files as the
// straight run's), explicit and implicit viscosity, with a translating and rotating wall.
TEST(ContinuumRestart, ContinuesBitIdentically) {
  // (modes 2, 3: a granular gas by kinetic theory, whose temperatures must continue too;
  // explicit, and implicit viscosity and conduction)
  for (const int mode : {0, 1, 2, 3}) {
    const bool implicit = mode == 1 || mode == 3;
    test::TempDir tmp;
    std::string text = R"(continuum:
  method: sph
  dimension: 2
  domain: {min: [-0.02, -0.02], max: [0.3, 0.15]}
  gravity: [0, -9.81]
  spacing: 0.005
  density: 1500
  rheology: {model: mu_i, grain_diameter: 1.0e-3, grain_density: 2500, max_viscosity: 200}
  time: {end: 1.0, viscous: VISCOUS}
  blocks:
    - {box: {min: [0, 0], max: [0.05, 0.05]}, hydrostatic: true}
  walls:
    - {name: floor, box: {min: [-0.02, -0.02], max: [0.3, 0]}}
    - {name: left, box: {min: [-0.02, 0], max: [0, 0.1]}}
    - {name: paddle, box: {min: [0.055, 0.005], max: [0.07, 0.045]}, angular_velocity: 5,
       initial_angle: 0.05, velocity: [0.1, 0]}
  output: {vtk_every: 0.002, series_every: 0.0005, checkpoint_every: 0.003}
)";
    text.replace(text.find("VISCOUS"), 7, implicit ? "implicit" : "explicit");
    if (mode >= 2) {
      text.insert(text.find("  time:"), R"(  kinetic_theory:
    restitution: 0.8
    grain_diameter: 1.0e-3
    grain_density: 2500
    initial_temperature: 0.001
)");
      text.replace(text.find("hydrostatic: true}"), 18, "volume_fraction: 0.3}");
    }
    auto c = input::parse_text(text);
    c.name = "restart";
    c.file = "case.yaml";
    RunOptions straight;
    straight.output = tmp.path() / "straight";
    straight.steps = 120;
    ASSERT_EQ(run_continuum_case(c, {}, straight), 0);
    RunOptions first = straight;
    first.output = tmp.path() / "split";
    first.steps = 50;
    ASSERT_EQ(run_continuum_case(c, {}, first), 0);
    RunOptions fresh;
    fresh.output = tmp.path() / "fresh";
    fresh.restart = tmp.path() / "split" / "sph_checkpoint_final.h5";
    fresh.steps = 70;
    ASSERT_EQ(run_continuum_case(c, {}, fresh), 0);
    RunOptions append = fresh;
    append.output = tmp.path() / "split";
    append.append = true;
    ASSERT_EQ(run_continuum_case(c, {}, append), 0);
    auto state = [](const std::filesystem::path& f) {
      auto h = io::h5::File::open_read(f);
      return std::make_tuple(h.read_vec3("particles/x"), h.read_vec3("particles/v"),
                             h.read_double("particles/rho"), h.read_int_attribute("/", "steps"),
                             h.read_double_attribute("/", "time"),
                             h.read_double("particles/theta"));
    };
    const auto ref = state(tmp.path() / "straight" / "sph_checkpoint_final.h5");
    EXPECT_EQ(std::get<3>(ref), 120);
    if (mode >= 2) {
      EXPECT_GT(std::get<5>(ref)[0], 0.0);  // (a fluid particle's temperature)
    }
    EXPECT_TRUE(state(tmp.path() / "fresh" / "sph_checkpoint_final.h5") == ref) << implicit;
    EXPECT_TRUE(state(tmp.path() / "split" / "sph_checkpoint_final.h5") == ref) << implicit;
    EXPECT_EQ(read_text_file(tmp.path() / "split" / "sph_series.csv"),
              read_text_file(tmp.path() / "straight" / "sph_series.csv"));
    EXPECT_EQ(read_text_file(tmp.path() / "split" / "sph_particles.pvd"),
              read_text_file(tmp.path() / "straight" / "sph_particles.pvd"));
    // a checkpoint of another case is refused with a clear error
    auto other = c;
    other.sph.walls.pop_back();
    auto elsewhere = fresh;
    elsewhere.output = tmp.path() / "other";
    EXPECT_THROW(run_continuum_case(other, {}, elsewhere), InputError);
    EXPECT_FALSE(std::filesystem::exists(tmp.path() / "other"));  // nothing written
  }
}

}  // namespace
}  // namespace gf
