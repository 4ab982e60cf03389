// SPDX-License-Identifier: GPL-3.0-or-later
// Unresolved CFD-DEM in the time loop: the volume-averaged fluid (fluid/fv) sub-cycled against
// the DEM, with the particle <-> cell mappings and drag laws of coupling/cfd_dem.
#pragma once

#include <cstdint>
#include <memory>
#include <ostream>
#include <span>
#include <vector>

#include "coupling/cfd_dem/drag_registry.hpp"
#include "coupling/cfd_dem/fluid_fraction.hpp"
#include "coupling/cfd_dem/mapping.hpp"
#include "fluid/fv/heat_transport.hpp"
#include "fluid/fv/navier_stokes.hpp"
#include "io/input/config.hpp"

namespace gf {

class ParticleStore;

/// The fluid of a case with `fluid:` and `coupling:` blocks and its exchange with the grains
/// (algorithm: docs/models/cfd_dem.md).
///
/// Every `interval` DEM steps (and once at the start), fluid_step():
///  1. fluid fraction eps per cell from the grains (centre-in-cell or divided volume), clamped
///     at min_fraction, and d eps/dt = (eps - eps_prev) / (interval dt);
///  2. per grain: u_f and eps interpolated to its centre, the drag law's beta_i (slip with the
///     grain's velocity now);
///  3. the reaction -beta_i (u_f - v_i) spread over the cells semi-implicitly as S = s_explicit
///     - K u (K = sum w beta / V_c taken implicitly by the fluid solver, so a stiff drag cannot
///     make the exchange unstable);
///  4. one fluid step of interval x dt;
///  5. u_f,i and grad p interpolated at the grains from the new fluid state, stored per grain.
/// On every DEM step, add_forces() adds beta_i (u_f,i - v_i) (the grain's current velocity) and
/// -V_i grad p_i to each grain.
///
/// The per-grain values live in ParticleStore fields (fluid_beta, fluid_velocity,
/// fluid_pressure_gradient), so the re-ordering at neighbour rebuilds and checkpoints carry them.
///
/// With coupling.heat_transfer the fluid also has a temperature (fluid/fv/heat_transport.hpp),
/// exchanged with the grains like the momentum: in step 2 each grain's conductance h_i A_i from
/// the Nusselt correlation (its slip, the fluid fraction at it); in step 3 the heat the grains
/// take, h_i A_i (T_f,i - T_i) with the T_f,i they read, spread over the cells with the implicit
/// part K = sum w h A / V; after the flow step one step of the fluid's temperature, read back
/// at the grains (field fluid_temperature). On every DEM step add_heat() gives each grain
/// h_i A_i (T_f,i - T_i) with its current temperature, and counts it (field
/// fluid_heat_received). The fluid took its side at the grains' temperatures of the fluid step;
/// what it lost that the grains did not receive over the interval (they changed temperature
/// meanwhile, an error of order dt_f / tau per interval that would add up) goes back into the
/// fluid's source at the next fluid step, cell by cell, so the energy of grains and fluid is
/// conserved to one interval's exchange, not only to O(dt_f / tau) of all heat exchanged.
class CfdDemCoupling {
 public:
  /// Builds the grid over the domain box and the fluid solver; registers the particle fields.
  CfdDemCoupling(const config::Case& cfg, ParticleStore& particles, double dem_dt);

  /// Steps 1-5 above (advances the fluid by interval x dem_dt).
  void fluid_step(ParticleStore& particles);
  /// Adds drag and pressure-gradient forces to the particles' force column (and, with
  /// coupling.torque: rotational, the hydrodynamic torque to their torque column).
  void add_forces(ParticleStore& particles) const;
  /// With coupling.heat_transfer: adds each grain's heat from the fluid, h A (T_f - T) [W], to q
  /// and its conductance h A [W/K] to h (the stability sum of the explicit update); `temperature`
  /// per grain [K]. A no-op without. Also counts the heat dt h A (T_f - T) of the step into the
  /// grain's fluid_heat_received [J].
  void add_heat(ParticleStore& particles, const double* temperature, double* q, double* h,
                double dt) const;
  [[nodiscard]] bool has_heat() const { return heat_ != nullptr; }
  /// The fluid's temperature (null without coupling.heat_transfer).
  [[nodiscard]] const fluid::FluidHeat* heat() const { return heat_.get(); }
  /// Heat flow from the grains into the fluid over the last fluid step [W] (negative: the fluid
  /// heats the grains), and through the box faces into the fluid [W].
  [[nodiscard]] double grain_heat_to_fluid() const { return heat_report_.particle_heat; }
  [[nodiscard]] double boundary_heat_to_fluid() const { return heat_report_.boundary_heat; }
  /// The same through one box face (fluid::box_face_index) [W].
  [[nodiscard]] double boundary_heat_to_fluid(int face) const {
    return heat_report_.face_heat[static_cast<std::size_t>(face)];
  }
  /// The heat the fluid has given the grains at its last step that they have not taken yet, J
  /// (they take it over the interval; it is settled at the next fluid step): the energy of
  /// grains plus fluid plus this is conserved to round-off when nothing crosses the box faces.
  [[nodiscard]] double heat_in_transit(const ParticleStore& particles) const;
  /// Whether DEM step number `step` (after it was taken) is due a fluid step.
  [[nodiscard]] bool due(std::int64_t step) const { return step % interval_ == 0; }

