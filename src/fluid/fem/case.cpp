// SPDX-License-Identifier: GPL-3.0-or-later
// Strict YAML reading of the `fluid_fem:` block and the run driver with VTU / CSV output.
#include "fluid/fem/case.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "core/files.hpp"
#include "core/names.hpp"
#include "core/scalar_text.hpp"
#include "core/stop.hpp"
#include "core/vtk_xml.hpp"
#include "fluid/fem/vtu.hpp"

namespace gf::fem {

double TimeFunctionSpec::operator()(double t) const {
  switch (kind) {
    case Kind::Sine:
      return std::sin(2.0 * std::numbers::pi * t / period);
    case Kind::Ramp:
      return t >= duration ? 1.0
                           : 0.5 * (1.0 - std::cos(std::numbers::pi * std::max(t, 0.0) / duration));
    case Kind::Constant:
      break;
  }
  return 1.0;
}

namespace {

/// "FILE:LINE:COLUMN: error: KEY.PATH: MESSAGE" at the key (when key_mark is not null) or the
/// node: the wording of errors when the caller gives no ErrorText.
ErrorText plain_error_text(const std::string& file) {
  return [file](const YAML::Node& at, const YAML::Mark& key_mark, const std::string& path,
                const std::string& message) {
    const YAML::Mark mk = !key_mark.is_null() ? key_mark
                          : at.IsDefined()    ? at.Mark()
                                              : YAML::Mark::null_mark();
    const std::string where =
        mk.line >= 0 ? fmt::format("{}:{}:{}", file, mk.line + 1, mk.column + 1) : file;
    return fmt::format("{}: error: {}: {}", where, path, message);
  };
}

/// Strict reader: every error names file:line:column (or the --set option that gave the value),
/// key path, expected and found.
class Reader {
 public:
  Reader(const std::string& file, ErrorText text)
      : text_(text ? std::move(text) : plain_error_text(file)) {}

  /// `found` overrides the description of the node (e.g. "edges 0 and 2 crossing"); `key_mark`:
  /// the error is about the key there (an unknown key), not about its value.
  [[noreturn]] void fail(const YAML::Node& at, const std::string& path, const std::string& expected,
                         const std::string& found_text = {},
                         const YAML::Mark& key_mark = YAML::Mark::null_mark()) const {
    std::string found = found_text.empty() ? "nothing" : found_text;
    if (found_text.empty() && at.IsDefined() && !at.IsNull()) {
      if (at.IsScalar()) {
        const std::string tag = given_tag(at.Tag());
        found = "'" + at.Scalar() + "'" +
                (tag.empty()  ? ""
                 : tag == "!" ? " (a quoted string)"
                              : fmt::format(" (tagged {})", tag));
      } else if (at.IsSequence())
        found = fmt::format("a list of {} items", at.size());
      else if (at.IsMap())
        found = "a map";
    }
    throw InputError(
        text_(at, key_mark, path, fmt::format("expected {}, found {}", expected, found)));
  }

  /// The text of a warning about `at`, placed as an error there is (file:line:column, or the
  /// --set option that gave the value), without the word "error".
  std::string warning(const YAML::Node& at, const std::string& path,
                      const std::string& message) const {
    std::string s = text_(at, YAML::Mark::null_mark(), path, message);
    if (const auto k = s.find(": error: "); k != std::string::npos) s.replace(k, 9, ": ");
    return s;
  }

  void keys(const YAML::Node& n, const std::string& path,
            std::initializer_list<const char*> allowed) const {
    if (!n.IsMap()) fail(n, path, "a map");
    for (const auto& kv : n) {
      const auto k = kv.first.as<std::string>();
      if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return k == a; })) {
        std::string list;
        for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        fail(kv.second, path + "." + k, "one of the keys {" + list + "}", "'" + k + "'",
             kv.first.Mark());
      }
    }
  }

  /// A child that must exist (fails at the parent's position when missing).
  YAML::Node need(const YAML::Node& parent, const std::string& key, const std::string& path) const {
    const YAML::Node n = parent[key];
    if (!n.IsDefined())
      throw InputError(text_(parent, YAML::Mark::null_mark(), path + "." + key,
                             "expected a value (required key), found nothing"));
    return n;
  }

  double number(const YAML::Node& n, const std::string& path,
                double lo = -std::numeric_limits<double>::infinity(),
                double hi = std::numeric_limits<double>::infinity(), bool open_lo = false) const {
    // (the rules of the shared reader: core/scalar_text.hpp; not '2500' quoted or !!str 2500)
    if (!n.IsScalar() || !tag_allows(n.Tag(), {"!!float", "!!int"})) fail(n, path, "a number");
    const auto parsed = parse_double(n.Scalar());
    if (!parsed) fail(n, path, "a number");
    const double v = *parsed;
    if (!std::isfinite(v) || v < lo || v > hi || (open_lo && v == lo))
      fail(n, path, fmt::format("a number in {}{}, {}]", open_lo ? "(" : "[", lo, hi));
    return v;
  }
  double number_or(const YAML::Node& parent, const std::string& key, const std::string& path,
                   double def, double lo = -std::numeric_limits<double>::infinity(),
                   double hi = std::numeric_limits<double>::infinity(),
                   bool open_lo = false) const {
    const YAML::Node n = parent[key];
    return n.IsDefined() ? number(n, path + "." + key, lo, hi, open_lo) : def;
  }
  int integer_or(const YAML::Node& parent, const std::string& key, const std::string& path, int def,
                 int lo, int hi) const {
    const YAML::Node n = parent[key];
    if (!n.IsDefined()) return def;
    const auto v = n.IsScalar() && tag_allows(n.Tag(), {"!!int", "!!float"})
                       ? parse_integer(n.Scalar())
                       : std::nullopt;
    if (!v || *v < lo || *v > hi)
      fail(n, path + "." + key, fmt::format("an integer in [{}, {}]", lo, hi));
    return static_cast<int>(*v);
  }
  bool boolean_or(const YAML::Node& parent, const std::string& key, const std::string& path,
                  bool def) const {
    const YAML::Node n = parent[key];
    if (!n.IsDefined()) return def;
    if (n.IsScalar() && tag_allows(n.Tag(), {"!!bool"}))
      if (const auto b = parse_bool(n.Scalar())) return *b;
    fail(n, path + "." + key, "true or false");
  }
  std::string choice(const YAML::Node& n, const std::string& path,
                     std::initializer_list<const char*> options) const {
    std::string list;
    for (const char* a : options) list += (list.empty() ? "" : " | ") + std::string(a);
    if (!n.IsScalar()) fail(n, path, "one of " + list);
    const auto v = n.Scalar();
    if (std::none_of(options.begin(), options.end(), [&](const char* a) { return v == a; }))
      fail(n, path, "one of " + list);
    return v;
  }
  Vec2 vec2(const YAML::Node& n, const std::string& path) const {
    if (!n.IsSequence() || n.size() != 2) fail(n, path, "a point [x, y] in m");
    return {number(n[0], path + "[0]"), number(n[1], path + "[1]")};
  }
  std::vector<Vec2> points(const YAML::Node& n, const std::string& path,
                           std::size_t min_count) const {
    if (!n.IsSequence() || n.size() < min_count)
      fail(n, path, fmt::format("a list of at least {} points [x, y]", min_count));
    std::vector<Vec2> v;
    for (std::size_t i = 0; i < n.size(); ++i)
      v.push_back(vec2(n[i], fmt::format("{}[{}]", path, i)));
    return v;
  }

 private:
  ErrorText text_;
};

/// `text` with control characters escaped (\n, \t, \xNN), cut to 60 characters: a value
/// quoted in a one-line message.
std::string printable(const std::string& text) {
  std::string out;
  for (const char ch : text) {
    const auto u = static_cast<unsigned char>(ch);
    if (ch == '\n')
      out += "\\n";
    else if (ch == '\r')
      out += "\\r";
    else if (ch == '\t')
      out += "\\t";
    else if (u < 0x20 || u == 0x7f)
      out += fmt::format("\\x{:02x}", u);
    else
      out += ch;
  }
  return out.size() > 60 ? out.substr(0, 57) + "..." : out;
}

TimeFunctionSpec parse_time_function(const Reader& r, const YAML::Node& n,
                                     const std::string& path) {
  TimeFunctionSpec f;
  if (!n.IsDefined()) return f;
  r.keys(n, path, {"type", "period", "duration"});
  const auto kind = r.choice(r.need(n, "type", path), path + ".type", {"constant", "sine", "ramp"});
  if (kind == "sine") {
    f.kind = TimeFunctionSpec::Kind::Sine;
    f.period = r.number(r.need(n, "period", path), path + ".period", 0, 1e30, true);
  } else if (kind == "ramp") {
    f.kind = TimeFunctionSpec::Kind::Ramp;
    f.duration = r.number(r.need(n, "duration", path), path + ".duration", 0, 1e30, true);
  }
  return f;
}

// ---- Geometry checks of the domain, bodies, refinement boxes and probes --------------------
//
// CGAL's constrained triangulation (mesh_cgal.cpp) needs simple, non-degenerate loops that do
// not meet: a repeated vertex crashes it, crossing loops make it throw, a zero-area body leaves
// no cells. So the case file is checked here, where an error can name the YAML node.
//
// Plain double predicates suffice: every verdict compares a distance (the area: with a strip tol
// wide) with a tolerance tol = 1e-12 x the outline's size (the larger of its extent and its
// largest coordinate, since differences of coordinates carry rounding of the latter's magnitude).
// Distances in doubles err by ~1e-16 of that size, four orders below tol, so rounding cannot turn
// "apart" into "touching" or back; geometry within tol of touching is refused as touching (a gap
// that thin could not be meshed anyway). The sign tests in segment_distance only decide a proper
// crossing, whose distance is 0 up to rounding either way.

std::string point_text(Vec2 p) {
  return fmt::format("[{}, {}]", p.x, p.y);
}

/// (a - o) x (b - o): > 0 when o, a, b turn counter-clockwise.
double cross(Vec2 o, Vec2 a, Vec2 b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

double distance(Vec2 a, Vec2 b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

double point_segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
  const double t = l2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / l2, 0.0, 1.0) : 0.0;
  return std::hypot(p.x - a.x - t * dx, p.y - a.y - t * dy);
}

/// Distance between the segments ab and cd: 0 when they cross, else the smallest distance of an
/// endpoint to the other segment (which is where two disjoint segments come closest; segments
/// that touch or overlap collinearly have an endpoint on the other one).
double segment_distance(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const double c1 = cross(a, b, c), c2 = cross(a, b, d), c3 = cross(c, d, a), c4 = cross(c, d, b);
  if (((c1 > 0 && c2 < 0) || (c1 < 0 && c2 > 0)) && ((c3 > 0 && c4 < 0) || (c3 < 0 && c4 > 0)))
    return 0.0;
  return std::min({point_segment_distance(c, a, b), point_segment_distance(d, a, b),
                   point_segment_distance(a, c, d), point_segment_distance(b, c, d)});
}

/// Distance from p to the closed polygonal ring `v` (its edges).
double ring_distance(Vec2 p, const std::vector<Vec2>& v) {
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < v.size(); ++k)
    d = std::min(d, point_segment_distance(p, v[k], v[(k + 1) % v.size()]));
  return d;
}

