// SPDX-License-Identifier: GPL-3.0-or-later
// Short-range repulsion between fluid_fem bodies: gaps from probe points, Glowinski's force law.
#include "coupling/fem_dem/collision.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"

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

/// Calls f(gap, probe body, facing body or -1 for the outline, key) for every probe and facing
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
    for (std::size_t k = 0; k < pa.size(); ++k) {
      const Probe& pr = pa[k];
      const bool outside = !inside_polygon(pr.p, ol);
      for (std::size_t e = 0; e < ol.size(); ++e) {
        const Vec2 q = closest_on_segment(pr.p, ol[e], ol[(e + 1) % ol.size()]);
        // an outline corner is the closest point of both its edges: counted with the edge that
        // starts there
        const Vec2 end = ol[(e + 1) % ol.size()];
        if (q.x == end.x && q.y == end.y) {
          const std::size_t next = (e + 1) % ol.size();
          const Vec2 qn = closest_on_segment(pr.p, ol[next], ol[(next + 1) % ol.size()]);
          if (qn.x == end.x && qn.y == end.y) continue;
        }
        f(gap_of(pr, q, outside), a, -1,
          ContactHistory::key(a, static_cast<int>(k), -1, static_cast<int>(e)));
      }
    }
    for (int b = 0; b < n; ++b) {
      if (b == a) continue;
      const auto& bb = spec.bodies[b];
      const bool a_circle = ba.kind == BodyShape::Kind::Circle;
      const bool b_circle = bb.kind == BodyShape::Kind::Circle;
      if (a_circle && b_circle && b < a) continue;  // once per pair of circles
      if (!a_circle && b_circle) continue;          // probed from the circle
      for (std::size_t k = 0; k < pa.size(); ++k) {
        const Probe& pr = pa[k];
        const Vec2 q = closest_on_body(pr.p, bb);
        Gap gp = gap_of(pr, q, inside_body(pr.p, bb));
        // Facing one of B's corners: if that corner, probing A, finds this probe's corner, the
        // two corners carry half each; if it finds the inside of one of A's edges, that gap
        // (no longer) carries the contact and this one none -- so the force does not jump when
        // two faces slide past each other's corners.
        if (!a_circle && !b_circle)
          for (const Vec2& v : bb.vertices)
            if (v.x == q.x && v.y == q.y) {
              const Vec2 back = closest_on_polygon(v, ba.vertices);
              gp.weight = back.x == pr.p.x && back.y == pr.p.y ? 0.5 : 0.0;
            }
        f(gp, a, b, ContactHistory::key(a, static_cast<int>(k), b, 0));
      }
    }
  }
}

}  // namespace

std::uint64_t ContactHistory::key(int body, int probe, int other, int edge) {
  const auto u = [](int v) { return static_cast<std::uint64_t>(static_cast<std::uint16_t>(v)); };
  return u(body) << 48 | u(probe) << 32 | u(other + 1) << 16 | u(edge);
}

