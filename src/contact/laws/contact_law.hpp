// SPDX-License-Identifier: GPL-3.0-or-later
// A contact law is the composition of five slots (normal, damping, tangential, rolling,
// cohesion), in the manner of LAMMPS's granular sub-models. All functions are pure, inline, and
// host/device.
#pragma once

#include <algorithm>

#include "contact/laws/cohesion.hpp"
#include "contact/laws/contact_io.hpp"
#include "contact/laws/damping.hpp"
#include "contact/laws/normal.hpp"
#include "contact/laws/rolling.hpp"
#include "contact/laws/tangential.hpp"

namespace gf::contact {

template <class Normal, class Damping, class Tangential, class Rolling, class Cohesion>
struct ContactLaw {
  using normal_slot = Normal;

  /// Force and rolling torque on i for one contact; updates the tangential history xi.
  /// The repulsive normal force (elastic + damping) is clamped at zero: at the end of a contact
  /// the dashpot cannot pull. Cohesion (the only attraction) is subtracted from it, so the total
  /// normal force may be negative; the Coulomb cap and the rolling resistance use the repulsive
  /// part (which, in contact, equals the total plus the cohesion: the load pressing the surfaces
  /// together, adhesion included). With Cohesive = false the cohesion slot is left out: the
  /// kernels of runs where no pair has cohesion (the same bits as with k_c = 0, fewer flops).
  template <bool Cohesive = true>
  GF_HOST_DEVICE static ContactResult evaluate(const PairCoeffs& c, const ContactKinematics& k,
                                               double dt, Vec3& xi) {
    double fe, s;
    Normal::elastic(c, k, fe, s);
    const double vn = dot(k.v_rel, k.normal);  // < 0 when approaching
    const double cn = Damping::coefficient(c, k, s);
    double fn = fe - cn * vn;
    fn = fn > 0 ? fn : 0.0;
    double fn_total = fn;
    if constexpr (Cohesive) fn_total = fn - Cohesion::force(c, k);  // k_c = 0: exactly fn
    ContactResult r;
    r.normal_force = fn;
    r.force = fn_total * k.normal + Tangential::force(c, k, s, cn, fn, dt, xi);
    r.rolling_torque = Rolling::torque(c, k, fn);
    return r;
  }

  GF_HOST_DEVICE static double elastic_energy(const PairCoeffs& c, double overlap, double r_eff) {
    return Normal::energy(c, overlap, r_eff);
  }
};

}  // namespace gf::contact
