// SPDX-License-Identifier: GPL-3.0-or-later
// The contact network output (output.contacts_csv, output.contacts_vtk): the records of a force
// stage against a brute-force search for touching pairs and against the forces the stage
// applied, for spheres between Lees-Edwards images and for spheres and spherocylinders between
// walls (grain pairs and grain-wall contacts together give every grain's force and every wall's
// reaction); the CSV and VTK files it writes; the files a run writes on its schedule; and the
// walls' interval means (series wall_force_mean, the rheology's wall tractions).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/files.hpp"
#include "io/input/parse_case.hpp"
#include "simulation/simulation.hpp"
#include "temp_dir.hpp"
#include "vtk_reader.hpp"

using namespace gf;

namespace {

config::Case rheology_case(const std::string& rel, std::vector<input::Override> sets) {
  return input::load_case(std::string(GF_SOURCE_DIR) + "/cases/rheology/" + rel, sets);
}

/// The touching records of the last recorded force stage.
std::vector<contact::ContactRecord> touching(const Simulation& sim) {
  std::vector<contact::ContactRecord> out;
  for (const auto& r : sim.contact_records())
    if (r.i >= 0) out.push_back(r);
  return out;
}

/// Sum over the records of the force each grain received (i: +F, j: -F).
std::vector<Vec3> record_forces(const Simulation& sim) {
  std::vector<Vec3> f(sim.particles().size());
  for (const auto& r : touching(sim)) {
    f[static_cast<std::size_t>(r.i)] += r.force;
    f[static_cast<std::size_t>(r.j)] -= r.force;
  }
  return f;
}

/// The touching wall records of the last recorded force stage.
std::vector<contact::ContactRecord> touching_walls(const Simulation& sim) {
  std::vector<contact::ContactRecord> out;
  for (const auto& r : sim.wall_contact_records())
    if (r.i >= 0) out.push_back(r);
  return out;
}

double max_norm(const std::vector<Vec3>& v) {
  double m = 0;
  for (const auto& a : v) m = std::max(m, norm(a));
  return m;
}

}  // namespace

// Dense spheres (phi = 0.35) sheared between Lees-Edwards images, after 3000 steps, with a soft
// spring (k = 600 N/m: contacts last 30 x longer, ~100 at a time instead of ~10): the records
// name exactly the pairs that a search over all pairs finds touching (nearest sliding image),
// each with its branch vector, unit normal along it, overlap r_i + r_j - |b| and contact point
// on the branch at r_i - overlap/2 from i; without gravity or walls the records' forces add up
// to the force on every grain. Round-off: the loop and this sum add the same few terms per grain
// in another order (1e-12 of the largest force); geometry to 1e-12 m.
TEST(ContactsOutput, SpheresMatchBruteForceAndTheAppliedForces) {
  const auto cfg = rheology_case("lees_edwards_spheres/case.yaml",
                                 {{"particles[0].fill.volume_fraction", "0.35"},
                                  {"shear.rate", "400"},
                                  {"contacts[0].stiffness", "600"},
                                  {"time.step", "1.0e-6"}});
  Simulation sim(cfg);
  for (int k = 0; k < 3000; ++k) sim.step();
  sim.collect_contacts(true);
  sim.step();
  sim.collect_contacts(false);
  const auto rec = touching(sim);
  ASSERT_GT(rec.size(), 50u);
  EXPECT_EQ(static_cast<std::int64_t>(rec.size()), sim.n_contacts());

  const ParticleStore& p = sim.particles();
  const Domain& d = sim.domain();
  std::set<std::pair<std::int64_t, std::int64_t>> brute, found;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const double rs = p.radius()[i] + p.radius()[j];
      if (norm2(d.delta(p.x()[i], p.x()[j])) < rs * rs)
        brute.insert({std::min(p.id()[i], p.id()[j]), std::max(p.id()[i], p.id()[j])});
    }
  for (const auto& r : rec) {
    const auto i = static_cast<std::size_t>(r.i), j = static_cast<std::size_t>(r.j);
    found.insert({std::min(p.id()[i], p.id()[j]), std::max(p.id()[i], p.id()[j])});
    const Vec3 b = d.delta(p.x()[i], p.x()[j]);
    EXPECT_LT(norm(r.branch - b), 1e-12);
    EXPECT_NEAR(norm(r.normal), 1.0, 1e-14);
    EXPECT_LT(norm(r.normal - (1 / norm(b)) * b), 1e-12);
    EXPECT_NEAR(r.overlap, p.radius()[i] + p.radius()[j] - norm(b), 1e-12);
    EXPECT_LT(norm(r.point - (p.x()[i] - (p.radius()[i] - 0.5 * r.overlap) * r.normal)), 1e-12);
  }
  EXPECT_EQ(found, brute);
  EXPECT_EQ(found.size(), rec.size());  // each pair once

  const auto f = record_forces(sim);
  const double scale = max_norm(f);
  ASSERT_GT(scale, 0);
  for (std::size_t i = 0; i < p.size(); ++i) EXPECT_LT(norm(f[i] - p.f()[i]), 1e-12 * scale) << i;
}

