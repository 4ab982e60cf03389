// SPDX-License-Identifier: GPL-3.0-or-later
// Outlets: grains whose centre enters an outlet region leave the run; the tallies, the mass
// balance, the contact histories of the grains that stay, the series and the case file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

#include "boundaries/fill.hpp"
#include "case_builder.hpp"
#include "contact/geometry/capsule.hpp"
#include "core/error.hpp"
#include "neighbor/verlet_list.hpp"
#include "simulation/simulation.hpp"
#include "state_compare.hpp"
#include "temp_dir.hpp"

using namespace gf;

namespace {

double total_mass(const ParticleStore& p) {
  double m = 0;
  for (std::size_t i = 0; i < p.size(); ++i) m += p.mass()[i];
  return m;
}

/// 3D: 150 spheres fall through a sieve of fixed spheres (gaps of one grain diameter) into two
/// outlets below it, the floor's left and right halves; one fixed sphere sits inside the left
/// outlet (fixed grains stay).
config::Case sieve_case() {
  auto c = test::base_case(2e-5, 1.0, {0, 0, -0.03}, {0.05, 0.05, 0.1});
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin",
                    {{"restitution", 0.5}, {"friction", 0.5}});
  auto& f = test::add_box_fill(c, "glass", 0.0015, 0.0025, {0, 0, 0.01}, {0.05, 0.05, 0.08},
                               config::Fill::Lattice::Random);
  f.count = 150;
  f.seed = 5;
  test::add_fixed_sphere_layer(c, "glass", 0.002, 0.01, 0, 0.05, 0, 0.05, 0.0);
  auto& lone = c.particles.back().explicit_particles->positions;
  lone.push_back({0.01, 0.01, -0.02});  // inside the left outlet
  test::add_box(c, "box", {0, 0, -0.03}, {0.05, 0.05, 0.1}, {"zmin", "zmax"}, "glass");
  test::add_outlet(c, "left", test::box_region({0, 0, -0.03}, {0.025, 0.05, -0.01}));
  test::add_outlet(c, "right", test::box_region({0.025, 0, -0.03}, {0.05, 0.05, -0.01}));
  return c;
}

}  // namespace

TEST(Outlets, TakeTheGrainsThatFallInAndKeepTheMassBalance) {
  const auto cfg = sieve_case();
  Simulation sim(cfg);
  const std::size_t n0 = sim.particles().size();
  const double m0 = total_mass(sim.particles());
  std::set<std::int64_t> ids0(sim.particles().id(), sim.particles().id() + n0);
  ASSERT_EQ(sim.outlet_tallies().size(), 2u);
  EXPECT_EQ(sim.outlet_tallies()[0].count + sim.outlet_tallies()[1].count, 0);
  for (int s = 0; s < 9000; ++s) sim.step();  // 0.18 s: most grains have fallen through
  const auto& p = sim.particles();
  const auto t = sim.outlet_tallies();
  const std::int64_t taken = t[0].count + t[1].count;
  // Both halves take grains, and every grain taken left the store: the count and the mass add up
  // (the mass to rounding: a sum of 150 positive terms in another order).
  EXPECT_GT(t[0].count, 10);
  EXPECT_GT(t[1].count, 10);
  EXPECT_EQ(static_cast<std::int64_t>(p.size()) + taken, static_cast<std::int64_t>(n0));
  EXPECT_NEAR(total_mass(p) + t[0].mass + t[1].mass, m0, 1e-13 * m0);
  // The grains left are grains of the start, each once; the fixed one in the outlet is one.
  std::set<std::int64_t> ids(p.id(), p.id() + p.size());
  EXPECT_EQ(ids.size(), p.size());
  EXPECT_TRUE(std::includes(ids0.begin(), ids0.end(), ids.begin(), ids.end()));
  bool lone_fixed_kept = false;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.fixed()[i] != 0 && p.x()[i].z < -0.01) lone_fixed_kept = true;
  EXPECT_TRUE(lone_fixed_kept);
  // The series read the tallies.
  EXPECT_EQ(sim.quantity("outlet_count.left"), static_cast<double>(t[0].count));
  EXPECT_EQ(sim.quantity("outlet_mass.right"), t[1].mass);
  EXPECT_EQ(sim.quantity("particle_count"), static_cast<double>(p.size()));
  // Nothing is lost on the way: no free grain below the sieve is further down than the outlets'
  // top by more than it can fall between two list builds (taken at the next one).
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.fixed()[i] != 0) continue;
    EXPECT_GT(p.x()[i].z, -0.013) << "grain " << p.id()[i];
  }
}

