// SPDX-License-Identifier: GPL-3.0-or-later
// Rheology of a sheared granular layer (flow along x, velocity gradient along z), as measured by
// Mahajan et al. (2019; after Campbell & Gong 1986) in a shear box:
//   - streaming stress   sigma_s = (1/V) sum_i m_i v'_i (x) v'_i, with v'_i the velocity relative
//     to the mean velocity of the particle's layer (one of `bins` layers of equal height);
//   - collisional stress sigma_c = (1/V) sum_pairs d_ij (x) F_ij (contact virial, F_ij the force
//     on i from j, d_ij = x_i - x_j; component [a][b] = d_a F_b), pairs counted by the midpoint of
//     their branch vector;
//   - total stress sigma = sigma_s + sigma_c, pressure P = tr(sigma)/3, N1 = s_xx - s_zz,
//     N2 = s_zz - s_yy, apparent friction mu = |s_xz| / P, viscosity eta = -s_xz / gamma_dot;
//   - granular temperature T = <v' . v'> / 3 (mean over the grains);
//   - in a fluid (grains carrying the `fluid_velocity` field, the fluid velocity interpolated at
//     each grain by the CFD-DEM coupling): the fluid temperature T_f = <u' . u'> / 3 of the fluid
//     velocity seen by the grains, u' relative to its layer mean, and the slip temperature
//     T_s = <(v' - u') . (v' - u')> / 3, the part of the grains' agitation that is not carried
//     by the fluid's own motion at the grid scale (e.g. streaks of the fluid across the
//     vorticity direction, which the layer means keep); without a fluid T_f = 0, T_s = T;
//   (layer sums with Bessel's correction for the mean taken from the same grains);
//   - order tensor S = <u (x) u> of the axes u of spherocylinders, the alignment angle
//     theta = 1/2 atan2(2 S_xz, S_xx - S_zz) between the preferred axis and the flow, and the
//     nematic order parameter (largest eigenvalue of (3 S - I) / 2);
//   - the actual shear rate (least-squares slope of v_x against z) and volume fraction;
//   - the contacts: coordination number Z = 2 C / N (C touching pairs counted like the virial,
//     N grains in the layer) and the contact fabric F = <n (x) n> over those pairs (n the unit
//     contact normal, tr F = 1; Oda 1982, Satake 1982), with the angle of its major axis
//     theta_F = 1/2 atan2(2 F_xz, F_xx - F_zz) in the flow-gradient plane (near -45 degrees, the
//     compressive axis of simple shear). For frictionless spheres sigma_c = (C/V) <l f_n n (x) n>
//     (l = |d|, f_n the normal force): normal stress differences come from F's anisotropy and from
//     how force and branch length vary with direction, which the fabric tells apart.
// Everything is restricted to the layer z_lo <= z < z_hi (grains by their centre). Stresses
// use the compressive-positive sign (pressure > 0); in simple shear u_x = gamma_dot z, s_xz < 0.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "core/domain.hpp"
#include "core/mat3.hpp"
#include "particles/particle_store.hpp"

namespace gf::analysis {

/// The measurement layer and its binning for the mean velocity.
struct RheologyRegion {
  double z_lo = 0, z_hi = 0;  ///< m
  int bins = 16;
  double area = 0;  ///< m^2, the box's cross-section normal to z (L_x L_y)
  double volume() const { return area * (z_hi - z_lo); }
};

/// What the force stage collects over the pairs counted in the layer (contact::ContactSink).
struct ContactSums {
  Mat3 virial;   ///< sum of d (x) F, N m
  Mat3 normals;  ///< sum of n (x) n (its trace: the number of pairs)
};

struct RheologySample {
  Mat3 streaming;    ///< Pa
  Mat3 collisional;  ///< Pa
  Mat3 order;        ///< <u u> of spherocylinder axes (zero without them)
  Mat3 fabric;       ///< <n n> of the contact normals (zero without contacts)
  std::int64_t grains = 0;
  std::int64_t contacts = 0;  ///< touching pairs counted in the layer
  std::int64_t rods = 0;
  double volume_fraction = 0;
  double shear_rate = 0;         ///< 1/s, measured
  double temperature = 0;        ///< m^2/s^2
  double fluid_temperature = 0;  ///< m^2/s^2, of the fluid velocity at the grains
  double slip_temperature = 0;   ///< m^2/s^2, of the grains relative to that fluid velocity
  double alignment_angle = 0;    ///< degrees
  double order_parameter = 0;
  double coordination = 0;  ///< 2 contacts / grains
  double fabric_angle = 0;  ///< degrees, major axis of F in the x-z plane

  Mat3 total() const { return streaming + collisional; }
  double pressure() const;
  double streaming_pressure() const;
  double collisional_pressure() const;
  /// sigma_xz, symmetric part (the virial of non-spherical grains has a small antisymmetric
  /// part that vanishes on average at steady state), Pa
  double shear_stress() const;
  double friction() const;                  ///< |sigma_xz| / P
  double viscosity() const;                 ///< -sigma_xz / gamma_dot (measured rate), Pa s
  double first_normal_difference() const;   ///< sigma_xx - sigma_zz
  double second_normal_difference() const;  ///< sigma_zz - sigma_yy
};

/// Normal stress differences of a stress tensor (flow x, gradient z, vorticity y), Pa:
/// N1 = sigma_xx - sigma_zz, N2 = sigma_zz - sigma_yy.
double first_normal_difference(const Mat3& s);
double second_normal_difference(const Mat3& s);

/// Measures one sample. `contacts` holds the sums over the pairs counted in the layer
/// (contact::ContactSink); `density` the density of each material (grain volume m / rho).
RheologySample measure_rheology(const ParticleStore& p, const RheologyRegion& region,
                                const ContactSums& contacts, std::span<const double> density);

/// Column names of a sample in the time series (rheology.csv, after time and strain), and the
/// values in that order.
const std::vector<std::string>& rheology_columns();
std::vector<double> rheology_values(const RheologySample& s);

}  // namespace gf::analysis
