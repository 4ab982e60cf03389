// SPDX-License-Identifier: GPL-3.0-or-later
// Narrow phase of spherocylinders (capsules): closest points of two segments, capsule-capsule,
// capsule-sphere, capsule-plane and capsule-cylinder-wall contacts.
//
// A capsule is the set of points within `radius` r of the segment c +- h u (half length h, unit
// axis u; body axis e_z). Two capsules touch when the distance d of their segments is below
// r_i + r_j; the overlap is delta = r_i + r_j - d, the normal n = (p_i - p_j)/d joins the closest
// points p_i, p_j of the two segments and points towards i, and the contact point lies midway
// between the two surfaces along n: x_c = p_j + (r_j - delta/2) n (as for two spheres).
// Locally the contact is between two spheres of radii r_i and r_j centred at p_i and p_j, so the
// contact laws are used with r_eff = r_i r_j / (r_i + r_j) for every pair of features: cap-cap
// and cap-side exactly as for spheres; for side-side (cylinder-cylinder) contacts this is our
// choice, not Hertz's exact value (crossed cylinders have the equivalent radius sqrt(R1 R2) on a
// flat, parallel cylinders a line contact); `feature_i/j` tell which case it is so that a law
// may refine it. References: Pournin, Weber, Tsukahara, Ferrez, Ramaioli and Liebling, Granular
// Matter 7 (2005) 119 (spherocylinder DEM); Kodam, Bharadwaj, Curtis, Hancock and Wassgren,
// Chem. Eng. Sci. 65 (2010) 5852 (contact detection); Ericson, Real-Time Collision Detection
// (2005) sec. 5.1.9 (clamped closest points of segments).
//
// Walls: a plane or cylinder wall with a capsule gives up to two contacts, one per end sphere
// that penetrates (see capsule_plane); this equals the deepest point when one end penetrates and
// gives the right restoring torque when the capsule lies flat (both ends in contact).
//
// Periodic boxes: pass the image of j nearest to i (the narrow phase knows no domain).
#pragma once

#include <cmath>

#include "core/host_device.hpp"
#include "core/quaternion.hpp"
#include "core/vec3.hpp"

