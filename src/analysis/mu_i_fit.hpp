// SPDX-License-Identifier: GPL-3.0-or-later
// Least-squares fit of the mu(I) friction law of dense granular flows to measured (I, mu) points
// (one per steady shear run, e.g. of a `grainflow sweep`).
//
// Law: Jop, Forterre & Pouliquen (2006), Nature 441:727, eqs. (2)-(3) (after GDR MiDi 2004,
// Eur. Phys. J. E 14:341):
//   mu(I) = mu_s + (mu_2 - mu_s) / (1 + I0 / I),   I = |gamma_dot| d / sqrt(P / rho_s),
// d the grains' diameter [m], rho_s their material density [kg/m^3], P the pressure [Pa],
// gamma_dot the shear rate [1/s]; mu_s, mu_2 and I0 are dimensionless.
//
// Fit: minimises S = sum_k (mu(I_k) - mu_k)^2, unweighted. With x_k = I_k / (I_k + I0) the law is
// linear in (mu_s, mu_2 - mu_s) for a given I0, so S(I0) is minimised exactly by linear least
// squares on a log grid of I0 over [I_min / 100, 100 I_max] (200 points per decade); the best
// grid point is refined by golden-section search on log I0 between its neighbours (a profile
// likelihood: no starting guess, no external optimiser). Standard errors of the parameters come
// from the linearised covariance s^2 (J^T J)^-1, s^2 = S / (n - 3) (J the Jacobian of mu(I_k)
// with respect to (mu_s, mu_2, I0)); they need n > 3.
// Unweighted because the per-run errors (blocking standard errors of one run each) are themselves
// uncertain by tens of percent and in measured sweeps smaller than the scatter of the points about
// the law, which is systematic and common to all points; weights 1/err^2 would then mostly follow
// the noise of the error estimates. The errors enter the reduced chi^2 only, as a diagnostic.
#pragma once

#include <cstddef>
#include <limits>
#include <span>
#include <string>

namespace gf::analysis {

/// Inertial number I = |shear_rate| d / sqrt(P / rho_s) [1] for shear rate [1/s], grain diameter
/// d [m], pressure P [Pa] and material density rho_s [kg/m^3]; NaN unless P, d and rho_s are
/// > 0 and every value is finite.
double inertial_number(double shear_rate, double diameter, double pressure, double density);

/// mu(I) = mu_s + (mu_2 - mu_s) / (1 + I0 / I) [1], for I >= 0 (mu(0) = mu_s).
double mu_i_friction(double inertial_number, double mu_s, double mu_2, double i0);

/// One measured point.
struct MuIPoint {
  double inertial_number = 0;                                      ///< I [1]
  double friction = 0;                                             ///< mu [1]
  double friction_err = std::numeric_limits<double>::quiet_NaN();  ///< standard error of mu [1]
};

enum class MuIFitStatus {
  Fitted,        ///< a physical fit: mu_2 > mu_s >= 0, I0 inside the search range
  TooFewPoints,  ///< fewer than 3 usable points, or fewer than 3 distinct I: nothing fitted
  Unphysical,    ///< the least-squares optimum is no friction law (see reason); not to be used
};

struct MuIFit {
  MuIFitStatus status = MuIFitStatus::TooFewPoints;
  bool ok() const { return status == MuIFitStatus::Fitted; }
  /// Why there is no fit or why it was rejected; for a fit, an empty string or a caveat (three
  /// points only, scatter beyond the errors).
  std::string note;
  std::size_t points = 0;    ///< usable points (finite I > 0 and finite mu)
  std::size_t distinct = 0;  ///< distinct I among them (1 % apart)
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  /// The least-squares optimum [1] (also for Unphysical, then not a friction law); NaN for
  /// TooFewPoints.
  double mu_s = nan, mu_2 = nan, i0 = nan;
  /// Standard errors of mu_s, mu_2, I0 [1] (linearised; NaN for 3 points).
  double mu_s_err = nan, mu_2_err = nan, i0_err = nan;
  double rms = nan;  ///< sqrt(S / n), root-mean-square residual in mu [1]
  /// sum (residual / err)^2 / (n - 3) [1]; NaN for n = 3 or when an error is missing or <= 0.
  double reduced_chi2 = nan;
  double i_min = nan, i_max = nan;     ///< range of I of the usable points [1]
  double i0_low = nan, i0_high = nan;  ///< search range of I0 [1]
};

/// Fits mu(I) to `points` (see above). Points with a non-finite or non-positive I or a
/// non-finite mu are left out (counted in neither `points` nor the fit).
MuIFit fit_mu_i(std::span<const MuIPoint> points);

}  // namespace gf::analysis
