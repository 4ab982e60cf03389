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
  EXPECT_NE(error_of(yes).find("t.yaml:10:12: error: particles[0].fixed: expected true or false"),
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
