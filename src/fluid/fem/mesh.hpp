// SPDX-License-Identifier: GPL-3.0-or-later
// Body-fitted 2D triangle meshes with P2 nodes: geometry input, mesh data, CGAL mesher entry.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace gf::fem {

/// A point or vector in the plane [m].
struct Vec2 {
  double x = 0.0;
  double y = 0.0;
};

/// A body (hole in the fluid domain): a circle or a simple polygon (counter-clockwise or not).
struct BodyShape {
  enum class Kind { Circle, Polygon };
  Kind kind = Kind::Circle;
  Vec2 centre;                 ///< circle centre, or reference point for torques [m]
  double radius = 0.0;         ///< circle radius [m]
  std::vector<Vec2> vertices;  ///< polygon vertices [m]
};

/// A rectangle in which the mesh size is at most h (e.g. a wake) [m].
struct SizeBox {
  Vec2 min, max;
  double h = 0.0;
};

/// What to mesh: the fluid region inside `outline` and outside every body.
struct MeshSpec {
  std::vector<Vec2> outline;  ///< outer boundary polygon [m]; edge k joins vertex k and k+1
  std::vector<BodyShape> bodies;
  double h_max = 0.05;          ///< largest edge length far from bodies [m]
  double h_body = 0.01;         ///< edge length on body surfaces [m]
  double grading = 0.3;         ///< growth of the size with distance from the nearest body [-]
  double min_angle_deg = 25.0;  ///< Delaunay refinement quality bound (<= 30 degrees terminates)
  std::vector<SizeBox> boxes;   ///< regions of locally bounded size
};

/// An edge of the mesh boundary with its P2 midpoint node.
struct BoundaryEdge {
  int a = -1, b = -1, mid = -1;  ///< node indices (vertices a, b; midpoint node)
  int cell = -1;                 ///< the triangle it belongs to
  int local_edge = -1;           ///< 0: nodes (0,1), 1: (1,2), 2: (2,0) of that triangle
  int outline_edge = -1;         ///< index of the outline edge, or -1
  int body = -1;                 ///< index of the body, or -1
};

/// A triangle mesh with quadratic (P2) node set. Nodes 0..n_vertices-1 are the triangle
/// vertices (the P1 nodes); the others are edge midpoints. On curved (circular) body
/// boundaries the midpoint lies on the circle, so the cells touching it are isoparametric.
struct Mesh {
  std::vector<Vec2> nodes;  ///< [m]
  int n_vertices = 0;
  std::vector<std::array<int, 6>> cells;  ///< v0, v1, v2, mid(0,1), mid(1,2), mid(2,0)
  std::vector<std::uint8_t> curved;       ///< per cell: 1 when a midpoint is off the chord
  std::vector<BoundaryEdge> boundary;

  [[nodiscard]] int n_nodes() const { return static_cast<int>(nodes.size()); }
  [[nodiscard]] int n_cells() const { return static_cast<int>(cells.size()); }
};

/// Meshes the domain with CGAL (constrained Delaunay triangulation + Delaunay refinement with
/// a size field graded away from the bodies and a minimum-angle bound), then adds P2 nodes.
/// Vertices on circles are projected onto the circle; circle edge midpoints are placed on it.
/// Throws gf::InputError for degenerate input (bodies outside the outline, overlaps).
Mesh build_mesh(const MeshSpec& spec);

/// Size field of `spec` at point p [m]: min(h_max, h_body + grading * distance to bodies,
/// h of every box containing p).
double mesh_size_at(const MeshSpec& spec, Vec2 p);

/// Area [m^2], centroid [m] and polar moment of area about the centroid [m^4] of a body (a
/// polygon of either orientation; a circle about its centre).
struct BodyGeometry {
  double area = 0.0;
  Vec2 centroid;
  double polar_moment = 0.0;
};
BodyGeometry body_geometry(const BodyShape& b);

/// Whether p lies inside the closed polygon v, either orientation (crossing number; meaningful
/// for p not on the polygon).
bool inside_polygon(Vec2 p, const std::vector<Vec2>& v);

/// Area of the mesh including curved cells [m^2] (a check of the geometry).
double mesh_area(const Mesh& mesh);

}  // namespace gf::fem
