// SPDX-License-Identifier: GPL-3.0-or-later
// Registry functions generated from the Rheologies list.
#include "continuum/rheology_registry.hpp"

#include <optional>

#include "core/error.hpp"

namespace gf::continuum {

std::vector<RheologyInfo> rheology_infos() {
  std::vector<RheologyInfo> out;
  for_each_type(Rheologies{}, [&]<class M>() {
    out.push_back(
        {M::key, M::summary, M::equation, M::reference, std::span<const ParamSpec>(M::params)});
  });
  return out;
}

const RheologyInfo* find_rheology(std::string_view key) {
  static const std::vector<RheologyInfo> infos = rheology_infos();
  for (const auto& d : infos)
    if (d.key == key) return &d;
  return nullptr;
}

RheologyParams prepare_rheology(std::string_view key, const std::map<std::string, double>& params) {
  const int idx = index_of_key(Rheologies{}, key);
  REQUIRE(idx >= 0, "unknown rheology '{}'", key);
  const RheologyInfo& info = *find_rheology(key);
  for (const auto& [name, value] : params) {
    const ParamSpec* spec = nullptr;
    for (const auto& s : info.params)
      if (s.name == name) spec = &s;
    REQUIRE(spec != nullptr, "rheology '{}' has no parameter '{}'", key, name);
    const bool low_ok = spec->min_exclusive ? value > spec->min : value >= spec->min;
    REQUIRE(low_ok && value <= spec->max, "rheology '{}': {} = {} is outside {}{}, {}]", key, name,
            value, spec->min_exclusive ? "(" : "[", spec->min, spec->max);
  }
  for (const auto& s : info.params)
    REQUIRE(s.default_value || params.count(std::string(s.name)),
            "rheology '{}' needs the parameter '{}' [{}] ({})", key, s.name, s.unit, s.description);
  auto get = [&](std::string_view name) -> std::optional<double> {
    auto it = params.find(std::string(name));
    if (it == params.end()) return std::nullopt;
    return it->second;
  };
  RheologyParams p;
  dispatch_index(Rheologies{}, idx, [&]<class M>() { M::prepare(p, get); });
  p.model = idx;
  if (key == MuI::key)
    REQUIRE(p.mu_2 > p.mu_s, "rheology 'mu_i': mu_2 = {} must exceed mu_s = {}", p.mu_2, p.mu_s);
  return p;
}

}  // namespace gf::continuum
