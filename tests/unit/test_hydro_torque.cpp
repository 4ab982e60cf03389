// SPDX-License-Identifier: GPL-3.0-or-later
// Hydrodynamic torque of CFD-DEM (src/coupling/cfd_dem/hydro_torque.hpp): the Stokes rotational
// resistances of a sphere (Kirchhoff's 8 pi mu a^3) and of spherocylinders (Tirado & Garcia de la
// Torre 1980 across the axis, the infinite cylinder along it), Dennis et al.'s inertia factor, and
// the split of the torque along and across a rod's axis, and the strain rate's part: a grain free
// of other torques turns on Jeffery's orbits.
//
// Tolerances: the references are the same formulas evaluated independently (Python's math
// module for the literals): 1e-12 relative is a few ulps of log/sqrt through ~10 operations;
// a wrong constant or exponent shows up at 1e-3 or more.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "coupling/cfd_dem/hydro_torque.hpp"

using namespace gf;
using namespace gf::cfd_dem;

namespace {
constexpr double kMu = 1e-3;  // Pa s
constexpr double kRel = 1e-12;
}  // namespace

TEST(HydroTorque, SphereResistanceIsKirchhoffs) {
  const double a = 0.5e-3;
  const RotationalResistance r = rotational_resistance(kMu, a, 0.0);
  const double kirchhoff = 8 * std::numbers::pi * kMu * a * a * a;
  EXPECT_NEAR(r.perp, kirchhoff, kRel * kirchhoff);
  EXPECT_EQ(r.par, r.perp);
}

TEST(HydroTorque, RodResistancesFollowTiradoGarciaDeLaTorre) {
  // {d, total length L, R_par = pi mu d^2 L, R_perp = pi mu L^3 / (3 (ln p + delta_perp))}:
  // Mahajan et al.'s rod (p = 4), the short end (p = 2) and a slender rod (p = 10).
  struct Case {
    double d, length, par, perp;
  };
  for (const Case& c : {Case{0.003, 0.012, 3.392920065876977e-10, 1.903956761082285e-09},
                        Case{0.002, 0.004, 5.026548245743670e-11, 1.404611533027015e-10},
                        Case{0.001, 0.010, 3.141592653589794e-11, 6.046925541933848e-10}}) {
    const double r = 0.5 * c.d, half = 0.5 * (c.length - c.d);
    const RotationalResistance res = rotational_resistance(kMu, r, half);
    EXPECT_NEAR(res.par, c.par, kRel * c.par) << "p = " << c.length / c.d;
    EXPECT_NEAR(res.perp, c.perp, kRel * c.perp) << "p = " << c.length / c.d;
    // Turning end over end is harder than a sphere of the rod's diameter turning, and harder
    // than spinning about the axis.
    EXPECT_GT(res.perp, rotational_resistance(kMu, r, 0.0).perp);
    EXPECT_GT(res.perp, res.par);
  }
}

TEST(HydroTorque, InertiaFactorIsStokesUpTo32AndContinuous) {
  EXPECT_EQ(rotational_inertia_factor(0.0), 1.0);
  EXPECT_EQ(rotational_inertia_factor(32.0), 1.0);
  // Dennis et al.'s two branches meet to 0.16 % at Re_R = 32.
  EXPECT_NEAR(rotational_inertia_factor(32.0000001), 1.001549224674157, kRel);
  EXPECT_NEAR(rotational_inertia_factor(100.0), 1.280202573495433, kRel);
}

