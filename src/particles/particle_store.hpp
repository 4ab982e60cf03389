// SPDX-License-Identifier: GPL-3.0-or-later
// ParticleStore: structure-of-arrays particle data driven by one field table.
//
// Every per-particle quantity is a column registered in the field table with its name, type,
// unit and flags. Restart files, VTK/CSV output, ghost exchange and spatial re-ordering all walk
// this table, so a new field is added in exactly one place (`add_field`).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "core/quaternion.hpp"
#include "core/vec3.hpp"
#include "particles/shapes.hpp"

namespace gf {

enum class FieldType { Real, Vec3, Int64, Int32, Quat };

/// Flags of a field: what the generic walkers do with it.
enum FieldFlags : unsigned {
  kRestart = 1u << 0,  ///< saved in checkpoints
  kOutput = 1u << 1,   ///< written to VTK / particle CSV
  kGhost = 1u << 2,    ///< copied to ghost particles (MPI halos)
};

struct FieldInfo {
  std::string name;
  FieldType type;
  std::string unit;
  unsigned flags;
};

using Column = std::variant<std::vector<double>, std::vector<Vec3>, std::vector<std::int64_t>,
                            std::vector<std::int32_t>, std::vector<Quat>>;

class ParticleStore {
 public:
  /// Built-in fields, in the order they are registered (their index in the table).
  enum Builtin : int {
    kId = 0,           ///< unique particle id, kept through re-ordering
    kMaterial,         ///< material index
    kRadius,           ///< m
    kMass,             ///< kg
    kInertia,          ///< moment of inertia, kg m^2 (spheres: 2/5 m r^2)
    kPosition,         ///< m
    kVelocity,         ///< m/s
    kAngularVelocity,  ///< rad/s
    kForce,            ///< N
    kTorque,           ///< N m
    kNumBuiltin
  };

  ParticleStore();

  std::size_t size() const { return n_; }
  void resize(std::size_t n);
  void reserve(std::size_t n);

  /// Registers a new per-particle field; returns its index. Names are unique.
  int add_field(const std::string& name, FieldType type, const std::string& unit, unsigned flags);
  int find_field(const std::string& name) const;  ///< -1 when absent

  const std::vector<FieldInfo>& fields() const { return info_; }
  Column& column(int f) { return cols_[f]; }
  const Column& column(int f) const { return cols_[f]; }

  template <class T>
  std::span<T> get(int f) {
    return std::get<std::vector<T>>(cols_[f]);
  }
  template <class T>
  std::span<const T> get(int f) const {
    return std::get<std::vector<T>>(cols_[f]);
  }

  // Typed shortcuts for the hot fields.
  std::int64_t* id() { return std::get<std::vector<std::int64_t>>(cols_[kId]).data(); }
  std::int32_t* material() { return std::get<std::vector<std::int32_t>>(cols_[kMaterial]).data(); }
  double* radius() { return std::get<std::vector<double>>(cols_[kRadius]).data(); }
  double* mass() { return std::get<std::vector<double>>(cols_[kMass]).data(); }
  double* inertia() { return std::get<std::vector<double>>(cols_[kInertia]).data(); }
  Vec3* x() { return std::get<std::vector<Vec3>>(cols_[kPosition]).data(); }
  Vec3* v() { return std::get<std::vector<Vec3>>(cols_[kVelocity]).data(); }
  Vec3* omega() { return std::get<std::vector<Vec3>>(cols_[kAngularVelocity]).data(); }
  Vec3* f() { return std::get<std::vector<Vec3>>(cols_[kForce]).data(); }
  Vec3* torque() { return std::get<std::vector<Vec3>>(cols_[kTorque]).data(); }
  const std::int64_t* id() const { return std::get<std::vector<std::int64_t>>(cols_[kId]).data(); }
  const std::int32_t* material() const {
    return std::get<std::vector<std::int32_t>>(cols_[kMaterial]).data();
  }
  const double* radius() const { return std::get<std::vector<double>>(cols_[kRadius]).data(); }
  const double* mass() const { return std::get<std::vector<double>>(cols_[kMass]).data(); }
  const double* inertia() const { return std::get<std::vector<double>>(cols_[kInertia]).data(); }
  const Vec3* x() const { return std::get<std::vector<Vec3>>(cols_[kPosition]).data(); }
  const Vec3* v() const { return std::get<std::vector<Vec3>>(cols_[kVelocity]).data(); }
  const Vec3* omega() const { return std::get<std::vector<Vec3>>(cols_[kAngularVelocity]).data(); }
  const Vec3* f() const { return std::get<std::vector<Vec3>>(cols_[kForce]).data(); }
  const Vec3* torque() const { return std::get<std::vector<Vec3>>(cols_[kTorque]).data(); }

