// SPDX-License-Identifier: GPL-3.0-or-later
// Energies and heights by deterministic reductions.
#include "analysis/measures.hpp"

#include <algorithm>
#include <limits>

namespace gf::analysis {

EnergyHeights energy_and_heights(const ParticleStore& p, const Vec3& gravity) {
  EnergyHeights e;
  const std::size_t n = p.size();
  if (n == 0) return e;
  const Vec3* x = p.x();
  const Vec3* v = p.v();
  const Vec3* w = p.omega();
  const double* m = p.mass();
  const double* in = p.inertia();
  double zmax = -std::numeric_limits<double>::infinity(), zsum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    e.kinetic_translational += 0.5 * m[i] * norm2(v[i]);
    e.kinetic_rotational += 0.5 * in[i] * norm2(w[i]);
    e.potential -= m[i] * dot(gravity, x[i]);
    zmax = std::max(zmax, x[i].z);
    zsum += x[i].z;
  }
  e.max_z = zmax;
  e.mean_z = zsum / static_cast<double>(n);
  return e;
}

}  // namespace gf::analysis
