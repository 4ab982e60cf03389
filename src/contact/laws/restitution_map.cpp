// SPDX-License-Identifier: GPL-3.0-or-later
// Numerical inversion of the realised restitution of a damped, clamped binary collision.
#include "contact/laws/restitution_map.hpp"

#include <cmath>
#include <map>
#include <mutex>
#include <utility>

#include "core/error.hpp"

namespace gf::contact {

namespace {

struct State {
  double x, v;
};

/// Acceleration and force of the dimensionless collision (unit effective mass).
double force(NormalKind kind, double zeta, const State& s) {
  const double x = s.x > 0 ? s.x : 0.0;
  double f;
  if (kind == NormalKind::Linear) {
    f = x + 2.0 * zeta * s.v;  // F_e - c v_n with v_n = -x'
  } else {
    f = x * std::sqrt(x) + 2.0 * zeta * std::sqrt(1.5) * std::sqrt(std::sqrt(x)) * s.v;
  }
  return f;
}

}  // namespace

double realised_restitution(NormalKind kind, double zeta) {
  // x = overlap, v = x' (approach speed 1 at t = 0); the force pushes the overlap back: x'' = -F.
  const double dt = 2e-4;
  State s{0.0, 1.0};
  auto acc = [&](const State& st) {
    double f = force(kind, zeta, st);
    return f > 0 ? -f : 0.0;
  };
  for (int step = 0; step < 2000000; ++step) {
    // RK4 on (x, v).
    const State k1{s.v, acc(s)};
    const State s2{s.x + 0.5 * dt * k1.x, s.v + 0.5 * dt * k1.v};
    const State k2{s2.v, acc(s2)};
    const State s3{s.x + 0.5 * dt * k2.x, s.v + 0.5 * dt * k2.v};
    const State k3{s3.v, acc(s3)};
    const State s4{s.x + dt * k3.x, s.v + dt * k3.v};
    const State k4{s4.v, acc(s4)};
    State n{s.x + dt / 6 * (k1.x + 2 * k2.x + 2 * k3.x + k4.x),
            s.v + dt / 6 * (k1.v + 2 * k2.v + 2 * k3.v + k4.v)};
    const double f_old = force(kind, zeta, s);
    const double f_new = force(kind, zeta, n);
    if (n.v < 0 && (f_new <= 0 || n.x <= 0)) {
      // Contact ends inside this step: when the clamped force vanishes or the overlap closes.
      double w = 1.0;
      if (f_new <= 0 && f_old > 0)
        w = f_old / (f_old - f_new);
      else if (n.x <= 0 && s.x > 0)
        w = s.x / (s.x - n.x);
      const double v_end = s.v + w * (n.v - s.v);
      return -v_end;
    }
    s = n;
  }
  return 0.0;  // never separated: fully plastic
}

double damping_ratio_for_restitution(NormalKind kind, double e) {
  REQUIRE(e > 0 && e <= 1, "restitution {} outside (0, 1]", e);
  if (e >= 1.0) return 0.0;
  static std::mutex mutex;
  static std::map<std::pair<int, double>, double> cache;
  std::lock_guard lock(mutex);
  const auto key = std::make_pair(static_cast<int>(kind), e);
  if (auto it = cache.find(key); it != cache.end()) return it->second;
  double lo = 0.0, hi = 1.0;
  while (realised_restitution(kind, hi) > e) {
    hi *= 2;
    REQUIRE(hi < 1e4, "restitution {} cannot be realised", e);
  }
  for (int it = 0; it < 60 && hi - lo > 1e-12 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (realised_restitution(kind, mid) > e ? lo : hi) = mid;
  }
  const double zeta = 0.5 * (lo + hi);
  cache[key] = zeta;
  return zeta;
}

}  // namespace gf::contact
