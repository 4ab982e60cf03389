// SPDX-License-Identifier: GPL-3.0-or-later
// Filling a region with spheres: cubic / hcp lattices, or random loose packing by sequential
// insertion without overlaps; radii fixed or drawn from a truncated distribution.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/rng.hpp"
#include "core/vec3.hpp"

namespace gf {

struct RadiusDistribution {
  enum class Kind { Fixed, Uniform, Normal, Lognormal };
  Kind kind = Kind::Fixed;
  double value = 0;          ///< Fixed, m
  double min = 0, max = 0;   ///< bounds / truncation, m
  double mean = 0, std = 0;  ///< of the radius, m (Normal, Lognormal)
  double largest() const { return kind == Kind::Fixed ? value : max; }
  /// One radius; truncated distributions are sampled by rejection.
  double sample(Rng& rng) const;
};

struct FillRegion {
  enum class Kind { Box, Cylinder };
  Kind kind = Kind::Box;
  Vec3 min, max;  ///< box, m
  Vec3 center, axis{0, 0, 1};
  double radius = 0, height = 0;  ///< cylinder (2D: a circle, height 0), m
  /// Whether a sphere of radius r lies entirely inside the region (2D: a disk, z ignored).
  bool contains(const Vec3& p, double r, bool two_d = false) const;
  /// Axis-aligned bounds.
  void bounds(Vec3& lo, Vec3& hi) const;
};

struct FillSpec {
  FillRegion region;
  enum class Lattice { Cubic, Hcp, Random };
  Lattice lattice = Lattice::Cubic;
  std::optional<double> spacing;      ///< m; default 2 r_max * 1.01
  std::optional<std::int64_t> count;  ///< cap (lattice) or target (random)
  std::int64_t max_attempts = 0;      ///< random insertion attempts; 0 = 1000 * count
  /// Lattices: half extents of a grain along x, y, z (an oriented elongated grain's bounding
  /// box); default the largest radius along every axis. A cubic lattice without `spacing` then
  /// spaces sites by 2 extent x 1.01 along each axis, so aligned rods pack tightly.
  std::optional<Vec3> extent;
  /// Lattices: take `count` sites at random among all sites of the region (uniform density)
  /// instead of the first ones.
  bool pick_random = false;
  /// 2D: grains in the plane z = 0 (the box's z range is ignored; cubic gives a square lattice,
  /// hcp a triangular one, random insertion in the plane). A cylinder region is then the circle
  /// of its radius about its centre (axis and height are not used).
  bool two_d = false;
};

struct FilledSphere {
  Vec3 x;
  double r;
};

/// Generates the spheres of one fill. `existing` spheres (already placed) are avoided by the
/// random insertion. Throws gf::InputError if a random fill cannot reach its count.
std::vector<FilledSphere> generate_fill(const FillSpec& spec, const RadiusDistribution& radius,
                                        Rng& rng, const std::vector<FilledSphere>& existing = {});

}  // namespace gf
