// SPDX-License-Identifier: GPL-3.0-or-later
// Cell binning by counting sort (stable: particles keep their index order within a cell).
#include "neighbor/cell_list.hpp"

#include <algorithm>
#include <cmath>

#include "core/exec.hpp"

namespace gf {

void CellList::build(const Domain& domain, const Vec3* x, std::size_t n, double cutoff) {
  domain_ = domain;
  const Vec3 L = domain.length();
  for (int k = 0; k < 3; ++k) {
    // Cap the grid so that memory stays bounded even with a tiny cutoff in a huge box.
    nc_[k] = std::max(1, static_cast<int>(std::floor(L[k] / cutoff)));
    nc_[k] = std::min(nc_[k], 1 << 10);
    inv_size_[k] = nc_[k] / L[k];
  }
  // Slab axis: the one with the most layers (most parallel slabs); ties keep the later axis.
  // With Lees-Edwards images, pairs across the gradient boundary are shifted along the flow
  // axis, so slabs across the flow axis would not bound which slabs a row writes to: the flow
  // axis is never the slab axis there.
  axis_ = {0, 1, 2};
  std::stable_sort(axis_.begin(), axis_.end(), [&](int a, int b) {
    const bool fa = domain.sheared() && a == domain.shear_flow;
    const bool fb = domain.sheared() && b == domain.shear_flow;
    if (fa != fb) return fb;  // the flow axis sorts first (never last)
    return nc_[a] < nc_[b];
  });
  const int nct = n_cells();
  start_.assign(static_cast<std::size_t>(nct) + 1, 0);
  cell_.resize(n);
  exec::parallel_for(static_cast<exec::index_t>(n),
                     [&](exec::index_t i) { cell_[i] = cell_of(x[i]); });
  for (std::size_t i = 0; i < n; ++i) ++start_[static_cast<std::size_t>(cell_[i]) + 1];
  for (int c = 0; c < nct; ++c) start_[c + 1] += start_[c];
  order_.resize(n);
  fill_.assign(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    order_[static_cast<std::size_t>(fill_[cell_[i]]++)] = static_cast<std::int32_t>(i);
}

int CellList::cell_of(const Vec3& p) const {
  int q[3];
  for (int k = 0; k < 3; ++k) {
    const int c = static_cast<int>(std::floor((p[k] - domain_.lo[k]) * inv_size_[k]));
    q[k] = std::clamp(c, 0, nc_[k] - 1);
  }
  return index(q);
}

int CellList::stencil(int c, int* out) const {
  int cq[3];
  cq[axis_[0]] = c % nc_[axis_[0]];
  cq[axis_[1]] = (c / nc_[axis_[0]]) % nc_[axis_[1]];
  cq[axis_[2]] = c / (nc_[axis_[0]] * nc_[axis_[1]]);
  const int g = domain_.shear_gradient, fl = domain_.shear_flow;
  // Lees-Edwards: across the gradient boundary the neighbour layer is the image shifted by
  // +-offset along the flow axis, s cells. A point of cell q in the shifted image lies within
  // one cell edge of the cells floor(q -+ s) - 1 .. floor(q -+ s) + 2 (four, not three).
  const double shift_cells = g >= 0 ? domain_.shear_offset * inv_size_[fl] : 0.0;
  int top[3] = {1, 1, 1};
  if (g >= 0) top[fl] = 2;
  int count = 0;
  int d[3];
  for (d[2] = -1; d[2] <= top[2]; ++d[2])
    for (d[1] = -1; d[1] <= top[1]; ++d[1])
      for (d[0] = -1; d[0] <= top[0]; ++d[0]) {
        int q[3] = {cq[0] + d[0], cq[1] + d[1], cq[2] + d[2]};
        int across = 0;  // +1: the upper image along the gradient axis, -1: the lower one
        if (g >= 0) across = q[g] >= nc_[g] ? 1 : (q[g] < 0 ? -1 : 0);
        if (across != 0)
          q[fl] = static_cast<int>(std::floor(cq[fl] - across * shift_cells)) + d[fl];
        else if (g >= 0 && d[fl] == 2)
          continue;
        bool ok = true;
        for (int k = 0; k < 3; ++k) {
          if (q[k] < 0 || q[k] >= nc_[k]) {
            if (!domain_.periodic[k]) {
              ok = false;
              break;
            }
            q[k] = ((q[k] % nc_[k]) + nc_[k]) % nc_[k];
          }
        }
        if (!ok) continue;
        const int id = index(q);
        if (std::find(out, out + count, id) == out + count) out[count++] = id;
      }
  return count;
}

}  // namespace gf
