// SPDX-License-Identifier: GPL-3.0-or-later
// The sphere-wall force loop (boundaries/wall.cpp) against an oracle written here: for every
// entry of the wall list, the contact of the sphere with the plane or cylinder from the
// definitions, the kinematics with the wall's velocity at the contact point, the law of the
// pair once. Moving walls (translation and rotation), two materials, rolling friction; forces,
// torques, histories, the walls' reactions and contact stiffness; and the AVX2 and baseline
// kernels giving the same bits. Circle walls in 2D: a disk at rest on an obstacle and in a drum.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <vector>

#include "boundaries/wall.hpp"
#include "contact/pair_forces.hpp"
#include "contact/registry.hpp"
#include "io/input/parse_case.hpp"
#include "simulation/simulation.hpp"

using namespace gf;
using contact::PairCoeffs;

namespace {

struct WallSetup {
  ParticleStore p;
  Material glass{"glass", 2500, 1e7, 0.3};
  Material steel{"steel", 7800, 2e8, 0.28};
  PairTable<PairCoeffs> pairs{2};
  std::vector<Wall> walls;
  WallContactList list;
  double t = 0.37;

  /// Spheres (radius 2-4 mm) in a cylinder of radius 0.05 m standing on a floor; the floor
  /// slides and the cylinder turns, so the wall velocity at a contact point varies.
  explicit WallSetup(const char* law, unsigned seed) {
    const Material* mats[2] = {&glass, &steel};
    for (int a = 0; a < 2; ++a)
      for (int b = a; b < 2; ++b) {
        std::map<std::string, double> prm{{"restitution", 0.5 + 0.1 * (a + b)},
                                          {"friction", 0.4 + 0.1 * (a + b)},
                                          {"rolling_friction", 0.05 * (a + b)}};
        if (std::string(law) == "hooke") {
          prm["stiffness"] = 3000.0;
          prm["tangential_stiffness_ratio"] = 2.0 / 7.0;
        }
        pairs.set(a, b, contact::prepare_pair(law, {mats[a], mats[b], 0.004}, prm));
      }
    Wall floor;
    floor.name = floor.group = "floor";
    floor.material = 1;
    floor.point0 = {0, 0, 0};
    floor.dir0 = {0, 0, 1};
    floor.motion.velocity = {0.3, -0.1, 0};
    Wall drum;
    drum.name = drum.group = "drum";
    drum.kind = WallKind::Cylinder;
    drum.material = 1;
    drum.point0 = {0, 0, 0};
    drum.dir0 = {0, 0, 1};
    drum.radius = 0.05;
    drum.inside = true;
    drum.motion.axis = {0, 0, 1};
    drum.motion.rate = 3.0;
    walls = {floor, drum};
    for (auto& w : walls) w.update_geometry(t);
    std::mt19937_64 g(seed);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 600; ++i) {
      const int m = static_cast<int>(u(g) * 2);
      const double r = 0.002 + 0.002 * u(g);
      // Half near the floor, half near the drum, some touching, some within the skin.
      const double phi = 2 * M_PI * u(g);
      const double rho = i % 2 ? 0.05 - r - 0.0015 * (u(g) - 0.7) : 0.045 * std::sqrt(u(g));
      const double z = i % 2 ? 0.02 + 0.1 * u(g) : r + 0.0015 * (u(g) - 0.7);
      const Vec3 x{rho * std::cos(phi), rho * std::sin(phi), z};
      const Vec3 v{u(g) - 0.5, u(g) - 0.5, u(g) - 0.5};
      const Vec3 w{100 * (u(g) - 0.5), 100 * (u(g) - 0.5), 100 * (u(g) - 0.5)};
      p.add_sphere(i + 1, m, r, mats[m]->density, x, v, w);
    }
    list.set_slots(1);
    list.build(walls, p.x(), p.radius(), p.size(), 0.001);
    // Histories as after a step, then new velocities.
    zero();
    compute_wall_forces(p, walls, list, pairs, t, 1e-5);
    for (std::size_t i = 0; i < p.size(); ++i) p.v()[i] = -0.6 * p.v()[i];
  }
  void zero() {
    for (std::size_t i = 0; i < p.size(); ++i) p.f()[i] = p.torque()[i] = {};
  }
};

