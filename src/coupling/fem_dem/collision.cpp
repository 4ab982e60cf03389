// SPDX-License-Identifier: GPL-3.0-or-later
// Short-range repulsion between fluid_fem bodies: gaps from probe points, Glowinski's force law.
#include "coupling/fem_dem/collision.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gf::fem_dem {

namespace {

using fem::BodyShape;

struct Probe {
  Vec2 p;
  double radius = 0;  // the probe's surface lies this far from p
};

std::vector<Probe> probes(const BodyShape& b) {
  if (b.kind == BodyShape::Kind::Circle) return {{b.centre, b.radius}};
  std::vector<Probe> out;
  for (const Vec2& v : b.vertices) out.push_back({v, 0.0});
  return out;
}

Vec2 closest_on_segment(Vec2 p, Vec2 a, Vec2 b) {
  const double ex = b.x - a.x, ey = b.y - a.y;
  const double l2 = ex * ex + ey * ey;
  const double t = l2 > 0 ? ((p.x - a.x) * ex + (p.y - a.y) * ey) / l2 : 0;
  if (t <= 0) return a;  // the ends exactly (corners are recognised by equality)
  if (t >= 1) return b;
  return {a.x + t * ex, a.y + t * ey};
}

double dist(Vec2 a, Vec2 b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

/// Closest point of a closed polyline to p.
Vec2 closest_on_polygon(Vec2 p, const std::vector<Vec2>& v) {
  Vec2 best = v[0];
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Vec2 q = closest_on_segment(p, v[i], v[(i + 1) % v.size()]);
    const double dq = dist(p, q);
    if (dq < d) {
      d = dq;
      best = q;
    }
  }
  return best;
}

/// Closest point of a body's surface to p.
Vec2 closest_on_body(Vec2 p, const BodyShape& b) {
  if (b.kind == BodyShape::Kind::Polygon) return closest_on_polygon(p, b.vertices);
  const double d = dist(p, b.centre);
  if (d == 0) return {b.centre.x + b.radius, b.centre.y};
  return {b.centre.x + b.radius * (p.x - b.centre.x) / d,
          b.centre.y + b.radius * (p.y - b.centre.y) / d};
}

using fem::inside_polygon;

bool inside_body(Vec2 p, const BodyShape& b) {
  if (b.kind == BodyShape::Kind::Polygon) return inside_polygon(p, b.vertices);
  return dist(p, b.centre) < b.radius;
}

/// One gap: the probe's surface point, the facing point and the gap g (negative: overlap).
struct Gap {
  Vec2 on_probe, facing;
  Vec2 n;  // unit, from the facing surface towards the probe
  double g = 0;
  double weight = 1;  // 1/2 where both bodies probe the same corner
};

/// The gap from a probe to the facing point q; `overlap`: the probe point lies on the far side
/// of the facing surface (inside the other body, or outside the outline).
Gap gap_of(const Probe& pr, Vec2 q, bool overlap) {
  Gap out;
  const double d = dist(pr.p, q);
  const double s = overlap ? -1.0 : 1.0;
  out.n = d > 0 ? Vec2{s * (pr.p.x - q.x) / d, s * (pr.p.y - q.y) / d} : Vec2{0, 1};
  out.g = s * d - pr.radius;
  out.on_probe = {pr.p.x - pr.radius * out.n.x, pr.p.y - pr.radius * out.n.y};
  out.facing = q;
  return out;
}

/// Calls f(gap, probe body, facing body or -1 for the outline) for every probe and facing
/// surface: every outline edge (a disk in a corner feels both walls; an outline corner counts
/// once), every other body; circle against circle and circle against polygon are probed from
/// the circle only, and where two polygons' corners meet each probe carries half the force.
template <class F>
void for_each_gap(const fem::MeshSpec& spec, F&& f) {
  const int n = static_cast<int>(spec.bodies.size());
  const auto& ol = spec.outline;
  for (int a = 0; a < n; ++a) {
    const auto& ba = spec.bodies[a];
    const auto pa = probes(ba);
    for (const auto& pr : pa) {
      const bool outside = !inside_polygon(pr.p, ol);
      for (std::size_t e = 0; e < ol.size(); ++e) {
        const Vec2 q = closest_on_segment(pr.p, ol[e], ol[(e + 1) % ol.size()]);
        // an outline corner is the closest point of both its edges: counted with the first
        const Vec2 end = ol[(e + 1) % ol.size()];
        if (q.x == end.x && q.y == end.y) {
          const std::size_t next = (e + 1) % ol.size();
          const Vec2 qn = closest_on_segment(pr.p, ol[next], ol[(next + 1) % ol.size()]);
          if (qn.x == end.x && qn.y == end.y) continue;
        }
        f(gap_of(pr, q, outside), a, -1);
      }
    }
    for (int b = 0; b < n; ++b) {
      if (b == a) continue;
      const auto& bb = spec.bodies[b];
      const bool a_circle = ba.kind == BodyShape::Kind::Circle;
      const bool b_circle = bb.kind == BodyShape::Kind::Circle;
      if (a_circle && b_circle && b < a) continue;  // once per pair of circles
      if (!a_circle && b_circle) continue;          // probed from the circle
      for (const auto& pr : pa) {
        const Vec2 q = closest_on_body(pr.p, bb);
        Gap gp = gap_of(pr, q, inside_body(pr.p, bb));
        if (!a_circle && !b_circle)
          for (const Vec2& v : bb.vertices)
            if (v.x == q.x && v.y == q.y) gp.weight = 0.5;  // B's corner probes A too
        f(gp, a, b);
      }
    }
  }
}

}  // namespace

std::vector<fem::BodyForce> collision_loads(const fem::MeshSpec& spec,
                                            const CollisionModel& model) {
  std::vector<fem::BodyForce> loads(spec.bodies.size());
  if (model.range <= 0 || model.force <= 0) return loads;
  auto add = [&](int body, Vec2 at, Vec2 force) {
    const Vec2 c = spec.bodies[body].centre;
    loads[body].force.x += force.x;
    loads[body].force.y += force.y;
    loads[body].torque += (at.x - c.x) * force.y - (at.y - c.y) * force.x;
  };
  for_each_gap(spec, [&](const Gap& gp, int a, int b) {
    if (gp.g >= model.range) return;
    const double s = (model.range - gp.g) / model.range;
    const double mag = gp.weight * model.force * s * s;
    const Vec2 mid{0.5 * (gp.on_probe.x + gp.facing.x), 0.5 * (gp.on_probe.y + gp.facing.y)};
    add(a, mid, {mag * gp.n.x, mag * gp.n.y});
    if (b >= 0) add(b, mid, {-mag * gp.n.x, -mag * gp.n.y});
  });
  return loads;
}

double smallest_gap(const fem::MeshSpec& spec) {
  double g = std::numeric_limits<double>::infinity();
  for_each_gap(spec, [&](const Gap& gp, int, int) { g = std::min(g, gp.g); });
  return g;
}

}  // namespace gf::fem_dem
