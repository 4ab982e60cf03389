// SPDX-License-Identifier: GPL-3.0-or-later
// Making the grains of one particle group: size, mass, inertia, orientation and (polygons) the
// body-frame outline, for every shape of the case file.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "core/quaternion.hpp"
#include "core/rng.hpp"
#include "io/input/config.hpp"
#include "particles/particle_store.hpp"

namespace gf {

/// Builds grains of one group into a store. Sizes come from the group's radius distribution;
/// polygon outlines from its polygon block.
class ShapeBuilder {
 public:
  /// `thickness`: depth of 2D grains (m). `seed`: for random polygon outlines.
  ShapeBuilder(const config::ParticleGroup& group, double density, double thickness,
               std::uint64_t seed);

  /// Radius of a sphere that contains any grain of the group (for placement without overlap).
  double placement_radius() const { return placement_radius_; }

  /// Appends one grain; `radius` is the size drawn from the distribution (sphere, disk: radius;
  /// spherocylinder: cap radius; polygon: equal-area radius; ignored for given vertices).
  /// Returns its index.
  std::size_t add(ParticleStore& p, std::int64_t id, int material, double radius, const Vec3& x,
                  const Vec3& v, const Vec3& omega, const Quat& q);

  /// The temperature (K) of the grains `add` makes, in a store with the field "temperature"
  /// (heat conduction).
  void set_temperature(double kelvin) { temperature_ = kelvin; }
  /// The heat source (W) of the grains `add` makes, in a store with the field "heat_source".
  void set_heat_source(double watts) { heat_source_ = watts; }

  /// Uniformly random orientation: 3D uniform on SO(3) (normalised Gaussian quaternion), 2D a
  /// uniform angle about z.
  static Quat random_orientation(Rng& rng, bool two_d);

 private:
  std::size_t add_body(ParticleStore& p, std::int64_t id, int material, double radius,
                       const Vec3& x, const Vec3& v, const Vec3& omega, const Quat& q);
  /// Adds the polygon outline (equal-area radius `radius`) to the table; returns its index.
  std::int32_t make_polygon(ParticleStore& p, double radius);

  const config::ParticleGroup& g_;
  double density_, thickness_;
  double placement_radius_ = 0;
  double circum_factor_ = 1;          ///< polygon circumradius / equal-area radius (bound)
  std::int32_t shared_polygon_ = -1;  ///< table entry shared by all grains, when there is one
  std::mt19937_64 poly_rng_;
  double temperature_ = 0, heat_source_ = 0;
};

}  // namespace gf
