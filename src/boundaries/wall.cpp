// SPDX-License-Identifier: GPL-3.0-or-later
// Wall surfaces for output, the particle-wall contact list, and the wall force loop.
#include "boundaries/wall.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <tuple>

#include "contact/batch_columns.hpp"
#include "contact/conduction.hpp"
#include "contact/pair_forces.hpp"
#include "contact/registry.hpp"
#include "contact/shape_forces.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"

namespace gf {

namespace {

/// Two unit vectors spanning the plane normal to n.
void tangent_basis(const Vec3& n, Vec3& a, Vec3& b) {
  a = std::abs(n.x) < 0.9 ? normalized(cross(n, Vec3{1, 0, 0}))
                          : normalized(cross(n, Vec3{0, 1, 0}));
  b = cross(n, a);
}

}  // namespace

SurfaceMesh Wall::surface(const Domain& domain) const {
  SurfaceMesh m;
  m.name = name;
  const Vec3 c = 0.5 * (domain.lo + domain.hi);
  const double diag = norm(domain.hi - domain.lo);
  if (kind == WallKind::Mesh) {
    m.points = mesh.points();
    m.triangles = mesh.triangles();
    return m;
  }
  Vec3 a, b;
  tangent_basis(dir, a, b);
  if (kind == WallKind::Plane) {
    // The plane clipped to the domain's bounding box along the two tangent directions.
    const Vec3 o = c - dot(c - point, dir) * dir;
    double lo_a = 1e300, hi_a = -1e300, lo_b = 1e300, hi_b = -1e300;
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 q{corner & 1 ? domain.hi.x : domain.lo.x, corner & 2 ? domain.hi.y : domain.lo.y,
                   corner & 4 ? domain.hi.z : domain.lo.z};
      lo_a = std::min(lo_a, dot(q - o, a));
      hi_a = std::max(hi_a, dot(q - o, a));
      lo_b = std::min(lo_b, dot(q - o, b));
      hi_b = std::max(hi_b, dot(q - o, b));
    }
    m.points = {o + lo_a * a + lo_b * b, o + hi_a * a + lo_b * b, o + hi_a * a + hi_b * b,
                o + lo_a * a + hi_b * b};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
  }
  // Cylinder: axial extent of the domain's projection, 48 segments around.
  double lo = 1e300, hi = -1e300;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 q{corner & 1 ? domain.hi.x : domain.lo.x, corner & 2 ? domain.hi.y : domain.lo.y,
                 corner & 4 ? domain.hi.z : domain.lo.z};
    lo = std::min(lo, dot(q - point, dir));
    hi = std::max(hi, dot(q - point, dir));
  }
  if (!(hi > lo)) {
    lo = -diag;
    hi = diag;
  }
  constexpr int seg = 48;
  for (int s = 0; s < seg; ++s) {
    const double phi = 2 * std::numbers::pi * s / seg;
    const Vec3 rad = radius * (std::cos(phi) * a + std::sin(phi) * b);
    m.points.push_back(point + lo * dir + rad);
    m.points.push_back(point + hi * dir + rad);
  }
  for (int s = 0; s < seg; ++s) {
    const int i0 = 2 * s, i1 = 2 * s + 1, j0 = 2 * ((s + 1) % seg), j1 = j0 + 1;
    m.triangles.push_back({i0, j0, j1});
    m.triangles.push_back({i0, j1, i1});
  }
  return m;
}

