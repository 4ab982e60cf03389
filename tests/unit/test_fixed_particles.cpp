// SPDX-License-Identifier: GPL-3.0-or-later
// Fixed (frozen) particle groups: they never move under either integrator, for every shape, in
// 2D and 3D, periodic and Lees-Edwards boxes; checkpoints continue them bit-identically; their
// input errors, echo, outputs, the fixed_force series, the time-step check, and the reduced mass
// the contact law takes against them.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "case_builder.hpp"
#include "contact/models.hpp"
#include "contact/pair_forces.hpp"
#include "core/error.hpp"
#include "core/files.hpp"
#include "io/csv/csv.hpp"
#include "io/input/echo.hpp"
#include "io/input/parse_case.hpp"
#include "io/input/validate.hpp"
#include "io/vtk/vtk.hpp"
#include "simulation/simulation.hpp"
#include "state_compare.hpp"
#include "temp_dir.hpp"
#include "vtk_reader.hpp"

using namespace gf;

namespace {

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

/// What must not change for a fixed grain: position, velocity, angular velocity and, with
/// shapes, orientation and angular momentum.
struct Frozen {
  Vec3 x, v, w, L;
  Quat q;
};

/// The state of every fixed grain, by id (the store re-orders its particles at list builds).
std::map<std::int64_t, Frozen> fixed_grains(const Simulation& sim) {
  const auto& p = sim.particles();
  std::map<std::int64_t, Frozen> out;
  if (!p.has_fixed()) return out;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.fixed()[i] == 0) continue;
    Frozen f{p.x()[i], p.v()[i], p.omega()[i], {}, {}};
    if (p.has_shapes()) {
      f.L = p.angular_momentum()[i];
      f.q = p.orientation()[i];
    }
    out[p.id()[i]] = f;
  }
  return out;
}

/// Runs `steps` steps and checks that the fixed grains kept every bit of their state, that they
/// were at rest to begin with, and that free grains pressed on them (fixed_force non-zero at some
/// step). Returns the largest |fixed_force| seen, N.
double run_and_expect_frozen(Simulation& sim, int steps) {
  const auto before = fixed_grains(sim);
  EXPECT_FALSE(before.empty());
  for (const auto& [id, f] : before) {
    EXPECT_EQ(f.v, Vec3{}) << id;
    EXPECT_EQ(f.w, Vec3{}) << id;
  }
  double load = 0;
  for (int s = 0; s < steps; ++s) {
    sim.step();
    load = std::max(load, std::abs(sim.quantity("fixed_force.x")) +
                              std::abs(sim.quantity("fixed_force.y")) +
                              std::abs(sim.quantity("fixed_force.z")));
  }
  const auto after = fixed_grains(sim);
  EXPECT_EQ(after.size(), before.size());
  for (const auto& [id, f] : before) {
    const auto it = after.find(id);
    if (it == after.end()) {
      ADD_FAILURE() << "fixed grain " << id << " lost";
      continue;
    }
    EXPECT_TRUE(same_bits(it->second.x, f.x)) << "position of fixed grain " << id;
    EXPECT_TRUE(same_bits(it->second.v, f.v)) << "velocity of fixed grain " << id;
    EXPECT_TRUE(same_bits(it->second.w, f.w)) << "angular velocity of fixed grain " << id;
    EXPECT_TRUE(same_bits(it->second.L, f.L)) << "angular momentum of fixed grain " << id;
    EXPECT_TRUE(same_bits(it->second.q, f.q)) << "orientation of fixed grain " << id;
  }
  EXPECT_GT(load, 0.0) << "no free grain touched the fixed ones";
  return load;
}

/// A rough base of 100 fixed glass spheres (r = 1 mm, touching, on a steel floor they overlap)
/// under 60 free spheres thrown down at it, gravity on, periodic in x and y.
config::Case sphere_bed_case(const std::string& integrator) {
  auto c = test::base_case(5e-6, 1.0, {0, 0, 0}, {0.02, 0.02, 0.03}, {true, true, false});
  c.integrator = integrator;
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_material(c, "steel", 7800, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin",
                    {{"restitution", 0.5}, {"friction", 0.5}, {"rolling_friction", 0.1}});
  test::add_contact(c, "glass", "steel", "hooke",
                    {{"restitution", 0.5}, {"friction", 0.5}, {"stiffness", 1e3}});
  test::add_fixed_sphere_layer(c, "glass", 0.001, 0.002, 0, 0.02, 0, 0.02, 0.001);
  auto& f = test::add_box_fill(c, "glass", 0.0008, 0.0012, {0, 0, 0.003}, {0.02, 0.02, 0.012},
                               config::Fill::Lattice::Random);
  f.count = 60;
  f.seed = 4;
  f.velocity = {0.1, 0, -0.6};
  f.velocity_jitter = 0.3;
  // The floor cuts into the fixed grains (z = 0.5 mm < r): were they not left out of the wall
  // list, it would push on them.
  test::add_plane(c, "floor", {0, 0, 0.0005}, {0, 0, 1}, "steel");
  c.output.quantities = {"fixed_force"};
  return c;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Fixed grains never move

class FixedParticlesIntegrator : public ::testing::TestWithParam<const char*> {};

// Spheres, with gravity and impacts (the free grains hit the bed at ~0.7 m/s and pile up on it),
// under velocity Verlet (with the deferred kick, as runs do) and Gear.
TEST_P(FixedParticlesIntegrator, SpheresKeepEveryBitUnderImpacts) {
  Simulation sim(sphere_bed_case(GetParam()));
  const auto before = fixed_grains(sim);
  ASSERT_EQ(before.size(), 100u);
  const auto& p = sim.particles();
  // The run's own loop defers the second half kick when nothing reads the velocities.
  for (int s = 0; s < 1000; ++s) sim.step(/*defer_kick=*/true);
  sim.complete_step();
  run_and_expect_frozen(sim, 5000);
  EXPECT_GT(sim.n_contacts(), 0);
  EXPECT_EQ(p.size(), 160u);
  // The floor never saw a grain: the fixed ones are not in its list, the free ones stay above.
  EXPECT_EQ(sim.n_wall_contacts(), 0);
  EXPECT_EQ(sim.walls()[0].force, Vec3{});
}

INSTANTIATE_TEST_SUITE_P(Both, FixedParticlesIntegrator,
                         ::testing::Values("velocity_verlet", "gear5"),
                         [](const auto& param_info) { return std::string(param_info.param); });

// Spherocylinders in several orientations (rigid rotation of the store with shapes) under free
// spherocylinders and spheres: orientation and angular momentum keep their bits too.
TEST(FixedParticles, SpherocylindersKeepEveryBit) {
  auto c = test::base_case(5e-6, 1.0, {0, 0, 0}, {0.024, 0.024, 0.03}, {true, true, false});
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "pom", 1400, 1e7, 0.3);
  test::add_contact(c, "pom", "pom", "hertz_mindlin",
                    {{"restitution", 0.5}, {"friction", 0.4}, {"rolling_friction", 0.05}});
  std::vector<Vec3> x;
  std::vector<Quat> q;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      x.push_back({0.003 + 0.006 * i, 0.003 + 0.006 * j, 0.0015});
      // Axes tilted every way: a turn of 0.3 .. 2.5 rad about horizontal axes of every heading.
      const double a = 0.7 * (i + 4 * j);
      q.push_back(
          quat_from_axis_angle(Vec3{std::cos(a), std::sin(a), 0}, 0.3 + 0.15 * (i + 4 * j) / 1.1));
    }
  test::add_capsules(c, "pom", 0.001, 0.004, x, q).fixed = true;
  auto& rods = test::add_capsule_fill(c, "pom", 0.001, 2.5, {0, 0, 0.006}, {0.024, 0.024, 0.02},
                                      config::Fill::Lattice::Random);
  rods.count = 25;
  rods.seed = 9;
  rods.velocity = {0, 0, -0.5};
  rods.velocity_jitter = 0.3;
  c.output.quantities = {"fixed_force"};
  Simulation sim(c);
  ASSERT_TRUE(sim.particles().has_shapes());
  run_and_expect_frozen(sim, 6000);
}

