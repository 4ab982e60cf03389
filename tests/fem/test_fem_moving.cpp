// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of bodies moving through the fluid_fem flow: free rigid bodies solved monolithically,
// ALE mesh motion and remeshing (coupling/fem_dem), against Faxen's wall-corrected Stokes drag.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "core/error.hpp"
#include "coupling/fem_dem/moving_bodies.hpp"
#include "fluid/fem/navier_stokes.hpp"
#include "moving_cases.hpp"

using namespace gf::fem;
using gf::fem_bench::drag_in_body_frame;
using gf::fem_bench::faxen_resistance;
using gf::fem_bench::settle_on_floor;
using gf::fem_bench::vertical_channel;
using gf::fem_dem::MeshMotion;
using gf::fem_dem::MovingBodyFlow;
using gf::fem_dem::MovingBodyOptions;
using gf::fem_dem::RigidPose;

// The solver's steady Stokes drag of a disk translating between walls is Faxen's: k = 0.2 and
// 0.3, Re = U 2a / nu = 2e-4 (inertia changes the drag by O(Re), far below 1e-3). The mesh
// (h_body = a / 10, P2-P1, reaction forces) resolves the drag to better than 1e-3 (the
// Schaefer-Turek 2D-1 drag is within 1e-4 on comparable meshes); the channel's ends at 5 l from
// the disk leave an error of exp(-4.2 * 5) ~ 1e-9 (slowest Stokes eigenmode of a channel).
TEST(FemMoving, PrescribedTranslationMatchesFaxenDrag) {
  for (const double k : {0.2, 0.3}) {
    const double l = 0.5, a = k * l, u = 1e-4;
    FlowProblem pb = vertical_channel(l, 10 * l, a, 0.0, a / 10, 0.1);
    pb.body_motion = {BodyMotion{{0, -u}, 0.0}};
    NavierStokes ns(std::move(pb));
    ASSERT_TRUE(ns.solve_steady({}).converged);
    const auto f = ns.reaction_forces()[0];
    const double expect = faxen_resistance(k) * 1.0 * u;  // mu = rho nu = 1
    std::printf("k = %.1f: F / F_Faxen = %.6f (stress integration %.6f)\n", k, f.force.y / expect,
                ns.stress_forces()[0].force.y / expect);
    EXPECT_NEAR(f.force.y / expect, 1.0, 1e-3);
    // sideways: zero by symmetry, up to the unstructured mesh's asymmetry (~ the drag's error)
    EXPECT_LT(std::abs(f.force.x), 1e-4 * expect);
  }
}

// A free body held by nothing in a fluid at rest, as dense as the fluid, stays at rest; its mass
// and moment of inertia are those of the disk.
TEST(FemMoving, NeutrallyBuoyantBodyStaysAtRest) {
  FlowProblem pb = vertical_channel(0.5, 3.0, 0.1, 0.0, 0.02, 0.1);
  pb.body_density = {1.0};
  pb.gravity = {0, -9.81};
  MovingBodyFlow run(std::move(pb));
  const NavierStokes& ns = run.flow();
  EXPECT_NEAR(ns.body_mass(0), std::numbers::pi * 0.01, 1e-12);
  EXPECT_NEAR(ns.body_inertia(0), 0.5 * std::numbers::pi * 0.01 * 0.01, 1e-12);
  NewtonOptions opt;
  opt.reuse_factorization = true;
  for (int s = 0; s < 5; ++s) run.step(0.01, 2, opt);
  const auto v = run.flow().body_velocity(0);
  EXPECT_LT(std::hypot(v.velocity.x, v.velocity.y), 1e-12);
  EXPECT_LT(std::abs(v.angular_velocity), 1e-12);
}

// A polygon body's centre becomes its centroid, with the polygon's area and polar moment.
TEST(FemMoving, FreePolygonMassProperties) {
  FlowProblem pb = vertical_channel(0.5, 3.0, 0.1, 0.0, 0.02, 0.1);
  BodyShape sq;
  sq.kind = BodyShape::Kind::Polygon;
  sq.centre = {0.3, 0.3};  // not the centroid: replaced by it
  sq.vertices = {{-0.1, 0.2}, {0.1, 0.2}, {0.1, 0.4}, {-0.1, 0.4}};
  pb.spec.bodies = {sq};
  pb.mesh = build_mesh(pb.spec);
  pb.body_density = {2.0};
  NavierStokes ns(std::move(pb));
  EXPECT_NEAR(ns.problem().spec.bodies[0].centre.x, 0.0, 1e-14);
  EXPECT_NEAR(ns.problem().spec.bodies[0].centre.y, 0.3, 1e-14);
  EXPECT_NEAR(ns.body_mass(0), 2.0 * 0.04, 1e-14);
  EXPECT_NEAR(ns.body_inertia(0), 2.0 * 0.04 * (0.04 + 0.04) / 12, 1e-15);
}

// Harmonic mesh motion: weights are 1 on the body, 0 on the outline, in [0, 1] inside; moving the
// body moves its nodes rigidly and keeps the outline.
TEST(FemMoving, MeshMotionMovesBodyNodesRigidly) {
  const FlowProblem pb = vertical_channel(0.5, 3.0, 0.1, 0.0, 0.02, 0.1);
  const Mesh& m = pb.mesh;
  const MeshMotion motion(m, 1);
  for (int k = 0; k < m.n_nodes(); ++k) {
    EXPECT_GE(motion.weight(0, k), -1e-12);
    EXPECT_LE(motion.weight(0, k), 1 + 1e-12);
  }
  const std::vector<RigidPose> ref = {{{0, 0}, 0}}, now = {{{0.02, -0.05}, 0.3}};
  const auto x = motion.nodes(ref, now);
  for (const auto& e : m.boundary)
    for (int v : {e.a, e.b, e.mid}) {
      const Vec2 p = m.nodes[v];
      if (e.body == 0) {
        const double c = std::cos(0.3), s = std::sin(0.3);
        EXPECT_NEAR(x[v].x, 0.02 + c * p.x - s * p.y, 1e-14);
        EXPECT_NEAR(x[v].y, -0.05 + s * p.x + c * p.y, 1e-14);
      } else {
        EXPECT_EQ(x[v].x, p.x);
        EXPECT_EQ(x[v].y, p.y);
      }
    }
}

namespace {

struct Settling {
  double velocity = 0;  ///< settling speed at the end [m/s]
  double drift = 0;     ///< |x| of the centre at the end [m]
  double travel = 0;    ///< distance fallen [m]
  int remeshes = 0;
};

/// The run of gf::fem_bench::stokes_settling to t_end with the step dt.
Settling settle(double t_end, double dt, const MovingBodyOptions& options, double h_body) {
  MovingBodyFlow run = gf::fem_bench::stokes_settling(options, h_body);
  gf::fem_bench::run_steps(run, dt, t_end);
  Settling r;
  r.velocity = -run.flow().body_velocity(0).velocity.y;
  r.drift = std::abs(run.poses()[0].centre.x);
  r.travel = 0.5 - run.poses()[0].centre.y;
  r.remeshes = run.remeshes();
  return r;
}

}  // namespace

