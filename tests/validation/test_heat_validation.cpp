// SPDX-License-Identifier: GPL-3.0-or-later
// Heat conduction through contacts (heat: block; contact/conduction.hpp, docs/models/heat.md).
//
// 1. A chain of N spheres pressed between a hot floor and a cold lid by a force F, no gravity:
//    every contact carries F, so its overlap and its Hertz contact radius are known in closed
//    form (a = (3 F R* / (4 E*))^(1/3), R* = R/2 between spheres, R on a wall), the spheres rest
//    where they are put, and the steady heat flow is that of the contact conductances in series,
//    Q = (T_hot - T_cold) / (2 / H_w + (N - 1) / H_p), with H = 2 k a (batchelor_obrien, equal
//    conductivities) or sqrt(2 pi) times that (intersection_area); the temperature falls by
//    Q / H across each contact.
//    Tolerance: the explicit step's fixed point is the ODE's (all flows balance whatever dt), so
//    the only error is the transient not yet decayed, exp(-t / tau) of the initial 50 K with tau
//    the slowest time constant of the chain (1 / the smallest eigenvalue of C^-1 L for the
//    uniform chain, computed below); each run lasts > 25 tau (< 1e-10 of 50 K left), and the
//    check is 1e-7 relative, which also covers the rounding of the sums.
// 2. Two spheres between adiabatic walls at 400 K and 300 K: the difference decays as
//    exp(-2 H t / C) (C = m c). The explicit Euler steps give exactly (1 - 2 H dt / C)^n, checked
//    to 1e-9 relative (rounding of n products); against the exponential the relative error is
//    1 - exp(-n (x^2/2 + x^3/3 + ...)) < n x^2/2 (1 + x), x = 2 H dt / C: 1.2e-3 here, and the
//    check is 1.5 n x^2/2; the thermal energy
//    m c (T_1 + T_2) is conserved to 1e-13 relative (the two flows are one number of opposite
//    signs).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "case_builder.hpp"
#include "dump.hpp"
#include "simulation/simulation.hpp"

using namespace gf;
using gf::test::Dump;

namespace {

constexpr double pi = std::numbers::pi;
constexpr double R = 1e-3, rho = 2500, E = 1e8, nu = 0.3, k_th = 100, c_p = 1;
const double e_star = E / (2 * (1 - nu * nu));  // equal materials (the walls' too)
const double mass = rho * 4.0 / 3.0 * pi * R * R * R;

/// Hertz overlap under force F at effective radius r_eff: F = 4/3 E* sqrt(R*) delta^(3/2).
double hertz_overlap(double force, double r_eff) {
  return std::pow(force / (4.0 / 3.0 * e_star * std::sqrt(r_eff)), 2.0 / 3.0);
}

config::Case chain_case(double dt, double t_end, const std::string& model) {
  auto c = test::base_case(dt, t_end, {-0.01, -0.01, -0.01}, {0.01, 0.01, 0.03});
  test::add_material(c, "soft", rho, E, nu);
  c.materials.back().thermal_conductivity = k_th;
  c.materials.back().heat_capacity = c_p;
  test::add_contact(c, "soft", "soft", "hertz_mindlin", {{"restitution", 0.5}, {"friction", 0}});
  config::Heat h;
  h.model = model;
  h.temperature = 350;
  c.heat = h;
  return c;
}

}  // namespace

