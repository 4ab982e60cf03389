// SPDX-License-Identifier: GPL-3.0-or-later
// HDF5 checkpoints: a small RAII wrapper over the HDF5 C API, the particle store <-> file mapping.
//
// Every failure becomes gf::IoError naming the file and the object; HDF5's own error-stack
// printing is switched off. Object paths are relative to the root ("particles/position",
// "contacts/pairs"); "" and "/" name the root. Writing a dataset creates the groups on its path.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "core/vec3.hpp"
#include "particles/particle_store.hpp"

namespace gf::io {

namespace h5 {

/// What a dataset holds, as far as the checkpoint readers care.
struct DatasetInfo {
  enum class Class { Float, Integer, Other };
  Class type_class = Class::Other;
  std::size_t type_size = 0;         ///< bytes per element
  std::vector<std::uint64_t> shape;  ///< one entry per dimension
};

/// One open HDF5 file. Move-only; closed by the destructor (errors there are swallowed; call
/// close() to see them).
class File {
 public:
  /// Creates (truncates) `path` for writing.
  static File create(const std::filesystem::path& path);
  /// Opens an existing file read-only.
  static File open_read(const std::filesystem::path& path);

  File(File&& other) noexcept;
  File& operator=(File&& other) noexcept;
  File(const File&) = delete;
  File& operator=(const File&) = delete;
  ~File();

  /// Flushes and closes; throws IoError when HDF5 reports a failure. Idempotent.
  void close();
  bool is_open() const { return id_ >= 0; }
  const std::filesystem::path& path() const { return path_; }

  /// True when a group or dataset exists at `object` (every component of the path is checked).
  bool exists(const std::string& object) const;
  bool is_group(const std::string& object) const;
  /// Creates a group and any missing parents; an existing group is fine.
  void create_group(const std::string& group);
  /// Names of the direct children (groups and datasets) of a group, in name order.
  std::vector<std::string> list(const std::string& group) const;

  // 1-D datasets (an existing dataset of the same name is replaced).
  void write(const std::string& dataset, std::span<const double> data);
  void write(const std::string& dataset, std::span<const std::int64_t> data);
  void write(const std::string& dataset, std::span<const std::int32_t> data);
  void write(const std::string& dataset, std::span<const std::uint8_t> data);
  /// N x 3 dataset of doubles.
  void write(const std::string& dataset, std::span<const Vec3> data);
  void write(const std::string& dataset, std::span<const Quat> data);  ///< n x 4 (w, x, y, z)

  DatasetInfo info(const std::string& dataset) const;

  /// Whole dataset; the file's element type must be of the same class (float / integer) and the
  /// shape must be 1-D (N x 3 for Vec3). Values are converted to the native type by HDF5.
  std::vector<double> read_double(const std::string& dataset) const;
  std::vector<std::int64_t> read_int64(const std::string& dataset) const;
  std::vector<std::int32_t> read_int32(const std::string& dataset) const;
  std::vector<std::uint8_t> read_uint8(const std::string& dataset) const;
  std::vector<Vec3> read_vec3(const std::string& dataset) const;

  /// Reads into `out`, whose size must equal the dataset's length.
  void read(const std::string& dataset, std::span<double> out) const;
  void read(const std::string& dataset, std::span<std::int64_t> out) const;
  void read(const std::string& dataset, std::span<std::int32_t> out) const;
  void read(const std::string& dataset, std::span<std::uint8_t> out) const;
  void read(const std::string& dataset, std::span<Vec3> out) const;
  void read(const std::string& dataset, std::span<Quat> out) const;

  // Attributes on a group, a dataset or the root ("" or "/"); an existing one is replaced.
  void set_attribute(const std::string& object, const std::string& name, const std::string& value);
  void set_attribute(const std::string& object, const std::string& name, const char* value);
  void set_attribute(const std::string& object, const std::string& name, double value);
  void set_attribute(const std::string& object, const std::string& name, std::int64_t value);
  void set_attribute(const std::string& object, const std::string& name, std::int32_t value);

  bool has_attribute(const std::string& object, const std::string& name) const;
  std::string read_string_attribute(const std::string& object, const std::string& name) const;
  double read_double_attribute(const std::string& object, const std::string& name) const;
  std::int64_t read_int_attribute(const std::string& object, const std::string& name) const;

 private:
  File(std::int64_t id, std::filesystem::path path) : id_(id), path_(std::move(path)) {}

  std::int64_t open_object(const std::string& object) const;  ///< caller closes (H5Oclose)
  std::int64_t checked_id(const std::string& what) const;

  std::int64_t id_ = -1;  ///< hid_t; -1 when closed
  std::filesystem::path path_;
};

}  // namespace h5

/// Writes every kRestart field of `store` into `group` (dataset named after the field, with
/// attributes "unit" and "type"), and the particle count as the group's attribute "count".
void save_particles(h5::File& file, const ParticleStore& store,
                    const std::string& group = "particles");

/// Resizes `store` to the saved count and reads every kRestart field by name, bit-exactly.
/// A missing field, a wrong length or a type that differs from the store's throws IoError; a
/// dataset in the file that is not a kRestart field of the store is ignored, unless the store
/// has a field of that name of another type (IoError).
void load_particles(h5::File& file, ParticleStore& store, const std::string& group = "particles");

/// Marks a file as a grainflow checkpoint: root attributes program = "grainflow", version and,
/// unless empty, kind (DEM / CFD-DEM checkpoints have none; "fluid_fem", "continuum_sph").
void set_checkpoint_identity(h5::File& file, const std::string& kind = "");

/// The kind of a grainflow checkpoint ("" for a DEM / CFD-DEM one); a file that is not a
/// grainflow checkpoint throws gf::InputError "PATH: not a grainflow checkpoint".
std::string checkpoint_kind(const h5::File& file, const std::filesystem::path& path);

/// Creates a checkpoint at `path` atomically: a temporary file next to it is created, filled by
/// `fill`, closed, and renamed over `path`. If anything throws, no file is left behind and an
/// existing `path` is untouched.
void write_checkpoint_atomically(const std::filesystem::path& path,
                                 const std::function<void(h5::File&)>& fill);

}  // namespace gf::io
