// SPDX-License-Identifier: GPL-3.0-or-later
// The only translation unit that includes CGAL: constrained Delaunay meshing of the fluid domain.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_map>

#include "core/error.hpp"
#include "fluid/fem/mesh.hpp"
#include "fluid/fem/p2_element.hpp"

namespace gf::fem {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb =
    CGAL::Triangulation_vertex_base_with_info_2<int, K, CGAL::Delaunay_mesh_vertex_base_2<K>>;
using Fb = CGAL::Delaunay_mesh_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds>;
using Point = Cdt::Point;

double dist_to_segment(Vec2 p, Vec2 a, Vec2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double l2 = dx * dx + dy * dy;
  double t = l2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / l2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p.x - a.x - t * dx, p.y - a.y - t * dy);
}

double dist_to_body(const BodyShape& b, Vec2 p) {
  if (b.kind == BodyShape::Kind::Circle)
    return std::max(0.0, std::hypot(p.x - b.centre.x, p.y - b.centre.y) - b.radius);
  double d = std::numeric_limits<double>::max();
  const std::size_t n = b.vertices.size();
  for (std::size_t i = 0; i < n; ++i)
    d = std::min(d, dist_to_segment(p, b.vertices[i], b.vertices[(i + 1) % n]));
  return d;
}

/// A point strictly inside a simple polygon (either orientation), also a thin or non-convex
/// one: at the leftmost vertex v (a convex one) with neighbours a and b, the centroid of the
/// triangle a v b when no other vertex lies in it, else the midpoint of v and the vertex in it
/// farthest from the line ab (the segment between them is a diagonal of the polygon).
Vec2 interior_point(const std::vector<Vec2>& poly) {
  const std::size_t n = poly.size();
  std::size_t iv = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (poly[i].x < poly[iv].x || (poly[i].x == poly[iv].x && poly[i].y < poly[iv].y)) iv = i;
  const std::size_t ia = (iv + n - 1) % n, ib = (iv + 1) % n;
  const Vec2 a = poly[ia], v = poly[iv], b = poly[ib];
  auto side = [](Vec2 o, Vec2 p, Vec2 q) {
    return (p.x - o.x) * (q.y - o.y) - (p.y - o.y) * (q.x - o.x);
  };
  const double turn = side(a, v, b);  // the sign of the triangle a v b
  double farthest = -1.0;
  std::size_t iq = n;
  for (std::size_t i = 0; i < n; ++i) {
    if (i == ia || i == iv || i == ib) continue;
    const Vec2 p = poly[i];
    const bool in =
        side(a, v, p) * turn >= 0 && side(v, b, p) * turn >= 0 && side(b, a, p) * turn >= 0;
    const double d = std::abs(side(a, b, p));
    if (in && d > farthest) {
      farthest = d;
      iq = i;
    }
  }
  if (iq == n) return {(a.x + v.x + b.x) / 3.0, (a.y + v.y + b.y) / 3.0};
  return {0.5 * (v.x + poly[iq].x), 0.5 * (v.y + poly[iq].y)};
}

int circle_segments(const BodyShape& b, double h) {
  const int n = static_cast<int>(std::ceil(2.0 * std::numbers::pi * b.radius / h));
  return std::max(16, (n + 3) / 4 * 4);  // a multiple of 4: angles 0, pi/2, pi, 3pi/2 are vertices
}

/// Delaunay refinement criteria: minimum angle and a graded size field (edge length).
class GradedCriteria {
 public:
  using Face_handle = Cdt::Face_handle;
  struct Quality {
    double sine2 = 0.0;  ///< squared sine of the smallest angle
    double size2 = 0.0;  ///< (longest edge / local size)^2
    bool operator<(const Quality& q) const {
      if (size2 > 1.0) return q.size2 > 1.0 ? size2 > q.size2 : true;
      if (q.size2 > 1.0) return false;
      return sine2 < q.sine2;
    }
  };
  class Is_bad {
   public:
    Is_bad(const MeshSpec* spec, double b) : spec_(spec), b_(b) {}
    CGAL::Mesh_2::Face_badness operator()(const Quality& q) const {
      if (q.size2 > 1.0) return CGAL::Mesh_2::IMPERATIVELY_BAD;
      return q.sine2 < b_ ? CGAL::Mesh_2::BAD : CGAL::Mesh_2::NOT_BAD;
    }
    CGAL::Mesh_2::Face_badness operator()(const Face_handle& fh, Quality& q) const {
      const Point& pa = fh->vertex(0)->point();
      const Point& pb = fh->vertex(1)->point();
      const Point& pc = fh->vertex(2)->point();
      const double a = CGAL::squared_distance(pb, pc), b = CGAL::squared_distance(pc, pa),
                   c = CGAL::squared_distance(pa, pb);
      const double area = std::abs(CGAL::area(pa, pb, pc));
      // smallest angle is opposite the shortest edge: sin = 2 area / (product of the two others)
      double emin = a, e1 = b, e2 = c;
      if (b < emin) {
        emin = b;
        e1 = a;
        e2 = c;
      }
      if (c < emin) {
        emin = c;
        e1 = a;
        e2 = b;
      }
      q.sine2 = 4.0 * area * area / (e1 * e2);
      const Vec2 g{(pa.x() + pb.x() + pc.x()) / 3.0, (pa.y() + pb.y() + pc.y()) / 3.0};
      const double h = mesh_size_at(*spec_, g);
      q.size2 = std::max({a, b, c}) / (h * h);
      return operator()(q);
    }

