// SPDX-License-Identifier: GPL-3.0-or-later
// The `analysis.rheology` output of a run: samples (analysis/rheology.hpp) written to
// rheology.csv, and at the end steady-state averages with standard errors next to the kinetic
// theory of Lun et al. (1984) for volume-equivalent spheres, in rheology_summary.csv.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/rheology.hpp"
#include "io/csv/csv.hpp"

namespace gf {

class Simulation;

/// Steady-state mean of one quantity, its standard error and the kinetic-theory value (NaN when
/// the theory has none).
struct RheologySummaryRow {
  std::string quantity;
  double mean = 0, std_error = 0, kinetic_theory = 0;
};

struct RheologySummary {
  double steady_start = 0;  ///< s, first sample of the average
  std::size_t samples = 0;  ///< samples averaged
  /// Largest |drift| of T, P and sigma_xz over the window, in standard errors (signed; see
  /// analysis::drift_in_standard_errors; NaN for fewer than 4 samples); beyond 3 the window is
  /// likely not steady.
  double drift = 0;
  std::vector<RheologySummaryRow> rows;
  const RheologySummaryRow* find(const std::string& q) const;
};

/// Reads a rheology_summary.csv: quantity -> {mean, std_error, kinetic_theory} (NaN where a
/// field does not parse).
std::map<std::string, std::array<double, 3>> read_rheology_summary(
    const std::filesystem::path& file);

class RheologyOutput {
 public:
  /// Opens dir/rheology.csv for the case's analysis.rheology block. With `continue_at` [s]
  /// (run --append), the samples already in the file up to that time are kept and count in the
  /// steady-state averages as if this run had taken them.
  RheologyOutput(const std::filesystem::path& dir, const Simulation& sim,
                 std::optional<double> continue_at = std::nullopt);

  /// Whether the step `step` ends on a sample (the force stage then collects the virial).
  bool due(std::int64_t step) const { return every_ > 0 && step % every_ == 0; }
  /// Takes a sample of the state after a step whose forces collected the virial.
  void sample(const Simulation& sim);
  /// Pushes the samples taken so far to rheology.csv (throws IoError when the write failed).
  void flush() { csv_->flush(); }
  /// Steady-state averages of the samples so far (also written to rheology_summary.csv).
  RheologySummary finish(const Simulation& sim);

  const std::vector<double>& times() const { return times_; }
  /// The sampled values of column k of analysis::rheology_columns(), then wall_sigma_xz,
  /// wall_sigma_zz (the shear walls' tractions; NaN without them).
  const std::vector<double>& column(std::size_t k) const { return values_[k]; }

 private:
  /// Replaces the steady rows of the fabric (F_.., fabric_angle) by means over the contacts of
  /// the samples from `start` on.
  void contact_weighted_fabric(std::size_t start, std::vector<RheologySummaryRow>& rows) const;

  std::filesystem::path dir_;
  std::int64_t every_ = 0;
  std::unique_ptr<io::SeriesCsv> csv_;
  std::vector<double> times_;
  std::vector<std::vector<double>> values_;
};

}  // namespace gf
