// SPDX-License-Identifier: GPL-3.0-or-later
// Sweep runner: child processes through posix_spawn, a bounded number at a time.
#include "simulation/sweep.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <string_view>
#include <thread>

#include "analysis/kinetic_theory.hpp"
#include "analysis/mu_i_fit.hpp"
#include "core/error.hpp"
#include "core/files.hpp"
#include "core/log.hpp"
#include "core/stop.hpp"
#include "io/input/echo.hpp"
#include "io/input/validate.hpp"
#include "simulation/rheology_output.hpp"
#include "simulation/simulation.hpp"

extern char** environ;

namespace gf {

namespace fs = std::filesystem;

namespace {

/// Index of the particle group whose fill gives a volume fraction (-1: none).
int fraction_group(const config::Case& c) {
  for (std::size_t g = 0; g < c.particles.size(); ++g)
    if (c.particles[g].fill && c.particles[g].fill->volume_fraction) return static_cast<int>(g);
  return -1;
}

/// Starts `args` with stdout and stderr to `log` (truncated, or appended to); returns the
/// child's pid.
pid_t spawn(const std::vector<std::string>& args, const fs::path& log, bool append = false) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(),
                                   O_WRONLY | O_CREAT | (append ? O_APPEND : O_TRUNC), 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  // Each child in a process group of its own: a Ctrl-C at the terminal reaches only the sweep,
  // which passes one SIGTERM on to each run (a second signal would end a run without outputs).
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attr, 0);
  // ... and told who its sweep is, so that it stops (with a checkpoint) if the sweep dies.
  const std::string key = fmt::format("{}=", stop::kParentEnv);
  const std::string parent = key + std::to_string(getpid());
  std::vector<char*> envp;
  for (char** e = environ; *e; ++e)
    if (std::string_view(*e).substr(0, key.size()) != key) envp.push_back(*e);
  envp.push_back(const_cast<char*>(parent.c_str()));
  envp.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &fa, &attr, argv.data(), envp.data());
  posix_spawnattr_destroy(&attr);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw std::runtime_error(fmt::format("cannot start {}: error {}", args[0], rc));
  return pid;
}

/// Whether the run in `dir` ended (summary.json with "completed": true; runs of builds before
/// that key: a checkpoint_final.h5).
bool run_completed(const fs::path& dir) {
  const fs::path summary = dir / "summary.json";
  if (!fs::exists(summary)) return false;
  const std::string text = read_text_file(summary);
  if (text.find("\"completed\"") == std::string::npos)
    return fs::exists(dir / "checkpoint_final.h5");
  return text.find("\"completed\": true") != std::string::npos;
}

/// The checkpoint of `dir` with the highest step (checkpoint_NNNNNNNNN.h5), if any.
std::optional<fs::path> newest_checkpoint(const fs::path& dir) {
  std::optional<fs::path> best;
  if (!fs::is_directory(dir)) return best;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n.size() == 23 && n.rfind("checkpoint_", 0) == 0 && n.ends_with(".h5") &&
        n.find_first_not_of("0123456789", 11) == 20 && (!best || n > best->filename().string()))
      best = e.path();
  }
  return best;
}

/// The plan of a sweep, as lines: its runs, then the resolved case (with the --set overrides)
/// that every run starts from, without comment lines (which name the program version and file).
/// `--continue` carries on a sweep only if its plan is this one's.
/// The resolved case's lines (comments left out), indented by two spaces, appended to `lines`.
void append_case_lines(const config::Case& c, std::vector<std::string>& lines) {
  std::istringstream echo(input::echo_yaml(c, ""));
  for (std::string l; std::getline(echo, l);)
    if (!l.empty() && l.front() != '#') lines.push_back("  " + l);
}

std::vector<std::string> sweep_plan(const config::Case& c, const std::vector<SweepPoint>& points) {
  std::vector<std::string> lines{
      "# grainflow sweep plan: `grainflow sweep --continue` carries on "
      "only the sweep this file describes"};
  std::string runs = "runs:";
  for (const auto& p : points) runs += " " + p.name;
  lines.push_back(runs);
  lines.emplace_back("case:");
  append_case_lines(c, lines);
  return lines;
}

