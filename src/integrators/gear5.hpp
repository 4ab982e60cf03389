// SPDX-License-Identifier: GPL-3.0-or-later
// Gear's 6-value (fifth-order) predictor-corrector for x'' = a(x, v, t).
//
// With the scaled derivatives r_k = dt^k / k! d^k x/dt^k (k = 0..5) a step is
//   predict:  r_k <- sum_{j >= k} C(j, k) r_j                    (Taylor / Pascal triangle)
//   evaluate: a_c = a(x_p, v_p, t + dt), Delta = dt^2/2 (a_c - a_p)
//   correct:  r_k <- r_k + c_k Delta,
//   c = (c0, 251/360, 1, 11/18, 1/6, 1/60)
// (Gear, Numerical Initial Value Problems in ODEs, 1971; Allen & Tildesley, Computer Simulation
// of Liquids, 1987, sec. 3.2 and appendix E, table E.2). c0 = 3/20 is Gear's value for forces
// that depend on positions only; c0 = 3/16 for forces that also depend on velocities. DEM
// contact forces carry a viscous dashpot (velocity dependent), so 3/16 is the default here
// (GearForces::VelocityDependent); tests/unit/test_gear.cpp measures both.
// One force evaluation per step, as velocity Verlet. The state keeps the unscaled derivatives in
// SI units, so dt may change between steps only at the cost of the method's accuracy.
#pragma once

#include <cstddef>

#include "core/domain.hpp"
#include "core/host_device.hpp"
#include "core/vec3.hpp"
#include "particles/particle_store.hpp"

namespace gf {

enum class GearForces { PositionOnly, VelocityDependent };

struct Gear5Coefficients {
  double c[6];
};

/// Gear's corrector coefficients for second-order equations, 6 values.
GF_HOST_DEVICE constexpr Gear5Coefficients gear5_coefficients(
    GearForces kind = GearForces::VelocityDependent) {
  return {{kind == GearForces::VelocityDependent ? 3.0 / 16.0 : 3.0 / 20.0, 251.0 / 360.0, 1.0,
           11.0 / 18.0, 1.0 / 6.0, 1.0 / 60.0}};
}

/// Per-body state: d[0] = x (m), d[1] = v (m/s), d[2] = a (m/s^2), d[3..5] = third to fifth
/// time derivatives of x (m/s^3, m/s^4, m/s^5).
struct Gear5State {
  Vec3 d[6];
};

/// Predictor: Taylor expansion of all six values over dt (s).
GF_HOST_DEVICE inline void gear5_predict(Gear5State& s, double dt) {
  // Scaled values r_k = dt^k/k! d_k, Pascal triangle, unscale.
  double scale[6] = {
      1, dt, dt * dt / 2, dt * dt * dt / 6, dt * dt * dt * dt / 24, dt * dt * dt * dt * dt / 120};
  Vec3 r[6];
  for (int k = 0; k < 6; ++k) r[k] = scale[k] * s.d[k];
  for (int k = 0; k < 5; ++k)
    for (int j = 4; j >= k; --j) r[j] += r[j + 1];
  for (int k = 0; k < 6; ++k) s.d[k] = (1.0 / scale[k]) * r[k];
}

/// Corrector with the acceleration a (m/s^2) evaluated at the predicted x, v.
GF_HOST_DEVICE inline void gear5_correct(Gear5State& s, const Vec3& a, double dt,
                                         const Gear5Coefficients& c) {
  const Vec3 da = a - s.d[2];
  // d_k += c_k k!/dt^k * dt^2/2 * da
  s.d[0] += (c.c[0] * 0.5 * dt * dt) * da;
  s.d[1] += (c.c[1] * 0.5 * dt) * da;
  s.d[2] += c.c[2] * da;
  s.d[3] += (c.c[3] * 3.0 / dt) * da;
  s.d[4] += (c.c[4] * 12.0 / (dt * dt)) * da;
  s.d[5] += (c.c[5] * 60.0 / (dt * dt * dt)) * da;
}

/// A state at rest in its higher derivatives: x, v, a given, d3..d5 = 0 (the usual start).
GF_HOST_DEVICE inline Gear5State gear5_start(const Vec3& x, const Vec3& v, const Vec3& a) {
  Gear5State s;
  s.d[0] = x;
  s.d[1] = v;
  s.d[2] = a;
  return s;
}

/// Loops over n bodies through core/exec: predict all; correct all with a = force / mass.
void gear5_predict(std::size_t n, Gear5State* s, double dt);
void gear5_correct(std::size_t n, Gear5State* s, const Vec3* force, const double* mass, double dt,
                   const Gear5Coefficients& c);

/// Gear5 on a particle store (`integrator: gear5`), one force evaluation per step:
///   predict (positions wrapped into periodic boxes) -> forces -> correct.
/// Translation: x'' = f/m. Rotation: the rotation vector phi with phi' = omega, omega' = T/I
/// (scalar I), exact for spheres and for 2D disks and polygons (rotation about z only; a
/// polygon's orientation follows phi_z). Spherocylinders need the rigid-body rotation of
/// rigid_bodies.hpp and are refused with gear5 (the simulation says so before running).
/// The higher derivatives are store fields (gear_x2..gear_x5, gear_phi, gear_w2..gear_w5: 9
/// Vec3, 216 B per particle), so they follow re-ordering and go into checkpoints.
/// Fixed grains (ParticleStore::fixed) are skipped: their state stays at rest where it began
/// (or follows a prescribed motion, set by Simulation::place_fixed_groups; their Gear
/// derivatives stay zero, unused).
struct Gear5Integrator {
  static constexpr const char* key = "gear5";
  /// Adds the fields (idempotent).
  static void enable(ParticleStore& p);
  /// The usual start: accelerations from the current forces and torques, higher derivatives 0.
  static void start(ParticleStore& p);
  static void predict(ParticleStore& p, const Domain& domain, double dt);
  static void correct(ParticleStore& p, const Domain& domain, double dt);
};

/// Small driver for tests and single-body studies: n_steps steps of dt from t0 with
/// accel(x, v, t) -> Vec3; calls observe(state, t) after each step (may be omitted).
template <class Accel, class Observe>
void gear5_run(Gear5State& s, Accel&& accel, double t0, double dt, long n_steps,
               const Gear5Coefficients& c, Observe&& observe) {
  double t = t0;
  for (long i = 0; i < n_steps; ++i) {
    gear5_predict(s, dt);
    t = t0 + static_cast<double>(i + 1) * dt;
    gear5_correct(s, accel(s.d[0], s.d[1], t), dt, c);
    observe(static_cast<const Gear5State&>(s), t);
  }
}
template <class Accel>
void gear5_run(Gear5State& s, Accel&& accel, double t0, double dt, long n_steps,
               const Gear5Coefficients& c) {
  gear5_run(s, accel, t0, dt, n_steps, c, [](const Gear5State&, double) {});
}

}  // namespace gf