void WallContactList::build(std::span<const Wall> walls, const Vec3* x, const double* r,
                            std::size_t n, double skin, std::span<const std::int64_t> perm,
                            const Vec3* half_axis, const std::int32_t* fixed) {
  old_entries_.swap(entries_);
  old_history_.swap(history_);
  entries_.clear();
  // Mesh walls: their triangles on a grid that reaches the largest sphere plus the skin.
  double r_max = 0;
  for (std::size_t i = 0; i < n; ++i) r_max = std::max(r_max, r[i]);
  for (const auto& w : walls)
    if (w.kind == WallKind::Mesh) w.mesh.index(r_max + 1.5 * skin);
  for (std::size_t i = 0; i < n; ++i) {
    if (fixed != nullptr && fixed[i] != 0) continue;
    for (std::size_t w = 0; w < walls.size(); ++w) {
      const auto ii = static_cast<std::int32_t>(i), ww = static_cast<std::int32_t>(w);
      if (walls[w].kind == WallKind::Mesh) {
        const TriangleMesh& mesh = walls[w].mesh;
        const auto [lo, hi] = mesh.candidates(x[i]);
        const Vec3 h = half_axis != nullptr ? half_axis[i] : Vec3{};
        // (the cheap bounds first: most candidates of a grain above a large flat part are
        // farther from the plane than the reach)
        if (h == Vec3{}) {
          for (const std::int32_t* t = lo; t != hi; ++t)
            if (mesh.distance_bound(*t, x[i]) - r[i] < skin &&
                mesh.distance(*t, x[i]) - r[i] < skin)
              entries_.push_back({ii, ww, *t});
        } else {
          const double r_cap = r[i] - norm(h);
          for (const std::int32_t* t = lo; t != hi; ++t)
            if (mesh.segment_distance_bound(*t, x[i] - h, x[i] + h) - r_cap < skin &&
                mesh.segment_distance(*t, x[i] - h, x[i] + h) - r_cap < skin)
              entries_.push_back({ii, ww, *t});
        }
        continue;
      }
      Vec3 nrm;
      if (walls[w].gap(x[i], r[i], nrm) < skin) entries_.push_back({ii, ww, 0});
    }
  }
  groups_.clear();
  for (std::size_t k = 0; k < entries_.size(); ++k)
    if (k == 0 || entries_[k].particle != entries_[k - 1].particle)
      groups_.push_back(static_cast<std::int64_t>(k));
  groups_.push_back(static_cast<std::int64_t>(entries_.size()));
  reactions_.assign(2 * entries_.size(), Vec3{});
  stiffness_.assign(entries_.size(), 0.0);
  // Carry the history: the old list is sorted by (old particle index, wall, element).
  const auto slots = static_cast<std::size_t>(slots_);
  history_.assign(slots * entries_.size(), Vec3{});
  using Key = std::tuple<std::int64_t, std::int32_t, std::int32_t>;
  for (std::size_t k = 0; k < entries_.size(); ++k) {
    const std::int64_t old_i =
        perm.empty() ? entries_[k].particle : perm[static_cast<std::size_t>(entries_[k].particle)];
    const Key want{old_i, entries_[k].wall, entries_[k].element};
    const auto it = std::lower_bound(old_entries_.begin(), old_entries_.end(), want,
                                     [&](const Entry& e, const Key& v) {
                                       return Key{e.particle, e.wall, e.element} < v;
                                     });
    if (it != old_entries_.end() && Key{it->particle, it->wall, it->element} == want)
      for (std::size_t s = 0; s < slots; ++s)
        history_[slots * k + s] =
            old_history_[slots * static_cast<std::size_t>(it - old_entries_.begin()) + s];
  }
}

void WallContactList::restore(std::vector<Entry> entries, std::vector<Vec3> history) {
  REQUIRE(static_cast<std::size_t>(slots_) * entries.size() == history.size(),
          "inconsistent wall contact list in checkpoint");
  entries_ = std::move(entries);
  history_ = std::move(history);
  groups_.clear();
  for (std::size_t k = 0; k < entries_.size(); ++k)
    if (k == 0 || entries_[k].particle != entries_[k - 1].particle)
      groups_.push_back(static_cast<std::int64_t>(k));
  groups_.push_back(static_cast<std::int64_t>(entries_.size()));
  reactions_.assign(2 * entries_.size(), Vec3{});
  stiffness_.assign(entries_.size(), 0.0);
}