namespace {

/// A 2D box (periodic in x) with a row of fixed grains at the bottom and free ones falling on
/// them: disks, or regular hexagons (and random polygons falling).
config::Case two_d_case(bool polygons, const std::string& integrator) {
  auto c = test::base_case(5e-6, 1.0, {0, 0, 0}, {0.04, 0.04, 0}, {true, false, false});
  c.dimension = 2;
  c.domain.thickness = 0.01;
  c.gravity = {0, -9.81, 0};
  c.integrator = integrator;
  test::add_material(c, "stone", 2600, 1e7, 0.3);
  test::add_contact(c, "stone", "stone", "hooke",
                    {{"restitution", 0.4}, {"friction", 0.5}, {"stiffness", 2e4}});
  std::vector<Vec3> base;
  std::vector<Quat> angles;
  for (int i = 0; i < 10; ++i) {
    base.push_back({0.002 + 0.004 * i, 0.002, 0});
    angles.push_back(quat_from_axis_angle(Vec3{0, 0, 1}, 0.3 * i));
  }
  if (polygons)
    test::add_polygons(c, "stone", 0.0018, 6, base, angles).fixed = true;
  else
    test::add_disks(c, "stone", 0.0018, base).fixed = true;
  // (polygons are placed by the sphere that holds any orientation: a taller region for them)
  auto& f = test::add_box_fill(c, "stone", 0.0012, 0.0016, {0, 0.006, 0},
                               {0.04, polygons ? 0.04 : 0.03, 0}, config::Fill::Lattice::Random);
  f.count = polygons ? 14 : 30;
  f.seed = 2;
  f.velocity = {0.2, -0.5, 0};
  f.velocity_jitter = 0.3;
  auto& g = c.particles.back();
  if (polygons) {
    g.kind = config::Shape::Polygon;
    g.shape = "polygon";
    g.polygon.kind = config::PolygonSpec::Kind::Random;
    g.polygon.min_vertices = 4;
    g.polygon.max_vertices = 7;
  } else {
    g.kind = config::Shape::Disk;
    g.shape = "disk";
  }
  c.output.quantities = {"fixed_force"};
  return c;
}

}  // namespace

class FixedParticles2D : public ::testing::TestWithParam<std::tuple<bool, const char*>> {};

TEST_P(FixedParticles2D, DisksAndPolygonsKeepEveryBit) {
  const auto [polygons, integrator] = GetParam();
  Simulation sim(two_d_case(polygons, integrator));
  EXPECT_EQ(sim.particles().has_shapes(), polygons);
  run_and_expect_frozen(sim, 8000);
  // 2D: the free grains stay in the plane and the fixed ones too.
  for (std::size_t i = 0; i < sim.particles().size(); ++i) EXPECT_EQ(sim.particles().x()[i].z, 0.0);
}

INSTANTIATE_TEST_SUITE_P(ShapesAndIntegrators, FixedParticles2D,
                         ::testing::Combine(::testing::Bool(),
                                            ::testing::Values("velocity_verlet", "gear5")),
                         [](const auto& param_info) {
                           return std::string(std::get<0>(param_info.param) ? "polygons_"
                                                                            : "disks_") +
                                  std::get<1>(param_info.param);
                         });

// Lees-Edwards: the grains start on the mean shear profile, except the fixed ones (obstacles at
// rest in the flow); the free grains wrap through the sliding boundary, the fixed ones near it
// do not move.
TEST(FixedParticles, StayPutInALeesEdwardsBox) {
  auto c = test::base_case(1e-5, 1.0, {0, 0, 0}, {0.02, 0.02, 0.02}, {true, true, true});
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin",
                    {{"restitution", 0.7}, {"friction", 0.5}});
  config::Shear sh;
  sh.rate = 50;
  sh.boundary = config::Shear::Boundary::LeesEdwards;
  sh.initial_profile = true;
  c.shear = sh;
  // Obstacles next to the top and bottom faces, where the profile's speed is largest.
  test::add_spheres(c, "glass", 0.0015,
                    {{0.005, 0.01, 0.0016}, {0.015, 0.01, 0.0184}, {0.01, 0.004, 0.01}});
  c.particles.back().fixed = true;
  auto& f = test::add_box_fill(c, "glass", 0.001, 0.001, {0, 0, 0}, {0.02, 0.02, 0.02},
                               config::Fill::Lattice::Random);
  f.count = 150;
  f.seed = 3;
  c.output.quantities = {"fixed_force"};
  Simulation sim(c);
  run_and_expect_frozen(sim, 3000);  // a strain of 1.5
}

// ---------------------------------------------------------------------------------------------
// Contacts with fixed grains

// Two fixed grains never interact (the list leaves their pairs out, and validate accepts their
// overlap); a free grain overlapping a fixed one is refused.
TEST(FixedParticles, FixedGrainsDoNotTouchOneAnother) {
  auto c = test::base_case(1e-5, 1.0, {0, 0, 0}, {0.02, 0.02, 0.02});
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin", {{"restitution", 0.5}});
  test::add_spheres(c, "glass", 0.002, {{0.008, 0.01, 0.01}, {0.011, 0.01, 0.01}});
  c.particles.back().fixed = true;
  EXPECT_NO_THROW(input::validate(c));
  Simulation sim(c);
  EXPECT_EQ(sim.neighbor_list().n_pairs(), 0u);
  EXPECT_EQ(sim.n_contacts(), 0);
  EXPECT_EQ(sim.quantity("elastic_energy"), 0.0);
  for (std::size_t i = 0; i < 2; ++i) EXPECT_EQ(sim.particles().f()[i], Vec3{});

  test::add_spheres(c, "glass", 0.001, {{0.0125, 0.01, 0.01}});  // into the second one
  try {
    input::validate(c);
    ADD_FAILURE() << "the overlap of a free and a fixed grain was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("overlaps particle 1 of particles[0]"), std::string::npos)
        << e.what();
  }
}

namespace {

/// A free glass sphere (r = 2 mm) pressed into a fixed one of the same size by `overlap`,
/// approaching at `speed`, no gravity. Extra material "rubber" with `other_model` for the
/// glass-rubber and rubber-rubber pairs when given (a case with two laws: the per-contact
/// dispatch of the force loop instead of the batched one).
config::Case pressed_pair(double overlap, double speed, const std::string& other_model = "") {
  auto c = test::base_case(1e-6, 1.0, {0, 0, 0}, {0.02, 0.02, 0.02});
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin",
                    {{"restitution", 0.5}, {"friction", 0.5}});
  if (!other_model.empty()) {
    test::add_material(c, "rubber", 1100, 1e6, 0.45);
    std::map<std::string, double> prm{{"restitution", 0.8}};
    if (other_model == "hooke") prm["stiffness"] = 500;
    test::add_contact(c, "glass", "rubber", other_model, prm);
    test::add_contact(c, "rubber", "rubber", other_model, prm);
  }
  const double r = 0.002;
  test::add_spheres(c, "glass", r, {{0.01, 0.01, 0.01}});
  c.particles.back().fixed = true;
  // Slightly off the vertical, so that the tangential spring and dashpot act too.
  const Vec3 n = normalized(Vec3{0.3, 0.1, 1});
  test::add_spheres(c, "glass", r, {Vec3{0.01, 0.01, 0.01} + (2 * r - overlap) * n},
                    {-speed * Vec3{0, 0, 1}}, {{0, 40, 0}});
  c.output.quantities = {"fixed_force"};
  return c;
}

/// The force on the free grain (id 2) after construction (the constructor evaluates the forces
/// of the initial state), N.
Vec3 free_grain_force(const Simulation& sim) {
  const auto& p = sim.particles();
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.id()[i] == 2) return p.f()[i];
  ADD_FAILURE() << "no grain with id 2";
  return {};
}

void expect_vec_near(const Vec3& a, const Vec3& b, double rel) {
  const double scale = std::max(norm(a), norm(b));
  EXPECT_LE(norm(a - b), rel * scale) << "(" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x
                                      << ", " << b.y << ", " << b.z << ")";
}

}  // namespace

// The contact law sees m* = the free grain's mass against a fixed grain (infinite mass), in all
// three force loops: the batched sphere loop, the per-contact dispatch of cases with several
// laws, and the loop of stores with shapes. Checked against the law evaluated by hand.
TEST(FixedParticles, ContactLawTakesTheFreeGrainsMass) {
  EXPECT_EQ(contact::reduced_mass(2.0, 3.0, false, false), 1.2);
  EXPECT_EQ(contact::reduced_mass(2.0, 3.0, false, true), 2.0);
  EXPECT_EQ(contact::reduced_mass(2.0, 3.0, true, false), 3.0);

  const double overlap = 2e-5, speed = 0.3, r = 0.002;
  const auto cfg = pressed_pair(overlap, speed);
  Simulation sim(cfg);
  const auto& p = sim.particles();
  // The law by hand: the kinematics of the free grain i against the fixed j at rest.
  const Vec3 n = normalized(Vec3{0.3, 0.1, 1});
  const double m = 2500 * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  contact::ContactKinematics kin;
  kin.overlap = overlap;
  kin.normal = n;
  const double arm = r - 0.5 * overlap;
  kin.v_rel = -speed * Vec3{0, 0, 1} - cross(arm * Vec3{0, 40, 0}, n);
  kin.omega_rel = {0, 40, 0};
  kin.r_eff = r / 2;
  kin.m_eff = m;
  Vec3 xi{};
  const auto& coeffs = sim.pairs()(0, 0);
  const auto expected = contact::HertzMindlin::Law::evaluate(coeffs, kin, sim.dt(), xi);
  expect_vec_near(free_grain_force(sim), expected.force, 1e-9);
  // The fixed grain takes the opposite force: the series' fixed_force.
  const Vec3 load{sim.quantity("fixed_force.x"), sim.quantity("fixed_force.y"),
                  sim.quantity("fixed_force.z")};
  expect_vec_near(load, -1.0 * expected.force, 1e-9);
  // With half the mass (the fixed grain's real mass counted in the reduced mass)
  // the damping would be sqrt(2) smaller: a different force, by far more than the tolerance.
  kin.m_eff = 0.5 * m;
  xi = {};
  const auto real_mass = contact::HertzMindlin::Law::evaluate(coeffs, kin, sim.dt(), xi);
  EXPECT_GT(norm(real_mass.force - expected.force), 1e-3 * norm(expected.force));

  // The per-contact dispatch (two laws in the case) and the loop of stores with shapes (a
  // spherocylinder far away) give the same force.
  Simulation mixed(pressed_pair(overlap, speed, "hooke"));
  expect_vec_near(free_grain_force(mixed), expected.force, 1e-9);
  auto with_rod = cfg;
  test::add_capsules(with_rod, "glass", 0.001, 0.002, {{0.003, 0.003, 0.003}});
  Simulation shapes(with_rod);
  ASSERT_TRUE(shapes.particles().has_shapes());
  expect_vec_near(free_grain_force(shapes), expected.force, 1e-9);
  EXPECT_EQ(p.size(), 2u);
}

