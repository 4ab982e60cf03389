// SPDX-License-Identifier: GPL-3.0-or-later
// The finite-volume fluid solver against published and analytic references: the lid-driven
// cavity at Re = 100 (Ghia, Ghia & Shin, J. Comput. Phys. 48 (1982) 387, Tables I and II) and
// the grid convergence of plane Poiseuille flow. Curves go to GF_VALIDATION_OUT for
// scripts/plot_fluid_fv.py.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "dump.hpp"
#include "fluid/fv/navier_stokes.hpp"

using namespace gf;
using namespace gf::fluid;

namespace {

// Ghia et al. (1982), Re = 100, 129 x 129 grid. Table I: u along the vertical line through the
// geometric centre (x = 0.5); Table II: v along the horizontal line (y = 0.5).
constexpr double kGhiaY[17] = {1.0000, 0.9766, 0.9688, 0.9609, 0.9531, 0.8516,
                               0.7344, 0.6172, 0.5000, 0.4531, 0.2813, 0.1719,
                               0.1016, 0.0703, 0.0625, 0.0547, 0.0000};
constexpr double kGhiaU[17] = {1.00000,  0.84123,  0.78871,  0.73722,  0.68717,  0.23151,
                               0.00332,  -0.13641, -0.20581, -0.21090, -0.15662, -0.10150,
                               -0.06434, -0.04775, -0.04192, -0.03717, 0.00000};
constexpr double kGhiaX[17] = {1.0000, 0.9688, 0.9609, 0.9531, 0.9453, 0.9063,
                               0.8594, 0.8047, 0.5000, 0.2344, 0.2266, 0.1563,
                               0.0938, 0.0781, 0.0703, 0.0625, 0.0000};
constexpr double kGhiaV[17] = {0.00000,  -0.05906, -0.07391, -0.08864, -0.10313, -0.16914,
                               -0.22445, -0.24533, 0.05454,  0.17527,  0.17507,  0.16077,
                               0.12317,  0.10890,  0.10091,  0.09233,  0.00000};

/// Linear interpolation of samples (s_k, v_k), s increasing, at s (clamped to the ends).
double interpolate(const std::vector<double>& s, const std::vector<double>& v, double x) {
  if (x <= s.front()) return v.front();
  if (x >= s.back()) return v.back();
  std::size_t k = 1;
  while (s[k] < x) ++k;
  const double w = (x - s[k - 1]) / (s[k] - s[k - 1]);
  return (1 - w) * v[k - 1] + w * v[k];
}

/// Runs the lid-driven cavity at Re = 100 on n x n cells to steady state; returns the maximum
/// deviations from Ghia's Table I (u) and II (v) in units of the lid speed.
std::pair<double, double> cavity(Convection scheme, const char* name) {
  const int n = 64;
  Grid g;
  g.dimension = 2;
  g.n = {n, n, 1};
  g.h = {1.0 / n, 1.0 / n, 1.0};
  FluidSettings s;
  s.density = 1.0;
  s.dynamic_viscosity = 0.01;  // Re = 1 * 1 / 0.01
  s.convection = scheme;
  for (BoxFace f : {BoxFace::XMin, BoxFace::XMax, BoxFace::YMin})
    s.boundary[box_face_index(f)] = BoundaryCondition::no_slip();
  s.boundary[box_face_index(BoxFace::YMax)] = BoundaryCondition::moving_wall({1.0, 0, 0});
  VolumeAveragedNS fluid(g, s);

  const auto t0 = std::chrono::steady_clock::now();
  const double dt = 0.5 / n;  // Courant number 0.5 (|u| + |v|) <= ~0.6
  std::vector<double> before;
  double change = 1.0;
  int steps = 0;
  while (change > 1e-8 && steps < 20000) {
    before.assign(fluid.face_velocity(0).begin(), fluid.face_velocity(0).end());
    before.insert(before.end(), fluid.face_velocity(1).begin(), fluid.face_velocity(1).end());
    fluid.step(dt);
    ++steps;
    change = 0.0;
    std::size_t k = 0;
    for (int a = 0; a < 2; ++a)
      for (double v : fluid.face_velocity(a)) change = std::max(change, std::abs(v - before[k++]));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LE(change, 1e-8) << "no steady state after " << steps << " steps";
  EXPECT_LE(fluid.divergence_norm(), 1e-8);

  // u(y) on the faces x = 0.5 (face i = n/2), v(x) on the faces y = 0.5, plus the walls.
  std::vector<double> ys{0.0}, us{0.0}, xs{0.0}, vs{0.0};
  for (int j = 0; j < n; ++j) {
    ys.push_back((j + 0.5) / n);
    us.push_back(fluid.face_velocity(0)[g.face_index(0, n / 2, j, 0)]);
    xs.push_back((j + 0.5) / n);
    vs.push_back(fluid.face_velocity(1)[g.face_index(1, j, n / 2, 0)]);
  }
  ys.push_back(1.0);
  us.push_back(1.0);
  xs.push_back(1.0);
  vs.push_back(0.0);

  test::Dump profile("fluid_fv_cavity_" + std::string(name), "s,u_of_y,v_of_x");
  for (std::size_t k = 0; k < ys.size(); ++k) profile.row(ys[k], us[k], vs[k]);
  double dev_u = 0.0, dev_v = 0.0;
  for (int k = 0; k < 17; ++k) {
    dev_u = std::max(dev_u, std::abs(interpolate(ys, us, kGhiaY[k]) - kGhiaU[k]));
    dev_v = std::max(dev_v, std::abs(interpolate(xs, vs, kGhiaX[k]) - kGhiaV[k]));
  }
  std::printf(
      "cavity Re=100 64x64 %s: %d steps, t = %.2f, %.1f s; max |u - Ghia| = %.4f, "
      "max |v - Ghia| = %.4f (of U)\n",
      name, steps, fluid.time(), seconds, dev_u, dev_v);
  return {dev_u, dev_v};
}

}  // namespace

// Lid-driven cavity, Re = U L / nu = 100 on 64 x 64 cells, run from rest to steady state by
// time stepping (Courant 0.5) until the largest change of a face velocity per step is below
// 1e-8 U (d|u|/dt < 1e-6 U^2/L; the slowest mode decays in ~2 L/U, so what is left is < 1e-5 U).
// Ghia's values are themselves a 129 x 129 second-order solution (accurate to a few 1e-3 U),
// and the profiles are read off our grid by linear interpolation between cell centres (error
// h^2 u''/8 ~ 1e-3 U near the lid). Tolerance: the criterion, max deviation over the 17
// points of each table <= 2 % of U, for both convection schemes (measured: ~0.5 % and ~0.9 %,
// see docs/validation/README.md).
TEST(FluidFVValidation, LidDrivenCavityRe100MatchesGhia) {
  for (auto [scheme, name] :
       {std::pair{Convection::VanLeer, "van_leer"}, std::pair{Convection::Central, "central"}}) {
    const auto [dev_u, dev_v] = cavity(scheme, name);
    EXPECT_LE(dev_u, 0.02) << name;
    EXPECT_LE(dev_v, 0.02) << name;
  }
}

// Grid convergence, for the plot of docs/validation: plane Poiseuille flow (body force, exact
// discrete error (h/H)^2 u_max, see tests/unit/test_fluid_fv.cpp) on 8 ... 64 cells, and the
// decaying Taylor-Green vortex u = (-cos x sin y, sin x cos y) exp(-2 nu t) on (0, 2 pi)^2,
// nu = 0.05, to t = 1 with dt = 1 / (2 N) (Courant ~0.3), which tests convection, pressure and
// BDF2 together: the max error over the u faces must fall at second order (observed order >= 1.9
// between the two finest grids). For van Leer the limiter clips only within O(h) of smooth
// extrema, where the slopes are O(h), so its difference to central is O(h^2) as well. Upwind
// adds a viscosity |u| h / 2, O(h): its order must lie in [0.8, 1.3] (first order; the upper
// bound leaves room for the O(h^2) part still visible at 32 -> 64, and fails a scheme that
// silently fell back to a second-order one).
TEST(FluidFVValidation, GridConvergence) {
  test::Dump poiseuille("fluid_fv_poiseuille_convergence", "n,error");
  for (int ny : {8, 16, 32, 64}) {
    FluidSettings s;
    s.density = 1.0;
    s.dynamic_viscosity = 1.0;
    s.gravity = {8.0, 0, 0};
    s.boundary[0] = s.boundary[1] = BoundaryCondition::periodic();
    Grid g;
    g.dimension = 2;
    g.n = {4, ny, 1};
    g.h = {0.25, 1.0 / ny, 1.0};
    g.periodic = {true, false, false};
    VolumeAveragedNS f(g, s);
    for (int n = 0; n < 400; ++n) f.step(0.02);  // 8 diffusion times: e^-80 of the start
    double e = 0.0;
    for (int j = 0; j < ny; ++j) {
      const double y = (j + 0.5) / ny;
      e = std::max(e, std::abs(f.face_velocity(0)[g.face_index(0, 1, j, 0)] - 4 * y * (1 - y)));
    }
    poiseuille.row(ny, e);
    EXPECT_NEAR(e * ny * ny, 1.0, 1e-6) << ny;
  }
  test::Dump tg("fluid_fv_taylor_green_convergence", "n,central,van_leer,upwind");
  const std::array<std::pair<Convection, const char*>, 3> schemes{
      {{Convection::Central, "central"},
       {Convection::VanLeer, "van Leer"},
       {Convection::Upwind, "upwind"}}};
  std::vector<double> err[3];
  for (int n : {16, 32, 64}) {
    for (int k = 0; k < 3; ++k) {
      const double nu = 0.05, len = 2 * M_PI;
      Grid g;
      g.dimension = 2;
      g.n = {n, n, 1};
      g.h = {len / n, len / n, 1.0};
      g.periodic = {true, true, false};
      FluidSettings s;
      s.density = 1.0;
      s.dynamic_viscosity = nu;
      s.convection = schemes[k].first;
      for (int b = 0; b < 4; ++b) s.boundary[b] = BoundaryCondition::periodic();
      VolumeAveragedNS f(g, s);
      f.set_velocity([](const Vec3& x) {
        return Vec3{-std::cos(x.x) * std::sin(x.y), std::sin(x.x) * std::cos(x.y), 0};
      });
      for (int step = 0; step < 2 * n; ++step) f.step(0.5 / n);
      const double decay = std::exp(-2 * nu * f.time());
      double e = 0.0;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const Vec3 x = g.face_center(0, i, j, 0);
          e = std::max(e, std::abs(f.face_velocity(0)[g.face_index(0, i, j, 0)] +
                                   std::cos(x.x) * std::sin(x.y) * decay));
        }
      err[k].push_back(e);
    }
    tg.row(n, err[0].back(), err[1].back(), err[2].back());
  }
  for (int k = 0; k < 3; ++k) {
    const double order = std::log2(err[k][1] / err[k][2]);
    std::printf("Taylor-Green %s: errors %.3e %.3e %.3e, order (32->64) %.2f\n", schemes[k].second,
                err[k][0], err[k][1], err[k][2], order);
    if (schemes[k].first == Convection::Upwind) {
      EXPECT_GE(order, 0.8);
      EXPECT_LE(order, 1.3);
    } else {
      EXPECT_GE(order, 1.9);
    }
  }
}
