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
  const double t = l2 > 0 ? std::clamp(((p.x - a.x) * ex + (p.y - a.y) * ey) / l2, 0.0, 1.0) : 0;
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

/// One gap: the probe's surface point, the facing point and the gap g (negative: overlap).
struct Gap {
  Vec2 on_probe, facing;
  Vec2 n;  // unit, from the facing surface towards the probe
  double g = 0;
};

Gap gap_of(const Probe& pr, Vec2 q) {
  Gap out;
  const double d = dist(pr.p, q);
  out.n = d > 0 ? Vec2{(pr.p.x - q.x) / d, (pr.p.y - q.y) / d} : Vec2{0, 1};
  out.g = d - pr.radius;
  out.on_probe = {pr.p.x - pr.radius * out.n.x, pr.p.y - pr.radius * out.n.y};
  out.facing = q;
  return out;
}

/// Calls f(gap, probe body, facing body or -1 for the outline) for every probe and facing
/// surface; circle against circle and circle against polygon are probed from the circle only.
template <class F>
void for_each_gap(const fem::MeshSpec& spec, F&& f) {
  const int n = static_cast<int>(spec.bodies.size());
  for (int a = 0; a < n; ++a) {
    const auto& ba = spec.bodies[a];
    const auto pa = probes(ba);
    for (const auto& pr : pa) f(gap_of(pr, closest_on_polygon(pr.p, spec.outline)), a, -1);
    for (int b = 0; b < n; ++b) {
      if (b == a) continue;
      const auto& bb = spec.bodies[b];
      const bool a_circle = ba.kind == BodyShape::Kind::Circle;
      const bool b_circle = bb.kind == BodyShape::Kind::Circle;
      if (a_circle && b_circle && b < a) continue;  // once per pair of circles
      if (!a_circle && b_circle) continue;          // probed from the circle
      for (const auto& pr : pa) f(gap_of(pr, closest_on_body(pr.p, bb)), a, b);
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
    const double mag = model.force * s * s;
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
