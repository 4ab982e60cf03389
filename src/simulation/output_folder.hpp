// SPDX-License-Identifier: GPL-3.0-or-later
// The output folder of a run: what an earlier run wrote there survives a run that fails.
#pragma once

#include <fmt/format.h>

#include <filesystem>

#include "core/error.hpp"

namespace gf {

struct RunOptions;

/// Creates an output folder; a non-empty one is refused (InputError) unless `overwrite`, and
/// then only if it is a grainflow output folder (it holds one of the files every run writes,
/// itself or in a sub-folder: a sweep's) that does not hold `case_file`. Its contents are
/// removed. For the sweep runner, whose runs each keep their own folder safe (OutputFolder).
void prepare_output_dir(const std::filesystem::path& dir, bool overwrite,
                        const std::filesystem::path& case_file = {});

/// The output folder of one run, prepared as prepare_output_dir does (with --append: used as it
/// is), but keeping the earlier contents until commit(): with --overwrite they are moved aside
/// into a hidden sibling folder `.<name>.grainflow-earlier`, with --append every file is
/// hard-linked there (a copy where links are refused). All writers replace files by renaming
/// (write_atomically) or write new ones, so these links keep the earlier bytes. commit() (the
/// run ended, also when stopped by a signal or --max-hours) drops them. Destroyed without
/// commit (the run failed: an exception is on its way out), it moves every file the run wrote
/// or replaced into a sibling folder `<name>.failed-<date>-<time>` for inspection, puts the
/// earlier files back and logs both. A run that is killed (SIGKILL, power loss) leaves the
/// hidden folder behind; the next run into that folder then refuses to start and says where
/// the earlier files are.
class OutputFolder {
 public:
  OutputFolder(const std::filesystem::path& dir, const RunOptions& opts);
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  ~OutputFolder();

  void commit();
  const std::filesystem::path& path() const { return dir_; }

 private:
  void restore() noexcept;

  std::filesystem::path dir_;
  std::filesystem::path earlier_;  ///< empty: nothing to keep (a new or empty folder)
  bool committed_ = false;
};

/// `load(file)` for --restart: a file that cannot be read (IoError: missing, truncated, damaged)
/// is the user's bad input, InputError (exit status 2), naming the option.
template <class Load>
auto load_restart(const std::filesystem::path& file, Load&& load) {
  try {
    return load(file);
  } catch (const IoError& e) {
    throw InputError(fmt::format("--restart {}: {}", file.string(), e.what()));
  }
}

}  // namespace gf
