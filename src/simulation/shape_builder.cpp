// SPDX-License-Identifier: GPL-3.0-or-later
// Grains of every shape: masses and moments of inertia from the shape's geometry.
#include "simulation/shape_builder.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "contact/geometry/polygon2d.hpp"
#include "core/error.hpp"
#include "io/input/validate.hpp"

namespace gf {

namespace {

using config::Shape;
constexpr double kPi = std::numbers::pi;

/// Half length of the cylindrical part of a spherocylinder of cap radius r.
double half_length_of(const config::ParticleGroup& g, double r) {
  return 0.5 * input::cylinder_length(g, r);
}

PolygonShape shape_of(const ConvexPolygon& outline) {
  PolygonShape s;
  const contact::PolygonProperties pr = contact::polygon_properties(outline);
  s.body = outline;
  for (int k = 0; k < outline.n; ++k) s.body.v[k] = outline.v[k] - pr.centroid;
  s.area = pr.area;
  s.equivalent_radius = pr.equivalent_radius;
  s.polar_moment = pr.polar_moment;
  for (int k = 0; k < outline.n; ++k) s.circumradius = std::max(s.circumradius, norm(s.body.v[k]));
  return s;
}

ConvexPolygon given_outline(const config::PolygonSpec& spec) {
  ConvexPolygon p;
  p.n = static_cast<int>(spec.vertices.size());
  for (int k = 0; k < p.n; ++k)
    p.v[k] = {spec.vertices[static_cast<std::size_t>(k)].x,
              spec.vertices[static_cast<std::size_t>(k)].y};
  return p;
}

}  // namespace

ShapeBuilder::ShapeBuilder(const config::ParticleGroup& group, double density, double thickness,
                           std::uint64_t seed)
    : g_(group), density_(density), thickness_(thickness), poly_rng_(seed ^ 0x9e3779b97f4a7c15ull) {
  const double r_max = g_.radius.largest();
  switch (g_.kind) {
    case Shape::Sphere:
    case Shape::Disk:
      placement_radius_ = r_max;
      break;
    case Shape::Spherocylinder:
      placement_radius_ = r_max + half_length_of(g_, r_max);
      break;
    case Shape::Polygon:
      switch (g_.polygon.kind) {
        case config::PolygonSpec::Kind::Vertices:
          placement_radius_ = shape_of(given_outline(g_.polygon)).circumradius;
          break;
        case config::PolygonSpec::Kind::Regular:
          circum_factor_ = input::polygon_reach_factor(g_.polygon);
          placement_radius_ = circum_factor_ * r_max;
          break;
        case config::PolygonSpec::Kind::Random:
          // The bound that `grainflow check` reports (a sample of the generator, plus 5 %);
          // make_polygon() redraws the rare outline beyond it, so it holds for every grain.
          circum_factor_ = input::polygon_reach_factor(g_.polygon);
          placement_radius_ = circum_factor_ * r_max;
          break;
      }
      break;
  }
}

Quat ShapeBuilder::random_orientation(Rng& rng, bool two_d) {
  if (two_d) return turn_about_z(Quat{}, rng.uniform(0.0, 2 * kPi));
  for (;;) {
    const Quat q{rng.normal(0, 1), rng.normal(0, 1), rng.normal(0, 1), rng.normal(0, 1)};
    if (norm2(q) > 1e-12) return normalized(q);
  }
}

std::int32_t ShapeBuilder::make_polygon(ParticleStore& p, double radius) {
  auto& table = p.polygons();
  if (shared_polygon_ >= 0) return shared_polygon_;
  ConvexPolygon outline;
  bool shared = false;
  switch (g_.polygon.kind) {
    case config::PolygonSpec::Kind::Vertices:
      outline = given_outline(g_.polygon);
      shared = true;
      break;
    case config::PolygonSpec::Kind::Regular:
      outline = contact::regular_polygon(g_.polygon.sides, circum_factor_ * radius);
      shared = g_.radius.kind == config::SizeDistribution::Kind::Fixed;
      break;
    case config::PolygonSpec::Kind::Random: {
      std::uniform_int_distribution<int> nv(g_.polygon.min_vertices, g_.polygon.max_vertices);
      std::uniform_real_distribution<double> el(g_.polygon.min_elongation,
                                                g_.polygon.max_elongation);
      for (int attempt = 0;; ++attempt) {
        const int n = nv(poly_rng_);
        const double e = el(poly_rng_);
        outline = contact::random_convex_polygon(poly_rng_, n, radius, e);
        if (shape_of(outline).circumradius <= circum_factor_ * radius) break;
        REQUIRE(attempt < 10000, "random polygon outlines exceed their size bound");
      }
      break;
    }
  }
  table.push_back(shape_of(outline));
  const auto idx = static_cast<std::int32_t>(table.size() - 1);
  if (shared) shared_polygon_ = idx;
  return idx;
}

std::size_t ShapeBuilder::add(ParticleStore& p, std::int64_t id, int material, double radius,
                              const Vec3& x, const Vec3& v, const Vec3& omega, const Quat& q) {
  const std::size_t i = add_body(p, id, material, radius, x, v, omega, q);
  if (const int f = p.find_field("temperature"); f >= 0) p.get<double>(f)[i] = temperature_;
  if (const int f = p.find_field("heat_source"); f >= 0) p.get<double>(f)[i] = heat_source_;
  return i;
}

std::size_t ShapeBuilder::add_body(ParticleStore& p, std::int64_t id, int material, double radius,
                                   const Vec3& x, const Vec3& v, const Vec3& omega, const Quat& q) {
  const double rho = density_;
  switch (g_.kind) {
    case Shape::Sphere: {
      const std::size_t i = p.add_sphere(id, material, radius, rho, x, v, omega);
      return i;
    }
    case Shape::Disk: {
      const std::size_t i = p.add_sphere(id, material, radius, rho, x, v, omega);
      const double m = rho * kPi * radius * radius * thickness_;
      p.mass()[i] = m;
      p.inertia()[i] = 0.5 * m * radius * radius;
      if (p.has_shapes()) p.shape()[i] = static_cast<std::int32_t>(ShapeCode::Disk);
      return i;
    }
    case Shape::Spherocylinder: {
      const double r = radius, h = half_length_of(g_, r), len = 2 * h;
      const std::size_t i = p.add_sphere(id, material, r + h, rho, x, v, omega);
      // Cylinder of length L plus a sphere split into two caps at the ends.
      const double m_cyl = rho * kPi * r * r * len, m_sph = rho * 4.0 / 3.0 * kPi * r * r * r;
      const double i_axis = 0.5 * m_cyl * r * r + 0.4 * m_sph * r * r;
      const double i_perp = m_cyl * (len * len / 12 + r * r / 4) +
                            m_sph * (0.4 * r * r + len * len / 4 + 3 * len * r / 8);
      p.mass()[i] = m_cyl + m_sph;
      p.inertia()[i] = i_perp;
      p.shape()[i] = static_cast<std::int32_t>(ShapeCode::Spherocylinder);
      p.half_length()[i] = h;
      p.orientation()[i] = q;
      p.inertia_body()[i] = {i_perp, i_perp, i_axis};
      return i;
    }
    case Shape::Polygon: {
      const std::int32_t k = make_polygon(p, radius);
      const PolygonShape& s = p.polygons()[static_cast<std::size_t>(k)];
      const std::size_t i = p.add_sphere(id, material, s.circumradius, rho, x, v, omega);
      p.mass()[i] = rho * s.area * thickness_;
      p.inertia()[i] = rho * s.polar_moment * thickness_;
      p.shape()[i] = static_cast<std::int32_t>(ShapeCode::Polygon);
      p.polygon()[i] = k;
      p.orientation()[i] = q;
      const double iz = p.inertia()[i];
      p.inertia_body()[i] = {iz, iz, iz};
      return i;
    }
  }
  return 0;
}

}  // namespace gf