// A fixed grain overlapping a wall gets no force from it, and the wall none from it; a free
// grain there does.
TEST(FixedParticles, FixedGrainsAndWallsDoNotInteract) {
  auto c = test::base_case(1e-5, 1.0, {0, 0, 0}, {0.02, 0.02, 0.02});
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin", {{"restitution", 0.5}});
  test::add_plane(c, "floor", {0, 0, 0}, {0, 0, 1}, "glass");
  test::add_spheres(c, "glass", 0.002, {{0.005, 0.01, 0.0015}});
  c.particles.back().fixed = true;
  {
    Simulation sim(c);
    EXPECT_EQ(sim.n_wall_contacts(), 0);
    EXPECT_EQ(sim.walls()[0].force, Vec3{});
    EXPECT_EQ(sim.particles().f()[0], Vec3{});
  }
  test::add_spheres(c, "glass", 0.002, {{0.015, 0.01, 0.0015}});
  Simulation sim(c);
  EXPECT_EQ(sim.n_wall_contacts(), 1);
  EXPECT_LT(sim.walls()[0].force.z, 0.0);
}

// The default skin bounds the moves of grains between list builds: fixed grains never move, so a
// large fixed obstacle does not set it (nor inflate the lists of the small free grains).
TEST(FixedParticles, DefaultSkinComesFromTheFreeGrains) {
  auto c = test::base_case(1e-5, 1.0, {0, 0, 0}, {0.1, 0.1, 0.1});
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin", {{"restitution", 0.5}});
  test::add_spheres(c, "glass", 0.02, {{0.05, 0.05, 0.03}});  // a boulder
  c.particles.back().fixed = true;
  auto& f = test::add_box_fill(c, "glass", 0.001, 0.001, {0, 0, 0.06}, {0.1, 0.1, 0.1},
                               config::Fill::Lattice::Cubic);
  f.count = 200;
  Simulation sim(c);
  EXPECT_EQ(sim.neighbor_list().skin(), 0.0005);
  std::string skin;
  for (const auto& [k, v] : input::validate(c).derived)
    if (k == "neighbor skin") skin = v;
  EXPECT_EQ(skin, "0.0005 m (default: half the largest radius of the grains that are not fixed)");
  // Every grain fixed: the largest of them.
  c.particles.back().fixed = true;
  Simulation all_fixed(c);
  EXPECT_EQ(all_fixed.neighbor_list().skin(), 0.01);
}

// ---------------------------------------------------------------------------------------------
// Checkpoints

namespace {

/// a: `before` + `after` steps with a checkpoint in between; b: loads it and takes `after`.
void expect_restart_continues(const config::Case& cfg, const std::string& tag, int before,
                              int after) {
  const auto file = std::filesystem::temp_directory_path() /
                    ("gf_fixed_restart_" + tag + "_" + std::to_string(::getpid()) + ".h5");
  Simulation a(cfg);
  for (int s = 0; s < before; ++s) a.step();
  a.save_checkpoint(file);
  for (int s = 0; s < after; ++s) a.step();
  Simulation b(cfg);
  b.load_checkpoint(file);
  std::filesystem::remove(file);
  EXPECT_EQ(b.step_count() + after, a.step_count());
  for (int s = 0; s < after; ++s) b.step();
  ASSERT_TRUE(b.particles().has_fixed());
  test::expect_same_state(a, b);  // every field, `fixed` included
  EXPECT_EQ(a.quantity("fixed_force.z"), b.quantity("fixed_force.z"));
}

}  // namespace

// (suite name Restart*: also run with two threads, see tests/CMakeLists.txt)
TEST(RestartFixedParticles, SpheresContinueBitIdentically) {
  expect_restart_continues(sphere_bed_case("velocity_verlet"), "spheres", 2500, 2500);
}

TEST(RestartFixedParticles, GearPolygonsContinueBitIdentically) {
  expect_restart_continues(two_d_case(true, "gear5"), "polygons", 3000, 3000);
}

// Runs without a fixed group carry no `fixed` field (their memory, outputs and checkpoints are
// as before); their checkpoints cannot continue a case with a fixed group (the loader names the
// missing field), and a case whose group is no longer fixed continues with the grains free.
TEST(RestartFixedParticles, TheFieldExistsOnlyWithAFixedGroup) {
  auto fixed_case = sphere_bed_case("velocity_verlet");
  auto free_case = fixed_case;
  free_case.particles[0].fixed = false;
  free_case.output.quantities.clear();
  Simulation free_sim(free_case);
  EXPECT_FALSE(free_sim.particles().has_fixed());
  EXPECT_EQ(free_sim.particles().fixed(), nullptr);
  EXPECT_EQ(free_sim.particles().find_field("fixed"), -1);
  const auto file = std::filesystem::temp_directory_path() /
                    ("gf_fixed_field_" + std::to_string(::getpid()) + ".h5");
  free_sim.save_checkpoint(file);
  Simulation fixed_sim(fixed_case);
  try {
    fixed_sim.load_checkpoint(file);
    ADD_FAILURE() << "a checkpoint without the field continued a case with a fixed group";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("particle field 'fixed' missing"), std::string::npos)
        << e.what();
  }
  Simulation(fixed_case).save_checkpoint(file);  // (the failed load emptied fixed_sim)
  Simulation released(free_case);
  released.load_checkpoint(file);
  std::filesystem::remove(file);
  for (int s = 0; s < 200; ++s) released.step();
  // The bed's grains (ids 1-100) move: the floor that cuts into them pushes them away now.
  const auto& p = released.particles();
  std::size_t moving = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.id()[i] <= 100 && norm(p.v()[i]) > 0) ++moving;
  EXPECT_EQ(moving, 100u);
  EXPECT_FALSE(p.has_fixed());
}

// ---------------------------------------------------------------------------------------------
// Outputs and the series

TEST(FixedParticles, ParticleOutputsCarryTheFlag) {
  Simulation sim(sphere_bed_case("velocity_verlet"));
  test::TempDir dir;
  io::write_particles_csv(dir / "p.csv", sim.particles());
  const std::string text = read_text_file(dir / "p.csv");
  const std::string header = text.substr(0, text.find('\n'));
  EXPECT_NE(header.find(",fixed"), std::string::npos) << header;
  io::write_particles_vtp(dir / "p.vtp", sim.particles());
  const test::VtkFile vtp(dir / "p.vtp");
  const auto flags = vtp.get<std::int32_t>("PointData/fixed", "Int32", 1);
  ASSERT_EQ(flags.size(), sim.particles().size());
  std::size_t n_fixed = 0;
  for (std::size_t i = 0; i < flags.size(); ++i) {
    EXPECT_EQ(flags[i], sim.particles().fixed()[i]);
    n_fixed += flags[i] != 0 ? 1 : 0;
  }
  EXPECT_EQ(n_fixed, 100u);
}

TEST(FixedParticles, FixedForceIsAVectorSeriesQuantity) {
  auto c = sphere_bed_case("velocity_verlet");
  c.output.quantities = {"kinetic_energy", "fixed_force", "fixed_force.z"};
  Simulation sim(c);
  EXPECT_EQ(sim.series_columns(),
            (std::vector<std::string>{"kinetic_energy", "fixed_force.x", "fixed_force.y",
                                      "fixed_force.z", "fixed_force.z"}));
  for (int s = 0; s < 4000; ++s) sim.step();
  // The sum over the fixed grains of f - m g, by hand.
  const auto& p = sim.particles();
  Vec3 sum{};
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.fixed()[i] != 0) sum += p.f()[i] - p.mass()[i] * sim.gravity();
  const auto row = sim.series_row(sim.series_columns());
  EXPECT_EQ(row[1], sum.x);
  EXPECT_EQ(row[2], sum.y);
  EXPECT_EQ(row[3], sum.z);
  EXPECT_EQ(row[4], sum.z);
  EXPECT_LT(sum.z, 0.0);  // the free grains press down on the bed

  EXPECT_TRUE(input::is_series_quantity("fixed_force", {}));
  EXPECT_TRUE(input::is_series_quantity("fixed_force.y", {}));
  EXPECT_FALSE(input::is_series_quantity("fixed_force.w", {}));
  EXPECT_FALSE(input::is_series_quantity("fixed_force.xx", {}));
}

