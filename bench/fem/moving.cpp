// SPDX-License-Identifier: GPL-3.0-or-later
// Time series of the moving-body validations (tests/fem/test_fem_moving.cpp) for the plots of
// docs/validation/fem/plot_moving.py:
//   gf_fem_bench_moving OUT_DIR
// writes moving_stokes.csv, moving_re10.csv, moving_floor_disk.csv, moving_floor_square.csv,
// moving_slope_hold.csv, moving_slope_slide.csv (columns t, x, y, angle, vx, vy, omega,
// remeshes, and for the slopes the contact force fx, fy; a first comment line with the
// reference).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "moving_cases.hpp"

namespace {

using gf::fem_dem::MovingBodyFlow;

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// Prints the cost of a run: wall time per step, the share of remeshing, Newton's work.
void report(const char* name, const MovingBodyFlow& run, const gf::fem_bench::StepTotals& t,
            double seconds) {
  std::printf(
      "%-18s %4d steps %3d remeshes %6d unknowns (last mesh) %6.2f s %6.1f ms/step, "
      "remeshing %5.2f s, Newton %.2f it. and %.2f LU per step\n",
      name, t.steps, run.remeshes(), run.flow().n_dofs(), seconds, 1e3 * seconds / t.steps,
      run.remesh_seconds(), double(t.iterations) / t.steps, double(t.factorizations) / t.steps);
}

struct Series {
  std::FILE* f;
  bool contact;
  explicit Series(const std::filesystem::path& p, const std::string& reference,
                  bool with_contact = false)
      : f(std::fopen(p.c_str(), "w")), contact(with_contact) {
    if (!f) throw std::runtime_error("cannot write " + p.string());
    std::fprintf(f, "# %s\nt,x,y,angle,vx,vy,omega,remeshes%s\n", reference.c_str(),
                 contact ? ",fx,fy" : "");
  }
  ~Series() { std::fclose(f); }
  Series(const Series&) = delete;
  Series& operator=(const Series&) = delete;
  void operator()(const MovingBodyFlow& r) const {
    const auto v = r.flow().body_velocity(0);
    const auto& p = r.poses()[0];
    std::fprintf(f, "%.6g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d", r.time(), p.centre.x, p.centre.y,
                 p.angle, v.velocity.x, v.velocity.y, v.angular_velocity, r.remeshes());
    if (contact)
      std::fprintf(f, ",%.9g,%.9g", r.contact_loads()[0].force.x, r.contact_loads()[0].force.y);
    std::fprintf(f, "\n");
  }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
    return 2;
  }
  const std::filesystem::path out = argv[1];
  std::filesystem::create_directories(out);
  using namespace gf::fem_bench;
  {
    const double ut = 0.5 * 100 * std::numbers::pi * 0.01 / faxen_resistance(0.2);
    const Series s(out / "moving_stokes.csv", "Faxen terminal speed U_t = " + std::to_string(ut));
    MovingBodyFlow run = stokes_settling({}, 0.02);
    const double t0 = now();
    const auto t = run_steps(run, 0.01, 1.0, [&](const MovingBodyFlow& r) { s(r); });
    report("stokes_settling", run, t, now() - t0);
  }
  {
    const double u_star = re10_terminal_speed();
    const Series s(out / "moving_re10.csv",
                   "steady speed in the disk's frame U* = " + std::to_string(u_star));
    MovingBodyFlow run = re10_settling();
    const double t0 = now();
    const auto t = run_steps(run, 0.01, 2.0, [&](const MovingBodyFlow& r) { s(r); });
    report("re10_settling", run, t, now() - t0);
  }
  {
    const Series s(out / "moving_floor_disk.csv", "balance gap 0.015");
    const double t0 = now();
    StepTotals t;
    const auto run = settle_on_floor(
        false, 0.0, 3.0, [&](const MovingBodyFlow& r) { s(r); }, &t);
    report("disk_onto_floor", run, t, now() - t0);
  }
  {
    const Series s(out / "moving_floor_square.csv", "balance gap 0.0194 (flat)");
    const double t0 = now();
    StepTotals t;
    const auto run = settle_on_floor(
        true, 0.3, 4.0, [&](const MovingBodyFlow& r) { s(r); }, &t);
    report("square_onto_floor", run, t, now() - t0);
  }
  for (const auto& [name, ratio] : {std::pair{"hold", 0.9}, {"slide", 1.1}}) {
    const double mu = 0.5, tan_s = ratio * mu;
    const std::string file = std::string("moving_slope_") + name + ".csv";
    const Series s(out / file,
                   "square on a slope, mu = 0.5, tan(slope) / mu = " + std::to_string(ratio), true);
    const double t0 = now();
    StepTotals t;
    const auto run = square_on_slope(
        tan_s, mu, 3.0, [&](const MovingBodyFlow& r) { s(r); }, &t);
    report(file.c_str(), run, t, now() - t0);
  }
  return 0;
}