namespace {

/// Geometry of one particle-wall contact.
using WallGeometry = contact::ShapeGeometry;  ///< normal from the wall to the particle

/// A sphere of radius r at x against the wall (slot geometry of spheres, disks, capsule ends).
bool sphere_wall(const Wall& w, const Vec3& x, double r, WallGeometry& g) {
  const double gap = w.gap(x, r, g.normal);
  if (gap >= 0) return false;
  g.overlap = -gap;
  g.point = x - (r - 0.5 * g.overlap) * g.normal;
  g.r_eff = r;
  return true;
}

/// Contact of slot `slot` of particle i with wall w; false when that slot is apart. Spheres and
/// disks use slot 0; spherocylinders one slot per end sphere (plane, inside of a cylinder: the
/// gap is smallest at the ends) or slot 0 at the closest point (outside of a cylinder); polygons
/// slot 0, the overlap with the wall's half-plane (or, for a cylinder, with the solid beyond its
/// circle: contact/geometry/disk_polygon.hpp) with l_c = R (equal-area radius: the
/// characteristic length against a rigid wall), see contact/shape_forces.hpp. Mesh walls: the
/// contact of triangle `element` if the surface's contact is there, slot 0 for a sphere, the
/// slots of TriangleMesh::capsule_contact for a spherocylinder (boundaries/triangle_mesh).
/// `cap`: the spherocylinder i, when the caller has it (one per particle, not per slot).
bool wall_slot_geometry(const Wall& w, std::int32_t element, const contact::ShapeView* s,
                        std::int64_t i, const Vec3& x, double r, int slot, WallGeometry& g,
                        const contact::Capsule* cap = nullptr) {
  if (w.kind == WallKind::Mesh) {  // spheres and spherocylinders (polygons are 2D: refused)
    double gap = 0;
    Vec3 centre = x;
    if (s == nullptr || s->code(i) == ShapeCode::Sphere) {
      if (slot != 0 || !w.mesh.sphere_contact(element, x, r, g.normal, gap)) return false;
    } else {
      const contact::Capsule c = cap != nullptr ? *cap : s->capsule(i, x);
      r = c.radius;
      if (!w.mesh.capsule_contact(element, slot, c.end0(), c.end1(), r, centre, g.normal, gap,
                                  g.force_scale))
        return false;
    }
    if (gap >= 0) return false;
    g.overlap = -gap;
    g.point = centre - (r - 0.5 * g.overlap) * g.normal;
    g.r_eff = r;
    return true;
  }
  if (s == nullptr || s->code(i) == ShapeCode::Sphere || s->code(i) == ShapeCode::Disk)
    return slot == 0 && sphere_wall(w, x, r, g);
  if (s->code(i) == ShapeCode::Polygon) {
    if (slot != 0) return false;
    contact::PolygonOverlap o;
    const ConvexPolygon poly = s->world_polygon(i, x);
    const Vec2 at{w.point.x, w.point.y};
    // (2D: a cylinder's axis is z, its section the circle about w.point)
    if (w.kind == WallKind::Cylinder) {
      if (!contact::polygon_circle_wall_overlap(poly, at, w.radius, w.inside, o)) return false;
      o.centroid = contact::point_on_centre_line(o, at);  // radial, through the axis
    } else if (!contact::polygon_halfplane_overlap(poly, at, Vec2{w.dir.x, w.dir.y}, o)) {
      return false;
    }
    const double req = s->equivalent_radius(i);
    contact::polygon_law_inputs(o, contact::polygon_characteristic_length(req, 0.0), g);
    g.r_eff = req;
    return true;
  }
  // (slots beyond the two ends exist for mesh walls only; a capsule of no length has one end)
  if (slot > 1) return false;
  const contact::Capsule c = cap != nullptr ? *cap : s->capsule(i, x);
  if (slot == 1 && !(c.half_length > 0)) return false;
  if (w.kind == WallKind::Cylinder && !w.inside) {
    contact::ShapeContact out[2];
    if (slot != 0 || contact::capsule_cylinder_wall(c, w.point, w.dir, w.radius, false, out) == 0)
      return false;
    g.overlap = out[0].overlap;
    g.normal = out[0].normal;
    g.point = out[0].point;
    g.r_eff = out[0].r_eff;
    return true;
  }
  return sphere_wall(w, slot == 0 ? c.end0() : c.end1(), c.radius, g);
}

/// The sphere-wall contacts of a run of wall-list entries, in structure-of-arrays form, so that
/// the contact law runs as a vectorised loop (as the sphere pair loop does, see
/// contact/pair_forces.cpp). On the stack of the thread that fills it.
struct WallBatch {
  static constexpr int cap = 128;
  std::int64_t k[cap];
  std::int32_t i[cap], w[cap];
  contact::VecColumns<cap> normal;    // from the wall to the grain
  double ov[cap], r[cap], m[cap];     // overlap, radius, mass
  contact::VecColumns<cap> dv;        // v_i - v_wall at the contact point
  contact::VecColumns<cap> om_i;      // omega_i
  contact::VecColumns<cap> om_w;      // omega_wall
  contact::VecColumns<cap> hist;      // history, in and out
  contact::CoeffColumns<cap> coeffs;  // pair constants
  contact::VecColumns<cap> f, t;      // force and torque on i
  contact::VecColumns<cap> rolling;   // rolling torque on i
  double fn[cap];                     // normal force
};

/// The law for the n contacts of a batch: the kinematics of the generic loop below for a sphere
/// (one slot, force scale 1, m* = m_i, R* = r_i, contact point at the middle of the overlap).
/// Cohesive: with the law's cohesion slot (some pair has k_c > 0; a wall is r_j -> infinity,
/// ContactKinematics::inv_r_sum = 0).
template <class Law, bool Cohesive>
__attribute__((always_inline)) inline void wall_batch_body(WallBatch& b, int n, int model,
                                                           double dt) {
  for (int c = 0; c < n; ++c) {
    contact::ContactKinematics kin;
    kin.overlap = b.ov[c];
    kin.normal = b.normal.get(c);
    const Vec3 arm = -(b.r[c] - 0.5 * kin.overlap) * kin.normal;
    const Vec3 omi = b.om_i.get(c);
    kin.v_rel = b.dv.get(c) + cross(omi, arm);
    kin.omega_rel = omi - b.om_w.get(c);
    kin.r_eff = b.r[c];
    kin.m_eff = b.m[c];
    const contact::PairCoeffs cc = b.coeffs.get(c, model);
    Vec3 h = b.hist.get(c);
    const contact::ContactResult res = Law::template evaluate<Cohesive>(cc, kin, dt, h);
    b.hist.set(c, h);
    const Vec3 t = cross(arm, res.force) + res.rolling_torque;
    b.f.set(c, res.force);
    b.t.set(c, t);
    b.rolling.set(c, res.rolling_torque);
    b.fn[c] = res.normal_force;
  }
}

using WallKernel = void (*)(WallBatch&, int, int, double);
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
template <class Law, bool Cohesive>
__attribute__((target("avx2"), noinline, flatten)) void wall_batch_avx2(WallBatch& b, int n,
                                                                        int model, double dt) {
  wall_batch_body<Law, Cohesive>(b, n, model, dt);
}
#endif
template <class Law, bool Cohesive>
__attribute__((noinline, flatten)) void wall_batch_default(WallBatch& b, int n, int model,
                                                           double dt) {
  wall_batch_body<Law, Cohesive>(b, n, model, dt);
}

/// compute_wall_forces for spheres (one slot) when every material pair uses one law: entries
/// scanned branch-free in runs of particle groups (threads never share a particle), the touching
/// ones' data gathered, the law vectorised, forces, torques, reactions and histories written
/// back in entry order (the same sums whatever the thread count).
template <class Law>
std::int64_t sphere_wall_forces(ParticleStore& p, std::span<Wall> walls, WallContactList& list,
                                const PairTable<contact::PairCoeffs>& pairs, int model, double t,
                                double dt, contact::ContactRecord* records) {
  const bool cohesive = contact::any_cohesion(pairs);
  WallKernel kernel = cohesive ? wall_batch_default<Law, true> : wall_batch_default<Law, false>;
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
  if (contact::avx2_kernels())
    kernel = cohesive ? wall_batch_avx2<Law, true> : wall_batch_avx2<Law, false>;
#endif
  const auto entries = list.entries();
  auto history = list.history();
  auto reaction = list.reactions();
  auto stiffness = list.stiffness();
  const Vec3* x = p.x();
  const Vec3* v = p.v();
  const Vec3* om = p.omega();
  Vec3* f = p.f();
  Vec3* tq = p.torque();
  const double* r = p.radius();
  const double* m = p.mass();
  const std::int32_t* mat = p.material();
  const auto groups = list.particle_groups();
  const std::int64_t n_groups = static_cast<std::int64_t>(groups.size()) - 1;
  // Runs of 64 particle groups (a few hundred entries) per task.
  constexpr std::int64_t run = 64;
  const std::int64_t n_runs = (n_groups + run - 1) / run;
  // The batch holds the touching entries among the entries [k_lo, k_hi).
  auto flush = [&](WallBatch & b, int n, std::int64_t k_lo, std::int64_t k_hi)
      __attribute__((noinline)) {
    for (int c = 0; c < n; ++c) {  // gather
      const std::int32_t i = b.i[c];
      const Wall& w = walls[static_cast<std::size_t>(b.w[c])];
      const Vec3 point = x[i] - (r[i] - 0.5 * b.ov[c]) * b.normal.get(c);
      b.dv.set(c, v[i] - w.velocity_at(point, t));
      b.om_i.set(c, om[i]);
      b.om_w.set(c, w.motion.omega());
      b.r[c] = r[i];
      b.m[c] = m[i];
      b.hist.set(c, history[static_cast<std::size_t>(b.k[c])]);
      b.coeffs.set(c, pairs(mat[i], w.material));
    }
    // Entries that are apart lose their history; the touching ones get theirs back below.
    std::fill(history.begin() + k_lo, history.begin() + k_hi, Vec3{});
    kernel(b, n, model, dt);
    for (int c = 0; c < n; ++c) {  // scatter, in entry order
      const std::int32_t i = b.i[c];
      const auto k = static_cast<std::size_t>(b.k[c]);
      const Wall& w = walls[static_cast<std::size_t>(b.w[c])];
      const Vec3 fc = b.f.get(c);
      const Vec3 rt = b.rolling.get(c);
      const Vec3 nrm = b.normal.get(c);
      const Vec3 point = x[i] - (r[i] - 0.5 * b.ov[c]) * nrm;
      f[i] += fc;
      tq[i] += b.t.get(c);
      reaction[2 * k] = -fc;
      reaction[2 * k + 1] = -(cross(point - w.torque_center(), fc) + rt);
      stiffness[k] = b.ov[c] > 0 ? 1.5 * b.fn[c] / b.ov[c] : 0.0;
      history[k] = b.hist.get(c);
      if (records != nullptr)
        records[k] = contact::ContactRecord{i, b.w[c], point, nrm, fc, x[i] - point, b.ov[c]};
    }
  };
  return exec::parallel_sum(
      n_runs, std::int64_t{0},
      [&](exec::index_t q) {
        const std::int64_t e_lo = groups[static_cast<std::size_t>(q * run)];
        const std::int64_t e_hi =
            groups[static_cast<std::size_t>(std::min(n_groups, (q + 1) * run))];
        WallBatch b;
        int n = 0;
        std::int64_t touching = 0;
        std::int64_t k_lo = e_lo;
        for (std::int64_t k = e_lo; k < e_hi; ++k) {
          const auto ku = static_cast<std::size_t>(k);
          const std::int32_t i = entries[ku].particle;
          const Wall& w = walls[static_cast<std::size_t>(entries[ku].wall)];
          Vec3 nrm;
          const double gap = w.gap(x[i], r[i], nrm);
          // Every entry starts apart (no reaction); the touching ones are written by the scatter.
          reaction[2 * ku] = reaction[2 * ku + 1] = {};
          stiffness[ku] = 0;
          b.k[n] = k;
          b.i[n] = i;
          b.w[n] = entries[ku].wall;
          b.normal.set(n, nrm);
          b.ov[n] = -gap;
          n += gap < 0;
          if (n == WallBatch::cap) {
            flush(b, n, k_lo, k + 1);
            touching += n;
            n = 0;
            k_lo = k + 1;
          }
        }
        flush(b, n, k_lo, e_hi);
        return touching + n;
      },
      /*min_parallel=*/64);
}

/// Any shape, any number of slots, a law per contact.
std::int64_t generic_wall_forces(ParticleStore& p, std::span<Wall> walls, WallContactList& list,
                                 const PairTable<contact::PairCoeffs>& pairs,
                                 const contact::ShapeView* sv, double t, double dt,
                                 contact::ContactRecord* records) {
  const auto entries = list.entries();
  auto history = list.history();
  auto reaction = list.reactions();
  auto stiffness = list.stiffness();
  Vec3* x = p.x();
  Vec3* v = p.v();
  Vec3* om = p.omega();
  Vec3* f = p.f();
  Vec3* tq = p.torque();
  const double* r = p.radius();
  const double* m = p.mass();
  const std::int32_t* mat = p.material();
  const int slots = list.slots();
  // Entries are sorted by particle: one group per particle, so threads never share a particle.
  const auto groups = list.particle_groups();
  const std::int64_t n_groups = static_cast<std::int64_t>(groups.size()) - 1;
  const auto su = static_cast<std::size_t>(slots);
  return exec::parallel_sum(n_groups, std::int64_t{0}, [&](exec::index_t gr) {
    std::int64_t touching = 0;
    const std::int64_t k_lo = groups[static_cast<std::size_t>(gr)];
    const std::int64_t k_hi = groups[static_cast<std::size_t>(gr) + 1];
    // The geometry of every slot of the particle's entries first: its contacts with one wall
    // share its mass, and a contact that moves to the next triangle of a mesh (a grain rolling
    // over an edge of a meshed floor) takes the history of the one it leaves, as on a plane.
    thread_local std::vector<WallGeometry> geo;
    thread_local std::vector<char> on;
    const auto n_at = static_cast<std::size_t>(k_hi - k_lo) * su;
    if (geo.size() < n_at) geo.resize(n_at);
    on.assign(n_at, 0);
    const auto at = [&](std::int64_t k, int slot) {
      return static_cast<std::size_t>(k - k_lo) * su + static_cast<std::size_t>(slot);
    };
    bool any_mesh = false;
    // A spherocylinder: its axis once for all its entries and slots.
    const int i_group = k_hi > k_lo ? entries[static_cast<std::size_t>(k_lo)].particle : 0;
    std::optional<contact::Capsule> cap;
    if (sv != nullptr && k_hi > k_lo && sv->code(i_group) == ShapeCode::Spherocylinder)
      cap = sv->capsule(i_group, x[i_group]);
    for (std::int64_t k = k_lo; k < k_hi; ++k) {
      const auto ku = static_cast<std::size_t>(k);
      const int i = entries[ku].particle;
      const Wall& w = walls[static_cast<std::size_t>(entries[ku].wall)];
      const bool is_mesh = w.kind == WallKind::Mesh;
      any_mesh = any_mesh || is_mesh;
      // (a triangle whose plane the whole axis is farther from than r: every slot apart)
      const bool near =
          !is_mesh || !cap ||
          w.mesh.capsule_near(entries[ku].element, cap->end0(), cap->end1(), cap->radius);
      for (int slot = 0; slot < slots; ++slot) {
        geo[at(k, slot)] = WallGeometry{};  // (force_scale 1 unless a polygon sets it)
        on[at(k, slot)] = near && wall_slot_geometry(w, entries[ku].element, sv, i, x[i], r[i],
                                                     slot, geo[at(k, slot)], cap ? &*cap : nullptr);
        // (apart mesh contacts keep their history until the hand-over below)
        if (!on[at(k, slot)] && !is_mesh) history[su * ku + static_cast<std::size_t>(slot)] = {};
      }
    }
    if (any_mesh) {
      // A new mesh contact takes the history of the contact of the same kind (the same end of a
      // spherocylinder, or its middle) among those of the same mesh that have just ended, the
      // nearest to it; only one that moved on: its triangle reaches the new contact point (it
      // shares the edge or vertex the contact crossed, up to a step's travel). A contact that
      // ends elsewhere while this one starts (a grain leaving a lifter as it lands on the barrel)
      // keeps its history to itself; two contacts changing triangles at once, in a valley, keep
      // their own.
      for (std::int64_t k = k_lo; k < k_hi; ++k) {
        const auto ku = static_cast<std::size_t>(k);
        const Wall& w = walls[static_cast<std::size_t>(entries[ku].wall)];
        if (w.kind != WallKind::Mesh) continue;
        for (int slot = 0; slot < slots; ++slot) {
          if (!on[at(k, slot)] || history[su * ku + static_cast<std::size_t>(slot)] != Vec3{})
            continue;
          const WallGeometry& g = geo[at(k, slot)];
          const Vec3 q = g.point + 0.5 * g.overlap * g.normal;  // on the wall's surface
          std::size_t donor = 0;
          bool found = false;
          double nearest = std::numeric_limits<double>::infinity();
          for (std::int64_t j = k_lo; j < k_hi; ++j) {
            const auto ju = static_cast<std::size_t>(j);
            if (entries[ju].wall != entries[ku].wall) continue;
            double d = -1;
            for (int sj = 0; sj < slots; ++sj) {
              const std::size_t hj = su * ju + static_cast<std::size_t>(sj);
              // (one end's contact never passes to the other end; a contact moves between an
              // end and the middle of the axis where an end slides over an edge)
              if ((slot < 2 && sj < 2 && sj != slot) || on[at(j, sj)] || history[hj] == Vec3{})
                continue;
              if (d < 0) d = w.mesh.distance(entries[ju].element, q);
              if (d < nearest) {
                nearest = d;
                donor = hj;
                found = true;
              }
            }
          }
          if (found && nearest <= 0.05 * g.r_eff) {
            history[su * ku + static_cast<std::size_t>(slot)] = history[donor];
            history[donor] = {};
          }
        }
      }
    }
    // The mass a contact acts on: the grain's, shared with its other contacts with the same wall
    // that push the same way, so that a flat impact has the damping, and hence the restitution,
    // that the law was given for one contact (a spherocylinder lying flat: half at each end).
    // Plane and cylinder walls: the number of touching slots. Meshes: 1 + the sum of the
    // positive cosines n . n_j to the grain's other contacts with the mesh (each times its
    // weight, see TriangleMesh::capsule_contact), which gives two contacts at an angle theta the
    // damping ratio of one for a push along their bisector (stiffness and damping both scale as
    // 1 + cos theta), and leaves contacts at right angles (a corner) independent.
    thread_local std::vector<std::size_t> touching_mesh;  // (indices into geo)
    touching_mesh.clear();
    if (any_mesh)
      for (std::size_t a = 0; a < n_at; ++a)
        if (on[a] != 0 &&
            walls[static_cast<std::size_t>(entries[static_cast<std::size_t>(k_lo) + a / su].wall)]
                    .kind == WallKind::Mesh)
          touching_mesh.push_back(a);
    const auto share = [&](std::int64_t k, int slot) {
      const auto ku = static_cast<std::size_t>(k);
      if (walls[static_cast<std::size_t>(entries[ku].wall)].kind != WallKind::Mesh) {
        int n_on = 0;
        for (int sl = 0; sl < slots; ++sl) n_on += on[at(k, sl)];
        return static_cast<double>(n_on);
      }
      const Vec3& n = geo[at(k, slot)].normal;
      double sum = 1;
      for (const std::size_t a : touching_mesh)
        if (a != at(k, slot) &&
            entries[static_cast<std::size_t>(k_lo) + a / su].wall == entries[ku].wall)
          sum += geo[a].force_scale * std::max(0.0, dot(n, geo[a].normal));
      return sum;
    };
    for (std::int64_t k = k_lo; k < k_hi; ++k) {
      const auto ku = static_cast<std::size_t>(k);
      const int i = entries[ku].particle;
      const Wall& w = walls[static_cast<std::size_t>(entries[ku].wall)];
      const contact::PairCoeffs& c = pairs(mat[i], w.material);
      Vec3 reaction_force{}, reaction_torque{};
      double k_sum = 0;
      for (int slot = 0; slot < slots; ++slot) {
        if (!on[at(k, slot)]) continue;
        Vec3& hist = history[su * ku + static_cast<std::size_t>(slot)];
        const WallGeometry& g = geo[at(k, slot)];
        const Vec3 arm = g.point - x[i];
        contact::ContactKinematics kin;
        kin.overlap = g.overlap;
        kin.normal = g.normal;
        kin.v_rel = v[i] + cross(om[i], arm) - w.velocity_at(g.point, t);
        kin.omega_rel = om[i] - w.motion.omega();
        kin.r_eff = g.r_eff;
        kin.m_eff = m[i] / (share(k, slot) * g.force_scale);
        contact::ContactResult res =
            dispatch_index(contact::ContactModels{}, c.model,
                           [&]<class M>() { return M::Law::evaluate(c, kin, dt, hist); });
        res.force = g.force_scale * res.force;
        res.rolling_torque = g.force_scale * res.rolling_torque;
        f[i] += res.force;
        tq[i] += cross(arm, res.force) + res.rolling_torque;
        reaction_force -= res.force;
        if (g.overlap > 0) k_sum += 1.5 * res.normal_force / g.overlap;
        reaction_torque -= cross(g.point - w.torque_center(), res.force) + res.rolling_torque;
        if (records != nullptr)
          records[static_cast<std::size_t>(slots) * ku + static_cast<std::size_t>(slot)] =
              contact::ContactRecord{i,         entries[ku].wall, g.point,  g.normal,
                                     res.force, x[i] - g.point,   g.overlap};
        ++touching;
      }
      reaction[2 * ku] = reaction_force;
      reaction[2 * ku + 1] = reaction_torque;
      stiffness[ku] = k_sum;
    }
    if (any_mesh)
      for (std::int64_t k = k_lo; k < k_hi; ++k)
        if (walls[static_cast<std::size_t>(entries[static_cast<std::size_t>(k)].wall)].kind ==
            WallKind::Mesh)
          for (int slot = 0; slot < slots; ++slot)
            if (!on[at(k, slot)])
              history[su * static_cast<std::size_t>(k) + static_cast<std::size_t>(slot)] = {};
    return touching;
  });
}

}  // namespace

