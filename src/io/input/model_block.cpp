// SPDX-License-Identifier: GPL-3.0-or-later
// Reading a registry model's parameters against its schema.
#include "io/input/model_block.hpp"

#include <fmt/format.h>

namespace gf::input {

std::map<std::string, double> read_schema_params(const YamlMap& m, const YamlNode& node,
                                                 const std::vector<ParamSpec>& schema,
                                                 const std::string& what) {
  std::map<std::string, double> params;
  for (const auto& p : schema) {
    Range range{p.min, p.max, p.min_exclusive, false};
    if (auto v = m.optional_number(p.name, range))
      params[std::string(p.name)] = *v;
    else if (!p.default_value)
      node.fail(
          fmt::format("[missing key] {} needs '{}' [{}]: {}", what, p.name, p.unit, p.description));
  }
  return params;
}

std::map<std::string, double> with_defaults(std::span<const ParamSpec> schema,
                                            const std::map<std::string, double>& given) {
  std::map<std::string, double> all;
  for (const auto& p : schema) {
    const auto g = given.find(std::string(p.name));
    if (g != given.end())
      all[g->first] = g->second;
    else if (p.default_value)
      all[std::string(p.name)] = *p.default_value;
  }
  return all;
}

}  // namespace gf::input
