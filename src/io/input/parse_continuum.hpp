// SPDX-License-Identifier: GPL-3.0-or-later
// The `continuum:` block of a case file (the granular phase or a liquid as a continuum, solved
// with SPH): parsed into continuum::SphConfig with located errors.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "continuum/sph.hpp"
#include "io/input/continuum_input.hpp"
#include "io/input/yaml_reader.hpp"

namespace gf::input {

/// What a `continuum:` case defines besides the solver's own configuration.
struct ContinuumCase {
  std::string name;
  std::string file;  ///< the case file, for messages
  continuum::SphConfig sph;
  std::string rheology;                           ///< registry key of the rheology
  std::map<std::string, double> rheology_params;  ///< its parameters as given (no defaults)
  /// kinetic theory (sph.kinetic_theory set): the keys of the closure set, radial distribution
  /// and dense-regime model, and their parameters as given (no defaults)
  std::string ktgf_closures, ktgf_radial, ktgf_dense;
  std::map<std::string, double> ktgf_params, ktgf_dense_params;
  double end_time = 0.0;  ///< [s]
  /// [s] each; 0: the first and last states only, every step, only sph_checkpoint_final.h5
  OutputSchedule output;
  bool sound_speed_given = false;  ///< false: c0 = 10 sqrt(2 |g| H), H the fluid's height
  /// Allowed but probably not meant (also logged as warnings when parsed): thin walls, a case
  /// that needs more than half the memory.
  std::vector<std::string> warnings;
};

/// Parses the `continuum` block `block` (the value under the key). Any error (unknown key, wrong
/// type, value out of range, missing key, unknown rheology or parameter) throws gf::InputError
/// with file:line:column, the key path, what was expected and what was found.
ContinuumCase parse_continuum(const YamlNode& block);

}  // namespace gf::input