// Spherocylinders between walls (the rods shear box, phi = 0.3, a soft spring k = 600 N/m for
// longer contacts): every touching pair recorded
// once, with a unit normal and a contact point within reach of both axes; for rods that touch
// no wall the records' forces add up to the force on the rod.
TEST(ContactsOutput, RodsAddUpToTheForceOnEachRod) {
  const auto cfg = rheology_case("shear_box_rods/case.yaml",
                                 {{"time.step", "1.0e-6"}, {"contacts[0].stiffness", "600"}});
  Simulation sim(cfg);
  for (int k = 0; k < 4000; ++k) sim.step();
  sim.collect_contacts(true);
  sim.step();
  const auto rec = touching(sim);
  ASSERT_GT(rec.size(), 20u);
  EXPECT_EQ(static_cast<std::int64_t>(rec.size()), sim.n_contacts());
  const ParticleStore& p = sim.particles();
  const double h = p.half_length()[0], r = p.radius()[0] - h;  // one rod size in this case
  for (const auto& c : rec) {
    EXPECT_NEAR(norm(c.normal), 1.0, 1e-12);
    EXPECT_GT(c.overlap, 0.0);
    // The contact point lies within one radius of both rods' centres' reach (h + r).
    EXPECT_LT(norm(c.point - p.x()[static_cast<std::size_t>(c.i)]), h + r);
    EXPECT_LT(norm(c.branch), 2 * (h + r));
  }
  const auto f = record_forces(sim);
  const double scale = max_norm(f);
  ASSERT_GT(scale, 0);
  const double zmax = sim.domain().hi.z, reach = h + r;
  int checked = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double z = p.x()[i].z;
    if (z < 1.5 * reach || z > zmax - 1.5 * reach) continue;  // may touch a wall
    EXPECT_LT(norm(f[i] - p.f()[i]), 1e-12 * scale) << i;
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

// A run writes contacts_NNNNNNNNN.csv on its schedule, from step 0: the header, one row per
// touching pair with the grains' ids and the normal force F . n, as many rows as the step's
// contacts.
TEST(ContactsOutput, RunWritesTheScheduledFiles) {
  test::TempDir tmp;
  const auto cfg = rheology_case("lees_edwards_spheres/case.yaml",
                                 {{"particles[0].fill.volume_fraction", "0.35"},
                                  {"shear.rate", "400"},
                                  {"shear.strain", "1.2"},
                                  {"contacts[0].stiffness", "600"},
                                  {"time.step", "1.0e-6"},
                                  {"output.vtk.every", "0"},
                                  {"output.contacts_csv.every", "1.0e-3"}});
  RunOptions o;
  o.output = tmp / "run";
  o.quiet = true;
  Simulation sim(cfg);
  sim.run(o);  // 3000 steps: files at 0, 1000, 2000, 3000
  for (int s : {0, 1000, 2000, 3000})
    EXPECT_TRUE(std::filesystem::exists(o.output / fmt::format("contacts_{:09d}.csv", s))) << s;
  std::istringstream in(read_text_file(o.output / "contacts_000003000.csv"));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "id_i,id_j,x,y,z,nx,ny,nz,fx,fy,fz,fn,overlap,bx,by,bz");
  std::int64_t rows = 0;
  while (std::getline(in, line)) {
    ++rows;
    std::vector<double> v;
    std::stringstream ss(line);
    std::string field;
    while (std::getline(ss, field, ',')) v.push_back(std::stod(field));
    ASSERT_EQ(v.size(), 16u) << line;
    EXPECT_NE(v[0], v[1]);
    EXPECT_NEAR(v[11], v[8] * v[5] + v[9] * v[6] + v[10] * v[7], 1e-12 * (std::abs(v[11]) + 1));
  }
  EXPECT_EQ(rows, sim.n_contacts());
  EXPECT_GT(rows, 50);
}

