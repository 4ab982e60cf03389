// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of the mu(I) fit (Jop, Forterre & Pouliquen 2006) and of mu_i_fit.txt of a sweep.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "analysis/mu_i_fit.hpp"
#include "core/files.hpp"
#include "io/input/parse_case.hpp"
#include "simulation/sweep.hpp"
#include "temp_dir.hpp"

using namespace gf;
using namespace gf::analysis;

namespace {

constexpr double kMuS = 0.38, kMu2 = 0.64, kI0 = 0.28;

/// n points of the law at I log-spaced over [0.01, 1], plus `noise` x u, u uniform in [-1, 1]
/// from a fixed mt19937 (its raw output is specified by the standard: the same on every
/// platform, unlike std::uniform_real_distribution's).
std::vector<MuIPoint> synthetic(int n, double noise) {
  std::mt19937 gen(12345);
  std::vector<MuIPoint> p;
  for (int k = 0; k < n; ++k) {
    const double i = 0.01 * std::pow(100.0, k / static_cast<double>(n - 1));
    const double u = 2.0 * (static_cast<double>(gen()) / 4294967295.0) - 1.0;
    p.push_back({i, mu_i_friction(i, kMuS, kMu2, kI0) + noise * u, noise > 0 ? noise : 0.003});
  }
  return p;
}

/// docs/validation/continuum_mu_i_calibration.csv: run, volume_fraction, shear_rate, pressure,
/// inertial_number, friction, friction_err (the Lees-Edwards sweep of
/// cases/rheology/mu_i_calibration, glass spheres d = 3 mm, rho_s = 2500 kg/m^3).
struct CalibrationRow {
  const char* run;
  double phi, rate, pressure, i, mu, mu_err;
};
constexpr CalibrationRow kCalibration[] = {
    {"phi_0.45_rate_20", 0.449771, 19.7649, 7.84728, 1.05834, 0.728919, 0.00472853},
    {"phi_0.5_rate_20", 0.500037, 19.8559, 23.6499, 0.612443, 0.67264, 0.00368845},
    {"phi_0.53_rate_20", 0.529882, 20.0566, 72.3936, 0.353589, 0.603281, 0.0028741},
    {"phi_0.55_rate_20", 0.549779, 20.2091, 234.541, 0.197938, 0.536641, 0.00260965},
    {"phi_0.57_rate_20", 0.570199, 20.5737, 3174.83, 0.0547701, 0.456784, 0.00305949},
    {"phi_0.58_rate_20", 0.580147, 20.0713, 12206.6, 0.0272503, 0.447083, 0.00267954},
};

}  // namespace

TEST(MuIFit, InertialNumberAndLaw) {
  // I = |rate| d / sqrt(P / rho): 20 x 0.003 / sqrt(250 / 2500) = 0.06 / 0.316... = 0.18974
  EXPECT_NEAR(inertial_number(-20, 0.003, 250, 2500), 0.06 / std::sqrt(0.1), 1e-15);
  EXPECT_TRUE(std::isnan(inertial_number(20, 0.003, 0, 2500)));
  EXPECT_TRUE(std::isnan(inertial_number(20, 0.003, -1, 2500)));
  EXPECT_TRUE(std::isnan(inertial_number(20, 0.003, NAN, 2500)));
  EXPECT_DOUBLE_EQ(mu_i_friction(0, kMuS, kMu2, kI0), kMuS);
  EXPECT_DOUBLE_EQ(mu_i_friction(kI0, kMuS, kMu2, kI0), 0.5 * (kMuS + kMu2));
  // The row of the calibration table agrees with its I (d = 3 mm, rho_s = 2500 kg/m^3).
  for (const auto& r : kCalibration)
    EXPECT_NEAR(inertial_number(r.rate, 0.003, r.pressure, 2500), r.i, 1e-5 * r.i) << r.run;
}

