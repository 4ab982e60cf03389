// SPDX-License-Identifier: GPL-3.0-or-later
// Triangle surfaces as walls: topology, closest points, contact ownership, the triangle grid.
#include "boundaries/triangle_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include "contact/geometry/capsule.hpp"

namespace gf {

namespace {

/// The parameter t in [0, 1] of the closest point a + t (b - a) of segment [a, b] to p.
double segment_parameter(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = dot(ab, ab);
  if (!(l2 > 0)) return 0.0;
  const double t = dot(p - a, ab) / l2;
  return t < 0 ? 0.0 : (t > 1 ? 1.0 : t);
}

/// a b - c d to within about one rounding of the result, cancellation or not (Kahan's method:
/// the rounding error of c d recovered with a fused multiply-add).
double kahan_det(double a, double b, double c, double d) {
  const double w = c * d;
  const double e = std::fma(-c, d, w);
  const double f = std::fma(a, b, -w);
  return f + e;
}

/// u x v with every component accurate to rounding: the normal of a thin triangle keeps its
/// direction (a plain cross product loses a factor length / height of it).
Vec3 accurate_cross(const Vec3& u, const Vec3& v) {
  return {kahan_det(u.y, v.z, u.z, v.y), kahan_det(u.z, v.x, u.x, v.z),
          kahan_det(u.x, v.y, u.y, v.x)};
}

/// The closest point q of the three edges of (a, b, c) to p, chosen by the distance from pp (the
/// projection of p on the plane, or p itself): the feature it lies on.
TriangleFeature closest_on_edges(const Vec3& p, const Vec3& pp, const Vec3& a, const Vec3& b,
                                 const Vec3& c, Vec3& q) {
  const Vec3* v[3] = {&a, &b, &c};
  double best = std::numeric_limits<double>::infinity();
  TriangleFeature f = TriangleFeature::Vertex0;
  for (int k = 0; k < 3; ++k) {
    const Vec3& u = *v[k];
    const Vec3& w = *v[(k + 1) % 3];
    const double t = segment_parameter(p, u, w);
    const Vec3 s = t <= 0 ? u : (t >= 1 ? w : u + t * (w - u));
    const Vec3 d = pp - s;
    const double d2 = dot(d, d);
    if (d2 < best) {
      best = d2;
      q = s;
      f = t <= 0   ? static_cast<TriangleFeature>(static_cast<int>(TriangleFeature::Vertex0) + k)
          : t >= 1 ? static_cast<TriangleFeature>(static_cast<int>(TriangleFeature::Vertex0) +
                                                  (k + 1) % 3)
                   : static_cast<TriangleFeature>(static_cast<int>(TriangleFeature::Edge0) + k);
    }
  }
  return f;
}

}  // namespace

TriangleFeature closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                    Vec3& q) {
  // The projection of p on the plane, if it lies strictly inside (left of the three edges seen
  // along the normal; a projection on an edge belongs to the edge). Projecting along the
  // cross-product normal keeps full accuracy for thin triangles, which area coordinates lose.
  const Vec3 n = accurate_cross(b - a, c - a);
  const double n2 = dot(n, n);
  Vec3 pp = p;
  if (n2 > 0) {
    pp = p - (dot(p - a, n) / n2) * n;
    if (dot(cross(b - a, pp - a), n) > 0 && dot(cross(c - b, pp - b), n) > 0 &&
        dot(cross(a - c, pp - c), n) > 0) {
      q = pp;
      return TriangleFeature::Face;
    }
  }
  // Otherwise the closest point of the three edges (also for degenerate triangles), chosen by
  // the in-plane distance from the projection (equal to the distance from p in exact arithmetic;
  // in doubles not swamped by the height of p when p is near an edge seen from afar).
  return closest_on_edges(p, pp, a, b, c, q);
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
    eps_ = 1e-9 * std::max(norm(hi - lo), 1e-300);
    const std::vector<int> map = merge_close_points(points0_, eps_);
    for (std::size_t t = 0; t < tris_.size(); ++t) {
      auto& tr = tris_[t];
      for (int k = 0; k < 3; ++k) tr[k] = map[static_cast<std::size_t>(tr[k])];
      if (tr[0] == tr[1] || tr[1] == tr[2] || tr[0] == tr[2])
        throw std::invalid_argument("triangle " + std::to_string(t) +
                                    " has two vertices closer than 1e-9 of the surface's size");
    }
  }
  // The same triangle twice (STL files have them) would count its contacts twice: kept once.
  {
    std::vector<std::pair<std::array<int, 3>, std::size_t>> keys;
    keys.reserve(tris_.size());
    for (std::size_t t = 0; t < tris_.size(); ++t) {
      auto k = tris_[t];
      std::sort(k.begin(), k.end());
      keys.emplace_back(k, t);
    }
    std::sort(keys.begin(), keys.end());
    std::vector<char> keep(tris_.size(), 1);
    for (std::size_t k = 1; k < keys.size(); ++k)
      if (keys[k].first == keys[k - 1].first) keep[keys[k].second] = 0;
    std::vector<std::array<int, 3>> kept;
    for (std::size_t t = 0; t < tris_.size(); ++t)
      if (keep[t]) kept.push_back(tris_[t]);
    duplicate_triangles_ = tris_.size() - kept.size();
    tris_ = std::move(kept);
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
  for (std::size_t s = 0; s < uses.size();) {
    std::size_t e = s;
    while (e < uses.size() && uses[e].u == uses[s].u && uses[e].v == uses[s].v) ++e;
    if (e - s == 1) ++boundary_edges_;
    if (e - s > 2) ++nonmanifold_edges_;
    s = e;
  }
  // Triangles around each vertex.
  std::vector<std::int32_t> count(points0_.size() + 1, 0);
  for (const auto& tr : tris_)
    for (int k = 0; k < 3; ++k) ++count[static_cast<std::size_t>(tr[k]) + 1];
  std::vector<std::int32_t> vertex_start(points0_.size() + 1, 0);
  for (std::size_t v = 0; v < points0_.size(); ++v)
    vertex_start[v + 1] = vertex_start[v] + count[v + 1];
  std::vector<std::int32_t> vertex_tris(static_cast<std::size_t>(vertex_start.back()), 0);
  std::vector<std::int32_t> fill(vertex_start.begin(), vertex_start.end() - 1);
  for (std::size_t t = 0; t < tris_.size(); ++t)
    for (int k = 0; k < 3; ++k)
      vertex_tris[static_cast<std::size_t>(fill[static_cast<std::size_t>(tris_[t][k])]++)] =
          static_cast<std::int32_t>(t);
  // Unit normals (for the plane test and the closest points) and inverse edge lengths.
  normals0_.resize(tris_.size());
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    const auto& tr = tris_[t];
    const Vec3& a = points0_[static_cast<std::size_t>(tr[0])];
    const Vec3 n = accurate_cross(points0_[static_cast<std::size_t>(tr[1])] - a,
                                  points0_[static_cast<std::size_t>(tr[2])] - a);
    const double len = norm(n);
    normals0_[t] = len > 0 ? (1.0 / len) * n : Vec3{};  // degenerate: no plane test
  }
  normals_ = normals0_;
  // Flat edges and vertices (for spherocylinders, see the header): an edge of exactly two
  // triangles whose planes agree to 1e-3 rad and that lie on either side of it; a vertex whose
  // edges are all flat.
  edge_flat_.assign(3 * tris_.size(), 0);
  flat_partner_.assign(3 * tris_.size(), -1);
  for (std::size_t s = 0; s + 1 < uses.size(); ++s) {
    const EdgeUse& e0 = uses[s];
    const EdgeUse& e1 = uses[s + 1];
    if (e0.u != e1.u || e0.v != e1.v) continue;
    if (s + 2 < uses.size() && uses[s + 2].u == e0.u && uses[s + 2].v == e0.v) continue;
    if (s > 0 && uses[s - 1].u == e0.u && uses[s - 1].v == e0.v) continue;
    const Vec3& na = normals0_[static_cast<std::size_t>(e0.tri)];
    const Vec3& nb = normals0_[static_cast<std::size_t>(e1.tri)];
    if (na == Vec3{} || nb == Vec3{} || norm(cross(na, nb)) > 1e-3) continue;
    const Vec3& u = points0_[static_cast<std::size_t>(e0.u)];
    const Vec3 along = points0_[static_cast<std::size_t>(e0.v)] - u;
    const auto opposite = [&](const EdgeUse& e) {
      return points0_[static_cast<std::size_t>(
          tris_[static_cast<std::size_t>(e.tri)][static_cast<std::size_t>((e.k + 2) % 3)])];
    };
    if (dot(cross(along, opposite(e0) - u), cross(along, opposite(e1) - u)) < 0) {
      const std::size_t a = 3 * static_cast<std::size_t>(e0.tri) + static_cast<std::size_t>(e0.k);
      const std::size_t b = 3 * static_cast<std::size_t>(e1.tri) + static_cast<std::size_t>(e1.k);
      edge_flat_[a] = edge_flat_[b] = 1;
      flat_partner_[a] = e1.tri;
      flat_partner_[b] = e0.tri;
    }
  }
  vertex_flat_.assign(points0_.size(), 1);
  for (std::size_t t = 0; t < tris_.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (edge_flat_[3 * t + static_cast<std::size_t>(k)] == 0)
        vertex_flat_[static_cast<std::size_t>(tris_[t][k])] =
            vertex_flat_[static_cast<std::size_t>(tris_[t][(k + 1) % 3])] = 0;
  inverse_edge_.resize(3 * tris_.size());
  for (std::size_t t = 0; t < tris_.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const double len = norm(points0_[static_cast<std::size_t>(tris_[t][(k + 1) % 3])] -
                              points0_[static_cast<std::size_t>(tris_[t][k])]);
      inverse_edge_[3 * t + static_cast<std::size_t>(k)] = len > 0 ? 1.0 / len : 0.0;
    }
  // Vertices lying on another triangle without being one of its vertices (T-junctions, where
  // a finer part of the mesh meets a coarser one): the triangles around such a vertex touch
  // that triangle although they share no vertex with it.
  std::vector<std::pair<std::int32_t, std::int32_t>> junctions;  // (vertex, triangle)
  if (!tris_.empty()) {
    // (cells of 1/64 of the extent: the reach eps alone would make far too many)
    index(eps_, std::max({hi0_.x - lo0_.x, hi0_.y - lo0_.y, hi0_.z - lo0_.z}) / 64);
    for (std::size_t v = 0; v < points0_.size(); ++v) {
      const auto [lo, hi] = candidates(points0_[v]);
      for (const std::int32_t* t = lo; t != hi; ++t) {
        const auto& tr = tris_[static_cast<std::size_t>(*t)];
        if (tr[0] == static_cast<int>(v) || tr[1] == static_cast<int>(v) ||
            tr[2] == static_cast<int>(v))
          continue;
        if (distance(*t, points0_[v]) <= eps_)
          junctions.emplace_back(static_cast<std::int32_t>(v), *t);
      }
    }
    indexed_reach_ = -1;
  }
  // Touching sets: the triangles sharing a vertex with each triangle, and the junction pairs
  // (flagged: they meet geometrically, whatever vertices they share). Entries 2 o + flag.
  std::vector<std::vector<std::int64_t>> touch(tris_.size());
  for (std::size_t t = 0; t < tris_.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<std::size_t>(tris_[t][k]);
      for (std::int32_t s = vertex_start[v]; s < vertex_start[v + 1]; ++s)
        touch[t].push_back(2 * std::int64_t{vertex_tris[static_cast<std::size_t>(s)]});
    }
  for (const auto& [v, t] : junctions)
    for (std::int32_t s = vertex_start[static_cast<std::size_t>(v)];
         s < vertex_start[static_cast<std::size_t>(v) + 1]; ++s) {
      const std::int32_t around = vertex_tris[static_cast<std::size_t>(s)];
      touch[static_cast<std::size_t>(around)].push_back(2 * std::int64_t{t} + 1);
      touch[static_cast<std::size_t>(t)].push_back(2 * std::int64_t{around} + 1);
    }
  touch_start_.assign(1, 0);
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    auto& list = touch[t];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    for (std::size_t k = 0; k < list.size(); ++k) {
      const auto o = static_cast<std::int32_t>(list[k] / 2);
      if (o == static_cast<std::int32_t>(t)) continue;
      if (k + 1 < list.size() && list[k + 1] / 2 == o) continue;  // the flagged one follows
      touch_tris_.push_back(o);
      touch_junction_.push_back(static_cast<char>(list[k] % 2));
    }
    touch_start_.push_back(static_cast<std::int32_t>(touch_tris_.size()));
  }
  t_junctions_ = junctions.size();
  bound_radius_.resize(tris_.size());
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    const auto& tr = tris_[t];
    const Vec3 c = (1.0 / 3.0) * (points0_[static_cast<std::size_t>(tr[0])] +
                                  points0_[static_cast<std::size_t>(tr[1])] +
                                  points0_[static_cast<std::size_t>(tr[2])]);
    double r = 0;
    for (int k = 0; k < 3; ++k)
      r = std::max(r, norm(points0_[static_cast<std::size_t>(tr[k])] - c));
    bound_radius_[t] = r * (1 + 1e-12) + eps_;  // (rounding of the centroid after motion)
  }
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
  for (std::size_t k = 0; k < normals0_.size(); ++k) normals_[k] = motion.rotate(normals0_[k], t);
  motion_ = motion;  // (the grid stays: it is in the body frame, see body_point)
  t_ = t;
  moving_ = true;
  back_cos_ = std::cos(motion.rate * t);
  back_sin_ = -std::sin(motion.rate * t);
}

