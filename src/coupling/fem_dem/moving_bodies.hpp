// SPDX-License-Identifier: GPL-3.0-or-later
// Bodies moving through a 2D fluid_fem flow: ALE mesh motion, remeshing, rigid-body poses.
//
// The first part of resolved FEM-DEM (DESIGN.md, method 3): bodies -- free (moved by the
// fluid's force and torque, buoyancy and gravity, solved monolithically with the flow, see
// fem::FlowProblem::body_density) or with a prescribed rigid velocity -- move through the fluid
// on a body-fitted mesh. Each step the mesh nodes follow the bodies by harmonic blending: node k
// moves by sum_b w_b(k) (T_b(x_k) - x_k), where T_b is body b's rigid motion since the mesh was
// built and w_b is the P1 harmonic function equal to 1 on body b and 0 on the outline and on the
// other bodies (so cells next to a body move almost rigidly with it, and the outline stays put).
// The flow is solved in ALE form on the moved mesh (fem::NavierStokes::move_mesh). When a cell's
// shape degrades past a bound, the domain is meshed again around the bodies where they are and
// the velocity is interpolated onto the new mesh; the BDF history restarts there (one BDF1
// step). Bodies keep apart by a short-range repulsion with optional Coulomb friction
// (collision.hpp); grains never touch, so restitution comes from the fluid film only.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "coupling/fem_dem/collision.hpp"
#include "fluid/fem/moving_state.hpp"
#include "fluid/fem/navier_stokes.hpp"

namespace gf::fem_dem {

using fem::Vec2;

/// Position of a body's centre [m] and its rotation angle [rad] (counter-clockwise).
struct RigidPose {
  Vec2 centre;
  double angle = 0.0;
};

/// Harmonic blending of the bodies' rigid motions over the nodes of one mesh.
class MeshMotion {
 public:
  /// Solves the P1 Laplace problems for the weights of each body on `mesh`.
  MeshMotion(const fem::Mesh& mesh, int n_bodies);

  /// Node positions [m] when the bodies, at `reference` when the mesh was built, are at `now`.
  [[nodiscard]] std::vector<Vec2> nodes(const std::vector<RigidPose>& reference,
                                        const std::vector<RigidPose>& now) const;
  /// Weight of body b at P2 node k (1 on the body, 0 on the outline and other bodies).
  [[nodiscard]] double weight(int body, int node) const { return w_[body][node]; }
  /// The node positions of the mesh it was built on [m].
  [[nodiscard]] const std::vector<Vec2>& reference_nodes() const { return ref_nodes_; }

 private:
  std::vector<Vec2> ref_nodes_;
  std::vector<std::vector<double>> w_;  // per body, per P2 node
};

/// Shape quality 4 sqrt(3) A / (l1^2 + l2^2 + l3^2) of the straight triangle through a cell's
/// vertices: 1 for an equilateral triangle, -> 0 for a flat one, < 0 for an inverted one.
double shape_quality(Vec2 a, Vec2 b, Vec2 c);
/// shape_quality of every cell of a mesh.
std::vector<double> qualities(const fem::Mesh& mesh);

struct MovingBodyOptions {
  /// Remesh when a cell's shape quality falls below this fraction of its value on the fresh mesh
  double remesh_ratio = 0.5;
  /// ... or below this value.
  double remesh_quality = 0.2;
  /// Repulsion across narrow gaps, evaluated at the poses of the step's end (off by default).
  CollisionModel collision;
  /// A warning when a film thins below this fraction of the repulsion range (then the bounded
  /// law pushes with more than (1 - f)^2 of its force scale, nearly the most it can, and a larger
  /// load closes the film, which the mesh cannot follow) or, with a core, of the core (the film
  /// then carries 1 / f force scales in a gap that needs as small cells), and again each time it
  /// halves; 0: none.
  double gap_warning = 0.05;
  /// The bodies' names for messages (empty: "body k").
  std::vector<std::string> body_names;
};

/// A fluid_fem flow whose bodies move (fixed steps; see the file comment).
class MovingBodyFlow {
 public:
  /// `problem` holds the bodies where they are at t = 0 and their (initial) velocities in
  /// body_motion; its mesh must have been built from its spec.
  explicit MovingBodyFlow(fem::FlowProblem problem, MovingBodyOptions options = {});

  [[nodiscard]] const fem::NavierStokes& flow() const { return *flow_; }
  [[nodiscard]] fem::NavierStokes& flow() { return *flow_; }
  [[nodiscard]] const std::vector<RigidPose>& poses() const { return poses_; }
  [[nodiscard]] double time() const { return flow_->time(); }
  [[nodiscard]] int remeshes() const { return remeshes_; }
  /// Contact loads (repulsion and friction; force [N/m], torque about the centre [N]) on each
  /// body in the last step.
  [[nodiscard]] const std::vector<fem::BodyForce>& contact_loads() const { return contact_loads_; }
  /// Friction springs of the contacts in range after the last step.
  [[nodiscard]] const ContactHistory& contact_history() const { return history_; }
  /// Wall time spent remeshing (meshing, new solver set-up, interpolation) [s].
  [[nodiscard]] double remesh_seconds() const { return remesh_seconds_; }
  /// The narrowest film after the last step (with a repulsion; g infinite before the first).
  [[nodiscard]] const NarrowGap& narrowest_gap() const { return gap_; }
  /// How many thin-film warnings (MovingBodyOptions::gap_warning) the run gave so far.
  [[nodiscard]] int gap_warnings() const { return gap_warnings_; }

