// SPDX-License-Identifier: GPL-3.0-or-later
// Verlet (neighbour) list with skin: a half list in CSR form, the tangential contact history
// stored next to each entry and carried across rebuilds (and across re-ordering).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "core/domain.hpp"
#include "neighbor/cell_list.hpp"
#include "particles/particle_store.hpp"

namespace gf {

/// Extra condition for a candidate pair (i, j) within the bounding-sphere cutoff, in the
/// (re-ordered) indices of the build; empty = keep every candidate. Used for elongated grains,
/// whose bounding spheres are much larger than the grains (see Simulation::update_neighbors).
using PairFilter = std::function<bool(std::int32_t i, std::int32_t j)>;

class VerletList {
 public:
  /// Re-orders every column of the store by cell (slab-major, see CellList), then builds the
  /// list of pairs i < j with |x_i - x_j| < r_i + r_j + skin (minimum image); histories of
  /// pairs already in the list are carried over (negated when the pair's orientation flips).
  /// Returns the permutation: new index k holds the particle that had index perm[k] at the
  /// previous build (-1: a grain added since). `previous` (grains removed or added since that
  /// build): the index at the previous build of each grain of the store, -1 for a grain added
  /// since; empty = the store's own order.
  std::span<const std::int64_t> sort_and_build(ParticleStore& p, const Domain& domain, double skin,
                                               const PairFilter& filter = {},
                                               std::span<const std::int64_t> previous = {});

  /// Builds without re-ordering (the particle order is kept; no slabs for threading).
  void build(const Domain& domain, const Vec3* x, const double* r, std::size_t n, double skin,
             const PairFilter& filter = {});

  /// True when some particle moved more than displacement_limit() since the last build (or the
  /// count changed).
  bool needs_rebuild(const Domain& domain, const Vec3* x, std::size_t n) const;
  /// The same test from the largest squared displacement since the last build, measured by the
  /// caller (the drift loop, DriftExtras): no pass of its own.
  bool needs_rebuild(const Domain& domain, double max_d2, std::size_t n) const {
    if (x_ref_.size() != n) return true;
    const double lim = displacement_limit(domain);
    return lim <= 0 || max_d2 > lim * lim;
  }

  /// How far a particle may move from its position at the last build before the list can miss
  /// a pair: skin/2. With Lees-Edwards images a pair across the gradient boundary also closes in
  /// by the change s of the offset: (skin - s)/2 when the reference positions follow the grains'
  /// wraps (follow_wraps()), else (skin - 3 s)/2, since a grain that crossed the boundary at an
  /// earlier offset is then measured through the current one, off by up to s (<= 0: rebuild now).
  double displacement_limit(const Domain& domain) const {
    return 0.5 *
           (skin_ - (refs_follow_wraps_ ? 1.0 : 3.0) * domain.offset_change(shear_offset_ref_));
  }
  /// Lees-Edwards offset at the last build (restart).
  double shear_offset_at_build() const { return shear_offset_ref_; }
  void set_shear_offset_at_build(double o) { shear_offset_ref_ = o; }

  /// The owner promises to move each grain's reference position by the jump of every wrap of
  /// that grain (VelocityVerlet's DriftExtras::wrap_refs), from the next build on: the
  /// displacement measured from the reference is then the grain's own, also across the
  /// Lees-Edwards boundary, and displacement_limit() need not allow for a crossing.
  void set_follow_wraps(bool on) { follow_wraps_ = on; }
  bool follows_wraps() const { return follow_wraps_; }
  /// The reference positions, to be moved with the wraps (empty before the first build).
  std::span<Vec3> follow_wraps() { return x_ref_; }
  /// Whether the current reference positions have followed every wrap since the build (restart).
  bool refs_follow_wraps() const { return refs_follow_wraps_; }
  void set_refs_follow_wraps(bool on) { refs_follow_wraps_ = on; }

  std::size_t n_particles() const { return offsets_.empty() ? 0 : offsets_.size() - 1; }
  std::size_t n_pairs() const { return neighbors_.size(); }
  std::int64_t n_builds() const { return n_builds_; }
  double skin() const { return skin_; }

  // CSR: the neighbours of i are neighbors()[offsets()[i] .. offsets()[i+1]), ascending.
  std::span<const std::int64_t> offsets() const { return offsets_; }
  std::span<const std::int32_t> neighbors() const { return neighbors_; }
  std::span<Vec3> history() { return history_; }
  std::span<const Vec3> history() const { return history_; }
  std::span<const Vec3> reference_positions() const { return x_ref_; }

  /// Slabs of consecutive particle indices for race-free threaded force loops: the rows of
  /// slab s write only to particles of slabs s and s+1, and of slab 0 also to the last slab.
  /// Slabs of the same phase (s % n_phases) can run concurrently. Empty: no slabs (serial).
  std::span<const std::int64_t> slab_starts() const { return slab_starts_; }
  int n_slabs() const {
    return slab_starts_.empty() ? 0 : static_cast<int>(slab_starts_.size()) - 1;
  }
  int n_phases() const { return n_phases_; }

  /// Replaces the whole state (restart); slabs are re-derived from the stored ones.
  void restore(std::vector<std::int64_t> offsets, std::vector<std::int32_t> neighbors,
               std::vector<Vec3> history, std::vector<Vec3> x_ref, double skin,
               std::int64_t n_builds, std::vector<std::int64_t> slab_starts, int n_phases);

  std::size_t bytes() const;

 private:
  void build_rows(const Domain& domain, const Vec3* x, const double* r, std::size_t n, double skin,
                  bool sorted, const PairFilter& filter = {});
  /// The stencil of the cell whose rows are being built (one per chunk of rows).
  struct StencilMemo {
    int cell = -1;
    int n = 0;
    int cells[36];
  };
  template <class ForNeighbours>
  void build_rows_in_chunks(std::size_t n, bool sorted, ForNeighbours& for_neighbours);
  void keep_old_histories();
  /// Histories of the pairs of the previous list (of n_before grains) for the new one; `perm`
  /// maps the new indices to those of the previous build.
  void carry_history(std::span<const std::int64_t> perm, std::size_t n_before);

  double skin_ = 0;
  double shear_offset_ref_ = 0;
  bool follow_wraps_ = false;       // the owner moves the references with the wraps
  bool refs_follow_wraps_ = false;  // ... and has done so since the last build
  std::int64_t n_builds_ = 0;
  std::vector<std::int64_t> offsets_;
  std::vector<std::int32_t> neighbors_;
  std::vector<Vec3> history_;
  std::vector<Vec3> x_ref_;
  std::vector<std::int64_t> slab_starts_;
  int n_phases_ = 1;
  CellList cells_;
  std::vector<std::int64_t> perm_;
  // During a rebuild: the pairs of the previous list that carry a history (the others have
  // none to carry), for the history transfer; freed once it is done.
  std::vector<std::int64_t> old_offsets_;
  std::vector<std::int32_t> old_neighbors_;
  std::vector<Vec3> old_history_;
};

}  // namespace gf
