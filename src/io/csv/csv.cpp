// SPDX-License-Identifier: GPL-3.0-or-later
// CSV writers: particle snapshots (atomic) and appended time series.
#include "io/csv/csv.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <array>
#include <cstdlib>
#include <iterator>
#include <ostream>
#include <string_view>
#include <variant>

#include "core/error.hpp"
#include "core/files.hpp"
#include "io/vtk/vtk.hpp"

namespace gf::io {

namespace {

/// Column names of one Vec3 field.
std::array<std::string, 3> vec3_columns(const std::string& name) {
  if (name == "position") return {"x", "y", "z"};
  if (name == "velocity") return {"vx", "vy", "vz"};
  if (name == "angular_velocity") return {"wx", "wy", "wz"};
  if (name == "force") return {"fx", "fy", "fz"};
  return {name + "_x", name + "_y", name + "_z"};
}

/// Column names of one quaternion field.
std::array<std::string, 4> quat_columns(const std::string& name) {
  if (name == "orientation") return {"qw", "qx", "qy", "qz"};
  return {name + "_w", name + "_x", name + "_y", name + "_z"};
}

/// Index of the field after whose columns ax,ay,az go (the store's orientation), or -1.
int axis_after_field(const ParticleStore& store) {
  if (!store.has_shapes()) return -1;
  const int f = store.find_field("orientation");
  return f >= 0 && (store.fields()[static_cast<std::size_t>(f)].flags & kOutput) ? f : -1;
}

void require_plain_name(const std::string& name, const std::filesystem::path& path) {
  REQUIRE(!name.empty() && name.find_first_of(",\"\r\n") == std::string::npos,
          "CSV column name '{}' for '{}' is empty or holds a comma, quote or line break", name,
          path.string());
}

}  // namespace

std::vector<std::string> particle_csv_columns(const ParticleStore& store) {
  std::vector<std::string> cols;
  const int axis_after = axis_after_field(store);
  const auto& fields = store.fields();
  for (std::size_t f = 0; f < fields.size(); ++f) {
    const FieldInfo& fi = fields[f];
    if (!(fi.flags & kOutput)) continue;
    if (fi.type == FieldType::Vec3) {
      for (auto& c : vec3_columns(fi.name)) cols.push_back(std::move(c));
    } else if (fi.type == FieldType::Quat) {
      for (auto& c : quat_columns(fi.name)) cols.push_back(std::move(c));
    } else {
      cols.push_back(fi.name);
    }
    if (static_cast<int>(f) == axis_after) cols.insert(cols.end(), {"ax", "ay", "az"});
  }
  return cols;
}

namespace {

/// Writes `header` and one row per touching record (i >= 0), formatted by row(it, record), into
/// `path` atomically, in blocks of about 1 MB.
template <class Row>
void write_record_rows(const std::filesystem::path& path, std::string_view header,
                       std::span<const contact::ContactRecord> records, Row row) {
  write_atomically(path, [&](std::ostream& out) {
    fmt::memory_buffer buf;
    auto it = std::back_inserter(buf);
    fmt::format_to(it, "{}\n", header);
    for (const auto& r : records) {
      if (r.i < 0) continue;
      row(it, r);
      if (buf.size() > (1u << 20)) {
        out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
        buf.clear();
      }
    }
    out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
  });
}

}  // namespace

void write_contacts_csv(const std::filesystem::path& path,
                        std::span<const contact::ContactRecord> records,
                        const ParticleStore& store) {
  const std::int64_t* id = store.id();
  write_record_rows(path, "id_i,id_j,x,y,z,nx,ny,nz,fx,fy,fz,fn,overlap,bx,by,bz", records,
                    [&](auto it, const contact::ContactRecord& r) {
                      fmt::format_to(it, "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
                                     id[r.i], id[r.j], r.point.x, r.point.y, r.point.z, r.normal.x,
                                     r.normal.y, r.normal.z, r.force.x, r.force.y, r.force.z,
                                     dot(r.force, r.normal), r.overlap, r.branch.x, r.branch.y,
                                     r.branch.z);
                    });
}

void write_wall_contacts_csv(const std::filesystem::path& path,
                             std::span<const contact::ContactRecord> records,
                             const ParticleStore& store, std::span<const std::string> wall_names) {
  const std::int64_t* id = store.id();
  for (const auto& r : records)
    REQUIRE(r.i < 0 || (r.j >= 0 && static_cast<std::size_t>(r.j) < wall_names.size()),
            "'{}': a wall contact names wall {} of {}", path.string(), r.j, wall_names.size());
  for (const auto& w : wall_names) require_plain_name(w, path);
  write_record_rows(path, "id,wall,x,y,z,nx,ny,nz,fx,fy,fz,fn,overlap,bx,by,bz", records,
                    [&](auto it, const contact::ContactRecord& r) {
                      fmt::format_to(it, "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
                                     id[r.i], wall_names[static_cast<std::size_t>(r.j)], r.point.x,
                                     r.point.y, r.point.z, r.normal.x, r.normal.y, r.normal.z,
                                     r.force.x, r.force.y, r.force.z, dot(r.force, r.normal),
                                     r.overlap, r.branch.x, r.branch.y, r.branch.z);
                    });
}

void write_particles_csv(const std::filesystem::path& path, const ParticleStore& store) {
  const std::vector<std::string> cols = particle_csv_columns(store);
  for (const auto& c : cols) require_plain_name(c, path);
  std::vector<const Column*> out_cols;
  const Column* axis_after = nullptr;  // ax,ay,az follow this column
  const auto& fields = store.fields();
  for (std::size_t f = 0; f < fields.size(); ++f)
    if (fields[f].flags & kOutput) out_cols.push_back(&store.column(static_cast<int>(f)));
  if (const int f = axis_after_field(store); f >= 0) axis_after = &store.column(f);

  write_atomically(path, [&](std::ostream& out) {
    fmt::memory_buffer buf;
    auto it = std::back_inserter(buf);
    fmt::format_to(it, "{}\n", fmt::join(cols, ","));
    for (std::size_t i = 0; i < store.size(); ++i) {
      bool first = true;
      for (const Column* col : out_cols) {
        std::visit(
            [&](const auto& v) {
              using T = typename std::decay_t<decltype(v)>::value_type;
              if constexpr (std::is_same_v<T, Vec3>)
                fmt::format_to(it, "{}{},{},{}", first ? "" : ",", v[i].x, v[i].y, v[i].z);
              else if constexpr (std::is_same_v<T, Quat>)
                fmt::format_to(it, "{}{},{},{},{}", first ? "" : ",", v[i].w, v[i].x, v[i].y,
                               v[i].z);
              else
                fmt::format_to(it, "{}{}", first ? "" : ",", v[i]);
            },
            *col);
        first = false;
        if (col == axis_after) {
          const Vec3 a = shape_axis(store.shape()[i], store.orientation()[i]);
          fmt::format_to(it, ",{},{},{}", a.x, a.y, a.z);
        }
      }
      buf.push_back('\n');
      if (buf.size() > (1u << 20)) {
        out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
        buf.clear();
      }
    }
    out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
  });
}

SeriesCsv::SeriesCsv(std::filesystem::path path, std::vector<std::string> columns)
    : path_(std::move(path)), columns_(std::move(columns)) {
  for (const auto& c : columns_) require_plain_name(c, path_);
  out_.open(path_, std::ios::binary | std::ios::trunc);
  if (!out_) throw IoError(fmt::format("cannot open '{}' for writing", path_.string()));
  out_ << "time";
  for (const auto& c : columns_) out_ << ',' << c;
  out_ << '\n';
  flush();  // the header is on disk at once, and a full disk is noticed here
}

SeriesCsv::SeriesCsv(std::filesystem::path path, std::vector<std::string> columns,
                     const SeriesContinuation& from)
    : path_(std::move(path)), columns_(std::move(columns)) {
  for (const auto& c : columns_) require_plain_name(c, path_);
  std::string header = "time";
  for (const auto& c : columns_) header += ',' + c;
  std::string kept_text = header + '\n';
  const auto lines = continued_csv_lines(path_, header, [&](double t) {
    return t < from.time || (t == from.time && from.keep_at_time);
  });
  for (const auto& line : lines) {
    std::vector<double> row;
    const char* p = line.c_str();
    char* end = nullptr;
    for (std::size_t k = 0; k <= columns_.size(); ++k) {
      row.push_back(std::strtod(p, &end));
      if (end == p || (*end != ',' && *end != '\0')) break;
      p = *end ? end + 1 : end;
    }
    if (row.size() != columns_.size() + 1 || *end != '\0') break;  // a torn last line
    kept_text += line + '\n';
    kept_.push_back(std::move(row));
  }
  write_atomically(path_, [&](std::ostream& o) { o << kept_text; });
  out_.open(path_, std::ios::binary | std::ios::app);
  if (!out_) throw IoError(fmt::format("cannot open '{}' for writing", path_.string()));
}

SeriesCsv::~SeriesCsv() {
  if (out_.is_open()) out_.flush();  // errors cannot be reported from here; flush() reports them
}

void SeriesCsv::append(double time, std::span<const double> values) {
  REQUIRE(values.size() == columns_.size(), "time series '{}': {} values for {} columns",
          path_.string(), values.size(), columns_.size());
  fmt::memory_buffer buf;
  auto it = std::back_inserter(buf);
  fmt::format_to(it, "{}", time);
  for (double v : values) fmt::format_to(it, ",{}", v);
  buf.push_back('\n');
  out_.write(buf.data(), static_cast<std::streamsize>(buf.size()));
  if (!out_) throw IoError(fmt::format("error while writing '{}'", path_.string()));
}

void SeriesCsv::flush() {
  out_.flush();
  if (!out_) throw IoError(fmt::format("error while writing '{}'", path_.string()));
}

}  // namespace gf::io
