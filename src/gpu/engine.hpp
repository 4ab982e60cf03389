// SPDX-License-Identifier: GPL-3.0-or-later
// The device step's orchestration (sphere_dem.hpp), written once over an execution back end
// `Exec`: its arrays, its loops over grains (each one of the bodies of kernels.hpp) and a few
// reductions. CudaExec (cuda_exec.cu) runs them on the GPU, HostExec (host_exec.cpp) in plain
// loops on the host.
//
// Exec provides: Array<T> (resize, upload, download, zero, ptr, size); drift, kick, cells,
// ranges, list and force (the bodies over all grains); sort_by_key (stable); max and sum over
// ints, sum over Vec3; copy (array to array); read / write of one value.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "core/stop.hpp"
#include "gpu/kernels.hpp"

namespace gf::gpu::detail {

/// What SphereDem forwards to (one engine per back end).
class EngineBase {
 public:
  virtual ~EngineBase() = default;
  virtual std::int64_t advance(std::int64_t n) = 0;
  virtual void download(ParticleStore& p) const = 0;
  virtual std::int64_t n_contacts() const = 0;
  virtual std::int64_t n_wall_contacts() const = 0;
  virtual std::vector<Vec3> wall_forces() const = 0;
  virtual std::vector<Vec3> wall_torques() const = 0;
  virtual std::vector<HistoryEntry> pair_history() const = 0;
  virtual std::vector<HistoryEntry> wall_history() const = 0;
  virtual DeviceCounts counts() const = 0;
};

template <class Exec>
class Engine final : public EngineBase {
  template <class T>
  using Array = typename Exec::template Array<T>;

 public:
  Engine(const ParticleStore& p, const SphereDemSetup& setup) : s_(setup) {
    REQUIRE(p.size() < (std::size_t{1} << 31), "the device back end takes fewer than 2^31 grains");
    REQUIRE(setup.skin > 0, "the device back end needs a positive neighbour skin");
    REQUIRE(setup.initial_slots > 0, "the device back end needs at least one neighbour slot");
    cap_ = setup.initial_slots;
    n_ = static_cast<int>(p.size());
    const std::size_t n = p.size();
    for (int a = 0; a < s_.pairs.n(); ++a)
      for (int b = 0; b < s_.pairs.n(); ++b)
        laws_.cohesive |= s_.pairs(a, b).model >= 0 && s_.pairs(a, b).cohesion > 0;
    x_.upload(p.x(), n);
    v_.upload(p.v(), n);
    om_.upload(p.omega(), n);
    f_.upload(p.f(), n);
    tq_.upload(p.torque(), n);
    r_.upload(p.radius(), n);
    m_.upload(p.mass(), n);
    inertia_.upload(p.inertia(), n);
    mat_.upload(p.material(), n);
    if (p.fixed() != nullptr) fixed_.upload(p.fixed(), n);
    if (!s_.fixed_motions.empty()) {
      REQUIRE(p.fixed_x0() != nullptr, "fixed groups with a motion need their positions at t = 0");
      x0_.upload(p.fixed_x0(), n);
    }
    x_ref_.resize(n);
    key_.resize(n);
    sorted_.resize(n);
    touching_.resize(n);
    touching_.zero();
    wall_touching_.resize(n);
    wall_touching_.zero();
    flag_.resize(1);
    flag_.zero();
    coeffs_.upload(s_.pairs.data(), static_cast<std::size_t>(s_.pairs.n()) * s_.pairs.n());
    walls_.upload(s_.walls.data(), s_.walls.size());
    wall_hist_.resize(s_.walls.size() * n);
    wall_hist_.zero();
    wall_reaction_.resize(s_.walls.size() * n);
    wall_reaction_.zero();
    wall_reaction_torque_.resize(s_.walls.size() * n);
    wall_reaction_torque_.zero();
    for (auto& l : lists_) l.found.resize(n);
    double dmax = 0;
    for (std::size_t i = 0; i < n; ++i) dmax = std::max(dmax, 2 * p.radius()[i]);
    set_grid(dmax);
    if (n == 0) return;
    // Histories at the start: given to the first build as if they were the list in use.
    if (!s_.pair_history.empty()) {
      std::vector<std::vector<HistoryEntry>> rows(n);
      for (const auto& e : s_.pair_history) {
        REQUIRE(e.i >= 0 && e.j >= 0 && e.i < n_ && e.j < n_ && e.i != e.j,
                "contact history of pair ({}, {}): no such pair among {} grains", e.i, e.j, n);
        rows[static_cast<std::size_t>(e.i)].push_back(e);
        rows[static_cast<std::size_t>(e.j)].push_back(HistoryEntry{e.j, e.i, -1.0 * e.h});
      }
      std::size_t width = 1;
      for (const auto& row : rows) width = std::max(width, row.size());
      std::vector<int> nb(width * n, -1), cnt(n);
      std::vector<Vec3> h(width * n);
      for (std::size_t i = 0; i < n; ++i) {
        cnt[i] = static_cast<int>(rows[i].size());
        for (std::size_t k = 0; k < rows[i].size(); ++k) {
          nb[k * n + i] = rows[i][k].j;
          h[k * n + i] = rows[i][k].h;
        }
      }
      auto& l = lists_[cur_];
      l.nb.upload(nb.data(), nb.size());
      l.count.upload(cnt.data(), cnt.size());
      l.hist.upload(h.data(), h.size());
      l.cap = static_cast<int>(width);
      have_list_ = true;
    }
    if (!s_.wall_history.empty()) {
      std::vector<Vec3> wh(s_.walls.size() * n);
      for (const auto& e : s_.wall_history) {
        REQUIRE(e.i >= 0 && e.i < n_ && e.j >= 0 && static_cast<std::size_t>(e.j) < s_.walls.size(),
                "wall contact history of grain {} and wall {}: no such pair", e.i, e.j);
        wh[static_cast<std::size_t>(e.j) * n + static_cast<std::size_t>(e.i)] = e.h;
      }
      wall_hist_.upload(wh.data(), wh.size());
    }
    s_.pair_history = {};
    s_.wall_history = {};
    build_list();
  }

