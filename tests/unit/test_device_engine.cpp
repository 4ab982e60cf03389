// SPDX-License-Identifier: GPL-3.0-or-later
// The device back end (docs/gpu.md) against the host step, on both of its back ends: the host
// mirror (every build; the device's algorithm in plain loops) and CUDA (builds with the preset
// `cuda`; skipped where no GPU is found). Oracles: the host run of the same case, the reference
// of the device's lists and kernels; energy conservation of an elastic gas.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <map>
#include <optional>
#include <ostream>
#include <thread>

#include "case_builder.hpp"
#include "core/stop.hpp"
#include "gpu/sphere_dem.hpp"
#include "simulation/simulation.hpp"
#include "temp_dir.hpp"

using namespace gf;

namespace gf {
// (test names and failure messages print the back end by name)
inline void PrintTo(Device d, std::ostream* os) {
  *os << (d == Device::Cuda ? "cuda" : d == Device::HostMirror ? "host mirror" : "cpu");
}
}  // namespace gf

namespace {

class DeviceEngine : public ::testing::TestWithParam<Device> {
 protected:
  void SetUp() override {
    std::string why;
    if (GetParam() == Device::Cuda && !gpu::device_available(&why)) GTEST_SKIP() << why;
  }
};

/// A case in the box [0, hi] under gravity, dt 1e-5 s, with glass grains (Hertz-Mindlin, friction,
/// rolling resistance) and steel for the walls (their law: the caller's).
config::Case glass_and_steel(const std::string& name, Vec3 hi) {
  auto c = test::base_case(1e-5, 1.0, {0, 0, 0}, hi);
  c.name = name;
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_material(c, "steel", 7800, 2e7, 0.28);
  test::add_contact(c, "glass", "glass", "hertz_mindlin",
                    {{"restitution", 0.5}, {"friction", 0.5}, {"rolling_friction", 0.05}});
  return c;
}

/// A polydisperse bed settling in a box with an open top (Hertz-Mindlin, friction, rolling
/// resistance, two materials with different laws); radii 1.5-3 mm (up to ~13 list partners per
/// grain: ListGrowsWhenAGrainHasMorePartners starts the list with fewer slots).
config::Case settling_case() {
  auto c = glass_and_steel("settling bed", {0.04, 0.04, 0.08});
  test::add_contact(c, "glass", "steel", "hooke",
                    {{"restitution", 0.6}, {"friction", 0.3}, {"stiffness", 2e3}});
  auto& f = test::add_box_fill(c, "glass", 0.0015, 0.003, {0, 0, 0}, {0.04, 0.04, 0.06},
                               config::Fill::Lattice::Random);
  f.count = 400;
  f.seed = 5;
  f.velocity_jitter = 0.3;
  test::add_box(c, "box", {0, 0, 0}, {0.04, 0.04, 0.08}, {"zmax"}, "steel");
  c.neighbor.skin = 0.0006;
  return c;
}

/// Monodisperse cohesive grains on a floor, periodic in x and y (linear springs, sjkr cohesion).
config::Case periodic_case() {
  auto c = test::base_case(1e-5, 1.0, {0, 0, 0}, {0.03, 0.03, 0.06}, {true, true, false});
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hooke",
                    {{"restitution", 0.4},
                     {"friction", 0.4},
                     {"stiffness", 400},
                     {"cohesion_energy_density", 2e4}});
  auto& f = test::add_box_fill(c, "glass", 0.002, 0.002, {0, 0, 0}, {0.03, 0.03, 0.04},
                               config::Fill::Lattice::Random);
  f.count = 250;
  f.seed = 3;
  f.velocity_jitter = 0.4;
  test::add_plane(c, "floor", {0, 0, 0}, {0, 0, 1}, "glass");
  return c;
}

/// Frictionless elastic spheres (restitution 1) in a fully periodic box
/// (ElasticGasConservesEnergy).
config::Case elastic_gas() {
  auto c = test::base_case(7e-6, 1.0, {0, 0, 0}, {0.03, 0.03, 0.03}, {true, true, true});
  c.name = "elastic gas";
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hooke",
                    {{"restitution", 1.0}, {"friction", 0.0}, {"stiffness", 1000}});
  auto& f = test::add_box_fill(c, "glass", 0.0015, 0.0015, {0, 0, 0}, {0.03, 0.03, 0.03},
                               config::Fill::Lattice::Random);
  f.count = 300;
  f.seed = 9;
  f.velocity_jitter = 0.5;
  return c;
}

