// SPDX-License-Identifier: GPL-3.0-or-later
// Shape factors the drag laws need for spherocylinders (capsules): volume, volume-equivalent
// diameter, surface sphericity and the crosswise sphericity seen by a flow at a given incidence.
//
// A spherocylinder is every point within radius r of a segment of length l (the cylinder part;
// l = 0 is a sphere). Its total length is L = l + 2r. Definitions follow Hoelzer & Sommerfeld,
// Powder Technol. 184 (2008) 361, sec. 2:
//   phi      = (surface of the volume-equivalent sphere) / (surface of the particle)
//   phi_perp = (cross-section of the volume-equivalent sphere) / (particle area projected on the
//              plane normal to the relative flow)
#pragma once

#include <cmath>

#include "core/host_device.hpp"
#include "core/vec3.hpp"

namespace gf::cfd_dem {

inline constexpr double kPi = 3.141592653589793;

/// Volume of a spherocylinder of radius r and cylinder length l, m^3: pi r^2 l + 4/3 pi r^3.
GF_HOST_DEVICE inline double spherocylinder_volume(double r, double l) {
  return kPi * r * r * l + 4.0 / 3.0 * kPi * r * r * r;
}

/// Surface area, m^2: the cylinder mantle 2 pi r l plus one full sphere 4 pi r^2.
GF_HOST_DEVICE inline double spherocylinder_surface(double r, double l) {
  return 2.0 * kPi * r * l + 4.0 * kPi * r * r;
}

/// Diameter of the sphere of volume V, m: d_v = (6 V / pi)^(1/3).
GF_HOST_DEVICE inline double volume_equivalent_diameter(double volume) {
  return std::cbrt(6.0 * volume / kPi);
}

/// Surface sphericity phi = pi d_v^2 / S (1 for a sphere, < 1 otherwise).
GF_HOST_DEVICE inline double spherocylinder_sphericity(double r, double l) {
  const double dv = volume_equivalent_diameter(spherocylinder_volume(r, l));
  return kPi * dv * dv / spherocylinder_surface(r, l);
}

/// Area of the spherocylinder projected along a direction at angle theta to its axis, m^2.
/// Exact: the shadow of the segment is a segment of length l sin(theta); the shadow of the body
/// is that segment dilated by a disk of radius r, a rectangle 2r x l sin(theta) plus a disk.
GF_HOST_DEVICE inline double spherocylinder_projected_area(double r, double l, double sin_theta) {
  return kPi * r * r + 2.0 * r * l * sin_theta;
}

/// Crosswise sphericity phi_perp = (pi d_v^2 / 4) / A_proj(theta); theta the angle between the
/// axis and the relative flow (sin_theta = 0: flow along the axis, 1: broadside).
GF_HOST_DEVICE inline double spherocylinder_crosswise_sphericity(double r, double l,
                                                                 double sin_theta) {
  const double dv = volume_equivalent_diameter(spherocylinder_volume(r, l));
  return 0.25 * kPi * dv * dv / spherocylinder_projected_area(r, l, sin_theta);
}

/// sin of the angle between the unit axis u and the direction of w (w != 0): |u x w| / |w|.
GF_HOST_DEVICE inline double sin_incidence(const Vec3& axis, const Vec3& w) {
  const double s = norm(cross(axis, w)) / norm(w);
  return s > 1.0 ? 1.0 : s;
}

}  // namespace gf::cfd_dem