struct Oracle {
  std::vector<Vec3> f, tq, hist;
  std::vector<Vec3> wall_force, wall_torque;
  std::vector<double> wall_k;
  std::int64_t touching = 0;
};

Oracle oracle(const WallSetup& s, double dt) {
  Oracle o;
  const std::size_t n = s.p.size();
  o.f.assign(n, {});
  o.tq.assign(n, {});
  o.wall_force.assign(s.walls.size(), {});
  o.wall_torque.assign(s.walls.size(), {});
  o.wall_k.assign(s.walls.size(), 0.0);
  const auto hist = s.list.history();
  o.hist.assign(hist.size(), {});
  const auto entries = s.list.entries();
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const int i = entries[k].particle;
    const Wall& w = s.walls[static_cast<std::size_t>(entries[k].wall)];
    const Vec3 x = s.p.x()[i];
    const double r = s.p.radius()[i];
    Vec3 nrm;
    double gap;
    if (w.kind == WallKind::Plane) {
      nrm = w.dir;
      gap = dot(x - w.point, w.dir) - r;
    } else {  // inside of an upright cylinder about the z axis
      const Vec3 radial{x.x - w.point.x, x.y - w.point.y, 0};
      nrm = -radial / norm(radial);
      gap = w.radius - norm(radial) - r;
    }
    if (gap >= 0) continue;
    ++o.touching;
    contact::ContactKinematics kin;
    kin.overlap = -gap;
    kin.normal = nrm;
    const Vec3 point = x - (r + gap / 2) * nrm;
    const Vec3 arm = point - x;
    const Vec3 v_wall =
        w.motion.velocity +
        cross(w.motion.rate * w.motion.axis, point - (w.motion.center + s.t * w.motion.velocity));
    kin.v_rel = s.p.v()[i] + cross(s.p.omega()[i], arm) - v_wall;
    kin.omega_rel = s.p.omega()[i] - w.motion.rate * w.motion.axis;
    kin.r_eff = r;
    kin.m_eff = s.p.mass()[i];
    const PairCoeffs& c = s.pairs(s.p.material()[i], w.material);
    Vec3 h = hist[k];
    const contact::ContactResult res =
        dispatch_index(contact::ContactModels{}, c.model,
                       [&]<class M>() { return M::Law::evaluate(c, kin, dt, h); });
    o.hist[k] = h;
    o.f[i] += res.force;
    o.tq[i] += cross(arm, res.force) + res.rolling_torque;
    const std::size_t wi = static_cast<std::size_t>(entries[k].wall);
    o.wall_force[wi] -= res.force;
    o.wall_torque[wi] -= cross(point - w.point, res.force) + res.rolling_torque;
    o.wall_k[wi] += 1.5 * res.normal_force / kin.overlap;
  }
  return o;
}

double max_norm(const std::vector<Vec3>& a) {
  double m = 0;
  for (const auto& v : a) m = std::max(m, norm(v));
  return m;
}

}  // namespace

class WallForcesOracle : public ::testing::TestWithParam<const char*> {};

// Same quantities, summed in another order: round-off only, 1e-10 of the largest value; a
// wrong normal, lever arm, wall velocity or history slot is an O(1) error.
TEST_P(WallForcesOracle, SpheresOnMovingPlaneAndInTurningCylinder) {
  WallSetup s(GetParam(), 11);
  const double dt = 1e-5;
  const Oracle o = oracle(s, dt);
  ASSERT_GT(o.touching, 150);
  s.zero();
  const std::int64_t touching = compute_wall_forces(s.p, s.walls, s.list, s.pairs, s.t, dt);
  EXPECT_EQ(touching, o.touching);
  const double fs = max_norm(o.f), ts = max_norm(o.tq), hs = max_norm(o.hist);
  ASSERT_GT(fs, 0);
  ASSERT_GT(hs, 0);
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    EXPECT_LE(norm(s.p.f()[i] - o.f[i]), 1e-10 * fs) << i;
    EXPECT_LE(norm(s.p.torque()[i] - o.tq[i]), 1e-10 * ts) << i;
  }
  const auto h = s.list.history();
  for (std::size_t k = 0; k < h.size(); ++k) EXPECT_LE(norm(h[k] - o.hist[k]), 1e-10 * hs) << k;
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    EXPECT_LE(norm(s.walls[w].force - o.wall_force[w]), 1e-10 * norm(o.wall_force[w])) << w;
    EXPECT_LE(norm(s.walls[w].torque - o.wall_torque[w]), 1e-10 * norm(o.wall_torque[w])) << w;
    EXPECT_NEAR(s.walls[w].contact_stiffness, o.wall_k[w], 1e-10 * o.wall_k[w]) << w;
  }
}

