// SPDX-License-Identifier: GPL-3.0-or-later
// Continuum (SPH) validation: a liquid at rest, transient plane Poiseuille flow (explicit and
// implicit viscosity), the Bagnold profile of a mu(I) layer flowing down an incline, and a mu(I)
// layer below its yield slope (implicit viscosity).
#include <fmt/format.h>
#include <gtest/gtest.h>

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

void run_poiseuille(bool implicit, double transient_tolerance, double steady_tolerance = 0.01,
                    int dimension = 2, int n = 20) {
  // Morris et al.'s case: L = 1 mm, nu = 1e-6 m^2/s, F = 1e-4 m/s^2 (Re = u_max L / nu =
  // 0.0125), n particles across, 3 wall layers (> 2h) each side; in 3D periodic along z too.
  const double l = 1e-3, nu = 1e-6, f = 1e-4, rho = 1000;
  const double dx = l / n, width = 8 * dx, th = 3 * dx;
  const double depth = dimension == 3 ? width : 0.0;
  const double u_max = f * l * l / (8 * nu);
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
  c.implicit_viscosity = implicit;
  SphSolver s(c);
  test::Dump dump(
      fmt::format("sph_poiseuille{}{}", implicit ? "_implicit" : "", dimension == 3 ? "_3d" : ""),
      "t,y,u,u_exact");
  for (double t_end : {0.0225, 0.045, 0.1125, 0.225, 1.0}) {
    while (s.time() < t_end - 1e-12) s.step(t_end);
    double err = 0;
    const auto& p = s.particles();
    for (std::size_t i = 0; i < s.n_fluid(); ++i) {
      const double ex = poiseuille(p.x[i].y, s.time(), f, nu, l);
      err = std::max(err, std::fabs(p.v[i].x - ex));
      if (p.x[i].x < dx) dump.row(s.time(), p.x[i].y, p.v[i].x, ex);
      EXPECT_LT(std::fabs(p.v[i].y), 1e-3 * u_max);
      EXPECT_LT(std::fabs(p.v[i].z), 1e-3 * u_max);
    }
    EXPECT_LT(err, (t_end < 1.0 ? transient_tolerance : steady_tolerance) * u_max)
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

// Steady uniform flow of a mu(I) layer on an incline (GDR MiDi 2004, sec. 4.1; Jop et al. 2006):
// p = rho g cos(theta) (H - y), tau = tan(theta) p, so mu(I) = tan(theta) everywhere and
// u(y) = 2/3 I_theta / d sqrt(phi g cos(theta)) (H^(3/2) - (H - y)^(3/2)) (the Bagnold profile),
// with I_theta = I0 (tan(theta) - mu_s) / (mu_2 - tan(theta)) and phi = rho / rho_s.
TEST(ValidationSph, BagnoldProfileOnIncline) {
  const double d = 1e-3, h = 0.02, rho_s = 2500, phi = 0.6, rho = phi * rho_s, g = 9.81;
  const double theta = 25.0 * std::numbers::pi / 180.0;
  const int n = 20;
  const double dx = h / n, width = 8 * dx, th = 3 * dx;
  SphConfig c;
  c.dimension = 2;
  c.domain.lo = {0, -th, 0};
  c.domain.hi = {width, 2 * h, 0};
  c.domain.periodic = {true, false, false};
  c.gravity = {g * std::sin(theta), -g * std::cos(theta), 0};
  c.spacing = dx;
  c.density = rho;
  c.sound_speed = 6.0;  // 10 x the surface speed 0.58 m/s
  const std::map<std::string, double> params{
      {"mu_s", 0.382},       {"mu_2", 0.643},          {"i0", 0.279},
      {"grain_diameter", d}, {"grain_density", rho_s}, {"max_viscosity", 30.0}};
  c.rheology = prepare_rheology("mu_i", params);
  c.blocks.push_back({{0, 0, 0}, {width, h, 0}, {}, true});
  c.walls.push_back(box_wall("bed", {0, -th, 0}, {width, 0, 0}));
  SphSolver s(c);
  const double i_theta = MuI::inertial_number_for(std::tan(theta), c.rheology);
  const double k = 2.0 / 3.0 * i_theta / d * std::sqrt(phi * g * std::cos(theta));
  const double u_s = k * std::pow(h, 1.5);
  while (s.time() < 4.0 - 1e-12) s.step(4.0);
  // Layer averages of u (the layers stay layers: the flow is a shear along them).
  std::vector<double> u(n, 0.0);
  std::vector<int> cnt(n, 0);
  const auto& p = s.particles();
  for (std::size_t i = 0; i < s.n_fluid(); ++i) {
    const int layer = static_cast<int>(std::floor(p.x[i].y / dx));
    ASSERT_GE(layer, 0);
    ASSERT_LT(layer, n);
    u[static_cast<std::size_t>(layer)] += p.v[i].x;
    ++cnt[static_cast<std::size_t>(layer)];
  }
  test::Dump dump("sph_bagnold", "y,u,u_exact");
  double err = 0;
  for (int j = 0; j < n; ++j) {
    const double y = (j + 0.5) * dx;
    const double ex = k * (std::pow(h, 1.5) - std::pow(h - y, 1.5));
    const double uj = u[static_cast<std::size_t>(j)] / cnt[static_cast<std::size_t>(j)];
    dump.row(y, uj, ex);
    err = std::max(err, std::fabs(uj - ex));
  }
  // The velocity is very sensitive to the stress: d ln I / d ln mu = mu / (I mu'(I)) = 8 here,
  // so a 0.5 % error of the viscous or pressure operators moves the profile by 4 % (before the
  // lattice normalisation of the pressure gradient the profile was 18 % slow). Measured
  // 0.9-1.5 % of u_s at t = 3.5-4 s, with the acoustic noise of Mach 0.1; 4 % bounds it.
  EXPECT_LT(err, 0.04 * u_s);
}

// Below the yield slope (tan(theta) < mu_s) a regularised mu(I) layer is a Newtonian film of
// viscosity max_viscosity: u(y) = rho g sin(theta) / eta_max (H y - y^2 / 2). The explicit
// viscous step would be 1.3e-6 s (eta_max = 1e3 Pa s) or 1.3e-7 s (1e4); the implicit one runs
// at the step of the acoustic and force limits.
struct FilmResult {
  double max_error = 0, u_surface = 0, max_speed = 0, step = 0;
};

FilmResult run_creeping_film(double eta_max) {
  const double d = 1e-3, h = 0.02, rho_s = 2500, phi = 0.6, rho = phi * rho_s, g = 9.81;
  const double theta = 15.0 * std::numbers::pi / 180.0;
  const int n = 20;
  const double dx = h / n, width = 8 * dx, th = 3 * dx;
  SphConfig c;
  c.dimension = 2;
  c.domain.lo = {0, -th, 0};
  c.domain.hi = {width, 2 * h, 0};
  c.domain.periodic = {true, false, false};
  c.gravity = {g * std::sin(theta), -g * std::cos(theta), 0};
  c.spacing = dx;
  c.density = rho;
  c.sound_speed = 6.0;
  c.implicit_viscosity = true;
  c.rheology = prepare_rheology(
      "mu_i", {{"grain_diameter", d}, {"grain_density", rho_s}, {"max_viscosity", eta_max}});
  c.blocks.push_back({{0, 0, 0}, {width, h, 0}, {}, true});
  c.walls.push_back(box_wall("bed", {0, -th, 0}, {width, 0, 0}));
  SphSolver s(c);
  // the film's viscous time rho H^2 / eta_max is below 1e-3 s: 0.05 s is steady
  while (s.time() < 0.05 - 1e-12) s.step(0.05);
  FilmResult out;
  out.step = s.last_step();
  out.max_speed = s.summary().max_speed;
  std::vector<double> u(n, 0.0);
  std::vector<int> cnt(n, 0);
  const auto& p = s.particles();
  for (std::size_t i = 0; i < s.n_fluid(); ++i) {
    const int layer = static_cast<int>(std::floor(p.x[i].y / dx));
    if (layer < 0 || layer >= n) continue;
    u[static_cast<std::size_t>(layer)] += p.v[i].x;
    ++cnt[static_cast<std::size_t>(layer)];
  }
  test::Dump dump(fmt::format("sph_creep_{:g}", eta_max), "y,u,u_exact");
  for (int j = 0; j < n; ++j) {
    const double y = (j + 0.5) * dx;
    const double ex = rho * g * std::sin(theta) / eta_max * (h * y - 0.5 * y * y);
    const double uj = u[static_cast<std::size_t>(j)] / cnt[static_cast<std::size_t>(j)];
    dump.row(y, uj, ex);
    out.max_error = std::max(out.max_error, std::fabs(uj - ex));
  }
  out.u_surface = rho * g * std::sin(theta) * h * h / (2 * eta_max);
  return out;
}

TEST(ValidationSph, MuIBelowYieldCreepsAsViscousFilm) {
  const auto film = run_creeping_film(1e3);
  EXPECT_GT(film.step, 10 * 1.3e-6);  // not held to the explicit viscous limit
  // Measured 0.68 % of the surface speed 7.6e-4 m/s; 2 % asserted. Before the shear rate of the
  // rheology was taken from the fluid alone (the walls' mirrored velocities made it ten times
  // too large next to the bed, so the bed layer slipped at a lowered viscosity) it was 3.4 %
  // here and 60 % at eta_max = 1e4.
  EXPECT_LT(film.max_error, 0.02 * film.u_surface);
  // At eta_max = 1e4 Pa s (u_s = 7.6e-5 m/s; explicit step 1.3e-7 s): measured 3.8 %, from
  // the top layers, where p -> 0 lets mu(I) p / gamma_dot fall below the cap; 6 % asserted.
  const auto stiff = run_creeping_film(1e4);
  EXPECT_LT(stiff.max_error, 0.06 * stiff.u_surface);
}

}  // namespace
}  // namespace gf::continuum
