// SPDX-License-Identifier: GPL-3.0-or-later
// MSER-5 truncation and Flyvbjerg-Petersen blocking (see the header).
#include "analysis/steady_stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace gf::analysis {

std::size_t mser_truncation(std::span<const double> x, std::size_t batch) {
  REQUIRE(batch > 0, "mser_truncation: batch size must be > 0");
  const std::size_t m = x.size() / batch;
  if (m < 2) return 0;
  // Batch means, shifted by the first one: a constant series gives exact zeros (MSER = 0 for all
  // d, so d = 0) and the sums lose no digits to a large offset.
  std::vector<double> b(m);
  for (std::size_t k = 0; k < m; ++k) {
    double s = 0;
    for (std::size_t j = 0; j < batch; ++j) s += x[k * batch + j];
    b[k] = s / static_cast<double>(batch);
  }
  const double shift = b[0];
  for (double& v : b) v -= shift;
  // Sum of squared deviations of each tail b[d..] by Welford's update run from the end (stable,
  // O(m) for all d).
  std::vector<double> tail_ss(m, 0.0);
  double mean = 0, ss = 0;
  for (std::size_t k = m; k-- > 0;) {
    const double count = static_cast<double>(m - k);
    const double delta = b[k] - mean;
    mean += delta / count;
    ss += delta * (b[k] - mean);
    tail_ss[k] = ss;
  }
  std::size_t best_d = 0;
  double best = std::numeric_limits<double>::infinity();
  const std::size_t last = std::min(m / 2, m - 2);  // a tail of one batch has MSER = 0
  for (std::size_t d = 0; d <= last; ++d) {
    const double n = static_cast<double>(m - d);
    const double stat = tail_ss[d] / (n * n);
    if (stat < best) {
      best = stat;
      best_d = d;
    }
  }
  return best_d * batch;
}

std::size_t common_truncation(const std::vector<std::span<const double>>& series,
                              std::size_t batch) {
  std::size_t t = 0;
  for (const auto& s : series) t = std::max(t, mser_truncation(s, batch));
  return t;
}

BlockAverage block_average(std::span<const double> x, std::size_t min_blocks) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  BlockAverage r;
  r.samples = x.size();
  r.blocks = x.size();
  r.block_size = 1;
  if (x.empty()) {
    r.mean = r.std_error = nan;
    return r;
  }
  // Work on x - x[0]: exact zeros for a constant series, no cancellation against an offset.
  const double shift = x[0];
  std::vector<double> y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) y[i] = x[i] - shift;
  auto mean_of = [](const std::vector<double>& v) {
    double s = 0;
    for (double e : v) s += e;
    return s / static_cast<double>(v.size());
  };
  r.mean = shift + mean_of(y);
  if (x.size() < 2) {
    r.std_error = nan;
    return r;
  }
  r.std_error = -1;
  std::size_t size = 1;
  while (true) {
    const std::size_t n = y.size();
    const double mu = mean_of(y);
    double ss = 0;
    for (double e : y) ss += (e - mu) * (e - mu);
    const double se = std::sqrt(ss / (static_cast<double>(n) * static_cast<double>(n - 1)));
    if (se > r.std_error) {
      r.std_error = se;
      r.blocks = n;
      r.block_size = size;
    }
    const std::size_t half = n / 2;
    if (half < 2 || half < min_blocks) break;
    for (std::size_t i = 0; i < half; ++i) y[i] = 0.5 * (y[2 * i] + y[2 * i + 1]);
    y.resize(half);
    size *= 2;
  }
  return r;
}

BlockAverage weighted_block_average(std::span<const double> x, std::span<const double> w,
                                    std::size_t min_blocks) {
  REQUIRE(x.size() == w.size(), "weighted_block_average: {} values, {} weights", x.size(),
          w.size());
  std::vector<double> xs, ws;
  double sw = 0, swx = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(w[i])) continue;
    xs.push_back(x[i]);
    ws.push_back(w[i]);
    sw += w[i];
    swx += w[i] * x[i];
  }
  if (!(sw != 0)) {
    BlockAverage r = block_average({});
    r.samples = xs.size();
    return r;
  }
  const double mean = swx / sw;
  const double w_mean = sw / static_cast<double>(ws.size());
  std::vector<double> lin(xs.size());
  for (std::size_t i = 0; i < xs.size(); ++i) lin[i] = ws[i] / w_mean * (xs[i] - mean);
  BlockAverage r = block_average(lin, min_blocks);
  r.mean = mean;
  return r;
}

namespace {

/// (mean of the second half of x - mean of its first half) / (2 se), se the standard error of
/// x's mean; NaN for fewer than 4 samples, 0 for se = 0 (a constant series).
double halves_drift(std::span<const double> x, double se) {
  if (x.size() < 4) return std::numeric_limits<double>::quiet_NaN();
  if (!(se > 0)) return 0.0;
  const std::size_t h = x.size() / 2;
  double diff = 0;  // sum of (late - early) pairs: no offset to cancel, one pass
  for (std::size_t i = 0; i < h; ++i) diff += x[x.size() - h + i] - x[i];
  return diff / static_cast<double>(h) / (2 * se);
}

}  // namespace

double drift_in_standard_errors(std::span<const double> x) {
  return halves_drift(x, block_average(x).std_error);
}

SteadyAverage steady_average(std::span<const double> x, std::optional<std::size_t> start) {
  SteadyAverage r;
  r.start = start ? *start : mser_truncation(x);
  REQUIRE(r.start <= x.size(), "steady_average: start {} beyond the {} samples", r.start, x.size());
  r.avg = block_average(x.subspan(r.start));
  r.drift = halves_drift(x.subspan(r.start), r.avg.std_error);
  return r;
}

}  // namespace gf::analysis
