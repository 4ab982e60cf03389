// SPDX-License-Identifier: GPL-3.0-or-later
// Neighbour lists against the brute-force oracle, with and without periodicity, and the
// history carried across rebuilds.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <map>
#include <numeric>
#include <random>

#include "neighbor/brute_force.hpp"
#include "neighbor/cell_list.hpp"
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

// A sparse cloud in a big box (cut-off ~5 mm in a 4 m box: 800^3 cells by the cut-off): the grid
// is coarsened to at most max(2^20, 8 n) cells, whose edges stay above the cut-off, and the
// list still equals the oracle (periodic and not).
TEST(Neighbor, SparseCloudInAHugeBoxGetsACoarserGridAndTheSamePairs) {
  for (const bool periodic : {false, true}) {
    Domain d{{0, 0, 0}, {4.0, 4.0, 4.0}, {periodic, periodic, periodic}};
    Cloud c = random_cloud(d, 2000, 0.002, 0.002, 11);
    // clusters of touching grains, so that there are pairs to find
    for (int i = 0; i < 2000; i += 4)
      for (int k = 1; k < 4 && i + k < 2000; ++k) c.x[i + k] = c.x[i] + Vec3{0.0045 * k, 0, 0};
    VerletList l;
    l.build(d, c.x.data(), c.r.data(), c.x.size(), 0.001);
    const auto expected = brute_force_pairs(d, c.x.data(), c.r.data(), c.x.size(), 0.001);
    ASSERT_GT(expected.size(), 1000u);
    EXPECT_EQ(list_pairs(l), expected) << periodic;
    const auto nc = CellList::grid(d.length(), 0.005, c.x.size());
    EXPECT_LE(static_cast<double>(nc[0]) * nc[1] * nc[2], 1048576.0);
    for (int k = 0; k < 3; ++k) EXPECT_GE(4.0 / nc[k], 0.005);
  }
}

// The cell stencil against geometry: every cell with an image (periodic, Lees-Edwards shifted)
// closer than the cutoff to cell c must be in c's stencil, which is ascending and without
// repeats, for grids of 1-5 cells per axis (folds onto the same cell), with and without
// periodicity, and Lees-Edwards offsets across the flow axis's range.
TEST(Neighbor, CellStencilHoldsEveryCellWithinTheCutoff) {
  struct Setup {
    std::array<bool, 3> periodic;
    int gradient;  // -1: no Lees-Edwards
  };
  const std::vector<Setup> setups{{{false, false, false}, -1},
                                  {{true, true, true}, -1},
                                  {{true, false, true}, -1},
                                  {{true, true, true}, 2},
                                  {{false, true, true}, 2}};
  const double cutoff = 1.0;
  int checked = 0;
  for (const Setup& su : setups)
    for (int nx = 1; nx <= 5; ++nx)
      for (int nz = 1; nz <= 5; nz += 2)
        for (double frac : {0.0, 0.13, -0.37, 0.49}) {
          // Cells of edge >= cutoff: the grid has floor(L / cutoff) cells per axis.
          Domain d{{0, 0, 0}, {nx * 1.1, 3.3, nz * 1.05}, su.periodic};
          if (su.gradient >= 0) {
            if (!su.periodic[0]) continue;
            d.shear_gradient = su.gradient;
            d.shear_flow = 0;
            d.shear_offset = frac * d.length().x;
          } else if (frac != 0.0) {
            continue;
          }
          CellList cells;
          const Vec3 one{0.5, 0.5, 0.5};
          cells.build(d, &one, 1, cutoff);
          const auto n = cells.dims();
          const Vec3 L = d.length();
          const Vec3 h{L.x / n[0], L.y / n[1], L.z / n[2]};
          for (int c = 0; c < cells.n_cells(); ++c) {
            int st[36];
            const int ns = cells.stencil(c, st);
            ASSERT_LE(ns, su.gradient >= 0 ? 36 : 27);
            for (int k = 1; k < ns; ++k) ASSERT_LT(st[k - 1], st[k]) << "cell " << c;
            // The cell's box from a point inside it.
            auto box_lo = [&](int cell) {
              for (int ix = 0; ix < n[0]; ++ix)
                for (int iy = 0; iy < n[1]; ++iy)
                  for (int iz = 0; iz < n[2]; ++iz) {
                    const Vec3 lo{ix * h.x, iy * h.y, iz * h.z};
                    if (cells.cell_of(lo + 0.5 * h) == cell) return lo;
                  }
              return Vec3{-1, -1, -1};
            };
            const Vec3 a = box_lo(c);
            for (int e = 0; e < cells.n_cells(); ++e) {
              const Vec3 b0 = box_lo(e);
              bool near = false;
              for (int sx = -2; sx <= 2 && !near; ++sx)
                for (int sy = -1; sy <= 1 && !near; ++sy)
                  for (int sz = -1; sz <= 1 && !near; ++sz) {
                    if ((sx != 0 && !d.periodic[0]) || (sy != 0 && !d.periodic[1]) ||
                        (sz != 0 && !d.periodic[2]))
                      continue;
                    Vec3 b{b0.x + sx * L.x, b0.y + sy * L.y, b0.z + sz * L.z};
                    if (d.shear_gradient == 2) b.x += sz * d.shear_offset;
                    double gap2 = 0;
                    for (int k = 0; k < 3; ++k) {
                      const double gap =
                          std::max({0.0, b[k] - (a[k] + h[k]), a[k] - (b[k] + h[k])});
                      gap2 += gap * gap;
                    }
                    near = gap2 < 0.999 * cutoff * cutoff;
                  }
              if (near) {
                ASSERT_TRUE(std::binary_search(st, st + ns, e))
                    << "cell " << e << " near cell " << c << ", grid " << n[0] << "x" << n[1] << "x"
                    << n[2] << ", offset " << d.shear_offset;
              }
              ++checked;
            }
          }
        }
  EXPECT_GT(checked, 10000);
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

// The in-place re-ordering (cycle following) against a gathered copy, for every column type.
TEST(Neighbor, StorePermuteInPlaceEqualsGather) {
  ParticleStore p;
  p.enable_shapes();  // adds Quat and int32 columns
  const int n = 1000;
  std::mt19937_64 g(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < n; ++i)
    p.add_sphere(100 + i, i % 3, 0.01 + 0.001 * u(g), 2500, {u(g), u(g), u(g)}, {u(g), 0, 0});
  for (int i = 0; i < n; ++i) p.orientation()[i] = Quat{u(g), u(g), u(g), u(g)};
  // Fixed points (0..5) and long cycles (the shuffled rest) both occur.
  std::vector<std::int64_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin() + 6, order.end(), g);
  const ParticleStore before = p;
  p.permute(order);
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(order[static_cast<std::size_t>(i)]);
    EXPECT_EQ(p.id()[i], before.id()[k]);
    EXPECT_EQ(p.x()[i], before.x()[k]);
    EXPECT_EQ(p.v()[i], before.v()[k]);
    EXPECT_EQ(p.radius()[i], before.radius()[k]);
    EXPECT_EQ(p.material()[i], before.material()[k]);
    EXPECT_EQ(p.orientation()[i].w, before.orientation()[k].w);
    EXPECT_EQ(p.orientation()[i].z, before.orientation()[k].z);
  }
  std::vector<std::int64_t> bad(static_cast<std::size_t>(n), 0);  // not a permutation
  EXPECT_THROW(p.permute(bad), std::exception);
}

