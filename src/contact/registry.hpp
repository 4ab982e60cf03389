// SPDX-License-Identifier: GPL-3.0-or-later
// The one list of contact models. Name lookup, list-models, describe, input validation and
// the force-loop dispatch all derive from `ContactModels`.
#pragma once

#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "contact/models.hpp"
#include "core/registry.hpp"

namespace gf::contact {

using ContactModels = TypeList<Hooke, HertzMindlin>;

/// Description of a registered model, for the command line and the input reader.
struct ModelInfo {
  std::string_view key, summary, equation, reference;
  std::span<const ParamSpec> params;
};

std::vector<ModelInfo> model_infos();
/// Index in ContactModels, or -1.
int model_index(std::string_view key);
const ModelInfo* find_model(std::string_view key);

/// Derives the pair constants of model `key` from parameter values (defaults already filled).
PairCoeffs prepare_pair(std::string_view key, const PairContext& ctx,
                        const std::map<std::string, double>& params);

/// Contact duration (s) of a binary elastic collision at impact speed v (Hertz) or any speed
/// (hooke).
double contact_time(const PairCoeffs& c, double r_eff, double m_eff, double v);

/// Rayleigh time t_R = pi r sqrt(rho / G) / (0.1631 nu + 0.8766), s (Li et al. 2005).
double rayleigh_time(const Material& m, double radius);

}  // namespace gf::contact
