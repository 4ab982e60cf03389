// SPDX-License-Identifier: GPL-3.0-or-later
// Volume-averaged incompressible Navier-Stokes on a uniform staggered Cartesian grid: the fluid
// of unresolved CFD-DEM ("model A", set I of Zhou, Kuang, Chu & Yu, J. Fluid Mech. 661 (2010)
// 482, eqs. (1)-(2); Anderson & Jackson, Ind. Eng. Chem. Fundam. 6 (1967) 527):
//
//   d(eps rho u)/dt + div(eps rho u u) = -eps grad p + div(eps mu grad u) + eps rho g + S,
//   d(eps)/dt + div(eps u) = 0,            S = S_explicit - K u,
//
// with eps the fluid fraction and d(eps)/dt given per cell by the caller, rho and mu constant,
// S the momentum the particles give the fluid per unit volume (K >= 0 is treated implicitly).
// The solver knows nothing about particles; src/coupling maps them onto eps, K and S.
//
// Discretisation (details and sources in docs/models/fluid_fv.md): MAC grid (Harlow & Welch,
// Phys. Fluids 8 (1965) 2182), p, eps, K, S at cell centres, velocity component a on the faces
// normal to axis a. Momentum in advective form eps rho (du/dt + u . grad u), which equals the
// conservative form above wherever continuity holds and keeps uniform flow uniform whatever
// eps does. Time: incremental pressure correction (Goda 1979; van Kan, SIAM J. Sci. Stat.
// Comput. 7 (1986) 870) with BDF2, implicit viscous and drag terms, convection extrapolated
// to t^{n+1} (SBDF2, Ascher, Ruuth & Wetton, SIAM J. Numer. Anal. 32 (1995) 797) -- second
// order in time for the velocity. Convection: central or van Leer-limited (bounded) fluxes.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/mat3.hpp"
#include "core/vec3.hpp"
#include "fluid/fv/boundary.hpp"
#include "fluid/fv/grid.hpp"
#include "fluid/fv/spd_solver.hpp"

namespace gf::fluid {

/// Convected value at the faces of the momentum control volumes.
enum class Convection {
  Central,  ///< second order; oscillates once the cell Reynolds number u h / nu exceeds ~2
  VanLeer,  ///< second order where smooth, bounded (TVD) at extrema (van Leer, JCP 14 (1974) 361)
  Upwind,   ///< first order, bounded; adds a numerical viscosity |u| h / 2 (OpenFOAM's `upwind`)
};

/// Physical parameters, boundary conditions and numerical choices.
struct FluidSettings {
  double density = 1000.0;          ///< rho [kg/m^3]
  double dynamic_viscosity = 1e-3;  ///< mu [Pa s]
  Vec3 gravity{};                   ///< g [m/s^2]
  /// One condition per box face, indexed by box_face_index(axis, side); in 2D the z faces are
  /// ignored.
  std::array<BoundaryCondition, 6> boundary{};
  Convection convection = Convection::VanLeer;
  /// 2: BDF2 (the first step is backward Euler); 1: backward Euler, for tests only (with
  /// convection it is not energy-stable, docs/models/fluid_fv.md)
  int time_order = 2;
  double max_courant = 1.0;  ///< step() refuses a dt with max_cfl(dt) above this
  /// Auto: Direct in 2D and on thin 3D grids (slabs, narrow columns), else JacobiCG
  /// (docs/models/fluid_fv.md, "Linear solvers").
  LinearSolver pressure_solver = LinearSolver::Auto;
  LinearSolver momentum_solver = LinearSolver::Auto;
  double pressure_tolerance = 1e-10;  ///< relative residual of the pressure-correction equation
  double momentum_tolerance = 1e-12;  ///< relative residual of the momentum predictor
  int max_iterations = 10000;         ///< of each CG solve
  /// Without a pressure outlet the volume of fluid is fixed: the net inflow through inlets
  /// must balance sum(d eps/dt) V. step() throws when the mismatch exceeds this fraction of the
  /// flux scale (see StepReport::compatibility_defect), and otherwise removes it uniformly.
  double max_compatibility_defect = 1e-6;
};

/// What one step did.
struct StepReport {
  int order = 1;                    ///< BDF order used
  double courant = 0.0;             ///< max_cfl(dt) at the start of the step
  int momentum_iterations = 0;      ///< CG iterations, summed over components
  int pressure_iterations = 0;      ///< CG iterations of the pressure correction
  double pressure_residual = 0.0;   ///< ||residual||_2 of the pressure correction [1/s]
  double compatibility_defect = 0;  ///< closed domains: |net inflow| / flux scale
  bool refactorized = false;        ///< matrices were re-assembled (eps, K or dt changed)
};

/// Volume-averaged incompressible Navier-Stokes solver (see the file header). Typical use:
///
///     VolumeAveragedNS fluid(grid, settings);
///     while (...) {
///       fluid.set_fluid_fraction(eps_new, deps_dt);    // eps at t + dt, d eps/dt over the step
///       fluid.set_momentum_source(s_explicit, k);      // S = s_explicit - k u  [N/m^3]
///       fluid.step(dt);
///       ... fluid.cell_velocity(c), fluid.pressure_gradient(c) ...
///     }
///
/// Fields are flat std::vector<double>: cell fields indexed by Grid::index, the velocity
/// component a by Grid::face_index(a, ...). Cell loops run through gf::exec::parallel_for.
class VolumeAveragedNS {
 public:
  /// Checks the settings (gf::Error with the reason when impossible) and sets u = 0, eps = 1,
  /// p = the outlet pressure (0 without outlet), no momentum source.
  VolumeAveragedNS(const Grid& grid, FluidSettings settings);

