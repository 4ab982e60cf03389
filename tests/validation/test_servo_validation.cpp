// SPDX-License-Identifier: GPL-3.0-or-later
// Stress-controlled (servo) walls: the wall finds the position where the grains push on it with
// the requested pressure, and the force balance of the packing holds.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "case_builder.hpp"
#include "dump.hpp"
#include "simulation/simulation.hpp"

using namespace gf;
using gf::test::Dump;

// 200 disks (2D) in a box 0.1 m wide: floor and side walls fixed, the lid a servo wall at
// 20 kPa (span: the two side walls, thickness 0.01 m, so 20 N). Once the lid has settled (its
// speed decays as the force error does), the lid carries 20 N and the floor 20 N plus the weight
// of the disks (0.75 N); wall friction on the sides takes part of the load between them, so the
// floor balance is checked with frictionless sides. The remaining error is the inertia of the
// still-moving packing: 1 % is ample after 0.5 s.
TEST(ValidationServo, LidHoldsThePressureAndTheFloorTheRest) {
  auto c = test::base_case(5e-6, 1.0, {0, 0, 0}, {0.1, 0.3, 0});
  c.dimension = 2;
  c.domain.thickness = 0.01;
  c.gravity = {0, -9.81, 0};
  test::add_material(c, "glass", 2500, 1e8, 0.3);
  test::add_material(c, "smooth", 2500, 1e8, 0.3);
  test::add_contact(c, "glass", "glass", "hooke",
                    {{"restitution", 0.3}, {"friction", 0.5}, {"stiffness", 1e6}});
  test::add_contact(c, "glass", "smooth", "hooke",
                    {{"restitution", 0.3}, {"friction", 0.0}, {"stiffness", 1e6}});
  auto& f = test::add_box_fill(c, "glass", 0.0025, 0.0035, {0, 0, 0}, {0.1, 0.12, 0},
                               config::Fill::Lattice::Random);
  f.count = 200;
  f.seed = 12;
  c.particles.back().kind = config::Shape::Disk;
  test::add_plane(c, "floor", {0, 0, 0}, {0, 1, 0}, "smooth");
  test::add_plane(c, "left", {0, 0, 0}, {1, 0, 0}, "smooth");
  test::add_plane(c, "right", {0.1, 0, 0}, {-1, 0, 0}, "smooth");
  test::add_plane(c, "lid", {0, 0.12, 0}, {0, -1, 0}, "smooth");
  config::Servo servo;
  servo.pressure = 2e4;
  servo.max_velocity = 0.5;
  servo.spans = {{"left", "right"}};
  c.walls.back().servo = servo;
  Simulation sim(c);
  double weight = 0;
  for (std::size_t i = 0; i < sim.particles().size(); ++i)
    weight += 9.81 * sim.particles().mass()[i];
  Dump trace("servo_lid", "t,lid_force,floor_force,lid_y");
  for (int s = 0; s < 100000; ++s) {
    sim.step();
    if (s % 500 == 0)
      trace.row(sim.time(), sim.walls()[3].force.y, -sim.walls()[0].force.y,
                sim.walls()[3].point.y);
  }
  const double lid = sim.walls()[3].force.y;     // pushed up by the grains: +y
  const double floor = -sim.walls()[0].force.y;  // pushed down
  const double target = 2e4 * 0.1 * 0.01;
  std::printf(
      "servo lid: force %.4f N (target %.4f), floor %.4f N (lid + weight %.4f), lid at "
      "y = %.4f m, speed %.2e m/s\n",
      lid, target, floor, lid + weight, sim.walls()[3].point.y,
      norm(sim.walls()[3].servo_velocity));
  EXPECT_NEAR(lid / target, 1.0, 0.01);
  EXPECT_NEAR(floor / (target + weight), 1.0, 0.01);
}
