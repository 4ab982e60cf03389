// SPDX-License-Identifier: GPL-3.0-or-later
// Uniform Cartesian grid of the finite-volume fluid solver (2D or 3D): cell indexing and
// geometry. Shared by the fluid solver (src/fluid/fv) and the particle-fluid mapping
// (src/coupling/cfd_dem); it knows nothing about particles.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "core/host_device.hpp"
#include "core/vec3.hpp"

namespace gf::fluid {

/// Cells are boxes of size h[a] (uniform per axis) starting at `lo`. In 2D the grid has one
/// layer of cells along z (n[2] = 1) and h[2] is the depth used for cell volumes.
struct Grid {
  int dimension = 3;              ///< 2 or 3
  std::array<int, 3> n{1, 1, 1};  ///< cells per axis
  Vec3 lo{};                      ///< lower corner
  Vec3 h{1, 1, 1};                ///< cell size per axis
  std::array<bool, 3> periodic{false, false, false};

  GF_HOST_DEVICE std::int64_t cell_count() const {
    return static_cast<std::int64_t>(n[0]) * n[1] * n[2];
  }
  /// Linear index of cell (i, j, k), x fastest.
  GF_HOST_DEVICE std::int64_t index(int i, int j, int k) const {
    return (static_cast<std::int64_t>(k) * n[1] + j) * n[0] + i;
  }
  /// Cell (i, j, k) of linear index c (the inverse of index).
  GF_HOST_DEVICE std::array<int, 3> cell_coords(std::int64_t c) const {
    return {static_cast<int>(c % n[0]), static_cast<int>((c / n[0]) % n[1]),
            static_cast<int>(c / (static_cast<std::int64_t>(n[0]) * n[1]))};
  }
  GF_HOST_DEVICE Vec3 hi() const {
    return {lo.x + n[0] * h.x, lo.y + n[1] * h.y, lo.z + n[2] * h.z};
  }
  GF_HOST_DEVICE double cell_volume() const { return h.x * h.y * h.z; }
  GF_HOST_DEVICE Vec3 cell_center(int i, int j, int k) const {
    return {lo.x + (i + 0.5) * h.x, lo.y + (j + 0.5) * h.y, lo.z + (k + 0.5) * h.z};
  }
  /// Cell index along axis a of coordinate c (may lie outside [0, n[a]) for points outside).
  GF_HOST_DEVICE int cell_of(int a, double c) const {
    return static_cast<int>(std::floor((c - lo[a]) / h[a]));
  }
  /// Cell index along axis a brought into [0, n[a]): wrapped when periodic, clamped otherwise.
  GF_HOST_DEVICE int fold(int a, int c) const {
    if (periodic[a]) {
      c %= n[a];
      return c < 0 ? c + n[a] : c;
    }
    return c < 0 ? 0 : (c >= n[a] ? n[a] - 1 : c);
  }

  // Faces of the staggered (MAC) grid. Faces normal to axis a carry the velocity component a;
  // along a there are n[a] + 1 of them (face i is the lower face of cell i), also on a
  // periodic axis, where face n[a] is the image of face 0 and holds the same value.

  /// Cells along each axis of the face array normal to axis a (n with n[a] + 1).
  GF_HOST_DEVICE std::array<int, 3> face_dims(int a) const {
    std::array<int, 3> d = n;
    d[a] += 1;
    return d;
  }
  /// Number of faces normal to axis a.
  GF_HOST_DEVICE std::int64_t face_count(int a) const {
    const std::array<int, 3> d = face_dims(a);
    return static_cast<std::int64_t>(d[0]) * d[1] * d[2];
  }
  /// Linear index of the face normal to axis a at (i, j, k), x fastest; i, j, k count faces
  /// along a and cells along the other axes.
  GF_HOST_DEVICE std::int64_t face_index(int a, int i, int j, int k) const {
    const std::array<int, 3> d = face_dims(a);
    return (static_cast<std::int64_t>(k) * d[1] + j) * d[0] + i;
  }
  /// Centre of the face normal to axis a at (i, j, k) [m].
  GF_HOST_DEVICE Vec3 face_center(int a, int i, int j, int k) const {
    Vec3 c = cell_center(i, j, k);
    c[a] -= 0.5 * h[a];
    return c;
  }
};

}  // namespace gf::fluid
