// SPDX-License-Identifier: GPL-3.0-or-later
// Particle <-> grid mapping of CFD-DEM (src/coupling/cfd_dem/mapping.hpp, fluid_fraction.hpp):
// volume conservation of the fluid fraction, continuity of the divided scheme, thread-count
// determinism, interpolation and the momentum-conserving deposit of forces.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/quaternion.hpp"
#include "core/rng.hpp"
#include "coupling/cfd_dem/fluid_fraction.hpp"
#include "coupling/cfd_dem/mapping.hpp"
#include "coupling/cfd_dem/stencil.hpp"
#include "particles/particle_store.hpp"

using namespace gf;
using namespace gf::cfd_dem;

namespace {

constexpr double kPiD = std::numbers::pi;
constexpr DepositScheme kSchemes[] = {DepositScheme::CentreInCell, DepositScheme::Divided,
                                      DepositScheme::Trilinear, DepositScheme::Smoothed};

fluid::Grid box_grid(std::array<int, 3> n, Vec3 lo, Vec3 h, std::array<bool, 3> periodic,
                     int dimension = 3) {
  fluid::Grid g;
  g.dimension = dimension;
  g.n = n;
  g.lo = lo;
  g.h = h;
  g.periodic = periodic;
  return g;
}

/// Random particles of a test: spheres (rod_fraction = 0) or a mix with spherocylinders.
struct Particles {
  std::vector<Vec3> x, axis;
  std::vector<double> radius, half_length;
  ParticleGeometry view() const {
    ParticleGeometry p;
    p.x = x;
    p.radius = radius;
    if (!half_length.empty()) {
      p.half_length = half_length;
      p.axis = axis;
    }
    return p;
  }
  double total_volume() const {
    double v = 0;
    const auto p = view();
    for (std::size_t i = 0; i < x.size(); ++i) v += p.volume(i);
    return v;
  }
};

/// n particles with centres uniform in the grid's box widened by one cell on every side (so
/// that bodies cross periodic boundaries and stick out of walls), radii in [rmin, rmax] cells.
Particles random_particles(const fluid::Grid& g, int n, double rmin, double rmax,
                           double rod_fraction, std::uint64_t seed) {
  Rng rng(seed);
  Particles p;
  const double hmin = std::min(g.h.x, std::min(g.h.y, g.h.z));
  for (int i = 0; i < n; ++i) {
    Vec3 c;
    for (int a = 0; a < 3; ++a) c[a] = rng.uniform(g.lo[a] - g.h[a], g.hi()[a] + g.h[a]);
    if (g.dimension == 2) c.z = 0.5 * (g.lo.z + g.hi().z);
    p.x.push_back(c);
    p.radius.push_back(rng.uniform(rmin, rmax) * hmin);
    if (rod_fraction > 0) {
      const bool rod = rng.uniform() < rod_fraction;
      p.half_length.push_back(rod ? rng.uniform(0.2, 2.0) * hmin : 0.0);
      Vec3 u{rng.normal(0, 1), rng.normal(0, 1), rng.normal(0, 1)};
      p.axis.push_back(normalized(u));
    }
  }
  return p;
}

std::vector<double> solid_volume(const fluid::Grid& g, const ParticleGeometry& p,
                                 DepositScheme scheme) {
  std::vector<double> s(g.cell_count(), 0.0);
  deposit_solid_volume(g, p, scheme, s);
  return s;
}

double sum(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s;
}

}  // namespace

// Sum over cells of the deposited solid volume = sum of particle volumes, for every scheme, with
// bodies across periodic faces and outside walls. The only error is round-off in the shares (48
// to ~600 terms per particle, weights summing to 1 within ~1e-16): 1e-12 relative.
TEST(FluidFraction, SolidVolumeConservedSpheresAndRods) {
  const auto g = box_grid({7, 6, 5}, {-2e-3, 0, 1e-3}, {1e-3, 1.2e-3, 0.9e-3}, {true, true, false});
  for (double rods : {0.0, 0.6}) {
    const auto parts = random_particles(g, 400, 0.1, 0.9, rods, 11);
    const double vp = parts.total_volume();
    for (auto scheme : kSchemes) {
      const auto s = solid_volume(g, parts.view(), scheme);
      EXPECT_NEAR(sum(s) / vp, 1.0, 1e-12) << "rods " << rods << " scheme " << int(scheme);
      RecordProperty("rel_error_rods" + std::to_string(int(rods * 10)) + "_scheme" +
                         std::to_string(int(scheme)),
                     fmt::format("{:.3g}", std::abs(sum(s) / vp - 1)));
      for (double v : s) EXPECT_GE(v, 0.0);
    }
  }
}

// Brute-force oracle for compute_footprints (one pair per distinct cell, a grain inside one
// cell as a single pair, and the divided scheme's face comparisons): deposits through it equal
// the sum over every raw sample point, each located with cell_containing, cell by cell. Radii
// from 0.05 to 1.3 cells (inside one cell, across faces, and wider than a cell, where the face
// comparison is not used), rods up to 4 cells long; the pairs are summed in another order, so
// the tolerance is round-off of ~600 terms: 1e-13 of the particle's value.
TEST(FluidFraction, CompactedFootprintsEqualTheRawSamplePoints) {
  for (int dim : {3, 2}) {
    const auto g =
        dim == 3
            ? box_grid({6, 5, 7}, {-1e-3, 0, 2e-3}, {1e-3, 1.1e-3, 0.9e-3}, {true, false, true})
            : box_grid({8, 6, 1}, {0, 0, 0}, {1e-3, 1e-3, 1e-3}, {false, true, false}, 2);
    const auto parts = random_particles(g, 300, 0.05, 1.3, 0.5, 23);
    const auto p = parts.view();
    for (auto scheme : kSchemes) {
      Footprints fp;
      compute_footprints(g, p, scheme, fp);
      ASSERT_EQ(fp.size(), p.size());
      std::vector<double> ones(p.size(), 1.0), fast(g.cell_count(), 0.0), slow(fast);
      deposit(fp, std::span<const double>(ones), std::span<double>(fast));
      std::vector<CellShare> raw;
      int single = 0;
      for (std::size_t i = 0; i < p.size(); ++i) {
        if (scheme == DepositScheme::Divided && p.half(i) == 0.0) {
          // A sphere's points located independently, with cell_containing.
          const auto pts = turned_sphere_sample_points();
          for (const Vec3& s : pts)
            slow[cell_containing(g, p.x[i] + p.radius[i] * s)] += 1.0 / pts.size();
        } else {
          raw.resize(footprint_size(g, p, i, scheme));
          footprint(g, p, i, scheme, raw.data());
          for (const auto& sh : raw) slow[sh.cell] += sh.weight;
        }
        const auto n_pairs = fp.offsets[i + 1] - fp.offsets[i];
        single += n_pairs == 1;
        std::vector<std::int64_t> cells;
        for (auto s = fp.offsets[i]; s < fp.offsets[i + 1]; ++s) cells.push_back(fp.shares[s].cell);
        std::sort(cells.begin(), cells.end());
        EXPECT_EQ(std::adjacent_find(cells.begin(), cells.end()), cells.end()) << "repeated cell";
      }
      for (std::int64_t c = 0; c < g.cell_count(); ++c)
        EXPECT_NEAR(fast[c], slow[c], 1e-13 * static_cast<double>(p.size())) << "cell " << c;
      if (scheme == DepositScheme::Divided) {
        EXPECT_GT(single, 10) << "no grain inside one cell";
      }
    }
  }
}