TEST(Outlets, GrainsInsideAtTheStartLeaveAtOnce) {
  auto cfg = sieve_case();
  cfg.outlets[0].region.min.z = -0.03;
  cfg.outlets[0].region.max = {0.05, 0.05, 0.1};  // the left outlet holds the whole box
  Simulation sim(cfg);
  // Only the fixed grains are left: 25 in the sieve and the one below it.
  EXPECT_EQ(sim.particles().size(), 26u);
  EXPECT_EQ(sim.outlet_tallies()[0].count, 150);
  EXPECT_EQ(sim.outlet_tallies()[1].count, 0);
  for (int s = 0; s < 10; ++s) sim.step();
  EXPECT_EQ(sim.particles().size(), 26u);
}

TEST(Outlets, TwoDimensionalCircleRegion) {
  // 2D: disks on a line fall under gravity (-y) into a circular outlet around one of them.
  auto c = test::base_case(1e-5, 1.0, {0, 0, 0}, {0.1, 0.1, 0});
  c.dimension = 2;
  c.gravity = {0, -9.81, 0};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hooke", {{"restitution", 0.5}, {"stiffness", 1e3}});
  test::add_disks(c, "glass", 0.002, {{0.02, 0.05, 0}, {0.05, 0.05, 0}, {0.08, 0.05, 0}});
  config::Region hole;
  hole.kind = config::Region::Kind::Cylinder;
  hole.center = {0.05, 0.03, 0};
  hole.radius = 0.005;
  test::add_outlet(c, "hole", hole);
  Simulation sim(c);
  // The middle disk falls 0.015 m in sqrt(2 x 0.015 / 9.81) = 0.055 s; the others pass by.
  for (int s = 0; s < 7000; ++s) sim.step();
  ASSERT_EQ(sim.particles().size(), 2u);
  EXPECT_EQ(sim.outlet_tallies()[0].count, 1);
  for (std::size_t i = 0; i < 2; ++i) EXPECT_NE(sim.particles().x()[i].x, 0.05);
}

// With a reinsert region the grains come back instead: none is lost, each lands at rest where it
// fits (a grain put onto another would be shot out at a speed far above the free fall's).
TEST(Outlets, ReinsertPutsTheGrainsBackAtRestWhereTheyFit) {
  auto cfg = sieve_case();
  cfg.outlets[1].reinsert = test::box_region({0, 0, 0.06}, {0.05, 0.05, 0.09});
  Simulation sim(cfg);
  const std::size_t n0 = sim.particles().size();
  double v_max = 0;
  for (int s = 0; s < 12000; ++s) {
    sim.step();
    for (std::size_t i = 0; i < sim.particles().size(); ++i)
      v_max = std::max(v_max, norm(sim.particles().v()[i]));
  }
  const auto t = sim.outlet_tallies();
  EXPECT_GT(t[0].count, 10);  // removed
  EXPECT_GT(t[1].count, 10);  // put back
  EXPECT_EQ(sim.particles().size() + static_cast<std::size_t>(t[0].count), n0);
  // Free fall from the top of the box (0.1 m) to the outlets' top (-0.01 m): 1.47 m/s.
  EXPECT_LT(v_max, 1.6);
  EXPECT_EQ(sim.quantity("particle_count"), static_cast<double>(sim.particles().size()));
}

