// SPDX-License-Identifier: GPL-3.0-or-later
// Flux limiters of the finite-volume convection schemes (fluid/fv, the two-fluid model).
#pragma once

namespace gf::fluid {

/// Van Leer's limited face value from the far-upwind, upwind and downwind values: the upwind
/// value plus the harmonic mean of the two slopes (zero at an extremum), i.e.
/// phi_U + psi(r) (phi_D - phi_U) / 2 with psi(r) = (r + |r|) / (1 + |r|) (van Leer, J. Comput.
/// Phys. 14 (1974) 361). The value lies between phi_U and phi_D (TVD for Courant numbers <= 1/2).
inline double van_leer(double far_upwind, double upwind, double downwind) {
  const double d0 = upwind - far_upwind, d1 = downwind - upwind;
  return d0 * d1 > 0.0 ? upwind + d0 * d1 / (d0 + d1) : upwind;
}

}  // namespace gf::fluid