TEST(HydroTorque, TorqueSplitsAlongAndAcrossTheAxis) {
  const double r = 1.5e-3, half = 4.5e-3, rho = 1000.0;
  const RotationalResistance res = rotational_resistance(kMu, r, half);
  const Vec3 axis{1, 0, 0};
  const Vec3 spin{0, 0, 0};
  const Vec3 omega{-1e-3, -2e-3, -3e-3};  // Re_R = rho d_v^2 |omega| / mu ~ 0.1: Stokes
  const double d_v = 2.0 * std::cbrt(r * r * (r + 1.5 * half));
  const Vec3 t = hydrodynamic_torque(res, axis, spin, Mat3{}, omega, rho, kMu, d_v);
  EXPECT_NEAR(t.x, 1e-3 * res.par, kRel * 1e-3 * res.par);
  EXPECT_NEAR(t.y, 2e-3 * res.perp, kRel * 2e-3 * res.perp);
  EXPECT_NEAR(t.z, 3e-3 * res.perp, kRel * 3e-3 * res.perp);
  // A grain turning with the fluid feels nothing.
  const Vec3 none = hydrodynamic_torque(res, axis, omega, Mat3{}, omega, rho, kMu, d_v);
  EXPECT_EQ(none.x, 0.0);
  EXPECT_EQ(none.y, 0.0);
  EXPECT_EQ(none.z, 0.0);
  // At Re_R = 100 (relative spin 100 mu / (rho d_v^2)) the torque is 1.28 times Stokes.
  const double w = 100.0 * kMu / (rho * d_v * d_v);
  const Vec3 fast =
      hydrodynamic_torque(res, Vec3{0, 0, 1}, Vec3{0, 0, w}, Mat3{}, Vec3{}, rho, kMu, d_v);
  EXPECT_NEAR(fast.z, 1.280202573495433 * res.par * w, 1e-9 * res.par * w);
}

namespace {
// A velocity gradient with every component non-zero (1/s): rotation and strain together.
Mat3 some_gradient() {
  Mat3 g;
  const double v[3][3] = {{0.3, 1.7, -0.4}, {-0.9, -0.5, 0.8}, {0.6, -1.1, 0.2}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) g.a[i][j] = v[i][j];
  return g;
}
}  // namespace

TEST(HydroTorque, RodsShapeFactorIsJefferysForItsAspectRatio) {
  EXPECT_EQ(rotational_resistance(kMu, 1e-3, 0.0).lambda, 0.0);  // sphere
  // p = L / d = 4: (16 - 1) / (16 + 1); p = 2: 3 / 5.
  EXPECT_NEAR(rotational_resistance(kMu, 1.5e-3, 4.5e-3).lambda, 15.0 / 17.0, kRel);
  EXPECT_NEAR(rotational_resistance(kMu, 1e-3, 1e-3).lambda, 0.6, kRel);
}

TEST(HydroTorque, TorqueFreeRodFollowsJefferysEquation) {
  // The torque vanishes at omega_J = Omega + lambda a x (E a) (Omega = curl(u) / 2, E the strain
  // rate), and then the axis turns as Jeffery's equation says, da/dt = omega_J x a
  // = W a + lambda (E a - (a . E a) a) with W = (g - g^T) / 2: two routes to the same vector,
  // equal to round-off (1e-12 of |g|).
  const Mat3 g = some_gradient(), e = strain_rate(g), w = 0.5 * (g + -1.0 * transpose(g));
  const RotationalResistance res = rotational_resistance(kMu, 1.5e-3, 4.5e-3);
  const double rho = 1000.0, d_v = 5e-4;  // Re_R = rho d_v^2 |rel| / mu < 1: Stokes
  const Vec3 a = normalized(Vec3{0.36, -0.48, 0.8});
  const Vec3 spin = rotation_rate(g);
  const Vec3 omega_j = spin + res.lambda * cross(a, e * a);
  const Vec3 t = hydrodynamic_torque(res, a, spin, e, omega_j, rho, kMu, d_v);
  EXPECT_LT(norm(t), kRel * res.perp);
  const Vec3 da = cross(omega_j, a);
  const Vec3 jeffery = w * a + res.lambda * (e * a - dot(a, e * a) * a);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(da[k], jeffery[k], 1e-12) << k;
  // Held still (omega = 0), the rod feels R_perp times the Jeffery rate across its axis plus
  // R_par times the spin along it.
  const Vec3 still = hydrodynamic_torque(res, a, spin, e, Vec3{}, rho, kMu, d_v);
  const Vec3 across = omega_j - dot(omega_j, a) * a;
  const Vec3 expected = res.perp * across + res.par * dot(spin, a) * a;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(still[k], expected[k], kRel * res.perp) << k;
  // A sphere feels no strain: only the rotation counts.
  const RotationalResistance ball = rotational_resistance(kMu, 1e-3, 0.0);
  const Vec3 s = hydrodynamic_torque(ball, a, spin, e, Vec3{}, rho, kMu, d_v);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(s[k], ball.perp * spin[k], kRel * ball.perp) << k;
}