// Terminal settling speed of a free disk between walls: the buoyant weight (rho_s - rho_f) g pi
// a^2 balances Faxen's drag, U_t = 1.5708 / 16.532 = 0.09502 m/s at k = 0.2 (Re = 0.019: the
// Oseen correction of a confined cylinder is O(Re k) ~ 0.4 %, hence the 1 % bound). The
// approach to U_t is exponential with the time (m + m_added) / (F/U) ~ 5 ms plus the channel's
// viscous diffusion l^2 / nu = 0.25 s: after 1 s the speed is within 1e-3 of U_t. The disk falls
// about one radius on the moving mesh; by symmetry it must not drift sideways.
TEST(FemMoving, FreeDiskSettlesAtFaxenTerminalVelocity) {
  const double ut = 0.5 * 100 * std::numbers::pi * 0.01 / faxen_resistance(0.2);
  const Settling s = settle(1.0, 0.01, {}, 0.02);
  std::printf("U = %.6f, U_t = %.6f (ratio %.5f), fell %.4f m, drift %.2e m, %d remeshes\n",
              s.velocity, ut, s.velocity / ut, s.travel, s.drift, s.remeshes);
  EXPECT_NEAR(s.velocity / ut, 1.0, 1e-2);
  EXPECT_GT(s.travel, 0.08);
  EXPECT_LT(s.drift, 1e-3 * s.travel);
}

// Remeshing on the way does not change the settling: with a quality bound that forces a fresh
// mesh every few steps, the speed after 0.5 s matches the run without remeshing to 0.2 % (the
// interpolation of the velocity onto each new mesh is P2-accurate and the step after a remesh is
// BDF1, whose error at this step is below that).
TEST(FemMoving, RemeshingKeepsTheSettlingSpeed) {
  const Settling plain = settle(0.5, 0.01, {}, 0.02);
  MovingBodyOptions often;
  often.remesh_ratio = 0.97;
  const Settling remeshed = settle(0.5, 0.01, often, 0.02);
  std::printf("remeshed %d times: U = %.6f against %.6f\n", remeshed.remeshes, remeshed.velocity,
              plain.velocity);
  EXPECT_GE(remeshed.remeshes, 5);
  EXPECT_NEAR(remeshed.velocity / plain.velocity, 1.0, 2e-3);
}

namespace {

/// Largest nodal velocity error [m/s] against plane Poiseuille flow (u_max 1, height 0.2) after
/// integrating to t = 0.2 s with BDF2 and step dt while the interior vertices oscillate
/// vertically, d = A sin(2 pi t / 0.2) sin(pi x) sin(pi y / 0.2), A = 0.02 (mesh speed up to
/// 0.63 m/s); midpoint nodes stay midpoints (straight cells, which carry the exact solution).
double poiseuille_on_moving_mesh(double dt) {
  FlowProblem pb;
  const double len = 1.0, height = 0.2;
  pb.spec.outline = {{0, 0}, {len, 0}, {len, height}, {0, height}};
  pb.spec.h_max = pb.spec.h_body = 0.05;
  pb.mesh = build_mesh(pb.spec);
  pb.viscosity = 0.01;
  OutlineBc wall, out, in;
  out.kind = OutlineBcKind::Outflow;
  in.kind = OutlineBcKind::Inflow;
  in.u_max = 1.0;
  pb.outline_bc = {wall, out, wall, in};
  const Mesh ref = pb.mesh;
  NavierStokes ns(std::move(pb));
  NewtonOptions opt;
  opt.tolerance = 1e-13;
  EXPECT_TRUE(ns.solve_steady(opt).converged);
  const int n = static_cast<int>(std::lround(0.2 / dt));
  for (int s = 1; s <= n; ++s) {
    const double t = s * dt;
    std::vector<Vec2> x = ref.nodes;
    for (int v = 0; v < ref.n_vertices; ++v)
      x[v].y += 0.02 * std::sin(2 * std::numbers::pi * t / 0.2) *
                std::sin(std::numbers::pi * ref.nodes[v].x / len) *
                std::sin(std::numbers::pi * ref.nodes[v].y / height);
    for (const auto& c : ref.cells)
      for (int e = 0; e < 3; ++e) {
        const Vec2 a = x[c[e]], b = x[c[(e + 1) % 3]];
        x[c[3 + e]] = {0.5 * (a.x + b.x), 0.5 * (a.y + b.y)};
      }
    ns.move_mesh(x, {});
    EXPECT_TRUE(ns.try_step(dt, 2, opt, 1, 1).newton.converged);
    ns.accept_step();
  }
  double err = 0;
  for (int k = 0; k < ns.mesh().n_nodes(); ++k) {
    const double y = ns.mesh().nodes[k].y;
    const Vec2 u = ns.velocity(k);
    err = std::max({err, std::abs(u.x - 4 * y * (height - y) / (height * height)), std::abs(u.y)});
  }
  return err;
}

}  // namespace

// ALE form: a steady flow stays steady under mesh motion. The nodal values follow the moving
// nodes, so the BDF derivative of a node's value must be cancelled by the mesh-velocity term of
// the convection, up to the BDF error: the error is second order in dt (a wrong sign or a missing
// term would leave an O(1) error: the mesh speed is 0.63 m/s against a flow of 1 m/s).
TEST(FemMoving, AleKeepsPoiseuilleFlowOnAnOscillatingMesh) {
  const double e1 = poiseuille_on_moving_mesh(0.01), e2 = poiseuille_on_moving_mesh(0.005);
  std::printf("max velocity error: %.3e (dt = 0.01), %.3e (dt = 0.005), ratio %.2f\n", e1, e2,
              e1 / e2);
  EXPECT_LT(e1, 2e-3);
  EXPECT_GT(e1 / e2, 3.0);
}

