// SPDX-License-Identifier: GPL-3.0-or-later
// The Lacey mixing index: exact for hand-counted cells and for a segregated bed (0), about 1 for
// a random mixture within its sampling scatter; the series quantity of a case.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "analysis/mixing.hpp"
#include "case_builder.hpp"
#include "simulation/simulation.hpp"

using namespace gf;

namespace {

/// A 10 x 10 x 10 simple cubic lattice of points (spacing 1 cm) in the cube [0, 0.1]^3; with
/// cells of 2 cm, 125 cells of 8 points each.
std::vector<Vec3> lattice() {
  std::vector<Vec3> x;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 10; ++k)
        x.push_back({0.005 + 0.01 * i, 0.005 + 0.01 * j, 0.005 + 0.01 * k});
  return x;
}

}  // namespace

// Three cells counted by hand: 4 grains (3 A), 2 grains (0 A) and 6 grains (3 A), and one cell
// of 1 grain left out by min_grains = 2. p = 6/12, s^2 = (4 (3/4 - 1/2)^2 + 2 (0 - 1/2)^2 +
// 6 (1/2 - 1/2)^2) / 12 = (1/4 + 1/2) / 12 = 1/16, s0^2 = 1/4, n = 4, sr^2 = 1/16: M = 1.
// With the last cell all A instead: p = 9/12, s^2 = (4 0 + 2 (3/4)^2 + 6 (1/4)^2) / 12 = 1.5/12,
// s0^2 = 3/16, sr^2 = 3/64, M = (3/16 - 1/8) / (3/16 - 3/64) = 4/9.
TEST(LaceyIndex, MatchesHandCountedCells) {
  std::vector<Vec3> x;
  std::vector<std::int32_t> kind;
  const auto put = [&](double cx, int a, int b) {
    for (int i = 0; i < a + b; ++i) {
      x.push_back({cx + 0.0005 * i, 0.05, 0.05});
      kind.push_back(i < a ? 0 : 1);
    }
  };
  put(0.005, 3, 1);
  put(0.015, 0, 2);
  put(0.025, 3, 3);
  put(0.035, 1, 0);  // one grain: not counted
  x.push_back({0.045, 0.05, 0.05});
  kind.push_back(-1);  // not a kind: ignored
  auto r = analysis::lacey_index(x.data(), kind.data(), x.size(), {0, 0, 0}, {0.1, 0.1, 0.1}, 0.01,
                                 3, 2);
  EXPECT_EQ(r.cells, 3u);
  EXPECT_DOUBLE_EQ(r.fraction, 0.5);
  EXPECT_DOUBLE_EQ(r.variance, 1.0 / 16);
  EXPECT_DOUBLE_EQ(r.per_cell, 4.0);
  EXPECT_NEAR(r.index, 1.0, 1e-14);
  for (std::size_t i = 6; i < 12; ++i) kind[i] = 0;
  r = analysis::lacey_index(x.data(), kind.data(), x.size(), {0, 0, 0}, {0.1, 0.1, 0.1}, 0.01, 3,
                            2);
  EXPECT_DOUBLE_EQ(r.fraction, 0.75);
  EXPECT_NEAR(r.index, 4.0 / 9.0, 1e-14);
}

// Segregated (one kind left of x = 0.06, the other right: every 2 cm cell pure): M = 0; the
// same lattice with kinds drawn at random (p = 1/2): M about 1. Its scatter: s^2 of 125 cells of
// 8 grains has a relative standard deviation of about sqrt(2 / 125) = 0.13, which moves M by
// 0.13 sr^2 / (s0^2 - sr^2) = 0.13 / 7 = 0.018; the bound 0.08 is over 4 of those, and 20 draws
// must average within 0.02 of 1 (0.018 / sqrt(20) = 0.004, and the estimate of p biases s^2 low
// by 1/125 of sr^2 only).
TEST(LaceyIndex, ZeroSegregatedAboutOneRandom) {
  const auto x = lattice();
  std::vector<std::int32_t> kind(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) kind[i] = x[i].x < 0.06 ? 0 : 1;
  const auto seg = analysis::lacey_index(x.data(), kind.data(), x.size(), {0, 0, 0},
                                         {0.1, 0.1, 0.1}, 0.02, 3, 5);
  EXPECT_EQ(seg.cells, 125u);
  EXPECT_DOUBLE_EQ(seg.per_cell, 8.0);
  EXPECT_NEAR(seg.index, 0.0, 1e-12);
  std::mt19937_64 g(3);
  double mean = 0;
  for (int draw = 0; draw < 20; ++draw) {
    for (auto& k : kind) k = static_cast<std::int32_t>(g() % 2);
    const auto r = analysis::lacey_index(x.data(), kind.data(), x.size(), {0, 0, 0},
                                         {0.1, 0.1, 0.1}, 0.02, 3, 5);
    EXPECT_NEAR(r.index, 1.0, 0.08) << "draw " << draw;
    mean += r.index / 20;
  }
  EXPECT_NEAR(mean, 1.0, 0.02);
  // One kind only: undefined, reported as 0.
  std::fill(kind.begin(), kind.end(), 1);
  EXPECT_EQ(
      analysis::lacey_index(x.data(), kind.data(), x.size(), {0, 0, 0}, {0.1, 0.1, 0.1}, 0.02, 3, 5)
          .index,
      0.0);
}

// In a case: the series quantity lacey_index is the function's value over the free grains of
// the two materials (2D: square cells); fixed grains and a third material are left out.
TEST(LaceyIndex, SeriesQuantityOfACase) {
  auto c = test::base_case(1e-5, 0.1, {0, 0, 0}, {0.1, 0.1, 0});
  c.dimension = 2;
  c.domain.thickness = 0.002;
  const std::vector<std::string> mats{"red", "blue", "grey"};
  for (const auto& a : mats) test::add_material(c, a, 2500, 1e7, 0.3);
  for (std::size_t a = 0; a < mats.size(); ++a)
    for (std::size_t b = a; b < mats.size(); ++b)
      test::add_contact(c, mats[a], mats[b], "hertz_mindlin", {{"restitution", 0.5}});
  std::vector<Vec3> left, right, base;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      (i < 4 ? left : right).push_back({0.005 + 0.01 * i, 0.005 + 0.01 * j, 0});
  for (int i = 0; i < 3; ++i) base.push_back({0.02 + 0.03 * i, 0.095, 0});
  test::add_disks(c, "red", 0.002, left);
  test::add_disks(c, "blue", 0.002, right);
  test::add_disks(c, "grey", 0.002, base).fixed = true;
  config::Mixing m;
  m.materials = {"red", "blue"};
  m.cell = 0.02;
  m.min_grains = 2;
  c.analysis.mixing = m;
  const Simulation sim(c);
  EXPECT_NEAR(sim.quantity("lacey_index"), 0.0, 1e-12);  // x < 0.04 red: every cell pure
  const auto r = sim.lacey_index();
  EXPECT_EQ(r.cells, 25u);
  EXPECT_DOUBLE_EQ(r.fraction, 0.4);  // 40 red of 100 (the 3 grey fixed ones left out)
  EXPECT_DOUBLE_EQ(r.per_cell, 4.0);
}
