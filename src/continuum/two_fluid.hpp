// SPDX-License-Identifier: GPL-3.0-or-later
// Eulerian-Eulerian two-fluid model (TFM): a fluid and one granular (solids) phase as
// interpenetrating continua on the uniform staggered Cartesian grid of src/fluid/fv, with the
// kinetic theory of granular flow (src/continuum/ktgf.hpp) for the solids stress and the drag
// laws of src/coupling/cfd_dem for the momentum exchange. The seed's framework (Gomez Fino 2014,
// eqs 1-2; Jackson 1997 as written by van Wachem et al., AIChE J. 47 (2001) 1035):
//
//   d(a)/dt + div(a u_s) = 0,                                    a = alpha_s, eps = 1 - a
//   a rho_s (du_s/dt + u_s . grad u_s) = -a grad p - grad P_s + div(tau_s) + beta (u_f - u_s)
//                                        + a rho_s g
//   d(eps)/dt + div(eps u_f) = 0
//   eps rho_f (du_f/dt + u_f . grad u_f) = -eps grad p + div(eps mu_f grad u_f) - beta (u_f - u_s)
//                                          + eps rho_f g
//
// ("model A": both phases feel the shared pressure gradient in proportion to their fraction).
// Closures: P_s = P_kt(a, Theta) + P_dense(a) [+ P_e(a), a particle pressure], tau_s = 2 mu_s D +
// (lambda_s - 2/3 mu_s) tr(D) I, beta = a beta_p / V_p with beta_p the per-particle coefficient of
// a drag law of the registry at the fluid fraction eps and the cell's slip. Dense regime
// (FrictionalModels): schaeffer_johnson_jackson adds the Johnson-Jackson pressure and Schaeffer's
// viscosity to the kinetic theory's (seed eqs 3, 6, 7); mu_i_switch is the seed's regime switch:
// above a frictional limit the viscosity of the mu(I) rheology at the solids pressure (seed eqs
// 8-11), with the seed's logarithmic pressure p0 ln((a_M - a_m) / (a_M - a)) (eq 14). The granular
// temperature is either algebraic, the local equilibrium of production and dissipation
// (Syamlal, Rogers & O'Brien 1993, the MFIX theory guide; van Wachem et al. 2001)
//   -P_kt tr(D) + 2 mu_kt D':D' + lambda_s tr(D)^2 = gamma_s + 3 beta Theta,
// solved in closed form since P_kt ~ Theta, mu_kt, lambda_s ~ sqrt(Theta), gamma_s ~ Theta^1.5 at
// fixed a (the dense parts are not fluctuation energy and stay out of the balance), or
// transported: the granular energy balance with convection, conduction and Johnson-Jackson wall
// fluxes (transport_temperature).
//
// One step (sec. "Algorithm" of docs/models/two_fluid.md):
//   1. cell closures at t^n (g0, P_s, dP_s/da, mu_s, lambda_s, beta);
//   2. solids momentum predictor on the faces: drag implicit in u_s (with the fluid velocity of
//      t^n), the viscous terms of u_s itself implicit, convection in flux form (only inflowing
//      mass changes a face's velocity), the rest explicit: u*;
//   3. solids continuity with the solids pressure implicit (the "implicit phase pressure" of
//      OpenFOAM's twoPhaseEulerFoam; the solids volume-fraction correction of MFIX): the change
//      delta = a~ - a^n raises each cell's pressure by psi = (dP_s/da) delta, the faces move by
//      u~ = u* - c_f grad(psi), c_f = 1 / (a_f rho_s / dt + beta_f), so the stiff pressure near
//      packing costs no time step (an SPD system for psi; a gradient, so momentum is conserved);
//   4. the fluid step of VolumeAveragedNS with the drag beta (u~ - u_f) implicit in u_f, whose
//      pressure correction phi enforces the continuity of the mixture, div(eps u_f + F) = 0,
//      with the solids flux F responding to phi as well and both phases' responses coupled by
//      the drag (set_shared_phase): correcting the fluid alone made a packed sediment ring, the
//      fluid forced to fill what the lagged solids left; then u_s = u~ - r_s grad(phi) and
//      a^{n+1} = a^n - dt div(F);
//   5. Theta^{n+1}, algebraic or transported, with the new solids velocities.
// The fluxes F of step 4 are the ones that move a, so the solids volume is conserved to
// round-off (a closed box; the rare clip of a below 0 or above the packing limit is counted in
// TwoFluidReport::clipped_volume).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "continuum/ktgf.hpp"
#include "continuum/rheology_registry.hpp"
#include "coupling/cfd_dem/drag_laws.hpp"
#include "fluid/fv/navier_stokes.hpp"

