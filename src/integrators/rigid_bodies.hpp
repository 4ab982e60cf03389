// SPDX-License-Identifier: GPL-3.0-or-later
// Rotation of non-spherical grains in a store with shapes, around the velocity Verlet kicks.
//
// VelocityVerlet kicks omega of every particle with the scalar moment of inertia, which is exact
// for spheres, disks and (2D, rotation about z only) polygons. RigidBodies then
//   - spherocylinders: replaces that by the NO_SQUISH step of rigid_rotation.hpp (world angular
//     momentum L kicked by the torque, free rotation of the orientation with the body-frame
//     principal moments, omega = R I^-1 R^T L), which conserves L and the energy of free
//     rotation;
//   - polygons: turns the orientation by omega_z dt about z with the half-step omega (the
//     leapfrog drift of the angle).
// Fixed grains (ParticleStore::fixed) are skipped: their orientation, L and omega stay (or, for
// a group with a prescribed motion, are set by Simulation::place_fixed_groups).
#pragma once

#include "particles/particle_store.hpp"

namespace gf {

struct RigidBodies {
  /// After VelocityVerlet::pre_force: half kick of L + free rotation (spherocylinders), turn of
  /// the polygons.
  static void pre_force(ParticleStore& p, double dt);
  /// After VelocityVerlet::post_force: second half kick of L (spherocylinders).
  static void post_force(ParticleStore& p, double dt);
  /// Sets L = R I R^T omega for spherocylinders (after building or editing omega).
  static void init_angular_momentum(ParticleStore& p);
};

}  // namespace gf
