// SPDX-License-Identifier: GPL-3.0-or-later
// The geometry of a wall's surface that the host's and the device's wall loops share (planes and
// cylinders; triangle meshes live in boundaries/triangle_mesh).
#pragma once

#include <cmath>
#include <cstdint>

#include "core/host_device.hpp"
#include "core/vec3.hpp"

namespace gf {

enum class WallKind : std::int32_t { Plane, Cylinder, Mesh };

/// Gap between a sphere (centre x, radius r) and a plane (through `point`, unit normal `dir`
/// towards the grains) or a cylinder (axis through `point` along unit `dir`, `radius`, the
/// grains inside or outside), negative = overlap; n: the unit normal from the surface to the
/// centre. Shared by the host's wall loops (Wall::gap) and the device's (gpu/kernels.hpp), so
/// both take the same bits.
GF_HOST_DEVICE inline double surface_gap(WallKind kind, const Vec3& point, const Vec3& dir,
                                         double radius, bool inside, const Vec3& x, double r,
                                         Vec3& n) {
  if (kind == WallKind::Plane) {
    n = dir;
    return dot(x - point, dir) - r;
  }
  const Vec3 d = x - point;
  Vec3 radial = d - dot(d, dir) * dir;
  const double rho = norm(radial);
  if (rho > 0)
    radial = radial / rho;
  else
    radial = std::abs(dir.x) < 0.9 ? normalized(cross(dir, Vec3{1, 0, 0}))
                                   : normalized(cross(dir, Vec3{0, 1, 0}));
  if (inside) {
    n = -radial;
    return radius - rho - r;
  }
  n = radial;
  return rho - radius - r;
}

}  // namespace gf
