// SPDX-License-Identifier: GPL-3.0-or-later
// The sphere force loop (contact/pair_forces.cpp) against a brute-force oracle written here: every
// pair of a random polydisperse packing of two materials is tested for contact, its kinematics
// built from the definitions and the contact law called once per pair, with the history the
// list holds for that pair. Covered: the batched loop (one law for all pairs; one or two
// materials; with and without rolling friction; open, periodic and Lees-Edwards boxes;
// batches that fill up in the middle of a row), the per-contact dispatch of mixed laws, the
// virial not changing a force, the contact fabric of both loops, and the AVX2 and baseline
// kernels giving the same bits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "contact/pair_forces.hpp"
#include "contact/registry.hpp"
#include "neighbor/verlet_list.hpp"

using namespace gf;
using contact::ContactKinematics;
using contact::PairCoeffs;

namespace {

enum class Box { Open, Periodic, Sheared };

Domain make_box(Box kind) {
  Domain d;
  d.lo = {0, 0, 0};
  d.hi = {0.05, 0.04, 0.045};
  if (kind != Box::Open) d.periodic = {true, true, true};
  if (kind == Box::Sheared) {
    d.shear_gradient = 2;
    d.shear_flow = 0;
    d.shear_velocity = 2.0;
    d.shear_offset = 0.0137;
  }
  return d;
}

struct Packing {
  ParticleStore p;
  Material glass{"glass", 2500, 1e7, 0.3};
  Material steel{"steel", 7800, 2e8, 0.28};
  PairTable<PairCoeffs> pairs;
  VerletList list;
  Domain d;

