// SPDX-License-Identifier: GPL-3.0-or-later
// Loops of the rigid-body rotation kernels over bodies, run through core/exec.
#include "integrators/rigid_rotation.hpp"

#include "core/exec.hpp"

namespace gf {

void rigid_rotation_pre_force(std::size_t n, Quat* q, Vec3* angular_momentum, Vec3* omega,
                              const Vec3* torque, const Vec3* inertia, double dt) {
  exec::parallel_for(static_cast<exec::index_t>(n), [&](exec::index_t i) {
    rigid_rotation_pre_force(q[i], angular_momentum[i], omega[i], torque[i], inertia[i], dt);
  });
}

void rigid_rotation_post_force(std::size_t n, const Quat* q, Vec3* angular_momentum, Vec3* omega,
                               const Vec3* torque, const Vec3* inertia, double dt) {
  exec::parallel_for(static_cast<exec::index_t>(n), [&](exec::index_t i) {
    rigid_rotation_post_force(q[i], angular_momentum[i], omega[i], torque[i], inertia[i], dt);
  });
}

}  // namespace gf
