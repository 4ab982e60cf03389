// SPDX-License-Identifier: GPL-3.0-or-later
// sjkr cohesion (docs/models/cohesion.md): a sphere brought into contact with a plane wall, and
// two equal spheres brought together, at low speed, without gravity and with strong damping,
// settle at the overlap where the elastic repulsion (Hooke, Hertz) equals the attraction k_c A.
// The equilibrium is computed here in closed form (Hooke) or by bisection (Hertz).
//
// Tolerance: a resting state of velocity Verlet is a state of zero force whatever dt (the drift
// x += v dt + F/m dt^2/2 and the kick leave x fixed only where F(x) = 0), so the settled overlap
// carries no discretisation error; what is left is the not yet decayed part of the approach,
// which decays as exp(-t / tau) with tau the slowest time constant of the damped contact about
// the equilibrium (computed below from its effective stiffness and the damping). Each run lasts
// > 40 tau, which leaves < 1e-17 of the initial offset; the check is 1e-6 relative to the
// equilibrium overlap, which is also the root solve's precision (1e-12) times a wide margin.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "case_builder.hpp"
#include "contact/registry.hpp"
#include "dump.hpp"
#include "simulation/simulation.hpp"

using namespace gf;
using gf::test::Dump;

namespace {

constexpr double pi = std::numbers::pi;
constexpr double R = 1e-3, rho = 2500, E = 1e7, nu = 0.3;
const double e_star = E / (2 * (1 - nu * nu));  // equal materials (the wall's too)
const double mass = rho * 4.0 / 3.0 * pi * R * R * R;

/// Root of g on [lo, hi] (g(lo) < 0 < g(hi)) by bisection to 1e-12 relative.
double bisect(const std::function<double(double)>& g, double lo, double hi) {
  for (int it = 0; it < 200 && hi - lo > 1e-12 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (g(mid) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

/// Contact area of a sphere of radius R on a wall (wall) or of two spheres of radius R.
double area(double delta, bool wall) {
  return wall ? pi * delta * (2 * R - delta) : pi * (R * delta - 0.25 * delta * delta);
}

struct Settled {
  double overlap = 0;  ///< m
  double speed = 0;    ///< m/s, at the end
};

/// Runs a sphere against the floor (wall) or two spheres head-on, starting apart by `gap` and
/// approaching at v0 (relative), for `t_end` seconds with time step dt. Restitution 0.3.
Settled settle(const std::string& law, double k, double kc, bool wall, double dt, double t_end,
               Dump* trace = nullptr) {
  const double gap = 2e-7, v0 = 2e-5;
  auto c = test::base_case(dt, t_end, {-0.01, -0.01, -0.01}, {0.01, 0.01, 0.01});
  test::add_material(c, "glass", rho, E, nu);
  std::map<std::string, double> prm{
      {"restitution", 0.3}, {"friction", 0.5}, {"cohesion_energy_density", kc}};
  if (law == "hooke") {
    prm["stiffness"] = k;
    prm["tangential_stiffness_ratio"] = 2.0 / 7.0;
  }
  test::add_contact(c, "glass", "glass", law, prm);
  if (wall) {
    test::add_spheres(c, "glass", R, {{0, 0, R + gap}}, {{0, 0, -v0}});
    test::add_plane(c, "floor", {0, 0, 0}, {0, 0, 1}, "glass");
  } else {
    test::add_spheres(c, "glass", R, {{0, 0, -R - 0.5 * gap}, {0, 0, R + 0.5 * gap}},
                      {{0, 0, 0.5 * v0}, {0, 0, -0.5 * v0}});
  }
  Simulation sim(c);
  const auto& p = sim.particles();
  auto overlap = [&] { return wall ? R - p.x()[0].z : 2 * R - norm(p.x()[1] - p.x()[0]); };
  const auto n = static_cast<long>(std::llround(t_end / dt));
  for (long s = 0; s < n; ++s) {
    sim.step();
    if (trace && s % 20 == 0) trace->row(sim.time(), overlap());
  }
  Settled out;
  out.overlap = overlap();
  out.speed = wall ? norm(p.v()[0]) : norm(p.v()[1] - p.v()[0]);
  return out;
}

/// Slowest decay time (s) of the damped motion about the equilibrium: m x'' + c x' + k_eff x = 0
/// with c = 2 zeta sqrt(m S) (S the elastic tangent stiffness there), k_eff = S - dF_coh/ddelta.
double decay_time(double m, double s, double k_eff, double zeta) {
  const double c = 2 * zeta * std::sqrt(m * s);
  const double disc = c * c - 4 * m * k_eff;
  // Overdamped: the slow root (c - sqrt(disc)) / 2m; underdamped: the envelope 2m / c.
  return disc > 0 ? 2 * m / (c - std::sqrt(disc)) : 2 * m / c;
}

}  // namespace

// Hooke: k delta = k_c pi delta (2R - delta) on a wall gives delta = 2R - k / (pi k_c); for two
// spheres k delta = k_c pi (R delta - delta^2 / 4) gives delta = 4 (R - k / (pi k_c)).
TEST(ValidationCohesion, HookeSettlesAtTheEquilibriumOverlap) {
  const double k = 100;
  const double zeta = contact::damping_ratio_for_restitution(contact::NormalKind::Linear, 0.3);
  for (const bool wall : {true, false}) {
    // k_c such that the overlap is 5 % of R.
    const double target = 0.05 * R;
    const double kc = wall ? k / (pi * (2 * R - target)) : k / (pi * (R - 0.25 * target));
    const double expected = wall ? 2 * R - k / (pi * kc) : 4 * (R - k / (pi * kc));
    const double m = wall ? mass : 0.5 * mass;
    const double k_eff =
        wall ? k - pi * kc * (2 * R - 2 * expected) : k - pi * kc * (R - 0.5 * expected);
    const double tau = decay_time(m, k, k_eff, zeta);
    const double dt = std::sqrt(m / k) / 50;
    const Settled s = settle("hooke", k, kc, wall, dt, 40 * tau + 0.01);
    EXPECT_NEAR(s.overlap, expected, 1e-6 * expected) << (wall ? "wall" : "pair");
    EXPECT_LT(s.speed, 1e-9);
    std::printf(
        "hooke %s: k_c %.6g J/m^3, tau %.3g s, overlap %.10g m, analytic %.10g m, rel %.2e\n",
        wall ? "wall" : "pair", kc, tau, s.overlap, expected, s.overlap / expected - 1);
  }
}

// Hertz: 4/3 E* sqrt(R*) delta^(3/2) = k_c A(delta), by bisection, for a sphere on a wall over a
// range of k_c (the curve of the plot) and for two equal spheres.
TEST(ValidationCohesion, HertzSettlesAtTheEquilibriumOverlap) {
  const double zeta = contact::damping_ratio_for_restitution(contact::NormalKind::Hertz, 0.3);
  Dump curve("cohesion_settled", "wall,kc,overlap,analytic");
  Dump trace("cohesion_approach", "t,overlap");
  for (const bool wall : {true, false}) {
    const double r_eff = wall ? R : 0.5 * R;
    const double m = wall ? mass : 0.5 * mass;
    for (const double kc : {1e4, 3e4, 1e5, 2e5, 4e5}) {
      if (!wall && kc != 1e5) continue;
      auto g = [&](double d) {
        return 4.0 / 3.0 * e_star * std::sqrt(r_eff) * std::pow(d, 1.5) - kc * area(d, wall);
      };
      const double expected = bisect(g, 1e-14, R);
      const double s_el = 2 * e_star * std::sqrt(r_eff * expected);
      const double h = 1e-6 * expected;  // dF_coh / ddelta by a central difference
      const double k_eff =
          s_el - kc * (area(expected + h, wall) - area(expected - h, wall)) / (2 * h);
      ASSERT_GT(k_eff, 0);  // a stable equilibrium
      const double tau = decay_time(m, s_el, k_eff, zeta);
      const double dt = 1e-6;  // >= 40 steps per period sqrt(m / S) at the deepest overlap
      EXPECT_LT(dt, std::sqrt(m / s_el) / 40);
      const Settled s = settle("hertz_mindlin", 0, kc, wall, dt, 40 * tau + 0.015,
                               wall && kc == 1e5 ? &trace : nullptr);
      EXPECT_NEAR(s.overlap, expected, 1e-6 * expected) << (wall ? "wall" : "pair") << " " << kc;
      EXPECT_LT(s.speed, 1e-9);
      curve.row(wall ? 1 : 0, kc, s.overlap, expected);
      std::printf(
          "hertz %s: k_c %.6g J/m^3, tau %.3g s, overlap %.10g m, analytic %.10g m, "
          "rel %.2e\n",
          wall ? "wall" : "pair", kc, tau, s.overlap, expected, s.overlap / expected - 1);
    }
  }
}

// The force-overlap curves of the plot: the law itself (sphere on a wall, at rest), Hertz and
// Hooke with k_c = 1e5 J/m^3.
TEST(ValidationCohesion, ForceOverlapCurve) {
  Dump curve("cohesion_force", "overlap,hertz,hooke,cohesion");
  const Material glass{"glass", rho, E, nu};
  const auto hz = contact::prepare_pair(
      "hertz_mindlin", {&glass, &glass, R},
      {{"restitution", 0.3}, {"friction", 0.5}, {"cohesion_energy_density", 1e5}});
  const auto hk = contact::prepare_pair("hooke", {&glass, &glass, R},
                                        {{"restitution", 0.3},
                                         {"stiffness", 100.0},
                                         {"tangential_stiffness_ratio", 2.0 / 7.0},
                                         {"cohesion_energy_density", 1e5}});
  for (int i = 1; i <= 200; ++i) {
    contact::ContactKinematics k{};
    k.overlap = 1e-4 * R * i;
    k.normal = {0, 0, 1};
    k.r_eff = R;
    k.m_eff = mass;
    Vec3 xi{};
    const double fz = contact::HertzMindlin::Law::evaluate(hz, k, 1e-6, xi).force.z;
    xi = {};
    const double fk = contact::Hooke::Law::evaluate(hk, k, 1e-6, xi).force.z;
    const double coh = 1e5 * area(k.overlap, true);
    EXPECT_NEAR(fz, 4.0 / 3.0 * e_star * std::sqrt(R) * std::pow(k.overlap, 1.5) - coh,
                1e-12 * coh);
    EXPECT_NEAR(fk, 100 * k.overlap - coh, 1e-12 * coh);
    curve.row(k.overlap, fz, fk, coh);
  }
}
