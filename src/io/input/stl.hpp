// SPDX-License-Identifier: GPL-3.0-or-later
// Triangle surfaces from STL files (ASCII or binary), read with CGAL's STL reader.
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "core/vec3.hpp"

namespace gf::io {

struct StlSurface {
  std::vector<Vec3> points;                   ///< distinct vertices (equal coordinates merged)
  std::vector<std::array<int, 3>> triangles;  ///< indices into points
  std::size_t dropped = 0;                    ///< degenerate triangles left out (zero area)
};

/// Reads an STL file; vertices with equal coordinates are merged, so that triangles sharing an
/// edge know it. Throws std::runtime_error with what went wrong (no such file, not STL, no
/// triangles, or only degenerate ones).
StlSurface read_stl(const std::filesystem::path& file);

}  // namespace gf::io
