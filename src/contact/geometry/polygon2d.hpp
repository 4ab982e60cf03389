// SPDX-License-Identifier: GPL-3.0-or-later
// 2D convex polygons: geometry, polygon-polygon and polygon-half-plane overlap (polygonal DEM).
//
// Polygonal DEM after Matuttis (seed 000, sec. 1.2; Matuttis, Luding and Herrmann, Powder
// Technol. 109 (2000) 278; Matuttis and Chen, Understanding the Discrete Element Method, Wiley
// 2014, ch. 7): two convex grains i, j interact through their overlap polygon A_ij = P_i ∩ P_j.
//   F_n = E A / l_c                          (E: modulus, Pa = N/m^2 per unit depth; A: m^2)
//   n   perpendicular to the line through the two points p1, p2 where the boundaries intersect,
//       oriented from j to i;
//   x_c the centroid of the overlap polygon (point of application).
// Characteristic length (our choice; the seed does not fix it): each grain deforms like a spring
// with F = E A_g / R_g (A_g: its share of the overlap area, R_g: radius of its equal-area disk);
// two such springs in series give l_c = R_i + R_j, and a rigid wall (R_j = 0) gives l_c = R_i.
// For two equal grains this is l_c = 2R, the equal-area diameter.
//
// The overlap is computed by Sutherland-Hodgman clipping of P_i by the edge half-planes of P_j
// (Sutherland and Hodgman, Comm. ACM 17 (1974) 32), each output vertex tagged with the boundary
// (of i or of j) its outgoing edge lies on; p1, p2 are the vertices where the tag changes.
// Polygons are counter-clockwise, at most kMaxPolygonVertices vertices.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

#include "core/host_device.hpp"
#include "particles/shapes.hpp"

