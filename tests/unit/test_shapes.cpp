// SPDX-License-Identifier: GPL-3.0-or-later
// Non-spherical grains through the whole simulation: restart continues bit-identically (shape
// fields, polygon table, two wall slots per capsule, Gear derivatives), results are bit-identical
// with 1 and 2 threads, fills give non-overlapping grains with the requested orientations.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

#include "case_builder.hpp"
#include "contact/shape_forces.hpp"
#include "core/exec.hpp"
#include "io/input/parse_case.hpp"
#include "simulation/simulation.hpp"
#include "state_compare.hpp"

using namespace gf;

namespace {

/// Spherocylinders (aspect ratio 3) poured into a box around a cylindrical post.
config::Case rods_case(std::int64_t count, double size = 0.06,
                       config::Fill::Lattice lattice = config::Fill::Lattice::Random) {
  const Vec3 hi{size, size, 2 * size};
  auto c = test::base_case(1e-5, 1.0, {0, 0, 0}, hi);
  c.gravity = {0, 0, -9.81};
  test::add_material(c, "pom", 1400, 1e7, 0.3);
  test::add_contact(c, "pom", "pom", "hertz_mindlin",
                    {{"restitution", 0.5}, {"friction", 0.4}, {"rolling_friction", 0.01}});
  auto& f = test::add_capsule_fill(c, "pom", 0.0015, 3.0, {0, 0, 0}, hi, lattice);
  f.count = count;
  f.seed = 5;
  f.velocity_jitter = 0.3;
  test::add_box(c, "box", {0, 0, 0}, hi, {"zmax"}, "pom");
  config::Wall post;
  post.name = "post";
  post.kind = config::Wall::Kind::Cylinder;
  post.center = {0.5 * size, 0.5 * size, 0};
  post.axis = {0, 0, 1};
  post.radius = 0.004;
  post.inside = false;
  post.material = "pom";
  c.walls.push_back(post);
  return c;
}

/// Makes the last group random irregular polygons of 4-9 vertices and elongations 1 to `elong`.
void make_random_polygons(config::Case& c, double elong) {
  auto& g = c.particles.back();
  g.kind = config::Shape::Polygon;
  g.shape = "polygon";
  g.polygon.kind = config::PolygonSpec::Kind::Random;
  g.polygon.min_vertices = 4;
  g.polygon.max_vertices = 9;
  g.polygon.min_elongation = 1.0;
  g.polygon.max_elongation = elong;
}

/// Random irregular polygons falling into a 2D box, Gear integrator.
config::Case polygons_case() {
  auto c = test::base_case(5e-6, 1.0, {0, 0, 0}, {0.15, 0.4, 0});
  c.dimension = 2;
  c.domain.thickness = 0.01;
  c.gravity = {0, -9.81, 0};
  c.integrator = "gear5";
  test::add_material(c, "stone", 2600, 1e7, 0.3);
  test::add_contact(c, "stone", "stone", "hooke",
                    {{"restitution", 0.5}, {"friction", 0.5}, {"stiffness", 1e5}});
  auto& f = test::add_box_fill(c, "stone", 0.0015, 0.0025, {0, 0, 0}, {0.15, 0.4, 0},
                               config::Fill::Lattice::Random);
  f.count = 150;
  f.seed = 9;
  f.velocity = {0, -1.0, 0};
  f.velocity_jitter = 0.8;
  make_random_polygons(c, 2.0);
  test::add_box(c, "box", {0, 0, 0}, {0.15, 0.4, 0}, {"ymax"}, "stone");
  return c;
}

/// 2D disks and random polygons together in a turning drum (a circular wall), velocity Verlet:
/// disk-polygon contacts and polygon-circle wall contacts.
config::Case mixed_drum_case() {
  auto c = test::base_case(5e-6, 1.0, {0, 0, 0}, {0.15, 0.15, 0});
  c.dimension = 2;
  c.domain.thickness = 0.01;
  c.gravity = {0, -9.81, 0};
  test::add_material(c, "stone", 2600, 1e7, 0.3);
  test::add_contact(c, "stone", "stone", "hooke",
                    {{"restitution", 0.5}, {"friction", 0.5}, {"stiffness", 1e5}});
  // (boxes inside the drum: polygons below, near the drum's bottom, disks above)
  auto& f = test::add_box_fill(c, "stone", 0.0015, 0.0025, {0.035, 0.02, 0}, {0.115, 0.065, 0},
                               config::Fill::Lattice::Random);
  f.count = 12;
  f.velocity = {0, -1.0, 0};
  f.seed = 9;
  f.velocity_jitter = 0.5;
  make_random_polygons(c, 1.5);
  auto& fd = test::add_box_fill(c, "stone", 0.0015, 0.0025, {0.03, 0.067, 0}, {0.12, 0.12, 0},
                                config::Fill::Lattice::Random);
  fd.count = 60;
  fd.velocity = {0, -1.0, 0};
  fd.seed = 10;
  fd.velocity_jitter = 0.5;
  c.particles.back().kind = config::Shape::Disk;
  c.particles.back().shape = "disk";
  test::add_cylinder(c, "drum", {0.075, 0.075, 0}, {0, 0, 1}, 0.07, true, "stone", 3);
  return c;
}

void check_restart(const config::Case& cfg, int steps, const char* tag) {
  const auto file = std::filesystem::temp_directory_path() /
                    (std::string("gf_restart_") + tag + "_" + std::to_string(::getpid()) + ".h5");
  Simulation a(cfg);
  for (int s = 0; s < steps; ++s) a.step();
  a.save_checkpoint(file);
  std::int64_t contact_steps = 0;  // contacts summed over the steps after the checkpoint
  for (int s = 0; s < steps; ++s) {
    a.step();
    contact_steps += a.n_contacts() + a.n_wall_contacts();
  }
  Simulation b(cfg);
  b.load_checkpoint(file);
  for (int s = 0; s < steps; ++s) b.step();
  EXPECT_GT(contact_steps, 1000);
  test::expect_same_state(a, b);
  std::filesystem::remove(file);
}

/// Smallest gap between the shapes of two grains over all pairs (negative: overlap), brute force.
double min_pair_gap(const Simulation& sim) {
  const auto& p = sim.particles();
  const contact::ShapeView s(p);
  double worst = 1e300;
  for (std::size_t i = 0; i < p.size(); ++i) {
    ConvexPolygon poly_i;
    if (s.code(static_cast<std::int64_t>(i)) == ShapeCode::Polygon)
      poly_i = s.world_polygon(static_cast<std::int64_t>(i), p.x()[i]);
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      contact::ShapeGeometry g;
      if (contact::shape_pair_geometry(s, static_cast<std::int64_t>(i),
                                       static_cast<std::int64_t>(j), p.x()[i], p.x()[j], &poly_i,
                                       g))
        worst = std::min(worst, -g.overlap);
      else
        worst = std::min(worst, 0.0 + 1e-300);
    }
  }
  return worst;
}

