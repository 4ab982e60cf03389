// SPDX-License-Identifier: GPL-3.0-or-later
// Lees-Edwards images: the shifted minimum image against a search over all 27 images, wrapping
// of positions and velocities, the neighbour list against the brute-force oracle at offsets
// that are not whole cells, and the contact virial and fabric (spheres and spherocylinders)
// against independent computations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "case_builder.hpp"
#include "contact/geometry/capsule.hpp"
#include "contact/pair_forces.hpp"
#include "contact/registry.hpp"
#include "contact/shape_forces.hpp"
#include "core/quaternion.hpp"
#include "integrators/velocity_verlet.hpp"
#include "io/input/parse_case.hpp"
#include "neighbor/brute_force.hpp"
#include "neighbor/verlet_list.hpp"
#include "simulation/simulation.hpp"

using namespace gf;

namespace {

Domain sheared_box(double offset) {
  Domain d;
  d.lo = {0, 0, 0};
  d.hi = {0.06, 0.04, 0.05};
  d.periodic = {true, true, true};
  d.shear_gradient = 2;
  d.shear_flow = 0;
  d.shear_velocity = 100.0 * 0.05;  // gamma_dot = 100 1/s
  d.shear_offset = offset;
  return d;
}

/// Nearest image of b to a by trying every image (i, j, k) of the sliding lattice: the image
/// k boxes up is shifted by k offset along x.
Vec3 nearest_image_delta(const Domain& d, const Vec3& a, const Vec3& b, int& image) {
  const Vec3 L = d.length();
  Vec3 best{};
  double best2 = 1e300;
  for (int k = -1; k <= 1; ++k)
    for (int j = -1; j <= 1; ++j)
      for (int i = -2; i <= 2; ++i) {
        const Vec3 img{b.x + i * L.x + k * d.shear_offset, b.y + j * L.y, b.z + k * L.z};
        const Vec3 dd = a - img;
        if (norm2(dd) < best2) {
          best2 = norm2(dd);
          best = dd;
          image = k;
        }
      }
  return best;
}

std::vector<Vec3> random_points(const Domain& d, int n, unsigned seed) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> x;
  const Vec3 L = d.length();
  for (int i = 0; i < n; ++i) x.push_back({u(g) * L.x, u(g) * L.y, u(g) * L.z});
  return x;
}

}  // namespace

TEST(LeesEdwards, ShiftedMinimumImageMatchesSearchOverImages) {
  for (double offset : {0.0, 0.0137, -0.0291, 0.0299, -0.03}) {
    const Domain d = sheared_box(offset);
    const auto x = random_points(d, 200, 5);
    int checked = 0;
    for (std::size_t a = 0; a < x.size(); ++a)
      for (std::size_t b = 0; b < x.size(); ++b) {
        int image = 0;
        const Vec3 ref = nearest_image_delta(d, x[a], x[b], image);
        const Vec3 got = d.delta(x[a], x[b]);
        // The image along z is chosen by |dz| < L_z / 2 first; for pairs within a cutoff
        // (< L/4 here) that is the nearest image, which is all the force loop needs.
        if (norm(ref) > 0.01) continue;
        ++checked;
        EXPECT_NEAR(norm(got - ref), 0.0, 1e-15) << offset;
        EXPECT_EQ(d.shear_image(x[a], x[b]), image);
      }
    EXPECT_GT(checked, 200);
  }
}

TEST(LeesEdwards, WrapMovesPositionAndVelocityToTheImage) {
  const Domain d = sheared_box(0.0213);
  // Leaving through the top: re-enter at the bottom, shifted back by the offset, slower by U.
  Vec3 p{0.03, 0.02, 0.0501}, v{1.0, 0, 0.5};
  d.wrap(p, &v);
  EXPECT_NEAR(p.z, 0.0001, 1e-15);
  EXPECT_NEAR(p.x, 0.03 - 0.0213, 1e-15);
  EXPECT_NEAR(v.x, 1.0 - d.shear_velocity, 1e-15);
  // And back through the bottom.
  d.wrap(p += Vec3{0, 0, -0.0002}, &v);
  EXPECT_NEAR(p.z, 0.0499, 1e-15);
  EXPECT_NEAR(p.x, 0.03, 1e-15);
  EXPECT_NEAR(v.x, 1.0, 1e-15);
  // The displacement to another grain does not change by wrapping.
  const Vec3 q{0.02, 0.021, 0.001};
  Vec3 a{0.025, 0.02, 0.0503}, va{};
  const Vec3 before = d.delta(a, q);
  d.wrap(a, &va);
  EXPECT_NEAR(norm(d.delta(a, q) - before), 0.0, 1e-15);
}