namespace {

/// A small case with a fixed bed and a free sphere, `extra` appended to the group of the bed.
std::string bed_case_text(const std::string& bed_extra,
                          const std::string& quantities = "[kinetic_energy, fixed_force.z]") {
  return R"(time: {step: 1.0e-5, end: 0.01}
domain: {min: [0, 0, 0], max: [0.1, 0.1, 0.1]}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
contacts:
  - {between: [glass, glass], model: hertz_mindlin, restitution: 0.5}
particles:
  - radius: 0.005
    material: glass
    fixed: true
)" + bed_extra +
         R"(  - radius: 0.005
    material: glass
    positions: [[0.05, 0.05, 0.08]]
    velocities: [[0, 0, -1]]
output:
  series: {every: 0.001, quantities: )" +
         quantities + "}\n";
}

/// An echo without its first line (which names the file it was read from).
std::string body(const std::string& echo) {
  return echo.substr(echo.find('\n') + 1);
}

/// The message of the InputError of loading and validating `text`, or "".
std::string error_of(const std::string& text, const std::string& file = "t.yaml") {
  try {
    input::validate(input::load_case_text(text, file));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Input

TEST(FixedParticlesInput, FlagIsReadAndDefaultsToFalse) {
  const auto c =
      input::load_case_text(bed_case_text("    positions: [[0.05, 0.05, 0.005]]\n"), "t.yaml");
  ASSERT_EQ(c.particles.size(), 2u);
  EXPECT_TRUE(c.particles[0].fixed);
  EXPECT_FALSE(c.particles[1].fixed);
  EXPECT_EQ(c.output.quantities, (std::vector<std::string>{"kinetic_energy", "fixed_force.z"}));
  // Zero velocities are no velocities: accepted.
  EXPECT_EQ(error_of(bed_case_text("    positions: [[0.05, 0.05, 0.005]]\n"
                                   "    velocities: [[0, 0, 0]]\n"
                                   "    angular_velocities: [[0, 0, 0]]\n")),
            "");
  EXPECT_EQ(error_of(bed_case_text("    fill: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.01]}, "
                                   "velocity: [0, 0, 0], velocity_jitter: 0}\n")),
            "");
  // yes / no are refused as everywhere.
  std::string yes = bed_case_text("    positions: [[0.05, 0.05, 0.005]]\n");
  yes.replace(yes.find("fixed: true"), 11, "fixed: yes");
  EXPECT_NE(error_of(yes).find("t.yaml:10:12: error: particles[0].fixed: expected true, false or "
                               "a prescribed motion"),
            std::string::npos)
      << error_of(yes);
}

// A fixed group with initial velocities is an error at the line of the first moving grain (its
// entry in the list, its line of the CSV file, or the fill's key), with exit code 2.
TEST(FixedParticlesInput, VelocitiesOfAFixedGroupAreRefused) {
  const std::string listed = bed_case_text(
      "    positions: [[0.02, 0.05, 0.005], [0.05, 0.05, 0.005]]\n"
      "    velocities: [[0, 0, 0], [0, 0.1, 0]]\n");
  std::string msg = error_of(listed);
  EXPECT_NE(msg.find("t.yaml:12:29: error: particles[0].velocities[1]: the grains of a fixed "
                     "group (fixed: true) stay at rest; expected no initial velocity (or zero), "
                     "found [0, 0.1, 0] for particle 1"),
            std::string::npos)
      << msg;
  msg =
      error_of(bed_case_text("    positions: [[0.05, 0.05, 0.005]]\n"
                             "    angular_velocities: [[0, 0, 3]]\n"));
  EXPECT_NE(msg.find("t.yaml:12:26: error: particles[0].angular_velocities[0]: the grains of a "
                     "fixed group (fixed: true) stay at rest; expected no initial angular "
                     "velocity (or zero), found [0, 0, 3]"),
            std::string::npos)
      << msg;
  msg =
      error_of(bed_case_text("    fill: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.01]}, "
                             "velocity: [0, 0, -1]}\n"));
  EXPECT_NE(msg.find("t.yaml:11:68: error: particles[0].fill.velocity: the grains of a fixed "
                     "group (fixed: true) stay at rest"),
            std::string::npos)
      << msg;
  msg =
      error_of(bed_case_text("    fill: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.01]}, "
                             "velocity_jitter: 0.1}\n"));
  EXPECT_NE(msg.find("particles[0].fill.velocity_jitter: the grains of a fixed group (fixed: "
                     "true) stay at rest; expected no velocity jitter (or 0), found 0.1"),
            std::string::npos)
      << msg;

  // A CSV file: the error names the file and its line.
  test::TempDir dir;
  std::ofstream(dir / "bed.csv") << "x,y,z,vx,vy,vz\n"
                                    "0.02,0.05,0.005,0,0,0\n"
                                    "# a comment\n"
                                    "0.05,0.05,0.005,0,0,-0.5\n";
  const auto case_file = dir.write("case.yaml", bed_case_text("    file: bed.csv\n"));
  msg.clear();
  try {
    input::load_case(case_file);
  } catch (const InputError& e) {
    msg = e.what();
  }
  EXPECT_NE(msg.find("bed.csv:4:1: error: particles[0].file: columns vx, vy, vz: the grains of a "
                     "fixed group (fixed: true) stay at rest; expected no initial velocity (or "
                     "zero), found [0, 0, -0.5] for particle 1"),
            std::string::npos)
      << msg;

  // The command line: exit code 2 (input error), the message on stderr.
  const auto bad = dir.write("bad.yaml", listed);
  const std::string cmd =
      std::string(GF_BINARY) + " check " + bad.string() + " > " + (dir / "log").string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  EXPECT_NE(read_text_file(dir / "log").find("bad.yaml:12:29: error: particles[0].velocities[1]"),
            std::string::npos)
      << read_text_file(dir / "log");

  // A case built in code is checked by the simulation as well.
  auto c = input::load_case_text(bed_case_text("    positions: [[0.05, 0.05, 0.005]]\n"), "t.yaml");
  c.particles[0].explicit_particles->velocities = {{0, 0, 1}};
  EXPECT_THROW(Simulation{c}, InputError);
}

TEST(FixedParticlesInput, FixedForceNeedsAFixedGroup) {
  std::string text = bed_case_text("    positions: [[0.05, 0.05, 0.005]]\n");
  text.replace(text.find("    fixed: true\n"), 16, "");
  const std::string msg = error_of(text);
  EXPECT_NE(msg.find("series quantity 'fixed_force.z' is the load on fixed grains; it needs a "
                     "particle group with fixed: true"),
            std::string::npos)
      << msg;
  std::string typo = bed_case_text("    positions: [[0.05, 0.05, 0.005]]\n", "[fixed_forse]");
  EXPECT_NE(error_of(typo).find("did you mean 'fixed_force'?"), std::string::npos)
      << error_of(typo);
}

// The echo writes `fixed` for every group and loads back to the same case (and the same echo).
TEST(FixedParticlesInput, EchoRoundTrips) {
  const auto c = input::load_case_text(
      bed_case_text("    fill: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.01]}, lattice: cubic}\n",
                    "[fixed_force, fixed_force.x]"),
      "t.yaml");
  const std::string text = input::echo_yaml(c, "1");
  EXPECT_NE(text.find("fixed: true"), std::string::npos) << text;
  EXPECT_NE(text.find("fixed: false"), std::string::npos) << text;
  test::TempDir dir;
  const auto again = input::load_case(dir.write("echo.yaml", text));
  ASSERT_EQ(again.particles.size(), 2u);
  EXPECT_TRUE(again.particles[0].fixed);
  EXPECT_FALSE(again.particles[1].fixed);
  EXPECT_EQ(again.output.quantities, c.output.quantities);
  // Resolved once, the echo is a fixed point (but for its first line, naming the file read).
  const std::string second = input::echo_yaml(again, "1");
  const auto third = input::load_case(dir.write("echo2.yaml", second));
  EXPECT_EQ(body(input::echo_yaml(third, "1")), body(second));
}

// The shipped rough-incline case: check passes, its echo loads back to the same echo.
TEST(FixedParticlesInput, ShippedRoughInclineEchoRoundTrips) {
  const std::filesystem::path file =
      std::filesystem::path(GF_SOURCE_DIR) / "cases" / "dem" / "rough_incline" / "case.yaml";
  const auto c = input::load_case(file);
  EXPECT_NO_THROW(input::validate(c));
  ASSERT_FALSE(c.particles.empty());
  EXPECT_TRUE(c.particles[0].fixed);
  const std::string text = input::echo_yaml(c, "1");
  test::TempDir dir;
  const auto again = input::load_case(dir.write("echo.yaml", text));
  EXPECT_TRUE(again.particles[0].fixed);
  const std::string second = input::echo_yaml(again, "1");
  const auto third = input::load_case(dir.write("echo2.yaml", second));
  EXPECT_EQ(body(input::echo_yaml(third, "1")), body(second));
}

// The time-step check leaves out what never happens: two fixed grains meeting, and fixed grains
// meeting walls; a free grain meets a fixed one at the impact speed (not twice) with m* its own
// mass; fixed grains do not count in the Rayleigh time. A bed of tiny fixed grains under large
// free ones therefore does not force the tiny grains' time step.
TEST(FixedParticlesInput, TimeStepCheckIgnoresWhatFixedGrainsNeverDo) {
  const std::string text = R"(time: {step: 2.0e-5, end: 0.01}
domain: {min: [0, 0, 0], max: [0.1, 0.1, 0.1]}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
contacts:
  - {between: [glass, glass], model: hertz_mindlin, restitution: 0.5}
particles:
  - radius: 0.0002
    material: glass
    fixed: true
    fill: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.0004]}, lattice: cubic}
  - radius: 0.004
    material: glass
    fill: {box: {min: [0, 0, 0.01], max: [0.1, 0.1, 0.1]}, lattice: random, count: 100}
