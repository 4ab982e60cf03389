// SPDX-License-Identifier: GPL-3.0-or-later
// The sjkr cohesion slot (contact/laws/cohesion.hpp) against the geometry written out here: the
// contact area of two spheres and of a sphere and a wall, and the forces of the force loops
// (batched sphere pairs, per-contact dispatch of mixed laws, plane and mesh walls,
// spherocylinders, 2D disks) against k delta - k_c A at rest. k_c = 0 gives the bits of the law
// without the cohesion slot, in the law and in whole runs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <string>

#include "case_builder.hpp"
#include "contact/registry.hpp"
#include "io/input/parse_case.hpp"
#include "simulation/simulation.hpp"

using namespace gf;
using namespace gf::contact;

namespace {

constexpr double pi = std::numbers::pi;

/// Area of the circle in which two sphere surfaces (radii ri, rj, centres d apart) intersect,
/// from the definition: the circle lies at x = (d^2 + ri^2 - rj^2) / (2d) from centre i and has
/// radius^2 = ri^2 - x^2.
double circle_area(double ri, double rj, double d) {
  const double x = (d * d + ri * ri - rj * rj) / (2 * d);
  return pi * (ri * ri - x * x);
}
/// The LIGGGHTS form of the same (cohesion_model_sjkr.h).
double liggghts_area(double ri, double rj, double d) {
  return -pi / 4 * ((d - ri - rj) * (d + ri - rj) * (d - ri + rj) * (d + ri + rj)) / (d * d);
}

ContactKinematics at_rest(double overlap, double r_eff, double inv_r_sum) {
  ContactKinematics k{};
  k.overlap = overlap;
  k.normal = {0, 0, 1};
  k.r_eff = r_eff;
  k.m_eff = 1e-5;
  k.inv_r_sum = inv_r_sum;
  return k;
}

/// A 3D case with hooke (k = 1000 N/m) between glass and glass, k_c = `kc`, no gravity.
std::string header(double kc, const std::string& extra_contacts = "") {
  return "time: {step: 1.0e-6, end: 1.0}\n"
         "domain: {min: [-0.02, -0.02, -0.02], max: [0.02, 0.02, 0.02]}\n"
         "gravity: [0, 0, 0]\n"
         "materials:\n"
         "  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}\n"
         "  steel: {density: 7800, youngs_modulus: 2.0e8, poisson_ratio: 0.3}\n"
         "contacts:\n"
         "  - {between: [glass, glass], model: hooke, restitution: 0.5, stiffness: 1000, "
         "cohesion_energy_density: " +
         std::to_string(kc) + "}\n" + extra_contacts;
}

/// The same case built in code (no particles yet).
config::Case hooke_case(double kc) {
  auto c = test::base_case(1e-6, 1.0, {-0.02, -0.02, -0.02}, {0.02, 0.02, 0.02});
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hooke",
                    {{"restitution", 0.5}, {"stiffness", 1000.0}, {"cohesion_energy_density", kc}});
  return c;
}

/// Force on the particle with id `id` after the simulation's first force evaluation.
Vec3 force_on(Simulation& sim, std::int64_t id) {
  const auto& p = sim.particles();
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.id()[i] == id) return p.f()[i];
  ADD_FAILURE() << "no particle " << id;
  return {};
}

}  // namespace

// The area written in delta, R* and 1/(R_i + R_j) against the two textbook forms, for unequal
// and equal spheres from a grazing to a deep overlap. The forms differ only in rounding: the
// textbook ones subtract nearly equal numbers (d - R_i - R_j = -delta) and lose about
// eps R / delta relative, <= 1e-11 for delta / R >= 1e-4; 1e-9 leaves room for that only.
TEST(Cohesion, AreaIsTheIntersectionCircleOfTheSpheres) {
  for (const auto& [ri, rj] : {std::pair{1e-3, 1e-3}, std::pair{1e-3, 2.5e-3}, {3e-3, 0.7e-3}}) {
    for (const double rel : {1e-4, 1e-3, 0.01, 0.1, 0.3}) {
      const double delta = rel * std::min(ri, rj);
      const double d = ri + rj - delta;
      const double a =
          pi * SjkrCohesion::intersection_radius2(delta, ri * rj / (ri + rj), 1.0 / (ri + rj));
      EXPECT_NEAR(a, circle_area(ri, rj, d), 1e-9 * a) << ri << " " << rj << " " << delta;
      EXPECT_NEAR(a, liggghts_area(ri, rj, d), 1e-9 * a) << ri << " " << rj << " " << delta;
    }
  }
  // A wall (R_j -> infinity): pi (R^2 - (R - delta)^2), LIGGGHTS' sphere-wall area; and the
  // limit of a very large second sphere.
  for (const double delta : {1e-7, 1e-5, 3e-4}) {
    const double r = 1e-3;
    const double a = pi * SjkrCohesion::intersection_radius2(delta, r, 0.0);
    EXPECT_NEAR(a, pi * (r * r - (r - delta) * (r - delta)), 1e-9 * a);
    EXPECT_NEAR(a, circle_area(r, 1e3, r + 1e3 - delta), 1e-5 * a);
  }
  // No area for coincident centres or a sphere inside the other (no NaN, no repulsion).
  EXPECT_EQ(SjkrCohesion::intersection_radius2(2e-3, 5e-4, 500.0), 0.0);
  EXPECT_EQ(SjkrCohesion::intersection_radius2(1.5e-3, 1e-3 * 0.5e-3 / 1.5e-3, 1 / 1.5e-3), 0.0);
}

