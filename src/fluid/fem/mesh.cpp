// SPDX-License-Identifier: GPL-3.0-or-later
// Mesh utilities that do not need CGAL (kept out of mesh_cgal.cpp to keep rebuilds cheap).
#include "fluid/fem/mesh.hpp"

#include <cmath>
#include <numbers>

#include "fluid/fem/p2_element.hpp"

namespace gf::fem {

double mesh_area(const Mesh& mesh) {
  const p2::Quadrature7 rule;
  double area = 0;
  for (const auto& cell : mesh.cells) {
    std::array<Vec2, 6> x;
    for (int k = 0; k < 6; ++k) x[k] = mesh.nodes[cell[k]];
    for (int q = 0; q < rule.n; ++q) {
      double phi[6], gx[6], gy[6];
      area += rule.w[q] * p2::gradients(x, rule.xi[q], rule.eta[q], phi, gx, gy);
    }
  }
  return area;
}

BodyGeometry body_geometry(const BodyShape& b) {
  BodyGeometry g;
  if (b.kind == BodyShape::Kind::Circle) {
    g.area = std::numbers::pi * b.radius * b.radius;
    g.centroid = b.centre;
    g.polar_moment = 0.5 * g.area * b.radius * b.radius;
    return g;
  }
  // Green's theorem over the edges, relative to the first vertex (round-off)
  const Vec2 o = b.vertices[0];
  const std::size_t n = b.vertices.size();
  double a2 = 0, cx = 0, cy = 0, j = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 p{b.vertices[i].x - o.x, b.vertices[i].y - o.y};
    const Vec2 q{b.vertices[(i + 1) % n].x - o.x, b.vertices[(i + 1) % n].y - o.y};
    const double cr = p.x * q.y - q.x * p.y;
    a2 += cr;
    cx += (p.x + q.x) * cr;
    cy += (p.y + q.y) * cr;
    j += cr * (p.x * p.x + p.x * q.x + q.x * q.x + p.y * p.y + p.y * q.y + q.y * q.y);
  }
  cx /= 3.0 * a2;
  cy /= 3.0 * a2;
  const double area = 0.5 * a2;  // signed like j
  g.area = std::abs(area);
  g.centroid = {o.x + cx, o.y + cy};
  g.polar_moment = std::abs(j / 12.0 - area * (cx * cx + cy * cy));  // parallel axes
  return g;
}

bool inside_polygon(Vec2 p, const std::vector<Vec2>& v) {
  bool in = false;
  for (std::size_t i = 0, j = v.size() - 1; i < v.size(); j = i++)
    if ((v[i].y > p.y) != (v[j].y > p.y) &&
        p.x < (v[j].x - v[i].x) * (p.y - v[i].y) / (v[j].y - v[i].y) + v[i].x)
      in = !in;
  return in;
}

}  // namespace gf::fem
