// SPDX-License-Identifier: GPL-3.0-or-later
// Unresolved CFD-DEM in the time loop: fluid sub-cycling, fluid fraction, drag, exchange.
#include "simulation/cfd_dem_coupling.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <utility>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/vtk_xml.hpp"
#include "coupling/cfd_dem/heat_transfer.hpp"
#include "coupling/cfd_dem/hydro_torque.hpp"
#include "coupling/cfd_dem/shape_factors.hpp"
#include "particles/particle_store.hpp"

namespace gf {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

fluid::BoundaryCondition to_bc(const config::FluidBoundary& b) {
  using K = config::FluidBoundary::Kind;
  switch (b.kind) {
    case K::Periodic:
      return fluid::BoundaryCondition::periodic();
    case K::NoSlip:
      return fluid::BoundaryCondition::no_slip();
    case K::MovingWall:
      return fluid::BoundaryCondition::moving_wall(b.velocity);
    case K::VelocityInlet:
      // The case gives the superficial velocity eps u (what a bed's flow rate is): the solver
      // divides it by the fluid fraction of the cell next to the inlet.
      return fluid::BoundaryCondition::velocity_inlet(b.velocity, true);
    case K::PressureOutlet:
      return fluid::BoundaryCondition::pressure_outlet(b.pressure);
  }
  return fluid::BoundaryCondition::no_slip();
}

}  // namespace