// A rod's divided footprint as compute_footprints builds it (binned by neighbour offset, with a
// fall-back where neighbours fold onto one cell) equals the raw sample points of footprint()
// merged in first-occurrence order, pair for pair and bit for bit: the same cells in the same
// order and the same weight sums. Rods shorter and longer than a cell, across periodic faces, a
// periodic axis of two cells (neighbours fold onto one cell) and outside walls (clamped).
TEST(FluidFraction, RodFootprintsEqualTheMergedSamplePointsBitForBit) {
  const auto g = box_grid({6, 2, 5}, {0, 0, 0}, {1e-3, 1.2e-3, 0.9e-3}, {true, true, false});
  const auto parts = random_particles(g, 600, 0.05, 0.4, 1.0, 31);
  const auto p = parts.view();
  Footprints fp;
  compute_footprints(g, p, DepositScheme::Divided, fp);
  std::vector<CellShare> raw;
  int rods = 0, multi = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.half(i) == 0.0) continue;
    ++rods;
    raw.resize(footprint_size(g, p, i, DepositScheme::Divided));
    footprint(g, p, i, DepositScheme::Divided, raw.data());
    std::vector<CellShare> merged;
    for (const auto& sh : raw) {
      auto it = std::find_if(merged.begin(), merged.end(),
                             [&](const CellShare& m) { return m.cell == sh.cell; });
      if (it == merged.end())
        merged.push_back(sh);
      else
        it->weight += sh.weight;
    }
    const auto n = fp.offsets[i + 1] - fp.offsets[i];
    multi += n > 1;
    if (merged.size() == 1) continue;  // inside one cell: the single pair (cell, 1)
    ASSERT_EQ(n, static_cast<std::int64_t>(merged.size())) << "rod " << i;
    for (std::int64_t k = 0; k < n; ++k) {
      EXPECT_EQ(fp.shares[fp.offsets[i] + k].cell, merged[k].cell) << "rod " << i << " pair " << k;
      EXPECT_EQ(fp.shares[fp.offsets[i] + k].weight, merged[k].weight)
          << "rod " << i << " pair " << k;
    }
  }
  EXPECT_GT(rods, 500);
  EXPECT_GT(multi, 300) << "too few rods across faces";
}

// 2D grid (one layer, depth h_z): volumes still conserved; z plays no role.
TEST(FluidFraction, SolidVolumeConserved2D) {
  const auto g = box_grid({9, 7, 1}, {0, 0, -0.5e-3}, {1e-3, 1e-3, 1e-3}, {true, false, false}, 2);
  const auto parts = random_particles(g, 200, 0.1, 0.5, 0.5, 5);
  for (auto scheme : kSchemes)
    EXPECT_NEAR(sum(solid_volume(g, parts.view(), scheme)) / parts.total_volume(), 1.0, 1e-12);
}

// Dilute: no clamping, and sum (1 - eps) V_cell = sum V_p.
TEST(FluidFraction, FluidFractionConservesVolumeWhenNotClamped) {
  const auto g = box_grid({6, 6, 6}, {0, 0, 0}, {1, 1, 1}, {true, true, true});
  const auto parts = random_particles(g, 30, 0.05, 0.12, 0.5, 3);
  std::vector<double> eps(g.cell_count());
  for (auto scheme : kSchemes) {
    const auto st = fluid_fraction(g, parts.view(), {scheme, 0.3}, eps);
    EXPECT_EQ(st.n_clamped, 0);
    double solid = 0;
    for (double e : eps) solid += (1 - e) * g.cell_volume();
    EXPECT_NEAR(solid / parts.total_volume(), 1.0, 1e-12);
    EXPECT_NEAR(st.solid_volume / parts.total_volume(), 1.0, 1e-12);
  }
}

// A sphere of 0.9 V_cell in one cell (centre-in-cell): eps would be 0.1, is clamped to 0.3.
TEST(FluidFraction, ClampCountsCells) {
  const auto g = box_grid({3, 3, 3}, {0, 0, 0}, {1, 1, 1}, {false, false, false});
  Particles p;
  p.x = {{1.5, 1.5, 1.5}, {0.5, 0.5, 0.5}};
  p.radius = {std::cbrt(0.9 * 3 / (4 * kPiD)), 0.1};
  std::vector<double> eps(g.cell_count());
  const auto st = fluid_fraction(g, p.view(), {DepositScheme::CentreInCell, 0.3}, eps);
  EXPECT_EQ(st.n_clamped, 1);
  EXPECT_NEAR(st.min_unclamped, 0.1, 1e-14);
  EXPECT_EQ(eps[g.index(1, 1, 1)], 0.3);
  EXPECT_NEAR(eps[g.index(0, 0, 0)], 1 - 4.0 / 3 * kPiD * 1e-3, 1e-15);
  EXPECT_THROW(fluid_fraction(g, p.view(), {DepositScheme::Divided, 0.0}, eps), Error);
  EXPECT_THROW(fluid_fraction(g, p.view(), {DepositScheme::Divided, 1.5}, eps), Error);
}

// A body well inside one cell puts all of its volume there with every scheme but trilinear.
TEST(FluidFraction, BodyInsideOneCellStaysThere) {
  const auto g = box_grid({4, 4, 4}, {0, 0, 0}, {1, 1, 1}, {false, false, false});
  Particles p;
  p.x = {{1.5, 2.5, 1.5}};
  p.radius = {0.1};
  p.half_length = {0.25};
  p.axis = {normalized(Vec3{1, 1, 1})};
  for (auto scheme : {DepositScheme::CentreInCell, DepositScheme::Divided}) {
    const auto s = solid_volume(g, p.view(), scheme);
    EXPECT_NEAR(s[g.index(1, 2, 1)] / p.total_volume(), 1.0, 1e-14);
  }
}