// A grain put back starts its contacts afresh: one that slid down a wall into the outlet (its
// tangential spring stretched to the Coulomb limit) and lands against the same wall again must not
// carry the old spring (the list build carries histories by grain and wall).
TEST(Outlets, ReinsertedGrainsForgetTheirContacts) {
  auto c = test::base_case(2e-5, 1.0, {0, 0, 0}, {0.03, 0.03, 0.12});
  c.gravity = {-2, 0, -9.81};  // pressed against the wall x = 0 while it falls
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin",
                    {{"restitution", 0.5}, {"friction", 0.1}});
  test::add_spheres(c, "glass", 0.004, {{0.004, 0.015, 0.05}});
  test::add_plane(c, "wall", {0, 0, 0}, {1, 0, 0}, "glass");
  // Put back with centres at x in [0.0037, 0.0039]: cutting into the wall.
  test::add_outlet(c, "pit", test::box_region({0, 0, 0}, {0.03, 0.03, 0.02})).reinsert =
      test::box_region({-0.0003, 0.010, 0.09}, {0.0079, 0.020, 0.11});
  Simulation sim(c);
  double h_before = 0;
  while (sim.outlet_tallies()[0].count == 0 && sim.step_count() < 20000) {
    if (sim.particles().x()[0].z < 0.03)  // sliding, its spring at the Coulomb limit
      for (const Vec3& h : sim.wall_list().history()) h_before = std::max(h_before, norm(h));
    sim.step();
  }
  ASSERT_EQ(sim.outlet_tallies()[0].count, 1);
  EXPECT_GT(sim.particles().x()[0].z, 0.09);
  EXPECT_GT(h_before, 1e-7);  // the stretched spring of the slide
  double h_after = 0;
  for (const Vec3& h : sim.wall_list().history()) h_after = std::max(h_after, norm(h));
  EXPECT_LT(h_after, 1e-3 * h_before);
}

TEST(Outlets, ReinsertWithoutRoomStopsTheRun) {
  // 2D: three disks fall together into the outlet; its reinsert region holds one disk.
  auto c = test::base_case(1e-5, 1.0, {0, 0, 0}, {0.1, 0.1, 0});
  c.dimension = 2;
  c.gravity = {0, -9.81, 0};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hooke", {{"restitution", 0.5}, {"stiffness", 1e3}});
  test::add_disks(c, "glass", 0.002, {{0.02, 0.03, 0}, {0.05, 0.03, 0}, {0.08, 0.03, 0}});
  test::add_outlet(c, "floor", test::box_region({0, 0, 0}, {0.1, 0.02, 0})).reinsert =
      test::box_region({0.045, 0.09, 0}, {0.0495, 0.0945, 0});
  Simulation sim(c);
  try {
    for (int s = 0; s < 10000; ++s) sim.step();
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("outlet 'floor' found no free place"), std::string::npos)
        << e.what();
  }
}