constexpr const char* kPlanFile = "sweep_plan.txt";

/// Refuses to continue the sweep in `dir` when its plan (written when it started) differs from
/// `plan`: its table would mix two sweeps, or drop the runs of the first. Names the first
/// difference. A folder of a build before the plan file gets it now, with a warning.
void check_sweep_plan(const fs::path& dir, const std::vector<std::string>& plan) {
  const fs::path file = dir / kPlanFile;
  if (!fs::exists(file)) {
    log::warn(
        "sweep --continue: '{}' has no {} (a sweep of an earlier build): it is not checked that "
        "its runs and case are this sweep's",
        dir.string(), kPlanFile);
    return;
  }
  std::vector<std::string> had;
  std::istringstream in(read_text_file(file));
  for (std::string l; std::getline(in, l);) had.push_back(l);
  // The plan's case as this build writes it: another build may write the same case otherwise
  // (a key added since, with its default), which is not another sweep.
  if (const auto at = std::find(had.begin(), had.end(), "case:"); at != had.end()) {
    std::string text;
    for (auto k = at + 1; k != had.end(); ++k) text += (k->size() >= 2 ? k->substr(2) : *k) + "\n";
    try {
      const config::Case old = input::load_case_text(text, file);
      had.erase(at + 1, had.end());
      append_case_lines(old, had);
    } catch (const Error& e) {
      log::warn(
          "sweep --continue: this build cannot read the case in '{}' ({}); it is compared "
          "as written",
          file.string(), e.what());
    }
  }
  const auto differ = std::mismatch(plan.begin(), plan.end(), had.begin(), had.end());
  if (differ.first == plan.end() && differ.second == had.end()) return;
  // A differing line with the lines it sits under (smaller indentation), e.g.
  // "contacts: > - between: [rod, rod] > restitution: 0.7".
  auto with_parents = [](const std::vector<std::string>& lines, std::size_t i) {
    if (i >= lines.size()) return std::string("(nothing)");
    auto indent = [](const std::string& l) { return l.find_first_not_of(' '); };
    std::string out = lines[i].substr(std::min(indent(lines[i]), lines[i].size()));
    for (std::size_t k = i, level = indent(lines[i]); k-- > 0 && level > 2;)
      if (indent(lines[k]) < level) {
        level = indent(lines[k]);
        out = lines[k].substr(level) + " > " + out;
      }
    return out;
  };
  const std::string now = with_parents(plan, differ.first - plan.begin());
  const std::string then = with_parents(had, differ.second - had.begin());
  const bool runs = now.starts_with("runs:") || then.starts_with("runs:");
  throw InputError(fmt::format(
      "sweep --continue: '{}' holds another sweep; continuing it would {} ({}):\n"
      "  that sweep: {}\n  this one:   {}\n"
      "continue it with the case and --set values it started with, or start this sweep in "
      "another folder (-o)",
      dir.string(),
      runs ? "leave runs of the two out of one table or mix them"
           : "mix runs of two different cases in one table",
      file.string(), then, now));
}

}  // namespace

std::vector<SweepPoint> sweep_points(const config::Case& c) {
  REQUIRE(c.sweep && c.shear, "the case has no sweep (or no shear) block");
  std::vector<double> phis = c.sweep->volume_fractions;
  std::vector<double> rates = c.sweep->shear_rates;
  if (phis.empty()) phis.push_back(std::nan(""));
  if (rates.empty()) rates.push_back(c.shear->rate);
  std::vector<SweepPoint> out;
  for (double phi : phis)
    for (double rate : rates) {
      SweepPoint p{phi, rate, ""};
      p.name = std::isnan(phi) ? fmt::format("rate_{:g}", rate)
                               : fmt::format("phi_{:g}_rate_{:g}", phi, rate);
      out.push_back(p);
    }
  return out;
}

