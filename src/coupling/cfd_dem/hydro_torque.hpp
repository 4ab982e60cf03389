// SPDX-License-Identifier: GPL-3.0-or-later
// Hydrodynamic torque of unresolved CFD-DEM: the viscous resistance of a grain to rotating
// relative to the local fluid, T = f(Re_R) R (Omega_f - omega), with Omega_f = curl(u_f) / 2 the
// fluid's local rotation rate, omega the grain's angular velocity and R its Stokes rotational
// resistance tensor. A grain that turns with the fluid (a sphere in simple shear at
// omega = -gamma_dot / 2) feels none; a spinning grain in fluid at rest is braked.
//
// Stokes resistances (N m s):
//   sphere of diameter d:       R = pi mu d^3                       (= 8 pi mu a^3, Kirchhoff)
//   spherocylinder, total length L = l + d, aspect ratio p = L / d, axis a:
//     about a transverse axis   R_perp = pi mu L^3 / (3 (ln p + delta_perp)),
//                               delta_perp = -0.662 + 0.917 / p - 0.050 / p^2
//                               (Tirado & Garcia de la Torre, J. Chem. Phys. 73 (1980) 1986,
//                               cylinders of 2 <= p <= 30; the caps are counted in L)
//     about its own axis        R_par = pi mu d^2 L   (an infinite cylinder's 4 pi mu r^2 per
//                               length; end effects O(1/p) neglected)
//   R = R_perp (I - a a) + R_par a a.
// Inertia of the fluid: f(Re_R) = C_R Re_R / (64 pi) with Dennis, Singh & Ingham (J. Fluid Mech.
// 101 (1980) 257) for a rotating sphere, C_R = 64 pi / Re_R (Re_R <= 32) and
// C_R = 12.9 / Re_R^0.5 + 128.4 / Re_R (32 < Re_R < 1000), Re_R = rho_f d_v^2 |Omega_f - omega|
// / mu (d_v: volume-equivalent diameter; the same factor for rods is an assumption, as for
// every non-spherical rotational drag in CFD-DEM). The torque is the Stokes one up to Re_R = 32.
//
// Not modelled: the fluid's reaction (a couple density; the volume-averaged equations carry no
// antisymmetric stress), the torque of the drag acting off the centre of elongated grains, and
// lift forces (Saffman, Magnus). Mahajan et al. (2019) used no hydrodynamic torque at all.
#pragma once

#include <cmath>
#include <numbers>

#include "core/host_device.hpp"
#include "core/vec3.hpp"

namespace gf::cfd_dem {

/// Stokes rotational resistances of a grain, N m s: about its axis and about an axis across it
/// (equal for a sphere).
struct RotationalResistance {
  double par = 0;
  double perp = 0;
};

/// Sphere of radius r (half_length 0) or spherocylinder of cap radius r and half cylinder
/// length half_length, in a fluid of viscosity mu.
GF_HOST_DEVICE inline RotationalResistance rotational_resistance(double mu, double r,
                                                                 double half_length) {
  const double pi = std::numbers::pi;
  const double d = 2.0 * r;
  if (half_length <= 0) {
    const double s = pi * mu * d * d * d;
    return {s, s};
  }
  const double length = 2.0 * half_length + d;
  const double p = length / d;
  const double delta = -0.662 + 0.917 / p - 0.050 / (p * p);
  return {pi * mu * d * d * length,
          pi * mu * length * length * length / (3.0 * (std::log(p) + delta))};
}

/// f(Re_R) = C_R / C_R,Stokes of a rotating sphere (Dennis et al. 1980): 1 up to Re_R = 32.
GF_HOST_DEVICE inline double rotational_inertia_factor(double re_r) {
  if (re_r <= 32.0) return 1.0;
  return (12.9 * std::sqrt(re_r) + 128.4) / (64.0 * std::numbers::pi);
}

/// Torque on a grain, N m: f(Re_R) R (spin - omega), spin = the fluid's curl(u) / 2 at the grain
/// (rad/s), omega its angular velocity, axis its unit axis (any unit vector for a sphere), d_v its
/// volume-equivalent diameter.
GF_HOST_DEVICE inline Vec3 hydrodynamic_torque(const RotationalResistance& r, const Vec3& axis,
                                               const Vec3& spin, const Vec3& omega, double rho_f,
                                               double mu, double d_v) {
  const Vec3 rel = spin - omega;
  const double re_r = rho_f * d_v * d_v * norm(rel) / mu;
  const double f = rotational_inertia_factor(re_r);
  return f * (r.perp * rel + (r.par - r.perp) * dot(axis, rel) * axis);
}

}  // namespace gf::cfd_dem