// The contact histories of the grains that stay are carried through a removal: a list built
// after the store lost grains and gained others (VerletList::sort_and_build with the grains'
// previous indices, -1 for the new ones) holds, for every pair of grains left, the history the
// previous list held for it, and none for a pair with a new grain.
TEST(Outlets, HistoriesOfTheGrainsLeftAreCarried) {
  ParticleStore p;
  Rng rng(7);
  const int n = 400;
  for (int i = 0; i < n; ++i)
    p.add_sphere(i, 0, 0.5 + 0.1 * rng.uniform(), 1000,
                 {7 * rng.uniform(), 7 * rng.uniform(), 7 * rng.uniform()});
  Domain d;
  d.lo = {0, 0, 0};
  d.hi = {7, 7, 7};
  d.periodic = {true, false, true};
  const double skin = 0.2;
  VerletList list;
  list.sort_and_build(p, d, skin);
  // A distinct history per pair: +v(a, b) seen from the grain of smaller id, -v from the other.
  auto value = [](std::int64_t row_id, std::int64_t col_id) {
    const double v =
        static_cast<double>(std::min(row_id, col_id) * 1000 + std::max(row_id, col_id));
    return row_id < col_id ? Vec3{v, 1, 2} : Vec3{-v, -1, -2};
  };
  auto for_entries = [&](auto&& visit) {
    const auto off = list.offsets();
    const auto nb = list.neighbors();
    for (std::size_t i = 0; i + 1 < off.size(); ++i)
      for (auto k = off[i]; k < off[i + 1]; ++k)
        visit(p.id()[i], p.id()[nb[static_cast<std::size_t>(k)]], static_cast<std::size_t>(k));
  };
  std::set<std::pair<std::int64_t, std::int64_t>> had;
  for_entries([&](std::int64_t a, std::int64_t b, std::size_t k) {
    list.history()[k] = value(a, b);
    had.insert({std::min(a, b), std::max(a, b)});
  });
  ASSERT_GT(had.size(), 500u);
  // Remove every third grain (by position in the store), as Simulation does: the grains left
  // first in their order, then a shrink.
  std::vector<std::int64_t> order, gone;
  for (std::size_t i = 0; i < p.size(); ++i)
    (i % 3 == 1 ? gone : order).push_back(static_cast<std::int64_t>(i));
  const std::size_t left = order.size();
  std::set<std::int64_t> gone_ids;
  for (auto i : gone) gone_ids.insert(p.id()[i]);
  order.insert(order.end(), gone.begin(), gone.end());
  p.permute(order);
  p.resize(left);
  order.resize(left);
  // And 60 grains new since the last build (an inlet's): no index then, no history now.
  for (int k = 0; k < 60; ++k) {
    p.add_sphere(1000 + k, 0, 0.5, 1000, {7 * rng.uniform(), 7 * rng.uniform(), 7 * rng.uniform()});
    order.push_back(-1);
  }
  list.sort_and_build(p, d, skin, {}, order);
  std::size_t carried = 0, with_new = 0;
  for_entries([&](std::int64_t a, std::int64_t b, std::size_t k) {
    ASSERT_FALSE(gone_ids.count(a) || gone_ids.count(b));
    with_new += a >= 1000 || b >= 1000;
    if (had.count({std::min(a, b), std::max(a, b)})) {
      EXPECT_EQ(list.history()[k], value(a, b)) << a << " " << b;
      ++carried;
    } else {
      EXPECT_EQ(list.history()[k], Vec3{});
    }
  });
  // (the positions did not change: every pair of grains left was in the list before)
  std::size_t expected = 0;
  for (const auto& [a, b] : had) expected += gone_ids.count(a) || gone_ids.count(b) ? 0 : 1;
  EXPECT_EQ(carried, expected);
  EXPECT_GT(carried, 200u);
  EXPECT_GT(with_new, 20u);
}

TEST(Outlets, TheCudaBackEndRefusesThem) {
  // It keeps every grain: it refuses the case, naming the outlet.
  EXPECT_NE(Simulation(sieve_case()).device_unsupported().find("outlets ('left'"),
            std::string::npos);
}

// A run continued from a checkpoint written between removals takes the same grains at the same
// steps as the uninterrupted run: the same state bit for bit, and the same tallies.
TEST(RestartOutlets, ContinueBitIdentically) {
  auto cfg = sieve_case();
  // The right half's grains come back (random places: the generator's state).
  cfg.outlets[1].reinsert = test::box_region({0, 0, 0.06}, {0.05, 0.05, 0.09});
  test::TempDir dir;
  const auto file = dir.path() / "outlets.h5";
  Simulation a(cfg);
  for (int s = 0; s < 5000; ++s) a.step();
  const auto before = a.outlet_tallies()[0].count + a.outlet_tallies()[1].count;
  EXPECT_GT(before, 0);
  a.save_checkpoint(file);
  for (int s = 0; s < 4000; ++s) a.step();
  Simulation b(cfg);
  b.load_checkpoint(file);
  for (int s = 0; s < 4000; ++s) b.step();
  EXPECT_GT(a.outlet_tallies()[0].count + a.outlet_tallies()[1].count, before + 10);
  test::expect_same_state(a, b);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(a.outlet_tallies()[k].count, b.outlet_tallies()[k].count);
    EXPECT_EQ(a.outlet_tallies()[k].mass, b.outlet_tallies()[k].mass);
  }
}

