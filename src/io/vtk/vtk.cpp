// SPDX-License-Identifier: GPL-3.0-or-later
// VTK XML PolyData writers of particles, polygons and walls (appended raw binary data).
#include "io/vtk/vtk.hpp"

#include <fmt/format.h>

#include <cstddef>
#include <cstdint>
#include <ostream>

#include "core/error.hpp"
#include "core/files.hpp"
#include "core/vtk_xml.hpp"

namespace gf::io {

namespace {

static_assert(sizeof(Quat) == 4 * sizeof(double) && offsetof(Quat, w) == 0,
              "Quat must be four packed doubles w, x, y, z");

using vtk::AppendedArrays;

/// Vertex cells 0..n-1 (connectivity and end offsets).
void add_vertex_cells(AppendedArrays& arrays, std::size_t n, std::string& xml) {
  std::vector<std::int64_t> conn(n), offsets(n);
  for (std::size_t i = 0; i < n; ++i) {
    conn[i] = static_cast<std::int64_t>(i);
    offsets[i] = static_cast<std::int64_t>(i + 1);
  }
  // One statement per array: blocks are laid out in the order they are added.
  const std::string conn_tag =
      AppendedArrays::tag(arrays.add_owned("connectivity", 1, std::move(conn)));
  const std::string offsets_tag =
      AppendedArrays::tag(arrays.add_owned("offsets", 1, std::move(offsets)));
  xml += "      <Verts>\n        " + conn_tag + "\n        " + offsets_tag + "\n      </Verts>\n";
}

/// The glyph arrays of a store with shapes (see write_particles_vtp), as point data.
void add_glyph_arrays(AppendedArrays& arrays, const ParticleStore& store, std::string& point_data) {
  const std::size_t n = store.size();
  std::vector<double> axis(3 * n), length(n), cap_radius(n), cylinder_scale(3 * n),
      cap_offset(3 * n);
  const std::int32_t* shape = store.shape();
  const double* half_length = store.half_length();
  const Quat* q = store.orientation();
  const double* radius = store.radius();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 a = shape_axis(shape[i], q[i]);
    const double h = half_length[i];
    const double rc =
        shape[i] == static_cast<std::int32_t>(ShapeCode::Polygon) ? 0.0 : radius[i] - h;
    const Vec3 off = h * a;
    length[i] = 2 * radius[i];
    cap_radius[i] = rc;
    for (int k = 0; k < 3; ++k) {
      axis[3 * i + k] = a[k];
      cap_offset[3 * i + k] = off[k];
      cylinder_scale[3 * i + k] = k == 0 ? 2 * h : 2 * rc;
    }
  }
  // One statement per array: blocks are laid out in the order they are added.
  point_data +=
      "        " + AppendedArrays::tag(arrays.add_owned("axis", 3, std::move(axis))) + "\n";
  point_data +=
      "        " + AppendedArrays::tag(arrays.add_owned("length", 1, std::move(length))) + "\n";
  point_data += "        " +
                AppendedArrays::tag(arrays.add_owned("cap_radius", 1, std::move(cap_radius))) +
                "\n";
  point_data +=
      "        " +
      AppendedArrays::tag(arrays.add_owned("cylinder_scale", 3, std::move(cylinder_scale))) + "\n";
  point_data += "        " +
                AppendedArrays::tag(arrays.add_owned("cap_offset", 3, std::move(cap_offset))) +
                "\n";
}

}  // namespace