TEST(LeesEdwards, ImageVelocityIsTheSlidingSpeed) {
  const Domain d = sheared_box(0.01);
  const Vec3 top{0.01, 0.01, 0.049}, bottom{0.01, 0.01, 0.001};
  EXPECT_EQ(d.image_velocity(top, bottom).x, d.shear_velocity);   // bottom's upper image
  EXPECT_EQ(d.image_velocity(bottom, top).x, -d.shear_velocity);  // top's lower image
  EXPECT_EQ(d.image_velocity(top, top).x, 0.0);
}

TEST(LeesEdwards, NeighbourListMatchesBruteForceAtAnyOffset) {
  for (double offset : {0.0, 0.0041, -0.0173, 0.0333, -0.0449}) {
    Domain d = sheared_box(offset);
    d.hi = {0.09, 0.06, 0.075};  // several cells along each axis
    d.shear_velocity = 100.0 * 0.075;
    const auto x = random_points(d, 1500, 11);
    std::vector<double> r(x.size(), 0.002);
    const double skin = 0.001;
    VerletList list;
    list.build(d, x.data(), r.data(), x.size(), skin);
    std::vector<std::pair<int, int>> got;
    for (std::size_t i = 0; i < list.n_particles(); ++i)
      for (auto k = list.offsets()[i]; k < list.offsets()[i + 1]; ++k)
        got.emplace_back(static_cast<int>(i), list.neighbors()[k]);
    std::sort(got.begin(), got.end());
    const auto want = brute_force_pairs(d, x.data(), r.data(), x.size(), skin);
    EXPECT_EQ(got, want) << "offset " << offset;
  }
}

TEST(LeesEdwards, RebuildWhenTheOffsetMovedBySkinOverThree) {
  Domain d = sheared_box(0.0);
  const auto x = random_points(d, 100, 3);
  std::vector<double> r(x.size(), 0.002);
  VerletList list;
  list.build(d, x.data(), r.data(), x.size(), 0.003);
  EXPECT_FALSE(list.needs_rebuild(d, x.data(), x.size()));
  d.shear_offset = 0.0009;  // skin - 3 x 0.0009 > 0: still valid
  EXPECT_FALSE(list.needs_rebuild(d, x.data(), x.size()));
  d.shear_offset = 0.0011;
  EXPECT_TRUE(list.needs_rebuild(d, x.data(), x.size()));
  // Offsets repeat every L_x: a full turn is no change.
  d.shear_offset = 0.0;
  const double o0 = list.shear_offset_at_build();
  d.set_shear_time((0.06 + 0.0001) / d.shear_velocity);
  EXPECT_NEAR(d.shear_offset, o0 + 0.0001, 1e-12);
  EXPECT_FALSE(list.needs_rebuild(d, x.data(), x.size()));
}

