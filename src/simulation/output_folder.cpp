// SPDX-License-Identifier: GPL-3.0-or-later
// Output folder policy: refusal of foreign folders, and the earlier contents kept until a run
// has succeeded.
#include "simulation/output_folder.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <array>
#include <ctime>
#include <vector>

#include "core/error.hpp"
#include "core/log.hpp"
#include "simulation/simulation.hpp"

namespace gf {

namespace fs = std::filesystem;

namespace {

/// Files that every kind of run writes into its folder at its start or end (DEM, CFD-DEM and
/// rheology runs, SPH, two-fluid, fluid_fem, the sweep runner's table).
constexpr std::array kRunFiles = {"resolved_case.yaml", "summary.json",   "sweep.csv",
                                  "sweep_plan.txt",     "fem_forces.csv", "fem_summary.txt"};

bool holds_run_file(const fs::path& dir) {
  for (const char* f : kRunFiles)
    if (fs::exists(dir / f)) return true;
  return false;
}

/// A folder grainflow wrote: a run's, or a sweep's (whose runs have sub-folders).
bool is_run_folder(const fs::path& dir) {
  if (holds_run_file(dir)) return true;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_directory() && holds_run_file(e.path())) return true;
  return false;
}

/// The folder as an absolute path without a trailing separator ("out/" and "out" alike).
fs::path normal(const fs::path& dir) {
  fs::path p = fs::weakly_canonical(fs::absolute(dir));
  if (p.filename().empty()) p = p.parent_path();
  return p;
}

fs::path earlier_of(const fs::path& dir) {
  return dir.parent_path() / fmt::format(".{}.grainflow-earlier", dir.filename().string());
}

/// Regular files and links under `root`, relative to it.
std::vector<fs::path> files_under(const fs::path& root) {
  std::vector<fs::path> out;
  if (!fs::exists(root)) return out;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (!e.is_directory() || e.is_symlink()) out.push_back(fs::relative(e.path(), root));
  return out;
}

/// Moves `from` to `to`, creating the parent folders of `to`.
void move_file(const fs::path& from, const fs::path& to) {
  fs::create_directories(to.parent_path());
  fs::rename(from, to);
}

}  // namespace

namespace {

/// The refusals of prepare_output_dir; true if the folder exists and is not empty.
bool check_output_dir(const fs::path& dir, bool overwrite, const fs::path& case_file) {
  if (!fs::exists(dir)) return false;
  if (!fs::is_directory(dir))
    throw InputError(fmt::format("output path '{}' exists and is not a folder", dir.string()));
  if (fs::is_empty(dir)) return false;
  if (!overwrite)
    throw InputError(fmt::format(
        "output folder '{}' exists and is not empty; choose another with --output, or pass "
        "--overwrite to replace it",
        dir.string()));
  if (!case_file.empty()) {
    // (the case file lies in the folder, or below it)
    const auto rel = normal(case_file).lexically_relative(normal(dir));
    if (!rel.empty() && *rel.begin() != "..")
      throw InputError(fmt::format(
          "--overwrite: output folder '{}' holds the case file '{}', which replacing the folder "
          "would delete; choose another folder with --output",
          dir.string(), case_file.string()));
  }
  if (!is_run_folder(dir))
    throw InputError(fmt::format(
        "--overwrite: output folder '{}' is not empty and holds no grainflow output (none of "
        "{}); --overwrite replaces only a folder a run wrote: choose another --output, or empty "
        "it yourself",
        dir.string(), fmt::join(kRunFiles, ", ")));
  return true;
}

/// Creates the folder; one that cannot be made (a path under a file, a read-only or special
/// file system) is the user's bad --output: InputError, exit status 2.
void create_output_dir(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
    throw InputError(
        fmt::format("output folder '{}' cannot be created: {}; choose another with "
                    "--output",
                    dir.string(), ec.message()));
}

}  // namespace

void prepare_output_dir(const fs::path& dir, bool overwrite, const fs::path& case_file) {
  if (check_output_dir(dir, overwrite, case_file))
    for (const auto& e : fs::directory_iterator(dir)) fs::remove_all(e.path());
  create_output_dir(dir);
}

