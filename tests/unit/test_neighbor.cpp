// SPDX-License-Identifier: GPL-3.0-or-later
// Neighbour lists against the brute-force oracle, with and without periodicity, and the
// history carried across rebuilds.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "neighbor/brute_force.hpp"
#include "neighbor/verlet_list.hpp"

using namespace gf;

namespace {

struct Cloud {
  std::vector<Vec3> x;
  std::vector<double> r;
};

Cloud random_cloud(const Domain& d, int n, double rmin, double rmax, unsigned seed) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(0, 1);
  Cloud c;
  for (int i = 0; i < n; ++i) {
    const Vec3 L = d.length();
    c.x.push_back({d.lo.x + u(g) * L.x, d.lo.y + u(g) * L.y, d.lo.z + u(g) * L.z});
    c.r.push_back(rmin + (rmax - rmin) * u(g));
  }
  return c;
}

std::vector<std::pair<int, int>> list_pairs(const VerletList& l) {
  std::vector<std::pair<int, int>> out;
  for (std::size_t i = 0; i < l.n_particles(); ++i)
    for (auto k = l.offsets()[i]; k < l.offsets()[i + 1]; ++k)
      out.emplace_back(static_cast<int>(i), l.neighbors()[k]);
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

class NeighborOracle : public ::testing::TestWithParam<std::array<bool, 3>> {};

TEST_P(NeighborOracle, VerletListEqualsBruteForce) {
  Domain d{{-0.1, 0.0, 0.2}, {0.5, 0.33, 0.61}, GetParam()};
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Cloud c = random_cloud(d, 1500, 0.004, 0.012, seed);  // polydisperse, factor 3
    const double skin = 0.003;
    VerletList l;
    l.build(d, c.x.data(), c.r.data(), c.x.size(), skin);
    const auto expected = brute_force_pairs(d, c.x.data(), c.r.data(), c.x.size(), skin);
    ASSERT_GT(expected.size(), 100u);
    EXPECT_EQ(list_pairs(l), expected) << "seed " << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(Periodicity, NeighborOracle,
                         ::testing::Values(std::array<bool, 3>{false, false, false},
                                           std::array<bool, 3>{true, true, true},
                                           std::array<bool, 3>{true, false, true}));

TEST(Neighbor, SmallPeriodicBoxWithFewCells) {
  // Two and three cells per periodic direction: stencil cells must not be visited twice.
  Domain d{{0, 0, 0}, {0.1, 0.1, 0.1}, {true, true, true}};
  const Cloud c = random_cloud(d, 300, 0.005, 0.01, 7);
  VerletList l;
  l.build(d, c.x.data(), c.r.data(), c.x.size(), 0.01);
  EXPECT_EQ(list_pairs(l), brute_force_pairs(d, c.x.data(), c.r.data(), c.x.size(), 0.01));
}

TEST(Neighbor, ParticlesOutsideNonPeriodicBoundsAreFound) {
  Domain d{{0, 0, 0}, {1, 1, 1}, {false, false, false}};
  std::vector<Vec3> x{{0.5, 0.5, 1.5}, {0.5, 0.5, 1.52}, {0.5, 0.5, -3.0}, {0.51, 0.5, -3.0}};
  std::vector<double> r{0.011, 0.011, 0.01, 0.01};
  VerletList l;
  l.build(d, x.data(), r.data(), x.size(), 0.001);
  EXPECT_EQ(list_pairs(l), (std::vector<std::pair<int, int>>{{0, 1}, {2, 3}}));
}

TEST(Neighbor, HistorySurvivesRebuildAndSkinCriterion) {
  Domain d{{0, 0, 0}, {1, 1, 1}, {false, false, false}};
  std::vector<Vec3> x{{0.5, 0.5, 0.5}, {0.519, 0.5, 0.5}, {0.8, 0.8, 0.8}};
  std::vector<double> r{0.01, 0.01, 0.01};
  VerletList l;
  l.build(d, x.data(), r.data(), x.size(), 0.004);
  ASSERT_EQ(l.n_pairs(), 1u);
  l.history()[0] = {1e-6, 2e-6, 0};
  x[2].x += 0.0019;  // less than skin / 2
  EXPECT_FALSE(l.needs_rebuild(d, x.data(), x.size()));
  x[2].x += 0.0002;  // now more than skin / 2
  EXPECT_TRUE(l.needs_rebuild(d, x.data(), x.size()));
  x[2] = {0.53, 0.5, 0.5};  // a new neighbour of both
  l.build(d, x.data(), r.data(), x.size(), 0.004);
  ASSERT_EQ(l.n_pairs(), 2u);  // (0,1) kept, (1,2) new; (0,2) too far
  EXPECT_EQ(l.neighbors()[0], 1);
  EXPECT_EQ(l.history()[0], (Vec3{1e-6, 2e-6, 0}));
  EXPECT_EQ(l.history()[1], (Vec3{}));
}