INSTANTIATE_TEST_SUITE_P(Laws, WallForcesOracle, ::testing::Values("hertz_mindlin", "hooke"));

TEST(WallForces, BaselineAndAvx2KernelsBitIdentical) {
  WallSetup a("hertz_mindlin", 12);
  WallSetup b("hertz_mindlin", 12);
  a.zero();
  b.zero();
  compute_wall_forces(a.p, a.walls, a.list, a.pairs, a.t, 1e-5);
  contact::use_baseline_kernels(true);
  compute_wall_forces(b.p, b.walls, b.list, b.pairs, b.t, 1e-5);
  contact::use_baseline_kernels(false);
  for (std::size_t i = 0; i < a.p.size(); ++i) {
    ASSERT_EQ(a.p.f()[i], b.p.f()[i]) << i;
    ASSERT_EQ(a.p.torque()[i], b.p.torque()[i]) << i;
  }
  for (std::size_t w = 0; w < a.walls.size(); ++w) ASSERT_EQ(a.walls[w].force, b.walls[w].force);
}

// 2D circle walls (a cylinder along z): a disk dropped onto the top of a circular obstacle
// (inside: false), and one dropped into a circular drum (inside: true; a separate run, since a
// grain outside a drum is deep inside its wall), come to rest on the vertical through the
// centre, touching the circle, and the wall then carries the disk's weight m g = rho pi r^2
// thickness g. Damped by restitution 0.2 over 0.3 s (~100 contact times): the residual bounce
// is below 1e-9 of the weight; the overlap (Hertz, ~1e-5 m) below 1e-4 m.
TEST(WallForces, DisksRestOnCircleObstacleAndInCircleDrum2D) {
  const double r = 0.002, weight = 2500 * std::numbers::pi * r * r * 0.01 * 9.81;
  for (const bool obstacle : {true, false}) {
    const Vec3 c = obstacle ? Vec3{0.05, 0.03, 0} : Vec3{0.05, 0.05, 0};
    const double want = obstacle ? 0.011 + r : 0.04 - r;  // centre distance when touching
    const auto cfg = input::load_case_text(std::string(R"(dimension: 2
time: {step: 2.0e-6, end: 0.3}
domain: {min: [0, 0], max: [0.1, 0.1], thickness: 0.01}
gravity: [0, -9.81]
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.3}
contacts:
  - {between: [glass, glass], model: hertz_mindlin, restitution: 0.2, friction: 0.5}
particles:
)") + (obstacle ? R"(  - {radius: 0.002, material: glass, positions: [[0.05, 0.0431]]}
walls:
  - {name: circle, cylinder: {center: [0.05, 0.03], radius: 0.011, inside: false},
     material: glass}
)"
                : R"(  - {radius: 0.002, material: glass, positions: [[0.05, 0.035]]}
walls:
  - {name: circle, cylinder: {center: [0.05, 0.05], radius: 0.04}, material: glass}
)"),
                                           "circle.yaml");
    Simulation sim(cfg);
    while (sim.time() < 0.3 - 1e-12) sim.step();
    const Vec3 x = sim.particles().x()[0];
    EXPECT_NEAR(x.x, c.x, 1e-9) << obstacle;
    EXPECT_NEAR(norm(x - c), want, 1e-4) << obstacle;
    const double overlap = obstacle ? want - norm(x - c) : norm(x - c) - want;
    EXPECT_GT(overlap, 0.0) << obstacle;  // in contact
    EXPECT_EQ(x.y > c.y, obstacle);       // on top of the obstacle, at the drum's bottom
    const auto& w = sim.walls()[0];
    EXPECT_NEAR(w.force.y, -weight, 1e-9 * weight) << obstacle;
    EXPECT_NEAR(w.force.x, 0.0, 1e-9 * weight) << obstacle;
  }
}