CfdDemCoupling::CfdDemCoupling(const config::Case& cfg, ParticleStore& particles, double dem_dt) {
  REQUIRE(cfg.fluid && cfg.coupling, "CFD-DEM needs both a fluid and a coupling block");
  const auto& f = *cfg.fluid;
  const auto& cp = *cfg.coupling;
  grid_.dimension = 3;
  grid_.n = f.cells;
  grid_.lo = cfg.domain.min;
  for (int k = 0; k < 3; ++k) grid_.h[k] = (cfg.domain.max[k] - cfg.domain.min[k]) / f.cells[k];
  grid_.periodic = cfg.domain.periodic;

  fluid::FluidSettings s;
  s.density = f.density;
  s.dynamic_viscosity = f.viscosity;
  s.gravity = cfg.gravity;
  for (int face = 0; face < 6; ++face) s.boundary[face] = to_bc(f.boundary[face]);
  s.convection = f.convection == "central"  ? fluid::Convection::Central
                 : f.convection == "upwind" ? fluid::Convection::Upwind
                                            : fluid::Convection::VanLeer;
  try {
    fluid_ = std::make_unique<fluid::VolumeAveragedNS>(grid_, s);
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    throw InputError(fmt::format("{}: fluid: {}", cfg.file.string(), e.what()));
  }
  if (cfg.shear && cfg.shear->initial_profile) {
    // Between shear walls the fluid starts, like the grains, on the steady Couette profile:
    // viscous diffusion across the gap takes h^2 / nu (~180 s for 48 mm of air), far longer
    // than a run, so a fluid started at rest would be set in motion by the grains alone.
    const Vec3 u0 = f.initial_velocity;
    const double rate = cfg.shear->rate, zmid = 0.5 * (cfg.domain.min.z + cfg.domain.max.z);
    fluid_->set_velocity([=](const Vec3& x) { return u0 + Vec3{rate * (x.z - zmid), 0, 0}; });
  } else if (norm2(f.initial_velocity) > 0) {
    const Vec3 u0 = f.initial_velocity;
    fluid_->set_velocity([u0](const Vec3&) { return u0; });
  }
  rho_f_ = f.density;
  mu_f_ = f.viscosity;
  interval_ = cp.interval;
  dt_fluid_ = cp.interval * dem_dt;
  law_ = cfd_dem::drag_index(cp.drag);
  REQUIRE(law_ >= 0, "unknown drag law '{}'", cp.drag);
  drag_params_ = cfd_dem::prepare_drag(cp.drag, cp.drag_params);
  const auto scheme = cfd_dem::deposit_scheme(cp.fluid_fraction);
  REQUIRE(scheme.has_value(), "unknown fluid-fraction scheme '{}'", cp.fluid_fraction);
  ff_options_.scheme = *scheme;
  ff_options_.min_fraction = cp.min_fraction;
  rate_from_motion_ = cp.fluid_fraction_rate != "difference";
  rate_from_derivative_ = cp.fluid_fraction_rate == "derivative";
  rate_relaxation_ = cp.rate_relaxation;
  pressure_gradient_force_ = cp.pressure_gradient_force;
  point_read_ =
      cp.interpolation == "cell" ? cfd_dem::PointRead::CellValue : cfd_dem::PointRead::Trilinear;
  torque_ = cp.torque == "rotational";

  // Pressure drop and superficial velocity along gravity's axis (the axis of a bed).
  const Vec3 g = cfg.gravity;
  if (norm2(g) > 0) {
    flow_axis_ = 0;
    for (int k = 1; k < 3; ++k)
      if (std::abs(g[k]) > std::abs(g[flow_axis_])) flow_axis_ = k;
  }
  closed_ = std::none_of(s.boundary.begin(), s.boundary.end(),
                         [](const auto& b) { return b.kind == fluid::BcKind::PressureOutlet; });

  // Per-grain exchange state as particle fields: the re-ordering at neighbour rebuilds and the
  // checkpoints carry them with the grains.
  f_beta_ = particles.add_field("fluid_beta", FieldType::Real, "N s/m", kRestart);
  // (analysis::measure_rheology reads "fluid_velocity" by name for the fluid/slip temperatures)
  f_uf_ = particles.add_field("fluid_velocity", FieldType::Vec3, "m/s", kRestart | kOutput);
  f_fixed_ = particles.add_field("fluid_force_fixed", FieldType::Vec3, "N", kRestart);
  if (torque_) {
    f_spin_ = particles.add_field("fluid_spin", FieldType::Vec3, "rad/s", kRestart);
    f_strain_diag_ =
        particles.add_field("fluid_strain_rate_diagonal", FieldType::Vec3, "1/s", kRestart);
    f_strain_off_ =
        particles.add_field("fluid_strain_rate_shear", FieldType::Vec3, "1/s", kRestart);
  }
  if (!cp.heat_transfer.empty()) {
    heat_law_ = cfd_dem::heat_transfer_index(cp.heat_transfer);
    REQUIRE(heat_law_ >= 0, "unknown heat transfer correlation '{}'", cp.heat_transfer);
    f_temperature_ = particles.find_field("temperature");
    if (f_temperature_ < 0 || !cfg.heat)
      throw InputError(
          fmt::format("{}: coupling.heat_transfer needs the grains' temperatures: a "
                      "heat: block",
                      cfg.file.string()));
    fluid::HeatSettings hs;
    hs.heat_capacity = f.heat_capacity;
    hs.thermal_conductivity = f.thermal_conductivity;
    hs.convection = f.temperature_convection == "upwind" ? fluid::Convection::Upwind
                                                         : fluid::Convection::VanLeer;
    hs.thermal_expansion = f.thermal_expansion;
    hs.reference_temperature =
        f.reference_temperature.value_or(f.temperature.value_or(cfg.heat->temperature));
    for (int face = 0; face < 6; ++face)
      hs.boundary_temperature[face] =
          f.boundary[face].temperature.value_or(std::numeric_limits<double>::quiet_NaN());
    try {
      heat_ = std::make_unique<fluid::FluidHeat>(*fluid_, hs,
                                                 f.temperature.value_or(cfg.heat->temperature));
    } catch (const InputError&) {
      throw;
    } catch (const Error& e) {
      throw InputError(fmt::format("{}: fluid: {}", cfg.file.string(), e.what()));
    }
    k_f_ = f.thermal_conductivity;
    prandtl_ = f.heat_capacity * mu_f_ / k_f_;
    f_conductance_ =
        particles.add_field("fluid_heat_conductance", FieldType::Real, "W/K", kRestart | kOutput);
    f_tf_ = particles.add_field("fluid_temperature", FieldType::Real, "K", kRestart | kOutput);
    f_received_ = particles.add_field("fluid_heat_received", FieldType::Real, "J", kRestart);
  }
}

