// SPDX-License-Identifier: GPL-3.0-or-later
// The resolved case (defaults filled in) written back as YAML, for the output folder.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "io/input/config.hpp"
#include "io/input/parse_continuum.hpp"

namespace gf::input {

/// Explicit particle lists longer than this are summarised (count and source) in the echo.
inline constexpr std::size_t echo_max_listed_particles = 20;

/// YAML text of the resolved configuration, opening with a comment that names the program
/// version and the case file. Loading it back gives the same Case, except that inline particle
/// lists longer than echo_max_listed_particles are summarised as {count, source}.
std::string echo_yaml(const config::Case& c, std::string_view program_version);

/// The same for a continuum case (`continuum:` block): every key with its value, defaults and
/// derived defaults (the sound speed, the rheology's parameters) filled in; loading it back gives
/// the same ContinuumCase.
std::string echo_continuum_yaml(const ContinuumCase& c, std::string_view program_version);

}  // namespace gf::input