void write_particles_vtp(const std::filesystem::path& path, const ParticleStore& store) {
  const std::size_t n = store.size();
  AppendedArrays arrays;
  const auto& fields = store.fields();

  std::string point_data;
  bool has_radius = false, has_velocity = false;
  for (std::size_t f = 0; f < fields.size(); ++f) {
    const FieldInfo& fi = fields[f];
    if (!(fi.flags & kOutput) || static_cast<int>(f) == ParticleStore::kPosition) continue;
    has_radius |= fi.name == "radius";
    has_velocity |= fi.name == "velocity";
    const auto& a = std::visit(
        [&](const auto& col) -> const AppendedArrays::Array& {
          using T = typename std::decay_t<decltype(col)>::value_type;
          if constexpr (std::is_same_v<T, Vec3>)
            return arrays.add(fi.name, std::span<const Vec3>(col));
          else if constexpr (std::is_same_v<T, Quat>)  // w, x, y, z (no member access on an
            return arrays.add(                         // empty column's null data())
                fi.name, 4,
                std::span<const double>(reinterpret_cast<const double*>(col.data()),
                                        4 * col.size()));
          else
            return arrays.add(fi.name, 1, std::span<const T>(col));
        },
        store.column(static_cast<int>(f)));
    point_data += "        " + AppendedArrays::tag(a) + "\n";
  }
  std::vector<double> speed(n);
  for (std::size_t i = 0; i < n; ++i) speed[i] = norm(store.v()[i]);
  const std::string speed_tag = AppendedArrays::tag(arrays.add_owned("speed", 1, std::move(speed)));
  point_data += "        " + speed_tag + "\n";
  if (store.has_shapes()) add_glyph_arrays(arrays, store, point_data);

  std::string attrs;
  if (has_radius) attrs += " Scalars=\"radius\"";
  if (has_velocity) attrs += " Vectors=\"velocity\"";
  write_points_vtp(path, arrays, attrs, point_data, std::span<const Vec3>(store.x(), n));
}

void write_points_vtp(const std::filesystem::path& path, vtk::AppendedArrays& arrays,
                      const std::string& point_attrs, const std::string& point_data,
                      std::span<const Vec3> points) {
  const std::size_t n = points.size();
  std::string xml = vtk::file_open("PolyData");
  xml += "  <PolyData>\n";
  xml += fmt::format(
      "    <Piece NumberOfPoints=\"{0}\" NumberOfVerts=\"{0}\" NumberOfLines=\"0\" "
      "NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n",
      n);
  xml += "      <PointData" + point_attrs + ">\n" + point_data + "      </PointData>\n";
  const std::string points_tag = AppendedArrays::tag(arrays.add("position", points));
  xml += "      <Points>\n        " + points_tag + "\n      </Points>\n";
  add_vertex_cells(arrays, n, xml);
  xml += "    </Piece>\n  </PolyData>\n";
  write_atomically(path, [&](std::ostream& out) {
    out << xml;
    arrays.write_appended(out);
    out << "</VTKFile>\n";
  });
}

std::size_t count_polygon_grains(const ParticleStore& store) {
  if (!store.has_shapes()) return 0;
  std::size_t count = 0;
  const std::int32_t* shape = store.shape();
  for (std::size_t i = 0; i < store.size(); ++i)
    count += shape[i] == static_cast<std::int32_t>(ShapeCode::Polygon);
  return count;
}

namespace {

enum class CellKind { Polys, Lines };

/// Writes a PolyData file of polygon or line cells. `cell_data` holds the tags of the cell arrays
/// already added to `arrays`, `cell_attrs` the CellData attributes (active scalars/vectors); the
/// points, connectivity and offsets are added after them (blocks are laid out in that order).
void write_cells_file(const std::filesystem::path& path, AppendedArrays& arrays, CellKind kind,
                      const std::string& cell_attrs, const std::string& cell_data,
                      std::span<const Vec3> points, std::vector<std::int64_t> conn,
                      std::vector<std::int64_t> offsets) {
  const bool lines = kind == CellKind::Lines;
  const char* section = lines ? "Lines" : "Polys";
  std::string xml = vtk::file_open("PolyData");
  xml += "  <PolyData>\n";
  xml += fmt::format(
      "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"{}\" "
      "NumberOfStrips=\"0\" NumberOfPolys=\"{}\">\n",
      points.size(), lines ? offsets.size() : 0, lines ? 0 : offsets.size());
  const std::string points_tag = AppendedArrays::tag(arrays.add("position", points));
  const std::string conn_tag =
      AppendedArrays::tag(arrays.add_owned("connectivity", 1, std::move(conn)));
  const std::string offsets_tag =
      AppendedArrays::tag(arrays.add_owned("offsets", 1, std::move(offsets)));
  xml += "      <CellData " + cell_attrs + ">\n" + cell_data + "      </CellData>\n";
  xml += "      <Points>\n        " + points_tag + "\n      </Points>\n";
  xml += fmt::format("      <{0}>\n        {1}\n        {2}\n      </{0}>\n", section, conn_tag,
                     offsets_tag);
  xml += "    </Piece>\n  </PolyData>\n";
  write_atomically(path, [&](std::ostream& out) {
    out << xml;
    arrays.write_appended(out);
    out << "</VTKFile>\n";
  });
}

}  // namespace

