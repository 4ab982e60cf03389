// SPDX-License-Identifier: GPL-3.0-or-later
// A small fluid_fem case (a channel with a turning disk and a triangle) shared by the FEM case
// tests and the restart tests, and a helper that edits it.
#pragma once

#include <gtest/gtest.h>

#include <string>

namespace gf::test {

inline constexpr const char* kFemChannelCase = R"(fluid_fem:
  fluid: {density: 1.0, viscosity: 0.01}
  domain:
    outline: [[0, 0], [1, 0], [1, 0.4], [0, 0.4]]
    boundaries:
      - {edges: [0, 2], type: wall}
      - {edges: [1], type: outflow}
      - {edges: [3], type: inflow, u_max: 0.5, time_function: {type: ramp, duration: 0.1}}
  bodies:
    - {name: disk, circle: {centre: [0.3, 0.2], radius: 0.05}, angular_velocity: 1.0}
    - {name: tri, polygon: [[0.6, 0.15], [0.7, 0.15], [0.65, 0.25]]}
  mesh: {h_max: 0.08, h_body: 0.03, grading: 0.3}
  time: {mode: unsteady, scheme: bdf2, step: 0.05, end: 0.2}
  output: {vtk_every: 0.1, probes: [[0.9, 0.2]], coefficients: {velocity: 0.33, length: 0.1}}
)";

/// `s` with its first `from` replaced by `to` (a test failure if `from` is absent).
inline std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? s : s.replace(at, from.size(), to);
}

}  // namespace gf::test