/// A rotating drum: a horizontal cylinder (axis y, radius 20 mm) turning at 6 rad/s between two
/// fixed end plates, a polydisperse charge thrown in with random velocities.
config::Case drum_case() {
  auto c = glass_and_steel("rotating drum", {0.04, 0.03, 0.04});
  test::add_contact(c, "glass", "steel", "hertz_mindlin",
                    {{"restitution", 0.6}, {"friction", 0.6}, {"rolling_friction", 0.02}});
  // (corners of the fill box within 17 mm of the axis: every grain starts inside)
  auto& f = test::add_box_fill(c, "glass", 0.0015, 0.0025, {0.009, 0.002, 0.007},
                               {0.031, 0.028, 0.026}, config::Fill::Lattice::Random);
  f.count = 120;
  f.seed = 11;
  f.velocity_jitter = 0.5;
  test::add_cylinder(c, "drum", {0.02, 0, 0.02}, {0, 1, 0}, 0.02, true, "steel", 6);
  test::add_plane(c, "back", {0, 0, 0}, {0, 1, 0}, "steel");
  test::add_plane(c, "front", {0, 0.03, 0}, {0, -1, 0}, "steel");
  c.neighbor.skin = 0.0006;
  return c;
}

/// Runs `cfg` for `steps` steps with `run` on `device`, into `dir`; returns the simulation.
std::unique_ptr<Simulation> run_case(const config::Case& cfg, Device device, std::int64_t steps,
                                     const std::filesystem::path& dir,
                                     std::optional<std::filesystem::path> restart = {}) {
  auto sim = std::make_unique<Simulation>(cfg);
  RunOptions o;
  o.output = dir;
  o.quiet = true;
  o.steps = steps;
  o.device = device;
  o.restart = restart;
  sim->run(o);
  return sim;
}

/// Index of each grain (by id) in b's store: runs may order their grains differently.
std::map<std::int64_t, std::size_t> index_by_id(const Simulation& b) {
  std::map<std::int64_t, std::size_t> at;
  for (std::size_t i = 0; i < b.particles().size(); ++i) at[b.particles().id()[i]] = i;
  return at;
}

/// Largest distance between the positions of the same grains (by id) in two runs, m.
double max_position_gap(const Simulation& a, const Simulation& b) {
  const auto at = index_by_id(b);
  double gap = 0;
  for (std::size_t i = 0; i < a.particles().size(); ++i)
    gap =
        std::max(gap, norm(a.particles().x()[i] - b.particles().x()[at.at(a.particles().id()[i])]));
  return gap;
}

/// The same case run on `device` (into tmp/gpu) and on the host step (tmp/cpu), and the largest
/// position gap between the two, m.
struct BothRuns {
  std::unique_ptr<Simulation> gpu, cpu;
  double gap;
};
BothRuns run_on_both(const config::Case& cfg, Device device, std::int64_t steps,
                     const std::filesystem::path& tmp) {
  auto gpu = run_case(cfg, device, steps, tmp / "gpu");
  auto cpu = run_case(cfg, Device::Cpu, steps, tmp / "cpu");
  const double gap = max_position_gap(*gpu, *cpu);
  return {std::move(gpu), std::move(cpu), gap};
}

/// The same grains (by id) have the same bits of position, velocity and spin in both runs.
void expect_same_grains(const Simulation& a, const Simulation& b, const std::string& what) {
  ASSERT_EQ(a.particles().size(), b.particles().size()) << what;
  const auto at = index_by_id(b);
  const auto& pa = a.particles();
  const auto& pb = b.particles();
  for (std::size_t i = 0; i < pa.size(); ++i) {
    const std::size_t k = at.at(pa.id()[i]);
    ASSERT_EQ(pa.x()[i], pb.x()[k]) << what << ", grain " << pa.id()[i];
    ASSERT_EQ(pa.v()[i], pb.v()[k]) << what << ", grain " << pa.id()[i];
    ASSERT_EQ(pa.omega()[i], pb.omega()[k]) << what << ", grain " << pa.id()[i];
  }
}

