// SPDX-License-Identifier: GPL-3.0-or-later
// Velocity Verlet loops, run through core/exec.
#include "integrators/velocity_verlet.hpp"

#include "core/exec.hpp"

namespace gf {

namespace {

/// Half kick v += h f / m, omega += h torque / I, optionally followed by the drift x += dt v.
template <bool Drift>
void kick(ParticleStore& p, const Domain* domain, double h, double dt) {
  Vec3* x = p.x();
  Vec3* v = p.v();
  Vec3* w = p.omega();
  const Vec3* f = p.f();
  const Vec3* t = p.torque();
  const double* m = p.mass();
  const double* in = p.inertia();
  // Wrapping is a no-op without periodic axes; skipping it keeps the loop short.
  const bool periodic =
      Drift && (domain->periodic[0] || domain->periodic[1] || domain->periodic[2]);
  exec::parallel_for(static_cast<exec::index_t>(p.size()), [&](exec::index_t i) {
    v[i] += (h / m[i]) * f[i];
    w[i] += (h / in[i]) * t[i];
    if constexpr (Drift) {
      x[i] += dt * v[i];
      if (periodic) domain->wrap(x[i], &v[i]);
    }
  });
}

}  // namespace

void VelocityVerlet::pre_force(ParticleStore& p, const Domain& domain, double dt) {
  kick<true>(p, &domain, 0.5 * dt, dt);
}

void VelocityVerlet::post_force(ParticleStore& p, double dt) {
  kick<false>(p, nullptr, 0.5 * dt, dt);
}

void reset_forces(ParticleStore& p, const Vec3& gravity) {
  Vec3* f = p.f();
  Vec3* t = p.torque();
  const double* m = p.mass();
  exec::parallel_for(static_cast<exec::index_t>(p.size()), [&](exec::index_t i) {
    f[i] = m[i] * gravity;
    t[i] = {};
  });
}

}  // namespace gf
