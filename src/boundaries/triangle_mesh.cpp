// SPDX-License-Identifier: GPL-3.0-or-later
// Triangle surfaces as walls: topology, closest points, contact ownership, the triangle grid.
#include "boundaries/triangle_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

namespace gf {

TriangleFeature closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                    Vec3& q) {
  // Regions of the plane of the triangle, tested in turn with the projections of p - (a, b, c)
  // on the edge vectors ab and ac (the barycentric coordinates of the projection of p, unscaled).
  const Vec3 ab = b - a, ac = c - a;
  const Vec3 ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) {
    q = a;
    return TriangleFeature::Vertex0;
  }
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) {
    q = b;
    return TriangleFeature::Vertex1;
  }
  const double vc = d1 * d4 - d3 * d2;  // area coordinate of c, scaled
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double s = d1 - d3 > 0 ? d1 / (d1 - d3) : 0.0;
    q = a + s * ab;
    return TriangleFeature::Edge0;
  }
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) {
    q = c;
    return TriangleFeature::Vertex2;
  }
  const double vb = d5 * d2 - d1 * d6;  // area coordinate of b, scaled
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double s = d2 - d6 > 0 ? d2 / (d2 - d6) : 0.0;
    q = a + s * ac;
    return TriangleFeature::Edge2;
  }
  const double va = d3 * d6 - d5 * d4;  // area coordinate of a, scaled
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double den = (d4 - d3) + (d5 - d6);
    const double s = den > 0 ? (d4 - d3) / den : 0.0;
    q = b + s * (c - b);
    return TriangleFeature::Edge1;
  }
  const double sum = va + vb + vc;
  if (!(sum > 0)) {  // degenerate (collinear) triangle that escaped the edge tests
    q = a;
    return TriangleFeature::Vertex0;
  }
  q = a + (vb / sum) * ab + (vc / sum) * ac;
  return TriangleFeature::Face;
}

namespace {

/// Merges vertices closer than `tol` (cells of size tol, the 27 around each point searched):
/// returns the new index of each old vertex and leaves the kept ones in `points`, in order.
std::vector<int> merge_close_points(std::vector<Vec3>& points, double tol) {
  std::vector<int> map(points.size());
  std::map<std::array<std::int64_t, 3>, std::vector<int>> cells;
  std::vector<Vec3> kept;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Vec3& p = points[k];
    const std::array<std::int64_t, 3> c{static_cast<std::int64_t>(std::floor(p.x / tol)),
                                        static_cast<std::int64_t>(std::floor(p.y / tol)),
                                        static_cast<std::int64_t>(std::floor(p.z / tol))};
    int found = -1;
    for (int dz = -1; dz <= 1 && found < 0; ++dz)
      for (int dy = -1; dy <= 1 && found < 0; ++dy)
        for (int dx = -1; dx <= 1 && found < 0; ++dx) {
          const auto it = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == cells.end()) continue;
          for (const int q : it->second)
            if (norm(kept[static_cast<std::size_t>(q)] - p) <= tol) {
              found = q;
              break;
            }
        }
    if (found < 0) {
      found = static_cast<int>(kept.size());
      kept.push_back(p);
      cells[c].push_back(found);
    }
    map[k] = found;
  }
  points = std::move(kept);
  return map;
}

}  // namespace

