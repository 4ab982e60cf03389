// SPDX-License-Identifier: GPL-3.0-or-later
// Continuum (SPH) validation: a liquid at rest, transient plane Poiseuille flow (explicit and
// implicit viscosity), the Bagnold profile of a mu(I) layer flowing down an incline, a mu(I)
// layer below its yield slope (implicit viscosity), Taylor-Couette flow (a rotating wall), and
// granular gases by kinetic theory (Haff cooling, plane Couette flow between no-slip and
// Johnson-Jackson plates, cooling through Johnson-Jackson plates).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "continuum/rheology_registry.hpp"
#include "continuum/sph.hpp"
#include "dump.hpp"

namespace gf::continuum {
namespace {

SphWall box_wall(const char* name, Vec3 lo, Vec3 hi) {
  SphWall w;
  w.name = name;
  w.lo = lo;
  w.hi = hi;
  return w;
}

// Plane Poiseuille flow started from rest (Morris, Fox & Zhu 1997, sec. 4.1): plates at y = 0
// and L, periodic in x, body force F along x. Series solution:
// u(y, t) = F / (2 nu) y (L - y) - sum_n 4 F L^2 / (nu pi^3 (2n+1)^3) sin((2n+1) pi y / L)
//           exp(-(2n+1)^2 pi^2 nu t / L^2).
double poiseuille(double y, double t, double f, double nu, double l) {
  const double pi = std::numbers::pi;
  double u = f / (2 * nu) * y * (l - y);
  for (int n = 0; n < 200; ++n) {
    const double m = 2 * n + 1;
    u -= 4 * f * l * l / (nu * pi * pi * pi * m * m * m) * std::sin(pi * y * m / l) *
         std::exp(-m * m * pi * pi * nu * t / (l * l));
  }
  return u;
}

/// With `free_slip_top` the top plate exerts no shear: the flow is the lower half of a
/// Poiseuille flow between plates 2L apart, u = poiseuille(y, t, F, nu, 2L).
void run_poiseuille(bool implicit, double transient_tolerance, double steady_tolerance = 0.01,
                    int dimension = 2, int n = 20, bool free_slip_top = false) {
  // Morris et al.'s case: L = 1 mm, nu = 1e-6 m^2/s, F = 1e-4 m/s^2 (Re = u_max L / nu =
  // 0.0125), n particles across, 3 wall layers (> 2h) each side; in 3D periodic along z too.
  const double l = 1e-3, nu = 1e-6, f = 1e-4, rho = 1000;
  const double dx = l / n, width = 8 * dx, th = 3 * dx;
  const double depth = dimension == 3 ? width : 0.0;
  const double span = free_slip_top ? 2 * l : l;  // of the Poiseuille flow it is part of
  const double u_max = f * span * span / (8 * nu);
  SphConfig c;
  c.dimension = dimension;
  c.domain.lo = {0, -th, 0};
  c.domain.hi = {width, l + th, depth};
  c.domain.periodic = {true, false, dimension == 3};
  c.gravity = {f, 0, 0};
  c.spacing = dx;
  c.density = rho;
  c.sound_speed = 100 * u_max;  // Mach 0.01: density varies by 1e-4
  c.rheology = prepare_rheology("newtonian", {{"viscosity", nu * rho}});
  c.blocks.push_back({{0, 0, 0}, {width, l, depth}, {}, false});
  c.walls.push_back(box_wall("bottom", {0, -th, 0}, {width, 0, depth}));
  c.walls.push_back(box_wall("top", {0, l, 0}, {width, l + th, depth}));
  c.walls.back().free_slip = free_slip_top;
  c.implicit_viscosity = implicit;
  SphSolver s(c);
  test::Dump dump(fmt::format("sph_poiseuille{}{}{}", implicit ? "_implicit" : "",
                              dimension == 3 ? "_3d" : "", free_slip_top ? "_free_slip" : ""),
                  "t,y,u,u_exact");
  const double t_steady = free_slip_top ? 4.0 : 1.0;  // 2.5 of the slowest mode's decay times
  for (double t_end : {0.0225, 0.045, 0.1125, 0.225, t_steady}) {
    while (s.time() < t_end - 1e-12) s.step(t_end);
    double err = 0;
    const auto& p = s.particles();
    for (std::size_t i = 0; i < s.n_fluid(); ++i) {
      const double ex = poiseuille(p.x[i].y, s.time(), f, nu, span);
      err = std::max(err, std::fabs(p.v[i].x - ex));
      if (p.x[i].x < dx) dump.row(s.time(), p.x[i].y, p.v[i].x, ex);
      // (against a free-slip plate, whose particles damp no motion, the acoustic noise across
      // reaches 1.1e-3 u_max)
      EXPECT_LT(std::fabs(p.v[i].y), (free_slip_top ? 2e-3 : 1e-3) * u_max);
      EXPECT_LT(std::fabs(p.v[i].z), 1e-3 * u_max);
    }
    EXPECT_LT(err, (t_end < t_steady ? transient_tolerance : steady_tolerance) * u_max)
        << "t = " << s.time();
  }
}

TEST(ValidationSph, PoiseuilleFlowFromRest) {
  // Measured 0.33-0.48 % of u_max at 20 particles across (0.10-0.16 % at 40: the error is the
  // no-slip extrapolation's, first order in dx near the plates). 1 % bounds it with room for
  // rounding, and fails for a viscous operator off by 2 % (as it was without the lattice
  // normalisation of the Laplacian) or for a slipping wall.
  run_poiseuille(false, 0.01);
}

TEST(ValidationSph, PoiseuilleFlowImplicitViscosity) {
  // Backward Euler at the acoustic step (100 steps to t = 1 s instead of 1896): the transient
  // carries its first-order time error, measured 0.8-1.7 % of u_max (2.5 % asserted); the steady
  // state must be the explicit one (0.48 %, 1 % asserted), walls taken implicitly included.
  run_poiseuille(true, 0.025);
}

TEST(ValidationSph, PoiseuilleFlow3D) {
  // The same flow in 3D (periodic along x and z), 10 particles across: the 3D kernel, its
  // lattice normalisations and the 3D neighbour search. Measured 1.0-1.45 % of u_max (the
  // error is first order in dx: 0.33-0.48 % in 2D at 20 across); 2 % asserted.
  run_poiseuille(false, 0.02, 0.02, 3, 10);
}

TEST(ValidationSph, PoiseuilleFlowAgainstFreeSlipWall) {
  // A no-slip bottom and a free-slip top: half of a Poiseuille flow twice as wide, whose centre
  // line (du/dy = 0) is the free-slip plate. Measured 0.08-0.12 % of u_max in the transient and
  // 0.16 % at steady state, largest at the no-slip plate (as in PoiseuilleFlowFromRest); the
  // free-slip plate's layer is within 0.07 %. 0.5 % asserted: a plate that sheared (the mirrored
  // no-slip velocity, or its own velocity, in the viscous term) would be tens of % off.
  run_poiseuille(false, 0.005, 0.005, 2, 20, true);
}

// Steady flow between plates at y = 0 (at rest) and y = L (moving at U along x), with Navier
// slip lengths b0 and b1 (u - u_wall = b du/dn, n into the liquid) and a body force F along x:
// u(y) = F / (2 nu) y (L - y) + A + B y, B = (U + (b1 - b0) F L / (2 nu)) / (L + b0 + b1),
// A = b0 (F L / (2 nu) + B).
struct NavierSlipRun {
  double max_error = 0;       ///< steady, over all fluid particles, relative to u_scale
  double slip_velocity[2]{};  ///< measured at the plates (extrapolated linearly), relative
  double slip_exact[2]{};
};

NavierSlipRun run_navier_slip(double f, double u_top, double b0, double b1, double t_end,
                              bool implicit = false) {
  const double l = 1e-3, nu = 1e-6, rho = 1000;
  const int n = 20;
  const double dx = l / n, width = 8 * dx, th = 3 * dx;
  const double c1 = f * l / (2 * nu);
  const double bb = (u_top + (b1 - b0) * c1) / (l + b0 + b1), aa = b0 * (c1 + bb);
  auto exact = [&](double y) { return f / (2 * nu) * y * (l - y) + aa + bb * y; };
  double u_scale = 0;
  for (int k = 0; k <= 100; ++k) u_scale = std::max(u_scale, std::fabs(exact(k * l / 100)));
  SphConfig c;
  c.dimension = 2;
  c.domain.lo = {0, -th, 0};
  c.domain.hi = {width, l + th, 0};
  c.domain.periodic = {true, false, false};
  c.gravity = {f, 0, 0};
  c.spacing = dx;
  c.density = rho;
  c.sound_speed = 100 * u_scale;  // Mach 0.01
  c.rheology = prepare_rheology("newtonian", {{"viscosity", nu * rho}});
  c.blocks.push_back({{0, 0, 0}, {width, l, 0}, {}, false});
  c.walls.push_back(box_wall("bottom", {0, -th, 0}, {width, 0, 0}));
  c.walls.back().slip_length = b0;
  c.walls.push_back(box_wall("top", {0, l, 0}, {width, l + th, 0}));
  c.walls.back().slip_length = b1;
  c.walls.back().velocity = {u_top, 0, 0};
  c.implicit_viscosity = implicit;
  SphSolver s(c);
  while (s.time() < t_end - 1e-12) s.step(t_end);
  NavierSlipRun out;
  test::Dump dump(fmt::format("sph_navier_slip_f{}_u{}{}", f > 0 ? 1 : 0, u_top > 0 ? 1 : 0,
                              implicit ? "_implicit" : ""),
                  "y,u,u_exact");
  // the plates' slip from the two layers next to each (a linear fit, exact for Couette flow)
  double lo1 = 0, lo2 = 0, hi1 = 0, hi2 = 0;
  int nlo1 = 0, nlo2 = 0, nhi1 = 0, nhi2 = 0;
  const auto& p = s.particles();
  for (std::size_t i = 0; i < s.n_fluid(); ++i) {
    const double y = p.x[i].y, u = p.v[i].x;
    out.max_error = std::max(out.max_error, std::fabs(u - exact(y)) / u_scale);
    if (p.x[i].x < dx) dump.row(y, u, exact(y));
    if (y < dx)
      lo1 += u, ++nlo1;
    else if (y < 2 * dx)
      lo2 += u, ++nlo2;
    if (y > l - dx)
      hi1 += u, ++nhi1;
    else if (y > l - 2 * dx)
      hi2 += u, ++nhi2;
  }
  lo1 /= nlo1, lo2 /= nlo2, hi1 /= nhi1, hi2 /= nhi2;
  out.slip_velocity[0] = (1.5 * lo1 - 0.5 * lo2) / u_scale;          // u at y = 0
  out.slip_velocity[1] = (1.5 * hi1 - 0.5 * hi2 - u_top) / u_scale;  // u - U at y = L
  out.slip_exact[0] = exact(0.0) / u_scale;
  out.slip_exact[1] = (exact(l) - u_top) / u_scale;
  return out;
}

TEST(ValidationSph, PoiseuilleFlowWithNavierSlip) {
  // Body force, the bottom plate slipping with b = L/4, the top without slip: u(0) = 0.415 u_max
  // of the profile. The slowest mode decays at nu k^2 = 5.1 1/s (Robin eigenvalue), so t = 2 s
  // leaves 4e-5 of the start.
  const auto r = run_navier_slip(1e-4, 0.0, 0.25e-3, 0.0, 2.0);
  // Measured: profile within 0.46 % of the largest speed, slip at the bottom 0.565 against
  // 0.556 (of the largest speed, extrapolated from the two layers next to it), top 0.009 against
  // 0. 1 % and 0.02 asserted (the errors are first order in dx at a wall, as without slip:
  // PoiseuilleFlowFromRest 0.48 %); a no-slip bottom would be 55 % off, a slip length off by a
  // factor two 12 % (the profile with b = L/2 has u(0) 0.675 of its maximum instead of 0.556).
  fmt::print("Navier slip Poiseuille: max error {:.4f}, slip {:.4f} (exact {:.4f}), top {:.4f}\n",
             r.max_error, r.slip_velocity[0], r.slip_exact[0], r.slip_velocity[1]);
  EXPECT_LT(r.max_error, 0.01);
  EXPECT_NEAR(r.slip_velocity[0], r.slip_exact[0], 0.02);
  EXPECT_NEAR(r.slip_velocity[1], r.slip_exact[1], 0.02);
}

TEST(ValidationSph, NavierSlipImplicitViscosity) {
  // The same with the viscous term backward Euler (the walls' mirrored velocities, slip
  // included, taken at the new velocities): the steady state must be the explicit one.
  const auto r = run_navier_slip(1e-4, 0.0, 0.25e-3, 0.0, 2.0, true);
  fmt::print("Navier slip Poiseuille, implicit: max error {:.4f}, slip {:.4f} (exact {:.4f})\n",
             r.max_error, r.slip_velocity[0], r.slip_exact[0]);
  EXPECT_LT(r.max_error, 0.01);
  EXPECT_NEAR(r.slip_velocity[0], r.slip_exact[0], 0.02);
}

TEST(ValidationSph, CouetteFlowWithNavierSlip) {
  // A plate moving at U over one at rest, both slipping with b = L/4: u = U (y + b) / (L + 2b),
  // U / 6 slips off at each plate (0.2 of the largest speed 5 U / 6). Measured: profile within
  // 0.18 %, slip 0.2016 and -0.2017 against 0.2 and -0.2: a wall velocity taken into the
  // mirrored velocity unscaled (2 u_w - s v~) would put the moving plate's slip far off. 1 % and
  // 0.01 asserted.
  const auto r = run_navier_slip(0.0, 1e-3, 0.25e-3, 0.25e-3, 2.0);
  fmt::print("Navier slip Couette: max error {:.4f}, slip {:.4f} {:.4f} (exact {:.4f} {:.4f})\n",
             r.max_error, r.slip_velocity[0], r.slip_velocity[1], r.slip_exact[0], r.slip_exact[1]);
  EXPECT_LT(r.max_error, 0.01);
  EXPECT_NEAR(r.slip_velocity[0], r.slip_exact[0], 0.01);
  EXPECT_NEAR(r.slip_velocity[1], r.slip_exact[1], 0.01);
}

// ---- Kinetic theory (the granular phase as a granular gas) ----

/// The lees_edwards_spheres grains of the DEM shear tests (d = 5.3 mm, rho_s = 1395 kg/m^3),
/// restitution e, closures of Lun et al. with Carnahan-Starling's g0, dense packing 0.6.
SphKineticTheory dem_grains(double e) {
  SphKineticTheory kt;
  kt.closures = prepare_ktgf(
      "lun", {{"restitution", e}, {"grain_diameter", 0.0053}, {"grain_density", 1395}});
  kt.dense = prepare_frictional("mu_i_switch");
  return kt;
}

/// The plane Couette box of the kinetic-theory tests: 2D, the dem_grains material at a = 0.1 in a
/// layer of height h and width `width` (particle spacing dx, periodic along x) between plates of
/// thickness 3 dx moving at -u and +u; sound speed 10 m/s (the dense packing's; the gas's own,
/// 3 m/s here, is taken when larger). jj: the plates' Johnson-Jackson condition, if any.
SphConfig couette_box(const SphKineticTheory& kt, double h, double width, double dx, double u,
                      bool implicit, const SphWall::JohnsonJackson* jj = nullptr) {
  const double d = 0.0053, a = 0.1, rho_s = 1395, th = 3 * dx;
  SphConfig c;
  c.dimension = 2;
  c.domain.lo = {0, -th, 0};
  c.domain.hi = {width, h + th, 0};
  c.domain.periodic = {true, false, false};
  c.spacing = dx;
  c.density = 0.6 * rho_s;
  c.sound_speed = 10;
  c.rheology = prepare_rheology(
      "mu_i", {{"grain_diameter", d}, {"grain_density", rho_s}, {"max_viscosity", 10}});
  c.kinetic_theory = kt;
  c.implicit_viscosity = implicit;
  SphBlock b{{0, 0, 0}, {width, h, 0}, {}, false};
  b.volume_fraction = a;
  c.blocks.push_back(b);
  c.walls.push_back(box_wall("bottom", {0, -th, 0}, {width, 0, 0}));
  c.walls.back().velocity = {-u, 0, 0};
  if (jj) c.walls.back().johnson_jackson = *jj;
  c.walls.push_back(box_wall("top", {0, h, 0}, {width, h + th, 0}));
  c.walls.back().velocity = {u, 0, 0};
  if (jj) c.walls.back().johnson_jackson = *jj;
  return c;
}

TEST(ValidationSphKineticTheory, HomogeneousCoolingFollowsHaff) {
  // A granular gas at rest (a = 0.1, e = 0.7, Theta0 = 1 m^2/s^2) in a periodic box, no gravity:
  // only the dissipation acts, and Theta(t) = Theta0 / (1 + t / tau)^2 (Haff 1983; tau = 35 ms
  // here). The sink is implicit (linearised), first order in dt / tau; at the acoustic step
  // (dt / tau = 6.7e-4) measured within 0.067 % of Haff's law over 0-5 tau, every particle the
  // same to 6e-15 (the state stays homogeneous). 0.5 % asserted: a dissipation off by its
  // factor (1 - e^2) or g0 is tens of % off.
  SphConfig c;
  c.dimension = 2;
  const double l = 0.1, dx = l / 20;
  c.domain.lo = {0, 0, 0};
  c.domain.hi = {l, l, 0};
  c.domain.periodic = {true, true, false};
  c.spacing = dx;
  c.density = 0.6 * 1395;
  c.sound_speed = 20;
  c.rheology = prepare_rheology(
      "mu_i", {{"grain_diameter", 0.0053}, {"grain_density", 1395}, {"max_viscosity", 10}});
  auto kt = dem_grains(0.7);
  kt.initial_temperature = 1.0;
  c.kinetic_theory = kt;
  SphBlock b{{0, 0, 0}, {l, l, 0}, {}, false};
  b.volume_fraction = 0.1;
  c.blocks.push_back(b);
  SphSolver s(c);
  const double tau = haff_time(0.1, 1.0, kt.closures);
  test::Dump dump("sph_ktgf_haff", "t,theta,theta_haff");
  double worst = 0, spread = 0;
  for (int q = 1; q <= 50; ++q) {
    const double t_q = 0.1 * tau * q;
    while (s.time() < t_q - 1e-15) s.step(t_q);
    const auto& p = s.particles();
    const double exact = haff_temperature(0.1, 1.0, s.time(), kt.closures);
    double lo = 1e300, hi = 0;
    for (std::size_t i = 0; i < s.n_fluid(); ++i) {
      lo = std::min(lo, p.theta[i]);
      hi = std::max(hi, p.theta[i]);
    }
    worst = std::max(worst, std::fabs(hi / exact - 1));
    spread = std::max(spread, (hi - lo) / exact);
    dump.row(s.time(), hi, exact);
  }
  fmt::print("SPH Haff: tau {:.4g} s, dt/tau {:.3g}, max error {:.3g}, spread {:.3g}\n", tau,
             s.last_step() / tau, worst, spread);
  EXPECT_LT(worst, 5e-3);
  EXPECT_LT(spread, 1e-9);
}

void run_ktgf_couette(bool implicit) {
  // Plane Couette flow of a granular gas: plates at y = 0 and H = 10 d moving at -U and +U
  // (shear rate 100 1/s), no-slip and adiabatic, periodic in x; the grains of the DEM test
  // RheologyValidation.LeesEdwardsNearlyElasticSpheresMatchLun (d = 5.3 mm, rho_s = 1395, e =
  // 0.95, a = 0.1). Uniform shear with Theta, P and the shear stress of
  // ktgf_simple_shear (viscous heating = dissipation) is then an exact steady solution of the
  // continuum equations (no heat flux anywhere); the gas starts cold (Theta0 = Theta / 10) and
  // at rest, and must reach it. DEM at these conditions measured T, P and
  // sigma_xz within 3 % of the same theory (Lees-Edwards, the test named above).
  // Measured (means over 0.5-1 s; steady from 0.3 s): the gas's volume fraction settles at
  // 0.0980 (-2 %: the continuity equation's wall term, the walls at the dense packing's density,
  // compresses the layers next to the plates); at that a the theory's Theta = 3.83 m^2/s^2 is
  // met within -0.3 %, P within +3.5 % and the shear stress within +3.7 % (both from the plates'
  // loads, with the walls' O(dx) error of the Poiseuille tests, 0.5 %, and the denser layers
  // next to them); against the nominal a = 0.1: +3.6, +4.6, +5.0 %. Asserted: Theta 2 %, P and
  // shear stress 5 %, a within 0.003. A production or
  // dissipation off by a factor (1 + e) / 2, or a pressure without its collisional part
  // (-33 %), fail.
  const double d = 0.0053, a = 0.1, rate = 100, h = 10 * d, u = 0.5 * rate * h;
  const int n = 20;
  const double dx = h / n, width = h;
  auto kt = dem_grains(0.95);
  const auto exact = ktgf_simple_shear(a, rate, kt.closures);
  kt.initial_temperature = 0.1 * exact.temperature;
  SphSolver s(couette_box(kt, h, width, dx, u, implicit));
  test::Dump dump(implicit ? "sph_ktgf_couette_implicit" : "sph_ktgf_couette",
                  "t,theta,pressure,shear_stress,a_min,a_max,theta_exact,p_exact,tau_exact");
  // Time averages over 0.5-1 s (the start's transient decays in about 0.2 s)
  double sum_theta = 0, sum_p = 0, sum_tau = 0, sum_a = 0;
  int samples = 0;
  // (implicit: 0.4-0.6 s, each step costs three linear solves)
  const int n_samples = implicit ? 60 : 100;
  const double t_average = implicit ? 0.4 : 0.5;
  for (int q = 1; q <= n_samples; ++q) {
    const double t_q = 0.01 * q;
    while (s.time() < t_q - 1e-12) s.step(t_q);
    const auto loads = s.wall_loads();
    const double tau = 0.5 * (loads.force[0].x - loads.force[1].x) / width;
    const double p = 0.5 * (loads.force[1].y - loads.force[0].y) / width;
    const auto sm = s.summary();
    dump.row(s.time(), sm.mean_temperature, p, tau, sm.min_volume_fraction, sm.max_volume_fraction,
             exact.temperature, exact.pressure, exact.shear_stress);
    if (s.time() > t_average - 1e-9) {
      sum_theta += sm.mean_temperature, sum_p += p, sum_tau += tau;
      sum_a += 0.5 * (sm.min_volume_fraction + sm.max_volume_fraction);
      ++samples;
    }
  }
  const double theta = sum_theta / samples, p = sum_p / samples, tau = sum_tau / samples;
  const double a_run = sum_a / samples;
  const auto at_run = ktgf_simple_shear(a_run, rate, kt.closures);
  fmt::print(
      "SPH KTGF Couette{}: Theta {:.4g} vs {:.4g} ({:+.2f} %), P {:.4g} vs {:.4g} "
      "({:+.2f} %), tau {:.4g} vs {:.4g} ({:+.2f} %); at the run's a = {:.4f}: {:+.2f}, "
      "{:+.2f}, {:+.2f} %\n",
      implicit ? " (implicit)" : "", theta, exact.temperature,
      100 * (theta / exact.temperature - 1), p, exact.pressure, 100 * (p / exact.pressure - 1), tau,
      exact.shear_stress, 100 * (tau / exact.shear_stress - 1), a_run,
      100 * (theta / at_run.temperature - 1), 100 * (p / at_run.pressure - 1),
      100 * (tau / at_run.shear_stress - 1));
  EXPECT_NEAR(theta / at_run.temperature, 1.0, 0.02);
  EXPECT_NEAR(p / at_run.pressure, 1.0, 0.05);
  EXPECT_NEAR(tau / at_run.shear_stress, 1.0, 0.05);
  EXPECT_NEAR(a_run, a, 0.003);
}

TEST(ValidationSphKineticTheory, SimpleShearReachesTheKineticTheoryState) {
  run_ktgf_couette(false);
}

TEST(ValidationSphKineticTheory, SimpleShearImplicitViscosityAndConduction) {
  // The same with backward-Euler viscosity and conduction (no diffusion limit on the step),
  // averaged over 0.4-0.6 s: the steady state must be the explicit one. Measured at the run's
  // a: Theta -0.34 %, P +3.47 %, shear stress +3.62 % (explicit: -0.32, +3.50, +3.66 %).
  run_ktgf_couette(true);
}

// ---- Johnson-Jackson walls (kinetic theory) ----

/// Means over the two layers of fluid particles next to each plate (y in [0, dx), [dx, 2 dx)
/// and the same below H), of y, u_x, a and Theta, accumulated over samples.
struct PlateLayers {
  double sum[4][5]{};  // layer (bottom 1, 2, top 1, 2) x (count, y, u, a, theta)
  void add(const SphSolver& s, double h, double dx, double rho_s) {
    const auto& p = s.particles();
    for (std::size_t i = 0; i < s.n_fluid(); ++i) {
      const double y = p.x[i].y;
      int k = -1;
      if (y < dx)
        k = 0;
      else if (y < 2 * dx)
        k = 1;
      else if (y > h - dx)
        k = 2;
      else if (y > h - 2 * dx)
        k = 3;
      if (k < 0) continue;
      const double q[5] = {1.0, y, p.v[i].x, p.rho[i] / rho_s, p.theta[i]};
      for (int m = 0; m < 5; ++m) sum[k][m] += q[m];
    }
  }
  /// Quantity m (2: u, 3: a, 4: Theta) at the plate y_p (0: bottom, 1: top), extrapolated
  /// linearly from the two layers' means.
  double at_plate(int plate, int m, double y_p) const {
    const auto& l1 = sum[2 * plate];
    const auto& l2 = sum[2 * plate + 1];
    const double y1 = l1[1] / l1[0], y2 = l2[1] / l2[0];
    const double f1 = l1[m] / l1[0], f2 = l2[m] / l2[0];
    return f1 + (f2 - f1) * (y_p - y1) / (y2 - y1);
  }
};

struct JjCouetteRun {
  double tau = 0;           ///< the plates' shear stress, time mean [Pa]
  double slip[2]{};         ///< the gas's velocity at each plate relative to it [m/s]
  double coefficient[2]{};  ///< C = (pi sqrt(3)/6) phi' (a/a_max) rho_s g0 sqrt(Theta) there
  double theta_wall[2]{}, a_wall[2]{};
  double work = 0;              ///< power of the plates, 2 tau U L [W/m]
  double bulk_dissipation = 0;  ///< sum_i V_i gamma_s(a_i, Theta_i) [W/m]
  double wall_dissipation = 0;  ///< the plates' (sqrt(3) pi/4)(1 - e_w^2)(a/a_max) rho_s g0
                                ///< Theta^(3/2) L, from the plate values [W/m]
  double u_scale = 0;           ///< the plate speed U [m/s]
  double theta_mean = 0;        ///< mass-weighted mean Theta [m^2/s^2]
  double a_mean = 0;            ///< mean volume fraction (mid-range of the extremes, as above)
  double theta_centre = 0;      ///< mean Theta of the middle fifth of the gap [m^2/s^2]
  double theta_end = 0;         ///< mass-weighted mean Theta at t_end [m^2/s^2]
  double max_speed = 0;         ///< largest speed of the gas at t_end [m/s]
};

/// The Couette flow of run_ktgf_couette (a = 0.1, 100 1/s nominal, e = 0.95) between plates
/// with the Johnson-Jackson condition, n particles across, means over t_average .. t_end.
JjCouetteRun run_jj_couette(double specularity, double wall_restitution, int n, double t_end,
                            double t_average, bool implicit = false) {
  const double d = 0.0053, rate = 100, h = 10 * d, u = 0.5 * rate * h, rho_s = 1395;
  const double dx = h / n, width = std::max(h, 8 * dx);
  auto kt = dem_grains(0.95);
  kt.initial_temperature = 0.37;  // a tenth of the no-slip steady state's
  const SphWall::JohnsonJackson jj{specularity, wall_restitution};
  SphSolver s(couette_box(kt, h, width, dx, u, implicit, &jj));
  PlateLayers layers;
  JjCouetteRun out;
  out.u_scale = u;
  int samples = 0;
  for (int q = 1; 0.01 * q < t_end + 1e-9; ++q) {
    const double t_q = 0.01 * q;
    while (s.time() < t_q - 1e-12) s.step(t_q);
    if (s.time() < t_average - 1e-9) continue;
    const auto loads = s.wall_loads();
    out.tau += 0.5 * (loads.force[0].x - loads.force[1].x) / width;
    layers.add(s, h, dx, rho_s);
    const auto& p = s.particles();
    double centre = 0;
    int n_centre = 0;
    for (std::size_t i = 0; i < s.n_fluid(); ++i) {
      out.bulk_dissipation +=
          p.mass[i] / p.rho[i] * collisional_dissipation(p.rho[i] / rho_s, p.theta[i], kt.closures);
      if (std::fabs(p.x[i].y - 0.5 * h) < 0.1 * h) centre += p.theta[i], ++n_centre;
    }
    out.theta_centre += centre / n_centre;
    const auto sm = s.summary();
    out.theta_mean += sm.mean_temperature;
    out.a_mean += 0.5 * (sm.min_volume_fraction + sm.max_volume_fraction);
    ++samples;
  }
  out.theta_end = s.summary().mean_temperature;
  out.max_speed = s.summary().max_speed;
  out.tau /= samples;
  out.bulk_dissipation /= samples;
  out.theta_mean /= samples;
  out.theta_centre /= samples;
  out.a_mean /= samples;
  out.work = 2 * out.tau * u * width;
  const double pi = std::numbers::pi, a_max = 0.6;
  for (int plate = 0; plate < 2; ++plate) {
    const double y_p = plate == 0 ? 0.0 : h;
    const double u_wall = plate == 0 ? -u : u;
    out.slip[plate] = layers.at_plate(plate, 2, y_p) - u_wall;
    out.a_wall[plate] = layers.at_plate(plate, 3, y_p);
    out.theta_wall[plate] = layers.at_plate(plate, 4, y_p);
    const double g0 = radial_distribution(out.a_wall[plate], kt.closures);
    const double k = out.a_wall[plate] / a_max * rho_s * g0;
    out.coefficient[plate] =
        pi * std::sqrt(3.0) / 6 * specularity * k * std::sqrt(out.theta_wall[plate]);
    out.wall_dissipation += std::sqrt(3.0) * pi / 4 * (1 - wall_restitution * wall_restitution) *
                            k * std::pow(out.theta_wall[plate], 1.5) * width;
  }
  fmt::print(
      "JJ Couette, phi' {} e_w {:.5f}, {} across{}: tau {:.4g} Pa, slip {:.4g} {:.4g} m/s; at the "
      "plates a {:.4f}, Theta {:.4g}; plates' power {:.4g} W/m, dissipation in the gas {:.4g} and "
      "at the plates {:.4g}\n",
      specularity, wall_restitution, n, implicit ? " (implicit)" : "", out.tau, out.slip[0],
      out.slip[1], out.a_wall[0], out.theta_wall[0], out.work, out.bulk_dissipation,
      out.wall_dissipation);
  return out;
}

/// The Couette flow between Johnson-Jackson plates whose energy flux vanishes: uniform shear
/// gamma_dot = 2 U / (H + 2 b) with slip u_s = b gamma_dot at each plate, b = mu_s / C =
/// mu_s(a, 1) / C(a, 1) (both ~ sqrt(Theta)), Theta that of homogeneous shear at gamma_dot, and
/// C u_s^2 = (sqrt(3) pi / 4) (1 - e_w^2) (a / a_max) rho_s g0 Theta^(3/2), i.e.
/// 1 - e_w^2 = (2/3) phi' u_s^2 / Theta.
struct JjNeutral {
  double b, rate, slip, theta, tau, wall_restitution;
};
JjNeutral jj_neutral(double specularity, double a, const KtgfParams& k) {
  const double d = 0.0053, h = 10 * d, u = 0.5 * 100 * h, a_max = 0.6;
  const double c1 = std::numbers::pi * std::sqrt(3.0) / 6 * specularity * a / a_max * k.density *
                    radial_distribution(a, k);
  JjNeutral r;
  r.b = solids_shear_viscosity(a, 1.0, k) / c1;
  r.rate = 2 * u / (h + 2 * r.b);
  r.slip = r.b * r.rate;
  const auto st = ktgf_simple_shear(a, r.rate, k);
  r.theta = st.temperature;
  r.tau = st.shear_stress;
  r.wall_restitution = std::sqrt(1 - 2.0 / 3.0 * specularity * r.slip * r.slip / r.theta);
  return r;
}

/// The checks of JohnsonJacksonCouetteSlipsAsTheWallConditionSays for one specularity; returns
/// the bottom plate's slip [m/s].
double check_jj_couette(double phi, bool implicit, double t_end, double t_average) {
  const auto k = dem_grains(0.95).closures;
  const auto nominal = jj_neutral(phi, 0.1, k);
  const auto r = run_jj_couette(phi, nominal.wall_restitution, 10, t_end, t_average, implicit);
  const auto ex = jj_neutral(phi, r.a_mean, k);
  fmt::print(
      "  at the run's a = {:.4f}: slip {:+.2f} {:+.2f} % of {:.4g} m/s; C u_slip / tau {:+.2f} "
      "{:+.2f} %; tau {:+.2f} % of {:.4g} Pa; Theta {:+.2f} % of {:.4g} (plates {:+.2f} {:+.2f} %, "
      "middle {:+.2f} %); power balance {:+.2f} %\n",
      r.a_mean, 100 * (r.slip[0] / ex.slip - 1), 100 * (-r.slip[1] / ex.slip - 1), ex.slip,
      100 * (r.coefficient[0] * r.slip[0] / r.tau - 1),
      100 * (-r.coefficient[1] * r.slip[1] / r.tau - 1), 100 * (r.tau / ex.tau - 1), ex.tau,
      100 * (r.theta_mean / ex.theta - 1), ex.theta, 100 * (r.theta_wall[0] / ex.theta - 1),
      100 * (r.theta_wall[1] / ex.theta - 1), 100 * (r.theta_centre / ex.theta - 1),
      100 * ((r.bulk_dissipation + r.wall_dissipation) / r.work - 1));
  EXPECT_NEAR(r.slip[0] / ex.slip, 1.0, 0.06) << phi;
  EXPECT_NEAR(-r.slip[1] / ex.slip, 1.0, 0.06) << phi;
  EXPECT_NEAR(r.coefficient[0] * r.slip[0] / r.tau, 1.0, 0.05) << phi;
  EXPECT_NEAR(-r.coefficient[1] * r.slip[1] / r.tau, 1.0, 0.05) << phi;
  EXPECT_NEAR(r.tau / ex.tau, 1.0, 0.07) << phi;
  EXPECT_NEAR(r.theta_mean / ex.theta, 1.0, 0.02) << phi;
  for (int plate = 0; plate < 2; ++plate)
    EXPECT_NEAR(r.theta_wall[plate] / r.theta_centre, 1.0, 0.01) << phi;
  return r.slip[0];
}

TEST(ValidationSphKineticTheory, JohnsonJacksonCouetteSlipsAsTheWallConditionSays) {
  // Plane Couette flow of the granular gas of SimpleShearReachesTheKineticTheoryState between
  // Johnson-Jackson plates, 10 particles across, specularity 0.5 and 1, each plate's e_w chosen
  // so that its energy flux vanishes in the exact solution (jj_neutral): uniform shear at
  // gamma_dot = 2 U / (H + 2 b) with slip b gamma_dot at each plate, b = mu_s / C (0.57 d / phi'),
  // and the homogeneous-shear Theta. Means over 0.4-0.8 s (steady from about 0.3 s), compared
  // with the solution at the run's a (0.097: the wall layers compress the gas by 3 %, as in the
  // no-slip test). Measured (phi' = 0.5; 1): slip +2.0 %; +3.9 % (+1.2 %; +2.3 % at 20 across:
  // first order in dx, as with Navier-slip walls); the wall condition itself, C u_slip against
  // the plates' shear stress (C from a and Theta extrapolated to the plates), -3.0 %; -1.2 %;
  // shear stress +4.7 %; +4.6 % (no-slip test: +3.7 %, the wall loads' bias); Theta -0.9 %;
  // -0.9 %, the same at the plates as in the middle to 0.01 % (no net flux: the flux's two parts
  // cancel as they should); the plates' power against the dissipation in the gas and at the
  // plates -3.3 %; -3.0 %. Asserted: slip 6 %, C u_slip 5 %, stress 7 %, Theta 2 %, flat 1 %. A
  // C off by sqrt(3) or 2 moves the slip by 20-45 %; the production by slip doubled or halved
  // moves Theta by +19 % / -10 % (phi' = 0.5; checked), and the plates' Theta first.
  const double slip_rough = check_jj_couette(1.0, false, 0.8, 0.4);
  const double slip_smooth = check_jj_couette(0.5, false, 0.8, 0.4);
  // a rougher wall grips more: b ~ 1 / phi', toward no slip
  EXPECT_LT(slip_rough, 0.6 * slip_smooth);
}

TEST(ValidationSphKineticTheory, JohnsonJacksonCouetteImplicitViscosityAndConduction) {
  // The same (phi' = 0.5) with backward-Euler viscosity and conduction, whose walls' mirrored
  // velocities and heat sources enter the implicit steps; means over 0.4-0.6 s. Measured: slip
  // +2.0 %, tau +4.7 %, Theta -0.9 % (explicit: +2.0, +4.7, -0.9 %).
  check_jj_couette(0.5, true, 0.6, 0.4);
}

TEST(ValidationSphKineticTheory, JohnsonJacksonWithoutSpecularityIsFreeSlip) {
  // phi' = 0 (specular reflections: no tangential momentum to the wall) and e_w = 1: the plates
  // move at -+U under a gas at rest and exert neither shear stress nor heat on it. It must stay
  // at rest and cool as in a periodic box (Haff, e = 0.95; 0.3 s = 0.1 tau).
  const auto r = run_jj_couette(0.0, 1.0, 10, 0.3, 0.2);
  const auto k = dem_grains(0.95).closures;
  const double haff = haff_temperature(0.1, 0.37, 0.3, k);
  fmt::print("JJ free slip: tau {:.3g} Pa, largest speed {:.3g} m/s, Theta {:.5g} (Haff {:.5g})\n",
             r.tau, r.max_speed, r.theta_end, haff);
  // Measured: tau 3.5e-5 Pa (no slip: 160 Pa), speeds up to 1.5e-5 m/s (the start's acoustic
  // noise; U = 2.65 m/s), Theta 0.03 % from Haff. Asserted 1e-3 Pa (phi' = 1e-5, b = 300 m,
  // would shear the gas at 2e-3 1/s: 1.6e-3 Pa), 1e-4 U, 0.5 %.
  EXPECT_LT(std::fabs(r.tau), 1e-3);
  EXPECT_LT(r.max_speed, 1e-4 * r.u_scale);
  EXPECT_NEAR(r.theta_end / haff, 1.0, 0.005);
}

TEST(ValidationSphKineticTheory, JohnsonJacksonWallsCoolAGasAtRest) {
  // A granular gas at rest (a = 0.1, Theta0 = 1 m^2/s^2) between plates at rest, periodic in x,
  // elastic grains (e = 1: no dissipation in the bulk), Johnson-Jackson plates with e_w = 0.98:
  // the gas loses energy only through the plates, at 2 L (sqrt(3) pi / 4) (1 - e_w^2) (a / a_max)
  // rho_s g0 Theta^(3/2) with a and Theta at the plates (extrapolated from the two layers next to
  // each). 20 particles across, 0-0.1 s (Theta falls by a quarter; the plates are 6 % colder than
  // the middle). Measured: the energy lost (grains' fluctuation and mean-flow energy) is +2.9 %
  // above the formula's integral (+3.3 % at 10 across): the solver takes a, g0 and Theta as kernel
  // means of the fluid next to each wall particle and its surface element from the fluid's kernel
  // sum, which grows as the cooled gas approaches the plates (+2.5 %). 5 % asserted; with e_w = 1
  // (the plates adiabatic; phi' does not act on a gas at rest) the energy must stay (it does,
  // exactly). At e_w = 0.9 (plates 25 %
  // colder than the middle) the solver's loss is 11 % above the formula (surface element +12 %:
  // the first layer of gas at 0.42 dx from the wall particles' surface instead of 0.5 dx).
  const double d = 0.0053, h = 10 * d, rho_s = 1395, a_max = 0.6;
  for (const double e_w : {0.98, 1.0}) {
    const int n = 20;
    const double dx = h / n, width = 8 * dx;
    auto kt = dem_grains(1.0);
    kt.initial_temperature = 1.0;
    const SphWall::JohnsonJackson jj{0.5, e_w};
    SphSolver s(couette_box(kt, h, width, dx, 0.0, false, &jj));  // plates at rest
    auto energy = [&] {
      double e = 0;
      const auto& p = s.particles();
      for (std::size_t i = 0; i < s.n_fluid(); ++i)
        e += p.mass[i] * (1.5 * p.theta[i] + 0.5 * norm2(p.v[i]));
      return e;
    };
    PlateLayers layers;
    auto loss = [&] {  // [W/m]
      layers = {};
      layers.add(s, h, dx, rho_s);
      double sum = 0;
      for (int plate = 0; plate < 2; ++plate) {
        const double y_p = plate == 0 ? 0.0 : h;
        const double aw = layers.at_plate(plate, 3, y_p), tw = layers.at_plate(plate, 4, y_p);
        sum += std::sqrt(3.0) * std::numbers::pi / 4 * (1 - e_w * e_w) * aw / a_max * rho_s *
               radial_distribution(aw, kt.closures) * std::pow(tw, 1.5) * width;
      }
      return sum;
    };
    const double e0 = energy();
    double lost_formula = 0, last = loss();
    const double every = 0.005;
    for (int q = 1; q <= 20; ++q) {
      while (s.time() < every * q - 1e-12) s.step(every * q);
      const double now = loss();
      lost_formula += 0.5 * (last + now) * every;  // (trapezoidal: 0.1 % of the loss)
      last = now;
    }
    const double lost = e0 - energy();
    fmt::print(
        "JJ cooling, e_w {}: energy {:.5g} J/m, lost {:.5g}, by the flux formula {:.5g}; "
        "Theta at the plates {:.4g}\n",
        e_w, e0, lost, lost_formula, layers.at_plate(0, 4, 0.0));
    if (e_w < 1)
      EXPECT_NEAR(lost / lost_formula, 1.0, 0.05);
    else
      EXPECT_LT(std::fabs(lost), 1e-3 * e0);
  }
}
// A liquid at rest in a tank: the pressure is hydrostatic and the walls carry the weight.
TEST(ValidationSph, HydrostaticTank) {
  const double h = 0.2, w = 0.1, g = 9.81, rho = 1000;
  const double dx = h / 20, th = 3 * dx;
  SphConfig c;
  c.dimension = 2;
  c.domain.lo = {-th, -th, 0};
  c.domain.hi = {w + th, h + 0.1, 0};
  c.gravity = {0, -g, 0};
  c.spacing = dx;
  c.density = rho;
  c.sound_speed = 10 * std::sqrt(2 * g * h);
  c.artificial_viscosity = 0.05;
  c.rheology = prepare_rheology("newtonian", {{"viscosity", 1e-3}});
  c.blocks.push_back({{0, 0, 0}, {w, h, 0}, {}, true});
  c.walls.push_back(box_wall("floor", {-th, -th, 0}, {w + th, 0, 0}));
  c.walls.push_back(box_wall("left", {-th, 0, 0}, {0, h + 0.05, 0}));
  c.walls.push_back(box_wall("right", {w, 0, 0}, {w + th, h + 0.05, 0}));
  SphSolver s(c);
  double mass = 0;
  for (std::size_t i = 0; i < s.n_fluid(); ++i) mass += s.particles().mass[i];
  // Time average of the wall forces over the second half of 1 s (many acoustic periods 4 h / c0
  // = 0.04 s): momentum balance makes it the weight exactly, up to the momentum change over
  // the window (the settling flow is ~1e-3 m/s).
  Vec3 force{};
  int samples = 0;
  test::Dump dump("sph_hydrostatic", "y,p,p_exact");
  while (s.time() < 1.0 - 1e-12) {
    s.step(1.0);
    if (s.time() > 0.5) {
      for (const auto& f : s.wall_forces()) force += f;
      ++samples;
    }
  }
  force = force / samples;
  EXPECT_NEAR(force.y / (mass * g), -1.0, 0.01);
  EXPECT_NEAR(force.x / (mass * g), 0.0, 0.005);
  // Pressure against rho0 g depth below the initial surface, averaged over all particles below
  // the top 20 % (where it is under 20 % of the bottom value and relative errors are large).
  const auto& p = s.particles();
  double err = 0;
  int n = 0;
  for (std::size_t i = 0; i < s.n_fluid(); ++i) {
    const double ex = rho * g * (h - p.x[i].y);
    dump.row(p.x[i].y, p.p[i], ex);
    if (p.x[i].y < 0.8 * h) {
      err += std::fabs(p.p[i] - ex) / (rho * g * h);
      ++n;
    }
  }
  // Measured 0.5-3 % while the column still rings (the acoustic mode is damped slowly by the
  // artificial viscosity); 4 % of the bottom pressure.
  EXPECT_LT(err / n, 0.04);
  EXPECT_LT(s.summary().max_speed, 0.05 * std::sqrt(g * h));
}

// A mu(I) layer (glass beads: d = 1 mm, rho_s = 2500, phi = 0.6, mu_s 0.382, mu_2 0.643, I0
// 0.279) 20 mm deep on a bed inclined at theta, periodic along the slope, 20 particles deep,
// starting at rest at hydrostatic pressure. c0 = 6 m/s: ten times the largest speed (0.58 m/s).
struct InclineLayer {
  static constexpr double d = 1e-3, h = 0.02, rho_s = 2500, phi = 0.6, rho = phi * rho_s, g = 9.81;
  static constexpr int n = 20;
  static constexpr double dx = h / n;
  double theta;
  SphConfig config;

