// SPDX-License-Identifier: GPL-3.0-or-later
// The Nusselt correlations of coupling.heat_transfer (coupling/cfd_dem/heat_transfer.hpp): their
// limits, values against the formulas written out independently, and the registry.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "coupling/cfd_dem/heat_transfer.hpp"

using namespace gf::cfd_dem;

TEST(HeatTransferLaws, ASphereInStillFluidConductsAtNusseltTwo) {
  // Conduction from a sphere into an infinite still medium: Nu = 2 exactly, for both (Gunn's
  // first bracket is 7 - 10 + 5 = 2 at eps = 1).
  EXPECT_DOUBLE_EQ(nusselt(heat_transfer_index("ranz_marshall"), 0.0, 0.7, 1.0), 2.0);
  EXPECT_NEAR(nusselt(heat_transfer_index("gunn"), 0.0, 0.7, 1.0), 2.0, 1e-12);
}

TEST(HeatTransferLaws, ValuesOfTheFormulas) {
  // Ranz-Marshall at Re = 100, Pr = 0.7: 2 + 0.6 * 10 * 0.7^(1/3) = 7.3274...
  EXPECT_NEAR(nusselt(heat_transfer_index("ranz_marshall"), 100.0, 0.7, 0.4),
              2.0 + 6.0 * std::cbrt(0.7), 1e-12);
  // Gunn in a bed (eps = 0.4, Re = 100 so Re_e = 40, Pr = 0.7): the two brackets by hand,
  // (7 - 4 + 0.8) (1 + 0.7 * 40^0.2 * 0.7^(1/3)) + (1.33 - 0.96 + 0.192) 40^0.7 * 0.7^(1/3).
  const double pr3 = std::cbrt(0.7);
  const double gunn =
      3.8 * (1 + 0.7 * std::pow(40.0, 0.2) * pr3) + 0.562 * std::pow(40.0, 0.7) * pr3;
  EXPECT_NEAR(nusselt(heat_transfer_index("gunn"), 100.0, 0.7, 0.4), gunn, 1e-12 * gunn);
  // A dense bed transfers more than an isolated sphere at the same slip.
  EXPECT_GT(nusselt(heat_transfer_index("gunn"), 100.0, 0.7, 0.4),
            nusselt(heat_transfer_index("ranz_marshall"), 100.0, 0.7, 0.4));
  // h A = Nu k / d * A: a sphere of d = 2 mm in air at Nu = 2: 2 * 0.026 * pi * 0.002.
  EXPECT_NEAR(fluid_conductance(2.0, 0.026, 0.002, std::numbers::pi * 4e-6),
              2.0 * 0.026 * std::numbers::pi * 0.002, 1e-18);
}

TEST(HeatTransferLaws, Registry) {
  const auto infos = heat_transfer_infos();
  ASSERT_EQ(infos.size(), 2u);
  for (std::size_t i = 0; i < infos.size(); ++i) {
    EXPECT_EQ(heat_transfer_index(infos[i].key), static_cast<int>(i));
    ASSERT_NE(find_heat_transfer(infos[i].key), nullptr);
    EXPECT_FALSE(infos[i].reference.empty());
    EXPECT_FALSE(infos[i].validity.empty());
  }
  EXPECT_EQ(heat_transfer_index("dittus_boelter"), -1);
  EXPECT_EQ(find_heat_transfer("none"), nullptr);
}
