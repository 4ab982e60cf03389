// SPDX-License-Identifier: GPL-3.0-or-later
// Temperature of the volume-averaged fluid of unresolved CFD-DEM: the energy equation of an
// incompressible fluid of constant properties, carried by the flow of a VolumeAveragedNS on the
// same grid (Zhou, Yu & Zulli, AIChE J. 55 (2009) 868, eq. (4), without viscous heating and
// radiation):
//
//   rho c_p [d(eps T)/dt + div(eps u T)] = div(eps k grad T) + Q,     Q = q_explicit - K T,
//
// with Q the heat the particles give the fluid per unit volume (K >= 0 taken implicitly, as the
// drag of the momentum exchange). It is solved in the advective form that continuity
// (d eps/dt + div(eps u) = 0) turns it into, eps rho c_p dT/dt + rho c_p (eps u . grad T), so
// that a uniform temperature stays uniform whatever the continuity residual of the flow.
//
// Discretisation: T at cell centres; the convecting fluxes eps u are those of the flow solver's
// faces (eps on a face: the mean of its two cells, as there); first-order upwind convection and
// central diffusion, both implicit with backward Euler, so any step is stable and T stays within
// the range of its initial, boundary and particle temperatures (the matrix is an M-matrix).
// Upwinding alone smears a front by a numerical diffusivity |u| h / 2 (plus u^2 dt / 2 from the
// implicit step), often more than the fluid's own; by default the face temperatures of the
// interior faces are van Leer's limited ones instead (second order where T is smooth, upwind at
// extrema), added as a deferred correction: the implicit upwind matrix is kept and the
// difference between the limited and the upwind face values, taken from the temperatures at
// the start of the step, goes to the right-hand side (Khosla & Rubin, Comput. Fluids 2 (1974)
// 207). A face's value is the same seen from both its cells, so the correction moves heat
// between cells and never creates any; at Courant numbers u dt / h <= 1, the flow solver's
// limit, it stays within the local extrema (tested). The non-symmetric
// system, for the change of T over the step, is solved by Eigen's BiCGSTAB with a light
// incomplete LU (the diagonal alone stalls on convection-dominated periodic rows).
//
// Boundaries, per box face, by the flow's condition there: periodic wraps; walls (no_slip,
// moving_wall) are adiabatic, or held at a temperature (conduction across half a cell); a
// velocity inlet brings fluid at its temperature (convected in, and held on the face for
// diffusion); a pressure outlet lets fluid leave at its own temperature (zero gradient) and brings
// back-flow in at the face's temperature (that of the cell next to it when none is given).
#pragma once

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "fluid/fv/navier_stokes.hpp"

namespace gf::fluid {

/// Thermal properties and boundary temperatures of the fluid.
struct HeatSettings {
  double heat_capacity = 0.0;         ///< c_p [J/(kg K)]
  double thermal_conductivity = 0.0;  ///< k [W/(m K)]
  /// Per box face (box_face_index): walls: the wall temperature [K] (NaN: adiabatic); inlets:
  /// the inflow temperature [K] (required); outlets: the back-flow temperature (NaN: the cell's).
  std::array<double, 6> boundary_temperature{};
  /// Face temperatures of the convection: VanLeer (deferred correction of the implicit upwind
  /// step, second order where smooth) or Upwind (first order). Central is refused: unbounded
  /// once u h / alpha exceeds 2, which the fluids here (alpha ~ 1e-7-1e-5 m^2/s) always do.
  Convection convection = Convection::VanLeer;
  /// Boussinesq buoyancy: the fluid's density varies as rho (1 - beta (T - T_ref)) in the
  /// gravity term only; beta [1/K] (0: none; 1/T for an ideal gas, 2.1e-4 for water at 20 C).
  double thermal_expansion = 0.0;
  double reference_temperature = 0.0;  ///< T_ref [K]
  double tolerance = 1e-12;            ///< relative residual of each solve
  int max_iterations = 1000;
};

/// What one step did.
struct HeatStepReport {
  int iterations = 0;                 ///< BiCGSTAB iterations
  double boundary_heat = 0;           ///< heat flow into the fluid through the box faces [W]
  std::array<double, 6> face_heat{};  ///< the same per box face (box_face_index) [W]
  double particle_heat = 0;           ///< heat flow from the particles, sum(q_explicit - K T) V [W]
};

/// The fluid's temperature on the cells of a VolumeAveragedNS's grid. Typical use, after each
/// flow step: set_source(q, k); step(dt, flow).
class FluidHeat {
 public:
  /// Checks the settings against the flow's boundary conditions (gf::Error: what is missing)
  /// and sets T = initial_temperature everywhere.
  FluidHeat(const VolumeAveragedNS& flow, HeatSettings settings, double initial_temperature);

