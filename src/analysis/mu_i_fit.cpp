// SPDX-License-Identifier: GPL-3.0-or-later
// mu(I) fit: exact linear least squares for each I0 of a log grid, golden-section refinement.
#include "analysis/mu_i_fit.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

namespace gf::analysis {

namespace {

constexpr std::size_t kMinPoints = 3;
constexpr double kDistinct = 1.01;      // I values closer than 1 % count as one
constexpr double kRangeFactor = 100.0;  // I0 searched over [I_min / 100, 100 I_max]
constexpr double kPerDecade = 200.0;    // grid points of log I0 per decade

/// mu = a + b x with x = I / (I + I0): a = mu_s, b = mu_2 - mu_s, and the sum of squared
/// residuals.
struct LinearFit {
  double a = 0, b = 0, ssr = 0;
};

LinearFit solve_linear(std::span<const MuIPoint> p, double i0) {
  const double n = static_cast<double>(p.size());
  double xm = 0, ym = 0;
  for (const auto& q : p) {
    xm += q.inertial_number / (q.inertial_number + i0);
    ym += q.friction;
  }
  xm /= n;
  ym /= n;
  double sxx = 0, sxy = 0;
  for (const auto& q : p) {
    const double dx = q.inertial_number / (q.inertial_number + i0) - xm;
    sxx += dx * dx;
    sxy += dx * (q.friction - ym);
  }
  LinearFit f;
  f.b = sxx > 0 ? sxy / sxx : 0.0;
  f.a = ym - f.b * xm;
  // The residuals themselves (not Syy - b Sxy), so that S -> 0 stays resolved for exact data.
  for (const auto& q : p) {
    const double r = f.a + f.b * q.inertial_number / (q.inertial_number + i0) - q.friction;
    f.ssr += r * r;
  }
  return f;
}

void append_note(std::string& note, const std::string& more) {
  if (!note.empty()) note += "; ";
  note += more;
}

}  // namespace

double inertial_number(double shear_rate, double diameter, double pressure, double density) {
  if (!(std::isfinite(shear_rate) && std::isfinite(diameter) && std::isfinite(pressure) &&
        std::isfinite(density) && pressure > 0 && diameter > 0 && density > 0))
    return std::numeric_limits<double>::quiet_NaN();
  return std::abs(shear_rate) * diameter / std::sqrt(pressure / density);
}

double mu_i_friction(double inertial_number, double mu_s, double mu_2, double i0) {
  return mu_s + (mu_2 - mu_s) * inertial_number / (inertial_number + i0);
}

MuIFit fit_mu_i(std::span<const MuIPoint> points) {
  MuIFit fit;
  std::vector<MuIPoint> p;
  for (const auto& q : points)
    if (std::isfinite(q.inertial_number) && q.inertial_number > 0 && std::isfinite(q.friction))
      p.push_back(q);
  fit.points = p.size();
  std::vector<double> is;
  for (const auto& q : p) is.push_back(q.inertial_number);
  std::sort(is.begin(), is.end());
  for (std::size_t k = 0; k < is.size(); ++k)
    if (k == 0 || is[k] > kDistinct * is[k - 1]) ++fit.distinct;
  if (!p.empty()) {
    fit.i_min = is.front();
    fit.i_max = is.back();
  }
  if (fit.points < kMinPoints) {
    fit.note = fmt::format(
        "{} usable point{} (finite friction and P > 0): the 3 parameters of mu(I) need at least {}",
        fit.points, fit.points == 1 ? "" : "s", kMinPoints);
    return fit;
  }
  if (fit.distinct < kMinPoints) {
    fit.note = fmt::format(
        "the {} points cover only {} distinct inertial number{} (1 % apart); mu(I) needs at least "
        "{} (in the hard-grain limit I depends on the volume fraction alone: sweep volume "
        "fractions, not only shear rates)",
        fit.points, fit.distinct, fit.distinct == 1 ? "" : "s", kMinPoints);
    return fit;
  }

  // Profile of S over a log grid of I0, then golden section between the best point's neighbours.
  fit.i0_low = fit.i_min / kRangeFactor;
  fit.i0_high = fit.i_max * kRangeFactor;
  const double t_lo = std::log(fit.i0_low), t_hi = std::log(fit.i0_high);
  const auto n_grid =
      static_cast<std::size_t>(std::ceil(kPerDecade * (t_hi - t_lo) / std::log(10.0))) + 1;
  const double dt = (t_hi - t_lo) / static_cast<double>(n_grid - 1);
  std::size_t best = 0;
  double best_ssr = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < n_grid; ++k) {
    const double ssr = solve_linear(p, std::exp(t_lo + dt * static_cast<double>(k))).ssr;
    if (ssr < best_ssr) {
      best_ssr = ssr;
      best = k;
    }
  }
  const bool at_edge = best == 0 || best == n_grid - 1;
  double t_best = t_lo + dt * static_cast<double>(best);
  if (!at_edge) {
    const double g = (std::sqrt(5.0) - 1) / 2;
    double a = t_best - dt, b = t_best + dt;
    double c = b - g * (b - a), d = a + g * (b - a);
    double fc = solve_linear(p, std::exp(c)).ssr, fd = solve_linear(p, std::exp(d)).ssr;
    for (int it = 0; it < 200 && b - a > 1e-13; ++it) {
      if (fc <= fd) {
        b = d;
        d = c;
        fd = fc;
        c = b - g * (b - a);
        fc = solve_linear(p, std::exp(c)).ssr;
      } else {
        a = c;
        c = d;
        fc = fd;
        d = a + g * (b - a);
        fd = solve_linear(p, std::exp(d)).ssr;
      }
    }
    const double t_mid = 0.5 * (a + b);
    if (solve_linear(p, std::exp(t_mid)).ssr <= best_ssr) t_best = t_mid;
  }
  fit.i0 = std::exp(t_best);
  const LinearFit lin = solve_linear(p, fit.i0);
  fit.mu_s = lin.a;
  fit.mu_2 = lin.a + lin.b;
  const double n = static_cast<double>(p.size());
  fit.rms = std::sqrt(lin.ssr / n);

