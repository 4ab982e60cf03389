// SPDX-License-Identifier: GPL-3.0-or-later
// Quaternions, 3x3 matrices and the rigid-body rotation scheme against the free symmetric top.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/mat3.hpp"
#include "core/quaternion.hpp"
#include "integrators/rigid_rotation.hpp"

using namespace gf;

TEST(RigidRotationAlgebra, QuaternionAndMatrix) {
  const Vec3 axis = normalized(Vec3{1, 2, 3});
  const Quat q = quat_from_axis_angle(axis, 0.7);
  const Vec3 b{0.3, -1.1, 0.4};
  // Rodrigues' formula as the independent reference.
  const Vec3 rod = std::cos(0.7) * b + std::sin(0.7) * cross(axis, b) +
                   (1 - std::cos(0.7)) * dot(axis, b) * axis;
  const Vec3 r = rotate(q, b);
  EXPECT_NEAR(norm(r - rod), 0.0, 1e-15);
  EXPECT_NEAR(norm(to_matrix(q) * b - rod), 0.0, 1e-15);
  EXPECT_NEAR(norm(rotate_inverse(q, r) - b), 0.0, 1e-15);
  // Composition: rotating by q2 q1 = q1 then q2.
  const Quat q2 = quat_from_axis_angle({0, 0, 1}, -1.3);
  EXPECT_NEAR(norm(rotate(q2 * q, b) - rotate(q2, rotate(q, b))), 0.0, 1e-15);
  // R R^T = 1, det R = 1.
  const Mat3 rr = to_matrix(q) * transpose(to_matrix(q));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(rr.a[i][j], i == j ? 1.0 : 0.0, 1e-15);
  EXPECT_NEAR(determinant(to_matrix(q)), 1.0, 1e-15);
  // dq/dt = 1/2 q (0, w_b) against a finite difference of q(t) = q0 (axis e, w t).
  const Vec3 wb{0.2, -0.5, 0.9};
  const double h = 1e-6, wn = norm(wb);
  const Quat qp = q * quat_from_axis_angle(wb / wn, wn * h),
             qm = q * quat_from_axis_angle(wb / wn, -wn * h);
  const Quat fd = (0.5 / h) * (qp + (-1.0) * qm), an = quat_derivative(q, wb);
  EXPECT_NEAR(fd.w - an.w, 0.0, 1e-9);
  EXPECT_NEAR(fd.x - an.x, 0.0, 1e-9);
  EXPECT_NEAR(fd.z - an.z, 0.0, 1e-9);
  // Inverse of a symmetric (inertia) tensor: R diag(1,2,3) R^T.
  const Mat3 in = to_matrix(q) * Mat3::diagonal({1, 2, 3}) * transpose(to_matrix(q));
  const Mat3 id = in * inverse_symmetric(in);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(id.a[i][j], i == j ? 1.0 : 0.0, 1e-14);
}

namespace {
// Torque-free symmetric top I1 = I2 = 1, I3 = 2 (kg m^2), unit-free. Euler's equations give, in
// the body frame, w3 = const and (w1, w2) turning at Omega = (I3 - I1)/I1 w3:
//   w1 = A cos(Omega t + phi0), w2 = A sin(Omega t + phi0);
// in the world frame the symmetry axis e3 precesses about the fixed L at the rate |L| / I1.
struct TopErrors {
  double body, axis;
};
// `split`: the NO_SQUISH splitting (which asymmetric bodies take) instead of the closed-form
// step that a symmetric top gets.
TopErrors symmetric_top(double dt, double t_end, bool split) {
  const Vec3 inertia{1, 1, 2};
  const Vec3 w0{0.6, 0.2, 1.5};  // body frame
  Quat q = quat_from_axis_angle(normalized(Vec3{0.3, -0.4, 1}), 0.4);
  const Vec3 L = rotate(q, Vec3{w0.x * inertia.x, w0.y * inertia.y, w0.z * inertia.z});
  const Vec3 e3_0 = rotate(q, Vec3{0, 0, 1});
  const double omega_b = (inertia.z - inertia.x) / inertia.x * w0.z;
  const double amp = std::hypot(w0.x, w0.y), phi0 = std::atan2(w0.y, w0.x);
  const double prec = norm(L) / inertia.x;
  const Vec3 lhat = normalized(L);
  TopErrors err{0, 0};
  const long n = std::lround(t_end / dt);
  Vec3 Lw = L, omega;
  for (long s = 1; s <= n; ++s) {
    if (split) {
      const Vec3 inverse = detail::inverse_inertia(inertia);
      detail::no_squish_rotation(q, Lw, inverse, dt);
      omega = detail::omega_world(q, Lw, inverse);
    } else {
      rigid_rotation_pre_force(q, Lw, omega, Vec3{}, inertia, dt);
      rigid_rotation_post_force(q, Lw, omega, Vec3{}, inertia, dt);
    }
    const double t = s * dt;
    const Vec3 wb = rotate_inverse(q, omega);
    const Vec3 wb_exact{amp * std::cos(omega_b * t + phi0), amp * std::sin(omega_b * t + phi0),
                        w0.z};
    err.body = std::max(err.body, norm(wb - wb_exact));
    const double ang = prec * t;  // Rodrigues rotation of e3(0) about L
    const Vec3 e3_exact = std::cos(ang) * e3_0 + std::sin(ang) * cross(lhat, e3_0) +
                          (1 - std::cos(ang)) * dot(lhat, e3_0) * lhat;
    err.axis = std::max(err.axis, norm(rotate(q, Vec3{0, 0, 1}) - e3_exact));
  }
  return err;
}
}  // namespace