double TriangleMesh::distance(std::int32_t tri, const Vec3& x) const {
  Vec3 q;
  closest(tri, x, q);
  return norm(x - q);
}

namespace {

/// Distance from the segment [p0, p1] to the point c (p0 == p1: a point).
double point_segment_distance(const Vec3& c, const Vec3& p0, const Vec3& p1) {
  const Vec3 d = p1 - p0;
  const double dd = norm2(d);
  const double s = dd > 0 ? std::clamp(dot(c - p0, d) / dd, 0.0, 1.0) : 0.0;
  return norm(c - (p0 + s * d));
}

}  // namespace

double TriangleMesh::segment_distance_bound(std::int32_t tri, const Vec3& p0,
                                            const Vec3& p1) const {
  const auto tu = static_cast<std::size_t>(tri);
  const auto& tr = tris_[tu];
  const Vec3& a = points_[static_cast<std::size_t>(tr[0])];
  const Vec3 centroid = (1.0 / 3.0) * (a + points_[static_cast<std::size_t>(tr[1])] +
                                       points_[static_cast<std::size_t>(tr[2])]);
  double bound = point_segment_distance(centroid, p0, p1) - bound_radius_[tu];
  const Vec3& n = normals_[tu];  // zero for a degenerate triangle: no plane bound
  const double h0 = dot(p0 - a, n), h1 = dot(p1 - a, n);
  if ((h0 > 0 && h1 > 0) || (h0 < 0 && h1 < 0))
    bound = std::max(bound, std::min(std::abs(h0), std::abs(h1)));
  // Rounding: the exact distance is computed along other paths (closest points, edge
  // parameters); a relative 1e-12 and eps_ keep the bound below it.
  return bound * (1 - 1e-12) - eps_;
}

