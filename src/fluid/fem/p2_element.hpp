// SPDX-License-Identifier: GPL-3.0-or-later
// Reference P2/P1 triangle: shape functions, 7-point quadrature, isoparametric geometry.
#pragma once

#include <array>
#include <cmath>

#include "fluid/fem/mesh.hpp"

namespace gf::fem::p2 {

/// 7-point degree-5 rule on the reference triangle (0,0), (1,0), (0,1) (Radon 1948;
/// Dunavant, Int. J. Numer. Meth. Eng. 21 (1985) 1129): weights sum to the area 1/2.
/// Exact for the mass (degree 4) and convection (degree 5) integrands on straight cells.
struct Quadrature7 {
  static constexpr int n = 7;
  std::array<double, n> xi{}, eta{}, w{};
  Quadrature7() {
    const double s = std::sqrt(15.0);
    const double a1 = (6.0 - s) / 21.0, b1 = (9.0 + 2.0 * s) / 21.0;
    const double a2 = (6.0 + s) / 21.0, b2 = (9.0 - 2.0 * s) / 21.0;
    const double w0 = 9.0 / 80.0, w1 = (155.0 - s) / 2400.0, w2 = (155.0 + s) / 2400.0;
    xi = {1.0 / 3.0, a1, b1, a1, a2, b2, a2};
    eta = {1.0 / 3.0, a1, a1, b1, a2, a2, b2};
    w = {w0, w1, w1, w1, w2, w2, w2};
  }
};

/// P2 shape functions (vertices 0,1,2 then midpoints of edges 01, 12, 20) at (xi, eta).
inline void shape(double xi, double eta, double* phi, double* dxi, double* deta) {
  const double l0 = 1.0 - xi - eta, l1 = xi, l2 = eta;
  phi[0] = l0 * (2 * l0 - 1);
  phi[1] = l1 * (2 * l1 - 1);
  phi[2] = l2 * (2 * l2 - 1);
  phi[3] = 4 * l0 * l1;
  phi[4] = 4 * l1 * l2;
  phi[5] = 4 * l2 * l0;
  // d/dxi: dl0 = -1, dl1 = 1, dl2 = 0; d/deta: dl0 = -1, dl1 = 0, dl2 = 1
  dxi[0] = -(4 * l0 - 1);
  dxi[1] = 4 * l1 - 1;
  dxi[2] = 0;
  dxi[3] = 4 * (l0 - l1);
  dxi[4] = 4 * l2;
  dxi[5] = -4 * l2;
  deta[0] = -(4 * l0 - 1);
  deta[1] = 0;
  deta[2] = 4 * l2 - 1;
  deta[3] = -4 * l1;
  deta[4] = 4 * l1;
  deta[5] = 4 * (l0 - l2);
}

/// Physical gradients of the 6 shape functions and det J of the isoparametric map at a point.
inline double gradients(const std::array<Vec2, 6>& x, double xi, double eta, double* phi,
                        double* gx, double* gy) {
  double dxi[6], deta[6];
  shape(xi, eta, phi, dxi, deta);
  double j00 = 0, j01 = 0, j10 = 0, j11 = 0;  // j_ab = dx_a / dxi_b
  for (int k = 0; k < 6; ++k) {
    j00 += x[k].x * dxi[k];
    j01 += x[k].x * deta[k];
    j10 += x[k].y * dxi[k];
    j11 += x[k].y * deta[k];
  }
  const double det = j00 * j11 - j01 * j10;
  const double inv = 1.0 / det;
  for (int k = 0; k < 6; ++k) {
    gx[k] = (j11 * dxi[k] - j10 * deta[k]) * inv;
    gy[k] = (-j01 * dxi[k] + j00 * deta[k]) * inv;
  }
  return det;
}

}  // namespace gf::fem::p2
