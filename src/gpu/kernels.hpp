// SPDX-License-Identifier: GPL-3.0-or-later
// The per-grain bodies of the device step (sphere_dem.hpp): one call handles grain (or sorted
// position) i. The CUDA back end runs each as a kernel with one thread per grain
// (cuda_exec.cu); the host mirror runs the same bodies in plain loops (host_exec.cpp), so that
// every build tests the device's algorithm against the host step.
#pragma once

#include <cmath>

#include "contact/pair_forces.hpp"
#include "contact/registry.hpp"
#include "core/domain.hpp"
#include "core/host_device.hpp"
#include "gpu/sphere_dem.hpp"

namespace gf::gpu::detail {

/// The grains' columns on the device.
struct Grains {
  int n = 0;
  Vec3 *x = nullptr, *v = nullptr, *om = nullptr, *f = nullptr, *tq = nullptr;
  Vec3* x_ref = nullptr;  ///< positions at the last list build
  const double *r = nullptr, *m = nullptr, *inertia = nullptr;
  const int* mat = nullptr;
  /// Non-zero for the grains of fixed groups (ParticleStore::fixed; null: none): never
  /// integrated, two of them never listed, no wall contacts, infinite mass in a contact.
  const int* fixed = nullptr;
  /// Positions at t = 0 of the grains of fixed groups with a prescribed motion (null: none).
  const Vec3* x0 = nullptr;
  GF_HOST_DEVICE bool is_fixed(int i) const { return fixed != nullptr && fixed[i] != 0; }
};

/// The prescribed motion of a fixed group placed at time t by the host: the cosine and sine of
/// its rotation angle come from the host's std::cos and std::sin, so that the device carries the
/// grains with the bits of the host step (Simulation::place_fixed_groups, RigidMotion::carry).
struct PlacedMotion {
  RigidMotion m;
  double t = 0, c = 1, s = 0;
  GF_HOST_DEVICE Vec3 carry(const Vec3& p0) const { return m.carry_by(p0, t, c, s); }
};

/// The first fixed[] value of a moving group (ParticleStore::kFixedMoving + its motion).
constexpr int kFixedMoving = ParticleStore::kFixedMoving;

/// Cell grid of the neighbour search: nc cells along each axis from lo, cell widths w.
struct CellGrid {
  int nc[3] = {1, 1, 1};
  Vec3 lo, w;
  bool periodic[3] = {false, false, false};
  GF_HOST_DEVICE int axis_cell(const Vec3& x, int k) const {
    const int c = static_cast<int>(std::floor((x[k] - lo[k]) / w[k]));
    // Grains outside a bounded box (falling out of an open side) go to the edge cells: their
    // neighbours are then still found, in the same or the next cell.
    return c < 0 ? 0 : (c >= nc[k] ? nc[k] - 1 : c);
  }
  GF_HOST_DEVICE int cell(const Vec3& x) const {
    return (axis_cell(x, 2) * nc[1] + axis_cell(x, 1)) * nc[0] + axis_cell(x, 0);
  }
};

/// The grains sorted by cell: key[s] the cell of sorted position s, sorted[s] its grain;
/// start[c], end[c] the sorted range of cell c (-1, -1 when empty).
struct Cells {
  CellGrid grid;
  int *key = nullptr, *sorted = nullptr, *start = nullptr, *end = nullptr;
};

/// A full neighbour list, column-major: slot k of grain i at k * n + i (a warp reads one slot of
/// 32 grains as one contiguous block); count[i] slots used, found[i] partners the build found
/// (more than cap when the list must grow).
struct List {
  int cap = 0;
  int *nb = nullptr, *count = nullptr, *found = nullptr;
  Vec3* hist = nullptr;
};

/// Walls: their surfaces, one tangential history and one reaction (force and torque on the wall,
/// the torque about the wall's point) per grain and wall, at w * n + i.
struct Walls {
  const DeviceWall* walls = nullptr;
  int n = 0;
  Vec3 *hist = nullptr, *reaction = nullptr, *reaction_torque = nullptr;
};

/// The per-pair constants (ContactModels' index in `model`).
struct Laws {
  const contact::PairCoeffs* coeffs = nullptr;
  int n_mat = 0;
  bool cohesive = false;
};

GF_HOST_DEVICE inline contact::ContactResult evaluate(const contact::PairCoeffs& c,
                                                      const contact::ContactKinematics& k,
                                                      double dt, Vec3& hist, bool cohesive) {
  return dispatch_index(contact::ContactModels{}, c.model,
                        [&]<class M>() -> contact::ContactResult {
                          return cohesive ? M::Law::template evaluate<true>(c, k, dt, hist)
                                          : M::Law::template evaluate<false>(c, k, dt, hist);
                        });
}

/// First half of a step for grain i: v += dt/2 F/m, omega += dt/2 T/I, x += dt v (wrapped into
/// periodic axes), force reset to m g; raises *rebuild when the grain moved more than half the
/// skin since the last build. The same operations in the same order as VelocityVerlet.
GF_HOST_DEVICE inline void drift_one(int i, const Grains& g, const Domain& dom, double dt,
                                     const Vec3& gravity, double half_skin2, int* rebuild) {
  if (g.is_fixed(i)) {  // at rest, bit for bit; its force reset as the others' (VelocityVerlet)
    g.f[i] = g.m[i] * gravity;
    g.tq[i] = Vec3{};
    return;
  }
  const double h = 0.5 * dt;
  const double hm = h / g.m[i], hw = h / g.inertia[i];
  Vec3 vi = g.v[i];
  vi += hm * g.f[i];
  g.om[i] += hw * g.tq[i];
  Vec3 xi = g.x[i];
  xi += dt * vi;
  if (dom.any_periodic()) dom.wrap(xi, &vi);
  g.x[i] = xi;
  g.v[i] = vi;
  g.f[i] = g.m[i] * gravity;
  g.tq[i] = Vec3{};
  const Vec3 d = dom.any_periodic() ? dom.delta(xi, g.x_ref[i]) : xi - g.x_ref[i];
  if (norm2(d) > half_skin2) *rebuild = 1;
}

/// After the drift: grain i, when of a fixed group with a prescribed motion, is placed where its
/// motion carries it at the step's end (position wrapped, velocity, spin), as the host step
/// places it; raises *rebuild as the drift does when it moved more than half the skin.
GF_HOST_DEVICE inline void place_one(int i, const Grains& g, const PlacedMotion* motions,
                                     const Domain& dom, double half_skin2, int* rebuild) {
  const int k = g.fixed[i] - kFixedMoving;
  if (k < 0) return;
  const PlacedMotion& pm = motions[k];
  const Vec3 at = pm.carry(g.x0[i]);  // (the rigid body's own point: not wrapped)
  Vec3 x = at;
  if (dom.any_periodic()) dom.wrap(x);
  g.x[i] = x;
  g.v[i] = pm.m.velocity_at(at, pm.t);
  g.om[i] = pm.m.omega();
  if (norm2(dom.delta(x, g.x_ref[i])) > half_skin2) *rebuild = 1;
}

/// Second half kick of grain i: v += dt/2 F/m, omega += dt/2 T/I.
GF_HOST_DEVICE inline void kick_one(int i, const Grains& g, double dt) {
  if (g.is_fixed(i)) return;
  const double h = 0.5 * dt;
  const double hm = h / g.m[i], hw = h / g.inertia[i];
  g.v[i] += hm * g.f[i];
  g.om[i] += hw * g.tq[i];
}

/// The cell of grain i, before the sort (sorted[i] = i).
GF_HOST_DEVICE inline void cell_one(int i, const Grains& g, const Cells& c) {
  c.key[i] = c.grid.cell(g.x[i]);
  c.sorted[i] = i;
}

/// After the sort: sorted position s opens and/or closes its cell's range.
GF_HOST_DEVICE inline void range_one(int s, int n, const Cells& c) {
  const int cell = c.key[s];
  if (s == 0 || c.key[s - 1] != cell) c.start[cell] = s;
  if (s == n - 1 || c.key[s + 1] != cell) c.end[cell] = s + 1;
}

/// The list of grain i: every j != i closer than r_i + r_j + skin (minimum image), in the order
/// of the sorted cells, up to l.cap slots (l.found[i] counts them all); the histories of pairs
/// in the old list are carried over.
GF_HOST_DEVICE inline void list_one(int i, const Grains& g, const Domain& dom, const Cells& c,
                                    double skin, const List& l, const List& old) {
  const int n = g.n;
  const Vec3 xi = g.x[i];
  const double ri = g.r[i];
  const bool fixed_i = g.is_fixed(i);
  const int n_old = old.count != nullptr ? old.count[i] : 0;
  // The distinct cells at offsets -1, 0, +1 along each axis (wrapped on periodic axes; fewer
  // than three cells along an axis would otherwise visit one twice).
  int cells[3][3], m[3];
  for (int k = 0; k < 3; ++k) {
    const int ci = c.grid.axis_cell(xi, k);
    m[k] = 0;
    for (int o = -1; o <= 1; ++o) {
      int cell = ci + o;
      if (c.grid.periodic[k])
        cell = (cell + c.grid.nc[k]) % c.grid.nc[k];
      else if (cell < 0 || cell >= c.grid.nc[k])
        continue;
      bool seen = false;
      for (int q = 0; q < m[k]; ++q) seen = seen || cells[k][q] == cell;
      if (!seen) cells[k][m[k]++] = cell;
    }
  }
  int found = 0;
  for (int a = 0; a < m[2]; ++a)
    for (int b = 0; b < m[1]; ++b)
      for (int e = 0; e < m[0]; ++e) {
        const int cell = (cells[2][a] * c.grid.nc[1] + cells[1][b]) * c.grid.nc[0] + cells[0][e];
        const int s_end = c.end[cell];
        for (int s = c.start[cell]; s >= 0 && s < s_end; ++s) {
          const int j = c.sorted[s];
          if (j == i || (fixed_i && g.is_fixed(j))) continue;  // (two fixed grains never meet)
          const Vec3 d = dom.delta(xi, g.x[j]);
          const double reach = ri + g.r[j] + skin;
          if (!(norm2(d) < reach * reach)) continue;  // (a non-finite position lists nothing)
          if (found < l.cap) {
            Vec3 h{};
            for (int q = 0; q < n_old; ++q)
              if (old.nb[static_cast<std::size_t>(q) * n + i] == j) {
                h = old.hist[static_cast<std::size_t>(q) * n + i];
                break;
              }
            l.nb[static_cast<std::size_t>(found) * n + i] = j;
            l.hist[static_cast<std::size_t>(found) * n + i] = h;
          }
          ++found;
        }
      }
  const int cnt = found < l.cap ? found : l.cap;
  // Slots in increasing partner index: a grain's forces are then summed in an order that does
  // not depend on where the cells were walked or when the list was built, so a run continued
  // from a checkpoint (whose first build comes at another step) gives the same bits.
  for (int k = 1; k < cnt; ++k) {
    const std::size_t sk = static_cast<std::size_t>(k) * n + i;
    const int j = l.nb[sk];
    const Vec3 h = l.hist[sk];
    int q = k - 1;
    for (; q >= 0 && l.nb[static_cast<std::size_t>(q) * n + i] > j; --q) {
      const std::size_t from = static_cast<std::size_t>(q) * n + i;
      const std::size_t to = from + static_cast<std::size_t>(n);
      l.nb[to] = l.nb[from];
      l.hist[to] = l.hist[from];
    }
    const std::size_t at = static_cast<std::size_t>(q + 1) * n + i;
    l.nb[at] = j;
    l.hist[at] = h;
  }
  l.count[i] = cnt;
  l.found[i] = found;
}

/// Contact forces on grain i from its listed grains and from the walls, added to m g. Each pair
/// is evaluated by both of its grains: the two evaluations are exact mirror images (normal,
/// relative velocity and history change sign; the same products and sums in the same order),
/// so the grains get equal and opposite forces and the two histories stay exact negatives.
/// Writes the grain's touching pairs and wall contacts, and its reaction on each wall. t: the
/// time of the step's end, where the walls are.
GF_HOST_DEVICE inline void force_one(int i, const Grains& g, const List& l, const Walls& w,
                                     const Laws& law, const Domain& dom, double dt, double t,
                                     int* touching, int* wall_touching) {
  const int n = g.n;
  const Vec3 xi = g.x[i], vi = g.v[i], omi = g.om[i];
  const double ri = g.r[i], mi = g.m[i];
  const bool fixed_i = g.is_fixed(i);
  const contact::PairCoeffs* c_row = law.coeffs + static_cast<std::size_t>(g.mat[i]) * law.n_mat;
  Vec3 fi{}, ti{};
  int touch = 0;
  const int cnt = l.count[i];
  for (int k = 0; k < cnt; ++k) {
    const std::size_t slot = static_cast<std::size_t>(k) * n + i;
    const int j = l.nb[slot];
    const Vec3 d = dom.delta(xi, g.x[j]);
    const double rj = g.r[j];
    const double rs = ri + rj;
    const double dist2 = norm2(d);
    if (dist2 >= rs * rs) {
      l.hist[slot] = Vec3{};
      continue;
    }
    ++touch;
    double arm_i, arm_j;
    contact::ContactKinematics kin = contact::touching_spheres(d, dist2, ri, rj, arm_i, arm_j);
    // Coincident centres: opposite normals for the two grains (the host's half list gives j
    // the opposite force).
    if (dist2 == 0 && i > j) kin.normal = -kin.normal;
    kin.m_eff = contact::reduced_mass(mi, g.m[j], fixed_i, g.is_fixed(j));
    kin.v_rel = vi - g.v[j] - cross(arm_i * omi + arm_j * g.om[j], kin.normal);
    kin.omega_rel = omi - g.om[j];
    Vec3 h = l.hist[slot];
    const contact::ContactResult res = evaluate(c_row[g.mat[j]], kin, dt, h, law.cohesive);
    l.hist[slot] = h;
    fi += res.force;
    ti += res.rolling_torque - arm_i * cross(kin.normal, res.force);
  }
  int wtouch = 0;
  for (int q = 0; q < w.n; ++q) {
    const DeviceWall pw = w.walls[q];
    const std::size_t slot = static_cast<std::size_t>(q) * n + i;
    contact::ContactKinematics kin;
    // (fixed grains: no wall contacts, as the host's wall list leaves them out)
    const double gap =
        fixed_i ? 1.0
                : surface_gap(pw.kind, pw.point, pw.dir, pw.radius, pw.inside, xi, ri, kin.normal);
    if (gap >= 0) {
      w.hist[slot] = Vec3{};
      w.reaction[slot] = Vec3{};
      w.reaction_torque[slot] = Vec3{};
      continue;
    }
    ++wtouch;
    kin.overlap = -gap;
    const Vec3 arm = -(ri - 0.5 * kin.overlap) * kin.normal;
    // (as the host's single-law wall loop: the wall's velocity at the contact point x_i + arm)
    kin.v_rel = (vi - pw.motion.velocity_at(xi + arm, t)) + cross(omi, arm);
    kin.omega_rel = omi - pw.motion.omega();
    kin.r_eff = ri;
    kin.m_eff = mi;
    kin.inv_r_sum = 0;
    Vec3 h = w.hist[slot];
    const contact::ContactResult res = evaluate(c_row[pw.material], kin, dt, h, law.cohesive);
    w.hist[slot] = h;
    w.reaction[slot] = -res.force;
    // (as the host's single-law wall loop: about the wall's point, the contact point x_i + arm)
    w.reaction_torque[slot] = -(cross(xi + arm - pw.point, res.force) + res.rolling_torque);
    fi += res.force;
    ti += cross(arm, res.force) + res.rolling_torque;
  }
  g.f[i] += fi;
  g.tq[i] += ti;
  touching[i] = touch;
  wall_touching[i] = wtouch;
}

}  // namespace gf::gpu::detail
