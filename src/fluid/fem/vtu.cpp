// SPDX-License-Identifier: GPL-3.0-or-later
// VTK XML unstructured grid of the fluid_fem fields (quadratic triangles, point data), binary.
#include "fluid/fem/vtu.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <ostream>

#include "core/files.hpp"
#include "core/vtk_xml.hpp"

namespace gf::fem {

void write_vtu(const std::filesystem::path& path, const NavierStokes& ns) {
  const Mesh& m = ns.mesh();
  const auto n_nodes = static_cast<std::size_t>(m.n_nodes());
  const auto n_cells = static_cast<std::size_t>(m.n_cells());
  std::vector<double> p(n_nodes, 0.0), velocity(3 * n_nodes, 0.0), points(3 * n_nodes, 0.0);
  for (int v = 0; v < m.n_vertices; ++v) p[v] = ns.pressure(v);
  for (const auto& c : m.cells)
    for (int e = 0; e < 3; ++e) p[c[3 + e]] = 0.5 * (p[c[e]] + p[c[(e + 1) % 3]]);
  for (std::size_t k = 0; k < n_nodes; ++k) {
    const Vec2 u = ns.velocity(static_cast<int>(k));
    velocity[3 * k] = u.x;
    velocity[3 * k + 1] = u.y;
    points[3 * k] = m.nodes[k].x;
    points[3 * k + 1] = m.nodes[k].y;
  }
  std::vector<std::int64_t> conn(6 * n_cells), offsets(n_cells);
  for (std::size_t c = 0; c < n_cells; ++c) {
    for (int j = 0; j < 6; ++j) conn[6 * c + j] = m.cells[c][j];
    offsets[c] = static_cast<std::int64_t>(6 * (c + 1));
  }
  std::vector<std::uint8_t> types(n_cells, 22);  // VTK_QUADRATIC_TRIANGLE

  // Tags are built in block order: one statement per array.
  vtk::AppendedArrays arrays;
  auto add = [&arrays](const char* name, int n_components, auto values) {
    return vtk::AppendedArrays::tag(arrays.add_owned(name, n_components, std::move(values)));
  };
  const std::string velocity_tag = add("velocity", 3, std::move(velocity));
  const std::string pressure_tag = add("pressure", 1, std::move(p));
  const std::string points_tag = add("position", 3, std::move(points));
  const std::string conn_tag = add("connectivity", 1, std::move(conn));
  const std::string offsets_tag = add("offsets", 1, std::move(offsets));
  const std::string types_tag = add("types", 1, std::move(types));
  std::string xml = vtk::file_open("UnstructuredGrid");
  xml += "  <UnstructuredGrid>\n";
  xml += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", n_nodes, n_cells);
  xml += "      <PointData Vectors=\"velocity\" Scalars=\"pressure\">\n        " + velocity_tag +
         "\n        " + pressure_tag + "\n      </PointData>\n";
  xml += "      <Points>\n        " + points_tag + "\n      </Points>\n";
  xml += "      <Cells>\n        " + conn_tag + "\n        " + offsets_tag + "\n        " +
         types_tag + "\n      </Cells>\n";
  xml += "    </Piece>\n  </UnstructuredGrid>\n";
  write_atomically(path, [&](std::ostream& out) {
    out << xml;
    arrays.write_appended(out);
    out << "</VTKFile>\n";
  });
}

}  // namespace gf::fem