// A grain that crosses the Lees-Edwards boundary is shifted by the offset of that moment; a
// displacement measured later through the current offset is off by the offset's change since.
// With DriftExtras::wrap_refs the reference takes the wrap's jump, and the measured displacement
// is the grain's own path, whatever the offset did; the list may then allow for the images'
// slide once, not three times.
TEST(LeesEdwards, ReferencesFollowTheWrapSoDisplacementsStayExact) {
  Domain d = sheared_box(0.0);
  ParticleStore p;
  p.add_sphere(1, 0, 0.002, 1000, {0.03, 0.02, 0.0499});
  p.mass()[0] = 1e-3;
  p.inertia()[0] = 1e-9;
  p.v()[0] = {0.0, 0.0, 1.0};  // up through the top at step 1
  const double dt = 1e-4;
  for (bool follow : {false, true}) {
    VerletList list;
    ParticleStore q = p;
    list.set_follow_wraps(follow);
    list.build(d, q.x(), q.radius(), 1, 0.003);
    EXPECT_EQ(list.refs_follow_wraps(), follow);
    double max_d2 = 0;
    for (int s = 1; s <= 5; ++s) {
      d.set_shear_time(s * dt);  // offset 0.5 mm per step
      DriftExtras extras;
      extras.x_ref = list.reference_positions().data();
      if (follow) extras.wrap_refs = list.follow_wraps().data();
      VelocityVerlet::pre_force(q, d, dt, &extras);
      max_d2 = extras.max_d2;
    }
    EXPECT_LT(q.x()[0].z, 0.01);               // wrapped to the bottom at step 1
    EXPECT_EQ(q.v()[0].x, -d.shear_velocity);  // 5 m/s slower than the upper image's flow
    // The grain's own path: 5 x 0.1 mm up, then 4 steps at -5 m/s along x (-2 mm). Through the
    // current offset (2.5 mm; 0.5 mm at the crossing) the x part is hidden: 0.5 mm only, which
    // is why the list without following references allows for three slides.
    if (follow)
      EXPECT_NEAR(std::sqrt(max_d2), std::hypot(5e-4, 2e-3), 1e-12);
    else
      EXPECT_NEAR(std::sqrt(max_d2), 5e-4, 1e-12);
    // The allowance for the slide: once with following references, three times without.
    EXPECT_NEAR(list.displacement_limit(d), 0.5 * (0.003 - (follow ? 1 : 3) * 0.0025), 1e-12);
    d.shear_offset = 0;
  }
}

namespace {

/// Every pair of grains that touches (spheres: centres closer than r_i + r_j; spherocylinders:
/// axes closer than the sum of the cap radii) by an O(N^2) search over the sliding images, each
/// as (i, j), i < j.
std::vector<std::pair<int, int>> touching_pairs(const ParticleStore& p, const Domain& d) {
  std::vector<std::pair<int, int>> out;
  const auto n = static_cast<int>(p.size());
  const double* hl = p.has_shapes() ? p.half_length() : nullptr;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const Vec3 dd = d.delta(p.x()[i], p.x()[j]);
      const double ri = p.radius()[i], rj = p.radius()[j];
      if (norm2(dd) >= (ri + rj) * (ri + rj)) continue;
      if (hl == nullptr) {
        out.emplace_back(i, j);
        continue;
      }
      const Vec3 ai = hl[i] * contact::capsule_axis(p.orientation()[i]);
      const Vec3 aj = hl[j] * contact::capsule_axis(p.orientation()[j]);
      const Vec3 xi = p.x()[i], xj = xi - dd;
      const auto sc = contact::closest_points_segments(xi - ai, xi + ai, xj - aj, xj + aj);
      const double reach = ri - hl[i] + rj - hl[j];
      if (sc.dist2 < reach * reach) out.emplace_back(i, j);
    }
  return out;
}

/// Runs `cfg` for `steps` steps and checks after each that the neighbour list holds every
/// touching pair; returns the number of (step, pair) checks made and of builds.
std::pair<std::int64_t, std::int64_t> expect_list_holds_every_contact(const config::Case& cfg,
                                                                      int steps) {
  Simulation sim(cfg);
  std::int64_t checked = 0;
  for (int s = 0; s < steps; ++s) {
    sim.step();
    const auto& list = sim.neighbor_list();
    const auto off = list.offsets();
    const auto nb = list.neighbors();
    for (const auto& [i, j] : touching_pairs(sim.particles(), sim.domain())) {
      const auto first = nb.begin() + off[static_cast<std::size_t>(i)];
      const auto last = nb.begin() + off[static_cast<std::size_t>(i) + 1];
      const auto first_j = nb.begin() + off[static_cast<std::size_t>(j)];
      const auto last_j = nb.begin() + off[static_cast<std::size_t>(j) + 1];
      const bool listed =
          std::find(first, last, j) != last || std::find(first_j, last_j, i) != last_j;
      ++checked;
      if (!listed) {
        ADD_FAILURE() << "step " << s + 1 << ": touching pair " << i << ", " << j
                      << " is not in the list (builds " << list.n_builds() << ")";
        return {checked, list.n_builds()};
      }
    }
  }
  return {checked, sim.neighbor_list().n_builds()};
}

}  // namespace

