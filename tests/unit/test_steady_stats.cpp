// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of the steady-state statistics: MSER-5 truncation and blocking standard errors.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "analysis/steady_stats.hpp"

using namespace gf::analysis;

// Tolerances: with a fixed seed the tests are deterministic; the bands below were chosen from the
// spread of the same estimators over thousands of seeds (numpy prototype of these algorithms), so
// that a change of the standard library's normal_distribution cannot make them fail, while a
// factor-2 error in a standard error or a truncation counted in batches instead of samples would.

TEST(SteadyStats, WhiteNoise) {
  std::mt19937_64 rng(20240611);
  std::normal_distribution<double> normal(0.0, 1.0);
  const std::size_t n = 4096;
  std::vector<double> x(n);
  for (double& v : x) v = normal(rng);
  const double expected = 1.0 / std::sqrt(static_cast<double>(n));
  // Level 0 alone (min_blocks = n): the naive SE; its relative scatter is 1/sqrt(2 (n - 1)) = 1.1%,
  // so 5% is more than 4 standard deviations.
  const BlockAverage naive = block_average(x, n);
  EXPECT_EQ(naive.block_size, 1u);
  EXPECT_EQ(naive.blocks, n);
  EXPECT_NEAR(naive.std_error / expected, 1.0, 0.05);
  // Blocking levels down to 16 blocks: each SE estimate has relative scatter
  // ~1/sqrt(2 (blocks - 1)), 18% at 16 blocks, and the maximum over the 9 levels is biased up
  // (mean 1.09/sqrt(n) over 4000 seeds; 8% of seeds above +25%, 0.35% above +50%). It is never
  // below the level-0 value, so the band is [-10%, +60%].
  const BlockAverage b = block_average(x);
  EXPECT_EQ(b.samples, n);
  EXPECT_GE(b.std_error, naive.std_error);
  EXPECT_GT(b.std_error / expected, 0.9);
  EXPECT_LT(b.std_error / expected, 1.6);
  EXPECT_GE(b.blocks, 16u);
  EXPECT_EQ(b.blocks * b.block_size, n);
  EXPECT_NEAR(b.mean, 0.0, 4 * expected);
}

TEST(SteadyStats, CorrelatedSeries) {
  // AR(1) x_k = a x_{k-1} + e_k, e ~ N(0, 1), started in its stationary distribution:
  // sigma_x = 1/sqrt(1 - a^2), SE of the mean = sigma_x sqrt((1 + a)/(1 - a)) / sqrt(n).
  const double a = 0.9;
  const std::size_t n = std::size_t{1} << 15;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> x(n);
  const double sigma_x = 1.0 / std::sqrt(1 - a * a);
  x[0] = sigma_x * normal(rng);
  for (std::size_t k = 1; k < n; ++k) x[k] = a * x[k - 1] + normal(rng);
  const double expected = sigma_x * std::sqrt((1 + a) / (1 - a)) / std::sqrt(double(n));
  // Over 1000 seeds the blocking estimate / expected ranged 0.86 - 1.72 (mean 1.08; 5% above 1.3,
  // 0.1% above 1.6): band [0.8, 1.6].
  const BlockAverage b = block_average(x);
  EXPECT_GT(b.std_error / expected, 0.8);
  EXPECT_LT(b.std_error / expected, 1.6);
  EXPECT_GT(b.block_size, 8u);  // beyond the correlation time 1/(1 - a) = 10 samples
  // The naive SE is sqrt((1 - a)/(1 + a)) = 0.23 of the true one: blocking must matter.
  const BlockAverage naive = block_average(x, n);
  EXPECT_LT(naive.std_error / expected, 0.3);
  EXPECT_LT(naive.std_error, 0.5 * b.std_error);
}

TEST(SteadyStats, TransientIsTruncated) {
  // x_k = 10 exp(-k/200) + N(0, 1). Over 4000 seeds MSER-5 cut at 460 - 875 samples; the residual
  // bias of the transient left after the cut is a fraction of an SE, but together with the noise
  // |mean| / SE exceeded 3 for 1.5% and 4 for 0.1% of the seeds: band 4 SE. Without the
  // truncation the bias is 2000/4000 = 0.5, about 30 SE.
  std::mt19937_64 rng(12345);
  std::normal_distribution<double> normal(0.0, 1.0);
  const std::size_t n = 4000;
  std::vector<double> x(n);
  for (std::size_t k = 0; k < n; ++k) x[k] = 10 * std::exp(-double(k) / 200) + normal(rng);
  const std::size_t t = mser_truncation(x);
  EXPECT_GE(t, 400u);
  EXPECT_LE(t, 2000u);
  EXPECT_EQ(t % 5, 0u);
  const SteadyAverage s = steady_average(x);
  EXPECT_EQ(s.start, t);
  EXPECT_EQ(s.avg.samples, n - t);
  EXPECT_LT(std::abs(s.avg.mean), 4 * s.avg.std_error);
  const SteadyAverage all = steady_average(x, 0);
  EXPECT_GT(all.avg.mean, 0.3);
  // a second, stationary series does not move the common window
  std::vector<double> y(n);
  for (double& v : y) v = normal(rng);
  EXPECT_EQ(common_truncation({x, y}), std::max(t, mser_truncation(y)));
  EXPECT_EQ(common_truncation({}), 0u);
}