  /// n random spheres (radius 2-4 mm, ~3 contacts each), material 0 or 1 (n_mat = 1: all 0),
  /// random velocities and spins. `laws`: the model of the glass-glass, glass-steel and
  /// steel-steel pairs.
  Packing(Box kind, int n, int n_mat, std::array<const char*, 3> laws, double rolling,
          unsigned seed)
      : pairs(n_mat), d(make_box(kind)) {
    const Material* mats[2] = {&glass, &steel};
    for (int a = 0; a < n_mat; ++a)
      for (int b = a; b < n_mat; ++b) {
        const std::string law = laws[static_cast<std::size_t>(a + b)];
        std::map<std::string, double> prm{{"restitution", 0.6 + 0.1 * (a + b)},
                                          {"friction", 0.3 + 0.1 * (a + b)},
                                          {"rolling_friction", a == b ? rolling : 0.0}};
        if (law == "hooke") {
          prm["stiffness"] = 2000.0;
          prm["tangential_stiffness_ratio"] = 2.0 / 7.0;
        }
        pairs.set(a, b, contact::prepare_pair(law, {mats[a], mats[b], 0.004}, prm));
      }
    std::mt19937_64 g(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const Vec3 L = d.length();
    for (int i = 0; i < n; ++i) {
      const int m = n_mat > 1 ? static_cast<int>(u(g) * 2) : 0;
      const double r = 0.002 + 0.002 * u(g);
      const Vec3 x{u(g) * L.x, u(g) * L.y, u(g) * L.z};
      const Vec3 v{u(g) - 0.5, u(g) - 0.5, u(g) - 0.5};
      const Vec3 w{200 * (u(g) - 0.5), 200 * (u(g) - 0.5), 200 * (u(g) - 0.5)};
      p.add_sphere(i + 1, m, r, mats[m]->density, x, v, w);
    }
    list.build(d, p.x(), p.radius(), p.size(), 0.001);
    // Histories as after a step: one call of the loop (forces dropped), then new velocities so
    // that the next call's relative velocities differ from those that made the histories.
    zero_forces();
    contact::compute_pair_forces(p, d, list, pairs, 1e-5);
    for (std::size_t i = 0; i < p.size(); ++i) p.v()[i] = -0.7 * p.v()[i];
  }

  void zero_forces() {
    for (std::size_t i = 0; i < p.size(); ++i) p.f()[i] = p.torque()[i] = {};
  }
};

struct OracleResult {
  std::vector<Vec3> f, tq, hist;
  std::int64_t touching = 0;
};

/// Every pair i < j by brute force: contact from the minimum (Lees-Edwards) image, kinematics
/// from the definitions (normal from j to i, contact point at the middle of the overlap,
/// R* = r_i r_j / (r_i + r_j), m* = m_i m_j / (m_i + m_j), v_rel with the image's sliding
/// velocity), the law of the pair's materials with the list's history for the pair.
OracleResult oracle(const Packing& s, double dt) {
  const ParticleStore& p = s.p;
  const std::size_t n = p.size();
  OracleResult o;
  o.f.assign(n, {});
  o.tq.assign(n, {});
  const auto hist = s.list.history();
  o.hist.assign(hist.begin(), hist.end());
  std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> entry;
  const auto off = s.list.offsets();
  const auto nb = s.list.neighbors();
  for (std::size_t i = 0; i < n; ++i)
    for (std::int64_t k = off[i]; k < off[i + 1]; ++k) {
      entry[{static_cast<std::int64_t>(i), nb[k]}] = k;
      o.hist[k] = {};  // apart unless found touching below
    }
  const Vec3* x = p.x();
  const double* r = p.radius();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const Vec3 dd = s.d.delta(x[i], x[j]);
      const double dist = norm(dd);
      const double overlap = r[i] + r[j] - dist;
      if (overlap <= 0) continue;
      const auto it = entry.find({static_cast<std::int64_t>(i), static_cast<std::int64_t>(j)});
      EXPECT_NE(it, entry.end()) << "touching pair " << i << "-" << j << " not in the list";
      if (it == entry.end()) continue;
      ++o.touching;
      ContactKinematics kin;
      kin.overlap = overlap;
      kin.normal = dd / dist;
      const double arm_i = r[i] - overlap / 2, arm_j = r[j] - overlap / 2;
      kin.r_eff = r[i] * r[j] / (r[i] + r[j]);
      const double mi = p.mass()[i], mj = p.mass()[j];
      kin.m_eff = mi * mj / (mi + mj);
      const Vec3 vj = p.v()[j] + s.d.image_velocity(x[i], x[j]);
      const Vec3 wi = p.omega()[i], wj = p.omega()[j];
      kin.v_rel = p.v()[i] - vj - cross(arm_i * wi + arm_j * wj, kin.normal);
      kin.omega_rel = wi - wj;
      const PairCoeffs& c = s.pairs(p.material()[i], p.material()[j]);
      Vec3 h = hist[it->second];
      const contact::ContactResult res =
          dispatch_index(contact::ContactModels{}, c.model,
                         [&]<class M>() { return M::Law::evaluate(c, kin, dt, h); });
      o.hist[it->second] = h;
      o.f[i] += res.force;
      o.f[j] -= res.force;
      const Vec3 nxf = cross(kin.normal, res.force);
      o.tq[i] += res.rolling_torque - arm_i * nxf;
      o.tq[j] -= res.rolling_torque + arm_j * nxf;
    }
  return o;
}

double max_norm(const std::vector<Vec3>& a) {
  double m = 0;
  for (const auto& v : a) m = std::max(m, norm(v));
  return m;
}

/// The loop's forces, torques and histories against the oracle's. The loop computes the same
/// quantities in another order and with fewer divisions (one reciprocal for 1/|d|, R* and m*;
/// one for the Coulomb cap and 1/k_t): round-off of a few ulp per contact, so 1e-10 of the
/// largest value per array. A wrong image, sign, lever arm or history slot is an O(1) error.
void check_against_oracle(Packing& s) {
  const double dt = 1e-5;
  const OracleResult o = oracle(s, dt);
  ASSERT_GT(o.touching, 300) << "too few contacts to test";
  s.zero_forces();
  const std::int64_t touching = contact::compute_pair_forces(s.p, s.d, s.list, s.pairs, dt);
  EXPECT_EQ(touching, o.touching);
  const double fs = max_norm(o.f), ts = max_norm(o.tq), hs = max_norm(o.hist);
  ASSERT_GT(fs, 0);
  ASSERT_GT(ts, 0);
  ASSERT_GT(hs, 0);
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    EXPECT_LE(norm(s.p.f()[i] - o.f[i]), 1e-10 * fs) << "force on " << i;
    EXPECT_LE(norm(s.p.torque()[i] - o.tq[i]), 1e-10 * ts) << "torque on " << i;
  }
  const auto h = s.list.history();
  for (std::size_t k = 0; k < h.size(); ++k)
    EXPECT_LE(norm(h[k] - o.hist[k]), 1e-10 * hs) << "history of entry " << k;
}

constexpr std::array<const char*, 3> kHertz{"hertz_mindlin", "hertz_mindlin", "hertz_mindlin"};

}  // namespace

class PairForcesOracle : public ::testing::TestWithParam<Box> {};

TEST_P(PairForcesOracle, OneMaterialHertz) {
  Packing s(GetParam(), 700, 1, kHertz, 0.0, 1);
  check_against_oracle(s);
}

TEST_P(PairForcesOracle, TwoMaterialsWithRollingFriction) {
  Packing s(GetParam(), 700, 2, kHertz, 0.2, 2);
  check_against_oracle(s);
}

TEST_P(PairForcesOracle, HookeForAllPairs) {
  Packing s(GetParam(), 700, 2, {"hooke", "hooke", "hooke"}, 0.1, 3);
  check_against_oracle(s);
}

TEST_P(PairForcesOracle, MixedLawsDispatchedPerContact) {
  Packing s(GetParam(), 700, 2, {"hertz_mindlin", "hooke", "hertz_mindlin"}, 0.1, 4);
  check_against_oracle(s);
}