// The rebuild test against the oracle in Lees-Edwards boxes at high shear (images sliding at 19
// and 9.6 m/s, several skins between builds): after every step the list holds every touching
// pair, for spheres (displacements measured in the drift) and for rods (measured from both ends).
TEST(LeesEdwards, ListHoldsEveryTouchingPairAfterEveryStep) {
  const auto spheres = input::load_case(
      std::string(GF_SOURCE_DIR) + "/cases/rheology/lees_edwards_spheres/case.yaml",
      {{"particles[0].fill.volume_fraction", "0.35"},
       {"shear.rate", "400"},
       {"time.step", "1.0e-6"}});
  const auto [n_sphere, builds_sphere] = expect_list_holds_every_contact(spheres, 600);
  EXPECT_GT(n_sphere, 100);  // pair-steps in contact (the lattice start collides late)
  EXPECT_GT(builds_sphere, 10);

  auto rods = test::lees_edwards_box(0.048, 200);
  test::add_aligned_rods(rods, 0.3, 5, 1.0);
  const auto [n_rod, builds_rod] = expect_list_holds_every_contact(rods, 500);
  EXPECT_GT(n_rod, 500);
  EXPECT_GT(builds_rod, 5);
}

// Grains at rest in the lab frame next to the gradient boundary (velocities that cancel the
// streaming profile the shear start adds), placed so that no pair is within reach at the start:
// only the images' slide (19.2 m/s) brings pairs into contact, after several skins of slide and
// with no grain moving before, so only the offset term of the rebuild test can have the pairs in
// the list when they touch (checked: with that term dropped both cases miss pairs). Spheres in
// pairs 3.5 mm apart through the boundary, 7 mm apart along the flow; rods along y in two layers
// 2.7 mm apart through the boundary, 5 mm apart along the flow.
TEST(LeesEdwards, ListFollowsTheSlidingImagesOfGrainsAtRest) {
  const double rate = 400, L = 0.048, half = 0.5 * L;
  auto at_rest = [&](const Vec3& x) { return Vec3{-rate * (x.z - half), 0, 0}; };
  auto box = [&] { return test::lees_edwards_box(L, rate); };
  {
    auto c = box();
    const double r = 0.002;
    std::vector<Vec3> x, v;
    for (int k = 0; k < 6; ++k) {
      const double xb = 0.004 + 0.0065 * k, y = 0.004 + 0.008 * k;
      // The upper grain's lower image sits at x - offset: it reaches the lower grain after
      // ~5 mm of slide (~260 steps), where the list (skin 1 mm) must have been rebuilt.
      for (const Vec3& p : {Vec3{xb, y, r}, Vec3{xb + 0.007, y, L - 0.0015}}) {
        x.push_back(p);
        v.push_back(at_rest(p));
      }
    }
    test::add_spheres(c, "pom", r, x, v);
    const auto [checked, builds] = expect_list_holds_every_contact(c, 600);
    EXPECT_GT(checked, 100);  // pair-steps in contact
    EXPECT_GT(builds, 3);
  }
  {
    auto c = box();
    std::vector<Vec3> x, v;
    std::vector<Quat> q;
    const Quat along_y = quat_from_axis_angle({1, 0, 0}, -1.5707963267948966);  // e_z -> e_y
    for (int layer = 0; layer < 2; ++layer)
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 3; ++j) {
          const Vec3 p{0.002 + 0.012 * i + 0.005 * layer, (j + 0.5) * 0.016,
                       layer == 0 ? 0.0015 : L - 0.0012};
          x.push_back(p);
          v.push_back(at_rest(p));
          q.push_back(along_y);
        }
    test::add_capsules(c, "pom", 0.0015, 0.009, x, q, v);
    const auto [checked, builds] = expect_list_holds_every_contact(c, 600);
    EXPECT_GT(checked, 100);
    EXPECT_GT(builds, 3);
  }
}