  std::int64_t advance(std::int64_t steps) override {
    if (n_ == 0) {
      counts_.steps += steps;
      return steps;
    }
    const double half_skin2 = 0.25 * s_.skin * s_.skin;
    const bool walls_move =
        std::any_of(s_.walls.begin(), s_.walls.end(), [](const DeviceWall& w) { return w.moves; });
    std::int64_t k = 0;
    for (; k < steps; ++k) {
      // A stop request (SIGINT / SIGTERM / --max-hours) ends the chunk early: the run then
      // writes its outputs and checkpoint at the step reached.
      if (k > 0 && k % 64 == 0 && stop::requested()) break;
      // The time of this step's end, where the host puts the walls (Simulation::step).
      const double t = static_cast<double>(s_.first_step + counts_.steps + 1) * s_.dt;
      Exec::drift(grains(), s_.domain, s_.dt, s_.gravity, half_skin2, flag_.ptr);
      if (!s_.fixed_motions.empty()) {
        // Each motion placed on the host (its cosine and sine, as RigidMotion::rotate takes
        // them), copied over (a few motions), its grains carried on the device.
        placed_host_.clear();
        for (const auto& m : s_.fixed_motions) {
          PlacedMotion pm{m, t};
          if (m.rate != 0) pm.c = std::cos(m.rate * t), pm.s = std::sin(m.rate * t);
          placed_host_.push_back(pm);
        }
        placed_.upload(placed_host_.data(), placed_host_.size());
        Exec::place(grains(), placed_.ptr, s_.domain, half_skin2, flag_.ptr);
      }
      if (Exec::read(flag_.ptr) != 0) {
        Exec::write(flag_.ptr, 0);
        build_list();
        ++counts_.list_builds;
      }
      if (walls_move) {
        // Placed on the host, as Wall::update_geometry does (the same bits: the device's sine
        // and cosine may differ in the last place), and copied over (a few walls).
        for (auto& w : s_.walls)
          if (w.moves) {
            w.point = w.motion.point_at(w.point0, t) + Vec3{};
            w.dir = w.motion.rotate(w.dir0, t);
          }
        walls_.upload(s_.walls.data(), s_.walls.size());
      }
      Exec::force(grains(), view(lists_[cur_]), walls(), laws(), s_.domain, s_.dt, t, touching_.ptr,
                  wall_touching_.ptr);
      Exec::kick(grains(), s_.dt);
      ++counts_.steps;
    }
    Exec::sync();
    return k;
  }

