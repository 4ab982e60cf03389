// SPDX-License-Identifier: GPL-3.0-or-later
// Walls (infinite plane, cylinder) with prescribed motion, their contact lists and reactions.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "boundaries/motion.hpp"
#include "contact/laws/contact_io.hpp"
#include "core/domain.hpp"
#include "core/surface_mesh.hpp"
#include "particles/material.hpp"
#include "particles/particle_store.hpp"

namespace gf {

enum class WallKind : std::int32_t { Plane, Cylinder };

/// One wall surface. A `box` of the case file becomes several planes sharing a group.
struct Wall {
  std::string name;   ///< e.g. "floor", or "box.zmin" for a face of a box
  std::string group;  ///< the case-file name it reports under (equal to name for single walls)
  WallKind kind = WallKind::Plane;
  int material = 0;
  // Geometry at t = 0.
  Vec3 point0;         ///< plane: a point; cylinder: a point on the axis (m)
  Vec3 dir0{0, 0, 1};  ///< plane: unit normal towards the particles; cylinder: unit axis
  double radius = 0;   ///< cylinder radius, m
  bool inside = true;  ///< cylinder: particles inside
  RigidMotion motion;
  // Current geometry (update_geometry).
  Vec3 point, dir;
  // Reactions of the last force evaluation: force by the particles on the wall, N; torque about
  // the motion centre (rotating walls) or point0's current image, N m.
  Vec3 force, torque;

  void update_geometry(double t) {
    point = motion.point_at(point0, t);
    dir = motion.rotate(dir0, t);
  }
  Vec3 torque_center() const { return point; }

  /// Gap between a sphere surface and the wall (negative = overlap) and the unit normal that
  /// points from the wall to the sphere centre.
  GF_HOST_DEVICE double gap(const Vec3& x, double r, Vec3& n) const {
    if (kind == WallKind::Plane) {
      n = dir;
      return dot(x - point, dir) - r;
    }
    const Vec3 d = x - point;
    Vec3 radial = d - dot(d, dir) * dir;
    const double rho = norm(radial);
    if (rho > 0)
      radial = radial / rho;
    else
      radial = std::abs(dir.x) < 0.9 ? normalized(cross(dir, Vec3{1, 0, 0}))
                                     : normalized(cross(dir, Vec3{0, 1, 0}));
    if (inside) {
      n = -radial;
      return radius - rho - r;
    }
    n = radial;
    return rho - radius - r;
  }

  /// Triangulated surface for output, sized to the domain.
  SurfaceMesh surface(const Domain& domain) const;
};

/// Particle-wall pairs within the skin, with their tangential history; rebuilt with the
/// Verlet list, history carried across rebuilds.
class WallContactList {
 public:
  struct Entry {
    std::int32_t particle;
    std::int32_t wall;
  };
  /// Pairs with a gap below the skin. `perm` maps new particle indices to those of the previous
  /// build (empty: unchanged order), so that histories follow re-ordered particles. `r` is the
  /// bounding radius.
  void build(std::span<const Wall> walls, const Vec3* x, const double* r, std::size_t n,
             double skin, std::span<const std::int64_t> perm = {});
  /// Contacts per entry (1 for spheres and disks; 2 when spherocylinders are present: one per end,
  /// see contact/geometry/capsule.hpp), each with its own tangential history. Set before build().
  void set_slots(int slots) { slots_ = slots; }
  int slots() const { return slots_; }
  std::span<const Entry> entries() const { return entries_; }
  std::span<Vec3> history() { return history_; }
  std::span<const Vec3> history() const { return history_; }
  void restore(std::vector<Entry> entries, std::vector<Vec3> history);
  /// Start of each particle's run of entries (plus the end): the unit of threading.
  std::span<const std::int64_t> particle_groups() const { return groups_; }
  /// History: slots() vectors per entry, entry-major.
  /// Per entry: reaction force on the wall and its torque (2 per entry), of the last evaluation.
  std::span<Vec3> reactions() { return reactions_; }
  std::size_t bytes() const {
    return (entries_.capacity() + old_entries_.capacity()) * sizeof(Entry) +
           (history_.capacity() + old_history_.capacity() + reactions_.capacity()) * sizeof(Vec3) +
           groups_.capacity() * 8;
  }

 private:
  std::vector<Entry> entries_, old_entries_;
  std::vector<Vec3> history_, old_history_, reactions_;
  std::vector<std::int64_t> groups_{0};
  int slots_ = 1;
};

/// Adds the wall contact forces and torques to the particles and accumulates the reactions on
/// the walls. Returns the number of active wall contacts.
std::int64_t compute_wall_forces(ParticleStore& p, std::span<Wall> walls, WallContactList& list,
                                 const PairTable<contact::PairCoeffs>& pairs, double t, double dt);

/// Elastic energy stored in all particle-wall contacts (J), for energy balances.
double wall_elastic_energy(const ParticleStore& p, std::span<const Wall> walls,
                           const WallContactList& list,
                           const PairTable<contact::PairCoeffs>& pairs);

}  // namespace gf
