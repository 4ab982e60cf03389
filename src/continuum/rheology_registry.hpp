// SPDX-License-Identifier: GPL-3.0-or-later
// The one list of continuum rheologies. Name lookup, list-models, describe, input validation and
// the per-particle dispatch (a switch, no virtual call) all derive from `Rheologies`.
#pragma once

#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "continuum/rheology.hpp"
#include "core/registry.hpp"

namespace gf::continuum {

using Rheologies = TypeList<Newtonian, MuI>;

/// Description of a registered rheology, for the command line, the docs and the input reader.
struct RheologyInfo {
  std::string_view key, summary, equation, reference;
  std::span<const ParamSpec> params;
};

/// Every model of Rheologies, in list order.
std::vector<RheologyInfo> rheology_infos();
/// The model's description, or nullptr for an unknown key.
const RheologyInfo* find_rheology(std::string_view key);

/// Checks the parameters of model `key` against its schema (unknown key, unknown name, value
/// out of range, missing required value: gf::Error naming them) and derives the constants eval
/// reads; defaults fill what is not given.
RheologyParams prepare_rheology(std::string_view key,
                                const std::map<std::string, double>& params = {});

/// Apparent dynamic viscosity [Pa s] of the model p.model at shear rate gamma_dot [1/s] and
/// pressure [Pa].
GF_HOST_DEVICE inline double apparent_viscosity(double gamma_dot, double pressure,
                                                const RheologyParams& p) {
  return dispatch_index(Rheologies{}, p.model,
                        [&]<class M>() { return M::eval(gamma_dot, pressure, p); });
}

}  // namespace gf::continuum
