// SPDX-License-Identifier: GPL-3.0-or-later
// `run --device cuda` (docs/gpu.md): what the CUDA back end refuses, and that a refused run
// writes nothing (every build; the engine itself: test_device_engine.cpp).
#include <gtest/gtest.h>

#include <filesystem>

#include "case_builder.hpp"
#include "core/error.hpp"
#include "gpu/sphere_dem.hpp"
#include "simulation/simulation.hpp"
#include "temp_dir.hpp"

using namespace gf;

namespace {

config::Case spheres_in_a_box() {
  auto c = test::base_case(1e-5, 0.01, {0, 0, 0}, {0.03, 0.03, 0.05});
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin", {{"restitution", 0.5}});
  auto& f = test::add_box_fill(c, "glass", 0.002, 0.002, {0, 0, 0}, {0.03, 0.03, 0.03},
                               config::Fill::Lattice::Cubic);
  f.count = 27;
  test::add_box(c, "box", {0, 0, 0}, {0.03, 0.03, 0.05}, {"zmax"}, "glass");
  return c;
}

/// Runs `c` with --device cuda: it must be refused with an input error that says `why`, before
/// anything is written or any step is taken.
void expect_refused(const config::Case& c, const std::string& why) {
  test::TempDir tmp;
  Simulation sim(c);
  RunOptions o;
  o.output = tmp / "out";
  o.quiet = true;
  o.device = Device::Cuda;
  try {
    sim.run(o);
    ADD_FAILURE() << "ran with --device cuda";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(tmp / "out"));
  EXPECT_EQ(sim.step_count(), 0);
}

}  // namespace

TEST(DeviceRun, NamesWhatTheBackEndCannotRun) {
  EXPECT_EQ(Simulation(spheres_in_a_box()).device_unsupported(), "");
  auto rods = spheres_in_a_box();
  rods.particles.clear();
  test::add_capsule_fill(rods, "glass", 0.001, 4, {0, 0, 0}, {0.03, 0.03, 0.03},
                         config::Fill::Lattice::Cubic)
      .count = 8;
  EXPECT_NE(Simulation(rods).device_unsupported().find("spherocylinders"), std::string::npos);
  auto gear = spheres_in_a_box();
  gear.integrator = "gear5";
  EXPECT_NE(Simulation(gear).device_unsupported().find("gear5"), std::string::npos);
  auto base = spheres_in_a_box();
  test::add_fixed_sphere_layer(base, "glass", 0.002, 0.005, 0, 0.03, 0, 0.03, 0.035);
  EXPECT_EQ(Simulation(base).device_unsupported(), "");  // fixed groups at rest: taken
  base.particles.back().motion = config::Motion{};
  base.particles.back().motion->velocity = {0.01, 0, 0};
  EXPECT_EQ(Simulation(base).device_unsupported(), "");  // and with a prescribed motion
  auto moving = spheres_in_a_box();
  test::add_plane(moving, "piston", {0, 0, 0.045}, {0, 0, -1}, "glass");
  moving.walls.back().motion.velocity = {0, 0, -0.1};
  EXPECT_EQ(Simulation(moving).device_unsupported(), "");  // prescribed motion: taken
  auto drum = spheres_in_a_box();
  config::Wall cyl;
  cyl.name = "drum";
  cyl.kind = config::Wall::Kind::Cylinder;
  cyl.center = {0.015, 0.015, 0};
  cyl.radius = 0.015;
  cyl.material = "glass";
  drum.walls.push_back(cyl);
  EXPECT_EQ(Simulation(drum).device_unsupported(), "");  // cylinders: taken
  auto chute = spheres_in_a_box();
  test::add_mesh(chute, "chute", {{0, 0, 0.01}, {0.03, 0, 0.01}, {0, 0.03, 0.02}}, {{0, 1, 2}},
                 "glass");
  EXPECT_NE(Simulation(chute).device_unsupported().find("wall 'chute' is a mesh"),
            std::string::npos);
  auto torque = spheres_in_a_box();
  torque.output.quantities = {"wall_torque.box"};  // the step's: the device has it
  EXPECT_EQ(Simulation(torque).device_unsupported(), "");
  torque.output.quantities = {"wall_torque_mean.box"};
  EXPECT_NE(Simulation(torque).device_unsupported().find("wall_torque_mean.box"),
            std::string::npos);
}

TEST(DeviceRun, BuildWithoutCudaSaysSo) {
  if (gpu::cuda_built()) GTEST_SKIP() << "this build has the CUDA back end";
  expect_refused(spheres_in_a_box(), "built without CUDA");
}

TEST(DeviceRun, RefusedRunWritesNothing) {
  auto c = spheres_in_a_box();
  c.integrator = "gear5";  // refused by every build
  expect_refused(c, "--device cuda: integrator: gear5");
}