// Histories follow their pairs through re-ordering rebuilds: only the touching pairs' entries
// are kept between the old and the new list (the rest carry zero), checked by particle ids.
TEST(Neighbor, HistoryFollowsPairsThroughSortedRebuilds) {
  Domain d{{0, 0, 0}, {0.3, 0.3, 0.3}, {true, false, true}};
  const Cloud c = random_cloud(d, 2000, 0.004, 0.008, 11);
  ParticleStore p;
  for (std::size_t i = 0; i < c.x.size(); ++i)
    p.add_sphere(static_cast<std::int64_t>(i), 0, c.r[i], 2500, c.x[i]);
  VerletList l;
  const double skin = 0.003;
  l.sort_and_build(p, d, skin);
  // Give every other entry a history (one with a negative zero component), keyed by ids.
  std::map<std::pair<std::int64_t, std::int64_t>, Vec3> by_ids;
  std::mt19937_64 g(3);
  std::uniform_real_distribution<double> u(-1e-5, 1e-5);
  for (std::size_t i = 0; i < l.n_particles(); ++i)
    for (auto k = l.offsets()[i]; k < l.offsets()[i + 1]; ++k) {
      if (k % 2 == 1) continue;
      const std::int32_t j = l.neighbors()[static_cast<std::size_t>(k)];
      const Vec3 h = k % 4 == 0 ? Vec3{u(g), u(g), u(g)} : Vec3{u(g), -0.0, 0.0};
      l.history()[static_cast<std::size_t>(k)] = h;
      by_ids[{p.id()[i], p.id()[j]}] = h;
    }
  ASSERT_GT(by_ids.size(), 500u);
  // Move everything a little (most pairs stay, many grains change cells), then rebuild: the
  // store is re-ordered by the new cells.
  std::mt19937_64 gm(5);
  std::uniform_real_distribution<double> du(-0.002, 0.002);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.x()[i] += Vec3{du(gm), du(gm), du(gm)};
    d.wrap(p.x()[i]);
  }
  const auto perm = l.sort_and_build(p, d, skin);
  std::size_t moved = 0;
  for (std::size_t k = 0; k < perm.size(); ++k) moved += perm[k] != static_cast<std::int64_t>(k);
  EXPECT_GT(moved, 100u);
  std::size_t carried = 0, zero = 0;
  for (std::size_t i = 0; i < l.n_particles(); ++i)
    for (auto k = l.offsets()[i]; k < l.offsets()[i + 1]; ++k) {
      const std::int32_t j = l.neighbors()[static_cast<std::size_t>(k)];
      const std::int64_t a = p.id()[i], b = p.id()[j];
      const Vec3 h = l.history()[static_cast<std::size_t>(k)];
      if (auto it = by_ids.find({a, b}); it != by_ids.end()) {
        EXPECT_EQ(std::bit_cast<std::uint64_t>(h.y), std::bit_cast<std::uint64_t>(it->second.y));
        EXPECT_EQ(h, it->second);
        ++carried;
      } else if (auto it2 = by_ids.find({b, a}); it2 != by_ids.end()) {
        EXPECT_EQ(h, -it2->second);
        ++carried;
      } else {
        EXPECT_EQ(h, Vec3{});
        ++zero;
      }
    }
  EXPECT_GT(carried, 400u);
  EXPECT_GT(zero, 400u);
}
