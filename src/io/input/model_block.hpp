// SPDX-License-Identifier: GPL-3.0-or-later
// A registry model as the case file names it: `KEY` or `{model: KEY, ...parameters}`, its
// parameters checked against the model's schema (core/params.hpp). Used by every block that picks
// a model from a registry (drag laws, particle pressure, rheologies, KTGF closures).
#pragma once

#include <map>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "core/params.hpp"
#include "io/input/yaml_reader.hpp"

namespace gf::input {

/// The parameters of a model's schema from map `m` (the node `node`): each in its range, every
/// one without a default required ("[missing key] WHAT needs 'name' [unit]: description").
std::map<std::string, double> read_schema_params(const YamlMap& m, const YamlNode& node,
                                                 const std::vector<ParamSpec>& schema,
                                                 const std::string& what);

/// Every parameter of `schema`, as given or at its default (for echoes of the resolved case).
std::map<std::string, double> with_defaults(std::span<const ParamSpec> schema,
                                            const std::map<std::string, double>& given);

/// A `{model: KEY, ...parameters}` block of registry `infos` (each with .key and .params), or a
/// bare `KEY` (every parameter at its default): the key, its info and its parameters as given
/// (range-checked; required ones present). An unknown key fails with "expected a `kind`: k1, k2,
/// ...`or_else`" and the closest key when it looks like a typo; an unknown parameter with its name.
template <class Info>
std::tuple<std::string, const Info*, std::map<std::string, double>> read_model_block(
    const YamlNode& node, const std::vector<Info>& infos, const std::string& kind,
    const std::string& or_else = "") {
  const bool bare = node.is_scalar();
  std::optional<YamlMap> m;
  if (!bare) m.emplace(node);
  const YamlNode model_node = bare ? node : m->at("model");
  std::string key = model_node.as_string();
  const Info* info = nullptr;
  std::vector<std::string> keys, accepted{"model"};
  for (const auto& i : infos) {
    keys.emplace_back(i.key);
    if (i.key == key) info = &i;
  }
  if (!info) {
    std::string hint;
    if (auto near = closest_match(key, keys)) hint = " (did you mean '" + *near + "'?)";
    model_node.fail("expected a " + kind + ": " + join(keys) + or_else + "; found '" + key + "'" +
                    hint);
  }
  std::map<std::string, double> params;
  if (!bare) {
    for (const auto& p : info->params) accepted.emplace_back(p.name);
    m->check_keys(accepted, "parameters of " + kind + " '" + key + "'");
    params = read_schema_params(*m, node, {info->params.begin(), info->params.end()},
                                kind + " '" + key + "'");
  } else {
    for (const auto& p : info->params)
      if (!p.default_value)
        node.fail("[missing key] " + kind + " '" + key + "' needs '" + std::string(p.name) + "' [" +
                  std::string(p.unit) + "]: " + std::string(p.description) +
                  "; write {model: " + key + ", " + std::string(p.name) + ": ...}");
  }
  return {std::move(key), info, std::move(params)};
}

}  // namespace gf::input