  void download(ParticleStore& p) const override {
    REQUIRE(static_cast<int>(p.size()) == n_, "download into a store of another size");
    const std::size_t n = p.size();
    x_.download(p.x(), n);
    v_.download(p.v(), n);
    om_.download(p.omega(), n);
    f_.download(p.f(), n);
    tq_.download(p.torque(), n);
  }

  std::int64_t n_contacts() const override {
    return n_ == 0 ? 0 : Exec::sum(touching_.ptr, n_) / 2;  // each pair counted by both grains
  }
  std::int64_t n_wall_contacts() const override {
    return n_ == 0 ? 0 : Exec::sum(wall_touching_.ptr, n_);
  }
  std::vector<Vec3> wall_forces() const override {
    std::vector<Vec3> out(s_.walls.size());
    for (std::size_t w = 0; w < out.size() && n_ > 0; ++w)
      out[w] = Exec::sum(wall_reaction_.ptr + w * static_cast<std::size_t>(n_), n_);
    return out;
  }

  std::vector<Vec3> wall_torques() const override {
    std::vector<Vec3> out(s_.walls.size());
    for (std::size_t w = 0; w < out.size() && n_ > 0; ++w)
      out[w] = Exec::sum(wall_reaction_torque_.ptr + w * static_cast<std::size_t>(n_), n_);
    return out;
  }

  std::vector<HistoryEntry> pair_history() const override {
    std::vector<HistoryEntry> out;
    if (!have_list_) return out;
    const auto& l = lists_[cur_];
    const std::size_t n = static_cast<std::size_t>(n_);
    std::vector<int> nb(l.nb.size), cnt(n);
    std::vector<Vec3> h(l.hist.size);
    l.nb.download(nb.data(), nb.size());
    l.count.download(cnt.data(), n);
    l.hist.download(h.data(), h.size());
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = 0; k < static_cast<std::size_t>(cnt[i]); ++k) {
        const int j = nb[k * n + i];
        const Vec3& hk = h[k * n + i];
        if (static_cast<int>(i) < j && hk != Vec3{})
          out.push_back(HistoryEntry{static_cast<std::int32_t>(i), j, hk});
      }
    return out;
  }

  std::vector<HistoryEntry> wall_history() const override {
    std::vector<HistoryEntry> out;
    const std::size_t n = static_cast<std::size_t>(n_);
    std::vector<Vec3> h(wall_hist_.size);
    wall_hist_.download(h.data(), h.size());
    for (std::size_t w = 0; w < s_.walls.size(); ++w)
      for (std::size_t i = 0; i < n; ++i)
        if (h[w * n + i] != Vec3{})
          out.push_back(HistoryEntry{static_cast<std::int32_t>(i), static_cast<std::int32_t>(w),
                                     h[w * n + i]});
    return out;
  }

  DeviceCounts counts() const override {
    DeviceCounts c = counts_;
    auto add = [&c](const auto&... a) { ((c.bytes += a.size * sizeof(*a.ptr)), ...); };
    add(x_, v_, om_, f_, tq_, x_ref_, x0_, r_, m_, inertia_, mat_, fixed_, placed_, key_, sorted_,
        cell_start_, cell_end_, touching_, wall_touching_, flag_, coeffs_, walls_, wall_hist_,
        wall_reaction_, wall_reaction_torque_);
    for (const auto& l : lists_) add(l.nb, l.count, l.found, l.hist);
    return c;
  }

 private:
  struct ListArrays {
    int cap = 0;
    Array<int> nb, count, found;
    Array<Vec3> hist;
  };
  static List view(ListArrays& l) {
    return List{l.cap, l.nb.ptr, l.count.ptr, l.found.ptr, l.hist.ptr};
  }