// Against the closed form over t = 20 (about 5 body-frame nutation periods). A symmetric top's
// free step is the closed form itself: exact to round-off (2000 steps of a few ulps each:
// 1e-14 measured, 1e-12 asserted). dt = 0.01 turns the top by a/2 = 0.008 per step about L (the
// precession's Taylor polynomials), dt = 0.05 by 0.04 (the library's sine and cosine).
TEST(RigidRotation, SymmetricTopIsExact) {
  for (const double dt : {0.01, 0.05}) {
    const TopErrors e = symmetric_top(dt, 20.0, false);
    std::printf(
        "[ measured ] symmetric top, t = 20, dt = %g: max|w_b err| %.2e, max|e3 err| %.2e\n", dt,
        e.body, e.axis);
    EXPECT_LT(e.body, 1e-12) << dt;
    EXPECT_LT(e.axis, 1e-12) << dt;
  }
}

// The step's renormalisation (one Newton step for 1/|q|) squares the norm's error: 1e-6 off
// goes to ~1e-12, then to round-off; a unit quaternion stays within round-off of unit.
TEST(RigidRotationAlgebra, RenormalizedSquaresTheNormError) {
  const Quat u = quat_from_axis_angle(normalized(Vec3{0.3, -0.4, 1}), 0.4);
  const Quat q = (1 + 1e-6) * u;
  const Quat q1 = detail::renormalized(q), q2 = detail::renormalized(q1);
  EXPECT_NEAR(std::sqrt(norm2(q1)), 1.0, 2e-12);
  EXPECT_GT(std::abs(std::sqrt(norm2(q1)) - 1.0), 1e-13);  // one step is not the exact norm
  EXPECT_NEAR(std::sqrt(norm2(q2)), 1.0, 4e-16);
  EXPECT_NEAR(std::sqrt(norm2(detail::renormalized(u))), 1.0, 4e-16);
  EXPECT_NEAR(q2.x / q2.w, u.x / u.w, 1e-15);  // the direction is kept
}

// The NO_SQUISH splitting on the same top is of second order: the error at dt = 0.01 is ~1e-4
// and falls by 4 when dt halves; the asserted bounds leave a factor ~3 over the measured values.
TEST(RigidRotation, NoSquishSplittingIsSecondOrder) {
  const TopErrors e1 = symmetric_top(0.01, 20.0, true), e2 = symmetric_top(0.005, 20.0, true);
  const double order_body = std::log2(e1.body / e2.body), order_axis = std::log2(e1.axis / e2.axis);
  std::printf(
      "[ measured ] symmetric top, t = 20: dt=0.01 max|w_b err| %.2e, max|e3 err| %.2e; "
      "dt=0.005 %.2e, %.2e; orders %.2f, %.2f\n",
      e1.body, e1.axis, e2.body, e2.axis, order_body, order_axis);
  EXPECT_LT(e1.body, 3e-3);
  EXPECT_LT(e1.axis, 3e-3);
  EXPECT_NEAR(order_body, 2.0, 0.2);
  EXPECT_NEAR(order_axis, 2.0, 0.2);
}

