// SPDX-License-Identifier: GPL-3.0-or-later
// Short-range repulsion between bodies in a fluid_fem flow and from the outline walls.
//
// Resolved bodies never touch: the fluid film between them must stay wide enough for the mesh.
// As in Glowinski, Pan, Hesla, Joseph & Periaux, "A fictitious domain approach to the direct
// numerical simulation of incompressible viscous flow past moving rigid bodies: application to
// particulate flow", J. Comput. Phys. 169 (2001) 363, eqs. (4.1)-(4.2), a repulsive force acts
// across a gap g narrower than a range rho:
//   F = F_0 ((rho - g) / rho)^2 n,   g < rho,
// along the line of closest approach n (from the other surface towards this body), applied at
// the middle of the gap, with F_0 [N/m] a force scale of the order of the bodies' buoyant weight.
// Gaps are measured from probes: the centre of a circle (minus its radius), each vertex of a
// polygon; one force per probe and facing surface (another body, each outline edge: a disk in a
// corner feels both walls). Between two polygons both bodies' vertices probe, so a face resting
// flat on a face carries a force at each corner; where two corners meet (each the other's
// closest point), each probe carries half, and a corner facing a corner that itself faces the
// inside of an edge carries nothing (that edge's gap holds the contact). A probe inside the other
// body (or outside the outline) has a negative gap and is pushed back out. (Glowinski et al. write
// the same law with the centres' distance for disks; this is its extension to polygons.)
//
// The law is bounded (F_0 at contact): a film loaded with more than F_0 closes, and the mesh then
// fails. An optional core g_c < rho (CollisionModel::core) makes the force grow as 1 / g inside
// it, like a lubrication film's resistance,
//   F = F_0 ((rho - g) / rho)^2 g_c / g,   g < g_c   (continuous at g_c; g_c / g capped at 100),
// so that a film holds a load L > F_0 at g ~ g_c F_0 / L instead of closing.
//
// Friction (optional, CollisionModel::friction > 0): each gap in range also carries a tangential
// force, a linear spring on the tangential displacement accumulated while the gap stays in range,
// capped by Coulomb's law (Cundall & Strack, Geotechnique 29 (1979) 47):
//   xi += v_t dt,   F_t = -k_t xi,   |F_t| <= mu F_n  (at the cap: sliding, xi = -F_t / k_t),
// with v_t the velocity of the probe body's material point at the middle of the gap (where the
// force acts, so rolling without slip does no work) relative to the facing body's material point
// there, along t = (-n_y, n_x); F_n the repulsion of that gap and k_t [N/m^2] a tangential
// stiffness per unit depth (by default 2 F_0 / rho, the repulsion's stiffness at zero gap; at a
// resting gap the normal stiffness is lower, so k_t is then a few times the normal one). A grain
// resting in a film on a slope then holds while tan(slope) < mu and slides above it, as a DEM grain
// does; the history (xi per probe and facing surface) is ContactHistory, kept from step to step.
//
// Rolling resistance (optional, CollisionModel::rolling_friction > 0, with friction): each gap in
// range also carries a torque, a rotational spring on the relative rotation accumulated while the
// gap stays in range, capped at mu_r R F_n (the elastic-plastic spring-dashpot model of Iwashita &
// Oda, J. Eng. Mech. 124 (1998) 285, and of Ai, Chen, Rotter & Ooi, Powder Technol. 206 (2011)
// 269, without its dashpot):
//   theta += (omega_probe - omega_facing) dt,   M = -k_r theta,   |M| <= mu_r R F_n,
// on the probe body (-M on the facing one), with R = r_a r_b / (r_a + r_b) the lever arms r of
// the two bodies from their centres to the middle of the gap (r_a against the outline) and
// k_r = k_t R^2. A disk resting on a floor then holds while tan(slope) < mu_r and rolls above it.
// A face resting on a face carries it at each corner, its cap with that corner's share of F_n.
#pragma once

#include <cstdint>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "fluid/fem/navier_stokes.hpp"

