// SPDX-License-Identifier: GPL-3.0-or-later
// Velocity Verlet for translation and rotation of spheres (Swope et al., J. Chem. Phys. 76
// (1982) 637): v(t+dt/2) = v(t) + dt/2 a(t); x(t+dt) = x(t) + dt v(t+dt/2); forces at t+dt;
// v(t+dt) = v(t+dt/2) + dt/2 a(t+dt). The same for omega with torque / moment of inertia.
// Fixed grains (ParticleStore::fixed) are skipped: they neither kick nor drift (those with a
// prescribed motion are placed by Simulation::place_fixed_groups).
#pragma once

#include "core/domain.hpp"
#include "particles/particle_store.hpp"

namespace gf {

/// What the drift loop can do besides kick and drift, saving two passes over the particles per
/// step: reset the forces for the next evaluation once the kick has used them (f = m g,
/// torque = 0), and find the largest squared displacement from the Verlet list's reference
/// positions (the rebuild test; minimum image in periodic boxes).
///
/// With `pending_kick` the loop first completes the previous step's second half kick, which the
/// caller deferred (post_force not called) because nothing read the velocities in between: the
/// same forces, the same two additions, so the same bits as post_force followed by pre_force,
/// in one pass over the particles instead of two.
struct DriftExtras {
  const Vec3* gravity = nullptr;  ///< reset the forces with this gravity; null: leave them
  const Vec3* x_ref = nullptr;    ///< reference positions (one per particle); null: no test
  bool pending_kick = false;      ///< complete the previous step's deferred post_force first
  double max_d2 = 0;              ///< out: the largest squared displacement, m^2
  /// Reference positions (one per particle, may be x_ref's) moved by the jump of each grain's
  /// wrap, so that a displacement measured from them is the grain's own also after it crossed a
  /// Lees-Edwards boundary (whose shift is the offset at the crossing, not the current one);
  /// null: left alone.
  Vec3* wrap_refs = nullptr;
};

struct VelocityVerlet {
  static constexpr const char* key = "velocity_verlet";
  /// First half kick and drift; wraps positions into the periodic box.
  static void pre_force(ParticleStore& p, const Domain& domain, double dt,
                        DriftExtras* extras = nullptr);
  /// Second half kick.
  static void post_force(ParticleStore& p, double dt);
};

/// Sets forces to m g and torques to zero (the start of each force evaluation).
void reset_forces(ParticleStore& p, const Vec3& gravity);

}  // namespace gf