walls:
  - {name: floor, plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: glass}
)";
  const auto c = input::load_case_text(text, "t.yaml");
  input::CheckReport report;
  ASSERT_NO_THROW(report = input::validate(c)) << error_of(text);
  std::string rayleigh;
  for (const auto& [k, v] : report.derived)
    if (k.rfind("Rayleigh time", 0) == 0) rayleigh = k;
  EXPECT_NE(rayleigh.find("r = 0.004 m"), std::string::npos) << rayleigh;
  // The same grains all free: the tiny ones set a time step 20 times shorter.
  std::string free = text;
  free.replace(free.find("    fixed: true\n"), 16, "");
  EXPECT_NE(error_of(free).find("t.yaml:1:14: error: time.step: expected a time step <="),
            std::string::npos)
      << error_of(free);
}

// ---------------------------------------------------------------------------------------------
// Fixed groups with prescribed motion (fixed: {translate, rotate}, the keys of walls[].motion)

namespace {

config::Motion translation(const Vec3& velocity, double start = 0) {
  config::Motion m;
  m.velocity = velocity;
  m.start = start;
  return m;
}

config::Motion rotation(const Vec3& axis, const Vec3& center, double rate,
                        const Vec3& velocity = {}) {
  config::Motion m;
  m.rotates = true;
  m.axis = normalized(axis);
  m.center = center;
  m.rate = rate;
  m.velocity = velocity;
  return m;
}

/// Makes group g of c a fixed group with prescribed motion m.
void set_motion(config::Case& c, std::size_t g, const config::Motion& m) {
  c.particles[g].fixed = true;
  c.particles[g].motion = m;
}

/// Rodrigues: d turned by `angle` about the unit `axis` (independent of RigidMotion).
Vec3 turned(const Vec3& d, const Vec3& axis, double angle) {
  return std::cos(angle) * d + std::sin(angle) * cross(axis, d) +
         (1 - std::cos(angle)) * dot(axis, d) * axis;
}

/// The reference state (position, orientation at t = 0) of every grain of a moving group, by id.
std::map<std::int64_t, std::pair<Vec3, Quat>> moving_grains(const Simulation& sim) {
  const auto& p = sim.particles();
  std::map<std::int64_t, std::pair<Vec3, Quat>> out;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.fixed()[i] >= ParticleStore::kFixedMoving)
      out[p.id()[i]] = {p.x()[i], p.has_shapes() ? p.orientation()[i] : Quat{}};
  return out;
}

/// The free grains' touching pairs by brute force (all pairs, minimum image), fixed pairs left
/// out as the list leaves them out: the count the force loop must find.
std::int64_t brute_force_contacts(const Simulation& sim) {
  const auto& p = sim.particles();
  std::int64_t n = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      if (p.fixed()[i] != 0 && p.fixed()[j] != 0) continue;
      const double rs = p.radius()[i] + p.radius()[j];
      if (norm2(sim.domain().delta(p.x()[i], p.x()[j])) < rs * rs) ++n;
    }
  return n;
}

/// A rough plate (100 fixed spheres, r = 1 mm) translating at 0.5 m/s along x and 0.1 m/s along
/// y in a box periodic in x and y, with 60 free spheres thrown onto it under gravity.
config::Case translating_plate_case(const std::string& integrator) {
  auto c = sphere_bed_case(integrator);
  c.walls.clear();  // (the plate would cut through the floor)
  set_motion(c, 0, translation({0.5, 0.1, 0}));
  return c;
}

}  // namespace

// The plate's grains are where the motion puts them, x0 + V t wrapped into the periodic box, to
// the last bit (analytic: no drift, whatever the number of steps), with velocity V and no spin;
// the plate travels more than a box length along x, wrapping through the boundary, and drags the
// free grains along.
TEST_P(FixedParticlesIntegrator, TranslatingPlateIsExactAndWraps) {
  Simulation sim(translating_plate_case(GetParam()));
  ASSERT_TRUE(sim.particles().has_fixed_motion());
  const auto x0 = moving_grains(sim);
  ASSERT_EQ(x0.size(), 100u);
  const Vec3 V{0.5, 0.1, 0};
  const std::int64_t builds0 = sim.neighbor_list().n_builds();
  int wrapped = 0;
  double load = 0;
  for (int s = 0; s < 9000; ++s) {  // 0.045 s: 22.5 mm along x, more than L_x = 20 mm
    sim.step(true);
    if (s % 1000 != 999) continue;
    sim.complete_step();
    load = std::max(load, std::abs(sim.quantity("fixed_force.z")));
    const auto& p = sim.particles();
    const double t = sim.time();
    for (std::size_t i = 0; i < p.size(); ++i) {
      const auto it = x0.find(p.id()[i]);
      if (it == x0.end()) continue;
      Vec3 expected = it->second.first + t * V;  // (the formula, evaluated the same way)
      sim.domain().wrap(expected);
      EXPECT_TRUE(same_bits(p.x()[i], expected)) << "grain " << p.id()[i] << " at step " << s;
      // Independently: the displacement is V t modulo the box.
      const Vec3 d = sim.domain().delta(p.x()[i], it->second.first);
      const Vec3 vt = t * V;
      EXPECT_NEAR(std::remainder(d.x - vt.x, 0.02), 0.0, 1e-15);
      EXPECT_NEAR(std::remainder(d.y - vt.y, 0.02), 0.0, 1e-15);
      EXPECT_EQ(d.z, 0.0);
      EXPECT_TRUE(same_bits(p.v()[i], V));
      EXPECT_EQ(p.omega()[i], Vec3{});
      if (p.x()[i].x < it->second.first.x) ++wrapped;
    }
  }
  EXPECT_GT(wrapped, 0) << "no grain of the plate crossed the periodic boundary";
  EXPECT_GT(load, 0.0) << "no free grain touched the plate";
  EXPECT_GT(sim.neighbor_list().n_builds(), builds0);
  // Friction on the plate drags the free grains along x.
  const auto& p = sim.particles();
  double vx = 0;
  int n_free = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.fixed()[i] == 0) {
      vx += p.v()[i].x;
      ++n_free;
    }
  EXPECT_GT(vx / n_free, 0.05);
}

// A translation with a start time: at rest (and in place) before it, then x0 + V (t - start).
TEST(FixedMotion, TranslationStartsAtItsStartTime) {
  auto c = translating_plate_case("velocity_verlet");
  c.particles[0].motion->start = 0.01;
  Simulation sim(c);
  const auto x0 = moving_grains(sim);
  for (int s = 0; s < 3000; ++s) {
    sim.step();
    const double t = sim.time();
    if (s % 500 != 0 && s != 1999 && s != 2000) continue;
    const auto& p = sim.particles();
    for (std::size_t i = 0; i < p.size(); ++i) {
      const auto it = x0.find(p.id()[i]);
      if (it == x0.end()) continue;
      if (t <= 0.01) {
        EXPECT_TRUE(same_bits(p.x()[i], it->second.first)) << t;
        EXPECT_EQ(p.v()[i], (t < 0.01 ? Vec3{} : Vec3{0.5, 0.1, 0})) << t;
      } else {
        Vec3 expected = it->second.first + (t - 0.01) * Vec3{0.5, 0.1, 0};
        sim.domain().wrap(expected);
        EXPECT_TRUE(same_bits(p.x()[i], expected)) << t;
        EXPECT_EQ(p.v()[i], (Vec3{0.5, 0.1, 0}));
      }
    }
  }
}