namespace gf::fem_dem {

using fem::Vec2;

struct CollisionModel {
  double range = 0.0;                 ///< rho [m]; 0: no repulsion
  double force = 0.0;                 ///< F_0 [N/m]
  double friction = 0.0;              ///< Coulomb coefficient mu of the tangential force; 0: none
  double tangential_stiffness = 0.0;  ///< k_t [N/m^2]; 0: 2 F_0 / rho
  double rolling_friction = 0.0;      ///< mu_r of the rolling torque (needs friction > 0); 0: none
  double core = 0.0;  ///< g_c [m]: below it the force grows as g_c / g (see above); 0: none

  /// The tangential stiffness in use [N/m^2].
  [[nodiscard]] double spring() const {
    return tangential_stiffness > 0 ? tangential_stiffness : 2.0 * force / range;
  }
};

/// The springs of one gap in range: tangential stretch xi [m] and rolling rotation [rad].
struct GapSprings {
  double slide = 0.0;
  double roll = 0.0;
  bool operator==(const GapSprings&) const = default;
};

/// The springs of every gap in range (one per probe and facing surface), carried from one step
/// to the next; a gap that opens past the range forgets them.
class ContactHistory {
 public:
  [[nodiscard]] std::size_t size() const { return springs_.size(); }
  /// Tangential stretch of the gaps from probe `probe` of body `body` to the outline edge `edge`
  /// (`other` = -1) or to body `other` (edge 0); 0 when not in range.
  [[nodiscard]] double stretch(int body, int probe, int other, int edge) const;
  /// Rolling rotation of that gap [rad]; 0 when not in range.
  [[nodiscard]] double rolled(int body, int probe, int other, int edge) const;
  [[nodiscard]] static std::uint64_t key(int body, int probe, int other, int edge);
  /// Every gap's (key, springs), by key (for checkpoints), and the history made of such a list.
  [[nodiscard]] std::vector<std::pair<std::uint64_t, GapSprings>> entries() const;
  static ContactHistory from_entries(const std::vector<std::uint64_t>& keys,
                                     const std::vector<double>& stretch,
                                     const std::vector<double>& roll);

 private:
  friend std::vector<fem::BodyForce> collision_loads(const fem::MeshSpec&, const CollisionModel&,
                                                     const std::vector<fem::BodyMotion>&, double,
                                                     const ContactHistory&, ContactHistory&);
  std::unordered_map<std::uint64_t, GapSprings> springs_;
};

/// F / F_0 of the repulsion across a gap g [m]: ((rho - g) / rho)^2, times the core's g_c / g.
double repulsion_scale(const CollisionModel& model, double g);

/// Repulsion loads (force [N/m] and torque about the centre [N]) on the bodies of `spec`, placed
/// where they are, from each other and from the outline (no friction).
std::vector<fem::BodyForce> collision_loads(const fem::MeshSpec& spec, const CollisionModel& model);

/// Repulsion and friction loads: as above, plus the tangential forces of model.friction, their
/// springs advanced over dt [s] with the bodies' velocities `velocity` (one per body; the outline
/// is at rest) and kept in `history`. For a step from one pose to the next, pass the velocities
/// of that displacement ((next - now) / dt), not those of the step's start: the springs then
/// stretch as the bodies move, and BDF2 does not pump energy into a resting contact.
std::vector<fem::BodyForce> collision_loads(const fem::MeshSpec& spec, const CollisionModel& model,
                                            const std::vector<fem::BodyMotion>& velocity, double dt,
                                            ContactHistory& history);
/// The same, the springs read from `before` and written to `after` (the state of the gaps in
/// range after this step; `before` is left as it was, e.g. until the step is accepted).
std::vector<fem::BodyForce> collision_loads(const fem::MeshSpec& spec, const CollisionModel& model,
                                            const std::vector<fem::BodyMotion>& velocity, double dt,
                                            const ContactHistory& before, ContactHistory& after);

/// The narrowest gap of a placement of the bodies: its width g [m] (negative: overlap) from a
/// probe of body `body` to body `other`, or (other = -1) to the outline's edge `edge`.
struct NarrowGap {
  double g = std::numeric_limits<double>::infinity();
  int body = -1;
  int other = -1;
  int edge = -1;
};
/// The narrowest gap between any two bodies of `spec` or between a body and the outline (g
/// infinite, body -1 without bodies).
NarrowGap narrowest_gap(const fem::MeshSpec& spec);
/// Its width [m].
double smallest_gap(const fem::MeshSpec& spec);

}  // namespace gf::fem_dem
