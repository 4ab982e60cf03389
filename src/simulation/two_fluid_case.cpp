// SPDX-License-Identifier: GPL-3.0-or-later
// Two-fluid cases: loading, `grainflow check` figures, the run loop and its outputs.
#include "simulation/two_fluid_case.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "core/error.hpp"
#include "core/files.hpp"
#include "core/log.hpp"
#include "core/stop.hpp"
#include "core/version.hpp"
#include "core/vtk_xml.hpp"
#include "coupling/cfd_dem/drag_registry.hpp"
#include "io/restart/h5.hpp"
#include "io/vtk/vtk.hpp"
#include "simulation/output_clock.hpp"

namespace gf {

namespace fs = std::filesystem;

std::optional<input::TwoFluidCase> load_two_fluid_case(
    const fs::path& file, fs::path& output_dir, const std::vector<input::Override>& overrides) {
  const auto root = input::YamlNode::parse_file(file);
  if (!root.is_map() || !root.raw()["two_fluid"]) return std::nullopt;
  input::apply_overrides(root.raw(), overrides, file);
  input::YamlMap top(root, {"name", "two_fluid", "output"});
  output_dir = fs::path("out") / file.parent_path().filename();
  if (auto out = top.find("output")) {
    input::YamlMap o(*out, {"directory"});
    output_dir = o.string("directory");
  }
  auto c = input::parse_two_fluid(top.at("two_fluid"));
  c.file = file.string();
  c.name = top.has("name") ? top.string("name") : file.parent_path().filename().string();
  return c;
}

namespace {

constexpr double kPi = 3.14159265358979323846;

/// The model with the case's initial state.
std::unique_ptr<continuum::TwoFluidModel> build_model(const input::TwoFluidCase& c) {
  auto model = std::make_unique<continuum::TwoFluidModel>(c.grid, c.settings);
  auto& m = *model;
  auto region_of = [&](const Vec3& x) -> const input::TwoFluidCase::Region* {
    const input::TwoFluidCase::Region* found = nullptr;
    for (const auto& r : c.initial) {
      bool in = true;
      for (int k = 0; k < c.grid.dimension; ++k) in = in && x[k] >= r.lo[k] && x[k] <= r.hi[k];
      if (in) found = &r;  // later regions override
    }
    return found;
  };
  m.set_solids(
      [&](const Vec3& x) {
        const auto* r = region_of(x);
        return r ? r->solids_fraction : 0.0;
      },
      c.initial_temperature);
  m.set_solids_velocity([&](const Vec3& x) {
    const auto* r = region_of(x);
    return r ? r->solids_velocity : Vec3{};
  });
  m.fluid().set_velocity([&](const Vec3&) { return c.fluid_velocity; });
  return model;
}

/// The axis "up" (against gravity; axis 1 without gravity) and its sign.
std::pair<int, double> vertical(const input::TwoFluidCase& c) {
  const Vec3 g = c.settings.fluid.gravity;
  int axis = 1;
  double best = 0.0;
  for (int k = 0; k < c.grid.dimension; ++k)
    if (std::abs(g[k]) > best) {
      best = std::abs(g[k]);
      axis = k;
    }
  return {axis, best > 0 && g[axis] > 0 ? -1.0 : 1.0};
}

/// One row of the series: the state's integral figures.
struct Figures {
  double solids_volume = 0, kinetic_energy = 0, mean_temperature = 0, max_fraction = 0;
  double pressure_drop = 0, bed_height = 0, outlet_superficial_velocity = 0;
};

Figures figures(const input::TwoFluidCase& c, const continuum::TwoFluidModel& m) {
  const auto& g = c.grid;
  Figures f;
  const auto a = m.solids_fraction();
  const auto th = m.granular_temperature();
  const double v = g.cell_volume(), rho_s = c.settings.ktgf.density;
  const auto [up, sign] = vertical(c);
  std::vector<double> layer(static_cast<std::size_t>(g.n[up]), 0.0);
  double mass_t = 0.0;
  for (std::int64_t cell = 0; cell < g.cell_count(); ++cell) {
    const double ac = a[static_cast<std::size_t>(cell)];
    f.solids_volume += ac * v;
    f.kinetic_energy += 0.5 * ac * rho_s * v * norm2(m.solids_velocity(cell));
    mass_t += ac * th[static_cast<std::size_t>(cell)];
    f.max_fraction = std::max(f.max_fraction, ac);
    layer[static_cast<std::size_t>(g.cell_coords(cell)[up])] += ac * v;
  }
  f.mean_temperature = f.solids_volume > 0 ? mass_t * v / f.solids_volume : 0.0;
  // Bed height: the level (from the bottom, against gravity) below which 95 % of the solids lie.
  const int n = g.n[up];
  double acc = 0.0;
  for (int i = 0; i < n && f.solids_volume > 0; ++i) {
    const int k = sign > 0 ? i : n - 1 - i;
    const double add = layer[static_cast<std::size_t>(k)];
    if (acc + add >= 0.95 * f.solids_volume) {
      f.bed_height = (i + (0.95 * f.solids_volume - acc) / add) * g.h[up];
      break;
    }
    acc += add;
  }
  const double lo = g.lo[up] + 0.5 * g.h[up], hi = g.hi()[up] - 0.5 * g.h[up];
  f.pressure_drop =
      sign > 0 ? m.fluid().pressure_drop(up, lo, hi) : m.fluid().pressure_drop(up, hi, lo);
  f.outlet_superficial_velocity = m.fluid().superficial_velocity(up, sign > 0 ? n : 0);
  return f;
}

/// Cell fields as VTK ImageData.
void write_vti(const fs::path& path, const continuum::TwoFluidModel& m) {
  const auto& g = m.grid();
  const auto nc = static_cast<std::size_t>(g.cell_count());
  std::vector<Vec3> us(nc), uf(nc);
  for (std::size_t c = 0; c < nc; ++c) us[c] = m.solids_velocity(static_cast<std::int64_t>(c));
  m.fluid().cell_velocities(uf);
  vtk::AppendedArrays arrays;
  std::string tags;
  auto add = [&](const char* name, std::span<const double> v) {
    tags += "        " + vtk::AppendedArrays::tag(arrays.add(name, 1, v)) + "\n";
  };
  add("solids_fraction", m.solids_fraction());
  add("granular_temperature", m.granular_temperature());
  add("solids_pressure", m.solids_pressure());
  add("solids_viscosity", m.solids_viscosity());
  add("exchange_coefficient", m.exchange_coefficient());
  add("pressure", m.fluid().pressure());
  tags += "        " +
          vtk::AppendedArrays::tag(arrays.add("solids_velocity", std::span<const Vec3>(us))) + "\n";
  tags += "        " +
          vtk::AppendedArrays::tag(arrays.add("fluid_velocity", std::span<const Vec3>(uf))) + "\n";
  write_atomically(path, [&](std::ostream& out) {
    vtk::write_image_data(out, g.n, g.lo, g.h, arrays, tags,
                          " Scalars=\"solids_fraction\" Vectors=\"solids_velocity\"");
  });
}

/// A run's checkpoint: the model state and the output schedule.
struct Checkpoint {
  continuum::TwoFluidModel::State state;
  std::int64_t steps = 0;
  double clipped = 0;  ///< solids volume clipped so far (the series' running total) [m^3]
  double next_vtk = 0, next_series = 0, next_checkpoint = 0, vtk_until = 0;
  std::int64_t n_vtk = 0;
};

void save_checkpoint(const fs::path& file, const Checkpoint& c) {
  io::write_checkpoint_atomically(file, [&](io::h5::File& h) {
    io::set_checkpoint_identity(h, "two_fluid");
    h.set_attribute("/", "time", c.state.time);
    h.set_attribute("/", "steps", c.steps);
    h.set_attribute("/", "clipped_volume", c.clipped);
    h.set_attribute("/", "next_vtk", c.next_vtk);
    h.set_attribute("/", "next_series", c.next_series);
    h.set_attribute("/", "next_checkpoint", c.next_checkpoint);
    h.set_attribute("/", "vtk_until", c.vtk_until);
    h.set_attribute("/", "n_vtk", c.n_vtk);
    const auto& f = c.state.fluid;
    h.set_attribute("/", "fluid_time", f.time);
    h.set_attribute("/", "fluid_dt_prev", f.dt_prev);
    h.set_attribute("/", "fluid_steps", f.n_steps);
    h.set_attribute("/", "fluid_history", static_cast<std::int64_t>(f.history));
    h.create_group("solids");
    for (const auto& [k, v] : c.state.arrays) h.write("solids/" + k, std::span<const double>(v));
    h.create_group("fluid");
    for (const auto& [k, v] : f.arrays) h.write("fluid/" + k, std::span<const double>(v));
  });
}

Checkpoint load_checkpoint(const fs::path& file, const continuum::TwoFluidModel& model) {
  auto h = io::h5::File::open_read(file);
  if (io::checkpoint_kind(h, file) != "two_fluid")
    throw InputError(
        fmt::format("{}: not a two-fluid checkpoint; a two_fluid case continues only "
                    "from a two_fluid_checkpoint_*.h5 of a two-fluid run",
                    file.string()));
  Checkpoint c;
  c.state.time = h.read_double_attribute("/", "time");
  c.steps = h.read_int_attribute("/", "steps");
  c.clipped = h.read_double_attribute("/", "clipped_volume");
  c.next_vtk = h.read_double_attribute("/", "next_vtk");
  c.next_series = h.read_double_attribute("/", "next_series");
  c.next_checkpoint = h.read_double_attribute("/", "next_checkpoint");
  c.vtk_until = h.read_double_attribute("/", "vtk_until");
  c.n_vtk = h.read_int_attribute("/", "n_vtk");
  auto& f = c.state.fluid;
  f.time = h.read_double_attribute("/", "fluid_time");
  f.dt_prev = h.read_double_attribute("/", "fluid_dt_prev");
  f.n_steps = h.read_int_attribute("/", "fluid_steps");
  f.history = static_cast<int>(h.read_int_attribute("/", "fluid_history"));
  // the array names of a model of this case (a checkpoint of another grid fails in restore)
  const auto names = model.state();
  for (const auto& [k, v] : names.arrays)
    if (h.exists("solids/" + k)) c.state.arrays.emplace_back(k, h.read_double("solids/" + k));
  for (const auto& [k, v] : names.fluid.arrays)
    if (h.exists("fluid/" + k)) f.arrays.emplace_back(k, h.read_double("fluid/" + k));
  return c;
}

}  // namespace

std::vector<std::pair<std::string, std::string>> describe_two_fluid_case(
    const input::TwoFluidCase& c) {
  const auto model = build_model(c);
  const auto& m = *model;
  const auto& g = c.grid;
  const auto& s = c.settings;
  std::vector<std::pair<std::string, std::string>> out;
  out.emplace_back("method", fmt::format("two-fluid model ({}D), closures {} / {}, drag {}",
                                         g.dimension, c.closures, c.radial, c.drag));
  const double d = s.ktgf.diameter;
  std::string cells = fmt::format("{} x {}", g.n[0], g.n[1]);
  if (g.dimension == 3) cells += fmt::format(" x {}", g.n[2]);
  out.emplace_back("cells, cell size / grain diameter",
                   fmt::format("{} = {}, {:.3g}{}", cells, g.cell_count(), g.h[0] / d,
                               g.h[0] / d < 3 ? " (below ~3: the continuum averages over less "
                                                "than a few grains)"
                                              : ""));
  const auto f = figures(c, m);
  out.emplace_back("solids volume [m^3] (2D: per depth h_z), max initial fraction",
                   fmt::format("{:.4g}, {:.3f} (cap {:.3f})", f.solids_volume, f.max_fraction,
                               m.packing_fraction()));
  // Terminal velocity of a single grain by the drag law (model A balance at eps -> 1).
  const double vp = kPi * d * d * d / 6.0, drho = s.ktgf.density - s.fluid.density;
  const double gmag = norm(s.fluid.gravity);
  if (gmag > 0 && drho > 0) {
    auto beta_p = [&](double eps, double slip) {
      cfd_dem::DragInput in;
      in.rho_f = s.fluid.density;
      in.mu_f = s.fluid.dynamic_viscosity;
      in.eps = eps;
      in.d_v = d;
      in.slip = {slip, 0, 0};
      return cfd_dem::drag_force(s.drag.law, in, s.drag).beta;
    };
    auto solve = [&](const std::function<double(double)>& fn) {
      double lo = 0.0, hi = 1e3;
      for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (fn(mid) < 0 ? lo : hi) = mid;
      }
      return 0.5 * (lo + hi);
    };
    const double ut = solve([&](double u) { return beta_p(1.0, u) * u - vp * drho * gmag; });
    out.emplace_back(
        "terminal velocity of a grain [m/s], Re_t",
        fmt::format("{:.4g}, {:.3g}", ut, s.fluid.density * ut * d / s.fluid.dynamic_viscosity));
    if (f.max_fraction > 0) {
      const double a = f.max_fraction, e = 1 - a, mu = s.fluid.dynamic_viscosity;
      const double umf = solve([&](double u) {
        return 150 * mu * a * a * u / (e * e * e * d * d) +
               1.75 * s.fluid.density * a * u * u / (e * e * e * d) - a * drho * gmag;
      });
      out.emplace_back("Ergun's minimum fluidisation velocity at that fraction [m/s]",
                       fmt::format("{:.4g}", umf));
    }
  }
  out.emplace_back("granular temperature",
                   s.temperature == continuum::GranularTemperature::Algebraic
                       ? "algebraic (local equilibrium)"
                       : "transported (convection, conduction)");
  const double dt = std::min(0.9 * m.stable_dt(), c.max_step);
  out.emplace_back("first time step [s]", fmt::format("{:.3g}", dt));
  out.emplace_back("steps to the end (at the first step)",
                   fmt::format("{:.0f}", std::ceil(c.end_time / dt)));
  return out;
}