TEST(MuIFit, RecoversExactLaw) {
  const auto p = synthetic(21, 0.0);
  const auto f = fit_mu_i(p);
  ASSERT_TRUE(f.ok()) << f.note;
  EXPECT_NEAR(f.mu_s, kMuS, 1e-6);
  EXPECT_NEAR(f.mu_2, kMu2, 1e-6);
  EXPECT_NEAR(f.i0, kI0, 1e-6);
  EXPECT_LT(f.rms, 1e-9);
  EXPECT_EQ(f.points, 21u);
  EXPECT_EQ(f.distinct, 21u);
  EXPECT_DOUBLE_EQ(f.i_min, 0.01);
  EXPECT_NEAR(f.i_max, 1.0, 1e-15);
  // Exact data have chi^2 = 0: no caveat.
  EXPECT_TRUE(f.note.empty()) << f.note;
}

TEST(MuIFit, RecoversNoisyLawWithinItsErrors) {
  // Uniform noise of +-0.003 has a standard deviation of 0.003 / sqrt(3) = 0.0017. The fit must
  // land within 3 of its own (linearised) standard errors of the true law, those errors must be
  // small enough to mean something, and the rms residual must be that of the noise less the 3
  // fitted degrees of freedom: sqrt((n - 3) / n) 0.0017 = 0.0016 for n = 21, within +-30 % (its
  // sampling spread for 18 degrees of freedom is about 1 / sqrt(2 x 18) = 17 %).
  const auto p = synthetic(21, 0.003);
  const auto f = fit_mu_i(p);
  ASSERT_TRUE(f.ok()) << f.note;
  EXPECT_NEAR(f.mu_s, kMuS, 3 * f.mu_s_err);
  EXPECT_NEAR(f.mu_2, kMu2, 3 * f.mu_2_err);
  EXPECT_NEAR(f.i0, kI0, 3 * f.i0_err);
  EXPECT_LT(f.mu_s_err, 0.005);
  EXPECT_LT(f.mu_2_err, 0.02);
  EXPECT_LT(f.i0_err, 0.05);
  const double sd = 0.003 / std::sqrt(3.0) * std::sqrt(18.0 / 21.0);
  EXPECT_NEAR(f.rms, sd, 0.3 * sd);
  // errors given as the noise's half-width (0.003 > its sd): chi^2 / dof about 1/3, no caveat
  EXPECT_LT(f.reduced_chi2, 1.0);
  EXPECT_TRUE(f.note.empty()) << f.note;
}

TEST(MuIFit, CalibrationDataMatchThePythonFit) {
  // scripts/plot_dem_vs_continuum.py (unweighted, a grid of step 0.001 in mu_s and of 400 points
  // over 4 decades of I0): mu_s 0.4200, mu_2 0.9087, I0 0.5983, rms 0.004437 -- within its grid
  // steps (1e-3 in mu_s, 2.3 % in I0, mu_2 following), not exactly.
  std::vector<MuIPoint> p;
  for (const auto& r : kCalibration) p.push_back({r.i, r.mu, r.mu_err});
  const auto f = fit_mu_i(p);
  ASSERT_TRUE(f.ok()) << f.note;
  EXPECT_NEAR(f.mu_s, 0.4200, 1e-3);
  EXPECT_NEAR(f.mu_2, 0.9087, 3e-3);
  EXPECT_NEAR(f.i0, 0.5983, 0.015);
  EXPECT_NEAR(f.rms, 0.00444, 1e-4);
  EXPECT_LE(f.rms, 0.0044366);  // the Python grid's optimum
  EXPECT_EQ(f.points, 6u);
  EXPECT_NEAR(f.i_min, 0.0272503, 1e-9);
  EXPECT_NEAR(f.i_max, 1.05834, 1e-9);
  // The least-squares optimum: no other (mu_s, mu_2, I0) nearby does better.
  auto ssr = [&](double ms, double m2, double i0) {
    double s = 0;
    for (const auto& q : p)
      s += std::pow(mu_i_friction(q.inertial_number, ms, m2, i0) - q.friction, 2);
    return s;
  };
  const double s0 = ssr(f.mu_s, f.mu_2, f.i0);
  EXPECT_NEAR(std::sqrt(s0 / 6), f.rms, 1e-12);
  for (double h : {1e-4, -1e-4}) {
    EXPECT_GT(ssr(f.mu_s + h, f.mu_2, f.i0), s0);
    EXPECT_GT(ssr(f.mu_s, f.mu_2 + h, f.i0), s0);
    EXPECT_GT(ssr(f.mu_s, f.mu_2, f.i0 * (1 + h)), s0);
  }
}

