// SPDX-License-Identifier: GPL-3.0-or-later
// Velocity Verlet for translation and rotation of spheres (Swope et al., J. Chem. Phys. 76
// (1982) 637): v(t+dt/2) = v(t) + dt/2 a(t); x(t+dt) = x(t) + dt v(t+dt/2); forces at t+dt;
// v(t+dt) = v(t+dt/2) + dt/2 a(t+dt). The same for omega with torque / moment of inertia.
#pragma once

#include "core/domain.hpp"
#include "particles/particle_store.hpp"

namespace gf {

struct VelocityVerlet {
  static constexpr const char* key = "velocity_verlet";
  /// First half kick and drift; wraps positions into the periodic box.
  static void pre_force(ParticleStore& p, const Domain& domain, double dt);
  /// Second half kick.
  static void post_force(ParticleStore& p, double dt);
};

/// Sets forces to m g and torques to zero (the start of each force evaluation).
void reset_forces(ParticleStore& p, const Vec3& gravity);

}  // namespace gf
