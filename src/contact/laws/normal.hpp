// SPDX-License-Identifier: GPL-3.0-or-later
// Normal-force slot: elastic repulsion as a function of overlap, and its tangent stiffness.
//
// hooke:  F_e = k_n delta                                  (linear spring)
// hertz:  F_e = 4/3 E* sqrt(R*) delta^(3/2)                (Hertz 1882; Johnson, Contact
//         Mechanics, 1985, eq. 4.22), tangent stiffness S_n = dF_e/ddelta = 2 E* sqrt(R* delta)
#pragma once

#include <cmath>

#include "contact/laws/contact_io.hpp"

namespace gf::contact {

/// Exponent family of the elastic law; selects the restitution -> damping mapping.
enum class NormalKind { Linear, Hertz };

struct HookeNormal {
  static constexpr NormalKind kind = NormalKind::Linear;
  /// Elastic force (N) and tangent stiffness (N/m).
  GF_HOST_DEVICE static void elastic(const PairCoeffs& c, const ContactKinematics& k, double& f,
                                     double& s) {
    s = c.stiffness;
    f = c.stiffness * k.overlap;
  }
  /// Stored elastic energy, J.
  GF_HOST_DEVICE static double energy(const PairCoeffs& c, double overlap, double /*r_eff*/) {
    return 0.5 * c.stiffness * overlap * overlap;
  }
};

struct HertzNormal {
  static constexpr NormalKind kind = NormalKind::Hertz;
  GF_HOST_DEVICE static void elastic(const PairCoeffs& c, const ContactKinematics& k, double& f,
                                     double& s) {
    const double a = std::sqrt(k.r_eff * k.overlap);  // contact radius
    s = 2.0 * c.stiffness * a;
    f = (2.0 / 3.0) * s * k.overlap;
  }
  GF_HOST_DEVICE static double energy(const PairCoeffs& c, double overlap, double r_eff) {
    return (8.0 / 15.0) * c.stiffness * std::sqrt(r_eff) * overlap * overlap * std::sqrt(overlap);
  }
};

}  // namespace gf::contact
