// SPDX-License-Identifier: GPL-3.0-or-later
// Building blocks of every VTK XML file grainflow writes (particles and walls in io/vtk, the
// finite-element fields of fluid/fem, the finite-volume fields of the CFD-DEM coupling): arrays
// as appended raw binary blocks (header_type UInt64, the machine's byte order), the <VTKFile>
// opening tag, XML escaping, and the .pvd collection of a time series. In core so that every
// layer that writes ParaView files shares one format.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <ostream>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "core/vec3.hpp"

namespace gf::vtk {

/// "LittleEndian" or "BigEndian": the byte order of this machine, declared in every file.
const char* byte_order();

/// `<?xml ...?>` and the opening `<VTKFile type="..." ...>` tag with this machine's byte order and
/// UInt64 block headers, each followed by a newline.
std::string file_open(const char* type);

/// `text` with the five XML special characters escaped, for attribute values.
std::string xml_escape(const std::string& text);

/// The VTK type name of an array element type.
template <class T>
constexpr const char* type_name() {
  if constexpr (std::is_same_v<T, double>)
    return "Float64";
  else if constexpr (std::is_same_v<T, std::int64_t>)
    return "Int64";
  else if constexpr (std::is_same_v<T, std::int32_t>)
    return "Int32";
  else if constexpr (std::is_same_v<T, std::uint8_t>)
    return "UInt8";
  else
    static_assert(sizeof(T) == 0, "no VTK type for this element type");
}

/// The arrays of one file: each becomes a <DataArray format="appended" offset=...> tag in the
/// header and a block (UInt64 byte count, raw bytes) in <AppendedData>, in the order added.
class AppendedArrays {
 public:
  struct Array {
    std::string name;
    const char* type;
    int n_components;
    const void* data;
    std::uint64_t n_bytes;
    std::uint64_t offset;
  };

  /// Registers an array that lives elsewhere until write_appended() is done.
  template <class T>
  const Array& add(const std::string& name, int n_components, std::span<const T> values) {
    arrays_.push_back(
        {name, type_name<T>(), n_components, values.data(), values.size_bytes(), offset_});
    offset_ += sizeof(std::uint64_t) + values.size_bytes();
    return arrays_.back();
  }
  /// Three doubles per point.
  const Array& add(const std::string& name, std::span<const Vec3> values);
  /// Registers an array owned by this object.
  template <class T>
  const Array& add_owned(const std::string& name, int n_components, std::vector<T> values) {
    auto& kept = owned<T>().emplace_back(std::move(values));
    return add(name, n_components, std::span<const T>(kept));
  }

  /// The <DataArray .../> tag of an array.
  static std::string tag(const Array& a);

  /// Writes the <AppendedData> element with every block, in registration order.
  void write_appended(std::ostream& out) const;

 private:
  template <class T>
  std::deque<std::vector<T>>& owned() {
    if constexpr (std::is_same_v<T, double>)
      return owned_double_;
    else if constexpr (std::is_same_v<T, std::int64_t>)
      return owned_int64_;
    else if constexpr (std::is_same_v<T, std::int32_t>)
      return owned_int32_;
    else
      return owned_uint8_;
  }

  std::deque<Array> arrays_;  // deque: references returned by add() stay valid
  std::uint64_t offset_ = 0;
  std::deque<std::vector<double>> owned_double_;
  std::deque<std::vector<std::int64_t>> owned_int64_;
  std::deque<std::vector<std::int32_t>> owned_int32_;
  std::deque<std::vector<std::uint8_t>> owned_uint8_;
};

/// A whole ImageData file (.vti) of cell data: n cells per axis from `origin` [m] with `spacing`
/// [m], the cell arrays `arrays` (each registered in the order of `tags`, which holds their
/// DataArray tags one per line, each line indented and ended by the caller) and the attributes
/// of <CellData> (e.g. ` Scalars="a" Vectors="u"`).
void write_image_data(std::ostream& out, const std::array<int, 3>& n, const Vec3& origin,
                      const Vec3& spacing, const AppendedArrays& arrays, const std::string& tags,
                      const std::string& cell_attributes);

/// A ParaView collection (.pvd) of time steps; the file is rewritten atomically on every add,
/// so it is always complete and can be opened while the run goes on.
class PvdSeries {
 public:
  explicit PvdSeries(std::filesystem::path pvd_file);
  /// Continues an existing series in place (run --append): keeps the data sets of `pvd_file`
  /// (if it exists) whose time is below `before` [s]; the file is rewritten on the next add().
  /// A file that is not such a series throws IoError.
  PvdSeries(std::filesystem::path pvd_file, double before);

  /// Adds a data set: `time` in s, `relative_file` relative to the .pvd's folder, `part` the
  /// piece number (several files at one time step).
  void add(double time, const std::string& relative_file, int part = 0);

  const std::filesystem::path& path() const { return path_; }
  std::size_t size() const { return entries_.size(); }
  /// Time of the last data set added; requires size() > 0.
  double last_time() const { return entries_.back().time; }

 private:
  struct Entry {
    double time;
    std::string file;
    int part;
  };
  std::filesystem::path path_;
  std::vector<Entry> entries_;
};

}  // namespace gf::vtk
