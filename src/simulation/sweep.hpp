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

/// The --set overrides that make run `p` of the sweep out of the case: the case's own
/// (`overrides`), then the point's shear rate and volume fraction.
std::vector<input::Override> point_overrides(const config::Case& c, const SweepPoint& p,
                                             const std::vector<input::Override>& overrides);

/// Reads and validates the case of every run of the sweep, so that a value that only one
/// combination makes invalid (an output interval in strain below a time step at the highest
/// rate, a fill that cannot hold the volume fraction) stops the sweep before it starts, with the
/// run's name in the message. Throws InputError; returns the warnings, each naming its run.
std::vector<std::string> check_sweep_points(const std::filesystem::path& case_file,
                                            const config::Case& c,
                                            const std::vector<input::Override>& overrides);

/// Runs the sweep (after check_sweep_points); returns 0 when every run succeeded, 1 otherwise
/// (the table then holds the runs that did).
int run_sweep(const std::filesystem::path& case_file, const config::Case& c,
              const SweepOptions& opts);

}  // namespace gf
