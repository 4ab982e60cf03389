// SPDX-License-Identifier: GPL-3.0-or-later
// The grainflow command line: run | sweep | check | list-models | describe <key>.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <filesystem>
#include <iostream>
#include <span>
#include <string>
#include <utility>

#include "contact/conduction.hpp"
#include "contact/registry.hpp"
#include "continuum/ktgf.hpp"
#include "continuum/rheology_registry.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/log.hpp"
#include "core/stop.hpp"
#include "core/version.hpp"
#include "coupling/cfd_dem/drag_registry.hpp"
#include "coupling/cfd_dem/heat_transfer.hpp"
#include "io/input/parse_case.hpp"
#include "io/input/validate.hpp"
#include "simulation/continuum_case.hpp"
#include "simulation/fem_case.hpp"
#include "simulation/simulation.hpp"
#include "simulation/sweep.hpp"
#include "simulation/two_fluid_case.hpp"

namespace {

constexpr int kExitInput = 2;

std::string param_range(const gf::ParamSpec& p) {
  const auto bound = [](double v) {
    return std::isinf(v) ? std::string(v < 0 ? "-inf" : "inf") : fmt::format("{}", v);
  };
  return fmt::format("{}{}, {}]", p.min_exclusive ? "(" : "[", bound(p.min), bound(p.max));
}

int list_models() {
  fmt::print("contact models (contacts[].model):\n");
  for (const auto& m : gf::contact::model_infos()) fmt::print("  {:<16} {}\n", m.key, m.summary);
  fmt::print("integrators (integrator):\n  {:<16} {}\n  {:<16} {}\n", "velocity_verlet",
             "velocity Verlet for translation and rotation (second order, symplectic)", "gear5",
             "Gear predictor-corrector with 6 values, translation and rotation (spheres, disks, "
             "polygons)");
  fmt::print("heat conduction models (heat.model):\n");
  for (const auto& m : gf::contact::conduction_infos())
    fmt::print("  {:<18} {}\n", m.key, m.summary);
  fmt::print("drag laws (coupling.drag, two_fluid drag):\n");
  for (const auto& d : gf::cfd_dem::drag_infos()) fmt::print("  {:<18} {}\n", d.key, d.summary);
  fmt::print("grain-fluid heat transfer correlations (coupling.heat_transfer):\n");
  for (const auto& h : gf::cfd_dem::heat_transfer_infos())
    fmt::print("  {:<18} {}\n", h.key, h.summary);
  fmt::print("continuum rheologies (continuum.rheology.model):\n");
  for (const auto& m : gf::continuum::rheology_infos())
    fmt::print("  {:<16} {}\n", m.key, m.summary);
  fmt::print("KTGF closure sets (two_fluid.solids.closures, continuum.kinetic_theory):\n");
  for (const auto& m : gf::continuum::ktgf_closure_infos())
    fmt::print("  {:<16} {}\n", m.key, m.summary);
  fmt::print("KTGF radial distributions at contact g0:\n");
  for (const auto& m : gf::continuum::radial_distribution_infos())
    fmt::print("  {:<18} {}\n", m.key, m.summary);
  fmt::print("KTGF dense-region (frictional) models:\n");
  for (const auto& m : gf::continuum::frictional_model_infos())
    fmt::print("  {:<26} {}\n", m.key, m.summary);
  fmt::print("particle-pressure models (two_fluid.solids.particle_pressure.model):\n");
  for (const auto& m : gf::continuum::particle_pressure_model_infos())
    fmt::print("  {:<26} {}\n", m.key, m.summary);
  fmt::print("\n`grainflow describe <key>` prints a model's equation, reference and parameters.\n");
  return 0;
}

void print_params(std::span<const gf::ParamSpec> params) {
  if (params.empty()) {
    fmt::print("  (none)\n");
    return;
  }
  fmt::print("  {:<28} {:<6} {:<10} {:<16} {}\n", "name", "unit", "default", "range", "meaning");
  for (const auto& p : params)
    fmt::print("  {:<28} {:<6} {:<10} {:<16} {}\n", p.name, p.unit,
               p.default_value ? fmt::format("{:.6g}", *p.default_value) : std::string("required"),
               param_range(p), p.description);
}

void describe_contact_model(const gf::contact::ModelInfo& mi) {
  const auto* m = &mi;
  const std::string_view key = m->key;
  fmt::print(
      "{} — {}\n\nequation:\n  {}\n\nreference:\n  {}\n\nparameters (per material pair, in "
      "contacts[]):\n",
      m->key, m->summary, m->equation, m->reference);
  print_params(m->params);
  // The restitution -> damping mapping actually used (numerical inversion, restitution_map.hpp).
  const auto kind =
      key == "hooke" ? gf::contact::NormalKind::Linear : gf::contact::NormalKind::Hertz;
  fmt::print(
      "\ndamping ratio zeta realising restitution e (dimensionless collision, clamped force):\n  e "
      "   ");
  for (double e : {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0}) fmt::print(" {:>7.1f}", e);
  fmt::print("\n  zeta ");
  for (double e : {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0})
    fmt::print(" {:>7.4f}", gf::contact::damping_ratio_for_restitution(kind, e));
  fmt::print("\n");
  fmt::print(
      "\nper-material parameters (materials:): density [kg/m^3], youngs_modulus [Pa], "
      "poisson_ratio [1]\n");
}

int describe(const std::string& key) {
  // One key may name models of several kinds (gidaspow: a KTGF closure set and a drag law):
  // each is printed.
  int found = 0;
  auto next = [&found] {
    if (found++ > 0) fmt::print("\n----------------------------------------\n\n");
  };
  if (const auto* r = gf::continuum::find_rheology(key)) {
    next();
    fmt::print(
        "{} — {}\n\nequation:\n  {}\n\nreference:\n  {}\n\nparameters (in continuum.rheology):\n",
        r->key, r->summary, r->equation, r->reference);
    print_params(r->params);
  }
  const std::pair<const gf::continuum::KtgfInfo*, const char*> ktgf[] = {
      {gf::continuum::find_ktgf_closure(key), "KTGF closure set"},
      {gf::continuum::find_radial_distribution(key), "KTGF radial distribution at contact"},
      {gf::continuum::find_frictional_model(key), "KTGF dense-region model"},
      {gf::continuum::find_particle_pressure_model(key), "two-fluid particle-pressure model"}};
  for (const auto& [k, kind] : ktgf)
    if (k) {
      next();
      fmt::print("{} — {}\n\nequation:\n  {}\n\nreference:\n  {}\n\nparameters ({}):\n", k->key,
                 k->summary, k->equation, k->reference, kind);
      print_params(k->params);
    }
  if (const auto* h = gf::contact::find_conduction(key)) {
    next();
    fmt::print(
        "{} — heat conduction model: {}\n\nequation:\n  {}\n\nreference:\n  {}\n\n"
        "parameters: heat.temperature [K] (initial); per material (materials:) "
        "thermal_conductivity [W/(m K)], heat_capacity [J/(kg K)]; particles[].temperature, "
        "walls[].temperature [K]\n",
        h->key, h->summary, h->equation, h->reference);
  }
  if (const auto* d = gf::cfd_dem::find_drag(key)) {
    next();
    fmt::print(
        "{} — drag law: {}\n\nequation:\n  {}\n\nreference:\n  {}\n\nvalidity:\n  {}\n\n"
        "parameters (in coupling.drag):\n",
        d->key, d->summary, d->equation, d->reference, d->validity);
    print_params(d->params);
  }
  if (const auto* h = gf::cfd_dem::find_heat_transfer(key)) {
    next();
    fmt::print(
        "{} — grain-fluid heat transfer: {}\n\nequation:\n  {}\n\nreference:\n  {}\n\n"
        "validity:\n  {}\n\nparameters: none; the fluid's heat_capacity [J/(kg K)], "
        "thermal_conductivity [W/(m K)], temperature [K] and the inlets' temperatures (fluid:), "
        "the grains' temperatures (heat:)\n",
        h->key, h->summary, h->equation, h->reference, h->validity);
  }
  if (const auto* m = gf::contact::find_model(key)) {
    next();
    describe_contact_model(*m);
  }
  if (found > 0) return 0;
  std::string keys;
  for (const auto& i : gf::contact::model_infos()) keys += fmt::format(" {}", i.key);
  for (const auto& i : gf::continuum::rheology_infos()) keys += fmt::format(" {}", i.key);
  for (const auto& i : gf::continuum::ktgf_closure_infos()) keys += fmt::format(" {}", i.key);
  for (const auto& i : gf::continuum::radial_distribution_infos())
    keys += fmt::format(" {}", i.key);
  for (const auto& i : gf::continuum::frictional_model_infos()) keys += fmt::format(" {}", i.key);
  for (const auto& i : gf::continuum::particle_pressure_model_infos())
    keys += fmt::format(" {}", i.key);
  for (const auto& i : gf::cfd_dem::drag_infos()) keys += fmt::format(" {}", i.key);
  for (const auto& i : gf::contact::conduction_infos()) keys += fmt::format(" {}", i.key);
  for (const auto& i : gf::cfd_dem::heat_transfer_infos()) keys += fmt::format(" {}", i.key);
  fmt::print(stderr, "error: unknown model key '{}'; known keys:{}\n", key, keys);
  return kExitInput;
}

std::vector<gf::input::Override> overrides(const std::vector<std::string>& sets) {
  std::vector<gf::input::Override> out;
  for (const auto& s : sets) out.push_back(gf::input::parse_override(s));
  return out;
}

int check(const std::string& file, const std::vector<std::string>& sets) {
  std::filesystem::path fem_dir;
  if (const auto fem_cfg = gf::load_fem_case(file, fem_dir, overrides(sets))) {
    fmt::print("{}: OK (fluid_fem case)\n", file);
    for (const auto& [k, v] : gf::fem::describe_case(*fem_cfg)) fmt::print("  {:<40} {}\n", k, v);
    for (const auto& w : fem_cfg->warnings) fmt::print("warning: {}\n", w);
    return 0;
  }
  if (const auto cc = gf::load_continuum_case(file, fem_dir, overrides(sets))) {
    const auto rows = gf::describe_continuum_case(*cc);  // builds the particles: may throw
    fmt::print("{}: OK (continuum case)\n", file);
    for (const auto& [k, v] : rows) fmt::print("  {:<52} {}\n", k, v);
    return 0;
  }
  if (const auto tc = gf::load_two_fluid_case(file, fem_dir, overrides(sets))) {
    const auto rows = gf::describe_two_fluid_case(*tc);
    fmt::print("{}: OK (two-fluid case)\n", file);
    for (const auto& [k, v] : rows) fmt::print("  {:<62} {}\n", k, v);
    return 0;
  }
  const auto cfg = gf::input::load_case(file, overrides(sets));
  const auto report = gf::input::validate(cfg);
  gf::Simulation sim(cfg);
  // A sweep: every run's case is read and checked too (throws for the first invalid one).
  std::vector<std::string> run_warnings;
  if (cfg.sweep) run_warnings = gf::check_sweep_points(file, cfg, overrides(sets));
  fmt::print("{}: OK\n", file);
  if (cfg.sweep)
    fmt::print("  {:<40} {} (each one's case checked)\n", "sweep runs (grainflow sweep)",
               gf::sweep_points(cfg).size());
  fmt::print("  {:<40} {}\n", "particles", sim.particles().size());
  fmt::print("  {:<40} {}\n", "walls (planes / cylinders / meshes)", sim.walls().size());
  if (!cfg.outlets.empty()) {
    std::string names;
    std::int64_t taken = 0;
    for (std::size_t k = 0; k < cfg.outlets.size(); ++k) {
      names += (k > 0 ? ", " : "") + cfg.outlets[k].name;
      taken += sim.outlet_tallies()[k].count;
    }
    // (grains placed inside an outlet leave at once: counted here, in the particles above not)
    fmt::print("  {:<40} {} ({}){}\n", "outlets", cfg.outlets.size(), names,
               taken > 0 ? fmt::format("; {} grain(s) placed inside them, taken at t = 0", taken)
                         : std::string());
  }
  if (!cfg.flow_meters.empty()) {
    std::string names;
    for (std::size_t k = 0; k < cfg.flow_meters.size(); ++k)
      names += (k > 0 ? ", " : "") + cfg.flow_meters[k].name;
    fmt::print("  {:<40} {} ({})\n", "flow meters", cfg.flow_meters.size(), names);
  }
  for (const auto& w : sim.walls())
    if (w.kind == gf::WallKind::Mesh)
      fmt::print(
          "  {:<40} {} triangles, {} vertices, {} open / {} non-manifold edges, {} T-junctions, "
          "{} repeated triangles left out\n",
          fmt::format("mesh wall '{}'", w.name), w.mesh.size(), w.mesh.points().size(),
          w.mesh.boundary_edges(), w.mesh.nonmanifold_edges(), w.mesh.t_junctions(),
          w.mesh.duplicate_triangles());
  for (const auto& wc : cfg.walls)
    if (wc.mesh_dropped > 0)
      fmt::print("warning: mesh wall '{}': {} degenerate (zero-area) triangles of {} left out\n",
                 wc.name, wc.mesh_dropped, wc.mesh_file.string());
  fmt::print("  {:<40} {}\n", "steps", std::llround(cfg.time.end / cfg.time.step));
  for (const auto& [k, v] : report.derived) fmt::print("  {:<40} {}\n", k, v);
  for (const auto& w : report.warnings) fmt::print("warning: {}\n", w);
  // (a run's warning that the base case gives too is said once, above)
  for (const auto& w : run_warnings) {
    const std::string text = w.substr(w.find(": ") + 2);
    if (std::find(report.warnings.begin(), report.warnings.end(), text) == report.warnings.end())
      fmt::print("warning: sweep run {}\n", w);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Idle OpenMP threads sleep instead of spinning unless the user says otherwise: spinning
  // threads make a run on a shared or oversubscribed machine ~10x slower, and the few barriers
  // per step cost microseconds against milliseconds of work.
  if (std::getenv("OMP_WAIT_POLICY") == nullptr) setenv("OMP_WAIT_POLICY", "passive", 0);
#if defined(__GLIBC__)
  // Arrays of 1 MiB and more (particle columns, neighbour lists) get their own mappings, which
  // go back to the system when freed. glibc's default threshold rises to the size of the
  // largest block freed so far, after which such arrays come from the heap and their memory
  // stays resident after a neighbour rebuild frees them: peak RSS then counts freed lists.
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
#endif
  CLI::App app{"grainflow: simulation of granular matter (DEM)", "grainflow"};
  app.set_version_flag("--version", std::string("grainflow ") + gf::version_string);
  app.require_subcommand(1);
  bool verbose = false, quiet = false;
  app.add_flag("-v,--verbose", verbose, "more log output");

  auto* run = app.add_subcommand("run", "run a case");
  std::string run_file;
  gf::RunOptions opts;
  std::string output, restart;
  int threads = 0;
  std::int64_t steps = -1;
  run->add_option("case", run_file, "case file (YAML)")->required();
  run->add_option("-o,--output", output, "output folder (default: output.directory of the case)");
  run->add_option("-t,--threads", threads,
                  "OpenMP threads (default: OMP_NUM_THREADS, else all cores)")
      ->check(CLI::Range(1, 4096));
  run->add_option("-r,--restart", restart, "continue from a checkpoint file")
      ->check(CLI::ExistingFile);
  run->add_option("--steps", steps, "run this many steps instead of up to time.end")
      ->check(CLI::Range(0L, 1L << 50));
  double max_hours = 0;
  run->add_option("--max-hours", max_hours,
                  "stop after this much wall time (hours) as on SIGTERM, with every output and a "
                  "checkpoint, exit status 3")
      ->check(CLI::PositiveNumber);
  run->add_flag("--overwrite", opts.overwrite, "replace the contents of an existing output folder");
  run->add_flag("--append", opts.append,
                "with --restart: continue in the checkpoint's folder (default output), keeping its "
                "series and samples up to the checkpoint")
      ->excludes("--overwrite");
  run->add_flag("-q,--quiet", quiet, "no progress output, warnings only");
  std::string device = "cpu";
  run->add_option(
         "--device", device,
         "where the DEM steps run: cpu, or cuda (a GPU; 3D spheres, plane, box and cylinder walls: "
         "docs/gpu.md)")
      ->check(CLI::IsMember({"cpu", "cuda"}));
  std::vector<std::string> sets;
  run->add_option("--set", sets, "replace a key of the case, e.g. --set shear.rate=100")
      ->type_name("KEY=VALUE");

  auto* sweep = app.add_subcommand(
      "sweep", "run every combination of a case's sweep lists (volume fraction x shear rate)");
  std::string sweep_file, sweep_output;
  gf::SweepOptions sweep_opts;
  std::int64_t sweep_steps = -1;
  sweep->add_option("case", sweep_file, "case file with a sweep: block")->required();
  sweep->add_option("-o,--output", sweep_output, "output folder (default: output.directory)");
  sweep
      ->add_option("-j,--processes", sweep_opts.processes,
                   "runs at a time (default: sweep.processes, else the number of cores)")
      ->check(CLI::Range(1, 4096));
  sweep->add_option("--steps", sweep_steps, "run this many steps in every run")
      ->check(CLI::Range(0L, 1L << 50));
  sweep
      ->add_option("--max-hours", max_hours,
                   "stop every run after this much wall time (hours), exit status 3 (--continue "
                   "finishes the sweep later)")
      ->check(CLI::PositiveNumber);
  sweep->add_flag("--overwrite", sweep_opts.overwrite, "replace an existing output folder");
  sweep
      ->add_flag("--continue", sweep_opts.resume,
                 "continue a stopped sweep in its folder: keep finished runs, continue stopped "
                 "ones from their newest checkpoint, start the rest")
      ->excludes("--overwrite");
  bool no_plots = false;
  sweep->add_flag("--no-plots", no_plots, "write the table only");
  sweep->add_option("--set", sets, "replace a key of the case in every run")
      ->type_name("KEY=VALUE");

  auto* chk =
      app.add_subcommand("check", "validate a case and print derived numbers, without running");
  std::string check_file;
  chk->add_option("case", check_file, "case file (YAML)")->required();
  chk->add_option("--set", sets, "replace a key of the case, e.g. --set shear.rate=100")
      ->type_name("KEY=VALUE");

  app.add_subcommand("list-models", "list the registered models");
  auto* desc = app.add_subcommand("describe", "equation, reference and parameters of a model");
  std::string key;
  desc->add_option("key", key, "model key, e.g. hertz_mindlin")->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitInput;
  }
  gf::log::init(verbose, quiet);
  if (max_hours > 0) gf::stop::set_time_limit(max_hours * 3600.0);  // from the program's start

  try {
    if (*run) {
      gf::exec::set_threads(threads);  // 0: OMP_NUM_THREADS, else all cores
      opts.output = output;
      opts.case_file = run_file;
      if (opts.append && output.empty() && !restart.empty())
        opts.output = std::filesystem::path(restart).parent_path();
      if (steps >= 0) opts.steps = steps;
      opts.quiet = quiet;
      if (!restart.empty()) opts.restart = restart;
      opts.device = device == "cuda" ? gf::Device::Cuda : gf::Device::Cpu;
      // The CUDA back end runs DEM steps; the other methods' cases run on the host.
      auto host_only = [&](const char* what) {
        if (opts.device == gf::Device::Cuda)
          throw gf::InputError(fmt::format(
              "{}: --device cuda: this is a {} case (the CUDA back end runs DEM cases of spheres)",
              run_file, what));
      };
      std::filesystem::path fem_dir;
      if (const auto fem_cfg = gf::load_fem_case(run_file, fem_dir, overrides(sets))) {
        host_only("resolved-flow (fluid_fem)");
        gf::stop::install_handlers();
        const int sig = gf::run_fem_case(*fem_cfg, fem_dir, opts);
        return sig ? gf::stop::exit_status(sig) : 0;
      }
      if (const auto cc = gf::load_continuum_case(run_file, fem_dir, overrides(sets))) {
        host_only("continuum");
        gf::stop::install_handlers();
        const int sig = gf::run_continuum_case(*cc, fem_dir, opts);
        return sig ? gf::stop::exit_status(sig) : 0;
      }
      if (const auto tc = gf::load_two_fluid_case(run_file, fem_dir, overrides(sets))) {
        host_only("two-fluid");
        gf::stop::install_handlers();
        const int sig = gf::run_two_fluid_case(*tc, fem_dir, opts);
        return sig ? gf::stop::exit_status(sig) : 0;
      }
      const auto cfg = gf::input::load_case(run_file, overrides(sets));
      const auto report = gf::input::validate(cfg);
      for (const auto& w : report.warnings) gf::log::warn("{}", w);
      if (cfg.sweep)
        gf::log::info(
            "the case has a sweep: block; this runs its base values only (grainflow "
            "sweep runs every combination)");
      gf::Simulation sim(cfg);
      // From here a first SIGINT / SIGTERM ends the run after its step, with every output and a
      // checkpoint written; the exit status then says so (128 + signal, as for a killed program).
      gf::stop::install_handlers();
      const auto summary = sim.run(opts);
      return summary.stop_signal ? gf::stop::exit_status(summary.stop_signal) : 0;
    }
    if (*sweep) {
      const auto cfg = gf::input::load_case(sweep_file, overrides(sets));
      if (!cfg.sweep)
        throw gf::InputError(fmt::format(
            "{}: error: no sweep: block (give sweep: {{volume_fraction: [...], shear_rate: "
            "[...]}})",
            sweep_file));
      const auto report = gf::input::validate(cfg);
      for (const auto& w : report.warnings) gf::log::warn("{}", w);
      sweep_opts.output = sweep_output;
      sweep_opts.program = std::filesystem::read_symlink("/proc/self/exe");
      if (sweep_steps >= 0) sweep_opts.steps = sweep_steps;
      sweep_opts.plots = !no_plots;
      sweep_opts.overrides = overrides(sets);
      gf::stop::install_handlers();
      return gf::run_sweep(sweep_file, cfg, sweep_opts);
    }
    if (*chk) return check(check_file, sets);
    if (app.got_subcommand("list-models")) return list_models();
    if (*desc) return describe(key);
  } catch (const gf::InputError& e) {
    // Messages from the case reader already read "file:line:col: error: ...".
    const std::string msg = e.what();
    fmt::print(stderr, "{}{}\n", msg.find("error: ") == std::string::npos ? "error: " : "", msg);
    return kExitInput;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 1;
  }
  return 0;
}
