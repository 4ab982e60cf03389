// SPDX-License-Identifier: GPL-3.0-or-later
// How well two kinds of grains are mixed: the Lacey mixing index over a grid of cells.
//
// Lacey (1954), as used for DEM mixers and drums: with p the fraction of kind A among the grains
// counted and c_j the fraction in cell j (n_j grains), the variance of the cells' fractions
// weighted by their grains, s^2 = sum_j n_j (c_j - p)^2 / sum_j n_j, lies between that of the
// fully segregated state, s0^2 = p (1 - p) (every cell pure), and that of a random mixture,
// sr^2 = p (1 - p) / n (binomial sampling of n grains a cell, n the mean over the cells counted).
// The index M = (s0^2 - s^2) / (s0^2 - sr^2) is 0 segregated and 1 randomly mixed (it scatters
// about 1 for a random mixture, by the sampling of s^2). Fractions by number; cells with fewer
// than `min_grains` grains (the surface, the walls) are left out.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/vec3.hpp"

namespace gf::analysis {

struct LaceyIndex {
  double index = 0;       ///< M; 0 when undefined (no cell counted, or one kind only)
  double fraction = 0;    ///< p, of kind A among the grains in the cells counted
  double variance = 0;    ///< s^2
  double segregated = 0;  ///< s0^2
  double random = 0;      ///< sr^2
  std::size_t cells = 0;  ///< cells counted
  double per_cell = 0;    ///< mean grains per cell counted
};

/// The Lacey index of the grains at x[0..n) whose kind[i] is 0 (A) or 1 (B); kind -1 grains are
/// not counted. Cells are cubes (2D: squares in x, y) of side `cell` from `lo`; grains outside
/// [lo, lo + cells x cell) are clamped into the outer cells.
LaceyIndex lacey_index(const Vec3* x, const std::int32_t* kind, std::size_t n, const Vec3& lo,
                       const Vec3& hi, double cell, int dimension, int min_grains);

}  // namespace gf::analysis