// d eps/dt from the solid flux, by hand for one grain inside one cell of a 3 x 3 x 3 grid moving
// along each axis: q = V_p v / V_cell in its cell, each face carries half of it, so the cell
// ahead loses solid at rate 0.5 q / h, the cell behind gains it, every other cell (its own
// included: half in, half out) sees 0. Across a periodic face the cell ahead is the first of the
// row; at a wall the face carries nothing, so the grain's own cell takes the loss there. Exact
// but for round-off of a few terms: 1e-14 of 0.5 q / h.
TEST(FluidFractionRate, OneGrainMovingAlongAnAxis) {
  for (bool periodic : {false, true}) {
    const auto g = box_grid({3, 3, 3}, {0, 0, 0}, {1, 1, 1}, {periodic, periodic, periodic});
    for (int a = 0; a < 3; ++a) {
      for (int at : {1, 2}) {  // the middle cell, and the last one (a wall or a periodic face)
        Particles p;
        Vec3 x{1.5, 1.5, 1.5};
        x[a] = at + 0.5;
        p.x = {x};
        p.radius = {0.2};
        Footprints fp;
        compute_footprints(g, p.view(), DepositScheme::Divided, fp);
        Vec3 v{};
        v[a] = 0.3;
        std::vector<double> rate(g.cell_count(), -1.0);
        SolidFluxScratch scratch;
        fluid_fraction_rate_from_flux(g, fp, std::span<const Vec3>(&v, 1), rate, scratch);
        const double half = 0.5 * p.total_volume() * 0.3 / g.cell_volume() / g.h[a];
        std::vector<double> expect(g.cell_count(), 0.0);
        std::array<int, 3> own{1, 1, 1}, ahead{1, 1, 1}, behind{1, 1, 1};
        own[a] = at;
        behind[a] = at - 1;
        ahead[a] = at + 1;
        expect[g.index(behind[0], behind[1], behind[2])] += half;
        if (ahead[a] < 3) {
          expect[g.index(ahead[0], ahead[1], ahead[2])] -= half;
        } else if (periodic) {
          ahead[a] = 0;
          expect[g.index(ahead[0], ahead[1], ahead[2])] -= half;
        } else {
          expect[g.index(own[0], own[1], own[2])] -= half;
        }
        for (std::int64_t c = 0; c < g.cell_count(); ++c)
          EXPECT_NEAR(rate[c], expect[c], 1e-14 * half)
              << "periodic " << periodic << " axis " << a << " at " << at << " cell " << c;
      }
    }
  }
}

// The solid volume is conserved: the rates sum to zero over a box with walls and periodic faces
// (every interior face is counted once in and once out; wall faces carry nothing) for random
// spheres and rods with random velocities, to round-off (~1e-15 of the largest rate times the
// cell count, 1e-12 of sum |rate|). In a fully periodic box a lattice moving as a whole, with
// the same footprint in every cell, gives q uniform and rate 0 (1e-12 of q / h).
TEST(FluidFractionRate, ConservesSolidVolumeAndVanishesForUniformFlux) {
  const auto g =
      box_grid({7, 6, 5}, {-2e-3, 0, 1e-3}, {1e-3, 1.2e-3, 0.9e-3}, {true, false, false});
  const auto parts = random_particles(g, 300, 0.1, 0.9, 0.5, 17);
  Rng rng(5);
  std::vector<Vec3> v(parts.x.size());
  for (auto& vi : v) vi = {rng.normal(0, 1), rng.normal(0, 1), rng.normal(0, 1)};
  Footprints fp;
  compute_footprints(g, parts.view(), DepositScheme::Divided, fp);
  std::vector<double> rate(g.cell_count());
  SolidFluxScratch scratch;
  fluid_fraction_rate_from_flux(g, fp, v, rate, scratch);
  double total = 0, magnitude = 0;
  for (double r : rate) total += r, magnitude += std::abs(r);
  EXPECT_GT(magnitude, 0.0);
  EXPECT_NEAR(total, 0.0, 1e-12 * magnitude);

  const auto gp = box_grid({4, 3, 2}, {0, 0, 0}, {1, 1, 1}, {true, true, true});
  Particles lattice;  // two grains per cell at the same offsets in every cell
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i)
        for (const Vec3 o : {Vec3{0.3, 0.4, 0.5}, Vec3{0.9, 0.7, 0.95}}) {
          lattice.x.push_back(Vec3{double(i), double(j), double(k)} + o);
          lattice.radius.push_back(0.2);
        }
  compute_footprints(gp, lattice.view(), DepositScheme::Divided, fp);
  std::vector<Vec3> u(lattice.x.size(), Vec3{0.4, -0.2, 0.7});
  std::vector<double> rp(gp.cell_count(), 1.0);
  fluid_fraction_rate_from_flux(gp, fp, u, rp, scratch);
  const double q = 2 * lattice.view().volume(0) * 0.7;
  for (double r : rp) EXPECT_NEAR(r, 0.0, 1e-12 * q);
}

