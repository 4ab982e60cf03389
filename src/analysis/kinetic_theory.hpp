// SPDX-License-Identifier: GPL-3.0-or-later
// Kinetic-theory predictions for steady simple shear of smooth inelastic spheres (Lun et al. 1984).
//
// Source: C. K. K. Lun, S. B. Savage, D. J. Jeffrey & N. Chepurniy (1984), J. Fluid Mech.
// 140:223-256, in the form of Mahajan et al. (eqs 17-21), with the Carnahan & Starling (1969)
// radial distribution at contact g0(phi) = (1 - phi/2) / (1 - phi)^3. With alpha = (1 + e) / 2,
// volume fraction phi, grain diameter d, material density rho_p, shear rate gamma_dot and granular
// temperature T (velocity variance per component, m^2/s^2):
//   mu*   = (5/96) rho_p d sqrt(pi T)  (Chapman-Enskog dilute viscosity (5/16) m sqrt(T/pi) / d^2)
//   F_c   = (1 + 8/5 alpha phi g0) (1 + 8/5 alpha (3 alpha - 2) phi g0) / (alpha (2 - alpha) g0)
//   F_s   = 768 / (25 pi) alpha phi^2 g0,   F = F_c + F_s
//   viscous heating = collisional dissipation (Haff):
//           mu* F gamma_dot^2 = (48 / sqrt(pi)) alpha (1 - alpha) rho_p phi^2 g0 T^{3/2} / d
//   =>  T = (5 pi / 4608) F d^2 gamma_dot^2 / (alpha (1 - alpha) phi^2 g0)        (needs e < 1)
//   P     = rho_p phi T (1 + 4 alpha phi g0)      streaming rho_p phi T, collisional the rest
//   s_xz  = -mu* F gamma_dot                      streaming (kinetic) part
//           -mu* gamma_dot (1 + 8/5 alpha (3 alpha - 2) phi g0) / (alpha (2 - alpha) g0),
//           collisional part = total - streaming
//   normal stresses isotropic at this order: s_xx = s_yy = s_zz = P.
// Signs: compressive positive (P > 0); for u_x = gamma_dot z the shear stress s_xz < 0. T and all
// stresses scale as gamma_dot^2 (Bagnold); the friction |s_xz| / P does not depend on gamma_dot.
// Valid for nearly elastic grains (1 - e << 1), binary collisions, phi below about 0.5.
#pragma once

namespace gf::analysis {

/// Carnahan-Starling radial distribution at contact, (1 - phi/2) / (1 - phi)^3; 0 <= phi < 1.
double carnahan_starling_g0(double phi);

/// Enskog collision frequency of one grain, 1/s: omega = (24 phi g0 / d) sqrt(T / pi) for
/// smooth spheres of diameter d with Maxwellian velocities of temperature T (m^2/s^2) (Chapman &
/// Cowling 1970, ch. 16; with g0 of Carnahan-Starling). With binary contacts of duration t_c a
/// grain then touches omega t_c others on average: the coordination number of a dilute gas.
double enskog_collision_frequency(double phi, double temperature, double diameter);

/// Steady simple-shear state of Lun et al. (1984); stresses compressive positive.
struct ShearFlowPrediction {
  double temperature = 0;               ///< m^2/s^2, velocity variance per component
  double pressure = 0;                  ///< Pa, = s_xx = s_yy = s_zz
  double pressure_streaming = 0;        ///< Pa, rho_p phi T
  double pressure_collisional = 0;      ///< Pa, rho_p phi T 4 alpha phi g0
  double shear_stress = 0;              ///< Pa, s_xz (negative for gamma_dot > 0)
  double shear_stress_streaming = 0;    ///< Pa, kinetic part of s_xz
  double shear_stress_collisional = 0;  ///< Pa, shear_stress - shear_stress_streaming
  double viscosity = 0;                 ///< Pa s, -s_xz / gamma_dot = mu* F
  double friction = 0;                  ///< 1, |s_xz| / P (independent of gamma_dot)
};

/// Prediction for volume fraction `phi` (0 < phi < 1), restitution `restitution` (0 <= e < 1),
/// grain diameter `diameter` (m), material density `density` (kg/m^3) and shear rate
/// `shear_rate` (1/s; either sign, stresses follow its sign).
ShearFlowPrediction lun_simple_shear(double phi, double restitution, double diameter,
                                     double density, double shear_rate);

/// Diameter of the sphere of volume `volume` (m^3), (6 V / pi)^(1/3), m.
double volume_equivalent_diameter(double volume);

}  // namespace gf::analysis
