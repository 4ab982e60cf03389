// SPDX-License-Identifier: GPL-3.0-or-later
// Cell binning by counting sort (stable: particles keep their index order within a cell).
#include "neighbor/cell_list.hpp"

#include <algorithm>
#include <cmath>

namespace gf {

void CellList::build(const Domain& domain, const Vec3* x, std::size_t n, double cutoff) {
  domain_ = domain;
  const Vec3 L = domain.length();
  for (int k = 0; k < 3; ++k) {
    // Cap the grid so that memory stays O(N) even with a tiny cutoff in a huge box.
    nc_[k] = std::max(1, static_cast<int>(std::floor(L[k] / cutoff)));
    nc_[k] = std::min(nc_[k], 1 << 10);
    inv_size_[k] = nc_[k] / L[k];
  }
  const int nct = n_cells();
  start_.assign(static_cast<std::size_t>(nct) + 1, 0);
  cell_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    cell_[i] = cell_of(x[i]);
    ++start_[cell_[i] + 1];
  }
  for (int c = 0; c < nct; ++c) start_[c + 1] += start_[c];
  order_.resize(n);
  std::vector<std::int64_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) order_[fill[cell_[i]]++] = static_cast<std::int32_t>(i);
}

int CellList::cell_of(const Vec3& p) const {
  int idx[3];
  for (int k = 0; k < 3; ++k) {
    int c = static_cast<int>(std::floor((p[k] - domain_.lo[k]) * inv_size_[k]));
    idx[k] = std::clamp(c, 0, nc_[k] - 1);
  }
  return (idx[2] * nc_[1] + idx[1]) * nc_[0] + idx[0];
}

int CellList::stencil(int c, int* out) const {
  const int cx = c % nc_[0], cy = (c / nc_[0]) % nc_[1], cz = c / (nc_[0] * nc_[1]);
  int count = 0;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        int q[3] = {cx + dx, cy + dy, cz + dz};
        bool ok = true;
        for (int k = 0; k < 3; ++k) {
          if (q[k] < 0 || q[k] >= nc_[k]) {
            if (!domain_.periodic[k]) { ok = false; break; }
            q[k] = (q[k] + nc_[k]) % nc_[k];
          }
        }
        if (!ok) continue;
        const int id = (q[2] * nc_[1] + q[1]) * nc_[0] + q[0];
        if (std::find(out, out + count, id) == out + count) out[count++] = id;
      }
  return count;
}

}  // namespace gf
