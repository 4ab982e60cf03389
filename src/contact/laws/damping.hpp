// SPDX-License-Identifier: GPL-3.0-or-later
// Damping slot: viscous normal damping proportional to the critical damping of the tangent
// stiffness, F_d = -2 zeta sqrt(m* S_n) v_n (Tsuji et al. 1992 form for Hertz, where S_n ~
// delta^(1/2) makes the damping ~ delta^(1/4)). zeta is chosen so that the *realised*
// restitution of a binary collision equals the requested e (restitution_map.hpp).
#pragma once

#include <cmath>

#include "contact/laws/contact_io.hpp"

namespace gf::contact {

struct ViscousDamping {
  /// Damping coefficient c (N s/m) for tangent stiffness s (N/m).
  GF_HOST_DEVICE static double coefficient(const PairCoeffs& c, const ContactKinematics& k,
                                           double s) {
    return 2.0 * c.damping_ratio * std::sqrt(k.m_eff * s);
  }
};

}  // namespace gf::contact