// Spin-down of a free disk (radius r1 = 0.1, 1e4 times denser than the fluid) inside a fixed
// circular wall (r2 = 0.3), on a fixed mesh (a circle's geometry does not change as it turns):
// the fluid is a quasi-steady Couette flow whose torque -4 pi mu omega r1^2 r2^2 / (r2^2 - r1^2)
// decays omega exponentially at the rate lambda = 4 pi mu r1^2 r2^2 / ((r2^2 - r1^2) I). The
// fluid's own angular momentum is < 1e-3 of the disk's (density ratio 1e4) and the start-up
// transient lasts r2^2 / nu = 0.9 s of the 40 s, so the decay rate matches to 0.5 %.
TEST(FemMoving, FreeDiskSpinsDownAtTheCouetteRate) {
  const double r1 = 0.1, r2 = 0.3, nu = 0.1, rho_s = 1e4;
  FlowProblem pb = gf::fem_bench::annulus(r1, r2, 0.02, 0.04, nu);
  pb.body_motion = {BodyMotion{{0, 0}, 1.0}};
  pb.body_density = {rho_s};
  NavierStokes ns(std::move(pb));
  const double inertia = rho_s * 0.5 * std::numbers::pi * std::pow(r1, 4);
  EXPECT_NEAR(ns.body_inertia(0), inertia, 1e-12 * inertia);
  const double lambda =
      4 * std::numbers::pi * nu * r1 * r1 * r2 * r2 / ((r2 * r2 - r1 * r1) * inertia);
  NewtonOptions opt;
  opt.reuse_factorization = true;
  const double dt = 0.25, t_end = 40.0;
  for (int s = 0; s < static_cast<int>(t_end / dt); ++s) {
    const auto r = ns.try_step(dt, 2, opt, 1, 1);
    ASSERT_TRUE(r.newton.converged) << "step " << s << ": " << r.newton.iterations
                                    << " iterations, last update " << r.newton.last_update;
    ns.accept_step();
  }
  const double omega = ns.body_velocity(0).angular_velocity;
  const double rate = -std::log(omega) / t_end;
  std::printf("omega(40 s) = %.6f: decay rate %.6f 1/s against %.6f (ratio %.5f)\n", omega, rate,
              lambda, rate / lambda);
  EXPECT_NEAR(rate / lambda, 1.0, 5e-3);
  // the reported torque is the fluid's on the spinning body: I domega/dt = -lambda I omega (the
  // Laplace form's correction uses the current spin, not the initial one)
  const double torque = ns.reaction_forces()[0].torque;
  EXPECT_NEAR(torque / (-lambda * inertia * omega), 1.0, 1e-2);
  const auto v = ns.body_velocity(0).velocity;
  EXPECT_LT(std::hypot(v.x, v.y), 1e-6 * omega * r1);
}

// Repulsion law: zero beyond the range, F_0 ((rho - g) / rho)^2 inside it, along the line of
// closest approach, equal and opposite between two bodies; a polygon's face parallel to a wall
// is pushed at both corners (no torque).
TEST(FemMoving, CollisionLoadsFollowTheRepulsionLaw) {
  using gf::fem_dem::collision_loads;
  using gf::fem_dem::CollisionModel;
  MeshSpec spec;
  spec.outline = {{-1, 0}, {1, 0}, {1, 2}, {-1, 2}};
  BodyShape a, b;
  a.radius = b.radius = 0.1;
  a.centre = {0, 1};
  b.centre = {0.25, 1};  // gap 0.05
  spec.bodies = {a, b};
  const CollisionModel model{0.1, 2.0};
  auto loads = collision_loads(spec, model);
  const double f = 2.0 * 0.25;  // ((0.1 - 0.05) / 0.1)^2 = 0.25
  EXPECT_NEAR(loads[0].force.x, -f, 1e-14);
  EXPECT_NEAR(loads[1].force.x, f, 1e-14);
  EXPECT_NEAR(loads[0].force.y, 0, 1e-14);
  EXPECT_NEAR(loads[0].torque, 0, 1e-14);
  EXPECT_NEAR(gf::fem_dem::narrowest_gap(spec).g, 0.05, 1e-15);
  EXPECT_EQ(gf::fem_dem::narrowest_gap(spec).other, 1);
  EXPECT_EQ(gf::fem_dem::narrowest_gap(spec).edge, -1);
  spec.bodies[1].centre = {0.31, 1};  // gap 0.11 > range
  loads = collision_loads(spec, model);
  EXPECT_EQ(loads[0].force.x, 0);
  // a disk 0.02 above the floor: pushed up by F_0 (0.08 / 0.1)^2
  spec.bodies = {a};
  spec.bodies[0].centre = {0, 0.12};
  loads = collision_loads(spec, model);
  EXPECT_NEAR(loads[0].force.y, 2.0 * 0.64, 1e-13);
  // a square 0.05 above the floor, face parallel: two corners, no torque
  BodyShape sq;
  sq.kind = BodyShape::Kind::Polygon;
  sq.vertices = {{-0.1, 0.05}, {0.1, 0.05}, {0.1, 0.25}, {-0.1, 0.25}};
  sq.centre = {0, 0.15};
  spec.bodies = {sq};
  loads = collision_loads(spec, model);
  EXPECT_NEAR(loads[0].force.y, 2 * 2.0 * 0.25, 1e-13);
  EXPECT_NEAR(loads[0].torque, 0, 1e-14);
  EXPECT_NEAR(gf::fem_dem::smallest_gap(spec), 0.05, 1e-15);
  const auto narrow = gf::fem_dem::narrowest_gap(spec);  // a lower corner on the floor (edge 0)
  EXPECT_EQ(narrow.body, 0);
  EXPECT_EQ(narrow.other, -1);
  EXPECT_EQ(narrow.edge, 0);
  // with a core g_c = 0.04 the force at g = 0.02 is the law's times g_c / g, and deep in the
  // core (and in an overlap) times 100 at most
  spec.bodies = {a};
  spec.bodies[0].centre = {0, 0.12};
  CollisionModel cored = model;
  cored.core = 0.04;
  EXPECT_NEAR(collision_loads(spec, cored)[0].force.y, 2.0 * 0.64 * 2.0, 1e-13);
  spec.bodies[0].centre = {0, 0.1 + 1e-5};
  EXPECT_NEAR(collision_loads(spec, cored)[0].force.y, 2.0 * 0.9999 * 0.9999 * 100, 1e-11);
  spec.bodies[0].centre = {0, 0.15};  // outside the core: the law as it was
  EXPECT_NEAR(collision_loads(spec, cored)[0].force.y, 2.0 * 0.25, 1e-13);
  EXPECT_NEAR(gf::fem_dem::repulsion_scale(cored, 0.05), 0.25, 1e-15);
  EXPECT_NEAR(gf::fem_dem::repulsion_scale(cored, 0.02), 0.64 * 2.0, 1e-15);
  EXPECT_EQ(gf::fem_dem::repulsion_scale(cored, 0.1), 0.0);
  // a disk in a corner is pushed by both walls
  spec.bodies = {a};
  spec.bodies[0].centre = {-0.88, 0.12};  // 0.02 from the side wall and from the floor
  loads = collision_loads(spec, model);
  EXPECT_NEAR(loads[0].force.x, 2.0 * 0.64, 1e-13);
  EXPECT_NEAR(loads[0].force.y, 2.0 * 0.64, 1e-13);
  // an overlap (negative gap) pushes the bodies apart, harder than contact
  spec.bodies = {a, b};
  spec.bodies[1].centre = {0.15, 1};  // overlap 0.05
  loads = collision_loads(spec, model);
  EXPECT_NEAR(loads[1].force.x, 2.0 * 1.5 * 1.5, 1e-13);
  EXPECT_LT(gf::fem_dem::narrowest_gap(spec).g, 0.0);
  // ... and with a core, 100 x that at most
  EXPECT_NEAR(collision_loads(spec, cored)[1].force.x, 2.0 * 1.5 * 1.5 * 100, 1e-11);
  // two squares meeting corner to corner: one force in all, not one per probe
  BodyShape s1 = sq, s2 = sq;
  s1.vertices = {{0, 0.5}, {0.2, 0.5}, {0.2, 0.7}, {0, 0.7}};
  s1.centre = {0.1, 0.6};
  s2.vertices = {{0.25, 0.75}, {0.45, 0.75}, {0.45, 0.95}, {0.25, 0.95}};
  s2.centre = {0.35, 0.85};
  spec.bodies = {s1, s2};
  loads = collision_loads(spec, model);
  const double g = std::hypot(0.05, 0.05);
  const double f1 = 2.0 * std::pow((0.1 - g) / 0.1, 2);
  EXPECT_NEAR(std::hypot(loads[1].force.x, loads[1].force.y), f1, 1e-13);
}