const char* name() {
  return ::testing::UnitTest::GetInstance()->current_test_info()->name();
}

}  // namespace

// The device run follows the host run of the same case. The two sum each grain's contact forces
// in different orders (and the host may take another wall loop), so they differ from the first step
// by rounding, ~1e-16 of the forces; a dense bed amplifies such differences (each collision
// multiplies them by a factor of order one), so the comparison stops after 3000 steps (0.03 s,
// ~20 contact times), while the grains are still falling and colliding. A wrong kernel (a
// missing pair, a history not carried over, a sign) moves grains by a good part of a radius
// within a few contact times; the bound, 1e-6 of the smallest radius, is far above the gap of the
// host mirror (5e-16 m: the same sums in another order) and far below any such error (histories
// dropped at each list build, tried once: a gap of 2.6e-3 m). The CUDA back end gives the host
// mirror's bits (GivesTheBitsOfTheHostMirror; on an H200, 2026-12-04).
TEST_P(DeviceEngine, SettlingBedFollowsTheHostRun) {
  test::TempDir tmp;
  const auto cfg = settling_case();
  const auto [gpu, cpu, gap] = run_on_both(cfg, GetParam(), 3000, tmp.path());
  std::printf("[%s] settling bed, 3000 steps: largest position gap %.3e m (%.3e of r_min)\n",
              name(), gap, gap / 0.0015);
  EXPECT_LT(gap, 1e-6 * 0.0015);
  EXPECT_EQ(gpu->n_contacts(), cpu->n_contacts());
  EXPECT_EQ(gpu->n_wall_contacts(), cpu->n_wall_contacts());
  EXPECT_NEAR(gpu->quantity("kinetic_energy"), cpu->quantity("kinetic_energy"),
              1e-6 * cpu->quantity("kinetic_energy"));
  EXPECT_NEAR(gpu->quantity("elastic_energy"), cpu->quantity("elastic_energy"),
              1e-6 * cpu->quantity("elastic_energy"));
}

// Walls with prescribed motion: a lid coming down on the bed while it turns about the vertical
// (its in-plane velocity drags the grains it touches) and a side wall turning about a vertical
// axis (its normal changes with time). Bound as above.
TEST_P(DeviceEngine, MovingWallsFollowTheHostRun) {
  test::TempDir tmp;
  auto cfg = settling_case();
  test::add_plane(cfg, "lid", {0.02, 0.02, 0.063}, {0, 0, -1}, "steel");
  cfg.walls.back().motion.velocity = {0, 0, -0.3};
  cfg.walls.back().motion.rotates = true;
  cfg.walls.back().motion.rate = 20;  // rad/s, about z through the lid's centre
  cfg.walls.back().motion.axis = {0, 0, 1};
  cfg.walls.back().motion.center = {0.02, 0.02, 0.063};
  test::add_plane(cfg, "flap", {0.002, 0.02, 0}, {1, 0, 0}, "steel");
  cfg.walls.back().motion.rotates = true;
  cfg.walls.back().motion.rate = 2;
  cfg.walls.back().motion.axis = {0, 0, 1};
  cfg.walls.back().motion.center = {0.002, 0.02, 0};
  cfg.output.quantities = {"wall_force.lid", "wall_torque.lid"};
  const auto [gpu, cpu, gap] = run_on_both(cfg, GetParam(), 3000, tmp.path());
  const Vec3 f = gpu->walls()[5].force, fc = cpu->walls()[5].force;
  std::printf(
      "[%s] moving walls, 3000 steps: largest position gap %.3e m; lid force %.6e / %.6e N, "
      "torque %.6e N m; flap force %.6e N, %lld wall contacts\n",
      name(), gap, f.z, fc.z, cpu->walls()[5].torque.z, cpu->walls()[6].force.x,
      static_cast<long long>(cpu->n_wall_contacts()));
  EXPECT_LT(gap, 1e-6 * 0.0015);
  EXPECT_GT(std::abs(fc.z), 0.0);  // the lid reached the grains
  EXPECT_NEAR(f.z, fc.z, 1e-6 * std::abs(fc.z));
  const Vec3 tq = gpu->walls()[5].torque, tqc = cpu->walls()[5].torque;
  EXPECT_LT(norm(tq - tqc), 1e-6 * norm(tqc) + 1e-15);
}