namespace {

/// 3D: an inlet pours spheres (r 1.5-2.5 mm; with `rods`, spherocylinders of aspect ratio 3) at
/// 2000 per second from a layer at the top of an open box onto its floor; optionally an outlet
/// in the floor's corner takes those that roll in.
config::Case pour_case(bool outlet, bool rods = false) {
  auto c = test::base_case(2e-5, 1.0, {0, 0, 0}, {0.05, 0.05, 0.12});
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hertz_mindlin",
                    {{"restitution", 0.5}, {"friction", 0.5}});
  config::ParticleGroup g;
  g.material = "glass";
  g.radius.kind = config::SizeDistribution::Kind::Uniform;
  g.radius.min = 0.0015;
  g.radius.max = 0.0025;
  if (rods) {
    g.shape = "spherocylinder";
    g.kind = config::Shape::Spherocylinder;
    g.radius.min = 0.001;
    g.radius.max = 0.0012;
    g.aspect_ratio = 3;
  }
  config::Inlet in;
  in.region = test::box_region({0, 0, 0.09}, {0.05, 0.05, 0.12});
  in.rate = 2000;
  in.velocity = {0, 0, -0.5};
  in.every = 0.01;
  in.stop = 0.3;
  g.inlet = in;
  c.particles.push_back(g);
  test::add_box(c, "box", {0, 0, 0}, {0.05, 0.05, 0.12}, {"zmax"}, "glass");
  if (outlet) {
    test::add_outlet(c, "corner", test::box_region({0, 0, 0}, {0.015, 0.015, 0.012}));
  }
  return c;
}

}  // namespace

// An inlet inserts its grains at the rate asked, in batches (a batch at t inserts those due by
// t + every), each grain where it overlaps no other, with new ids; it stops at `stop`.
TEST(Inlets, InsertAtTheRateWithoutOverlapsAndWithNewIds) {
  Simulation sim(pour_case(false));
  EXPECT_EQ(sim.particles().size(), 20u);  // the first batch, at t = 0: 2000/s x 0.01 s
  std::set<std::int64_t> ids;
  for (int s = 0; s < 20000; ++s) {  // 0.4 s
    const std::size_t before = sim.particles().size();
    sim.step();
    const auto& p = sim.particles();
    if (p.size() == before) continue;
    // A batch: at t = k every, 20 more grains (due by t + every), none overlapping any grain.
    EXPECT_EQ(p.size(), before + 20) << "t = " << sim.time();
    for (std::size_t i = 0; i < p.size(); ++i)
      for (std::size_t j = i + 1; j < p.size(); ++j) {
        if (p.x()[i].z < 0.09 || p.x()[j].z < 0.09) continue;  // (the new ones are up there)
        const double gap = norm(p.x()[i] - p.x()[j]) - p.radius()[i] - p.radius()[j];
        EXPECT_GT(gap, -1e-5) << "t = " << sim.time() << ", ids " << p.id()[i] << " " << p.id()[j];
      }
  }
  const auto& p = sim.particles();
  EXPECT_EQ(sim.inserted_grains(), 600);  // 2000/s x 0.3 s, then it stops
  ASSERT_EQ(p.size(), 600u);
  ids.insert(p.id(), p.id() + p.size());
  EXPECT_EQ(ids.size(), 600u);
  EXPECT_EQ(*ids.begin(), 1);
  EXPECT_EQ(*ids.rbegin(), 600);
  double z_max = 0;
  for (std::size_t i = 0; i < p.size(); ++i) z_max = std::max(z_max, p.x()[i].z);
  EXPECT_LT(z_max, 0.06);  // all have fallen onto the heap
  EXPECT_NE(sim.device_unsupported().find("inlet"), std::string::npos);
}