   private:
    const MeshSpec* spec_;
    double b_;
  };
  GradedCriteria(const MeshSpec* spec, double b) : spec_(spec), b_(b) {}
  [[nodiscard]] Is_bad is_bad_object() const { return Is_bad(spec_, b_); }

 private:
  const MeshSpec* spec_;
  double b_;
};

std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

}  // namespace

double mesh_size_at(const MeshSpec& spec, Vec2 p) {
  double d = std::numeric_limits<double>::max();
  for (const auto& b : spec.bodies) d = std::min(d, dist_to_body(b, p));
  double h =
      spec.bodies.empty() ? spec.h_max : std::min(spec.h_max, spec.h_body + spec.grading * d);
  for (const auto& b : spec.boxes)
    if (p.x >= b.min.x && p.x <= b.max.x && p.y >= b.min.y && p.y <= b.max.y) h = std::min(h, b.h);
  return h;
}

namespace {
void triangulate(const MeshSpec& spec, Cdt& cdt, std::vector<Point>& seeds);
Mesh finish_mesh(const MeshSpec& spec, Cdt& cdt);
}  // namespace

Mesh build_mesh(const MeshSpec& spec) {
  if (spec.outline.size() < 3)
    throw InputError("fluid_fem mesh: the outline needs at least 3 vertices");
  if (!(spec.h_max > 0) || !(spec.h_body > 0) || spec.grading < 0)
    throw InputError("fluid_fem mesh: sizes must be positive and grading non-negative");
  if (!(spec.min_angle_deg > 0 && spec.min_angle_deg <= 33))
    throw InputError(
        "fluid_fem mesh: min_angle must be in (0, 33] degrees for refinement to terminate");
  for (std::size_t i = 0; i < spec.bodies.size(); ++i) {
    const auto& b = spec.bodies[i];
    std::vector<Vec2> pts = b.vertices;
    if (b.kind == BodyShape::Kind::Circle) {
      if (!(b.radius > 0))
        throw InputError(fmt::format("fluid_fem mesh: body {} has radius <= 0", i));
      pts = {{b.centre.x + b.radius, b.centre.y},
             {b.centre.x - b.radius, b.centre.y},
             {b.centre.x, b.centre.y + b.radius},
             {b.centre.x, b.centre.y - b.radius}};
    } else if (b.vertices.size() < 3) {
      throw InputError(fmt::format("fluid_fem mesh: polygon body {} needs at least 3 vertices", i));
    }
    for (const auto& p : pts)
      if (!inside_polygon(p, spec.outline))
        throw InputError(
            fmt::format("fluid_fem mesh: body {} reaches outside the domain outline", i));
  }

  Cdt cdt;
  std::vector<Point> seeds;
  // CGAL's own failures (constraints that cross, a precondition of the refinement) carry its
  // source file and line; they become an error that says what failed in words. (Release builds
  // check few CGAL preconditions: the case reader refuses the geometries known to break it.)
  try {
    triangulate(spec, cdt, seeds);
  } catch (const CGAL::Failure_exception& e) {
    throw InputError(fmt::format(
        "fluid_fem mesh: CGAL could not mesh the domain ({}{}{}): check that the outline and "
        "bodies are simple polygons that neither cross nor nearly touch",
        e.message(), e.message().empty() ? "" : ": ", e.expression()));
  } catch (const Cdt::Intersection_of_constraints_exception&) {
    throw InputError(
        "fluid_fem mesh: CGAL could not mesh the domain: two boundary edges (of the outline or "
        "bodies) cross");
  }
  return finish_mesh(spec, cdt);
}

