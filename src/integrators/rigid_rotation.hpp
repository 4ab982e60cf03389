// SPDX-License-Identifier: GPL-3.0-or-later
// Rotation of rigid bodies with a diagonal body-frame inertia tensor, for velocity-Verlet-type
// stepping: L += dt/2 T; free rotation over dt; forces; L += dt/2 T.
//
// State per body: the unit quaternion q (body -> world) and the world-frame angular momentum L.
// The free rotation uses the symmetric splitting of the free rigid-body Hamiltonian
//   H = L1^2/(2 I1) + L2^2/(2 I2) + L3^2/(2 I3)   (L_k body-frame components)
// into three exactly solvable rotations about the body axes, composed as
//   R1(dt/2) R2(dt/2) R3(dt) R2(dt/2) R1(dt/2),
// which is the NO_SQUISH free-rotation step of Miller, Eleftheriou, Pattnaik, Ndirango, Newns
// and Martyna, J. Chem. Phys. 116 (2002) 8649, eqs. (23)-(25), in quaternion form (also
// Dullweber, Leimkuhler and McLachlan, J. Chem. Phys. 107 (1997) 5840). Each sub-flow about
// body axis k by the angle phi = h L_k / I_k maps q -> q (cos(phi/2), sin(phi/2) e_k) and
// L_body -> rot(e_k, -phi) L_body, so the world L is unchanged exactly, |L| is conserved, the
// step is symplectic and time-reversible (second order), and the energy error stays bounded.
#pragma once

#include <cmath>
#include <cstddef>

#include "core/host_device.hpp"
#include "core/quaternion.hpp"
#include "core/vec3.hpp"

namespace gf {

/// Kick of the world-frame angular momentum L (kg m^2/s) by the torque (N m) over h (s).
GF_HOST_DEVICE inline void rotation_kick(Vec3& angular_momentum, const Vec3& torque, double h) {
  angular_momentum += h * torque;
}

/// Angular velocity (rad/s, world frame) omega = R I^-1 R^T L of a body with principal
/// moments `inertia` (kg m^2, body frame, all > 0).
GF_HOST_DEVICE inline Vec3 angular_velocity_world(const Quat& q, const Vec3& angular_momentum,
                                                  const Vec3& inertia) {
  const Vec3 lb = rotate_inverse(q, angular_momentum);
  return rotate(q, Vec3{lb.x / inertia.x, lb.y / inertia.y, lb.z / inertia.z});
}

/// Rotational kinetic energy (J) 1/2 L_b . I^-1 L_b.
GF_HOST_DEVICE inline double rotational_energy(const Quat& q, const Vec3& angular_momentum,
                                               const Vec3& inertia) {
  const Vec3 lb = rotate_inverse(q, angular_momentum);
  return 0.5 * (lb.x * lb.x / inertia.x + lb.y * lb.y / inertia.y + lb.z * lb.z / inertia.z);
}

namespace detail {
/// Exact flow of L_k^2 / (2 I_k) over h: rotation about body axis k (0, 1, 2).
GF_HOST_DEVICE inline void body_axis_rotation(int k, Quat& q, Vec3& lb, double inertia_k,
                                              double h) {
  const double phi = h * lb[k] / inertia_k;
  const double c = std::cos(phi), s = std::sin(phi);
  const double ch = std::cos(0.5 * phi), sh = std::sin(0.5 * phi);
  Quat r{ch, 0, 0, 0};
  if (k == 0)
    r.x = sh;
  else if (k == 1)
    r.y = sh;
  else
    r.z = sh;
  q = q * r;
  // L_body -> rot(e_k, -phi) L_body.
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  const double li = lb[i], lj = lb[j];
  lb[i] = c * li + s * lj;
  lb[j] = -s * li + c * lj;
}
}  // namespace detail

/// Torque-free rotation of orientation q over dt (s) at constant world angular momentum L
/// (kg m^2/s); `inertia` = principal moments (kg m^2). q is renormalised.
GF_HOST_DEVICE inline void free_rotation(Quat& q, const Vec3& angular_momentum, const Vec3& inertia,
                                         double dt) {
  Vec3 lb = rotate_inverse(q, angular_momentum);
  detail::body_axis_rotation(0, q, lb, inertia.x, 0.5 * dt);
  detail::body_axis_rotation(1, q, lb, inertia.y, 0.5 * dt);
  detail::body_axis_rotation(2, q, lb, inertia.z, dt);
  detail::body_axis_rotation(1, q, lb, inertia.y, 0.5 * dt);
  detail::body_axis_rotation(0, q, lb, inertia.x, 0.5 * dt);
  q = normalized(q);
}

/// First half of a velocity-Verlet step for one body: L += dt/2 T(t); free rotation over dt;
/// omega (world, rad/s) updated for the force evaluation at t + dt.
GF_HOST_DEVICE inline void rigid_rotation_pre_force(Quat& q, Vec3& angular_momentum, Vec3& omega,
                                                    const Vec3& torque, const Vec3& inertia,
                                                    double dt) {
  rotation_kick(angular_momentum, torque, 0.5 * dt);
  free_rotation(q, angular_momentum, inertia, dt);
  omega = angular_velocity_world(q, angular_momentum, inertia);
}

/// Second half: L += dt/2 T(t + dt); omega updated.
GF_HOST_DEVICE inline void rigid_rotation_post_force(const Quat& q, Vec3& angular_momentum,
                                                     Vec3& omega, const Vec3& torque,
                                                     const Vec3& inertia, double dt) {
  rotation_kick(angular_momentum, torque, 0.5 * dt);
  omega = angular_velocity_world(q, angular_momentum, inertia);
}

/// Loops of the two halves over n bodies (arrays of length n), through core/exec.
void rigid_rotation_pre_force(std::size_t n, Quat* q, Vec3* angular_momentum, Vec3* omega,
                              const Vec3* torque, const Vec3* inertia, double dt);
void rigid_rotation_post_force(std::size_t n, const Quat* q, Vec3* angular_momentum, Vec3* omega,
                               const Vec3* torque, const Vec3* inertia, double dt);

}  // namespace gf
