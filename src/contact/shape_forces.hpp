// SPDX-License-Identifier: GPL-3.0-or-later
// Narrow phase for every supported pair of shapes and the force loop of stores with shapes.
//
// Pairs: sphere-sphere and disk-disk (sphere_sphere), spherocylinder with spherocylinder or
// sphere (capsule_capsule, a sphere being a capsule of zero length), polygon-polygon (overlap
// polygon; see polygon2d.hpp). The result is the same ContactKinematics the contact laws take,
// plus the contact point, so every law applies unchanged:
//   - capsules: overlap and normal of the two locally touching spheres, r_eff of their radii
//     (and 1 / (r_i + r_j) for the cohesion area);
//   - polygons: the law sees the mean penetration delta = A / w of the overlap A across its
//     chord w = |p2 - p1| (the width of the contact), and its force is scaled by s = w / l_c
//     with l_c = R_i + R_j (equal-area radii). A linear law with stiffness k thus gives
//     F_n = s k delta = k A / l_c, the polygonal-DEM force with the 2D modulus k (N/m). The law
//     is given the mass m_eff / s, so that its damping 2 zeta sqrt(m k) scaled by s is
//     2 zeta sqrt(m s k): critical damping of the actual contact stiffness s k, and a flat face
//     hitting a flat face realises the requested restitution (a vertex contact stiffens as it
//     deepens, like Hertz's). Everything the law returns is scaled by s (the Coulomb cap
//     mu F_n is then consistent); r_eff = R_i R_j / (R_i + R_j).
//   - a disk and a polygon: the same overlap-area law, with the exact overlap of the disk and
//     the polygon (contact/geometry/disk_polygon.hpp) and R_disk as the disk's equal-area radius,
//     so that a disk meets a polygon as the limit of a polygon of many sides would; the force
//     acts on the line through the disk's centre (no torque on it from the normal force).
#pragma once

#include <cstdint>

#include "contact/geometry/capsule.hpp"
#include "contact/geometry/disk_polygon.hpp"
#include "contact/geometry/polygon2d.hpp"
#include "contact/laws/contact_io.hpp"
#include "contact/pair_forces.hpp"
#include "core/domain.hpp"
#include "core/exec.hpp"
#include "neighbor/verlet_list.hpp"
#include "particles/material.hpp"
#include "particles/particle_store.hpp"

namespace gf::contact {

/// Read-only view of the shape columns of a store.
struct ShapeView {
  const std::int32_t* shape;
  const double* radius;  ///< bounding radius
  const double* half_length;
  const Quat* orientation;
  const std::int32_t* polygon;
  const PolygonShape* polygons;

  explicit ShapeView(const ParticleStore& p)
      : shape(p.shape()),
        radius(p.radius()),
        half_length(p.half_length()),
        orientation(p.orientation()),
        polygon(p.polygon()),
        polygons(p.polygons().data()) {}

