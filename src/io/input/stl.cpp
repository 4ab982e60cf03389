// SPDX-License-Identifier: GPL-3.0-or-later
// STL reading through CGAL::IO::read_STL (it detects ASCII or binary and merges equal vertices).
#include "io/input/stl.hpp"

#include <CGAL/IO/STL.h>
#include <CGAL/Simple_cartesian.h>
#include <fmt/format.h>

#include <cmath>
#include <fstream>

namespace gf::io {

StlSurface read_stl(const std::filesystem::path& file) {
  namespace fs = std::filesystem;
  if (!fs::exists(file)) throw std::runtime_error("no such file");
  if (!fs::is_regular_file(file)) throw std::runtime_error("not a regular file");
  if (!std::ifstream(file, std::ios::binary))
    throw std::runtime_error("the file cannot be opened for reading");
  using Point = CGAL::Simple_cartesian<double>::Point_3;
  std::vector<Point> points;
  std::vector<std::array<std::size_t, 3>> tris;
  if (!CGAL::IO::read_STL(file.string(), points, tris))
    throw std::runtime_error(
        "not a readable STL file (ASCII 'solid ... facet normal ... outer loop / vertex x y z' "
        "or binary: 80-byte header, triangle count, 50 bytes per triangle)");
  if (tris.empty()) throw std::runtime_error("the file has no triangles");
  StlSurface s;
  s.points.reserve(points.size());
  for (const auto& p : points) {
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
      throw std::runtime_error(
          fmt::format("a vertex has a non-finite coordinate ({}, {}, {})", p.x(), p.y(), p.z()));
    s.points.push_back({p.x(), p.y(), p.z()});
  }
  for (const auto& t : tris) {
    const Vec3 &a = s.points[t[0]], &b = s.points[t[1]], &c = s.points[t[2]];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || !(norm(cross(b - a, c - a)) > 0)) {
      ++s.dropped;
      continue;
    }
    s.triangles.push_back({static_cast<int>(t[0]), static_cast<int>(t[1]), static_cast<int>(t[2])});
  }
  if (s.triangles.empty())
    throw std::runtime_error(fmt::format("all {} triangles are degenerate (zero area)", s.dropped));
  // Vertices of dropped triangles only are left out too.
  std::vector<int> renumber(s.points.size(), -1);
  std::vector<Vec3> used;
  for (auto& t : s.triangles)
    for (int& v : t) {
      auto& r = renumber[static_cast<std::size_t>(v)];
      if (r < 0) {
        r = static_cast<int>(used.size());
        used.push_back(s.points[static_cast<std::size_t>(v)]);
      }
      v = r;
    }
  s.points = std::move(used);
  return s;
}

}  // namespace gf::io