/// 2D disks under a servo lid (span: the side walls), the lid switching to a prescribed
/// translation halfway: servo state and the translation start go through checkpoints.
config::Case servo_case() {
  auto c = test::base_case(5e-6, 1.0, {0, 0, 0}, {0.05, 0.1, 0});
  c.dimension = 2;
  c.domain.thickness = 0.01;
  c.gravity = {0, -9.81, 0};
  test::add_material(c, "glass", 2500, 1e8, 0.3);
  test::add_contact(c, "glass", "glass", "hooke",
                    {{"restitution", 0.3}, {"friction", 0.5}, {"stiffness", 1e6}});
  auto& f = test::add_box_fill(c, "glass", 0.0025, 0.0035, {0, 0, 0}, {0.05, 0.06, 0},
                               config::Fill::Lattice::Random);
  f.count = 60;
  f.seed = 3;
  c.particles.back().kind = config::Shape::Disk;
  test::add_plane(c, "floor", {0, 0, 0}, {0, 1, 0}, "glass");
  test::add_plane(c, "left", {0, 0, 0}, {1, 0, 0}, "glass");
  test::add_plane(c, "right", {0.05, 0, 0}, {-1, 0, 0}, "glass");
  test::add_plane(c, "lid", {0, 0.065, 0}, {0, -1, 0}, "glass");
  config::Servo servo;
  servo.pressure = 1e4;
  servo.max_velocity = 0.5;
  servo.spans = {{"left", "right"}};
  servo.until = 0.02;
  c.walls.back().servo = servo;
  c.walls.back().motion.velocity = {0, -0.01, 0};
  c.walls.back().motion.start = 0.02;
  return c;
}

}  // namespace

TEST(RestartShapes, ServoWallsContinueBitIdentically) {
  check_restart(servo_case(), 3000, "servo");
}

TEST(RestartShapes, CapsulesContinueBitIdentically) {
  check_restart(rods_case(300), 1500, "rods");
}

TEST(RestartShapes, PolygonsWithGearContinueBitIdentically) {
  check_restart(polygons_case(), 4000, "polygons");
}