TEST(ValidationHeat, ChainConductsTheSeriesConductanceOfItsHertzContacts) {
  const int n = 6;
  const double force = 0.01;
  const double d_p = hertz_overlap(force, 0.5 * R), d_w = hertz_overlap(force, R);
  const double a_p = std::cbrt(3 * force * 0.5 * R / (4 * e_star));
  const double a_w = std::cbrt(3 * force * R / (4 * e_star));
  ASSERT_NEAR(a_p, std::sqrt(0.5 * R * d_p), 1e-12 * a_p);  // (the same radius, two ways)
  std::vector<Vec3> x;
  for (int k = 0; k < n; ++k) x.push_back({0, 0, R - d_w + k * (2 * R - d_p)});
  const double lid = x.back().z + R - d_w;
  // Slowest time constant of the chain: C^-1 L with L tridiagonal (H_w + H_p at the ends,
  // 2 H_p inside, -H_p off the diagonal); its smallest eigenvalue by inverse iteration.
  auto slowest_tau = [&](double h_p, double h_w) {
    std::vector<double> v(n, 1.0);
    double lambda = 0;
    for (int it = 0; it < 200; ++it) {
      // Solve L y = v (Thomas algorithm), then normalise.
      std::vector<double> diag(n), rhs = v, y(n);
      for (int k = 0; k < n; ++k) diag[k] = (k == 0 || k == n - 1) ? h_w + h_p : 2 * h_p;
      for (int k = 1; k < n; ++k) {
        const double f = -h_p / diag[k - 1];
        diag[k] -= f * -h_p;
        rhs[k] -= f * rhs[k - 1];
      }
      y[n - 1] = rhs[n - 1] / diag[n - 1];
      for (int k = n - 2; k >= 0; --k) y[k] = (rhs[k] + h_p * y[k + 1]) / diag[k];
      double norm_y = 0, norm_v = 0;
      for (int k = 0; k < n; ++k) {
        norm_y += y[k] * y[k];
        norm_v += v[k] * v[k];
      }
      lambda = std::sqrt(norm_v / norm_y);
      for (int k = 0; k < n; ++k) v[k] = y[k] / std::sqrt(norm_y);
    }
    return mass * c_p / lambda;
  };
  Dump profile("heat_chain", "model,k,z,temperature,analytic");
  for (const std::string model : {"batchelor_obrien", "intersection_area"}) {
    const double factor = model == "batchelor_obrien" ? 1.0 : std::sqrt(2 * pi);
    const double h_p = factor * 2 * k_th * a_p, h_w = factor * 2 * k_th * a_w;
    const double q = (400.0 - 300.0) / (2 / h_w + (n - 1) / h_p);
    const double tau = slowest_tau(h_p, h_w);
    const double dt = 5e-6, t_end = 25 * tau;
    auto c = chain_case(dt, t_end, model);
    test::add_spheres(c, "soft", R, x);
    test::add_plane(c, "floor", {0, 0, 0}, {0, 0, 1}, "soft");
    c.walls.back().temperature = 400;
    test::add_plane(c, "lid", {0, 0, lid}, {0, 0, -1}, "soft");
    c.walls.back().temperature = 300;
    Simulation sim(c);
    const auto steps = static_cast<long>(std::llround(t_end / dt));
    for (long s = 0; s < steps; ++s) sim.step();
    const auto& p = sim.particles();
    const auto& temp = p.get<double>(p.find_field("temperature"));
    double v_max = 0;
    for (int k = 0; k < n; ++k) v_max = std::max(v_max, norm(p.v()[k]));
    EXPECT_LT(v_max, 1e-12) << "the chain was put at rest in its equilibrium";
    EXPECT_NEAR(sim.quantity("wall_heat_flow.floor"), -q, 1e-7 * q) << model;
    EXPECT_NEAR(sim.quantity("wall_heat_flow.lid"), q, 1e-7 * q) << model;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const auto k = static_cast<double>(p.id()[i] - 1);  // (ids count the positions from 1)
      const double expected = 400 - q * (1 / h_w + k / h_p);
      EXPECT_NEAR(temp[i], expected, 1e-7 * 100) << model << " sphere " << k;
      profile.row(factor, k, p.x()[i].z, temp[i], expected);
    }
    std::printf("%s: Q = %.9g W (analytic %.9g W, rel %.2e), tau %.3g s, %ld steps\n",
                model.c_str(), sim.quantity("wall_heat_flow.lid"), q,
                sim.quantity("wall_heat_flow.lid") / q - 1, tau, steps);
  }
}

TEST(ValidationHeat, TwoSpheresRelaxExponentially) {
  const double force = 0.01;
  const double d_p = hertz_overlap(force, 0.5 * R), d_w = hertz_overlap(force, R);
  const double h = 2 * k_th * std::sqrt(0.5 * R * d_p);
  const double cap = mass * c_p;
  const double rate = 2 * h / cap;  // of T_1 - T_2
  const double dt = 5e-7, t_end = 3 / rate;
  auto c = chain_case(dt, t_end, "batchelor_obrien");
  test::add_spheres(c, "soft", R, {{0, 0, R - d_w}});
  c.particles.back().temperature = 400;
  test::add_spheres(c, "soft", R, {{0, 0, R - d_w + 2 * R - d_p}});
  c.particles.back().temperature = 300;
  test::add_plane(c, "floor", {0, 0, 0}, {0, 0, 1}, "soft");  // adiabatic: no temperature
  test::add_plane(c, "lid", {0, 0, 4 * R - 2 * d_w - d_p}, {0, 0, -1}, "soft");
  Simulation sim(c);
  const auto& p = sim.particles();
  const int f = p.find_field("temperature");
  const double e0 = sim.quantity("thermal_energy");
  EXPECT_NEAR(e0, cap * 700, 1e-14 * cap * 700);
  Dump curve("heat_two_spheres", "t,difference,exponential");
  const auto steps = static_cast<long>(std::llround(t_end / dt));
  double worst_discrete = 0, worst_exp = 0;
  for (long s = 1; s <= steps; ++s) {
    sim.step();
    const auto& temp = p.get<double>(f);
    const double diff = (p.id()[0] == 1 ? 1 : -1) * (temp[0] - temp[1]);
    const double discrete = 100 * std::pow(1 - rate * dt, static_cast<double>(s));
    const double exact = 100 * std::exp(-rate * dt * static_cast<double>(s));
    worst_discrete = std::max(worst_discrete, std::abs(diff / discrete - 1));
    worst_exp = std::max(worst_exp, std::abs(diff / exact - 1));
    if (s % 50 == 0) curve.row(sim.time(), diff, exact);
  }
  EXPECT_LT(worst_discrete, 1e-9);
  const double leading = static_cast<double>(steps) * (rate * dt) * (rate * dt) / 2;
  EXPECT_LT(worst_exp, 1.5 * leading);
  EXPECT_NEAR(sim.quantity("thermal_energy"), e0, 1e-13 * e0);
  EXPECT_NEAR(sim.quantity("temperature_mean"), 350, 350 * 1e-13);
  std::printf(
      "two spheres: H = %.6g W/K, %ld steps, worst rel. error %.2e (explicit steps), %.2e "
      "(exponential)\n",
      h, steps, worst_discrete, worst_exp);
}