// Friction on the repulsion's gaps (Cundall-Strack spring capped by Coulomb): a square sliding
// along the floor loads the spring of each of its two corners by v dt per step until the force
// reaches mu F_n, then slides at the cap; reversing the motion unloads the spring from the cap
// (no jump); a disk rolling without slipping (v = -omega r) loads nothing, one spinning in place
// is braked by the spring of its contact point; between two bodies the forces are equal and
// opposite; a gap that opens past the range forgets its spring.
TEST(FemMoving, CollisionFrictionSticksThenSlidesAtTheCoulombLimit) {
  using gf::fem_dem::collision_loads;
  using gf::fem_dem::CollisionModel;
  using gf::fem_dem::ContactHistory;
  MeshSpec spec;
  spec.outline = {{-1, 0}, {1, 0}, {1, 2}, {-1, 2}};
  BodyShape sq;
  sq.kind = BodyShape::Kind::Polygon;
  sq.vertices = {{-0.1, 0.05}, {0.1, 0.05}, {0.1, 0.25}, {-0.1, 0.25}};
  sq.centre = {0, 0.15};
  spec.bodies = {sq};
  const double mu = 0.5, k_t = 40.0, dt = 0.01;
  const CollisionModel model{0.1, 2.0, mu, k_t};
  const double f_n = 2.0 * 0.25;  // per corner, gap 0.05 of 0.1
  ContactHistory h;
  std::vector<BodyMotion> v(1);
  v[0].velocity = {0.1, 0};
  for (int step = 1; step <= 12; ++step) {
    const auto l = collision_loads(spec, model, v, dt, h);
    const double spring = k_t * 0.1 * dt * step;  // per corner
    EXPECT_NEAR(l[0].force.x, -2 * std::min(spring, mu * f_n), 1e-13) << "step " << step;
    EXPECT_NEAR(l[0].force.y, 2 * f_n, 1e-13);
    // the friction acts 0.125 below the centre (mid-gap): it tips the square forwards
    EXPECT_NEAR(l[0].torque, 0.125 * l[0].force.x, 1e-13);
  }
  EXPECT_EQ(h.size(), 2u);  // two corners on the floor (side walls out of range)
  // stretch along the floor's tangent t = (-n_y, n_x) = (-1, 0): negative for motion along +x
  EXPECT_NEAR(h.stretch(0, 0, -1, 0), -mu * f_n / k_t, 1e-15);
  v[0].velocity = {-0.1, 0};  // back: the spring unloads from the cap
  auto l = collision_loads(spec, model, v, dt, h);
  EXPECT_NEAR(l[0].force.x, -2 * (mu * f_n - k_t * 0.1 * dt), 1e-13);
  // the gap opens past the range: the springs are forgotten
  MeshSpec far = spec;
  for (auto& p : far.bodies[0].vertices) p.y += 0.1;
  far.bodies[0].centre.y += 0.1;
  l = collision_loads(far, model, v, dt, h);
  EXPECT_EQ(h.size(), 0u);
  EXPECT_EQ(l[0].force.x, 0);
  // disks on the floor at gap 0.05: rolling without slipping loads no spring; spinning does
  BodyShape disk;
  disk.radius = 0.1;
  disk.centre = {0, 0.15};
  spec.bodies = {disk};
  v[0].velocity = {0.2, 0};
  v[0].angular_velocity = -0.2 / 0.125;  // the contact point sits mid-gap, 0.125 below
  l = collision_loads(spec, model, v, dt, h);
  EXPECT_NEAR(l[0].force.x, 0, 1e-15);
  v[0].velocity = {0, 0};
  v[0].angular_velocity = 1.0;  // the contact point moves at +0.125 in x
  l = collision_loads(spec, model, v, dt, h);
  EXPECT_NEAR(l[0].force.x, -k_t * 0.125 * dt, 1e-13);
  EXPECT_NEAR(l[0].torque, -0.125 * k_t * 0.125 * dt, 1e-13);  // braking the spin
  // two disks side by side (gap 0.05), one sliding up past the other: opposite forces
  BodyShape a = disk, b = disk;
  a.centre = {0, 1};
  b.centre = {0.25, 1};
  spec.bodies = {a, b};
  ContactHistory h2;
  std::vector<BodyMotion> v2(2);
  v2[0].velocity = {0, 0.1};
  l = collision_loads(spec, model, v2, dt, h2);
  EXPECT_NEAR(l[0].force.y, -k_t * 0.1 * dt, 1e-13);
  EXPECT_NEAR(l[1].force.y, k_t * 0.1 * dt, 1e-13);
  EXPECT_NEAR(l[0].force.x, -f_n, 1e-13);
  // two squares stacked (gap 0.05): aligned, the four corners pair up and carry half each;
  // shifted sideways, each upper-left / lower-right corner faces the other's edge and the
  // corner-to-corner duplicates carry nothing: the same two forces, no jump
  for (const double dx : {0.0, 1e-12, 0.05}) {
    BodyShape lo = sq, hi = sq;
    lo.vertices = {{0, 0.5}, {0.2, 0.5}, {0.2, 0.7}, {0, 0.7}};
    lo.centre = {0.1, 0.6};
    hi.vertices = {{dx, 0.75}, {0.2 + dx, 0.75}, {0.2 + dx, 0.95}, {dx, 0.95}};
    hi.centre = {0.1 + dx, 0.85};
    spec.bodies = {lo, hi};
    ContactHistory h3;
    std::vector<BodyMotion> v3(2);
    v3[1].velocity = {0.1, 0};
    l = collision_loads(spec, model, v3, dt, h3);
    EXPECT_NEAR(l[1].force.y, 2 * f_n, 1e-13) << "dx = " << dx;
    EXPECT_NEAR(l[1].force.x, -2 * k_t * 0.1 * dt, 1e-13) << "dx = " << dx;
    EXPECT_NEAR(l[0].force.x, -l[1].force.x, 1e-15);
  }
  // without friction the history-taking overload is the plain repulsion
  const auto plain = collision_loads(spec, CollisionModel{0.1, 2.0});
  const auto none = collision_loads(spec, CollisionModel{0.1, 2.0}, v2, dt, h2);
  for (int j = 0; j < 2; ++j) {
    EXPECT_EQ(plain[j].force.x, none[j].force.x);
    EXPECT_EQ(plain[j].force.y, none[j].force.y);
    EXPECT_EQ(plain[j].torque, none[j].torque);
  }
}

