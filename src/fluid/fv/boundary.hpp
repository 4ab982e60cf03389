// SPDX-License-Identifier: GPL-3.0-or-later
// Boundary conditions of the finite-volume fluid solver, one per face of the grid's box.
#pragma once

#include <functional>
#include <string_view>
#include <utility>

#include "core/vec3.hpp"

namespace gf::fluid {

/// Faces of the box, numbered 2 * axis + side (side 0: the lower face, at grid.lo).
enum class BoxFace { XMin = 0, XMax = 1, YMin = 2, YMax = 3, ZMin = 4, ZMax = 5 };

constexpr int box_face_index(BoxFace f) {
  return static_cast<int>(f);
}
constexpr int box_face_index(int axis, int side) {
  return 2 * axis + side;
}
constexpr std::string_view box_face_name(int face) {
  constexpr std::string_view names[] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
  return names[face];
}

enum class BcKind {
  Periodic,        ///< pairs with the opposite face; the grid's axis must be periodic too
  NoSlip,          ///< wall at rest: u = 0
  MovingWall,      ///< wall sliding in its own plane: u = velocity (tangential)
  VelocityInlet,   ///< u given (vector; normal and tangential components)
  PressureOutlet,  ///< p = pressure on the face, zero normal gradient of every velocity component
};

/// Condition on one box face. Build with the named constructors below.
struct BoundaryCondition {
  BcKind kind = BcKind::NoSlip;
  /// MovingWall: velocity of the wall [m/s] (its normal component must be zero).
  /// VelocityInlet: velocity of the fluid on the face [m/s], used when `profile` is empty.
  Vec3 velocity{};
  /// VelocityInlet: velocity [m/s] at a point [m] of the face (e.g. a parabola). It is called
  /// from the solver's (possibly threaded) loops, so it must be a pure function.
  std::function<Vec3(const Vec3&)> profile;
  /// VelocityInlet: the given velocity is the superficial velocity eps u (what a fluidised bed
  /// specifies); the fluid velocity on the face is then velocity / eps of the adjacent cell.
  bool superficial = false;
  double pressure = 0.0;  ///< PressureOutlet: static pressure on the face [Pa]

  static BoundaryCondition periodic() { return of(BcKind::Periodic); }
  static BoundaryCondition no_slip() { return of(BcKind::NoSlip); }
  static BoundaryCondition moving_wall(const Vec3& wall_velocity) {
    BoundaryCondition b = of(BcKind::MovingWall);
    b.velocity = wall_velocity;
    return b;
  }
  static BoundaryCondition velocity_inlet(const Vec3& u, bool superficial = false) {
    BoundaryCondition b = of(BcKind::VelocityInlet);
    b.velocity = u;
    b.superficial = superficial;
    return b;
  }
  static BoundaryCondition velocity_inlet(std::function<Vec3(const Vec3&)> u_of_x,
                                          bool superficial = false) {
    BoundaryCondition b = of(BcKind::VelocityInlet);
    b.profile = std::move(u_of_x);
    b.superficial = superficial;
    return b;
  }
  static BoundaryCondition pressure_outlet(double p) {
    BoundaryCondition b = of(BcKind::PressureOutlet);
    b.pressure = p;
    return b;
  }

 private:
  static BoundaryCondition of(BcKind k) {
    BoundaryCondition b;
    b.kind = k;
    return b;
  }
};

}  // namespace gf::fluid