// Spherocylinders come in randomly oriented, placed by the sphere that holds any of them: no two
// overlap where they are inserted (distance of the axes against the sum of the cap radii).
TEST(Inlets, SpherocylindersComeInRandomlyOrientedAndApart) {
  Simulation sim(pour_case(false, true));
  const auto& p = sim.particles();
  ASSERT_TRUE(p.has_shapes());
  double min_gap = INFINITY, mean_axis_z = 0;
  int checked = 0;
  for (int s = 0; s < 2000; ++s) {  // 0.04 s: four batches after the first, still near the top
    const std::size_t before = p.size();
    sim.step();
    if (p.size() == before) continue;
    for (std::size_t i = before; i < p.size(); ++i) {
      const Vec3 ai = p.half_length()[i] * contact::capsule_axis(p.orientation()[i]);
      mean_axis_z += std::abs(contact::capsule_axis(p.orientation()[i]).z);
      ++checked;
      for (std::size_t j = 0; j < p.size(); ++j) {
        if (j == i) continue;
        const Vec3 aj = p.half_length()[j] * contact::capsule_axis(p.orientation()[j]);
        const auto c = contact::closest_points_segments(p.x()[i] - ai, p.x()[i] + ai, p.x()[j] - aj,
                                                        p.x()[j] + aj);
        const double caps = p.radius()[i] - p.half_length()[i] + p.radius()[j] - p.half_length()[j];
        min_gap = std::min(min_gap, std::sqrt(c.dist2) - caps);
      }
    }
  }
  EXPECT_EQ(sim.inserted_grains(), 100);  // 2000/s, batches at 0, 0.01, 0.02, 0.03, 0.04 s
  EXPECT_EQ(checked, 80);
  EXPECT_GT(min_gap, 0.0);
  // |axis . z| of uniformly random axes averages 1/2 (standard deviation of a mean of 80: 0.03).
  EXPECT_NEAR(mean_axis_z / checked, 0.5, 0.1);
}

// Inlet and outlet together: what came in is what is there plus what left, and a run continued
// from a checkpoint inserts and takes the same grains (ids, places: the generator's state).
TEST(RestartInlets, ContinueBitIdentically) {
  for (const bool rods : {false, true}) {
    SCOPED_TRACE(rods ? "spherocylinders" : "spheres");
    const auto cfg = pour_case(true, rods);
    test::TempDir dir;
    const auto file = dir.path() / "inlets.h5";
    Simulation a(cfg);
    for (int s = 0; s < 6000; ++s) a.step();
    a.save_checkpoint(file);
    for (int s = 0; s < 6000; ++s) a.step();
    Simulation b(cfg);
    b.load_checkpoint(file);
    for (int s = 0; s < 6000; ++s) b.step();
    test::expect_same_state(a, b);
    EXPECT_EQ(a.inserted_grains(), b.inserted_grains());
    EXPECT_EQ(a.outlet_tallies()[0].count, b.outlet_tallies()[0].count);
    EXPECT_GT(a.outlet_tallies()[0].count, 5);
    EXPECT_EQ(a.inserted_grains(),
              static_cast<std::int64_t>(a.particles().size()) + a.outlet_tallies()[0].count);
  }
}