std::int64_t compute_wall_forces(ParticleStore& p, std::span<Wall> walls, WallContactList& list,
                                 const PairTable<contact::PairCoeffs>& pairs, double t, double dt,
                                 contact::ContactRecord* records) {
  const auto entries = list.entries();
  auto reaction = list.reactions();
  auto stiffness = list.stiffness();
  std::optional<contact::ShapeView> shapes;
  if (p.has_shapes()) shapes.emplace(p);
  const contact::ShapeView* sv = shapes ? &*shapes : nullptr;
  const int slots = list.slots();
  // Spheres whose wall pairs all use one law, with no mesh walls: the batched, vectorised loop.
  int model = -1;
  const bool meshes = std::any_of(walls.begin(), walls.end(),
                                  [](const Wall& w) { return w.kind == WallKind::Mesh; });
  const bool uniform =
      sv == nullptr && slots == 1 && !meshes && contact::uniform_model(pairs, model);
  const std::int64_t active =
      uniform ? dispatch_index(contact::ContactModels{}, model,
                               [&]<class M>() {
                                 return sphere_wall_forces<typename M::Law>(p, walls, list, pairs,
                                                                            model, t, dt, records);
                               })
              : generic_wall_forces(p, walls, list, pairs, sv, t, dt, records);
  // Reactions summed in entry order: the same bits whatever the thread count.
  for (auto& w : walls) {
    w.force = {};
    w.torque = {};
    w.contact_stiffness = 0;
  }
  for (std::size_t k = 0; k < entries.size(); ++k) {
    Wall& w = walls[static_cast<std::size_t>(entries[k].wall)];
    w.force += reaction[2 * k];
    w.torque += reaction[2 * k + 1];
    w.contact_stiffness += stiffness[k];
  }
  return active;
}