// Grains sheared between walls, one step recorded after the box has filled its contacts: the
// grain pairs and the grain-wall records together add up to the force on every grain (no
// gravity, no fluid), and each wall's records to minus its reaction; every wall record lies on
// its wall's side: unit normal along the plane's normal, overlap > 0, contact point within the
// overlap of the wall's plane, branch from the point to the grain's centre. Spheres take the
// batched wall loop (one law for all pairs; the plates have friction 0.5, so the records carry
// tangential forces), rods the per-contact loop with two slots per entry. Round-off: the loops
// and this sum add the same few terms per grain in another order (1e-12 of the largest force).
void check_walls_close_the_balance(const config::Case& cfg, int steps, std::size_t min_walls) {
  Simulation sim(cfg);
  for (int k = 0; k < steps; ++k) sim.step();
  sim.collect_contacts(true);
  sim.step();
  sim.collect_contacts(false);
  const auto walls = touching_walls(sim);
  ASSERT_GE(walls.size(), min_walls);
  EXPECT_EQ(static_cast<std::int64_t>(walls.size()), sim.n_wall_contacts());
  const ParticleStore& p = sim.particles();
  auto f = record_forces(sim);
  std::vector<Vec3> reaction(sim.walls().size());
  bool tangential = false;
  for (const auto& r : walls) {
    ASSERT_GE(r.j, 0);
    ASSERT_LT(static_cast<std::size_t>(r.j), sim.walls().size());
    const Wall& w = sim.walls()[static_cast<std::size_t>(r.j)];
    const Vec3 x = p.x()[static_cast<std::size_t>(r.i)];
    f[static_cast<std::size_t>(r.i)] += r.force;
    reaction[static_cast<std::size_t>(r.j)] -= r.force;
    EXPECT_NEAR(norm(r.normal), 1.0, 1e-12);
    EXPECT_NEAR(std::abs(dot(r.normal, w.dir)), 1.0, 1e-12);  // a plane's normal
    EXPECT_GT(dot(x - w.point, r.normal), 0.0);               // the grain on the normal's side
    EXPECT_GT(r.overlap, 0.0);
    EXPECT_NEAR(dot(r.point - w.point, r.normal), -0.5 * r.overlap, 1e-12);
    EXPECT_LT(norm(r.branch - (x - r.point)), 1e-15);
    EXPECT_GE(dot(r.force, r.normal), 0.0);  // 0 where damping would pull: the law clamps it
    tangential |= norm(r.force - dot(r.force, r.normal) * r.normal) > 1e-6 * norm(r.force);
  }
  EXPECT_TRUE(tangential);
  const double scale = max_norm(f);
  ASSERT_GT(scale, 0);
  for (std::size_t i = 0; i < p.size(); ++i) EXPECT_LT(norm(f[i] - p.f()[i]), 1e-12 * scale) << i;
  for (std::size_t w = 0; w < reaction.size(); ++w)
    EXPECT_LT(norm(reaction[w] - sim.walls()[w].force), 1e-12 * scale) << sim.walls()[w].name;
}

TEST(ContactsOutput, SpheresAndWallsAddUpToEveryForce) {
  check_walls_close_the_balance(
      rheology_case("shear_box_spheres/case.yaml", {{"particles[0].fill.volume_fraction", "0.3"},
                                                    {"shear.rate", "400"},
                                                    {"contacts[0].stiffness", "600"},
                                                    {"contacts[1].stiffness", "600"},
                                                    {"time.step", "1.0e-6"}}),
      3000, 5);
}

TEST(ContactsOutput, RodsAndWallsAddUpToEveryForce) {
  check_walls_close_the_balance(
      rheology_case("shear_box_rods/case.yaml", {{"time.step", "1.0e-6"},
                                                 {"contacts[0].stiffness", "600"},
                                                 {"contacts[1].stiffness", "600"}}),
      4000, 5);
}

