// SPDX-License-Identifier: GPL-3.0-or-later
// Rolling slot: constant directional torque (model A of Ai et al., Powder Technol. 206 (2011)
// 269, eq. 7): M_r = -mu_r R* F_n omega_rel / |omega_rel|, switched off for |omega_rel| below
// a small threshold so that a grain at rest does not chatter.
#pragma once

#include <cmath>

#include "contact/laws/contact_io.hpp"

namespace gf::contact {

struct ConstantTorqueRolling {
  static constexpr double omega_threshold = 1e-12;  ///< rad/s
  GF_HOST_DEVICE static Vec3 torque(const PairCoeffs& c, const ContactKinematics& k, double fn) {
    // Selects, not branches (see tangential.hpp): a zero coefficient or a spin below the
    // threshold gives a zero torque.
    const double w = norm(k.omega_rel);
    const bool on = c.rolling_friction != 0 && w >= omega_threshold;
    return (on ? -c.rolling_friction * k.r_eff * fn / w : 0.0) * k.omega_rel;
  }
};

}  // namespace gf::contact
