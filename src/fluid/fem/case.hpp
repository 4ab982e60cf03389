// SPDX-License-Identifier: GPL-3.0-or-later
// The `fluid_fem:` block of a case file: parsed configuration and the standalone run driver.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fluid/fem/moving_state.hpp"
#include "fluid/fem/navier_stokes.hpp"
#include "fluid/fem/time_stepping.hpp"

namespace gf::fem {

/// Time function of an inflow: constant 1, sin(2 pi t / period), or a smooth ramp
/// (1 - cos(pi t / duration)) / 2 up to `duration`, then 1.
struct TimeFunctionSpec {
  enum class Kind { Constant, Sine, Ramp };
  Kind kind = Kind::Constant;
  double period = 1.0;    ///< [s]
  double duration = 1.0;  ///< [s]
  [[nodiscard]] double operator()(double t) const;
};

struct FemOutputConfig {
  double vtk_every = 0.0;         ///< [s]; 0: only the initial and final states
  double csv_every = 0.0;         ///< [s]; 0: every accepted step
  std::vector<Vec2> probes;       ///< points where u and p are recorded [m]
  double coef_velocity = 0.0;     ///< if > 0: C_D, C_L = 2 F / (rho U^2 L) columns [m/s]
  double coef_length = 0.0;       ///< [m]
  double checkpoint_every = 0.0;  ///< [s]; 0: a checkpoint only at the end (or at a stop)
};

/// Everything the `fluid_fem:` block defines (units SI).
struct FemCaseConfig {
  std::string file;  ///< case file, for messages
  std::string name;  ///< the case's `name` (top level; for the echo of the resolved case)
  std::string output_directory;  ///< the case's `output.directory` (top level) [path]
  MeshSpec mesh;
  double density = 1.0;     ///< [kg/m^3]
  double viscosity = 1e-3;  ///< kinematic [m^2/s]
  std::vector<OutlineBc> outline_bc;
  std::vector<TimeFunctionSpec> inflow_time;  ///< per outline edge
  std::vector<std::string> body_names;
  /// Per body: the prescribed rigid velocity, or for a free body its initial velocity.
  std::vector<BodyMotion> body_motion;
  /// Per body: 0 for a body whose velocity is prescribed, else the solid density [kg/m^3] of a
  /// free body (moved by the fluid's force and torque, buoyancy and gravity). A case with a free
  /// body runs on a moving mesh, on which every body moves with its velocity (see
  /// docs/models/fluid_fem.md, "Free bodies and moving meshes").
  std::vector<double> body_density;
  Vec2 gravity;      ///< [m/s^2], acting on free bodies (the pressure is the dynamic one)
  GravityTilt tilt;  ///< `tilt`: the domain turning, gravity with it
  /// Moving mesh: remesh when a cell's shape quality falls below remesh_ratio x its value on the
  /// fresh mesh or below remesh_quality (the defaults of fem_dem::MovingBodyOptions).
  double remesh_ratio = 0.5;
  double remesh_quality = 0.2;
  /// Repulsion across gaps narrower than repulsion_range [m] with the force scale
  /// repulsion_force [N/m] (fem_dem::CollisionModel; 0: none).
  double repulsion_range = 0.0;
  double repulsion_force = 0.0;
  /// Coulomb friction coefficient of the repulsion's gaps (0: none) and the tangential spring
  /// [N/m^2] carrying it (0: 2 repulsion_force / repulsion_range).
  double repulsion_friction = 0.0;
  double repulsion_tangential_stiffness = 0.0;
  /// Rolling resistance mu_r of the repulsion's gaps (0: none; only with friction).
  double repulsion_rolling_friction = 0.0;
  /// Gap [m] below which the repulsion grows as 1 / gap (0: Glowinski's bounded law only).
  double repulsion_core = 0.0;
  bool steady = true;
  /// unsteady: start from the steady solution for the boundary data at t = 0 (consistent initial
  /// conditions by Newton) instead of from rest
  bool initial_steady = false;
  TimeControl time;
  NewtonOptions newton;
  bool newton_nested = true;  ///< steady solves: start from a coarser mesh's solution
  FemOutputConfig output;
  /// What the case asks that works but gives poor results (e.g. a gap between bodies narrower
  /// than the mesh size there), for `grainflow check` and the start of a run.
  std::vector<std::string> warnings;