/// Crossing-number test (either orientation); meaningful for p farther than tol from the ring.
bool inside_ring(Vec2 p, const std::vector<Vec2>& v) {
  return inside_polygon(p, v);
}

/// p lies in the open region bounded by the ring, farther than tol from it.
bool strictly_inside(Vec2 p, const std::vector<Vec2>& v, double tol) {
  return ring_distance(p, v) > tol && inside_ring(p, v);
}

/// The closed ring of an outline or polygon body (`node` its YAML list, `path` its key path):
/// consecutive vertices distinct (the last joins back to the first, so it must not repeat it),
/// a non-zero area, and simple: no two edges cross or touch, except adjacent edges at their
/// shared vertex, and those must not fold back onto each other. Either orientation is accepted
/// (the mesher and the boundary normals do not depend on it).
void check_ring(const Reader& r, const YAML::Node& node, const std::string& path,
                const std::vector<Vec2>& v, double tol) {
  const std::size_t n = v.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    if (distance(v[i], v[j]) > tol) continue;
    if (j == 0)
      r.fail(node[n - 1], fmt::format("{}[{}]", path, n - 1),
             fmt::format("a last vertex other than the first: the ring closes itself (the last "
                         "edge joins vertex {} back to vertex 0), so the first vertex must not be "
                         "repeated",
                         n - 1),
             point_text(v[i]) + ", the same point as vertex 0");
    r.fail(node[j], fmt::format("{}[{}]", path, j),
           fmt::format("a vertex distinct from the one before it (vertex {})", i),
           point_text(v[j]) + " again");
  }
  // Signed area (shoelace about vertex 0, which keeps the rounding to the ring's own size),
  // compared with the area of a strip tol wide along the ring's extent.
  double area2 = 0.0, extent = 0.0;
  for (std::size_t i = 1; i + 1 < n; ++i) area2 += cross(v[0], v[i], v[i + 1]);
  for (std::size_t i = 1; i < n; ++i) extent = std::max(extent, distance(v[0], v[i]));
  if (std::abs(0.5 * area2) <= tol * extent)
    r.fail(node, path, "a polygon enclosing a non-zero area",
           fmt::format("{} vertices enclosing none (all on one line, or loops of opposite sense "
                       "that cancel)",
                       n));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const Vec2 a = v[i], b = v[(i + 1) % n], c = v[j], d = v[(j + 1) % n];
      bool bad = false, adjacent = true;
      if (j == i + 1)  // shared vertex b == c: they overlap iff a or d lies on the other edge
        bad = point_segment_distance(d, a, b) <= tol || point_segment_distance(a, c, d) <= tol;
      else if (i == 0 && j == n - 1)  // shared vertex a == d
        bad = point_segment_distance(c, a, b) <= tol || point_segment_distance(b, c, d) <= tol;
      else {
        adjacent = false;
        bad = segment_distance(a, b, c, d) <= tol;
      }
      if (bad)
        r.fail(node, path,
               "a simple polygon: no two edges crossing or touching (edge k joins vertex k and "
               "k + 1, the last edge joins back to vertex 0)",
               fmt::format("edges {} ({} to {}) and {} ({} to {}) {}", i, point_text(a),
                           point_text(b), j, point_text(c), point_text(d),
                           adjacent ? "folding back onto each other" : "crossing or touching"));
    }
}

/// Why bodies a and b (a before b in the list) are not disjoint, or "" when they are: circles and
/// polygons must not overlap, touch, or contain one another.
std::string body_overlap(const BodyShape& a, const BodyShape& b, double tol) {
  using Kind = BodyShape::Kind;
  if (a.kind == Kind::Circle && b.kind == Kind::Circle) {
    const double d = distance(a.centre, b.centre);
    if (d <= a.radius + b.radius + tol)
      return fmt::format(
          "its centre {:.6g} m from the other's, within the sum of the radii, {:.6g} m", d,
          a.radius + b.radius);
    return {};
  }
  if (a.kind == Kind::Circle || b.kind == Kind::Circle) {
    const BodyShape& c = a.kind == Kind::Circle ? a : b;
    const BodyShape& p = a.kind == Kind::Circle ? b : a;
    const bool own = &c == &b;  // the circle is b, the body the message is about
    const char* circle = own ? "its circle" : "the other's circle";
    const char* polygon = own ? "the other's polygon" : "its polygon";
    if (strictly_inside(c.centre, p.vertices, tol))
      return fmt::format("{} centred inside {}", circle, polygon);
    const double d = ring_distance(c.centre, p.vertices);
    if (d <= c.radius + tol)
      return fmt::format("{} (radius {} m) reaching {}, {:.6g} m from the centre", circle, c.radius,
                         polygon, d);
    return {};
  }
  const auto& u = a.vertices;
  const auto& v = b.vertices;
  for (std::size_t i = 0; i < v.size(); ++i)
    for (std::size_t k = 0; k < u.size(); ++k)
      if (segment_distance(v[i], v[(i + 1) % v.size()], u[k], u[(k + 1) % u.size()]) <= tol)
        return fmt::format("its edge {} crossing or touching the other's edge {}", i, k);
  // no edges meet: one polygon inside the other, or apart
  if (inside_ring(v[0], u)) return "its polygon inside the other";
  if (inside_ring(u[0], v)) return "the other polygon inside its own";
  return {};
}

// ---- Gaps narrower than the mesh ----------------------------------------------------------
//
// A gap between two bodies, or a body and the outline, narrower than the mesh size there (h_body,
// or a refinement box's h) is meshed all the same: Delaunay refinement puts cells as small as the
// gap into it, about one across. Decided:
// - below 0.1 x the size there it is an error. The mesher then makes cells over ten times finer
//   than asked for along the whole narrow stretch (their number grows as 1 / gap, unbounded as
//   the gap closes; near 1e-12 of the domain, CGAL's inexact constructions misplace points); and
//   a circle's vertices, meshed on chords and then moved onto the circle by up to the sagitta
//   (at most ~0.05 x the edge length, 16 or more edges per circle), can fold the cells of a gap
//   of that order inside out. Nothing the run would then report could be trusted, and the fix
//   (a smaller h_body or a box over the gap, or a wider gap) is the user's, so the case is
//   refused before anything is written, at the body's place in the file.
// - between 0.1 and 1 x the size it is a warning (grainflow check, and the log of a run): the mesh
//   is sound and the lubrication flow in the gap is a parabola that P2 velocities hold exactly,
//   but only about one cell spans it, so the force there is coarse. Refusing it would refuse
//   cases whose gap flow does not matter.

/// A gap between two boundaries: its width [m] and the point halfway across it.
struct Gap {
  double width = std::numeric_limits<double>::infinity();
  Vec2 middle;
};

Vec2 closest_on_segment(Vec2 p, Vec2 a, Vec2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
  const double t = l2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / l2, 0.0, 1.0) : 0.0;
  return {a.x + t * dx, a.y + t * dy};
}

Gap point_gap(Vec2 p, Vec2 q) {
  return {distance(p, q), {0.5 * (p.x + q.x), 0.5 * (p.y + q.y)}};
}

/// Between two rings that do not meet (the closest pair has an endpoint of an edge).
Gap ring_gap(const std::vector<Vec2>& u, const std::vector<Vec2>& v) {
  Gap g;
  auto keep = [&g](const Gap& c) {
    if (c.width < g.width) g = c;
  };
  for (std::size_t i = 0; i < u.size(); ++i)
    for (std::size_t k = 0; k < v.size(); ++k) {
      const Vec2 a = u[i], b = u[(i + 1) % u.size()], c = v[k], d = v[(k + 1) % v.size()];
      keep(point_gap(a, closest_on_segment(a, c, d)));
      keep(point_gap(c, closest_on_segment(c, a, b)));
    }
  return g;
}

/// Between a circle and a ring outside it (or around it).
Gap circle_ring_gap(const BodyShape& c, const std::vector<Vec2>& v) {
  Vec2 q;
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < v.size(); ++k) {
    const Vec2 p = closest_on_segment(c.centre, v[k], v[(k + 1) % v.size()]);
    if (distance(c.centre, p) < d) {
      d = distance(c.centre, p);
      q = p;
    }
  }
  const double w = d - c.radius, f = d > 0 ? (c.radius + 0.5 * w) / d : 0.0;
  return {w, {c.centre.x + f * (q.x - c.centre.x), c.centre.y + f * (q.y - c.centre.y)}};
}

Gap body_gap(const BodyShape& a, const BodyShape& b) {
  using Kind = BodyShape::Kind;
  if (a.kind == Kind::Circle && b.kind == Kind::Circle) {
    const double d = distance(a.centre, b.centre), w = d - a.radius - b.radius;
    const double f = d > 0 ? (a.radius + 0.5 * w) / d : 0.0;
    return {
        w,
        {a.centre.x + f * (b.centre.x - a.centre.x), a.centre.y + f * (b.centre.y - a.centre.y)}};
  }
  if (a.kind == Kind::Circle) return circle_ring_gap(a, b.vertices);
  if (b.kind == Kind::Circle) return circle_ring_gap(b, a.vertices);
  return ring_gap(a.vertices, b.vertices);
}

/// Every body's gaps to the outline and to the bodies before it against the mesh size at the
/// surfaces bounding the gap (see above): an error below 0.1 x that size, a warning (cfg.warnings)
/// below it.
void check_gaps(const Reader& r, const YAML::Node& bodies, const std::string& bp,
                FemCaseConfig& cfg) {
  const auto& shapes = cfg.mesh.bodies;
  for (std::size_t j = 0; j < shapes.size(); ++j) {
    const std::string p = fmt::format("{}[{}]", bp, j);
    auto judge = [&](const Gap& g, const std::string& other) {
      // The cells in a gap take the size at the surfaces that bound it (h_body, or a box's h
      // over the gap), not the graded size halfway across (h_body + grading x half the width,
      // which a large grading would make the gap's own width).
      double h = std::min(cfg.mesh.h_max, cfg.mesh.h_body);
      for (const auto& b : cfg.mesh.boxes)
        if (g.middle.x >= b.min.x && g.middle.x <= b.max.x && g.middle.y >= b.min.y &&
            g.middle.y <= b.max.y)
          h = std::min(h, b.h);
      if (g.width >= h) return;
      if (g.width < 0.1 * h)
        r.fail(
            bodies[j], p,
            fmt::format("a body clear of {} by at least 0.1 x the mesh size there, {:.6g} m "
                        "(a narrower gap needs cells over ten times finer than asked for, "
                        "and curved cells on a circle may fold over); lower mesh.h_body, add "
                        "a mesh.boxes entry over the gap with h <= 10 x its width, or widen it",
                        other, h),
            fmt::format("a gap of {:.6g} m at [{:.6g}, {:.6g}]", g.width, g.middle.x, g.middle.y));
      cfg.warnings.push_back(r.warning(
          bodies[j], p,
          fmt::format("the gap of {:.6g} m between '{}' and {} at [{:.6g}, {:.6g}] is narrower "
                      "than the mesh size there, {:.6g} m: about one cell spans it and the flow "
                      "in it is coarsely resolved; lower mesh.h_body (or a box's h) to a "
                      "fraction of the gap",
                      g.width, cfg.body_names[j], other, g.middle.x, g.middle.y, h)));
    };
    const auto& s = shapes[j];
    judge(s.kind == BodyShape::Kind::Circle ? circle_ring_gap(s, cfg.mesh.outline)
                                            : ring_gap(s.vertices, cfg.mesh.outline),
          "the domain outline");
    for (std::size_t i = 0; i < j; ++i)
      judge(body_gap(shapes[i], s), fmt::format("{}[{}] ('{}')", bp, i, cfg.body_names[i]));
  }
}