double TriangleMesh::distance_bound(std::int32_t tri, const Vec3& x) const {
  // segment_distance_bound for a segment of one point, without the segment's projection (this
  // one runs for every candidate triangle of every grain at each wall-list build).
  const auto tu = static_cast<std::size_t>(tri);
  const auto& tr = tris_[tu];
  const Vec3& a = points_[static_cast<std::size_t>(tr[0])];
  const Vec3 centroid = (1.0 / 3.0) * (a + points_[static_cast<std::size_t>(tr[1])] +
                                       points_[static_cast<std::size_t>(tr[2])]);
  double bound = norm(centroid - x) - bound_radius_[tu];
  const double h = dot(x - a, normals_[tu]);
  if (h != 0) bound = std::max(bound, std::abs(h));
  return bound * (1 - 1e-12) - eps_;
}

double TriangleMesh::segment_distance(std::int32_t tri, const Vec3& p0, const Vec3& p1) const {
  // The least distance is at an end of the segment, between the segment and an edge, or zero
  // where the segment crosses the triangle.
  const auto tu = static_cast<std::size_t>(tri);
  const auto& tr = tris_[tu];
  double d = std::min(distance(tri, p0), distance(tri, p1));
  for (int k = 0; k < 3; ++k) {
    const contact::SegmentClosest sc = contact::closest_points_segments(
        p0, p1, points_[static_cast<std::size_t>(tr[static_cast<std::size_t>(k)])],
        points_[static_cast<std::size_t>(tr[static_cast<std::size_t>((k + 1) % 3)])]);
    d = std::min(d, std::sqrt(sc.dist2));
  }
  const Vec3& n = normals_[tu];
  const Vec3& a = points_[static_cast<std::size_t>(tr[0])];
  const double h0 = dot(p0 - a, n), h1 = dot(p1 - a, n);
  if (n != Vec3{} && ((h0 < 0 && h1 > 0) || (h0 > 0 && h1 < 0))) {
    const Vec3 x = p0 + (h0 / (h0 - h1)) * (p1 - p0);
    Vec3 q;
    if (closest(tri, x, q) == TriangleFeature::Face) return 0;
  }
  return d;
}

