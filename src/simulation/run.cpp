// SPDX-License-Identifier: GPL-3.0-or-later
// The run: output folder policy, scheduled outputs (VTK, CSV, series, checkpoints), progress,
// and the end-of-run timing summary.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/files.hpp"
#include "core/log.hpp"
#include "core/progress.hpp"
#include "core/stop.hpp"
#include "core/version.hpp"
#include "gpu/sphere_dem.hpp"
#include "io/csv/csv.hpp"
#include "io/input/echo.hpp"
#include "io/input/parse_case.hpp"
#include "io/vtk/vtk.hpp"
#include "simulation/rheology_output.hpp"
#include "simulation/simulation.hpp"

namespace gf {

namespace fs = std::filesystem;

namespace {

/// Steps between events for an interval in seconds (0 = never).
std::int64_t every_steps(double every, double dt) {
  if (every <= 0) return 0;
  return std::max<std::int64_t>(1, std::llround(every / dt));
}

bool due(std::int64_t step, std::int64_t every) {
  return every > 0 && step % every == 0;
}

std::int64_t peak_rss_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<std::int64_t>(u.ru_maxrss) * 1024;
}

}  // namespace

namespace {

/// --append continues series.csv, whose columns must stay, and rheology.csv, whose samples the
/// steady-state averages and their block errors take as evenly spaced and alike: the series
/// quantities and the rheology sampling of `cfg` must be those of the run being continued (its
/// resolved case in the folder), checked before anything is written. Other intervals may change
/// (the time columns and file names say when each output was written). A resolved case this
/// build cannot read (a much older build's) is not compared.
void check_append_schedule(const fs::path& dir, const config::Case& cfg) {
  const fs::path earlier = dir / "resolved_case.yaml";
  if (!fs::exists(earlier)) return;
  config::Case old;
  try {
    old = input::load_case(earlier);
  } catch (const Error& e) {
    log::warn("--append: cannot read '{}' ({}); the rheology sampling is not compared",
              earlier.string(), e.what());
    return;
  }
  auto refuse = [&](const std::string& key, const std::string& now, const std::string& then) {
    throw InputError(
        fmt::format("--append: {} is {} in this case but {} in the run being continued ('{}'): "
                    "its file would mix the two; continue with the same {}, or without "
                    "--append in a new folder (--output)",
                    key, now, then, earlier.string(), key));
  };
  if (cfg.output.series.every > 0 && old.output.series.every > 0 &&
      cfg.output.quantities != old.output.quantities)
    refuse("output.series.quantities", fmt::format("[{}]", fmt::join(cfg.output.quantities, ", ")),
           fmt::format("[{}]", fmt::join(old.output.quantities, ", ")));
  if (!cfg.analysis.rheology) return;
  const auto& r = *cfg.analysis.rheology;
  const auto& ro = old.analysis.rheology;
  if (!ro) refuse("analysis.rheology", fmt::format("every {} s", r.every), "off");
  if (std::abs(r.every - ro->every) > 1e-9 * std::max(r.every, ro->every))
    refuse("analysis.rheology", fmt::format("every {} s", r.every),
           fmt::format("every {} s", ro->every));
  if (r.bins != ro->bins)
    refuse("analysis.rheology.bins", std::to_string(r.bins), std::to_string(ro->bins));
}

}  // namespace

void check_append(const fs::path& dir, const RunOptions& opts) {
  if (!opts.append) return;
  if (!opts.restart)
    throw InputError("--append continues a run in its folder: give the checkpoint (--restart)");
  if (opts.overwrite) throw InputError("--append and --overwrite exclude each other");
  if (!fs::is_directory(dir))
    throw InputError(fmt::format("--append: output folder '{}' does not exist", dir.string()));
}

