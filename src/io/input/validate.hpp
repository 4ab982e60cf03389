// SPDX-License-Identifier: GPL-3.0-or-later
// Whole-case cross-checks (domain, overlaps, time step vs contact times) and derived numbers.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "io/input/config.hpp"

namespace gf::input {

/// What `grainflow check` prints besides errors.
struct CheckReport {
  /// Human-readable derived numbers, in order: (what, value with unit).
  std::vector<std::pair<std::string, std::string>> derived;
  /// Things that are allowed but probably not meant.
  std::vector<std::string> warnings;
};

/// Checks what needs several blocks of the case at once and throws gf::InputError (with the
/// file:line:column of the culprit) on the first failure:
///  - every referenced material exists and every used material pair has a contacts entry;
///  - explicit particles lie inside the domain and do not overlap one another (cell method);
///  - fill regions lie inside the domain; periodic lengths exceed 2 (2 r_max + skin);
///  - the time step is at most 0.3 x min(Rayleigh time, contact time) (warning above 0.15 x).
///    The Rayleigh time (smallest grain of each material) counts for materials whose contacts
///    use elastic moduli (every model except hooke, whose stiffness is given directly); the
///    contact time is computed for every used pair with the two smallest grains, at an impact
///    speed max(initial speeds) + sqrt(2 |g| H), H the domain height along gravity, >= 0.1 m/s.
CheckReport validate(const config::Case& c);

}  // namespace gf::input
