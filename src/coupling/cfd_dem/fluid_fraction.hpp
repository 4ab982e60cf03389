// SPDX-License-Identifier: GPL-3.0-or-later
// Fluid (void) fraction per cell from the particles: eps_c = 1 - V_solid,c / V_cell, with the
// solid volume deposited by one of the schemes of mapping.hpp (centre-in-cell, divided,
// trilinear or smoothed). Volume is conserved before clamping:
// sum_c (1 - eps_c) V_cell = sum_p V_p.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "coupling/cfd_dem/mapping.hpp"
#include "fluid/fv/grid.hpp"

namespace gf::cfd_dem {

struct FluidFractionOptions {
  DepositScheme scheme = DepositScheme::Divided;
  /// Lower bound of eps: a cell whose deposited solid volume would leave less fluid is clamped
  /// (random close packing is eps ~ 0.36; lower values are deposition artefacts of cells not
  /// much larger than grains, and the drag laws are not fitted there). In (0, 1].
  double min_fraction = 0.3;
};

struct FluidFractionStats {
  std::int64_t n_clamped = 0;  ///< cells raised to min_fraction
  double min_unclamped = 1.0;  ///< smallest eps before clamping
  double solid_volume = 0.0;   ///< sum over cells of the deposited solid volume, m^3
};

/// solid[c] += solid volume of the particles in cell c (m^3; adds, the caller zeroes).
void deposit_solid_volume(const fluid::Grid& g, const ParticleGeometry& p, DepositScheme scheme,
                          std::span<double> solid, DepositScratch* scratch = nullptr);

/// The same with footprints built by compute_footprints (which keep the volumes).
void deposit_solid_volume(const Footprints& fp, std::span<double> solid);

/// eps[c] = max(1 - solid[c] / V_cell, min_fraction); returns the clamp count. eps may alias
/// solid (converted in place).
FluidFractionStats fluid_fraction_from_solid(const fluid::Grid& g, std::span<const double> solid,
                                             double min_fraction, std::span<double> eps);

/// The fluid fraction of every cell (overwrites eps, g.cell_count() entries).
FluidFractionStats fluid_fraction(const fluid::Grid& g, const ParticleGeometry& p,
                                  const FluidFractionOptions& options, std::span<double> eps,
                                  DepositScratch* scratch = nullptr);
/// The same with footprints built on g by compute_footprints.
FluidFractionStats fluid_fraction(const fluid::Grid& g, const Footprints& fp, double min_fraction,
                                  std::span<double> eps);

/// d eps/dt per cell from the grains' velocities v (one per particle of fp): the solid volume
/// flux density q_c = sum_p w_pc V_p v_p / V_cell (m/s), deposited with the footprints fp,
/// averaged onto the faces between cells (zero on walls, wrapped across periodic faces), and
/// rate_c = div q (1/s), from the solid continuity d(1 - eps)/dt + div((1 - eps) v) = 0. Unlike
/// the change of the deposited eps, which moves in steps as sample points cross faces, it is
/// smooth in time; it sums to zero over the box (to round-off). rate has g.cell_count()
/// entries; scratch keeps its buffers between calls (no allocation once sized).
struct SolidFluxScratch {
  std::vector<Vec3> volume_velocity;  ///< V_p v_p per particle, m^4/s
  std::vector<Vec3> flux;             ///< q per cell, m/s
};
void fluid_fraction_rate_from_flux(const fluid::Grid& g, const Footprints& fp,
                                   std::span<const Vec3> v, std::span<double> rate,
                                   SolidFluxScratch& scratch);

}  // namespace gf::cfd_dem