// Asymmetric body I = (1, 2, 3) started near the unstable middle axis (tumbling), 1e5 steps of
// dt = 0.01 (|w| dt ~ 0.01): |L| (body frame) is kept to round-off, the energy error is bounded
// (no drift: its maximum over the second half is not larger than over the first half by more
// than 10 %) and small (O(dt^2): 7e-7 relative measured, 1e-5 asserted).
TEST(RigidRotation, AsymmetricConservation) {
  const Vec3 inertia{1, 2, 3};
  Quat q = quat_from_axis_angle(normalized(Vec3{1, 1, 0}), 0.3);
  Vec3 L = rotate(q, Vec3{0.05, 2.0, 0.1});
  const double e0 = rotational_energy(q, L, inertia), l0 = norm(rotate_inverse(q, L));
  double max_de1 = 0, max_de2 = 0, max_dl = 0;
  Vec3 omega;
  const long n = 100000;
  for (long s = 0; s < n; ++s) {
    rigid_rotation_pre_force(q, L, omega, Vec3{}, inertia, 0.01);
    rigid_rotation_post_force(q, L, omega, Vec3{}, inertia, 0.01);
    const double de = std::abs(rotational_energy(q, L, inertia) - e0) / e0;
    (s < n / 2 ? max_de1 : max_de2) = std::max(s < n / 2 ? max_de1 : max_de2, de);
    max_dl = std::max(max_dl, std::abs(norm(rotate_inverse(q, L)) - l0) / l0);
  }
  std::printf(
      "[ measured ] asymmetric body, 1e5 steps: max rel. energy error %.2e (first half) %.2e "
      "(second half), max rel. |L_body| error %.2e\n",
      max_de1, max_de2, max_dl);
  EXPECT_LT(max_de1, 1e-5);
  EXPECT_LT(max_de2, 1.1 * max_de1 + 1e-12);
  EXPECT_LT(max_dl, 1e-12);
}

// With a constant world torque, L(t) = L0 + T t exactly (the kicks are exact), and the loop
// version over several bodies equals the per-body kernel.
TEST(RigidRotation, TorqueKicksAndLoop) {
  const Vec3 inertia{0.5, 0.7, 0.9}, torque{0.1, -0.2, 0.3};
  Quat q[3];
  Vec3 L[3], w[3], T[3], I[3];
  for (int b = 0; b < 3; ++b) {
    q[b] = quat_from_axis_angle(normalized(Vec3{1.0 + b, 0.5, -0.2}), 0.1 * b);
    L[b] = {0.3 * b, 0.1, -0.4};
    T[b] = torque;
    I[b] = inertia;
  }
  Quat q1 = q[1];
  Vec3 L1 = L[1], w1;
  const double dt = 1e-3;
  for (int s = 0; s < 1000; ++s) {
    rigid_rotation_pre_force(3, q, L, w, T, I, dt);
    rigid_rotation_post_force(3, q, L, w, T, I, dt);
    rigid_rotation_pre_force(q1, L1, w1, torque, inertia, dt);
    rigid_rotation_post_force(q1, L1, w1, torque, inertia, dt);
  }
  EXPECT_NEAR(norm(L[1] - (Vec3{0.3, 0.1, -0.4} + 1.0 * torque)), 0.0, 1e-12);
  EXPECT_EQ(q[1].w, q1.w);
  EXPECT_EQ(L[1].x, L1.x);
  EXPECT_NEAR(norm2(q[2]), 1.0, 1e-15);
}

// cos_sin: the small-angle polynomials agree with the library to a few ulps (4e-16 relative
// asserted; measured 1.1e-16), and larger angles are the library's.
TEST(RigidRotationAlgebra, CosSinMatchesTheLibrary) {
  double worst = 0;
  for (int k = -4000; k <= 4000; ++k) {
    const double x = 0.0205 * k / 4000 + 1e-7;
    double c = 0, s = 0;
    cos_sin(x, c, s);
    worst = std::max({worst, std::abs(c - std::cos(x)), std::abs(s - std::sin(x)) / std::abs(x)});
  }
  std::printf("[ measured ] cos_sin: largest relative difference from the library %.2e\n", worst);
  EXPECT_LT(worst, 4e-16);
  double c = 0, s = 0;
  cos_sin(2.5, c, s);
  EXPECT_EQ(c, std::cos(2.5));
  EXPECT_EQ(s, std::sin(2.5));
}

// A symmetric top at rest stays at rest (no 0/0 in the precession axis L/|L|).
TEST(RigidRotation, SymmetricTopAtRest) {
  Quat q = quat_from_axis_angle(normalized(Vec3{1, 2, 3}), 0.7);
  const Quat q0 = q;
  Vec3 L{}, omega{1, 1, 1};
  rigid_rotation_pre_force(q, L, omega, Vec3{}, Vec3{2, 2, 1}, 0.01);
  EXPECT_NEAR(norm(Vec3{q.x - q0.x, q.y - q0.y, q.z - q0.z}) + std::abs(q.w - q0.w), 0.0, 1e-15);
  EXPECT_EQ(norm(omega), 0.0);
}