namespace {

/// One material with itself: Hooke law of stiffness k (N/m), e = 0.7, Coulomb friction mu.
PairTable<contact::PairCoeffs> hooke_table(const Material& m, double k, double mu) {
  PairTable<contact::PairCoeffs> pairs{1};
  pairs.set(0, 0,
            contact::prepare_pair("hooke", {&m, &m, 0.004},
                                  {{"restitution", 0.7},
                                   {"stiffness", k},
                                   {"friction", mu},
                                   {"rolling_friction", 0.0},
                                   {"tangential_stiffness_ratio", 2.0 / 7.0}}));
  return pairs;
}

/// Overlapping spheres at rest (no damping, no friction force), Hooke law k = 1000 N/m.
struct VirialSetup {
  ParticleStore p;
  Material m{"m", 2500, 1e7, 0.3};
  PairTable<contact::PairCoeffs> pairs = hooke_table(m, 1000.0, 0.0);
  explicit VirialSetup(const Domain& d, int n, unsigned seed) {
    std::mt19937_64 g(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const Vec3 L = d.length();
    for (int i = 0; i < n; ++i)
      p.add_sphere(i + 1, 0, 0.003 + 0.002 * u(g), 2500,
                   {d.lo.x + u(g) * L.x, d.lo.y + u(g) * L.y, d.lo.z + u(g) * L.z});
    for (std::size_t i = 0; i < p.size(); ++i) {
      p.mass()[i] = 1e-3;
      p.inertia()[i] = 1e-9;
    }
  }
};

/// The virial of the force loop over a fresh list (forces zeroed first); `touching` gets the
/// number of touching pairs, `normals` (if given) the sum of n (x) n over them.
Mat3 loop_virial(VirialSetup& s, const Domain& d, std::int64_t& touching, Mat3* normals = nullptr) {
  VerletList list;
  list.build(d, s.p.x(), s.p.radius(), s.p.size(), 0.001);
  std::vector<Mat3> rows(s.p.size()), nrows(s.p.size());
  contact::ContactSink sink;
  sink.rows = rows.data();
  if (normals != nullptr) sink.normals = nrows.data();
  for (std::size_t i = 0; i < s.p.size(); ++i) s.p.f()[i] = {};
  touching = contact::compute_pair_forces(s.p, d, list, s.pairs, 1e-6, &sink);
  Mat3 w;
  for (const auto& r : rows) w = w + r;
  if (normals != nullptr) {
    *normals = {};
    for (const auto& r : nrows) *normals = *normals + r;
  }
  return w;
}

/// Every component of w equals that of ref within `tol` x the largest diagonal entry of ref.
void expect_virial_near(const Mat3& w, const Mat3& ref, double tol) {
  double scale = 0;
  for (int a = 0; a < 3; ++a) scale = std::max(scale, std::abs(ref.a[a][a]));
  ASSERT_GT(scale, 0);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) EXPECT_NEAR(w.a[a][b], ref.a[a][b], tol * scale) << a << b;
}

/// The virial and the contact fabric (sum of n n) of a dense random packing in a periodic
/// (optionally sheared) box by the force loop, against O(N^2) sums written here: F = k delta n
/// for every overlapping pair.
void check_periodic_virial(Domain d) {
  VirialSetup s(d, 400, 21);
  std::int64_t touching = 0;
  Mat3 nn;
  const Mat3 w = loop_virial(s, d, touching, &nn);
  ASSERT_GT(touching, 100);
  Mat3 ref, ref_nn;
  const Vec3* x = s.p.x();
  const double* r = s.p.radius();
  for (std::size_t i = 0; i < s.p.size(); ++i)
    for (std::size_t j = i + 1; j < s.p.size(); ++j) {
      const Vec3 dd = d.delta(x[i], x[j]);
      const double dist = norm(dd), overlap = r[i] + r[j] - dist;
      if (overlap <= 0) continue;
      const Vec3 f = (1000.0 * overlap / dist) * dd;
      ref = ref + outer(dd, f);
      ref_nn = ref_nn + outer((1 / dist) * dd, (1 / dist) * dd);
    }
  // Same pairs, same products, summed in a different order: round-off only (~1e-15 relative
  // per term, a few hundred terms); 1e-10 of the pressure scale leaves a wide margin but
  // catches any missed pair or a wrong image (each pair is ~1e-3 of the sum).
  expect_virial_near(w, ref, 1e-10);
  // The fabric's trace counts the pairs exactly (round-off aside); each entry is a sum of a few
  // hundred terms of order 1.
  EXPECT_NEAR(nn.a[0][0] + nn.a[1][1] + nn.a[2][2], static_cast<double>(touching), 1e-9);
  expect_virial_near(nn, ref_nn, 1e-12);
}

}  // namespace

