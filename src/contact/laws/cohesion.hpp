// SPDX-License-Identifier: GPL-3.0-or-later
// Cohesion slot: the simplified JKR model ("cohesion sjkr" of LIGGGHTS), an attractive normal
// force proportional to the contact area, acting only while the surfaces overlap:
//   F_coh = k_c A                                       (k_c: cohesion energy density, J/m^3)
//   A = pi a^2, a^2 = delta (2R* - delta + delta^2 u / 2)(1 - delta u / 2) / (1 - delta u)^2
// with u = 1 / (R_i + R_j). This is the area of the circle in which the two sphere surfaces
// intersect, A = -pi/4 (d - R_i - R_j)(d + R_i - R_j)(d - R_i + R_j)(d + R_i + R_j) / d^2 at
// centre distance d = R_i + R_j - delta, written in delta, R* and u so that a wall is u = 0:
// A = pi delta (2R - delta) = pi (R^2 - (R - delta)^2). Johnson, Kendall & Roberts, Proc. R. Soc.
// Lond. A 324 (1971) 301 for the adhesive contact; the linear-in-area simplification as in
// LIGGGHTS (cohesion_model_sjkr.h, Kloss et al., Prog. Comput. Fluid Dyn. 12 (2012) 140).
// 2D: disks take the same area pi a^2, as the spheres the 2D elastic laws assume (their
// stiffness does not scale with domain.thickness either); an area 2 a t of cylinders of depth t
// made the equilibrium overlap grow with t and pulled disks through walls at the default t = 1 m.
#pragma once

#include <cmath>
#include <limits>

#include "contact/laws/contact_io.hpp"

namespace gf::contact {

struct SjkrCohesion {
  /// Squared radius a^2 (m^2) of the circle where two spheres of effective radius R* = r_eff and
  /// 1 / (R_i + R_j) = inv_r_sum (0 for a wall) intersect at overlap delta. Valid while the
  /// centre distance exceeds |R_i - R_j|; clamped at 0 beyond (and for coincident centres).
  GF_HOST_DEVICE_INLINE static double intersection_radius2(double delta, double r_eff,
                                                           double inv_r_sum) {
    const double du = delta * inv_r_sum;
    const double w = 1.0 - du;  // d / (R_i + R_j)
    const double w2 = w * w;
    const double a2 = delta * (2.0 * r_eff - delta + 0.5 * delta * du) * (1.0 - 0.5 * du) /
                      (w2 > 0 ? w2 : 1.0);  // (selects: a vectorised lane never divides by 0)
    return w2 > 0 && a2 > 0 ? a2 : 0.0;
  }
  /// Contact area A (m^2) of the contact k.
  GF_HOST_DEVICE_INLINE static double area(const PairCoeffs& /*c*/, const ContactKinematics& k) {
    return 3.141592653589793 * intersection_radius2(k.overlap, k.r_eff, k.inv_r_sum);
  }
  /// Magnitude of the attractive force k_c A (N); exactly 0 when k_c = 0.
  GF_HOST_DEVICE_INLINE static double force(const PairCoeffs& c, const ContactKinematics& k) {
    const double a = area(c, k);
    return c.cohesion > 0 ? c.cohesion * a : 0.0;
  }
};

// Resting states, for `grainflow check` and the tests (host only): two equal spheres of radius r
// (wall = false: R* = r/2, u = 1/(2r), A = pi (r delta - delta^2/4)) or a sphere of radius r on a
// wall (wall = true: R* = r, u = 0, A = pi delta (2r - delta); cylinders and meshes are flat at
// the contact, as for the elastic laws), at rest with no other load. The net normal force is then
// F_e(delta) - k_c A(delta), F_e the elastic repulsion of the normal slot `Normal` (normal.hpp).

/// Kinematics of the resting contact above at overlap delta (m).
inline ContactKinematics resting_kinematics(double r, bool wall, double delta) {
  ContactKinematics k{};
  k.overlap = delta;
  k.r_eff = wall ? r : 0.5 * r;
  k.inv_r_sum = wall ? 0.0 : 0.5 / r;
  return k;
}

/// Net normal force F_e - k_c A (N; > 0 repulsive) of the resting contact above at overlap delta.
template <class Normal>
inline double resting_normal_force(const PairCoeffs& c, double r, bool wall, double delta) {
  const ContactKinematics k = resting_kinematics(r, wall, delta);
  double f, s;
  Normal::elastic(c, k, f, s);
  return f - SjkrCohesion::force(c, k);
}

/// Unloaded equilibrium overlap (m) of the resting contact above: grains that touch
/// (delta -> 0+) are pulled in while k_c A > F_e and stop at the first delta where F_e = k_c A
/// (a stable balance: beyond it the repulsion wins). F_e / delta does not decrease with delta
/// (hooke: k_n; hertz: 4/3 E* sqrt(R* delta)) and A / delta decreases, so there is one crossing,
/// found by bisection to ~1e-15 relative. Closed forms for hooke (unit tests): a pair
/// 4 (r - k_n / (pi k_c)), a wall 2 r - k_n / (pi k_c). Returns
///  - 0 when F_e >= k_c A from first touch (k_c = 0; hooke with k_n >= 2 pi k_c R*): the
///    cohesion holds no overlap at rest;
///  - +infinity when k_c A > F_e all the way to coincident centres (a pair, delta -> 2r; up to
///    1e-6 of it, where the area formula loses its digits): cohesion always wins and the grains
///    are pulled onto each other (hooke: k_c >= 2 k_n / (pi r); hertz: k_c >= 8 E* / (3 pi)).
///    On a wall A vanishes at delta = 2r (the sphere through it), so there is always a root.
template <class Normal>
inline double equilibrium_overlap(const PairCoeffs& c, double r, bool wall) {
  double lo = 0, hi = 2 * r * (1 - 1e-6);
  if (resting_normal_force<Normal>(c, r, wall, hi) < 0)
    return std::numeric_limits<double>::infinity();
  // Invariant: attraction wins at lo (or lo = 0), repulsion at hi. Stays lo = 0 (returns 0) when
  // the repulsion wins at every overlap.
  for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (resting_normal_force<Normal>(c, r, wall, mid) < 0 ? lo : hi) = mid;
  }
  return lo > 0 ? 0.5 * (lo + hi) : 0.0;
}

/// The k_c (J/m^3) whose equilibrium_overlap is delta (0 < delta < 2r, m): F_e(delta) / A(delta),
/// the same balance solved for k_c. The equilibrium overlap grows with k_c, so a smaller k_c
/// rests at a smaller overlap.
template <class Normal>
inline double cohesion_for_overlap(const PairCoeffs& c, double r, bool wall, double delta) {
  const ContactKinematics k = resting_kinematics(r, wall, delta);
  double f, s;
  Normal::elastic(c, k, f, s);
  return f / SjkrCohesion::area(c, k);
}

}  // namespace gf::contact