namespace gf::continuum {

/// Tangential condition of the solids at a wall (a box face that is a wall or an inlet for the
/// fluid; the solids' normal velocity there is zero).
enum class SolidsWall {
  NoSlip,    ///< u_s = wall velocity
  FreeSlip,  ///< zero shear stress
  /// Johnson & Jackson (1987) partial slip: wall shear stress (pi sqrt(3) / 6) phi' (a / a_max)
  /// rho_s g0 sqrt(Theta) |u_slip| against the slip, phi' the specularity coefficient.
  JohnsonJackson,
};

/// How the granular temperature is found.
enum class GranularTemperature {
  /// Local equilibrium of production and dissipation (no convection, no conduction): dense,
  /// collision-dominated beds (MFIX's algebraic option, with Syamlal's closures, which it
  /// requires: with closures of finite dilute viscosity the balance gives Theta ~ 1/a^2).
  Algebraic,
  /// The granular energy balance with convection and conduction (MFIX's default; needed where
  /// energy is carried, e.g. from a sheared wall layer into the bulk).
  Transport,
};

/// Physical parameters and numerical choices of the two-fluid model.
struct TwoFluidSettings {
  /// The fluid phase: density, viscosity, gravity, boundary conditions, convection, linear
  /// solvers (fluid/fv). A wall or inlet face is a wall for the solids, an outlet lets solids out,
  /// a periodic face is periodic for both.
  fluid::FluidSettings fluid;
  KtgfParams ktgf;  ///< closure set and grain material (diameter, density, restitution)
  /// Dense-region closure; frictional = false: kinetic theory only. schaeffer_johnson_jackson:
  /// the Johnson-Jackson pressure and Schaeffer's viscosity added to the kinetic theory's;
  /// mu_i_switch (the seed's regime switch): above its frictional limit the viscosity of the
  /// mu(I) rheology `dense_rheology` at the solids pressure, and the pressure `log_pressure`.
  bool frictional = true;
  FrictionalParams dense;
  RheologyParams dense_rheology;  ///< mu_i_switch: prepare_rheology("mu_i", ...)
  /// mu_i_switch: the seed's eq 14, P = p0 ln((a_M - a_m) / (a_M - a)) for a > a_m (Gomez Fino
  /// 2014; Josserand, Lagree & Lhuillier, Europhys. Lett. 73 (2006) 363), added to P_kt.
  struct LogPressure {
    double p0 = 0.0;            ///< [Pa], the seed's rho g h scale
    double min_fraction = 0.0;  ///< a_m [1]
    double max_fraction = 0.0;  ///< a_M [1]: the pressure diverges there
  } log_pressure;
  /// Particle pressure added to P_s at every fraction (e.g. Gidaspow & Ettehadieh's elastic
  /// modulus): model < 0 none. Where the grains barely fluctuate (liquid fluidisation) it is
  /// what resists voidage disturbances below the dense regime. Not fluctuation energy: it stays
  /// out of the granular energy balance, as the frictional pressure does.
  ParticlePressureParams particle_pressure{-1};
  cfd_dem::DragParams drag;  ///< drag law (index in cfd_dem::DragLaws)
  std::array<SolidsWall, 6> solids_wall{SolidsWall::NoSlip, SolidsWall::NoSlip, SolidsWall::NoSlip,
                                        SolidsWall::NoSlip, SolidsWall::NoSlip, SolidsWall::NoSlip};
  double specularity = 0.5;       ///< phi' of JohnsonJackson walls [1]
  double wall_restitution = 0.9;  ///< e_w, particle-wall restitution of JohnsonJackson walls [1]
  GranularTemperature temperature = GranularTemperature::Algebraic;
  /// Largest volume fraction a cell may reach [1]; 0: just below the frictional a_max (or the
  /// packing limit of g0, whichever is lower).
  double max_fraction = 0.0;
  double min_temperature = 1e-12;  ///< floor of Theta [m^2/s^2]
  double max_courant = 0.5;        ///< solids Courant limit of step()
  /// Face value of the volume fraction in its flux: VanLeer (second order where smooth, bounded
  /// between the upwind and downwind cells: fronts and bubble edges stay sharp) or Upwind (first
  /// order, smears a front over ~2 cells). Central is refused (unbounded).
  fluid::Convection fraction_convection = fluid::Convection::VanLeer;
  double tolerance = 1e-12;  ///< relative residual of the volume-fraction solve
};

/// What one step did.
struct TwoFluidReport {
  int momentum_iterations = 0;  ///< CG iterations of the solids predictor, summed over components
  int fraction_iterations = 0;  ///< CG iterations of the implicit volume-fraction equation
  double solids_courant = 0.0;  ///< dt * max over cells of sum_a |u_s,a| / h_a (of a substep)
  int substeps = 1;             ///< steps taken: more than 1 when the Courant number was too high
  double clipped_volume = 0.0;  ///< solids volume added (+) or removed (-) by clipping [m^3]
  fluid::StepReport fluid;      ///< the fluid solver's report
};

/// The two-fluid model on a fluid::Grid. Typical use:
///
///     TwoFluidModel tfm(grid, settings);
///     tfm.set_solids([](const Vec3& x) { return x.z < 0.2 ? 0.5 : 0.0; });
///     while (t < t_end) { double dt = std::min(0.9 * tfm.stable_dt(), dt_max); tfm.step(dt); }
///
/// Cell fields are indexed by Grid::index, face fields by Grid::face_index (component a on the
/// faces normal to a), as in fluid::VolumeAveragedNS.
class TwoFluidModel {
 public:
  /// Checks the settings (gf::Error naming what is wrong); no solids, fluid at rest.
  TwoFluidModel(const fluid::Grid& grid, TwoFluidSettings settings);

