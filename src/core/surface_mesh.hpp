// SPDX-License-Identifier: GPL-3.0-or-later
// A triangle surface (walls, meshes) in world coordinates, for output and geometry queries.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/vec3.hpp"

namespace gf {

struct SurfaceMesh {
  std::string name;
  std::vector<Vec3> points;                   ///< m
  std::vector<std::array<int, 3>> triangles;  ///< indices into points
};

}  // namespace gf
