// SPDX-License-Identifier: GPL-3.0-or-later
// ParaView output: particles and wall surfaces as VTK XML PolyData (.vtp), .pvd time series.
//
// Files use appended raw binary data (header_type UInt64, the machine's byte order, which is
// LittleEndian on every supported platform) and are written atomically (temporary file, rename).
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "core/surface_mesh.hpp"
#include "core/vec3.hpp"
#include "particles/particle_store.hpp"

namespace gf::io {

/// Particles as points (positions, m) with one vertex cell each. Point data: every field flagged
/// kOutput except position, under its field-table name (Real -> Float64, Vec3 -> 3 x Float64,
/// Int64 -> Int64, Int32 -> Int32), plus "speed" = |velocity| (m/s).
void write_particles_vtp(const std::filesystem::path& path, const ParticleStore& store);

/// Walls as triangles. Cell data: "wall_id" (Int32, the index into `meshes`) and "wall_force"
/// (3 x Float64, N: the total force on that wall, repeated on each of its triangles).
/// `force_per_mesh` has one entry per mesh. An empty list gives a valid empty file.
void write_surfaces_vtp(const std::filesystem::path& path, std::span<const SurfaceMesh> meshes,
                        std::span<const Vec3> force_per_mesh);

/// A ParaView collection (.pvd) of time steps; the file is rewritten atomically on every add,
/// so it is always complete and can be opened while the run goes on.
class PvdSeries {
 public:
  explicit PvdSeries(std::filesystem::path pvd_file);

  /// Adds a data set: `time` in s, `relative_file` relative to the .pvd's folder, `part` the
  /// piece number (several files at one time step).
  void add(double time, const std::string& relative_file, int part = 0);

  const std::filesystem::path& path() const { return path_; }
  std::size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    double time;
    std::string file;
    int part;
  };
  std::filesystem::path path_;
  std::vector<Entry> entries_;
};

/// `text` with the five XML special characters escaped, for attribute values.
std::string xml_escape(const std::string& text);

}  // namespace gf::io