  /// Initial solids volume fraction a(x) [1] sampled at the cell centres, solids at rest and
  /// Theta = theta0 [m^2/s^2]; the fluid fraction follows (eps = 1 - a).
  void set_solids(const std::function<double(const Vec3&)>& fraction, double theta0 = 0.0);
  /// Solids velocity u_s(x) [m/s] sampled at the face centres (walls keep zero normal velocity).
  void set_solids_velocity(const std::function<Vec3(const Vec3&)>& velocity);
  /// The fluid solver, e.g. for set_velocity, set_pressure or set_boundary before the run (the
  /// closures are re-evaluated at the next step).
  fluid::VolumeAveragedNS& fluid() {
    stale_ = true;
    return fluid_;
  }
  [[nodiscard]] const fluid::VolumeAveragedNS& fluid() const { return fluid_; }

  /// Largest step [s] the explicit parts allow: solids Courant number max_courant and the
  /// fluid's max_courant (the drag, the solids pressure and the solids viscous stress of u_s
  /// itself are implicit).
  [[nodiscard]] double stable_dt() const;
  /// Advances by dt [s]: one step, or substeps of dt / 2^k where the predicted solids Courant
  /// number exceeds max_courant (the fluid solver checks its own Courant number and throws).
  TwoFluidReport step(double dt);

  /// Everything a restart needs to continue bit-identically: the fluid solver's state, the
  /// solids fraction, temperature and face velocities, and the clock (the closures follow from
  /// them).
  struct State {
    double time = 0.0;
    std::vector<std::pair<std::string, std::vector<double>>> arrays;
    fluid::VolumeAveragedNS::State fluid;
  };
  [[nodiscard]] State state() const;
  /// Restores a state() of a model on the same grid and settings (gf::Error when an array is
  /// missing or has another size).
  void restore(const State& state);