// A rotating drum (cylinder walls on the device, boundaries/wall_surface.hpp's gap shared with
// the host): the frictional drum drags the charge and takes a torque about its axis. 6000 steps:
// the charge has landed (11 grains on the walls), the two runs are still 2e-12 m apart (at 8000
// steps the chaos of the collisions has made it 5e-10 m, and the torque 1e-6 apart). Bound as in
// SettlingBedFollowsTheHostRun; the torque, a sum over the grains touching the drum, agrees to
// 1e-6 of itself (the drum's velocity left out of the contacts, tried once: 5e-3 m apart, the
// torque 40 % off).
TEST_P(DeviceEngine, RotatingDrumFollowsTheHostRun) {
  test::TempDir tmp;
  auto cfg = drum_case();
  cfg.output.quantities = {"wall_torque.drum"};
  const auto [gpu, cpu, gap] = run_on_both(cfg, GetParam(), 6000, tmp.path());
  const Vec3 tq = gpu->walls()[0].torque, tqc = cpu->walls()[0].torque;
  std::printf(
      "[%s] rotating drum, 6000 steps: largest position gap %.3e m; drum torque %.6e / "
      "%.6e N m about its axis, %lld wall contacts\n",
      name(), gap, tq.y, tqc.y, static_cast<long long>(cpu->n_wall_contacts()));
  EXPECT_LT(gap, 1e-6 * 0.0015);
  EXPECT_GE(cpu->n_wall_contacts(), 5);
  EXPECT_GT(std::abs(tqc.y), 0.0);  // the charge lies on the drum
  EXPECT_LT(norm(tq - tqc), 1e-6 * norm(tqc));
  EXPECT_EQ(gpu->n_wall_contacts(), cpu->n_wall_contacts());
}

// A rough base of fixed grains under the settling bed (periodic in x and y, no floor): the free
// grains land on the fixed ones, which never move, never meet one another and act with infinite
// mass (contact::reduced_mass). Bound as in SettlingBedFollowsTheHostRun; the base's load (the
// series' fixed_force: the contact forces on the fixed grains) agrees to 1e-6 of itself.
TEST_P(DeviceEngine, FixedBaseFollowsTheHostRun) {
  test::TempDir tmp;
  auto cfg = settling_case();
  cfg.walls.clear();
  cfg.domain.periodic = {true, true, false};
  cfg.domain.min.z = -0.004;
  // 8 x 8 glass spheres of r = 2.5 mm, 4.9 mm apart at z = -1 mm: the fixed neighbours overlap
  // by 0.1 mm and must be left out of the lists (else they count as contacts); the free grains
  // fall onto them.
  test::add_fixed_sphere_layer(cfg, "glass", 0.0025, 0.0049, 0, 0.04, 0, 0.04, -0.001);
  cfg.output.quantities = {"fixed_force"};
  const auto [gpu, cpu, gap] = run_on_both(cfg, GetParam(), 5000, tmp.path());
  const double load = gpu->quantity("fixed_force.z"), load_c = cpu->quantity("fixed_force.z");
  std::printf(
      "[%s] fixed base, 5000 steps: largest position gap %.3e m; load on the base %.6e / "
      "%.6e N, %lld contacts\n",
      name(), gap, load, load_c, static_cast<long long>(cpu->n_contacts()));
  EXPECT_LT(gap, 1e-6 * 0.0015);
  EXPECT_LT(load_c, 0.0);  // the bed presses on the base
  EXPECT_NEAR(load, load_c, 1e-6 * std::abs(load_c));
  EXPECT_EQ(gpu->n_contacts(), cpu->n_contacts());
  // (summed over the host's lists rebuilt from the device's state: without the fixed pairs)
  EXPECT_NEAR(gpu->quantity("elastic_energy"), cpu->quantity("elastic_energy"),
              1e-6 * cpu->quantity("elastic_energy"));
  const auto& p = gpu->particles();
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.fixed()[i] != 0) {
      ASSERT_EQ(p.v()[i], Vec3{}) << "fixed grain " << p.id()[i];
      ASSERT_EQ(p.x()[i].z, -0.001) << "fixed grain " << p.id()[i];
    }
}

