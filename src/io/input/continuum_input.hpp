// SPDX-License-Identifier: GPL-3.0-or-later
// Parts shared by the continuum methods' blocks (`continuum:` SPH, `two_fluid:`): a
// kinetic-theory (KTGF) block, the output schedule.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "continuum/ktgf.hpp"
#include "core/params.hpp"
#include "io/input/model_block.hpp"
#include "io/input/yaml_reader.hpp"

namespace gf::input {

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
