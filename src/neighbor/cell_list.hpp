// SPDX-License-Identifier: GPL-3.0-or-later
// Uniform cell grid over the domain, for finding all pairs closer than a cutoff in O(N).
//
// Cells are numbered with the *slab axis* (the axis with the most cells) varying slowest, so
// sorting particles by cell gives a slab-major order: one cell layer across the slab axis is a
// slab, and pairs i < j are always in the same or the next slab (or, across a periodic
// boundary, in the first and the last). The force loop uses this for race-free threading.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/domain.hpp"

namespace gf {

class CellList {
 public:
  /// Bins n positions into cells of edge >= cutoff (counting sort, stable). Particles outside
  /// the domain in non-periodic directions go to the border cells (correct, just slower).
  void build(const Domain& domain, const Vec3* x, std::size_t n, double cutoff);

  /// The grid build() uses for n particles in a box of edge lengths `length`: per axis
  /// floor(L / cutoff) cells (at least 1, at most 1024), then, while there are more than
  /// max(2^20, 8 n) cells, the axis with the most cells halved (cells stay >= cutoff). Cells
  /// beyond a few per particle only cost memory and the time to clear them: one 0.1 mm grain
  /// in a 1 m box had 2.1e8 cells, 3.3 GB and 11 s of set-up.
  static std::array<int, 3> grid(const Vec3& length, double cutoff, std::size_t n);

  int n_cells() const { return nc_[0] * nc_[1] * nc_[2]; }
  /// Particles of cell c are order()[begin(c) .. begin(c+1)).
  std::int64_t begin(int c) const { return start_[static_cast<std::size_t>(c)]; }
  /// Particle indices sorted by cell (slab-major).
  const std::vector<std::int32_t>& order() const { return order_; }
  int cell_of(const Vec3& p) const;
  /// Cell of particle i as binned by the last build.
  int cell_of_particle(std::size_t i) const { return cell_[i]; }
  /// Distinct neighbour cells of cell c (itself included), periodic images folded, in ascending
  /// order: at most 27, or 36 across a Lees-Edwards boundary.
  int stencil(int c, int* out36) const;
  const std::array<int, 3>& dims() const { return nc_; }
  int slab_axis() const { return axis_[2]; }
  int n_layers() const { return nc_[axis_[2]]; }
  /// Cells per slab layer.
  int cells_per_layer() const { return nc_[axis_[0]] * nc_[axis_[1]]; }

 private:
  int index(const int q[3]) const {
    return (q[axis_[2]] * nc_[axis_[1]] + q[axis_[1]]) * nc_[axis_[0]] + q[axis_[0]];
  }
  Domain domain_;
  std::array<int, 3> nc_{1, 1, 1};
  std::array<int, 3> axis_{0, 1, 2};  ///< fastest, middle, slowest (slab) axis
  Vec3 inv_size_;
  std::vector<std::int64_t> start_, fill_;
  std::vector<std::int32_t> order_;
  std::vector<std::int32_t> cell_;
};

}  // namespace gf