  // --- state and inputs -------------------------------------------------------------------

  /// Sets the velocity by sampling u0(x) [m/s] at the face centres (boundary faces keep their
  /// conditions); the next step starts a new BDF history (backward Euler).
  void set_velocity(const std::function<Vec3(const Vec3&)>& u0);
  /// Sets the pressure [Pa] per cell (an initial condition, e.g. hydrostatic). In a closed
  /// domain only differences matter; its mean is set to zero at the next step.
  void set_pressure(std::span<const double> p);
  /// Fluid fraction eps (0 < eps <= 1) at the end of the next step and its rate d eps/dt [1/s]
  /// over that step, per cell. Continuity is enforced as div(eps u) = -d eps/dt.
  void set_fluid_fraction(std::span<const double> eps, std::span<const double> eps_rate);
  /// Particle momentum source S = s_explicit - k u per cell: s_explicit [N/m^3] and the drag
  /// coefficient k >= 0 [kg/(m^3 s)], which is treated implicitly (stable for any k dt / rho).
  void set_momentum_source(std::span<const Vec3> s_explicit, std::span<const double> k);
  /// A second incompressible phase that shares the pressure (the solids of a two-fluid model),
  /// per face normal to each axis (the layout of face_velocity; spans of the face counts):
  struct SharedPhase {
    std::array<std::span<const double>, 3> flux;      ///< its predicted volume flux F* [m/s]
    std::array<std::span<const double>, 3> fraction;  ///< its volume fraction a at the face
    /// how its flux follows its velocity: F = F* + carried du_s (the upwind fraction) [1]
    std::array<std::span<const double>, 3> carried;
    /// its momentum diagonal less the drag, a rho_s / dt [kg/(m^3 s)]; 0 where it has no
    /// momentum equation (walls)
    std::array<std::span<const double>, 3> inertia;
  };
  /// While set, the pressure correction phi enforces the continuity of the mixture,
  /// div(eps u + F) = 0, in place of div(eps u) = -d eps/dt (the rate of set_fluid_fraction is
  /// then not used), so neither phase can fill or empty a cell on its own. Both phases' face
  /// momentum equations respond to grad(phi) together, coupled by the implicit drag K of
  /// set_momentum_source (the same K acts on the second phase):
  ///   A_f du - K du_s = -eps grad(phi),   (inertia + K) du_s - K du = -a grad(phi)
  /// (A_f = eps rho c0 / dt + K): with a strong drag the two move together, as they do, and the
  /// drag each phase feels after the correction is the one the other feels (correcting each on its
  /// own let the fluid's share of the drag lag a step behind, which in a gas-fluidised bed loaded
  /// the bed with 20-50 % more than its weight). correction_gradient and shared_response give the
  /// caller du_s = -shared_response grad(phi). All spans empty removes the phase.
  void set_shared_phase(const SharedPhase& phase);
  /// Velocity response of the shared phase to grad(phi) [m^3 s/kg] of the last correction.
  [[nodiscard]] std::span<const double> shared_response(int a) const { return shared_response_[a]; }
  /// grad(phi) [Pa/m] of the last step's pressure correction on the faces normal to axis a (on
  /// an outlet face from phi = 0 on the face; zero on walls and inlets), for a shared phase.
  [[nodiscard]] std::span<const double> correction_gradient(int a) const { return grad_phi_[a]; }
  /// Replaces the condition on one box face by one of the same kind (new values).
  void set_boundary(BoxFace face, const BoundaryCondition& bc);

