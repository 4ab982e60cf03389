// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/conduction.hpp"

#include "contact/shape_forces.hpp"

namespace gf::contact {

std::vector<ConductionInfo> conduction_infos() {
  std::vector<ConductionInfo> out;
  for_each_type(ConductionModels{}, [&]<class M>() {
    out.push_back({M::key, M::summary, M::equation, M::reference});
  });
  return out;
}

int conduction_index(std::string_view key) {
  return index_of_key(ConductionModels{}, key);
}

const ConductionInfo* find_conduction(std::string_view key) {
  static const std::vector<ConductionInfo> infos = conduction_infos();
  const int i = conduction_index(key);
  return i < 0 ? nullptr : &infos[static_cast<std::size_t>(i)];
}

void pair_heat_flows(const ParticleStore& p, const Domain& domain, const VerletList& list,
                     int model, const PairTable<double>& k_series, const double* temperature,
                     double* q, double* h, std::vector<double>& entry_h) {
  const std::int32_t* mat = p.material();
  // The conductance of every entry (0 when apart), rows over the threads; then the flows,
  // serially in list order: the same bits at any thread count.
  entry_h.assign(list.neighbors().size(), 0.0);
  for_each_touching_pair(
      p, domain, list,
      [&](std::size_t i, std::int32_t j, double overlap, double r_eff, double s, std::int64_t k) {
        entry_h[static_cast<std::size_t>(k)] =
            s * contact_conductance(model, overlap, r_eff, k_series(mat[i], mat[j]));
      },
      /*parallel_rows=*/true);
  const auto off = list.offsets();
  const auto nb = list.neighbors();
  for (std::size_t i = 0; i < list.n_particles(); ++i)
    for (std::int64_t k = off[i]; k < off[i + 1]; ++k) {
      const double hc = entry_h[static_cast<std::size_t>(k)];
      if (hc == 0.0) continue;
      const std::int32_t j = nb[k];
      const double flow = hc * (temperature[j] - temperature[i]);
      q[i] += flow;
      q[j] -= flow;
      h[i] += hc;
      h[j] += hc;
    }
}

void pair_heat_flows_from_overlaps(const ParticleStore& p, const VerletList& list, int model,
                                   const PairTable<double>& k_series, const double* temperature,
                                   const double* overlaps, double* q, double* h) {
  const std::int32_t* mat = p.material();
  const double* r = p.radius();
  const auto off = list.offsets();
  const auto nb = list.neighbors();
  for (std::size_t i = 0; i < list.n_particles(); ++i)
    for (std::int64_t k = off[i]; k < off[i + 1]; ++k) {
      const double overlap = overlaps[k];
      if (!(overlap > 0.0)) continue;
      const std::int32_t j = nb[k];
      const double r_eff = r[i] * r[j] / (r[i] + r[j]);  // as sphere_sphere's
      const double hc = contact_conductance(model, overlap, r_eff, k_series(mat[i], mat[j]));
      const double flow = hc * (temperature[j] - temperature[i]);
      q[i] += flow;
      q[j] -= flow;
      h[i] += hc;
      h[j] += hc;
    }
}

}  // namespace gf::contact