TriangleFeature TriangleMesh::closest(std::int32_t tri, const Vec3& x, Vec3& q,
                                      double* margin) const {
  const auto tu = static_cast<std::size_t>(tri);
  const auto& tr = tris_[tu];
  const Vec3& a = points_[static_cast<std::size_t>(tr[0])];
  const Vec3& b = points_[static_cast<std::size_t>(tr[1])];
  const Vec3& c = points_[static_cast<std::size_t>(tr[2])];
  const Vec3& n = normals_[tu];
  if (margin != nullptr) *margin = 0;
  if (n == Vec3{}) return closest_on_triangle(x, a, b, c, q);  // degenerate
  // As closest_on_triangle, with the unit normal computed once: the projection, inside when
  // strictly left of the three edges; then the distance to the nearest edge (the margin: how
  // far inside the face, for the ownership test) from the same signed areas.
  const Vec3 pp = x - dot(x - a, n) * n;
  const double s0 = dot(cross(b - a, pp - a), n);
  const double s1 = dot(cross(c - b, pp - b), n);
  const double s2 = dot(cross(a - c, pp - c), n);
  if (s0 > 0 && s1 > 0 && s2 > 0) {
    q = pp;
    if (margin != nullptr) {
      const double* il = &inverse_edge_[3 * tu];
      *margin = std::min({s0 * il[0], s1 * il[1], s2 * il[2]});
    }
    return TriangleFeature::Face;
  }
  return closest_on_edges(x, pp, a, b, c, q);
}

namespace {

/// 2 for a face point, 1 for an edge point, 0 for a vertex.
int dimension(TriangleFeature f) {
  return f == TriangleFeature::Face ? 2 : (f <= TriangleFeature::Edge2 ? 1 : 0);
}

}  // namespace

bool TriangleMesh::owns(std::int32_t tri, TriangleFeature f, double margin, const Vec3& x,
                        const Vec3& q, bool shared_point) const {
  if (f == TriangleFeature::Face && margin > eps_) return true;
  // q on the boundary of tri (within eps_). Each touching triangle whose closest point q2 could
  // be the same contact (it contains q, or tri contains q2: a symmetric test, so that both see
  // the pair alike) competes: a face-interior q2 takes the contact; otherwise the nearer point
  // (the sign of |x - q|^2 - |x - q2|^2), then a face point before an edge point before a vertex,
  // then the lower index. Every quantity is computed alike from both sides (the difference of
  // squares is evaluated as (q2 - q) . ((x - q) + (x - q2)), exactly antisymmetric and not
  // swamped by the distance), so of two competitors exactly one keeps the contact.
  const int dim = dimension(f);
  const double dist = norm(x - q);
  for (std::int32_t s = touch_start_[static_cast<std::size_t>(tri)];
       s < touch_start_[static_cast<std::size_t>(tri) + 1]; ++s) {
    const std::int32_t other = touch_tris_[static_cast<std::size_t>(s)];
    // Only a triangle that contains q, or whose closest point lies in tri, competes; both lie
    // then in what the two share. A neighbour sharing an edge competes only if q is on that edge
    // (were its closest point on the edge and q elsewhere, q would be nearer: tri contains the
    // edge), one sharing a vertex only if q is that vertex: cheap tests that leave out most of a
    // fan around a vertex. Triangles meeting tri at a T-junction (no shared vertex) are tested
    // in full, after a bounding-sphere check.
    const auto& to = tris_[static_cast<std::size_t>(other)];
    const auto& tt = tris_[static_cast<std::size_t>(tri)];
    int shared[3], n_shared = 0;
    if (touch_junction_[static_cast<std::size_t>(s)] == 0)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          if (tt[i] == to[j]) shared[n_shared++] = tt[i];
    if (n_shared == 1) {
      if (norm(q - points_[static_cast<std::size_t>(shared[0])]) > eps_) continue;
    } else if (n_shared == 2) {
      const Vec3& u = points_[static_cast<std::size_t>(shared[0])];
      const Vec3& w = points_[static_cast<std::size_t>(shared[1])];
      const double t = segment_parameter(q, u, w);
      if (norm(q - (u + t * (w - u))) > eps_) continue;
    } else {
      const Vec3 centroid = (1.0 / 3.0) * (points_[static_cast<std::size_t>(to[0])] +
                                           points_[static_cast<std::size_t>(to[1])] +
                                           points_[static_cast<std::size_t>(to[2])]);
      if (norm(x - centroid) - bound_radius_[static_cast<std::size_t>(other)] > dist + eps_)
        continue;
    }
    Vec3 q2, tmp;
    double margin2 = 0;
    const TriangleFeature f2 = closest(other, x, q2, &margin2);
    closest(other, q, tmp);
    bool competing = norm(q - tmp) <= eps_;
    if (!competing) {
      closest(tri, q2, tmp);
      competing = norm(q2 - tmp) <= eps_;
    }
    if (!competing) continue;
    if (f2 == TriangleFeature::Face && margin2 > eps_) return false;
    const double closer = dot(q2 - q, (x - q) + (x - q2));
    if (!shared_point) {
      if (closer > 4 * eps_ * dist) return false;
      continue;
    }
    if (closer != 0) {
      if (closer > 0) return false;
      continue;
    }
    const int dim2 = dimension(f2);
    if (dim2 != dim ? dim2 > dim : other < tri) return false;
  }
  return true;
}