// Fixed groups with prescribed motions under the bed: a belt (the left half of the base)
// translating at 5 cm/s, and a turntable (the right half) turning at 3 rad/s about a vertical
// axis. Their grains are carried analytically (the turntable's cosine and sine from the host:
// kernels.hpp's PlacedMotion) and drag the bed. Bounds as in FixedBaseFollowsTheHostRun; the
// turntable's torque (fixed_torque, about its axis) agrees to 1e-6 of itself.
TEST_P(DeviceEngine, MovingFixedGroupsFollowTheHostRun) {
  test::TempDir tmp;
  auto cfg = settling_case();
  cfg.walls.clear();
  cfg.domain.periodic = {true, true, false};
  cfg.domain.min.z = -0.004;
  auto& belt = test::add_fixed_sphere_layer(cfg, "glass", 0.0025, 0.0049, 0, 0.02, 0, 0.04, -0.001);
  belt.motion = config::Motion{};
  belt.motion->velocity = {0.05, 0, 0};
  auto& table =
      test::add_fixed_sphere_layer(cfg, "glass", 0.0025, 0.0049, 0.02, 0.04, 0, 0.04, -0.001);
  table.motion = config::Motion{};
  table.motion->rotates = true;
  table.motion->axis = {0, 0, 1};
  table.motion->center = {0.03, 0.02, 0};
  table.motion->rate = 3;
  cfg.output.quantities = {"fixed_force", "fixed_torque"};
  const auto [gpu, cpu, gap] = run_on_both(cfg, GetParam(), 5000, tmp.path());
  const double load = gpu->quantity("fixed_force.z"), load_c = cpu->quantity("fixed_force.z");
  const double tq = gpu->quantity("fixed_torque.z"), tq_c = cpu->quantity("fixed_torque.z");
  std::printf(
      "[%s] moving fixed groups, 5000 steps: largest position gap %.3e m; load %.6e / "
      "%.6e N, turntable torque %.6e / %.6e N m, %lld contacts\n",
      name(), gap, load, load_c, tq, tq_c, static_cast<long long>(cpu->n_contacts()));
  EXPECT_LT(gap, 1e-6 * 0.0015);
  EXPECT_LT(load_c, 0.0);
  EXPECT_NEAR(load, load_c, 1e-6 * std::abs(load_c));
  EXPECT_GT(std::abs(tq_c), 0.0);  // the bed lies on the turntable
  EXPECT_NEAR(tq, tq_c, 1e-6 * std::abs(tq_c));
  EXPECT_EQ(gpu->n_contacts(), cpu->n_contacts());
  EXPECT_NEAR(gpu->quantity("elastic_energy"), cpu->quantity("elastic_energy"),
              1e-6 * cpu->quantity("elastic_energy"));
  // The carried grains: where their motions put them at t = 0.05 s, with their velocities.
  const auto& p = gpu->particles();
  const auto at = index_by_id(*cpu);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.fixed()[i] != 0) {
      const std::size_t k = at.at(p.id()[i]);
      ASSERT_NE(p.v()[i], Vec3{}) << "fixed grain " << p.id()[i];
      ASSERT_EQ(p.x()[i], cpu->particles().x()[k]) << "fixed grain " << p.id()[i];
      ASSERT_EQ(p.v()[i], cpu->particles().v()[k]) << "fixed grain " << p.id()[i];
    }
}