  /// Heat from the particles per cell, Q = q_explicit - k T [W/m^3], with k >= 0 [W/(m^3 K)].
  void set_source(std::span<const double> q_explicit, std::span<const double> k);
  /// Sets the temperature [K] per cell (an initial condition or a restart).
  void set_temperature(std::span<const double> t);

  /// Advances T by dt [s] with the flow's current face velocities and fluid fraction (those at
  /// the end of its last step). `eps_start`: the fluid fraction per cell at the start of the
  /// step (none: the flow's current one, grains at rest). With it the heat stored changes
  /// exactly by what crosses the faces and comes from the particles, to the extent that the
  /// flow's continuity held eps_end - eps_start = -dt div(eps u) (see the .cpp).
  /// gf::Error when the solve does not converge.
  HeatStepReport step(double dt, const VolumeAveragedNS& flow,
                      std::span<const double> eps_start = {});

  [[nodiscard]] std::span<const double> temperature() const { return t_; }
  [[nodiscard]] const HeatSettings& settings() const { return s_; }
  /// Thermal energy sum(eps rho c_p T V) [J] with the flow's fluid fraction (2D: of a layer of
  /// depth h_z).
  [[nodiscard]] double energy(const VolumeAveragedNS& flow) const;
  /// Fluid-volume-weighted mean temperature sum(eps T V) / sum(eps V) [K].
  [[nodiscard]] double mean_temperature(const VolumeAveragedNS& flow) const;
  /// Adds the Boussinesq buoyancy of the current temperatures to a momentum source per cell
  /// (VolumeAveragedNS::set_momentum_source's s_explicit): s_c += -eps_c rho beta (T_c - T_ref) g,
  /// with the flow's density, fluid fraction and gravity. Nothing without thermal_expansion.
  void add_buoyancy(const VolumeAveragedNS& flow, std::span<Vec3> s) const;

 private:
  using Matrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  /// One face of a cell: the neighbour's unknown (-1: a box face), the face's flux index and
  /// whether it is the cell's lower (-1) or upper (+1) face along axis `axis`.
  struct Link {
    int neighbor = -1;
    int entry = -1;  ///< position of (row, neighbor) in the row-major values
    int box_face = -1;
    std::int64_t face = 0;
    std::int8_t axis = 0, side = 0;
  };

  /// m_out (T_f - T_upwind) of link m of cell c at the current temperatures [K/s], m_out the
  /// face's outward eps u / h [1/s] and T_f van Leer's face value; 0 without a far-upwind cell
  /// (beyond an inlet: the inflow temperature's mirror value).
  [[nodiscard]] double convection_correction(std::int64_t c, int m, double out) const;

  Grid grid_;
  int dim_ = 3;
  double rho_c_ = 0.0;
  HeatSettings s_;
  std::array<BcKind, 6> kinds_{};
  std::vector<double> t_, q_, k_;
  std::vector<Link> links_;  // 2 * dim per cell
  std::vector<int> diag_;    // position of (c, c) in the values
  Matrix a_;
  Eigen::VectorXd b_, x_;
  Eigen::BiCGSTAB<Matrix, Eigen::IncompleteLUT<double>> solver_;
};

}  // namespace gf::fluid