TEST(RestartShapes, DisksAndPolygonsInADrumContinueBitIdentically) {
  check_restart(mixed_drum_case(), 8000, "mixed_drum");
  // The run has the new kinds of contact: disks touching polygons, polygons touching the drum
  // (counted at ten instants of the second half of its 0.08 s).
  Simulation sim(mixed_drum_case());
  int mixed = 0, on_drum = 0;
  for (int s = 1; s <= 16000; ++s) {
    sim.step();
    if (s <= 8000 || s % 800 != 0) continue;
    const auto& p = sim.particles();
    const contact::ShapeView v(p);
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (v.code(static_cast<std::int64_t>(i)) != ShapeCode::Polygon) continue;
      const ConvexPolygon poly = v.world_polygon(static_cast<std::int64_t>(i), p.x()[i]);
      contact::PolygonOverlap o;
      on_drum += contact::polygon_circle_wall_overlap(poly, {0.075, 0.075}, 0.07, true, o);
      for (std::size_t j = 0; j < p.size(); ++j)
        mixed += v.code(static_cast<std::int64_t>(j)) == ShapeCode::Disk &&
                 contact::disk_polygon_overlap({p.x()[j].x, p.x()[j].y}, p.radius()[j], poly, o);
    }
  }
  std::printf("at ten instants: %d disk-polygon contacts, %d polygon-drum contacts\n", mixed,
              on_drum);
  EXPECT_GT(mixed, 20);
  EXPECT_GT(on_drum, 10);
}

// The narrow phase of a disk and a polygon in both orders of the pair (the disk grain i, then
// grain j): the same overlap and contact point, opposite normals pointing from j to i, and the
// point on the line through the disk's centre along the normal (no torque on the disk from the
// normal force), also when the overlap is lopsided (a corner pressed in off the disk's centre).
TEST(ShapePairs, DiskAndPolygonInBothOrders) {
  auto c = test::base_case(5e-6, 1.0, {0, 0, 0}, {0.1, 0.1, 0});
  c.dimension = 2;
  c.domain.thickness = 0.01;
  test::add_material(c, "stone", 2600, 1e7, 0.3);
  test::add_contact(c, "stone", "stone", "hooke", {{"restitution", 0.5}, {"stiffness", 1e5}});
  test::add_disks(c, "stone", 0.004, {{0.02, 0.05, 0}});
  test::add_polygons(c, "stone", 0.005, 5, {{0.07, 0.05, 0}}, {turn_about_z(Quat{}, 0.3)});
  const Simulation sim(c);
  const auto& p = sim.particles();
  const contact::ShapeView s(p);
  const std::int64_t d = s.code(0) == ShapeCode::Disk ? 0 : 1, q = 1 - d;
  const Vec3 xq{0.07, 0.05, 0};
  const ConvexPolygon poly = s.world_polygon(q, xq);
  int lopsided = 0;
  for (int k = 0; k < 72; ++k) {
    // The disk's centre on a circle about the polygon's, a little nearer than touching a vertex.
    const double a = 0.0873 * k, reach = 0.004 + 0.0049;
    const Vec3 xd = xq + Vec3{reach * std::cos(a), reach * std::sin(a), 0};
    contact::ShapeGeometry g1, g2;
    const bool t1 = contact::shape_pair_geometry(s, d, q, xd, xq, nullptr, g1);
    const bool t2 = contact::shape_pair_geometry(s, q, d, xq, xd, &poly, g2);
    ASSERT_EQ(t1, t2) << k;
    if (!t1) continue;
    EXPECT_EQ(g1.overlap, g2.overlap);
    EXPECT_EQ(g1.normal.x, -g2.normal.x);
    EXPECT_EQ(g1.normal.y, -g2.normal.y);
    EXPECT_EQ(g1.point.x, g2.point.x);
    EXPECT_GT(dot(g1.normal, xd - xq), 0.0) << k;  // from the polygon (j) to the disk (i)
    EXPECT_NEAR(g1.r_eff, 0.004 * 0.005 / 0.009, 1e-18);
    const Vec3 arm = g1.point - xd;
    EXPECT_LT(std::abs(arm.x * g1.normal.y - arm.y * g1.normal.x), 1e-15) << k;
    // (the overlap's centroid is off that line when the contact is lopsided)
    contact::PolygonOverlap o;
    ASSERT_TRUE(contact::disk_polygon_overlap({xd.x, xd.y}, 0.004, poly, o));
    lopsided += std::abs(cross(o.centroid - Vec2{xd.x, xd.y}, o.normal)) > 1e-6;
  }
  EXPECT_GT(lopsided, 10);
}

