// SPDX-License-Identifier: GPL-3.0-or-later
// ASCII VTK XML writers for the fluid_fem fields (quadratic triangles, point data).
#include "fluid/fem/vtu.hpp"

#include <fmt/format.h>

#include <ostream>

#include "core/files.hpp"

namespace gf::fem {

void write_vtu(const std::filesystem::path& path, const NavierStokes& ns) {
  const Mesh& m = ns.mesh();
  std::vector<double> p(m.n_nodes(), 0.0);
  for (int v = 0; v < m.n_vertices; ++v) p[v] = ns.pressure(v);
  for (const auto& c : m.cells)
    for (int e = 0; e < 3; ++e) p[c[3 + e]] = 0.5 * (p[c[e]] + p[c[(e + 1) % 3]]);
  write_atomically(path, [&](std::ostream& os) {
    os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
          "byte_order=\"LittleEndian\">\n"
       << "<UnstructuredGrid>\n"
       << fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", m.n_nodes(),
                      m.n_cells())
       << "<PointData Vectors=\"velocity\" Scalars=\"pressure\">\n"
       << "<DataArray type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\" "
          "format=\"ascii\">\n";
    for (int k = 0; k < m.n_nodes(); ++k) {
      const Vec2 u = ns.velocity(k);
      os << fmt::format("{:.9g} {:.9g} 0\n", u.x, u.y);
    }
    os << "</DataArray>\n<DataArray type=\"Float64\" Name=\"pressure\" format=\"ascii\">\n";
    for (double v : p) os << fmt::format("{:.9g}\n", v);
    os << "</DataArray>\n</PointData>\n<Points>\n<DataArray type=\"Float64\" "
          "NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const auto& x : m.nodes) os << fmt::format("{:.12g} {:.12g} 0\n", x.x, x.y);
    os << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" "
          "format=\"ascii\">\n";
    for (const auto& c : m.cells)
      os << fmt::format("{} {} {} {} {} {}\n", c[0], c[1], c[2], c[3], c[4], c[5]);
    os << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (int c = 0; c < m.n_cells(); ++c) os << 6 * (c + 1) << '\n';
    os << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (int c = 0; c < m.n_cells(); ++c) os << "22\n";  // VTK_QUADRATIC_TRIANGLE
    os << "</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  });
}

void write_pvd(const std::filesystem::path& path,
               const std::vector<std::pair<double, std::string>>& entries) {
  write_atomically(path, [&](std::ostream& os) {
    os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n<Collection>\n";
    for (const auto& [t, f] : entries)
      os << fmt::format("<DataSet timestep=\"{:.9g}\" part=\"0\" file=\"{}\"/>\n", t, f);
    os << "</Collection>\n</VTKFile>\n";
  });
}

}  // namespace gf::fem
