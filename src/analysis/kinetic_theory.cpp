// SPDX-License-Identifier: GPL-3.0-or-later
// Lun et al. (1984) simple-shear predictions and the Carnahan-Starling g0 (see the header).
#include "analysis/kinetic_theory.hpp"

#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace gf::analysis {

double carnahan_starling_g0(double phi) {
  REQUIRE(phi >= 0 && phi < 1, "carnahan_starling_g0: volume fraction {} not in [0, 1)", phi);
  const double q = 1 - phi;
  return (1 - 0.5 * phi) / (q * q * q);
}

double enskog_collision_frequency(double phi, double temperature, double diameter) {
  REQUIRE(temperature >= 0 && diameter > 0,
          "enskog_collision_frequency: temperature {} m^2/s^2 or diameter {} m out of range",
          temperature, diameter);
  return 24 * phi * carnahan_starling_g0(phi) / diameter *
         std::sqrt(temperature / std::numbers::pi);
}

ShearFlowPrediction lun_simple_shear(double phi, double restitution, double diameter,
                                     double density, double shear_rate) {
  using std::numbers::pi;
  REQUIRE(phi > 0 && phi < 1, "lun_simple_shear: volume fraction {} not in (0, 1)", phi);
  REQUIRE(restitution >= 0 && restitution < 1,
          "lun_simple_shear: restitution {} not in [0, 1) (e = 1 has no steady temperature)",
          restitution);
  REQUIRE(diameter > 0 && std::isfinite(diameter), "lun_simple_shear: diameter {} m not > 0",
          diameter);
  REQUIRE(density > 0 && std::isfinite(density), "lun_simple_shear: density {} kg/m^3 not > 0",
          density);
  REQUIRE(std::isfinite(shear_rate), "lun_simple_shear: shear rate {} 1/s not finite", shear_rate);

  const double a = 0.5 * (1 + restitution);
  const double g0 = carnahan_starling_g0(phi);
  const double kinetic = (1 + 1.6 * a * (3 * a - 2) * phi * g0) / (a * (2 - a) * g0);
  const double f_c = (1 + 1.6 * a * phi * g0) * kinetic;
  const double f_s = 768.0 / (25.0 * pi) * a * phi * phi * g0;
  const double f = f_c + f_s;
  // T = t1 gamma_dot^2 from mu* F gamma_dot^2 = (48/sqrt(pi)) a (1-a) rho phi^2 g0 T^1.5 / d.
  const double t1 = 5.0 * pi / 4608.0 * f * diameter * diameter / (a * (1 - a) * phi * phi * g0);
  // mu* = (5/96) rho d sqrt(pi T) = m1 |gamma_dot|
  const double m1 = 5.0 / 96.0 * density * diameter * std::sqrt(pi * t1);
  const double collisional_p = 4 * a * phi * g0;

  ShearFlowPrediction r;
  r.temperature = t1 * shear_rate * shear_rate;
  r.pressure_streaming = density * phi * r.temperature;
  r.pressure_collisional = r.pressure_streaming * collisional_p;
  r.pressure = r.pressure_streaming * (1 + collisional_p);
  const double mu_star = m1 * std::abs(shear_rate);
  r.viscosity = mu_star * f;
  r.shear_stress = -r.viscosity * shear_rate;
  r.shear_stress_streaming = -mu_star * kinetic * shear_rate;
  r.shear_stress_collisional = r.shear_stress - r.shear_stress_streaming;
  // |s_xz| / P with gamma_dot = 1 (the rate cancels; defined also for gamma_dot = 0)
  r.friction = m1 * f / (density * phi * t1 * (1 + collisional_p));
  return r;
}

double volume_equivalent_diameter(double volume) {
  REQUIRE(volume >= 0, "volume_equivalent_diameter: volume {} m^3 < 0", volume);
  return std::cbrt(6.0 * volume / std::numbers::pi);
}

}  // namespace gf::analysis