// The smoothed (and the trilinear) deposit's rate is its time derivative: for random spheres
// and rods (radii
// 0.1-0.9 cells, rods up to 4 cells long, some across periodic faces and some beyond the
// outermost centres at walls, where the stencil is constant) moving at random v and turning at
// random omega, the deposit of footprint_rates equals the central difference of the
// deposited solid volume over t +- delta (centres x +- v delta, axes turned by +- delta omega),
// cell by cell. The weights are linear in each point's coordinates between cell centres, so the
// difference is exact but for the axis' turn (O(delta^2)), round-off (1e-16 V / delta: delta =
// 1e-8 cells of travel gives 1e-8 of the rates) and a point within delta of a centre plane (the
// mean of two slopes there; ~1e-4 expected hits in this set): 1e-6 of the largest cell rate.
// Each grain's rates sum to zero (the solid volume is conserved), and in 2D too.
TEST(FluidFractionRate, ContinuousDepositsRateIsTheirTimeDerivative) {
  for (const auto scheme : {DepositScheme::Smoothed, DepositScheme::Trilinear})
    for (int dim : {3, 2}) {
      const auto g =
          dim == 3
              ? box_grid({6, 5, 7}, {-1e-3, 0, 2e-3}, {1e-3, 1.1e-3, 0.9e-3}, {true, false, false})
              : box_grid({8, 6, 1}, {0, 0, 0}, {1e-3, 1e-3, 1e-3}, {false, true, false}, 2);
      auto parts = random_particles(g, 200, 0.1, 0.9, dim == 3 ? 0.5 : 0.0, 41);
      Rng rng(7);
      std::vector<Vec3> v(parts.x.size()), w(parts.x.size());
      for (std::size_t i = 0; i < v.size(); ++i) {
        v[i] = {rng.normal(0, 1), rng.normal(0, 1), dim == 3 ? rng.normal(0, 1) : 0.0};
        w[i] = {rng.normal(0, 300), rng.normal(0, 300), rng.normal(0, 300)};  // ~0.3 rad per ms
      }
      Footprints rates;
      footprint_rates(g, parts.view(), scheme, v, w, rates);
      std::vector<double> rate(g.cell_count(), 0.0);
      deposit(rates, std::span<const double>(rates.volume), std::span<double>(rate));
      for (std::size_t i = 0; i < parts.x.size(); ++i) {
        double total = 0, magnitude = 0;
        for (auto q = rates.offsets[i]; q < rates.offsets[i + 1]; ++q)
          total += rates.shares[q].weight, magnitude += std::abs(rates.shares[q].weight);
        EXPECT_NEAR(total, 0.0, 1e-12 * magnitude) << "grain " << i;
      }
      // The deposits that move in steps have none.
      EXPECT_THROW(footprint_rates(g, parts.view(), DepositScheme::Divided, v, w, rates), Error);
      const double delta = 1e-8 * g.h.x;  // s: v ~ 1 m/s
      const auto moved = [&](double sign) {
        Particles q = parts;
        for (std::size_t i = 0; i < q.x.size(); ++i) {
          q.x[i] += sign * delta * v[i];
          if (!q.axis.empty())
            q.axis[i] = normalized(q.axis[i] + sign * delta * cross(w[i], q.axis[i]));
        }
        return solid_volume(g, q.view(), scheme);
      };
      const auto ahead = moved(1.0), behind = moved(-1.0);
      double largest = 0;
      for (double r : rate) largest = std::max(largest, std::abs(r));
      EXPECT_GT(largest, 0.0);
      for (std::int64_t c = 0; c < g.cell_count(); ++c)
        EXPECT_NEAR(rate[c], (ahead[c] - behind[c]) / (2 * delta), 1e-6 * largest)
            << "scheme " << int(scheme) << " dim " << dim << " cell " << c;
    }
}

// The one walk over the sample points gives what the two separate calls give, bit for bit (the
// same sums in the same order), for spheres and rods crossing periodic faces and walls, 3D and
// 2D, and with grains that do not turn (omega empty); 9000 grains: two blocks of the builder
// (8192 each), the first filled by several threads.
TEST(FluidFractionRate, OnePassEqualsFootprintsAndRatesBitForBit) {
  const auto same = [](const Footprints& a, const Footprints& b, const char* what) {
    ASSERT_EQ(a.offsets, b.offsets) << what;
    ASSERT_EQ(a.shares.size(), b.shares.size()) << what;
    for (std::size_t q = 0; q < a.shares.size(); ++q) {
      EXPECT_EQ(a.shares[q].cell, b.shares[q].cell) << what << " pair " << q;
      EXPECT_EQ(a.shares[q].weight, b.shares[q].weight) << what << " pair " << q;
    }
    EXPECT_EQ(a.volume, b.volume) << what;
  };
  for (const auto scheme : {DepositScheme::Smoothed, DepositScheme::Trilinear})
    for (int dim : {3, 2})
      for (bool turning : {true, false}) {
        const auto g =
            dim == 3 ? box_grid({6, 5, 7}, {-1e-3, 0, 2e-3}, {1e-3, 1.1e-3, 0.9e-3},
                                {true, false, false})
                     : box_grid({8, 6, 1}, {0, 0, 0}, {1e-3, 1e-3, 1e-3}, {false, true, false}, 2);
        auto parts = random_particles(g, 9000, 0.1, 1.4, dim == 3 ? 0.5 : 0.0, 43);
        Rng rng(9);
        std::vector<Vec3> v(parts.x.size()), w;
        for (auto& vi : v)
          vi = {rng.normal(0, 1), rng.normal(0, 1), dim == 3 ? rng.normal(0, 1) : 0.0};
        if (turning)
          for (std::size_t i = 0; i < v.size(); ++i)
            w.push_back({rng.normal(0, 300), rng.normal(0, 300), rng.normal(0, 300)});
        Footprints fp, rates, fp1, rates1;
        compute_footprints(g, parts.view(), scheme, fp);
        footprint_rates(g, parts.view(), scheme, v, w, rates);
        footprints_with_rates(g, parts.view(), scheme, v, w, fp1, rates1);
        same(fp, fp1, "footprints");
        same(rates, rates1, "rates");
        EXPECT_THROW(
            footprints_with_rates(g, parts.view(), DepositScheme::Divided, v, w, fp1, rates1),
            Error);
      }
}