  /// Advances by dt [s] with BDF of the given order (lower right after the start and after a
  /// remesh): predicts the poses at t + dt from the bodies' velocities (second-order
  /// Adams-Bashforth), moves or rebuilds the mesh, and solves. Throws gf::Error when Newton
  /// does not converge.
  fem::StepResult step(double dt, int order, const fem::NewtonOptions& newton);

  /// The same step, tentative (for step-size control, fem::integrate): the flow is solved on the
  /// moved (or new) mesh, and accept_step() takes the poses and contacts, reject_step() moves
  /// the mesh back (a remesh done for the step stays: the flow on the new mesh is the same
  /// state). rtol, atol: the error estimate's tolerances (fem::NavierStokes::try_step). A step
  /// the mesh cannot follow, or whose Newton solve fails, returns newton.converged = false
  /// (StepResult::failure says why when Newton was not the reason).
  fem::StepResult try_step(double dt, int order, const fem::NewtonOptions& newton,
                           double rtol = 1.0, double atol = 1.0, bool neighbour_errors = false);
  void accept_step();
  void reject_step();

  /// A force [N/m] and torque about the centre [N] on a free body, besides the fluid's, gravity
  /// and the repulsion (e.g. DEM contacts), applied in every following step until changed
  /// (remeshing keeps it).
  void set_external_load(int body, Vec2 force, double torque);

  /// Meshes the domain again with the bodies at their current poses and interpolates the flow.
  void remesh();

  /// What a checkpoint keeps of the run between two steps besides flow().state()
  /// (fluid/fem/moving_state.hpp).
  [[nodiscard]] fem::MovingFlowState state() const;
  /// Continues from a checkpoint of a run of the same problem (same outline, bodies' shapes and
  /// densities): rebuilds the solver and the mesh motion on the kept mesh and restores the flow,
  /// the poses and the contacts, so that the following steps are those the checkpointed run
  /// took. Throws gf::Error for a state of another problem.
  void restore(const fem::NavierStokes::State& flow, const fem::MovingFlowState& s);

 private:
  fem::StepResult try_step_or_throw(double dt, int order, const fem::NewtonOptions& newton,
                                    double rtol, double atol, bool neighbour_errors);
  [[nodiscard]] std::vector<RigidPose> predicted_poses(double dt) const;
  /// The spec's bodies placed at `poses` (polygons' vertices moved rigidly).
  [[nodiscard]] fem::MeshSpec placed_spec(const std::vector<RigidPose>& poses) const;
  /// The poses the mesh follows (circles: translation only).
  [[nodiscard]] std::vector<RigidPose> mesh_poses(const std::vector<RigidPose>& poses) const;
  [[nodiscard]] double quality_ratio(const std::vector<Vec2>& nodes, double& worst) const;
  /// The mesh motion and reference qualities of a freshly built flow_ (constructor, remesh).
  void start_mesh();
  /// "2.5e-05 m, between 'a' and the outline's edge 3" for messages.
  [[nodiscard]] std::string describe(const NarrowGap& gap) const;
  /// The thin-film warning after an accepted step (MovingBodyOptions::gap_warning).
  void watch_gap();

  MovingBodyOptions options_;
  std::unique_ptr<fem::NavierStokes> flow_;
  std::unique_ptr<MeshMotion> motion_;
  fem::MeshSpec reference_spec_;  // the spec the current mesh was built from
  std::vector<RigidPose> reference_poses_, poses_;
  std::vector<fem::BodyMotion> previous_velocity_;  // at the step before the last (AB2)
  double previous_dt_ = 0.0;
  std::vector<double> reference_quality_;      // per cell, on the fresh mesh
  std::vector<fem::BodyForce> external_;       // per body (set_external_load)
  std::vector<fem::BodyForce> contact_loads_;  // per body, of the last step
  ContactHistory history_;
  // the tentative step's (try_step until accept_step / reject_step)
  bool pending_ = false;
  std::vector<RigidPose> pending_poses_;
  ContactHistory pending_history_;
  std::vector<fem::BodyForce> pending_contact_;
  std::vector<fem::BodyMotion> pending_velocity_;
  double pending_dt_ = 0.0;
  NarrowGap pending_gap_, gap_;
  double warned_gap_ = std::numeric_limits<double>::infinity();  // the last warning's gap
  int gap_warnings_ = 0;
  int remeshes_ = 0;
  double remesh_seconds_ = 0.0;
};

}  // namespace gf::fem_dem
