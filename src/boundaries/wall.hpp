// SPDX-License-Identifier: GPL-3.0-or-later
// Walls (infinite plane, cylinder, triangle mesh) with prescribed motion, their contact lists and
// reactions.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "boundaries/motion.hpp"
#include "boundaries/triangle_mesh.hpp"
#include "boundaries/wall_surface.hpp"
#include "contact/laws/contact_io.hpp"
#include "contact/pair_forces.hpp"
#include "core/domain.hpp"
#include "core/surface_mesh.hpp"
#include "particles/material.hpp"
#include "particles/particle_store.hpp"

namespace gf {

/// One wall surface. A `box` of the case file becomes several planes sharing a group.
struct Wall {
  std::string name;   ///< e.g. "floor", or "box.zmin" for a face of a box
  std::string group;  ///< the case-file name it reports under (equal to name for single walls)
  WallKind kind = WallKind::Plane;
  int material = 0;
  // Geometry at t = 0.
  Vec3 point0;         ///< plane: a point; cylinder: a point on the axis; mesh: its reference (m)
  Vec3 dir0{0, 0, 1};  ///< plane: unit normal towards the particles; cylinder: unit axis; mesh: a
                       ///< unit vector normal to the rotation axis (tracks the rotation)
  double radius = 0;   ///< cylinder radius; mesh: largest distance of a vertex from point0 (m)
  bool inside = true;  ///< cylinder: particles inside
  TriangleMesh mesh;   ///< mesh walls: the surface (vertices follow the motion)
  RigidMotion motion;
  /// Servo (stress control, plane walls): target force servo_pressure x area along -dir, the
  /// area the product of the distances between the walls of each span pair (indices into the
  /// simulation's walls; times the thickness in 2D), speed limit.
  bool servo = false;
  double servo_pressure = 0;  ///< Pa
  std::vector<std::array<std::int32_t, 2>> servo_spans;
  double servo_max_velocity = 0;  ///< m/s
  double servo_until = 1e300;     ///< s
  double servo_gain = 1e-2;       ///< fraction of the force error corrected per step
  Vec3 servo_offset;              ///< displacement by the servo so far, m (checkpointed)
  Vec3 servo_velocity;            ///< current servo velocity, m/s (checkpointed)
  // Current geometry (update_geometry).
  Vec3 point, dir;
  // Reactions of the last force evaluation: force by the particles on the wall, N; torque about
  // the motion centre (rotating walls) or point0's current image, N m.
  Vec3 force, torque;
  /// Normal stiffness of the wall's contacts, sum of dF_n/d(delta) <= 1.5 F_n/delta (Hertz's
  /// exponent; exact for Hertz, 1.5 x for linear springs), N/m: the servo's gain.
  double contact_stiffness = 0;
  /// Temperature of the wall's surface, K (heat: block); NaN: adiabatic (no heat exchanged).
  double temperature = std::numeric_limits<double>::quiet_NaN();
  /// Heat flow from the grains into the wall at the last heat step, W (wall_heat_flows).
  double heat_flow = 0;

  void update_geometry(double t) {
    point = motion.point_at(point0, t) + servo_offset;
    dir = motion.rotate(dir0, t);
    if (kind == WallKind::Mesh) mesh.place(motion, t);
  }
  /// Velocity of the wall surface at p (prescribed motion plus servo).
  GF_HOST_DEVICE Vec3 velocity_at(const Vec3& p, double t) const {
    return motion.velocity_at(p, t) + servo_velocity;
  }
  /// One servo step after a force evaluation: the wall moves along its normal by
  /// dx = g (F_target - F) / K, K = contact_stiffness, F = -force . dir the push of the
  /// particles: a relaxed Newton step on the force that corrects the fraction g (servo_gain) of
  /// the error per step if the packing responded at once. It does not: its slowest mode takes
  /// many steps, so g must be small (1e-3: the wall relaxes over ~1000 steps, slower than the
  /// packing, which then follows quasi-statically; large g pumps the packing into oscillation).
  /// Limited to v_max dt; with no contact, v_max dt towards the particles.
  void servo_step(double t, double dt, double target_force) {
    if (!servo) return;
    if (t >= servo_until || !(target_force > 0)) {
      servo_velocity = {};
      return;
    }
    const double push = -dot(force, dir);
    const double limit = servo_max_velocity * dt;
    double dx =
        contact_stiffness > 0 ? servo_gain * (target_force - push) / contact_stiffness : limit;
    dx = dx > limit ? limit : (dx < -limit ? -limit : dx);
    servo_velocity = (dx / dt) * dir;
    servo_offset += dx * dir;
  }
  Vec3 torque_center() const { return point; }

