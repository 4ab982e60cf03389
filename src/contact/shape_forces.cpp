// SPDX-License-Identifier: GPL-3.0-or-later
// Force loop of stores with shapes: the same slab-phased rows as the sphere loop, with the
// general narrow phase and lever arms from the centres to the contact point.
#include "contact/shape_forces.hpp"

#include "contact/registry.hpp"
#include "contact/row_loop.hpp"

namespace gf::contact {

namespace {

/// Calls visit(i, j, k, geometry) for every touching pair of the list, and miss(k) for the
/// entries that are apart; row(i) returns the number of touching pairs of row i.
template <class Visit, class Miss>
std::int64_t touching_rows(const ParticleStore& p, const Domain& domain, const VerletList& list,
                           Visit&& visit, Miss&& miss, const PairSkip* skip = nullptr) {
  const ShapeView s(p);
  const Vec3* x = p.x();
  const auto off = list.offsets();
  const auto nb = list.neighbors();
  auto row = [&](std::int64_t i) -> std::int64_t {
    const Vec3 xi = x[i];
    ConvexPolygon poly_i;
    if (s.code(i) == ShapeCode::Polygon) poly_i = s.world_polygon(i, xi);
    const Capsule cap_i = s.capsule(i, xi);  // (its axis: once per row, not per pair)
    std::int64_t touching = 0;
    for (std::int64_t k = off[i]; k < off[i + 1]; ++k) {
      const std::int32_t j = nb[k];
      if (skip && skip->gap[k] - skip->moved[i] - skip->moved[j] - skip->slide > 0) {
        miss(k);
        continue;
      }
      const Vec3 xj = xi - domain.delta(xi, x[j]);  // the image of j nearest to i
      ShapeGeometry g;
      if (!shape_pair_geometry(s, i, j, xi, xj, &poly_i, g, &cap_i)) {
        miss(k);
        continue;
      }
      ++touching;
      visit(i, j, k, xj, g);
    }
    return touching;
  };
  return for_rows_in_slabs(list, row);
}

}  // namespace

std::int64_t compute_shape_pair_forces(ParticleStore& p, const Domain& domain, VerletList& list,
                                       const PairTable<PairCoeffs>& pairs, double dt,
                                       const ContactSink* report, const PairSkip* skip) {
  const Vec3* x = p.x();
  const Vec3* v = p.v();
  const Vec3* om = p.omega();
  Vec3* f = p.f();
  Vec3* tq = p.torque();
  const double* m = p.mass();
  const std::int32_t* fixed = p.fixed();  // null: no fixed grains
  const std::int32_t* mat = p.material();
  auto hist = list.history();
  return touching_rows(
      p, domain, list,
      [&](std::int64_t i, std::int32_t j, std::int64_t k, const Vec3& xj, const ShapeGeometry& g) {
        const Vec3 arm_i = g.point - x[i], arm_j = g.point - xj;
        ContactKinematics kin;
        kin.overlap = g.overlap;
        kin.normal = g.normal;
        kin.r_eff = g.r_eff;
        kin.inv_r_sum = g.inv_r_sum;
        // (xj is the image of j nearest to i; with Lees-Edwards it moves with the image.)
        const Vec3 vj = v[j] + domain.image_velocity(x[i], x[j]);
        kin.v_rel = v[i] + cross(om[i], arm_i) - vj - cross(om[j], arm_j);
        kin.omega_rel = om[i] - om[j];
        const bool fixed_i = fixed != nullptr && fixed[i] != 0;
        const bool fixed_j = fixed != nullptr && fixed[j] != 0;
        kin.m_eff = fixed_i || fixed_j ? reduced_mass(m[i], m[j], fixed_i, fixed_j) / g.force_scale
                                       : m[i] * m[j] / ((m[i] + m[j]) * g.force_scale);
        const PairCoeffs& c = pairs(mat[i], mat[j]);
        ContactResult res = dispatch_index(ContactModels{}, c.model, [&]<class M>() {
          return M::Law::evaluate(c, kin, dt, hist[k]);
        });
        res.force = g.force_scale * res.force;
        res.rolling_torque = g.force_scale * res.rolling_torque;
        f[i] += res.force;
        tq[i] += res.rolling_torque + cross(arm_i, res.force);
        f[j] -= res.force;
        tq[j] -= res.rolling_torque + cross(arm_j, res.force);
        if (report)
          report->add(k, static_cast<std::int32_t>(i), j, x[i], x[i] - xj, g.normal, g.point,
                      res.force, g.overlap);
      },
      [&](std::int64_t k) { hist[k] = {}; }, skip);
}

double shape_pair_elastic_energy(const ParticleStore& p, const Domain& domain,
                                 const VerletList& list, const PairTable<PairCoeffs>& pairs) {
  const std::int32_t* mat = p.material();
  // Serial: the sum is then in list order whatever the thread count (output only).
  double e = 0;
  for_each_touching_pair(
      p, domain, list,
      [&](std::size_t i, std::int32_t j, double overlap, double r_eff, double scale, std::int64_t) {
        const PairCoeffs& c = pairs(mat[i], mat[j]);
        e += scale * dispatch_index(ContactModels{}, c.model, [&]<class M>() {
               return M::Law::elastic_energy(c, overlap, r_eff);
             });
      });
  return e;
}

}  // namespace gf::contact
