// SPDX-License-Identifier: GPL-3.0-or-later
// Reading a case.yaml into a gf::config::Case: every key typed, range-checked and located.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "io/input/config.hpp"

namespace YAML {
class Node;
}

namespace gf::input {

/// Reads and checks a case file (see docs/case-file.md). Relative CSV paths are taken from the
/// case file's folder. Throws gf::InputError "FILE:LINE:COLUMN: error: KEY.PATH: ..." on the first
/// problem. Cross-checks that need the whole case (domain bounds of particles, overlaps, time
/// step) are done by validate() (validate.hpp).
config::Case load_case(const std::filesystem::path& file);

/// A value that replaces (or adds) one key of a case file before it is read, as given on the
/// command line: `shear.rate=100`, `particles[0].fill.volume_fraction=0.3`.
struct Override {
  std::string path;   ///< dot-separated keys, [i] for list items
  std::string value;  ///< YAML scalar text
};

/// Parses "KEY.PATH=VALUE"; throws gf::InputError for a malformed text.
Override parse_override(std::string_view text);

/// Applies overrides to a parsed YAML document in place (a missing list item is an error; a
/// missing map key is added); `file` names the case in messages. Throws gf::InputError.
void apply_overrides(const YAML::Node& root, const std::vector<Override>& overrides,
                     const std::filesystem::path& file);

/// load_case with overrides applied to the YAML first (a missing list item is an error; a
/// missing map key is added). Messages about an overridden value name its key path.
config::Case load_case(const std::filesystem::path& file, const std::vector<Override>& overrides);

/// Same as load_case, from text; `file` names the text in messages and locates relative paths.
config::Case load_case_text(const std::string& yaml_text, const std::filesystem::path& file);

/// Names accepted in `output.series.quantities` besides the per-wall ones PREFIX.WALL (each also
/// with a .x, .y or .z component suffix), PREFIX one of wall_series_prefixes().
const std::vector<std::string>& series_quantity_names();

/// The quantities of series_quantity_names() that are vectors: NAME gives three columns NAME.x,
/// NAME.y, NAME.z, and NAME.x (.y, .z) one component ("fixed_force", "fixed_torque").
std::span<const std::string_view> vector_series_quantities();

/// The per-wall series quantities, with their dot: "wall_force.", "wall_torque.",
/// "wall_force_mean.", "wall_torque_mean.", "wall_position.".
std::span<const std::string_view> wall_series_prefixes();

/// The outlet series prefix `quantity` starts with ("outlet_mass.": the mass that left through
/// outlet OUTLET so far, kg; "outlet_count.": the number of grains), or empty.
std::string_view outlet_series_prefix(std::string_view quantity);

/// The flow-meter series prefix `quantity` starts with ("flow_mass.": the net mass that crossed
/// meter METER along its normal so far, kg; "flow_count.": the net number of grains;
/// "flow_rate.": the net mass per time over the interval since the previous series row, kg/s),
/// or empty.
std::string_view flow_meter_series_prefix(std::string_view quantity);

/// The region series prefix `quantity` starts with ("region_count.": the number of free grains
/// whose centres lie in region REGION now; "region_mass.": their mass, kg), or empty.
std::string_view region_series_prefix(std::string_view quantity);

/// Whether `quantity` is an accepted series quantity for a case with walls named `wall_names`
/// (the outlet and flow-meter quantities are checked against their names by the reader).
bool is_series_quantity(std::string_view quantity, const std::vector<std::string>& wall_names);

}  // namespace gf::input