namespace gf::contact {

/// A spherocylinder in the world frame.
struct Capsule {
  Vec3 center;             ///< centre of mass, m
  Vec3 axis{0, 0, 1};      ///< unit axis direction (world)
  double half_length = 0;  ///< half the length L of the cylindrical part, m (0: a sphere)
  double radius = 0;       ///< radius r of the caps and cylinder, m
  GF_HOST_DEVICE Vec3 end0() const { return center - half_length * axis; }
  GF_HOST_DEVICE Vec3 end1() const { return center + half_length * axis; }
};

/// World axis of a capsule with orientation q (its body axis is e_z).
GF_HOST_DEVICE inline Vec3 capsule_axis(const Quat& q) {
  return rotate_z(q);
}

/// Which part of the surface carries the contact.
enum class CapsuleFeature : int { Cap, Side, Plane };

/// One contact of a capsule i with a body or wall j.
struct ShapeContact {
  double overlap = 0;   ///< delta > 0, m
  Vec3 normal;          ///< unit normal from j (or the wall) towards i
  Vec3 point;           ///< contact point, midway between the surfaces along the normal, m
  double radius_i = 0;  ///< local radius of curvature of i at the contact, m
  double radius_j = 0;  ///< of j, m; 0 for a wall (taken as flat)
  double r_eff = 0;     ///< radius for the contact law: r_i r_j/(r_i + r_j), walls r_i, m
  CapsuleFeature feature_i = CapsuleFeature::Cap;
  CapsuleFeature feature_j = CapsuleFeature::Cap;
};

/// Closest points p = p0 + s (p1 - p0), q = q0 + t (q1 - q0), s, t in [0, 1].
struct SegmentClosest {
  double s = 0, t = 0;
  Vec3 p, q;
  double dist2 = 0;  ///< |p - q|^2, m^2
};

namespace detail {
GF_HOST_DEVICE constexpr double clamp01(double x) {
  return x < 0 ? 0.0 : (x > 1 ? 1.0 : x);
}
/// A unit vector perpendicular to the unit vector u.
GF_HOST_DEVICE inline Vec3 any_perpendicular(const Vec3& u) {
  return std::abs(u.x) < 0.9 ? normalized(cross(u, Vec3{1, 0, 0}))
                             : normalized(cross(u, Vec3{0, 1, 0}));
}
}  // namespace detail

/// Closest points of the segments [p0, p1] and [q0, q1]. Robust for degenerate (point)
/// segments and for (nearly) parallel ones: the line-line parameter is computed from cross
/// products, s = ((q0 - p0) x d2) . n / |n|^2 with n = d1 x d2, which keeps its relative accuracy
/// down to tiny angles (a e - b^2 would lose it by cancellation); below sin(angle) = 1e-12 the
/// segments are treated as parallel (the distance then varies by less than 1e-12 of their length
/// along the common part) and the pair returned is the middle of the overlap of their projections
/// (the closest ends when they do not overlap). Otherwise the minimiser is unique and is found by
/// clamping s, taking the best t for it, and re-clamping (Ericson 2005, sec. 5.1.9).
GF_HOST_DEVICE inline SegmentClosest closest_points_segments(const Vec3& p0, const Vec3& p1,
                                                             const Vec3& q0, const Vec3& q1) {
  using detail::clamp01;
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = dot(d1, d1), e = dot(d2, d2), b = dot(d1, d2), c = dot(d1, r), f = dot(d2, r);
  // Lengths below 1e-12 of the configuration's scale are points.
  const double tiny = 1e-24 * (a + e + dot(r, r)) + 1e-300;
  double s = 0, t = 0;
  if (a <= tiny && e <= tiny) {
    s = t = 0;
  } else if (a <= tiny) {
    t = clamp01(f / e);
  } else if (e <= tiny) {
    s = clamp01(-c / a);
  } else {
    // (the reciprocals up front: off the dependent chain below)
    const double inv_a = 1.0 / a, inv_e = 1.0 / e;
    const Vec3 n = cross(d1, d2);
    const double nn = dot(n, n);  // a e sin^2(angle)
    if (nn > 1e-24 * a * e) {
      s = clamp01(dot(cross(-r, d2), n) / nn);
    } else {
      // Parallel: parameters of q0 and q1 on segment p; middle of the overlap with [0, 1].
      const double sq0 = -c * inv_a, sq1 = (b - c) * inv_a;
      const double lo = sq0 < sq1 ? sq0 : sq1, hi = sq0 < sq1 ? sq1 : sq0;
      const double l = lo > 0 ? lo : 0.0, h = hi < 1 ? hi : 1.0;
      s = l <= h ? 0.5 * (l + h) : (hi < 0 ? 0.0 : 1.0);
    }
    // Best t for this s, then best s for a clamped t.
    t = (b * s + f) * inv_e;
    if (t < 0) {
      t = 0;
      s = clamp01(-c * inv_a);
    } else if (t > 1) {
      t = 1;
      s = clamp01((b - c) * inv_a);
    }
  }
  SegmentClosest out;
  out.s = s;
  out.t = t;
  out.p = p0 + s * d1;
  out.q = q0 + t * d2;
  out.dist2 = norm2(out.p - out.q);
  return out;
}

/// Capsule-capsule contact; false when they do not touch. Normal towards i.
GF_HOST_DEVICE inline bool capsule_capsule(const Capsule& ci, const Capsule& cj, ShapeContact& k) {
  const double rs = ci.radius + cj.radius;
  const SegmentClosest sc = closest_points_segments(ci.end0(), ci.end1(), cj.end0(), cj.end1());
  if (sc.dist2 >= rs * rs) return false;
  const double dist = std::sqrt(sc.dist2);
  const Vec3 dc = ci.center - cj.center;
  if (dist > 1e-12 * rs) {
    k.normal = (sc.p - sc.q) / dist;
  } else {
    // The axes cross (or coincide): normal perpendicular to both axes, towards i's centre.
    const Vec3 x = cross(ci.axis, cj.axis);
    const double nx = norm(x);
    Vec3 n;
    if (nx > 1e-9) {
      n = x / nx;
    } else {
      const Vec3 perp = dc - dot(dc, ci.axis) * ci.axis;
      n = norm(perp) > 1e-12 * rs ? normalized(perp) : detail::any_perpendicular(ci.axis);
    }
    k.normal = dot(n, dc) < 0 ? -n : n;
  }
  k.overlap = rs - dist;
  k.point = sc.q + (cj.radius - 0.5 * k.overlap) * k.normal;
  k.radius_i = ci.radius;
  k.radius_j = cj.radius;
  k.r_eff = ci.radius * cj.radius / rs;
  const bool side_i = ci.half_length > 0 && sc.s > 0 && sc.s < 1;
  const bool side_j = cj.half_length > 0 && sc.t > 0 && sc.t < 1;
  k.feature_i = side_i ? CapsuleFeature::Side : CapsuleFeature::Cap;
  k.feature_j = side_j ? CapsuleFeature::Side : CapsuleFeature::Cap;
  return true;
}

/// Capsule i with a sphere j (centre xj, radius rj, m); false when they do not touch.
GF_HOST_DEVICE inline bool capsule_sphere(const Capsule& ci, const Vec3& xj, double rj,
                                          ShapeContact& k) {
  return capsule_capsule(ci, Capsule{xj, Vec3{0, 0, 1}, 0.0, rj}, k);
}

namespace detail {
/// Contact of the end sphere at e (radius r) of capsule with a wall, given the gap and normal.
GF_HOST_DEVICE inline ShapeContact end_wall_contact(const Vec3& e, double r, double gap,
                                                    const Vec3& n, CapsuleFeature f) {
  ShapeContact k;
  k.overlap = -gap;
  k.normal = n;
  k.point = e - (r - 0.5 * k.overlap) * n;
  k.radius_i = r;
  k.radius_j = 0;
  k.r_eff = r;
  k.feature_i = f;
  k.feature_j = CapsuleFeature::Plane;
  return k;
}
}  // namespace detail

/// Capsule with the plane through `point` with unit normal `normal` (towards the particles).
/// The gap is linear along the axis, so the deepest points are the ends: one contact per end
/// sphere that penetrates (0, 1 or 2 written to out). A capsule lying flat gets two contacts of
/// equal overlap at its two ends, which carry the restoring torque of a line contact; a tilted
/// one gets its deepest point. A sphere (half_length 0) gets at most one.
GF_HOST_DEVICE inline int capsule_plane(const Capsule& ci, const Vec3& point, const Vec3& normal,
                                        ShapeContact out[2]) {
  int n = 0;
  const Vec3 ends[2] = {ci.end0(), ci.end1()};
  const int n_ends = ci.half_length > 0 ? 2 : 1;
  for (int e = 0; e < n_ends; ++e) {
    const double gap = dot(ends[e] - point, normal) - ci.radius;
    if (gap < 0)
      out[n++] = detail::end_wall_contact(ends[e], ci.radius, gap, normal, CapsuleFeature::Cap);
  }
  return n;
}

/// Capsule with a plane, one contact at the deepest point (midpoint of the axis when the capsule
/// is parallel to the plane within 1e-12 of its length); false when apart.
GF_HOST_DEVICE inline bool capsule_plane_deepest(const Capsule& ci, const Vec3& point,
                                                 const Vec3& normal, ShapeContact& k) {
  const double g0 = dot(ci.end0() - point, normal) - ci.radius;
  const double g1 = dot(ci.end1() - point, normal) - ci.radius;
  const double g = g0 < g1 ? g0 : g1;
  if (g >= 0) return false;
  const bool flat = std::abs(g0 - g1) <= 1e-12 * (2 * ci.half_length + ci.radius);
  const Vec3 e = flat ? ci.center : (g0 < g1 ? ci.end0() : ci.end1());
  k = detail::end_wall_contact(e, ci.radius, g, normal,
                               flat ? CapsuleFeature::Side : CapsuleFeature::Cap);
  return true;
}

/// Capsule with a cylinder wall (a point on the axis, unit axis, radius R in m); `inside` when
/// the particles are inside. Inside, the gap R - rho(s) - r is concave along the capsule axis,
/// so its minima are the ends: one contact per penetrating end (as capsule_plane). Outside (a
/// pillar) the gap rho(s) - R - r is convex: one contact at its minimum (the middle of the
/// capsule when it is parallel to the cylinder axis). Returns the number written to out.
GF_HOST_DEVICE inline int capsule_cylinder_wall(const Capsule& ci, const Vec3& axis_point,
                                                const Vec3& axis, double radius, bool inside,
                                                ShapeContact out[2]) {
  auto radial_of = [&](const Vec3& x, double& rho) {
    const Vec3 d = x - axis_point;
    Vec3 rad = d - dot(d, axis) * axis;
    rho = norm(rad);
    return rho > 0 ? rad / rho : detail::any_perpendicular(axis);
  };
  int n = 0;
  if (inside) {
    const Vec3 ends[2] = {ci.end0(), ci.end1()};
    const int n_ends = ci.half_length > 0 ? 2 : 1;
    for (int e = 0; e < n_ends; ++e) {
      double rho;
      const Vec3 rad = radial_of(ends[e], rho);
      const double gap = radius - rho - ci.radius;
      if (gap < 0)
        out[n++] = detail::end_wall_contact(ends[e], ci.radius, gap, -rad, CapsuleFeature::Cap);
    }
    return n;
  }
  const Vec3 e0 = ci.end0(), d = ci.end1() - e0;
  const Vec3 u = (e0 - axis_point) - dot(e0 - axis_point, axis) * axis;
  const Vec3 w = d - dot(d, axis) * axis;
  const double ww = dot(w, w);
  const double s = ww > 1e-24 * (dot(d, d) + 1e-300) ? detail::clamp01(-dot(u, w) / ww) : 0.5;
  const Vec3 x = e0 + s * d;
  double rho;
  const Vec3 rad = radial_of(x, rho);
  const double gap = rho - radius - ci.radius;
  if (gap >= 0) return 0;
  const bool side = ci.half_length > 0 && s > 0 && s < 1;
  out[n++] = detail::end_wall_contact(x, ci.radius, gap, rad,
                                      side ? CapsuleFeature::Side : CapsuleFeature::Cap);
  return n;
}

}  // namespace gf::contact
