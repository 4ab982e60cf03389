// SPDX-License-Identifier: GPL-3.0-or-later
// Drag laws against terminal settling velocities: one sphere released from rest in a quiescent
// fluid, integrated with the semi-implicit update the CFD-DEM coupling uses,
//   m v_{n+1} = m v_n + dt (m g - V_p grad p) + dt beta(v_n) (u_f - v_{n+1}),  u_f = 0,
// whose fixed point is the exact balance of weight, buoyancy and drag (so the terminal value
// carries no time-step error). Added mass and the Basset history force are neglected: they
// change the transient, not the terminal velocity. Curves go to GF_VALIDATION_OUT for
// scripts/plot_drag.py.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <string>

#include "coupling/cfd_dem/drag_registry.hpp"
#include "dump.hpp"

using namespace gf;
using namespace gf::cfd_dem;

namespace {

constexpr double kPiD = std::numbers::pi;
constexpr double kG = 9.81;

struct Settling {
  double d, rho_p, rho_f, mu;
};

/// Settles one sphere with drag law `key` for n_tau particle response times (tau = rho_p d^2 /
/// (18 mu)) in steps of tau / steps_per_tau; returns the final speed (m/s) and dumps v(t)
/// (unless dump_name is empty).
double settle(const Settling& s, std::string_view key, const std::string& dump_name,
              double n_tau = 10, int steps_per_tau = 1000) {
  const double vp = kPiD * s.d * s.d * s.d / 6, m = s.rho_p * vp;
  const double tau = s.rho_p * s.d * s.d / (18 * s.mu), dt = tau / steps_per_tau;
  const Vec3 g{0, 0, -kG};
  const Vec3 grad_p = s.rho_f * g;  // hydrostatic fluid at rest
  const Vec3 f_ext = m * g + pressure_gradient_force(vp, grad_p);
  const DragParams params = prepare_drag(key);
  std::optional<test::Dump> dump;
  if (!dump_name.empty()) dump.emplace(dump_name, "t,v");
  Vec3 v{};
  const int n = static_cast<int>(n_tau * steps_per_tau);
  for (int step = 0; step <= n; ++step) {
    if (dump && step % 10 == 0) dump->row(step * dt, -v.z);
    DragInput in;
    in.rho_f = s.rho_f;
    in.mu_f = s.mu;
    in.eps = 1.0;
    in.d_v = s.d;
    in.slip = -v;  // u_f - v_p with the fluid at rest
    const double beta = drag_force(params.law, in, params).beta;
    v = (m * v + dt * f_ext) / (m + dt * beta);
  }
  return -v.z;
}

}  // namespace

// The case: d = 100 um, rho_p = 3000, rho_f = 10 kg/m^3, nu = 1e-5 m^2/s (mu = 1e-4
// Pa s). Reference 0.13734 m/s (Re = 1.37, where the Schiller-Naumann correction is +19 %
// over Stokes' 0.1630 m/s). Required: 1 %; measured 0.137337 (-0.002 %). Schiller-Naumann and
// the laws that reduce to it at eps = 1 (wen_yu, gidaspow) are asserted. The others are other
// fits and differ by what their single-sphere limits differ at Re ~ 1.4 (checked to their
// measured values within 1 %, so a change shows): holzer_sommerfeld 0.13907 (+1.3 %: its
// sphere C_D is 1.5 % lower there), di_felice 0.12861 (-6.4 %: Dallavalle's C_D0 is 7 % above
// the standard curve at Re ~ 1), beetstra 0.14611 (+6.4 %: its phi -> 0 limit was fitted to
// arrays, not to the isolated sphere). Run for 20 response times: the residual of the
// relaxation is below 1e-9 (checked against 30).
TEST(DragValidation, TerminalVelocityGasMatchesReference) {
  const Settling s{100e-6, 3000, 10, 1e-4};
  const double ref = 0.13734;
  const std::map<std::string_view, double> others{
      {"holzer_sommerfeld", 0.13907}, {"di_felice", 0.12861}, {"beetstra", 0.14611}};
  for (const auto& info : drag_infos()) {
    const double v = settle(s, info.key, "drag_terminal_gas_" + std::string(info.key), 20);
    RecordProperty(std::string(info.key), std::to_string(v));
    if (info.key == "schiller_naumann" || info.key == "wen_yu" || info.key == "gidaspow") {
      EXPECT_NEAR(v / ref, 1.0, 0.01) << info.key << " v_t = " << v;
    } else {
      EXPECT_NEAR(v / others.at(info.key), 1.0, 0.01) << info.key << " v_t = " << v;
    }
  }
  EXPECT_NEAR(settle(s, "schiller_naumann", "", 30) / settle(s, "schiller_naumann", "", 20), 1.0,
              1e-9);
}

