// SPDX-License-Identifier: GPL-3.0-or-later
// Steady-state averages of a sampled time series: MSER-5 truncation and blocking standard errors.
//
// - MSER-5 (White 1997, Simulation 69:323; Franklin & White 2008): the series is cut into batch
//   means b_0 .. b_{m-1} of `batch` consecutive samples (an incomplete last batch is dropped); the
//   truncation d (in batches, 0 <= d <= min(m/2, m-2)) minimises
//       MSER(d) = sum_{k >= d} (b_k - mean_{k >= d} b)^2 / (m - d)^2,
//   the smallest d on ties; the start of the steady window is d * batch samples.
// - Blocking (Flyvbjerg & Petersen 1989, J. Chem. Phys. 91:461): the naive standard error of the
//   mean, sqrt(sum (x - mean)^2 / (n (n - 1))), is computed on the series and on its successive
//   pairwise averages (an odd last value is dropped) while at least `min_blocks` blocks remain;
//   the largest estimate over the levels is reported (conservative plateau value).
// - Drift check: MSER finds the best start but never says "not steady" (a series that still
//   decays at the end gets a window anyway). The window's drift is the difference of the means
//   of its second and first halves in units of their standard error, 2 SE of the window's mean
//   (each half has about twice the window's variance of the mean); more than 3 says the run is
//   likely too short for a steady average.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

namespace gf::analysis {

/// MSER truncation of `x`, in samples (a multiple of `batch`); 0 for fewer than 2 batches.
std::size_t mser_truncation(std::span<const double> x, std::size_t batch = 5);

/// The largest MSER truncation of several series of equal sampling, so that they share one
/// steady window; 0 for none.
std::size_t common_truncation(const std::vector<std::span<const double>>& series,
                              std::size_t batch = 5);

struct BlockAverage {
  double mean = 0;             ///< mean of all samples (NaN for none); unit of the series
  double std_error = 0;        ///< standard error of the mean (NaN for fewer than 2 samples)
  std::size_t samples = 0;     ///< samples averaged
  std::size_t blocks = 0;      ///< blocks at the level that gave std_error
  std::size_t block_size = 1;  ///< samples per block at that level (a power of 2)
};

/// Mean and blocking standard error of `x`; levels with at least `min_blocks` blocks are used
/// (level 0, the samples themselves, always).
BlockAverage block_average(std::span<const double> x, std::size_t min_blocks = 16);

/// Ratio estimate sum w x / sum w (e.g. a per-contact mean from per-sample means x over w
/// contacts) over the samples where both are finite, with the blocking standard error of the
/// linearised series (w / mean w)(x - estimate) (the delta method for a ratio of means).
/// NaN mean and error where the weights sum to zero; `samples` counts the samples used.
BlockAverage weighted_block_average(std::span<const double> x, std::span<const double> w,
                                    std::size_t min_blocks = 16);

struct SteadyAverage {
  BlockAverage avg;       ///< over x[start..]
  std::size_t start = 0;  ///< first sample of the steady window
  double drift = 0;       ///< drift_in_standard_errors of the window (from avg's std_error)
};

/// (mean of the second half of x - mean of its first half) / (2 block_average(x).std_error):
/// the drift over x in standard errors; 0 for a constant series, NaN for fewer than 4 samples.
double drift_in_standard_errors(std::span<const double> x);

/// Block average over x[start..], with `start` given or else mser_truncation(x).
SteadyAverage steady_average(std::span<const double> x, std::optional<std::size_t> start = {});

}  // namespace gf::analysis
