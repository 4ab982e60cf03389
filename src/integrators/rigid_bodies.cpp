// SPDX-License-Identifier: GPL-3.0-or-later
// Loops of the rigid-body rotation of spherocylinders and the turn of polygons.
#include "integrators/rigid_bodies.hpp"

#include "core/exec.hpp"
#include "integrators/rigid_rotation.hpp"

namespace gf {

void RigidBodies::pre_force(ParticleStore& p, double dt) {
  if (!p.has_shapes()) return;
  const std::int32_t* shape = p.shape();
  Quat* q = p.orientation();
  Vec3* L = p.angular_momentum();
  Vec3* w = p.omega();
  const Vec3* t = p.torque();
  const Vec3* inertia = p.inertia_body();
  const std::int32_t* fixed = p.fixed();  // fixed grains keep their orientation
  exec::parallel_for(static_cast<exec::index_t>(p.size()), [&](exec::index_t i) {
    if (fixed != nullptr && fixed[i] != 0) return;
    switch (static_cast<ShapeCode>(shape[i])) {
      case ShapeCode::Spherocylinder:
        rigid_rotation_pre_force(q[i], L[i], w[i], t[i], inertia[i], dt);
        break;
      case ShapeCode::Polygon:
        q[i] = turn_about_z(q[i], w[i].z * dt);
        break;
      default:
        break;
    }
  });
}

void RigidBodies::post_force(ParticleStore& p, double dt) {
  if (!p.has_shapes()) return;
  const std::int32_t* shape = p.shape();
  const Quat* q = p.orientation();
  Vec3* L = p.angular_momentum();
  Vec3* w = p.omega();
  const Vec3* t = p.torque();
  const Vec3* inertia = p.inertia_body();
  const std::int32_t* fixed = p.fixed();  // fixed grains keep L = 0, omega = 0
  exec::parallel_for(static_cast<exec::index_t>(p.size()), [&](exec::index_t i) {
    if (fixed != nullptr && fixed[i] != 0) return;
    if (static_cast<ShapeCode>(shape[i]) == ShapeCode::Spherocylinder)
      rigid_rotation_post_force(q[i], L[i], w[i], t[i], inertia[i], dt);
  });
}

void RigidBodies::init_angular_momentum(ParticleStore& p) {
  if (!p.has_shapes()) return;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (static_cast<ShapeCode>(p.shape()[i]) != ShapeCode::Spherocylinder) continue;
    const Quat& q = p.orientation()[i];
    const Vec3 wb = rotate_inverse(q, p.omega()[i]);
    const Vec3& I = p.inertia_body()[i];
    p.angular_momentum()[i] = rotate(q, Vec3{I.x * wb.x, I.y * wb.y, I.z * wb.z});
  }
}

}  // namespace gf
