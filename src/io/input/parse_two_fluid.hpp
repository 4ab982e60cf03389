// SPDX-License-Identifier: GPL-3.0-or-later
// The `two_fluid:` block of a case file (Eulerian-Eulerian fluid + granular phase on a Cartesian
// grid, continuum::TwoFluidModel): parsed with located errors, and echoed resolved.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "continuum/two_fluid.hpp"
#include "io/input/continuum_input.hpp"
#include "io/input/yaml_reader.hpp"

namespace gf::input {

/// What a `two_fluid:` case defines besides the model's settings.
struct TwoFluidCase {
  std::string name;
  std::string file;  ///< the case file, for messages
  fluid::Grid grid;
  continuum::TwoFluidSettings settings;
  /// registry keys and parameters as given (no defaults), for the echo
  std::string closures, radial, dense, drag;
  std::map<std::string, double> ktgf_params, dense_params, drag_params;
  std::map<std::string, double> rheology_params;  ///< mu_i_switch: mu_s, mu_2, i0, max_viscosity
  /// particle-pressure model key ("" none) and its parameters as given
  std::string particle_pressure;
  std::map<std::string, double> particle_pressure_params;
  /// A box of the initial state (later boxes override earlier ones where they overlap).
  struct Region {
    Vec3 lo, hi;
    double solids_fraction = 0.0;
    Vec3 solids_velocity{};
  };
  std::vector<Region> initial;
  Vec3 fluid_velocity{};             ///< initial fluid velocity everywhere [m/s]
  double initial_temperature = 0.0;  ///< [m^2/s^2]
  /// Inlet jets (a strip of an inlet face with its own velocity), for the echo.
  struct Jet {
    int face = 0;
    double from = 0, to = 0;
    Vec3 velocity{};
  };
  std::vector<Jet> jets;
  double end_time = 0.0;  ///< [s]
  double max_step = 0.0;  ///< [s]
  /// [s] each; 0: first and last states only, every step, only two_fluid_checkpoint_final.h5
  OutputSchedule output;
  /// Allowed but probably not meant (also logged as warnings when parsed): a grid that needs
  /// more than half the memory.
  std::vector<std::string> warnings;
};

/// Parses the `two_fluid` block (the value under the key). Any error (unknown key, wrong type,
/// value out of range, missing key, unknown model or parameter, inconsistent boundaries) throws
/// gf::InputError with file:line:column, the key path, what was expected and what was found.
TwoFluidCase parse_two_fluid(const YamlNode& block);

/// The resolved case (defaults filled in) as YAML, with the program version.
std::string echo_two_fluid_yaml(const TwoFluidCase& c, const std::string& version);

}  // namespace gf::input
