// SPDX-License-Identifier: GPL-3.0-or-later
// Parameter schema a model declares: name, unit, default, admissible range, scope, meaning.
#pragma once

#include <limits>
#include <optional>
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

}  // namespace gf