// The law at rest: F_n = k delta - k_c A along the normal; the Coulomb cap and the rolling
// torque use the repulsive part k delta (the load pressing the surfaces together).
TEST(Cohesion, LawSubtractsCohesionAndCapsFrictionWithTheRepulsivePart) {
  Material glass{"glass", 2500, 1e7, 0.3};
  const PairCoeffs c = prepare_pair("hooke", {&glass, &glass, 1e-3},
                                    {{"restitution", 1.0},
                                     {"stiffness", 1000.0},
                                     {"friction", 0.4},
                                     {"rolling_friction", 0.1},
                                     {"cohesion_energy_density", 5e5},
                                     {"tangential_stiffness_ratio", 2.0 / 7.0}});
  EXPECT_EQ(c.cohesion, 5e5);
  ContactKinematics k = at_rest(2e-5, 5e-4, 1.0 / 2e-3);
  const double area = pi * (1e-3 * 2e-5 - 0.25 * 2e-5 * 2e-5);  // equal spheres: pi (R d - d^2/4)
  Vec3 xi{};
  auto r = Hooke::Law::evaluate(c, k, 1e-6, xi);
  EXPECT_NEAR(r.force.z, 1000 * 2e-5 - 5e5 * area, 1e-15);
  EXPECT_LT(r.force.z, 0.0);  // attractive at this overlap
  EXPECT_DOUBLE_EQ(r.normal_force, 1000 * 2e-5);
  k.v_rel = {1.0, 0, 0};  // sliding fast
  k.omega_rel = {0, 5.0, 0};
  xi = {};
  r = Hooke::Law::evaluate(c, k, 1e-3, xi);
  EXPECT_NEAR(std::hypot(r.force.x, r.force.y), 0.4 * 1000 * 2e-5, 1e-15);
  EXPECT_NEAR(r.rolling_torque.y, -0.1 * 5e-4 * 1000 * 2e-5, 1e-18);
}

// k_c = 0: the law with the cohesion slot gives the bits of the law without it, for random
// contacts (approaching, separating, sliding, rolling), both models.
TEST(Cohesion, ZeroCohesionGivesTheBitsOfTheLawWithout) {
  Material glass{"glass", 2500, 1e7, 0.3};
  std::mt19937_64 g(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const char* law : {"hooke", "hertz_mindlin"}) {
    std::map<std::string, double> prm{{"restitution", 0.4},
                                      {"friction", 0.3},
                                      {"rolling_friction", 0.05},
                                      {"cohesion_energy_density", 0.0}};
    if (std::string(law) == "hooke") {
      prm["stiffness"] = 500.0;
      prm["tangential_stiffness_ratio"] = 2.0 / 7.0;
    }
    const PairCoeffs c = prepare_pair(law, {&glass, &glass, 1e-3}, prm);
    for (int n = 0; n < 2000; ++n) {
      ContactKinematics k = at_rest(1e-5 * (1 + u(g)), 5e-4 * (1.2 + u(g)), (n % 3) * 400.0);
      k.normal = normalized(Vec3{u(g), u(g), u(g)});
      k.v_rel = {u(g), u(g), u(g)};
      k.omega_rel = {10 * u(g), 10 * u(g), 10 * u(g)};
      k.m_eff = 1e-5 * (1.5 + u(g));
      Vec3 xi_a{1e-6 * u(g), 1e-6 * u(g), 1e-6 * u(g)}, xi_b = xi_a;
      const ContactResult a = dispatch_index(ContactModels{}, c.model, [&]<class M>() {
        return M::Law::template evaluate<true>(c, k, 1e-5, xi_a);
      });
      const ContactResult b = dispatch_index(ContactModels{}, c.model, [&]<class M>() {
        return M::Law::template evaluate<false>(c, k, 1e-5, xi_b);
      });
      ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << law << " contact " << n;
      ASSERT_EQ(std::memcmp(&xi_a, &xi_b, sizeof xi_a), 0) << law << " contact " << n;
    }
  }
}