TriangleMesh::TriangleMesh(std::vector<Vec3> points, std::vector<std::array<int, 3>> triangles)
    : points0_(std::move(points)), tris_(std::move(triangles)) {
  const auto nv = static_cast<std::int64_t>(points0_.size());
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    const auto& tr = tris_[t];
    for (int k = 0; k < 3; ++k)
      if (tr[k] < 0 || tr[k] >= nv)
        throw std::invalid_argument("triangle " + std::to_string(t) + " has vertex index " +
                                    std::to_string(tr[k]) + " out of range [0, " +
                                    std::to_string(nv) + ")");
    if (tr[0] == tr[1] || tr[1] == tr[2] || tr[0] == tr[2])
      throw std::invalid_argument("triangle " + std::to_string(t) + " repeats a vertex");
  }
  // Triangles that share an edge must share its vertices for the contact ownership to see it:
  // vertices within 1e-9 of the surface's size are one (STL files repeat every vertex per
  // triangle; exporters round differently). A triangle that collapses is an error.
  if (!points0_.empty()) {
    Vec3 lo = points0_[0], hi = points0_[0];
    for (const auto& p : points0_)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    const double tol = 1e-9 * std::max(norm(hi - lo), 1e-300);
    const std::vector<int> map = merge_close_points(points0_, tol);
    for (std::size_t t = 0; t < tris_.size(); ++t) {
      auto& tr = tris_[t];
      for (int k = 0; k < 3; ++k) tr[k] = map[static_cast<std::size_t>(tr[k])];
      if (tr[0] == tr[1] || tr[1] == tr[2] || tr[0] == tr[2])
        throw std::invalid_argument("triangle " + std::to_string(t) +
                                    " has two vertices closer than 1e-9 of the surface's size");
    }
  }
  points_ = points0_;
  lo0_ = hi0_ = points0_.empty() ? Vec3{} : points0_[0];
  for (const auto& p : points0_)
    for (int k = 0; k < 3; ++k) {
      lo0_[k] = std::min(lo0_[k], p[k]);
      hi0_[k] = std::max(hi0_[k], p[k]);
    }
  // Edges: (smaller vertex, larger vertex, triangle, edge), sorted so that the triangles of an
  // edge are adjacent.
  struct EdgeUse {
    int u, v;
    std::int32_t tri;
    int k;
  };
  std::vector<EdgeUse> uses;
  uses.reserve(3 * tris_.size());
  for (std::size_t t = 0; t < tris_.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int u = tris_[t][k], v = tris_[t][(k + 1) % 3];
      uses.push_back({std::min(u, v), std::max(u, v), static_cast<std::int32_t>(t), k});
    }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return x.u != y.u ? x.u < y.u : (x.v != y.v ? x.v < y.v : x.tri < y.tri);
  });
  std::vector<std::vector<std::int32_t>> across(3 * tris_.size());
  for (std::size_t s = 0; s < uses.size();) {
    std::size_t e = s;
    while (e < uses.size() && uses[e].u == uses[s].u && uses[e].v == uses[s].v) ++e;
    if (e - s == 1) ++boundary_edges_;
    if (e - s > 2) ++nonmanifold_edges_;
    for (std::size_t a = s; a < e; ++a)
      for (std::size_t b = s; b < e; ++b)
        if (a != b)
          across[3 * static_cast<std::size_t>(uses[a].tri) + static_cast<std::size_t>(uses[a].k)]
              .push_back(uses[b].tri);
    s = e;
  }
  edge_start_.assign(1, 0);
  for (const auto& list : across) {
    edge_tris_.insert(edge_tris_.end(), list.begin(), list.end());
    edge_start_.push_back(static_cast<std::int32_t>(edge_tris_.size()));
  }
  std::vector<std::int32_t> count(points0_.size() + 1, 0);
  for (const auto& tr : tris_)
    for (int k = 0; k < 3; ++k) ++count[static_cast<std::size_t>(tr[k]) + 1];
  vertex_start_.assign(points0_.size() + 1, 0);
  for (std::size_t v = 0; v < points0_.size(); ++v)
    vertex_start_[v + 1] = vertex_start_[v] + count[v + 1];
  vertex_tris_.assign(static_cast<std::size_t>(vertex_start_.back()), 0);
  std::vector<std::int32_t> fill(vertex_start_.begin(), vertex_start_.end() - 1);
  for (std::size_t t = 0; t < tris_.size(); ++t)
    for (int k = 0; k < 3; ++k)
      vertex_tris_[static_cast<std::size_t>(fill[static_cast<std::size_t>(tris_[t][k])]++)] =
          static_cast<std::int32_t>(t);
}

double TriangleMesh::radius_about(const Vec3& c) const {
  double r = 0;
  for (const auto& p : points0_) r = std::max(r, norm(p - c));
  return r;
}

void TriangleMesh::place(const RigidMotion& motion, double t) {
  const bool at_rest = motion.rate == 0 && motion.velocity == Vec3{};
  if (at_rest) return;
  for (std::size_t k = 0; k < points0_.size(); ++k) points_[k] = motion.point_at(points0_[k], t);
  indexed_reach_ = -1;  // the grid follows the vertices
}