// A run with walls and output.contacts_vtk writes, on its schedule, wall_contacts_N.csv (one row
// per grain-wall contact, the wall by name) next to contacts_N.csv, and contacts_N.vtp with one
// line per contact (pairs, then walls) listed in contacts.pvd: the lines join each grain's
// centre to its partner's touching image or to the wall's contact point, with the records'
// forces, normal forces and ids as cell data.
TEST(ContactsOutput, RunWritesWallContactsAndTheVtkNetwork) {
  test::TempDir tmp;
  const auto cfg =
      rheology_case("shear_box_spheres/case.yaml", {{"particles[0].fill.volume_fraction", "0.3"},
                                                    {"shear.rate", "400"},
                                                    {"shear.strain", "1.2"},
                                                    {"contacts[0].stiffness", "600"},
                                                    {"contacts[1].stiffness", "600"},
                                                    {"time.step", "1.0e-6"},
                                                    {"analysis.rheology.every_strain", "0.4"},
                                                    {"output.vtk.every", "0"},
                                                    {"output.series.every", "0"},
                                                    {"output.contacts_csv.every", "1.5e-3"},
                                                    {"output.contacts_vtk.every", "1.0e-3"}});
  RunOptions o;
  o.output = tmp / "run";
  o.quiet = true;
  Simulation sim(cfg);
  sim.run(o);  // 3000 steps: CSV at 0, 1500, 3000; VTK at 0, 1000, 2000, 3000
  for (int s : {0, 1500, 3000}) {
    EXPECT_TRUE(std::filesystem::exists(o.output / fmt::format("contacts_{:09d}.csv", s))) << s;
    EXPECT_TRUE(std::filesystem::exists(o.output / fmt::format("wall_contacts_{:09d}.csv", s)))
        << s;
  }
  EXPECT_FALSE(std::filesystem::exists(o.output / "wall_contacts_000001000.csv"));
  for (int s : {0, 1000, 2000, 3000})
    EXPECT_TRUE(std::filesystem::exists(o.output / fmt::format("contacts_{:09d}.vtp", s))) << s;
  const std::string pvd = read_text_file(o.output / "contacts.pvd");
  EXPECT_NE(pvd.find("contacts_000002000.vtp"), std::string::npos);

  // The CSV of the walls at the last step: its rows are the step's wall contacts.
  std::istringstream in(read_text_file(o.output / "wall_contacts_000003000.csv"));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "id,wall,x,y,z,nx,ny,nz,fx,fy,fz,fn,overlap,bx,by,bz");
  std::int64_t rows = 0;
  std::set<std::string> names;
  while (std::getline(in, line)) {
    ++rows;
    std::stringstream ss(line);
    std::string field;
    std::vector<std::string> v;
    while (std::getline(ss, field, ',')) v.push_back(field);
    ASSERT_EQ(v.size(), 16u) << line;
    names.insert(v[1]);
  }
  EXPECT_EQ(rows, sim.n_wall_contacts());
  EXPECT_GT(rows, 0);
  for (const auto& n : names) EXPECT_TRUE(n == "shear_bottom" || n == "shear_top") << n;

  const test::VtkFile vtp(o.output / "contacts_000003000.vtp");
  const auto pairs = touching(sim);
  const auto walls = touching_walls(sim);
  const std::size_t n = pairs.size() + walls.size();
  EXPECT_EQ(vtp.piece("NumberOfLines"), std::to_string(n));
  EXPECT_EQ(vtp.piece("NumberOfPoints"), std::to_string(2 * n));
  const auto pts = vtp.get<double>("Points/position", "Float64", 3);
  const auto fn = vtp.get<double>("CellData/fn", "Float64", 1);
  const auto force = vtp.get<double>("CellData/force", "Float64", 3);
  const auto id_j = vtp.get<std::int64_t>("CellData/id_j", "Int64", 1);
  const auto wall = vtp.get<std::int32_t>("CellData/wall", "Int32", 1);
  const auto conn = vtp.get<std::int64_t>("Lines/connectivity", "Int64", 1);
  ASSERT_EQ(pts.size(), 6 * n);
  ASSERT_EQ(fn.size(), n);
  ASSERT_EQ(conn.size(), 2 * n);
  const ParticleStore& p = sim.particles();
  for (std::size_t c = 0; c < n; ++c) {
    const bool to_wall = c >= pairs.size();
    const auto& r = to_wall ? walls[c - pairs.size()] : pairs[c];
    const Vec3 a{pts[6 * c], pts[6 * c + 1], pts[6 * c + 2]};
    const Vec3 b{pts[6 * c + 3], pts[6 * c + 4], pts[6 * c + 5]};
    const Vec3 xi = p.x()[static_cast<std::size_t>(r.i)];
    EXPECT_EQ(a, xi);
    EXPECT_LT(norm(b - (to_wall ? r.point : xi - r.branch)), 1e-15) << c;
    EXPECT_EQ(fn[c], dot(r.force, r.normal));
    EXPECT_EQ(force[3 * c + 2], r.force.z);
    EXPECT_EQ(id_j[c], to_wall ? -1 : p.id()[static_cast<std::size_t>(r.j)]);
    EXPECT_EQ(wall[c], to_wall ? r.j : -1);
    EXPECT_EQ(conn[2 * c], static_cast<std::int64_t>(2 * c));
  }
}