// Two spheres at rest (radii 1 and 1.5 mm) at several overlaps: the force on each is
// (k delta - k_c A) along the line of centres, A from circle_area. Once through the batched
// loop (one law) and once through the per-contact dispatch (a second material with another law
// makes the laws mixed). Only rounding separates the two sides: 1e-9 of k delta.
TEST(Cohesion, SphereSphereForceMatchesTheArea) {
  const double kc = 3e5, k = 1000, ri = 1e-3, rj = 1.5e-3;
  for (const bool mixed : {false, true}) {
    for (const double delta : {1e-6, 2e-5, 1e-4, 4e-4}) {
      const double d = ri + rj - delta;
      std::string text = header(kc, mixed ? "  - {between: [glass, steel], model: hertz_mindlin, "
                                            "restitution: 0.5}\n"
                                            "  - {between: [steel, steel], model: hertz_mindlin, "
                                            "restitution: 0.5}\n"
                                          : "");
      text +=
          "particles:\n"
          "  - {radius: 0.001, material: glass, positions: [[0, 0, 0]]}\n"
          "  - {radius: 0.0015, material: glass, positions: [[0, 0, " +
          std::to_string(d) + "]]}\n";
      if (mixed) text += "  - {radius: 0.001, material: steel, positions: [[0.01, 0.01, 0.01]]}\n";
      // (std::to_string keeps 6 decimals: d is rounded to 1e-6 m; the overlap is taken from it)
      const double d_used = std::stod(std::to_string(d));
      const double ov = ri + rj - d_used;
      Simulation sim(input::load_case_text(text, "cohesion.yaml"));
      const double expected = k * ov - kc * circle_area(ri, rj, d_used);
      const Vec3 f = force_on(sim, 2);
      EXPECT_NEAR(f.z, expected, 1e-9 * k * ov + 1e-15) << "delta " << ov << " mixed " << mixed;
      EXPECT_NEAR(f.x, 0.0, 1e-15);
      EXPECT_NEAR(force_on(sim, 1).z, -f.z, 1e-15);
    }
  }
}

// A sphere (R = 1 mm) at rest on a plane wall (the batched wall loop) and on a meshed square
// (the generic wall loop): F = k delta - k_c pi delta (2R - delta); the wall's reaction is the
// opposite. Rounding only: 1e-9 of k delta.
TEST(Cohesion, SphereWallForceMatchesTheArea) {
  const double kc = 3e5, k = 1000, r = 1e-3;
  for (const bool mesh : {false, true}) {
    for (const double delta : {1e-6, 2e-5, 1e-4, 4e-4}) {
      auto c = hooke_case(kc);
      test::add_spheres(c, "glass", r, {{0, 0, r - delta}});
      if (mesh)
        test::add_mesh(c, "floor",
                       {{-0.01, -0.01, 0}, {0.01, -0.01, 0}, {0.01, 0.01, 0}, {-0.01, 0.01, 0}},
                       {{0, 1, 2}, {0, 2, 3}}, "glass");
      else
        test::add_plane(c, "floor", {0, 0, 0}, {0, 0, 1}, "glass");
      Simulation sim(c);
      const double ov = r - sim.particles().x()[0].z;
      const double expected = k * ov - kc * pi * ov * (2 * r - ov);
      EXPECT_NEAR(force_on(sim, 1).z, expected, 1e-9 * k * ov)
          << "delta " << ov << " mesh " << mesh;
      EXPECT_NEAR(sim.walls()[0].force.z, -expected, 1e-9 * k * ov);
    }
  }
}

// Spherocylinders (cap radius 1 mm, cylinder 4 mm) crossed at right angles, touching side to
// side: the contact of two spheres of the cap radius (R* = r/2, R_i + R_j = 2r); one lying on a
// plane wall: two end contacts, each a sphere of the cap radius on the wall.
TEST(Cohesion, SpherocylinderContactsUseTheCapRadius) {
  const double kc = 3e5, k = 1000, r = 1e-3, delta = 5e-5;
  {
    auto c = hooke_case(kc);
    const Quat along_x = quat_from_axis_angle({0, 1, 0}, pi / 2);
    const Quat along_y = quat_from_axis_angle({1, 0, 0}, pi / 2);
    test::add_capsules(c, "glass", r, 0.004, {{0, 0, 0}, {0, 0, 2 * r - delta}},
                       {along_x, along_y});
    Simulation sim(c);
    const double expected = k * delta - kc * circle_area(r, r, 2 * r - delta);
    EXPECT_NEAR(force_on(sim, 2).z, expected, 1e-9 * k * delta);
    EXPECT_NEAR(force_on(sim, 1).z, -expected, 1e-9 * k * delta);
  }
  {
    auto c = hooke_case(kc);
    const Quat along_x = quat_from_axis_angle({0, 1, 0}, pi / 2);
    test::add_capsules(c, "glass", r, 0.004, {{0, 0, r - delta}}, {along_x});
    test::add_plane(c, "floor", {0, 0, 0}, {0, 0, 1}, "glass");
    Simulation sim(c);
    const double expected = 2 * (k * delta - kc * pi * delta * (2 * r - delta));
    EXPECT_NEAR(force_on(sim, 1).z, expected, 1e-9 * k * delta);
  }
}

