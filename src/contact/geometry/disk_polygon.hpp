// SPDX-License-Identifier: GPL-3.0-or-later
// 2D: overlap of a convex polygon with a disk (disk grains among polygons, polygons against an
// obstacle post) and with the outside of a circle (polygons in a drum or any circular vessel).
//
// The overlap is the region the polygonal-DEM force of polygon2d.hpp acts on: its area A, its
// centroid, and the chord between the two points where the boundaries cross, the normal being
// perpendicular to the chord (Matuttis' rule, as for two polygons). The force acts on the line
// through the circle's centre along the normal (point_on_centre_line): the overlap does not change
// when the polygon turns about that centre, so the contact exerts no torque about it, as the
// radial pressure on a circular boundary would not (at the centroid itself a frictionless disk
// would be spun by a polygon's corner). A disk is
// round, so its overlap with a polygon is bounded by polygon edges and a circular arc; it is
// computed exactly (no polygonal stand-in for the disk):
//   - every edge a -> b of the polygon is cut where it crosses the circle, and each piece p -> q
//     contributes to the region P ∩ D the part of the triangle (c, p, q) inside the disk: the
//     triangle itself when the piece lies inside, the circular sector between the directions of
//     p and q when it lies outside (Green's theorem over the boundary of P ∩ D);
//   - P \ D (the part of a polygon outside a vessel) sums, over the pieces outside, the triangle
//     less the sector: only the pieces beyond the circle contribute, rather than the whole
//     polygon in area(P) - area(P ∩ D) (each piece's triangle and sector still cancel to about
//     the overlap's depth over the radius: 1e-12 relative for a 1e-4 deep overlap in a drum).
// First moments the same way: a triangle's is its area times the mean of its corners, a sector's
// from angle α to β is r^3/3 (sin β - sin α, cos α - cos β) about the centre.
//
// Crossings: E where the polygon's boundary (CCW) enters the disk, L where it leaves. Each run
// of polygon boundary in the overlap (E -> L for P ∩ D, L -> E for P \ D) has the overlap on its
// left, closed by an arc of the circle; n = perp(E - L) (perp: +90°) is perpendicular to the
// chord and points from the polygon into the disk for P ∩ D, from the vessel's wall into the
// polygon for P \ D. With several runs the normals add: n = perp(ΣE - ΣL).
#pragma once

#include <cmath>

#include "contact/geometry/polygon2d.hpp"