// A carried grain must raise the list's rebuild as a free one does: a fixed sphere sweeping at
// 1 m/s into a free one at rest, with no gravity (nothing else moves, so only the carried
// grain's own displacement brings the pair into the list), knocks it away as on the host.
TEST_P(DeviceEngine, CarriedGrainTriggersTheListBuild) {
  test::TempDir tmp;
  auto cfg = glass_and_steel("sweep", {0.06, 0.02, 0.02});
  cfg.gravity = {0, 0, 0};
  test::add_spheres(cfg, "glass", 0.002, {{0.03, 0.01, 0.01}});
  test::add_spheres(cfg, "glass", 0.002, {{0.005, 0.01, 0.0101}});
  cfg.particles.back().fixed = true;
  cfg.particles.back().motion = config::Motion{};
  cfg.particles.back().motion->velocity = {1, 0, 0};
  cfg.neighbor.skin = 0.0006;
  const auto [gpu, cpu, gap] = run_on_both(cfg, GetParam(), 4000, tmp.path());
  const Vec3 v = gpu->particles().v()[gpu->particles().fixed()[0] == 0 ? 0 : 1];
  std::printf("[%s] sweep, 4000 steps: largest position gap %.3e m; free grain at %.4f m/s\n",
              name(), gap, norm(v));
  EXPECT_GT(norm(v), 1.0);  // knocked away (at ~(1 + e) x 1 m/s)
  EXPECT_LT(gap, 1e-6 * 0.002);
}

TEST_P(DeviceEngine, PeriodicCohesiveBedFollowsTheHostRun) {
  test::TempDir tmp;
  const auto cfg = periodic_case();
  const auto [gpu, cpu, gap] = run_on_both(cfg, GetParam(), 3000, tmp.path());
  std::printf("[%s] periodic cohesive bed, 3000 steps: largest position gap %.3e m\n", name(), gap);
  EXPECT_LT(gap, 1e-6 * 0.002);
  EXPECT_EQ(gpu->n_contacts(), cpu->n_contacts());
}

// Fixed summation order (full list, one thread per grain, stable sort of the cells): two device
// runs give the same bits.
TEST_P(DeviceEngine, RunsAreReproducible) {
  test::TempDir tmp;
  const auto cfg = settling_case();
  const auto a = run_case(cfg, GetParam(), 2000, tmp / "a");
  const auto b = run_case(cfg, GetParam(), 2000, tmp / "b");
  ASSERT_EQ(a->particles().size(), b->particles().size());
  for (std::size_t i = 0; i < a->particles().size(); ++i) {
    ASSERT_EQ(a->particles().x()[i], b->particles().x()[i]) << "grain " << i;
    ASSERT_EQ(a->particles().v()[i], b->particles().v()[i]) << "grain " << i;
  }
}

// An elastic gas (restitution 1: no damping; frictionless) in a fully periodic box conserves
// energy up to velocity Verlet's bounded O(dt^2) error. Linear springs, r = 1.5 mm
// (m* = 1.77e-5 kg), k = 1000 N/m: contact time t_c = pi sqrt(m*/k) = 4.2e-4 s, dt = 7e-6 s
// = t_c / 60, so a contact's energy is integrated to ~(dt/t_c)^2 ~ 3e-4 of itself; about one
// grain in fifteen is in a contact at any time, and the error does not accumulate over the
// ~30 collisions per grain of the 20000 steps: the host run of this case stays within 7e-5 of
// its start. Bound 3e-4; a lost or doubled contact or a wrong history drifts by per cents.
TEST_P(DeviceEngine, ElasticGasConservesEnergy) {
  test::TempDir tmp;
  const auto c = elastic_gas();
  Simulation start(c);
  const double e0 = start.total_energy();
  const auto gpu = run_case(c, GetParam(), 20000, tmp / "gpu");
  const double e1 = gpu->total_energy();
  std::printf("[%s] elastic gas, 20000 steps, %lld contacts now: energy %.9e -> %.9e J (%.2e)\n",
              name(), static_cast<long long>(gpu->n_contacts()), e0, e1, (e1 - e0) / e0);
  EXPECT_GT(gpu->n_contacts(), 0);
  EXPECT_NEAR(e1, e0, 3e-4 * e0);
}