TEST(Virial, PeriodicBoxMatchesPairSum) {
  Domain d;
  d.lo = {0, 0, 0};
  d.hi = {0.06, 0.05, 0.04};
  d.periodic = {true, true, true};
  check_periodic_virial(d);
}

TEST(Virial, LeesEdwardsBoxMatchesPairSum) {
  Domain d = sheared_box(0.0217);
  d.hi = {0.06, 0.05, 0.04};
  // Images at rest (grains at rest would otherwise meet their sliding images with a damping
  // force that the elastic oracle leaves out).
  d.shear_velocity = 0;
  check_periodic_virial(d);
}

TEST(Virial, OpenBoxEqualsSumOfPositionTimesForce) {
  // Without periodic images, sum over pairs (x_i - x_j) F_ij = sum_i x_i F_i (Newton's third
  // law): an identity that does not use the pair decomposition at all.
  Domain d;
  d.lo = {0, 0, 0};
  d.hi = {0.05, 0.05, 0.05};
  VirialSetup s(d, 300, 4);
  std::int64_t touching = 0;
  const Mat3 w = loop_virial(s, d, touching);
  ASSERT_GT(touching, 0);
  Mat3 ref;
  for (std::size_t i = 0; i < s.p.size(); ++i)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) ref.a[a][b] += s.p.x()[i][a] * s.p.f()[i][b];
  // x_i F_i sums large cancelling terms (|x| ~ 0.05 m vs branch vectors ~ 0.005 m): round-off
  // ~1e-14 relative; 1e-10 as required by the issue.
  expect_virial_near(w, ref, 1e-10);
}

namespace {

/// Closest points of the segments c_i + s a_i (|s| <= h_i) and c_j + t a_j (|t| <= h_j), as the
/// difference p_i - p_j, written here from the definition: the squared distance is a convex
/// quadratic in (s, t), so its minimum over the rectangle is the interior stationary point (if
/// it lies inside) or the best of the four edges, each a clamped one-dimensional minimum.
Vec3 segment_gap(const Vec3& ci, const Vec3& ai, double hi, const Vec3& cj, const Vec3& aj,
                 double hj) {
  const Vec3 w = ci - cj;
  const double ab = dot(ai, aj), wa = dot(w, ai), wb = dot(w, aj);
  auto gap = [&](double s, double t) { return w + s * ai - t * aj; };
  Vec3 best{};
  double best2 = 1e300;
  auto consider = [&](double s, double t) {
    const Vec3 g = gap(s, t);
    if (norm2(g) < best2) {
      best2 = norm2(g);
      best = g;
    }
  };
  const double det = 1 - ab * ab;
  if (det > 1e-12) {
    const double s = (ab * wb - wa) / det, t = (wb - ab * wa) / det;
    if (std::abs(s) <= hi && std::abs(t) <= hj) consider(s, t);
  }
  for (double s : {-hi, hi}) consider(s, std::clamp(wb + s * ab, -hj, hj));
  for (double t : {-hj, hj}) consider(std::clamp(t * ab - wa, -hi, hi), t);
  return best;
}

}  // namespace

