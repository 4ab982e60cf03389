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

/// Displacement x_i - x_j: the minimum image only when some axis is periodic, the Lees-Edwards
/// shift only in a sheared box (the periodic loop of other runs stays as it was).
template <bool Periodic, bool Sheared>
inline Vec3 pair_delta(const Domain& dom, const Vec3& a, const Vec3& b) {
  if constexpr (Sheared)
    return dom.delta(a, b);
  else if constexpr (Periodic)
    return dom.min_image(a - b);
  else
    return a - b;
}

/// The force loop over the rows of the half list. The narrow phase is sphere_sphere
/// (pair_forces.hpp) inlined by hand: one reciprocal instead of three divisions for the normal,
/// the minimum image only in periodic domains, the per-row values (x_i, r_i, the row of the
/// material-pair table) loaded once per row. The row is inlined into the slab loop so that the
/// array pointers stay in registers. Without rolling friction in any pair (Rolling = false) the
/// law's rolling torque is zero and is left out of the torque sums.
template <bool Periodic, bool Sheared, bool Rolling, bool Virial, class Eval>
std::int64_t pair_loop(ParticleStore& p, const Domain& domain, VerletList& list,
                       const PairTable<PairCoeffs>& pairs, double dt, const VirialSink* virial,
                       Eval&& eval) {
  const Vec3* const x = p.x();
  const Vec3* const v = p.v();
  const Vec3* const om = p.omega();
  Vec3* const f = p.f();
  Vec3* const tq = p.torque();
  const double* const r = p.radius();
  const double* const m = p.mass();
  const std::int32_t* const mat = p.material();
  const std::int64_t* const off = list.offsets().data();
  const std::int32_t* const nb = list.neighbors().data();
  Vec3* const hist = list.history().data();
  const PairCoeffs* const coeffs = pairs.data();
  const std::size_t n_mat = static_cast<std::size_t>(pairs.n());
  const Domain dom = domain;
  const VirialSink sink = virial ? *virial : VirialSink{};
  auto row = [ =, &eval ](std::int64_t i) __attribute__((always_inline))->std::int64_t {
    const Vec3 xi = x[i];
    const double ri = r[i];
    const double mi = m[i];
    const PairCoeffs* const c_row = coeffs + static_cast<std::size_t>(mat[i]) * n_mat;
    std::int64_t touching = 0;
    Vec3 fi{}, ti{};
    [[maybe_unused]] Mat3 wi{};
    const std::int64_t end = off[i + 1];
    for (std::int64_t k = off[i]; k < end; ++k) {
      const std::int32_t j = nb[k];
      const Vec3 d = pair_delta<Periodic, Sheared>(dom, xi, x[j]);
      const double rj = r[j];
      const double rs = ri + rj;
      const double dist2 = norm2(d);
      if (dist2 >= rs * rs) {
        hist[k] = {};
        continue;
      }
      ++touching;
      ContactKinematics kin;
      const double dist = std::sqrt(dist2);
      kin.overlap = rs - dist;
      kin.normal = dist > 0 ? (1.0 / dist) * d : Vec3{0, 0, 1};
      const double arm_i = ri - 0.5 * kin.overlap;
      const double arm_j = rj - 0.5 * kin.overlap;
      kin.r_eff = ri * rj / rs;
      const double mj = m[j];
      kin.m_eff = mi * mj / (mi + mj);
      Vec3 vj = v[j];
      if constexpr (Sheared) vj += dom.image_velocity(xi, x[j]);
      kin.v_rel = v[i] - vj - cross(arm_i * om[i] + arm_j * om[j], kin.normal);
      kin.omega_rel = om[i] - om[j];
      const ContactResult res = eval(c_row[mat[j]], kin, dt, hist[k]);
      const Vec3 nxf = cross(kin.normal, res.force);
      fi += res.force;
      f[j] -= res.force;
      if constexpr (Virial) {
        if (sink.counts(xi, d))
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) wi.a[a][b] += d[a] * res.force[b];
      }
      if constexpr (Rolling) {
        ti += res.rolling_torque - arm_i * nxf;
        tq[j] -= res.rolling_torque + arm_j * nxf;
      } else {
        ti -= arm_i * nxf;
        tq[j] -= arm_j * nxf;
      }
    }
    f[i] += fi;
    tq[i] += ti;
    if constexpr (Virial) sink.rows[i] = sink.rows[i] + wi;
    return touching;
  };
  return for_rows_in_slabs(list, row);
}

template <bool Periodic, bool Sheared, class Eval>
std::int64_t pair_loop(ParticleStore& p, const Domain& domain, VerletList& list,
                       const PairTable<PairCoeffs>& pairs, double dt, bool rolling,
                       const VirialSink* virial, Eval&& eval) {
  if (virial)
    return rolling
               ? pair_loop<Periodic, Sheared, true, true>(p, domain, list, pairs, dt, virial, eval)
               : pair_loop<Periodic, Sheared, false, true>(p, domain, list, pairs, dt, virial,
                                                           eval);
  return rolling
             ? pair_loop<Periodic, Sheared, true, false>(p, domain, list, pairs, dt, virial, eval)
             : pair_loop<Periodic, Sheared, false, false>(p, domain, list, pairs, dt, virial, eval);
}

template <class Eval>
std::int64_t pair_loop(ParticleStore& p, const Domain& domain, VerletList& list,
                       const PairTable<PairCoeffs>& pairs, double dt, const VirialSink* virial,
                       Eval&& eval) {
  bool rolling = false;
  for (int a = 0; a < pairs.n(); ++a)
    for (int b = 0; b < pairs.n(); ++b) rolling = rolling || pairs(a, b).rolling_friction != 0;
  if (domain.sheared())
    return pair_loop<true, true>(p, domain, list, pairs, dt, rolling, virial, eval);
  if (domain.any_periodic())
    return pair_loop<true, false>(p, domain, list, pairs, dt, rolling, virial, eval);
  return pair_loop<false, false>(p, domain, list, pairs, dt, rolling, virial, eval);
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
                                 const PairTable<PairCoeffs>& pairs, double dt,
                                 const VirialSink* virial) {
  int model;
  if (uniform_model(pairs, model)) {
    return dispatch_index(ContactModels{}, model, [&]<class M>() {
      return pair_loop(p, domain, list, pairs, dt, virial,
                       [](const PairCoeffs& c, const ContactKinematics& k, double h, Vec3& xi) {
                         return M::Law::evaluate(c, k, h, xi);
                       });
    });
  }
  return pair_loop(p, domain, list, pairs, dt, virial,
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
