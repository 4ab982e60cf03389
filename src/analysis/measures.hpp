// SPDX-License-Identifier: GPL-3.0-or-later
// Scalar measurements of the particle state for the series output (energies, heights, contacts).
#pragma once

#include <cstdint>

#include "core/vec3.hpp"
#include "particles/particle_store.hpp"

namespace gf::analysis {

struct EnergyHeights {
  double kinetic_translational = 0;  ///< J, sum of m v^2 / 2
  double kinetic_rotational = 0;     ///< J, sum of I w^2 / 2 (spherocylinders: w . L / 2)
  double potential = 0;              ///< J, -sum m g.x (zero at the origin)
  double max_z = 0;                  ///< m, largest centre height (along `up_axis`)
  double mean_z = 0;                 ///< m
};

/// Energies and heights; heights are the coordinate `up_axis` (2 = z in 3D, 1 = y in 2D).
EnergyHeights energy_and_heights(const ParticleStore& p, const Vec3& gravity, int up_axis = 2);

/// Mean number of contacts per particle, 2 C / N (particle-particle contacts only).
inline double coordination_number(std::int64_t n_contacts, std::size_t n_particles) {
  return n_particles ? 2.0 * static_cast<double>(n_contacts) / static_cast<double>(n_particles)
                     : 0.0;
}

}  // namespace gf::analysis
