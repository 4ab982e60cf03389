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

namespace {

/// The heat flows of the list's entries, serially in list order (the same bits at any thread
/// count): `conductance(i, j, k)` gives entry k's H (W/K; 0 when apart), H (T_j - T_i) goes to
/// i and the opposite to j, H to both conductance sums.
template <class Conductance>
void scatter_heat_flows(const VerletList& list, const double* temperature, double* q, double* h,
                        Conductance&& conductance) {
  const auto off = list.offsets();
  const auto nb = list.neighbors();
  for (std::size_t i = 0; i < list.n_particles(); ++i)
    for (std::int64_t k = off[i]; k < off[i + 1]; ++k) {
      const std::int32_t j = nb[k];
      const double hc = conductance(i, j, k);
      if (hc == 0.0) continue;
      const double flow = hc * (temperature[j] - temperature[i]);
      q[i] += flow;
      q[j] -= flow;
      h[i] += hc;
      h[j] += hc;
    }
}

}  // namespace

void pair_heat_flows(const ParticleStore& p, const Domain& domain, const VerletList& list,
                     int model, const PairTable<double>& k_series, const double* temperature,
                     double* q, double* h, std::vector<double>& entry_h) {
  const std::int32_t* mat = p.material();
  // The conductance of every entry (0 when apart), rows over the threads; then the flows.
  entry_h.assign(list.neighbors().size(), 0.0);
  for_each_touching_pair(
      p, domain, list,
      [&](std::size_t i, std::int32_t j, double overlap, double r_eff, double s, std::int64_t k) {
        entry_h[static_cast<std::size_t>(k)] =
            s * contact_conductance(model, overlap, r_eff, k_series(mat[i], mat[j]));
      },
      /*parallel_rows=*/true);
  scatter_heat_flows(list, temperature, q, h, [&](std::size_t, std::int32_t, std::int64_t k) {
    return entry_h[static_cast<std::size_t>(k)];
  });
}

void pair_heat_flows_from_overlaps(const ParticleStore& p, const VerletList& list, int model,
                                   const PairTable<double>& k_series, const double* temperature,
                                   const double* overlaps, double* q, double* h) {
  const std::int32_t* mat = p.material();
  const double* r = p.radius();
  scatter_heat_flows(list, temperature, q, h, [&](std::size_t i, std::int32_t j, std::int64_t k) {
    const double overlap = overlaps[k];
    if (!(overlap > 0.0)) return 0.0;
    const double r_eff = r[i] * r[j] / (r[i] + r[j]);  // as sphere_sphere's
    return contact_conductance(model, overlap, r_eff, k_series(mat[i], mat[j]));
  });
}

}  // namespace gf::contact