// Rolling resistance (CollisionModel::rolling_friction): a disk on the floor at gap 0.05, turning
// in place, loads its rotational spring k_r = k_t R^2 by omega dt per step (R = 0.125, the lever
// from the centre to mid-gap) up to the cap mu_r R F_n, and the torque opposes the turning; a disk
// rolling without slip on the floor gets the same torque (the rotation is relative to the floor),
// a second disk turning with it (same omega) none between them; the springs unload on reversal.
TEST(FemMoving, RollingResistanceLoadsToItsCapAndOpposesTheTurn) {
  using gf::fem_dem::collision_loads;
  using gf::fem_dem::CollisionModel;
  using gf::fem_dem::ContactHistory;
  MeshSpec spec;
  spec.outline = {{-1, 0}, {1, 0}, {1, 2}, {-1, 2}};
  BodyShape disk;
  disk.radius = 0.1;
  disk.centre = {0, 0.15};
  spec.bodies = {disk};
  const double mu = 0.5, mu_r = 0.1, k_t = 40.0, dt = 0.01, omega = 0.2;
  CollisionModel model{0.1, 2.0, mu, k_t};
  model.rolling_friction = mu_r;
  const double f_n = 2.0 * 0.25, r = 0.125;
  ContactHistory h;
  std::vector<BodyMotion> v(1);
  v[0].angular_velocity = omega;  // turning in place: the friction springs load too
  for (int step = 1; step <= 8; ++step) {
    const auto l = collision_loads(spec, model, v, dt, h);
    const double roll = std::min(k_t * r * r * omega * dt * step, mu_r * r * f_n);
    const double slide = std::min(k_t * omega * r * dt * step, mu * f_n);  // mid-gap speed omega r
    EXPECT_NEAR(l[0].torque, -roll - r * slide, 1e-13) << "step " << step;
    EXPECT_NEAR(h.rolled(0, 0, -1, 0), std::min(omega * dt * step, mu_r * f_n / (k_t * r)), 1e-15);
  }
  v[0].angular_velocity = -omega;  // reversal: unloads from the cap
  collision_loads(spec, model, v, dt, h);
  EXPECT_NEAR(h.rolled(0, 0, -1, 0), mu_r * f_n / (k_t * r) - omega * dt, 1e-15);
  // rolling without slip (v = -omega r at mid-gap cancels): no sliding spring, the rolling one
  ContactHistory rolling;
  v[0].angular_velocity = omega;
  v[0].velocity = {-omega * r, 0};
  const auto l = collision_loads(spec, model, v, dt, rolling);
  EXPECT_NEAR(l[0].force.x, 0.0, 1e-13);
  EXPECT_NEAR(l[0].torque, -k_t * r * r * omega * dt, 1e-13);
  // two disks side by side turning together: no rolling between them (only their floors')
  BodyShape other = disk;
  other.centre = {0.25, 0.15};
  spec.bodies = {disk, other};
  ContactHistory pair;
  std::vector<BodyMotion> w(2);
  w[0].angular_velocity = w[1].angular_velocity = omega;
  collision_loads(spec, model, w, dt, pair);
  EXPECT_EQ(pair.rolled(0, 0, 1, 0), 0.0);
  EXPECT_NEAR(pair.rolled(0, 0, -1, 0), omega * dt, 1e-15);
  // without rolling_friction nothing rolls
  model.rolling_friction = 0;
  ContactHistory none;
  collision_loads(spec, model, w, dt, none);
  EXPECT_EQ(none.rolled(0, 0, -1, 0), 0.0);
}

// A mesh motion that inverts a cell is refused (gf::Error) and leaves the mesh and the bodies
// where they were, so the caller can retry with a shorter step.
TEST(FemMoving, MoveMeshThatInvertsACellLeavesTheMeshWhereItWas) {
  NavierStokes ns(vertical_channel(0.5, 2.0, 0.1, 0.0, 0.05, 0.2));
  const std::vector<Vec2> before = ns.mesh().nodes;
  std::vector<Vec2> x = before;
  const auto& c = ns.mesh().cells[0];
  x[c[0]] = {2 * x[c[1]].x - x[c[0]].x + 3 * (x[c[2]].x - x[c[1]].x),  // far across its edge
             2 * x[c[1]].y - x[c[0]].y + 3 * (x[c[2]].y - x[c[1]].y)};
  EXPECT_THROW(ns.move_mesh(x, {{0.0, 0.3}}), gf::Error);
  EXPECT_EQ(ns.mesh().nodes.size(), before.size());
  for (std::size_t k = 0; k < before.size(); ++k) {
    EXPECT_EQ(ns.mesh().nodes[k].x, before[k].x);
    EXPECT_EQ(ns.mesh().nodes[k].y, before[k].y);
  }
  EXPECT_EQ(ns.problem().spec.bodies[0].centre.y, 0.0);
  ns.move_mesh(before, {{0.0, 0.0}});  // the mesh where it is: accepted
}

// External loads given to the moving flow last over steps and remeshes: a disk (density 1.5)
// held by a load equal to its buoyant weight stays at rest.
TEST(FemMoving, ExternalLoadOutlastsARemesh) {
  MovingBodyFlow run = gf::fem_bench::stokes_settling({}, 0.02);
  const double weight = 0.5 * 100 * std::numbers::pi * 0.01;
  run.set_external_load(0, {0, weight}, 0.0);
  NewtonOptions opt;
  opt.reuse_factorization = true;
  for (int s = 0; s < 4; ++s) {
    run.step(0.01, 2, opt);
    if (s == 1) run.remesh();
  }
  EXPECT_EQ(run.remeshes(), 1);
  EXPECT_LT(std::abs(run.flow().body_velocity(0).velocity.y), 1e-9);
}

// A film pressed by nearly the most the repulsion can push thins far below the mesh size: the run
// warns when it falls below 5 % of the range and again each time it halves, naming the film
// (here the disk and the floor, outline edge 0). A disk 4 mm above the floor (range 0.03 m,
// F_0 = 4 W) carries W + 2.96 W: the balance F_0 s^2 = 3.96 W lies at a gap of 0.5 % of the range
// (1.5e-4 m), so the film passes 1.5e-3 and 7.5e-4 m on its way (in ~1 s at nu = 0.005).
namespace {

/// Buoyant weight W [N/m] of the disk of disk_above_floor.
const double kDiskWeight = (2.0 - 1.0) * 10 * std::numbers::pi * 0.01;

/// The disk of floor_box (radius 0.1, density 2; nu = 0.005, g = 10) 4 mm above the floor, with a
/// repulsion of range 0.03 m, F_0 = 4 W and the given core, named 'disk'.
MovingBodyFlow disk_above_floor(double core) {
  BodyShape disk;
  disk.radius = 0.1;
  disk.centre = {0, 0.104};
  MovingBodyOptions opt;
  opt.collision = {0.03, 4 * kDiskWeight};
  opt.collision.core = core;
  opt.body_names = {"disk"};
  return MovingBodyFlow(gf::fem_bench::floor_box(disk, 0.005, {0, -10}, {}), opt);
}

}  // namespace

