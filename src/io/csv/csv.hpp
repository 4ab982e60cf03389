// SPDX-License-Identifier: GPL-3.0-or-later
// CSV output: particle snapshots from the field table, and time series appended row by row.
//
// Numbers are written in the shortest form that reads back to the same double (fmt "{}").
#pragma once

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <span>
#include <string>
#include <vector>

#include "contact/pair_forces.hpp"
#include "particles/particle_store.hpp"

namespace gf::io {

/// Column names of a particle CSV: every kOutput field in field-table order; Vec3 fields are
/// split into three columns: position -> x,y,z; velocity -> vx,vy,vz; angular_velocity ->
/// wx,wy,wz; force -> fx,fy,fz; any other NAME -> NAME_x,NAME_y,NAME_z. Quaternion fields into
/// four: orientation -> qw,qx,qy,qz; any other NAME -> NAME_w,NAME_x,NAME_y,NAME_z. When the
/// store has shapes (columns shape, half_length, qw..qz, polygon), the orientation columns are
/// followed by ax,ay,az = io::shape_axis(shape, q) (io/vtk/vtk.hpp): a spherocylinder's world
/// axis; R(q) e_x for disks and polygons. See docs/output.md.
std::vector<std::string> particle_csv_columns(const ParticleStore& store);

/// One row per particle under the header of particle_csv_columns (SI units; integer fields as
/// integers, reals in the shortest form that reads back to the same double). Atomic.
void write_particles_csv(const std::filesystem::path& path, const ParticleStore& store);

/// The touching pairs of a force stage (records with i < 0 left out), one row each in the
/// records' order: id_i,id_j (the grains' ids), x,y,z (contact point), nx,ny,nz (unit normal,
/// from j to i), fx,fy,fz (force on i from j; j gets the opposite), fn (its normal component
/// F . n, > 0 repulsive), overlap, bx,by,bz (branch vector x_i - x_j to the image of j that
/// touches i). SI units, numbers as in write_particles_csv. Atomic.
void write_contacts_csv(const std::filesystem::path& path,
                        std::span<const contact::ContactRecord> records,
                        const ParticleStore& store);

/// The touching grain-wall contacts of a force stage (records with i < 0 left out; record j is
/// the wall's index into `wall_names`), one row each in the records' order: id (the grain's id),
/// wall (its name), x,y,z (contact point), nx,ny,nz (unit normal, from the wall to the grain),
/// fx,fy,fz (force on the grain; the wall gets the opposite), fn (F . n, > 0 repulsive), overlap,
/// bx,by,bz (x_grain - contact point). SI units, numbers as in write_particles_csv. Atomic.
void write_wall_contacts_csv(const std::filesystem::path& path,
                             std::span<const contact::ContactRecord> records,
                             const ParticleStore& store, std::span<const std::string> wall_names);

/// Where a continued time series picks up (run --append): rows later than `time` [s] were
/// written after the checkpoint and are dropped; a row at exactly `time` is kept or dropped as
/// `keep_at_time` says (dropped when the run writes it again).
struct SeriesContinuation {
  double time = 0.0;
  bool keep_at_time = true;
};

/// A time-series CSV: header `time,<columns>`, then one row per append. The file is created
/// (truncated) by the constructor and kept open; rows are buffered and reach the disk at the
/// latest on flush() or destruction.
class SeriesCsv {
 public:
  SeriesCsv(std::filesystem::path path, std::vector<std::string> columns);
  /// Continues the series in `path` (a missing file starts afresh): its header must name the
  /// same columns (else InputError); the rows up to `from` are kept (kept_rows()), the file is
  /// rewritten with them atomically, and new rows are appended.
  SeriesCsv(std::filesystem::path path, std::vector<std::string> columns,
            const SeriesContinuation& from);
  ~SeriesCsv();
  SeriesCsv(SeriesCsv&&) noexcept = default;
  SeriesCsv& operator=(SeriesCsv&&) noexcept = default;
  SeriesCsv(const SeriesCsv&) = delete;
  SeriesCsv& operator=(const SeriesCsv&) = delete;

  /// One row: `time` in s, then one value per column (count must match).
  void append(double time, std::span<const double> values);
  void append(double time, std::initializer_list<double> values) {
    append(time, std::span<const double>(values.begin(), values.size()));
  }
  /// Pushes buffered rows to the file; throws IoError when the write failed.
  void flush();

  const std::filesystem::path& path() const { return path_; }
  const std::vector<std::string>& columns() const { return columns_; }
  /// Rows kept from the file when continuing: time, then one value per column.
  const std::vector<std::vector<double>>& kept_rows() const { return kept_; }

 private:
  std::filesystem::path path_;
  std::vector<std::string> columns_;
  std::ofstream out_;
  std::vector<std::vector<double>> kept_;
};

}  // namespace gf::io