// By mass: an inlet with mass_rate inserts grains until the mass inserted reaches the mass due by
// the end of each batch's interval; each batch overshoots by less than one grain, so after k
// batches the mass lies in [due, due + one grain), whatever the radii drawn. A continued run
// inserts what the uninterrupted one does (the mass inserted is in the checkpoint).
TEST(Inlets, MassRateInsertsTheMassDueWithinAGrain) {
  auto cfg = pour_case(true);
  auto& in = *cfg.particles[0].inlet;
  in.rate = 0;
  in.mass_rate = 0.1;  // kg/s: ~1000 grains of 1.5-2.5 mm a second
  const double m_max = 2500 * 4.0 / 3.0 * M_PI * std::pow(0.0025, 3);
  test::TempDir dir;
  const auto file = dir.path() / "mass_inlet.h5";
  Simulation a(cfg);
  for (int s = 1; s <= 12000; ++s) {  // 0.24 s: 24 batches
    a.step();
    if (s == 6000) a.save_checkpoint(file);
    if (s % 500 != 0) continue;
    // At t = k every the batch of [t, t + every) is in: the mass due by t + every.
    const double due = 0.1 * (a.time() + 0.01);
    double mass = 0;
    for (std::size_t i = 0; i < a.particles().size(); ++i) mass += a.particles().mass()[i];
    mass += a.outlet_tallies()[0].mass;
    EXPECT_GE(mass, due * (1 - 1e-9)) << "t = " << a.time();
    EXPECT_LT(mass, due + m_max) << "t = " << a.time();
  }
  // About the mean grain's worth: 0.1 kg/s over the 2500 kg/m^3 mean sphere of r in [1.5, 2.5] mm
  // (mean r^3 = (2.5^4 - 1.5^4) / (4 x 1) mm^3 = 8.5 mm^3): 1123 grains/s, 281 by t = 0.25 s.
  EXPECT_NEAR(static_cast<double>(a.inserted_grains()), 281, 40);
  Simulation b(cfg);
  b.load_checkpoint(file);
  for (int s = 6000; s < 12000; ++s) b.step();
  test::expect_same_state(a, b);
  EXPECT_EQ(a.inserted_grains(), b.inserted_grains());
}

namespace {

/// 2D: an inlet pours random convex polygons (5-8 vertices, elongation 1-1.6, equal-area radius
/// 1.5-2.5 mm) at 500 per second from a layer at the top of a box open above onto its floor.
config::Case polygon_pour_case() {
  auto c = test::base_case(2e-5, 1.0, {0, 0, 0}, {0.1, 0.12, 0});
  c.dimension = 2;
  c.domain.thickness = 0.004;
  c.gravity = {0, -9.81, 0};
  test::add_material(c, "glass", 2500, 1e7, 0.3);
  test::add_contact(c, "glass", "glass", "hooke",
                    {{"stiffness", 1e3}, {"restitution", 0.5}, {"friction", 0.5}});
  config::ParticleGroup g;
  g.material = "glass";
  g.shape = "polygon";
  g.kind = config::Shape::Polygon;
  g.polygon.kind = config::PolygonSpec::Kind::Random;
  g.polygon.min_elongation = 1.0;
  g.polygon.max_elongation = 1.6;
  g.radius.kind = config::SizeDistribution::Kind::Uniform;
  g.radius.min = 0.0015;
  g.radius.max = 0.0025;
  config::Inlet in;
  in.region = test::box_region({0, 0.09, 0}, {0.1, 0.12, 0});
  in.rate = 500;
  in.velocity = {0, -0.5, 0};
  g.inlet = in;
  c.particles.push_back(g);
  test::add_plane(c, "floor", {0, 0, 0}, {0, 1, 0}, "glass");
  test::add_plane(c, "left", {0, 0, 0}, {1, 0, 0}, "glass");
  test::add_plane(c, "right", {0.1, 0, 0}, {-1, 0, 0}, "glass");
  return c;
}

}  // namespace