std::vector<std::pair<std::uint64_t, GapSprings>> ContactHistory::entries() const {
  std::vector<std::pair<std::uint64_t, GapSprings>> e(springs_.begin(), springs_.end());
  std::sort(e.begin(), e.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return e;
}

ContactHistory ContactHistory::from_entries(const std::vector<std::uint64_t>& keys,
                                            const std::vector<double>& stretch,
                                            const std::vector<double>& roll) {
  REQUIRE(keys.size() == stretch.size() && keys.size() == roll.size(),
          "contact history: {} keys, {} stretches and {} rotations", keys.size(), stretch.size(),
          roll.size());
  ContactHistory h;
  for (std::size_t i = 0; i < keys.size(); ++i)
    h.springs_.emplace(keys[i], GapSprings{stretch[i], roll[i]});
  return h;
}

double ContactHistory::stretch(int body, int probe, int other, int edge) const {
  const auto it = springs_.find(key(body, probe, other, edge));
  return it == springs_.end() ? 0.0 : it->second.slide;
}

double ContactHistory::rolled(int body, int probe, int other, int edge) const {
  const auto it = springs_.find(key(body, probe, other, edge));
  return it == springs_.end() ? 0.0 : it->second.roll;
}

namespace {

/// The loads of the repulsion and, with `history`, of friction (see the header).
std::vector<fem::BodyForce> loads_of(const fem::MeshSpec& spec, const CollisionModel& model,
                                     const std::vector<fem::BodyMotion>* velocity, double dt,
                                     const std::unordered_map<std::uint64_t, GapSprings>* history,
                                     std::unordered_map<std::uint64_t, GapSprings>* next) {
  std::vector<fem::BodyForce> loads(spec.bodies.size());
  if (model.range <= 0 || model.force <= 0) return loads;
  auto add = [&](int body, Vec2 at, Vec2 force) {
    const Vec2 c = spec.bodies[body].centre;
    loads[body].force.x += force.x;
    loads[body].force.y += force.y;
    loads[body].torque += (at.x - c.x) * force.y - (at.y - c.y) * force.x;
  };
  // velocity of body b's material point at x (the outline, b = -1, is at rest)
  auto point_velocity = [&](int b, Vec2 x) {
    if (b < 0) return Vec2{0, 0};
    const auto& m = (*velocity)[b];
    const Vec2 c = spec.bodies[b].centre;
    return Vec2{m.velocity.x - m.angular_velocity * (x.y - c.y),
                m.velocity.y + m.angular_velocity * (x.x - c.x)};
  };
  const bool friction = history != nullptr && model.friction > 0;
  const bool rolling = friction && model.rolling_friction > 0;
  const double k_t = friction ? model.spring() : 0.0;
  auto omega = [&](int b) { return b < 0 ? 0.0 : (*velocity)[b].angular_velocity; };
  auto lever = [&](int b, Vec2 x) { return dist(x, spec.bodies[b].centre); };
  for_each_gap(spec, [&](const Gap& gp, int a, int b, std::uint64_t key) {
    if (gp.g >= model.range || gp.weight == 0) return;
    const double mag = gp.weight * model.force * repulsion_scale(model, gp.g);
    const Vec2 mid{0.5 * (gp.on_probe.x + gp.facing.x), 0.5 * (gp.on_probe.y + gp.facing.y)};
    Vec2 f{mag * gp.n.x, mag * gp.n.y};
    if (friction) {
      const Vec2 t{-gp.n.y, gp.n.x};
      const Vec2 va = point_velocity(a, mid), vb = point_velocity(b, mid);
      const double v_t = (va.x - vb.x) * t.x + (va.y - vb.y) * t.y;
      const auto it = history->find(key);
      const GapSprings before = it == history->end() ? GapSprings{} : it->second;
      double xi = before.slide + v_t * dt;
      const double k = gp.weight * k_t, cap = model.friction * mag;
      double f_t = -k * xi;
      if (std::abs(f_t) > cap) {  // sliding: the spring stays at the Coulomb limit
        f_t = std::copysign(cap, f_t);
        xi = -f_t / k;
      }
      f.x += f_t * t.x;
      f.y += f_t * t.y;
      double theta = 0.0, m_r = 0.0;
      if (rolling) {
        const double ra = lever(a, mid), rb = b < 0 ? 0.0 : lever(b, mid);
        const double r = b < 0 ? ra : ra * rb / (ra + rb);
        theta = before.roll + (omega(a) - omega(b)) * dt;
        const double k_r = k * r * r, cap_r = model.rolling_friction * r * mag;
        m_r = -k_r * theta;
        if (std::abs(m_r) > cap_r) {  // rolling: the spring stays at its limit
          m_r = std::copysign(cap_r, m_r);
          theta = -m_r / k_r;
        }
      }
      (*next)[key] = GapSprings{xi, theta};
      add(a, mid, f);
      loads[a].torque += m_r;
      if (b >= 0) {
        add(b, mid, {-f.x, -f.y});
        loads[b].torque -= m_r;
      }
      return;
    }
    add(a, mid, f);
    if (b >= 0) add(b, mid, {-f.x, -f.y});
  });
  return loads;
}

}  // namespace

double repulsion_scale(const CollisionModel& model, double g) {
  if (!(g < model.range)) return 0.0;
  const double s = (model.range - g) / model.range;
  // the core's g_c / g stops growing at 1 % of g_c (and so in an overlap)
  const double core = model.core > 0 ? model.core / std::max(g, 0.01 * model.core) : 1.0;
  return s * s * std::max(1.0, core);
}

std::vector<fem::BodyForce> collision_loads(const fem::MeshSpec& spec,
                                            const CollisionModel& model) {
  return loads_of(spec, model, nullptr, 0.0, nullptr, nullptr);
}

std::vector<fem::BodyForce> collision_loads(const fem::MeshSpec& spec, const CollisionModel& model,
                                            const std::vector<fem::BodyMotion>& velocity, double dt,
                                            const ContactHistory& before, ContactHistory& after) {
  REQUIRE(velocity.size() == spec.bodies.size(), "collision_loads: {} velocities for {} bodies",
          velocity.size(), spec.bodies.size());
  REQUIRE(spec.bodies.size() < 0xffff && spec.outline.size() < 0x10000,
          "collision_loads: friction histories are keyed for fewer than 65535 bodies and 65536 "
          "outline edges ({} and {})",
          spec.bodies.size(), spec.outline.size());
  REQUIRE(&before != &after, "collision_loads: before and after must be different histories");
  after.springs_.clear();
  return loads_of(spec, model, &velocity, dt, &before.springs_, &after.springs_);
}

std::vector<fem::BodyForce> collision_loads(const fem::MeshSpec& spec, const CollisionModel& model,
                                            const std::vector<fem::BodyMotion>& velocity, double dt,
                                            ContactHistory& history) {
  ContactHistory after;
  auto loads = collision_loads(spec, model, velocity, dt, history, after);
  history = std::move(after);
  return loads;
}

NarrowGap narrowest_gap(const fem::MeshSpec& spec) {
  NarrowGap n;
  for_each_gap(spec, [&](const Gap& gp, int a, int b, std::uint64_t key) {
    if (gp.g < n.g) n = {gp.g, a, b, b < 0 ? static_cast<int>(key & 0xffffU) : -1};
  });
  return n;
}

double smallest_gap(const fem::MeshSpec& spec) {
  return narrowest_gap(spec).g;
}

}  // namespace gf::fem_dem
