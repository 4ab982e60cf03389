// SPDX-License-Identifier: GPL-3.0-or-later
// Rotation of rigid bodies with a diagonal body-frame inertia tensor, for velocity-Verlet-type
// stepping: L += dt/2 T; free rotation over dt; forces; L += dt/2 T.
//
// State per body: the unit quaternion q (body -> world) and the world-frame angular momentum L.
// Symmetric tops (spherocylinders) take an exact free rotation (below). Other bodies take the
// symmetric splitting of the free rigid-body Hamiltonian
//   H = L1^2/(2 I1) + L2^2/(2 I2) + L3^2/(2 I3)   (L_k body-frame components)
// into three exactly solvable rotations about the body axes, composed as
//   R1(dt/2) R2(dt/2) R3(dt) R2(dt/2) R1(dt/2),
// which is the NO_SQUISH free-rotation step of Miller, Eleftheriou, Pattnaik, Ndirango, Newns
// and Martyna, J. Chem. Phys. 116 (2002) 8649, eqs. (23)-(25), in quaternion form (also
// Dullweber, Leimkuhler and McLachlan, J. Chem. Phys. 107 (1997) 5840). Each sub-flow about
// body axis k by the angle phi = h L_k / I_k maps q -> q (cos(phi/2), sin(phi/2) e_k) and
// L_body -> rot(e_k, -phi) L_body, so the world L is unchanged exactly, |L| is conserved, the
// step is symplectic and time-reversible (second order), and the energy error stays bounded.
//
// Bodies with I1 = I2 (symmetric tops about body axis 3: spherocylinders) need no splitting: the
// free motion is known in closed form (e.g. Landau & Lifshitz, Mechanics, sect. 33): the body
// turns about the fixed L at the rate |L| / I1 (precession) and about its own axis 3 at the rate
// (1/I3 - 1/I1) L3 (L3 = L . R e3, constant), so over dt
//   q -> (cos(a/2), sin(a/2) L/|L|) q (cos(b/2), sin(b/2) e3),  a = |L| dt / I1,
//                                                                 b = (1/I3 - 1/I1) L3 dt.
// That step is exact (the torque kicks are the only splitting left: still symplectic, second
// order), and it costs two small rotations instead of five. The test is I1 == I2 exactly (the
// shape builder sets both from one value): a body whose I1 and I2 differ in the last bit takes
// NO_SQUISH, with its O(dt^2) error.
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

namespace detail {
/// 1 / inertia, per component: the steps below multiply (a division's latency is that of four
/// multiplications, and they stand in one dependent chain). A symmetric top (I1 = I2) takes
/// two divisions, not three.
GF_HOST_DEVICE inline Vec3 inverse_inertia(const Vec3& inertia) {
  const double ix = 1.0 / inertia.x;
  return {ix, inertia.y == inertia.x ? ix : 1.0 / inertia.y, 1.0 / inertia.z};
}
/// omega (world) = R I^-1 R^T L from the inverse principal moments; for a symmetric top
/// (I1 = I2) the same as L / I1 + (1/I3 - 1/I1) (L . a) a with a its axis.
GF_HOST_DEVICE inline Vec3 omega_world(const Quat& q, const Vec3& angular_momentum,
                                       const Vec3& inverse_inertia) {
  if (inverse_inertia.x == inverse_inertia.y) {
    const Vec3 a = rotate_z(q);
    return inverse_inertia.x * angular_momentum +
           ((inverse_inertia.z - inverse_inertia.x) * dot(angular_momentum, a)) * a;
  }
  const Vec3 lb = rotate_inverse(q, angular_momentum);
  return rotate(q,
                Vec3{lb.x * inverse_inertia.x, lb.y * inverse_inertia.y, lb.z * inverse_inertia.z});
}
}  // namespace detail

/// Angular velocity (rad/s, world frame) omega = R I^-1 R^T L of a body with principal
/// moments `inertia` (kg m^2, body frame, all > 0).
GF_HOST_DEVICE inline Vec3 angular_velocity_world(const Quat& q, const Vec3& angular_momentum,
                                                  const Vec3& inertia) {
  return detail::omega_world(q, angular_momentum, detail::inverse_inertia(inertia));
}

/// Rotational kinetic energy (J) 1/2 L_b . I^-1 L_b.
GF_HOST_DEVICE inline double rotational_energy(const Quat& q, const Vec3& angular_momentum,
                                               const Vec3& inertia) {
  const Vec3 lb = rotate_inverse(q, angular_momentum);
  return 0.5 * (lb.x * lb.x / inertia.x + lb.y * lb.y / inertia.y + lb.z * lb.z / inertia.z);
}