void write_polygons_vtp(const std::filesystem::path& path, const ParticleStore& store) {
  const std::size_t n_cells = count_polygon_grains(store);
  std::vector<Vec3> points;
  std::vector<std::int64_t> conn, offsets, id;
  std::vector<std::int32_t> material;
  std::vector<Vec3> velocity, angular_velocity;
  std::vector<double> speed, area;
  offsets.reserve(n_cells);
  id.reserve(n_cells);
  material.reserve(n_cells);
  velocity.reserve(n_cells);
  angular_velocity.reserve(n_cells);
  speed.reserve(n_cells);
  area.reserve(n_cells);
  const auto& table = store.polygons();
  for (std::size_t i = 0; i < store.size() && n_cells > 0; ++i) {
    if (store.shape()[i] != static_cast<std::int32_t>(ShapeCode::Polygon)) continue;
    const std::int32_t k = store.polygon()[i];
    REQUIRE(k >= 0 && static_cast<std::size_t>(k) < table.size(),
            "'{}': polygon grain {} (id {}) refers to polygon {} of a table of {}", path.string(),
            i, store.id()[i], k, table.size());
    const ConvexPolygon& body = table[static_cast<std::size_t>(k)].body;
    REQUIRE(body.n >= 3 && body.n <= kMaxPolygonVertices,
            "'{}': polygon {} (grain id {}) has {} vertices, expected 3 to {}", path.string(), k,
            store.id()[i], body.n, kMaxPolygonVertices);
    const Vec3 x = store.x()[i];
    const Quat q = store.orientation()[i];
    for (int j = 0; j < body.n; ++j) {
      conn.push_back(static_cast<std::int64_t>(points.size()));
      points.push_back(x + rotate(q, Vec3{body.v[j].x, body.v[j].y, 0.0}));
    }
    offsets.push_back(static_cast<std::int64_t>(conn.size()));
    id.push_back(store.id()[i]);
    material.push_back(store.material()[i]);
    velocity.push_back(store.v()[i]);
    angular_velocity.push_back(store.omega()[i]);
    speed.push_back(norm(store.v()[i]));
    area.push_back(table[static_cast<std::size_t>(k)].area);
  }

  AppendedArrays arrays;
  std::string cell_data;
  cell_data += "        " + AppendedArrays::tag(arrays.add_owned("id", 1, std::move(id))) + "\n";
  cell_data +=
      "        " + AppendedArrays::tag(arrays.add_owned("material", 1, std::move(material))) + "\n";
  cell_data += "        " +
               AppendedArrays::tag(arrays.add("velocity", std::span<const Vec3>(velocity))) + "\n";
  cell_data +=
      "        " +
      AppendedArrays::tag(arrays.add("angular_velocity", std::span<const Vec3>(angular_velocity))) +
      "\n";
  cell_data +=
      "        " + AppendedArrays::tag(arrays.add_owned("speed", 1, std::move(speed))) + "\n";
  cell_data +=
      "        " + AppendedArrays::tag(arrays.add_owned("area", 1, std::move(area))) + "\n";
  write_cells_file(path, arrays, CellKind::Polys, "Scalars=\"speed\" Vectors=\"velocity\"",
                   cell_data, points, std::move(conn), std::move(offsets));
}