  /// One time step of size dt [s] (BDF2 after the first step if time_order = 2). Throws
  /// gf::Error when max_cfl(dt) exceeds settings().max_courant.
  StepReport step(double dt);

  /// Everything a restart needs to continue bit-identically: the velocities of the last two
  /// steps, the convection term of the last step, pressure, the inputs last set, the linear
  /// solvers' starting guesses, and the clock. Arrays are named; Vec3 arrays are flattened.
  struct State {
    double time = 0.0, dt_prev = 0.0;
    std::int64_t n_steps = 0;
    int history = 0;
    std::vector<std::pair<std::string, std::vector<double>>> arrays;
  };
  [[nodiscard]] State state() const;
  /// Restores a state() of a solver on the same grid and settings (gf::Error when an array is
  /// missing or has another size).
  void restore(const State& state);

  // --- results ------------------------------------------------------------------------------

  [[nodiscard]] const Grid& grid() const { return grid_; }
  [[nodiscard]] const FluidSettings& settings() const { return s_; }
  [[nodiscard]] double time() const { return time_; }
  [[nodiscard]] std::int64_t step_count() const { return n_steps_; }

  /// Velocity component a [m/s] on the faces normal to axis a (empty for a = 2 in 2D).
  [[nodiscard]] std::span<const double> face_velocity(int a) const { return u_[a]; }
  /// Pressure [Pa] per cell.
  [[nodiscard]] std::span<const double> pressure() const { return p_; }
  /// Fluid fraction per cell (as last set).
  [[nodiscard]] std::span<const double> fluid_fraction() const { return eps_; }
  /// Velocity at the centre of a cell [m/s]: mean of its two faces per axis (w = 0 in 2D).
  [[nodiscard]] Vec3 cell_velocity(std::int64_t cell) const;
  /// Pressure gradient at the centre of a cell [Pa/m]: mean of the face gradients on both sides
  /// per axis; at a wall or inlet, where the face gradient is not known, the other side's.
  [[nodiscard]] Vec3 pressure_gradient(std::int64_t cell) const;
  /// Velocity gradient at the centre of a cell [1/s], g.a[i][j] = d u_i / d x_j. Across an
  /// axis j != i from the centre values of the neighbours (wrapped on periodic axes); at a wall
  /// or inlet from its tangential velocity half a cell away, at an outlet zero. Along its own
  /// axis (d u_i / d x_i) from the cell's two faces: the cell's term of the divergence. Exact for
  /// a linear profile (Couette u_x = gamma_dot y: g.a[0][1] = gamma_dot in every cell, the rest
  /// 0); rotation_rate(g) and strain_rate(g) (core/mat3.hpp) give the fluid's spin and strain.
  [[nodiscard]] Mat3 cell_velocity_gradient(std::int64_t cell) const;
  /// cell_velocity, pressure_gradient and cell_velocity_gradient of every cell (out has
  /// cell_count entries).
  void cell_velocities(std::span<Vec3> out) const;
  void pressure_gradients(std::span<Vec3> out) const;
  void cell_velocity_gradients(std::span<Mat3> out) const;