TEST(MuIFit, TooFewPointsGiveNoFit) {
  std::vector<MuIPoint> p{{0.1, 0.45, 0.003}, {0.3, 0.5, 0.003}};
  auto f = fit_mu_i(p);
  EXPECT_EQ(f.status, MuIFitStatus::TooFewPoints);
  EXPECT_NE(f.note.find("2 usable points"), std::string::npos) << f.note;
  EXPECT_TRUE(std::isnan(f.mu_s));
  // A third point without pressure (I = NaN) or friction does not count.
  p.push_back({NAN, 0.6, 0.003});
  p.push_back({0.5, NAN, 0.003});
  p.push_back({0.0, 0.4, 0.003});
  f = fit_mu_i(p);
  EXPECT_EQ(f.status, MuIFitStatus::TooFewPoints);
  EXPECT_EQ(f.points, 2u);
  EXPECT_TRUE(fit_mu_i({}).note.find("0 usable points") != std::string::npos);
  // Shear rates at one volume fraction: (nearly) one I, however many runs.
  const std::vector<MuIPoint> same_i{
      {0.2, 0.5, 0.003}, {0.201, 0.51, 0.003}, {0.1995, 0.49, 0.003}, {0.35, 0.55, 0.003}};
  f = fit_mu_i(same_i);
  EXPECT_EQ(f.status, MuIFitStatus::TooFewPoints);
  EXPECT_EQ(f.distinct, 2u);
  EXPECT_NE(f.note.find("distinct inertial number"), std::string::npos) << f.note;
}

TEST(MuIFit, ThreePointsPassThroughWithACaveat) {
  std::vector<MuIPoint> p;
  for (double i : {0.02, 0.2, 1.0}) p.push_back({i, mu_i_friction(i, kMuS, kMu2, kI0), 0.003});
  const auto f = fit_mu_i(p);
  ASSERT_TRUE(f.ok()) << f.note;
  EXPECT_NEAR(f.mu_s, kMuS, 1e-6);
  EXPECT_NEAR(f.mu_2, kMu2, 1e-6);
  EXPECT_NEAR(f.i0, kI0, 1e-6);
  EXPECT_TRUE(std::isnan(f.mu_s_err));
  EXPECT_TRUE(std::isnan(f.reduced_chi2));
  EXPECT_NE(f.note.find("3 points for 3 parameters"), std::string::npos) << f.note;
}

TEST(MuIFit, UnphysicalDataAreRejected) {
  // Friction falling with I (e.g. a sweep in the wrong regime): mu_2 < mu_s.
  std::vector<MuIPoint> falling;
  for (double i : {0.02, 0.05, 0.1, 0.2, 0.5, 1.0})
    falling.push_back({i, mu_i_friction(i, 0.6, 0.4, 0.2), 0.003});
  auto f = fit_mu_i(falling);
  EXPECT_EQ(f.status, MuIFitStatus::Unphysical);
  EXPECT_FALSE(f.ok());
  EXPECT_NE(f.note.find("does not rise"), std::string::npos) << f.note;
  // Friction linear in I over the range: no saturation, I0 runs to the upper end.
  std::vector<MuIPoint> linear;
  for (double i : {0.01, 0.02, 0.05, 0.1, 0.2}) linear.push_back({i, 0.4 + 0.5 * i, 0.003});
  f = fit_mu_i(linear);
  EXPECT_EQ(f.status, MuIFitStatus::Unphysical);
  EXPECT_NE(f.note.find("upper end"), std::string::npos) << f.note;
  // Already saturated: a step below the smallest I, I0 runs to the lower end.
  std::vector<MuIPoint> saturated;
  for (double i : {0.1, 0.2, 0.5, 1.0})
    saturated.push_back({i, mu_i_friction(i, 0.3, 0.6, 1e-6), 0.003});
  f = fit_mu_i(saturated);
  EXPECT_EQ(f.status, MuIFitStatus::Unphysical);
  EXPECT_NE(f.note.find("lower end"), std::string::npos) << f.note;
  // Non-monotone: up, then down again.
  const std::vector<MuIPoint> hump{{0.01, 0.40, 0.003},
                                   {0.03, 0.50, 0.003},
                                   {0.1, 0.60, 0.003},
                                   {0.3, 0.50, 0.003},
                                   {1.0, 0.40, 0.003}};
  f = fit_mu_i(hump);
  EXPECT_FALSE(f.ok() && f.note.empty()) << "a hump passes as a clean friction law";
}

