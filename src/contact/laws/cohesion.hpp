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

}  // namespace gf::contact
