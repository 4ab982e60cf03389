// SPDX-License-Identifier: GPL-3.0-or-later
// The rule for names that head CSV columns and series quantities (walls, fluid_fem bodies).
#pragma once

#include <algorithm>
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

}  // namespace gf