  /// How far the surface moved since it had `point_b`, `dir_b` (a bound for any point within
  /// `diag` of it): a plane sliding in its own plane (a shear wall) has not moved, nor a
  /// cylinder along its axis. A mesh: its reference point's displacement plus its radius times
  /// |dir - dir_b| = 2 sin(angle / 2), the norm of the change of rotation (dir is normal to the
  /// axis), which bounds the displacement of every vertex.
  double moved_since(const Vec3& point_b, const Vec3& dir_b, double diag) const {
    const Vec3 d = point - point_b;
    if (kind == WallKind::Mesh) return norm(d) + radius * norm(dir - dir_b);
    const double along = dot(d, dir);
    const double shift = kind == WallKind::Plane ? std::abs(along) : norm(d - along * dir);
    return shift + diag * norm(dir - dir_b);
  }

  /// Gap between a sphere surface and the wall (negative = overlap) and the unit normal that
  /// points from the wall to the sphere centre. Planes and cylinders (a mesh: its triangles'
  /// TriangleMesh::sphere_contact).
  GF_HOST_DEVICE double gap(const Vec3& x, double r, Vec3& n) const {
    return surface_gap(kind, point, dir, radius, inside, x, r, n);
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
    std::int32_t element = 0;  ///< mesh walls: the triangle; 0 otherwise
  };
  /// Pairs with a gap below the skin (a mesh wall: one entry per triangle within the skin, in
  /// increasing order). `perm` maps new particle indices to those of the previous
  /// build (empty: unchanged order; -1: a grain added since), so that histories follow
  /// re-ordered particles. `r` is the
  /// bounding radius. `half_axis` (optional): h u of each spherocylinder (zero for round grains),
  /// so that a mesh's triangles are listed by their distance from the axis (r - h the cap
  /// radius) rather than from the bounding sphere: the skin then bounds the move of any point of
  /// the axis, which the rebuild criterion for spherocylinders (their ends' moves) guarantees.
  /// `fixed` (optional): grains with fixed[i] != 0 are left out. A fixed grain and a wall are
  /// both immobile boundaries: a force between them would move nothing and only add a constant to
  /// the wall's reaction (docs/models/fixed_particles.md).
  void build(std::span<const Wall> walls, const Vec3* x, const double* r, std::size_t n,
             double skin, std::span<const std::int64_t> perm = {}, const Vec3* half_axis = nullptr,
             const std::int32_t* fixed = nullptr);
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
  /// Per entry: normal stiffness of its active contacts (servo gain), of the last evaluation.
  std::span<double> stiffness() { return stiffness_; }
  std::size_t bytes() const {
    return (entries_.capacity() + old_entries_.capacity()) * sizeof(Entry) +
           (history_.capacity() + old_history_.capacity() + reactions_.capacity()) * sizeof(Vec3) +
           groups_.capacity() * 8;
  }

 private:
  std::vector<Entry> entries_, old_entries_;
  std::vector<Vec3> history_, old_history_, reactions_;
  std::vector<double> stiffness_;  ///< per entry: normal stiffness of its contacts, N/m
  std::vector<std::int64_t> groups_{0};
  int slots_ = 1;
};

/// Adds the wall contact forces and torques to the particles and accumulates the reactions on
/// the walls. Returns the number of active wall contacts.
/// With `records` (list.entries().size() * list.slots() entries, each ContactRecord{} before the
/// call), records[slots * k + slot] gets the contact of slot `slot` of entry k when it touches:
/// i the grain, j the wall's index in `walls`, the contact point, the unit normal from the wall
/// to the grain, the force on the grain, the overlap and the branch x_i - point.
std::int64_t compute_wall_forces(ParticleStore& p, std::span<Wall> walls, WallContactList& list,
                                 const PairTable<contact::PairCoeffs>& pairs, double t, double dt,
                                 contact::ContactRecord* records = nullptr);

/// Elastic energy stored in all particle-wall contacts (J), for energy balances.
double wall_elastic_energy(const ParticleStore& p, std::span<const Wall> walls,
                           const WallContactList& list,
                           const PairTable<contact::PairCoeffs>& pairs);

/// Heat exchanged with the walls that have a temperature (the others are adiabatic): for each
/// touching grain i adds H (T_w - T_i) to q[i] (W) and H to h[i] (W/K), with the conductance H
/// of conduction model `model` (contact/conduction.hpp) of the grain's and the wall's material
/// (`k_series` per material pair, W/(m K)); sets each wall's heat_flow, summed in entry order.
void wall_heat_flows(const ParticleStore& p, std::span<Wall> walls, const WallContactList& list,
                     int model, const PairTable<double>& k_series, const double* temperature,
                     double* q, double* h);

}  // namespace gf