namespace {

/// Calls f(k, slot, geometry) for every touching slot of every entry of the list, in entry order.
template <class F>
void for_each_wall_touch(const ParticleStore& p, std::span<const Wall> walls,
                         const WallContactList& list, F&& f) {
  std::optional<contact::ShapeView> shapes;
  if (p.has_shapes()) shapes.emplace(p);
  const contact::ShapeView* sv = shapes ? &*shapes : nullptr;
  const auto entries = list.entries();
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const auto& entry = entries[k];
    const int i = entry.particle;
    const Wall& w = walls[static_cast<std::size_t>(entry.wall)];
    for (int slot = 0; slot < list.slots(); ++slot) {
      WallGeometry g;
      if (wall_slot_geometry(w, entry.element, sv, i, p.x()[i], p.radius()[i], slot, g))
        f(k, slot, g);
    }
  }
}

}  // namespace

double wall_elastic_energy(const ParticleStore& p, std::span<const Wall> walls,
                           const WallContactList& list,
                           const PairTable<contact::PairCoeffs>& pairs) {
  const std::int32_t* mat = p.material();
  const auto entries = list.entries();
  double e = 0;
  for_each_wall_touch(p, walls, list, [&](std::size_t k, int, const WallGeometry& g) {
    const int i = entries[k].particle;
    const contact::PairCoeffs& c =
        pairs(mat[i], walls[static_cast<std::size_t>(entries[k].wall)].material);
    e += g.force_scale * dispatch_index(contact::ContactModels{}, c.model, [&]<class M>() {
           return M::Law::elastic_energy(c, g.overlap, g.r_eff);
         });
  });
  return e;
}

void wall_heat_flows(const ParticleStore& p, std::span<Wall> walls, const WallContactList& list,
                     int model, const PairTable<double>& k_series, const double* temperature,
                     double* q, double* h) {
  const std::int32_t* mat = p.material();
  const auto entries = list.entries();
  for (auto& w : walls) w.heat_flow = 0;
  for_each_wall_touch(p, walls, list, [&](std::size_t k, int, const WallGeometry& g) {
    Wall& w = walls[static_cast<std::size_t>(entries[k].wall)];
    if (std::isnan(w.temperature)) return;
    const int i = entries[k].particle;
    const double hc = g.force_scale * contact::contact_conductance(model, g.overlap, g.r_eff,
                                                                   k_series(mat[i], w.material));
    const double flow = hc * (w.temperature - temperature[i]);
    q[i] += flow;
    h[i] += hc;
    w.heat_flow -= flow;
  });
}

}  // namespace gf