  /// Courant number max over cells of dt * sum_a max(|u_a| on its two faces) / h_a.
  [[nodiscard]] double max_cfl(double dt) const;
  /// Mean pressure [Pa] over the plane x_axis = coordinate [m]: linear in between cell centres;
  /// at an outlet the outlet pressure, at other boundaries linearly extrapolated.
  [[nodiscard]] double mean_pressure(int axis, double coordinate) const;
  /// mean_pressure(axis, x1) - mean_pressure(axis, x2) [Pa].
  [[nodiscard]] double pressure_drop(int axis, double x1, double x2) const;
  /// Volume flux sum(eps u_a A) [m^3/s] through the face plane number `plane` (0..n[axis]).
  [[nodiscard]] double flow_rate(int axis, int plane) const;
  /// Superficial velocity flow_rate / cross-section area [m/s] of that plane.
  [[nodiscard]] double superficial_velocity(int axis, int plane) const;
  /// Kinetic energy sum(rho eps u^2 / 2) over the faces' control volumes [J] (2D: of a layer of
  /// depth h_z).
  [[nodiscard]] double kinetic_energy() const;
  /// max over cells of |div(eps u) + d eps/dt| [1/s]: zero up to the pressure solver's tolerance.
  [[nodiscard]] double divergence_norm() const;

 private:
  using Index3 = std::array<int, 3>;
  /// One link of the viscous stencil of a momentum unknown. Its kind, partner and geometry depend
  /// only on the grid and the kinds of the boundary conditions and are found once
  /// (momentum_neighbor); the coefficient and the Dirichlet value follow eps and the boundary
  /// values and are refreshed when the matrices are re-assembled (refresh_link).
  struct Neighbor {
    enum Kind : std::int8_t { None, Unknown, Known, Dirichlet } kind = None;
    std::int8_t axis = 0;     ///< b: the link points to f + side e_b
    std::int8_t side = 0;     ///< -1 or +1
    std::int8_t n_cells = 0;  ///< cells whose mean eps sits at the link: 1 (b = a) or 4 (edge)
    bool doubled = false;     ///< Unknown: inner link of an outlet face (half volume)
    int unknown = -1;         ///< Unknown: its index
    int entry = -1;           ///< Unknown: position of (unknown, row) in the matrix's values
    std::int64_t face = -1;   ///< Known: the neighbour (boundary) face, whose value is in u_
    std::array<int, 4> cells{-1, -1, -1, -1};  ///< the cells of eps_link (inside the grid)
    double coefficient = 0.0;                  ///< mu eps_link / h_b^2 per unit volume
    double value = 0.0;  ///< Dirichlet: the boundary value (ghost 2 value - u)
  };
  /// The two cells on either side of a face along its normal, folded into the grid (wrapped on
  /// periodic axes, clamped at the other boundaries, where eps and K have zero normal gradient).
  using FaceCells = std::array<int, 2>;

  void check_settings() const;
  void build_momentum_systems();
  void build_pressure_system();
  void refresh_boundary_faces(std::vector<double> (&u)[3]) const;
  void update_coefficients(double dt, double c0);
  void update_responses();  // fluid_response_, shared_response_ (after update_coefficients)
  void compute_convection(int a, std::vector<double>& out) const;
  StepReport solve_momentum(double dt, const std::array<double, 5>& bdf);
  void solve_pressure(StepReport& report);

  [[nodiscard]] const BoundaryCondition& bc(int axis, int side) const {
    return s_.boundary[box_face_index(axis, side)];
  }
  [[nodiscard]] Index3 unflatten_face(int a, std::int64_t f) const;
  [[nodiscard]] Index3 unflatten_cell(std::int64_t c) const;
  [[nodiscard]] double eps_cell(Index3 c) const;
  [[nodiscard]] bool face_in_grid(int a, Index3 f) const;
  [[nodiscard]] double eps_face(int a, Index3 f) const;
  [[nodiscard]] double eps_u(int a, Index3 f) const;
  void update_face_fraction();
  [[nodiscard]] double face_value(const std::vector<double>& u, int c, Index3 q) const;
  [[nodiscard]] double boundary_velocity(int axis, int side, int c, Index3 q) const;
  [[nodiscard]] double face_gradient(int a, std::int64_t fi, int i, const double* p,
                                     bool correction) const;
  [[nodiscard]] std::int64_t face_offset(int c, const Index3& q) const {
    return q[0] * face_stride_[c][0] + q[1] * face_stride_[c][1] + q[2] * face_stride_[c][2];
  }
  [[nodiscard]] double convecting_flux(int a, const Index3& f, std::int64_t fi, int b, int s) const;
  [[nodiscard]] Neighbor momentum_neighbor(int a, Index3 f, int b, int s) const;
  void refresh_link(int a, const Index3& f, Neighbor& nb) const;
  void build_face_tables();