// A device run's checkpoint holds the device's contact histories: the host continues it as it
// continues its own run, and a device run continues a host checkpoint likewise.
TEST_P(DeviceEngine, CheckpointsCrossBetweenDeviceAndHost) {
  test::TempDir tmp;
  const auto cfg = settling_case();
  const auto cpu_whole = run_case(cfg, Device::Cpu, 6000, tmp / "cpu_whole");
  // Device first, host second.
  run_case(cfg, GetParam(), 4000, tmp / "gpu_first");
  const auto host_after =
      run_case(cfg, Device::Cpu, 2000, tmp / "host_after", tmp / "gpu_first/checkpoint_final.h5");
  // Host first, device second.
  run_case(cfg, Device::Cpu, 4000, tmp / "cpu_first");
  const auto gpu_after =
      run_case(cfg, GetParam(), 2000, tmp / "gpu_after", tmp / "cpu_first/checkpoint_final.h5");
  std::int64_t with_history = 0;
  for (const Vec3& h : host_after->neighbor_list().history()) with_history += h != Vec3{};
  const double g1 = max_position_gap(*host_after, *cpu_whole);
  const double g2 = max_position_gap(*gpu_after, *cpu_whole);
  std::printf("[%s] device -> host: gap %.3e m; host -> device: gap %.3e m; %lld histories\n",
              name(), g1, g2, static_cast<long long>(with_history));
  EXPECT_GT(with_history, 20);  // (82 touching pairs with a history at the end, 2026-12-04)
  EXPECT_LT(g1, 1e-6 * 0.0015);
  EXPECT_LT(g2, 1e-6 * 0.0015);
}

INSTANTIATE_TEST_SUITE_P(Backends, DeviceEngine,
                         ::testing::Values(Device::HostMirror, Device::Cuda),
                         [](const ::testing::TestParamInfo<Device>& p) {
                           return p.param == Device::Cuda ? std::string("Cuda")
                                                          : std::string("HostMirror");
                         });

// A device run continued from its own checkpoint gives the bits of the run that was not cut:
// the checkpoint holds the device's histories, and each grain sums its pairs in partner order,
// whatever the step of the list's build (kernels.hpp, list_one).
TEST_P(DeviceEngine, CheckpointContinuesBitIdentically) {
  // A settling bed (walls, friction, rolling), and a fast elastic gas, whose grains change
  // cells (and so the order in which a list build meets them) between the builds of the two runs.
  for (const auto& cfg : {settling_case(), elastic_gas()}) {
    test::TempDir tmp;
    const auto whole = run_case(cfg, GetParam(), 3000, tmp / "whole");
    run_case(cfg, GetParam(), 600, tmp / "first");
    const auto rest =
        run_case(cfg, GetParam(), 2400, tmp / "rest", tmp / "first/checkpoint_final.h5");
    ASSERT_EQ(whole->step_count(), rest->step_count());
    expect_same_grains(*whole, *rest, cfg.name);
    for (std::size_t w = 0; w < whole->walls().size(); ++w)
      EXPECT_EQ(whole->walls()[w].force, rest->walls()[w].force);
  }
}

// The list's slots grow when a build finds a grain with more partners than slots: the engine is
// started with two slots per grain on the settling bed (up to ~20 partners per grain) and must
// give the host's run all the same.
TEST_P(DeviceEngine, ListGrowsWhenAGrainHasMorePartners) {
  auto cfg = settling_case();
  cfg.walls.clear();
  cfg.domain.periodic = {true, true, false};
  test::add_plane(cfg, "floor", {0, 0, 0}, {0, 0, 1}, "steel");
  Simulation host(cfg), dev(cfg);
  gpu::SphereDemSetup s;
  s.domain = dev.domain();
  s.gravity = dev.gravity();
  s.dt = dev.dt();
  s.skin = dev.neighbor_list().skin();
  s.pairs = dev.pairs();
  for (const auto& w : dev.walls()) {
    gpu::DeviceWall p;
    p.point0 = p.point = w.point;
    p.dir0 = p.dir = w.dir;
    p.material = w.material;
    s.walls.push_back(p);
  }
  s.initial_slots = 2;
  gpu::SphereDem engine(dev.particles(), s,
                        GetParam() == Device::Cuda ? gpu::Backend::Cuda : gpu::Backend::HostMirror);
  const int steps = 3000;
  ASSERT_EQ(engine.advance(steps), steps);
  engine.download(dev.particles());
  for (int k = 0; k < steps; ++k) host.step();
  host.complete_step();
  const auto c = engine.counts();
  const double gap = max_position_gap(dev, host);
  std::printf("[%s] list grown to %d slots per grain, %lld builds; gap %.3e m\n", name(),
              c.list_capacity, static_cast<long long>(c.list_builds), gap);
  EXPECT_GT(c.list_capacity, 8);
  EXPECT_LT(gap, 1e-6 * 0.0015);
  EXPECT_EQ(engine.n_contacts(), host.n_contacts());
}