TEST(SteadyStats, ConstantAndShortSeries) {
  const std::vector<double> c(1000, 0.1);
  EXPECT_EQ(mser_truncation(c), 0u);
  const SteadyAverage s = steady_average(c);
  EXPECT_EQ(s.start, 0u);
  EXPECT_EQ(s.avg.mean, 0.1);
  EXPECT_EQ(s.avg.std_error, 0.0);

  const std::vector<double> one{3.0};
  EXPECT_EQ(mser_truncation(one), 0u);
  const BlockAverage b1 = block_average(one);
  EXPECT_EQ(b1.mean, 3.0);
  EXPECT_TRUE(std::isnan(b1.std_error));
  EXPECT_TRUE(std::isnan(block_average(std::vector<double>{}).std_error));
  EXPECT_EQ(mser_truncation(std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8, 9}), 0u);  // < 2 batches

  // two samples: SE = |x1 - x0| / 2
  const BlockAverage b2 = block_average(std::vector<double>{1.0, 2.0});
  EXPECT_DOUBLE_EQ(b2.mean, 1.5);
  EXPECT_DOUBLE_EQ(b2.std_error, 0.5);
}

// MSER always returns a window; the drift check says whether it is steady. A series still
// decaying at its end (x_k = exp(-k/100) + 0.01 N(0,1), 400 samples, window = MSER's) drifts by
// many standard errors; stationary AR(1) noise (a = 0.9, 4000 samples) stays within 3: the same
// estimator on 2000 such series (numpy, other seeds) exceeded 3 for 0.25 % of them and never 4,
// so the seed below is not a lucky one.
TEST(SteadyStats, DriftSeparatesTransientsFromSteadyNoise) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> decay(400);
  for (std::size_t k = 0; k < decay.size(); ++k)
    decay[k] = std::exp(-double(k) / 100) + 0.01 * normal(rng);
  const std::size_t t = mser_truncation(decay);
  const double z = drift_in_standard_errors(std::span<const double>(decay).subspan(t));
  EXPECT_LT(z, -3.0);                                // falling: the second half's mean is lower
  EXPECT_DOUBLE_EQ(steady_average(decay).drift, z);  // the window's drift, from its own average

  std::vector<double> ar(4000);
  double v = 0;
  for (double& e : ar) e = v = 0.9 * v + normal(rng);
  EXPECT_LT(std::abs(drift_in_standard_errors(ar)), 3.0);

  EXPECT_EQ(drift_in_standard_errors(std::vector<double>(10, 2.5)), 0.0);
  EXPECT_TRUE(std::isnan(drift_in_standard_errors(std::vector<double>{1, 2, 3})));
}

// Per-contact averages from per-sample means: sample i holds k_i contacts (Poisson, mean 2, so
// a seventh of the samples has none) with independent values of mean 0.3 and spread 0.1; x_i is
// their mean, w_i = k_i. The weighted estimate is then exactly the mean over all contacts, and
// its standard error that of N independent values, 0.1 / sqrt(N) (level 0 of the linearised
// series, min_blocks = n: relative scatter ~1/sqrt(2n) = 1.6 % plus the spread of k, so 10 %).
// The plain mean of the x_i would count the empty samples' 0 and be 14 % low.
TEST(SteadyStats, WeightedAverageIsThePerContactMean) {
  std::mt19937_64 rng(77);
  std::poisson_distribution<int> count(2.0);
  std::normal_distribution<double> value(0.3, 0.1);
  const std::size_t n = 2048;
  std::vector<double> x(n), w(n);
  double sum = 0, contacts = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const int k = count(rng);
    double s = 0;
    for (int c = 0; c < k; ++c) s += value(rng);
    x[i] = k > 0 ? s / k : 0.0;
    w[i] = k;
    sum += s;
    contacts += k;
  }
  const BlockAverage a = weighted_block_average(x, w, n);
  EXPECT_NEAR(a.mean, sum / contacts, 1e-14);
  EXPECT_NEAR(a.std_error / (0.1 / std::sqrt(contacts)), 1.0, 0.1);
  EXPECT_EQ(a.samples, n);
  EXPECT_LT(block_average(x).mean, 0.27);

  // Samples with a non-finite value or weight are left out (rows of an older build's series);
  // weights that sum to zero give NaN, not 0/0 noise.
  const std::vector<double> xs{1, 2, 3, NAN, 4}, ws{1, 0, 3, 5, NAN};
  const BlockAverage b = weighted_block_average(xs, ws);
  EXPECT_DOUBLE_EQ(b.mean, 2.5);
  EXPECT_EQ(b.samples, 3u);
  const BlockAverage none = weighted_block_average(xs, std::vector<double>(5, 0.0));
  EXPECT_TRUE(std::isnan(none.mean));
  EXPECT_TRUE(std::isnan(none.std_error));
}
