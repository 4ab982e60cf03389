// SPDX-License-Identifier: GPL-3.0-or-later
// Columns of a contact batch: the structure-of-arrays form in which the sphere pair and wall
// loops (contact/pair_forces.cpp, boundaries/wall.cpp) hand their touching contacts to a
// vectorised law loop. One vector or one set of pair constants per contact, one array each.
#pragma once

#include "contact/laws/contact_io.hpp"
#include "core/host_device.hpp"
#include "core/vec3.hpp"

namespace gf::contact {

/// A vector per contact, as three columns (x, y, z).
template <int N>
struct VecColumns {
  double x[N], y[N], z[N];
  GF_HOST_DEVICE_INLINE void set(int c, const Vec3& v) {
    x[c] = v.x;
    y[c] = v.y;
    z[c] = v.z;
  }
  GF_HOST_DEVICE_INLINE Vec3 get(int c) const { return {x[c], y[c], z[c]}; }
};

/// The per-pair constants a law reads, one column each (the others stay zero).
template <int N>
struct CoeffColumns {
  double stiffness[N], kt_ratio[N], sqrt_kt_ratio[N], damping_ratio[N], friction[N],
      rolling_friction[N], cohesion[N];
  GF_HOST_DEVICE_INLINE void set(int c, const PairCoeffs& p) {
    stiffness[c] = p.stiffness;
    kt_ratio[c] = p.kt_ratio;
    sqrt_kt_ratio[c] = p.sqrt_kt_ratio;
    damping_ratio[c] = p.damping_ratio;
    friction[c] = p.friction;
    rolling_friction[c] = p.rolling_friction;
    cohesion[c] = p.cohesion;
  }
  GF_HOST_DEVICE_INLINE PairCoeffs get(int c, int model) const {
    return PairCoeffs{model,       stiffness[c],        0.0,
                      kt_ratio[c], sqrt_kt_ratio[c],    damping_ratio[c],
                      friction[c], rolling_friction[c], cohesion[c]};
  }
};

}  // namespace gf::contact