// 2D disks take the area pi a^2 of the spheres the 2D elastic law assumes, whatever the depth
// (t = 5 mm here): F = k delta - k_c pi a^2, a^2 from the circle of intersection; a disk on a
// line wall with a^2 = delta (2R - delta).
TEST(Cohesion, DisksUseTheSphereAreaWhateverTheDepth) {
  const double kc = 3e5, k = 1000, r = 1e-3, rj = 2e-3, delta = 5e-5, t = 0.005;
  auto c2d = [&] {
    auto c = test::base_case(1e-6, 1.0, {-0.02, -0.02, 0}, {0.02, 0.02, 0});
    c.dimension = 2;
    c.domain.thickness = t;
    test::add_material(c, "glass", 2500, 1e7, 0.3);
    test::add_contact(c, "glass", "glass", "hooke",
                      {{"restitution", 0.5}, {"stiffness", k}, {"cohesion_energy_density", kc}});
    return c;
  };
  {
    auto c = c2d();
    test::add_disks(c, "glass", r, {{0, 0, 0}});
    test::add_disks(c, "glass", rj, {{0, r + rj - delta, 0}});
    Simulation sim(c);
    const double a = std::sqrt(circle_area(r, rj, r + rj - delta) / pi);
    const double expected = k * delta - kc * pi * a * a;
    EXPECT_NEAR(force_on(sim, 2).y, expected, 1e-9 * k * delta);
  }
  {
    auto c = c2d();
    test::add_disks(c, "glass", r, {{0, r - delta, 0}});
    test::add_plane(c, "floor", {0, 0, 0}, {0, 1, 0}, "glass");
    Simulation sim(c);
    const double expected = k * delta - kc * pi * delta * (2 * r - delta);
    EXPECT_NEAR(force_on(sim, 1).y, expected, 1e-9 * k * delta);
  }
}

// k_c = 0 in a whole run: 60 spheres of two materials settling on a floor in a box, with a
// third material that no grain uses and that has cohesion with glass. Its pair makes every loop
// take the cohesive kernels (batched sphere pairs with gathered pair constants and rolling on,
// batched walls); the trajectories must be those of the same run without that pair, bit for bit.
TEST(Cohesion, ZeroCohesionRunIsBitIdenticalToTheKernelsWithout) {
  auto make = [](bool sticky_pair) {
    auto c = test::base_case(2e-5, 1.0, {0, 0, 0}, {0.03, 0.03, 0.06});
    c.gravity = {0, 0, -9.81};
    test::add_material(c, "glass", 2500, 1e7, 0.3);
    test::add_material(c, "sticky", 2500, 1e7, 0.3);
    test::add_contact(c, "glass", "glass", "hertz_mindlin",
                      {{"restitution", 0.5}, {"friction", 0.4}, {"cohesion_energy_density", 0.0}});
    if (sticky_pair)
      test::add_contact(c, "glass", "sticky", "hertz_mindlin",
                        {{"restitution", 0.5}, {"cohesion_energy_density", 1e5}});
    auto& f = test::add_box_fill(c, "glass", 0.0015, 0.0025, {0, 0, 0}, {0.03, 0.03, 0.05},
                                 config::Fill::Lattice::Random);
    f.count = 60;
    f.seed = 11;
    f.velocity_jitter = 0.2;
    test::add_box(c, "box", {0, 0, 0}, {0.03, 0.03, 0.06}, {"zmax"}, "glass");
    return c;
  };
  Simulation a(make(false)), b(make(true));
  for (int s = 0; s < 3000; ++s) {
    a.step();
    b.step();
  }
  const auto& pa = a.particles();
  const auto& pb = b.particles();
  ASSERT_EQ(pa.size(), pb.size());
  int n_touch = 0;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    ASSERT_EQ(std::memcmp(&pa.x()[i], &pb.x()[i], sizeof(Vec3)), 0) << i;
    ASSERT_EQ(std::memcmp(&pa.v()[i], &pb.v()[i], sizeof(Vec3)), 0) << i;
    ASSERT_EQ(std::memcmp(&pa.omega()[i], &pb.omega()[i], sizeof(Vec3)), 0) << i;
    n_touch += pa.x()[i].z < 0.01;
  }
  EXPECT_GT(n_touch, 5);  // the grains have landed and touch
  EXPECT_EQ(std::memcmp(&a.walls()[0].force, &b.walls()[0].force, sizeof(Vec3)), 0);
}