// Stokes regime: a 10 um glass sphere (2500 kg/m^3) in water (mu = 1e-3 Pa s). Stokes:
// v = (rho_p - rho_f) g d^2 / (18 mu) = 8.175e-5 m/s, Re = 8.2e-4. Schiller-Naumann's
// correction there is 0.15 Re^0.687 = 0.11 %, Oseen's first inertial correction 3/16 Re =
// 0.015 %: both far inside the required 1 %. Every law but di_felice is within 1 % (measured:
// schiller_naumann -0.12 %); di_felice is 3.4 % faster (Dallavalle's C_D0 Re = (0.63 sqrt(Re) +
// 4.8)^2 = 23.2 here instead of 24; 23.04 at Re -> 0), asserted within [+2 %, +5 %]. The
// transient follows v_St (1 - exp(-t/tau)), tau = rho_p d^2 / (18 mu), within 1 % of v_St
// (measured 0.11 %, the Schiller-Naumann correction; the implicit Euler error at dt = tau/1000
// is ~ 0.02 %). Added mass, which would lengthen tau by (1 + rho_f / (2 rho_p)) = 1.2 in water,
// is neglected on both sides.
TEST(DragValidation, TerminalVelocityStokesRegime) {
  const Settling s{10e-6, 2500, 1000, 1e-3};
  const double v_st = (s.rho_p - s.rho_f) * kG * s.d * s.d / (18 * s.mu);
  const double re = s.rho_f * v_st * s.d / s.mu;
  EXPECT_LT(re, 1e-3);
  for (const auto& info : drag_infos()) {
    const double v = settle(s, info.key, "drag_terminal_stokes_" + std::string(info.key));
    RecordProperty(std::string(info.key) + "_over_stokes", std::to_string(v / v_st));
    if (info.key == "di_felice") {
      EXPECT_NEAR(v / v_st, 1.035, 0.015) << info.key;
    } else {
      EXPECT_NEAR(v / v_st, 1.0, 0.01) << info.key << " v_t = " << v;
    }
  }
  // Transient against the analytic Stokes solution.
  const double vp = kPiD * s.d * s.d * s.d / 6, m = s.rho_p * vp;
  const double tau = s.rho_p * s.d * s.d / (18 * s.mu), dt = tau / 1000;
  const DragParams p = prepare_drag("schiller_naumann");
  double v = 0, worst = 0;
  for (int step = 1; step <= 5000; ++step) {
    DragInput in;
    in.rho_f = s.rho_f;
    in.mu_f = s.mu;
    in.d_v = s.d;
    in.slip = {0, 0, v};  // settling speed v downwards: u_f - v_p = +v along z
    const double beta = drag_force(p.law, in, p).beta;
    v = (m * v + dt * (s.rho_p - s.rho_f) * vp * kG) / (m + dt * beta);
    worst = std::max(worst, std::abs(v - v_st * (1 - std::exp(-step * dt / tau))) / v_st);
  }
  EXPECT_LT(worst, 0.01);
  RecordProperty("stokes_transient_max_error", std::to_string(worst));
}

// Curves of every law for the docs: the drag normalised by Stokes, f = beta / (3 pi mu d), vs
// Re at eps = 1 and vs eps at Re_e = 1 and 100; and Hoelzer-Sommerfeld's C_D for the L/d = 4
// spherocylinder end-on and broadside. Checked: the Stokes limit at eps = 1 (f -> 1 within
// 1 % at Re = 1e-3, di_felice 0.96), which every law must meet for the single-particle case.
TEST(DragValidation, LawCurvesForTheDocs) {
  const double rho = 1000, mu = 1e-3, d = 1e-3;
  auto f_of = [&](std::string_view key, double re_e, double eps) {
    DragInput in;
    in.rho_f = rho;
    in.mu_f = mu;
    in.eps = eps;
    in.d_v = d;
    const double u = re_e * mu / (eps * rho * d);  // interstitial slip for this Re_e
    in.slip = {u, 0, 0};
    const DragParams p = prepare_drag(key);
    return drag_force(p.law, in, p).beta / (3 * kPiD * mu * d);
  };
  for (const auto& info : drag_infos()) {
    const std::string k(info.key);
    {
      test::Dump dump("drag_curve_re_" + k, "re,f");
      for (double l = -2; l <= 4.0001; l += 0.05)
        dump.row(std::pow(10, l), f_of(k, std::pow(10, l), 1));
    }
    for (double re : {1.0, 100.0}) {
      test::Dump dump("drag_curve_eps_re" + std::to_string(int(re)) + "_" + k, "eps,f");
      for (double e = 0.4; e <= 1.00001; e += 0.01) dump.row(e, f_of(k, re, std::min(e, 1.0)));
    }
    const double stokes = f_of(k, 1e-3, 1);
    EXPECT_NEAR(stokes, k == "di_felice" ? 0.96 : 1.0, 0.01) << k;
  }
  const double r = 0.5e-3, l = 6 * r;
  test::Dump dump("drag_hs_rod", "re,cd_end_on,cd_broadside,cd_sphere");
  for (double lg = -1; lg <= 4.0001; lg += 0.05) {
    const double re = std::pow(10, lg);
    double cd[3];
    int q = 0;
    for (auto [axis, len] : {std::pair{Vec3{1, 0, 0}, l}, std::pair{Vec3{0, 1, 0}, l},
                             std::pair{Vec3{1, 0, 0}, 0.0}}) {
      const double dv = volume_equivalent_diameter(spherocylinder_volume(r, len));
      const double u = re * mu / (rho * dv);
      const DragInput in = spherocylinder_drag_input(rho, mu, 1, r, len, axis, {u, 0, 0});
      const DragParams p = prepare_drag("holzer_sommerfeld");
      cd[q++] = drag_force(p.law, in, p).beta * u / (0.5 * rho * u * u * kPiD * dv * dv / 4);
    }
    dump.row(re, cd[0], cd[1], cd[2]);
  }
}