  // --- results ------------------------------------------------------------------------------
  [[nodiscard]] const fluid::Grid& grid() const { return grid_; }
  [[nodiscard]] const TwoFluidSettings& settings() const { return s_; }
  [[nodiscard]] double time() const { return time_; }
  [[nodiscard]] double packing_fraction() const { return a_max_; }
  /// Solids volume fraction per cell [1].
  [[nodiscard]] std::span<const double> solids_fraction() const { return alpha_; }
  /// Granular temperature per cell [m^2/s^2].
  [[nodiscard]] std::span<const double> granular_temperature() const { return theta_; }
  /// Solids pressure P_kt + P_dense (+ P_e) per cell at the last closure evaluation [Pa].
  [[nodiscard]] std::span<const double> solids_pressure() const { return ps_; }
  /// Effective solids shear viscosity per cell at the last closure evaluation [Pa s].
  [[nodiscard]] std::span<const double> solids_viscosity() const { return mu_; }
  /// Momentum-exchange coefficient beta per cell at the last closure evaluation [kg/(m^3 s)].
  [[nodiscard]] std::span<const double> exchange_coefficient() const { return beta_; }
  /// Solids velocity component a on the faces normal to axis a [m/s].
  [[nodiscard]] std::span<const double> solids_face_velocity(int a) const { return us_[a]; }
  /// Solids volume flux per unit face area through the faces normal to axis a over the last
  /// step [m/s] (what moved a: first-order upwind a times u_s).
  [[nodiscard]] std::span<const double> solids_face_flux(int a) const { return flux_[a]; }
  /// Solids velocity at a cell centre (mean of the two faces per axis) [m/s].
  [[nodiscard]] Vec3 solids_velocity(std::int64_t cell) const;
  /// Total solids volume sum(a V) [m^3] (2D: per depth h_z).
  [[nodiscard]] double solids_volume() const;
  /// Closures of one cell at (a, Theta) with strain-rate invariant gamma_dot [1/s] and slip
  /// speed |u_f - u_s| [m/s]: what step() evaluates, for tests and output.
  struct CellClosures {
    double g0 = 0, pressure = 0, kinetic_pressure = 0, pressure_slope = 0;
    double viscosity = 0, bulk_viscosity = 0, beta = 0;
  };
  [[nodiscard]] CellClosures closures(double a, double theta, double gamma_dot, double slip) const;
  /// Algebraic granular temperature of a cell with volume fraction a, strain rate (tr D,
  /// D':D') [1/s, 1/s^2] and exchange coefficient beta: the positive root of the balance in the
  /// file header [m^2/s^2].
  [[nodiscard]] double algebraic_temperature(double a, double trace_d, double dev_dd,
                                             double beta) const;

 private:
  using Index3 = std::array<int, 3>;
  enum class FaceKind : std::int8_t { Interior, Wall, Outlet, PeriodicImage };

  void check_settings();
  void build_fraction_system();
  /// The closures of every cell at the present state; strain_rates_current: trace_d_ and
  /// dev_dd_ already hold its strain rates (update_temperature found them), else found here.
  void evaluate_closures(bool strain_rates_current = false);
  void update_strain_rates();  ///< trace_d_, dev_dd_ of every cell (strain_rate)
  struct Link {
    enum Kind : std::int8_t { None, Unknown, Known, Wall, Self } kind = None;
    int unknown = -1;        ///< Unknown: its index
    int entry = -1;          ///< Unknown: position of (unknown, row) in the matrix's values
    std::int64_t face = -1;  ///< Unknown / Known: the neighbouring face
  };
  [[nodiscard]] Index3 face_coords(int a, std::int64_t f) const;
  [[nodiscard]] Link momentum_link(int a, Index3 q, int b, int side) const;
  void build_momentum_systems();
  int solids_predictor(double dt);
  TwoFluidReport advance(double dt, int depth);
  void solids_pressure_step(double dt, TwoFluidReport& report);
  double fluid_step(double dt, TwoFluidReport& report);
  void update_temperature(double dt);
  void transport_temperature(double dt);
  [[nodiscard]] double wall_energy_flux(int b, int side, std::int64_t c) const;
  /// max over cells of sum_a max(|u_a| on the cell's two faces) / h_a [1/s].
  [[nodiscard]] double max_outflow_rate(const std::vector<double> (&u)[3]) const;
  [[nodiscard]] FaceKind face_kind(int a, int i) const;
  [[nodiscard]] double u_at(int a, Index3 q) const;
  [[nodiscard]] double wall_ratio(int b, int side, std::int64_t cell) const;
  [[nodiscard]] Vec3 wall_velocity(int b, int side) const;
  [[nodiscard]] std::int64_t cell(Index3 c) const;
  /// The cell upwind of the face at coordinates q (component a) for a velocity u; across an
  /// outlet or a wall the one inside.
  [[nodiscard]] std::int64_t upwind_cell(int a, Index3 q, double u) const;
  /// The volume fraction carried through the face at coordinates q (component a) by a velocity
  /// u: the upwind cell's, or van Leer's limited value of the upwind, far-upwind and downwind
  /// cells (settings' fraction_convection; the upwind cell's where one of them is missing).
  [[nodiscard]] double face_fraction(int a, Index3 q, double u) const;
  /// div(flux_) of cell c [1/s].
  [[nodiscard]] double flux_divergence(std::int64_t c) const;
  /// adv_flux_ of component b at the face of cell coordinates q (wrapped across periodic axes).
  [[nodiscard]] double advective_flux(int b, Index3 q) const;
  [[nodiscard]] double cell_mean(const std::vector<double>& f, Index3 c0, Index3 c1, Index3 c2,
                                 Index3 c3) const;
  void strain_rate(std::int64_t c, double& trace_d, double& dev_dd) const;

