// SPDX-License-Identifier: GPL-3.0-or-later
// ParaView output: particles and wall surfaces as VTK XML PolyData (.vtp), .pvd time series.
//
// Files use appended raw binary data (header_type UInt64, the machine's byte order, which is
// LittleEndian on every supported platform) and are written atomically (temporary file, rename).
// docs/output.md lists every array and shows how to draw capsules and polygons in ParaView.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "contact/pair_forces.hpp"
#include "core/quaternion.hpp"
#include "core/surface_mesh.hpp"
#include "core/vec3.hpp"
#include "core/vtk_xml.hpp"
#include "particles/particle_store.hpp"
#include "particles/shapes.hpp"

namespace gf::io {

/// The world direction written as `axis` (VTK) and ax,ay,az (CSV) for a grain of shape `shape`
/// and orientation `q` (body -> world): R(q) e_z for 3D shapes (a spherocylinder's axis; any
/// fixed body direction of a sphere), R(q) e_x for the 2D shapes (disk, polygon), whose e_z is
/// the plane normal: there it shows the rotation angle in the plane. Unit when q is.
inline Vec3 shape_axis(std::int32_t shape, const Quat& q) {
  const bool planar = shape == static_cast<std::int32_t>(ShapeCode::Disk) ||
                      shape == static_cast<std::int32_t>(ShapeCode::Polygon);
  return rotate(q, planar ? Vec3{1, 0, 0} : Vec3{0, 0, 1});
}

/// Particles as points (positions, m) with one vertex cell each. Point data: every field flagged
/// kOutput except position, under its field-table name (Real -> Float64, Vec3 -> 3 x Float64,
/// Int64 -> Int64, Int32 -> Int32, Quat -> 4 x Float64 in the order w, x, y, z), plus "speed" =
/// |velocity| (m/s). When the store has shapes, also the glyph arrays (3 x Float64 or Float64):
///   axis            shape_axis(shape, orientation), 1
///   length          tip-to-tip length 2 (half_length + cap radius) = 2 radius, m
///                   (sphere, disk: the diameter; polygon: the circumscribed diameter)
///   cap_radius      radius of the rounded ends, m: radius - half_length (sphere, disk: radius;
///                   polygon: 0, it has no rounded part)
///   cylinder_scale  (2 half_length, 2 cap_radius, 2 cap_radius), m: per-axis scale of a unit
///                   cylinder glyph laid along glyph x, giving the cylindrical part of a capsule
///   cap_offset      half_length * axis, m: centre of the +end cap relative to the grain centre
void write_particles_vtp(const std::filesystem::path& path, const ParticleStore& store);

/// A PolyData file of points, each a vertex cell, written atomically. `point_data` holds the
/// tags (one per line) of the point arrays already added to `arrays`, `point_attrs` the
/// PointData attributes (e.g. ` Scalars="radius" Vectors="velocity"`, with a leading space, or
/// empty); the positions, connectivity and offsets are added after them.
void write_points_vtp(const std::filesystem::path& path, vtk::AppendedArrays& arrays,
                      const std::string& point_attrs, const std::string& point_data,
                      std::span<const Vec3> points);

/// Number of polygon grains (shape Polygon) in `store`; 0 when it has no shapes.
std::size_t count_polygon_grains(const ParticleStore& store);

/// 2D polygon grains as real polygons: one polygon cell per polygon grain, in store order, whose
/// points are the world vertices x + R(q) (vx, vy, 0) (m, counter-clockwise seen from +z) of the
/// body polygon `store.polygons()[polygon[i]]`. Cell data: "id" (Int64), "material" (Int32),
/// "velocity" (3 x Float64, m/s), "angular_velocity" (3 x Float64, rad/s), "speed" (Float64, m/s),
/// "area" (Float64, m^2). Other shapes are left out; a store without polygon grains gives a valid
/// empty file. A polygon index outside the table or a polygon of fewer than 3 vertices is an
/// error (nothing written).
void write_polygons_vtp(const std::filesystem::path& path, const ParticleStore& store);

/// Walls as triangles. Cell data: "wall_id" (Int32, the index into `meshes`) and "wall_force"
/// (3 x Float64, N: the total force on that wall, repeated on each of its triangles).
/// `force_per_mesh` has one entry per mesh. An empty list gives a valid empty file.
void write_surfaces_vtp(const std::filesystem::path& path, std::span<const SurfaceMesh> meshes,
                        std::span<const Vec3> force_per_mesh);

/// The contact network as line cells (docs/output.md): one line per touching record (i >= 0),
/// first the grain pairs, then the grain-wall contacts, each from the centre of grain i to
/// x_i - branch (the image of grain j that touches i; for a wall record, the contact point).
/// Cell data: "fn" (Float64, N: F . n, > 0 repulsive), "force" (3 x Float64, N: on grain i),
/// "normal" (3 x Float64, unit, towards i), "overlap" (Float64, m), "id_i", "id_j" (Int64,
/// grain ids; id_j = -1 for a wall), "wall" (Int32, the wall's index, -1 for a grain pair).
void write_contacts_vtp(const std::filesystem::path& path,
                        std::span<const contact::ContactRecord> pairs,
                        std::span<const contact::ContactRecord> walls, const ParticleStore& store);

/// The .pvd time series and XML escaping are the shared ones of core/vtk_xml.hpp.
using vtk::PvdSeries;
using vtk::xml_escape;

}  // namespace gf::io
