// SPDX-License-Identifier: GPL-3.0-or-later
// Two-fluid model against analytic references: batch sedimentation (Kynch's front speed and the
// sediment's weight), a packed bed (Ergun), a fluidised bed (the pressure drop carries the bed),
// homogeneous cooling of the granular energy (Haff) and Couette flow in the kinetic-theory
// steady state, with no-slip and Johnson-Jackson walls. Each run takes a second or two. Curves
// go to GF_VALIDATION_OUT for scripts/plot_two_fluid.py (docs/validation/two_fluid.png).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <vector>

#include "continuum/rheology_registry.hpp"
#include "continuum/two_fluid.hpp"
#include "coupling/cfd_dem/drag_registry.hpp"
#include "dump.hpp"

using namespace gf;
using namespace gf::continuum;

namespace {

constexpr double kG = 9.81;
constexpr double kPi = 3.14159265358979323846;

/// Glass beads of diameter d in water, gravity along -y, the dense-region closure on.
TwoFluidSettings beads_in_water(double d, const char* drag) {
  TwoFluidSettings s;
  s.fluid.density = 1000.0;
  s.fluid.dynamic_viscosity = 1e-3;
  s.fluid.gravity = {0.0, -kG, 0.0};
  s.ktgf = prepare_ktgf("syamlal",
                        {{"restitution", 0.9}, {"grain_diameter", d}, {"grain_density", 2500.0}});
  s.dense = prepare_frictional("schaeffer_johnson_jackson");
  s.drag = cfd_dem::prepare_drag(drag);
  s.fluid.boundary[0] = s.fluid.boundary[1] = fluid::BoundaryCondition::periodic();
  return s;
}

/// A 2D column: n_x cells periodic in x, n_y cells of size h, walls or the given conditions in y.
fluid::Grid column(int nx, int ny, double h) {
  fluid::Grid g;
  g.dimension = 2;
  g.n = {nx, ny, 1};
  g.h = {h, h, h};
  g.periodic = {true, false, false};
  return g;
}

/// Advances to time t_end with steps of at most dt_max (and 0.9 of the stable step).
void run_to(TwoFluidModel& m, double t_end, double dt_max,
            const std::function<void(const TwoFluidReport&)>& each = {}) {
  while (m.time() < t_end - 1e-12) {
    const double dt = std::min({0.9 * m.stable_dt(), dt_max, t_end - m.time()});
    const TwoFluidReport r = m.step(dt);
    if (each) each(r);
  }
}

/// Root of f on [lo, hi] by bisection (f(lo) < 0 < f(hi)).
double bisect(const std::function<double(double)>& f, double lo, double hi) {
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

/// Per-grain drag coefficient beta_p [N s/m] of the settings' law at fluid fraction eps and slip.
double beta_p(const TwoFluidSettings& s, double eps, double slip) {
  cfd_dem::DragInput in;
  in.rho_f = s.fluid.density;
  in.mu_f = s.fluid.dynamic_viscosity;
  in.eps = eps;
  in.d_v = s.ktgf.diameter;
  in.slip = {slip, 0, 0};
  return cfd_dem::drag_force(s.drag.law, in, s.drag).beta;
}

/// The interstitial slip of a suspension at fluid fraction eps whose grains are carried by the
/// drag (model A): beta_p slip = V_p eps (rho_s - rho_f) g.
double equilibrium_slip(const TwoFluidSettings& s, double eps) {
  const double d = s.ktgf.diameter, vp = kPi * d * d * d / 6.0;
  const double w = vp * eps * (s.ktgf.density - s.fluid.density) * kG;
  return bisect([&](double u) { return beta_p(s, eps, u) * u - w; }, 0.0, 10.0);
}

/// y of the upper edge of the suspension: where a crosses level going up column x = 0.
double front(const TwoFluidModel& m, double level) {
  const auto& g = m.grid();
  const auto a = m.solids_fraction();
  double y = 0.0;
  for (int j = 0; j + 1 < g.n[1]; ++j) {
    const double a0 = a[g.index(0, j, 0)], a1 = a[g.index(0, j + 1, 0)];
    if (a0 >= level && a1 < level) y = (j + 0.5 + (a0 - level) / (a0 - a1)) * g.h.y;
  }
  return y;
}

}  // namespace

// Batch sedimentation of a uniform suspension in a closed column (Kynch 1952): the upper front
// between clear liquid and suspension falls at the hindered settling speed u_s(a0) of the
// suspension, which the drag law fixes: in a closed column eps u_f + a u_s = 0, so the slip is
// -u_s / eps and the force balance of the grains gives beta_p slip = V_p eps (rho_s - rho_f) g.
// 200 um glass beads in water at a0 = 0.2, cells of 5 d: the front is a self-sharpening shock
// (upwind smears it over ~2 cells, but it keeps its speed), so its speed, fitted over 4 s (37 mm of
// travel), must match u_s within 1 % (measured: -0.06 %); the sediment comes to rest and its
// solids pressure carries its buoyant weight; the solids volume is conserved to round-off.
TEST(ValidationTwoFluid, BatchSedimentationFollowsKynch) {
  TwoFluidSettings s = beads_in_water(2e-4, "di_felice");
  const fluid::Grid g = column(4, 80, 1e-3);
  TwoFluidModel m(g, s);
  const double a0 = 0.2, h0 = 0.07;
  m.set_solids([&](const Vec3& x) { return x.y < h0 ? a0 : 0.0; });
  const double v0 = m.solids_volume();
  const double eps0 = 1.0 - a0;
  const double u_hs = eps0 * equilibrium_slip(s, eps0);
  // The single grain (eps -> 1) and Richardson & Zaki's exponent (Rowe 1987) for comparison.
  const double u_t = equilibrium_slip(s, 1.0 - 1e-9);
  const double re_t = s.fluid.density * u_t * s.ktgf.diameter / s.fluid.dynamic_viscosity;
  const double n_rz = (4.7 + 0.41 * std::pow(re_t, 0.75)) / (1.0 + 0.175 * std::pow(re_t, 0.75));
  double clipped = 0.0, clipped_net = 0.0;
  test::Dump history("two_fluid_sedimentation_front", "t,front,kynch");
  double next = 0.0;
  auto count = [&](const TwoFluidReport& r) {
    clipped += std::abs(r.clipped_volume);
    clipped_net += r.clipped_volume;
    if (m.time() >= next - 1e-12) {
      history.row(m.time(), front(m, 0.5 * a0), h0 - u_hs * m.time());
      next += 0.05;
    }
  };
  run_to(m, 0.5, 2e-3, count);
  const double y1 = front(m, 0.5 * a0);
  run_to(m, 4.5, 2e-3, count);
  const double y2 = front(m, 0.5 * a0);
  const double speed = (y1 - y2) / 4.0;
  std::printf(
      "front speed %.6f m/s, Kynch (di_felice) %.6f m/s (%+.3f %%); u_t %.5f m/s, Re_t "
      "%.2f, u_hs/u_t %.4f, Richardson-Zaki eps^n %.4f (n = %.3f)\n",
      speed, u_hs, 100 * (speed / u_hs - 1), u_t, re_t, u_hs / u_t, std::pow(eps0, n_rz), n_rz);
  EXPECT_NEAR(speed / u_hs, 1.0, 0.01);
  // Di Felice's voidage function against Richardson & Zaki's correlation: within 10 % here
  // (the two fits to hindered-settling data differ by that much at Re_t ~ 5).
  EXPECT_NEAR(u_hs / u_t / std::pow(eps0, n_rz), 1.0, 0.10);
  run_to(m, 7.0, 2e-3, count);
  // The sediment at rest: solids pressure difference between cells 0 and 15 (well inside the
  // sediment, which ends near cell 24) against the buoyant weight of the grains between their
  // centres (trapezoid over cells: 0.5 %), and no grain moving faster than 1e-5 m/s there.
  const double drho_g = (s.ktgf.density - s.fluid.density) * kG;
  double w = 0.0, umax = 0.0;
  for (int j = 0; j <= 15; ++j) {
    const double a = m.solids_fraction()[g.index(0, j, 0)];
    w += (j == 0 || j == 15 ? 0.5 : 1.0) * a * g.h.y * drho_g;
    umax = std::max(umax, std::abs(m.solids_velocity(g.index(0, j, 0)).y));
  }
  const auto ps = m.solids_pressure();
  const double dps = ps[g.index(0, 0, 0)] - ps[g.index(0, 15, 0)];
  std::printf(
      "sediment: P_s(0) - P_s(15) %.4f Pa, buoyant weight between %.4f Pa (%+.3f %%), max "
      "|u_s| %.2e m/s, a(floor) %.4f; clipped %.2e of the volume\n",
      dps, w, 100 * (dps / w - 1), umax, m.solids_fraction()[0], clipped / v0);
  EXPECT_NEAR(dps / w, 1.0, 5e-3);
  EXPECT_LT(umax, 1e-5);
  {
    test::Dump profile("two_fluid_sediment_profile", "y,alpha,solids_pressure,weight_above");
    double above = 0.0;
    for (int j = g.n[1] - 1; j >= 0; --j) {
      const double a = m.solids_fraction()[g.index(0, j, 0)];
      const double wj = above + 0.5 * a * g.h.y * drho_g;
      profile.row((j + 0.5) * g.h.y, a, ps[g.index(0, j, 0)], wj);
      above += a * g.h.y * drho_g;
    }
  }
  // Conservation to round-off of what the fluxes move; the implicit pressure increment's flux at
  // the upper front draws a trace from the clear cells above (a mean fraction of the face), which
  // the clip of a at 0 restores and reports: measured 1.4e-11 of the volume over the run.
  EXPECT_NEAR((m.solids_volume() - clipped_net) / v0, 1.0, 1e-12);
  EXPECT_LT(clipped, 1e-10 * v0);
}

// A packed bed below minimum fluidisation stays at rest, and the liquid's pressure gradient
// through it is Ergun's (the Gidaspow drag law is Ergun's below eps = 0.8):
//   -dp/dy - rho_f g = 150 mu a^2 U / (eps^3 d^2) + 1.75 rho_f a U^2 / (eps^3 d).
// The bed is uniform, so the discrete gradient has no truncation error: 0.1 % (the drag at the
// face is the mean of two equal cells; measured 1e-6). Then above minimum fluidisation the bed
// lifts, and the mean pressure drop over it equals the weight of the mixture it carries (the
// momentum balance of the column: 1 %, the time-averaged acceleration of the bubbling bed).
TEST(ValidationTwoFluid, PackedBedFollowsErgunThenFluidises) {
  TwoFluidSettings s = beads_in_water(5e-4, "gidaspow");
  s.dense.max_viscosity = 1.0;  // Pa s: a lighter frictional plug (default 100 Pa s)
  const fluid::Grid g = column(2, 60, 2e-3);
  const double a0 = 0.55, d = 5e-4, mu = 1e-3, rho = 1000.0;
  const double eps = 1.0 - a0;
  // Ergun's minimum fluidisation: the pressure gradient equals the buoyant weight a (rho_s -
  // rho_f) g.
  auto ergun_at = [&](double a, double u) {
    const double e = 1.0 - a;
    return 150 * mu * a * a * u / (e * e * e * d * d) + 1.75 * rho * a * u * u / (e * e * e * d);
  };
  auto ergun = [&](double u) { return ergun_at(a0, u); };
  const double weight = a0 * (2500.0 - rho) * kG;
  const double u_mf = bisect([&](double u) { return ergun(u) - weight; }, 0.0, 1.0);
  for (const double ratio : {0.5, 2.0}) {
    const double U = ratio * u_mf;
    s.fluid.boundary[2] = fluid::BoundaryCondition::velocity_inlet(Vec3{0, U, 0}, true);
    s.fluid.boundary[3] = fluid::BoundaryCondition::pressure_outlet(0.0);
    TwoFluidModel m(g, s);
    m.set_solids([&](const Vec3& x) { return x.y < 0.03 ? a0 : 0.0; });
    m.fluid().set_velocity([&](const Vec3& x) { return Vec3{0, x.y < 0.03 ? U / eps : U, 0}; });
    auto drop = [&](int j0, int j1) {  // p(j0) - p(j1) and the mixture weight between the centres
      const auto p = m.fluid().pressure();
      const auto a = m.solids_fraction();
      double w = 0.0;
      for (int j = j0; j <= j1; ++j) {
        const double half = (j == j0 || j == j1) ? 0.5 : 1.0;
        const double aj = a[g.index(0, j, 0)];
        w += half * g.h.y * kG * (rho + aj * (2500.0 - rho));
      }
      return std::pair{p[g.index(0, j0, 0)] - p[g.index(0, j1, 0)], w};
    };
    if (ratio < 1) {
      run_to(m, 3.0, 2e-3);
      // The bed settles a little (its frictional pressure must carry what the drag does not),
      // so Ergun is evaluated with each cell's fraction and integrated between cells 2 and 10.
      const auto pr = m.fluid().pressure();
      const auto af = m.solids_fraction();
      double ref = 0.0, umax = 0.0;
      for (int j = 2; j <= 10; ++j) {
        const double aj = af[g.index(0, j, 0)];
        ref += (j == 2 || j == 10 ? 0.5 : 1.0) * g.h.y * (ergun_at(aj, U) + rho * kG);
        umax = std::max(umax, norm(m.solids_velocity(g.index(0, j, 0))));
      }
      const double dp = pr[g.index(0, 2, 0)] - pr[g.index(0, 10, 0)];
      std::printf(
          "U/U_mf %.1f (U_mf %.5f m/s): p(2) - p(10) = %.4f Pa, Ergun + hydrostatic %.4f "
          "(%+.2e), a(6) %.4f, max |u_s| %.2e m/s\n",
          ratio, u_mf, dp, ref, dp / ref - 1, af[g.index(0, 6, 0)], umax);
      EXPECT_NEAR(dp / ref, 1.0, 1e-3);
      EXPECT_LT(umax, 1e-5);
      test::Dump bed("two_fluid_packed_bed", "y,alpha,pressure,ergun_gradient");
      for (int j = 0; j < g.n[1]; ++j)
        bed.row((j + 0.5) * g.h.y, af[g.index(0, j, 0)], pr[g.index(0, j, 0)],
                ergun_at(std::min(af[g.index(0, j, 0)], 0.6), U) + rho * kG);
    } else {
      run_to(m, 1.0, 2e-3);
      double dp = 0.0, w = 0.0;
      int n = 0;
      test::Dump series("two_fluid_fluidised_bed", "t,pressure_drop,mixture_weight,bed_top");
      run_to(m, 3.0, 2e-3, [&](const TwoFluidReport&) {
        const auto [a, b] = drop(0, 50);
        dp += a;
        w += b;
        ++n;
        series.row(m.time(), a, b, front(m, 0.2));
      });
      std::printf("U/U_mf %.1f: mean pressure drop %.3f Pa, mixture weight %.3f Pa (%+.3f %%)\n",
                  ratio, dp / n, w / n, 100 * (dp / w - 1));
      EXPECT_NEAR(dp / w, 1.0, 0.01);
      // The bed has expanded: its mean fraction is below the packed a0.
      double top = front(m, 0.2);
      EXPECT_GT(top, 0.03);
    }
  }
}

// Homogeneous cooling (Haff 1983) with the granular energy balance: in a periodic box at rest the
// energy equation is (3/2) a rho_s dTheta/dt = -gamma_s, whose solution is
// Theta0 / (1 + t / tau)^2 (continuum::haff_temperature). The implicit step linearises gamma_s in
// Theta; with dt = tau / 400 its error is below 0.2 % (measured +0.09 % at tau and 3 tau).
TEST(ValidationTwoFluid, HomogeneousCoolingFollowsHaff) {
  TwoFluidSettings s;
  s.fluid.density = 1.2;
  s.fluid.dynamic_viscosity = 1e-12;  // no gas damping 3 beta Theta
  s.ktgf = prepare_ktgf(
      "lun", {{"restitution", 0.8}, {"grain_diameter", 1e-3}, {"grain_density", 2500.0}});
  s.frictional = false;
  s.drag = cfd_dem::prepare_drag("wen_yu");
  s.temperature = GranularTemperature::Transport;
  fluid::Grid g;
  g.dimension = 2;
  g.n = {4, 4, 1};
  g.h = {1e-2, 1e-2, 1e-2};
  g.periodic = {true, true, false};
  for (int f = 0; f < 4; ++f) s.fluid.boundary[f] = fluid::BoundaryCondition::periodic();
  TwoFluidModel m(g, s);
  const double a = 0.3, theta0 = 0.01;
  m.set_solids([&](const Vec3&) { return a; }, theta0);
  const double tau = haff_time(a, theta0, s.ktgf);
  test::Dump curve("two_fluid_haff", "t_over_tau,theta,haff");
  for (int k = 1; k <= 30; ++k) {
    run_to(m, 0.1 * k * tau, tau / 400);
    const double ref = haff_temperature(a, theta0, m.time(), s.ktgf);
    const double th = m.granular_temperature()[5];
    curve.row(0.1 * k, th, ref);
    if (k % 10 != 0 || k == 20) continue;  // checked at tau and 3 tau
    std::printf("t = %d tau: Theta %.6e, Haff %.6e (%+.3f %%)\n", k / 10, th, ref,
                100 * (th / ref - 1));
    EXPECT_NEAR(th / ref, 1.0, 2e-3);
  }
}

// Couette flow of a granular phase between walls sliding at -U and +U (the fluid moves with them,
// so there is no slip and no drag): the kinetic-theory steady state of simple shear has a linear
// profile, uniform a, and Theta = (mu_s(a, 1) / gamma_s(a, 1)) gamma_dot^2 (ktgf_simple_shear).
// With no-slip walls gamma_dot = 2 U / H. With Johnson-Jackson walls the wall stress C u_slip
// equals mu_s gamma_dot, and since mu_s and C both scale as sqrt(Theta) ~ gamma_dot, u_slip /
// gamma_dot = mu_s / C is a constant: gamma_dot = U / (H / 2 + mu_s / C). The algebraic temperature
// is exact for this state; the run starts from the analytic state and must keep it (the stencils,
// the wall ghost values and the closures agree with the theory to round-off: 1e-9 in u, 1e-8 in
// Theta).
TEST(ValidationTwoFluid, CouetteFlowIsTheKineticTheoryState) {
  for (const bool jj : {false, true}) {
    TwoFluidSettings s;
    s.fluid.density = 1.2;
    s.fluid.dynamic_viscosity = 1.8e-5;
    s.ktgf = prepare_ktgf(
        "syamlal", {{"restitution", 0.8}, {"grain_diameter", 1e-3}, {"grain_density", 2500.0}});
    s.frictional = false;
    s.drag = cfd_dem::prepare_drag("wen_yu");
    // A gas of negligible viscosity: the theory's state has no gas damping 3 beta Theta.
    s.fluid.dynamic_viscosity = 1e-12;
    const double U = 0.5, H = 0.02, a = 0.3;
    fluid::Grid g;
    g.dimension = 2;
    g.n = {2, 20, 1};
    g.h = {1e-3, H / 20, 1e-3};
    g.periodic = {true, false, false};
    s.fluid.boundary[0] = s.fluid.boundary[1] = fluid::BoundaryCondition::periodic();
    s.fluid.boundary[2] = fluid::BoundaryCondition::moving_wall(Vec3{-U, 0, 0});
    s.fluid.boundary[3] = fluid::BoundaryCondition::moving_wall(Vec3{U, 0, 0});
    if (jj) {
      s.solids_wall[2] = s.solids_wall[3] = SolidsWall::JohnsonJackson;
      s.specularity = 0.3;
    }
    TwoFluidModel m(g, s);
    double gd = 2 * U / H;
    if (jj) {
      const KtgfProperties p1 = ktgf_properties(a, 1.0, s.ktgf);
      const double c1 = kPi * std::sqrt(3.0) / 6.0 * s.specularity * (a / m.packing_fraction()) *
                        s.ktgf.density * p1.g0;
      gd = U / (H / 2 + p1.shear_viscosity / c1);
    }
    const KtgfShearState ref = ktgf_simple_shear(a, gd, s.ktgf);
    TwoFluidModel run(g, s);
    run.set_solids([&](const Vec3&) { return a; }, ref.temperature);
    run.set_solids_velocity([&](const Vec3& x) { return Vec3{gd * (x.y - H / 2), 0, 0}; });
    run.fluid().set_velocity([&](const Vec3& x) { return Vec3{gd * (x.y - H / 2), 0, 0}; });
    for (int i = 0; i < 200; ++i) {
      run.step(1e-5);
      if (std::getenv("DBG") && i < 3) {
        for (int j = 0; j < g.n[1]; j += 3)
          std::printf("  j %d u %.6f ref %.6f th %.6g a %.6f uy %.3g\n", j,
                      run.solids_velocity(g.index(1, j, 0)).x, gd * ((j + 0.5) * g.h.y - H / 2),
                      run.granular_temperature()[g.index(1, j, 0)],
                      run.solids_fraction()[g.index(1, j, 0)],
                      run.solids_velocity(g.index(1, j, 0)).y);
        std::printf("  theta ref %.6g\n", ref.temperature);
      }
    }
    double err_u = 0.0, err_t = 0.0, err_a = 0.0;
    for (int j = 0; j < g.n[1]; ++j) {
      const std::int64_t c = g.index(1, j, 0);
      const double y = (j + 0.5) * g.h.y;
      err_u = std::max(err_u, std::abs(run.solids_velocity(c).x - gd * (y - H / 2)) / U);
      err_t = std::max(err_t, std::abs(run.granular_temperature()[c] / ref.temperature - 1));
      err_a = std::max(err_a, std::abs(run.solids_fraction()[c] - a));
    }
    const double tau = run.solids_viscosity()[g.index(0, 10, 0)] * gd;
    std::printf(
        "%s walls: gamma_dot %.4f 1/s, errors u %.2e, Theta %.2e, a %.2e; shear stress "
        "%.6f Pa vs %.6f\n",
        jj ? "Johnson-Jackson" : "no-slip", gd, err_u, err_t, err_a, tau, ref.shear_stress);
    test::Dump prof(jj ? "two_fluid_couette_jj" : "two_fluid_couette_noslip",
                    "y,u,u_theory,theta,theta_theory");
    for (int j = 0; j < g.n[1]; ++j) {
      const std::int64_t c = g.index(1, j, 0);
      const double y = (j + 0.5) * g.h.y;
      prof.row(y, run.solids_velocity(c).x, gd * (y - H / 2), run.granular_temperature()[c],
               ref.temperature);
    }
    EXPECT_LT(err_u, 1e-9);
    EXPECT_LT(err_t, 1e-8);
    EXPECT_LT(err_a, 1e-12);
    EXPECT_NEAR(tau / ref.shear_stress, 1.0, 1e-9);
  }
}

// The seed's regime switch in the two-fluid model: a dense layer flowing down a rough incline
// (angle theta) under the mu(I) rheology (Jop, Forterre & Pouliquen 2006; GDR MiDi 2004) with the
// seed's logarithmic pressure. In the steady uniform flow the shear stress is the weight of the
// grains above, tau(y) = sin(theta) W(y), and the normal stress carries it, P(y) = cos(theta) W(y);
// the rheology gives mu(I) = tan(theta) everywhere and gamma_dot = I sqrt(P / rho_s) / d, so
//   u(y) = int_0^y I(tan theta) sqrt(cos(theta) W(y') / rho_s) / d dy'
// (Bagnold's profile, u ~ h^1.5 - (h - y)^1.5; trapezoids over half cells with the model's
// fraction profile in W). Tolerance 3 % of the speed at 0.8 h, over the lower 80 % of the layer
// (the smeared surface cell aside): the first-order upwind convection, the half-cell shear at the
// no-slip base and what is left of the start at t = 3 s (+0.7 % from 3 s to 4 s) are the errors
// (measured 0.3 %). The closure pressure P_s of the stiff logarithmic law (dP/da = 4e4 Pa) jitters
// by ~1 % around the weight from step to step; the implicit pressure increment carries the
// difference, so mu(I) evaluated at the closure pressure alone (I changes by 8 % per 1 % of P at
// this angle) is no reference; it is dumped for the record.
TEST(ValidationTwoFluid, DenseLayerOnAnInclineFollowsMuI) {
  TwoFluidSettings s;
  s.fluid.density = 1e-2;  // a tenuous gas: drag negligible
  s.fluid.dynamic_viscosity = 1e-7;
  const double theta = 25.0 * kPi / 180.0, d = 5e-4, rho_s = 2500.0;
  s.fluid.gravity = {kG * std::sin(theta), -kG * std::cos(theta), 0.0};
  s.ktgf = prepare_ktgf("syamlal",
                        {{"restitution", 0.8}, {"grain_diameter", d}, {"grain_density", rho_s}});
  s.dense = prepare_frictional("mu_i_switch", {{"frictional_limit", 0.5}});
  s.dense_rheology = prepare_rheology(
      "mu_i", {{"grain_diameter", d}, {"grain_density", rho_s}, {"max_viscosity", 50.0}});
  s.log_pressure = {2000.0, 0.55, 0.6};
  s.drag = cfd_dem::prepare_drag("wen_yu");
  fluid::Grid g = column(2, 40, 5e-4);
  s.fluid.boundary[0] = s.fluid.boundary[1] = fluid::BoundaryCondition::periodic();
  s.fluid.boundary[3] = fluid::BoundaryCondition::pressure_outlet(0.0);
  s.solids_wall[2] = SolidsWall::NoSlip;
  TwoFluidModel m(g, s);
  const double h = 0.01;
  m.set_solids([&](const Vec3& x) { return x.y < h ? 0.56 : 0.0; }, 1e-6);
  run_to(m, 3.0, 1e-3);
  // mu(I) = tan(theta) (pure mu(I), Bagnold) and I of mu = tau / P (the model's pressure).
  auto i_of = [](double mu) { return 0.279 * (mu - 0.382) / (0.643 - mu); };
  const double i_bagnold = i_of(std::tan(theta));
  const auto a = m.solids_fraction();
  const auto ps = m.solids_pressure();
  std::vector<double> w(static_cast<std::size_t>(g.n[1]) + 1, 0.0);  // weight above each face
  for (int j = g.n[1] - 1; j >= 0; --j) w[j] = w[j + 1] + a[g.index(0, j, 0)] * rho_s * kG * g.h.y;
  // gamma_dot at a level with weight ww above and pressure pp
  auto rate = [&](double ww, double pp) {
    if (!(pp > 0)) return 0.0;
    const double mu = std::min(std::sin(theta) * ww / pp, 0.64);
    return mu > 0.382 ? i_of(mu) * std::sqrt(pp / rho_s) / d : 0.0;
  };
  double u_ref = 0.0, u_bag = 0.0, err = 0.0, u_top = 0.0, u_ref_top = 0.0;
  test::Dump prof("two_fluid_incline", "y,alpha,u,u_mu_i,u_bagnold,pressure,weight_pressure");
  for (int j = 0; j < g.n[1]; ++j) {
    // the pressure on the faces: the mean of the two cells (the floor: extrapolated)
    const double pc = ps[g.index(0, j, 0)];
    const double p_lo =
        j == 0 ? pc + 0.5 * (pc - ps[g.index(0, 1, 0)]) : 0.5 * (pc + ps[g.index(0, j - 1, 0)]);
    const double p_hi = j + 1 < g.n[1] ? 0.5 * (pc + ps[g.index(0, j + 1, 0)]) : 0.0;
    const double wc = 0.5 * (w[j] + w[j + 1]);
    u_ref += 0.25 * g.h.y * (rate(w[j], p_lo) + rate(wc, pc));
    const double cth = std::cos(theta);
    u_bag += 0.25 * g.h.y * (i_bagnold / d) *
             (std::sqrt(cth * w[j] / rho_s) + std::sqrt(cth * wc / rho_s));
    const double u = m.solids_velocity(g.index(0, j, 0)).x;
    prof.row((j + 0.5) * g.h.y, a[g.index(0, j, 0)], u, u_ref, u_bag, pc, cth * wc);
    if ((j + 0.5) * g.h.y < 0.8 * h) {
      err = std::max(err, std::abs(u - u_bag));
      u_top = u_bag;
      u_ref_top = u_ref;
    }
    u_ref += 0.25 * g.h.y * (rate(wc, pc) + rate(w[j + 1], p_hi));
    u_bag += 0.25 * g.h.y * (i_bagnold / d) *
             (std::sqrt(cth * wc / rho_s) + std::sqrt(cth * w[j + 1] / rho_s));
  }
  std::printf(
      "incline %.0f deg: u at 0.8 h %.4f m/s, Bagnold (pressure = weight, I = %.4f) %.4f (max "
      "error %.2f %%); mu(I) at the closure pressure %.4f; a(base) %.4f\n",
      theta * 180 / kPi, m.solids_velocity(g.index(0, 15, 0)).x, i_bagnold, u_top,
      100 * err / u_top, u_ref_top, a[0]);
  EXPECT_LT(err, 0.03 * u_top);
}
// A gas-fluidised column (500 um glass beads in air, Geldart B, 2 U_mf): the bed does not expand
// smoothly as in a liquid but slugs (the bed lifts as a plug, collapses, lifts again; its top
// moves between 0.12 and 0.25 m), so the pressure drop swings by +-30 % from step to step. Over
// time the column's momentum balance fixes its mean: mean(p(0) - p(top)) = W + dM/dt, W the weight
// of the mixture between the two cell centres and M the momentum of the two phases between them.
// The discrete momentum is conserved (the drag summed over faces is the same for both phases, the
// solids stresses are gradients of cell quantities), so the mean must match within the few Pa
// the floor cell's solids stress and the sampling add (1 % asserted; measured -0.8 % for the
// pressure drop alone, of which -0.85 % is the column's momentum change over the window). An
// earlier implicit solids pressure, (dP_s/da)_face grad(delta), was not a gradient and loaded the
// bed with +26 % at dt = 5e-4 s (+3.7 % at 1e-4 s).
TEST(ValidationTwoFluid, GasFluidisedColumnCarriesItsWeight) {
  TwoFluidSettings s;
  s.fluid.density = 1.2;
  s.fluid.dynamic_viscosity = 1.8e-5;
  s.fluid.gravity = {0.0, -kG, 0.0};
  const double d = 5e-4, rho_s = 2500.0, mu = 1.8e-5, rho = 1.2;
  s.ktgf = prepare_ktgf("syamlal",
                        {{"restitution", 0.9}, {"grain_diameter", d}, {"grain_density", rho_s}});
  s.dense = prepare_frictional("schaeffer_johnson_jackson");
  s.drag = cfd_dem::prepare_drag("gidaspow");
  s.fluid.boundary[0] = s.fluid.boundary[1] = fluid::BoundaryCondition::periodic();
  const double h = 2.5e-3;
  const int nx = 2, ny = 100;
  const fluid::Grid g = column(nx, ny, h);
  const double a0 = 0.55, eps0 = 1.0 - a0;
  auto ergun = [&](double u) {
    return 150 * mu * a0 * a0 * u / (eps0 * eps0 * eps0 * d * d) +
           1.75 * rho * a0 * u * u / (eps0 * eps0 * eps0 * d);
  };
  const double u_mf = bisect([&](double u) { return ergun(u) - a0 * (rho_s - rho) * kG; }, 0, 5);
  const double U = 2.0 * u_mf;
  s.fluid.boundary[2] = fluid::BoundaryCondition::velocity_inlet(Vec3{0, U, 0}, true);
  s.fluid.boundary[3] = fluid::BoundaryCondition::pressure_outlet(0.0);
  TwoFluidModel m(g, s);
  m.set_solids([&](const Vec3& x) { return x.y < 0.1 ? a0 : 0.0; });
  m.fluid().set_velocity([&](const Vec3& x) { return Vec3{0, x.y < 0.1 ? U / eps0 : U, 0}; });
  auto momentum = [&]() {  // per unit area, faces 1 .. ny - 1
    const auto us = m.solids_face_velocity(1);
    const auto uf = m.fluid().face_velocity(1);
    const auto a = m.solids_fraction();
    double sum = 0.0;
    for (int i = 0; i < nx; ++i)
      for (int j = 1; j < ny; ++j) {
        const double af = 0.5 * (a[g.index(i, j - 1, 0)] + a[g.index(i, j, 0)]);
        const auto f = g.face_index(1, i, j, 0);
        sum += (af * rho_s * us[f] + (1.0 - af) * rho * uf[f]) * h / nx;
      }
    return sum;
  };
  double dp = 0.0, w = 0.0, m0 = 0.0, t0 = 0.0;
  int n = 0;
  test::Dump series("two_fluid_gas_column", "t,pressure_drop,mixture_weight,bed_top");
  run_to(m, 0.5, 5e-4);
  m0 = momentum();
  t0 = m.time();
  run_to(m, 2.0, 5e-4, [&](const TwoFluidReport&) {
    const auto p = m.fluid().pressure();
    const auto a = m.solids_fraction();
    double drop = 0.0, wt = 0.0;
    for (int i = 0; i < nx; ++i) {
      drop += (p[g.index(i, 0, 0)] - p[g.index(i, ny - 1, 0)]) / nx;
      for (int j = 0; j < ny; ++j)
        wt += (j == 0 || j == ny - 1 ? 0.5 : 1.0) * h * kG *
              (rho + a[g.index(i, j, 0)] * (rho_s - rho)) / nx;
    }
    dp += drop;
    w += wt;
    ++n;
    series.row(m.time(), drop, wt, front(m, 0.2));
  });
  const double rate = (momentum() - m0) / (m.time() - t0);
  dp /= n;
  w /= n;
  std::printf(
      "gas column at 2 U_mf (U_mf %.4f m/s): mean pressure drop %.2f Pa, mixture weight %.2f Pa "
      "(%+.2f %%), momentum change %.2f Pa: balance %+.3f %% of the weight\n",
      u_mf, dp, w, 100 * (dp / w - 1), rate, 100 * (dp - w - rate) / w);
  EXPECT_NEAR(dp, w + rate, 0.01 * w);
  EXPECT_NEAR(dp / w, 1.0, 0.02);
}

// A liquid-fluidised bed expands uniformly (glass beads in water, Geldart's particulate regime):
// at a superficial velocity U above U_mf the grains float where the drag carries their buoyant
// weight, Ergun(a, U) = a (rho_s - rho_f) g, which fixes one fraction a* for the whole bed and
// its height a0 h0 / a*. Without a particle pressure nothing in the model resists a disturbance
// of the fraction below the frictional limit (Theta ~ 0 in a liquid bed), and the faces, which
// see the mean of two cells, cannot see an odd-even pattern: the bed keeps alternating cells
// about 10 % above and below a* that never settle (measured with particle_pressure none: 11 %
// at h = 2 mm, 14 % at 1 mm, grains still moving at 0.5-2 mm/s after 6 s). With Gidaspow &
// Ettehadieh's elastic modulus G = dP_e/da (4.7 Pa at a*) the pattern is no longer neutral. What
// remains is a steady one seeded by the surface cell (its upper face sees an empty cell, so its
// drag and weight differ from the interior's) and it decays into the bed at a rate the
// linearised face balance predicts: with F(a) = Ergun(a, U) - a (rho_s - rho_f) g at the face
// mean of two cells and the modulus's gradient G (a_{j+1} - a_j) / h, a deviation
// d_{j+1} = -q d_j solves F' (d_j + d_{j+1}) / 2 = G (d_{j+1} - d_j) / h, i.e.
// q = (F' h + 2 G) / (F' h - 2 G): 1.20 per cell at h = 2 mm, 1.45 at 1 mm (a discretisation
// pattern that vanishes with h). Asserted: the bed below its three top cells at rest (1e-5 m/s),
// its top at the uniform height within a quarter cell, the deviations alternating with the
// predicted ratio (5 %: the linearisation, and a fit over cells whose deviation is 1e-4 to 5 % of
// a*), and at 1 mm the lower half within 0.1 % of a* (measured 0.02 %).
TEST(ValidationTwoFluid, LiquidFluidisedBedExpandsUniformly) {
  const double h0 = 0.03, a0 = 0.55, d = 5e-4, mu = 1e-3, rho = 1000.0, rho_s = 2500.0;
  auto ergun_at = [&](double a, double u) {
    const double e = 1.0 - a;
    return 150 * mu * a * a * u / (e * e * e * d * d) + 1.75 * rho * a * u * u / (e * e * e * d);
  };
  auto excess = [&](double a, double u) { return ergun_at(a, u) - a * (rho_s - rho) * kG; };
  const double u_mf = bisect([&](double u) { return excess(a0, u); }, 0.0, 1.0);
  const double U = 2.0 * u_mf;
  // The drag grows faster than the weight as the bed packs: one root below a0.
  const double a_star = bisect([&](double a) { return excess(a, U); }, 0.2, a0);
  const double h_star = a0 * h0 / a_star;
  const double slope_f = (excess(a_star + 1e-6, U) - excess(a_star - 1e-6, U)) / 2e-6;
  for (const double h : {2e-3, 1e-3}) {
    TwoFluidSettings s = beads_in_water(d, "gidaspow");
    s.dense.max_viscosity = 1.0;  // Pa s, as in PackedBedFollowsErgunThenFluidises
    s.particle_pressure = prepare_particle_pressure("gidaspow_ettehadieh");
    const fluid::Grid g = column(2, static_cast<int>(std::lround(0.12 / h)), h);
    s.fluid.boundary[2] = fluid::BoundaryCondition::velocity_inlet(Vec3{0, U, 0}, true);
    s.fluid.boundary[3] = fluid::BoundaryCondition::pressure_outlet(0.0);
    TwoFluidModel m(g, s);
    m.set_solids([&](const Vec3& x) { return x.y < h0 ? a0 : 0.0; });
    m.fluid().set_velocity([&](const Vec3& x) { return Vec3{0, x.y < h0 ? U / (1 - a0) : U, 0}; });
    run_to(m, 6.0, 2e-3);
    const double modulus = m.closures(a_star, 0.0, 0.0, 0.0).pressure_slope;
    const double q = (slope_f * h + 2 * modulus) / (slope_f * h - 2 * modulus);
    const auto a = m.solids_fraction();
    const double top = front(m, 0.5 * a_star);
    const int n_bed = static_cast<int>(h_star / h);  // cells wholly inside the uniform bed
    double umax = 0.0, lower = 0.0, log_ratio = 0.0;
    int n_ratio = 0;
    bool alternates = true;
    test::Dump profile(h > 1.5e-3 ? "two_fluid_liquid_bed_2mm" : "two_fluid_liquid_bed_1mm",
                       "y,alpha,alpha_uniform");
    for (int j = 0; j < g.n[1]; ++j) {
      const double y = (j + 0.5) * h, dev = a[g.index(0, j, 0)] / a_star - 1.0;
      profile.row(y, a[g.index(0, j, 0)], j < n_bed ? a_star : 0.0);
      if (j >= n_bed) continue;
      // (the surface cell's upper face carries the free fall of the empty cell above, and at
      // h = 2 mm the surface breathes slowly: 1.5e-4 m/s in the cell below it, 8e-6 in the next)
      if (j + 3 < n_bed) umax = std::max(umax, norm(m.solids_velocity(g.index(0, j, 0))));
      if (y < 0.5 * h_star) lower = std::max(lower, std::abs(dev));
      if (j + 1 < n_bed) {
        const double next = a[g.index(0, j + 1, 0)] / a_star - 1.0;
        if (std::abs(dev) > 1e-4 && std::abs(next) < 0.05) {
          alternates = alternates && dev * next < 0;
          log_ratio += std::log(std::abs(next / dev));
          ++n_ratio;
        }
      }
    }
    const double ratio = std::exp(log_ratio / std::max(n_ratio, 1));
    std::printf(
        "liquid bed at 2 U_mf (U_mf %.5f m/s), h = %.0f mm: uniform a* %.4f, height %.2f mm; top "
        "%.2f mm (%+.2f cells); G(a*) %.2f Pa, surface pattern decays by %.3f per cell (predicted "
        "%.3f, %d pairs); lower half max |a - a*| / a* %.1e; max |u_s| %.1e m/s\n",
        u_mf, 1e3 * h, a_star, 1e3 * h_star, 1e3 * top, (top - h_star) / h, modulus, ratio, q,
        n_ratio, lower, umax);
    EXPECT_LT(umax, 1e-5);
    EXPECT_NEAR(top, h_star, 0.25 * h);
    EXPECT_TRUE(alternates);
    EXPECT_GE(n_ratio, 5);
    EXPECT_NEAR(ratio / q, 1.0, 0.05);
    if (h < 1.5e-3) {
      EXPECT_LT(lower, 1e-3);
    }
  }
}