/// The bodies (`bodies` their YAML list) of a parsed block: polygons simple (check_ring), every
/// body strictly inside the outline, bodies pairwise disjoint, names unique.
void check_bodies(const Reader& r, const YAML::Node& bodies, const std::string& bp,
                  const FemCaseConfig& cfg, double tol) {
  const auto& outline = cfg.mesh.outline;
  const auto& shapes = cfg.mesh.bodies;
  for (std::size_t j = 0; j < shapes.size(); ++j) {
    const auto& s = shapes[j];
    const YAML::Node b = bodies[j];
    const std::string p = fmt::format("{}[{}]", bp, j);
    if (s.kind == BodyShape::Kind::Circle) {
      if (!strictly_inside(s.centre, outline, tol))
        r.fail(b["circle"]["centre"], p + ".circle.centre",
               "a centre inside the domain outline (bodies are holes in the fluid)",
               point_text(s.centre));
      const double d = ring_distance(s.centre, outline);
      if (d <= s.radius + tol)
        r.fail(b["circle"]["radius"], p + ".circle.radius",
               fmt::format("a radius below {:.6g} m, the distance from the centre to the domain "
                           "outline (a body lies strictly inside it)",
                           d));
    } else {
      const auto& v = s.vertices;
      check_ring(r, b["polygon"], p + ".polygon", v, tol);
      for (std::size_t k = 0; k < v.size(); ++k)
        if (!strictly_inside(v[k], outline, tol))
          r.fail(b["polygon"][k], fmt::format("{}.polygon[{}]", p, k),
                 "a vertex inside the domain outline (a body lies strictly inside it)",
                 point_text(v[k]));
      for (std::size_t k = 0; k < v.size(); ++k)
        for (std::size_t m = 0; m < outline.size(); ++m)
          if (segment_distance(v[k], v[(k + 1) % v.size()], outline[m],
                               outline[(m + 1) % outline.size()]) <= tol)
            r.fail(b["polygon"], p + ".polygon",
                   "a polygon inside the domain outline (a body lies strictly inside it)",
                   fmt::format("its edge {} crossing or touching outline edge {}", k, m));
    }
    for (std::size_t i = 0; i < j; ++i)
      if (const auto why = body_overlap(shapes[i], s, tol); !why.empty())
        r.fail(b, p,
               fmt::format("a body clear of {}[{}] ('{}'): bodies must not overlap or touch", bp, i,
                           cfg.body_names[i]),
               why);
  }
  // Names head the columns of fem_forces.csv. Unnamed bodies are called body<index>, which a
  // given name may take too.
  for (std::size_t j = 0; j < shapes.size(); ++j)
    for (std::size_t i = 0; i < j; ++i) {
      if (cfg.body_names[i] != cfg.body_names[j]) continue;
      const bool named_j = bodies[j]["name"].IsDefined();
      const std::size_t at = named_j ? j : i, other = named_j ? i : j;
      r.fail(bodies[at]["name"], fmt::format("{}[{}].name", bp, at),
             fmt::format("a name no other body has ({}[{}] is called '{}' too{})", bp, other,
                         cfg.body_names[other],
                         bodies[other]["name"].IsDefined() ? "" : ", the name of an unnamed body"));
    }
}

/// Probes must lie in the fluid: inside the outline and outside every body, boundaries included
/// (a probe on a body's surface, as in the Schaefer-Turek cases, reads the wall pressure).
void check_probes(const Reader& r, const YAML::Node& probes, const std::string& pp,
                  const FemCaseConfig& cfg, double tol) {
  for (std::size_t k = 0; k < cfg.output.probes.size(); ++k) {
    const Vec2 q = cfg.output.probes[k];
    const std::string p = fmt::format("{}[{}]", pp, k);
    if (ring_distance(q, cfg.mesh.outline) > tol && !inside_ring(q, cfg.mesh.outline))
      r.fail(probes[k], p, "a point inside the domain outline (a probe samples the fluid)",
             point_text(q));
    for (std::size_t j = 0; j < cfg.mesh.bodies.size(); ++j) {
      const auto& b = cfg.mesh.bodies[j];
      const bool in = b.kind == BodyShape::Kind::Circle ? distance(q, b.centre) < b.radius - tol
                                                        : strictly_inside(q, b.vertices, tol);
      if (in)
        r.fail(probes[k], p,
               fmt::format("a point in the fluid, not inside body {} ('{}')", j, cfg.body_names[j]),
               point_text(q));
    }
  }
}

/// Period [s] of the fastest contact mode of free body j (cfg.repulsion_range > 0). Repulsion
/// and friction are explicit loads, fixed over each step, so this mode must span several steps.
/// Its estimate: the stiffer of the repulsion at contact (2 F_0 / rho) and the friction spring,
/// on two contacts (a body resting on a face), the tangential ones coupled to rocking about the
/// centre at the equal-area radius r_e (effective stiffness x (1 + A r_e^2 / J): 3 for a disk,
/// 2.9 for a square). In review the scheme was neutral down to ~3 steps per period of a single
/// mode.
double contact_period(const FemCaseConfig& cfg, std::size_t j) {
  const BodyGeometry geo = body_geometry(cfg.mesh.bodies[j]);
  const double k_n = 2 * cfg.repulsion_force / cfg.repulsion_range;
  const double k_t =
      cfg.repulsion_friction > 0
          ? (cfg.repulsion_tangential_stiffness > 0 ? cfg.repulsion_tangential_stiffness : k_n)
          : 0.0;
  // (a rolling spring k_t R^2 per contact doubles the rotational stiffness at most)
  const double rocking = 1 + (cfg.repulsion_rolling_friction > 0 ? 2.0 : 1.0) * geo.area *
                                 (geo.area / std::numbers::pi) / geo.polar_moment;
  const double k = 2 * std::max(k_n, k_t * rocking);
  return 2 * std::numbers::pi * std::sqrt(cfg.body_density[j] * geo.area / k);
}

/// `gravity` and `moving_mesh` of the block, and what free bodies (a body with a density) need
/// of the rest of it: an unsteady run from rest with fixed steps. Gravity with no free body acts on
/// nothing (the pressure is the dynamic one): a warning.
void parse_moving_bodies(const Reader& r, const YAML::Node& block, FemCaseConfig& cfg) {
  const std::string root = "fluid_fem";
  if (const auto g = block["gravity"]; g.IsDefined()) {
    if (!g.IsSequence() || g.size() != 2)
      r.fail(g, root + ".gravity", "a vector [gx, gy] in m/s^2");
    cfg.gravity = {r.number(g[0], root + ".gravity[0]"), r.number(g[1], root + ".gravity[1]")};
  }
  int first_free = -1;
  for (std::size_t j = 0; j < cfg.body_density.size(); ++j)
    if (cfg.body_density[j] > 0 && first_free < 0) first_free = static_cast<int>(j);
  if (const auto tilt = block["tilt"]; tilt.IsDefined()) {
    const std::string tp = root + ".tilt";
    if (!tilt.IsMap()) r.fail(tilt, tp, "a map {rate: deg/s, start: s, end: s}");
    r.keys(tilt, tp, {"rate", "start", "end"});
    if (first_free < 0)
      r.fail(tilt, tp, "no tilt without a free body (it turns the gravity on free bodies)");
    if (cfg.gravity.x == 0 && cfg.gravity.y == 0)
      r.fail(tilt, tp, "no tilt without gravity (fluid_fem.gravity: the tilt turns it)");
    const double inf = std::numeric_limits<double>::infinity();
    if (!tilt["rate"].IsDefined()) r.fail(tilt, tp + ".rate", "a rate in deg/s (the tilt's speed)");
    const double rate = r.number(tilt["rate"], tp + ".rate", -inf, inf);
    if (rate == 0) r.fail(tilt["rate"], tp + ".rate", "a rate other than 0 (deg/s)");
    cfg.tilt.rate = rate;
    cfg.tilt.start =
        tilt["start"].IsDefined() ? r.number(tilt["start"], tp + ".start", 0, inf) : 0.0;
    if (!tilt["end"].IsDefined())
      r.fail(tilt, tp + ".end", "an end time in s (the tilt stops there)");
    cfg.tilt.end = r.number(tilt["end"], tp + ".end", 0, inf);
    if (!(cfg.tilt.end > cfg.tilt.start))
      r.fail(tilt["end"], tp + ".end",
             fmt::format("a time after tilt.start ({:g} s)", cfg.tilt.start));
  }
  if (first_free < 0) {
    if (const auto mm = block["moving_mesh"]; mm.IsDefined())
      r.fail(mm, root + ".moving_mesh",
             "no moving_mesh block without a free body (the mesh moves only when a body has a "
             "density)");
    if (cfg.gravity.x != 0 || cfg.gravity.y != 0)
      cfg.warnings.push_back(r.warning(
          block["gravity"], root + ".gravity",
          "gravity acts on free bodies only (those with a density) and there is none: the "
          "flow does not change with it (its pressure is the dynamic one, without rho g.x)"));
    return;
  }
  if (const auto mm = block["moving_mesh"]; mm.IsDefined()) {
    const std::string mp = root + ".moving_mesh";
    r.keys(mm, mp, {"remesh_ratio", "remesh_quality", "repulsion"});
    auto fraction = [&](const char* key, double def) {
      const YAML::Node n = mm[key];
      if (!n.IsDefined()) return def;
      const double v = r.number(n, mp + "." + key, 0, 1, true);
      if (v >= 1) r.fail(n, mp + "." + key, "a number in (0, 1)");
      return v;
    };
    cfg.remesh_ratio = fraction("remesh_ratio", cfg.remesh_ratio);
    cfg.remesh_quality = fraction("remesh_quality", cfg.remesh_quality);
    if (const auto rep = mm["repulsion"]; rep.IsDefined()) {
      const std::string rp = mp + ".repulsion";
      if (!rep.IsMap())
        r.fail(rep, rp,
               "a map {range: m, force: N/m, friction, tangential_stiffness: N/m^2, "
               "rolling_friction} (repulsion "
               "across narrow gaps, with optional Coulomb friction)");
      r.keys(rep, rp,
             {"range", "force", "friction", "tangential_stiffness", "rolling_friction", "core"});
      for (const char* k : {"range", "force"})
        if (!rep[k].IsDefined())
          r.fail(rep, rp + "." + k,
                 fmt::format("a {} ({}): both range and force are needed", k,
                             std::string(k) == "range" ? "gap in m" : "force scale in N/m"));
      const double inf = std::numeric_limits<double>::infinity();
      cfg.repulsion_range = r.number(rep["range"], rp + ".range", 0, inf, true);
      cfg.repulsion_force = r.number(rep["force"], rp + ".force", 0, inf, true);
      // The film the repulsion keeps must hold a cell or two: remeshing a narrower gap fails.
      double h_min = cfg.mesh.h_body;
      for (const auto& box : cfg.mesh.boxes) h_min = std::min(h_min, box.h);
      if (cfg.repulsion_range < h_min)
        cfg.warnings.push_back(r.warning(
            rep["range"], rp + ".range",
            fmt::format("the range {:g} m is below the smallest cell size at the bodies ({:g} m): "
                        "the film it keeps is narrower than a cell and a remesh in such a gap "
                        "can fail; 1-2 x mesh.h_body works (docs/models/fem_dem.md)",
                        cfg.repulsion_range, h_min)));
      if (rep["friction"].IsDefined())
        cfg.repulsion_friction = r.number(rep["friction"], rp + ".friction", 0, inf);
      if (rep["tangential_stiffness"].IsDefined()) {
        if (cfg.repulsion_friction == 0)
          r.fail(rep["tangential_stiffness"], rp + ".tangential_stiffness",
                 "no tangential_stiffness without a friction coefficient > 0 (the spring carries "
                 "the friction force)");
        cfg.repulsion_tangential_stiffness =
            r.number(rep["tangential_stiffness"], rp + ".tangential_stiffness", 0, inf, true);
      }
      if (rep["rolling_friction"].IsDefined()) {
        if (cfg.repulsion_friction == 0)
          r.fail(rep["rolling_friction"], rp + ".rolling_friction",
                 "no rolling_friction without a friction coefficient > 0 (the gaps' springs "
                 "are kept only with friction)");
        cfg.repulsion_rolling_friction =
            r.number(rep["rolling_friction"], rp + ".rolling_friction", 0, inf);
      }
      if (rep["core"].IsDefined()) {
        cfg.repulsion_core = r.number(rep["core"], rp + ".core", 0, inf, true);
        if (!(cfg.repulsion_core < cfg.repulsion_range))
          r.fail(rep["core"], rp + ".core",
                 fmt::format("a gap below the range ({:g} m): the core is the innermost part of "
                             "the repulsion",
                             cfg.repulsion_range));
      }
    }
  }
  if (cfg.repulsion_range == 0)
    cfg.warnings.push_back(r.warning(
        block["moving_mesh"].IsDefined() ? block["moving_mesh"] : block, root + ".moving_mesh",
        "no repulsion between bodies and walls (moving_mesh.repulsion: {range, force}): a free "
        "body that comes close to a wall or another body stops the run when the mesh in the "
        "gap can no longer be rebuilt"));
  const std::string why = fmt::format("{}.bodies[{}] ('{}') is free: it has a density", root,
                                      first_free, cfg.body_names[first_free]);
  const auto time = block["time"];
  const std::string tp = root + ".time";
  if (cfg.steady)
    r.fail(time["mode"], tp + ".mode", fmt::format("unsteady ({}, and moves in time)", why));
  if (cfg.time.adaptive && cfg.repulsion_range > 0) {
    // the error estimate does not see the explicit contact loads' stability: dt_max must
    double fastest = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < cfg.body_density.size(); ++j)
      if (cfg.body_density[j] > 0) fastest = std::min(fastest, contact_period(cfg, j));
    if (cfg.time.dt_max > fastest / 6) {
      const auto ad = time["adaptive"];
      cfg.warnings.push_back(r.warning(
          ad["dt_max"].IsDefined() ? ad["dt_max"] : ad, tp + ".adaptive.dt_max",
          fmt::format("{:g} s is more than 1/6 of the fastest contact period ({:.4g} s, `grainflow "
                      "check`): the explicit contact loads may ring or blow up at such steps, "
                      "which the error estimate does not see; {:.3g} s or less is safe",
                      cfg.time.dt_max, fastest, fastest / 6)));
    }
  }
  if (cfg.initial_steady)
    r.fail(time["initial"], tp + ".initial",
           fmt::format("rest: a run with free bodies starts from rest ({})", why));
}

}  // namespace

