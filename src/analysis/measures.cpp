// SPDX-License-Identifier: GPL-3.0-or-later
// Energies and heights by deterministic reductions.
#include "analysis/measures.hpp"

#include <algorithm>
#include <limits>

namespace gf::analysis {

EnergyHeights energy_and_heights(const ParticleStore& p, const Vec3& gravity, int up_axis) {
  EnergyHeights e;
  const std::size_t n = p.size();
  if (n == 0) return e;
  const Vec3* x = p.x();
  const Vec3* v = p.v();
  const Vec3* w = p.omega();
  const double* m = p.mass();
  const double* in = p.inertia();
  const std::int32_t* shape = p.has_shapes() ? p.shape() : nullptr;
  const Vec3* L = p.has_shapes() ? p.angular_momentum() : nullptr;
  double zmax = -std::numeric_limits<double>::infinity(), zsum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    e.kinetic_translational += 0.5 * m[i] * norm2(v[i]);
    if (shape && static_cast<ShapeCode>(shape[i]) == ShapeCode::Spherocylinder)
      e.kinetic_rotational += 0.5 * dot(w[i], L[i]);
    else
      e.kinetic_rotational += 0.5 * in[i] * norm2(w[i]);
    e.potential -= m[i] * dot(gravity, x[i]);
    zmax = std::max(zmax, x[i][up_axis]);
    zsum += x[i][up_axis];
  }
  e.max_z = zmax;
  e.mean_z = zsum / static_cast<double>(n);
  return e;
}

}  // namespace gf::analysis