TEST(FemMoving, ThinningFilmIsReportedWithItsBodies) {
  MovingBodyFlow run = disk_above_floor(0.0);
  const double w = kDiskWeight;
  EXPECT_TRUE(std::isinf(run.narrowest_gap().g));  // (before the first step)
  run.set_external_load(0, {0, -2.96 * w}, 0.0);
  NewtonOptions newton;
  newton.reuse_factorization = true;
  double first = 0, before_first = 0, before = 0;
  testing::internal::CaptureStderr();  // (the log goes to one of them, as set up or by default)
  testing::internal::CaptureStdout();
  for (int s = 0; s < 400 && run.gap_warnings() < 2; ++s) {
    before = run.narrowest_gap().g;  // (the film before this step)
    run.step(0.01, 2, newton);
    if (run.gap_warnings() == 1 && first == 0) {
      first = run.narrowest_gap().g;
      before_first = before;
    }
  }
  const std::string said =
      testing::internal::GetCapturedStdout() + testing::internal::GetCapturedStderr();
  std::printf("film %.3g m after %.2f s, %d warnings (first at %.3g m, %.3g m the step before)\n",
              run.narrowest_gap().g, run.time(), run.gap_warnings(), first, before_first);
  EXPECT_EQ(run.gap_warnings(), 2);
  EXPECT_GE(before_first, 0.05 * 0.03);  // warned at the step that crossed 5 % of the range
  EXPECT_LT(first, 0.05 * 0.03);
  EXPECT_GE(before, 0.5 * first);  // ... and again at the one that halved it
  EXPECT_LT(run.narrowest_gap().g, 0.5 * first);
  EXPECT_NE(said.find("between 'disk' and the outline's edge 0"), std::string::npos) << said;
  EXPECT_GT(run.narrowest_gap().g, 0.0);
  EXPECT_EQ(run.narrowest_gap().body, 0);
  EXPECT_EQ(run.narrowest_gap().other, -1);
  EXPECT_EQ(run.narrowest_gap().edge, 0);
}

// The core keeps a film open under a load beyond the force scale: a disk pressed onto the floor
// with 2 F_0 (its buoyant weight W plus 7 W; range 0.03 m, F_0 = 4 W, core 0.003 m) comes to rest
// where F_0 ((rho - g) / rho)^2 g_c / g = 2 F_0 (g = 1.37e-3 m; without the core the film would
// close). The rest gap within 1 %: the fluid carries no load at rest, the contact force is exact
// (CollisionLoadsFollowTheRepulsionLaw), and after 2 s the disk still approaches at < 1e-5 m/s.
TEST(ValidationFemMoving, CoreHoldsAFilmLoadedBeyondTheForceScale) {
  MovingBodyFlow run = disk_above_floor(0.003);
  const double w = kDiskWeight;
  run.set_external_load(0, {0, -7 * w}, 0.0);
  gf::fem_bench::run_steps(run, 0.01, 2.0);
  double lo = 1e-6, hi = 0.003;  // F_0 s^2 g_c / g = 2 F_0, decreasing in g
  for (int i = 0; i < 100; ++i) {
    const double g = 0.5 * (lo + hi), s = (0.03 - g) / 0.03;
    (s * s * 0.003 / g > 2 ? lo : hi) = g;
  }
  const double gap = run.poses()[0].centre.y - 0.1;
  const auto v = run.flow().body_velocity(0).velocity;
  std::printf("gap %.5g m (balance %.5g), speed %.2e m/s, narrowest %.5g m\n", gap, lo,
              std::hypot(v.x, v.y), run.narrowest_gap().g);
  EXPECT_NEAR(gap, lo, 0.01 * lo);
  EXPECT_LT(std::hypot(v.x, v.y), 1e-5);
  EXPECT_EQ(run.gap_warnings(), 0);  // (with a core, films warn at 5 % of the core)
}

// A disk on a tilting floor (4 deg/s from t = 0.5 s; nu = 0.005, mu = 0.5): without rolling
// resistance nothing holds it, it rolls from the first degrees; with mu_r = 0.2 it holds until
// tan(theta) = mu_r (11.31 deg: the friction W sin at the lever R to mid-gap against the cap
// mu_r R W cos, R cancels), within 0.5 deg as the square's slip (the spring period is ~0.4 deg of
// tilt), then rolls (1 mm/s within 2 deg more) without sliding (friction below mu N).
TEST(ValidationFemMoving, RollingResistanceHoldsADiskUpToItsAngle) {
  GravityTilt tilt;
  tilt.rate = 4.0;
  tilt.start = 0.5;
  tilt.end = 9.0;
  auto tilt_deg = [&](double t) { return tilt.angle(t) * 180 / std::numbers::pi; };
  double free_moving = -1;
  gf::fem_bench::disk_on_tilting_floor(0.5, 0.0, 1.5, tilt, [&](const MovingBodyFlow& run) {
    if (free_moving < 0 && std::abs(run.flow().body_velocity(0).velocity.x) > 1e-3)
      free_moving = tilt_deg(run.time());
  });
  const double mu_r = 0.2, critical = std::atan(mu_r) * 180 / std::numbers::pi;
  double saturated = -1, moving = -1, ratio = 0, x_before = 0;
  gf::fem_bench::disk_on_tilting_floor(0.5, mu_r, 4.5, tilt, [&](const MovingBodyFlow& run) {
    const double t = run.time(), theta = tilt_deg(t);
    const auto& h = run.contact_history();
    const auto& c = run.contact_loads()[0];
    // the floor's rolling spring at its cap mu_r R F_n: rotation mu_r F_n / (k_t R)
    const double k_t = 2 * (4 * std::numbers::pi * 0.1) / 0.03;  // 2 F_0 / range
    const double r = 0.1 + 0.5 * (run.poses()[0].centre.y - 0.1);
    const double cap = mu_r * c.force.y / (k_t * r);
    if (t > 0.6 && saturated < 0 && std::abs(h.rolled(0, 0, -1, 0)) >= 0.999 * cap)
      saturated = theta;
    if (t > 0.6 && moving < 0 && std::abs(run.flow().body_velocity(0).velocity.x) > 1e-3) {
      moving = theta;
      ratio = std::abs(c.force.x) / (0.5 * c.force.y);
    }
    if (theta < critical - 1) x_before = run.poses()[0].centre.x;
  });
  std::printf(
      "no rolling resistance: moving at 1 mm/s at %.2f deg; mu_r = %.1f: spring at its cap "
      "at %.2f deg, moving at %.2f deg (atan mu_r = %.2f deg), friction / mu N %.3f; "
      "moved %.2e m before\n",
      free_moving, mu_r, saturated, moving, critical, ratio, x_before);
  EXPECT_GT(free_moving, 0.0);
  EXPECT_LT(free_moving, 3.0);
  EXPECT_NEAR(saturated, critical, 0.5);
  EXPECT_GT(moving, critical - 0.5);
  EXPECT_LT(moving, critical + 2.0);
  EXPECT_LT(ratio, 0.9);
  EXPECT_LT(std::abs(x_before), 2e-3);
}