TEST(MuIFit, SweepWritesTheFitFile) {
  // The six runs of the calibration sweep through the sweep's writer, with the case's grains.
  const auto c = input::load_case(
      std::filesystem::path(GF_SOURCE_DIR) / "cases/rheology/mu_i_calibration/case.yaml", {});
  std::vector<SweepRunResult> runs;
  for (const auto& r : kCalibration) runs.push_back({r.run, r.rate, r.pressure, r.mu, r.mu_err});
  test::TempDir tmp;
  const auto f = write_mu_i_fit(c, runs, tmp.path());
  ASSERT_TRUE(f.ok()) << f.note;
  const std::string text = read_text_file(tmp / "mu_i_fit.txt");
  EXPECT_NE(text.find("status: fitted"), std::string::npos) << text;
  EXPECT_NE(text.find("rheology: {model: mu_i, mu_s: 0.420"), std::string::npos) << text;
  EXPECT_NE(text.find("grain_diameter: 0.003, grain_density: 2500, max_viscosity: 1.0e4}"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("I_range: [0.02725, 1.058]"), std::string::npos) << text;
  EXPECT_NE(text.find("phi_0.58_rate_20"), std::string::npos) << text;

  // Two runs: the file says why there is no fit, and has no rheology block.
  runs.resize(2);
  const auto g = write_mu_i_fit(c, runs, tmp.path());
  EXPECT_EQ(g.status, MuIFitStatus::TooFewPoints);
  const std::string none = read_text_file(tmp / "mu_i_fit.txt");
  EXPECT_NE(none.find("status: no fit"), std::string::npos) << none;
  EXPECT_NE(none.find("reason: 2 usable points"), std::string::npos) << none;
  EXPECT_EQ(none.find("rheology:"), std::string::npos) << none;
}

TEST(MuIFit, SweepEndToEnd) {
  // A tiny sweep of three runs (a few hundred steps of ~1000 grains each, about a second):
  // mu_i_fit.txt is written next to sweep.csv, with a fit or the reason for none (such short runs
  // are far from steady, so either may come out).
  test::TempDir tmp;
  const auto out = tmp / "sweep";
  const std::string cmd = std::string(GF_BINARY) + " sweep " + GF_SOURCE_DIR +
                          "/cases/rheology/mu_i_calibration/case.yaml --steps 200 -j 2 "
                          "--no-plots -o " +
                          out.string() +
                          " --set 'sweep.volume_fraction=[0.45, 0.5, 0.55]' --set "
                          "analysis.rheology.every_strain=0.0004 > " +
                          (tmp / "sweep.log").string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << read_text_file(tmp / "sweep.log");
  ASSERT_TRUE(std::filesystem::exists(out / "sweep.csv"));
  ASSERT_TRUE(std::filesystem::exists(out / "mu_i_fit.txt")) << read_text_file(tmp / "sweep.log");
  const std::string text = read_text_file(out / "mu_i_fit.txt");
  EXPECT_NE(text.find("status: "), std::string::npos) << text;
  for (const char* run : {"phi_0.45_rate_20", "phi_0.5_rate_20", "phi_0.55_rate_20"})
    EXPECT_NE(text.find(run), std::string::npos) << text;
  if (text.find("status: fitted") != std::string::npos)
    EXPECT_NE(text.find("rheology: {model: mu_i"), std::string::npos) << text;
  else
    EXPECT_NE(text.find("reason: "), std::string::npos) << text;
}