void CfdDemCoupling::fluid_step(ParticleStore& particles) {
  // The fluid's convection is explicit: a step above its Courant limit is a run that has to
  // stop, said in the case's terms (the fluid step is coupling.interval DEM steps), before any
  // state changes (a NaN Courant number too).
  if (const double courant = fluid_->max_cfl(dt_fluid_);
      !(courant <= fluid_->settings().max_courant)) {
    if (!std::isfinite(courant))
      throw Error("CFD-DEM: the fluid velocity is not finite: the coupled run has diverged");
    const auto most = static_cast<long long>(static_cast<double>(interval_) *
                                             fluid_->settings().max_courant / courant);
    throw Error(fmt::format(
        "CFD-DEM: the fluid step of {:g} s (coupling.interval = {} DEM steps) gives a Courant "
        "number {:.3g} above {} (the fluid's convection is explicit): {}",
        dt_fluid_, interval_, courant, fluid_->settings().max_courant,
        most >= 1 ? fmt::format("lower coupling.interval to {} or less", most)
                  : std::string("lower time.step")));
  }
  const auto t0 = Clock::now();
  const cfd_dem::ParticleGeometry geo = cfd_dem::geometry_of(particles, geo_buffers_);
  const std::size_t n = geo.size();
  const auto nc = static_cast<std::size_t>(grid_.cell_count());
  // resize() is a no-op once the sizes are reached: no allocation after the first step.
  for (auto* v : {&eps_, &eps_prev_, &eps_rate_, &k_}) v->resize(nc);
  for (auto* v : {&s_explicit_, &cell_u_, &cell_gradp_}) v->resize(nc);
  eps_p_.resize(n);
  u_p_.resize(n);
  gradp_p_.resize(n);
  stencils_.resize(n);

  // The grains stay put during this call: one set of footprints serves every deposit. With the
  // derivative rate the footprints' time derivatives come from the same walk over the points.
  if (rate_from_derivative_)
    cfd_dem::footprints_with_rates(
        grid_, geo, ff_options_.scheme, std::span<const Vec3>(particles.v(), n),
        std::span<const Vec3>(particles.omega(), n), footprints_, rate_fp_);
  else
    cfd_dem::compute_footprints(grid_, geo, ff_options_.scheme, footprints_);
  cfd_dem::fluid_fraction(grid_, footprints_, ff_options_.min_fraction, eps_);
  if (first_) std::copy(eps_.begin(), eps_.end(), eps_prev_.begin());
  if (rate_from_motion_) {
    // The divergence of the grains' solid volume flux: smooth, where the deposited eps moves in
    // steps as sample points cross faces (a lattice suspension crossing faces together sees
    // no return flow between the crossings with the difference).
    // Under-relaxed between fluid steps: the rate follows the grains' velocities at once, the
    // fluid's pressure answers at once, and the grains feel that pressure (-V grad p) over the
    // next interval, an explicit loop whose gain is about the added mass of the returning fluid
    // over the grains' mass, (rho_f / rho_p) (1 - eps) / eps times a grid factor. Above 1 (rods
    // in water at phi = 0.4: the fluid's energy grew 4x per 0.2 ms) it diverges; relaxing by a
    // keeps the loop stable up to a gain of 2 / a - 1 (a = 0.3: 5.7) and delays the rate by
    // ~1/a fluid steps, short against a grain's response time.
    // With a continuous deposit the rate can instead be its exact time derivative (deposited
    // with the same shares): it integrates to the deposited fraction itself, where the
    // face-averaged flux spreads each grain's change over one cell more and its integral
    // drifts from the deposit.
    rate_new_.resize(nc);
    if (rate_from_derivative_) {
      std::fill(rate_new_.begin(), rate_new_.end(), 0.0);
      cfd_dem::deposit(rate_fp_, std::span<const double>(rate_fp_.volume), rate_new_,
                       -1.0 / grid_.cell_volume());
    } else {
      cfd_dem::fluid_fraction_rate_from_flux(
          grid_, footprints_, std::span<const Vec3>(particles.v(), n), rate_new_, solid_flux_);
    }
    const double a = first_ ? 1.0 : rate_relaxation_;
    exec::parallel_for(static_cast<exec::index_t>(nc),
                       [&](exec::index_t c) { eps_rate_[c] += a * (rate_new_[c] - eps_rate_[c]); });
  } else {
    const double inv_dt = 1.0 / dt_fluid_;
    exec::parallel_for(static_cast<exec::index_t>(nc),
                       [&](exec::index_t c) { eps_rate_[c] = (eps_[c] - eps_prev_[c]) * inv_dt; });
  }
  if (closed_) {
    // Without an outlet the fluid volume is fixed, so sum(d eps/dt) must vanish. Moving grains
    // conserve the solid volume, but the clamp at min_fraction does not: remove its (small)
    // net rate uniformly, or the pressure equation has no solution.
    double sum = 0;
    for (double r : eps_rate_) sum += r;
    const double mean = sum / static_cast<double>(nc);
    for (double& r : eps_rate_) r -= mean;
  }

  // Drag coefficients with the fluid velocity before the step and the grains' velocities now.
  fluid_->cell_velocities(cell_u_);
  cfd_dem::point_stencils(grid_, geo.x, stencils_, point_read_);  // read again after the fluid step
  cfd_dem::interpolate_at(grid_, stencils_, std::span<const Vec3>(cell_u_), u_p_,
                          std::span<const double>(eps_), eps_p_);
  const Vec3* v = particles.v();
  auto beta = particles.get<double>(f_beta_);
  exec::parallel_for(static_cast<exec::index_t>(n), [&](exec::index_t i) {
    const Vec3 slip = u_p_[i] - v[i];
    const double half = geo.half(static_cast<std::size_t>(i));
    cfd_dem::DragInput in;
    if (half > 0) {
      in = cfd_dem::spherocylinder_drag_input(rho_f_, mu_f_, eps_p_[i], geo.radius[i], 2.0 * half,
                                              geo.axis[i], slip);
    } else {
      in.rho_f = rho_f_;
      in.mu_f = mu_f_;
      in.eps = eps_p_[i];
      in.d_v = 2.0 * geo.radius[i];
      in.slip = slip;
    }
    beta[i] = cfd_dem::drag_force(law_, in, drag_params_).beta;
  });
  // The fluid gets the reaction of the drag the grains feel, -beta_i (u_f,i - v_i) with the
  // u_f,i they read, not beta_i (v_i - u_c) with its own cell values (which differ inside a
  // cell with trilinear reads: a grain carried at the interpolated velocity would push its
  // cell's fluid, by 5 % of the shear across it in CfdDemValidation's Couette test).
  cfd_dem::drag_exchange_source(footprints_, beta, std::span<const Vec3>(v, n),
                                std::span<const Vec3>(u_p_), std::span<const Vec3>(cell_u_),
                                s_explicit_, k_);

  if (heat_) {
    exchange_heat(particles, geo);
    heat_->add_buoyancy(*fluid_, s_explicit_);  // with the temperatures before the step
  }

  fluid_->set_fluid_fraction(eps_, eps_rate_);
  fluid_->set_momentum_source(s_explicit_, k_);
  fluid_->step(dt_fluid_);
  if (heat_) {
    // The fluid's temperature over the same step, carried by the new velocities; the grains
    // read it until the next fluid step.
    heat_report_ = heat_->step(dt_fluid_, *fluid_, eps_prev_);
    const auto t_new = heat_->temperature();
    const double v_dt = grid_.cell_volume() * dt_fluid_;
    heat_given_.resize(t_new.size());
    for (std::size_t c = 0; c < t_new.size(); ++c)
      heat_given_[c] = v_dt * (heat_k_[c] * t_new[c] - heat_qx_[c]);
    cfd_dem::interpolate_at(grid_, stencils_, heat_->temperature(), particles.get<double>(f_tf_));
  }
  std::copy(eps_.begin(), eps_.end(), eps_prev_.begin());
  first_ = false;

  // What the grains see until the next fluid step: u_f,i, and the part of their force that
  // stays fixed until then, beta_i u_f,i - V_i grad p_i (add_forces subtracts beta_i v_i). With
  // coupling.pressure_gradient_force off, cell_gradp_ stays as sized (zero): drag only.
  fluid_->cell_velocities(cell_u_);
  if (pressure_gradient_force_) fluid_->pressure_gradients(cell_gradp_);
  auto uf = particles.get<Vec3>(f_uf_);
  cfd_dem::interpolate_at(grid_, stencils_, std::span<const Vec3>(cell_u_), uf,
                          std::span<const Vec3>(cell_gradp_), std::span<Vec3>(gradp_p_));
  auto fixed = particles.get<Vec3>(f_fixed_);
  exec::parallel_for(static_cast<exec::index_t>(n), [&](exec::index_t i) {
    const auto k = static_cast<std::size_t>(i);
    fixed[k] = beta[k] * uf[k] + cfd_dem::pressure_gradient_force(geo.volume(k), gradp_p_[k]);
  });
  if (torque_) {
    // The fluid's rotation and strain rates at the grains, read like its velocity (the torque
    // itself follows the grain's angular velocity and axis at every DEM step, in add_torques).
    cell_grad_.resize(nc);
    for (auto* cells : {&cell_spin_, &cell_strain_diag_, &cell_strain_off_}) cells->resize(nc);
    fluid_->cell_velocity_gradients(cell_grad_);
    exec::parallel_for(static_cast<exec::index_t>(nc), [&](exec::index_t c) {
      const Mat3 e = strain_rate(cell_grad_[c]);
      cell_spin_[c] = rotation_rate(cell_grad_[c]);
      cell_strain_diag_[c] = {e.a[0][0], e.a[1][1], e.a[2][2]};
      cell_strain_off_[c] = {e.a[1][2], e.a[0][2], e.a[0][1]};
    });
    cfd_dem::interpolate_at(grid_, stencils_, std::span<const Vec3>(cell_spin_),
                            particles.get<Vec3>(f_spin_), std::span<const Vec3>(cell_strain_diag_),
                            particles.get<Vec3>(f_strain_diag_));
    cfd_dem::interpolate_at(grid_, stencils_, std::span<const Vec3>(cell_strain_off_),
                            particles.get<Vec3>(f_strain_off_));
  }
  seconds_ += seconds_since(t0);
}

