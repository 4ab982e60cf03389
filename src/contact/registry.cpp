// SPDX-License-Identifier: GPL-3.0-or-later
// Registry functions generated from the ContactModels list.
#include "contact/registry.hpp"

#include <cmath>
#include <numbers>

namespace gf::contact {

std::vector<ModelInfo> model_infos() {
  std::vector<ModelInfo> out;
  for_each_type(ContactModels{}, [&]<class M>() {
    out.push_back(
        {M::key, M::summary, M::equation, M::reference, std::span<const ParamSpec>(M::params)});
  });
  return out;
}

int model_index(std::string_view key) {
  return index_of_key(ContactModels{}, key);
}

const ModelInfo* find_model(std::string_view key) {
  static const std::vector<ModelInfo> infos = model_infos();
  for (const auto& m : infos)
    if (m.key == key) return &m;
  return nullptr;
}

PairCoeffs prepare_pair(std::string_view key, const PairContext& ctx,
                        const std::map<std::string, double>& params) {
  const int idx = model_index(key);
  REQUIRE(idx >= 0, "unknown contact model '{}'", key);
  auto get = [&](std::string_view name) { return param_value(params, name); };
  PairCoeffs c =
      dispatch_index(ContactModels{}, idx, [&]<class M>() { return M::prepare(ctx, get); });
  c.model = idx;
  return c;
}

double contact_time(const PairCoeffs& c, double r_eff, double m_eff, double v) {
  const int hertz = model_index("hertz_mindlin");
  if (c.model == hertz) {
    // Johnson (1985) eq. 11.24: t_c = 2.868 (m*^2 / (R* E*^2 v))^(1/5).
    return 2.868 * std::pow(m_eff * m_eff / (r_eff * c.stiffness * c.stiffness * v), 0.2);
  }
  return std::numbers::pi * std::sqrt(m_eff / c.stiffness);
}

double rayleigh_time(const Material& m, double radius) {
  const double g = m.youngs_modulus / (2 * (1 + m.poisson_ratio));
  return std::numbers::pi * radius * std::sqrt(m.density / g) / (0.1631 * m.poisson_ratio + 0.8766);
}

}  // namespace gf::contact