  /// Adds the shape fields (shape, half_length, orientation, angular_momentum, inertia_body,
  /// polygon; see particles/shapes.hpp) once; runs of spheres only never carry them. Existing
  /// particles become spheres with identity orientation. Idempotent.
  void enable_shapes();
  bool has_shapes() const { return shape_field_ >= 0; }
  /// Shape fields; valid only when has_shapes().
  std::int32_t* shape() { return get<std::int32_t>(shape_field_).data(); }
  const std::int32_t* shape() const { return get<std::int32_t>(shape_field_).data(); }
  double* half_length() { return get<double>(shape_field_ + 1).data(); }
  const double* half_length() const { return get<double>(shape_field_ + 1).data(); }
  Quat* orientation() { return get<Quat>(shape_field_ + 2).data(); }
  const Quat* orientation() const { return get<Quat>(shape_field_ + 2).data(); }
  Vec3* angular_momentum() { return get<Vec3>(shape_field_ + 3).data(); }
  const Vec3* angular_momentum() const { return get<Vec3>(shape_field_ + 3).data(); }
  Vec3* inertia_body() { return get<Vec3>(shape_field_ + 4).data(); }
  const Vec3* inertia_body() const { return get<Vec3>(shape_field_ + 4).data(); }
  std::int32_t* polygon() { return get<std::int32_t>(shape_field_ + 5).data(); }
  const std::int32_t* polygon() const { return get<std::int32_t>(shape_field_ + 5).data(); }

  /// Values of the field `fixed`: a free grain; a grain of a fixed group at rest (`fixed: true`);
  /// kFixedMoving + k for a grain of a fixed group that follows prescribed motion k (the k-th
  /// group with `fixed: {translate, rotate}` of the case).
  static constexpr std::int32_t kFree = 0, kFixedAtRest = 1, kFixedMoving = 2;

  /// Adds the field `fixed` (Int32: kFixedAtRest for a grain of a particle group with
  /// `fixed: true`, which keeps its initial position and orientation and has zero velocity and
  /// angular velocity; kFixedMoving + k for one of a group with prescribed motion k, which the
  /// simulation places; 0 otherwise) once, zero for every grain so far; runs without fixed
  /// grains never carry it. Saved in checkpoints, copied to ghosts and written to the particle
  /// outputs. Idempotent.
  void enable_fixed();
  bool has_fixed() const { return fixed_field_ >= 0; }
  /// The `fixed` column, or null when the store has none (no grain is fixed).
  std::int32_t* fixed() {
    return fixed_field_ >= 0 ? get<std::int32_t>(fixed_field_).data() : nullptr;
  }
  const std::int32_t* fixed() const {
    return fixed_field_ >= 0 ? get<std::int32_t>(fixed_field_).data() : nullptr;
  }

  /// Adds the reference state of grains with prescribed motion (after enable_shapes, if any):
  /// `fixed_x0` (Vec3, m), the position at t = 0 (not wrapped), and with shapes `fixed_q0`
  /// (Quat), the orientation at t = 0; their motion carries them to time t analytically, never
  /// by integration. Saved in checkpoints and copied to ghosts, not written to the outputs; runs
  /// without a moving fixed group never carry them. Idempotent.
  void enable_fixed_motion();
  bool has_fixed_motion() const { return fixed_x0_field_ >= 0; }
  /// `fixed_x0` and `fixed_q0` (null without: no moving group, or no shapes for the latter).
  Vec3* fixed_x0() { return fixed_x0_field_ >= 0 ? get<Vec3>(fixed_x0_field_).data() : nullptr; }
  const Vec3* fixed_x0() const {
    return fixed_x0_field_ >= 0 ? get<Vec3>(fixed_x0_field_).data() : nullptr;
  }
  Quat* fixed_q0() { return fixed_q0_field_ >= 0 ? get<Quat>(fixed_q0_field_).data() : nullptr; }
  const Quat* fixed_q0() const {
    return fixed_q0_field_ >= 0 ? get<Quat>(fixed_q0_field_).data() : nullptr;
  }

  /// Body-frame polygons that polygon grains refer to (field `polygon`); saved in checkpoints.
  std::vector<PolygonShape>& polygons() { return polygons_; }
  const std::vector<PolygonShape>& polygons() const { return polygons_; }

  /// Appends one sphere; other fields are zero. Returns its index.
  std::size_t add_sphere(std::int64_t id, int material, double radius, double density,
                         const Vec3& x, const Vec3& v = {}, const Vec3& omega = {});

  /// Re-orders every column in place: new[i] = old[order[i]] (no copy of a column: the
  /// permutation's cycles are followed, with one bit per particle of scratch).
  void permute(std::span<const std::int64_t> order);

  /// Gives back the memory of unused capacity (after the particles are placed; before a
  /// checkpoint replaces them).
  void shrink_to_fit();

  /// Bytes held by all columns (capacity), for memory reports.
  std::size_t bytes() const;

 private:
  std::size_t n_ = 0;
  std::vector<FieldInfo> info_;
  std::vector<Column> cols_;
  std::vector<std::uint64_t> done_;  ///< permute(): one bit per particle, cycle visited
  int shape_field_ = -1;             ///< index of `shape`; the other shape fields follow it
  int fixed_field_ = -1;             ///< index of `fixed` (enable_fixed), -1 without
  int fixed_x0_field_ = -1;          ///< index of `fixed_x0` (enable_fixed_motion), -1 without
  int fixed_q0_field_ = -1;          ///< index of `fixed_q0` (with shapes), -1 without
  std::vector<PolygonShape> polygons_;
};

/// Index of the first grain whose position, velocity or angular velocity has a component that
/// is NaN or infinite (a diverged run, a damaged checkpoint); nullopt when all are finite.
std::optional<std::size_t> first_non_finite_grain(const ParticleStore& p);

}  // namespace gf