int run_two_fluid_case(const input::TwoFluidCase& c, const fs::path& default_dir,
                       const RunOptions& opts) {
  const fs::path dir = opts.output.empty() ? default_dir : opts.output;
  check_append(dir, opts);
  const auto model = build_model(c);
  auto& m = *model;
  std::optional<Checkpoint> resume;
  std::int64_t steps = 0;
  if (opts.restart) {
    resume = load_restart(*opts.restart, [&](const fs::path& f) { return load_checkpoint(f, m); });
    try {
      m.restore(resume->state);
    } catch (const Error& e) {
      throw InputError(
          fmt::format("{}: --restart {}: {}", c.file, opts.restart->string(), e.what()));
    }
    steps = resume->steps;
  }
  const bool append = resume && opts.append;
  const std::string header =
      "time,steps,dt,substeps,solids_volume,solids_kinetic_energy,mean_granular_temperature,"
      "max_solids_fraction,pressure_drop,bed_height,outlet_superficial_velocity,clipped_volume";
  std::ostringstream series;
  series << header << '\n';
  if (append) {
    const double until = m.time();
    for (const auto& line :
         continued_csv_lines(dir / "two_fluid_series.csv", header,
                             [until](double t) { return t <= until * (1 + 1e-8) + 1e-300; }))
      series << line << '\n';
  }
  OutputFolder folder(dir, opts);
  write_atomically(dir / "resolved_case.yaml",
                   [&](std::ostream& o) { o << input::echo_two_fluid_yaml(c, version_string); });
  log::info("two-fluid run: {} cells, output in '{}'", c.grid.cell_count(), dir.string());
  if (resume)
    log::info("continuing from '{}' at t = {} s (step {})", opts.restart->string(), m.time(),
              steps);
  double last_dt = 0.0, clipped = resume ? resume->clipped : 0.0;
  int substeps = 0;
  auto sample = [&] {
    const auto f = figures(c, m);
    series << fmt::format(
        "{:.9g},{},{:.6g},{},{:.12g},{:.9g},{:.6g},{:.6g},{:.9g},{:.6g},{:.6g},{:.3g}\n", m.time(),
        steps, last_dt, substeps, f.solids_volume, f.kinetic_energy, f.mean_temperature,
        f.max_fraction, f.pressure_drop, f.bed_height, f.outlet_superficial_velocity, clipped);
  };
  auto flush_series = [&] {
    write_atomically(dir / "two_fluid_series.csv", [&](std::ostream& os) { os << series.str(); });
  };
  vtk::PvdSeries pvd =
      append ? vtk::PvdSeries(dir / "two_fluid.pvd",
                              std::nextafter(resume->vtk_until, std::numeric_limits<double>::max()))
             : vtk::PvdSeries(dir / "two_fluid.pvd");
  std::int64_t n_vtk = resume ? resume->n_vtk : 0;
  auto write_vtk = [&] {
    const auto name = fmt::format("two_fluid_{:05d}.vti", n_vtk++);
    write_vti(dir / name, m);
    pvd.add(m.time(), name);
  };
  OutputClock clock(c.output, c.end_time);
  double last_vtk_time = resume ? resume->vtk_until : 0.0;
  if (resume) {
    clock.next_vtk = resume->next_vtk;
    clock.next_series = resume->next_series;
    clock.next_checkpoint = resume->next_checkpoint;
  }
  auto checkpoint = [&](const fs::path& file) {
    Checkpoint ck;
    ck.state = m.state();
    ck.steps = steps;
    ck.clipped = clipped;
    ck.next_vtk = clock.next_vtk;
    ck.next_series = clock.next_series;
    ck.next_checkpoint = clock.next_checkpoint;
    ck.vtk_until = last_vtk_time;
    ck.n_vtk = n_vtk;
    save_checkpoint(file, ck);
  };
  const auto start = std::chrono::steady_clock::now();
  if (!append) {
    write_vtk();
    last_vtk_time = m.time();
    sample();
  }
  flush_series();
  const std::int64_t first_step = steps;
  int sig = 0;
  while (!clock.finished(m.time())) {
    if (opts.steps && steps - first_step >= *opts.steps) break;
    const double dt = std::min({0.9 * m.stable_dt(), c.max_step, clock.until() - m.time()});
    const auto r = m.step(dt);
    ++steps;
    last_dt = dt;
    substeps = r.substeps;
    clipped += r.clipped_volume;
    for (double a : m.solids_fraction())
      if (!std::isfinite(a))
        throw Error(
            fmt::format("two-fluid: the run diverged at t = {} s (step {}); lower "
                        "time.max_step or time.courant",
                        m.time(), steps));
    if (clock.series_due(m.time())) sample();
    if (clock.vtk_due(m.time())) {
      write_vtk();
      last_vtk_time = m.time();
      flush_series();
    }
    if (clock.checkpoint_due(m.time()))
      checkpoint(dir / fmt::format("two_fluid_checkpoint_{:09d}.h5", steps));
    if ((sig = stop::requested()) != 0) break;
  }
  checkpoint(dir / "two_fluid_checkpoint_final.h5");
  if (last_vtk_time < m.time()) write_vtk();
  flush_series();
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto run_steps = steps - first_step;
  const auto f = figures(c, m);
  std::ostringstream sum;
  sum << fmt::format("grainflow {}\ncase {}\nmethod two_fluid, closures {}, drag {}\n",
                     version_string, c.name, c.closures, c.drag);
  sum << fmt::format("time {:.9g} s\nsteps {} ({} in this run)\ncells {}\nwall time {:.3f} s\n",
                     m.time(), steps, run_steps, c.grid.cell_count(), wall);
  sum << fmt::format(
      "cell-steps per second {:.4g}\n",
      wall > 0 ? static_cast<double>(c.grid.cell_count()) * static_cast<double>(run_steps) / wall
               : 0.0);
  sum << fmt::format("solids volume {:.12g} m^3\nclipped volume {:.3g} m^3\n", f.solids_volume,
                     clipped);
  sum << fmt::format("pressure drop {:.9g} Pa\nbed height {:.6g} m\n", f.pressure_drop,
                     f.bed_height);
  write_atomically(dir / "two_fluid_summary.txt", [&](std::ostream& os) { os << sum.str(); });
  log::info("two-fluid run done: t = {:.6g} s, {} steps, {:.1f} s wall", m.time(), run_steps, wall);
  if (sig)
    log::warn(
        "two-fluid run stopped by {}: outputs up to the last step and "
        "two_fluid_checkpoint_final.h5 written in '{}'",
        stop::signal_name(sig), dir.string());
  folder.commit();
  return sig;
}

}  // namespace gf
