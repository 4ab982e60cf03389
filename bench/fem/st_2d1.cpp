// SPDX-License-Identifier: GPL-3.0-or-later
// Schaefer-Turek 2D-1 (steady, Re = 20) on one mesh: errors and times as CSV.
// Usage: st_2d1 [h_body] [h_max] [grading] [reuse|full] [mesh dump file]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fluid/fem/schaefer_turek.hpp"

using namespace gf::fem;

int main(int argc, char** argv) {
  namespace st = schaefer_turek;
  const double h_body = argc > 1 ? std::atof(argv[1]) : 0.01;
  const double h_max = argc > 2 ? std::atof(argv[2]) : 4 * h_body;
  const double grading = argc > 3 ? std::atof(argv[3]) : 0.25;
  const std::string variant = argc > 4 ? argv[4] : "full";
  const bool reuse = variant == "reuse" || variant == "nested";
  const bool nested = variant == "nested";
  const char* dump = argc > 5 ? argv[5] : nullptr;  // write the mesh for bench/fem/dolfinx_2d1.py
  auto t0 = std::chrono::steady_clock::now();
  auto sec = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  FlowProblem pb = st::make_problem({h_max, h_body, grading}, 0.3);
  const double t_mesh = sec();
  if (dump != nullptr) {
    FILE* fp = std::fopen(dump, "w");
    std::fprintf(fp, "%d %d\n", pb.mesh.n_nodes(), pb.mesh.n_cells());
    for (const auto& p : pb.mesh.nodes) std::fprintf(fp, "%.17g %.17g\n", p.x, p.y);
    for (const auto& c : pb.mesh.cells)
      std::fprintf(fp, "%d %d %d %d %d %d\n", c[0], c[1], c[2], c[3], c[4], c[5]);
    std::fclose(fp);
  }
  NavierStokes ns(std::move(pb));
  const double t_setup = sec();
  NewtonOptions opt;
  opt.tolerance = 1e-10;
  opt.reuse_factorization = reuse;
  const NewtonReport rep = nested ? solve_steady_nested(ns, opt) : ns.solve_steady(opt);
  const double t_solve = sec();
  const auto f = ns.reaction_forces()[0];
  const auto fs = ns.stress_forces()[0];
  const auto c = st::coefficients(ns, f, 0.2);
  const auto cs = st::coefficients(ns, fs, 0.2);
  std::printf(
      "h_body,h_max,cells,dofs,newton_it,factorizations,converged,cd,cl,dp,cd_err,cl_err,dp_err,cd_"
      "stress,cl_stress,"
      "t_mesh,t_setup,t_solve,t_assembly,t_factor,t_total\n");
  std::printf(
      "%g,%g,%d,%d,%d,%d,%d,%.10f,%.10f,%.10f,%.3e,%.3e,%.3e,%.10f,%.10f,%.3f,%.3f,%.3f,%.3f,%.3f,%"
      ".3f\n",
      h_body, h_max, ns.mesh().n_cells(), ns.n_dofs(), rep.iterations, rep.factorizations,
      rep.converged ? 1 : 0, c.cd, c.cl, c.dp, c.cd / st::kCd1 - 1, c.cl / st::kCl1 - 1,
      c.dp / st::kDp1 - 1, cs.cd, cs.cl, t_mesh, t_setup - t_mesh, t_solve - t_setup,
      ns.assembly_seconds(), ns.lu().factor_seconds(), t_solve);
  return rep.converged ? 0 : 1;
}
