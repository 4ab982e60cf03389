// SPDX-License-Identifier: GPL-3.0-or-later
// Continuum (SPH) cases: loading, `grainflow check` figures, the run loop and its outputs.
#include "simulation/continuum_case.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "continuum/rheology_registry.hpp"
#include "core/error.hpp"
#include "core/files.hpp"
#include "core/log.hpp"
#include "core/stop.hpp"
#include "core/version.hpp"
#include "core/vtk_xml.hpp"
#include "io/input/echo.hpp"
#include "io/restart/h5.hpp"
#include "io/vtk/vtk.hpp"
#include "simulation/output_clock.hpp"

namespace gf {

namespace fs = std::filesystem;

std::optional<input::ContinuumCase> load_continuum_case(
    const fs::path& file, fs::path& output_dir, const std::vector<input::Override>& overrides) {
  const auto root = input::YamlNode::parse_file(file);
  if (!root.is_map() || !root.raw()["continuum"]) return std::nullopt;
  input::apply_overrides(root.raw(), overrides, file);
  input::YamlMap top(root, {"name", "continuum", "output"});
  output_dir = fs::path("out") / file.parent_path().filename();
  if (auto out = top.find("output")) {
    input::YamlMap o(*out, {"directory"});
    output_dir = o.string("directory");
  }
  auto c = input::parse_continuum(top.at("continuum"));
  c.file = file.string();
  c.name = top.has("name") ? top.string("name") : file.parent_path().filename().string();
  return c;
}

namespace {

/// The solver of a case; its set-up errors (overlaps, walls outside the domain) name the file.
continuum::SphSolver build_solver(const input::ContinuumCase& c) {
  try {
    return continuum::SphSolver(c.sph);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: continuum: {}", c.file, e.what()));
  }
}

}  // namespace

std::vector<std::pair<std::string, std::string>> describe_continuum_case(
    const input::ContinuumCase& c) {
  const continuum::SphSolver s = build_solver(c);
  const auto& cfg = s.config();
  std::vector<std::pair<std::string, std::string>> out;
  out.emplace_back("method", fmt::format("SPH ({}D, weakly compressible), rheology {}",
                                         cfg.dimension, c.rheology));
  out.emplace_back("fluid particles / wall particles",
                   fmt::format("{} / {}", s.n_fluid(), s.particles().size() - s.n_fluid()));
  out.emplace_back("smoothing length h, support 2h [m]",
                   fmt::format("{:.4g}, {:.4g}", s.kernel().h, s.kernel().support()));
  out.emplace_back("sound speed c0 [m/s]",
                   fmt::format("{:.4g}{}", cfg.sound_speed,
                               c.sound_speed_given ? "" : " (default: 10 sqrt(2 g H))"));
  const double g = norm(cfg.gravity);
  if (g > 0) {
    const auto sm = s.summary();
    const double height = dot(sm.max_position - sm.min_position, cfg.gravity / g);
    out.emplace_back("Mach number of a free fall over the fluid's height",
                     fmt::format("{:.3f} (keep below ~0.1)",
                                 std::sqrt(2 * g * std::fabs(height)) / cfg.sound_speed));
  }
  const double dt_acoustic = cfg.cfl * s.kernel().h / cfg.sound_speed;
  out.emplace_back("acoustic time step cfl h / c0 [s]", fmt::format("{:.3g}", dt_acoustic));
  if (cfg.rheology.model == index_of_key(continuum::Rheologies{}, continuum::MuI::key)) {
    const double dt_visc =
        0.125 * s.kernel().h * s.kernel().h * cfg.density / cfg.rheology.max_viscosity;
    out.emplace_back(
        "viscous time step at max_viscosity [s]",
        fmt::format("{:.3g}{}", dt_visc,
                    cfg.implicit_viscosity ? " (implicit viscosity: not a limit)" : ""));
  }
  if (const auto& kt = cfg.kinetic_theory) {
    const double d = kt->closures.diameter;
    const double ratio = cfg.spacing / d;
    out.emplace_back("kinetic theory: rho0 / rho_s, dx / d",
                     fmt::format("{:.4g}, {:.3g}{}", cfg.density / kt->closures.density, ratio,
                                 ratio < 3 ? " (below ~3: fields that vary on the grain "
                                             "scale lie outside a continuum model's validity)"
                                           : ""));
  }
  out.emplace_back("first time step [s]", fmt::format("{:.3g}", s.stable_step()));
  out.emplace_back("steps to the end (at the first step)",
                   fmt::format("{:.0f}", std::ceil(c.end_time / s.stable_step())));
  return out;
}

namespace {

/// Fluid and wall particles with their fields (walls: their prescribed velocity).
void write_sph_vtp(const fs::path& path, const continuum::SphSolver& s) {
  const auto& p = s.particles();
  const std::size_t n = p.size();
  std::vector<Vec3> vel(n);
  for (std::size_t i = 0; i < n; ++i) vel[i] = i < s.n_fluid() ? p.v[i] : p.u_wall[i];
  vtk::AppendedArrays arrays;
  std::string data;
  auto add = [&](const char* name, auto values) {
    data += "        " + vtk::AppendedArrays::tag(arrays.add(name, 1, values)) + "\n";
  };
  data += "        " +
          vtk::AppendedArrays::tag(arrays.add("velocity", std::span<const Vec3>(vel))) + "\n";
  add("pressure", std::span<const double>(p.p));
  add("density", std::span<const double>(p.rho));
  add("viscosity", std::span<const double>(p.eta));
  add("shear_rate", std::span<const double>(p.gamma_dot));
  // (the arrays keep spans: the volume fractions live as long as the writer)
  std::vector<double> a;
  if (const auto& kt = s.config().kinetic_theory) {
    a.resize(n);
    for (std::size_t i = 0; i < n; ++i) a[i] = p.rho[i] / kt->closures.density;
    add("granular_temperature", std::span<const double>(p.theta));
    add("volume_fraction", std::span<const double>(a));
  }
  add("wall", std::span<const std::int32_t>(p.wall_index));
  add("id", std::span<const std::int64_t>(p.id));
  io::write_points_vtp(path, arrays, " Vectors=\"velocity\" Scalars=\"pressure\"", data,
                       std::span<const Vec3>(p.x));
}

}  // namespace

namespace {

/// A continuum run's checkpoint: the solver state and the output schedule.
struct ContinuumCheckpoint {
  continuum::SphState state;
  double next_vtk = 0, next_series = 0, next_checkpoint = 0;  ///< [s]
  std::int64_t n_vtk = 0;  ///< sph_particles_*.vtp the schedule wrote so far
  /// time of the last data set the schedule wrote, up to which --append keeps the .pvd series (a
  /// data set written only because the run stopped is dropped)
  double vtk_until = 0;
};

void save_continuum_checkpoint(const fs::path& file, const ContinuumCheckpoint& c) {
  io::write_checkpoint_atomically(file, [&](io::h5::File& h) {
    const auto& st = c.state;
    const auto& p = st.particles;
    io::set_checkpoint_identity(h, "continuum_sph");
    h.set_attribute("/", "time", st.t);
    h.set_attribute("/", "steps", st.steps);
    h.set_attribute("/", "dt_last", st.dt_last);
    h.set_attribute("/", "a_max", st.a_max);
    h.set_attribute("/", "v_max", st.v_max);
    h.set_attribute("/", "eta_max", st.eta_max);
    h.set_attribute("/", "n_fluid", static_cast<std::int64_t>(st.n_fluid));
    h.set_attribute("/", "n_removed", static_cast<std::int64_t>(st.n_removed));
    h.set_attribute("/", "next_vtk", c.next_vtk);
    h.set_attribute("/", "next_series", c.next_series);
    h.set_attribute("/", "next_checkpoint", c.next_checkpoint);
    h.set_attribute("/", "n_vtk", c.n_vtk);
    h.set_attribute("/", "vtk_until", c.vtk_until);
    h.create_group("particles");
    h.write("particles/id", std::span<const std::int64_t>(p.id));
    h.write("particles/x", std::span<const Vec3>(p.x));
    h.write("particles/v", std::span<const Vec3>(p.v));
    h.write("particles/a", std::span<const Vec3>(p.a));
    h.write("particles/rho", std::span<const double>(p.rho));
    h.write("particles/drho", std::span<const double>(p.drho));
    h.write("particles/p", std::span<const double>(p.p));
    h.write("particles/mass", std::span<const double>(p.mass));
    h.write("particles/eta", std::span<const double>(p.eta));
    h.write("particles/gamma_dot", std::span<const double>(p.gamma_dot));
    h.write("particles/u_wall", std::span<const Vec3>(p.u_wall));
    h.write("particles/v_ghost", std::span<const Vec3>(p.v_ghost));
    h.write("particles/wall_index", std::span<const std::int32_t>(p.wall_index));
    h.write("particles/theta", std::span<const double>(p.theta));
    h.write("particles/dv_viscous", std::span<const Vec3>(p.dv_viscous));
    h.write("particles/x_built", std::span<const Vec3>(st.x_built));
  });
}

ContinuumCheckpoint load_continuum_checkpoint(const fs::path& file) {
  auto h = io::h5::File::open_read(file);
  if (io::checkpoint_kind(h, file) != "continuum_sph")
    throw InputError(
        fmt::format("{}: not a continuum (SPH) checkpoint; a continuum case continues only from a "
                    "sph_checkpoint_*.h5 of a continuum run",
                    file.string()));
  ContinuumCheckpoint c;
  auto& st = c.state;
  auto& p = st.particles;
  st.t = h.read_double_attribute("/", "time");
  st.steps = h.read_int_attribute("/", "steps");
  st.dt_last = h.read_double_attribute("/", "dt_last");
  st.a_max = h.read_double_attribute("/", "a_max");
  st.v_max = h.read_double_attribute("/", "v_max");
  st.eta_max = h.read_double_attribute("/", "eta_max");
  st.n_fluid = static_cast<std::size_t>(h.read_int_attribute("/", "n_fluid"));
  st.n_removed = static_cast<std::size_t>(h.read_int_attribute("/", "n_removed"));
  c.next_vtk = h.read_double_attribute("/", "next_vtk");
  c.next_series = h.read_double_attribute("/", "next_series");
  c.next_checkpoint = h.read_double_attribute("/", "next_checkpoint");
  c.n_vtk = h.read_int_attribute("/", "n_vtk");
  c.vtk_until = h.read_double_attribute("/", "vtk_until");
  p.id = h.read_int64("particles/id");
  p.x = h.read_vec3("particles/x");
  p.v = h.read_vec3("particles/v");
  p.a = h.read_vec3("particles/a");
  p.rho = h.read_double("particles/rho");
  p.drho = h.read_double("particles/drho");
  p.p = h.read_double("particles/p");
  p.mass = h.read_double("particles/mass");
  p.eta = h.read_double("particles/eta");
  p.gamma_dot = h.read_double("particles/gamma_dot");
  p.u_wall = h.read_vec3("particles/u_wall");
  p.v_ghost = h.read_vec3("particles/v_ghost");
  p.wall_index = h.read_int32("particles/wall_index");
  // (checkpoints written before kinetic theory have no temperatures: a liquid's are 0)
  p.theta = h.exists("particles/theta") ? h.read_double("particles/theta")
                                        : std::vector<double>(p.wall_index.size(), 0.0);
  // (nor the last viscous changes, from which the implicit viscous solves start: zero, as in the
  // builds that started them from the velocities alone)
  p.dv_viscous = h.exists("particles/dv_viscous") ? h.read_vec3("particles/dv_viscous")
                                                  : std::vector<Vec3>(p.wall_index.size(), Vec3{});
  st.x_built = h.read_vec3("particles/x_built");
  return c;
}

}  // namespace

int run_continuum_case(const input::ContinuumCase& c, const fs::path& default_dir,
                       const RunOptions& opts) {
  const fs::path dir = opts.output.empty() ? default_dir : opts.output;
  // Every input check happens before the folder is touched: the case, the checkpoint, --append.
  check_append(dir, opts);
  auto s = build_solver(c);
  std::optional<ContinuumCheckpoint> resume;
  if (opts.restart) {
    resume = load_restart(*opts.restart, load_continuum_checkpoint);
    try {
      s.restore(resume->state);
    } catch (const InputError& e) {
      throw InputError(
          fmt::format("{}: --restart {}: {}", c.file, opts.restart->string(), e.what()));
    }
  }
  const bool append = resume && opts.append;
  const int dim = c.sph.dimension;
  const char* axes = "xyz";
  std::string header =
      "time,steps,dt,n_fluid,kinetic_energy,max_speed,max_density_error,max_viscosity";
  for (int k = 0; k < dim; ++k) header += fmt::format(",min_{0},max_{0}", axes[k]);
  const bool kt = c.sph.kinetic_theory.has_value();
  if (kt) header += ",mean_granular_temperature,min_volume_fraction,max_volume_fraction";
  for (const auto& w : c.sph.walls)
    for (int k = 0; k < dim; ++k) header += fmt::format(",force_{}.{}", axes[k], w.name);
  // torque about each wall's rotation centre (2D: the z component only)
  for (const auto& w : c.sph.walls)
    for (int k = (dim == 2 ? 2 : 0); k < 3; ++k)
      header += fmt::format(",torque_{}.{}", axes[k], w.name);
  std::ostringstream series;
  series << header << '\n';
  if (append) {
    // the earlier run's rows up to the checkpoint (9 significant digits of t)
    const double until = s.time();
    for (const auto& line : continued_csv_lines(dir / "sph_series.csv", header, [until](double t) {
           return t <= until * (1 + 1e-8) + 1e-300;
         }))
      series << line << '\n';
  }
  OutputFolder folder(dir, opts);
  write_atomically(dir / "resolved_case.yaml",
                   [&](std::ostream& o) { o << input::echo_continuum_yaml(c, version_string); });
  log::info("continuum (SPH) run: {} fluid and {} wall particles, output in '{}'", s.n_fluid(),
            s.particles().size() - s.n_fluid(), dir.string());
  if (resume)
    log::info("continuing from '{}' at t = {} s (step {})", opts.restart->string(), s.time(),
              s.steps());
  auto sample = [&] {
    const auto sm = s.summary();
    series << fmt::format("{:.9g},{},{:.6g},{},{:.9g},{:.9g},{:.6g},{:.6g}", s.time(), s.steps(),
                          s.last_step(), sm.n_fluid, sm.kinetic_energy, sm.max_speed,
                          sm.max_density_error, sm.max_viscosity);
    for (int k = 0; k < dim; ++k)
      series << fmt::format(",{:.9g},{:.9g}", sm.min_position[k], sm.max_position[k]);
    if (kt)
      series << fmt::format(",{:.9g},{:.6g},{:.6g}", sm.mean_temperature, sm.min_volume_fraction,
                            sm.max_volume_fraction);
    const auto loads = s.wall_loads();
    for (const auto& f : loads.force)
      for (int k = 0; k < dim; ++k) series << fmt::format(",{:.9g}", f[k]);
    for (const auto& m : loads.torque)
      for (int k = (dim == 2 ? 2 : 0); k < 3; ++k) series << fmt::format(",{:.9g}", m[k]);
    series << '\n';
  };
  auto flush_series = [&] {
    write_atomically(dir / "sph_series.csv", [&](std::ostream& os) { os << series.str(); });
  };
  // (appending: the data sets up to and including the checkpoint's time stay)
  vtk::PvdSeries pvd =
      append ? vtk::PvdSeries(dir / "sph_particles.pvd",
                              std::nextafter(resume->vtk_until, std::numeric_limits<double>::max()))
             : vtk::PvdSeries(dir / "sph_particles.pvd");
  std::int64_t n_vtk = resume ? resume->n_vtk : 0;  // file numbers continue over restarts
  auto write_vtk = [&] {
    const auto name = fmt::format("sph_particles_{:05d}.vtp", n_vtk++);
    write_sph_vtp(dir / name, s);
    pvd.add(s.time(), name);
  };
  OutputClock clock(c.output, c.end_time);
  if (resume) {
    clock.next_vtk = resume->next_vtk;
    clock.next_series = resume->next_series;
    clock.next_checkpoint = resume->next_checkpoint;
  }
  double last_vtk_time = resume ? resume->vtk_until : 0.0;
  auto checkpoint = [&](const fs::path& file) {
    ContinuumCheckpoint ck;
    ck.state = s.state();
    ck.next_vtk = clock.next_vtk;
    ck.next_series = clock.next_series;
    ck.next_checkpoint = clock.next_checkpoint;
    ck.n_vtk = n_vtk;
    ck.vtk_until = last_vtk_time;
    save_continuum_checkpoint(file, ck);
  };
  const auto start = std::chrono::steady_clock::now();
  if (!append) {
    write_vtk();
    last_vtk_time = s.time();
    sample();
  }
  flush_series();
  const std::int64_t first_step = s.steps();
  // A step that has shrunk a millionfold from the run's first is a run diverging slowly (speeds
  // of 1e13 m/s at steps of 1e-25 s, never quite infinite): stop it as diverged.
  const double first_stable_step = s.stable_step();
  int sig = 0;
  while (!clock.finished(s.time())) {
    if (opts.steps && s.steps() - first_step >= *opts.steps) break;
    s.step(clock.until());  // lands exactly on output times: evenly spaced series
    if (s.n_fluid() == 0) throw Error("SPH: every fluid particle has left the domain");
    if (!std::isfinite(s.max_speed()))
      throw Error(
          fmt::format("SPH: the run diverged at t = {} s (step {}); lower time.cfl or "
                      "raise sound_speed",
                      s.time(), s.steps()));
    if (s.stable_step() < 1e-6 * first_stable_step)
      throw Error(fmt::format(
          "SPH: the run diverged at t = {} s (step {}): the time step fell to {:.3g} s from "
          "{:.3g} s at the start; lower time.cfl, raise sound_speed or add artificial_viscosity",
          s.time(), s.steps(), s.stable_step(), first_stable_step));
    // (a speed of ten times the sound speed, itself meant to be ten times the largest expected
    // speed: the weakly compressible model has broken down)
    if (s.max_speed() > 10.0 * c.sph.sound_speed)
      throw Error(fmt::format(
          "SPH: the run diverged at t = {} s (step {}): a particle moves at {:.3g} m/s, over ten "
          "times the sound speed {:.3g} m/s; raise sound_speed (to about ten times the largest "
          "expected speed) or lower time.cfl",
          s.time(), s.steps(), s.max_speed(), c.sph.sound_speed));
    if (clock.series_due(s.time())) sample();
    if (clock.vtk_due(s.time())) {
      write_vtk();
      last_vtk_time = s.time();
      flush_series();
    }
    if (clock.checkpoint_due(s.time()))
      checkpoint(dir / fmt::format("sph_checkpoint_{:09d}.h5", s.steps()));
    if ((sig = stop::requested()) != 0) break;
  }
  // (the checkpoint first: it records the schedule's files, not the one of a stop)
  checkpoint(dir / "sph_checkpoint_final.h5");
  if (last_vtk_time < s.time()) write_vtk();
  flush_series();
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto sm = s.summary();
  const auto run_steps = s.steps() - first_step;
  std::ostringstream sum;
  sum << fmt::format("grainflow {}\ncase {}\nmethod sph, rheology {}\n", version_string, c.name,
                     c.rheology);
  sum << fmt::format(
      "time {:.9g} s\nsteps {} ({} in this run)\nfluid particles {} ({} left the "
      "domain)\n",
      s.time(), s.steps(), run_steps, sm.n_fluid, s.n_removed());
  sum << fmt::format(
      "wall particles {}\nwall time {:.3f} s\nparticle-steps per second {:.4g}\n",
      s.particles().size() - s.n_fluid(), wall,
      wall > 0 ? static_cast<double>(s.particles().size()) * static_cast<double>(run_steps) / wall
               : 0.0);
  sum << fmt::format("kinetic energy {:.9g} J\nmax density error {:.4g}\n", sm.kinetic_energy,
                     sm.max_density_error);
  write_atomically(dir / "sph_summary.txt", [&](std::ostream& os) { os << sum.str(); });
  if (c.sph.implicit_viscosity)
    log::info(
        "SPH run done: t = {:.6g} s, {} steps, {:.1f} s wall; implicit viscous solves: {:.1f} "
        "BiCGSTAB iterations per component",
        s.time(), run_steps, wall, s.mean_viscous_iterations());
  else
    log::info("SPH run done: t = {:.6g} s, {} steps, {:.1f} s wall", s.time(), run_steps, wall);
  if (sig)
    log::warn(
        "SPH run stopped by {}: outputs up to the last step and sph_checkpoint_final.h5 "
        "written in '{}'",
        stop::signal_name(sig), dir.string());
  folder.commit();
  return sig;
}

}  // namespace gf
