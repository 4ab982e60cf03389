// SPDX-License-Identifier: GPL-3.0-or-later
// A rigid triangle surface (an STL wall): its topology, its vertices at the current time, a grid
// of its triangles for the contact list, and the contact of a sphere with one of its triangles.
//
// Contacts with a triangulated surface. A sphere near a surface made of triangles is within reach
// of several of them: of the two triangles on either side of an edge it rolls over, of the fan
// around a vertex. Taking every triangle the sphere overlaps as a contact counts the same touch
// two or six times (a sphere resting on the shared edge of a flat square made of two triangles
// would feel twice its weight). The surface, not each triangle, is what the sphere touches: its
// contacts are the local minima of the distance from the centre x to the union of the
// triangles, each taken once. The closest point q of one triangle is
// - inside its face (farther than eps, 1e-9 of the surface's size, from its edges): a local
//   minimum of the whole surface, always a contact;
// - on (or within eps of) its boundary: then every triangle that contains q (those sharing a
//   vertex with it, or meeting it at a T-junction) is asked for its own closest point q' to x,
//   and the first in the order (|x - q'|, then a face point before an edge point before a
//   vertex, then the lower index) takes the contact. If another triangle containing q has a
//   closer point, q is no local minimum and nobody takes it there; if the minimum is shared
//   (the centre above an edge of a flat part, beyond a convex edge or corner, where all these
//   triangles have q' = q), one of them takes it. The distances are computed alike from every
//   triangle, so the order is one strict total order, whoever asks.
// Each contact thus appears once, with the normal (x - q)/|x - q|: face normals on flat parts, the
// bisecting direction at convex edges and corners, and one contact per face in concave corners
// (a sphere in the corner of a meshed box has three, as with three planes). The decision needs
// only the geometry of the touching triangles, not the other contacts, so every entry of the wall
// list is evaluated on its own; ties are decided by the same computation in every triangle, so
// centres within rounding of an edge still get one contact. Surfaces with edges of three or more
// triangles, open rims, T-junctions and sliver triangles are handled; vertices within eps are
// merged and repeated triangles kept once. Overlapping coplanar triangles are not detected.
//
// Spherocylinders (axis segment p0-p1, radius r). Their contacts with the surface are those of
// spheres of radius r at chosen points of the axis, at most eight per triangle, each owned as a
// sphere's (above), so that no touch is counted twice:
// - the two end spheres (slots 0 and 1), as on a plane wall (capsule.hpp): a grain lying on a
//   flat part touches it at both ends, whatever the triangles under it. An end counts fully
//   where the distance to the surface does not decrease from it into the axis (the lower end of
//   a tilted rod, the ends of a level one); an end over a face (its closest point on a face, a
//   flat edge or vertex: two triangles in one plane to 1e-3 rad on either side, or the foot of
//   the perpendicular on a neighbour's plane) where the distance decreases into the axis (the
//   higher end of a tilted rod) counts with the weight l / r, l the length of the axis over the
//   flat part it lies over (up to r); an end beyond a convex edge or corner where the distance
//   decreases into the axis does not count (the minimum lies inside);
// - at an edge k of the triangle that is not flat (slot 2 + k), one of two points of the axis:
//   where the axis, going out of the triangle's prism across that edge, gets closer to the
//   triangle's plane (it dips beyond a ridge, a lifter's edge, a box's edge), the point of the
//   axis closest to the edge: a local minimum of the distance along the axis, which counts if
//   it lies strictly inside the axis and the edge, the triangle's closest point to it is on that
//   edge, the triangle owns it (at a concave edge the faces are closer and hold the grain), no
//   neighbour across the edge takes the crossing below, and no end has its own minimum there (an
//   axis nearly parallel to a ridge rests on its ends; an axis parallel to the edge, sine below
//   1e-9, gets none). Where the axis leaves level or rising, the point where it crosses the
//   prism's side over the edge: the end of the part of the axis that lies over the face, which,
//   as an end on a plane, counts whether or not the distance is least there, with the weight
//   l / r of that part's length (up to r); so a grain lying across a box's top, or tilted over
//   it, rests on both edges it crosses, as on a plane it rests on both ends. The two points
//   coincide for an axis parallel to the face: the contact moves from one to the other
//   continuously as the grain tilts;
// - at a corner that is not flat (5 + k, vertex k): the point of the axis closest to it, on the
//   same terms as the closest point to an edge (none for an axis along one of its edges).
// The weights make the contacts change continuously as a grain moves: an end sliding onto a
// face over an edge, or the free end of a rod across a ridge reaching the far face, brings its
// contact in from nothing. A weight w scales the contact's force (and its mass share, so that
// its damping ratio is that of a full contact). Limits: edges at T-junctions, edges of three or
// more triangles and edges next to zero-area triangles count as rims, not as flat, so a rod
// lying across such an edge of a flat part can get contacts there as at a convex edge; flat
// means within 1e-3 rad, so convex edges flatter than that hold no middle contact (the ends do).
// The axis point of an edge contact is computed with the edge in one orientation (lower vertex
// index first), so that the triangles sharing the edge ask about the same point.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "boundaries/motion.hpp"
#include "core/vec3.hpp"