INSTANTIATE_TEST_SUITE_P(Boxes, PairForcesOracle,
                         ::testing::Values(Box::Open, Box::Periodic, Box::Sheared),
                         [](const auto& param_info) {
                           const Box b = param_info.param;
                           return b == Box::Open       ? std::string("Open")
                                  : b == Box::Periodic ? std::string("Periodic")
                                                       : std::string("LeesEdwards");
                         });

// Sampling the stress (the virial) on some steps must not change the trajectory: the forces with
// and without the virial are the same bits.
TEST(PairForces, VirialLeavesForcesBitIdentical) {
  for (Box kind : {Box::Open, Box::Sheared}) {
    Packing a(kind, 700, 2, kHertz, 0.2, 5);
    Packing b(kind, 700, 2, kHertz, 0.2, 5);
    a.zero_forces();
    b.zero_forces();
    std::vector<Mat3> rows(b.p.size());
    contact::ContactSink sink;
    sink.rows = rows.data();
    contact::compute_pair_forces(a.p, a.d, a.list, a.pairs, 1e-5);
    contact::compute_pair_forces(b.p, b.d, b.list, b.pairs, 1e-5, &sink);
    for (std::size_t i = 0; i < a.p.size(); ++i) {
      ASSERT_EQ(a.p.f()[i], b.p.f()[i]) << i;
      ASSERT_EQ(a.p.torque()[i], b.p.torque()[i]) << i;
    }
    double trace = 0;
    for (const auto& w : rows) trace += w.a[0][0] + w.a[1][1] + w.a[2][2];
    EXPECT_GT(trace, 0);  // repulsive contacts: positive virial
  }
}

// The contact fabric (sum of n n over the touching pairs) collected by the batched loop (one
// law) and by the per-contact dispatch (mixed laws), against a sum over all pairs written here:
// the fabric does not depend on the law, only on which pairs touch and their normals.
TEST(PairForces, FabricOfBothLoopsMatchesPairSum) {
  for (Box kind : {Box::Open, Box::Sheared})
    for (const auto laws :
         {kHertz, std::array<const char*, 3>{"hertz_mindlin", "hooke", "hertz_mindlin"}}) {
      Packing s(kind, 700, 2, laws, 0.1, 7);
      s.zero_forces();
      std::vector<Mat3> rows(s.p.size()), normals(s.p.size());
      contact::ContactSink sink;
      sink.rows = rows.data();
      sink.normals = normals.data();
      const auto touching = contact::compute_pair_forces(s.p, s.d, s.list, s.pairs, 1e-5, &sink);
      ASSERT_GT(touching, 300);
      Mat3 got, ref;
      for (const auto& w : normals) got = got + w;
      const Vec3* x = s.p.x();
      const double* r = s.p.radius();
      std::int64_t pairs = 0;
      for (std::size_t i = 0; i < s.p.size(); ++i)
        for (std::size_t j = i + 1; j < s.p.size(); ++j) {
          const Vec3 d = s.d.delta(x[i], x[j]);
          if (norm2(d) >= (r[i] + r[j]) * (r[i] + r[j])) continue;
          ++pairs;
          const Vec3 n = (1.0 / norm(d)) * d;
          ref = ref + outer(n, n);
        }
      EXPECT_EQ(touching, pairs);
      // Sums of a few hundred unit-size terms in another order: round-off ~1e-13.
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) EXPECT_NEAR(got.a[a][b], ref.a[a][b], 1e-10) << a << b;
      EXPECT_NEAR(got.a[0][0] + got.a[1][1] + got.a[2][2], static_cast<double>(pairs), 1e-10);
    }
}

// The AVX2 kernel (where the CPU has it) and the baseline kernel do the same IEEE operations in
// the same order, without FMA: the same bits.
TEST(PairForces, BaselineAndAvx2KernelsBitIdentical) {
  Packing a(Box::Periodic, 700, 2, kHertz, 0.2, 6);
  Packing b(Box::Periodic, 700, 2, kHertz, 0.2, 6);
  a.zero_forces();
  b.zero_forces();
  contact::compute_pair_forces(a.p, a.d, a.list, a.pairs, 1e-5);
  contact::use_baseline_kernels(true);
  contact::compute_pair_forces(b.p, b.d, b.list, b.pairs, 1e-5);
  contact::use_baseline_kernels(false);
  for (std::size_t i = 0; i < a.p.size(); ++i) {
    ASSERT_EQ(a.p.f()[i], b.p.f()[i]) << i;
    ASSERT_EQ(a.p.torque()[i], b.p.torque()[i]) << i;
  }
  const auto ha = a.list.history(), hb = b.list.history();
  for (std::size_t k = 0; k < ha.size(); ++k) ASSERT_EQ(ha[k], hb[k]) << k;
}