  GF_HOST_DEVICE ShapeCode code(std::int64_t i) const { return static_cast<ShapeCode>(shape[i]); }
  /// Capsule of particle i at position x (a sphere: zero length).
  GF_HOST_DEVICE Capsule capsule(std::int64_t i, const Vec3& x) const {
    const double h = half_length[i];
    return Capsule{x, h > 0 ? capsule_axis(orientation[i]) : Vec3{0, 0, 1}, h, radius[i] - h};
  }
  /// World polygon of polygon grain i at position x. Its orientation is a turn by θ about z,
  /// q = (cos θ/2, 0, 0, sin θ/2), so cos θ = w² - z² and sin θ = 2 w z (over w² + z², which
  /// is 1 up to rounding): no trigonometric call in the narrow phase, where it took half the
  /// time of a polygon run.
  GF_HOST_DEVICE ConvexPolygon world_polygon(std::int64_t i, const Vec3& x) const {
    const Quat& q = orientation[i];
    const double n2 = q.w * q.w + q.z * q.z;
    return polygon_to_world(polygons[polygon[i]].body, Vec2{x.x, x.y}, (q.w * q.w - q.z * q.z) / n2,
                            2 * q.w * q.z / n2);
  }
  GF_HOST_DEVICE double equivalent_radius(std::int64_t i) const {
    return polygons[polygon[i]].equivalent_radius;
  }
};

/// Geometry of one contact: overlap, normal (from j to i), r_eff and the contact point.
struct ShapeGeometry {
  double overlap = 0;
  Vec3 normal;
  Vec3 point;
  double r_eff = 0;
  double force_scale = 1;  ///< s: polygons (see the file comment); 1 otherwise
  double inv_r_sum = 0;    ///< 1 / (r_i + r_j) of the touching spheres (cohesion); walls 0
};

/// Law inputs of a polygon overlap (area A, chord end points p1, p2) for characteristic length
/// l_c: delta = A / w, force scale s = w / l_c, w = |p2 - p1| (sqrt(A) when the boundaries do
/// not cross twice, e.g. one grain inside the other).
GF_HOST_DEVICE inline void polygon_law_inputs(const PolygonOverlap& o, double l_c,
                                              ShapeGeometry& g) {
  double w = o.chord ? norm(o.p2 - o.p1) : std::sqrt(o.area);
  if (!(w > 1e-9 * l_c)) w = 1e-9 * l_c;
  g.overlap = o.area / w;
  g.force_scale = w / l_c;
  g.normal = {o.normal.x, o.normal.y, 0};
  g.point = {o.centroid.x, o.centroid.y, 0};
}

/// Narrow phase of i (at xi) with j (at xj, the image nearest to i); false when apart.
/// `poly_i` is i's world polygon when i is a polygon, `cap_i` (optional) s.capsule(i, xi):
/// computed once per row by the caller.
GF_HOST_DEVICE inline bool shape_pair_geometry(const ShapeView& s, std::int64_t i, std::int64_t j,
                                               const Vec3& xi, const Vec3& xj,
                                               const ConvexPolygon* poly_i, ShapeGeometry& g,
                                               const Capsule* cap_i = nullptr) {
  const ShapeCode ci = s.code(i), cj = s.code(j);
  // Bounding spheres (circles) apart: most pairs of the Verlet list end here, before any
  // polygon transform or segment computation.
  const double reach = s.radius[i] + s.radius[j];
  if (norm2(xi - xj) >= reach * reach) return false;
  if (ci == ShapeCode::Polygon || cj == ShapeCode::Polygon) {
    PolygonOverlap o;
    double ri = 0, rj = 0;
    if (ci == cj) {
      if (!polygon_overlap(*poly_i, s.world_polygon(j, xj), o)) return false;
      ri = s.equivalent_radius(i);
      rj = s.equivalent_radius(j);
    } else if (ci == ShapeCode::Disk) {
      ri = s.radius[i];
      rj = s.equivalent_radius(j);
      if (!disk_polygon_overlap(Vec2{xi.x, xi.y}, ri, s.world_polygon(j, xj), o)) return false;
      o.centroid = point_on_centre_line(o, Vec2{xi.x, xi.y});
    } else if (cj == ShapeCode::Disk) {
      ri = s.equivalent_radius(i);
      rj = s.radius[j];
      if (!disk_polygon_overlap(Vec2{xj.x, xj.y}, rj, *poly_i, o)) return false;
      o.centroid = point_on_centre_line(o, Vec2{xj.x, xj.y});
      o.normal = -o.normal;  // from j (the disk) to i
    } else {
      return false;  // a polygon with a 3D shape: refused before the run
    }
    polygon_law_inputs(o, polygon_characteristic_length(ri, rj), g);
    g.r_eff = ri * rj / (ri + rj);
    return true;
  }
  if (s.half_length[i] == 0 && s.half_length[j] == 0) {
    // Two spheres (or disks).
    const Vec3 d = xi - xj;
    const double dist2 = norm2(d), rs = s.radius[i] + s.radius[j];
    if (dist2 >= rs * rs) return false;
    const double dist = std::sqrt(dist2);
    g.overlap = rs - dist;
    g.normal = dist > 0 ? d / dist : Vec3{0, 0, 1};
    g.point = xj + (s.radius[j] - 0.5 * g.overlap) * g.normal;
    g.r_eff = s.radius[i] * s.radius[j] / rs;
    g.inv_r_sum = 1.0 / rs;
    return true;
  }
  const Capsule ca = cap_i ? *cap_i : s.capsule(i, xi), cb = s.capsule(j, xj);
  ShapeContact k;
  if (!capsule_capsule(ca, cb, k)) return false;
  g.overlap = k.overlap;
  g.normal = k.normal;
  g.point = k.point;
  g.r_eff = k.r_eff;
  g.inv_r_sum = 1.0 / (ca.radius + cb.radius);  // the two locally touching spheres
  return true;
}

/// What lets the force loop skip list entries that cannot touch without testing them:
/// `gap[k]`, the distance of entry k's two axes (segments) at the list's build less the sum of
/// their radii (m), and `moved[i]`, the largest displacement since that build of either end of
/// grain i's axis (m). Every point of an axis moves by a convex combination of its ends' moves,
/// so the axes of entry k are now at least gap[k] - moved[i] - moved[j] farther apart than the
/// radii allow: apart when that is > 0. Between Lees-Edwards images the images across the
/// gradient boundary have also slid along the flow axis by `slide` (m) since the build, so the
/// test is gap[k] - moved[i] - moved[j] - slide > 0: every image of the pair is then apart (each
/// image's distance fell by at most the moves and the slide, and the build's gap is the smallest
/// over the images). Exact: the same forces as testing every entry, given moves measured from
/// references that followed the grains' wraps (VerletList::set_follow_wraps; through the current
/// offset a grain that crossed the boundary would look up to `slide` nearer its reference).
struct PairSkip {
  const double* gap = nullptr;
  const double* moved = nullptr;
  double slide = 0.0;
};

/// Force loop over the half Verlet list for a store with shapes (forces, torques at the
/// contact point; histories of separated pairs cleared). Returns the touching pairs. With
/// `skip`, entries that cannot touch (PairSkip) are treated as apart without a narrow phase.
std::int64_t compute_shape_pair_forces(ParticleStore& p, const Domain& domain, VerletList& list,
                                       const PairTable<PairCoeffs>& pairs, double dt,
                                       const ContactSink* report = nullptr,
                                       const PairSkip* skip = nullptr);

/// Calls f(i, j, overlap, r_eff, scale, k) for every touching pair of the list (k its entry):
/// spheres and disks by sphere_sphere, a store with shapes by shape_pair_geometry, `scale` the
/// polygons' force scale (1 for other shapes). Serially in list order (rows, then their
/// entries), or with `parallel_rows` the rows spread over the threads (f must then write only
/// what belongs to its entry k).
template <class F>
void for_each_touching_pair(const ParticleStore& p, const Domain& domain, const VerletList& list,
                            F&& f, bool parallel_rows = false) {
  const Vec3* x = p.x();
  const auto off = list.offsets();
  const auto nb = list.neighbors();
  const auto rows = static_cast<exec::index_t>(list.n_particles());
  auto run = [&](auto&& row) {
    if (parallel_rows)
      exec::parallel_for(rows, row);
    else
      for (exec::index_t i = 0; i < rows; ++i) row(i);
  };
  if (!p.has_shapes()) {
    const double* r = p.radius();
    run([&](exec::index_t ii) {
      const auto i = static_cast<std::size_t>(ii);
      for (std::int64_t k = off[i]; k < off[i + 1]; ++k) {
        const std::int32_t j = nb[k];
        ContactKinematics kin;
        double ai, aj;
        if (sphere_sphere(domain, x[i], x[j], r[i], r[j], kin, ai, aj))
          f(i, j, kin.overlap, kin.r_eff, 1.0, k);
      }
    });
    return;
  }
  const ShapeView s(p);
  run([&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    ConvexPolygon poly_i;
    if (s.code(static_cast<std::int64_t>(i)) == ShapeCode::Polygon)
      poly_i = s.world_polygon(static_cast<std::int64_t>(i), x[i]);
    for (std::int64_t k = off[i]; k < off[i + 1]; ++k) {
      const std::int32_t j = nb[k];
      const Vec3 xj = x[i] - domain.delta(x[i], x[j]);
      ShapeGeometry g;
      if (shape_pair_geometry(s, static_cast<std::int64_t>(i), j, x[i], xj, &poly_i, g))
        f(i, j, g.overlap, g.r_eff, g.force_scale, k);
    }
  });
}

/// Elastic energy stored in all contacts of a store (with or without shapes), J, for energy
/// balances; summed in list order.
double shape_pair_elastic_energy(const ParticleStore& p, const Domain& domain,
                                 const VerletList& list, const PairTable<PairCoeffs>& pairs);

}  // namespace gf::contact