  Grid grid_;
  FluidSettings s_;
  int dim_ = 3;
  bool closed_ = false;  // no pressure outlet: the pressure is fixed up to a constant
  double time_ = 0.0;
  std::int64_t n_steps_ = 0;
  int history_ = 0;  // steps since set_velocity (BDF2 needs one)
  double dt_prev_ = 0.0;

  std::vector<double> u_[3], u_old_[3], u_new_[3];  // faces: u^n, u^{n-1}, u^{n+1}
  std::vector<double> conv_[3], conv_old_[3];       // eps u . grad u at faces, at n and n-1
  std::vector<double> p_, phi_cell_;                // cells
  std::vector<double> eps_, eps_rate_, drag_;       // cells (inputs)
  std::vector<Vec3> source_;                        // cells (input)
  std::vector<double> eps_f_[3];                    // eps on faces (mean of the two cells)
  std::vector<double> flux_[3];                     // eps u on faces at t^n (the convecting fluxes)
  std::vector<double> a_face_[3];  // eps rho c0/dt + K on faces: the predictor's diagonal
  bool shared_ = false;            // a second phase shares the pressure
  std::vector<double> shared_flux_[3], shared_fraction_[3], shared_carried_[3],
      shared_inertia_[3];  // faces: the shared phase (SharedPhase)
  std::vector<double> fluid_response_[3], shared_response_[3];  // faces: du per grad(phi)
  std::vector<double> grad_phi_[3];             // faces: grad(phi) of the last correction
  std::vector<FaceCells> face_cells_[3];        // per face (built once)
  std::array<std::int64_t, 3> face_stride_[3];  // face index step along each axis, per component
  bool coefficients_dirty_ = true;  // eps or K changed since the matrices were assembled
  bool assemble_ = true;            // this step re-assembles the matrices
  bool links_dirty_ = true;         // a boundary condition changed: momentum links re-cached
  double coef_dt_ = 0.0, coef_c0_ = 0.0;

  // Implicit momentum predictor of component a: unknowns are the faces that have a momentum
  // equation (interior, periodic, outlet); row weight 1/2 on outlet faces (half volumes).
  struct Momentum {
    std::vector<std::int64_t> face_of_unknown;
    std::vector<Index3> coords;        // of face_of_unknown (no divisions in the step's loops)
    std::vector<int> unknown_of_face;  // -1: not an unknown
    std::vector<Neighbor> links;       // 2 * dim per unknown: (axis b, side -/+)
    std::vector<int> diag_entry;       // position of (r, r) in the matrix's values
    SpdSolver::Matrix matrix;
    Eigen::VectorXd rhs, x;
    SpdSolver solver;
  };
  Momentum mom_[3];

  // Row of the pressure matrix of one cell, found once: its lower face per axis, and per side
  // (2 a + (s > 0)) where the neighbour's coefficient goes.
  struct PressureRow {
    static constexpr int kNone = -1;    // wall or inlet: no flux of phi
    static constexpr int kOutlet = -2;  // phi = 0 half a cell away: the diagonal only
    std::array<std::int64_t, 3> face{};
    std::array<int, 6> entry{};  // position of the neighbour's entry in the values, or the above
    int diag = 0;                // position of the diagonal entry
  };
  std::vector<PressureRow> prow_;
  SpdSolver::Matrix pmatrix_;
  Eigen::VectorXd prhs_, phi_;
  Eigen::VectorXd flux_scale_;  // per cell: sum of |eps u| / h over its faces + |d eps/dt|
  SpdSolver psolver_;
};

}  // namespace gf::fluid