void CfdDemCoupling::exchange_heat(ParticleStore& particles, const cfd_dem::ParticleGeometry& geo) {
  const std::size_t n = geo.size();
  const auto nc = static_cast<std::size_t>(grid_.cell_count());
  heat_value_.resize(n);
  heat_q_.assign(nc, 0.0);
  heat_k_.assign(nc, 0.0);
  const auto cond = particles.get<double>(f_conductance_);
  const auto tf = particles.get<double>(f_tf_);
  const double* temp = std::as_const(particles).get<double>(f_temperature_).data();
  const Vec3* v = particles.v();
  // The fluid's temperature before this step at the grains' positions now: what the grains
  // felt over the last interval, and what the deposit below is consistent with.
  cfd_dem::interpolate_at(grid_, stencils_, heat_->temperature(), tf);
  exec::parallel_for(static_cast<exec::index_t>(n), [&](exec::index_t i) {
    const auto k = static_cast<std::size_t>(i);
    const double l = 2.0 * geo.half(k), r = geo.radius[k];
    const double d_v = cfd_dem::volume_equivalent_diameter(cfd_dem::spherocylinder_volume(r, l));
    const double re = rho_f_ * norm(u_p_[k] - v[k]) * d_v / mu_f_;
    const double nu = cfd_dem::nusselt(heat_law_, re, prandtl_, eps_p_[k]);
    cond[k] = cfd_dem::fluid_conductance(nu, k_f_, d_v, cfd_dem::spherocylinder_surface(r, l));
    heat_value_[k] = cond[k] * (temp[k] - tf[k]);  // into the fluid, W
  });
  // Q = sum w h A (T_p - T_seen) / V + K T_c - K T: the heat the grains give at the fluid's
  // present temperature, implicit in its change over the step (the form of
  // drag_exchange_source, so that a grain at the temperature it reads exchanges nothing).
  const double inv_v = 1.0 / grid_.cell_volume();
  cfd_dem::deposit(footprints_, std::span<const double>(heat_value_), std::span<double>(heat_q_),
                   inv_v);
  cfd_dem::deposit(footprints_, std::span<const double>(cond.data(), n), std::span<double>(heat_k_),
                   inv_v);
  const auto tc = heat_->temperature();
  for (std::size_t c = 0; c < nc; ++c) heat_q_[c] += heat_k_[c] * tc[c];
  heat_qx_.assign(heat_q_.begin(), heat_q_.end());
  // What the fluid gave over its last step that the grains did not take since (they changed
  // temperature over the interval) returns to it now, cell by cell (deposited with the grains'
  // footprints now: the sum over cells is exact, the place within a grain's move).
  const auto received = particles.get<double>(f_received_);
  if (heat_given_.size() == nc) {
    heat_received_.assign(nc, 0.0);
    cfd_dem::deposit(footprints_, std::span<const double>(received.data(), n),
                     std::span<double>(heat_received_));
    const double per_step = inv_v / dt_fluid_;
    for (std::size_t c = 0; c < nc; ++c)
      heat_q_[c] += (heat_given_[c] - heat_received_[c]) * per_step;
  }
  std::fill(received.begin(), received.end(), 0.0);
  heat_->set_source(heat_q_, heat_k_);
}