std::vector<input::Override> point_overrides(const config::Case& c, const SweepPoint& p,
                                             const std::vector<input::Override>& overrides) {
  std::vector<input::Override> out = overrides;
  out.push_back({"shear.rate", fmt::format("{}", p.shear_rate)});
  if (!std::isnan(p.volume_fraction))
    out.push_back({fmt::format("particles[{}].fill.volume_fraction", fraction_group(c)),
                   fmt::format("{}", p.volume_fraction)});
  return out;
}

std::vector<std::string> check_sweep_points(const fs::path& case_file, const config::Case& c,
                                            const std::vector<input::Override>& overrides) {
  std::vector<std::string> warnings;
  for (const auto& p : sweep_points(c)) {
    try {
      const auto report =
          input::validate(input::load_case(case_file, point_overrides(c, p, overrides)));
      for (const auto& w : report.warnings) warnings.push_back(fmt::format("{}: {}", p.name, w));
    } catch (const InputError& e) {
      throw InputError(fmt::format(
          "{}\n(in sweep run {}: --set shear.rate={}{})", e.what(), p.name, p.shear_rate,
          std::isnan(p.volume_fraction)
              ? ""
              : fmt::format(" and volume fraction {}", p.volume_fraction)));
    }
  }
  return warnings;
}