double TriangleMesh::distance(std::int32_t tri, const Vec3& x) const {
  const auto& tr = tris_[static_cast<std::size_t>(tri)];
  Vec3 q;
  closest_on_triangle(x, points_[static_cast<std::size_t>(tr[0])],
                      points_[static_cast<std::size_t>(tr[1])],
                      points_[static_cast<std::size_t>(tr[2])], q);
  return norm(x - q);
}

bool TriangleMesh::owns(std::int32_t tri, TriangleFeature f, const Vec3& d) const {
  if (f == TriangleFeature::Face) return true;
  // A neighbour "ties" when it has no point closer than q (its own closest point is q, up to
  // rounding); the lowest index among the tied triangles takes the contact.
  const double tol = 1e-9 * norm(d);
  const auto& tr = tris_[static_cast<std::size_t>(tri)];
  const auto P = [&](int v) -> const Vec3& { return points_[static_cast<std::size_t>(v)]; };
  if (f <= TriangleFeature::Edge2) {
    const int k = static_cast<int>(f) - static_cast<int>(TriangleFeature::Edge0);
    const int u = tr[k], v = tr[(k + 1) % 3];
    const Vec3 e = normalized(P(v) - P(u));
    const auto slot = static_cast<std::size_t>(3 * tri + k);
    for (std::int32_t s = edge_start_[slot]; s < edge_start_[slot + 1]; ++s) {
      const std::int32_t other = edge_tris_[static_cast<std::size_t>(s)];
      const auto& to = tris_[static_cast<std::size_t>(other)];
      const int w = to[0] != u && to[0] != v ? to[0] : (to[1] != u && to[1] != v ? to[1] : to[2]);
      Vec3 in = P(w) - P(u);
      in = in - dot(in, e) * e;  // into the other triangle, normal to the edge
      const double len = norm(in);
      if (!(len > 0)) continue;  // a degenerate neighbour has no interior
      const double s_in = dot(in, d) / len;
      if (s_in > tol || other < tri) return false;
    }
    return true;
  }
  const int vtx = tr[static_cast<int>(f) - static_cast<int>(TriangleFeature::Vertex0)];
  const Vec3& pv = P(vtx);
  for (std::int32_t s = vertex_start_[static_cast<std::size_t>(vtx)];
       s < vertex_start_[static_cast<std::size_t>(vtx) + 1]; ++s) {
    const std::int32_t other = vertex_tris_[static_cast<std::size_t>(s)];
    if (other == tri) continue;
    const auto& to = tris_[static_cast<std::size_t>(other)];
    double s_in = -1e300;
    for (int k = 0; k < 3; ++k) {
      if (to[k] == vtx) continue;
      const Vec3 e = P(to[k]) - pv;
      const double len = norm(e);
      if (len > 0) s_in = std::max(s_in, dot(e, d) / len);
    }
    if (s_in > tol || other < tri) return false;
  }
  return true;
}

bool TriangleMesh::sphere_contact(std::int32_t tri, const Vec3& x, double r, Vec3& normal,
                                  double& gap) const {
  const auto& tr = tris_[static_cast<std::size_t>(tri)];
  const Vec3& a = points_[static_cast<std::size_t>(tr[0])];
  const Vec3& b = points_[static_cast<std::size_t>(tr[1])];
  const Vec3& c = points_[static_cast<std::size_t>(tr[2])];
  Vec3 q;
  const TriangleFeature f = closest_on_triangle(x, a, b, c, q);
  const Vec3 d = x - q;
  const double dist = norm(d);
  if (dist >= r) return false;
  if (!owns(tri, f, d)) return false;
  if (dist > 0) {
    normal = (1.0 / dist) * d;
  } else {  // the centre on the surface: either side of the face
    const Vec3 n = cross(b - a, c - a);
    const double len = norm(n);
    normal = len > 0 ? (1.0 / len) * n : Vec3{0, 0, 1};
  }
  gap = dist - r;
  return true;
}

std::uint64_t TriangleMesh::cell_key(const Vec3& x) const {
  std::uint64_t key = 0;
  for (int k = 2; k >= 0; --k) {
    const double s = std::floor((x[k] - origin_[k]) / h_);
    if (!(s >= 0) || s >= static_cast<double>(cells_[static_cast<std::size_t>(k)]))
      return std::numeric_limits<std::uint64_t>::max();
    key = key * static_cast<std::uint64_t>(cells_[static_cast<std::size_t>(k)]) +
          static_cast<std::uint64_t>(s);
  }
  return key;
}