bool TriangleMesh::sphere_contact(std::int32_t tri, const Vec3& x, double r, Vec3& normal,
                                  double& gap) const {
  // Farther than r from the triangle's plane: apart (most entries of a wall list are).
  const auto tu = static_cast<std::size_t>(tri);
  if (std::abs(dot(x - points_[static_cast<std::size_t>(tris_[tu][0])], normals_[tu])) >=
      r * (1 + 1e-12))
    return false;
  Vec3 q;
  double margin = 0;
  const TriangleFeature f = closest(tri, x, q, &margin);
  const Vec3 d = x - q;
  const double dist = norm(d);
  if (dist >= r) return false;
  if (!owns(tri, f, margin, x, q)) return false;
  if (dist > 0) {
    normal = (1.0 / dist) * d;
  } else {  // the centre on the surface: either side of the face
    const auto& tr = tris_[static_cast<std::size_t>(tri)];
    const Vec3& a = points_[static_cast<std::size_t>(tr[0])];
    const Vec3 n = cross(points_[static_cast<std::size_t>(tr[1])] - a,
                         points_[static_cast<std::size_t>(tr[2])] - a);
    const double len = norm(n);
    normal = len > 0 ? (1.0 / len) * n : Vec3{0, 0, 1};
  }
  gap = dist - r;
  return true;
}

bool TriangleMesh::flat(std::int32_t tri, TriangleFeature f) const {
  const auto tu = static_cast<std::size_t>(tri);
  if (f == TriangleFeature::Face) return true;
  if (f <= TriangleFeature::Edge2)
    return edge_flat_[3 * tu + static_cast<std::size_t>(static_cast<int>(f) - 1)] != 0;
  return vertex_flat_[static_cast<std::size_t>(
             tris_[tu][static_cast<std::size_t>(static_cast<int>(f) - 4)])] != 0;
}

bool TriangleMesh::face_like(std::int32_t tri, const Vec3& x, const Vec3& q) const {
  const Vec3& n = normals_[static_cast<std::size_t>(tri)];
  return n != Vec3{} && norm(cross(x - q, n)) <= 2 * eps_;
}

namespace {

/// Whether the distance from the axis end e to its closest point q does not decrease into the
/// axis (direction `in`), to within a slope of 1e-9 (rounding, and an axis parallel to a ridge).
bool end_is_minimum(const Vec3& e, const Vec3& q, const Vec3& in) {
  return dot(e - q, in) >= -1e-9 * norm(e - q) * norm(in);
}

}  // namespace

bool TriangleMesh::capsule_near(std::int32_t tri, const Vec3& p0, const Vec3& p1, double r) const {
  const auto tu = static_cast<std::size_t>(tri);
  const Vec3& n = normals_[tu];
  if (n == Vec3{}) return true;
  const Vec3& a = points_[static_cast<std::size_t>(tris_[tu][0])];
  const double h0 = dot(p0 - a, n), h1 = dot(p1 - a, n), lim = r * (1 + 1e-12);
  return !((h0 >= lim && h1 >= lim) || (h0 <= -lim && h1 <= -lim));
}

Vec3 TriangleMesh::edge_out(std::int32_t tri, int k) const {
  const auto tu = static_cast<std::size_t>(tri);
  const auto& tr = tris_[tu];
  const auto ku = static_cast<std::size_t>(k);
  const Vec3& u0 = points_[static_cast<std::size_t>(tr[ku])];
  Vec3 out = cross(points_[static_cast<std::size_t>(tr[(ku + 1) % 3])] - u0, normals_[tu]);
  if (dot(out, points_[static_cast<std::size_t>(tr[(ku + 2) % 3])] - u0) > 0) out = -1.0 * out;
  return out;
}

