// SPDX-License-Identifier: GPL-3.0-or-later
// What a checkpoint of a run whose bodies move keeps besides the flow solver's state.
//
// A moving run (fem_dem::MovingBodyFlow) solves on a mesh that was built around the bodies where
// they were at the last remesh and has moved with them since. To continue it bit-identically a
// checkpoint keeps that mesh as it was built (the solver and the mesh motion are rebuilt on it;
// NavierStokes::State then puts the nodes where they are), the bodies as they were meshed, and
// the bodies' poses, the velocities of the step before (the pose predictor is second-order
// Adams-Bashforth), their loads and the contacts' friction springs. The flow solver's state is
// NavierStokes::State; this struct holds the rest, as plain arrays (it is written to HDF5).
#pragma once

#include <cstdint>
#include <vector>

#include "fluid/fem/mesh.hpp"

namespace gf::fem {

struct MovingFlowState {
  std::vector<BodyShape> reference_bodies;  ///< the bodies the mesh was built around, there [m]
  std::vector<double> body_density;         ///< [kg/m^3] per body (0: prescribed motion)
  Mesh reference_mesh;                      ///< that mesh, its nodes where they were built
  /// Per body x, y [m] and angle [rad]: when the mesh was built, and now.
  std::vector<double> reference_poses, poses;
  /// Per body vx, vy [m/s], omega [rad/s] at the start of the last step (empty before one).
  std::vector<double> previous_velocity;
  double previous_dt = 0.0;  ///< [s] the last step (0 before one)
  /// Per body fx, fy [N/m], torque [N]: loads set from outside (empty: none), and the contacts'
  /// loads of the last step.
  std::vector<double> external_loads, contact_loads;
  /// Friction springs of the gaps in range: key (fem_dem::ContactHistory::key), tangential
  /// stretch [m] and rolling rotation [rad].
  std::vector<std::uint64_t> history_keys;
  std::vector<double> history_stretch, history_roll;
  std::int64_t remeshes = 0;
  double remesh_seconds = 0.0;  ///< [s] wall time of the remeshes so far
};

}  // namespace gf::fem