// A sphere (r = 0.4 h) moving along x, y or z across a cell face in steps of h/1000 (0.0025 r).
// Centre-in-cell: eps of the cell it leaves jumps once by V_p / V_cell = 0.268. Divided: the
// turned 48-point set has no two points closer than 0.0016 r along an axis, so one step moves at
// most two points: jump <= 2 V_p / 48 / V_cell = 0.0112 (measured: one point, 0.0056). The
// volume beyond the face follows the exact spherical cap within 0.1 V_p (a 48-point quadrature
// of a step function; measured 0.056-0.073 along the axes, 0.099 the worst of 65 directions in
// the design study, see sphere_sample_points). Smoothed has no steps at all: a step moves every
// point's stencil weights by at most 1/1000 of its share, so the cell's solid volume changes by
// at most V_p / 1000 per step (measured: that, where the whole sphere is between the same
// centres along the other axes).
TEST(FluidFraction, DividedAndSmoothedAreContinuousCentreInCellJumps) {
  const auto g = box_grid({4, 4, 4}, {0, 0, 0}, {1, 1, 1}, {false, false, false});
  const double r = 0.4, vp = 4.0 / 3 * kPiD * r * r * r;
  for (int axis = 0; axis < 3; ++axis) {
    Particles p;
    p.x = {{1.5, 1.5, 1.5}};
    p.radius = {r};
    std::vector<double> eps(g.cell_count());
    double prev_c = -1, prev_d = -1, max_jump_c = 0, max_jump_d = 0, max_cap_err = 0;
    double prev_s = -1, max_jump_s = 0;
    int jumps_c = 0;
    for (int step = 0; step <= 1400; ++step) {
      p.x[0][axis] = 1.3 + step * 1e-3;
      fluid_fraction(g, p.view(), {DepositScheme::CentreInCell, 0.3}, eps);
      const double ec = eps[g.index(1, 1, 1)];
      fluid_fraction(g, p.view(), {DepositScheme::Divided, 0.3}, eps);
      const double ed = eps[g.index(1, 1, 1)];
      fluid_fraction(g, p.view(), {DepositScheme::Smoothed, 0.3}, eps);
      const double es = eps[g.index(1, 1, 1)];
      if (step > 0) {
        max_jump_c = std::max(max_jump_c, std::abs(ec - prev_c));
        if (ec != prev_c) ++jumps_c;
        max_jump_d = std::max(max_jump_d, std::abs(ed - prev_d));
        max_jump_s = std::max(max_jump_s, std::abs(es - prev_s));
      }
      prev_c = ec, prev_d = ed, prev_s = es;
      // Exact solid volume beyond the face (a cap of height hc) = what left cell (1, 1, 1).
      const double hc = std::clamp(p.x[0][axis] + r - 2.0, 0.0, 2 * r);
      const double beyond = kPiD * hc * hc * (3 * r - hc) / 3;
      max_cap_err = std::max(max_cap_err, std::abs((1 - ed) - (vp - beyond)) / vp);
    }
    EXPECT_EQ(jumps_c, 1) << axis;
    EXPECT_NEAR(max_jump_c, vp, 1e-12) << axis;
    EXPECT_LE(max_jump_d, 2 * vp / 48 + 1e-12) << axis;
    EXPECT_LT(max_cap_err, 0.1) << axis;
    EXPECT_LE(max_jump_s, 1.001e-3 * vp) << axis;  // V_cell = 1
    EXPECT_GT(max_jump_s, 0.0) << axis;
    RecordProperty("divided_max_jump_over_vp_axis" + std::to_string(axis),
                   std::to_string(max_jump_d / vp));
    RecordProperty("divided_max_cap_error_over_vp_axis" + std::to_string(axis),
                   std::to_string(max_cap_err));
  }
}

// A rod (r = 0.1, l = 0.6: L/d = 4) moving along its own axis (z) across a face: every
// sample point has its own axial position, so one step (0.001) moves at most one cylinder point
// (share V_cyl / 48) or a cap point (V_sphere / 48; the four points of a cap band share z in the
// rod's frame, so up to 4 of those): jump <= 4 V_sphere / 48 / V_cell. Centre-in-cell jumps by
// the whole V_p.
TEST(FluidFraction, DividedRodAlongItsAxisIsNearlyContinuous) {
  const auto g = box_grid({3, 3, 3}, {0, 0, 0}, {1, 1, 1}, {false, false, false});
  Particles p;
  p.x = {{1.5, 1.5, 1.0}};
  p.radius = {0.1};
  p.half_length = {0.3};
  p.axis = {{0, 0, 1}};
  const double vsph = 4.0 / 3 * kPiD * 1e-3, vcyl = kPiD * 0.01 * 0.6;
  ASSERT_EQ(cylinder_slabs(0.1, 0.3), 6);
  std::vector<double> eps(g.cell_count());
  double prev = -1, max_jump = 0;
  for (int step = 0; step <= 1000; ++step) {
    p.x[0].z = 1.5 + step * 1e-3;
    fluid_fraction(g, p.view(), {DepositScheme::Divided, 0.3}, eps);
    const double e = eps[g.index(1, 1, 1)];
    if (step > 0) max_jump = std::max(max_jump, std::abs(e - prev));
    prev = e;
  }
  EXPECT_LE(max_jump, std::max(4 * vsph / 48, 2 * vcyl / 48) + 1e-12);
  EXPECT_NEAR(prev, 1.0, 1e-12);  // all of it has left cell (1, 1, 1)
}

// The sample set: 48 points inside the unit sphere, centroid at the centre (exactly, by
// symmetry of the construction, to round-off), second moment near the ball's 1/5 per axis.
TEST(FluidFraction, SphereSamplePoints) {
  const auto pts = sphere_sample_points();
  ASSERT_EQ(pts.size(), 48u);
  Vec3 c{}, m2{};
  for (const Vec3& q : pts) {
    EXPECT_LT(norm(q), 1.0);
    c += q / 48.0;
    m2 += Vec3{q.x * q.x, q.y * q.y, q.z * q.z} / 48.0;
  }
  EXPECT_LT(norm(c), 1e-15);
  // Centroids lie inside their pieces, so the discrete second moment is below the ball's 1/5
  // (0.155 across the bands, 0.185 along z).
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(m2[a], 0.2, 0.05);
  EXPECT_EQ(cylinder_slabs(0.5, 1.5), 6);  // l = 3 = 6 r
  EXPECT_EQ(cylinder_slabs(0.5, 0.0), 0);
}

// Same fields with 1 and 2 threads, bit for bit: ~9000 particles (two footprint blocks, so the
// parallel loops do run threaded), every scheme, volume and force deposits.
TEST(FluidFraction, ThreadDeterminismOneAndTwoThreads) {
#if !defined(_OPENMP)
  GTEST_SKIP() << "built without OpenMP";
#else
  const auto g = box_grid({12, 10, 8}, {0, 0, 0}, {1, 1, 1}, {true, false, true});
  const auto parts = random_particles(g, 9000, 0.05, 0.45, 0.3, 21);
  Rng rng(4);
  std::vector<Vec3> f(parts.x.size());
  for (auto& v : f) v = {rng.normal(0, 1), rng.normal(0, 1), rng.normal(0, 1)};
  const int before = exec::n_threads();
  for (auto scheme : kSchemes) {
    std::vector<double> eps1(g.cell_count()), eps2(g.cell_count());
    std::vector<Vec3> fc1(g.cell_count()), fc2(g.cell_count());
    exec::set_threads(1);
    fluid_fraction(g, parts.view(), {scheme, 0.3}, eps1);
    deposit_reaction_forces(g, parts.view(), scheme, f, fc1);
    exec::set_threads(2);
    fluid_fraction(g, parts.view(), {scheme, 0.3}, eps2);
    deposit_reaction_forces(g, parts.view(), scheme, f, fc2);
    exec::set_threads(before);
    EXPECT_EQ(std::memcmp(eps1.data(), eps2.data(), eps1.size() * sizeof(double)), 0)
        << int(scheme);
    EXPECT_EQ(std::memcmp(fc1.data(), fc2.data(), fc1.size() * sizeof(Vec3)), 0) << int(scheme);
  }
#endif
}

