// SPDX-License-Identifier: GPL-3.0-or-later
// Restitution -> damping ratio, such that a binary collision realises the requested e.
//
// With F = F_e(delta) - 2 zeta sqrt(m* S_n) v_n clamped at F >= 0, the dimensionless collision
//   linear: x'' = -x - 2 zeta x'                 (x = delta / (v0 sqrt(m*/k)), t in sqrt(m*/k))
//   hertz:  x'' = -x^(3/2) - 2 zeta sqrt(3/2) x^(1/4) x'
// has a restitution e(zeta) that depends on zeta only, not on the impact speed or the material.
// The closed forms (e = exp(-pi zeta / sqrt(1 - zeta^2)) for linear without the clamp, the
// log-based formula of Tsuji et al. for Hertz) miss the realised value by up to ~20 % for small
// e once the force is clamped, so e(zeta) is integrated numerically (RK4, 2e4 steps per
// collision, contact end located by interpolation at F = 0) and inverted by bisection.
#pragma once

#include "contact/laws/normal.hpp"

namespace gf::contact {

/// Realised restitution for a damping ratio (dimensionless collision integrated by RK4).
double realised_restitution(NormalKind kind, double zeta);

/// The damping ratio zeta that realises restitution e in (0, 1]; e = 1 gives 0.
double damping_ratio_for_restitution(NormalKind kind, double e);

}  // namespace gf::contact