namespace gf::contact {

// Vec2, ConvexPolygon and kMaxPolygonVertices live with the particle shapes (particles/shapes.hpp);
// these names keep the narrow phase readable.
using gf::ConvexPolygon;
using gf::kMaxPolygonVertices;
using gf::Vec2;

inline constexpr int kMaxOverlapVertices = 2 * kMaxPolygonVertices + 2;

/// Area (m^2), centroid (m), polar second moment of area about the centroid
/// J = integral |x - c|^2 dA (m^4; moment of inertia = areal density * J) and the radius of the
/// equal-area disk (m), from the shoelace formulas.
struct PolygonProperties {
  double area = 0;
  Vec2 centroid;
  double polar_moment = 0;
  double equivalent_radius = 0;
};

GF_HOST_DEVICE inline PolygonProperties polygon_properties(const Vec2* v, int n) {
  PolygonProperties p;
  if (n < 3) return p;
  // Relative to v[0] to limit cancellation.
  const Vec2 o = v[0];
  double a2 = 0, cx = 0, cy = 0, jxx = 0, jyy = 0;
  for (int k = 0; k < n; ++k) {
    const Vec2 p0 = v[k] - o, p1 = v[(k + 1) % n] - o;
    const double c = cross(p0, p1);
    a2 += c;
    cx += (p0.x + p1.x) * c;
    cy += (p0.y + p1.y) * c;
    jxx += (p0.x * p0.x + p0.x * p1.x + p1.x * p1.x) * c;
    jyy += (p0.y * p0.y + p0.y * p1.y + p1.y * p1.y) * c;
  }
  p.area = 0.5 * a2;
  if (p.area <= 0) return p;
  const Vec2 c{cx / (3 * a2), cy / (3 * a2)};
  p.centroid = o + c;
  // Second moments about the origin o are (jxx + jyy)/12; shift to the centroid.
  p.polar_moment = (jxx + jyy) / 12.0 - p.area * dot(c, c);
  p.equivalent_radius = std::sqrt(p.area / 3.141592653589793);
  return p;
}
GF_HOST_DEVICE inline PolygonProperties polygon_properties(const ConvexPolygon& poly) {
  return polygon_properties(poly.v, poly.n);
}

/// World image of a body-frame polygon at `position` (m) turned by the angle whose cosine and
/// sine are c and s (CCW).
GF_HOST_DEVICE inline ConvexPolygon polygon_to_world(const ConvexPolygon& body,
                                                     const Vec2& position, double c, double s) {
  ConvexPolygon w;
  w.n = body.n;
  for (int k = 0; k < body.n; ++k)
    w.v[k] = {position.x + c * body.v[k].x - s * body.v[k].y,
              position.y + s * body.v[k].x + c * body.v[k].y};
  return w;
}
/// World image of a body-frame polygon at `position` (m) turned by `angle` (rad, CCW).
GF_HOST_DEVICE inline ConvexPolygon polygon_to_world(const ConvexPolygon& body,
                                                     const Vec2& position, double angle) {
  return polygon_to_world(body, position, std::cos(angle), std::sin(angle));
}

/// Overlap of grain i with grain j (or a wall).
struct PolygonOverlap {
  double area = 0;     ///< overlap area A, m^2
  Vec2 centroid;       ///< centroid of the overlap polygon = contact point, m
  Vec2 p1, p2;         ///< the two points where the boundaries intersect, m
  Vec2 normal;         ///< unit normal, perpendicular to p2 - p1, from j (or the wall) to i
  int n_vertices = 0;  ///< vertices of the overlap polygon
  bool chord = true;   ///< false when the boundaries do not cross twice (one grain inside the
                       ///< other, or touching degenerately); the normal is then along c_i - c_j
};

/// Characteristic length l_c = R_i + R_j (m) of F_n = E A / l_c; R = equal-area disk radius,
/// R_j = 0 for a rigid wall. See the file comment.
GF_HOST_DEVICE constexpr double polygon_characteristic_length(double r_i, double r_j) {
  return r_i + r_j;
}

/// Normal force magnitude F_n = E A / l_c: with the 2D modulus E in N/m (Young's modulus times
/// the depth of the grains), A in m^2 and l_c in m, F_n is in N.
GF_HOST_DEVICE constexpr double polygon_normal_force(double modulus, double area, double l_c) {
  return modulus * area / l_c;
}

namespace detail {
/// Working polygon of the clipper; tag[k] = 0 when the edge v[k] -> v[k+1] lies on i's boundary,
/// 1 when on j's (or the wall's).
struct TaggedPolygon {
  int n = 0;
  Vec2 v[kMaxOverlapVertices];
  std::int8_t tag[kMaxOverlapVertices];
};

/// Keeps the part of `in` with cross(b - a, x - a) >= 0 (left of the directed line a -> b).
/// Returns false, leaving `out` untouched, when every vertex of `in` is on the kept side: the
/// clip would copy `in` unchanged (same vertices, same tags), so the caller keeps using `in`.
/// Most edges of j do not cut i, and skipping their copies halves the cost of an overlap.
GF_HOST_DEVICE inline bool clip_left_of(const TaggedPolygon& in, const Vec2& a, const Vec2& b,
                                        TaggedPolygon& out) {
  const Vec2 d = b - a;
  // Vertices within 1e-12 of the edge length of the line count as on it, so that edges of i
  // that lie along an edge of j (aligned faces: squares stacked in a column) are classified the
  // same way at both ends and keep i's tag, instead of rounding leaving slivers whose tags put
  // the chord, and hence the normal, askew.
  const double tol = 1e-12 * dot(d, d);
  double side[kMaxOverlapVertices];
  bool cuts = false;
  for (int k = 0; k < in.n; ++k) {
    const double sx = cross(d, in.v[k] - a);
    side[k] = std::abs(sx) <= tol ? 0.0 : sx;
    cuts = cuts || side[k] < 0;
  }
  if (!cuts) return false;
  out.n = 0;
  for (int k = 0; k < in.n; ++k) {
    const int k1 = k + 1 == in.n ? 0 : k + 1;
    const Vec2 p = in.v[k], q = in.v[k1];
    const double sp = side[k], sq = side[k1];
    if (out.n + 2 > kMaxOverlapVertices) return true;  // cannot happen for convex input
    if (sp >= 0) {
      if (sq >= 0) {
        out.v[out.n] = p;
        out.tag[out.n++] = in.tag[k];
      } else if (sp > 0) {  // leaves: p, then the crossing, from which the edge runs on the line
        out.v[out.n] = p;
        out.tag[out.n++] = in.tag[k];
        out.v[out.n] = p + (sp / (sp - sq)) * (q - p);
        out.tag[out.n++] = 1;
      } else {  // p on the line, q outside
        out.v[out.n] = p;
        out.tag[out.n++] = 1;
      }
    } else if (sq > 0) {  // enters: the crossing, from which the edge runs on p -> q
      out.v[out.n] = p + (sp / (sp - sq)) * (q - p);
      out.tag[out.n++] = in.tag[k];
    }
  }
  return true;
}

/// o.normal = n / |n|; (1, 0) when n is zero (both the chord and the fallback degenerate).
GF_HOST_DEVICE inline void set_unit_normal(PolygonOverlap& o, Vec2 n) {
  double len = norm(n);
  if (!(len > 0)) {
    n = {1, 0};
    len = 1;
  }
  o.normal = (1.0 / len) * n;
}

/// Area, centroid, chord and normal of the clipped polygon `w`; `fallback` is used as the normal
/// direction when the boundaries do not cross twice. False when the area is zero.
GF_HOST_DEVICE inline bool finish_overlap(const TaggedPolygon& w, const Vec2& fallback,
                                          double area_scale, PolygonOverlap& o) {
  if (w.n < 3) return false;
  const PolygonProperties pr = polygon_properties(w.v, w.n);
  if (!(pr.area > 1e-14 * area_scale)) return false;
  o.area = pr.area;
  o.centroid = pr.centroid;
  o.n_vertices = w.n;
  // Vertices where the tag changes: i -> j (x1) and j -> i (x2).
  int x1 = -1, x2 = -1;
  for (int k = 0; k < w.n; ++k) {
    const int prev = w.tag[k == 0 ? w.n - 1 : k - 1];
    if (prev == 0 && w.tag[k] == 1 && x1 < 0) x1 = k;
    if (prev == 1 && w.tag[k] == 0 && x2 < 0) x2 = k;
  }
  Vec2 n;
  double len = 0;
  if (x1 >= 0 && x2 >= 0) {
    // Going CCW, i's boundary runs from x2 to x1 on the right of x2 -> x1, j's on its left; the
    // normal from j to i points from i's piece to j's piece: the left normal of x1 - x2.
    o.p1 = w.v[x2];
    o.p2 = w.v[x1];
    n = perp(o.p2 - o.p1);
    len = norm(n);
  }
  o.chord = len > 1e-12 * std::sqrt(area_scale);
  if (!o.chord) {
    o.p1 = o.p2 = o.centroid;
    n = fallback;
  }
  set_unit_normal(o, n);
  return true;
}
}  // namespace detail

/// Overlap of convex CCW world polygons i and j; false when they do not overlap (area below
/// 1e-14 of the smaller polygon's bounding scale squared).
GF_HOST_DEVICE inline bool polygon_overlap(const ConvexPolygon& pi, const ConvexPolygon& pj,
                                           PolygonOverlap& o) {
  detail::TaggedPolygon buf[2];
  buf[0].n = pi.n;
  for (int k = 0; k < pi.n; ++k) {
    buf[0].v[k] = pi.v[k];
    buf[0].tag[k] = 0;
  }
  int cur = 0;
  for (int e = 0; e < pj.n && buf[cur].n > 0; ++e) {
    if (detail::clip_left_of(buf[cur], pj.v[e], pj.v[e + 1 == pj.n ? 0 : e + 1], buf[1 - cur]))
      cur = 1 - cur;
  }
  // Size scale: the squared extent of i, for the zero-area threshold; fallback normal c_i - c_j.
  Vec2 ci{0, 0}, cj{0, 0};
  for (int k = 0; k < pi.n; ++k) ci = ci + pi.v[k];
  for (int k = 0; k < pj.n; ++k) cj = cj + pj.v[k];
  ci = (1.0 / pi.n) * ci;
  cj = (1.0 / pj.n) * cj;
  double scale = 0;
  for (int k = 0; k < pi.n; ++k) scale = std::fmax(scale, dot(pi.v[k] - ci, pi.v[k] - ci));
  return detail::finish_overlap(buf[cur], ci - cj, scale, o);
}

/// Overlap of polygon i with the solid half-plane {x : (x - point) . normal < 0} of a wall whose
/// unit normal points towards the grains; the normal returned is the wall normal.
GF_HOST_DEVICE inline bool polygon_halfplane_overlap(const ConvexPolygon& pi, const Vec2& point,
                                                     const Vec2& normal, PolygonOverlap& o) {
  detail::TaggedPolygon in, out;
  in.n = pi.n;
  for (int k = 0; k < pi.n; ++k) {
    in.v[k] = pi.v[k];
    in.tag[k] = 0;
  }
  // Inside = behind the wall: cross(perp(n), x - point) = -(x - point) . n >= 0.
  // Nothing cut off: the whole grain is behind the wall, and the whole grain is the overlap.
  if (!detail::clip_left_of(in, point, point + perp(normal), out)) out = in;
  Vec2 ci{0, 0};
  for (int k = 0; k < pi.n; ++k) ci = ci + pi.v[k];
  ci = (1.0 / pi.n) * ci;
  double scale = 0;
  for (int k = 0; k < pi.n; ++k) scale = std::fmax(scale, dot(pi.v[k] - ci, pi.v[k] - ci));
  if (!detail::finish_overlap(out, normal, scale, o)) return false;
  o.normal = normal;  // exact: the chord lies on the wall line
  return true;
}

/// Regular n-gon (3 <= n <= kMaxPolygonVertices) with circumradius R (m) centred at the origin,
/// first vertex at angle `phase` (rad).
ConvexPolygon regular_polygon(int n, double circumradius, double phase = 0);

/// Random irregular convex polygon with n vertices: n jittered angles on an ellipse of aspect
/// ratio `elongation` (>= 1, long axis along x), scaled to the equal-area radius `mean_radius`
/// (m) and centred on its centroid. Deterministic for a given generator state.
ConvexPolygon random_convex_polygon(std::mt19937_64& rng, int n, double mean_radius,
                                    double elongation);

/// True when the polygon is strictly convex and counter-clockwise.
bool is_convex_ccw(const ConvexPolygon& poly);

}  // namespace gf::contact