namespace gf {

/// Where on a triangle its closest point to a given point lies.
enum class TriangleFeature : std::int8_t { Face, Edge0, Edge1, Edge2, Vertex0, Vertex1, Vertex2 };

/// The closest point of triangle (a, b, c) to p and the feature it lies on; edge k joins vertex k
/// and vertex k + 1 (mod 3). Face only when the projection of p lies strictly inside; degenerate
/// (zero-area) triangles give the closest point of their three edges.
TriangleFeature closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                    Vec3& q);

class TriangleMesh {
 public:
  TriangleMesh() = default;
  /// Vertices (m) and triangles (vertex indices). Vertices closer than 1e-9 of the surface's
  /// size are merged (points() may hold fewer than given) and repeated triangles kept once
  /// (triangles() may hold fewer). Throws std::invalid_argument for an index out of range or a
  /// triangle with a repeated (or merged) vertex.
  TriangleMesh(std::vector<Vec3> points, std::vector<std::array<int, 3>> triangles);

  std::size_t size() const { return tris_.size(); }
  bool empty() const { return tris_.empty(); }
  const std::vector<Vec3>& points() const { return points_; }
  const std::vector<Vec3>& points0() const { return points0_; }
  const std::vector<std::array<int, 3>>& triangles() const { return tris_; }
  /// Lower and upper corners of the vertices at t = 0.
  Vec3 lo0() const { return lo0_; }
  Vec3 hi0() const { return hi0_; }
  /// Largest distance of a vertex (t = 0) from c, m.
  double radius_about(const Vec3& c) const;
  /// Edges shared by more than two triangles, and edges of one triangle only (the rim of an open
  /// surface).
  std::size_t nonmanifold_edges() const { return nonmanifold_edges_; }
  std::size_t boundary_edges() const { return boundary_edges_; }
  /// Triangles given twice (same three vertices), kept once.
  std::size_t duplicate_triangles() const { return duplicate_triangles_; }
  /// Vertices lying inside an edge or face of another triangle (T-junctions).
  std::size_t t_junctions() const { return t_junctions_; }

  /// Vertices at time t under the motion (unchanged, bit for bit, for a wall at rest); the
  /// grid of index() follows without being rebuilt.
  void place(const RigidMotion& motion, double t);

  /// Contact of a sphere (centre x, radius r) with triangle `tri`, false when the triangle's
  /// closest point is not a contact of the surface (see the file comment) or is farther than r.
  /// `normal`: unit, from the surface to the centre; `gap`: distance - r (< 0: overlap).
  bool sphere_contact(std::int32_t tri, const Vec3& x, double r, Vec3& normal, double& gap) const;
  /// Contacts a spherocylinder can have with one triangle (see capsule_contact).
  static constexpr int capsule_slots = 8;
  /// Contact `slot` of a spherocylinder (axis p0-p1, radius r) with the surface at triangle
  /// `tri` (see the file comment): 0 and 1 the end spheres at p0 and p1, 2 + k the axis against
  /// edge k, 5 + k against vertex k; false when it is not this triangle's or is apart. `centre`:
  /// the axis point that carries it (the contact of a sphere of radius r there); `normal` and
  /// `gap` as for sphere_contact.
  /// `weight` in (0, 1]: the share of a full contact (1 but for a face's contact where the
  /// distance is not least, which grows with the length of the axis over the face, see the
  /// file comment).
  bool capsule_contact(std::int32_t tri, int slot, const Vec3& p0, const Vec3& p1, double r,
                       Vec3& centre, Vec3& normal, double& gap, double& weight) const;
  /// False when the whole axis p0-p1 is farther than r from the plane of `tri` (no slot of
  /// capsule_contact touches): a cheap test for the entries of a wall list.
  bool capsule_near(std::int32_t tri, const Vec3& p0, const Vec3& p1, double r) const;
  /// Distance from the segment [p0, p1] to triangle `tri` (0 where it pierces it).
  double segment_distance(std::int32_t tri, const Vec3& p0, const Vec3& p1) const;
  /// Distance from x to triangle `tri` (current vertices).
  double distance(std::int32_t tri, const Vec3& x) const;
  /// A cheap lower bound of distance(tri, x) (never above it but for rounding, 1e-12 relative):
  /// the larger of the distance to the triangle's plane and the distance to its bounding sphere
  /// about the centroid. Lets a search skip the exact closest point for far triangles.
  double distance_bound(std::int32_t tri, const Vec3& x) const;
  /// The same for segment_distance(tri, p0, p1): the distance to the plane when both ends lie on
  /// one side of it (0 otherwise), or to the bounding sphere when larger.
  double segment_distance_bound(std::int32_t tri, const Vec3& p0, const Vec3& p1) const;