namespace detail {
/// Exact flow of L_k^2 / (2 I_k) over h: rotation about body axis k (0, 1, 2).
GF_HOST_DEVICE inline void body_axis_rotation(int k, Quat& q, Vec3& lb, double inverse_inertia_k,
                                              double h) {
  const double phi = h * lb[k] * inverse_inertia_k;
  // One cosine and sine, of the half angle (the quaternion's); the angle's from them.
  double ch = 1, sh = 0;
  cos_sin(0.5 * phi, ch, sh);
  const double c = 1 - 2 * sh * sh, s = 2 * sh * ch;
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

/// Back onto the unit sphere a quaternion whose norm is 1 to a few round-offs (a product of unit
/// quaternions): one Newton step for 1/|q|, q (3 - |q|^2) / 2, which leaves |q| - 1 at the square
/// of what it was (below round-off) with multiplications only, instead of a root and a division
/// in the step's dependent chain. A norm off by more converges over a few steps.
GF_HOST_DEVICE inline Quat renormalized(const Quat& q) {
  return (1.5 - 0.5 * norm2(q)) * q;
}

/// Exact free rotation of a symmetric top (inverse_inertia.x == inverse_inertia.y) over dt.
GF_HOST_DEVICE inline void symmetric_top_rotation(Quat& q, const Vec3& angular_momentum,
                                                  const Vec3& inverse_inertia, double dt) {
  // Spin about the body's axis 3 (right factor), by b = (1/I3 - 1/I1) L3 dt.
  const double l3 = dot(angular_momentum, rotate_z(q));
  double cb = 1, sb = 0;
  cos_sin(0.5 * dt * (inverse_inertia.z - inverse_inertia.x) * l3, cb, sb);
  // Precession about L (left factor), by a = |L| dt / I1: (cos(a/2), sin(a/2) / |L| L). With
  // x = a/2 = h |L|, h = dt / (2 I1): sin(x) / |L| = h sin(x)/x, and for the small x of a time
  // step both cos x and sin(x)/x are Taylor polynomials in x^2 = h^2 |L|^2 (exact to round-off
  // for |x| < 0.02, as in cos_sin): no root and no division.
  const double half = 0.5 * dt * inverse_inertia.x;
  const double l2 = norm2(angular_momentum);
  const double x2 = half * half * l2;
  double ca = 1, f = half;
  if (x2 < 0.02 * 0.02) {
    ca = 1 + x2 * (-0.5 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320))));
    f = half * (1 + x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040))));
  } else {
    const double l = std::sqrt(l2);
    double sa = 0;
    cos_sin(half * l, ca, sa);
    f = sa / l;
  }
  const Quat precession{ca, f * angular_momentum.x, f * angular_momentum.y, f * angular_momentum.z};
  q = renormalized(precession * q * Quat{cb, 0, 0, sb});
}

/// NO_SQUISH free rotation (any body) over dt.
GF_HOST_DEVICE inline void no_squish_rotation(Quat& q, const Vec3& angular_momentum,
                                              const Vec3& inverse_inertia, double dt) {
  Vec3 lb = rotate_inverse(q, angular_momentum);
  body_axis_rotation(0, q, lb, inverse_inertia.x, 0.5 * dt);
  body_axis_rotation(1, q, lb, inverse_inertia.y, 0.5 * dt);
  body_axis_rotation(2, q, lb, inverse_inertia.z, dt);
  body_axis_rotation(1, q, lb, inverse_inertia.y, 0.5 * dt);
  body_axis_rotation(0, q, lb, inverse_inertia.x, 0.5 * dt);
  q = normalized(q);
}

GF_HOST_DEVICE inline void free_rotation(Quat& q, const Vec3& angular_momentum,
                                         const Vec3& inverse_inertia, double dt) {
  if (inverse_inertia.x == inverse_inertia.y)
    symmetric_top_rotation(q, angular_momentum, inverse_inertia, dt);
  else
    no_squish_rotation(q, angular_momentum, inverse_inertia, dt);
}
}  // namespace detail

/// Torque-free rotation of orientation q over dt (s) at constant world angular momentum L
/// (kg m^2/s); `inertia` = principal moments (kg m^2): exact for I1 = I2, NO_SQUISH otherwise.
/// q is renormalised.
GF_HOST_DEVICE inline void free_rotation(Quat& q, const Vec3& angular_momentum, const Vec3& inertia,
                                         double dt) {
  detail::free_rotation(q, angular_momentum, detail::inverse_inertia(inertia), dt);
}

/// First half of a velocity-Verlet step for one body: L += dt/2 T(t); free rotation over dt;
/// omega (world, rad/s) updated for the force evaluation at t + dt.
GF_HOST_DEVICE inline void rigid_rotation_pre_force(Quat& q, Vec3& angular_momentum, Vec3& omega,
                                                    const Vec3& torque, const Vec3& inertia,
                                                    double dt) {
  rotation_kick(angular_momentum, torque, 0.5 * dt);
  const Vec3 inverse_inertia = detail::inverse_inertia(inertia);
  detail::free_rotation(q, angular_momentum, inverse_inertia, dt);
  omega = detail::omega_world(q, angular_momentum, inverse_inertia);
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
