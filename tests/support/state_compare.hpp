// SPDX-License-Identifier: GPL-3.0-or-later
// Bit-for-bit comparison of two simulation states (restart and determinism tests).
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <span>
#include <variant>

#include "simulation/simulation.hpp"

namespace gf::test {

template <class T>
inline bool same_bits(std::span<const T> a, std::span<const T> b) {
  // (memcmp must not see the null data() of an empty span, even for 0 bytes)
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size_bytes()) == 0);
}

/// Every particle field, the contact histories, wall forces and wall positions are identical.
inline void expect_same_state(const Simulation& a, const Simulation& b) {
  ASSERT_EQ(a.particles().size(), b.particles().size());
  for (const auto& f : a.particles().fields()) {
    const int k = a.particles().find_field(f.name);
    std::visit(
        [&](const auto& va) {
          using V = std::decay_t<decltype(va)>;
          const auto& vb = std::get<V>(b.particles().column(k));
          EXPECT_TRUE(same_bits(std::span(va), std::span(vb))) << "field " << f.name;
        },
        a.particles().column(k));
  }
  EXPECT_TRUE(same_bits(a.neighbor_list().history(), b.neighbor_list().history()));
  for (std::size_t w = 0; w < a.walls().size(); ++w) {
    EXPECT_EQ(a.walls()[w].force, b.walls()[w].force);
    EXPECT_EQ(a.walls()[w].point, b.walls()[w].point);
  }
}

}  // namespace gf::test