  /// Indexes the triangles on a grid (in the body frame, so valid for any placement) so that
  /// `candidates` returns, in increasing order, every triangle within `reach` of a point (and
  /// some farther ones); cells of the reach, at least `min_cell`. Kept while the reach does not
  /// change (a cache, hence const).
  void index(double reach, double min_cell = 0) const;
  /// Triangles possibly within the reach given to index() of x; empty outside the grid.
  std::pair<const std::int32_t*, const std::int32_t*> candidates(const Vec3& x) const;

 private:
  /// Whether the contact of the centre x at q (feature f; a face point `margin` from the
  /// nearest edge) on `tri` is this triangle's (see the file comment).
  /// `shared_point` false: the contact is this triangle's alone (a spherocylinder's axis leaving
  /// its face), so it is kept unless a competitor is closer by more than 2 eps (ties kept).
  bool owns(std::int32_t tri, TriangleFeature f, double margin, const Vec3& x, const Vec3& q,
            bool shared_point = true) const;
  /// closest_on_triangle with the stored unit normal; `margin`: for a face point, its distance
  /// to the nearest edge (0 otherwise).
  TriangleFeature closest(std::int32_t tri, const Vec3& x, Vec3& q, double* margin = nullptr) const;
  /// Whether feature f of `tri` is flat: its face, a flat edge or a flat vertex (the surface
  /// continues in the triangle's plane across it, to 1e-3 rad).
  bool flat(std::int32_t tri, TriangleFeature f) const;
  /// Whether q, the closest point of `tri` to x, is the foot of the perpendicular from x (to
  /// within 2 eps): x faces the plane of the triangle rather than an edge or corner.
  bool face_like(std::int32_t tri, const Vec3& x, const Vec3& q) const;
  /// Where the axis p0 + s axis crosses the side of the prism of `tri` over its edge k (the
  /// plane through the edge along the normal): s, whether 0 < s < 1, and whether it leaves the
  /// prism there level or rising (away from the plane).
  struct EdgeExit {
    double s = 0;
    bool leaves = false, rising = false;
    int inward = 1;  ///< the sense of s going back into the prism
  };
  /// The in-plane normal of edge k of `tri`, away from the triangle (not unit).
  Vec3 edge_out(std::int32_t tri, int k) const;
  /// Length of the axis p0 + s axis from s in the sense `dir` (+1, -1) that lies over the prism
  /// of `tri` and of the triangles continuing it across flat edges, up to `cap` (m).
  double flat_run(std::int32_t tri, const Vec3& p0, const Vec3& axis, double s, int dir,
                  double cap) const;
  EdgeExit edge_exit(std::int32_t tri, int k, const Vec3& p0, const Vec3& axis) const;
  std::uint64_t cell_key(const Vec3& x) const;
  /// x taken back to the body frame of the vertices at t = 0 (the inverse of the last place()).
  Vec3 body_point(const Vec3& x) const;

  std::vector<Vec3> points0_, points_;
  std::vector<std::array<int, 3>> tris_;
  // The triangles touching each triangle (sharing a vertex, or meeting it at a T-junction), CSR,
  // the triangle itself left out; fixed for a rigid surface.
  std::vector<std::int32_t> touch_start_, touch_tris_;
  std::vector<char> touch_junction_;  ///< per touch_tris_ entry: the pair meets at a T-junction
  std::size_t nonmanifold_edges_ = 0, boundary_edges_ = 0, duplicate_triangles_ = 0,
              t_junctions_ = 0;
  RigidMotion motion_;  ///< of the last place() (moving_: not at rest), at time t_
  double t_ = 0;
  double back_cos_ = 1, back_sin_ = 0;  ///< cos and sin of -rate t_ (body_point)
  bool moving_ = false;
  std::vector<Vec3> normals0_, normals_;  ///< unit normals (zero if degenerate), t = 0 and now
  std::vector<double> bound_radius_;
  std::vector<char> edge_flat_;             ///< 3 per triangle: edge k is flat (see flat())
  std::vector<std::int32_t> flat_partner_;  ///< 3 per triangle: across a flat edge k, else -1
  std::vector<char> vertex_flat_;           ///< per vertex: all its edges are flat
  std::vector<double> inverse_edge_;  ///< 3 per triangle: 1 / length of edge k (0: degenerate) ///<
                                      ///< per triangle: largest vertex distance from the centroid
  double eps_ = 0;  ///< 1e-9 of the surface's size: merging, containment and edge tolerance
  Vec3 lo0_, hi0_;
  // Grid (a cache of index()): cells of size h_ from origin_; sorted keys of the occupied cells,
  // with their triangles.
  mutable double indexed_reach_ = -1, h_ = 0;
  mutable Vec3 origin_;
  mutable std::array<std::int64_t, 3> cells_{};
  mutable std::vector<std::uint64_t> keys_;
  mutable std::vector<std::int64_t> cell_start_;
  mutable std::vector<std::int32_t> cell_tris_;
};

}  // namespace gf
