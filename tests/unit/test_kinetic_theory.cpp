// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of the Lun et al. (1984) simple-shear predictions and the Carnahan-Starling g0.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "analysis/kinetic_theory.hpp"
#include "core/error.hpp"

using namespace gf;
using namespace gf::analysis;
using std::numbers::pi;

namespace {

/// Haff dissipation rate per volume, (48 / sqrt(pi)) alpha (1 - alpha) rho phi^2 g0 T^1.5 / d.
double haff_dissipation(double phi, double e, double d, double rho, double t) {
  const double a = 0.5 * (1 + e);
  return 48.0 / std::sqrt(pi) * a * (1 - a) * rho * phi * phi * carnahan_starling_g0(phi) *
         std::pow(t, 1.5) / d;
}

}  // namespace

TEST(KineticTheory, CarnahanStarlingG0) {
  EXPECT_EQ(carnahan_starling_g0(0.0), 1.0);
  EXPECT_EQ(carnahan_starling_g0(0.5), 6.0);  // 0.75 / 0.125
  EXPECT_THROW(carnahan_starling_g0(1.0), Error);
  EXPECT_THROW(carnahan_starling_g0(-0.1), Error);
}

TEST(KineticTheory, RejectsElasticAndBadInput) {
  EXPECT_THROW(lun_simple_shear(0.3, 1.0, 1e-3, 2500, 10), Error);  // no steady T for e = 1
  EXPECT_THROW(lun_simple_shear(0.0, 0.9, 1e-3, 2500, 10), Error);
  EXPECT_THROW(lun_simple_shear(0.3, 0.9, 0.0, 2500, 10), Error);
  EXPECT_THROW(lun_simple_shear(0.3, 0.9, 1e-3, -1, 10), Error);
}

TEST(KineticTheory, DiluteLimitIsChapmanEnskogViscosity) {
  const double d = 2e-3, rho = 2500, rate = 50;
  const ShearFlowPrediction p = lun_simple_shear(1e-6, 1 - 1e-6, d, rho, rate);
  const double mu_star = 5.0 / 96.0 * rho * d * std::sqrt(pi * p.temperature);
  EXPECT_NEAR(p.viscosity / mu_star, 1.0, 1e-4);
  // ... which is (5/16) m sqrt(T/pi) / d^2 for a grain of mass m
  const double m = rho * pi * d * d * d / 6;
  EXPECT_NEAR(mu_star / (5.0 / 16.0 * m * std::sqrt(p.temperature / pi) / (d * d)), 1.0, 1e-14);
  // streaming stresses dominate
  EXPECT_NEAR(p.shear_stress_streaming / p.shear_stress, 1.0, 1e-4);
  EXPECT_NEAR(p.pressure_streaming / p.pressure, 1.0, 1e-4);
}

TEST(KineticTheory, ViscousHeatingBalancesDissipation) {
  const double d = 5.3e-3, rho = 1395, rate = 37;
  for (double phi : {0.01, 0.1, 0.3, 0.45}) {
    for (double e : {0.0, 0.5, 0.7, 0.95, 0.999}) {
      const ShearFlowPrediction p = lun_simple_shear(phi, e, d, rho, rate);
      const double heating = p.viscosity * rate * rate;
      const double loss = haff_dissipation(phi, e, d, rho, p.temperature);
      EXPECT_NEAR(heating / loss, 1.0, 1e-12) << "phi " << phi << " e " << e;
      EXPECT_NEAR(-p.shear_stress / rate, p.viscosity, 1e-14 * p.viscosity);
      EXPECT_NEAR(p.friction, std::abs(p.shear_stress) / p.pressure, 1e-14 * p.friction);
      EXPECT_LT(p.shear_stress, 0.0);
      EXPECT_GT(p.pressure, 0.0);
    }
  }
}

TEST(KineticTheory, BagnoldScaling) {
  const ShearFlowPrediction a = lun_simple_shear(0.35, 0.8, 1e-3, 2500, 10);
  for (double k : {0.1, 3.0, 250.0}) {
    const ShearFlowPrediction b = lun_simple_shear(0.35, 0.8, 1e-3, 2500, 10 * k);
    EXPECT_NEAR(b.temperature / (a.temperature * k * k), 1.0, 1e-12);
    EXPECT_NEAR(b.pressure / (a.pressure * k * k), 1.0, 1e-12);
    EXPECT_NEAR(b.shear_stress / (a.shear_stress * k * k), 1.0, 1e-12);
    EXPECT_NEAR(b.viscosity / (a.viscosity * k), 1.0, 1e-12);
    EXPECT_NEAR(b.friction / a.friction, 1.0, 1e-12);
  }
  // reversed shear: same T and P, shear stress changes sign
  const ShearFlowPrediction r = lun_simple_shear(0.35, 0.8, 1e-3, 2500, -10);
  EXPECT_DOUBLE_EQ(r.temperature, a.temperature);
  EXPECT_DOUBLE_EQ(r.shear_stress, -a.shear_stress);
  EXPECT_DOUBLE_EQ(r.viscosity, a.viscosity);
  // no shear: a state at rest, with the rate-independent friction
  const ShearFlowPrediction z = lun_simple_shear(0.35, 0.8, 1e-3, 2500, 0);
  EXPECT_EQ(z.temperature, 0.0);
  EXPECT_EQ(z.pressure, 0.0);
  EXPECT_EQ(z.shear_stress, 0.0);
  EXPECT_DOUBLE_EQ(z.friction, a.friction);
}