double CfdDemCoupling::heat_in_transit(const ParticleStore& particles) const {
  if (!heat_) return 0.0;
  double given = 0.0, received = 0.0;
  for (const double g : heat_given_) given += g;
  for (const double r : particles.get<double>(f_received_)) received += r;
  return given - received;
}

void CfdDemCoupling::add_heat(ParticleStore& particles, const double* temperature, double* q,
                              double* h, double dt) const {
  if (!heat_) return;
  const auto t0 = Clock::now();
  const double* cond = std::as_const(particles).get<double>(f_conductance_).data();
  const double* tf = std::as_const(particles).get<double>(f_tf_).data();
  double* received = particles.get<double>(f_received_).data();
  exec::parallel_for(static_cast<exec::index_t>(particles.size()), [&](exec::index_t i) {
    const double flow = cond[i] * (tf[i] - temperature[i]);
    q[i] += flow;
    h[i] += cond[i];
    received[i] += dt * flow;
  });
  force_seconds_ += seconds_since(t0);
}

fluid::VolumeAveragedNS::State CfdDemCoupling::state() const {
  auto st = fluid_->state();
  std::vector<double> prev(eps_prev_);
  prev.resize(static_cast<std::size_t>(grid_.cell_count()), 1.0);  // before the first step
  st.arrays.emplace_back("coupling_eps_prev", std::move(prev));
  std::vector<double> rate(eps_rate_);
  rate.resize(static_cast<std::size_t>(grid_.cell_count()), 0.0);
  st.arrays.emplace_back("coupling_eps_rate", std::move(rate));  // the relaxed flux rate
  if (heat_) {
    st.arrays.emplace_back("fluid_temperature", std::vector<double>(heat_->temperature().begin(),
                                                                    heat_->temperature().end()));
    std::vector<double> given(heat_given_);
    given.resize(static_cast<std::size_t>(grid_.cell_count()), 0.0);
    st.arrays.emplace_back("fluid_heat_given", std::move(given));
  }
  return st;
}