RunSummary Simulation::run(const RunOptions& opts) {
  const fs::path dir = opts.output.empty() ? cfg_.output.directory : opts.output;
  check_append(dir, opts);
  if (opts.append) check_append_schedule(dir, cfg_);
  if (opts.restart) load_restart(*opts.restart, [this](const fs::path& f) { load_checkpoint(f); });
  // --device cuda: the steps run on the GPU, from the state now (checked and set up before
  // anything is written).
  std::shared_ptr<gpu::SphereDem> device;
  if (opts.device != Device::Cpu) {
    std::string why = device_unsupported();
    if (why.empty() && opts.device == Device::Cuda && !gpu::cuda_built())
      why = "this grainflow was built without CUDA (CMake preset 'cuda', docs/gpu.md)";
    if (!why.empty())
      throw InputError(fmt::format("{}: --device cuda: {}", cfg_.file.string(), why));
    if (opts.device == Device::Cuda && !gpu::device_available(&why))
      throw Error(fmt::format("--device cuda: {}", why));
    device = start_device(opts.device);
    const auto c = device->counts();
    log::info("device: {}, {} neighbour slots per grain, {:.1f} MB ({:.0f} bytes per grain)",
              opts.device == Device::Cuda ? "cuda" : "host mirror", c.list_capacity,
              static_cast<double>(c.bytes) / 1e6,
              particles_.size() ? static_cast<double>(c.bytes) / particles_.size() : 0.0);
  }
  OutputFolder folder(dir, opts);
  // --append: the outputs continue from the checkpoint's time; what the earlier run wrote after
  // it is dropped (rows, data sets) or rewritten when reached again (files named by the step).
  const std::optional<double> resume_time =
      opts.append ? std::optional<double>(time()) : std::nullopt;
  auto pvd = [&](const char* name) {
    return resume_time ? std::make_unique<io::PvdSeries>(dir / name, *resume_time)
                       : std::make_unique<io::PvdSeries>(dir / name);
  };

  // The resolved case, and beside it the CSV files of its long particle lists (written first:
  // the case names them).
  std::vector<input::EchoFile> echo_files;
  const std::string resolved = input::echo_yaml(cfg_, version_string, &echo_files);
  for (const auto& f : echo_files)
    write_atomically(dir / f.name, [&](std::ostream& o) { o << f.text; });
  write_atomically(dir / "resolved_case.yaml", [&](std::ostream& o) { o << resolved; });

  const std::int64_t first = step_;
  const std::int64_t builds_before = nlist_.n_builds();  // a restart carries the count over
  std::int64_t last = std::llround(cfg_.time.end / dt_);
  if (opts.steps) last = first + *opts.steps;
  const auto& out = cfg_.output;
  const std::int64_t vtk_every = every_steps(out.vtk.every, dt_);
  const std::int64_t csv_every = every_steps(out.particles_csv.every, dt_);
  const std::int64_t contacts_every = every_steps(out.contacts_csv.every, dt_);
  const std::int64_t contacts_vtk_every = every_steps(out.contacts_vtk.every, dt_);
  const std::int64_t series_every = every_steps(out.series.every, dt_);
  const std::int64_t ckpt_every = every_steps(out.checkpoint.every, dt_);

  std::unique_ptr<io::PvdSeries> pvd_particles, pvd_walls, pvd_polygons, pvd_fluid, pvd_contacts;
  if (contacts_vtk_every > 0) pvd_contacts = pvd("contacts.pvd");
  if (vtk_every > 0) {
    pvd_particles = pvd("particles.pvd");
    if (cfd_) pvd_fluid = pvd("fluid.pvd");
    if (!walls_.empty()) pvd_walls = pvd("walls.pvd");
    if (io::count_polygon_grains(particles_) > 0) pvd_polygons = pvd("polygons.pvd");
  }
  std::unique_ptr<io::SeriesCsv> series;
  std::vector<std::string> columns;
  if (series_every > 0) {
    columns = series_columns();
    // (a row at the checkpoint's step is written again below, when it is due)
    series = resume_time
                 ? std::make_unique<io::SeriesCsv>(dir / "series.csv", columns,
                                                   io::SeriesContinuation{*resume_time, false})
                 : std::make_unique<io::SeriesCsv>(dir / "series.csv", columns);
  }

  std::unique_ptr<RheologyOutput> rheology;
  if (cfg_.analysis.rheology) rheology = std::make_unique<RheologyOutput>(dir, *this, resume_time);

  auto last_flush = StageTimers::clock::now();
  // `sampled`: the step just taken ended on a rheology sample.
  // A run that diverged stops with an error before it writes non-finite numbers (or a
  // checkpoint of them): the grains are checked before every output and every 1000 steps.
  auto check_finite = [&] {
    if (const auto bad = first_non_finite_grain(particles_))
      throw Error(fmt::format(
          "the run diverged at t = {} s (step {}): grain {} has a non-finite position, velocity "
          "or spin (a time step too long for the contact stiffness, or an overlap too deep at "
          "the start?); nothing of this step was written",
          time(), step_, particles_.id()[*bad]));
  };
  auto write_outputs = [&](bool sampled) {
    StageTimers::Scope timer(timers_, Stage::Output);
    const double t = time();
    if (due(step_, vtk_every) || due(step_, csv_every) || due(step_, contacts_every) ||
        due(step_, contacts_vtk_every) || (series && due(step_, series_every)) ||
        due(step_, ckpt_every) || sampled || step_ % 1000 == 0)
      check_finite();
    if (due(step_, vtk_every)) {
      const std::string pf = fmt::format("particles_{:09d}.vtp", step_);
      io::write_particles_vtp(dir / pf, particles_);
      pvd_particles->add(t, pf);
      if (pvd_polygons) {
        const std::string polyf = fmt::format("polygons_{:09d}.vtp", step_);
        io::write_polygons_vtp(dir / polyf, particles_);
        pvd_polygons->add(t, polyf);
      }
      if (pvd_fluid) {
        const std::string ff = fmt::format("fluid_{:09d}.vti", step_);
        write_atomically(dir / ff, [&](std::ostream& o) { cfd_->write_vti(o); });
        pvd_fluid->add(t, ff);
      }
      if (pvd_walls) {
        std::vector<SurfaceMesh> meshes;
        std::vector<Vec3> forces;
        for (auto& w : walls_) {
          meshes.push_back(w.surface(domain_));
          forces.push_back(w.force);
        }
        const std::string wf = fmt::format("walls_{:09d}.vtp", step_);
        io::write_surfaces_vtp(dir / wf, meshes, forces);
        pvd_walls->add(t, wf);
      }
    }
    if (due(step_, csv_every))
      io::write_particles_csv(dir / fmt::format("particles_{:09d}.csv", step_), particles_);
    // (The contacts of a checkpoint's step are those the run that wrote it recorded: a restart
    // has not evaluated that step's forces.)
    if (due(step_, contacts_every)) write_contacts_csv(dir);
    if (std::string f; due(step_, contacts_vtk_every) && write_contacts_vtp(dir, f))
      pvd_contacts->add(t, f);
    const bool row = series && due(step_, series_every);
    if (row) {
      series->append(t, series_row(columns));
      series_row_written();
    }
    // Someone may be watching the time series of a long run: flush them every few seconds (on
    // steps that wrote a row), and before each checkpoint, so that a run killed later and
    // restarted from that checkpoint has every row up to it on disk.
    const bool checkpoint = due(step_, ckpt_every) && step_ != first;
    if (checkpoint ||
        ((row || sampled) &&
         std::chrono::duration<double>(StageTimers::clock::now() - last_flush).count() > 3.0)) {
      if (series) series->flush();
      if (rheology) rheology->flush();
      last_flush = StageTimers::clock::now();
    }
    if (checkpoint) save_checkpoint(dir / fmt::format("checkpoint_{:09d}.h5", step_));
  };

  log::info("run: {} particles, {} walls, steps {} -> {} (dt = {} s), output in '{}'",
            particles_.size(), walls_.size(), first, last, dt_, dir.string());
  write_outputs(false);

  Progress progress(time(), static_cast<double>(last) * dt_, stderr, 5.0);
  const auto t_start = StageTimers::clock::now();
  run_started_ = t_start;
  // The fluid's time is its own stage, "fluid" (kept by the coupling).
  auto fluid_seconds = [this] { return cfd_ ? cfd_->seconds() : 0.0; };
  const double loop_before =
      timers_.loop_seconds() - timers_.seconds(Stage::Output) + fluid_seconds();
  // Whether anything reads the grains' velocities after step s: then step s completes its
  // second half kick, else the next step's drift does it in the same pass (Simulation::step).
  auto observed_after = [&](std::int64_t s, bool sample) {
    return sample || s >= last || due(s, vtk_every) || due(s, csv_every) ||
           (series && due(s, series_every)) || due(s, ckpt_every);
  };
  // After each step (or device chunk) and its outputs: the progress line, and whether a stop was
  // requested (SIGINT / SIGTERM / time limit: the run then ends with the outputs below).
  auto reported_stop = [&] {
    if (!opts.quiet)
      progress.update(time(), static_cast<std::int64_t>(particles_.size()) * (step_ - first),
                      n_contacts_);
    return stop::requested() != 0;
  };
  // A device run advances on the GPU up to the next step whose state something reads (an
  // output, the 1000-step check), then copies the state back for it; the lists and contact
  // histories too where they are read (checkpoints, the elastic energy).
  const bool energy_columns = std::any_of(columns.begin(), columns.end(), [](const std::string& c) {
    return c == "elastic_energy" || c == "total_energy";
  });
  std::int64_t lists_synced_at = -1;  // the step whose state the host's lists hold, if any
  while (device && step_ < last) {
    std::int64_t next = std::min(last, (step_ / 1000 + 1) * 1000);
    for (std::int64_t s = step_ + 1; s < next; ++s)
      if (observed_after(s, false)) {
        next = s;
        break;
      }
    {
      StageTimers::Scope timer(timers_, Stage::Force);  // (the whole device step)
      next = step_ + device->advance(next - step_);     // (fewer on a stop request)
    }
    step_ = next;
    {
      StageTimers::Scope timer(timers_, Stage::Output);
      const bool checkpoint = due(step_, ckpt_every) && step_ != first;
      const bool lists =
          checkpoint || step_ == last || (energy_columns && due(step_, series_every));
      sync_from_device(*device, lists);
      lists_synced_at = lists ? step_ : -1;
    }
    write_outputs(false);
    if (reported_stop()) break;
  }
  // The final checkpoint needs the lists of the last step (a run that took no step keeps the
  // host's state as it was: the device has evaluated nothing).
  if (device && step_ != first && lists_synced_at != step_) {
    StageTimers::Scope timer(timers_, Stage::Output);
    sync_from_device(*device, true);
  }
  while (!device && step_ < last) {
    const bool sample = rheology && rheology->due(step_ + 1);
    collect_virial(sample);
    collect_contacts(due(step_ + 1, contacts_every) || due(step_ + 1, contacts_vtk_every));
    step(/*defer_kick=*/!observed_after(step_ + 1, sample));
    if (sample) {
      StageTimers::Scope timer(timers_, Stage::Output);
      rheology->sample(*this);
      reset_wall_means(WallMeans::Rheology);
    }
    write_outputs(sample);
    if (reported_stop()) break;
  }
  // An interrupted run may end on a step whose second half kick was deferred: complete it, so
  // that the checkpoint holds the same state as one written by an uninterrupted run.
  complete_step();
  const int stop_signal = step_ < last ? stop::requested() : 0;
  const std::int64_t steps = step_ - first;
  const std::int64_t pstep = static_cast<std::int64_t>(particles_.size()) * steps;
  if (!opts.quiet) progress.finish(time(), pstep, n_contacts_);
  // The final state is always kept, whatever the output intervals; a stopped run names its
  // checkpoint by the step (unless the schedule just wrote it), the end of the run by "final".
  const fs::path final_checkpoint =
      dir / (stop_signal ? fmt::format("checkpoint_{:09d}.h5", step_) : "checkpoint_final.h5");
  {
    StageTimers::Scope timer(timers_, Stage::Output);
    check_finite();
    if (series && !due(step_, series_every)) {
      series->append(time(), series_row(columns));
    }
    if (series) series->flush();
    if (rheology) rheology->finish(*this);
    if (!(stop_signal && due(step_, ckpt_every) && step_ != first))
      save_checkpoint(final_checkpoint);
  }
  const double wall = std::chrono::duration<double>(StageTimers::clock::now() - t_start).count();
  const double loop =
      timers_.loop_seconds() - timers_.seconds(Stage::Output) + fluid_seconds() - loop_before;

  RunSummary s;
  s.n_particles = static_cast<std::int64_t>(particles_.size());
  s.steps = steps;
  s.loop_seconds = loop;
  s.particle_steps_per_second = loop > 0 ? static_cast<double>(pstep) / loop : 0.0;
  s.peak_rss_bytes = peak_rss_bytes();
  s.stop_signal = stop_signal;
  s.checkpoint = final_checkpoint;

  std::string stages;
  for (int k = 0; k < static_cast<int>(Stage::Setup); ++k) {
    const auto st = static_cast<Stage>(k);
    stages += fmt::format("{}\"{}\": {:.6f}", k ? ", " : "", stage_names[k], timers_.seconds(st));
  }
  if (cfd_) stages += fmt::format(", \"fluid\": {:.6f}", cfd_->seconds());
  write_atomically(dir / "summary.json", [&](std::ostream& o) {
    o << fmt::format(
        "{{\n  \"program\": \"grainflow {}\",\n  \"n_particles\": {},\n  \"steps\": {},\n  "
        "\"threads\": {},\n  \"device\": \"{}\",\n"
        "  \"loop_seconds\": {:.6f},\n  \"wall_seconds\": {:.6f},\n  "
        "\"particle_steps_per_second\": {:.6g},\n"
        "  \"peak_rss_bytes\": {},\n  \"neighbor_builds\": {},\n  \"stages\": {{{}}},\n"
        "  \"completed\": {},\n  \"stopped_by\": {},\n  \"time\": {:.17g},\n"
        "  \"step\": {},\n  \"runs\": {},\n  \"wall_seconds_all_runs\": {}\n}}\n",
        version_string, s.n_particles, s.steps, exec::n_threads(),
        device ? (opts.device == Device::Cuda ? "cuda" : "host_mirror") : "cpu", s.loop_seconds,
        wall, s.particle_steps_per_second, s.peak_rss_bytes,
        device ? device->counts().list_builds : nlist_.n_builds() - builds_before, stages,
        stop_signal ? "false" : "true",
        stop_signal ? fmt::format("\"{}\"", stop::signal_name(stop_signal)) : "null", time(), step_,
        runs_before_ + 1,
        std::isnan(wall_seconds_before_) ? "null"
                                         : fmt::format("{:.6f}", wall_seconds_before_ + wall));
  });
  // This run now counts among those before any later one (a run() again, a checkpoint saved
  // after it).
  ++runs_before_;
  wall_seconds_before_ += wall;
  run_started_.reset();
  folder.commit();  // (the log lines below cannot fail the run)

  log::info("timing summary ({} steps, {} thread{}):", steps, exec::n_threads(),
            exec::n_threads() > 1 ? "s" : "");
  const double total = timers_.loop_seconds() + fluid_seconds();
  for (int k = 0; k < static_cast<int>(Stage::Setup); ++k) {
    const double sec = timers_.seconds(static_cast<Stage>(k));
    log::info("  {:<10} {:10.3f} s  {:5.1f} %", stage_names[k], sec,
              total > 0 ? 100 * sec / total : 0.0);
  }
  if (cfd_)
    log::info("  {:<10} {:10.3f} s  {:5.1f} %", "fluid", cfd_->seconds(),
              total > 0 ? 100 * cfd_->seconds() / total : 0.0);
  log::info(
      "  {:<10} {:10.3f} s  ({:.3g} particle-steps/s without output, {} neighbour builds, peak "
      "memory {:.1f} MiB)",
      "total", total, s.particle_steps_per_second,
      device ? device->counts().list_builds : nlist_.n_builds() - builds_before,
      s.peak_rss_bytes / 1048576.0);
  if (stop_signal)
    log::warn(
        "run stopped by {} at t = {} s (step {} of {}): outputs written; continue with "
        "--restart {} (and --append to carry on in this folder)",
        stop::signal_name(stop_signal), time(), step_, last, final_checkpoint.string());
  return s;
}

}  // namespace gf
