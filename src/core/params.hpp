// SPDX-License-Identifier: GPL-3.0-or-later
// Parameter schema a model declares: name, unit, default, admissible range, scope, meaning.
#pragma once

#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace gf {

enum class ParamScope { PerMaterial, PerPair };

struct ParamSpec {
  std::string_view name;
  std::string_view unit;                ///< SI unit, "1" for dimensionless
  std::optional<double> default_value;  ///< empty: required (unless the model says otherwise)
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;
  ParamScope scope = ParamScope::PerPair;
  std::string_view description;
};

/// Checks given parameter values against a model's schema: every name must be in `specs` and
/// every value in its range (gf::Error naming `what`, e.g. "drag law 'wen_yu'", the parameter
/// and the range), and with `require_all` every parameter without a default must be given.
void check_params(std::string_view what, std::span<const ParamSpec> specs,
                  const std::map<std::string, double>& params, bool require_all = false);

/// The value of `name` in `params`, if given (the accessor models' prepare() functions read).
inline std::optional<double> param_value(const std::map<std::string, double>& params,
                                         std::string_view name) {
  const auto it = params.find(std::string(name));
  if (it == params.end()) return std::nullopt;
  return it->second;
}

}  // namespace gf