double TriangleMesh::flat_run(std::int32_t tri, const Vec3& p0, const Vec3& axis, double s, int dir,
                              double cap) const {
  const double len = norm(axis);
  const double end = dir > 0 ? 1.0 : 0.0;
  double run = 0;
  for (int walk = 0; walk < 64 && tri >= 0; ++walk) {
    const auto tu = static_cast<std::size_t>(tri);
    if (normals_[tu] == Vec3{}) return run;
    // The first side of the prism the axis crosses going on (a convex prism: the nearest).
    int k_exit = -1;
    double s_exit = end;
    for (int k = 0; k < 3; ++k) {
      const Vec3 out = edge_out(tri, k);
      const double den = dot(axis, out);
      if (!(dir * den > 0)) continue;
      const Vec3& u0 = points_[static_cast<std::size_t>(tris_[tu][static_cast<std::size_t>(k)])];
      const double sk = dot(u0 - p0, out) / den;
      if (dir * sk < dir * s_exit) {
        s_exit = sk;
        k_exit = k;
      }
    }
    run += std::max(0.0, dir * (s_exit - s)) * len;
    if (run >= cap || k_exit < 0) return std::min(run, cap);  // (k_exit < 0: the axis ends here)
    s = s_exit;
    tri = flat_partner_[3 * tu + static_cast<std::size_t>(k_exit)];  // -1: not flat, stop
  }
  return std::min(run, cap);
}

TriangleMesh::EdgeExit TriangleMesh::edge_exit(std::int32_t tri, int k, const Vec3& p0,
                                               const Vec3& axis) const {
  EdgeExit e;
  const auto tu = static_cast<std::size_t>(tri);
  const Vec3& n = normals_[tu];
  if (n == Vec3{}) return e;
  const auto& tr = tris_[tu];
  const auto ku = static_cast<std::size_t>(k);
  const Vec3& u0 = points_[static_cast<std::size_t>(tr[ku])];
  const Vec3 out = edge_out(tri, k);
  const double den = dot(axis, out);
  if (den == 0) return e;
  e.s = dot(u0 - p0, out) / den;
  const double h = dot(p0 + e.s * axis - u0, n);
  e.leaves = e.s > 0 && e.s < 1;
  e.rising = h * den >= 0 ? dot(axis, n) >= 0 : dot(axis, n) <= 0;
  e.inward = den > 0 ? -1 : 1;
  return e;
}