void write_surfaces_vtp(const std::filesystem::path& path, std::span<const SurfaceMesh> meshes,
                        std::span<const Vec3> force_per_mesh) {
  REQUIRE(force_per_mesh.size() == meshes.size(), "{} wall forces given for {} wall meshes",
          force_per_mesh.size(), meshes.size());
  std::vector<Vec3> points;
  std::vector<std::int64_t> conn, offsets;
  std::vector<std::int32_t> wall_id;
  std::vector<Vec3> force;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const SurfaceMesh& mesh = meshes[m];
    const auto base = static_cast<std::int64_t>(points.size());
    const auto n_points = static_cast<int>(mesh.points.size());
    points.insert(points.end(), mesh.points.begin(), mesh.points.end());
    for (const auto& tri : mesh.triangles) {
      for (int k : tri) {
        REQUIRE(k >= 0 && k < n_points, "wall '{}': triangle vertex {} outside [0, {})", mesh.name,
                k, n_points);
        conn.push_back(base + k);
      }
      offsets.push_back(static_cast<std::int64_t>(conn.size()));
      wall_id.push_back(static_cast<std::int32_t>(m));
      force.push_back(force_per_mesh[m]);
    }
  }
  AppendedArrays arrays;
  // One statement per array: blocks are laid out in the order they are added.
  std::string cell_data =
      "        " + AppendedArrays::tag(arrays.add_owned("wall_id", 1, std::move(wall_id))) + "\n";
  cell_data += "        " +
               AppendedArrays::tag(arrays.add("wall_force", std::span<const Vec3>(force))) + "\n";
  write_cells_file(path, arrays, CellKind::Polys, "Scalars=\"wall_id\" Vectors=\"wall_force\"",
                   cell_data, points, std::move(conn), std::move(offsets));
}

void write_contacts_vtp(const std::filesystem::path& path,
                        std::span<const contact::ContactRecord> pairs,
                        std::span<const contact::ContactRecord> walls, const ParticleStore& store) {
  std::vector<Vec3> points, force, normal;
  std::vector<std::int64_t> conn, offsets, id_i, id_j;
  std::vector<std::int32_t> wall;
  std::vector<double> fn, overlap;
  const std::int64_t* id = store.id();
  auto add = [&](const contact::ContactRecord& r, bool to_wall) {
    const Vec3 xi = store.x()[r.i];
    conn.push_back(static_cast<std::int64_t>(points.size()));
    conn.push_back(static_cast<std::int64_t>(points.size()) + 1);
    offsets.push_back(static_cast<std::int64_t>(conn.size()));
    points.push_back(xi);
    points.push_back(xi - r.branch);  // the touching image of j, or the contact point on the wall
    id_i.push_back(id[r.i]);
    id_j.push_back(to_wall ? -1 : id[r.j]);
    wall.push_back(to_wall ? r.j : -1);
    force.push_back(r.force);
    normal.push_back(r.normal);
    fn.push_back(dot(r.force, r.normal));
    overlap.push_back(r.overlap);
  };
  for (const auto& r : pairs)
    if (r.i >= 0) add(r, false);
  for (const auto& r : walls)
    if (r.i >= 0) add(r, true);

  AppendedArrays arrays;
  std::string cell_data;
  // One statement per array: blocks are laid out in the order they are added.
  cell_data += "        " + AppendedArrays::tag(arrays.add_owned("fn", 1, std::move(fn))) + "\n";
  cell_data +=
      "        " + AppendedArrays::tag(arrays.add("force", std::span<const Vec3>(force))) + "\n";
  cell_data +=
      "        " + AppendedArrays::tag(arrays.add("normal", std::span<const Vec3>(normal))) + "\n";
  cell_data +=
      "        " + AppendedArrays::tag(arrays.add_owned("overlap", 1, std::move(overlap))) + "\n";
  cell_data +=
      "        " + AppendedArrays::tag(arrays.add_owned("id_i", 1, std::move(id_i))) + "\n";
  cell_data +=
      "        " + AppendedArrays::tag(arrays.add_owned("id_j", 1, std::move(id_j))) + "\n";
  cell_data +=
      "        " + AppendedArrays::tag(arrays.add_owned("wall", 1, std::move(wall))) + "\n";
  write_cells_file(path, arrays, CellKind::Lines, "Scalars=\"fn\" Vectors=\"force\"", cell_data,
                   points, std::move(conn), std::move(offsets));
}

}  // namespace gf::io
