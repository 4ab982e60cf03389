// SPDX-License-Identifier: GPL-3.0-or-later
// Memory a case will need, estimated from the case file before anything is allocated, against
// the machine's memory: a case that cannot fit is bad input (exit 2), not an out-of-memory kill.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "core/vec3.hpp"
#include "io/input/config.hpp"

namespace gf::input {

// Bytes per item at a run's peak, from measured peak resident set sizes (the argument and the
// numbers are in memory_budget.cpp). Rounded up: an estimate, not a bound.
/// A DEM grain with its neighbour list, by shape. Slopes of peak RSS between two sizes of a
/// case (2026-12-03): spheres 229-386 B (random / cubic / hcp fills), 2D disks 504 B,
/// spherocylinders 416 B spaced and ~370 B more once settled (contact histories), polygons
/// 1053 B (each random polygon has its own ~300 B shape-table entry of 16 vertices).
inline double bytes_per_grain(config::Shape kind) {
  switch (kind) {
    case config::Shape::Sphere:
      return 400;
    case config::Shape::Disk:
      return 550;
    case config::Shape::Spherocylinder:
      return 800;
    case config::Shape::Polygon:
      return 1100;
  }
  return 1100;
}
/// A round grain (sphere, disk) in a store that also holds shaped grains (spherocylinders,
/// polygons) carries their columns too. Slopes of peak RSS: 281 B per disk alone, 383 B beside
/// 100 polygons (20 000 to 80 000 disks in a 2D drum, 100 steps, 2026-12-05); 214-232 B per
/// sphere alone, 345-357 B beside 100 spherocylinders (20 000 to 110 000 spheres of a random fill
/// in a box, 50 steps, 2026-12-05): +102 B in 2D, +125 B in 3D: 130 B.
inline constexpr double kBytesPerRoundGrainInShapedStore = 130;
/// Heat conduction (heat:) adds per grain its temperature and the step's two sums (24 B) and the
/// conductance of each of its neighbour-list entries (8 B each, ~5-10 entries): 100 B.
inline constexpr double kBytesPerGrainHeat = 100;
inline constexpr double kBytesPerLatticeSite = 32;     ///< a lattice fill's candidate site
inline constexpr double kBytesPerNeighbourCell = 16;   ///< a cell of neighbor::CellList
inline constexpr double kBytesPerSphParticle = 800;    ///< an SPH particle (fluid or wall)
inline constexpr double kBytesPerTwoFluidCell = 4200;  ///< a two-fluid grid cell
inline constexpr double kBytesPerCfdCell = 2200;       ///< a CFD-DEM (fluid:) grid cell

/// Particles and cells are indexed by 32-bit integers in the neighbour search.
inline constexpr double kMaxIndexed = 2147483647.0;

/// The machine's physical memory, bytes (sysconf; 0 when unknown).
double physical_memory_bytes();

/// The memory a case may use, bytes: GRAINFLOW_MEMORY_LIMIT when set (a number of bytes, e.g.
/// 8e9, or with a unit: 512M, 16G, 1.5T, 16GB, 16GiB; k M G T are powers of 1000, Ki Mi Gi Ti
/// of 1024), else physical_memory_bytes() (infinite when unknown). An unreadable value of the
/// variable throws gf::InputError.
double memory_limit_bytes();

/// "350 GB", "1.2 MB", "512 B" (powers of 1000).
std::string bytes_text(double bytes);

/// Cells of the neighbour search's grid (CellList::grid) for about `particles` particles over a
/// box of edge lengths `length` with cells of edge >= `cutoff`: per axis max(1, floor(L /
/// cutoff)), at most 1024, and in all at most max(2^20, 8 particles); in 2D along z over the
/// slab a 2D run gives the grid, z in +-max(cutoff, 1 mm) (Simulation: at least 2 cells, more
/// for grains much smaller than 1 mm).
double neighbour_cells(const Vec3& length, double cutoff, int dimension, double particles);

/// Compares an estimate with memory_limit_bytes(). Above it: throws gf::InputError at `loc`,
/// "WHAT need about X of memory; this machine has Y" (or "...; GRAINFLOW_MEMORY_LIMIT is Y").
/// Above half of it: returns a warning with the same numbers. Else nothing.
std::optional<std::string> check_memory_use(const config::SourceLoc& loc, std::string_view what,
                                            double bytes);

}  // namespace gf::input