// Spherocylinders (random sizes and orientations, ~4 contacts each) through the shape force
// loop: in an open box the virial equals sum_i x_i F_i (Newton's third law, independent of
// how each pair's force is found); in open, periodic and Lees-Edwards boxes the contact fabric
// (sum of n n) equals a sum over all pairs of the unit gaps between their axes' closest points.
TEST(Virial, CapsulesVirialAndFabricMatchPairSums) {
  const Material m{"m", 1395, 1e7, 0.3};
  const auto pairs = hooke_table(m, 6e5, 0.3);
  Domain open;
  open.lo = {0, 0, 0};
  open.hi = {0.06, 0.04, 0.05};
  Domain periodic = open;
  periodic.periodic = {true, true, true};
  for (const Domain& d : {open, periodic, sheared_box(0.0217)}) {
    ParticleStore p;
    p.enable_shapes();
    std::mt19937_64 g(9);
    std::uniform_real_distribution<double> u(0, 1);
    const Vec3 L = d.length();
    for (int k = 0; k < 320; ++k) {
      const double r = 0.001 + 0.001 * u(g), h = 0.002 + 0.004 * u(g);
      const std::size_t i =
          p.add_sphere(k + 1, 0, r + h, 1395, {u(g) * L.x, u(g) * L.y, u(g) * L.z},
                       {u(g) - 0.5, u(g) - 0.5, u(g) - 0.5});
      p.shape()[i] = static_cast<std::int32_t>(ShapeCode::Spherocylinder);
      p.half_length()[i] = h;
      const Vec3 axis = normalized(Vec3{u(g) - 0.5, u(g) - 0.5, u(g) - 0.5});
      p.orientation()[i] = quat_from_axis_angle(axis, 2 * std::numbers::pi * u(g));
      p.mass()[i] = 1e-4;
    }
    VerletList list;
    list.build(d, p.x(), p.radius(), p.size(), 0.001);
    std::vector<Mat3> rows(p.size()), normals(p.size());
    contact::ContactSink sink;
    sink.rows = rows.data();
    sink.normals = normals.data();
    const auto touching = contact::compute_shape_pair_forces(p, d, list, pairs, 1e-6, &sink);
    ASSERT_GT(touching, 200);
    Mat3 w, nn;
    for (std::size_t i = 0; i < p.size(); ++i) {
      w = w + rows[i];
      nn = nn + normals[i];
    }
    Mat3 ref_nn;
    std::int64_t count = 0;
    const Vec3* x = p.x();
    for (std::size_t i = 0; i < p.size(); ++i)
      for (std::size_t j = i + 1; j < p.size(); ++j) {
        const double hi = p.half_length()[i], hj = p.half_length()[j];
        const Vec3 xj = x[i] - d.delta(x[i], x[j]);  // the image of j nearest to i
        const Vec3 gap = segment_gap(x[i], contact::capsule_axis(p.orientation()[i]), hi, xj,
                                     contact::capsule_axis(p.orientation()[j]), hj);
        const double reach = p.radius()[i] - hi + p.radius()[j] - hj;
        if (norm2(gap) >= reach * reach) continue;
        ++count;
        const Vec3 n = (1.0 / norm(gap)) * gap;
        ref_nn = ref_nn + outer(n, n);
      }
    EXPECT_EQ(touching, count);
    // The loop's narrow phase finds the same closest points by another route: round-off of
    // order 1e-12 in each unit normal (near-parallel axes amplify it), summed over ~500 pairs.
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) EXPECT_NEAR(nn.a[a][b], ref_nn.a[a][b], 1e-8) << a << b;
    if (!d.periodic[0]) {
      Mat3 ref;
      for (std::size_t i = 0; i < p.size(); ++i) ref = ref + outer(x[i], p.f()[i]);
      // As OpenBoxEqualsSumOfPositionTimesForce: cancelling terms, round-off ~1e-14 relative.
      expect_virial_near(w, ref, 1e-10);
    }
  }
}