// A group of spherocylinders turning about a tilted axis, and a group of spheres turning and
// translating (a paddle on a moving frame), among free rods and spheres under gravity: every
// grain of them sits at c + V t + R(w t)(x0 - c), its axis turned by R(w t), with the rigid
// velocity V + w x (x - c(t)), the angular velocity w and the angular momentum I w of its turned
// body, checked against Rodrigues' formula evaluated here.
TEST(FixedMotion, RotatingGroupsOfRodsAndSpheres) {
  auto c = test::base_case(5e-6, 1.0, {0, 0, 0}, {0.04, 0.04, 0.04}, {true, true, false});
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "pom", 1400, 1e7, 0.3);
  test::add_contact(c, "pom", "pom", "hertz_mindlin",
                    {{"restitution", 0.5}, {"friction", 0.4}, {"rolling_friction", 0.05}});
  std::vector<Vec3> x;
  std::vector<Quat> q;
  for (int i = 0; i < 6; ++i) {
    x.push_back({0.008 + 0.004 * i, 0.02, 0.006});
    q.push_back(quat_from_axis_angle(normalized(Vec3{1, 2, 0}), 0.4 * i));
  }
  test::add_capsules(c, "pom", 0.001, 0.002, x, q);
  const Vec3 axis = normalized(Vec3{0.2, -0.1, 1});
  const Vec3 centre{0.02, 0.02, 0.005};
  const double rate = 40;  // rad/s
  set_motion(c, 0, rotation(axis, centre, rate));
  test::add_spheres(c, "pom", 0.0012,
                    {{0.01, 0.03, 0.012}, {0.014, 0.03, 0.012}, {0.018, 0.03, 0.012}});
  const Vec3 V{0.2, 0, 0};
  set_motion(c, 1, rotation({0, 0, 1}, {0.014, 0.03, 0.012}, -25, V));
  auto& rods = test::add_capsule_fill(c, "pom", 0.001, 2.5, {0, 0, 0.016}, {0.04, 0.04, 0.035},
                                      config::Fill::Lattice::Random);
  rods.count = 25;
  rods.seed = 9;
  rods.velocity = {0, 0, -0.5};
  c.output.quantities = {"fixed_force", "fixed_torque"};
  Simulation sim(c);
  const auto ref = moving_grains(sim);
  ASSERT_EQ(ref.size(), 9u);
  double load = 0;
  for (int s = 0; s < 8000; ++s) {  // 0.04 s: 1.6 rad, and 8 mm along x
    sim.step();
    load = std::max(load, norm(Vec3{sim.quantity("fixed_force.x"), sim.quantity("fixed_force.y"),
                                    sim.quantity("fixed_force.z")}));
    if (s % 2000 != 1999) continue;
    const double t = sim.time();
    const auto& p = sim.particles();
    for (std::size_t i = 0; i < p.size(); ++i) {
      const auto it = ref.find(p.id()[i]);
      if (it == ref.end()) continue;
      const bool rod = p.id()[i] <= 6;
      const Vec3 ax = rod ? axis : Vec3{0, 0, 1};
      const double w = rod ? rate : -25.0;
      const Vec3 c0 = rod ? centre : Vec3{0.014, 0.03, 0.012};
      const Vec3 ct = rod ? c0 : c0 + t * V;
      Vec3 expected = ct + turned(it->second.first - c0, ax, w * t);
      sim.domain().wrap(expected);
      EXPECT_LT(norm(sim.domain().delta(p.x()[i], expected)), 1e-15) << p.id()[i];
      const Vec3 r = ct + turned(it->second.first - c0, ax, w * t) - ct;
      const Vec3 v_expected = (rod ? Vec3{} : V) + cross(w * ax, r);
      EXPECT_LT(norm(p.v()[i] - v_expected), 1e-14) << p.id()[i];
      EXPECT_LT(norm(p.omega()[i] - w * ax), 1e-14) << p.id()[i];
      if (!rod) continue;
      const Vec3 body_axis = rotate(p.orientation()[i], Vec3{0, 0, 1});
      const Vec3 axis_expected = turned(rotate(it->second.second, Vec3{0, 0, 1}), ax, w * t);
      EXPECT_LT(norm(body_axis - axis_expected), 1e-14) << p.id()[i];
      EXPECT_NEAR(norm2(p.orientation()[i]), 1.0, 1e-14);
      const Vec3 wb = rotate_inverse(p.orientation()[i], p.omega()[i]);
      const Vec3& I = p.inertia_body()[i];
      const Vec3 L = rotate(p.orientation()[i], Vec3{I.x * wb.x, I.y * wb.y, I.z * wb.z});
      EXPECT_LT(norm(p.angular_momentum()[i] - L), 1e-12 * norm(L)) << p.id()[i];
    }
  }
  EXPECT_GT(load, 0.0) << "no free grain touched the moving groups";
}

// 2D: a turning paddle of hexagons (rotation about z; the sign of a 2D axis [0, 0, -1] is in the
// rate) under both integrators: the orientation angle is angle0 + rate t, the position turned.
class FixedMotion2D : public ::testing::TestWithParam<const char*> {};

TEST_P(FixedMotion2D, TurningPolygonsFollowTheirAngle) {
  auto c = two_d_case(true, GetParam());
  const Vec3 centre{0.02, 0.002, 0};
  set_motion(c, 0, rotation({0, 0, 1}, centre, -30));
  Simulation sim(c);
  const auto ref = moving_grains(sim);
  ASSERT_EQ(ref.size(), 10u);
  for (int s = 0; s < 6000; ++s) sim.step();
  const double t = sim.time(), angle = -30 * t;
  const auto& p = sim.particles();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto it = ref.find(p.id()[i]);
    if (it == ref.end()) continue;
    Vec3 expected = centre + turned(it->second.first - centre, {0, 0, 1}, angle);
    sim.domain().wrap(expected);
    EXPECT_LT(norm(sim.domain().delta(p.x()[i], expected)), 1e-15);
    EXPECT_EQ(p.x()[i].z, 0.0);
    // The body's x axis turned by angle0 + angle, angle0 = 0.3 (id - 1).
    const Vec3 ex = rotate(p.orientation()[i], Vec3{1, 0, 0});
    const double a = 0.3 * static_cast<double>(p.id()[i] - 1) + angle;
    EXPECT_LT(norm(ex - Vec3{std::cos(a), std::sin(a), 0}), 1e-14);
    EXPECT_EQ(p.omega()[i], (Vec3{0, 0, -30}));
  }
}

INSTANTIATE_TEST_SUITE_P(Both, FixedMotion2D, ::testing::Values("velocity_verlet", "gear5"),
                         [](const auto& param_info) { return std::string(param_info.param); });

// The neighbour list follows moving fixed grains: free grains at rest (no gravity, apart), a
// plate sweeping through them along the periodic x axis and a paddle of spheres turning among
// them. The free grains alone would never ask for a rebuild; the contacts the force loop finds
// equal a brute-force count over all pairs (velocity Verlet: the positions after a step are
// those the forces saw; Gear corrects them afterwards).
TEST(FixedMotion, NeighbourListFollowsMovingFixedGrains) {
  auto c = test::base_case(5e-6, 1.0, {0, 0, 0}, {0.02, 0.02, 0.02}, {true, true, false});
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin",
                    {{"restitution", 0.5}, {"friction", 0.5}});
  test::add_fixed_sphere_layer(c, "glass", 0.001, 0.002, 0, 0.01, 0, 0.02, 0.004);
  set_motion(c, 0, translation({1.0, 0, 0}));
  test::add_spheres(c, "glass", 0.001, {{0.0145, 0.01, 0.014}, {0.0175, 0.01, 0.014}});
  set_motion(c, 1, rotation({0, 1, 0}, {0.016, 0.01, 0.014}, 150));
  // Free grains 2.5 mm ahead of the plate (in its path: it reaches them after 500 steps, having
  // moved six skins) and around the paddle (whose grains reach new neighbours after a turn of a
  // fraction of a radian).
  auto& f = test::add_box_fill(c, "glass", 0.0008, 0.0008, {0.0125, 0, 0.0025}, {0.02, 0.02, 0.018},
                               config::Fill::Lattice::Random);
  f.count = 150;
  f.seed = 5;
  Simulation sim(c);
  std::int64_t touching = 0;
  const std::int64_t builds0 = sim.neighbor_list().n_builds();
  ASSERT_EQ(sim.n_contacts(), 0);
  for (int s = 0; s < 3000; ++s) {
    sim.step();
    const std::int64_t expected = brute_force_contacts(sim);
    ASSERT_EQ(sim.n_contacts(), expected) << "step " << s;
    touching += expected;
  }
  EXPECT_GT(touching, 100);
  EXPECT_GT(sim.neighbor_list().n_builds(), builds0 + 5);
}

// Checkpoints carry the reference state; a restart continues bit-identically (spheres on a
// translating plate across the periodic boundary; turning rods and spheres; Gear with turning
// hexagons), also with two threads (suite name Restart*).
TEST(RestartFixedParticles, TranslatingPlateContinuesBitIdentically) {
  expect_restart_continues(translating_plate_case("velocity_verlet"), "plate", 2500, 2500);
}