// The walls' interval means (series wall_force_mean / wall_torque_mean, rheology wall
// tractions) are the means of the forces and torques the steps applied: against a sum taken
// here over 700 steps (to round-off of the same sums), each reader with its own interval; an
// interval without steps reports the means of the interval its reset closed (the row written at
// that step, written again by a restart from there), before the first reset the current force.
TEST(WallMeans, AreTheMeansOfTheStepsSinceTheReset) {
  const auto cfg =
      rheology_case("shear_box_spheres/case.yaml", {{"particles[0].fill.volume_fraction", "0.3"},
                                                    {"shear.rate", "400"},
                                                    {"contacts[0].stiffness", "600"},
                                                    {"contacts[1].stiffness", "600"},
                                                    {"time.step", "1.0e-6"}});
  using M = Simulation::WallMeans;
  Simulation sim(cfg);
  const std::size_t n = sim.walls().size();
  ASSERT_EQ(n, 2u);
  for (std::size_t w = 0; w < n; ++w)
    EXPECT_EQ(sim.wall_mean_force(M::Series, w), sim.walls()[w].force);
  std::vector<Vec3> f0(n), t0(n);
  for (int k = 0; k < 3000; ++k) {
    sim.step();
    for (std::size_t w = 0; w < n; ++w) {
      f0[w] += sim.walls()[w].force;
      t0[w] += sim.walls()[w].torque;
    }
  }
  sim.reset_wall_means(M::Series);
  sim.reset_wall_means(M::Series);  // (a second reset at the same step closes nothing)
  ASSERT_GT(norm(f0[0]), 0.0);
  for (std::size_t w = 0; w < n; ++w) {
    EXPECT_LE(norm(sim.wall_mean_force(M::Series, w) - (1.0 / 3000) * f0[w]), 1e-13 * norm(f0[w]));
    EXPECT_LE(norm(sim.wall_mean_torque(M::Series, w) - (1.0 / 3000) * t0[w]), 1e-13 * norm(t0[w]));
  }
  EXPECT_NE(sim.wall_mean_force(M::Series, 0), sim.walls()[0].force);  // (the top: no contact)
  std::vector<Vec3> f(n), t(n), f_late(n);
  for (int k = 0; k < 700; ++k) {
    if (k == 300) sim.reset_wall_means(M::Rheology);
    sim.step();
    for (std::size_t w = 0; w < n; ++w) {
      f[w] += sim.walls()[w].force;
      t[w] += sim.walls()[w].torque;
      if (k >= 300) f_late[w] += sim.walls()[w].force;
    }
  }
  ASSERT_GT(norm(f[0]) + norm(f[1]), 0.0);  // (the top wall may have had no contact yet)
  for (std::size_t w = 0; w < n; ++w) {
    EXPECT_LE(norm(sim.wall_mean_force(M::Series, w) - (1.0 / 700) * f[w]), 1e-13 * norm(f[w]));
    EXPECT_LE(norm(sim.wall_mean_torque(M::Series, w) - (1.0 / 700) * t[w]), 1e-13 * norm(t[w]));
    EXPECT_LE(norm(sim.wall_mean_force(M::Rheology, w) - (1.0 / 400) * f_late[w]),
              1e-13 * norm(f_late[w]));
  }
  // The series reads the same means (by wall name, per component), and counts wall contacts.
  EXPECT_EQ(sim.quantity("wall_force_mean.shear_bottom.z"), sim.wall_mean_force(M::Series, 0).z);
  EXPECT_EQ(sim.quantity("wall_torque_mean.shear_top.y"), sim.wall_mean_torque(M::Series, 1).y);
  EXPECT_EQ(sim.quantity("wall_contact_count"), static_cast<double>(sim.n_wall_contacts()));
}
