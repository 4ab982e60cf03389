// SPDX-License-Identifier: GPL-3.0-or-later
// Force loop over the half Verlet list. When every material pair uses the same law the loop is
// instantiated for that law alone (no dispatch per contact); otherwise a switch per contact.
#include "contact/pair_forces.hpp"

#include <array>

#include "contact/registry.hpp"
#include "contact/row_loop.hpp"
#include "core/exec.hpp"

namespace gf::contact {

namespace {

template <class Eval>
std::int64_t pair_loop(ParticleStore& p, const Domain& domain, VerletList& list,
                       const PairTable<PairCoeffs>& pairs, double dt, Eval&& eval) {
  const Vec3* x = p.x();
  const Vec3* v = p.v();
  const Vec3* om = p.omega();
  Vec3* f = p.f();
  Vec3* tq = p.torque();
  const double* r = p.radius();
  const double* m = p.mass();
  const std::int32_t* mat = p.material();
  const auto off = list.offsets();
  const auto nb = list.neighbors();
  auto hist = list.history();
  auto row = [&](std::int64_t i) -> std::int64_t {
    const Vec3 xi = x[i];
    const double ri = r[i];
    std::int64_t touching = 0;
    Vec3 fi{}, ti{};
    for (std::int64_t k = off[i]; k < off[i + 1]; ++k) {
      const std::int32_t j = nb[k];
      ContactKinematics kin;
      double arm_i, arm_j;
      if (!sphere_sphere(domain, xi, x[j], ri, r[j], kin, arm_i, arm_j)) {
        hist[k] = {};
        continue;
      }
      ++touching;
      kin.v_rel = v[i] - v[j] - cross(arm_i * om[i] + arm_j * om[j], kin.normal);
      kin.omega_rel = om[i] - om[j];
      kin.m_eff = m[i] * m[j] / (m[i] + m[j]);
      const PairCoeffs& c = pairs(mat[i], mat[j]);
      const ContactResult res = eval(c, kin, dt, hist[k]);
      const Vec3 nxf = cross(kin.normal, res.force);
      fi += res.force;
      ti += res.rolling_torque - arm_i * nxf;
      f[j] -= res.force;
      tq[j] -= res.rolling_torque + arm_j * nxf;
    }
    f[i] += fi;
    tq[i] += ti;
    return touching;
  };
  return for_rows_in_slabs(list, row);
}

bool uniform_model(const PairTable<PairCoeffs>& pairs, int& model) {
  model = -1;
  for (int a = 0; a < pairs.n(); ++a)
    for (int b = 0; b < pairs.n(); ++b) {
      const int mm = pairs(a, b).model;
      if (mm < 0) continue;
      if (model >= 0 && mm != model) return false;
      model = mm;
    }
  return model >= 0;
}

}  // namespace

std::int64_t compute_pair_forces(ParticleStore& p, const Domain& domain, VerletList& list,
                                 const PairTable<PairCoeffs>& pairs, double dt) {
  int model;
  if (uniform_model(pairs, model)) {
    return dispatch_index(ContactModels{}, model, [&]<class M>() {
      return pair_loop(p, domain, list, pairs, dt,
                       [](const PairCoeffs& c, const ContactKinematics& k, double h, Vec3& xi) {
                         return M::Law::evaluate(c, k, h, xi);
                       });
    });
  }
  return pair_loop(p, domain, list, pairs, dt,
                   [](const PairCoeffs& c, const ContactKinematics& k, double h, Vec3& xi) {
                     return dispatch_index(ContactModels{}, c.model, [&]<class M>() {
                       return M::Law::evaluate(c, k, h, xi);
                     });
                   });
}

double pair_elastic_energy(const ParticleStore& p, const Domain& domain, const VerletList& list,
                           const PairTable<PairCoeffs>& pairs) {
  const Vec3* x = p.x();
  const double* r = p.radius();
  const std::int32_t* mat = p.material();
  const auto off = list.offsets();
  const auto nb = list.neighbors();
  double e = 0;
  for (std::size_t i = 0; i < list.n_particles(); ++i)
    for (std::int64_t k = off[i]; k < off[i + 1]; ++k) {
      const std::int32_t j = nb[k];
      ContactKinematics kin;
      double ai, aj;
      if (!sphere_sphere(domain, x[i], x[j], r[i], r[j], kin, ai, aj)) continue;
      const PairCoeffs& c = pairs(mat[i], mat[j]);
      e += dispatch_index(ContactModels{}, c.model, [&]<class M>() {
        return M::Law::elastic_energy(c, kin.overlap, kin.r_eff);
      });
    }
  return e;
}

}  // namespace gf::contact
