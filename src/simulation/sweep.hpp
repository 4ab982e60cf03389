// SPDX-License-Identifier: GPL-3.0-or-later
// `grainflow sweep`: runs every combination of a case's sweep lists (volume fractions x shear
// rates) as separate processes of this program, several at a time, then gathers their
// rheology summaries into one table (sweep.csv) and draws the rheology plots from it
// (scripts/plot_sweep.py, Python with matplotlib).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/input/config.hpp"
#include "io/input/parse_case.hpp"

namespace gf {

struct SweepOptions {
  std::filesystem::path output;       ///< empty: the case's output.directory
  std::filesystem::path program;      ///< this executable (children run `program run ...`)
  int processes = 0;                  ///< 0: sweep.processes, else the number of cores
  std::optional<std::int64_t> steps;  ///< passed on to every run (smoke tests)
  bool overwrite = false;
  /// Continue a stopped sweep in its folder: finished runs are kept, stopped or killed ones
  /// continue from their newest checkpoint (run --append), the others start.
  bool resume = false;
  bool plots = true;
  std::vector<input::Override> overrides;  ///< passed on to every run
};

/// One combination of the sweep and its result folder.
struct SweepPoint {
  double volume_fraction = 0;  ///< nominal (the fill's), NaN when the sweep does not vary it
  double shear_rate = 0;       ///< nominal (shear.rate)
  std::string name;            ///< folder under the sweep's output
};

/// The combinations of a case's sweep block, in table order (volume fraction major).
std::vector<SweepPoint> sweep_points(const config::Case& c);

/// Runs the sweep; returns 0 when every run succeeded, 1 otherwise (the table then holds the
/// runs that did).
int run_sweep(const std::filesystem::path& case_file, const config::Case& c,
              const SweepOptions& opts);

}  // namespace gf
