// SPDX-License-Identifier: GPL-3.0-or-later
// Loops of the Gear predictor-corrector kernels over bodies, run through core/exec.
#include "integrators/gear5.hpp"

#include <array>
#include <cmath>

#include "core/error.hpp"
#include "core/exec.hpp"

namespace gf {

void gear5_predict(std::size_t n, Gear5State* s, double dt) {
  exec::parallel_for(static_cast<exec::index_t>(n),
                     [&](exec::index_t i) { gear5_predict(s[i], dt); });
}

void gear5_correct(std::size_t n, Gear5State* s, const Vec3* force, const double* mass, double dt,
                   const Gear5Coefficients& c) {
  exec::parallel_for(static_cast<exec::index_t>(n), [&](exec::index_t i) {
    gear5_correct(s[i], (1.0 / mass[i]) * force[i], dt, c);
  });
}

namespace {

const char* const kGearFields[9] = {"gear_x2", "gear_x3", "gear_x4", "gear_x5", "gear_phi",
                                    "gear_w2", "gear_w3", "gear_w4", "gear_w5"};

/// The nine extra columns of Gear5Integrator, in kGearFields order.
std::array<Vec3*, 9> gear_columns(ParticleStore& p) {
  std::array<Vec3*, 9> c{};
  for (int k = 0; k < 9; ++k) {
    const int f = p.find_field(kGearFields[k]);
    REQUIRE(f >= 0, "gear5: the store has no field '{}' (Gear5Integrator::enable not called)",
            kGearFields[k]);
    c[static_cast<std::size_t>(k)] = p.get<Vec3>(f).data();
  }
  return c;
}

/// Runs body(translation state, rotation state, i) over all particles, loading the states from
/// the store and writing them back.
template <class Body>
void for_gear_states(ParticleStore& p, Body&& body) {
  const auto c = gear_columns(p);
  Vec3* x = p.x();
  Vec3* v = p.v();
  Vec3* w = p.omega();
  const bool polygons = p.has_shapes();
  const std::int32_t* shape = polygons ? p.shape() : nullptr;
  Quat* q = polygons ? p.orientation() : nullptr;
  // Fixed grains are never integrated: their states (x, v = 0, omega = 0, derivatives 0) stay.
  const std::int32_t* fixed = p.fixed();
  exec::parallel_for(static_cast<exec::index_t>(p.size()), [&](exec::index_t i) {
    if (fixed != nullptr && fixed[i] != 0) return;
    Gear5State tr, rot;
    tr.d[0] = x[i];
    tr.d[1] = v[i];
    rot.d[0] = c[4][i];
    rot.d[1] = w[i];
    for (int k = 0; k < 4; ++k) {
      tr.d[k + 2] = c[static_cast<std::size_t>(k)][i];
      rot.d[k + 2] = c[static_cast<std::size_t>(k) + 5][i];
    }
    const double phi_z = rot.d[0].z;
    body(tr, rot, i);
    x[i] = tr.d[0];
    v[i] = tr.d[1];
    c[4][i] = rot.d[0];
    w[i] = rot.d[1];
    for (int k = 0; k < 4; ++k) {
      c[static_cast<std::size_t>(k)][i] = tr.d[k + 2];
      c[static_cast<std::size_t>(k) + 5][i] = rot.d[k + 2];
    }
    if (polygons && static_cast<ShapeCode>(shape[i]) == ShapeCode::Polygon)
      q[i] = turn_about_z(q[i], rot.d[0].z - phi_z);
  });
}

}  // namespace

void Gear5Integrator::enable(ParticleStore& p) {
  for (const char* name : kGearFields)
    if (p.find_field(name) < 0) p.add_field(name, FieldType::Vec3, "SI", kRestart);
}

void Gear5Integrator::start(ParticleStore& p) {
  const auto c = gear_columns(p);
  const std::int32_t* fixed = p.fixed();
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (auto* col : c) col[i] = {};
    if (fixed != nullptr && fixed[i] != 0) continue;  // at rest, and stays so
    c[0][i] = (1.0 / p.mass()[i]) * p.f()[i];
    c[5][i] = (1.0 / p.inertia()[i]) * p.torque()[i];
  }
}

void Gear5Integrator::predict(ParticleStore& p, const Domain& domain, double dt) {
  for_gear_states(p, [&](Gear5State& tr, Gear5State& rot, exec::index_t) {
    gear5_predict(tr, dt);
    domain.wrap(tr.d[0]);
    gear5_predict(rot, dt);
  });
}

void Gear5Integrator::correct(ParticleStore& p, const Domain& domain, double dt) {
  const Gear5Coefficients coef = gear5_coefficients(GearForces::VelocityDependent);
  const Vec3* f = p.f();
  const Vec3* t = p.torque();
  const double* m = p.mass();
  const double* in = p.inertia();
  for_gear_states(p, [&](Gear5State& tr, Gear5State& rot, exec::index_t i) {
    gear5_correct(tr, (1.0 / m[i]) * f[i], dt, coef);
    domain.wrap(tr.d[0]);
    gear5_correct(rot, (1.0 / in[i]) * t[i], dt, coef);
  });
}

}  // namespace gf
