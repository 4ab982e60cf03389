// SPDX-License-Identifier: GPL-3.0-or-later
// Tangential slot: spring with history (the accumulated tangential displacement xi), dashpot
// and Coulomb cap |F_t| <= mu F_n (Cundall & Strack 1979). The history is kept in the tangent
// plane: each step it is projected onto the current tangent plane and rescaled to its old
// length (rotation with the contact frame), then advanced by v_t dt.
//   linear:  k_t = kt_ratio k_n                             (hooke)
//   mindlin: k_t = 8 G* sqrt(R* delta)                       (Mindlin 1949, no-slip stiffness)
// Both are k_t = kt_ratio S_n with the normal tangent stiffness S_n (for Hertz, S_n = 2E* sqrt(R*
// delta), so kt_ratio = 4G*/E*): one per-pair constant, no extra square root per contact.
// Damping uses the same zeta as the normal direction: c_t = 2 zeta sqrt(m* k_t)
// = c_n sqrt(kt_ratio).
// When sliding, xi is reset so that the spring alone would give the capped force.
#pragma once

#include <cmath>

#include "contact/laws/contact_io.hpp"

namespace gf::contact {

/// Tangential force for tangential stiffness kt and damping coefficient ct; updates xi.
GF_HOST_DEVICE_INLINE Vec3 tangential_force(const PairCoeffs& c, const ContactKinematics& k,
                                            double kt, double ct, double normal_force, double dt,
                                            Vec3& xi) {
  const Vec3& n = k.normal;
  const Vec3 vt = k.v_rel - dot(k.v_rel, n) * n;
  // Rotate the history into the current tangent plane, keeping its magnitude. Written with
  // selects instead of branches (the values that are not chosen are computed and dropped), so
  // that a loop over contacts vectorises; a zero history stays zero since the projection of
  // zero is zero and its scale is 1.
  const double len2_old = norm2(xi);
  const Vec3 xp = xi - dot(xi, n) * n;
  const double len2_new = norm2(xp);
  const bool rescale = len2_old > 0 && len2_new > 0;
  xi = (rescale ? std::sqrt(len2_old / len2_new) : 1.0) * xp;
  xi += dt * vt;
  Vec3 ft = -kt * xi - ct * vt;
  const double cap = c.friction * normal_force;
  const double ft2 = norm2(ft);
  const bool slide = ft2 > cap * cap;
  // cap / |F_t| and 1 / k_t from one division (kt = 0, a damper alone, takes 1 in the product).
  const double ft_len = std::sqrt(ft2);
  const double kt_or_1 = kt > 0 ? kt : 1.0;
  const double q = 1.0 / (kt_or_1 * ft_len);
  ft *= slide ? cap * kt_or_1 * q : 1.0;
  // Sliding: the spring alone carries the capped force.
  xi = slide ? (kt > 0 ? -ft_len * q : 0.0) * ft : xi;
  return ft;
}

/// Linear (hooke) and Mindlin (hertz_mindlin) springs: k_t = kt_ratio S_n, c_t = c_n
/// sqrt(kt_ratio).
struct HistoryTangential {
  GF_HOST_DEVICE static Vec3 force(const PairCoeffs& c, const ContactKinematics& k, double sn,
                                   double cn, double fn, double dt, Vec3& xi) {
    return tangential_force(c, k, c.kt_ratio * sn, c.sqrt_kt_ratio * cn, fn, dt, xi);
  }
};

}  // namespace gf::contact