// A tentative step (for step-size control) that is rejected leaves the run as it was: poses,
// friction springs, contact loads, unknowns and time; the same step tried again (full Newton, no
// kept LU) gives the same bits as the first try, and only acceptance moves the poses.
TEST(FemMoving, RejectedTryLeavesTheRunAsItWas) {
  MovingBodyFlow run = gf::fem_bench::square_on_slope(0.45, 0.5, 0.2);
  const auto poses = run.poses();
  const auto springs = run.contact_history().entries();
  ASSERT_FALSE(springs.empty());
  const auto loads = run.contact_loads();
  const auto x = run.flow().solution();
  const double t = run.time();
  const NewtonOptions opt;
  const auto first = run.try_step(0.01, 2, opt, 1e-3, 1e-5);
  ASSERT_TRUE(first.newton.converged);
  EXPECT_GE(first.error, 0.0);  // (an estimate: enough states known)
  const auto x1 = run.flow().solution();
  EXPECT_EQ(run.poses()[0].centre.x, poses[0].centre.x);  // pending until accepted
  run.reject_step();
  run.reject_step();  // (a second reject is harmless)
  EXPECT_EQ(run.time(), t);
  EXPECT_EQ(run.flow().solution(), x);
  EXPECT_EQ(run.contact_history().entries(), springs);
  EXPECT_EQ(run.contact_loads()[0].force.x, loads[0].force.x);
  EXPECT_EQ(run.poses()[0].centre.x, poses[0].centre.x);
  EXPECT_EQ(run.poses()[0].angle, poses[0].angle);
  const auto again = run.try_step(0.01, 2, opt, 1e-3, 1e-5);
  EXPECT_EQ(again.error, first.error);
  EXPECT_EQ(run.flow().solution(), x1);
  run.accept_step();
  EXPECT_NE(run.poses()[0].centre.x, poses[0].centre.x);
  EXPECT_NE(run.contact_history().entries(), springs);
  EXPECT_NEAR(run.time(), t + 0.01, 1e-15);
  // right after a remesh the history restarts: no estimate (-1) until k + 1 states are known
  run.remesh();
  const auto fresh = run.try_step(0.01, 2, opt, 1e-3, 1e-5);
  EXPECT_EQ(fresh.error, -1.0);
  run.accept_step();
  EXPECT_EQ(run.try_step(0.01, 2, opt, 1e-3, 1e-5).error, -1.0);  // BDF2 from 2 states
  run.accept_step();
  EXPECT_GE(run.try_step(0.01, 2, opt, 1e-3, 1e-5).error, 0.0);
  run.accept_step();
}

// A disk settles onto the floor of a closed box and comes to rest where the repulsion carries
// its buoyant weight W: F_0 ((rho - g) / rho)^2 = W gives g = rho (1 - 1/2) = 0.015 m for
// F_0 = 4 W. It falls 0.285 m through the fluid (Re ~ 10), remeshing on the way, and after
// 3 s its speed has decayed (squeeze film) to below 1 % of the free fall's.
TEST(ValidationFemMoving, DiskComesToRestOnTheFloorAtTheRepulsionsBalance) {
  const MovingBodyFlow run = settle_on_floor(false, 0.0, 3.0);
  const double gap = run.poses()[0].centre.y - 0.1;
  const auto v = run.flow().body_velocity(0);
  std::printf("gap %.5f m (balance 0.015), speed %.2e m/s, %d remeshes\n", gap,
              std::hypot(v.velocity.x, v.velocity.y), run.remeshes());
  EXPECT_NEAR(gap, 0.015, 1e-3);
  EXPECT_LT(std::hypot(v.velocity.x, v.velocity.y), 1e-3);
  EXPECT_GE(run.remeshes(), 1);
}

// A square released tilted by 0.3 rad lands on a corner, turns onto its face and comes to rest
// flat, each of the two lower corners carrying half the buoyant weight: F_0 s^2 = W / 2, s =
// (rho - g) / rho = 1 / sqrt(8), g = 0.0194 m. The torque that turns it comes from the repulsion
// acting off the centre (the fluid only damps the rotation).
TEST(ValidationFemMoving, TiltedSquareLandsFlat) {
  const MovingBodyFlow run = settle_on_floor(true, 0.3, 4.0);
  const double angle = run.poses()[0].angle + 0.3;
  const double off = std::remainder(angle, std::numbers::pi / 2);
  const auto v = run.flow().body_velocity(0);
  const double gap = run.poses()[0].centre.y - 0.1;  // flat: the lower face is 0.1 below
  std::printf(
      "angle %.4f rad (off flat %.2e), gap %.5f (balance 0.0194), speed %.2e, "
      "%d remeshes\n",
      angle, off, gap, std::hypot(v.velocity.x, v.velocity.y), run.remeshes());
  EXPECT_LT(std::abs(off), 0.01);
  EXPECT_NEAR(gap, 0.0194, 2e-3);  // still closing at ~1e-3 m/s (squeeze film)
  EXPECT_LT(std::hypot(v.velocity.x, v.velocity.y), 1e-3);
}

// Settling at Re ~ 10 on the moving mesh against the steady flow seen from the disk: a disk of
// density 1.5 (radius 0.1, nu = 0.02, g = 30) falls from rest through a channel of half-width
// 0.5, the mesh following it (ALE) and remeshed on the way; its final speed must be the U* at
// which the steady drag in the disk's frame (sliding walls, uniform inflow; solved by Newton on
// a mesh of the same sizes) balances the buoyant weight. Galilean invariance makes the two the
// same problem, so this checks the ALE convection and the free body's equations where inertia
// matters (at Re ~ 10 the drag is 1.9x Faxen's Stokes value). The disk falls ~1.8 m (9
// diameters) in 2 s; the speed's relaxation time is (m + m_added) / (dF/dU) ~ 0.1 s, and what
// is left after 2 s is the slow viscous relaxation of the wake (measured: the speed changes by
// 0.1 % over the last 0.5 s; checked < 0.2 %). Two different meshes (and the remeshing) leave ~0.3
// % between the drags; allowed 1 %.
TEST(ValidationFemMoving, SettlingAtReTenMatchesTheSteadyFlowInTheDisksFrame) {
  const double u_star = gf::fem_bench::re10_terminal_speed();
  MovingBodyFlow run = gf::fem_bench::re10_settling();
  double u_at_2 = 0;
  int steps = 0;
  gf::fem_bench::run_steps(run, 0.01, 2.0, [&](const MovingBodyFlow& r) {
    if (++steps == 150) u_at_2 = -r.flow().body_velocity(0).velocity.y;
  });
  const double u = -run.flow().body_velocity(0).velocity.y;
  std::printf(
      "U* = %.5f (Re %.2f); settling: U(1.5 s) = %.5f, U(2 s) = %.5f (ratio %.5f), "
      "fell %.3f m, drift %.2e m, %d remeshes\n",
      u_star, u_star * 0.2 / 0.02, u_at_2, u, u / u_star, 1.5 - run.poses()[0].centre.y,
      std::abs(run.poses()[0].centre.x), run.remeshes());
  EXPECT_NEAR(u / u_star, 1.0, 1e-2);
  EXPECT_NEAR(u / u_at_2, 1.0, 2e-3);
}