bool TriangleMesh::capsule_contact(std::int32_t tri, int slot, const Vec3& p0, const Vec3& p1,
                                   double r, Vec3& centre, Vec3& normal, double& gap,
                                   double& weight) const {
  const auto tu = static_cast<std::size_t>(tri);
  const auto& tr = tris_[tu];
  const Vec3& n = normals_[tu];
  weight = 1;
  if (!capsule_near(tri, p0, p1, r)) return false;
  const Vec3 axis = p1 - p0;
  if (!(norm2(axis) > 0)) {  // a sphere: its one end
    if (slot != 0) return false;
    centre = p0;
    return sphere_contact(tri, centre, r, normal, gap);
  }
  if (slot < 2) {  // an end sphere
    centre = slot == 0 ? p0 : p1;
    if (!sphere_contact(tri, centre, r, normal, gap)) return false;
    Vec3 q;
    const TriangleFeature f = closest(tri, centre, q);
    if (end_is_minimum(centre, q, slot == 0 ? axis : p0 - p1)) return true;
    // Over a face (of this triangle, or of one that shares the point: the end exactly above an
    // edge that a side face owns), the distance decreasing into the axis: counted as on a
    // plane, by the length of the axis over the flat part that holds it (up to r).
    std::int32_t face = flat(tri, f) || face_like(tri, centre, q) ? tri : -1;
    for (std::int32_t j = touch_start_[tu]; face < 0 && j < touch_start_[tu + 1]; ++j) {
      const std::int32_t o = touch_tris_[static_cast<std::size_t>(j)];
      Vec3 qo;
      closest(o, centre, qo);
      if (norm(qo - q) <= eps_ && face_like(o, centre, qo)) face = o;
    }
    if (face < 0) return false;
    weight = flat_run(face, p0, axis, slot == 0 ? 0.0 : 1.0, slot == 0 ? 1 : -1, r) / r;
    return weight > 0;
  }
  // The axis point nearest to edge k or vertex k.
  const bool edge = slot < 5;
  const int k = edge ? slot - 2 : slot - 5;
  const auto feature = static_cast<TriangleFeature>(
      static_cast<int>(edge ? TriangleFeature::Edge0 : TriangleFeature::Vertex0) + k);
  if (flat(tri, feature)) return false;
  const EdgeExit exit = edge ? edge_exit(tri, k, p0, axis) : EdgeExit{};
  const bool leaves = exit.leaves, rising = exit.rising;
  const double s_leave = exit.s;
  // The point where the axis leaves over the edge, at its distance from the plane (the foot on
  // the edge), this triangle's alone.
  const auto leave = [&]() {
    if (!leaves) return false;
    const auto ku = static_cast<std::size_t>(k);
    const Vec3& u0 = points_[static_cast<std::size_t>(tr[ku])];
    const Vec3& u1 = points_[static_cast<std::size_t>(tr[(ku + 1) % 3])];
    const Vec3 c = p0 + s_leave * axis;
    const double h = dot(c - u0, n);
    const Vec3 q = c - h * n;
    const double t = dot(q - u0, u1 - u0) / norm2(u1 - u0);
    const double dist = std::abs(h);
    if (!(t >= 0 && t < 1) || !(dist < r) || !(dist > 0)) return false;
    if (!owns(tri, feature, 0, c, q, /*shared=*/false)) return false;
    // By the length of the axis over the flat part it leaves (up to r), so that the contact
    // grows from nothing as an end moves onto a face (where the end's own contact already is).
    weight = flat_run(tri, p0, axis, s_leave, exit.inward, r) / r;
    if (!(weight > 0)) return false;
    centre = c;
    normal = h > 0 ? n : -1.0 * n;
    gap = dist - r;
    return true;
  };
  if (edge && rising) return leave();
  double s = 0;
  if (edge) {
    int ia = tr[static_cast<std::size_t>(k)], ib = tr[static_cast<std::size_t>((k + 1) % 3)];
    if (ia > ib) std::swap(ia, ib);
    const Vec3& va = points_[static_cast<std::size_t>(ia)];
    const Vec3& vb = points_[static_cast<std::size_t>(ib)];
    const Vec3 e = vb - va;
    if (!(norm2(cross(axis, e)) > 1e-18 * norm2(axis) * norm2(e))) return false;  // parallel
    const contact::SegmentClosest sc = contact::closest_points_segments(p0, p1, va, vb);
    if (!(sc.s > 0 && sc.s < 1 && sc.t > 0 && sc.t < 1)) return false;
    s = sc.s;
  } else {
    const int v = tr[static_cast<std::size_t>(k)];
    const Vec3& pv = points_[static_cast<std::size_t>(v)];
    s = dot(pv - p0, axis) / norm2(axis);
    if (!(s > 0 && s < 1)) return false;
    // An axis along an edge of the corner (a rod lying along a ridge over one of its vertices)
    // rests on its ends, not on the vertex.
    for (std::int32_t j = touch_start_[tu] - 1; j < touch_start_[tu + 1]; ++j) {
      const std::int32_t o = j < touch_start_[tu] ? tri : touch_tris_[static_cast<std::size_t>(j)];
      const auto& to = tris_[static_cast<std::size_t>(o)];
      for (int ko = 0; ko < 3; ++ko) {
        const auto kou = static_cast<std::size_t>(ko);
        if (to[kou] != v && to[(kou + 1) % 3] != v) continue;
        if (edge_flat_[3 * static_cast<std::size_t>(o) + kou] != 0) continue;
        const Vec3 e = points_[static_cast<std::size_t>(to[(kou + 1) % 3])] -
                       points_[static_cast<std::size_t>(to[kou])];
        if (!(norm2(cross(axis, e)) > 1e-18 * norm2(axis) * norm2(e))) return false;
      }
    }
  }
  centre = p0 + s * axis;
  Vec3 q;
  double margin = 0;
  const TriangleFeature f = closest(tri, centre, q, &margin);
  // (an axis dipping by a rounding error: the closest point to the edge found over the face)
  if (f != feature) return edge && f == TriangleFeature::Face && leave();
  const Vec3 d = centre - q;
  const double dist = norm(d);
  if (!(dist < r) || !(dist > 0)) return false;
  // A neighbour across the edge that the axis leaves level or rising holds the contact (an axis
  // level to within rounding: its point there and this one coincide).
  if (edge) {
    const int va = tr[static_cast<std::size_t>(k)], vb = tr[static_cast<std::size_t>((k + 1) % 3)];
    for (std::int32_t j = touch_start_[tu]; j < touch_start_[tu + 1]; ++j) {
      const auto ju = static_cast<std::size_t>(j);
      if (touch_junction_[ju] != 0) continue;
      const std::int32_t o = touch_tris_[ju];
      const auto& to = tris_[static_cast<std::size_t>(o)];
      for (int ko = 0; ko < 3; ++ko) {
        const int oa = to[static_cast<std::size_t>(ko)],
                  ob = to[static_cast<std::size_t>((ko + 1) % 3)];
        if (!((oa == va && ob == vb) || (oa == vb && ob == va))) continue;
        const EdgeExit other = edge_exit(o, ko, p0, axis);
        Vec3 c2, n2;
        double g2 = 0, w2 = 0;
        if (other.leaves && other.rising && capsule_contact(o, 2 + ko, p0, p1, r, c2, n2, g2, w2))
          return false;
      }
    }
  }
  // An end whose own minimum is on this feature carries the contact (an axis nearly parallel to
  // a ridge).
  for (int end = 0; end < 2; ++end) {
    const Vec3& pe = end == 0 ? p0 : p1;
    Vec3 qe;
    if (closest(tri, pe, qe) == feature && end_is_minimum(pe, qe, end == 0 ? axis : p0 - p1))
      return false;
  }
  if (!owns(tri, feature, margin, centre, q)) return false;
  normal = (1.0 / dist) * d;
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

void TriangleMesh::index(double reach, double min_cell) const {
  // A grid for a larger reach serves (its candidates are a superset): the wall list asks with
  // the skin and, when only the walls moved, 1.5 x the skin.
  if (reach <= indexed_reach_ && 2 * reach >= indexed_reach_) return;
  indexed_reach_ = reach;
  keys_.clear();
  cell_start_.assign(1, 0);
  cell_tris_.clear();
  if (tris_.empty()) return;
  // In the body frame (points at t = 0): the grid stays valid however the surface moves, and a
  // query point is taken back to that frame (body_point). Cells of the reach (at least min_cell,
  // and at most 256 along the largest extent); a triangle is listed in the cells whose centre is
  // within reach + half a cell diagonal of it, found column by column along the axis closest to
  // its normal, so that a large or slanted triangle fills a slab of cells, not its bounding box.
  // A query thus gets the triangles within reach + a cell diagonal, 2.7 x the reach (cells of
  // twice the reach gave 4.5 x, about (4.5 / 2.7)^2 = 2.8 times as many candidates near a flat
  // surface; the neighbour stage of bench/mesh/silo_vs_liggghts.py took 1.5 x as long).
  const Vec3 span = hi0_ - lo0_;
  const double extent = std::max({span.x, span.y, span.z, 1e-300});
  h_ = std::max({reach, min_cell, extent / 256});
  for (int k = 0; k < 3; ++k) {
    origin_[k] = lo0_[k] - reach - 1e-3 * h_;
    cells_[static_cast<std::size_t>(k)] =
        static_cast<std::int64_t>(std::floor((hi0_[k] + reach + 1e-3 * h_ - origin_[k]) / h_)) + 1;
  }
  const double near = reach + 0.5 * std::sqrt(3.0) * h_;
  std::vector<std::pair<std::uint64_t, std::int32_t>> uses;
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    const Vec3& a = points0_[static_cast<std::size_t>(tris_[t][0])];
    const Vec3& b = points0_[static_cast<std::size_t>(tris_[t][1])];
    const Vec3& c = points0_[static_cast<std::size_t>(tris_[t][2])];
    std::array<std::int64_t, 3> c0{}, c1{};
    for (int k = 0; k < 3; ++k) {
      const auto n = cells_[static_cast<std::size_t>(k)];
      c0[static_cast<std::size_t>(k)] = std::clamp<std::int64_t>(
          static_cast<std::int64_t>(
              std::floor((std::min({a[k], b[k], c[k]}) - near - origin_[k]) / h_)),
          0, n - 1);
      c1[static_cast<std::size_t>(k)] = std::clamp<std::int64_t>(
          static_cast<std::int64_t>(
              std::floor((std::max({a[k], b[k], c[k]}) + near - origin_[k]) / h_)),
          0, n - 1);
    }
    // The axis w closest to the normal; columns over the other two (u, v).
    const Vec3 nrm = cross(b - a, c - a);
    const double len = norm(nrm);
    int w = 2;
    if (std::abs(nrm.x) >= std::abs(nrm.y) && std::abs(nrm.x) >= std::abs(nrm.z))
      w = 0;
    else if (std::abs(nrm.y) >= std::abs(nrm.z))
      w = 1;
    const int u = (w + 1) % 3, v = (w + 2) % 3;
    const auto uu = static_cast<std::size_t>(u), vv = static_cast<std::size_t>(v),
               ww = static_cast<std::size_t>(w);
    const bool flat = len > 0 && std::abs(nrm[w]) > 1e-6 * len;
    for (std::int64_t iu = c0[uu]; iu <= c1[uu]; ++iu)
      for (std::int64_t iv = c0[vv]; iv <= c1[vv]; ++iv) {
        std::int64_t k0 = c0[ww], k1 = c1[ww];
        if (flat) {
          // The plane's w over the column (a linear function: extremes at the corners), widened
          // by the reach along w (near / |cos| of the normal's angle to w).
          double lo = 1e300, hi = -1e300;
          for (int cu = 0; cu < 2; ++cu)
            for (int cv = 0; cv < 2; ++cv) {
              const double pu = origin_[u] + static_cast<double>(iu + cu) * h_;
              const double pv = origin_[v] + static_cast<double>(iv + cv) * h_;
              const double pw = a[w] - (nrm[u] * (pu - a[u]) + nrm[v] * (pv - a[v])) / nrm[w];
              lo = std::min(lo, pw);
              hi = std::max(hi, pw);
            }
          const double widen = near * len / std::abs(nrm[w]);
          k0 = std::max(k0, static_cast<std::int64_t>(std::floor((lo - widen - origin_[w]) / h_)));
          k1 = std::min(k1, static_cast<std::int64_t>(std::floor((hi + widen - origin_[w]) / h_)));
        }
        for (std::int64_t iw = k0; iw <= k1; ++iw) {
          std::array<std::int64_t, 3> cell{};
          cell[uu] = iu;
          cell[vv] = iv;
          cell[ww] = iw;
          const Vec3 centre{origin_.x + (static_cast<double>(cell[0]) + 0.5) * h_,
                            origin_.y + (static_cast<double>(cell[1]) + 0.5) * h_,
                            origin_.z + (static_cast<double>(cell[2]) + 0.5) * h_};
          Vec3 q;
          closest_on_triangle(centre, a, b, c, q);
          if (norm(centre - q) > near) continue;
          uses.emplace_back(
              static_cast<std::uint64_t>(cell[0] + cells_[0] * (cell[1] + cells_[1] * cell[2])),
              static_cast<std::int32_t>(t));
        }
      }
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

Vec3 TriangleMesh::body_point(const Vec3& x) const {
  if (!moving_) return x;
  // The inverse rotation (angle -rate t, cosine and sine kept by place()), Rodrigues' formula.
  const Vec3 d = x - motion_.center_at(t_);
  const Vec3& k = motion_.axis;
  return motion_.center + back_cos_ * d + back_sin_ * cross(k, d) + (1 - back_cos_) * dot(k, d) * k;
}

std::pair<const std::int32_t*, const std::int32_t*> TriangleMesh::candidates(const Vec3& x) const {
  const std::uint64_t key = cell_key(body_point(x));
  if (key == std::numeric_limits<std::uint64_t>::max()) return {nullptr, nullptr};  // off the grid
  const auto it = std::lower_bound(keys_.begin(), keys_.end(), key);
  if (it == keys_.end() || *it != key) return {nullptr, nullptr};
  const auto c = static_cast<std::size_t>(it - keys_.begin());
  return {cell_tris_.data() + cell_start_[c], cell_tris_.data() + cell_start_[c + 1]};
}

}  // namespace gf