void CfdDemCoupling::restore(const fluid::VolumeAveragedNS::State& st) {
  fluid_->restore(st);
  const auto nc = static_cast<std::size_t>(grid_.cell_count());
  bool restored_temperature = false;
  for (const auto& [name, v] : st.arrays)
    if (name == "coupling_eps_prev") {
      REQUIRE(v.size() == nc, "coupling restore: {} fluid fractions for {} cells", v.size(), nc);
      eps_prev_ = v;
    } else if (name == "coupling_eps_rate") {
      REQUIRE(v.size() == nc, "coupling restore: {} rates for {} cells", v.size(), nc);
      eps_rate_ = v;  // absent in older checkpoints: the relaxation restarts from zero
    } else if (name == "fluid_temperature" && heat_) {
      REQUIRE(v.size() == nc, "coupling restore: {} temperatures for {} cells", v.size(), nc);
      heat_->set_temperature(v);
      restored_temperature = true;
    } else if (name == "fluid_heat_given" && heat_) {
      REQUIRE(v.size() == nc, "coupling restore: {} heat values for {} cells", v.size(), nc);
      heat_given_ = v;
    }
  REQUIRE(!heat_ || restored_temperature,
          "coupling restore: the checkpoint has no fluid temperature (written without "
          "coupling.heat_transfer)");
  REQUIRE(eps_prev_.size() == nc, "coupling restore: no fluid fraction of the last fluid step");
  first_ = st.n_steps == 0;
}

