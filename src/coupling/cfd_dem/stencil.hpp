// SPDX-License-Identifier: GPL-3.0-or-later
// Point <-> cell weights on the fluid grid: the cell containing a point, and the trilinear
// (2D: bilinear) stencil between cell centres used both to interpolate cell-centred fields to a
// point and, with the same weights, to deposit a particle's force back onto the cells (so the
// two operations are adjoint and the deposit conserves momentum exactly).
#pragma once

#include <cmath>
#include <cstdint>

#include "core/host_device.hpp"
#include "core/vec3.hpp"
#include "fluid/fv/grid.hpp"

namespace gf::cfd_dem {

/// Linear index of the cell containing x. Periodic axes wrap; along a wall axis a point outside
/// the box belongs to the nearest boundary cell (nothing deposited there is lost). 2D grids have
/// one layer: z is ignored.
GF_HOST_DEVICE inline std::int64_t cell_containing(const fluid::Grid& g, const Vec3& x) {
  const int i = g.fold(0, g.cell_of(0, x.x));
  const int j = g.fold(1, g.cell_of(1, x.y));
  const int k = g.dimension == 2 ? 0 : g.fold(2, g.cell_of(2, x.z));
  return g.index(i, j, k);
}

/// Up to 8 cells and weights (sum 1) of the trilinear stencil between cell centres.
struct CellStencil {
  std::int64_t cell[8];
  double weight[8];
  int n = 0;
};

namespace detail {

/// The two cells (lo, hi) and the weight t of hi along axis a for coordinate c. Periodic: wrap.
/// Wall: beyond the outermost centres the stencil clamps to the boundary cell (constant
/// extrapolation), so values are bounded and deposits stay inside. One cell: (0, 0, t = 0).
GF_HOST_DEVICE inline void axis_stencil(const fluid::Grid& g, int a, double c, int& lo, int& hi,
                                        double& t) {
  const int n = g.n[a];
  const double s = (c - g.lo[a]) / g.h[a] - 0.5;  // position in units of cells from centre 0
  if (n == 1) {
    lo = hi = 0;
    t = 0.0;
    return;
  }
  if (g.periodic[a]) {
    const double f = std::floor(s);
    t = s - f;
    const int i = static_cast<int>(f);
    lo = g.fold(a, i);
    hi = g.fold(a, i + 1);
    return;
  }
  if (s <= 0.0) {
    lo = 0, hi = 1, t = 0.0;
  } else if (s >= n - 1) {
    lo = n - 2, hi = n - 1, t = 1.0;
  } else {
    const double f = std::floor(s);
    lo = static_cast<int>(f);
    hi = lo + 1;
    t = s - f;
  }
}

}  // namespace detail

/// Trilinear stencil of point x (bilinear on 2D grids).
GF_HOST_DEVICE inline CellStencil trilinear_stencil(const fluid::Grid& g, const Vec3& x) {
  int lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  double t[3] = {0, 0, 0};
  const int dims = g.dimension == 2 ? 2 : 3;
  for (int a = 0; a < dims; ++a) detail::axis_stencil(g, a, x[a], lo[a], hi[a], t[a]);
  CellStencil s;
  const int nk = dims == 3 ? 2 : 1;
  for (int c = 0; c < nk; ++c) {
    const int k = c ? hi[2] : lo[2];
    const double wk = dims == 3 ? (c ? t[2] : 1.0 - t[2]) : 1.0;
    for (int b = 0; b < 2; ++b) {
      const int j = b ? hi[1] : lo[1];
      const double wj = b ? t[1] : 1.0 - t[1];
      for (int d = 0; d < 2; ++d) {
        const int i = d ? hi[0] : lo[0];
        const double wi = d ? t[0] : 1.0 - t[0];
        s.cell[s.n] = g.index(i, j, k);
        s.weight[s.n] = wi * wj * wk;
        ++s.n;
      }
    }
  }
  return s;
}

/// The same trilinear stencil in the form interpolation wants: the cell at the lower corner,
/// the index step to the upper cell along each axis (negative where a periodic axis wraps; 0 on
/// a one-cell axis and along z in 2D) and the fraction t of the upper cell along each axis. A
/// field is then read as nested linear interpolations (7 lerps of 8 values), with no index or
/// weight arrays to build: the coupling interpolates every grain at every fluid step.
struct LerpStencil {
  std::int64_t base = 0;
  std::int64_t step[3] = {0, 0, 0};
  double t[3] = {0, 0, 0};
};

/// Compact trilinear stencil of point x (bilinear on 2D grids); same cells and weights as
/// trilinear_stencil.
GF_HOST_DEVICE inline LerpStencil lerp_stencil(const fluid::Grid& g, const Vec3& x) {
  int lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  LerpStencil s;
  const int dims = g.dimension == 2 ? 2 : 3;
  for (int a = 0; a < dims; ++a) detail::axis_stencil(g, a, x[a], lo[a], hi[a], s.t[a]);
  const std::int64_t stride[3] = {1, g.n[0], static_cast<std::int64_t>(g.n[0]) * g.n[1]};
  s.base = g.index(lo[0], lo[1], lo[2]);
  for (int a = 0; a < 3; ++a) s.step[a] = (hi[a] - lo[a]) * stride[a];
  return s;
}

/// The stencil that reads the value of the cell containing x (piecewise-constant fields, as
/// CFDEMcoupling's drag models without `interpolation` and DPMFoam's `cell` scheme read them).
GF_HOST_DEVICE inline LerpStencil cell_value_stencil(const fluid::Grid& g, const Vec3& x) {
  LerpStencil s;
  s.base = cell_containing(g, x);
  return s;
}

/// Value of a cell-centred field (double or Vec3) at the compact stencil's point.
template <class T>
GF_HOST_DEVICE inline T interpolate(const LerpStencil& s, const T* field) {
  const T* p = field + s.base;
  const std::int64_t sx = s.step[0], sy = s.step[1], sz = s.step[2];
  const double tx = s.t[0], ty = s.t[1];
  auto lerp = [](const T& a, const T& b, double t) { return a + t * (b - a); };
  auto plane = [&](const T* q) {
    return lerp(lerp(q[0], q[sx], tx), lerp(q[sy], q[sy + sx], tx), ty);
  };
  const T lower = plane(p);
  if (sz == 0) return lower;  // 2D, or one cell along z
  return lerp(lower, plane(p + sz), s.t[2]);
}

}  // namespace gf::cfd_dem
