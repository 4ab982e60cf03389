// SPDX-License-Identifier: GPL-3.0-or-later
// Cell binning by counting sort (stable: particles keep their index order within a cell).
#include "neighbor/cell_list.hpp"

#include <algorithm>
#include <cmath>

#include "core/exec.hpp"

namespace gf {

std::array<int, 3> CellList::grid(const Vec3& length, double cutoff, std::size_t n) {
  std::array<int, 3> nc{1, 1, 1};
  for (int k = 0; k < 3; ++k) {
    // Cap the grid so that memory stays bounded even with a tiny cutoff in a huge box.
    // (clamped as a double: a ratio beyond INT_MAX must not reach the cast)
    const double m = std::floor(length[k] / cutoff);
    nc[k] = m >= 1.0 ? static_cast<int>(std::min(m, 1024.0)) : 1;
  }
  const double cap = std::max(1048576.0, 8.0 * static_cast<double>(n));
  while (static_cast<double>(nc[0]) * nc[1] * nc[2] > cap) {
    int& largest = *std::max_element(nc.begin(), nc.end());
    largest = std::max(1, largest / 2);
  }
  return nc;
}

void CellList::build(const Domain& domain, const Vec3* x, std::size_t n, double cutoff) {
  domain_ = domain;
  const Vec3 L = domain.length();
  nc_ = grid(L, cutoff, n);
  for (int k = 0; k < 3; ++k) inv_size_[k] = nc_[k] / L[k];
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
  int cq[3], stride[3];
  cq[axis_[0]] = c % nc_[axis_[0]];
  cq[axis_[1]] = (c / nc_[axis_[0]]) % nc_[axis_[1]];
  cq[axis_[2]] = c / (nc_[axis_[0]] * nc_[axis_[1]]);
  stride[axis_[0]] = 1;
  stride[axis_[1]] = nc_[axis_[0]];
  stride[axis_[2]] = nc_[axis_[0]] * nc_[axis_[1]];
  // The neighbour layers first..first+count-1 along axis k as id offsets (layer x stride),
  // folded into the box along periodic axes, dropped beyond the others.
  auto layers = [&](int k, int first, int count, int* offset) {
    int m = 0;
    for (int q = first; q < first + count; ++q) {
      int f = q;
      if (f < 0 || f >= nc_[k]) {
        if (!domain_.periodic[k]) continue;
        f = ((f % nc_[k]) + nc_[k]) % nc_[k];
      }
      offset[m++] = f * stride[k];
    }
    return m;
  };
  // Inserts id in ascending order; skips a repeat (a periodic axis of fewer cells than the
  // stencil is wide folds two layers onto one). Nearly always an append: the loops below run
  // the slowest axis outermost.
  int count = 0;
  auto insert = [&](int id) {
    int at = count;
    while (at > 0 && out[at - 1] > id) --at;
    if (at > 0 && out[at - 1] == id) return;
    for (int k = count; k > at; --k) out[k] = out[k - 1];
    out[at] = id;
    ++count;
  };
  const int g = domain_.shear_gradient;
  if (g < 0) {
    int off[3][3], m[3];
    for (int k = 0; k < 3; ++k) m[k] = layers(k, cq[k] - 1, 3, off[k]);
    const int a0 = axis_[0], a1 = axis_[1], a2 = axis_[2];
    for (int i2 = 0; i2 < m[a2]; ++i2)
      for (int i1 = 0; i1 < m[a1]; ++i1)
        for (int i0 = 0; i0 < m[a0]; ++i0) insert(off[a2][i2] + off[a1][i1] + off[a0][i0]);
    return count;
  }
  // Lees-Edwards: across the gradient boundary the neighbour layer is the image shifted by
  // +-offset along the flow axis, s cells. A point of cell q in the shifted image lies within
  // one cell edge of the cells floor(q -+ s) - 1 .. floor(q -+ s) + 2 (four, not three).
  const int fl = domain_.shear_flow, o = 3 - g - fl;
  const double shift_cells = domain_.shear_offset * inv_size_[fl];
  int flow_off[4], other_off[3];
  const int m_flow = layers(fl, cq[fl] - 1, 3, flow_off);
  const int m_other = layers(o, cq[o] - 1, 3, other_off);
  const bool flow_slower = stride[fl] > stride[o];  // ascending: the slower in-layer axis outside
  for (int qg = cq[g] - 1; qg <= cq[g] + 1; ++qg) {
    const int across = qg >= nc_[g] ? 1 : (qg < 0 ? -1 : 0);
    int base[1];
    if (layers(g, qg, 1, base) == 0) continue;
    int shifted[4];
    const int* f_off = flow_off;
    int m_f = m_flow;
    if (across != 0) {
      const int first = static_cast<int>(std::floor(cq[fl] - across * shift_cells)) - 1;
      m_f = layers(fl, first, 4, shifted);
      f_off = shifted;
    }
    const int* outer = flow_slower ? f_off : other_off;
    const int* inner = flow_slower ? other_off : f_off;
    const int m_outer = flow_slower ? m_f : m_other, m_inner = flow_slower ? m_other : m_f;
    for (int a = 0; a < m_outer; ++a)
      for (int b = 0; b < m_inner; ++b) insert(base[0] + outer[a] + inner[b]);
  }
  return count;
}

}  // namespace gf