FemCaseConfig parse_fluid_fem(const YAML::Node& block, const std::string& file,
                              const ErrorText& error_text) {
  const Reader r(file, error_text);
  const std::string root = "fluid_fem";
  FemCaseConfig cfg;
  cfg.file = file;
  r.keys(block, root,
         {"fluid", "domain", "bodies", "mesh", "time", "newton", "output", "gravity", "tilt",
          "moving_mesh"});

  const auto fluid = r.need(block, "fluid", root);
  r.keys(fluid, root + ".fluid", {"density", "viscosity"});
  cfg.density =
      r.number(r.need(fluid, "density", root + ".fluid"), root + ".fluid.density", 0, 1e30, true);
  cfg.viscosity = r.number(r.need(fluid, "viscosity", root + ".fluid"), root + ".fluid.viscosity",
                           0, 1e30, true);

  const auto dom = r.need(block, "domain", root);
  const std::string dp = root + ".domain";
  r.keys(dom, dp, {"outline", "boundaries"});
  const auto outline = r.need(dom, "outline", dp);
  cfg.mesh.outline = r.points(outline, dp + ".outline", 3);
  // Length tolerance of the geometry checks (see check_ring): 1e-12 of the outline's size.
  const double tol = [&] {
    double lo_x = 1e300, hi_x = -1e300, lo_y = 1e300, hi_y = -1e300, coord = 0;
    for (const auto& v : cfg.mesh.outline) {
      lo_x = std::min(lo_x, v.x);
      hi_x = std::max(hi_x, v.x);
      lo_y = std::min(lo_y, v.y);
      hi_y = std::max(hi_y, v.y);
      coord = std::max({coord, std::abs(v.x), std::abs(v.y)});
    }
    return 1e-12 * std::max({hi_x - lo_x, hi_y - lo_y, coord});
  }();
  check_ring(r, outline, dp + ".outline", cfg.mesh.outline, tol);
  const std::size_t ne = cfg.mesh.outline.size();
  cfg.outline_bc.assign(ne, OutlineBc{});
  cfg.inflow_time.assign(ne, TimeFunctionSpec{});
  if (const auto bnd = dom["boundaries"]; bnd.IsDefined()) {
    const std::string bp = dp + ".boundaries";
    if (!bnd.IsSequence())
      r.fail(bnd, bp, "a list of {edges: [...], type: wall | inflow | outflow, ...}");
    std::set<int> seen;
    for (std::size_t i = 0; i < bnd.size(); ++i) {
      const auto b = bnd[i];
      const std::string p = fmt::format("{}[{}]", bp, i);
      r.keys(b, p, {"edges", "type", "profile", "u_max", "time_function"});
      const auto edges = r.need(b, "edges", p);
      if (!edges.IsSequence() || edges.size() == 0)
        r.fail(edges, p + ".edges", "a non-empty list of outline edge indices");
      const auto type = r.choice(r.need(b, "type", p), p + ".type", {"wall", "inflow", "outflow"});
      OutlineBc bc;
      bc.kind = type == "wall"     ? OutlineBcKind::Wall
                : type == "inflow" ? OutlineBcKind::Inflow
                                   : OutlineBcKind::Outflow;
      TimeFunctionSpec tf;
      if (bc.kind == OutlineBcKind::Inflow) {
        bc.u_max = r.number(r.need(b, "u_max", p), p + ".u_max");
        if (b["profile"].IsDefined())
          bc.parabolic =
              r.choice(b["profile"], p + ".profile", {"parabolic", "uniform"}) == "parabolic";
        tf = parse_time_function(r, b["time_function"], p + ".time_function");
      } else {
        for (const char* k : {"profile", "u_max", "time_function"})
          if (b[k].IsDefined())
            r.fail(b[k], p + "." + k, "no such key for a " + type + " boundary");
      }
      for (std::size_t j = 0; j < edges.size(); ++j) {
        const std::string ep = fmt::format("{}.edges[{}]", p, j);
        const double e = r.number(edges[j], ep, 0, static_cast<double>(ne - 1));
        if (e != std::floor(e))
          r.fail(edges[j], ep, fmt::format("an integer edge index in [0, {}]", ne - 1));
        if (!seen.insert(static_cast<int>(e)).second)
          r.fail(edges[j], ep, "an edge not listed before");
        cfg.outline_bc[static_cast<std::size_t>(e)] = bc;
        cfg.inflow_time[static_cast<std::size_t>(e)] = tf;
      }
    }
    // Fluid that flows in must leave: with no outflow edge the mass of an inflow has nowhere to
    // go (the solver would converge with the excess vanishing where the pressure is pinned).
    const bool outflow =
        std::any_of(cfg.outline_bc.begin(), cfg.outline_bc.end(),
                    [](const OutlineBc& b) { return b.kind == OutlineBcKind::Outflow; });
    for (std::size_t i = 0; i < bnd.size() && !outflow; ++i)
      if (bnd[i]["type"].IsScalar() && bnd[i]["type"].Scalar() == "inflow" &&
          r.number(bnd[i]["u_max"], "") != 0)
        r.fail(bnd[i]["type"], fmt::format("{}[{}].type", bp, i),
               "an outflow edge somewhere when an edge is an inflow (the inflowing fluid must "
               "leave the domain; there is no outflow edge)",
               "an inflow in a closed domain");
  }

  if (const auto bodies = block["bodies"]; bodies.IsDefined()) {
    const std::string bp = root + ".bodies";
    if (!bodies.IsSequence()) r.fail(bodies, bp, "a list of bodies");
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      const auto b = bodies[i];
      const std::string p = fmt::format("{}[{}]", bp, i);
      r.keys(b, p,
             {"name", "circle", "polygon", "centre", "velocity", "angular_velocity", "density"});
      BodyShape s;
      const auto name = b["name"];
      if (name.IsDefined() && !name.IsScalar()) r.fail(name, p + ".name", "a name (text)");
      // Refused rather than quoted in the CSV header: a column NAME.fx must read back the same
      // in every CSV reader, including a split on commas, and in the shell; the rule is the one
      // of wall names (DEM cases).
      if (name.IsDefined() && !is_column_name(name.Scalar()))
        r.fail(name, p + ".name",
               "a name of letters, digits, '_' and '-', starting with a letter or '_' (it heads "
               "the columns NAME.fx, NAME.fy, ... of fem_forces.csv)",
               "'" + printable(name.Scalar()) + "'");
      cfg.body_names.push_back(name.IsDefined() && name.IsScalar() ? name.Scalar()
                                                                   : fmt::format("body{}", i));
      if (b["circle"].IsDefined() == b["polygon"].IsDefined())
        r.fail(b, p, "exactly one of 'circle' or 'polygon'");
      if (const auto c = b["circle"]; c.IsDefined()) {
        r.keys(c, p + ".circle", {"centre", "radius"});
        s.kind = BodyShape::Kind::Circle;
        s.centre = r.vec2(r.need(c, "centre", p + ".circle"), p + ".circle.centre");
        s.radius =
            r.number(r.need(c, "radius", p + ".circle"), p + ".circle.radius", 0, 1e30, true);
        if (b["centre"].IsDefined())
          r.fail(b["centre"], p + ".centre", "no 'centre' for a circle (use circle.centre)");
      } else {
        s.kind = BodyShape::Kind::Polygon;
        s.vertices = r.points(b["polygon"], p + ".polygon", 3);
        Vec2 mean{0, 0};
        for (const auto& v : s.vertices) {
          mean.x += v.x / s.vertices.size();
          mean.y += v.y / s.vertices.size();
        }
        s.centre = b["centre"].IsDefined() ? r.vec2(b["centre"], p + ".centre") : mean;
      }
      BodyMotion m;
      if (b["velocity"].IsDefined()) m.velocity = r.vec2(b["velocity"], p + ".velocity");
      m.angular_velocity = r.number_or(b, "angular_velocity", p, 0.0);
      // A free body: its velocities above are initial values; a polygon turns about its
      // centroid (the solver's centre of a free body), so a `centre` key would be ignored.
      const double rho_s = r.number_or(b, "density", p, 0.0, 0, 1e30, true);
      if (rho_s > 0 && s.kind == BodyShape::Kind::Polygon) {
        if (b["centre"].IsDefined())
          r.fail(b["centre"], p + ".centre",
                 "no 'centre' for a free body (one with a density): it turns about its "
                 "centroid");
        s.centre = body_geometry(s).centroid;
      }
      cfg.mesh.bodies.push_back(s);
      cfg.body_motion.push_back(m);
      cfg.body_density.push_back(rho_s);
    }
    check_bodies(r, bodies, bp, cfg, tol);
  }

  const auto mesh = r.need(block, "mesh", root);
  const std::string mp = root + ".mesh";
  r.keys(mesh, mp, {"h_max", "h_body", "grading", "min_angle", "boxes"});
  cfg.mesh.h_max = r.number(r.need(mesh, "h_max", mp), mp + ".h_max", 0, 1e30, true);
  cfg.mesh.h_body = r.number_or(mesh, "h_body", mp, cfg.mesh.h_max, 0, cfg.mesh.h_max, true);
  cfg.mesh.grading = r.number_or(mesh, "grading", mp, 0.3, 0, 1e30);
  cfg.mesh.min_angle_deg = r.number_or(mesh, "min_angle", mp, 25.0, 0, 33, true);
  if (const auto boxes = mesh["boxes"]; boxes.IsDefined()) {
    if (!boxes.IsSequence())
      r.fail(boxes, mp + ".boxes", "a list of {min: [x, y], max: [x, y], h: size}");
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      const std::string p = fmt::format("{}.boxes[{}]", mp, i);
      r.keys(boxes[i], p, {"min", "max", "h"});
      SizeBox sb{r.vec2(r.need(boxes[i], "min", p), p + ".min"),
                 r.vec2(r.need(boxes[i], "max", p), p + ".max"),
                 r.number(r.need(boxes[i], "h", p), p + ".h", 0, 1e30, true)};
      if (!(sb.max.x > sb.min.x && sb.max.y > sb.min.y))
        r.fail(boxes[i]["max"], p + ".max",
               fmt::format("a corner above and to the right of min {} (x and y both larger)",
                           point_text(sb.min)),
               point_text(sb.max));
      cfg.mesh.boxes.push_back(sb);
    }
  }
  const double max_size = [&] {
    double lo_x = 1e300, hi_x = -1e300, lo_y = 1e300, hi_y = -1e300;
    for (const auto& v : cfg.mesh.outline) {
      lo_x = std::min(lo_x, v.x);
      hi_x = std::max(hi_x, v.x);
      lo_y = std::min(lo_y, v.y);
      hi_y = std::max(hi_y, v.y);
    }
    return std::max(hi_x - lo_x, hi_y - lo_y);
  }();
  if (max_size > 0 && std::max(max_size, 1e-300) / cfg.mesh.h_body > 1e4)
    r.fail(mesh["h_body"].IsDefined() ? mesh["h_body"] : mesh["h_max"], mp + ".h_body",
           fmt::format("a size >= domain size / 1e4 = {} m (more than ~1e8 cells otherwise)",
                       max_size / 1e4));
  for (std::size_t i = 0; i < cfg.mesh.boxes.size(); ++i)  // the same bound in a box
    if (max_size > 0 && max_size / cfg.mesh.boxes[i].h > 1e4)
      r.fail(mesh["boxes"][i]["h"], fmt::format("{}.boxes[{}].h", mp, i),
             fmt::format("a size >= domain size / 1e4 = {} m (more than ~1e8 cells otherwise)",
                         max_size / 1e4));
  if (const auto bodies = block["bodies"]; bodies.IsDefined())
    check_gaps(r, bodies, root + ".bodies", cfg);

  const auto time = r.need(block, "time", root);
  const std::string tp = root + ".time";
  r.keys(time, tp, {"mode", "scheme", "step", "end", "adaptive", "initial"});
  cfg.steady = r.choice(r.need(time, "mode", tp), tp + ".mode", {"steady", "unsteady"}) == "steady";
  if (!cfg.steady) {
    if (time["scheme"].IsDefined()) {
      const auto scheme =
          r.choice(time["scheme"], tp + ".scheme", {"bdf1", "bdf2", "bdf3", "auto"});
      cfg.time.variable_order = scheme == "auto";
      cfg.time.order = cfg.time.variable_order ? kMaxBdfOrder : scheme.back() - '0';
      if (cfg.time.variable_order && !time["adaptive"].IsDefined())
        r.fail(time["scheme"], tp + ".scheme",
               "bdf1, bdf2 or bdf3 (auto chooses the order from the step's error estimates, so "
               "it needs an `adaptive:` block)");
    }
    if (time["initial"].IsDefined())
      cfg.initial_steady =
          r.choice(time["initial"], tp + ".initial", {"rest", "steady"}) == "steady";
    cfg.time.dt = r.number(r.need(time, "step", tp), tp + ".step", 0, 1e30, true);
    cfg.time.t_end = r.number(r.need(time, "end", tp), tp + ".end", 0, 1e30, true);
    if (const auto ad = time["adaptive"]; ad.IsDefined()) {
      r.keys(ad, tp + ".adaptive", {"rtol", "atol", "dt_max", "dt_min"});
      cfg.time.adaptive = true;
      cfg.time.rtol = r.number_or(ad, "rtol", tp + ".adaptive", 1e-3, 0, 1, true);
      cfg.time.atol = r.number_or(ad, "atol", tp + ".adaptive", 1e-4, 0, 1e30, true);
      cfg.time.dt_max = r.number_or(ad, "dt_max", tp + ".adaptive", cfg.time.t_end, 0, 1e30, true);
      cfg.time.dt_min = r.number_or(ad, "dt_min", tp + ".adaptive", 1e-9, 0, 1e30, true);
    }
  } else {
    for (const char* k : {"scheme", "step", "end", "adaptive", "initial"})
      if (time[k].IsDefined()) r.fail(time[k], tp + "." + k, "no such key with mode: steady");
  }

  cfg.newton.reuse_factorization = !cfg.steady;  // measured: pays for time stepping (see docs)
  if (const auto nw = block["newton"]; nw.IsDefined()) {
    const std::string np = root + ".newton";
    r.keys(nw, np,
           {"tolerance", "max_iterations", "picard_iterations", "reuse_factorization", "nested"});
    cfg.newton_nested = r.boolean_or(nw, "nested", np, cfg.newton_nested);
    cfg.newton.tolerance = r.number_or(nw, "tolerance", np, cfg.newton.tolerance, 0, 1, true);
    cfg.newton.max_iterations =
        r.integer_or(nw, "max_iterations", np, cfg.newton.max_iterations, 1, 1000);
    cfg.newton.picard_iterations = r.integer_or(nw, "picard_iterations", np, 0, 0, 1000);
    cfg.newton.reuse_factorization =
        r.boolean_or(nw, "reuse_factorization", np, cfg.newton.reuse_factorization);
  }

  if (const auto out = block["output"]; out.IsDefined()) {
    const std::string op = root + ".output";
    r.keys(out, op, {"vtk_every", "csv_every", "checkpoint_every", "probes", "coefficients"});
    cfg.output.vtk_every = r.number_or(out, "vtk_every", op, 0.0, 0, 1e30);
    cfg.output.csv_every = r.number_or(out, "csv_every", op, 0.0, 0, 1e30);
    cfg.output.checkpoint_every = r.number_or(out, "checkpoint_every", op, 0.0, 0, 1e30);
    if (out["probes"].IsDefined()) {
      cfg.output.probes = r.points(out["probes"], op + ".probes", 1);
      check_probes(r, out["probes"], op + ".probes", cfg, tol);
    }
    if (const auto c = out["coefficients"]; c.IsDefined()) {
      r.keys(c, op + ".coefficients", {"velocity", "length"});
      cfg.output.coef_velocity = r.number(r.need(c, "velocity", op + ".coefficients"),
                                          op + ".coefficients.velocity", 0, 1e30, true);
      cfg.output.coef_length = r.number(r.need(c, "length", op + ".coefficients"),
                                        op + ".coefficients.length", 0, 1e30, true);
    }
  }
  parse_moving_bodies(r, block, cfg);
  return cfg;
}

