// SPDX-License-Identifier: GPL-3.0-or-later
// Plain data passed to and from the contact-law kernels (one contact at a time).
#pragma once

#include "core/host_device.hpp"
#include "core/vec3.hpp"

namespace gf::contact {

/// Per-material-pair constants, derived once before the time loop (see ContactLaw::prepare).
struct PairCoeffs {
  int model = -1;               ///< index of the law in ContactModels; -1 = no interaction
  double stiffness = 0;         ///< hooke: k_n, N/m; hertz: E* (effective modulus), Pa
  double shear_modulus = 0;     ///< hertz_mindlin: G*, Pa
  double kt_ratio = 0;          ///< k_t / S_n: hooke: given; hertz_mindlin: 8G*/(2E*) = 4G*/E*
  double sqrt_kt_ratio = 0;     ///< sqrt(kt_ratio): tangential over normal damping coefficient
  double damping_ratio = 0;     ///< zeta: damping over critical damping of the tangent stiffness
  double friction = 0;          ///< Coulomb coefficient mu
  double rolling_friction = 0;  ///< rolling resistance coefficient mu_r
  double cohesion = 0;          ///< sjkr cohesion energy density k_c, J/m^3 (0: none)
};

/// Kinematics of one contact, from the narrow phase.
struct ContactKinematics {
  double overlap;  ///< delta > 0, m
  Vec3 normal;     ///< unit normal pointing from j (or the wall) to i
  Vec3 v_rel;      ///< velocity of i's contact point relative to j's, m/s
  Vec3 omega_rel;  ///< omega_i - omega_j, rad/s (rolling)
  double r_eff;    ///< effective radius R* = r_i r_j / (r_i + r_j) (wall: r_i), m
  double m_eff;    ///< effective mass m* (wall: m_i), kg
  /// 1 / (r_i + r_j) of the two (locally) touching spheres, 1/m; 0 for a wall (r_j -> infinity).
  /// Read by the cohesion slot only (the intersection area of the two surfaces).
  double inv_r_sum = 0;
};

/// What a law returns for particle i; j receives the opposite force and rolling torque.
struct ContactResult {
  Vec3 force;           ///< N, on i
  Vec3 rolling_torque;  ///< N m, on i
  /// N, scalar >= 0: the repulsive part (elastic + damping, clamped at 0) that the Coulomb cap,
  /// rolling resistance and wall stiffness estimate use; the normal component of `force` is
  /// this less the cohesion k_c A (so it may be attractive).
  double normal_force;
};

}  // namespace gf::contact