  Grains grains() {
    Grains g{n_,         x_.ptr, v_.ptr, om_.ptr,      f_.ptr,  tq_.ptr,
             x_ref_.ptr, r_.ptr, m_.ptr, inertia_.ptr, mat_.ptr};
    if (fixed_.size > 0) g.fixed = fixed_.ptr;
    if (x0_.size > 0) g.x0 = x0_.ptr;
    return g;
  }
  Walls walls() {
    return Walls{walls_.ptr, static_cast<int>(s_.walls.size()), wall_hist_.ptr, wall_reaction_.ptr,
                 wall_reaction_torque_.ptr};
  }
  Laws laws() const { return Laws{coeffs_.ptr, s_.pairs.n(), laws_.cohesive}; }

  void set_grid(double max_diameter) {
    double width = max_diameter + s_.skin;
    const Vec3 len = s_.domain.length();
    // At most ~8 cells per grain (and 2^20 in all for small runs): a sparse cloud in a large
    // box gets wider cells, not gigabytes of empty ones.
    const double max_cells = 8.0 * n_ + (1 << 20);
    const double cells =
        std::max(1.0, len.x / width) * std::max(1.0, len.y / width) * std::max(1.0, len.z / width);
    if (cells > max_cells) width *= std::cbrt(cells / max_cells);
    for (int k = 0; k < 3; ++k) {
      cells_.grid.periodic[k] = s_.domain.periodic[k];
      cells_.grid.lo[k] = s_.domain.lo[k];
      int nc = static_cast<int>(std::floor(len[k] / width));
      nc = std::max(1, std::min(nc, 1 << 10));
      cells_.grid.nc[k] = nc;
      cells_.grid.w[k] = len[k] / nc;
    }
    const std::size_t n_cells =
        static_cast<std::size_t>(cells_.grid.nc[0]) * cells_.grid.nc[1] * cells_.grid.nc[2];
    cell_start_.resize(n_cells);
    cell_end_.resize(n_cells);
  }

  /// Sorts the grains by cell and builds the list into the spare set of arrays (growing its
  /// slots until every grain's partners fit), carrying the histories of the list in use; then
  /// swaps.
  void build_list() {
    Cells c{cells_.grid, key_.ptr, sorted_.ptr, cell_start_.ptr, cell_end_.ptr};
    Exec::cells(grains(), c);
    Exec::sort_by_key(key_.ptr, sorted_.ptr, n_);
    cell_start_.fill(-1);
    cell_end_.fill(-1);
    Exec::ranges(n_, c);
    const int nxt = 1 - cur_;
    auto& l = lists_[nxt];
    l.cap = std::max(l.cap, cap_);
    const List none{};
    for (;;) {
      const std::size_t slots = static_cast<std::size_t>(l.cap) * static_cast<std::size_t>(n_);
      if (l.nb.size < slots) {
        l.nb.resize(slots);
        l.hist.resize(slots);
      }
      l.count.resize(static_cast<std::size_t>(n_));
      Exec::list(grains(), s_.domain, c, s_.skin, view(l), have_list_ ? view(lists_[cur_]) : none);
      const int need = Exec::max(l.found.ptr, n_);
      if (need <= l.cap) break;
      l.cap = std::max(need + 8, l.cap + l.cap / 2);  // room to grow, then build again
    }
    cap_ = l.cap;
    cur_ = nxt;
    have_list_ = true;
    Exec::copy(x_ref_.ptr, x_.ptr, static_cast<std::size_t>(n_));
    counts_.list_capacity = cap_;
  }

  SphereDemSetup s_;
  int n_ = 0;
  Laws laws_;
  Array<Vec3> x_, v_, om_, f_, tq_, x_ref_, x0_;
  Array<PlacedMotion> placed_;
  std::vector<PlacedMotion> placed_host_;  ///< (kept: no allocation per step)
  Array<double> r_, m_, inertia_;
  Array<int> mat_, fixed_, key_, sorted_, cell_start_, cell_end_, touching_, wall_touching_, flag_;
  Array<contact::PairCoeffs> coeffs_;
  Array<DeviceWall> walls_;
  Array<Vec3> wall_hist_, wall_reaction_, wall_reaction_torque_;
  ListArrays lists_[2];
  int cur_ = 0;   ///< the list in use
  int cap_ = 32;  ///< slots per grain of the next build (grows)
  bool have_list_ = false;
  Cells cells_;
  DeviceCounts counts_;
};

}  // namespace gf::gpu::detail
