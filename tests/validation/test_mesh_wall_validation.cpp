// SPDX-License-Identifier: GPL-3.0-or-later
// Triangle-mesh walls (STL surfaces) against analytic results and against the analytic walls
// they triangulate. A flat surface cut into triangles must act as the plane it is: a sphere
// rolling down a meshed incline crosses dozens of triangle edges, and each crossing would reset
// its tangential spring (and let it slip) if the history did not move to the next triangle; a
// sphere hitting an edge or a vertex shared by several triangles must feel one contact, not one
// per triangle, or its rebound would follow a stiffer, differently damped law. In a concave
// corner it must feel one contact per face, as with planes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "case_builder.hpp"
#include "dump.hpp"
#include "simulation/simulation.hpp"

using namespace gf;

namespace {

constexpr double g0 = 9.81;

/// A rectangle u in [u0, u1] x v in [v0, v1] of the plane through `o` spanned by unit du, dv,
/// cut into n_u x n_v squares of two triangles with alternating diagonals.
void add_grid(std::vector<Vec3>& pts, std::vector<std::array<int, 3>>& tris, Vec3 o, Vec3 du,
              Vec3 dv, double u0, double u1, double v0, double v1, int n_u, int n_v) {
  const int base = static_cast<int>(pts.size());
  for (int j = 0; j <= n_v; ++j)
    for (int i = 0; i <= n_u; ++i)
      pts.push_back(o + (u0 + (u1 - u0) * i / n_u) * du + (v0 + (v1 - v0) * j / n_v) * dv);
  const auto id = [&](int i, int j) { return base + j * (n_u + 1) + i; };
  for (int j = 0; j < n_v; ++j)
    for (int i = 0; i < n_u; ++i) {
      if ((i + j) % 2 == 0) {
        tris.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        tris.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        tris.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        tris.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
}

config::Case sphere_case(double dt, double end, Vec3 lo, Vec3 hi, const char* law, double e,
                         double mu) {
  auto c = test::base_case(dt, end, lo, hi);
  test::add_material(c, "glass", 2500, 1e8, 0.3);
  test::add_material(c, "steel", 7800, 2e8, 0.3);
  std::map<std::string, double> prm{{"restitution", e}, {"friction", mu}};
  if (std::string(law) == "hooke") prm["stiffness"] = 2e4;
  test::add_contact(c, "glass", "steel", law, prm);
  test::add_contact(c, "glass", "glass", law, prm);
  return c;
}

}  // namespace

// Rolling without slipping down an incline of angle theta: a = (5/7) g sin(theta) for a solid
// sphere (I = 2/5 m r^2), needing mu >= (2/7) tan(theta) = 0.10 at 20 degrees (mu = 0.5 here).
// The meshed incline (1 cm squares of two triangles, 5 mm sphere: an edge every ~0.7 cm of
// travel, ~30 crossings over the run) must give the plane's trajectory: the contact normal and
// overlap are the plane's on every triangle, and the history moves with the contact, so the
// two runs differ by rounding only (1e-9 of the distance rolled allows 1e5 ulps). Against the
// analytic distance: the spring's start-up (the static friction force builds over a few contact
// times of ~1e-4 s, during which the sphere slips a little) and the normal oscillation of the
// dropped-in contact cost well under 0.5 % over 0.25 s.
TEST(ValidationMeshWall, RollsDownAMeshedInclineAsOnThePlane) {
  const double theta = 20 * std::numbers::pi / 180, r = 0.005, T = 0.25;
  const Vec3 down{std::cos(theta), 0, -std::sin(theta)}, n{std::sin(theta), 0, std::cos(theta)};
  const Vec3 y{0, 1, 0};
  auto run = [&](bool mesh, bool history_transfer_check) {
    auto c =
        sphere_case(1e-5, T, {-0.05, -0.05, -0.2}, {0.35, 0.05, 0.05}, "hertz_mindlin", 0.5, 0.5);
    test::add_spheres(c, "glass", r, {r * n + 0.0013 * y});
    c.gravity = {0, 0, -g0};
    if (mesh) {
      std::vector<Vec3> pts;
      std::vector<std::array<int, 3>> tris;
      add_grid(pts, tris, {0, 0, 0}, down, y, -0.02, 0.3, -0.03, 0.03, 32, 6);
      test::add_mesh(c, "incline", pts, tris, "steel");
    } else {
      test::add_plane(c, "incline", {0, 0, 0}, n, "steel");
    }
    (void)history_transfer_check;
    Simulation sim(c);
    test::Dump trace(mesh ? "mesh_incline_mesh" : "mesh_incline_plane", "t,s,omega");
    for (int k = 0; sim.time() < T - 1e-12; ++k) {
      sim.step();
      if (k % 250 == 0)
        trace.row(sim.time(), dot(sim.particles().x()[0] - r * n, down),
                  dot(sim.particles().omega()[0], cross(n, down)));
    }
    return std::pair<Vec3, Vec3>{sim.particles().x()[0], sim.particles().omega()[0]};
  };
  const auto [x_plane, w_plane] = run(false, false);
  const auto [x_mesh, w_mesh] = run(true, false);
  const double s_plane = dot(x_plane, down), s_mesh = dot(x_mesh, down);
  const double s_exact = 0.5 * (5.0 / 7.0) * g0 * std::sin(theta) * T * T;
  std::printf("incline: rolled %.9f m on the mesh, %.9f m on the plane, %.9f m analytic\n", s_mesh,
              s_plane, s_exact);
  EXPECT_NEAR(s_mesh, s_plane, 1e-9 * s_plane);
  EXPECT_NEAR(norm(w_mesh - w_plane), 0.0, 1e-9 * norm(w_plane));
  EXPECT_NEAR(s_mesh / s_exact, 1.0, 5e-3);
  // Rolling: omega = v / r about the axis n x down; v = (5/7) g sin(theta) T.
  const double w_exact = (5.0 / 7.0) * g0 * std::sin(theta) * T / r;
  EXPECT_NEAR(dot(w_mesh, cross(n, down)) / w_exact, 1.0, 5e-3);
}

// Head-on impacts on a shared edge and a shared vertex of a mesh: one contact, so the rebound
// is the plane's (the linear spring-dashpot gives the restitution coefficient exactly; with the
// contact counted once per triangle, k and c would be multiplied by the count and the damping
// ratio by its square root: e = 0.5 would become 0.37 for 2 triangles (0.39 measured), 0.09 for 8).
TEST(ValidationMeshWall, EdgeAndVertexImpactsRestituteAsOnePlane) {
  const double r = 0.005, v0 = 1.0, e = 0.5;
  auto rebound = [&](int which) {
    auto c = sphere_case(2e-6, 0.02, {-0.1, -0.1, -0.1}, {0.1, 0.1, 0.1}, "hooke", e, 0.0);
    test::add_spheres(c, "glass", r, {{0, 0, r + 1e-4}}, {{0, 0, -v0}});
    std::vector<Vec3> pts;
    std::vector<std::array<int, 3>> tris;
    if (which == 0) {
      test::add_plane(c, "target", {0, 0, 0}, {0, 0, 1}, "steel");
    } else if (which == 1) {  // a roof ridge along y through the origin, slopes of 30 degrees
      const double a = 30 * std::numbers::pi / 180;
      add_grid(pts, tris, {0, 0, 0}, {-std::cos(a), 0, -std::sin(a)}, {0, 1, 0}, 0, 0.05, -0.05,
               0.05, 5, 10);
      add_grid(pts, tris, {0, 0, 0}, {std::cos(a), 0, -std::sin(a)}, {0, 1, 0}, 0, 0.05, -0.05,
               0.05, 5, 10);
      test::add_mesh(c, "target", pts, tris, "steel");
    } else {  // the apex of a flat-topped fan of 8 triangles (flat: the vertex has 8 owners)
      pts.push_back({0, 0, 0});
      for (int k = 0; k < 8; ++k) {
        const double phi = 2 * std::numbers::pi * k / 8;
        pts.push_back({0.05 * std::cos(phi), 0.05 * std::sin(phi), 0});
      }
      for (int k = 0; k < 8; ++k) tris.push_back({0, 1 + k, 1 + (k + 1) % 8});
      test::add_mesh(c, "target", pts, tris, "steel");
    }
    Simulation sim(c);
    while (sim.time() < 0.02 - 1e-12) sim.step();
    return sim.particles().v()[0];
  };
  const Vec3 v_plane = rebound(0), v_ridge = rebound(1), v_apex = rebound(2);
  test::Dump d("mesh_rebound", "target,vz");  // 0 plane, 1 ridge, 2 apex of a fan
  d.row(0, v_plane.z);
  d.row(1, v_ridge.z);
  d.row(2, v_apex.z);
  std::printf("rebound: plane %.9f, ridge %.9f, apex of a fan %.9f m/s (e v0 = %.3f)\n", v_plane.z,
              v_ridge.z, v_apex.z, e * v0);
  // The spring-dashpot's e is exact for the continuous contact; dt = 2e-6 s resolves the contact
  // time (~1.6 ms) with ~800 steps: 0.5 % covers the time discretisation.
  EXPECT_NEAR(v_plane.z / (e * v0), 1.0, 5e-3);
  EXPECT_NEAR(v_ridge.z, v_plane.z, 1e-9);
  EXPECT_NEAR(v_apex.z, v_plane.z, 1e-9);
  EXPECT_NEAR(std::hypot(v_ridge.x, v_ridge.y), 0.0, 1e-12);
  EXPECT_NEAR(std::hypot(v_apex.x, v_apex.y), 0.0, 1e-12);
}

// A sphere pushed into the inside corner of a meshed box by gravity along the diagonal: three
// contacts (one per face, as with three planes), each carrying the weight's component along its
// normal, m g / sqrt(3); with the same forces, to rounding, as three plane walls.
TEST(ValidationMeshWall, ConcaveCornerHasOneContactPerFace) {
  const double r = 0.005;
  auto run = [&](bool mesh) {
    auto c = sphere_case(1e-5, 0.5, {-0.01, -0.01, -0.01}, {0.05, 0.05, 0.05}, "hertz_mindlin", 0.3,
                         0.5);
    test::add_spheres(c, "glass", r, {{r + 2e-4, r + 1e-4, r + 3e-4}});
    c.gravity = (-g0 / std::sqrt(3.0)) * Vec3{1, 1, 1};
    if (mesh) {  // the three faces at the origin, 4 x 4 squares each
      std::vector<Vec3> pts;
      std::vector<std::array<int, 3>> tris;
      add_grid(pts, tris, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0, 0.04, 0, 0.04, 4, 4);
      add_grid(pts, tris, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, 0, 0.04, 0, 0.04, 4, 4);
      add_grid(pts, tris, {0, 0, 0}, {0, 0, 1}, {1, 0, 0}, 0, 0.04, 0, 0.04, 4, 4);
      test::add_mesh(c, "corner", pts, tris, "steel");
    } else {
      test::add_plane(c, "floor", {0, 0, 0}, {0, 0, 1}, "steel");
      test::add_plane(c, "side_x", {0, 0, 0}, {1, 0, 0}, "steel");
      test::add_plane(c, "side_y", {0, 0, 0}, {0, 1, 0}, "steel");
    }
    Simulation sim(c);
    while (sim.time() < 0.5 - 1e-12) sim.step();
    Vec3 f;
    for (const auto& w : sim.walls()) f += w.force;
    return std::tuple<Vec3, std::int64_t, Vec3>{sim.particles().x()[0], sim.n_wall_contacts(), f};
  };
  const auto [x_p, n_p, f_p] = run(false);
  const auto [x_m, n_m, f_m] = run(true);
  const double weight = g0 * 2500 * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  std::printf(
      "corner: %lld contacts (planes %lld), force on the walls (%.6g, %.6g, %.6g) N, "
      "weight %.6g N\n",
      static_cast<long long>(n_m), static_cast<long long>(n_p), f_m.x, f_m.y, f_m.z, weight);
  EXPECT_EQ(n_m, 3);
  EXPECT_EQ(n_p, 3);
  EXPECT_NEAR(norm(x_m - x_p), 0.0, 1e-12);
  // At rest after 0.5 s (the contacts are damped, e = 0.3): the walls carry the weight.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(f_m[k], -weight / std::sqrt(3.0), 1e-6 * weight);
}

namespace {

/// A rod (spherocylinder) of radius 1.5 mm and cylinder length 9 mm (12 mm tip to tip, the
/// headline rods) lying along u = (cos phi, sin phi, 0): its orientation.
Quat lying_along(double phi) {
  // body axis e_z turned onto x, then about z by phi
  return turn_about_z(quat_from_axis_angle({0, 1, 0}, std::numbers::pi / 2), phi);
}
constexpr double rod_r = 0.0015, rod_l = 0.009;

}  // namespace

// A spherocylinder dropped nearly flat, spinning, onto a meshed floor (1 cm squares of two
// triangles, the rod 12 mm long: its ends cross triangle edges while it slides and turns) and
// onto the plane (with a mesh wall elsewhere): the same motion. On both its contacts are its end
// spheres; each end's contact moves from triangle to triangle with its history, and the two ends
// share the grain's mass on the mesh as on the plane (normals parallel), so the runs differ by the
// order in which the two end forces are added (rounding) only: 1e-9 of the distances moved allows
// 1e5 ulps.
TEST(ValidationMeshWall, RodDroppedOnAMeshedFloorMovesAsOnThePlane) {
  const double T = 0.15;
  auto run = [&](bool mesh) {
    auto c =
        sphere_case(2e-6, T, {-0.06, -0.06, -0.02}, {0.06, 0.06, 0.05}, "hertz_mindlin", 0.5, 0.15);
    // tilted by 2 degrees (one end lands first), spinning about z, sliding along x
    const Quat q = quat_from_axis_angle({1, 0, 0}, 2 * std::numbers::pi / 180) * lying_along(0.3);
    test::add_capsules(c, "glass", rod_r, rod_l, {{0.0013, 0.0021, rod_r + 0.0008}}, {q},
                       {{0.3, 0.1, -0.3}}, {{0, 0, 60.0}});
    c.gravity = {0, 0, -g0};
    if (mesh) {
      std::vector<Vec3> pts;
      std::vector<std::array<int, 3>> tris;
      add_grid(pts, tris, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, -0.05, 0.05, -0.05, 0.05, 10, 10);
      test::add_mesh(c, "floor", pts, tris, "steel");
    } else {
      // (and a mesh wall far away: the wall list then has the mesh's eight slots per entry,
      // of which a plane must use the two ends only)
      test::add_plane(c, "floor", {0, 0, 0}, {0, 0, 1}, "steel");
      test::add_mesh(c, "far", {{0.05, 0.05, 0.04}, {0.06, 0.05, 0.04}, {0.05, 0.06, 0.04}},
                     {{0, 1, 2}}, "steel");
    }
    Simulation sim(c);
    test::Dump trace(mesh ? "mesh_rod_floor_mesh" : "mesh_rod_floor_plane", "t,x,y,z,wz");
    std::int64_t max_contacts = 0;
    for (int k = 0; sim.time() < T - 1e-12; ++k) {
      sim.step();
      max_contacts = std::max(max_contacts, sim.n_wall_contacts());
      const auto& p = sim.particles();
      if (k % 250 == 0) trace.row(sim.time(), p.x()[0].x, p.x()[0].y, p.x()[0].z, p.omega()[0].z);
    }
    const auto& p = sim.particles();
    return std::tuple<Vec3, Vec3, Vec3, std::int64_t>{p.x()[0], p.v()[0], p.omega()[0],
                                                      max_contacts};
  };
  const auto [x_p, v_p, w_p, n_p] = run(false);
  const auto [x_m, v_m, w_m, n_m] = run(true);
  std::printf(
      "rod on a floor: x mesh (%.9f, %.9f, %.9f), plane (%.9f, %.9f, %.9f); omega_z %.6f / %.6f; "
      "at most %lld / %lld contacts\n",
      x_m.x, x_m.y, x_m.z, x_p.x, x_p.y, x_p.z, w_m.z, w_p.z, static_cast<long long>(n_m),
      static_cast<long long>(n_p));
  EXPECT_EQ(n_m, 2);
  EXPECT_EQ(n_p, 2);
  EXPECT_GT(std::hypot(x_p.x - 0.0013, x_p.y - 0.0021), 0.003);  // it slid across edges
  EXPECT_NEAR(norm(x_m - x_p), 0.0, 1e-9 * 0.01);
  EXPECT_NEAR(norm(v_m - v_p), 0.0, 1e-9);
  EXPECT_NEAR(norm(w_m - w_p), 0.0, 1e-9 * std::max(1.0, norm(w_p)));
}

// A rod falling flat across a roof ridge (slopes of 30 degrees, meshed) at its middle touches the
// ridge only, with the normal through its centre of mass: it rebounds as a sphere from a plane,
// with the restitution e of the linear spring-dashpot (exact for the continuous contact) and
// without turning. Counted at its two ends only (as on a plane), it would fall through the ridge.
TEST(ValidationMeshWall, RodFallingAcrossARidgeRestitutes) {
  const double v0 = 1.0, e = 0.5;
  auto c = sphere_case(5e-7, 0.02, {-0.1, -0.1, -0.1}, {0.1, 0.1, 0.1}, "hooke", e, 0.0);
  test::add_capsules(c, "glass", rod_r, rod_l, {{0, 0.002, rod_r + 1e-4}}, {lying_along(0.2)},
                     {{0, 0, -v0}});
  std::vector<Vec3> pts;
  std::vector<std::array<int, 3>> tris;
  const double a = 30 * std::numbers::pi / 180;
  add_grid(pts, tris, {0, 0, 0}, {-std::cos(a), 0, -std::sin(a)}, {0, 1, 0}, 0, 0.05, -0.05, 0.05,
           5, 10);
  add_grid(pts, tris, {0, 0, 0}, {std::cos(a), 0, -std::sin(a)}, {0, 1, 0}, 0, 0.05, -0.05, 0.05, 5,
           10);
  test::add_mesh(c, "roof", pts, tris, "steel");
  Simulation sim(c);
  std::int64_t max_contacts = 0;
  while (sim.time() < 0.02 - 1e-12) {
    sim.step();
    max_contacts = std::max(max_contacts, sim.n_wall_contacts());
  }
  const Vec3 v = sim.particles().v()[0], w = sim.particles().omega()[0];
  std::printf(
      "rod across a ridge: rebound %.9f m/s (e v0 = %.3f), |omega| %.3g 1/s, %lld contact\n", v.z,
      e * v0, norm(w), static_cast<long long>(max_contacts));
  EXPECT_EQ(max_contacts, 1);
  // The error of the rebound is first order in dt (0.67 % at dt = 2e-6 s, 0.17 % at 5e-7 s): dt
  // = 5e-7 s resolves the contact time (0.31 ms for this light rod) with ~600 steps; 0.5 %.
  EXPECT_NEAR(v.z / (e * v0), 1.0, 5e-3);
  EXPECT_NEAR(std::hypot(v.x, v.y), 0.0, 1e-9);
  EXPECT_NEAR(norm(w), 0.0, 1e-6);
}

// A rod lying across the edge of a table (a meshed box, top at z = 0), let go at rest: with its
// centre of mass over the table it stays, held by its inner end and the edge (the table carries
// its weight); with the centre of mass beyond the edge it tips about the edge and falls off.
TEST(ValidationMeshWall, RodOverATableEdgeStaysOrTipsByItsCentreOfMass) {
  const double half = 0.5 * rod_l + rod_r;  // half the tip-to-tip length
  auto run = [&](double overhang) {         // centre of mass beyond the edge x = 0, m
    auto c = sphere_case(2e-6, 0.25, {-0.06, -0.03, -0.06}, {0.03, 0.03, 0.02}, "hertz_mindlin",
                         0.3, 0.5);
    test::add_capsules(c, "glass", rod_r, rod_l, {{overhang, 0.0004, rod_r}}, {lying_along(0)});
    c.gravity = {0, 0, -g0};
    std::vector<Vec3> pts;
    std::vector<std::array<int, 3>> tris;
    add_grid(pts, tris, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, -0.04, 0, -0.02, 0.02, 4, 4);  // top
    add_grid(pts, tris, {0, 0, 0}, {0, 1, 0}, {0, 0, -1}, -0.02, 0.02, 0, 0.04, 4, 4);  // side
    test::add_mesh(c, "table", pts, tris, "steel");
    Simulation sim(c);
    test::Dump trace(overhang < 0 ? "mesh_rod_table_in" : "mesh_rod_table_out", "t,x,z");
    for (int k = 0; sim.time() < 0.25 - 1e-12; ++k) {
      sim.step();
      if (k % 250 == 0) trace.row(sim.time(), sim.particles().x()[0].x, sim.particles().x()[0].z);
    }
    const double weight = g0 * 2500 * std::numbers::pi * rod_r * rod_r * (rod_l + 4.0 / 3 * rod_r);
    return std::tuple<Vec3, double, double, std::int64_t>{
        sim.particles().x()[0], norm(sim.particles().omega()[0]), -sim.walls()[0].force.z / weight,
        sim.n_wall_contacts()};
  };
  const auto [x_in, w_in, load_in, n_in] = run(-0.3 * half);
  const auto [x_out, w_out, load_out, n_out] = run(0.3 * half);
  std::printf(
      "rod over a table edge: centre 0.3 half-lengths inside: z %.6g m, |omega| %.3g, load/weight "
      "%.9f, %lld contacts; outside: z %.4g m\n",
      x_in.z, w_in, load_in, static_cast<long long>(n_in), x_out.z);
  EXPECT_EQ(n_in, 2);  // the inner end and the edge
  EXPECT_NEAR(x_in.z, rod_r, 0.02 * rod_r);
  EXPECT_NEAR(w_in, 0.0, 1e-3);
  EXPECT_NEAR(load_in, 1.0, 1e-6);
  EXPECT_LT(x_out.z, -half);  // fell off, below the table top by more than its half length
}

// A rod dropped across a narrow bar (a meshed box 6 mm wide, like a lifter; the rod 12 mm long)
// with its centre of mass 1 mm off the bar's middle: it comes to rest on the bar's two top
// edges, both ends free (the contacts where the axis leaves the bar's top face), tilted towards
// the heavier side by no more than the edges' overlaps allow, the bar carrying its weight.
// Counted as local minima of the distance only, it would rest on one edge at a time and rock.
TEST(ValidationMeshWall, RodAcrossANarrowBarRestsOnBothEdges) {
  auto c =
      sphere_case(2e-6, 0.3, {-0.03, -0.03, -0.03}, {0.03, 0.03, 0.03}, "hertz_mindlin", 0.3, 0.5);
  test::add_capsules(c, "glass", rod_r, rod_l, {{0.001, 0.0003, rod_r + 2e-4}}, {lying_along(0)});
  c.gravity = {0, 0, -g0};
  std::vector<Vec3> pts;
  std::vector<std::array<int, 3>> tris;
  const double w = 0.003;                                                              // half width
  add_grid(pts, tris, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, -w, w, -0.01, 0.01, 2, 4);      // top
  add_grid(pts, tris, {-w, 0, 0}, {0, 1, 0}, {0, 0, -1}, -0.01, 0.01, 0, 0.01, 4, 2);  // sides
  add_grid(pts, tris, {w, 0, 0}, {0, 1, 0}, {0, 0, -1}, -0.01, 0.01, 0, 0.01, 4, 2);
  test::add_mesh(c, "bar", pts, tris, "steel");
  Simulation sim(c);
  test::Dump trace("mesh_rod_bar", "t,z,tilt");
  double max_w_late = 0;
  for (int k = 0; sim.time() < 0.3 - 1e-12; ++k) {
    sim.step();
    if (sim.time() > 0.2) max_w_late = std::max(max_w_late, norm(sim.particles().omega()[0]));
    if (k % 250 == 0)
      trace.row(sim.time(), sim.particles().x()[0].z,
                std::asin(rotate_z(sim.particles().orientation()[0]).z));
  }
  const double weight = g0 * 2500 * std::numbers::pi * rod_r * rod_r * (rod_l + 4.0 / 3 * rod_r);
  const double load = -sim.walls()[0].force.z / weight;
  const Vec3 x = sim.particles().x()[0];
  std::printf(
      "rod across a bar: %lld contacts, load/weight %.9f, centre z %.6g m, |omega| after "
      "0.2 s <= %.3g 1/s\n",
      static_cast<long long>(sim.n_wall_contacts()), load, x.z, max_w_late);
  EXPECT_EQ(sim.n_wall_contacts(), 2);
  EXPECT_NEAR(load, 1.0, 1e-6);
  EXPECT_NEAR(x.z, rod_r, 0.02 * rod_r);
  EXPECT_LT(max_w_late, 1e-3);
}