// Polygons come in at the rate, randomly turned, apart (their circumcircles: the placement),
// each batch with new random outlines; a continued run inserts the same outlines in the same
// places (the batch count seeds them; the outline table is in the checkpoint).
TEST(Inlets, PolygonsComeInWithNewOutlinesEveryBatch) {
  const auto cfg = polygon_pour_case();
  test::TempDir dir;
  const auto file = dir.path() / "polygon_inlet.h5";
  Simulation a(cfg);
  const auto& p = a.particles();
  ASSERT_TRUE(p.has_shapes());
  double min_gap = INFINITY;
  std::int64_t last_id = 0;  // the new grains of a step: ids above (the list build re-orders)
  for (int s = 1; s <= 10000; ++s) {  // 0.2 s
    a.step();
    if (s == 5000) a.save_checkpoint(file);
    std::int64_t top = last_id;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.id()[i] <= last_id) continue;
      top = std::max(top, p.id()[i]);
      for (std::size_t j = 0; j < p.size(); ++j)
        if (j != i)
          min_gap = std::min(min_gap, norm(p.x()[i] - p.x()[j]) - p.radius()[i] - p.radius()[j]);
    }
    last_id = top;
  }
  // 500/s: 5 a batch at 0, 0.01, ..., 0.2 s (the batch at 0.2 s inserts those due by 0.21 s).
  EXPECT_EQ(a.inserted_grains(), 105);
  EXPECT_EQ(p.size(), 105u);
  EXPECT_GT(min_gap, 0.0);
  // Random outlines: every grain its own, across batches too.
  std::set<std::vector<double>> outlines;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& shape = p.polygons()[static_cast<std::size_t>(p.polygon()[i])];
    std::vector<double> key;
    for (int k = 0; k < shape.body.n; ++k) key.push_back(shape.body.v[k].x);
    outlines.insert(key);
  }
  EXPECT_EQ(outlines.size(), 105u);
  Simulation b(cfg);
  b.load_checkpoint(file);
  for (int s = 5000; s < 10000; ++s) b.step();
  test::expect_same_state(a, b);
  ASSERT_EQ(a.particles().polygons().size(), b.particles().polygons().size());
}

// An outlet that takes the polygons an inlet pours frees their outlines: the table is compacted
// once most of it is unused (each grain keeps its own outline, renumbered), so a long run with
// polygons coming and going holds a table about the size of its grains, not of all it ever made;
// a continued run compacts at the same builds and keeps the bits.
TEST(Inlets, OutletsFreeThePolygonOutlines) {
  auto cfg = polygon_pour_case();
  cfg.particles[0].inlet->rate = 2000;
  test::add_outlet(cfg, "low", test::box_region({0, 0, 0}, {0.1, 0.03, 0}));
  test::TempDir dir;
  const auto file = dir.path() / "compact.h5";
  Simulation a(cfg);
  const auto& p = a.particles();
  auto outline_of = [&](std::size_t i) {
    const auto& shape = p.polygons()[static_cast<std::size_t>(p.polygon()[i])];
    std::vector<double> key;
    for (int k = 0; k < shape.body.n; ++k)
      key.insert(key.end(), {shape.body.v[k].x, shape.body.v[k].y});
    return key;
  };
  std::map<std::int64_t, std::vector<double>> before;
  std::size_t largest = 0;
  for (int s = 1; s <= 20000; ++s) {  // 0.4 s
    a.step();
    largest = std::max(largest, p.polygons().size());
    if (s == 10000) a.save_checkpoint(file);
    if (s == 18000)
      for (std::size_t i = 0; i < p.size(); ++i) before[p.id()[i]] = outline_of(i);
  }
  std::printf("%lld polygons inserted, %zu in the box, table %zu (largest %zu)\n",
              static_cast<long long>(a.inserted_grains()), p.size(), p.polygons().size(), largest);
  EXPECT_GT(a.inserted_grains(), 300);
  EXPECT_LT(p.size(), 100u);
  EXPECT_LT(p.polygons().size(), static_cast<std::size_t>(a.inserted_grains()) / 2)
      << "the table grew with every grain ever inserted";
  EXPECT_LE(largest, 256u + 2 * 100u);
  int kept = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (auto it = before.find(p.id()[i]); it != before.end()) {
      ++kept;
      EXPECT_EQ(outline_of(i), it->second) << "grain " << p.id()[i];
    }
  EXPECT_GT(kept, 5);
  Simulation b(cfg);
  b.load_checkpoint(file);
  for (int s = 10000; s < 20000; ++s) b.step();
  test::expect_same_state(a, b);
  EXPECT_EQ(a.particles().polygons().size(), b.particles().polygons().size());
}
