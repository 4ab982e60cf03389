// SPDX-License-Identifier: GPL-3.0-or-later
// The resolved case (defaults filled in) written back as YAML, for the output folder.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "io/input/config.hpp"
#include "io/input/parse_continuum.hpp"

namespace gf::input {

/// Explicit particle lists longer than this are summarised (count and source) in the echo.
inline constexpr std::size_t echo_max_listed_particles = 20;

/// A file that a resolved case refers to, to be written beside it: its name (relative to the
/// resolved case's folder) and its text.
struct EchoFile {
  std::string name;
  std::string text;
};

/// YAML text of the resolved configuration, opening with a comment that names the program
/// version and the case file. With `files`, the explicit particles of a group read from a CSV
/// file or listed inline beyond echo_max_listed_particles go to a CSV file of their own
/// (resolved_particles_<group index>.csv, the columns of `particles[].file`) that the echo names
/// as the group's `file` and appends to `files`: written beside the echo, the two load back into
/// the same Case (orientations to round-off: the CSV reader normalises quaternions), whatever
/// becomes of the source files. Without `files` a CSV source is named by its absolute path and
/// long inline lists are summarised as {count, source} (a digest for comparing plans, not a
/// loadable case).
std::string echo_yaml(const config::Case& c, std::string_view program_version,
                      std::vector<EchoFile>* files = nullptr);

/// The same for a continuum case (`continuum:` block): every key with its value, defaults and
/// derived defaults (the sound speed, the rheology's parameters) filled in; loading it back gives
/// the same ContinuumCase.
std::string echo_continuum_yaml(const ContinuumCase& c, std::string_view program_version);

}  // namespace gf::input
