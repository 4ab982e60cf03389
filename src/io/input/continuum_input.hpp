// SPDX-License-Identifier: GPL-3.0-or-later
// Parts shared by the continuum methods' blocks (`continuum:` SPH, `two_fluid:`): a model's
// parameters against its registry schema, a kinetic-theory (KTGF) block, the output schedule.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "continuum/ktgf.hpp"
#include "core/params.hpp"
#include "io/input/yaml_reader.hpp"

namespace gf::input {

/// The parameters of a model's schema from map `m` (the node `node`): each in its range, every
/// one without a default required ("[missing key] WHAT needs 'name' [unit]: description").
std::map<std::string, double> read_schema_params(const YamlMap& m, const YamlNode& node,
                                                 const std::vector<ParamSpec>& schema,
                                                 const std::string& what);

/// A `{model: KEY, ...parameters}` block of registry `infos` (each with .key and .params): the
/// key, its info and its parameters as given (range-checked; required ones present). An unknown
/// key fails with "a `kind`: k1, k2, ...`or_else`", an unknown parameter with its name.
template <class Info>
std::tuple<std::string, const Info*, std::map<std::string, double>> read_model_block(
    const YamlNode& node, const std::vector<Info>& infos, const std::string& kind,
    const std::string& or_else = "") {
  YamlMap m(node);
  const auto model_node = m.at("model");
  std::string key = model_node.as_string();
  const Info* info = nullptr;
  std::vector<std::string> keys, accepted{"model"};
  for (const auto& i : infos) {
    keys.emplace_back(i.key);
    if (i.key == key) info = &i;
  }
  if (!info) model_node.fail_expected("a " + kind + ": " + join(keys) + or_else);
  for (const auto& p : info->params) accepted.emplace_back(p.name);
  m.check_keys(accepted, "parameters of " + kind + " '" + key + "'");
  auto params = read_schema_params(m, node, {info->params.begin(), info->params.end()},
                                   kind + " '" + key + "'");
  return {std::move(key), info, std::move(params)};
}

/// A KTGF block as read: registry keys, parameters as given, and the prepared constants.
struct KtgfInput {
  std::string closures, radial, dense;
  std::map<std::string, double> params, dense_params;
  continuum::KtgfParams ktgf;
  std::optional<continuum::FrictionalParams> frictional;  ///< none: `dense: none`
};

/// Reads {closures (default lun), radial_distribution (default carnahan_starling), the set's and
/// the distribution's parameters (restitution, grain_diameter, grain_density, ...), dense:
/// {model, ...} (default `default_dense`; `none` when allow_none)} plus the caller's `extra`
/// keys (read by the caller). Errors are located InputErrors.
KtgfInput read_ktgf_input(const YamlNode& block, const std::vector<std::string>& extra,
                          const std::string& default_dense, bool allow_none);

/// The output schedule {vtk_every, series_every, checkpoint_every} [s], each >= 0.
struct OutputSchedule {
  double vtk_every = 0.0, series_every = 0.0, checkpoint_every = 0.0;
};
OutputSchedule read_output_schedule(const YamlNode& node);

}  // namespace gf::input
