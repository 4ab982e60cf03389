// SPDX-License-Identifier: GPL-3.0-or-later
// Registry functions generated from the Rheologies list.
#include "continuum/rheology_registry.hpp"

#include <fmt/format.h>

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
  check_params(fmt::format("rheology '{}'", key), info.params, params, true);
  auto get = [&](std::string_view name) { return param_value(params, name); };
  RheologyParams p;
  dispatch_index(Rheologies{}, idx, [&]<class M>() { M::prepare(p, get); });
  p.model = idx;
  return p;
}

}  // namespace gf::continuum
