// SPDX-License-Identifier: GPL-3.0-or-later
// ParaView output of P2-P1 fields: .vtu with quadratic triangles (appended binary data, see
// core/vtk_xml.hpp); the series index is a vtk::PvdSeries.
#pragma once

#include <filesystem>

#include "fluid/fem/navier_stokes.hpp"

namespace gf::fem {

/// Writes the mesh (VTK_QUADRATIC_TRIANGLE cells) with velocity [m/s] at every P2 node and
/// pressure (P1, linearly interpolated at the edge midpoints) at every node, atomically.
void write_vtu(const std::filesystem::path& path, const NavierStokes& ns);

}  // namespace gf::fem
