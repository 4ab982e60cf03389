// SPDX-License-Identifier: GPL-3.0-or-later
// Checking model parameters against their schema (shared by every model registry).
#include "core/params.hpp"

#include "core/error.hpp"

namespace gf {

void check_params(std::string_view what, std::span<const ParamSpec> specs,
                  const std::map<std::string, double>& params, bool require_all) {
  for (const auto& [name, value] : params) {
    const ParamSpec* spec = nullptr;
    for (const auto& s : specs)
      if (s.name == name) spec = &s;
    REQUIRE(spec != nullptr, "{} has no parameter '{}'", what, name);
    const bool low_ok = spec->min_exclusive ? value > spec->min : value >= spec->min;
    REQUIRE(low_ok && value <= spec->max, "{}: {} = {} is outside {}{}, {}]", what, name, value,
            spec->min_exclusive ? "(" : "[", spec->min, spec->max);
  }
  if (!require_all) return;
  for (const auto& s : specs)
    REQUIRE(s.default_value || params.count(std::string(s.name)),
            "{} needs the parameter '{}' [{}] ({})", what, s.name, s.unit, s.description);
}

}  // namespace gf