// Trilinear interpolation between cell centres is exact for linear fields wherever the point
// lies between the outermost centres (round-off: 1e-12 of the field's range).
TEST(FluidFractionInterpolation, ExactForLinearFields) {
  for (int dim : {3, 2}) {
    const auto g = box_grid({6, 5, dim == 3 ? 7 : 1}, {-1, 0.5, 2}, {0.3, 0.4, 0.25},
                            {false, true, false}, dim);
    const Vec3 grad{1.5, -2.0, dim == 3 ? 0.7 : 0.0};
    std::vector<double> f(g.cell_count());
    std::vector<Vec3> fv(g.cell_count());
    for (int k = 0; k < g.n[2]; ++k)
      for (int j = 0; j < g.n[1]; ++j)
        for (int i = 0; i < g.n[0]; ++i) {
          const Vec3 c = g.cell_center(i, j, k);
          f[g.index(i, j, k)] = 3.0 + dot(grad, c);
          fv[g.index(i, j, k)] = {dot(grad, c), -2 * dot(grad, c), 1.0};
        }
    Rng rng(8);
    std::vector<Vec3> x;
    for (int q = 0; q < 200; ++q) {
      Vec3 p;
      for (int a = 0; a < 3; ++a)
        p[a] = rng.uniform(g.lo[a] + 0.5 * g.h[a], g.hi()[a] - 0.5 * g.h[a]);
      if (dim == 2) p.z = rng.uniform(-5, 5);  // ignored on a 2D grid
      x.push_back(p);
    }
    std::vector<double> out(x.size());
    std::vector<Vec3> outv(x.size());
    interpolate_to_points(g, f, x, out);
    interpolate_to_points(g, fv, x, outv);
    for (std::size_t q = 0; q < x.size(); ++q) {
      // y is periodic: the linear field is not, so only points between the centres of y
      // cells 0 and n-1 are compared (all of them here).
      EXPECT_NEAR(out[q], 3.0 + dot(grad, x[q]), 1e-12) << dim;
      EXPECT_NEAR(outv[q].y, -2 * dot(grad, x[q]), 1e-12) << dim;
      EXPECT_NEAR(outv[q].z, 1.0, 1e-14);
    }
  }
}

// Oracle for the interpolation: the weighted sum over the 8-cell stencil that the deposits use
// (trilinear_stencil), against which the compact nested-lerp path of the coupling is checked.
template <class T>
T interpolate_by_weights(const CellStencil& s, const T* field) {
  T v{};
  for (int q = 0; q < s.n; ++q) v += s.weight[q] * field[s.cell[q]];
  return v;
}

// Periodic axis: between the last centre and the first (across the face), the value blends
// f[n-1] and f[0]; a point and its image one period away give the same value. Wall axis:
// constant (the boundary cell's value) between the wall and the first centre.
TEST(FluidFractionInterpolation, PeriodicWrapAndWallClamp) {
  const auto g = box_grid({5, 4, 3}, {0, 0, 0}, {1, 1, 1}, {true, false, false});
  std::vector<double> f(g.cell_count());
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 5; ++i) f[g.index(i, j, k)] = 10.0 * i + j;
  auto at = [&](Vec3 x) { return interpolate_by_weights(trilinear_stencil(g, x), f.data()); };
  // x = 4.75: a quarter of the way from centre 4 (value 40) to centre 0 (value 0, wrapped).
  EXPECT_NEAR(at({4.75, 1.5, 1.5}), 0.75 * 40 + 0.25 * 0 + 1, 1e-12);
  EXPECT_NEAR(at({0.25, 1.5, 1.5}), 0.75 * 0 + 0.25 * 40 + 1, 1e-12);  // from the other side
  EXPECT_NEAR(at({0.25 + 5, 1.5, 1.5}), at({0.25, 1.5, 1.5}), 1e-12);
  EXPECT_NEAR(at({0.25 - 10, 1.5, 1.5}), at({0.25, 1.5, 1.5}), 1e-12);
  // y is a wall axis: below the first centre (y < 0.5) the value is cell 0's; beyond the box too.
  EXPECT_NEAR(at({2.5, 0.2, 1.5}), 20.0, 1e-12);
  EXPECT_NEAR(at({2.5, -3.0, 1.5}), 20.0, 1e-12);
  EXPECT_NEAR(at({2.5, 3.9, 1.5}), 23.0, 1e-12);
  EXPECT_NEAR(at({2.5, 1.0, 1.5}), 20.5, 1e-12);
  // Weights always sum to one.
  const auto s = trilinear_stencil(g, {4.9, 0.1, 2.7});
  double w = 0;
  for (int q = 0; q < s.n; ++q) w += s.weight[q];
  EXPECT_NEAR(w, 1.0, 1e-15);
}

/// Random drag coefficients and particle velocities for particles that see fluid velocity
/// u_seen[p], with the total drag sum_p beta_p (u_seen_p - v_p) and the sum of its magnitudes.
struct RandomDrag {
  std::vector<double> beta;
  std::vector<Vec3> v;
  Vec3 total{};
  double scale = 0;
  RandomDrag(Rng& rng, const std::vector<Vec3>& u_seen) : beta(u_seen.size()), v(u_seen.size()) {
    for (std::size_t i = 0; i < v.size(); ++i) {
      beta[i] = rng.uniform(1e-6, 1e-5);
      v[i] = {rng.normal(0, 0.1), rng.normal(0, 0.1), rng.normal(0, 0.1)};
      total += beta[i] * (u_seen[i] - v[i]);
      scale += norm(beta[i] * (u_seen[i] - v[i]));
    }
  }
};

/// Random cell fields (scalar and vector, values in [-1, 1]) on g and 300 random points in the
/// box widened by two cells on every side (outside walls, across periodic faces).
struct RandomFieldsAndPoints {
  std::vector<double> f;
  std::vector<Vec3> fv, x;
  RandomFieldsAndPoints(const fluid::Grid& g, std::uint64_t seed) {
    Rng rng(seed);
    f.resize(g.cell_count());
    fv.resize(g.cell_count());
    for (std::size_t c = 0; c < f.size(); ++c) {
      f[c] = rng.uniform(-1, 1);
      fv[c] = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
    }
    for (int q = 0; q < 300; ++q) {
      Vec3 p;
      for (int a = 0; a < 3; ++a) p[a] = rng.uniform(g.lo[a] - 2 * g.h[a], g.hi()[a] + 2 * g.h[a]);
      x.push_back(p);
    }
  }
};