  if (p.size() > kMinPoints) {
    const double dof = n - static_cast<double>(kMinPoints);
    Eigen::MatrixXd jac(p.size(), 3);
    double chi2 = 0;
    bool have_errors = true;
    for (std::size_t k = 0; k < p.size(); ++k) {
      const double i = p[k].inertial_number, x = i / (i + fit.i0);
      jac(k, 0) = 1 - x;                                                       // d mu / d mu_s
      jac(k, 1) = x;                                                           // d mu / d mu_2
      jac(k, 2) = -(fit.mu_2 - fit.mu_s) * i / ((i + fit.i0) * (i + fit.i0));  // d mu / d I0
      const double r = mu_i_friction(i, fit.mu_s, fit.mu_2, fit.i0) - p[k].friction;
      const double e = p[k].friction_err;
      if (std::isfinite(e) && e > 0)
        chi2 += (r / e) * (r / e);
      else
        have_errors = false;
    }
    if (have_errors) fit.reduced_chi2 = chi2 / dof;
    const Eigen::Matrix3d jtj = jac.transpose() * jac;
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(jtj);
    if (lu.isInvertible()) {
      const Eigen::Matrix3d cov = lu.inverse() * (lin.ssr / dof);
      fit.mu_s_err = std::sqrt(std::max(0.0, cov(0, 0)));
      fit.mu_2_err = std::sqrt(std::max(0.0, cov(1, 1)));
      fit.i0_err = std::sqrt(std::max(0.0, cov(2, 2)));
    }
  }

  // A friction law rises with I from mu_s >= 0, and I0 lies inside the range the data can tell.
  if (!(fit.mu_2 > fit.mu_s)) {
    fit.status = MuIFitStatus::Unphysical;
    fit.note = fmt::format(
        "mu_2 = {:.4g} <= mu_s = {:.4g}: the friction does not rise with I over the points, so "
        "they define no mu(I) law",
        fit.mu_2, fit.mu_s);
  } else if (at_edge && best == 0) {
    fit.status = MuIFitStatus::Unphysical;
    fit.note = fmt::format(
        "I0 at the lower end of its search range ({:.3g} = I_min / {:g}): the friction is "
        "already saturated at the smallest I, mu_s and I0 are not determined (add runs at "
        "smaller I, i.e. denser)",
        fit.i0, kRangeFactor);
  } else if (at_edge) {
    fit.status = MuIFitStatus::Unphysical;
    fit.note = fmt::format(
        "I0 at the upper end of its search range ({:.3g} = {:g} I_max): the friction does not "
        "saturate over the points (it rises about linearly in I), mu_2 and I0 are not determined "
        "separately (add runs at larger I, i.e. looser)",
        fit.i0, kRangeFactor);
  } else if (fit.mu_s < 0) {
    fit.status = MuIFitStatus::Unphysical;
    fit.note = fmt::format("mu_s = {:.4g} < 0: no friction law", fit.mu_s);
  } else {
    fit.status = MuIFitStatus::Fitted;
    if (p.size() == kMinPoints)
      append_note(fit.note,
                  "3 points for 3 parameters: the curve passes through them, with no residual "
                  "and no error estimate (add runs)");
    // chi^2 / dof has a standard deviation of about sqrt(2 / dof): 3 of them above 1.
    if (std::isfinite(fit.reduced_chi2)) {
      const double dof = n - static_cast<double>(kMinPoints);
      if (fit.reduced_chi2 > 1 + 3 * std::sqrt(2 / dof))
        append_note(fit.note,
                    fmt::format("the points scatter about the fit by more than their errors "
                                "(reduced chi^2 = {:.3g}): the law describes them only roughly, "
                                "or the runs' errors are underestimated (longer runs)",
                                fit.reduced_chi2));
    }
    if (std::isfinite(fit.i0_err) && fit.i0_err > 0.5 * fit.i0)
      append_note(fit.note, fmt::format("I0 is poorly determined (+- {:.2g}): widen the range of I",
                                        fit.i0_err));
  }
  return fit;
}

}  // namespace gf::analysis