void CfdDemCoupling::add_forces(ParticleStore& particles) const {
  const auto t0 = Clock::now();
  const std::size_t n = particles.size();
  const double* beta = std::as_const(particles).get<double>(f_beta_).data();
  const Vec3* fixed = std::as_const(particles).get<Vec3>(f_fixed_).data();
  const Vec3* v = particles.v();
  Vec3* f = particles.f();
  exec::parallel_for(static_cast<exec::index_t>(n),
                     [&](exec::index_t i) { f[i] += fixed[i] - beta[i] * v[i]; });
  if (torque_) add_torques(particles);
  force_seconds_ += seconds_since(t0);
}

void CfdDemCoupling::add_torques(ParticleStore& particles) const {
  const std::size_t n = particles.size();
  const auto& store = std::as_const(particles);
  const Vec3* spin = store.get<Vec3>(f_spin_).data();
  const Vec3* diag = store.get<Vec3>(f_strain_diag_).data();
  const Vec3* off = store.get<Vec3>(f_strain_off_).data();
  const Vec3* omega = particles.omega();
  Vec3* torque = particles.torque();
  exec::parallel_for(static_cast<exec::index_t>(n), [&](exec::index_t i) {
    const auto g = cfd_dem::grain_shape(particles, static_cast<std::size_t>(i));
    const double d_v = cfd_dem::volume_equivalent_diameter(
        cfd_dem::spherocylinder_volume(g.radius, 2.0 * g.half_length));
    Mat3 strain = Mat3::diagonal(diag[i]);
    strain.a[1][2] = strain.a[2][1] = off[i].x;
    strain.a[0][2] = strain.a[2][0] = off[i].y;
    strain.a[0][1] = strain.a[1][0] = off[i].z;
    torque[i] +=
        cfd_dem::hydrodynamic_torque(cfd_dem::rotational_resistance(mu_f_, g.radius, g.half_length),
                                     g.axis, spin[i], strain, omega[i], rho_f_, mu_f_, d_v);
  });
}

double CfdDemCoupling::pressure_drop() const {
  // The dynamic part: the hydrostatic difference rho_f |g| L of a fluid at rest is taken off,
  // so that a fixed bed reads its frictional loss and a fluidised bed its buoyant weight / area.
  const int a = flow_axis_;
  const double lo = grid_.lo[a], hi = grid_.hi()[a];
  return fluid_->pressure_drop(a, lo, hi) + rho_f_ * fluid_->settings().gravity[a] * (hi - lo);
}

double CfdDemCoupling::superficial_velocity() const {
  return fluid_->superficial_velocity(flow_axis_, grid_.n[flow_axis_] / 2);
}

double CfdDemCoupling::min_fluid_fraction() const {
  const auto eps = fluid_->fluid_fraction();
  return eps.empty() ? 1.0 : *std::min_element(eps.begin(), eps.end());
}

void CfdDemCoupling::write_vti(std::ostream& out) const {
  const auto& g = grid_;
  std::vector<Vec3> u(static_cast<std::size_t>(g.cell_count()));
  fluid_->cell_velocities(u);
  vtk::AppendedArrays arrays;  // tags in block order: one statement per array
  const std::string eps_tag =
      vtk::AppendedArrays::tag(arrays.add("fluid_fraction", 1, fluid_->fluid_fraction()));
  const std::string p_tag = vtk::AppendedArrays::tag(arrays.add("pressure", 1, fluid_->pressure()));
  const std::string u_tag =
      vtk::AppendedArrays::tag(arrays.add("velocity", std::span<const Vec3>(u)));
  std::string tags = "        " + eps_tag + "\n        " + p_tag + "\n        " + u_tag + "\n";
  if (heat_)
    tags += "        " +
            vtk::AppendedArrays::tag(arrays.add("temperature", 1, heat_->temperature())) + "\n";
  vtk::write_image_data(out, g.n, g.lo, g.h, arrays, tags,
                        " Scalars=\"fluid_fraction\" Vectors=\"velocity\"");
}

}  // namespace gf