namespace {

/// Shortest text that reads back to the same double.
std::string num(double v) {
  return fmt::format("{}", v);
}

void emit_point(YAML::Emitter& out, Vec2 p) {
  out << YAML::Flow << YAML::BeginSeq << num(p.x) << num(p.y) << YAML::EndSeq;
}

void emit_points(YAML::Emitter& out, const std::vector<Vec2>& v) {
  out << YAML::Flow << YAML::BeginSeq;
  for (const auto& p : v) emit_point(out, p);
  out << YAML::EndSeq;
}

}  // namespace

std::string echo_fluid_fem_yaml(const FemCaseConfig& cfg, const std::string& program_version) {
  YAML::Emitter out;
  out.SetIndent(2);
  auto key = [&out](const char* k) -> YAML::Emitter& {
    return out << YAML::Key << k << YAML::Value;
  };
  out << YAML::BeginMap;
  if (!cfg.name.empty()) key("name") << cfg.name;
  key("fluid_fem") << YAML::BeginMap;
  key("fluid") << YAML::Flow << YAML::BeginMap;
  key("density") << num(cfg.density);
  key("viscosity") << num(cfg.viscosity);
  out << YAML::EndMap << YAML::Comment("kg/m^3, kinematic m^2/s");
  key("gravity");
  emit_point(out, cfg.gravity);
  out << YAML::Comment("m/s^2, on free bodies");
  if (cfg.tilt.rate != 0) {
    key("tilt") << YAML::Flow << YAML::BeginMap;
    key("rate") << num(cfg.tilt.rate);
    key("start") << num(cfg.tilt.start);
    key("end") << num(cfg.tilt.end);
    out << YAML::EndMap << YAML::Comment("deg/s (counter-clockwise), s, s");
  }

  key("domain") << YAML::BeginMap;
  key("outline");
  emit_points(out, cfg.mesh.outline);
  key("boundaries") << YAML::BeginSeq;  // one entry per outline edge
  for (std::size_t k = 0; k < cfg.outline_bc.size(); ++k) {
    const auto& bc = cfg.outline_bc[k];
    out << YAML::Flow << YAML::BeginMap;
    key("edges") << YAML::Flow << YAML::BeginSeq << k << YAML::EndSeq;
    key("type") << (bc.kind == OutlineBcKind::Wall     ? "wall"
                    : bc.kind == OutlineBcKind::Inflow ? "inflow"
                                                       : "outflow");
    if (bc.kind == OutlineBcKind::Inflow) {
      key("profile") << (bc.parabolic ? "parabolic" : "uniform");
      key("u_max") << num(bc.u_max);
      const auto& f = cfg.inflow_time[k];
      key("time_function") << YAML::Flow << YAML::BeginMap;
      switch (f.kind) {
        case TimeFunctionSpec::Kind::Constant:
          key("type") << "constant";
          break;
        case TimeFunctionSpec::Kind::Sine:
          key("type") << "sine";
          key("period") << num(f.period);
          break;
        case TimeFunctionSpec::Kind::Ramp:
          key("type") << "ramp";
          key("duration") << num(f.duration);
          break;
      }
      out << YAML::EndMap;
    }
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;

  if (!cfg.mesh.bodies.empty()) {
    key("bodies") << YAML::BeginSeq;
    for (std::size_t j = 0; j < cfg.mesh.bodies.size(); ++j) {
      const auto& b = cfg.mesh.bodies[j];
      const double rho_s = j < cfg.body_density.size() ? cfg.body_density[j] : 0.0;
      out << YAML::Flow << YAML::BeginMap;
      key("name") << cfg.body_names[j];
      if (b.kind == BodyShape::Kind::Circle) {
        key("circle") << YAML::Flow << YAML::BeginMap;
        key("centre");
        emit_point(out, b.centre);
        key("radius") << num(b.radius);
        out << YAML::EndMap;
      } else {
        key("polygon");
        emit_points(out, b.vertices);
        if (rho_s == 0) {  // (a free polygon turns about its centroid)
          key("centre");
          emit_point(out, b.centre);
        }
      }
      key("velocity");
      emit_point(out, cfg.body_motion[j].velocity);
      key("angular_velocity") << num(cfg.body_motion[j].angular_velocity);
      if (rho_s > 0) key("density") << num(rho_s);
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }

  key("mesh") << YAML::Flow << YAML::BeginMap;
  key("h_max") << num(cfg.mesh.h_max);
  key("h_body") << num(cfg.mesh.h_body);
  key("grading") << num(cfg.mesh.grading);
  key("min_angle") << num(cfg.mesh.min_angle_deg);
  key("boxes") << YAML::Flow << YAML::BeginSeq;
  for (const auto& b : cfg.mesh.boxes) {
    out << YAML::Flow << YAML::BeginMap;
    key("min");
    emit_point(out, b.min);
    key("max");
    emit_point(out, b.max);
    key("h") << num(b.h);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  if (cfg.has_free_bodies()) {
    key("moving_mesh") << YAML::Flow << YAML::BeginMap;
    key("remesh_ratio") << num(cfg.remesh_ratio);
    key("remesh_quality") << num(cfg.remesh_quality);
    if (cfg.repulsion_range > 0) {
      key("repulsion") << YAML::Flow << YAML::BeginMap;
      key("range") << num(cfg.repulsion_range);
      key("force") << num(cfg.repulsion_force);
      if (cfg.repulsion_friction > 0) key("friction") << num(cfg.repulsion_friction);
      if (cfg.repulsion_tangential_stiffness > 0)
        key("tangential_stiffness") << num(cfg.repulsion_tangential_stiffness);
      if (cfg.repulsion_rolling_friction > 0)
        key("rolling_friction") << num(cfg.repulsion_rolling_friction);
      if (cfg.repulsion_core > 0) key("core") << num(cfg.repulsion_core);
      out << YAML::EndMap;
    }
    out << YAML::EndMap;
  }

  key("time") << YAML::Flow << YAML::BeginMap;
  const auto& t = cfg.time;
  if (cfg.steady) {
    key("mode") << "steady";
  } else {
    key("mode") << "unsteady";
    key("scheme") << (t.variable_order ? std::string("auto") : fmt::format("bdf{}", t.order));
    key("step") << num(t.dt);
    key("end") << num(t.t_end);
    key("initial") << (cfg.initial_steady ? "steady" : "rest");
    if (t.adaptive) {
      key("adaptive") << YAML::Flow << YAML::BeginMap;
      key("rtol") << num(t.rtol);
      key("atol") << num(t.atol);
      key("dt_max") << num(t.dt_max);
      key("dt_min") << num(t.dt_min);
      out << YAML::EndMap;
    }
  }
  out << YAML::EndMap;

  key("newton") << YAML::Flow << YAML::BeginMap;
  key("tolerance") << num(cfg.newton.tolerance);
  key("max_iterations") << cfg.newton.max_iterations;
  key("picard_iterations") << cfg.newton.picard_iterations;
  key("reuse_factorization") << cfg.newton.reuse_factorization;
  key("nested") << cfg.newton_nested;
  out << YAML::EndMap;

  key("output") << YAML::BeginMap;
  const auto& o = cfg.output;
  key("vtk_every") << num(o.vtk_every);
  key("csv_every") << num(o.csv_every);
  key("checkpoint_every") << num(o.checkpoint_every);
  if (!o.probes.empty()) {
    key("probes");
    emit_points(out, o.probes);
  }
  if (o.coef_velocity > 0) {
    key("coefficients") << YAML::Flow << YAML::BeginMap;
    key("velocity") << num(o.coef_velocity);
    key("length") << num(o.coef_length);
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  out << YAML::EndMap;  // fluid_fem

  if (!cfg.output_directory.empty()) {
    key("output") << YAML::Flow << YAML::BeginMap;
    key("directory") << cfg.output_directory;
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  return fmt::format(
      "# grainflow {}: resolved configuration of {} (defaults filled in; SI units)\n{}\n",
      program_version, cfg.file, out.c_str());
}

Mesh build_case_mesh(const FemCaseConfig& cfg) {
  // The case reader refuses the geometries known to break the mesher; what still fails is named
  // by the keys that make the geometry, without a line (no single one is at fault).
  auto refuse = [&cfg](const std::string& why) {
    std::string text = why;
    if (text.rfind("fluid_fem mesh: ", 0) == 0) text = text.substr(16);
    return InputError(fmt::format(
        "{}: error: fluid_fem.domain.outline / fluid_fem.bodies / fluid_fem.mesh: the fluid "
        "region cannot be meshed: {}",
        cfg.file, text));
  };
  try {
    return build_mesh(cfg.mesh);
  } catch (const InputError& e) {  // (CGAL's own failures arrive as InputError too)
    throw refuse(e.what());
  } catch (const std::bad_alloc&) {
    throw refuse("its mesh does not fit in memory (raise mesh.h_max, mesh.h_body or the boxes' h)");
  }
  // (a gf::Error, a mesh that fails the mesher's own checks, is a program error: exit status 1,
  // not the user's geometry)
}

std::vector<std::pair<std::string, std::string>> describe_case(const FemCaseConfig& cfg) {
  std::vector<std::pair<std::string, std::string>> rows;
  auto row = [&rows](std::string label, std::string value) {
    rows.emplace_back(std::move(label), std::move(value));
  };
  std::string names;
  double size = 0.0;  // largest body extent [m]
  for (std::size_t j = 0; j < cfg.mesh.bodies.size(); ++j) {
    const auto& b = cfg.mesh.bodies[j];
    names += (j ? ", " : "") + cfg.body_names[j];
    double d = 2.0 * b.radius;
    if (b.kind == BodyShape::Kind::Polygon)
      for (const auto& p : b.vertices)
        for (const auto& q : b.vertices) d = std::max(d, std::hypot(p.x - q.x, p.y - q.y));
    size = std::max(size, d);
  }
  row("bodies",
      fmt::format("{}{}", cfg.mesh.bodies.size(), names.empty() ? "" : " (" + names + ")"));
  const Mesh mesh = build_case_mesh(cfg);
  int n_free = 0;
  for (const double d : cfg.body_density) n_free += d > 0 ? 1 : 0;
  row("mesh: cells, P2 nodes, unknowns",
      fmt::format("{}, {}, {}", mesh.n_cells(), mesh.n_nodes(),
                  2 * mesh.n_nodes() + mesh.n_vertices + 3 * n_free));
  row("mesh sizes h_body, h_max (m)", fmt::format("{:g}, {:g}", cfg.mesh.h_body, cfg.mesh.h_max));
  row("density (kg/m^3), viscosity (m^2/s)", fmt::format("{:g}, {:g}", cfg.density, cfg.viscosity));
  double u_settle = 0.0;  // largest settling speed estimate of a free body [m/s]
  if (n_free > 0) {
    row("moving mesh (free bodies)",
        fmt::format("{} free of {} bodies; every body moves with its velocity; remesh below {:g} "
                    "x the fresh quality or {:g}",
                    n_free, cfg.mesh.bodies.size(), cfg.remesh_ratio, cfg.remesh_quality));
    row("gravity (m/s^2)", fmt::format("[{:g}, {:g}]", cfg.gravity.x, cfg.gravity.y));
    if (cfg.tilt.rate != 0) {
      const Vec2 last = cfg.tilt.gravity(cfg.gravity, cfg.tilt.end);
      row("tilt",
          fmt::format("{:g} deg/s from {:g} s to {:g} s: {:g} deg, gravity then [{:.4g}, "
                      "{:.4g}] m/s^2 in the domain's frame",
                      cfg.tilt.rate, cfg.tilt.start, cfg.tilt.end,
                      cfg.tilt.angle(cfg.tilt.end) * 180.0 / std::numbers::pi, last.x, last.y));
    }
  }
  const double g = std::hypot(cfg.gravity.x, cfg.gravity.y);
  if (n_free > 0 && cfg.repulsion_range > 0) {
    // What the films can carry: the bounded law at most F_0; a bed's lowest films carry the
    // grains above them.
    double heaviest = 0.0, total = 0.0;
    for (std::size_t j = 0; j < cfg.body_density.size(); ++j)
      if (cfg.body_density[j] > 0) {
        const double w = std::abs(cfg.body_density[j] - cfg.density) * g *
                         body_geometry(cfg.mesh.bodies[j]).area;
        heaviest = std::max(heaviest, w);
        total += w;
      }
    std::string load = heaviest > 0
                           ? fmt::format(
                                 " = {:.3g} x the heaviest free body's buoyant weight ({:.3g} "
                                 "x all free bodies' together)",
                                 cfg.repulsion_force / heaviest, cfg.repulsion_force / total)
                           : "";
    const double rc = cfg.repulsion_core, range = cfg.repulsion_range;
    std::string core =
        "at most F_0 per film: a film loaded beyond it closes and the run fails "
        "(a core, repulsion.core, holds larger loads)";
    if (rc > 0) {
      // the gap that carries 2 F_0: s^2 g_c / g = 2 (decreasing in g; bisection)
      double lo = 0.01 * rc, hi = rc;
      for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi), s = (range - mid) / range;
        (s * s * rc / mid > 2.0 ? lo : hi) = mid;
      }
      // undamped period of the lightest free body on two such films (stiffness L^2 / (F_0 g)
      // each, d/dg of F_0 s^2 g_c / g without the outer factor's slope)
      double mass = std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j < cfg.body_density.size(); ++j)
        if (cfg.body_density[j] > 0)
          mass = std::min(mass, cfg.body_density[j] * body_geometry(cfg.mesh.bodies[j]).area);
      const double k = 2.0 * 2.0 * cfg.repulsion_force / lo;
      const double period = 2 * std::numbers::pi * std::sqrt(mass / k);
      core = fmt::format(
          "core {:g} m: a film holds a load L > F_0 in a gap ~ g_c F_0 / L (2 F_0 at {:.3g} m; at "
          "most ~100 F_0, at g_c / 100); loaded with 2 F_0 the lightest free body's undamped "
          "contact period is {:.3g} s = {:.3g} {} (the squeeze films damp it; a body that rings "
          "there needs a smaller step)",
          rc, lo, period, period / (cfg.time.adaptive ? cfg.time.dt_max : cfg.time.dt),
          cfg.time.adaptive ? "x time.adaptive.dt_max" : "steps");
    }
    row("repulsion", fmt::format("range {:g} m, force scale F_0 {:g} N/m{}; {}", range,
                                 cfg.repulsion_force, load, core));
  }
  const double mu = cfg.density * cfg.viscosity;
  for (std::size_t j = 0; j < cfg.body_density.size(); ++j) {
    const double rho_s = cfg.body_density[j];
    if (rho_s <= 0) continue;
    const auto& b = cfg.mesh.bodies[j];
    const std::string who = fmt::format("'{}': ", cfg.body_names[j]);
    const BodyGeometry geo = body_geometry(b);  // about the centroid, the body's centre
    const double area = geo.area, polar = geo.polar_moment;
    const double ratio = rho_s / cfg.density;
    const double d = 2.0 * std::sqrt(area / std::numbers::pi);  // (area-) equivalent diameter
    row(who + "mass (kg/m), moment of inertia (kg m), per unit depth",
        fmt::format("{:.4g}, {:.4g}", rho_s * area, rho_s * polar));
    row(who + "density ratio rho_s / rho_f", fmt::format("{:.4g}", ratio));
    if (cfg.repulsion_range > 0 && !cfg.steady) {
      const double period = contact_period(cfg, j);
      // (adaptive steps: counted in the largest step the controller may take)
      const double step = cfg.time.adaptive ? cfg.time.dt_max : cfg.time.dt;
      const double steps = period / step;
      row(who + "fastest contact period (s)",
          fmt::format("{:.4g} = {:.3g} {}{}", period, steps,
                      cfg.time.adaptive ? "x time.adaptive.dt_max" : "steps",
                      steps < 6 ? fmt::format(" (< 6: the explicit contact loads may ring or blow "
                                              "up; lower the {}, the force or the tangential "
                                              "stiffness)",
                                              cfg.time.adaptive ? "dt_max" : "step")
                                : ""));
    }
    if (g == 0) {
      row(who + "buoyant weight", "none (no gravity)");
      continue;
    }
    const double weight = (rho_s - cfg.density) * g * area;
    row(who + "buoyant weight (rho_s - rho_f) g A (N/m)", fmt::format("{:.4g}", weight));
    row(who + "Archimedes number |rho_s/rho_f - 1| g d^3 / nu^2",
        fmt::format("{:.4g} (d = {:.4g} m, the diameter of equal area)",
                    std::abs(ratio - 1) * g * d * d * d / (cfg.viscosity * cfg.viscosity), d));
    // A cylinder's Stokes drag has no unbounded limit (Stokes' paradox): it is set by the
    // walls. Faxen's drag of a cylinder midway between two walls, at its distance l to the
    // outline from each (Happel & Brenner 1965, sec. 7-4), F = 4 pi mu U / (ln(1/k) - 0.9157 +
    // 1.7244 k^2 - 1.7302 k^4 + 2.4056 k^6 - 4.5913 k^8), k = a / l, balanced against the
    // buoyant weight: exact for that geometry at Re << 1, a scale elsewhere.
    const double a = 0.5 * d;
    const double l = ring_distance(b.centre, cfg.mesh.outline);
    const double k = a / l, k2 = k * k;
    const double denom = std::log(1 / k) - 0.9157 + 1.7244 * k2 - 1.7302 * k2 * k2 +
                         2.4056 * k2 * k2 * k2 - 4.5913 * k2 * k2 * k2 * k2;
    if (k > 0.5 || denom <= 0) {
      row(who + "settling speed estimate (Faxen)",
          fmt::format("none: the outline is too close (k = a / l = {:.3g} > 0.5)", k));
      continue;
    }
    const double u = std::abs(weight) * denom / (4 * std::numbers::pi * mu);
    u_settle = std::max(u_settle, u);
    row(who + "settling speed estimate U (m/s)",
        fmt::format("{:.4g} (Faxen's drag between walls {:.4g} m away, k = {:.3g}; Stokes flow)", u,
                    l, k));
    row(who + "Reynolds number U d / nu of that speed",
        fmt::format(
            "{:.4g}{}", u * d / cfg.viscosity,
            u * d / cfg.viscosity > 1 ? " (> 1: inertia lowers the speed; a scale only)" : ""));
  }
  double u_max = 0.0, u_mean = 0.0;  // at full strength of the time functions
  for (const auto& bc : cfg.outline_bc)
    if (bc.kind == OutlineBcKind::Inflow) {
      u_max = std::max(u_max, bc.u_max);
      u_mean = std::max(u_mean, bc.parabolic ? 2.0 / 3.0 * bc.u_max : bc.u_max);
    }
  for (const auto& m : cfg.body_motion)
    u_max = std::max(u_max, std::hypot(m.velocity.x, m.velocity.y));
  if (u_mean > 0) {
    row("mean inflow speed U (m/s)", fmt::format("{:g}", u_mean));
    if (size > 0)
      row("Reynolds number U D / nu (D: largest body)",
          fmt::format("{:.4g} (D = {:g} m)", u_mean * size / cfg.viscosity, size));
  }
  if (cfg.steady) {
    row("time stepping", "steady (Newton)");
    return rows;
  }
  const auto& t = cfg.time;
  row("time stepping",
      fmt::format("unsteady, BDF{}{}, {} step {:g} s, end {:g} s", t.variable_order ? "1-" : "",
                  t.order, t.adaptive ? "adaptive, first" : "fixed", t.dt, t.t_end));
  if (!t.adaptive) row("steps", fmt::format("{}", std::llround(t.t_end / t.dt)));
  if (u_max > 0)
    row("Courant number u_max dt / h_body", fmt::format("{:.3g}", u_max * t.dt / cfg.mesh.h_body));
  if (u_settle > 0)
    row("settling travel per step U dt / h_body",
        fmt::format("{:.3g}", u_settle * t.dt / cfg.mesh.h_body));
  row("viscous number nu dt / h_body^2",
      fmt::format("{:.3g}", cfg.viscosity * t.dt / (cfg.mesh.h_body * cfg.mesh.h_body)));
  return rows;
}

namespace {

/// The header line and the rows up to time `until` [s] of a CSV an earlier run wrote (first
/// column t, 9 significant digits: compared with a relative tolerance of 1e-8), for --append.
std::string kept_csv(const std::filesystem::path& file, const std::string& header, double until) {
  std::string out = header + '\n';
  for (const auto& line : continued_csv_lines(
           file, header, [until](double t) { return t <= until * (1 + 1e-8) + 1e-300; }))
    out += line + '\n';
  return out;
}

}  // namespace

std::uint64_t mesh_hash(const Mesh& m) {
  std::uint64_t h = 1469598103934665603ULL;
  auto add = [&h](const void* data, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ULL;
  };
  add(m.nodes.data(), m.nodes.size() * sizeof(Vec2));
  add(m.cells.data(), m.cells.size() * sizeof(m.cells[0]));
  return h;
}

int run_fluid_fem(const FemCaseConfig& cfg, const std::filesystem::path& output_dir, int max_steps,
                  const FemCheckpointIo& io, const FemMovingFlowFactory& moving_factory) {
  const auto t_start = std::chrono::steady_clock::now();
  std::filesystem::create_directories(output_dir);
  FlowProblem pb;
  pb.spec = cfg.mesh;
  pb.mesh = build_case_mesh(cfg);
  pb.density = cfg.density;
  pb.viscosity = cfg.viscosity;
  pb.outline_bc = cfg.outline_bc;
  for (std::size_t k = 0; k < pb.outline_bc.size(); ++k)
    if (cfg.inflow_time[k].kind != TimeFunctionSpec::Kind::Constant)
      pb.outline_bc[k].time_function = cfg.inflow_time[k];
  pb.body_motion = cfg.body_motion;
  pb.body_density = cfg.body_density;
  pb.gravity = cfg.gravity;
  pb.tilt = cfg.tilt;
  // Free bodies: the flow lives in the moving run (a remesh replaces it); else here.
  const bool is_moving = cfg.has_free_bodies();
  // the mesh the case starts on: a checkpoint of this case was written by a run that started on
  // the same one (a moving run meshes again later)
  const std::uint64_t start_mesh_hash = mesh_hash(pb.mesh);
  REQUIRE(!is_moving || moving_factory,
          "run_fluid_fem: a case with free bodies needs the moving-mesh driver (coupling layer)");
  std::unique_ptr<NavierStokes> fixed;
  std::unique_ptr<FemMovingFlow> moving;
  if (is_moving)
    moving = moving_factory(std::move(pb), cfg);
  else
    fixed = std::make_unique<NavierStokes>(std::move(pb));
  auto flow = [&]() -> const NavierStokes& { return moving ? moving->flow() : *fixed; };
  const std::size_t nb = cfg.mesh.bodies.size();

  std::string forces_header = "t,dt,order";  // dt and BDF order of the step that ended at t
  for (std::size_t j = 0; j < nb; ++j) {
    const auto& n = cfg.body_names[j];
    forces_header += fmt::format(",{0}.fx,{0}.fy,{0}.torque,{0}.fx_stress,{0}.fy_stress", n);
    if (cfg.output.coef_velocity > 0) forces_header += fmt::format(",{0}.cd,{0}.cl", n);
    if (is_moving)
      forces_header += fmt::format(",{0}.x,{0}.y,{0}.angle,{0}.vx,{0}.vy,{0}.omega", n);
  }
  std::string probes_header = "t";
  for (std::size_t i = 0; i < cfg.output.probes.size(); ++i)
    probes_header += fmt::format(",p{0},ux{0},uy{0}", i);
  // --append: the rows the earlier run wrote up to the checkpoint come first.
  const bool append = io.resume && io.append;
  std::ostringstream forces, probes;
  forces << (append ? kept_csv(output_dir / "fem_forces.csv", forces_header, io.resume->flow.t)
                    : forces_header + '\n');
  probes << (append ? kept_csv(output_dir / "fem_probes.csv", probes_header, io.resume->flow.t)
                    : probes_header + '\n');
  auto record = [&](const NavierStokes& s, double dt) {
    const auto fr = s.reaction_forces();
    const auto fs = s.stress_forces();
    forces << fmt::format("{:.9g},{:.6g},{}", s.time(), dt, s.last_order());
    for (std::size_t j = 0; j < nb; ++j) {
      forces << fmt::format(",{:.10g},{:.10g},{:.10g},{:.10g},{:.10g}", fr[j].force.x,
                            fr[j].force.y, fr[j].torque, fs[j].force.x, fs[j].force.y);
      if (cfg.output.coef_velocity > 0) {
        const double sc = 2.0 / (cfg.density * cfg.output.coef_velocity * cfg.output.coef_velocity *
                                 cfg.output.coef_length);
        forces << fmt::format(",{:.10g},{:.10g}", sc * fr[j].force.x, sc * fr[j].force.y);
      }
      if (moving) {
        const int b = static_cast<int>(j);
        const Vec2 c = moving->centre(b);
        const BodyMotion v = s.body_velocity(b);
        forces << fmt::format(",{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g}", c.x, c.y,
                              moving->angle(b), v.velocity.x, v.velocity.y, v.angular_velocity);
      }
    }
    forces << '\n';
    probes << fmt::format("{:.9g}", s.time());
    for (const auto& p : cfg.output.probes) {
      const Vec2 u = s.velocity_at(p);
      probes << fmt::format(",{:.10g},{:.10g},{:.10g}", s.pressure_at(p), u.x, u.y);
    }
    probes << '\n';
  };
  const FemCheckpoint* resume = io.resume;
  if (resume) {
    if (cfg.steady)
      throw InputError(
          fmt::format("{}: error: --restart: a steady fluid_fem case has no time "
                      "steps to continue",
                      cfg.file));
    if (resume->mesh_hash != start_mesh_hash)
      throw InputError(fmt::format(
          "{}: error: --restart: the checkpoint belongs to another mesh (the case's domain, "
          "bodies or mesh sizes changed, or another build meshed it)",
          cfg.file));
    if (resume->moving.has_value() != is_moving)
      throw InputError(fmt::format(
          "{}: error: --restart: the checkpoint is of a run {} free bodies and this case has {} "
          "(a body's density changed)",
          cfg.file, is_moving ? "without" : "with", is_moving ? "some" : "none"));
    if (moving) {
      std::vector<double> density = cfg.body_density;
      density.resize(nb, 0.0);
      if (resume->moving->body_density != density)
        throw InputError(fmt::format(
            "{}: error: --restart: the checkpoint's bodies have other densities (which bodies are "
            "free, or how heavy, changed since it was written)",
            cfg.file));
      moving->restore(resume->flow, *resume->moving);
    } else
      fixed->restore(resume->flow);
  }
  // (appending: the data sets up to and including the checkpoint's time stay; the state there
  // is not written again)
  // (checkpoints before 2026-12-01 did not record fields_until: everything up to their time)
  const double fields_until = !append ? 0.0 : resume->fields_until.value_or(resume->flow.t);
  vtk::PvdSeries series =
      append ? vtk::PvdSeries(output_dir / "fem_fields.pvd",
                              std::nextafter(fields_until, std::numeric_limits<double>::max()))
             : vtk::PvdSeries(output_dir / "fem_fields.pvd");
  // Numbering of the field files continues over restarts (an appended series also keeps the
  // earlier run's data sets up to the checkpoint).
  const std::int64_t fields_before =
      (resume ? resume->n_fields : 0) - static_cast<std::int64_t>(series.size());
  auto fields_written = [&] { return fields_before + static_cast<std::int64_t>(series.size()); };
  auto flush = [&] {
    write_atomically(output_dir / "fem_forces.csv", [&](std::ostream& os) { os << forces.str(); });
    write_atomically(output_dir / "fem_probes.csv", [&](std::ostream& os) { os << probes.str(); });
  };
  // The divergence watchdog: what of a state is not finite ("" when all is), checked before
  // anything of it is written. (Newton's method refuses a non-finite iterate, so a step that
  // blows up is retried with smaller steps and fails as StepFailure; this catches the rest,
  // e.g. forces that overflow.)
  auto non_finite = [&](const NavierStokes& s) -> std::string {
    for (const double v : s.solution())
      if (!std::isfinite(v)) return "the velocity or pressure";
    for (std::size_t j = 0; moving && j < nb; ++j) {
      const int b = static_cast<int>(j);
      const Vec2 c = moving->centre(b);
      if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(moving->angle(b)))
        return fmt::format("the position of body '{}'", cfg.body_names[j]);
    }
    const auto fr = s.reaction_forces();
    const auto fs = s.stress_forces();
    for (std::size_t j = 0; j < nb; ++j)
      for (const double v :
           {fr[j].force.x, fr[j].force.y, fr[j].torque, fs[j].force.x, fs[j].force.y})
        if (!std::isfinite(v)) return fmt::format("the force on body '{}'", cfg.body_names[j]);
    return {};
  };
  auto write_fields = [&](const NavierStokes& s) {
    const std::string name = fmt::format("fem_fields_{:05d}.vtu", fields_written());
    write_vtu(output_dir / name, s);
    series.add(s.time(), name);
    flush();
  };

  // Steady Newton solve for the boundary data at the current time (steady mode, or the
  // consistent initial state of an unsteady run); a steady solve gains nothing from the chord
  // method, so an unsteady run's reuse_factorization is switched off for it.
  auto solve_steady = [&](const char* what) {
    NewtonOptions opt = cfg.newton;
    if (!cfg.steady) opt.reuse_factorization = false;
    const auto rep =
        cfg.newton_nested ? solve_steady_nested(*fixed, opt) : fixed->solve_steady(opt);
    if (!rep.converged)
      throw Error(fmt::format(
          "fluid_fem: {} Newton did not converge in {} iterations (last update {:.3g}); "
          "try newton.picard_iterations or a finer mesh",
          what, rep.iterations, rep.last_update));
    return fmt::format("{}: Newton iterations {}, factorizations {}\n", what, rep.iterations,
                       rep.factorizations);
  };
  std::string summary;
  int stop_signal = 0;
  if (cfg.steady) {
    summary = solve_steady("steady");
    if (const auto bad = non_finite(*fixed); !bad.empty())
      throw Error(fmt::format("fluid_fem: the steady solution diverged: {} is not finite", bad));
    record(*fixed, 0.0);
    write_fields(*fixed);
  } else {
    if (cfg.initial_steady && !resume) summary = solve_steady("initial steady state");
    if (!append) write_fields(flow());
    double next_vtk = cfg.output.vtk_every, next_csv = 0.0;
    double next_ckpt = cfg.output.checkpoint_every;
    std::int64_t steps_before = 0;
    TimeLoopState loop;
    if (resume) {
      next_vtk = resume->next_vtk;
      next_csv = resume->next_csv;
      next_ckpt = resume->next_checkpoint;
      steps_before = resume->steps;
      loop = resume->loop;
      summary = fmt::format("continued from t = {:.9g} s (step {})\n", flow().time(), steps_before);
    }
    std::int64_t steps = steps_before;
    auto checkpoint = [&](const std::string& name) {
      if (!io.save) return;
      FemCheckpoint c;
      c.flow = flow().state();
      if (moving) c.moving = moving->state();
      c.loop = loop;
      c.steps = steps;
      c.next_vtk = next_vtk;
      c.next_csv = next_csv;
      c.next_checkpoint = next_ckpt;
      c.n_fields = fields_written();
      c.mesh_hash = start_mesh_hash;
      c.fields_until =
          series.size() > 0 ? series.last_time() : -std::numeric_limits<double>::infinity();
      c.runs = (resume ? resume->runs : 0) + 1;
      c.wall_seconds =
          (resume ? resume->wall_seconds : 0.0) +
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
      flush();  // the series up to the checkpoint are on disk with it
      io.save(output_dir / name, c);
    };
    // Advances an output time past t by whole intervals (at least one).
    auto advance = [](double& next, double every, double t) {
      next += every * std::max(1.0, std::floor((t - next) / every + 1));
    };
    TimeControl tc = cfg.time;
    tc.max_steps = max_steps;
    // A run that diverges stops with an error (exit status 1) naming the time and the step; the
    // series are written up to the last good step (into the folder a failed run leaves, see
    // simulation/output_folder.hpp), nothing of the failed step.
    auto diverged = [&](const std::string& why) {
      flush();
      return Error(fmt::format(
          "fluid_fem: the run diverged at t = {:.9g} s (step {}): {}; nothing of that step was "
          "written. Try a smaller time.step (or adaptive steps, time.adaptive), a finer mesh, "
          "or a slower inflow",
          flow().time(), steps + 1, why));
    };
    // After every accepted step: the watchdog, then the outputs due.
    auto observe = [&](const NavierStokes& s, double h) {
      if (const auto bad = non_finite(s); !bad.empty()) throw diverged(bad + " is not finite");
      ++steps;
      const double eps = 1e-9 * h;
      if (s.time() >= next_csv - eps) {
        record(s, h);
        next_csv = s.time() + cfg.output.csv_every;
      }
      if (cfg.output.vtk_every > 0 && s.time() >= next_vtk - eps) {
        write_fields(s);
        advance(next_vtk, cfg.output.vtk_every, s.time());
      }
      if (cfg.output.checkpoint_every > 0 && s.time() >= next_ckpt - eps &&
          s.time() < cfg.time.t_end - eps) {
        advance(next_ckpt, cfg.output.checkpoint_every, s.time());
        checkpoint(fmt::format("fem_checkpoint_{:07d}.h5", steps));
      }
    };
    TimeStats st;
    try {
      st = moving ? integrate(*moving, tc, cfg.newton, observe, &loop)
                  : integrate(*fixed, tc, cfg.newton, observe, &loop);
    } catch (const StepFailure& e) {
      throw diverged(e.what());
    }
    // The last state is always written out; the checkpoint comes first, so that it does not
    // count that data set as one of the schedule's (unless the schedule just wrote it): a run
    // continued in place (--append) drops it and numbers its next file as a run never stopped.
    checkpoint(st.stop_signal ? fmt::format("fem_checkpoint_{:07d}.h5", steps)
                              : std::string("fem_checkpoint_final.h5"));
    if (cfg.output.vtk_every == 0 || series.last_time() < flow().time()) write_fields(flow());
    summary += fmt::format(
        "unsteady BDF{}{}: steps {} (at orders 1/2/3: {}/{}/{}), rejected {}, Newton iterations "
        "{}, factorizations {}\n",
        cfg.time.variable_order ? "1-" : "", cfg.time.order, st.steps, st.steps_at_order[1],
        st.steps_at_order[2], st.steps_at_order[3], st.rejected, st.newton_iterations,
        st.factorizations);
    if (moving) {
      summary += fmt::format("moving mesh: remeshes {}\n", moving->remeshes());
      for (std::size_t j = 0; j < nb; ++j) {
        const int b = static_cast<int>(j);
        const Vec2 c = moving->centre(b);
        const BodyMotion v = flow().body_velocity(b);
        summary += fmt::format(
            "body '{}' at t = {:.9g} s: centre [{:.9g}, {:.9g}] m, angle {:.9g} rad, velocity "
            "[{:.9g}, {:.9g}] m/s, angular velocity {:.9g} rad/s\n",
            cfg.body_names[j], flow().time(), c.x, c.y, moving->angle(b), v.velocity.x,
            v.velocity.y, v.angular_velocity);
      }
    }
    if (resume) {
      summary += fmt::format("steps since t = 0 (over restarts): {}\n", steps);
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
      summary += std::isnan(resume->wall_seconds)
                     ? fmt::format("runs over restarts: {}\n", resume->runs + 1)
                     : fmt::format("runs over restarts: {}, wall time of them all {:.3f} s\n",
                                   resume->runs + 1, resume->wall_seconds + wall);
    }
    if ((stop_signal = st.stop_signal))
      summary += fmt::format("stopped by {} at t = {:.9g} s (time.end {} s)\n",
                             stop::signal_name(stop_signal), flow().time(), cfg.time.t_end);
  }
  const NavierStokes& ns = flow();
  write_vtu(output_dir / "fem_mesh.vtu", ns);
  flush();
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  summary += fmt::format(
      "cells {}, P2 nodes {}, unknowns {}\nwall time {:.3f} s (assembly {:.3f} s, LU factorisation "
      "{:.3f} s, LU solves {:.3f} s{})\n",
      ns.mesh().n_cells(), ns.mesh().n_nodes(), ns.n_dofs(), wall, ns.assembly_seconds(),
      ns.lu().factor_seconds(), ns.lu().solve_seconds(),
      moving && moving->remeshes() > 0 ? "; these three on the last mesh only" : "");
  write_atomically(output_dir / "fem_summary.txt", [&](std::ostream& os) { os << summary; });
  return stop_signal;
}

}  // namespace gf::fem
