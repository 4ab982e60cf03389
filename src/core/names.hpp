// SPDX-License-Identifier: GPL-3.0-or-later
// The rule for names that head CSV columns and series quantities (walls, fluid_fem bodies), and
// the names of a box's faces.
#pragma once

#include <algorithm>
#include <array>
#include <string_view>

namespace gf {

/// Letters, digits, '_' and '-', starting with a letter or '_' (ASCII): such a name reads back
/// the same from `NAME.fx`-style column headers with any CSV reader, a split on commas included.
inline bool is_column_name(std::string_view name) {
  auto letter = [](char ch) { return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z'); };
  return !name.empty() && (letter(name.front()) || name.front() == '_') &&
         std::all_of(name.begin(), name.end(), [&](char ch) {
           return letter(ch) || (ch >= '0' && ch <= '9') || ch == '_' || ch == '-';
         });
}

/// The faces of an axis-aligned box as the case file and the series name them (a box wall's
/// NAME.xmin, fluid.boundary's keys, fluid_boundary_heat_flow.FACE), index 2 axis + side.
inline constexpr std::array<std::string_view, 6> kBoxFaceNames = {"xmin", "xmax", "ymin",
                                                                  "ymax", "zmin", "zmax"};
/// The same faces as the two-fluid block's boundaries spell them; every block that takes a box's
/// faces as keys accepts both spellings.
inline constexpr std::array<std::string_view, 6> kBoxFaceAliases = {"x_min", "x_max", "y_min",
                                                                    "y_max", "z_min", "z_max"};

/// The index (2 axis + side) of a box face named either way; -1 for any other name.
inline int box_face_index(std::string_view name) {
  for (int k = 0; k < 6; ++k)
    if (name == kBoxFaceNames[k] || name == kBoxFaceAliases[k]) return k;
  return -1;
}

}  // namespace gf
