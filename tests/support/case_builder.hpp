// SPDX-License-Identifier: GPL-3.0-or-later
// Builds small config::Case objects in code for tests (no YAML involved).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/quaternion.hpp"
#include "io/input/config.hpp"

namespace gf::test {

inline config::Case base_case(double dt, double end, Vec3 lo, Vec3 hi,
                              std::array<bool, 3> periodic = {}) {
  config::Case c;
  c.file = "test.yaml";
  c.name = "test";
  c.time.step = dt;
  c.time.end = end;
  c.domain.min = lo;
  c.domain.max = hi;
  c.domain.periodic = periodic;
  c.gravity = {0, 0, 0};
  c.output.directory = "";
  return c;
}

inline void add_material(config::Case& c, const std::string& name, double rho, double e,
                         double nu) {
  config::Material m;
  m.name = name;
  m.density = rho;
  m.youngs_modulus = e;
  m.poisson_ratio = nu;
  c.materials.push_back(m);
}

inline void add_contact(config::Case& c, const std::string& a, const std::string& b,
                        const std::string& model, std::map<std::string, double> params) {
  config::Contact k;
  k.between = {a, b};
  k.model = model;
  if (!params.count("friction")) params["friction"] = 0.5;
  if (!params.count("rolling_friction")) params["rolling_friction"] = 0.0;
  if (model == "hooke" && !params.count("tangential_stiffness_ratio"))
    params["tangential_stiffness_ratio"] = 2.0 / 7.0;
  k.params = params;
  c.contacts.push_back(k);
}

inline void add_spheres(config::Case& c, const std::string& material, double radius,
                        std::vector<Vec3> x, std::vector<Vec3> v = {}, std::vector<Vec3> w = {}) {
  config::ParticleGroup g;
  g.material = material;
  g.radius.value = radius;
  config::Explicit e;
  e.positions = std::move(x);
  e.velocities = std::move(v);
  e.angular_velocities = std::move(w);
  g.explicit_particles = e;
  c.particles.push_back(g);
}

inline void add_plane(config::Case& c, const std::string& name, Vec3 point, Vec3 normal,
                      const std::string& material) {
  config::Wall w;
  w.name = name;
  w.kind = config::Wall::Kind::Plane;
  w.point = point;
  w.normal = normal;
  w.material = material;
  c.walls.push_back(w);
}

/// A cylinder wall of the given axis through `center` (2D: the circle about `center`, axis z),
/// `inside` as a drum, turning at `rate` rad/s about its own axis when rate != 0.
inline config::Wall& add_cylinder(config::Case& c, const std::string& name, Vec3 center, Vec3 axis,
                                  double radius, bool inside, const std::string& material,
                                  double rate = 0) {
  config::Wall w;
  w.name = name;
  w.kind = config::Wall::Kind::Cylinder;
  w.center = center;
  w.axis = axis;
  w.radius = radius;
  w.inside = inside;
  w.material = material;
  if (rate != 0) {
    w.motion.rotates = true;
    w.motion.axis = axis;
    w.motion.center = center;
    w.motion.rate = rate;
  }
  c.walls.push_back(w);
  return c.walls.back();
}

/// A triangle-mesh wall given in code (the case file reads it from STL: mesh: {file: ...}).
inline void add_mesh(config::Case& c, const std::string& name, std::vector<Vec3> points,
                     std::vector<std::array<int, 3>> triangles, const std::string& material) {
  config::Wall w;
  w.name = name;
  w.kind = config::Wall::Kind::Mesh;
  w.mesh_points = std::move(points);
  w.mesh_triangles = std::move(triangles);
  w.material = material;
  c.walls.push_back(w);
}

/// A box region (fills, outlets, inlets) from its corners.
inline config::Region box_region(Vec3 lo, Vec3 hi) {
  config::Region r;
  r.kind = config::Region::Kind::Box;
  r.min = lo;
  r.max = hi;
  return r;
}

/// An outlet of the given region; returns it for further settings (reinsert), valid until the
/// next push_back.
inline config::Outlet& add_outlet(config::Case& c, const std::string& name,
                                  const config::Region& region) {
  config::Outlet o;
  o.name = name;
  o.region = region;
  c.outlets.push_back(o);
  return c.outlets.back();
}

/// A fill of a box region, uniform radii in [r_min, r_max] (equal: monodisperse); returns the
/// fill for further settings (spacing, count, seed, ...), valid until the next push_back.
inline config::Fill& add_box_fill(config::Case& c, const std::string& material, double r_min,
                                  double r_max, Vec3 lo, Vec3 hi, config::Fill::Lattice lattice) {
  config::ParticleGroup g;
  g.material = material;
  if (r_min == r_max) {
    g.radius.value = r_min;
  } else {
    g.radius.kind = config::SizeDistribution::Kind::Uniform;
    g.radius.min = r_min;
    g.radius.max = r_max;
  }
  config::Fill f;
  f.region.kind = config::Region::Kind::Box;
  f.region.min = lo;
  f.region.max = hi;
  f.lattice = lattice;
  g.fill = f;
  c.particles.push_back(g);
  return *c.particles.back().fill;
}

inline void add_box(config::Case& c, const std::string& name, Vec3 lo, Vec3 hi,
                    std::vector<std::string> open, const std::string& material) {
  config::Wall w;
  w.name = name;
  w.kind = config::Wall::Kind::Box;
  w.min = lo;
  w.max = hi;
  w.open = std::move(open);
  w.material = material;
  c.walls.push_back(w);
}

/// A box fill of spherocylinders of cap radius r and aspect ratio (tip-to-tip length over
/// diameter) `aspect`.
inline config::Fill& add_capsule_fill(config::Case& c, const std::string& material, double radius,
                                      double aspect, Vec3 lo, Vec3 hi,
                                      config::Fill::Lattice lattice) {
  config::Fill& f = add_box_fill(c, material, radius, radius, lo, hi, lattice);
  config::ParticleGroup& g = c.particles.back();
  g.kind = config::Shape::Spherocylinder;
  g.shape = "spherocylinder";
  g.aspect_ratio = aspect;
  return f;
}

/// Explicit spherocylinders of cap radius r and cylinder length L; `q` one orientation each
/// (body axis e_z), empty = identity.
inline config::ParticleGroup& add_capsules(config::Case& c, const std::string& material,
                                           double radius, double length, std::vector<Vec3> x,
                                           std::vector<Quat> q = {}, std::vector<Vec3> v = {},
                                           std::vector<Vec3> w = {}) {
  add_spheres(c, material, radius, std::move(x), std::move(v), std::move(w));
  config::ParticleGroup& g = c.particles.back();
  g.shape = "spherocylinder";
  g.kind = config::Shape::Spherocylinder;
  g.length = length;
  g.explicit_particles->orientations = std::move(q);
  return g;
}

/// Explicit 2D polygons: regular n-gons of equal-area radius r (a 2D case: dimension 2).
inline config::ParticleGroup& add_polygons(config::Case& c, const std::string& material,
                                           double radius, int sides, std::vector<Vec3> x,
                                           std::vector<Quat> q = {}, std::vector<Vec3> v = {},
                                           std::vector<Vec3> w = {}) {
  add_spheres(c, material, radius, std::move(x), std::move(v), std::move(w));
  config::ParticleGroup& g = c.particles.back();
  g.shape = "polygon";
  g.kind = config::Shape::Polygon;
  g.polygon.kind = config::PolygonSpec::Kind::Regular;
  g.polygon.sides = sides;
  g.explicit_particles->orientations = std::move(q);
  return g;
}

/// Explicit 2D disks.
inline config::ParticleGroup& add_disks(config::Case& c, const std::string& material, double radius,
                                        std::vector<Vec3> x, std::vector<Vec3> v = {}) {
  add_spheres(c, material, radius, std::move(x), std::move(v));
  config::ParticleGroup& g = c.particles.back();
  g.shape = "disk";
  g.kind = config::Shape::Disk;
  return g;
}

/// A rough base: explicit spheres of radius r on a square lattice of spacing `spacing` (>= 2r)
/// with centres at height z, as many rows as fit in x in [lo_x, hi_x] and y in [lo_y, hi_y]
/// (centres at lo + (k + 1/2) spacing), in one group with fixed: true. Returns the group.
inline config::ParticleGroup& add_fixed_sphere_layer(config::Case& c, const std::string& material,
                                                     double radius, double spacing, double lo_x,
                                                     double hi_x, double lo_y, double hi_y,
                                                     double z) {
  const int nx = static_cast<int>((hi_x - lo_x) / spacing + 1e-9);
  const int ny = static_cast<int>((hi_y - lo_y) / spacing + 1e-9);
  std::vector<Vec3> x;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      x.push_back({lo_x + (i + 0.5) * spacing, lo_y + (j + 0.5) * spacing, z});
  add_spheres(c, material, radius, std::move(x));
  config::ParticleGroup& g = c.particles.back();
  g.fixed = true;
  return g;
}

/// A cube of side L between Lees-Edwards images (flow x, gradient z) sheared at `rate` 1/s, dt
/// 1e-6 s, with the frictionless material of Mahajan et al.'s shear boxes ("pom": 1400 kg/m^3,
/// Hooke k_n = 6e5 N/m, e = 0.7) and no grains yet.
inline config::Case lees_edwards_box(double L, double rate) {
  auto c = base_case(1e-6, 1.0, {0, 0, 0}, {L, L, L}, {true, true, true});
  add_material(c, "pom", 1400, 1e7, 0.3);
  add_contact(c, "pom", "pom", "hooke",
              {{"stiffness", 6e5}, {"restitution", 0.7}, {"friction", 0.0}});
  c.shear = config::Shear{};
  c.shear->rate = rate;
  c.shear->boundary = config::Shear::Boundary::LeesEdwards;
  return c;
}

/// Rods of aspect ratio 4 (cap radius 1.5 mm) of material "pom" filling the whole box at volume
/// fraction phi, aligned with x on a lattice of their own extents, with a random velocity kick.
inline config::Fill& add_aligned_rods(config::Case& c, double phi, std::uint64_t seed,
                                      double velocity_jitter) {
  auto& f = add_capsule_fill(c, "pom", 0.0015, 4.0, c.domain.min, c.domain.max,
                             config::Fill::Lattice::Cubic);
  f.volume_fraction = phi;
  f.orientation = quat_from_axis_angle({0, 1, 0}, 1.5707963267948966);  // e_z -> e_x
  f.seed = seed;
  f.velocity_jitter = velocity_jitter;
  return f;
}

}  // namespace gf::test