  /// Whether a body is free: then the run moves the bodies and the mesh.
  [[nodiscard]] bool has_free_bodies() const {
    for (const double d : body_density)
      if (d > 0) return true;
    return false;
  }
};

/// Words and places an error of the block: (the YAML node it is about, the mark of its key when
/// the error is about the key itself, else a null mark, its key path, the message "expected ...,
/// found ...") -> the whole text of the gf::InputError. The case loader passes the shared
/// reader's (io/input: it names a --set option instead of a place in the file for an
/// overridden value); without one it is "FILE:LINE:COLUMN: error: KEY.PATH: MESSAGE".
using ErrorText = std::function<std::string(const YAML::Node& at, const YAML::Mark& key_mark,
                                            const std::string& path, const std::string& message)>;

/// Parses the `fluid_fem` block (the node under the key, not the document root). Any error
/// (unknown key, wrong type, value out of range, missing key) throws gf::InputError with
/// file:line:column, the key path, what was expected and what was found (worded by `error_text`
/// when given).
FemCaseConfig parse_fluid_fem(const YAML::Node& block, const std::string& file,
                              const ErrorText& error_text = {});

/// YAML text of the resolved case (a whole case file: `name`, the `fluid_fem` block with every
/// default filled in, `output.directory`), opening with a comment naming the program version and
/// the case file. Reading it back gives the same FemCaseConfig.
std::string echo_fluid_fem_yaml(const FemCaseConfig& cfg, const std::string& program_version);

/// build_mesh(cfg.mesh) with its failures worded for the user: a geometry the mesher cannot
/// mesh (CGAL's errors included) is a gf::InputError naming the case file and its keys.
Mesh build_case_mesh(const FemCaseConfig& cfg);

/// Derived numbers of a case for `grainflow check` (label, value), meshing it to count cells
/// and unknowns: the inflow's mean speed U, the largest body's size D, Re = U D / nu, and for
/// unsteady runs the steps and the Courant (U_max dt / h_body) and viscous (nu dt / h_body^2)
/// numbers of the first step on the finest cells; per free body its mass and moment of inertia
/// per unit depth, density ratio, Archimedes number, and a settling speed estimate (Faxen's drag
/// of a cylinder midway between two walls at the body's distance from the outline) with its
/// Reynolds number.
std::vector<std::pair<std::string, std::string>> describe_case(const FemCaseConfig& cfg);

/// An unsteady fluid_fem run between two steps: what a checkpoint holds to continue it
/// bit-identically (the caller writes and reads it; see simulation/fem_case.cpp).
struct FemCheckpoint {
  NavierStokes::State flow;
  TimeLoopState loop;
  std::int64_t steps = 0;  ///< accepted steps since the run began (over all restarts)
  double next_vtk = 0.0, next_csv = 0.0, next_checkpoint = 0.0;  ///< [s] output schedule
  std::int64_t n_fields = 0;    ///< fem_fields_*.vtu written so far (the numbering continues)
  std::uint64_t mesh_hash = 0;  ///< mesh_hash() of the mesh it belongs to
  /// Time of the last field data set the schedule wrote (-inf: none), up to which --append keeps
  /// fem_fields.pvd: a data set written only because the run stopped there is dropped. Empty for
  /// a checkpoint of a build before 2026-12-01 (then everything up to its time is kept).
  std::optional<double> fields_until;
  std::int64_t runs = 1;    ///< runs over restarts up to this checkpoint, its own included
  double wall_seconds = 0;  ///< their wall time up to this checkpoint [s] (NaN: not recorded)
  /// A run with free bodies: the moving mesh and the bodies (mesh_hash is that of the mesh the
  /// run started on).
  std::optional<MovingFlowState> moving;
};

/// Checkpoint hooks of run_fluid_fem: `save` writes one (empty: none written); `resume`
/// continues from one instead of starting at t = 0.
struct FemCheckpointIo {
  std::function<void(const std::filesystem::path&, const FemCheckpoint&)> save;
  const FemCheckpoint* resume = nullptr;
  /// With resume: continue the CSV and ParaView series of the run in output_dir (rows and data
  /// sets up to the checkpoint's time are kept) instead of starting them afresh.
  bool append = false;
};

/// A flow whose bodies move through the domain on a moving mesh (cases with free bodies). The
/// coupling layer provides it (coupling/fem_dem MovingBodyFlow, wrapped by simulation/fem_case):
/// fluid/fem does not depend on that module.
/// Its flow() is the flow on the current mesh (a remesh replaces it: do not keep the
/// reference); a step (Stepper) is taken with BDF of the given order, lower after the start and
/// after a remesh.
class FemMovingFlow : public Stepper {
 public:
  /// Centre [m] and rotation angle since t = 0 [rad, counter-clockwise] of body j.
  [[nodiscard]] virtual Vec2 centre(int body) const = 0;
  [[nodiscard]] virtual double angle(int body) const = 0;
  /// Times the domain was meshed again.
  [[nodiscard]] virtual int remeshes() const = 0;
  /// What a checkpoint keeps besides flow().state(), and the continuation from both (a state of
  /// another problem throws gf::Error).
  [[nodiscard]] virtual MovingFlowState state() const = 0;
  virtual void restore(const NavierStokes::State& flow, const MovingFlowState& s) = 0;
};

/// Makes the moving flow of a case with free bodies from its problem (mesh built, bodies at
/// their t = 0 places).
using FemMovingFlowFactory =
    std::function<std::unique_ptr<FemMovingFlow>(FlowProblem, const FemCaseConfig&)>;

/// FNV-1a hash of a mesh's node coordinates and cells: the same case meshed again gives the
/// same value, any other mesh (almost surely) another.
std::uint64_t mesh_hash(const Mesh& m);

/// Builds the mesh and runs the case, writing into output_dir: fem_mesh.vtu, fem_fields_*.vtu +
/// fem_fields.pvd (ParaView series), fem_forces.csv (per body: reaction force and torque,
/// stress-integrated force, coefficients if configured), fem_probes.csv, fem_summary.txt.
/// Every file is written atomically. max_steps >= 0 stops an unsteady run after that many steps
/// (smoke tests: `grainflow run --steps N`). Unsteady runs with `io.save` write
/// fem_checkpoint_NNNNNNN.h5 every output.checkpoint_every, at a stop, and
/// fem_checkpoint_final.h5 at the end. Returns the SIGINT / SIGTERM that ended an unsteady run
/// early (its outputs up to the last step are written), else 0; throws gf::Error, and
/// gf::InputError for a checkpoint of another mesh or of a steady case.
///
/// A case with free bodies runs on a moving mesh made by `moving` (required then): fixed steps
/// (a failed step is retried with a quarter of the step, as on a fixed mesh), fem_forces.csv
/// gains per body NAME.x, NAME.y, NAME.angle, NAME.vx, NAME.vy, NAME.omega, every field file
/// holds the moved mesh, the summary counts the remeshes; its checkpoints also keep the moving
/// mesh and the bodies (FemCheckpoint::moving), and it continues from them bit-identically.
int run_fluid_fem(const FemCaseConfig& cfg, const std::filesystem::path& output_dir,
                  int max_steps = -1, const FemCheckpointIo& io = {},
                  const FemMovingFlowFactory& moving = {});

}  // namespace gf::fem