  /// The fluid's state and the coupling's own (the fluid fraction of the last fluid step) for a
  /// checkpoint; the grains' exchange fields are particle fields and travel with the grains.
  [[nodiscard]] fluid::VolumeAveragedNS::State state() const;
  /// Restores a state() written by the same case (gf::Error on a missing or mis-sized array).
  void restore(const fluid::VolumeAveragedNS::State& state);

  [[nodiscard]] const fluid::VolumeAveragedNS& fluid() const { return *fluid_; }
  [[nodiscard]] const fluid::Grid& grid() const { return grid_; }
  [[nodiscard]] int interval() const { return interval_; }
  /// Wall-clock seconds spent in fluid_step and add_forces.
  [[nodiscard]] double seconds() const { return seconds_ + force_seconds_; }

  /// Axis of the pressure drop and superficial velocity series: gravity's axis, else z.
  [[nodiscard]] int flow_axis() const { return flow_axis_; }
  /// p(bottom plane) - p(top plane) along flow_axis, Pa.
  [[nodiscard]] double pressure_drop() const;
  /// Superficial velocity through the middle face plane along flow_axis, m/s.
  [[nodiscard]] double superficial_velocity() const;
  /// Smallest fluid fraction of a cell (as last set).
  [[nodiscard]] double min_fluid_fraction() const;

  /// The fluid's cell fields (fluid_fraction, pressure [Pa], velocity [m/s] at cell centres) as
  /// a VTK ImageData file (.vti, appended binary data), for ParaView next to the particles.
  void write_vti(std::ostream& out) const;

 private:
  /// f(Re_R) R (Omega_f + lambda a x (E a) - omega) on every grain
  /// (coupling/cfd_dem/hydro_torque.hpp).
  void add_torques(ParticleStore& particles) const;
  /// Step 2-3 of the heat exchange: the grains' conductances and the fluid's source.
  void exchange_heat(ParticleStore& particles, const cfd_dem::ParticleGeometry& geo);

  fluid::Grid grid_;
  std::unique_ptr<fluid::VolumeAveragedNS> fluid_;
  int interval_ = 1;
  double dt_fluid_ = 0;
  double rho_f_ = 0, mu_f_ = 0;
  int law_ = -1;
  cfd_dem::DragParams drag_params_;
  cfd_dem::FluidFractionOptions ff_options_;
  int flow_axis_ = 2;
  bool first_ = true;
  bool closed_ = false;                         // no pressure outlet: the fluid volume is fixed
  int f_beta_ = -1, f_uf_ = -1, f_fixed_ = -1;  // particle field indices
  double seconds_ = 0;
  mutable double force_seconds_ = 0;

  // Reused between fluid steps (sized on the first one).
  cfd_dem::StoreGeometry geo_buffers_;
  // d eps/dt from the grains' motion (else from the eps difference): the solid flux, or with
  // rate_from_derivative_ the continuous deposit's time derivative
  bool rate_from_motion_ = true;
  bool rate_from_derivative_ = false;
  cfd_dem::Footprints rate_fp_;  // the footprints' rates (derivative only)
  cfd_dem::SolidFluxScratch solid_flux_;
  double rate_relaxation_ = 0.3;         // under-relaxation of the flux rate between fluid steps
  bool pressure_gradient_force_ = true;  // grains feel -V grad p (else drag only)
  bool torque_ = false;                  // coupling.torque: rotational
  // With torque_: the fluid's curl(u) / 2 and strain rate (diagonal xx, yy, zz; off-diagonal
  // yz, xz, xy) at each grain, and their cell values.
  int f_spin_ = -1, f_strain_diag_ = -1, f_strain_off_ = -1;
  std::vector<Mat3> cell_grad_;
  std::vector<Vec3> cell_spin_, cell_strain_diag_, cell_strain_off_;
  cfd_dem::PointRead point_read_ = cfd_dem::PointRead::Trilinear;  // coupling.interpolation
  std::vector<double> rate_new_;    // the flux rate of this step before relaxation
  cfd_dem::Footprints footprints_;  // of the grains at the current fluid step
  std::vector<double> eps_, eps_prev_, eps_rate_, k_, eps_p_;
  std::vector<Vec3> s_explicit_, cell_u_, cell_gradp_, u_p_, gradp_p_;
  std::vector<cfd_dem::LerpStencil> stencils_;  // the grains' interpolation stencils this step

  // coupling.heat_transfer: the correlation, the fluid's temperature and its properties, the
  // grains' fields (conductance h A [W/K], fluid temperature read at the grain [K], temperature)
  // and per-cell sources.
  int heat_law_ = -1;
  std::unique_ptr<fluid::FluidHeat> heat_;
  fluid::HeatStepReport heat_report_;
  double k_f_ = 0, prandtl_ = 0;
  int f_conductance_ = -1, f_tf_ = -1, f_temperature_ = -1, f_received_ = -1;
  std::vector<double> heat_q_, heat_k_, heat_value_;
  // Per cell: the heat the fluid gave the grains over its last step, J (dt_f V (K T - q)), and
  // what the grains received since, J; their difference returns to the fluid next step.
  std::vector<double> heat_given_, heat_received_;
  std::vector<double> heat_qx_;  // per cell: the exchange part of the source (no correction)
};

}  // namespace gf