void TriangleMesh::index(double reach) const {
  if (reach == indexed_reach_) return;
  indexed_reach_ = reach;
  keys_.clear();
  cell_start_.assign(1, 0);
  cell_tris_.clear();
  if (tris_.empty()) return;
  Vec3 lo = points_[0], hi = points_[0];
  for (const auto& p : points_)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  // Cells at least twice the reach and at least the mean triangle extent, so that a triangle
  // spans a few cells; at most 2^20 per direction.
  double extent = 0;
  for (const auto& tr : tris_) {
    double e = 0;
    for (int k = 0; k < 3; ++k) {
      const Vec3& p0 = points_[static_cast<std::size_t>(tr[0])];
      e = std::max(e, norm(points_[static_cast<std::size_t>(tr[k])] - p0));
    }
    extent += e;
  }
  extent /= static_cast<double>(tris_.size());
  const double span = norm(hi - lo) + 2 * reach;
  h_ = std::max({2 * reach, extent, span * 1e-6, 1e-12});
  for (int k = 0; k < 3; ++k) {
    origin_[k] = lo[k] - reach - 1e-3 * h_;
    const double n = std::floor((hi[k] + reach + 1e-3 * h_ - origin_[k]) / h_) + 1;
    h_ = std::max(h_, (hi[k] - lo[k] + 2 * reach) / double(1 << 20));
    cells_[static_cast<std::size_t>(k)] = static_cast<std::int64_t>(n);
  }
  for (int k = 0; k < 3; ++k)  // again with the final h
    cells_[static_cast<std::size_t>(k)] =
        static_cast<std::int64_t>(std::floor((hi[k] + reach + 1e-3 * h_ - origin_[k]) / h_)) + 1;
  std::vector<std::pair<std::uint64_t, std::int32_t>> uses;
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    std::array<std::int64_t, 3> c0{}, c1{};
    for (int k = 0; k < 3; ++k) {
      double a = 1e300, b = -1e300;
      for (int v = 0; v < 3; ++v) {
        a = std::min(a, points_[static_cast<std::size_t>(tris_[t][v])][k]);
        b = std::max(b, points_[static_cast<std::size_t>(tris_[t][v])][k]);
      }
      const auto n = cells_[static_cast<std::size_t>(k)];
      c0[static_cast<std::size_t>(k)] = std::clamp<std::int64_t>(
          static_cast<std::int64_t>(std::floor((a - reach - origin_[k]) / h_)), 0, n - 1);
      c1[static_cast<std::size_t>(k)] = std::clamp<std::int64_t>(
          static_cast<std::int64_t>(std::floor((b + reach - origin_[k]) / h_)), 0, n - 1);
    }
    for (std::int64_t iz = c0[2]; iz <= c1[2]; ++iz)
      for (std::int64_t iy = c0[1]; iy <= c1[1]; ++iy)
        for (std::int64_t ix = c0[0]; ix <= c1[0]; ++ix)
          uses.emplace_back(static_cast<std::uint64_t>(ix + cells_[0] * (iy + cells_[1] * iz)),
                            static_cast<std::int32_t>(t));
  }
  std::sort(uses.begin(), uses.end());
  for (std::size_t s = 0; s < uses.size(); ++s) {
    if (s == 0 || uses[s].first != uses[s - 1].first) {
      if (s > 0) cell_start_.push_back(static_cast<std::int64_t>(cell_tris_.size()));
      keys_.push_back(uses[s].first);
    }
    cell_tris_.push_back(uses[s].second);
  }
  cell_start_.push_back(static_cast<std::int64_t>(cell_tris_.size()));
}

std::pair<const std::int32_t*, const std::int32_t*> TriangleMesh::candidates(const Vec3& x) const {
  const std::uint64_t key = cell_key(x);
  const auto it = std::lower_bound(keys_.begin(), keys_.end(), key);
  if (it == keys_.end() || *it != key) return {nullptr, nullptr};
  const auto c = static_cast<std::size_t>(it - keys_.begin());
  return {cell_tris_.data() + cell_start_[c], cell_tris_.data() + cell_start_[c + 1]};
}

}  // namespace gf