namespace gf::contact {

namespace detail {

/// A circle of centre c, radius r cut by the edges of a convex CCW polygon: area and first moment
/// (about c) of P ∩ D or P \ D, and the boundary crossings.
struct CircleCut {
  double area = 0;
  Vec2 moment;  ///< first moment about the circle's centre, m^3
  /// Crossings in the polygon's order, relative to c; enters[m]: E (else L).
  int n_cross = 0;
  Vec2 cross[2 * kMaxPolygonVertices];
  bool enters[2 * kMaxPolygonVertices];
};

/// First moment about the centre of the sector of radius r between the directions of p and q
/// (the shorter way round, signed as the turn from p to q).
GF_HOST_DEVICE inline Vec2 sector_moment(const Vec2& p, const Vec2& q, double r) {
  const Vec2 u = (1.0 / norm(p)) * p, w = (1.0 / norm(q)) * q;
  return (r * r * r / 3.0) * Vec2{w.y - u.y, u.x - w.x};
}

GF_HOST_DEVICE inline double sector_area(const Vec2& p, const Vec2& q, double r) {
  return 0.5 * r * r * std::atan2(cross(p, q), dot(p, q));
}

/// True when the disk (c, r) lies wholly beyond the line of one edge of the convex CCW polygon
/// (touching at most): then P ∩ D is empty. A disk within the polygon's bounding circle that does
/// not touch it, the common case of a neighbour list, is thus dismissed at n cross products
/// without cutting the edges (a disk off a corner, beyond no edge's line, is cut and found apart).
GF_HOST_DEVICE inline bool beyond_an_edge(const ConvexPolygon& poly, const Vec2& c, double r) {
  for (int e = 0; e < poly.n; ++e) {
    const Vec2 a = poly.v[e], d = poly.v[e + 1 == poly.n ? 0 : e + 1] - a;
    const double s = cross(d, c - a);  // |d| times the signed distance, > 0 inside
    if (s < 0 && s * s >= r * r * dot(d, d)) return true;
  }
  return false;
}

/// True when every vertex, hence the convex polygon, lies inside the circle: P \ D is empty.
GF_HOST_DEVICE inline bool within_circle(const ConvexPolygon& poly, const Vec2& c, double r) {
  for (int v = 0; v < poly.n; ++v)
    if (!(dot(poly.v[v] - c, poly.v[v] - c) < r * r)) return false;
  return true;
}

/// Cuts polygon `poly` by the circle (c, r); `outside`: the region P \ D instead of P ∩ D.
GF_HOST_DEVICE inline void cut_by_circle(const ConvexPolygon& poly, const Vec2& c, double r,
                                         bool outside, CircleCut& k) {
  const double r2 = r * r;
  for (int e = 0; e < poly.n; ++e) {
    const Vec2 a = poly.v[e] - c, b = poly.v[e + 1 == poly.n ? 0 : e + 1] - c;
    const Vec2 d = b - a;
    const double dd = dot(d, d);
    if (!(dd > 0)) continue;  // repeated vertex
    const bool in_a = dot(a, a) < r2, in_b = dot(b, b) < r2;
    // The part [t0, t1] of the edge inside the disk (empty when t0 >= t1), from the roots of
    // |a + t d|^2 = r^2. An end strictly inside is inside; an end on the circle counts as outside.
    // An edge with one end inside always crosses, once: the crossing is kept even where rounding
    // puts the root a hair beyond the end (then at the end), so that every entry has its exit (a
    // vertex on the circle gives a leave and an entry at the same point, which add nothing).
    double t0 = 1, t1 = 0;
    const double bh = dot(a, d), disc = bh * bh - dd * (dot(a, a) - r2);
    if (disc > 0 || in_a != in_b) {
      const double sq = std::sqrt(std::fmax(disc, 0.0));
      const double lo = (-bh - sq) / dd, hi = (-bh + sq) / dd;
      t0 = in_a ? 0.0 : std::fmin(std::fmax(lo, 0.0), 1.0);
      t1 = in_b ? 1.0 : std::fmax(std::fmin(hi, 1.0), 0.0);
    }
    const bool cut = t0 < t1 || in_a != in_b;
    if (cut && !in_a) {
      k.cross[k.n_cross] = a + t0 * d;
      k.enters[k.n_cross++] = true;
    }
    if (cut && !in_b) {
      k.cross[k.n_cross] = a + t1 * d;
      k.enters[k.n_cross++] = false;
    }
    // Pieces: [0, t0] outside, [t0, t1] inside, [t1, 1] outside (or all of it outside).
    auto add_outside = [&](const Vec2& p, const Vec2& q) {
      const double sa = sector_area(p, q, r);
      const Vec2 sm = sector_moment(p, q, r);
      if (outside) {
        const double ta = 0.5 * cross(p, q);
        k.area += ta - sa;
        k.moment = k.moment + (ta / 3.0) * (p + q) - sm;
      } else {
        k.area += sa;
        k.moment = k.moment + sm;
      }
    };
    if (!cut) {
      add_outside(a, b);
      continue;
    }
    const Vec2 p0 = a + t0 * d, p1 = a + t1 * d;
    if (t0 > 0) add_outside(a, p0);
    if (!outside) {
      const double ta = 0.5 * cross(p0, p1);
      k.area += ta;
      k.moment = k.moment + (ta / 3.0) * (p0 + p1);
    }
    if (t1 < 1) add_outside(p1, b);
  }
}

/// The overlap from a cut: area, centroid, chord and normal (see the file comment). When the
/// boundaries do not cross (one shape inside the other) the normal points from the polygon's
/// vertex mean to the circle's centre.
/// perp(ΣE - ΣL) = Σ w_k n_k (w_k, n_k: each run's chord width and normal) is, up to its sign,
/// the gradient of the overlap's area with respect to a translation of the polygon: the overlap
/// shrinks as the disk moves along it, or as the polygon in a vessel does; its direction is the
/// normal and its length the rate dA/dδ at which the overlap changes along it,
/// the width that polygon_law_inputs turns into the contact's stiffness factor s = w / l_c. With
/// one run that is the chord's own length; with several (a flat face of a polygon in a vessel
/// touches it at both corners) the chord is an equivalent one, through the centroid,
/// perpendicular to the normal, of that width.
GF_HOST_DEVICE inline bool finish_circle_overlap(const CircleCut& k, const ConvexPolygon& poly,
                                                 const Vec2& c, bool outside, PolygonOverlap& o) {
  Vec2 mean{0, 0};
  for (int v = 0; v < poly.n; ++v) mean = mean + poly.v[v];
  mean = (1.0 / poly.n) * mean;
  double scale = 0;
  for (int v = 0; v < poly.n; ++v)
    scale = std::fmax(scale, dot(poly.v[v] - mean, poly.v[v] - mean));
  if (!(k.area > 1e-14 * scale)) return false;
  o.area = k.area;
  o.centroid = c + (1.0 / k.area) * k.moment;
  o.n_vertices = 0;
  const double tol = 1e-12 * std::sqrt(scale);
  // Runs of polygon boundary in the overlap start at an entry (P ∩ D) or at a leave (P \ D) and
  // end at the next crossing. A leave followed by an entry at the same point (a vertex on the
  // circle) is no crossing: it is skipped (it adds nothing to ΣE - ΣL either).
  auto touching = [&](int m) {  // crossing m is half of such a pair
    const int next = m + 1 == k.n_cross ? 0 : m + 1, prev = m == 0 ? k.n_cross - 1 : m - 1;
    return (!k.enters[m] && k.enters[next] && norm(k.cross[next] - k.cross[m]) <= tol) ||
           (k.enters[m] && !k.enters[prev] && norm(k.cross[prev] - k.cross[m]) <= tol);
  };
  Vec2 sum{0, 0}, first, last;
  int runs = 0;
  for (int m = 0; m < k.n_cross; ++m) {
    sum = k.enters[m] ? sum + k.cross[m] : sum - k.cross[m];
    if (touching(m) || k.enters[m] != !outside) continue;
    int e = m;  // the run's end: the next crossing that is not half of a touching pair
    do {
      e = e + 1 == k.n_cross ? 0 : e + 1;
    } while (e != m && touching(e));
    first = k.cross[m];
    last = k.cross[e];
    ++runs;
  }
  Vec2 n = perp(sum);
  o.chord = runs > 0 && norm(n) > tol;
  if (o.chord && runs == 1) {
    o.p1 = c + (outside ? first : last);  // the leave L
    o.p2 = c + (outside ? last : first);  // the entry E
  } else if (o.chord) {
    const Vec2 t = 0.5 * perp(n);
    o.p1 = o.centroid + t;
    o.p2 = o.centroid - t;
  } else {
    o.p1 = o.p2 = o.centroid;
    n = c - mean;
  }
  set_unit_normal(o, n);
  return true;
}

}  // namespace detail

/// The point where the contact force of an overlap with the circle of centre c acts: the centroid
/// moved along the chord onto the line through c along the normal (see the file comment).
GF_HOST_DEVICE inline Vec2 point_on_centre_line(const PolygonOverlap& o, const Vec2& c) {
  return c + dot(o.centroid - c, o.normal) * o.normal;
}

/// Overlap of a disk (centre c, radius r) with a convex CCW world polygon; the normal points from
/// the polygon into the disk (the disk is grain i). False when they do not overlap (area below
/// 1e-14 of the polygon's squared size).
GF_HOST_DEVICE inline bool disk_polygon_overlap(const Vec2& c, double r, const ConvexPolygon& poly,
                                                PolygonOverlap& o) {
  if (detail::beyond_an_edge(poly, c, r)) return false;
  detail::CircleCut k;
  detail::cut_by_circle(poly, c, r, false, k);
  return detail::finish_circle_overlap(k, poly, c, false, o);
}

/// Overlap of a polygon with a circular wall of centre c and radius r: with the solid outside the
/// circle when `inside` (a vessel, the grains within; the normal points inwards) or with the
/// solid disk otherwise (a post; the normal points outwards). Normal from the wall to the grain.
GF_HOST_DEVICE inline bool polygon_circle_wall_overlap(const ConvexPolygon& poly, const Vec2& c,
                                                       double r, bool inside, PolygonOverlap& o) {
  if (inside ? detail::within_circle(poly, c, r) : detail::beyond_an_edge(poly, c, r)) return false;
  detail::CircleCut k;
  detail::cut_by_circle(poly, c, r, inside, k);
  // (without crossings the normal points towards the centre; turned below for a post)
  if (!detail::finish_circle_overlap(k, poly, c, inside, o)) return false;
  if (!inside) {  // the run-to-arc normal points into the post: turn it to the grain
    o.normal = -o.normal;
    if (o.chord) {
      const Vec2 t = o.p1;
      o.p1 = o.p2;
      o.p2 = t;
    }
  }
  return true;
}

}  // namespace gf::contact