TEST(ShapeFill, GrainsDoNotOverlapAndOrientationsAreRandom) {
  const Simulation rods(rods_case(400, 0.08));
  EXPECT_EQ(rods.particles().size(), 400u);
  EXPECT_GE(min_pair_gap(rods), 0.0);
  // Axes uniform on the sphere: <|u_z|> = 1/2, <u_z^2> = 1/3 (400 samples: +- 0.03).
  double mean_abs = 0, mean_sq = 0;
  for (std::size_t i = 0; i < rods.particles().size(); ++i) {
    const Vec3 u = rotate(rods.particles().orientation()[i], Vec3{0, 0, 1});
    mean_abs += std::abs(u.z) / 400;
    mean_sq += u.z * u.z / 400;
    EXPECT_NEAR(rods.particles().half_length()[i], 0.0015 * 2, 1e-15);  // L = 2 r (3 - 1)
  }
  EXPECT_NEAR(mean_abs, 0.5, 0.05);
  EXPECT_NEAR(mean_sq, 1.0 / 3.0, 0.05);
  const Simulation poly(polygons_case());
  EXPECT_EQ(poly.particles().size(), 150u);
  EXPECT_GE(min_pair_gap(poly), 0.0);
  EXPECT_GT(poly.particles().polygons().size(), 100u);  // one outline per random grain
  // Disks filled beside polygons: no disk-polygon pair overlaps either.
  const Simulation mixed(mixed_drum_case());
  EXPECT_EQ(mixed.particles().size(), 72u);
  EXPECT_GE(min_pair_gap(mixed), 0.0);
}

// 2D fills in a circle (a `cylinder` region in 2D): a hexagonal lattice of disks and then,
// in the same circle, random polygons and disks that avoid the grains already placed. Every
// grain lies inside the circle and no two overlap (brute force over the exact shapes); the
// lattice holds about the sites `grainflow check` estimates.
TEST(ShapeFill, TwoDimensionalCircleRegions) {
  auto c = test::base_case(5e-6, 1.0, {0, 0, 0}, {0.15, 0.15, 0});
  c.dimension = 2;
  c.domain.thickness = 0.01;
  test::add_material(c, "stone", 2600, 1e7, 0.3);
  test::add_contact(c, "stone", "stone", "hooke", {{"restitution", 0.5}, {"stiffness", 1e5}});
  auto circle = [](config::Fill& f, double radius) {
    f.region.kind = config::Region::Kind::Cylinder;
    f.region.center = {0.075, 0.075, 0};
    f.region.radius = radius;
    f.region.height = 0;
  };
  auto& lat = test::add_box_fill(c, "stone", 0.002, 0.002, {}, {}, config::Fill::Lattice::Hcp);
  circle(lat, 0.03);
  lat.spacing = 0.0045;
  c.particles.back().kind = config::Shape::Disk;
  c.particles.back().shape = "disk";
  const Simulation only_lattice(c);
  const std::size_t n_lattice = only_lattice.particles().size();
  // Sites of a hexagonal lattice of pitch s in the circle of radius R - r: ~ pi (R - r)^2 /
  // (s^2 sqrt(3) / 2).
  const double sites = 3.141592653589793 * 0.028 * 0.028 / (0.0045 * 0.0045 * std::sqrt(3.0) / 2);
  EXPECT_NEAR(static_cast<double>(n_lattice) / sites, 1.0, 0.1) << n_lattice;
  // A ring around it: random polygons, then random disks, in the circle of radius 0.07.
  auto& rp = test::add_box_fill(c, "stone", 0.0015, 0.0025, {}, {}, config::Fill::Lattice::Random);
  circle(rp, 0.07);
  rp.count = 40;
  rp.seed = 3;
  make_random_polygons(c, 1.5);
  auto& rd = test::add_box_fill(c, "stone", 0.0015, 0.0025, {}, {}, config::Fill::Lattice::Random);
  circle(rd, 0.07);
  rd.count = 60;
  rd.seed = 4;
  c.particles.back().kind = config::Shape::Disk;
  c.particles.back().shape = "disk";
  const Simulation sim(c);
  const auto& p = sim.particles();
  EXPECT_EQ(p.size(), n_lattice + 100);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double d = std::hypot(p.x()[i].x - 0.075, p.x()[i].y - 0.075);
    const bool lattice = p.id()[i] < static_cast<std::int64_t>(n_lattice);  // (ids by group)
    EXPECT_LE(d + p.radius()[i], (lattice ? 0.03 : 0.07) * (1 + 1e-12)) << i;
    EXPECT_EQ(p.x()[i].z, 0.0);
  }
  EXPECT_GE(min_pair_gap(sim), 0.0);
}