TEST(RestartFixedParticles, TurningRodsContinueBitIdentically) {
  auto c = test::base_case(5e-6, 1.0, {0, 0, 0}, {0.03, 0.03, 0.03}, {true, true, false});
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "pom", 1400, 1e7, 0.3);
  test::add_contact(c, "pom", "pom", "hertz_mindlin", {{"restitution", 0.5}, {"friction", 0.4}});
  test::add_capsules(c, "pom", 0.001, 0.004,
                     {{0.009, 0.015, 0.004}, {0.015, 0.015, 0.004}, {0.021, 0.015, 0.004}},
                     {quat_from_axis_angle({1, 0, 0}, 1.5707963267948966), Quat{},
                      quat_from_axis_angle({0, 1, 0}, 1.5707963267948966)});
  set_motion(c, 0, rotation({0, 0, 1}, {0.015, 0.015, 0.004}, 60, {0.3, 0, 0}));
  auto& rods = test::add_capsule_fill(c, "pom", 0.001, 2.5, {0, 0, 0.01}, {0.03, 0.03, 0.028},
                                      config::Fill::Lattice::Random);
  rods.count = 20;
  rods.seed = 4;
  rods.velocity = {0, 0, -0.5};
  c.output.quantities = {"fixed_force", "fixed_torque"};
  expect_restart_continues(c, "rods", 3000, 3000);
}

TEST(RestartFixedParticles, GearTurningPolygonsContinueBitIdentically) {
  auto c = two_d_case(true, "gear5");
  set_motion(c, 0, rotation({0, 0, 1}, {0.02, 0.002, 0}, 20, {0.1, 0, 0}));
  expect_restart_continues(c, "polygons_moving", 3000, 3000);
}

// A checkpoint whose grains name a motion the case does not have is refused; runs without a
// moving group carry no reference fields.
TEST(RestartFixedParticles, MotionsMustMatchTheCase) {
  Simulation at_rest(sphere_bed_case("velocity_verlet"));
  EXPECT_FALSE(at_rest.particles().has_fixed_motion());
  EXPECT_EQ(at_rest.particles().find_field("fixed_x0"), -1);
  EXPECT_EQ(at_rest.particles().find_field("fixed_q0"), -1);
  const auto file = std::filesystem::temp_directory_path() /
                    ("gf_fixed_motion_" + std::to_string(::getpid()) + ".h5");
  auto moving = translating_plate_case("velocity_verlet");
  Simulation(moving).save_checkpoint(file);
  // Without the motion (fixed: true): the checkpoint's grains follow motion 1 of none.
  auto none = moving;
  none.particles[0].motion.reset();
  Simulation sim(none);
  try {
    sim.load_checkpoint(file);
    ADD_FAILURE() << "a checkpoint with moving grains continued a case without motion";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("belongs to a fixed group with prescribed motion 1"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove(file);
}

// fixed_torque: the torque on the turning groups about their centre c(t) (which translates with
// them), the sum over their grains of (x - c) x (f - m g) + torque, x not wrapped; fixed_force
// still sums every fixed grain.
TEST(FixedMotion, FixedTorqueIsAboutTheRotationCentre) {
  auto c = test::base_case(5e-6, 1.0, {0, 0, 0}, {0.02, 0.02, 0.03}, {true, true, false});
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin",
                    {{"restitution", 0.5}, {"friction", 0.5}});
  test::add_fixed_sphere_layer(c, "glass", 0.001, 0.002, 0, 0.02, 0, 0.02, 0.001);  // at rest
  const Vec3 centre{0.01, 0.01, 0.005}, V{0.4, 0, 0};
  test::add_spheres(
      c, "glass", 0.001,
      {{0.006, 0.01, 0.005}, {0.008, 0.01, 0.005}, {0.012, 0.01, 0.005}, {0.014, 0.01, 0.005}});
  set_motion(c, 1, rotation({0, 0, 1}, centre, 50, V));
  // Free grains resting on the paddle's grains (0.1 mm above them) and more falling.
  test::add_spheres(c, "glass", 0.0008,
                    {{0.006, 0.01, 0.0069},
                     {0.008, 0.0102, 0.0069},
                     {0.012, 0.0098, 0.0069},
                     {0.014, 0.01, 0.0069}});
  auto& f = test::add_box_fill(c, "glass", 0.0008, 0.0008, {0, 0, 0.0085}, {0.02, 0.02, 0.025},
                               config::Fill::Lattice::Random);
  f.count = 80;
  f.seed = 3;
  c.output.quantities = {"fixed_force", "fixed_torque"};
  Simulation sim(c);
  EXPECT_EQ(sim.series_columns(),
            (std::vector<std::string>{"fixed_force.x", "fixed_force.y", "fixed_force.z",
                                      "fixed_torque.x", "fixed_torque.y", "fixed_torque.z"}));
  const auto ref = moving_grains(sim);
  double largest = 0;
  for (int s = 0; s < 8000; ++s) {
    sim.step();
    if (s % 400 != 399) continue;
    const double t = sim.time();
    const auto& p = sim.particles();
    Vec3 torque{}, force{};
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.fixed()[i] != 0) force += p.f()[i] - p.mass()[i] * sim.gravity();
      const auto it = ref.find(p.id()[i]);
      if (it == ref.end()) continue;
      const Vec3 arm = turned(it->second.first - centre, {0, 0, 1}, 50 * t);
      torque += cross(arm, p.f()[i] - p.mass()[i] * sim.gravity()) + p.torque()[i];
    }
    const auto row = sim.series_row(sim.series_columns());
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(row[static_cast<std::size_t>(k)], force[k]);
      EXPECT_NEAR(row[3 + static_cast<std::size_t>(k)], torque[k], 1e-12 * (norm(torque) + 1e-9));
    }
    EXPECT_EQ(sim.quantity("fixed_torque"), row[5]);
    largest = std::max(largest, norm(torque));
  }
  EXPECT_GT(largest, 0.0) << "no free grain touched the paddle";
}

// ---------------------------------------------------------------------------------------------
// Input of prescribed motions

namespace {

/// bed_case_text with the bed's fixed: replaced by `fixed` (its text after "fixed: ").
std::string moving_bed_text(const std::string& fixed, const std::string& bed_extra,
                            const std::string& quantities = "[kinetic_energy, fixed_force.z]") {
  std::string text = bed_case_text(bed_extra, quantities);
  text.replace(text.find("fixed: true"), 11, "fixed: " + fixed);
  return text;
}

}  // namespace

// fixed: takes the keys of walls[].motion, read by the same reader: translate {velocity,
// start}, rotate {axis, center, rpm | rate}, both together (a turning paddle on a moving frame).
TEST(FixedMotionInput, MotionIsReadWithTheWallsKeys) {
  const std::string bed = "    positions: [[0.05, 0.05, 0.005]]\n";
  auto c = input::load_case_text(
      moving_bed_text("{translate: {velocity: [0.1, 0, 0], start: 0.002}}", bed), "t.yaml");
  ASSERT_TRUE(c.particles[0].motion);
  EXPECT_TRUE(c.particles[0].fixed);
  EXPECT_EQ(c.particles[0].motion->velocity, (Vec3{0.1, 0, 0}));
  EXPECT_EQ(c.particles[0].motion->start, 0.002);
  EXPECT_FALSE(c.particles[0].motion->rotates);
  EXPECT_FALSE(c.particles[1].motion);
  EXPECT_EQ(c.particles[0].fixed_loc.line, 10);
  c = input::load_case_text(
      moving_bed_text("\n      rotate: {axis: [0, 0, 2], center: [0.05, 0.05, 0], rpm: 60}\n"
                      "      translate: {velocity: [0, 0.1, 0]}",
                      bed),
      "t.yaml");
  ASSERT_TRUE(c.particles[0].motion);
  EXPECT_TRUE(c.particles[0].motion->rotates);
  EXPECT_EQ(c.particles[0].motion->axis, (Vec3{0, 0, 1}));
  EXPECT_EQ(c.particles[0].motion->center, (Vec3{0.05, 0.05, 0}));
  EXPECT_NEAR(c.particles[0].motion->rate, 2 * std::numbers::pi, 1e-15);
  EXPECT_EQ(c.particles[0].motion->velocity, (Vec3{0, 0.1, 0}));
  EXPECT_EQ(error_of(moving_bed_text("\n      rotate: {axis: [0, 0, 1], center: [0.05, 0.05, "
                                     "0], rpm: 60}\n      translate: {velocity: [0, 0.1, 0]}",
                                     bed)),
            "");
  // A translation at zero velocity is rest.
  c = input::load_case_text(moving_bed_text("{translate: {velocity: [0, 0, 0]}}", bed), "t.yaml");
  EXPECT_TRUE(c.particles[0].fixed);
  EXPECT_FALSE(c.particles[0].motion);
  // fixed: false is a free group.
  c = input::load_case_text(moving_bed_text("false", bed, "[kinetic_energy]"), "t.yaml");
  EXPECT_FALSE(c.particles[0].fixed);
}

