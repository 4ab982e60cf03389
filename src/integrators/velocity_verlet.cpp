// SPDX-License-Identifier: GPL-3.0-or-later
// Velocity Verlet loops, run through core/exec.
#include "integrators/velocity_verlet.hpp"

#include <limits>

#include "core/exec.hpp"

namespace gf {

namespace {

/// Half kick v += h f / m, omega += h torque / I (twice with `twice`: the deferred second half
/// kick of the previous step, then this step's first), optionally followed by the drift
/// x += dt v (Drift), the reset of f and torque (Reset) and the largest squared displacement
/// from x_ref (Track), which the function returns (0 without Track). `wrap_refs` (may be null)
/// take each wrap's jump (DriftExtras::wrap_refs) before the displacement is measured.
template <bool Drift, bool Reset, bool Track>
double kick(ParticleStore& p, const Domain* domain, double h, double dt, const Vec3& g,
            const Vec3* x_ref, bool twice = false, Vec3* wrap_refs = nullptr) {
  Vec3* x = p.x();
  Vec3* v = p.v();
  Vec3* w = p.omega();
  Vec3* f = p.f();
  Vec3* t = p.torque();
  const double* m = p.mass();
  const double* in = p.inertia();
  // Wrapping is a no-op without periodic axes; skipping it keeps the loop short.
  const bool periodic =
      Drift && (domain->periodic[0] || domain->periodic[1] || domain->periodic[2]);
  // The faces a grain must cross to be wrapped (+-inf along the other axes): a grain inside
  // them, nearly every grain in a step, skips the call.
  constexpr double inf = std::numeric_limits<double>::infinity();
  Vec3 face_lo{-inf, -inf, -inf}, face_hi{inf, inf, inf};
  if (periodic) {
    for (int k = 0; k < 3; ++k) {
      if (domain->periodic[k]) {
        face_lo[k] = domain->lo[k];
        face_hi[k] = domain->hi[k];
      }
    }
  }
  // References that follow the wraps hold each grain's own displacement: no image to find.
  const bool own_refs = wrap_refs != nullptr && wrap_refs == x_ref;
  auto one = [&](exec::index_t i) {
    // (each factor once: the compiler cannot reuse it across the stores to v and w, which may
    // alias m and in; the same values, so the same bits as dividing twice)
    const double hm = h / m[i], hw = h / in[i];
    if (twice) {
      v[i] += hm * f[i];
      w[i] += hw * t[i];
    }
    v[i] += hm * f[i];
    w[i] += hw * t[i];
    if constexpr (Reset) {
      f[i] = m[i] * g;
      t[i] = {};
    }
    if constexpr (Drift) {
      x[i] += dt * v[i];
      const Vec3 xi = x[i];
      if (periodic && (xi.x < face_lo.x || xi.x >= face_hi.x || xi.y < face_lo.y ||
                       xi.y >= face_hi.y || xi.z < face_lo.z || xi.z >= face_hi.z)) {
        if (wrap_refs != nullptr) {
          const Vec3 before = x[i];
          domain->wrap(x[i], &v[i]);
          if (x[i] != before) wrap_refs[i] += x[i] - before;
        } else {
          domain->wrap(x[i], &v[i]);
        }
      }
    }
  };
  const auto n = static_cast<exec::index_t>(p.size());
  auto run = [&](auto&& body) {
    if constexpr (Track) {
      return exec::parallel_max(n, 0.0, [&](exec::index_t i) {
        body(i);
        return norm2(periodic && !own_refs ? domain->delta(x[i], x_ref[i]) : x[i] - x_ref[i]);
      });
    } else {
      exec::parallel_for(n, body);  // no reduction where nothing is measured
      return 0.0;
    }
  };
  // Fixed grains (a group with fixed: true) are never integrated: no kick, no drift, no wrap;
  // their velocities stay zero and their positions bit for bit (those of a group with a
  // prescribed motion are placed by the simulation, analytically). Their forces are reset like
  // the others' (the next evaluation adds to m g; the series' fixed_force takes m g off). Runs
  // without fixed grains keep the loop without the test.
  if (const std::int32_t* fixed = p.fixed()) {
    return run([&](exec::index_t i) {
      if (fixed[i] == 0) {
        one(i);
      } else if constexpr (Reset) {
        f[i] = m[i] * g;
        t[i] = {};
      }
    });
  }
  return run(one);
}

}  // namespace

void VelocityVerlet::pre_force(ParticleStore& p, const Domain& domain, double dt,
                               DriftExtras* extras) {
  const double h = 0.5 * dt;
  if (!extras) {
    kick<true, false, false>(p, &domain, h, dt, {}, nullptr);
    return;
  }
  const Vec3 g = extras->gravity ? *extras->gravity : Vec3{};
  const Vec3* ref = extras->x_ref;
  const bool two = extras->pending_kick;
  Vec3* follow = extras->wrap_refs;
  extras->max_d2 = extras->gravity
                       ? (ref ? kick<true, true, true>(p, &domain, h, dt, g, ref, two, follow)
                              : kick<true, true, false>(p, &domain, h, dt, g, ref, two, follow))
                       : (ref ? kick<true, false, true>(p, &domain, h, dt, g, ref, two, follow)
                              : kick<true, false, false>(p, &domain, h, dt, g, ref, two, follow));
}

void VelocityVerlet::post_force(ParticleStore& p, double dt) {
  kick<false, false, false>(p, nullptr, 0.5 * dt, dt, {}, nullptr);
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
