// SPDX-License-Identifier: GPL-3.0-or-later
// ParaView output of P2-P1 fields: .vtu with quadratic triangles and a .pvd series index.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "fluid/fem/navier_stokes.hpp"

namespace gf::fem {

/// Writes the mesh (VTK_QUADRATIC_TRIANGLE cells) with velocity [m/s] at every P2 node and
/// pressure [Pa] (P1, linearly interpolated at the edge midpoints), atomically.
void write_vtu(const std::filesystem::path& path, const NavierStokes& ns);

/// Writes a .pvd collection listing (time [s], file name relative to the .pvd) pairs.
void write_pvd(const std::filesystem::path& path,
               const std::vector<std::pair<double, std::string>>& entries);

}  // namespace gf::fem