// The compact stencil (nested lerps) reads the same cells with the same weights as the
// 8-cell stencil of the deposits: equal to round-off (a few ulp of the field's range, 1e-13
// here) at points inside, outside, across periodic faces and on one-cell axes; and the
// stored-stencil path of the coupling equals the point path bit for bit.
TEST(FluidFractionInterpolation, CompactStencilMatchesCellStencil) {
  for (int dim : {3, 2}) {
    for (const auto& n : {std::array<int, 3>{7, 5, 6}, std::array<int, 3>{1, 4, 3}}) {
      const auto g = box_grid({n[0], n[1], dim == 3 ? n[2] : 1}, {-1, 0.5, 2}, {0.3, 0.4, 0.25},
                              {true, false, true}, dim);
      const RandomFieldsAndPoints r(g, 21);
      const auto& f = r.f;
      const auto &fv = r.fv, &x = r.x;
      std::vector<LerpStencil> st(x.size());
      point_stencils(g, x, st);
      std::vector<double> out(x.size()), out2(x.size());
      std::vector<Vec3> outv(x.size()), outv2(x.size()), outg(x.size());
      interpolate_to_points(g, f, x, out);
      interpolate_to_points(g, fv, x, outv);
      interpolate_at(g, st, std::span<const Vec3>(fv), std::span<Vec3>(outv2),
                     std::span<const double>(f), std::span<double>(out2));
      for (std::size_t q = 0; q < x.size(); ++q) {
        const CellStencil cs = trilinear_stencil(g, x[q]);
        EXPECT_NEAR(out[q], interpolate_by_weights(cs, f.data()), 1e-13) << dim << " " << q;
        const Vec3 ref = interpolate_by_weights(cs, fv.data());
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(outv[q][a], ref[a], 1e-13) << dim << " " << q;
        EXPECT_EQ(out[q], out2[q]);
        EXPECT_EQ(outv[q].x, outv2[q].x);
        EXPECT_EQ(outv[q].z, outv2[q].z);
      }
    }
  }
}

// The consistent exchange for trilinear reads: with a non-uniform fluid (random cell values)
// and each particle's fluid velocity interpolated from it, the fluid's source at u = cell_u is
// minus the total drag the particles feel, for every footprint scheme (round-off, 1e-12 of
// sum |F| as above). The plain form misses by sum_p beta_p (sum_c w_pc u_c - u_seen_p), which
// is checked to be far from round-off for the volume footprints (centre, divided), so the test
// tells the two apart; with the trilinear deposit the two forms agree.
TEST(FluidFractionInterpolation, ConsistentExchangeReturnsTheDragTheGrainsFeel) {
  const auto g = box_grid({6, 5, 4}, {0, 0, 0}, {2e-3, 2e-3, 2e-3}, {true, true, false});
  const auto parts = random_particles(g, 300, 0.1, 0.4, 0.3, 29);
  Rng rng(8);
  std::vector<Vec3> cell_u(g.cell_count());
  for (auto& u : cell_u) u = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
  std::vector<Vec3> u_seen(parts.x.size());
  interpolate_to_points(g, cell_u, parts.x, u_seen);
  const RandomDrag drag(rng, u_seen);
  const auto& [beta, v, drag_total, scale] = drag;
  for (auto scheme : kSchemes) {
    Footprints fp;
    compute_footprints(g, parts.view(), scheme, fp);
    std::vector<Vec3> s_exp(g.cell_count(), Vec3{1, 1, 1});  // overwritten
    std::vector<double> k(g.cell_count(), 1.0);
    auto fluid_total = [&] {
      Vec3 t{};
      for (std::int64_t c = 0; c < g.cell_count(); ++c)
        t += (s_exp[c] - k[c] * cell_u[c]) * g.cell_volume();
      return t;
    };
    drag_exchange_source(fp, beta, v, u_seen, cell_u, s_exp, k);
    EXPECT_LT(norm(fluid_total() + drag_total) / scale, 1e-12) << int(scheme);
    // The plain form: the grains' drag only where the deposit is the adjoint of the read
    // (trilinear deposit: sum_c w_pc u_c = u_seen_p exactly), not for the volume footprints.
    drag_exchange_source(fp, beta, v, s_exp, k);
    if (scheme == DepositScheme::Trilinear)
      EXPECT_LT(norm(fluid_total() + drag_total) / scale, 1e-12);
    else
      EXPECT_GT(norm(fluid_total() + drag_total) / scale, 1e-3) << int(scheme);
  }
}

// coupling.interpolation: cell reads the value of the cell containing the point, exactly (no
// arithmetic on the field), through the same interpolate_at path: checked against an oracle
// that locates the cell by integer division on its own, at random points inside, outside the
// walls (nearest boundary cell) and beyond periodic faces (wrapped), in 3D and 2D.
TEST(FluidFractionInterpolation, CellValueReadIsTheContainingCell) {
  for (int dim : {3, 2}) {
    const auto g = box_grid({5, 4, dim == 3 ? 3 : 1}, {-1, 0.5, 2}, {0.3, 0.4, 0.25},
                            {true, false, true}, dim);
    const RandomFieldsAndPoints r(g, 5);
    const auto& f = r.f;
    const auto &fv = r.fv, &x = r.x;
    std::vector<LerpStencil> st(x.size());
    point_stencils(g, x, st, PointRead::CellValue);
    std::vector<double> out(x.size());
    std::vector<Vec3> outv(x.size());
    interpolate_at(g, st, std::span<const Vec3>(fv), std::span<Vec3>(outv),
                   std::span<const double>(f), std::span<double>(out));
    for (std::size_t q = 0; q < x.size(); ++q) {
      int ijk[3] = {0, 0, 0};
      for (int a = 0; a < dim; ++a) {
        int i = static_cast<int>(std::floor((x[q][a] - g.lo[a]) / g.h[a]));
        if (g.periodic[a])
          i = ((i % g.n[a]) + g.n[a]) % g.n[a];
        else
          i = std::clamp(i, 0, g.n[a] - 1);
        ijk[a] = i;
      }
      const auto c = static_cast<std::size_t>(ijk[0] + g.n[0] * (ijk[1] + g.n[1] * ijk[2]));
      EXPECT_EQ(out[q], f[c]) << dim << " " << q;
      EXPECT_EQ(outv[q].x, fv[c].x) << dim << " " << q;
      EXPECT_EQ(outv[q].z, fv[c].z) << dim << " " << q;
    }
  }
}