analysis::MuIFit write_mu_i_fit(const config::Case& c, const std::vector<SweepRunResult>& runs,
                                const fs::path& dir) {
  // The grains' diameter and density, as for the kinetic theory of rheology_summary.csv.
  double d = std::nan(""), rho = std::nan("");
  std::string material;
  if (!c.particles.empty()) {
    const auto& g = c.particles.front();
    material = g.material;
    for (const auto& m : c.materials)
      if (m.name == g.material) rho = m.density;
    const double measure = input::grain_measure(g, g.radius.largest());
    d = c.dimension == 2 ? std::sqrt(4 * measure / std::numbers::pi)
                         : analysis::volume_equivalent_diameter(measure);
  }
  std::vector<analysis::MuIPoint> points;
  for (const auto& r : runs)
    points.push_back(
        {analysis::inertial_number(r.shear_rate, d, r.pressure, rho), r.friction, r.friction_err});
  const auto fit = analysis::fit_mu_i(points);
  const bool have_values = std::isfinite(fit.mu_s);

  // max_viscosity: 10 x the largest apparent viscosity mu P / |gamma_dot| of the fitted runs,
  // rounded up to a power of ten, so that every measured state lies on the mu(I) branch.
  double eta_runs = 0;
  for (std::size_t k = 0; k < runs.size(); ++k)
    if (std::isfinite(points[k].inertial_number) && points[k].inertial_number > 0 &&
        std::isfinite(runs[k].friction))
      eta_runs =
          std::max(eta_runs, runs[k].friction * runs[k].pressure / std::abs(runs[k].shear_rate));
  const int eta_exponent = eta_runs > 0 && std::isfinite(eta_runs)
                               ? static_cast<int>(std::ceil(std::log10(10 * eta_runs)))
                               : 0;

  const std::string status = fit.ok()                                           ? "fitted"
                             : fit.status == analysis::MuIFitStatus::Unphysical ? "rejected"
                                                                                : "no fit";
  write_atomically(dir / "mu_i_fit.txt", [&](std::ostream& o) {
    o << "# mu(I) of the runs of this sweep (grainflow sweep; docs/case-file.md, sweep)\n"
         "# law: mu(I) = mu_s + (mu_2 - mu_s) / (1 + I0 / I),  I = |shear_rate| d / sqrt(P / "
         "rho_s)\n"
         "#      (Jop, Forterre & Pouliquen 2006, Nature 441:727, eqs. 2-3)\n";
    o << fmt::format(
        "# d = {:.6g} m: {} diameter of the largest grain of particles[0]{}; rho_s = {:.6g} "
        "kg/m^3 (material '{}')\n",
        d, c.dimension == 2 ? "area-equivalent" : "volume-equivalent",
        c.particles.size() > 1 ? fmt::format(" (of {} groups)", c.particles.size()) : "", rho,
        material);
    o << "# fit: least squares in mu, unweighted (mu_err enters the reduced chi^2 only); for "
         "each I0 of a log grid\n"
         "# the law is linear in (mu_s, mu_2 - mu_s) and solved exactly, the best I0 refined by "
         "golden section\n"
         "# (analysis/mu_i_fit.hpp); residual = mu_fit - mu\n#\n";
    o << fmt::format("# {:<24} {:>12} {:>12} {:>12} {:>10} {:>10} {:>10} {:>10}\n", "run",
                     "rate [1/s]", "P [Pa]", "I", "mu", "mu_err", "mu_fit", "residual");
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const double i = points[k].inertial_number;
      const bool used = std::isfinite(i) && i > 0 && std::isfinite(runs[k].friction);
      const double mf =
          have_values && used ? analysis::mu_i_friction(i, fit.mu_s, fit.mu_2, fit.i0) : NAN;
      o << fmt::format(
          "  {:<24} {:>12.6g} {:>12.6g} {:>12.6g} {:>10.6g} {:>10.3g} {:>10.6g} "
          "{:>10.3g}{}\n",
          runs[k].name, runs[k].shear_rate, runs[k].pressure, i, runs[k].friction,
          runs[k].friction_err, mf, mf - runs[k].friction,
          used ? "" : "  (not used: P <= 0 or friction not finite)");
    }
    o << "\n";
    o << fmt::format("status: {}\n", status);
    if (!fit.note.empty()) o << fmt::format("{}: {}\n", fit.ok() ? "note" : "reason", fit.note);
    o << fmt::format("points: {} ({} distinct I)\n", fit.points, fit.distinct);
    o << fmt::format("I_range: [{:.4g}, {:.4g}]\n", fit.i_min, fit.i_max);
    if (!have_values) return;
    if (!fit.ok())
      o << "# the least-squares optimum below is NO friction law (see reason): do not use it\n";
    o << fmt::format("mu_s: {:.6g} +- {:.2g}\n", fit.mu_s, fit.mu_s_err);
    o << fmt::format("mu_2: {:.6g} +- {:.2g}\n", fit.mu_2, fit.mu_2_err);
    o << fmt::format("i0: {:.6g} +- {:.2g}   (searched over [{:.3g}, {:.3g}])\n", fit.i0,
                     fit.i0_err, fit.i0_low, fit.i0_high);
    o << fmt::format("rms_residual: {:.3g}\n", fit.rms);
    o << fmt::format("reduced_chi2: {:.3g}\n", fit.reduced_chi2);
    if (!fit.ok()) return;
    o << fmt::format(
        "\n# For a continuum case (continuum.rheology). Valid over the I range above, an "
        "extrapolation outside it.\n"
        "# max_viscosity (the regularisation cap): 10 x the largest apparent viscosity mu P / "
        "|shear_rate| of the runs\n"
        "# ({:.3g} Pa s), rounded up to a power of ten: every measured state flows on the mu(I) "
        "branch, below the cap.\n"
        "# A static region creeps at about mu_s p / max_viscosity: check that against the "
        "target flow's pressures\n"
        "# (a larger cap: stiffer static regions and, with an explicit viscous step, a smaller "
        "time step).\n",
        eta_runs);
    o << fmt::format(
        "rheology: {{model: mu_i, mu_s: {:.4f}, mu_2: {:.4f}, i0: {:.4g}, grain_diameter: {:.6g}, "
        "grain_density: {:.6g}, max_viscosity: 1.0e{}}}\n",
        fit.mu_s, fit.mu_2, fit.i0, d, rho, eta_exponent);
  });
  const std::string file = (dir / "mu_i_fit.txt").string();
  if (fit.ok())
    log::info(
        "sweep: mu(I) fit of {} runs over I = {:.3g} .. {:.3g} (Jop et al. 2006): mu_s = {:.4f} "
        "+- {:.2g}, mu_2 = {:.4f} +- {:.2g}, I0 = {:.4g} +- {:.2g} (rms {:.2g}){}; in '{}'",
        fit.points, fit.i_min, fit.i_max, fit.mu_s, fit.mu_s_err, fit.mu_2, fit.mu_2_err, fit.i0,
        fit.i0_err, fit.rms, fit.note.empty() ? "" : "; " + fit.note, file);
  else if (fit.status == analysis::MuIFitStatus::Unphysical)
    log::warn("sweep: no mu(I) law from the {} runs: {} (see '{}')", fit.points, fit.note, file);
  else
    log::info("sweep: no mu(I) fit: {} (see '{}')", fit.note, file);
  return fit;
}

