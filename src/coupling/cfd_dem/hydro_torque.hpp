// SPDX-License-Identifier: GPL-3.0-or-later
// Hydrodynamic torque of unresolved CFD-DEM: the Stokes torque on a grain in the local linear
// flow, T = f(Re_R) R (Omega_f + lambda a x (E a) - omega). Omega_f = curl(u_f) / 2 is the
// fluid's rotation rate, E its strain rate, omega the grain's angular velocity, a its axis, R its
// Stokes rotational resistance tensor and lambda its shape factor. A grain free of other torques
// turns at omega = Omega_f + lambda a x (E a): a sphere (lambda = 0) with the fluid's rotation
// (omega = -gamma_dot / 2 in simple shear), an axisymmetric grain on Jeffery's orbits, whose axis
// obeys da/dt = W a + lambda (E a - (a . E a) a) (Jeffery, Proc. R. Soc. A 102 (1922) 161, for
// spheroids; Bretherton, J. Fluid Mech. 14 (1962) 284: any body of revolution, with its own
// lambda). A grain spinning in fluid at rest is braked.
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
// Shape factor: lambda = (p^2 - 1) / (p^2 + 1), Jeffery's exact value for a spheroid of the rod's
// aspect ratio (0 for a sphere). A spherocylinder's own "equivalent aspect ratio" is not known in
// closed form; for blunt cylinders it is smaller than p (Harris & Pittman, J. Colloid Interface
// Sci. 50 (1975) 280: 1.14 p^0.844 = 3.7 at p = 4, lambda 0.862 against 0.882 here, a Jeffery
// period 8 % shorter), and rounded ends bring it closer to p.
// Inertia of the fluid: f(Re_R) = C_R Re_R / (64 pi) with Dennis, Singh & Ingham (J. Fluid Mech.
// 101 (1980) 257) for a rotating sphere, C_R = 64 pi / Re_R (Re_R <= 32) and
// C_R = 12.9 / Re_R^0.5 + 128.4 / Re_R (32 < Re_R < 1000), Re_R = rho_f d_v^2 |relative rotation|
// / mu (d_v: volume-equivalent diameter; the same factor for rods is an assumption, as for
// every non-spherical rotational drag in CFD-DEM). The torque is the Stokes one up to Re_R = 32.
//
// Not modelled: the fluid's reaction (a couple density; the volume-averaged equations carry no
// antisymmetric stress), the pitching torque of an elongated grain at an incidence to its slip
// velocity at finite Reynolds numbers (zero in Stokes flow; e.g. Zastawny et al., Int. J.
// Multiphase Flow 39 (2012) 227), inertial drift off Jeffery's orbits, and lift forces (Saffman,
// Magnus). Mahajan et al. (2019) used no hydrodynamic torque at all.
#pragma once

#include <cmath>
#include <numbers>

#include "core/host_device.hpp"
#include "core/mat3.hpp"
#include "core/vec3.hpp"

namespace gf::cfd_dem {

/// Stokes rotational resistances of a grain, N m s: about its axis and about an axis across it
/// (equal for a sphere).
struct RotationalResistance {
  double par = 0;
  double perp = 0;
  double lambda = 0;  ///< Jeffery's shape factor (p^2 - 1) / (p^2 + 1); 0 for a sphere
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
          pi * mu * length * length * length / (3.0 * (std::log(p) + delta)),
          (p * p - 1.0) / (p * p + 1.0)};
}

/// f(Re_R) = C_R / C_R,Stokes of a rotating sphere (Dennis et al. 1980): 1 up to Re_R = 32.
GF_HOST_DEVICE inline double rotational_inertia_factor(double re_r) {
  if (re_r <= 32.0) return 1.0;
  return (12.9 * std::sqrt(re_r) + 128.4) / (64.0 * std::numbers::pi);
}

/// Torque on a grain, N m: f(Re_R) R (spin + lambda axis x (strain axis) - omega), spin and
/// strain the fluid's curl(u) / 2 (rad/s) and strain rate (1/s) at the grain, omega its angular
/// velocity, axis its unit axis (any unit vector for a sphere), d_v its volume-equivalent
/// diameter.
GF_HOST_DEVICE inline Vec3 hydrodynamic_torque(const RotationalResistance& r, const Vec3& axis,
                                               const Vec3& spin, const Mat3& strain,
                                               const Vec3& omega, double rho_f, double mu,
                                               double d_v) {
  // The Jeffery term lies across the axis, so R_par sees the spin's part along it only.
  const Vec3 rel = spin + r.lambda * cross(axis, strain * axis) - omega;
  const double re_r = rho_f * d_v * d_v * norm(rel) / mu;
  const double f = rotational_inertia_factor(re_r);
  return f * (r.perp * rel + (r.par - r.perp) * dot(axis, rel) * axis);
}

}  // namespace gf::cfd_dem