// Momentum conservation: sum over cells of the deposited reaction = - sum over particles of
// the drag, for every scheme (also across periodic faces and outside walls). Error: round-off
// of sum w_pc = 1 (~1e-16 per particle), so 1e-13 of sum |F|.
TEST(FluidFractionInterpolation, MomentumDepositConservesTotalForce) {
  const auto g = box_grid({8, 7, 6}, {0, 0, 0}, {1e-3, 1e-3, 1e-3}, {true, false, true});
  const auto parts = random_particles(g, 500, 0.1, 0.6, 0.4, 17);
  Rng rng(2);
  std::vector<Vec3> f(parts.x.size());
  Vec3 total{};
  double scale = 0;
  for (auto& v : f) {
    v = {rng.normal(0, 1e-6), rng.normal(0, 1e-6), rng.normal(3e-6, 1e-6)};
    total += v;
    scale += norm(v);
  }
  for (auto scheme : kSchemes) {
    std::vector<Vec3> cell(g.cell_count());
    deposit_reaction_forces(g, parts.view(), scheme, f, cell);
    Vec3 sum_cells{};
    for (const Vec3& c : cell) sum_cells += c;
    EXPECT_LT(norm(sum_cells + total) / scale, 1e-13) << int(scheme);
    RecordProperty("momentum_rel_error_scheme" + std::to_string(int(scheme)),
                   fmt::format("{:.3g}", norm(sum_cells + total) / scale));
  }
}

// Semi-implicit exchange for the fluid solver (S = s_explicit - k u): with a uniform fluid
// velocity U the fluid's total source sum_c (s_c - k_c U) V_c equals minus the particles'
// total drag sum_p beta_p (U - v_p), to round-off (1e-12 of sum |F|), for every scheme.
TEST(FluidFractionInterpolation, DragExchangeSourceConservesMomentum) {
  const auto g = box_grid({6, 5, 4}, {0, 0, 0}, {2e-3, 2e-3, 2e-3}, {true, true, false});
  const auto parts = random_particles(g, 300, 0.1, 0.4, 0.3, 23);
  Rng rng(6);
  const Vec3 u_f{0.1, -0.05, 0.2};
  const RandomDrag drag(rng, std::vector<Vec3>(parts.x.size(), u_f));
  const auto& [beta, v, drag_total, scale] = drag;
  for (auto scheme : kSchemes) {
    std::vector<Vec3> s_exp(g.cell_count(), Vec3{1, 1, 1});  // overwritten
    std::vector<double> k(g.cell_count(), 1.0);
    drag_exchange_source(g, parts.view(), scheme, beta, v, s_exp, k);
    Vec3 fluid_total{};
    for (std::int64_t c = 0; c < g.cell_count(); ++c)
      fluid_total += (s_exp[c] - k[c] * u_f) * g.cell_volume();
    EXPECT_LT(norm(fluid_total + drag_total) / scale, 1e-12) << int(scheme);
  }
}

// The trilinear deposit is the adjoint of the interpolation: sum_c f_c D_c = - sum_p F_p . f(x_p).
TEST(FluidFractionInterpolation, TrilinearDepositIsAdjointOfInterpolation) {
  const auto g = box_grid({6, 5, 4}, {0, 0, 0}, {1, 1, 1}, {true, false, false});
  const auto parts = random_particles(g, 100, 0.1, 0.3, 0.0, 9);
  Rng rng(1);
  std::vector<Vec3> field(g.cell_count()), f(parts.x.size()), at(parts.x.size());
  for (auto& v : field) v = {rng.uniform(), rng.uniform(), rng.uniform()};
  for (auto& v : f) v = {rng.normal(0, 1), rng.normal(0, 1), rng.normal(0, 1)};
  std::vector<Vec3> cell(g.cell_count());
  deposit_reaction_forces(g, parts.view(), DepositScheme::Trilinear, f, cell);
  interpolate_to_points(g, field, parts.x, at);
  double lhs = 0, rhs = 0;
  for (std::size_t c = 0; c < cell.size(); ++c) lhs += dot(field[c], cell[c]);
  for (std::size_t p = 0; p < f.size(); ++p) rhs -= dot(f[p], at[p]);
  EXPECT_NEAR(lhs, rhs, 1e-12 * std::abs(rhs));
}

// A ParticleStore view: the cap radius is the bounding radius minus half the cylinder, the axis
// the orientation applied to e_z; disks and polygons are refused.
TEST(FluidFraction, ParticleStoreView) {
  ParticleStore s;
  s.add_sphere(0, 0, 1e-3, 2500, {1, 1, 1});
  s.add_sphere(1, 0, 3e-3, 2500, {2, 1, 1});
  StoreGeometry buf;
  auto p = geometry_of(s, buf);
  EXPECT_TRUE(p.half_length.empty());
  EXPECT_EQ(p.radius[1], 3e-3);
  s.enable_shapes();
  s.shape()[1] = static_cast<std::int32_t>(ShapeCode::Spherocylinder);
  s.half_length()[1] = 2e-3;
  s.orientation()[1] = quat_from_axis_angle({0, 1, 0}, kPiD / 2);  // e_z -> e_x
  p = geometry_of(s, buf);
  EXPECT_NEAR(p.radius[1], 1e-3, 1e-18);
  EXPECT_EQ(p.half_length[1], 2e-3);
  EXPECT_NEAR(p.axis[1].x, 1.0, 1e-15);
  EXPECT_NEAR(p.volume(1), kPiD * 1e-6 * 4e-3 + 4.0 / 3 * kPiD * 1e-9, 1e-20);
  s.shape()[0] = static_cast<std::int32_t>(ShapeCode::Polygon);
  EXPECT_THROW(geometry_of(s, buf), Error);
}

TEST(FluidFraction, BadInputIsAnError) {
  const auto g = box_grid({3, 3, 3}, {0, 0, 0}, {1, 1, 1}, {false, false, false});
  Particles p;
  p.x = {{1, 1, 1}, {2, 2, 2}};
  p.radius = {0.1};  // one radius for two particles
  std::vector<double> eps(g.cell_count());
  EXPECT_THROW(fluid_fraction(g, p.view(), {}, eps), Error);
  p.radius = {0.1, -0.1};
  EXPECT_THROW(fluid_fraction(g, p.view(), {}, eps), Error);
  p.radius = {0.1, 0.1};
  p.half_length = {0.1, 0.1};
  p.axis = {{0, 0, 1}, {0, 0, 2}};  // not a unit vector
  EXPECT_THROW(fluid_fraction(g, p.view(), {}, eps), Error);
  p.axis = {{0, 0, 1}, {0, 1, 0}};
  std::vector<double> short_eps(5);
  EXPECT_THROW(fluid_fraction(g, p.view(), {}, short_eps), Error);
  EXPECT_NO_THROW(fluid_fraction(g, p.view(), {}, eps));
}
