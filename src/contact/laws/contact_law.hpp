// SPDX-License-Identifier: GPL-3.0-or-later
// A contact law is the composition of four slots (normal, damping, tangential, rolling), in the
// manner of LAMMPS's granular sub-models. All functions are pure, inline, and host/device.
#pragma once

#include <algorithm>

#include "contact/laws/contact_io.hpp"
#include "contact/laws/damping.hpp"
#include "contact/laws/normal.hpp"
#include "contact/laws/rolling.hpp"
#include "contact/laws/tangential.hpp"

namespace gf::contact {

template <class Normal, class Damping, class Tangential, class Rolling>
struct ContactLaw {
  using normal_slot = Normal;

  /// Force and rolling torque on i for one contact; updates the tangential history xi.
  /// The normal force is never attractive: at the end of a contact the dashpot cannot pull.
  GF_HOST_DEVICE static ContactResult evaluate(const PairCoeffs& c, const ContactKinematics& k,
                                               double dt, Vec3& xi) {
    double fe, s;
    Normal::elastic(c, k, fe, s);
    const double vn = dot(k.v_rel, k.normal);  // < 0 when approaching
    const double cn = Damping::coefficient(c, k, s);
    double fn = fe - cn * vn;
    fn = fn > 0 ? fn : 0.0;
    ContactResult r;
    r.normal_force = fn;
    r.force = fn * k.normal + Tangential::force(c, k, s, cn, fn, dt, xi);
    r.rolling_torque = Rolling::torque(c, k, fn);
    return r;
  }

  GF_HOST_DEVICE static double elastic_energy(const PairCoeffs& c, double overlap, double r_eff) {
    return Normal::energy(c, overlap, r_eff);
  }
};

}  // namespace gf::contact
