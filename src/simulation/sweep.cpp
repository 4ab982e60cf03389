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
#include <optional>
#include <sstream>
#include <string_view>
#include <thread>

#include "core/error.hpp"
#include "core/files.hpp"
#include "core/log.hpp"
#include "core/stop.hpp"
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

int run_sweep(const fs::path& case_file, const config::Case& c, const SweepOptions& opts) {
  const auto points = sweep_points(c);
  // Every run's case is valid before the first one starts (warnings are each run's own, in its
  // log).
  check_sweep_points(case_file, c, opts.overrides);
  const fs::path dir = opts.output.empty() ? c.output.directory : opts.output;
  if (opts.resume) {
    if (opts.overwrite) throw InputError("sweep: --continue and --overwrite exclude each other");
    if (!fs::is_directory(dir))
      throw InputError(fmt::format("sweep --continue: no sweep folder '{}'", dir.string()));
  } else {
    prepare_output_dir(dir, opts.overwrite);
  }
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
  }
  write_atomically(dir / "sweep.csv", [&](std::ostream& o) {
    o << "run,volume_fraction_nominal,shear_rate_nominal";
    for (const auto& q : quantities) o << fmt::format(",{0},{0}_err,{0}_kt", q);
    o << "\n";
    for (const auto& l : lines) o << l << "\n";
  });
  log::info("sweep: table of {} runs in '{}'", lines.size(), (dir / "sweep.csv").string());
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