int run_sweep(const fs::path& case_file, const config::Case& c, const SweepOptions& opts) {
  const auto points = sweep_points(c);
  // Every run's case is valid before the first one starts (warnings are each run's own, in its
  // log).
  check_sweep_points(case_file, c, opts.overrides);
  const auto plan = sweep_plan(c, points);
  const fs::path dir = opts.output.empty() ? c.output.directory : opts.output;
  if (opts.resume) {
    if (opts.overwrite) throw InputError("sweep: --continue and --overwrite exclude each other");
    if (!fs::is_directory(dir))
      throw InputError(fmt::format("sweep --continue: no sweep folder '{}'", dir.string()));
    check_sweep_plan(dir, plan);
  } else {
    prepare_output_dir(dir, opts.overwrite);
  }
  write_atomically(dir / kPlanFile, [&](std::ostream& o) {
    for (const auto& l : plan) o << l << "\n";
  });
  int procs = opts.processes > 0 ? opts.processes : c.sweep->processes;
  if (procs <= 0) procs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  log::info("sweep: {} runs, {} at a time, output in '{}'", points.size(), procs, dir.string());

  std::map<pid_t, std::size_t> running;
  std::vector<int> status(points.size(), -1);
  std::size_t next = 0;
  bool forwarded = false;  // the stop request was passed on to the running children
  // Waits for one child to end. Polls, so that a SIGINT / SIGTERM to the sweep is passed on to
  // the runs at once (each then ends its step and writes its outputs and a checkpoint).
  auto reap = [&]() {
    int st = 0;
    pid_t pid = 0;
    while ((pid = waitpid(-1, &st, WNOHANG)) == 0) {
      if (stop::requested() && !forwarded) {
        for (const auto& [child, k] : running) kill(child, SIGTERM);
        forwarded = true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    if (pid < 0) return;
    const std::size_t k = running.at(pid);
    running.erase(pid);
    status[k] = WIFEXITED(st) ? WEXITSTATUS(st) : 128;
    log::info("sweep: {} {} ({} of {} done)", points[k].name,
              status[k] == 0 ? "finished" : fmt::format("FAILED (exit {})", status[k]),
              std::count_if(status.begin(), status.end(), [](int s) { return s >= 0; }),
              points.size());
  };
  while (next < points.size() || !running.empty()) {
    while (next < points.size() && static_cast<int>(running.size()) < procs && !stop::requested()) {
      const auto& p = points[next];
      const fs::path run_dir = dir / p.name;
      std::vector<std::string> args{
          opts.program.string(), "run", case_file.string(), "--output", run_dir.string(),
          "--threads",           "1",   "--quiet"};
      if (opts.resume) {
        if (run_completed(run_dir)) {
          status[next] = 0;
          log::info("sweep: {} finished before; kept", p.name);
          ++next;
          continue;
        }
        if (const auto ckpt = newest_checkpoint(run_dir)) {
          args.insert(args.end(), {"--restart", ckpt->string(), "--append"});
          log::info("sweep: {} continues from {}", p.name, ckpt->filename().string());
        } else {
          args.push_back("--overwrite");  // started and left no checkpoint: start again
        }
      }
      if (opts.steps) {
        args.push_back("--steps");
        args.push_back(std::to_string(*opts.steps));
      }
      for (const auto& o : point_overrides(c, p, opts.overrides)) {
        args.push_back("--set");
        args.push_back(o.path + "=" + o.value);
      }
      // (a continued run adds to its log)
      running[spawn(args, dir / (p.name + ".log"), opts.resume)] = next;
      ++next;
    }
    if (running.empty()) break;  // stopped before the remaining runs started
    reap();
  }
  if (const int sig = stop::requested()) {
    log::warn(
        "sweep: stopped by {}: {} of {} runs finished, {} stopped early (each wrote a checkpoint "
        "to continue from; see its .log), {} not started; the table has the finished runs",
        stop::signal_name(sig), std::count(status.begin(), status.end(), 0), points.size(),
        std::count(status.begin(), status.end(), stop::exit_status(SIGTERM)), points.size() - next);
  }

  // One table: nominal values, then mean, standard error and kinetic theory per quantity.
  std::vector<std::string> quantities;
  std::vector<std::string> lines;
  std::vector<SweepRunResult> results;  // for the mu(I) fit
  int failed = 0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const fs::path summary = dir / points[k].name / "rheology_summary.csv";
    if (status[k] != 0 || !fs::exists(summary)) {
      ++failed;
      continue;
    }
    const auto s = read_rheology_summary(summary);
    if (quantities.empty())
      for (const auto& [q, v] : s) quantities.push_back(q);
    std::string line =
        fmt::format("{},{:g},{}", points[k].name, points[k].volume_fraction, points[k].shear_rate);
    for (const auto& q : quantities) {
      const auto it = s.find(q);
      const std::array<double, 3> v =
          it == s.end() ? std::array<double, 3>{NAN, NAN, NAN} : it->second;
      line += fmt::format(",{:.10g},{:.10g},{:.10g}", v[0], v[1], v[2]);
    }
    lines.push_back(line);
    auto mean = [&](const char* q, std::size_t i = 0) {
      const auto it = s.find(q);
      return it == s.end() ? std::nan("") : it->second[i];
    };
    results.push_back({points[k].name, mean("shear_rate"), mean("pressure"), mean("friction"),
                       mean("friction", 1)});
  }
  write_atomically(dir / "sweep.csv", [&](std::ostream& o) {
    o << "run,volume_fraction_nominal,shear_rate_nominal";
    for (const auto& q : quantities) o << fmt::format(",{0},{0}_err,{0}_kt", q);
    o << "\n";
    for (const auto& l : lines) o << l << "\n";
  });
  log::info("sweep: table of {} runs in '{}'", lines.size(), (dir / "sweep.csv").string());
  write_mu_i_fit(c, results, dir);
  if (failed > 0 && !stop::requested())
    log::warn("sweep: {} of {} runs failed or wrote no rheology summary (see their .log files)",
              failed, points.size());
  if (opts.plots && !lines.empty()) {
    const fs::path script = fs::path(GF_SCRIPTS_DIR) / "plot_sweep.py";
    const std::vector<std::string> args{"/usr/bin/python3", script.string(),
                                        (dir / "sweep.csv").string(), dir.string()};
    if (!fs::exists(script) || !fs::exists(args[0])) {
      log::warn("sweep: no plots ({} or python3 not found); run: python3 plot_sweep.py {} {}",
                script.string(), args[2], args[3]);
    } else {
      const pid_t pid = spawn(args, dir / "plots.log");
      int st = 0;
      waitpid(pid, &st, 0);
      if (WIFEXITED(st) && WEXITSTATUS(st) == 0)
        log::info("sweep: plots in '{}'", dir.string());
      else
        log::warn("sweep: plotting failed (see {}); needs python3-matplotlib",
                  (dir / "plots.log").string());
    }
  }
  if (const int sig = stop::requested()) return stop::exit_status(sig);
  return failed == 0 ? 0 : 1;
}

}  // namespace gf
