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
// flat on a face carries a force at each corner; where two corners meet, each probe carries
// half. A probe inside the other body (or outside the outline) has a negative gap and is pushed
// back out. (Glowinski et al. write the same law with the centres' distance for
// disks; this is its extension to polygons.)
#pragma once

#include <vector>

#include "fluid/fem/navier_stokes.hpp"

namespace gf::fem_dem {

using fem::Vec2;

struct CollisionModel {
  double range = 0.0;  ///< rho [m]; 0: no repulsion
  double force = 0.0;  ///< F_0 [N/m]
};

/// Repulsion loads (force [N/m] and torque about the centre [N]) on the bodies of `spec`, placed
/// where they are, from each other and from the outline.
std::vector<fem::BodyForce> collision_loads(const fem::MeshSpec& spec, const CollisionModel& model);

/// Smallest gap [m] between any two bodies of `spec` or between a body and the outline.
double smallest_gap(const fem::MeshSpec& spec);

}  // namespace gf::fem_dem