TEST(ShapesThreadDeterminism, CapsulesOneAndTwoThreadsBitIdentical) {
  // Enough grains for the threaded slab loop (>= 8192).
  const auto cfg = rods_case(9000, 0.2, config::Fill::Lattice::Cubic);
  std::vector<Vec3> out[2];
  for (int t = 0; t < 2; ++t) {
    const int before = exec::n_threads();
    exec::set_threads(t + 1);
    Simulation sim(cfg);
    for (int s = 0; s < 60; ++s) sim.step();
    exec::set_threads(before);
    const auto& p = sim.particles();
    out[t].assign(p.x(), p.x() + p.size());
    out[t].insert(out[t].end(), p.omega(), p.omega() + p.size());
    EXPECT_GT(sim.n_contacts(), 0);
  }
  ASSERT_EQ(out[0].size(), out[1].size());
  EXPECT_EQ(std::memcmp(out[0].data(), out[1].data(), out[0].size() * sizeof(Vec3)), 0);
}

namespace {

/// Runs `cfg` twice, the capsules' force loop skipping the list entries that cannot touch
/// (contact::PairSkip) and testing every entry; both must give the same state, bit for bit.
void expect_skip_changes_nothing(const config::Case& cfg, int steps, bool skips) {
  Simulation a(cfg), b(cfg);
  b.use_pair_skip(false);
  for (int s = 0; s < steps; ++s) {
    a.step();
    b.step();
  }
  EXPECT_EQ(a.pair_skip_active(), skips);
  EXPECT_FALSE(b.pair_skip_active());
  if (skips) {
    EXPECT_GT(a.n_contacts(), 0);
  }
  EXPECT_GT(a.neighbor_list().n_builds(), 2);
  test::expect_same_state(a, b);
}

}  // namespace

// Skipping is exact: rods settling in a box with a post (friction, rolling resistance,
// tangential histories: an entry skipped while touching would lose its history and change the
// run), rods sheared between walls in a periodic box (images across x and y), and rods between
// Lees-Edwards images, whose slide since the build the skip takes off the gaps (at 200 1/s the
// images slide at 14.4 m/s, by up to the skin between builds: more than a rod's radius).
TEST(CapsulePairSkip, SameStateAsTestingEveryEntry) {
  expect_skip_changes_nothing(rods_case(300), 3000, true);

  auto sheared =
      input::load_case(std::string(GF_SOURCE_DIR) + "/cases/rheology/shear_box_rods/case.yaml",
                       {{"particles[0].fill.volume_fraction", "0.4"}, {"time.step", "1.0e-6"}});
  expect_skip_changes_nothing(sheared, 3000, true);

  auto le = test::lees_edwards_box(0.072, 200);
  test::add_aligned_rods(le, 0.3, 3, 1.0);
  expect_skip_changes_nothing(le, 1500, true);
}

// Two rods at rest across the Lees-Edwards boundary meet only through the slide of the images
// (14.4 m/s at 200 1/s in a 72 mm box): the image of the lower rod passes the upper one 2.5 mm
// above it in z, close enough to touch (diameter 3 mm). Between two builds the pair's gap shrinks
// by the slide alone, so a skip that ignored it would miss the start of the contact until the next
// build (checked: without PairSkip::slide the states differ); with it the run is the one that tests
// every entry, bit for bit, and the rods do collide.
TEST(CapsulePairSkip, LeesEdwardsImagesSlideIntoContact) {
  auto c = test::lees_edwards_box(0.072, 200);
  const Quat along_y = quat_from_axis_angle({1, 0, 0}, -1.5707963267948966);  // e_z -> e_y
  // (velocities that cancel the streaming profile the shear start adds: both rods at rest)
  test::add_capsules(c, "pom", 0.0015, 0.009, {{0.036, 0.036, 0.071}, {0.031, 0.036, 0.0015}},
                     {along_y, along_y}, {{-200 * 0.035, 0, 0}, {200 * 0.0345, 0, 0}});
  Simulation a(c), b(c);
  b.use_pair_skip(false);
  std::int64_t touched = 0;
  bool skipping = false;  // (the list is empty again once the rods have parted)
  for (int s = 0; s < 1200; ++s) {
    a.step();
    b.step();
    touched += a.n_contacts();
    skipping = skipping || a.pair_skip_active();
  }
  EXPECT_TRUE(skipping);
  EXPECT_GT(touched, 10);                       // steps in contact
  EXPECT_GT(norm(a.particles().v()[0]), 1e-3);  // the collision moved the rods
  test::expect_same_state(a, b);
}
