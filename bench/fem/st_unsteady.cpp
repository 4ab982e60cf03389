// SPDX-License-Identifier: GPL-3.0-or-later
// Schaefer-Turek 2D-2 (Re = 100, periodic) and 2D-3 (U(t) = 1.5 sin(pi t / 8)) with BDF2 (or
// BDF1 / BDF3 with `order k`, variable order 1-3 with `order auto`, which needs `adaptive`).
// Usage: st_unsteady <2|3> <h_body> <h_max> <dt> <t_end> <out.csv> [reuse] [adaptive rtol] [wake h]
//        [order k|auto] [dt_max s]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>

#include "fluid/fem/schaefer_turek.hpp"
#include "fluid/fem/time_stepping.hpp"

using namespace gf::fem;
namespace st = schaefer_turek;

int main(int argc, char** argv) {
  if (argc < 7) {
    std::fprintf(stderr,
                 "usage: st_unsteady <2|3> h_body h_max dt t_end out.csv [reuse] [adaptive rtol] "
                 "[wake h] [order k|auto] [dt_max s]\n");
    return 2;
  }
  const int which = std::atoi(argv[1]);
  const double h_body = std::atof(argv[2]), h_max = std::atof(argv[3]), dt = std::atof(argv[4]);
  const double t_end = std::atof(argv[5]);
  const std::string out = argv[6];
  bool reuse = false, adaptive = false;
  double h_wake = 0;
  double rtol = 1e-3, dt_max = 0.05;
  int order = 2;
  bool variable_order = false;
  for (int i = 7; i < argc; ++i) {
    if (std::string(argv[i]) == "reuse") reuse = true;
    if (std::string(argv[i]) == "adaptive" && i + 1 < argc) {
      adaptive = true;
      rtol = std::atof(argv[++i]);
    }
    if (std::string(argv[i]) == "wake" && i + 1 < argc) h_wake = std::atof(argv[++i]);
    if (std::string(argv[i]) == "dt_max" && i + 1 < argc) dt_max = std::atof(argv[++i]);
    if (std::string(argv[i]) == "order" && i + 1 < argc) {
      variable_order = std::string(argv[++i]) == "auto";
      order = variable_order ? kMaxBdfOrder : std::atoi(argv[i]);
    }
  }
  auto t0 = std::chrono::steady_clock::now();
  auto sec = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  std::function<double(double)> f;
  double u_max = 1.5;
  if (which == 3) {
    f = [](double t) { return std::sin(std::numbers::pi * t / 8.0); };
  } else {
    f = [](double t) { return t < 1.0 ? 0.5 * (1 - std::cos(std::numbers::pi * t)) : 1.0; };
  }
  NavierStokes ns(st::make_problem({h_max, h_body, 0.2, h_wake}, u_max, f));
  std::fprintf(stderr, "cells %d dofs %d\n", ns.mesh().n_cells(), ns.n_dofs());
  FILE* fp = std::fopen(out.c_str(), "w");
  std::fprintf(fp, "t,dt,cd,cl,dp,cd_stress,cl_stress\n");
  NewtonOptions opt;
  opt.tolerance = 1e-8;
  opt.reuse_factorization = reuse;
  TimeControl tc;
  tc.order = order;
  tc.variable_order = variable_order;
  tc.dt = dt;
  tc.t_end = t_end;
  tc.adaptive = adaptive;
  tc.rtol = rtol;
  tc.atol = rtol;  // velocities are O(1) m/s
  tc.dt_max = dt_max;
  const auto stats = integrate(ns, tc, opt, [&](const NavierStokes& s, double h) {
    const double ubar = 2.0 / 3.0 * 1.5;  // coefficients use the peak mean velocity 1 m/s
    const auto c = st::coefficients(s, s.reaction_forces()[0], ubar);
    const auto cs = st::coefficients(s, s.stress_forces()[0], ubar);
    std::fprintf(fp, "%.8f,%.3e,%.10f,%.10f,%.10f,%.10f,%.10f\n", s.time(), h, c.cd, c.cl, c.dp,
                 cs.cd, cs.cl);
  });
  std::fclose(fp);
  std::printf(
      "steps %d (orders 1/2/3: %d/%d/%d) rejected %d newton %d factorizations %d wall %.1f s "
      "(factor %.1f s, assembly %.1f s, solve %.1f s)\n",
      stats.steps, stats.steps_at_order[1], stats.steps_at_order[2], stats.steps_at_order[3],
      stats.rejected, stats.newton_iterations, stats.factorizations, sec(),
      ns.lu().factor_seconds(), ns.assembly_seconds(), ns.lu().solve_seconds());
  return 0;
}