  InclineLayer(double theta_degrees, double eta_max, bool implicit)
      : theta(theta_degrees * std::numbers::pi / 180.0) {
    const double width = 8 * dx, th = 3 * dx;
    auto& c = config;
    c.dimension = 2;
    c.domain.lo = {0, -th, 0};
    c.domain.hi = {width, 2 * h, 0};
    c.domain.periodic = {true, false, false};
    c.gravity = {g * std::sin(theta), -g * std::cos(theta), 0};
    c.spacing = dx;
    c.density = rho;
    c.sound_speed = 6.0;
    c.implicit_viscosity = implicit;
    c.rheology = prepare_rheology(
        "mu_i", {{"grain_diameter", d}, {"grain_density", rho_s}, {"max_viscosity", eta_max}});
    c.blocks.push_back({{0, 0, 0}, {width, h, 0}, {}, true});
    c.walls.push_back(box_wall("bed", {0, -th, 0}, {width, 0, 0}));
  }

  /// Runs to time t and returns the largest deviation of the layers' mean velocity from
  /// `exact(y)`, writing both to the curve `name`.
  template <class Exact>
  double run_and_compare(double t, const std::string& name, Exact&& exact) const {
    SphSolver s(config);
    while (s.time() < t - 1e-12) s.step(t);
    std::vector<double> u(n, 0.0);
    std::vector<int> cnt(n, 0);
    const auto& p = s.particles();
    for (std::size_t i = 0; i < s.n_fluid(); ++i) {
      const int layer = static_cast<int>(std::floor(p.x[i].y / dx));
      EXPECT_GE(layer, 0);
      EXPECT_LT(layer, n);
      if (layer < 0 || layer >= n) continue;
      u[static_cast<std::size_t>(layer)] += p.v[i].x;
      ++cnt[static_cast<std::size_t>(layer)];
    }
    test::Dump dump(name, "y,u,u_exact");
    double err = 0;
    for (int j = 0; j < n; ++j) {
      const double y = (j + 0.5) * dx;
      const double uj = u[static_cast<std::size_t>(j)] / cnt[static_cast<std::size_t>(j)];
      dump.row(y, uj, exact(y));
      err = std::max(err, std::fabs(uj - exact(y)));
    }
    return err;
  }
};

// Steady uniform flow on a 25 deg incline (GDR MiDi 2004, sec. 4.1; Jop et al. 2006):
// p = rho g cos(theta) (H - y), tau = tan(theta) p, so mu(I) = tan(theta) everywhere and
// u(y) = 2/3 I_theta / d sqrt(phi g cos(theta)) (H^(3/2) - (H - y)^(3/2)) (the Bagnold profile),
// with I_theta = I0 (tan(theta) - mu_s) / (mu_2 - tan(theta)) and phi = rho / rho_s.
TEST(ValidationSph, BagnoldProfileOnIncline) {
  using L = InclineLayer;
  const InclineLayer layer(25.0, 30.0, false);
  const double i_theta = MuI::inertial_number_for(std::tan(layer.theta), layer.config.rheology);
  const double k = 2.0 / 3.0 * i_theta / L::d * std::sqrt(L::phi * L::g * std::cos(layer.theta));
  const double u_s = k * std::pow(L::h, 1.5);
  const double err = layer.run_and_compare(4.0, "sph_bagnold", [&](double y) {
    return k * (std::pow(L::h, 1.5) - std::pow(L::h - y, 1.5));
  });
  // The velocity is very sensitive to the stress: d ln I / d ln mu = mu / (I mu'(I)) = 8 here,
  // so a 0.5 % error of the viscous or pressure operators moves the profile by 4 % (before the
  // lattice normalisation of the pressure gradient the profile was 18 % slow). Measured
  // 0.9-1.5 % of u_s at t = 3.5-4 s, with the acoustic noise of Mach 0.1; 4 % bounds it.
  EXPECT_LT(err, 0.04 * u_s);
}

// Below the yield slope (tan(theta) < mu_s) a regularised mu(I) layer is a Newtonian film of
// viscosity max_viscosity: u(y) = rho g sin(theta) / eta_max (H y - y^2 / 2). The explicit
// viscous step would be 1.3e-6 s (eta_max = 1e3 Pa s) or 1.3e-7 s (1e4); the implicit one runs
// at the step of the acoustic and force limits. The film's viscous time rho H^2 / eta_max is
// below 1e-3 s: at 0.05 s it is steady.
TEST(ValidationSph, MuIBelowYieldCreepsAsViscousFilm) {
  using L = InclineLayer;
  for (const double eta_max : {1e3, 1e4}) {
    const InclineLayer layer(15.0, eta_max, true);
    // not held to the explicit viscous limit 0.125 h^2 rho / eta_max
    const SphSolver start(layer.config);
    const double h_k = start.kernel().h;
    EXPECT_GT(start.stable_step(), 10 * 0.125 * h_k * h_k * L::rho / eta_max);
    const double a = L::rho * L::g * std::sin(layer.theta) / eta_max;
    const double u_s = 0.5 * a * L::h * L::h;  // 7.6e-4 and 7.6e-5 m/s
    const double err =
        layer.run_and_compare(0.05, fmt::format("sph_creep_{:g}", eta_max),
                              [&](double y) { return a * (L::h * y - 0.5 * y * y); });
    // eta_max = 1e3: measured 0.68 % of u_s; 2 % asserted. Before the shear rate of the
    // rheology was taken from the fluid alone (the walls' mirrored velocities made it ten times
    // too large next to the bed, so the bed layer slipped at a lowered viscosity) it was 3.4 %
    // here and 60 % at 1e4. eta_max = 1e4: measured 3.8 %, from the top layers, where p -> 0
    // lets mu(I) p / gamma_dot fall below the cap; 6 % asserted.
    EXPECT_LT(err, (eta_max < 5e3 ? 0.02 : 0.06) * u_s) << "eta_max = " << eta_max;
  }
}

// Taylor-Couette flow (2D): a Newtonian liquid between an inner cylinder of radius R1 turning
// at Omega and a fixed outer cylinder of radius R2, no gravity. Steady state (Landau & Lifshitz,
// Fluid Mechanics, 2nd ed., sec. 18): u_theta(r) = A r + B / r,
// A = -Omega R1^2 / (R2^2 - R1^2), B = Omega R1^2 R2^2 / (R2^2 - R1^2); shear stress
// tau_r_theta = eta r d(u_theta / r)/dr = -2 eta B / r^2, so the torque of the liquid on the inner
// cylinder, per metre of depth, is 2 pi r^2 tau = -4 pi eta B (against its rotation) and the
// outer cylinder's is +4 pi eta B.
struct TaylorCouette {
  /// time average of a ring's (width dx) mean of u_theta - exact, largest over the rings and
  /// the ring next to the inner cylinder [/ (Omega R1)]
  double err_rings = 0, err_wall_ring = 0;
  double torque_inner = 0, torque_outer = 0;  ///< time averages [/ (4 pi eta B)]
};

TaylorCouette run_taylor_couette(int n) {
  // R1 = G = R2 - R1 = 1 mm, nu = 1e-6 m^2/s, Omega = 1 rad/s: Re = Omega R1 G / nu = 1; the
  // slowest transient decays as exp(-~pi^2 nu t / G^2), below 1e-3 Omega R1 after 0.6 G^2 / nu.
  // Averages over t = 0.6 .. 1 s: a particle's u_theta is 5-15 % of Omega R1 off at any instant
  // (particle disorder; the flow turns the lattice by about a radian), a ring's mean drifts by
  // about 1 % over 0.5 s.
  const double r1 = 1e-3, r2 = 2e-3, nu = 1e-6, rho = 1000, omega = 1.0;
  const double t_avg = 0.6, t_end = 1.0;
  const double eta = nu * rho;
  const double dx = (r2 - r1) / n, th = 3 * dx;
  const double u0 = omega * r1;
  const double a = -omega * r1 * r1 / (r2 * r2 - r1 * r1);
  const double b = omega * r1 * r1 * r2 * r2 / (r2 * r2 - r1 * r1);
  SphConfig c;
  c.dimension = 2;
  const double ext = r2 + th + dx;
  c.domain.lo = {-ext, -ext, 0};
  c.domain.hi = {ext, ext, 0};
  c.spacing = dx;
  c.density = rho;
  // Mach 0.1. The viscous step limits (at 20 across: 5.3e-4 s against 1.2e-3 s acoustic); a
  // larger c0 or a background pressure makes the particle noise larger, not smaller.
  c.sound_speed = 10 * u0;
  c.rheology = prepare_rheology("newtonian", {{"viscosity", eta}});
  SphBlock liquid;  // the annulus R1 < r <= R2 on the walls' lattice
  liquid.shape = SphBlock::Shape::Cylinder;
  liquid.radius = r2;
  liquid.thickness = r2 - r1;
  c.blocks.push_back(liquid);
  SphWall inner;  // a rigid shell 3 dx (> 2h) thick: the same rigid body as a solid disk
  inner.name = "inner";
  inner.shape = SphWall::Shape::Cylinder;
  inner.radius = r1;
  inner.thickness = th;
  inner.angular_velocity = {0, 0, omega};
  c.walls.push_back(inner);
  SphWall outer;
  outer.name = "outer";
  outer.shape = SphWall::Shape::Cylinder;
  outer.radius = r2 + th;
  outer.thickness = th;
  c.walls.push_back(outer);
  SphSolver s(c);
  auto exact = [&](double r) { return a * r + b / r; };
  std::vector<double> ring_err(static_cast<std::size_t>(n), 0.0);  // summed over samples
  TaylorCouette out;
  int samples = 0;
  while (s.time() < t_end - 1e-12) {
    s.step(s.time() < t_avg ? t_avg : t_end);
    if (s.time() < t_avg - 1e-12) continue;
    const auto m = s.wall_torques();
    out.torque_inner += m[0].z;
    out.torque_outer += m[1].z;
    std::vector<double> sum(static_cast<std::size_t>(n), 0.0);
    std::vector<int> cnt(static_cast<std::size_t>(n), 0);
    const auto& p = s.particles();
    for (std::size_t i = 0; i < s.n_fluid(); ++i) {
      const double r = std::hypot(p.x[i].x, p.x[i].y);
      const auto k =
          static_cast<std::size_t>(std::clamp(static_cast<int>((r - r1) / dx), 0, n - 1));
      sum[k] += (p.x[i].x * p.v[i].y - p.x[i].y * p.v[i].x) / r - exact(r);
      ++cnt[k];
    }
    for (std::size_t k = 0; k < sum.size(); ++k) ring_err[k] += sum[k] / std::max(1, cnt[k]);
    ++samples;
  }
  const double m_exact = 4 * std::numbers::pi * eta * b;
  out.torque_inner /= samples * m_exact;
  out.torque_outer /= samples * m_exact;
  test::Dump dump(fmt::format("sph_taylor_couette_{}", n), "r,u_theta,u_exact");
  for (int k = 0; k < n; ++k) {
    const double r = r1 + (k + 0.5) * dx;
    const double e = ring_err[static_cast<std::size_t>(k)] / samples;
    dump.row(r, exact(r) + e, exact(r));
    out.err_rings = std::max(out.err_rings, std::fabs(e) / u0);
    if (k == 0) out.err_wall_ring = e / u0;
  }
  return out;
}

TEST(ValidationSph, TaylorCouetteFlow) {
  // 20 particles across the gap (about 11 s on one core). Measured over t = 0.6-1 s (and over
  // 0.3-0.6 s and 1-1.4 s), in units of Omega R1 and 4 pi eta B:
  //   20 across: wall ring +0.62 % (+0.51, +0.59), rings 1.2 % (0.75, 1.4), torque inner
  //              -0.998 (-0.999, -1.012), outer 1.033 (0.993, 1.064);
  //   10 across: wall ring +0.26 %, rings 1.6 %, torque inner -0.990, outer 1.043.
  // Without the rotating wall's midpoint velocity in the mirrored velocity (Adami's
  // 2 u_w - v~ with u_w the wall particle's own velocity) the liquid slips on the inner
  // cylinder: wall ring -1.5 to -1.7 % at 20 across (-3.6 % at 10); without the surface term
  // eta n x Omega of the torque the inner torque is -0.66 (the Morris term's stress eta grad v
  // lacks eta (grad v)^T). 1 % on the wall ring, 2.5 % on every ring (the slow ~1 % drift of
  // the rings' means), 3 % on the inner torque and 7 % on the outer one (it drifts with the
  // rings) bound what was measured and fail for either defect.
  const auto r = run_taylor_couette(20);
  EXPECT_LT(std::fabs(r.err_wall_ring), 0.01);
  EXPECT_LT(r.err_rings, 0.025);
  EXPECT_NEAR(r.torque_inner, -1.0, 0.03);
  EXPECT_NEAR(r.torque_outer, 1.0, 0.07);
}

}  // namespace
}  // namespace gf::continuum
