// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of the KTGF closures (continuum/ktgf.hpp): g0 hand values, dilute limits, the
// identities between the sets, homogeneous shear against analysis::lun_simple_shear, Haff cooling
// against RK4, the dense-region regime switch and parameter validation. Pure functions: ms.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "analysis/kinetic_theory.hpp"
#include "continuum/ktgf.hpp"
#include "continuum/rheology_registry.hpp"
#include "core/error.hpp"

using namespace gf;
using namespace gf::continuum;
using std::numbers::pi;
using ::testing::HasSubstr;

namespace {

constexpr double kD = 1e-3;      // grain diameter, m
constexpr double kRho = 2500.0;  // glass, kg/m^3

KtgfParams set(std::string_view key, double e, std::string_view radial = "carnahan_starling",
               std::map<std::string, double> extra = {}) {
  extra["restitution"] = e;
  extra["grain_diameter"] = kD;
  extra["grain_density"] = kRho;
  return prepare_ktgf(key, extra, radial);
}

double rel(double got, double want) {
  return std::abs(got - want) / std::abs(want);
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

/// mu* = (5/96) rho d sqrt(pi T) and kappa* = (75/384) rho d sqrt(pi T): Chapman-Enskog.
double mu_star(double theta) {
  return 5.0 / 96.0 * kRho * kD * std::sqrt(pi * theta);
}
double kappa_star(double theta) {
  return 75.0 / 384.0 * kRho * kD * std::sqrt(pi * theta);
}

constexpr const char* kSets[] = {"lun", "syamlal", "gidaspow"};

}  // namespace

// ---- radial distribution ----------------------------------------------------------------------

// Hand numbers: CS(0.3) = 0.85 / 0.7^3 = 0.85 / 0.343; CS(0.5) = 0.75 / 0.125 = 6 exactly.
// Lun-Savage with a_max = 0.64 at a = 0.32: (1/2)^(-1.6) = 2^1.6 = 3.0314331330207964; with
// a_max = 0.6 at a = 0.3: (1/2)^(-1.5) = 2 sqrt(2). Ma-Ahmadi at 0.3: numerator 1 + 0.75 +
// 4.5904 * 0.09 + 4.515439 * 0.027 = 2.285052853, denominator (1 - (0.3/0.64356)^3)^0.678021 with
// 0.3/0.64356 = 0.46615700, cubed 0.10129701: 0.89870299^0.678021 = 0.93014531, g0 = 2.4566622.
// Tolerances: a few ulp for closed forms; 1e-7 for the eight-digit hand values.
TEST(KtgfRadial, HandValues) {
  const auto cs = set("lun", 0.9);
  EXPECT_EQ(radial_distribution(0.0, cs), 1.0);
  EXPECT_NEAR(radial_distribution(0.3, cs), 0.85 / 0.343, 1e-15);
  EXPECT_EQ(radial_distribution(0.5, cs), 6.0);
  const auto ls = set("lun", 0.9, "lun_savage");
  EXPECT_DOUBLE_EQ(ls.packing_limit, 0.64);
  EXPECT_NEAR(radial_distribution(0.32, ls), std::pow(2.0, 1.6), 1e-14);
  EXPECT_NEAR(radial_distribution(0.32, ls), 3.0314331330207964, 1e-14);
  const auto ls6 = set("lun", 0.9, "lun_savage", {{"packing_limit", 0.6}});
  EXPECT_NEAR(radial_distribution(0.3, ls6), 2 * std::sqrt(2.0), 1e-14);
  const auto ma = set("lun", 0.9, "ma_ahmadi");
  EXPECT_DOUBLE_EQ(ma.packing_limit, 0.64356);
  EXPECT_NEAR(radial_distribution(0.3, ma), 2.285052853 / 0.93014531, 1e-7);
  EXPECT_NEAR(radial_distribution(0.3, ma), 2.4566622, 1e-7);
}

// Every g0 has the exact second virial coefficient, g0 = 1 + (5/2) a + O(a^2): the slope at
// h = 1e-6 differs from 2.5 by about 4.5 h (the a^2 term, 4.5 to 4.59 for the three), so 1e-5.
TEST(KtgfRadial, SecondVirialCoefficient) {
  for (const char* r : {"carnahan_starling", "lun_savage", "ma_ahmadi"}) {
    const auto p = set("lun", 0.9, r);
    const double h = 1e-6;
    EXPECT_NEAR((radial_distribution(h, p) - 1) / h, 2.5, 1e-5) << r;
  }
}

// Lun-Savage diverges at a_max as (1 - a/a_max)^(-2.5 a_max): at a = a_max (1 - 1e-6) it is
// 1e-6^(-1.6) = 10^9.6. 1 - a/a_max is then 1e-6 known to ~1e-16 absolute, 1e-10 relative, so
// the power is good to ~2e-10: tolerance 1e-9. At and beyond a_max it is infinite, as is
// Ma-Ahmadi's at 0.64356 (it grows only as (3 (1 - a/a_max))^-0.678: 3.2e4 at 1e-6 below);
// Carnahan-Starling is still finite there (it diverges at a = 1 only).
TEST(KtgfRadial, DivergenceAtThePackingLimit) {
  const auto ls = set("lun", 0.9, "lun_savage");
  EXPECT_LT(rel(radial_distribution(0.64 * (1 - 1e-6), ls), std::pow(10.0, 9.6)), 1e-9);
  EXPECT_TRUE(std::isinf(radial_distribution(0.64, ls)));
  EXPECT_TRUE(std::isinf(radial_distribution(0.7, ls)));
  const auto ma = set("lun", 0.9, "ma_ahmadi");
  EXPECT_GT(radial_distribution(0.64356 * (1 - 1e-6), ma), 1e4);
  EXPECT_TRUE(std::isinf(radial_distribution(0.64356, ma)));
  const auto cs = set("lun", 0.9);
  EXPECT_TRUE(std::isfinite(radial_distribution(0.64356, cs)));
  EXPECT_TRUE(std::isinf(radial_distribution(1.0, cs)));
  // The properties at the divergence stay non-finite instead of silently finite.
  EXPECT_FALSE(std::isfinite(solids_pressure(0.64, 1.0, ls)));
}

// ---- dilute limits ------------------------------------------------------------------------------

// a = 1e-9: every correction to the dilute value is O(a g0) ~ 1e-8 (the largest, 16/5 a in mu_s
// and 24/5 a in kappa_s, are 5e-9), so the limits hold to 1e-7. Elastic grains (e = 1): lun and
// gidaspow give the Chapman-Enskog viscosity mu* = (5/96) rho d sqrt(pi T) and conductivity
// kappa* = (75/384) rho d sqrt(pi T); their pressure is the ideal-gas rho a T. syamlal keeps only
// the dense-gas terms: mu_s and kappa_s ~ a, P_s ~ a^2, no dilute limit (that is the set, not a
// defect to fudge). For e < 1 the sets' dilute limits differ by an e-dependent factor
// (lun: 4 / ((1+e)(3-e)), gidaspow: 2 / (1+e); both 1 at e = 1).
TEST(KtgfDilute, ChapmanEnskogLimit) {
  const double a = 1e-9, theta = 0.04;
  for (const char* k : {"lun", "gidaspow"}) {
    const auto p = set(k, 1.0);
    EXPECT_LT(rel(solids_shear_viscosity(a, theta, p), mu_star(theta)), 1e-7) << k;
    EXPECT_LT(rel(granular_conductivity(a, theta, p), kappa_star(theta)), 1e-7) << k;
    EXPECT_LT(rel(solids_pressure(a, theta, p), kRho * a * theta), 1e-7) << k;
  }
  const auto s = set("syamlal", 1.0);
  EXPECT_LT(solids_shear_viscosity(a, theta, s) / mu_star(theta), 1e-8);
  EXPECT_LT(granular_conductivity(a, theta, s) / kappa_star(theta), 1e-8);
  EXPECT_LT(solids_pressure(a, theta, s) / (kRho * a * theta), 1e-8);

  const double e = 0.8, eta = 0.9;
  const auto lun = set("lun", e), gid = set("gidaspow", e);
  EXPECT_LT(rel(solids_shear_viscosity(a, theta, lun), mu_star(theta) * 4 / ((1 + e) * (3 - e))),
            1e-7);
  EXPECT_LT(
      rel(granular_conductivity(a, theta, lun), kappa_star(theta) * 8 / (eta * (41 - 33 * eta))),
      1e-7);
  EXPECT_LT(rel(solids_shear_viscosity(a, theta, gid), mu_star(theta) * 2 / (1 + e)), 1e-7);
  EXPECT_LT(rel(granular_conductivity(a, theta, gid), kappa_star(theta) * 2 / (1 + e)), 1e-7);
  EXPECT_LT(rel(solids_pressure(a, theta, lun), kRho * a * theta), 1e-7);
  EXPECT_LT(rel(solids_pressure(a, theta, gid), kRho * a * theta), 1e-7);
}

// ---- identities between the sets --------------------------------------------------------------

// The sets are transcribed from different sources; these identities, derived by hand from the
// formulas in the papers, tie them together (any typo in a coefficient breaks one). Exact
// algebra, so only round-off: 1e-13 relative.
//  - e = 1: gidaspow's mu_s and kappa_s equal lun's (both Enskog's first approximation).
//  - syamlal = lun without the purely streaming terms:
//      mu_lun - mu_syamlal       = mu* / (eta (2-eta) g0) (1 + 8/5 eta (3 eta - 2) a g0)
//      kappa_lun - kappa_syamlal = kappa* 8 / (eta (41 - 33 eta)) (1/g0) (1 + 12/5 eta^2
//                                  (4 eta - 3) a g0)
//      P_lun - P_syamlal         = rho a T
//  - bulk viscosity and dissipation are the same in all sets; no dissipation at e = 1.
TEST(KtgfIdentities, GidaspowEqualsLunForElasticGrains) {
  const auto lun = set("lun", 1.0), gid = set("gidaspow", 1.0);
  for (double a : {0.01, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6}) {
    const double theta = 0.3;
    EXPECT_LT(rel(solids_shear_viscosity(a, theta, gid), solids_shear_viscosity(a, theta, lun)),
              1e-13)
        << a;
    EXPECT_LT(rel(granular_conductivity(a, theta, gid), granular_conductivity(a, theta, lun)),
              1e-13)
        << a;
    EXPECT_LT(rel(solids_pressure(a, theta, gid), solids_pressure(a, theta, lun)), 1e-13) << a;
    EXPECT_EQ(collisional_dissipation(a, theta, lun), 0.0);
  }
}

TEST(KtgfIdentities, SyamlalIsLunWithoutStreamingTerms) {
  for (double e : {0.5, 0.8, 0.95, 1.0}) {
    const double eta = 0.5 * (1 + e);
    const auto lun = set("lun", e), sya = set("syamlal", e), gid = set("gidaspow", e);
    for (double a : {0.05, 0.2, 0.35, 0.5}) {
      const double theta = 0.7;
      const double g0 = radial_distribution(a, lun);
      const double mu_stream =
          mu_star(theta) / (eta * (2 - eta) * g0) * (1 + 1.6 * eta * (3 * eta - 2) * a * g0);
      const double kappa_stream = kappa_star(theta) * 8 / (eta * (41 - 33 * eta)) / g0 *
                                  (1 + 2.4 * eta * eta * (4 * eta - 3) * a * g0);
      const double mu_l = solids_shear_viscosity(a, theta, lun);
      const double kappa_l = granular_conductivity(a, theta, lun);
      EXPECT_NEAR(mu_l - solids_shear_viscosity(a, theta, sya), mu_stream, 1e-13 * mu_l) << e << a;
      EXPECT_NEAR(kappa_l - granular_conductivity(a, theta, sya), kappa_stream, 1e-13 * kappa_l)
          << e << a;
      EXPECT_NEAR(solids_pressure(a, theta, lun) - solids_pressure(a, theta, sya), kRho * a * theta,
                  1e-13 * solids_pressure(a, theta, lun));
      // Lun's kinetic (streaming) viscosity is that same term.
      EXPECT_LT(rel(Lun::kinetic_viscosity(a, theta, g0, lun), mu_stream), 1e-14);
      // shared closures
      const double lam = 4.0 / 3.0 * a * a * kRho * kD * g0 * (1 + e) * std::sqrt(theta / pi);
      const double gam =
          12 * (1 - e * e) * g0 * kRho * a * a * std::pow(theta, 1.5) / (kD * std::sqrt(pi));
      for (const auto* p : {&lun, &sya, &gid}) {
        EXPECT_LT(rel(solids_bulk_viscosity(a, theta, *p), lam), 1e-14);
        if (e < 1) {
          EXPECT_LT(rel(collisional_dissipation(a, theta, *p), gam), 1e-14);
        }
      }
    }
  }
}

// The seed's eq 4 (Syamlal's kinetic viscosity) term by term, and ktgf_properties agreeing with
// the single-property functions (one g0 for all).
TEST(KtgfIdentities, SeedEquationFourAndPropertiesBundle) {
  const double e = 0.85, a = 0.4, theta = 0.02;
  const auto sya = set("syamlal", e);
  const double g0 = radial_distribution(a, sya);
  const double eq4 = a * kD * kRho * std::sqrt(theta * pi) / (6 * (3 - e)) *
                     (1 + 2.0 / 5.0 * (1 + e) * (3 * e - 1) * a * g0);
  EXPECT_LT(rel(Syamlal::kinetic_viscosity(a, theta, g0, sya), eq4), 1e-14);
  for (const char* k : kSets) {
    const auto p = set(k, e, "ma_ahmadi");
    const auto all = ktgf_properties(a, theta, p);
    EXPECT_EQ(all.g0, radial_distribution(a, p));
    EXPECT_EQ(all.pressure, solids_pressure(a, theta, p)) << k;
    EXPECT_EQ(all.shear_viscosity, solids_shear_viscosity(a, theta, p)) << k;
    EXPECT_EQ(all.bulk_viscosity, solids_bulk_viscosity(a, theta, p)) << k;
    EXPECT_EQ(all.conductivity, granular_conductivity(a, theta, p)) << k;
    EXPECT_EQ(all.dissipation, collisional_dissipation(a, theta, p)) << k;
    EXPECT_GT(all.kinetic_viscosity, 0.0);
    EXPECT_LT(all.kinetic_viscosity, all.shear_viscosity);
  }
}

// ---- homogeneous simple shear ----------------------------------------------------------------

// The lun set against the independent implementation analysis::lun_simple_shear (Mahajan et al.'s
// form of the same theory: alpha = (1+e)/2 is our eta, phi our a, T our Theta, all per component;
// F = F_c + F_s is mu_s / mu*). The one difference in definitions is the sign convention: the
// analysis stresses are compressive-positive, so its s_xz = -mu gamma_dot < 0 for gamma_dot > 0,
// while ktgf gives the tension-positive sigma_xy = +mu gamma_dot; the pressures are the same. Both
// are closed forms of the same algebra evaluated in a different order: agreement to 1e-12.
TEST(KtgfShear, LunMatchesMahajanForm) {
  for (double e : {0.3, 0.5, 0.7, 0.8, 0.9, 0.95, 0.99}) {
    const auto p = set("lun", e);
    for (double a : {0.02, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6}) {
      for (double rate : {0.5, 30.0, -200.0}) {
        const auto s = ktgf_simple_shear(a, rate, p);
        const auto m = analysis::lun_simple_shear(a, e, kD, kRho, rate);
        const std::string where = fmt::format("e {} a {} rate {}", e, a, rate);
        EXPECT_LT(rel(s.temperature, m.temperature), 1e-12) << where;
        EXPECT_LT(rel(s.pressure, m.pressure), 1e-12) << where;
        EXPECT_LT(rel(s.shear_stress, -m.shear_stress), 1e-12) << where;
        EXPECT_LT(rel(s.viscosity, m.viscosity), 1e-12) << where;
        EXPECT_LT(rel(s.friction, m.friction), 1e-12) << where;
        // the streaming (kinetic) part of the shear stress
        const double g0 = radial_distribution(a, p);
        EXPECT_LT(
            rel(Lun::kinetic_viscosity(a, s.temperature, g0, p) * rate, -m.shear_stress_streaming),
            1e-12)
            << where;
      }
    }
  }
}

// For every set and g0: at the returned state viscous heating equals dissipation (round-off,
// 1e-13: this checks that mu_s ~ sqrt(T) and gamma_s ~ T^1.5 really hold, which the closed form
// assumes), T ~ gamma_dot^2 and stresses ~ gamma_dot^2 (Bagnold), the friction is |tau|/P and
// does not depend on the rate, the shear stress has the sign of the rate.
TEST(KtgfShear, BalanceAndBagnoldScaling) {
  for (const char* k : kSets)
    for (const char* r : {"carnahan_starling", "lun_savage", "ma_ahmadi"})
      for (double e : {0.6, 0.9})
        for (double a : {0.05, 0.3, 0.55}) {
          const auto p = set(k, e, r);
          const std::string where = fmt::format("{} {} e {} a {}", k, r, e, a);
          const double rate = 40.0;
          const auto s = ktgf_simple_shear(a, rate, p);
          const double heating = solids_shear_viscosity(a, s.temperature, p) * rate * rate;
          EXPECT_LT(rel(heating, collisional_dissipation(a, s.temperature, p)), 1e-13) << where;
          const auto s2 = ktgf_simple_shear(a, -2 * rate, p);
          EXPECT_LT(rel(s2.temperature, 4 * s.temperature), 1e-13) << where;
          EXPECT_LT(rel(s2.pressure, 4 * s.pressure), 1e-13) << where;
          EXPECT_LT(rel(s2.shear_stress, -4 * s.shear_stress), 1e-13) << where;
          EXPECT_LT(rel(s.friction, s.shear_stress / s.pressure), 1e-13) << where;
          EXPECT_LT(rel(s2.friction, s.friction), 1e-13) << where;
          EXPECT_GT(s.shear_stress, 0.0);
        }
}

// The table of docs/models/ktgf.md: T / (d gamma_dot)^2, P / (rho d^2 gamma_dot^2),
// tau / (rho d^2 gamma_dot^2) and tau / P at e = 0.7, 0.9, a = 0.1, 0.3, 0.5 (Carnahan-Starling).
// The expected numbers come from a separate transcription of the formulas (Python, printed to 6
// significant digits), so the tolerance is the rounding of 6 digits: 1e-5 relative.
TEST(KtgfShear, TableOfTheSetsInHomogeneousShear) {
  struct Row {
    const char* set;
    double e, a, t, p, tau;
  };
  const Row rows[] = {
      {"lun", 0.7, 0.1, 2.30309, 0.332353, 0.157267},
      {"lun", 0.7, 0.3, 0.377087, 0.399075, 0.178323},
      {"lun", 0.7, 0.5, 0.272304, 1.5249, 0.735952},
      {"lun", 0.9, 0.1, 6.59693, 0.986372, 0.284033},
      {"lun", 0.9, 0.3, 1.21025, 1.38879, 0.38198},
      {"lun", 0.9, 0.5, 0.883386, 5.47699, 1.60205},
      {"syamlal", 0.7, 0.1, 0.535492, 0.0237262, 0.017632},
      {"syamlal", 0.7, 0.3, 0.300081, 0.227554, 0.126591},
      {"syamlal", 0.7, 0.5, 0.262446, 1.33847, 0.696349},
      {"syamlal", 0.9, 0.1, 1.64712, 0.0815653, 0.035436},
      {"syamlal", 0.9, 0.3, 0.95505, 0.809426, 0.267773},
      {"syamlal", 0.9, 0.5, 0.844407, 4.81312, 1.4972},
      {"gidaspow", 0.7, 0.1, 2.78912, 0.40249, 0.209591},
      {"gidaspow", 0.7, 0.3, 0.45239, 0.478768, 0.234322},
      {"gidaspow", 0.7, 0.5, 0.312413, 1.74951, 0.904403},
      {"gidaspow", 0.9, 0.1, 7.05179, 1.05438, 0.31391},
      {"gidaspow", 0.9, 0.3, 1.28678, 1.47661, 0.418777},
      {"gidaspow", 0.9, 0.5, 0.926143, 5.74208, 1.71976},
  };
  const double rate = 100.0, s2 = kD * kD * rate * rate;
  fmt::print("| set | e | a | T/(d gd)^2 | P/(rho d^2 gd^2) | tau/(rho d^2 gd^2) | tau/P |\n");
  for (const auto& r : rows) {
    const auto s = ktgf_simple_shear(r.a, rate, set(r.set, r.e));
    const double t = s.temperature / s2, p = s.pressure / (kRho * s2),
                 tau = s.shear_stress / (kRho * s2);
    fmt::print("| {} | {} | {} | {:.4g} | {:.4g} | {:.4g} | {:.3f} |\n", r.set, r.e, r.a, t, p, tau,
               s.friction);
    const std::string where = fmt::format("{} e {} a {}", r.set, r.e, r.a);
    EXPECT_LT(rel(t, r.t), 1e-5) << where;
    EXPECT_LT(rel(p, r.p), 1e-5) << where;
    EXPECT_LT(rel(tau, r.tau), 1e-5) << where;
  }
}

// ---- homogeneous cooling ----------------------------------------------------------------------

// (3/2) a rho dT/dt = -gamma_s(a, T), integrated by RK4 with the set's own dissipation function
// (not the closed form's constant), step tau/2000, to t = 10 tau (T falls by 121). RK4's global
// error is ~ (h/tau)^4 = 6e-14 relative times a modest constant, so the closed form
// T0 / (1 + t/tau)^2 must agree to 1e-8 (the brief's bound) with room to spare. tau itself is
// checked against d sqrt(pi) / (4 (1 - e^2) g0 a sqrt(T0)) (round-off).
TEST(KtgfHaff, ClosedFormMatchesRk4) {
  for (const char* k : kSets)
    for (const char* r : {"carnahan_starling", "lun_savage"}) {
      const auto p = set(k, 0.8, r);
      const double a = 0.3, t0 = 1e-2;
      const double tau = haff_time(a, t0, p);
      const double g0 = radial_distribution(a, p);
      EXPECT_LT(rel(tau, kD * std::sqrt(pi) / (4 * (1 - 0.64) * g0 * a * std::sqrt(t0))), 1e-14);
      auto rhs = [&](double th) { return -collisional_dissipation(a, th, p) / (1.5 * a * kRho); };
      const int n = 20000;
      const double h = 10 * tau / n;
      double th = t0, worst = 0;
      for (int i = 1; i <= n; ++i) {
        const double k1 = rhs(th), k2 = rhs(th + 0.5 * h * k1), k3 = rhs(th + 0.5 * h * k2),
                     k4 = rhs(th + h * k3);
        th += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
        worst = std::max(worst, rel(th, haff_temperature(a, t0, i * h, p)));
      }
      EXPECT_LT(worst, 1e-8) << k << " " << r;
      EXPECT_LT(rel(haff_temperature(a, t0, 10 * tau, p), t0 / 121), 1e-14);
    }
}

// ---- dense regions ------------------------------------------------------------------------------

// The seed's switch: at a <= a_fric (0.55) the KTGF viscosity alone; above it the mu(I)
// rheology's apparent viscosity min(mu(I) P / gamma_dot, eta_max), computed here by hand from
// Jop et al.'s law (mu_s 0.382, mu_2 0.643, I0 0.279 for glass beads). Exact equality with
// MuI::eval (the same code path), 1e-14 against the hand formula.
TEST(KtgfRegime, MuISwitchBelowAndAboveTheFrictionalLimit) {
  const auto k = set("syamlal", 0.9);
  const auto sw = prepare_frictional("mu_i_switch");
  EXPECT_DOUBLE_EQ(sw.frictional_limit, 0.55);
  const auto rheo = prepare_rheology(
      "mu_i", {{"grain_diameter", kD}, {"grain_density", kRho}, {"max_viscosity", 1e3}});
  const double theta = 1e-3, rate = 20.0, pressure = 400.0;
  for (double a : {0.3, 0.5, 0.55}) {
    const auto v = effective_shear_viscosity(a, theta, rate, pressure, k, sw, rheo);
    EXPECT_EQ(v.regime, FlowRegime::Kinetic) << a;
    EXPECT_EQ(v.viscosity, solids_shear_viscosity(a, theta, k)) << a;
    EXPECT_EQ(v.kinetic_viscosity, v.viscosity);
    EXPECT_EQ(v.frictional_viscosity, 0.0);
  }
  for (double a : {0.56, 0.6}) {
    const auto v = effective_shear_viscosity(a, theta, rate, pressure, k, sw, rheo);
    EXPECT_EQ(v.regime, FlowRegime::Frictional) << a;
    EXPECT_EQ(v.viscosity, MuI::eval(rate, pressure, rheo));
    const double inertial = rate * kD / std::sqrt(pressure / kRho);
    const double mu = 0.382 + (0.643 - 0.382) / (0.279 / inertial + 1);
    EXPECT_LT(rel(v.viscosity, mu * pressure / rate), 1e-14);
    EXPECT_EQ(v.frictional_viscosity, v.viscosity);
    EXPECT_EQ(v.kinetic_viscosity, solids_shear_viscosity(a, theta, k));  // reported anyway
  }
  // At rest under load the rheology's cap applies, not a division by zero.
  EXPECT_EQ(effective_shear_viscosity(0.6, theta, 0.0, pressure, k, sw, rheo).viscosity, 1e3);
  // A lower frictional limit (the seed tried 0.4) moves the switch.
  const auto sw4 = prepare_frictional("mu_i_switch", {{"frictional_limit", 0.4}});
  EXPECT_EQ(effective_shear_viscosity(0.45, theta, rate, pressure, k, sw4, rheo).regime,
            FlowRegime::Frictional);
}

// Schaeffer + Johnson-Jackson (seed eqs 3, 6, 7) with the defaults Fr 0.05 Pa, n 2, p 5,
// a_min 0.5, a_max 0.64, phi 28.5 deg: at a = 0.6, P_f = 0.05 * 0.1^2 / 0.04^5 = 4882.8125 Pa
// (hand), mu_f = P_f sin(28.5 deg) / gamma_dot, added to the KTGF viscosity. Below a_min only
// KTGF; at rest or at a_max the cap (100 Pa s).
TEST(KtgfRegime, SchaefferJohnsonJackson) {
  const auto k = set("lun", 0.9);
  const auto f = prepare_frictional("schaeffer_johnson_jackson");
  const RheologyParams unused;
  const double theta = 1e-3, rate = 50.0;
  EXPECT_NEAR(johnson_jackson_pressure(0.6, f), 4882.8125, 1e-9);
  EXPECT_EQ(johnson_jackson_pressure(0.5, f), 0.0);
  EXPECT_TRUE(std::isinf(johnson_jackson_pressure(0.64, f)));
  const auto below = effective_shear_viscosity(0.45, theta, rate, 0.0, k, f, unused);
  EXPECT_EQ(below.regime, FlowRegime::Kinetic);
  EXPECT_EQ(below.viscosity, solids_shear_viscosity(0.45, theta, k));
  const auto above = effective_shear_viscosity(0.6, theta, rate, 0.0, k, f, unused);
  EXPECT_EQ(above.regime, FlowRegime::Frictional);
  const double mu_f = 4882.8125 * std::sin(28.5 * pi / 180) / rate;
  EXPECT_LT(rel(above.frictional_viscosity, mu_f), 1e-13);
  EXPECT_LT(rel(above.viscosity, solids_shear_viscosity(0.6, theta, k) + mu_f), 1e-13);
  EXPECT_EQ(effective_shear_viscosity(0.6, theta, 0.0, 0.0, k, f, unused).frictional_viscosity,
            100.0);
  EXPECT_EQ(schaeffer_viscosity(johnson_jackson_pressure(0.64, f), rate, f), 100.0);
}

// ---- registry and validation
// ----------------------------------------------------------------------

TEST(KtgfRegistry, ListsAndLookup) {
  std::vector<std::string_view> keys;
  for (const auto& i : ktgf_closure_infos()) {
    keys.push_back(i.key);
    EXPECT_FALSE(i.equation.empty());
    EXPECT_FALSE(i.reference.empty());
    EXPECT_EQ(i.params.size(), 3u);
  }
  EXPECT_EQ(keys, (std::vector<std::string_view>{"lun", "syamlal", "gidaspow"}));
  EXPECT_EQ(radial_distribution_infos().size(), 3u);
  EXPECT_EQ(frictional_model_infos().size(), 2u);
  EXPECT_NE(find_ktgf_closure("gidaspow"), nullptr);
  EXPECT_EQ(find_ktgf_closure("mu_i"), nullptr);
  EXPECT_NE(find_radial_distribution("ma_ahmadi"), nullptr);
  EXPECT_NE(find_frictional_model("mu_i_switch"), nullptr);
  EXPECT_EQ(set("gidaspow", 0.9).model, 2);
  EXPECT_EQ(set("lun", 0.9, "ma_ahmadi").radial, 2);
}

TEST(KtgfParams, ValidationErrors) {
  const std::map<std::string, double> ok{
      {"restitution", 0.9}, {"grain_diameter", kD}, {"grain_density", kRho}};
  auto with = [&](std::string name, double v) {
    auto m = ok;
    m[name] = v;
    return m;
  };
  EXPECT_THAT(error_of([&] { prepare_ktgf("lun84", ok); }),
              HasSubstr("unknown KTGF closure set 'lun84' (known: lun, syamlal, gidaspow)"));
  EXPECT_THAT(error_of([&] { prepare_ktgf("lun", ok, "percus_yevick"); }),
              HasSubstr("unknown radial distribution 'percus_yevick'"));
  EXPECT_THAT(error_of([&] { prepare_ktgf("lun", with("restitutio", 0.9)); }),
              HasSubstr("'lun' with radial distribution 'carnahan_starling' has no parameter "
                        "'restitutio'"));
  EXPECT_THAT(error_of([&] { prepare_ktgf("syamlal", with("restitution", 1.2)); }),
              HasSubstr("restitution = 1.2 is outside [0, 1]"));
  EXPECT_THAT(error_of([&] { prepare_ktgf("gidaspow", with("grain_diameter", 0.0)); }),
              HasSubstr("grain_diameter = 0 is outside (0, 1]"));
  EXPECT_THAT(error_of([&] {
                prepare_ktgf("lun", {{"restitution", 0.9}, {"grain_density", 1}});
              }),
              HasSubstr("needs the parameter 'grain_diameter' [m]"));
  // packing_limit belongs to lun_savage only
  EXPECT_THAT(error_of([&] { prepare_ktgf("lun", with("packing_limit", 0.6)); }),
              HasSubstr("has no parameter 'packing_limit'"));
  EXPECT_THAT(error_of([&] { prepare_ktgf("lun", with("packing_limit", 0.8), "lun_savage"); }),
              HasSubstr("packing_limit = 0.8 is outside (0, 0.7405]"));
  EXPECT_THAT(error_of([&] { prepare_frictional("schaeffer"); }),
              HasSubstr("unknown frictional model 'schaeffer' (known: schaeffer_johnson_jackson, "
                        "mu_i_switch)"));
  EXPECT_THAT(error_of([&] {
                prepare_frictional("schaeffer_johnson_jackson", {{"min_fraction", 0.7}});
              }),
              HasSubstr("min_fraction = 0.7 must be below max_fraction = 0.64"));
  EXPECT_THAT(error_of([&] {
                prepare_frictional("schaeffer_johnson_jackson",
                                   {{"min_fraction", 0.6}, {"max_fraction", 0.6}});
              }),
              HasSubstr("min_fraction = 0.6 must be below max_fraction = 0.6"));
  EXPECT_THAT(error_of([&] {
                prepare_frictional("mu_i_switch", {{"frictional_limit", -0.1}});
              }),
              HasSubstr("frictional_limit = -0.1 is outside (0, 1]"));
  EXPECT_THAT(error_of([&] {
                prepare_frictional("mu_i_switch", {{"friction_angle", 30}});
              }),
              HasSubstr("frictional model 'mu_i_switch' has no parameter 'friction_angle'"));
  // the homogeneous states need dissipation and a state below the packing limit
  const auto elastic = set("lun", 1.0);
  EXPECT_THAT(error_of([&] { ktgf_simple_shear(0.3, 10, elastic); }),
              HasSubstr("restitution 1 not in [0, 1)"));
  EXPECT_THAT(error_of([&] { haff_time(0.3, 1.0, elastic); }), HasSubstr("haff_time"));
  const auto ls = set("lun", 0.9, "lun_savage");
  EXPECT_THAT(error_of([&] { ktgf_simple_shear(0.64, 10, ls); }),
              HasSubstr("volume fraction 0.64 not in (0, 0.64)"));
  EXPECT_THAT(error_of([&] { ktgf_simple_shear(0.3, NAN, ls); }), HasSubstr("not finite"));
  EXPECT_THAT(error_of([&] { haff_time(0.3, 0.0, ls); }), HasSubstr("not > 0"));
  EXPECT_THAT(error_of([&] { haff_temperature(0.3, 1.0, -1.0, ls); }), HasSubstr("time -1 s < 0"));
}
