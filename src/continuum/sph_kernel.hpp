// SPDX-License-Identifier: GPL-3.0-or-later
// The Wendland C2 smoothing kernel of the SPH solver, in 2D and 3D.
//
// W(r, h) = sigma_d / h^d (1 - q/2)^4 (2q + 1), q = r / h in [0, 2] (zero beyond: support 2h),
// sigma_2 = 7 / (4 pi), sigma_3 = 21 / (16 pi) (Wendland, Adv. Comput. Math. 4 (1995) 389;
// normalisation as in Dehnen & Aly, MNRAS 425 (2012) 1068, table 1, with H = 2h). It has no
// pairing instability, so particles stay on a regular arrangement at large neighbour counts.
#pragma once

#include <numbers>

#include "core/host_device.hpp"

namespace gf::continuum {

struct WendlandC2 {
  double h = 1.0;      ///< smoothing length [m]
  double norm = 0.0;   ///< sigma_d / h^d
  double dnorm = 0.0;  ///< sigma_d / h^(d+1)

  WendlandC2() = default;
  WendlandC2(int dimension, double smoothing_length) : h(smoothing_length) {
    const double pi = std::numbers::pi;
    if (dimension == 2) {
      norm = 7.0 / (4.0 * pi * h * h);
    } else {
      norm = 21.0 / (16.0 * pi * h * h * h);
    }
    dnorm = norm / h;
  }
  /// Support radius 2h [m].
  GF_HOST_DEVICE double support() const { return 2.0 * h; }
  /// W(r) [1/m^d].
  GF_HOST_DEVICE double value(double r) const {
    const double q = r / h;
    if (q >= 2.0) return 0.0;
    const double s = 1.0 - 0.5 * q;
    return norm * s * s * s * s * (2.0 * q + 1.0);
  }
  /// dW/dr [1/m^(d+1)] (<= 0).
  GF_HOST_DEVICE double derivative(double r) const {
    const double q = r / h;
    if (q >= 2.0) return 0.0;
    const double s = 1.0 - 0.5 * q;
    return -5.0 * dnorm * q * s * s * s;
  }
};

}  // namespace gf::continuum
