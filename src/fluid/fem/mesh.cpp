// SPDX-License-Identifier: GPL-3.0-or-later
// Mesh utilities that do not need CGAL (kept out of mesh_cgal.cpp to keep rebuilds cheap).
#include "fluid/fem/mesh.hpp"

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

bool inside_polygon(Vec2 p, const std::vector<Vec2>& v) {
  bool in = false;
  for (std::size_t i = 0, j = v.size() - 1; i < v.size(); j = i++)
    if ((v[i].y > p.y) != (v[j].y > p.y) &&
        p.x < (v[j].x - v[i].x) * (p.y - v[i].y) / (v[j].y - v[i].y) + v[i].x)
      in = !in;
  return in;
}

}  // namespace gf::fem