// Bad input: each an error at its file:line:column and key path, naming what was expected.
TEST(FixedMotionInput, BadMotionsAreClearErrors) {
  const std::string bed = "    positions: [[0.05, 0.05, 0.005]]\n";
  struct Bad {
    std::string fixed, extra, expected;
  };
  const std::string forms =
      "expected true, false or a prescribed motion with the keys of walls[].motion: {translate: "
      "{velocity: V, start: T}, rotate: {axis: A, center: C, rpm: N (or rate: W)}}";
  const std::vector<Bad> cases{
      {"yes", bed, "t.yaml:10:12: error: particles[0].fixed: " + forms + ", found 'yes'"},
      {"3", bed, "t.yaml:10:12: error: particles[0].fixed: " + forms + ", found '3'"},
      {"[0.1, 0, 0]", bed, "t.yaml:10:12: error: particles[0].fixed: " + forms},
      {"{}", bed, "t.yaml:10:12: error: particles[0].fixed: " + forms + " (an empty map"},
      {"{velocity: [0.1, 0, 0]}", bed, "particles[0].fixed.velocity: unknown key"},
      {"{translate: {velocity: 0.1}}", bed, "particles[0].fixed.translate.velocity: expected"},
      {"{rotate: {center: [0, 0, 0], rpm: 10}}", bed,
       "missing required key 'axis' in 'particles[0].fixed.rotate'"},
      {"{rotate: {axis: [0, 0, 1], rpm: 10, rate: 1}}", bed, "particles[0].fixed.rotate"},
      {"{translate: {velocity: [0.1, 0, 0]}}",
       "    positions: [[0.02, 0.05, 0.005], [0.05, 0.05, 0.005]]\n"
       "    velocities: [[0, 0, 0], [0.1, 0, 0]]\n",
       "t.yaml:12:29: error: particles[0].velocities[1]: the grains of a fixed group with a "
       "prescribed motion (fixed: {translate, rotate}) take their velocities from the motion; "
       "expected no initial velocity (or zero), found [0.1, 0, 0] for particle 1"},
      {"{rotate: {axis: [0, 0, 1], rpm: 10}}",
       "    fill: {box: {min: [0, 0, 0], max: [0.1, 0.1, 0.01]}, velocity: [0, 0, -1]}\n",
       "particles[0].fill.velocity: the grains of a fixed group with a prescribed motion"},
  };
  for (const auto& b : cases) {
    const std::string msg = error_of(moving_bed_text(b.fixed, b.extra));
    EXPECT_NE(msg.find(b.expected), std::string::npos) << b.fixed << "\n" << msg;
  }
  // Unknown keys name the accepted ones.
  EXPECT_NE(error_of(moving_bed_text("{velocity: [0.1, 0, 0]}", bed)).find("translate"),
            std::string::npos);

  // fixed_torque needs a turning group, and one centre.
  std::string msg = error_of(moving_bed_text("{translate: {velocity: [0.1, 0, 0]}}", bed,
                                             "[fixed_force, fixed_torque.z]"));
  EXPECT_NE(msg.find("series quantity 'fixed_torque.z' is the torque on the rotating fixed "
                     "groups about their rotation centre; it needs a particle group with fixed: "
                     "{rotate: {...}}"),
            std::string::npos)
      << msg;
  std::string two = moving_bed_text("{rotate: {axis: [0, 0, 1], center: [0.05, 0.05, 0], rpm: 10}}",
                                    bed, "[fixed_torque]");
  two.replace(two.find("  - radius: 0.005\n    material: glass\n    positions: [[0.05, 0.05, "
                       "0.08]]"),
              0,
              "  - radius: 0.005\n    material: glass\n    fixed: {rotate: {axis: [0, 0, 1], "
              "center: [0.02, 0.05, 0], rpm: 10}}\n    positions: [[0.02, 0.02, 0.05]]\n");
  msg = error_of(two);
  EXPECT_NE(msg.find("error: output.series.quantities[0]: series quantity 'fixed_torque' is the "
                     "torque on the rotating fixed groups about their rotation centre; expected "
                     "one centre, but the groups at t.yaml:10 and t.yaml:14 turn about different "
                     "ones"),
            std::string::npos)
      << msg;
  // The same centre: accepted.
  std::string same = two;
  const std::string other_centre = "center: [0.02, 0.05, 0]";
  same.replace(same.find(other_centre), other_centre.size(), "center: [0.05, 0.05, 0]");
  EXPECT_EQ(error_of(same), "");

  // Lees-Edwards: refused at the group's fixed: value.
  const std::string le = R"(time: {step: 1.0e-5, end: 0.01}
domain: {min: [0, 0, 0], max: [0.1, 0.1, 0.1], periodic: [true, true, true]}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
contacts:
  - {between: [glass, glass], model: hertz_mindlin, restitution: 0.5}
particles:
  - radius: 0.005
    material: glass
    fixed: {translate: {velocity: [0.1, 0, 0]}}
    positions: [[0.05, 0.05, 0.05]]
shear: {rate: 10, boundary: lees_edwards}
)";
  msg = error_of(le);
  EXPECT_NE(msg.find("t.yaml:10:12: error: particles[0].fixed: a fixed group with a prescribed "
                     "motion is not available in a Lees-Edwards shear box"),
            std::string::npos)
      << msg;
  auto code = input::load_case_text(bed_case_text(bed), "t.yaml");
  code.particles[0].motion = translation({0.1, 0, 0});
  code.particles[0].explicit_particles->velocities = {{0.1, 0, 0}};
  EXPECT_THROW(Simulation{code}, InputError);
  code.particles[0].explicit_particles->velocities.clear();
  code.particles[0].fixed = false;
  EXPECT_THROW(Simulation{code}, InputError);

  // The command line: exit code 2, the message on stderr.
  test::TempDir dir;
  const auto bad = dir.write("bad.yaml", moving_bed_text("{}", bed));
  const std::string cmd =
      std::string(GF_BINARY) + " check " + bad.string() + " > " + (dir / "log").string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  EXPECT_NE(read_text_file(dir / "log").find("bad.yaml:10:12: error: particles[0].fixed: expected"),
            std::string::npos)
      << read_text_file(dir / "log");
}

// The echo writes a moving group's fixed: as a motion map (the walls' form, rate in rad/s) and
// loads back to the same motion; check reports the moving group's speed in the impact speed.
TEST(FixedMotionInput, EchoRoundTripsAndCheckCountsTheSpeed) {
  const auto c = input::load_case_text(
      moving_bed_text("{translate: {velocity: [2, 0, 0], start: 0.001}, rotate: {axis: [0, 1, "
                      "0], center: [0.05, 0.05, 0.005], rpm: 30}}",
                      "    positions: [[0.05, 0.05, 0.005]]\n", "[fixed_force, fixed_torque]"),
      "t.yaml");
  const std::string text = input::echo_yaml(c, "1");
  EXPECT_NE(text.find("fixed:\n      translate: {velocity: [2, 0, 0], start: 0.001}"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("fixed: false"), std::string::npos) << text;
  test::TempDir dir;
  const auto again = input::load_case(dir.write("echo.yaml", text));
  ASSERT_TRUE(again.particles[0].motion);
  EXPECT_EQ(again.particles[0].motion->velocity, c.particles[0].motion->velocity);
  EXPECT_EQ(again.particles[0].motion->start, c.particles[0].motion->start);
  EXPECT_EQ(again.particles[0].motion->axis, c.particles[0].motion->axis);
  EXPECT_EQ(again.particles[0].motion->center, c.particles[0].motion->center);
  EXPECT_EQ(again.particles[0].motion->rate, c.particles[0].motion->rate);
  const std::string second = input::echo_yaml(again, "1");
  const auto third = input::load_case(dir.write("echo2.yaml", second));
  EXPECT_EQ(body(input::echo_yaml(third, "1")), body(second));
  // The impact speed: the free grain's 1 m/s is below the group's 2 m/s + pi rad/s x reach.
  std::string impact;
  for (const auto& [k, v] : input::validate(c).derived)
    if (k.rfind("impact speed", 0) == 0) impact = v;
  EXPECT_NE(impact.find("(initial 2.3"), std::string::npos) << impact;
}

// check warns when a translation carries a group out of the box along a non-periodic axis (its
// grains then meet nothing); along periodic axes the group wraps.
TEST(FixedMotionInput, CheckWarnsWhenAGroupLeavesTheBox) {
  std::string text = moving_bed_text("{translate: {velocity: [0, 0.2, 0]}}",
                                     "    positions: [[0.05, 0.05, 0.005]]\n");
  text.replace(text.find("end: 0.01"), 9, "end: 1.0");
  std::string warning;
  for (const auto& w : input::validate(input::load_case_text(text, "t.yaml")).warnings)
    if (w.find("fixed group") != std::string::npos) warning = w;
  EXPECT_EQ(
      warning,
      "t.yaml:10: the fixed group's translation carries it 0.2 m along y by time.end, more "
      "than the domain's length 0.1 m along that non-periodic axis: its grains leave the box");
  text.replace(text.find("max: [0.1, 0.1, 0.1]}"), 21,
               "max: [0.1, 0.1, 0.1], periodic: [false, true, false]}");
  for (const auto& w : input::validate(input::load_case_text(text, "t.yaml")).warnings)
    EXPECT_EQ(w.find("fixed group"), std::string::npos) << w;
}