// A SIGTERM during a device run ends it within 64 steps with its outputs and a checkpoint at
// the step reached (core/stop.hpp); continuing from it gives the bits of an uncut device run.
TEST_P(DeviceEngine, StoppedRunContinuesBitIdentically) {
  test::TempDir tmp;
  const auto cfg = settling_case();
  RunOptions o;
  o.output = tmp / "stopped";
  o.quiet = true;
  o.device = GetParam();
  o.steps = 2'000'000;  // ~a minute at least: the signal comes first
  stop::install_handlers();
  std::jthread sender([] {  // (joined however the test ends)
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ::kill(::getpid(), SIGTERM);
  });
  Simulation a(cfg);
  const RunSummary s = a.run(o);
  stop::reset();
  ASSERT_EQ(s.stop_signal, SIGTERM);
  ASSERT_GT(s.steps, 0);
  ASSERT_LT(s.steps, *o.steps);
  ASSERT_TRUE(std::filesystem::exists(s.checkpoint)) << s.checkpoint;
  const auto rest = run_case(cfg, GetParam(), 500, tmp / "rest", s.checkpoint);
  const auto whole = run_case(cfg, GetParam(), s.steps + 500, tmp / "whole");
  ASSERT_EQ(rest->step_count(), whole->step_count());
  expect_same_grains(*whole, *rest, "stopped and continued");
}

// A device run that diverges (a step far too long for the contacts) stops with the host's
// message, before it writes the step: the copy back skips the lists of non-finite grains.
TEST_P(DeviceEngine, DivergedRunIsReported) {
  test::TempDir tmp;
  auto cfg = settling_case();
  cfg.time.step = 2e-3;  // 200 x: the contacts blow up
  try {
    run_case(cfg, GetParam(), 1000, tmp / "out");  // (the last step syncs the lists)
    FAIL() << "the run did not diverge";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the run diverged"), std::string::npos) << e.what();
  }
}

// The CUDA kernels and the host mirror run the same bodies with no contracted multiply-adds and
// IEEE division and square root on both sides (cuda_exec.cu, host_exec.cpp), the walls placed
// on the host: the two give the same bits, here over a settling bed with moving walls and a
// rotating drum. (Any difference, a contraction or an approximate math function, shows at once.)
TEST(DeviceEngineCuda, GivesTheBitsOfTheHostMirror) {
  std::string why;
  if (!gpu::device_available(&why)) GTEST_SKIP() << why;
  test::TempDir tmp;
  auto bed = settling_case();
  test::add_plane(bed, "lid", {0.02, 0.02, 0.063}, {0, 0, -1}, "steel");
  bed.walls.back().motion.velocity = {0, 0, -0.3};
  bed.walls.back().motion.rotates = true;
  bed.walls.back().motion.rate = 20;
  bed.walls.back().motion.axis = {0, 0, 1};
  bed.walls.back().motion.center = {0.02, 0.02, 0.063};
  for (const auto& [what, cfg] : {std::pair{"settling bed", bed}, {"drum", drum_case()}}) {
    const auto cuda = run_case(cfg, Device::Cuda, 3000, tmp / (std::string(what) + "_cuda"));
    const auto mirror =
        run_case(cfg, Device::HostMirror, 3000, tmp / (std::string(what) + "_mirror"));
    expect_same_grains(*cuda, *mirror, what);
    EXPECT_EQ(cuda->n_contacts(), mirror->n_contacts()) << what;
  }
}