  fluid::Grid grid_;
  TwoFluidSettings s_;
  fluid::VolumeAveragedNS fluid_;
  int dim_ = 3;
  double time_ = 0.0;
  double a_max_ = 0.0;        // cap of the volume fraction
  double v_p_ = 0.0;          // grain volume [m^3]
  double a_floor_ = 1e-6;     // mass and drag of an empty cell are those of this fraction
  bool stale_ = true;         // closures not evaluated for the present state
  bool mu_i_switch_ = false;  // dense regime by mu(I) with the logarithmic pressure

  std::vector<double> alpha_, alpha_old_, theta_;      // cells
  std::vector<double> ps_, dps_, mu_, lambda_, beta_;  // cells, closures at t^n
  std::vector<double> trace_d_, dev_dd_;               // cells: tr D, D':D' of the last closures
  std::vector<double> us_[3], ustar_[3];               // faces: u_s, predictor u*
  std::vector<double> coef_[3];  // faces: c_f = 1 / (m/dt + beta), u per grad(psi)
  std::vector<double> face_fraction_[3], inertia_[3];  // faces: a_f, a_f rho_s / dt (0: wall)
  std::vector<double> flux_[3];                        // faces: the solids volume flux F [m/s]
  std::vector<double> carried_[3];                     // faces: a_up, F per u_s
  std::vector<double> adv_flux_[3];  // faces: a_up u_s of t^n [m/s], carries the momentum
  std::vector<double> delta_;        // cells: a^{n+1} - a^n
  std::vector<Vec3> us_cell_, uf_cell_, source_;  // cells
  std::vector<double> eps_, eps_rate_;            // cells

  // Implicit volume-fraction system: per cell the positions of its diagonal and of its (up to
  // 2 dim) neighbours in the matrix's values, and which face links them.
  struct Row {
    int diag = 0;
    std::array<int, 6> entry{};          // -1: no link (wall, outlet)
    std::array<std::int64_t, 6> face{};  // face index of the link (component = side / 2)
  };
  std::vector<Row> rows_;
  fluid::SpdSolver::Matrix matrix_;
  Eigen::VectorXd rhs_, x_;
  fluid::SpdSolver solver_;
  fluid::SpdSolver::Matrix theta_matrix_;  // granular energy: the same pattern
  Eigen::VectorXd theta_rhs_, theta_x_;
  fluid::SpdSolver theta_solver_;

  // Implicit solids momentum predictor per component: unknowns are the interior faces.
  struct Momentum {
    std::vector<std::int64_t> face_of_unknown;
    std::vector<int> unknown_of_face;  // -1: not an unknown
    std::vector<Link> links;           // 2 dim per unknown: (axis b, side -/+)
    std::vector<int> diag_entry;
    fluid::SpdSolver::Matrix matrix;
    Eigen::VectorXd rhs, x;
    fluid::SpdSolver solver;
  };
  Momentum mom_[3];
};

}  // namespace gf::continuum