namespace {

/// The constrained triangulation of the outline and bodies, refined to the size field (seeds:
/// one point inside every body, whose region is left out).
void triangulate(const MeshSpec& spec, Cdt& cdt, std::vector<Point>& seeds) {
  auto add_loop = [&cdt](const std::vector<Vec2>& loop) {
    std::vector<Cdt::Vertex_handle> vh;
    for (const auto& p : loop) vh.push_back(cdt.insert(Point(p.x, p.y)));
    for (std::size_t i = 0; i < vh.size(); ++i)
      cdt.insert_constraint(vh[i], vh[(i + 1) % vh.size()]);
  };
  add_loop(spec.outline);
  for (const auto& b : spec.bodies) {
    std::vector<Vec2> loop;
    if (b.kind == BodyShape::Kind::Circle) {
      const int n = circle_segments(b, spec.h_body);
      for (int k = 0; k < n; ++k) {
        const double a = 2.0 * std::numbers::pi * k / n;
        loop.push_back({b.centre.x + b.radius * std::cos(a), b.centre.y + b.radius * std::sin(a)});
      }
      seeds.emplace_back(b.centre.x, b.centre.y);
    } else {
      const std::size_t n = b.vertices.size();
      for (std::size_t i = 0; i < n; ++i) {  // split polygon edges to the body size
        const Vec2 p = b.vertices[i], q = b.vertices[(i + 1) % n];
        const int m = std::max(
            1, static_cast<int>(std::ceil(std::hypot(q.x - p.x, q.y - p.y) / spec.h_body)));
        for (int k = 0; k < m; ++k)
          loop.push_back({p.x + (q.x - p.x) * k / m, p.y + (q.y - p.y) * k / m});
      }
      Vec2 c{0, 0};
      for (const auto& p : b.vertices) {
        c.x += p.x / n;
        c.y += p.y / n;
      }
      if (!inside_polygon(c, b.vertices)) c = interior_point(b.vertices);  // non-convex
      seeds.emplace_back(c.x, c.y);
    }
    add_loop(loop);
  }

  const double s = std::sin(spec.min_angle_deg * std::numbers::pi / 180.0);
  GradedCriteria criteria(&spec, s * s);
  CGAL::refine_Delaunay_mesh_2(cdt, seeds.begin(), seeds.end(), criteria, false);
}

/// Area of a closed ring [m^2] (either orientation).
double ring_area(const std::vector<Vec2>& v) {
  double a2 = 0.0;
  for (std::size_t i = 1; i + 1 < v.size(); ++i)
    a2 += (v[i].x - v[0].x) * (v[i + 1].y - v[0].y) - (v[i].y - v[0].y) * (v[i + 1].x - v[0].x);
  return 0.5 * std::abs(a2);
}

/// A mesh the solver can use: cells, none folded over (det J > 0 at every quadrature point; the
/// cells are counter-clockwise), and covering the fluid region (not a body's inside instead).
void check_mesh(const MeshSpec& spec, const Mesh& mesh) {
  if (mesh.cells.empty())
    throw InputError("fluid_fem mesh: the mesh has no cells (no fluid left between the bodies?)");
  const p2::Quadrature7 rule;
  for (const auto& cell : mesh.cells) {
    std::array<Vec2, 6> x;
    for (int k = 0; k < 6; ++k) x[k] = mesh.nodes[cell[k]];
    for (int q = 0; q < rule.n; ++q) {
      double phi[6], gx[6], gy[6];
      if (!(p2::gradients(x, rule.xi[q], rule.eta[q], phi, gx, gy) > 0))
        throw InputError(fmt::format(
            "fluid_fem mesh: a cell near [{:.6g}, {:.6g}] folds over once its vertices are moved "
            "onto a circular body: a gap there narrower than the mesh size; lower mesh.h_body",
            x[0].x, x[0].y));
    }
  }
  double fluid = ring_area(spec.outline);
  for (const auto& b : spec.bodies)
    fluid -= b.kind == BodyShape::Kind::Circle ? std::numbers::pi * b.radius * b.radius
                                               : ring_area(b.vertices);
  const double area = mesh_area(mesh);
  // (curved cells make the circles' area exact but for ~(h / r)^4; 1e-3 is far above that and
  // far below any region meshed or left out by mistake)
  if (!(std::abs(area - fluid) <= 1e-3 * ring_area(spec.outline)))
    throw Error(fmt::format(
        "fluid_fem mesh: the mesh covers {:.6g} m^2 where the fluid covers {:.6g} m^2 (a body's "
        "inside meshed, or fluid left out)",
        area, fluid));
}

/// The mesh with P2 nodes and classified boundary edges from the refined triangulation.
Mesh finish_mesh(const MeshSpec& spec, Cdt& cdt) {
  Mesh mesh;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) v->info() = -1;
  std::vector<std::array<int, 3>> tris;
  std::unordered_map<const void*, int> face_index;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    std::array<int, 3> t{};
    for (int i = 0; i < 3; ++i) {
      auto v = f->vertex(i);
      if (v->info() < 0) {
        v->info() = static_cast<int>(mesh.nodes.size());
        mesh.nodes.push_back({v->point().x(), v->point().y()});
      }
      t[i] = v->info();
    }
    face_index[&*f] = static_cast<int>(tris.size());
    tris.push_back(t);
  }
  mesh.n_vertices = static_cast<int>(mesh.nodes.size());

  // Boundary edges and their classification (outline edge or body).
  double scale = 0;
  for (const auto& p : spec.outline) scale = std::max({scale, std::abs(p.x), std::abs(p.y)});
  const double eps = 1e-9 * std::max(scale, 1e-300);
  std::vector<double> sagitta(spec.bodies.size(), 0.0);
  for (std::size_t i = 0; i < spec.bodies.size(); ++i)
    if (spec.bodies[i].kind == BodyShape::Kind::Circle)
      sagitta[i] = spec.bodies[i].radius *
                   (1 - std::cos(std::numbers::pi / circle_segments(spec.bodies[i], spec.h_body)));
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    for (int i = 0; i < 3; ++i) {
      auto n = f->neighbor(i);
      if (!cdt.is_infinite(n) && n->is_in_domain()) continue;
      BoundaryEdge e;
      e.cell = face_index[&*f];
      e.local_edge = (i + 1) % 3;
      e.a = f->vertex((i + 1) % 3)->info();
      e.b = f->vertex((i + 2) % 3)->info();
      const Vec2 pa = mesh.nodes[e.a], pb = mesh.nodes[e.b];
      const Vec2 m{0.5 * (pa.x + pb.x), 0.5 * (pa.y + pb.y)};
      for (std::size_t k = 0; k < spec.outline.size() && e.outline_edge < 0; ++k)
        if (dist_to_segment(m, spec.outline[k], spec.outline[(k + 1) % spec.outline.size()]) < eps)
          e.outline_edge = static_cast<int>(k);
      for (std::size_t k = 0; k < spec.bodies.size() && e.outline_edge < 0 && e.body < 0; ++k) {
        const auto& b = spec.bodies[k];
        if (b.kind == BodyShape::Kind::Circle) {
          if (std::abs(std::hypot(m.x - b.centre.x, m.y - b.centre.y) - b.radius) <=
              1.01 * sagitta[k] + eps)
            e.body = static_cast<int>(k);
        } else if (dist_to_body(b, m) < eps) {
          e.body = static_cast<int>(k);
        }
      }
      REQUIRE(e.outline_edge >= 0 || e.body >= 0, "boundary edge at ({}, {}) matches no boundary",
              m.x, m.y);
      mesh.boundary.push_back(e);
    }
  }
  // Project vertices on circles onto the circle (Steiner points lie on chords).
  for (const auto& e : mesh.boundary) {
    if (e.body < 0 || spec.bodies[e.body].kind != BodyShape::Kind::Circle) continue;
    const auto& b = spec.bodies[e.body];
    for (int v : {e.a, e.b}) {
      Vec2& p = mesh.nodes[v];
      const double r = std::hypot(p.x - b.centre.x, p.y - b.centre.y);
      p = {b.centre.x + (p.x - b.centre.x) * b.radius / r,
           b.centre.y + (p.y - b.centre.y) * b.radius / r};
    }
  }
  // P2 nodes: one per edge; on circles the midpoint is on the circle.
  std::unordered_map<std::uint64_t, int> mid;
  mid.reserve(tris.size() * 2);
  auto mid_node = [&](int a, int b) {
    auto [it, inserted] = mid.try_emplace(edge_key(a, b), static_cast<int>(mesh.nodes.size()));
    if (inserted)
      mesh.nodes.push_back(
          {0.5 * (mesh.nodes[a].x + mesh.nodes[b].x), 0.5 * (mesh.nodes[a].y + mesh.nodes[b].y)});
    return it->second;
  };
  for (const auto& t : tris)
    mesh.cells.push_back(
        {t[0], t[1], t[2], mid_node(t[0], t[1]), mid_node(t[1], t[2]), mid_node(t[2], t[0])});
  mesh.curved.assign(mesh.cells.size(), 0);
  for (auto& e : mesh.boundary) {
    e.mid = mid.at(edge_key(e.a, e.b));
    if (e.body < 0 || spec.bodies[e.body].kind != BodyShape::Kind::Circle) continue;
    const auto& b = spec.bodies[e.body];
    Vec2& p = mesh.nodes[e.mid];
    const double r = std::hypot(p.x - b.centre.x, p.y - b.centre.y);
    p = {b.centre.x + (p.x - b.centre.x) * b.radius / r,
         b.centre.y + (p.y - b.centre.y) * b.radius / r};
    mesh.curved[e.cell] = 1;
  }
  check_mesh(spec, mesh);
  return mesh;
}

}  // namespace

}  // namespace gf::fem
