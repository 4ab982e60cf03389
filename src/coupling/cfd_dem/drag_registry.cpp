// SPDX-License-Identifier: GPL-3.0-or-later
// Registry functions generated from the DragLaws list.
#include "coupling/cfd_dem/drag_registry.hpp"

#include <fmt/format.h>

#include <optional>

#include "core/error.hpp"

namespace gf::cfd_dem {

std::vector<DragInfo> drag_infos() {
  std::vector<DragInfo> out;
  for_each_type(DragLaws{}, [&]<class L>() {
    out.push_back({L::key, L::summary, L::equation, L::reference, L::validity,
                   std::span<const ParamSpec>(L::params)});
  });
  return out;
}

int drag_index(std::string_view key) {
  return index_of_key(DragLaws{}, key);
}

const DragInfo* find_drag(std::string_view key) {
  static const std::vector<DragInfo> infos = drag_infos();
  for (const auto& d : infos)
    if (d.key == key) return &d;
  return nullptr;
}

DragParams prepare_drag(std::string_view key, const std::map<std::string, double>& params) {
  const int idx = drag_index(key);
  REQUIRE(idx >= 0, "unknown drag law '{}'", key);
  const DragInfo& info = *find_drag(key);
  check_params(fmt::format("drag law '{}'", key), info.params, params);
  auto get = [&](std::string_view name) { return param_value(params, name); };
  DragParams p;
  dispatch_index(DragLaws{}, idx, [&]<class L>() { L::prepare(p, get); });
  p.law = idx;
  return p;
}

}  // namespace gf::cfd_dem
