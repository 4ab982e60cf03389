// SPDX-License-Identifier: GPL-3.0-or-later
// `grainflow sweep`: runs every combination of a case's sweep lists (volume fractions x shear
// rates) as separate processes of this program, several at a time, then gathers their
// rheology summaries into one table (sweep.csv), fits the mu(I) friction law to its runs
// (mu_i_fit.txt; analysis/mu_i_fit.hpp) and draws the rheology plots from it
// (scripts/plot_sweep.py, Python with matplotlib).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "analysis/mu_i_fit.hpp"
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

/// One finished run of a sweep, as the mu(I) fit uses it (steady means of rheology_summary.csv).
struct SweepRunResult {
  std::string name;
  double shear_rate = 0;    ///< 1/s, measured
  double pressure = 0;      ///< Pa
  double friction = 0;      ///< |sigma_xz| / P
  double friction_err = 0;  ///< standard error of the friction
};

/// Fits mu(I) (analysis::fit_mu_i) to the runs, with I = |shear_rate| d / sqrt(P / rho_s), d the
/// volume-equivalent diameter (2D: area-equivalent) of the largest grain of the case's first
/// particle group and rho_s its material's density; writes dir/mu_i_fit.txt (the points, the
/// fit or why there is none, and a continuum `rheology:` block) and logs the fit. Returns it.
analysis::MuIFit write_mu_i_fit(const config::Case& c, const std::vector<SweepRunResult>& runs,
                                const std::filesystem::path& dir);

/// Runs the sweep (after check_sweep_points); returns 0 when every run succeeded, 1 otherwise
/// (the table then holds the runs that did).
int run_sweep(const std::filesystem::path& case_file, const config::Case& c,
              const SweepOptions& opts);

}  // namespace gf