// Coulomb's law on a slope, in the fluid: the square of settle_on_floor rests flat on the floor
// with gravity tilted by the slope angle (the slope in its own frame) and friction mu = 0.5 on
// the repulsion's gaps. Below the friction angle (tan = 0.9 mu) it holds: once the start's
// oscillation (period ~0.15 s, damped by the film in ~0.3 s) has died out it is at rest and the
// friction carries the buoyant weight's component along the slope, W sin = 0.1641 N/m, to the
// precision of the steady state (measured 2.4e-4; checked 1e-3: the fluid at rest adds no force
// along the slope, what is left is the film's last creep), within a centimetre of where it
// started (measured 4.2 mm: the friction's torque tips the square forwards by 0.028 rad onto its
// front corner, which moves the centre ~3.3 mm, and the springs stretch by W sin / (2 k_t) =
// 0.8 mm; the start's overshoot, to 0.43 W, stays below the Coulomb limit 0.455 W: no slip).
// Above it (tan = 1.1 mu) it slides: the net force W (sin - mu cos) = 0.017 N/m against the
// film's shear drives it at 8 mm/s after 3 s (2.5e-5 m/s when held), 2.4 cm down the slope;
// the friction is then mu times the normal load (the spring at its cap).
TEST(ValidationFemMoving, SquareOnASlopeHoldsBelowTheFrictionAngleAndSlidesAbove) {
  const double mu = 0.5, w = 0.4;
  const auto report = [&](const char* what, double tan_s, const MovingBodyFlow& run) {
    const auto& c = run.contact_loads()[0];
    const auto v = run.flow().body_velocity(0).velocity;
    const double cos_s = 1 / std::sqrt(1 + tan_s * tan_s), sin_s = tan_s * cos_s;
    std::printf(
        "%s (tan = %.3f): moved %.3e m, speed %.2e m/s, friction %.5f N/m (W sin %.5f), "
        "normal %.5f (W cos %.5f), angle %.2e rad\n",
        what, tan_s, run.poses()[0].centre.x, std::hypot(v.x, v.y), -c.force.x, w * sin_s,
        c.force.y, w * cos_s, run.poses()[0].angle);
  };
  {
    const double tan_s = 0.9 * mu;
    const MovingBodyFlow run = gf::fem_bench::square_on_slope(tan_s, mu, 3.0);
    report("holds ", tan_s, run);
    const double sin_s = tan_s / std::sqrt(1 + tan_s * tan_s);
    const auto v = run.flow().body_velocity(0).velocity;
    EXPECT_LT(std::abs(run.poses()[0].centre.x), 1e-2);
    EXPECT_LT(std::hypot(v.x, v.y), 1e-4);
    EXPECT_NEAR(-run.contact_loads()[0].force.x, w * sin_s, 1e-3 * w * sin_s);
  }
  {
    // ten times less viscous: the film barely damps the start's oscillation, and a friction
    // scheme that feeds it (springs stretched with the step's start velocities: +2 % per step
    // under BDF2) kept the square ringing at ~2e-3 m/s and creeping down the slope (review)
    const double tan_s = 0.9 * mu;
    const MovingBodyFlow run = gf::fem_bench::square_on_slope(tan_s, mu, 4.0, {}, nullptr, 0.005);
    report("holds, nu = 0.005", tan_s, run);
    const double sin_s = tan_s / std::sqrt(1 + tan_s * tan_s);
    const auto v = run.flow().body_velocity(0).velocity;
    EXPECT_LT(std::hypot(v.x, v.y), 1e-4);
    EXPECT_NEAR(-run.contact_loads()[0].force.x, w * sin_s, 1e-3 * w * sin_s);
  }
  {
    const double tan_s = 1.1 * mu;
    const MovingBodyFlow run = gf::fem_bench::square_on_slope(tan_s, mu, 3.0);
    report("slides", tan_s, run);
    const auto& c = run.contact_loads()[0];
    EXPECT_GT(run.poses()[0].centre.x, 0.01);
    EXPECT_GT(run.flow().body_velocity(0).velocity.x, 2e-3);
    EXPECT_NEAR(-c.force.x, mu * c.force.y, 1e-9);
  }
}

// Tilting the floor (a tilting-box test, `tilt`): the same square rests on a level floor, then
// the domain turns at 4 deg/s. The square holds until tan(theta) = mu (26.57 deg for mu = 0.5)
// and slides from there: quasi-statically the friction needed, W sin(theta), reaches mu N with
// N = W cos(theta). The friction saturates within 0.5 deg of that angle (the contact's spring
// period, ~0.1 s, is 0.4 deg of tilt; the film's normal load differs from W cos by < 1 %), and
// the square gains 1 mm/s along the floor within 2 deg more (its sliding speed grows as
// W (sin - mu cos) against the film's drag). In the thinner liquid of the slope test
// (nu = 0.005): at nu = 0.05 the square's rocking as the load shifts to its downhill corner (it
// turns 1.7 deg over the tilt) squeezes the films, whose lubrication forces add 5 % to the
// normal load and delay the slip to 28.0 deg (measured 2026-12-04; 26.72 deg at nu = 0.005).
TEST(ValidationFemMoving, TiltedFloorSlidesAtTheFrictionAngle) {
  const double mu = 0.5;
  GravityTilt tilt;
  tilt.rate = 4.0;
  tilt.start = 0.5;
  tilt.end = 9.0;
  double saturated = -1, moving = -1, x_before = 0;
  bool downhill = false;  // a counter-clockwise tilt turns gravity towards -x
  const auto each = [&](const MovingBodyFlow& run) {
    const double t = run.time();
    const double theta = tilt.angle(t) * 180 / std::numbers::pi;
    const auto& c = run.contact_loads()[0];
    const double ft = std::abs(c.force.x), fn = c.force.y;  // (the floor is y = 0)
    if (t > 0.6 && saturated < 0 && ft >= 0.999 * mu * fn) saturated = theta;
    if (t > 0.6 && moving < 0 && std::abs(run.flow().body_velocity(0).velocity.x) > 1e-3) {
      moving = theta;
      downhill = run.flow().body_velocity(0).velocity.x < 0 && c.force.x > 0;
    }
    if (theta < 25) x_before = run.poses()[0].centre.x;
  };
  gf::fem_bench::square_on_slope(0.0, mu, 8.0, each, nullptr, 0.005, tilt);
  const double critical = std::atan(mu) * 180 / std::numbers::pi;
  std::printf(
      "friction saturated at %.2f deg, moving at 1 mm/s at %.2f deg (atan mu = %.2f deg); "
      "moved %.2e m before 25 deg\n",
      saturated, moving, critical, x_before);
  EXPECT_NEAR(saturated, critical, 0.5);
  EXPECT_GT(moving, critical - 0.5);
  EXPECT_LT(moving, critical + 2.0);
  EXPECT_LT(std::abs(x_before), 1e-2);
  EXPECT_TRUE(downhill);
  const Vec2 g = tilt.gravity({0, -10}, 0.5 + 30 / 4.0);  // 30 degrees
  EXPECT_NEAR(g.x, -5.0, 1e-12);
  EXPECT_NEAR(g.y, -10 * std::sqrt(0.75), 1e-12);
}