TEST(KineticTheory, StreamingAndCollisionalParts) {
  for (double phi : {0.05, 0.2, 0.4}) {
    for (double e : {0.6, 0.9}) {
      const ShearFlowPrediction p = lun_simple_shear(phi, e, 1e-3, 2500, 20);
      const double a = 0.5 * (1 + e), g0 = carnahan_starling_g0(phi);
      EXPECT_NEAR((p.pressure_streaming + p.pressure_collisional) / p.pressure, 1.0, 1e-14);
      EXPECT_NEAR((p.shear_stress_streaming + p.shear_stress_collisional) / p.shear_stress, 1.0,
                  1e-14);
      const double c = 4 * a * phi * g0;
      EXPECT_NEAR(p.pressure_collisional / p.pressure, c / (1 + c), 1e-14);
      EXPECT_LT(p.shear_stress_collisional, 0.0);
    }
  }
}

TEST(KineticTheory, ReferenceValue) {
  // phi = 0.1, e = 0.7, d = 5.3 mm, rho = 1395 kg/m^3, gamma_dot = 100 1/s, written out again.
  const double phi = 0.1, e = 0.7, d = 5.3e-3, rho = 1395, gd = 100;
  const double a = (1 + e) / 2;
  const double g0 = (1 - phi / 2) / ((1 - phi) * (1 - phi) * (1 - phi));
  const double kin = (1 + 8.0 / 5.0 * a * (3 * a - 2) * phi * g0) / (a * (2 - a) * g0);
  const double fc = (1 + 8.0 / 5.0 * a * phi * g0) * kin;
  const double fs = 768.0 / (25.0 * pi) * a * phi * phi * g0;
  const double f = fc + fs;
  const double t = 5 * pi / 4608 * f * d * d * gd * gd / (a * (1 - a) * phi * phi * g0);
  const double mu_star = 5.0 / 96.0 * rho * d * std::sqrt(pi * t);
  const double pressure = rho * phi * t * (1 + 4 * a * phi * g0);
  const double shear = -mu_star * f * gd;

  const ShearFlowPrediction p = lun_simple_shear(phi, e, d, rho, gd);
  EXPECT_NEAR(p.temperature / t, 1.0, 1e-13);
  EXPECT_NEAR(p.pressure / pressure, 1.0, 1e-13);
  EXPECT_NEAR(p.shear_stress / shear, 1.0, 1e-13);
  EXPECT_NEAR(p.shear_stress_streaming / (-mu_star * kin * gd), 1.0, 1e-13);
  EXPECT_NEAR(p.pressure_streaming / (rho * phi * t), 1.0, 1e-13);
  // Independent values computed by hand with Python, 8 significant digits, checked to half a unit
  // of the last digit (g0 = 1.303155007, F = 1.12256012):
  // T = 0.64693775 m^2/s^2, P = 130.23416 Pa, s_xz = -61.626094 Pa, mu = 0.47319454.
  EXPECT_NEAR(p.temperature, 0.64693775, 5e-9);
  EXPECT_NEAR(p.pressure, 130.23416, 5e-6);
  EXPECT_NEAR(p.shear_stress, -61.626094, 5e-7);
  EXPECT_NEAR(p.friction, 0.47319454, 5e-9);
}

TEST(KineticTheory, VolumeEquivalentDiameter) {
  const double d = 5.3e-3;
  EXPECT_NEAR(volume_equivalent_diameter(pi * d * d * d / 6) / d, 1.0, 1e-14);
  EXPECT_EQ(volume_equivalent_diameter(0.0), 0.0);
}

// The Enskog collision frequency as the rate of a grain sweeping the cross-section pi d^2 through
// neighbours of number density n = 6 phi / (pi d^3), enhanced by g0, at the Maxwellian mean
// relative speed <|g|> = 4 sqrt(T / pi) (sqrt 2 times the mean speed sqrt(8 T / pi)), written
// here by Monte Carlo over relative velocities: the same to the sampling error (2e5 samples of a
// speed whose relative spread is 0.42: 0.1 %, so 0.5 %).
TEST(KineticTheory, EnskogCollisionFrequency) {
  const double phi = 0.2, T = 0.37, d = 0.004;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, std::sqrt(2 * T));  // relative velocity components
  double sum = 0;
  const int n = 200000;
  for (int k = 0; k < n; ++k) {
    const double a = g(rng), b = g(rng), c = g(rng);
    sum += std::sqrt(a * a + b * b + c * c);
  }
  const double density = 6 * phi / (std::numbers::pi * d * d * d);
  const double expected =
      density * std::numbers::pi * d * d * gf::analysis::carnahan_starling_g0(phi) * (sum / n);
  EXPECT_NEAR(gf::analysis::enskog_collision_frequency(phi, T, d) / expected, 1.0, 0.005);
  EXPECT_THROW(gf::analysis::enskog_collision_frequency(phi, T, 0.0), gf::Error);
}