OutputFolder::OutputFolder(const fs::path& dir, const RunOptions& opts) : dir_(dir) {
  const bool keep = fs::is_directory(dir) && !fs::is_empty(dir) && (opts.append || opts.overwrite);
  if (keep) {
    const fs::path d = normal(dir);
    earlier_ = earlier_of(d);
    if (fs::exists(earlier_))
      throw InputError(fmt::format(
          "'{}' holds files of '{}' that a run set aside and did not put back (it was killed?): "
          "move what you want to keep back into '{}', then remove '{}'",
          earlier_.string(), dir.string(), dir.string(), earlier_.string()));
  }
  if (!opts.append) check_output_dir(dir, opts.overwrite, opts.case_file);
  if (!keep) {
    if (!opts.append) create_output_dir(dir);
    return;
  }
  std::vector<fs::path> moved;
  try {
    fs::create_directories(earlier_);
    if (opts.append) {
      // Hard links: the run replaces files by renaming, so each link keeps the earlier bytes.
      for (const auto& rel : files_under(dir)) {
        const fs::path src = dir / rel, dst = earlier_ / rel;
        fs::create_directories(dst.parent_path());
        std::error_code ec;
        if (fs::is_symlink(src))
          fs::copy_symlink(src, dst);
        else if (fs::create_hard_link(src, dst, ec); ec)
          fs::copy_file(src, dst);
      }
    } else {
      for (const auto& e : fs::directory_iterator(dir)) {
        fs::rename(e.path(), earlier_ / e.path().filename());
        moved.push_back(e.path().filename());
      }
    }
  } catch (...) {
    // Not started: put back what was moved, drop the links.
    std::error_code ec;
    for (const auto& name : moved) fs::rename(earlier_ / name, dir / name, ec);
    fs::remove_all(earlier_, ec);
    throw;
  }
}

void OutputFolder::commit() {
  committed_ = true;
  if (earlier_.empty()) return;
  std::error_code ec;
  fs::remove_all(earlier_, ec);
  if (ec)
    log::warn("could not remove '{}' (the replaced outputs): {}", earlier_.string(), ec.message());
  earlier_.clear();
}

OutputFolder::~OutputFolder() {
  if (!committed_ && !earlier_.empty()) restore();
}

void OutputFolder::restore() noexcept {
  try {
    // What the failed run wrote or replaced: every file that is not one of the earlier files
    // (the same file as its link in earlier_).
    std::time_t now = std::time(nullptr);
    std::tm tm{};
    localtime_r(&now, &tm);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
    const fs::path d = normal(dir_);
    const fs::path failed =
        d.parent_path() / fmt::format("{}.failed-{}", d.filename().string(), stamp);
    std::size_t n_failed = 0;
    for (const auto& rel : files_under(dir_)) {
      const fs::path f = dir_ / rel, e = earlier_ / rel;
      std::error_code ec;
      if (fs::exists(e) && fs::equivalent(f, e, ec)) continue;
      move_file(f, failed / rel);
      ++n_failed;
    }
    for (const auto& rel : files_under(earlier_)) {
      const fs::path to = dir_ / rel;
      fs::create_directories(to.parent_path());
      std::error_code ec;
      if (fs::exists(to) && fs::equivalent(earlier_ / rel, to, ec)) continue;
      fs::rename(earlier_ / rel, to);
    }
    // Folders the failed run made, now empty.
    std::vector<fs::path> dirs;
    for (const auto& e : fs::recursive_directory_iterator(dir_))
      if (e.is_directory() && !e.is_symlink()) dirs.push_back(e.path());
    for (auto it = dirs.rbegin(); it != dirs.rend(); ++it) {
      std::error_code ec;
      if (!fs::exists(earlier_ / fs::relative(*it, dir_)) && fs::is_empty(*it, ec))
        fs::remove(*it, ec);
    }
    fs::remove_all(earlier_);
    if (n_failed > 0)
      log::warn("the run failed: '{}' is as it was before it; the {} file{} it wrote are in '{}'",
                dir_.string(), n_failed, n_failed == 1 ? "" : "s", failed.string());
    else
      log::warn("the run failed: '{}' is as it was before it", dir_.string());
  } catch (const std::exception& e) {
    log::warn(
        "the run failed, and putting back the earlier files of '{}' failed too ({}): they are "
        "in '{}'",
        dir_.string(), e.what(), earlier_.string());
  }
}

}  // namespace gf
