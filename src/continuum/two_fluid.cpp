// SPDX-License-Identifier: GPL-3.0-or-later
// Two-fluid model on the MAC grid: closures per cell, the solids momentum predictor, the
// volume-fraction equation with implicit solids pressure, and the coupling to the fluid solver.
//
// Stencils (docs/models/two_fluid.md): the solids velocity lives on the faces like the fluid's;
// a, Theta, P_s, mu_s, lambda_s, beta at cell centres. Normal viscous stresses at cell centres,
// shear stresses at cell edges with mu averaged over the edge's four cells, so div(tau) on a face
// is a difference of stresses (the transposed gradient included). Convection of u_s in flux
// form less u_s times continuity, first-order upwind (MFIX's staggered scheme: only inflowing
// mass changes a face's velocity; upwinding keeps dense fronts free of overshoots).
// The volume-fraction flux carries van Leer's limited face value of a, or the upwind cell's
// (bounded: a >= 0 for a solids Courant number below 1/2, resp. 1, before the implicit pressure
// part). Values outside the grid across an axis
// b != a come from the wall rule u_ghost - u_w = r (u_in - u_w) with r = -1 (no slip), +1 (free
// slip) or the Johnson-Jackson ratio, which makes the shear stress at the wall edge
// mu (u_ghost - u_in) / h equal the condition's.
#include "continuum/two_fluid.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "coupling/cfd_dem/drag_registry.hpp"
#include "fluid/fv/limiter.hpp"

namespace gf::continuum {

namespace {

using fluid::entry_position;
using fluid::zero_column;

constexpr double kPi = 3.14159265358979323846;
/// A cell holds solids (for the stencils at free surfaces) above this volume fraction.
constexpr double kPresent = 1e-3;
/// Floor of dP_s/da in the implicit solids pressure [Pa]: below it the increment is negligible.
constexpr double kMinPressureSlope = 1e-6;

int wrap(int i, int n) {
  i %= n;
  return i < 0 ? i + n : i;
}

/// The seed's dense-regime pressure (Gomez Fino 2014, eq 14, after Josserand, Lagree & Lhuillier
/// 2006): p0 ln((a_M - a_m) / (a_M - a)) for a > a_m, 0 below [Pa].
double logarithmic_pressure(double a, const TwoFluidSettings::LogPressure& lp) {
  if (!(a > lp.min_fraction)) return 0.0;
  return lp.p0 * std::log((lp.max_fraction - lp.min_fraction) / (lp.max_fraction - a));
}

}  // namespace

TwoFluidModel::TwoFluidModel(const fluid::Grid& grid, TwoFluidSettings settings)
    : grid_(grid), s_(std::move(settings)), fluid_(grid, s_.fluid), dim_(grid.dimension) {
  check_settings();
  const std::int64_t nc = grid_.cell_count();
  alpha_.assign(nc, 0.0);
  alpha_old_.assign(nc, 0.0);
  theta_.assign(nc, s_.min_temperature);
  for (auto* f :
       {&ps_, &dps_, &mu_, &lambda_, &beta_, &delta_, &eps_, &eps_rate_, &trace_d_, &dev_dd_})
    f->assign(nc, 0.0);
  eps_.assign(nc, 1.0);
  us_cell_.assign(nc, Vec3{});
  uf_cell_.assign(nc, Vec3{});
  source_.assign(nc, Vec3{});
  for (int a = 0; a < 3; ++a) {
    const std::int64_t nf = a < dim_ ? grid_.face_count(a) : 0;
    for (auto* v : {&us_[a], &ustar_[a], &coef_[a], &face_fraction_[a], &inertia_[a], &carried_[a],
                    &flux_[a], &adv_flux_[a]})
      v->assign(nf, 0.0);
  }
  build_fraction_system();
  build_momentum_systems();
  evaluate_closures();
}

void TwoFluidModel::check_settings() {
  const KtgfParams& k = s_.ktgf;
  REQUIRE(k.diameter > 0 && k.density > 0,
          "two-fluid model: grain diameter {} m and density {} kg/m^3 must be > 0", k.diameter,
          k.density);
  REQUIRE(k.restitution >= 0 && k.restitution < 1,
          "two-fluid model: the algebraic granular temperature needs a restitution in [0, 1), "
          "got {}",
          k.restitution);
  REQUIRE(s_.temperature != GranularTemperature::Algebraic ||
              k.model == index_of_key(KtgfClosures{}, Syamlal::key),
          "two-fluid model: the algebraic granular temperature needs the '{}' closures, whose "
          "viscosity vanishes with the volume fraction; with the others the local balance gives "
          "Theta ~ 1/a^2 in dilute cells (use the transported temperature)",
          Syamlal::key);
  REQUIRE(s_.drag.law >= 0, "two-fluid model: no drag law (use cfd_dem::prepare_drag)");
  REQUIRE(s_.particle_pressure.model < static_cast<int>(particle_pressure_model_infos().size()),
          "two-fluid model: no particle-pressure model {} (use prepare_particle_pressure)",
          s_.particle_pressure.model);
  REQUIRE(s_.specularity >= 0 && s_.specularity <= 1,
          "two-fluid model: specularity coefficient {} outside [0, 1]", s_.specularity);
  REQUIRE(s_.wall_restitution >= 0 && s_.wall_restitution <= 1,
          "two-fluid model: wall restitution {} outside [0, 1]", s_.wall_restitution);
  REQUIRE(s_.fraction_convection != fluid::Convection::Central,
          "two-fluid model: the volume fraction's flux must be bounded (van Leer or upwind), not "
          "central");
  REQUIRE(s_.max_courant > 0 && s_.max_courant <= 1,
          "two-fluid model: max_courant {} outside (0, 1]", s_.max_courant);
  mu_i_switch_ =
      s_.frictional && s_.dense.model == index_of_key(FrictionalModels{}, MuISwitch::key);
  if (mu_i_switch_) {
    REQUIRE(s_.dense_rheology.model == index_of_key(Rheologies{}, MuI::key),
            "two-fluid model: the '{}' dense regime needs the 'mu_i' rheology (prepare_rheology)",
            MuISwitch::key);
    const auto& lp = s_.log_pressure;
    REQUIRE(lp.p0 > 0 && lp.min_fraction > 0 && lp.min_fraction < lp.max_fraction &&
                lp.max_fraction < 1,
            "two-fluid model: the '{}' dense regime needs its pressure p0 ln((a_M - a_m) / (a_M - "
            "a)) with p0 > 0 and 0 < a_m < a_M < 1 (got p0 = {}, a_m = {}, a_M = {})",
            MuISwitch::key, lp.p0, lp.min_fraction, lp.max_fraction);
  }
  // The cap stays below every divergence: g0's packing limit, the frictional a_max, the a_M of
  // the logarithmic pressure.
  double limit = k.packing_limit > 0 ? k.packing_limit : 1.0;
  if (s_.frictional)
    limit = std::min(limit, mu_i_switch_ ? s_.log_pressure.max_fraction : s_.dense.max_fraction);
  a_max_ = s_.max_fraction > 0 ? s_.max_fraction : limit - 0.005;
  REQUIRE(a_max_ > 0 && a_max_ < limit,
          "two-fluid model: max_fraction {} must lie in (0, {}) (the packing limit of g0 and the "
          "frictional a_max)",
          a_max_, limit);
  v_p_ = kPi * k.diameter * k.diameter * k.diameter / 6.0;
  for (int face = 0; face < 6; ++face) {
    if (face / 2 >= dim_) continue;
    const auto kind = s_.fluid.boundary[face].kind;
    REQUIRE((kind == fluid::BcKind::Periodic) == grid_.periodic[face / 2],
            "two-fluid model: face {} is periodic for the fluid but the grid's axis is not (or "
            "the reverse)",
            fluid::box_face_name(face));
  }
}

std::int64_t TwoFluidModel::cell(Index3 c) const {
  for (int b = 0; b < 3; ++b) c[b] = grid_.fold(b, c[b]);
  return grid_.index(c[0], c[1], c[2]);
}

TwoFluidModel::FaceKind TwoFluidModel::face_kind(int a, int i) const {
  if (grid_.periodic[a]) return i == grid_.n[a] ? FaceKind::PeriodicImage : FaceKind::Interior;
  if (i > 0 && i < grid_.n[a]) return FaceKind::Interior;
  const auto& bc = s_.fluid.boundary[fluid::box_face_index(a, i == 0 ? 0 : 1)];
  return bc.kind == fluid::BcKind::PressureOutlet ? FaceKind::Outlet : FaceKind::Wall;
}

Vec3 TwoFluidModel::wall_velocity(int b, int side) const {
  const auto& bc = s_.fluid.boundary[fluid::box_face_index(b, side)];
  return bc.kind == fluid::BcKind::MovingWall ? bc.velocity : Vec3{};
}

double TwoFluidModel::wall_ratio(int b, int side, std::int64_t c) const {
  switch (s_.solids_wall[fluid::box_face_index(b, side)]) {
    case SolidsWall::NoSlip:
      return -1.0;
    case SolidsWall::FreeSlip:
      return 1.0;
    case SolidsWall::JohnsonJackson: {
      const double a = std::min(alpha_[c], a_max_);
      const double g0 = radial_distribution(a, s_.ktgf);
      const double cjj = kPi * std::sqrt(3.0) / 6.0 * s_.specularity * (a / a_max_) *
                         s_.ktgf.density * g0 * std::sqrt(theta_[c]);
      const double num = 2.0 * mu_[c] - cjj * grid_.h[b], den = 2.0 * mu_[c] + cjj * grid_.h[b];
      return den > 0 ? num / den : 1.0;
    }
  }
  return -1.0;
}

// Solids velocity component a at face coordinates q (faces along a, cells across), which may lie
// one step outside the grid: wrapped on periodic axes, the boundary face along a, the wall rule
// across a wall.
std::int64_t TwoFluidModel::upwind_cell(int a, Index3 q, double u) const {
  Index3 ql = q;
  --ql[a];
  const bool lower_inside = grid_.periodic[a] || q[a] > 0;
  const bool upper_inside = grid_.periodic[a] || q[a] < grid_.n[a];
  return u > 0 ? (lower_inside ? cell(ql) : cell(q)) : (upper_inside ? cell(q) : cell(ql));
}

double TwoFluidModel::face_fraction(int a, Index3 q, double u) const {
  const double up = alpha_[upwind_cell(a, q, u)];
  if (s_.fraction_convection != fluid::Convection::VanLeer || u == 0.0) return up;
  // Cells along a: upwind U, far upwind FU, downwind D (face q[a] lies between q[a] - 1 and q[a]).
  const int iu = u > 0 ? q[a] - 1 : q[a], id = u > 0 ? q[a] : q[a] - 1;
  const int ifu = u > 0 ? q[a] - 2 : q[a] + 1;
  auto inside = [&](int i) { return grid_.periodic[a] || (i >= 0 && i < grid_.n[a]); };
  if (!inside(iu) || !inside(id) || !inside(ifu)) return up;
  Index3 cd = q, cfu = q;
  cd[a] = id;
  cfu[a] = ifu;
  // Between the upwind and downwind values also in floating point (a trace of 1e-171 minus a
  // rounding must not turn negative).
  const double down = alpha_[cell(cd)];
  return std::clamp(fluid::van_leer(alpha_[cell(cfu)], up, down), std::min(up, down),
                    std::max(up, down));
}

double TwoFluidModel::flux_divergence(std::int64_t c) const {
  const Index3 q = grid_.cell_coords(c);
  double div = 0.0;
  for (int b = 0; b < dim_; ++b) {
    Index3 hi = q;
    ++hi[b];
    div += (flux_[b][grid_.face_index(b, hi[0], hi[1], hi[2])] -
            flux_[b][grid_.face_index(b, q[0], q[1], q[2])]) /
           grid_.h[b];
  }
  return div;
}

double TwoFluidModel::advective_flux(int b, Index3 q) const {
  for (int c = 0; c < dim_; ++c)
    if (grid_.periodic[c]) q[c] = wrap(q[c], grid_.n[c]);
  return adv_flux_[b][grid_.face_index(b, q[0], q[1], q[2])];
}

double TwoFluidModel::u_at(int a, Index3 q) const {
  for (int b = 0; b < dim_; ++b) {
    if (b == a) {
      q[b] = grid_.periodic[b] ? wrap(q[b], grid_.n[b]) : std::clamp(q[b], 0, grid_.n[b]);
      continue;
    }
    if (q[b] >= 0 && q[b] < grid_.n[b]) continue;
    if (grid_.periodic[b]) {
      q[b] = wrap(q[b], grid_.n[b]);
      continue;
    }
    const int side = q[b] < 0 ? 0 : 1;
    q[b] = side == 0 ? 0 : grid_.n[b] - 1;
    const double u_in = u_at(a, q);
    // The cell next to the wall: for a face along a, the mean of its two cells' ratios is
    // replaced by the upper cell's (the lower at the face n[a]); the difference is a half-cell
    // shift of the ratio, which varies slowly.
    Index3 cq = q;
    cq[a] = std::min(cq[a], grid_.n[a] - 1);
    const double r = wall_ratio(b, side, cell(cq));
    const double uw = wall_velocity(b, side)[a];
    return uw + r * (u_in - uw);
  }
  return us_[a][grid_.face_index(a, q[0], q[1], q[2])];
}

double TwoFluidModel::cell_mean(const std::vector<double>& f, Index3 c0, Index3 c1, Index3 c2,
                                Index3 c3) const {
  return 0.25 * (f[cell(c0)] + f[cell(c1)] + f[cell(c2)] + f[cell(c3)]);
}

Vec3 TwoFluidModel::solids_velocity(std::int64_t c) const {
  const auto q = grid_.cell_coords(c);
  Vec3 u{};
  for (int a = 0; a < dim_; ++a) {
    Index3 hi = q;
    ++hi[a];
    u[a] = 0.5 * (us_[a][grid_.face_index(a, q[0], q[1], q[2])] +
                  us_[a][grid_.face_index(a, hi[0], hi[1], hi[2])]);
  }
  return u;
}

double TwoFluidModel::solids_volume() const {
  double v = 0.0;
  for (double a : alpha_) v += a;
  return v * grid_.cell_volume();
}

void TwoFluidModel::set_solids(const std::function<double(const Vec3&)>& fraction, double theta0) {
  REQUIRE(theta0 >= 0, "two-fluid model: initial granular temperature {} < 0", theta0);
  for (int k = 0; k < grid_.n[2]; ++k)
    for (int j = 0; j < grid_.n[1]; ++j)
      for (int i = 0; i < grid_.n[0]; ++i) {
        const std::int64_t c = grid_.index(i, j, k);
        const double a = fraction(grid_.cell_center(i, j, k));
        REQUIRE(a >= 0 && a <= a_max_,
                "two-fluid model: initial volume fraction {} at cell ({}, {}, {}) outside [0, {}]",
                a, i, j, k, a_max_);
        alpha_[c] = a;
        theta_[c] = std::max(theta0, s_.min_temperature);
        eps_[c] = 1.0 - a;
        eps_rate_[c] = 0.0;
      }
  for (int a = 0; a < dim_; ++a) std::fill(us_[a].begin(), us_[a].end(), 0.0);
  fluid_.set_fluid_fraction(eps_, eps_rate_);
  evaluate_closures();
}

void TwoFluidModel::set_solids_velocity(const std::function<Vec3(const Vec3&)>& velocity) {
  for (int a = 0; a < dim_; ++a) {
    const auto d = grid_.face_dims(a);
    for (int k = 0; k < d[2]; ++k)
      for (int j = 0; j < d[1]; ++j)
        for (int i = 0; i < d[0]; ++i) {
          const int ia = Index3{i, j, k}[a];
          const FaceKind kind = face_kind(a, ia);
          us_[a][grid_.face_index(a, i, j, k)] =
              kind == FaceKind::Wall ? 0.0 : velocity(grid_.face_center(a, i, j, k))[a];
        }
  }
  evaluate_closures();
}

TwoFluidModel::State TwoFluidModel::state() const {
  State st;
  st.time = time_;
  st.fluid = fluid_.state();
  st.arrays.emplace_back("alpha", alpha_);
  st.arrays.emplace_back("theta", theta_);
  for (int a = 0; a < dim_; ++a) st.arrays.emplace_back("us" + std::to_string(a), us_[a]);
  return st;
}

void TwoFluidModel::restore(const State& st) {
  auto get = [&](const std::string& name, std::size_t n) -> const std::vector<double>& {
    for (const auto& [key, v] : st.arrays)
      if (key == name) {
        REQUIRE(v.size() == n, "two-fluid restore: '{}' has {} values, the grid needs {}", name,
                v.size(), n);
        return v;
      }
    throw Error(fmt::format("two-fluid restore: no array '{}'", name));
  };
  fluid_.restore(st.fluid);
  alpha_ = get("alpha", alpha_.size());
  theta_ = get("theta", theta_.size());
  for (int a = 0; a < dim_; ++a) us_[a] = get("us" + std::to_string(a), us_[a].size());
  for (std::size_t c = 0; c < alpha_.size(); ++c) eps_[c] = 1.0 - alpha_[c];
  time_ = st.time;
  evaluate_closures();
}

// ---------------------------------------------------------------------------------------------
// Closures
// ---------------------------------------------------------------------------------------------

TwoFluidModel::CellClosures TwoFluidModel::closures(double a, double theta, double gamma_dot,
                                                    double slip) const {
  CellClosures r;
  const KtgfParams& k = s_.ktgf;
  const double ac = std::clamp(a, 0.0, a_max_);
  auto pressure = [&](double x) {
    double p = continuum::solids_pressure(x, theta, k);
    if (mu_i_switch_)
      p += logarithmic_pressure(x, s_.log_pressure);
    else if (s_.frictional)
      p += johnson_jackson_pressure(x, s_.dense);
    if (s_.particle_pressure.model >= 0) p += particle_pressure(x, s_.particle_pressure);
    return p;
  };
  r.g0 = radial_distribution(ac, k);
  r.kinetic_pressure = continuum::solids_pressure(ac, theta, k);
  r.pressure = pressure(ac);
  // dP_s/da at fixed Theta by a central difference inside [0, a_max] (one-sided at the ends).
  const double h = 1e-7;
  const double lo = std::max(ac - h, 0.0), hi = std::min(ac + h, a_max_);
  r.pressure_slope = hi > lo ? (pressure(hi) - pressure(lo)) / (hi - lo) : 0.0;
  if (s_.frictional) {
    r.viscosity =
        effective_shear_viscosity(ac, theta, gamma_dot, r.pressure, k, s_.dense, s_.dense_rheology)
            .viscosity;
  } else {
    r.viscosity = solids_shear_viscosity(ac, theta, k);
  }
  r.bulk_viscosity = solids_bulk_viscosity(ac, theta, k);
  cfd_dem::DragInput in;
  in.rho_f = s_.fluid.density;
  in.mu_f = s_.fluid.dynamic_viscosity;
  in.eps = std::max(1.0 - ac, 1e-3);
  in.d_v = k.diameter;
  in.slip = Vec3{slip, 0.0, 0.0};
  const double beta_p = cfd_dem::drag_force(s_.drag.law, in, s_.drag).beta;
  r.beta = std::max(ac, a_floor_) * beta_p / v_p_;
  return r;
}

double TwoFluidModel::algebraic_temperature(double a, double trace_d, double dev_dd,
                                            double beta) const {
  if (!(a > a_floor_)) return s_.min_temperature;
  const KtgfParams& k = s_.ktgf;
  const double ac = std::min(a, a_max_);
  // Coefficients at Theta = 1: P = kp Theta, mu = km sqrt(Theta), lambda = kl sqrt(Theta),
  // gamma = kg Theta^1.5; the balance divided by sqrt(Theta) is kg x^2 + b x - c = 0, x^2 = Theta.
  const KtgfProperties p = ktgf_properties(ac, 1.0, k);
  const double b = p.pressure * trace_d + 3.0 * beta;
  const double c = 2.0 * p.shear_viscosity * dev_dd + p.bulk_viscosity * trace_d * trace_d;
  const double kg = p.dissipation;
  if (!(c > 0.0) && !(b < 0.0)) return s_.min_temperature;
  const double disc = std::sqrt(b * b + 4.0 * kg * c);
  // The two forms of the positive root, each free of cancellation on its side of b = 0.
  const double x = b > 0.0 ? 2.0 * c / (b + disc) : (disc - b) / (2.0 * kg);
  return std::max(x * x, s_.min_temperature);
}

// The strain rate of the solids in a cell. At a free surface (a neighbour across a face holds
// no solids, a <= kPresent) that face's velocity belongs to grains that are not there: above a
// bed the empty faces fall at the grains' free-settling speed, and differencing against them
// compressed the surface cell at hundreds per second and heated it (-P tr D). There the gradient
// is one-sided from the present side (zero across an isolated cell); walls keep their rule.
void TwoFluidModel::strain_rate(std::int64_t c, double& trace_d, double& dev_dd) const {
  const auto q = grid_.cell_coords(c);
  auto present = [&](Index3 x) {
    for (int b = 0; b < dim_; ++b)
      if (!grid_.periodic[b] && (x[b] < 0 || x[b] >= grid_.n[b])) return true;
    return alpha_[cell(x)] > kPresent;
  };
  // Cell-centred velocity component a of the cell at coordinates x (may be one outside the
  // grid across an axis: the wall rule applies through u_at).
  auto ucc = [&](int a, Index3 x) {
    Index3 hi = x;
    ++hi[a];
    return 0.5 * (u_at(a, x) + u_at(a, hi));
  };
  double g[3][3] = {};
  for (int a = 0; a < dim_; ++a) {
    Index3 hi = q, lo = q;
    ++hi[a];
    --lo[a];
    g[a][a] = present(hi) && present(lo) ? (u_at(a, hi) - u_at(a, q)) / grid_.h[a] : 0.0;
    for (int b = 0; b < dim_; ++b) {
      if (b == a) continue;
      Index3 up = q, dn = q;
      ++up[b];
      --dn[b];
      const bool p_up = present(up), p_dn = present(dn);
      if (p_up && p_dn)
        g[a][b] = (ucc(a, up) - ucc(a, dn)) / (2.0 * grid_.h[b]);
      else if (p_up)
        g[a][b] = (ucc(a, up) - ucc(a, q)) / grid_.h[b];
      else if (p_dn)
        g[a][b] = (ucc(a, q) - ucc(a, dn)) / grid_.h[b];
    }
  }
  trace_d = g[0][0] + g[1][1] + g[2][2];
  double dd = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      const double d = 0.5 * (g[a][b] + g[b][a]);
      dd += d * d;
    }
  dev_dd = std::max(dd - trace_d * trace_d / 3.0, 0.0);
}

void TwoFluidModel::update_strain_rates() {
  exec::parallel_for(grid_.cell_count(),
                     [&](std::int64_t c) { strain_rate(c, trace_d_[c], dev_dd_[c]); });
}

void TwoFluidModel::evaluate_closures(bool strain_rates_current) {
  stale_ = false;
  if (!strain_rates_current) update_strain_rates();
  fluid_.cell_velocities(uf_cell_);
  exec::parallel_for(grid_.cell_count(), [&](std::int64_t c) {
    us_cell_[c] = solids_velocity(c);
    const CellClosures r = closures(alpha_[c], theta_[c], std::sqrt(2.0 * dev_dd_[c]),
                                    norm(uf_cell_[c] - us_cell_[c]));
    ps_[c] = r.pressure;
    dps_[c] = r.pressure_slope;
    mu_[c] = r.viscosity;
    lambda_[c] = r.bulk_viscosity;
    beta_[c] = r.beta;
  });
}

void TwoFluidModel::update_temperature(double dt) {
  update_strain_rates();
  if (s_.temperature == GranularTemperature::Algebraic) {
    exec::parallel_for(grid_.cell_count(), [&](std::int64_t c) {
      theta_[c] = algebraic_temperature(alpha_[c], trace_d_[c], dev_dd_[c], beta_[c]);
    });
    return;
  }
  transport_temperature(dt);
}

// (3/2) rho_s [(a Theta)^{n+1} - (a Theta)^n] / dt + (3/2) rho_s div(F Theta_up)
//   = -P_kt tr(D) + 2 mu_kt D':D' + lambda tr(D)^2 + div(kappa grad Theta) - gamma_s - 3 beta Theta
// with F the solids flux of this step (so a uniform Theta stays uniform), convection upwind and
// explicit, conduction implicit, the sinks linear in Theta^{n+1} (gamma_s = k_g sqrt(Theta^n)
// Theta^{n+1}; P_kt tr(D) implicit where it cools, tr(D) > 0), the viscous heating explicit.
// Johnson-Jackson walls add their energy flux to the cells beside them; other walls and
// outlets are adiabatic. An SPD system on the pattern of the volume-fraction equation.
void TwoFluidModel::transport_temperature(double dt) {
  const std::int64_t nc = grid_.cell_count();
  const KtgfParams& k = s_.ktgf;
  const double rho_s = k.density;
  double* values = theta_matrix_.valuePtr();
  exec::parallel_for(nc, [&](std::int64_t c) {
    const Row& row = rows_[c];
    zero_column(theta_matrix_, static_cast<int>(c));
    const Index3 qc = grid_.cell_coords(c);
    const double a = std::min(alpha_[c], a_max_), a_old = std::min(alpha_old_[c], a_max_);
    const double th = theta_[c];
    const KtgfProperties p = ktgf_properties(std::max(a, 1e-300), 1.0, k);
    const double tr = trace_d_[c], dev = dev_dd_[c];
    const double sq = std::sqrt(th);
    double diag = 1.5 * rho_s * std::max(a, a_floor_) / dt + p.dissipation * sq + 3.0 * beta_[c];
    double rhs = 1.5 * rho_s * std::max(a_old, a_floor_) * th / dt +
                 (2.0 * p.shear_viscosity * dev + p.bulk_viscosity * tr * tr) * sq;
    if (tr > 0.0)
      diag += p.pressure * tr;
    else
      rhs -= p.pressure * tr * th;
    const double kappa_c = p.conductivity * sq;
    for (int b = 0; b < dim_; ++b)
      for (int side = 0; side < 2; ++side) {
        const std::int64_t f = row.face[2 * b + side];
        Index3 nq = qc;
        nq[b] += side == 0 ? -1 : 1;
        const bool inside = grid_.periodic[b] || (nq[b] >= 0 && nq[b] < grid_.n[b]);
        const std::int64_t nb = inside ? cell(nq) : c;
        // Convection: outflow (+) through this face, upwind Theta, explicit.
        const double out = (side == 1 ? 1.0 : -1.0) * flux_[b][f];
        rhs -= 1.5 * rho_s * out * (out > 0 ? th : theta_[nb]) / grid_.h[b];
        if (!inside) {
          if (face_kind(b, side == 0 ? 0 : grid_.n[b]) == FaceKind::Wall &&
              s_.solids_wall[fluid::box_face_index(b, side)] == SolidsWall::JohnsonJackson)
            rhs += wall_energy_flux(b, side, c) / grid_.h[b];
          continue;
        }
        const int e = row.entry[2 * b + side];
        if (e < 0) continue;
        const double an = std::min(alpha_[nb], a_max_);
        const double kappa_n =
            ktgf_property(KtgfProperty::Conductivity, std::max(an, 1e-300), theta_[nb], k);
        const double kf = 0.5 * (kappa_c + kappa_n) / (grid_.h[b] * grid_.h[b]);
        values[e] -= kf;
        diag += kf;
      }
    values[row.diag] = diag;
    theta_rhs_[c] = rhs;
  });
  theta_solver_.matrix_changed();
  for (std::int64_t c = 0; c < nc; ++c) theta_x_[c] = theta_[c];
  theta_solver_.solve(theta_matrix_, theta_rhs_, theta_x_, s_.tolerance, 1e-300, 100000);
  for (std::int64_t c = 0; c < nc; ++c)
    theta_[c] =
        alpha_[c] > a_floor_ ? std::max(theta_x_[c], s_.min_temperature) : s_.min_temperature;
}

// Johnson & Jackson (1987) granular energy flux into the solids at a wall [W/m^2]: the work of
// the wall shear stress on the slip minus the collisional dissipation at the wall,
//   q = (pi sqrt(3) / 6) phi' (a / a_max) rho_s g0 sqrt(Theta) |u_slip|^2
//       - (sqrt(3) pi / 4) (1 - e_w^2) (a / a_max) rho_s g0 Theta^1.5,
// u_slip the solids velocity at the wall (the mean of the first cell and its ghost) relative to
// the wall.
double TwoFluidModel::wall_energy_flux(int b, int side, std::int64_t c) const {
  const double a = std::min(alpha_[c], a_max_);
  const double th = theta_[c];
  const double g0 = radial_distribution(a, s_.ktgf);
  const double base = (a / a_max_) * s_.ktgf.density * g0;
  const Index3 q = grid_.cell_coords(c);
  const Vec3 uw = wall_velocity(b, side);
  const double r = wall_ratio(b, side, c);
  double slip2 = 0.0;
  for (int a_ = 0; a_ < dim_; ++a_) {
    if (a_ == b) continue;
    Index3 hi = q;
    ++hi[a_];
    const double u_in = 0.5 * (u_at(a_, q) + u_at(a_, hi)) - uw[a_];
    const double slip = 0.5 * (1.0 + r) * u_in;  // (u_in + u_ghost) / 2 relative to the wall
    slip2 += slip * slip;
  }
  const double ew = s_.wall_restitution;
  return kPi * std::sqrt(3.0) / 6.0 * s_.specularity * base * std::sqrt(th) * slip2 -
         std::sqrt(3.0) * kPi / 4.0 * (1.0 - ew * ew) * base * th * std::sqrt(th);
}

// ---------------------------------------------------------------------------------------------
// Solids momentum predictor
// ---------------------------------------------------------------------------------------------

// Face coordinates of the face with linear index f among the faces normal to axis a.
TwoFluidModel::Index3 TwoFluidModel::face_coords(int a, std::int64_t f) const {
  const auto d = grid_.face_dims(a);
  return {static_cast<int>(f % d[0]), static_cast<int>((f / d[0]) % d[1]),
          static_cast<int>(f / (static_cast<std::int64_t>(d[0]) * d[1]))};
}

// The link of momentum unknown (a, q) towards q + side e_b: the neighbouring face, if it is an
// unknown, or the wall it crosses. Fixed by the grid and the boundary kinds.
TwoFluidModel::Link TwoFluidModel::momentum_link(int a, Index3 q, int b, int side) const {
  Link l;
  Index3 nq = q;
  nq[b] += side;
  if (b == a) {
    if (grid_.periodic[a]) {
      nq[a] = wrap(nq[a], grid_.n[a]);
    } else if (face_kind(a, nq[a]) != FaceKind::Interior) {
      l.kind = face_kind(a, nq[a]) == FaceKind::Outlet ? Link::Known : Link::None;
      l.face = grid_.face_index(a, nq[0], nq[1], nq[2]);
      return l;
    }
  } else if (nq[b] < 0 || nq[b] >= grid_.n[b]) {
    if (!grid_.periodic[b]) {
      l.kind = Link::Wall;
      return l;
    }
    nq[b] = wrap(nq[b], grid_.n[b]);
  }
  l.face = grid_.face_index(a, nq[0], nq[1], nq[2]);
  l.kind = l.face == grid_.face_index(a, q[0], q[1], q[2]) ? Link::Self : Link::Unknown;
  return l;
}

void TwoFluidModel::build_momentum_systems() {
  for (int a = 0; a < dim_; ++a) {
    Momentum& m = mom_[a];
    const std::int64_t nf = grid_.face_count(a);
    m.unknown_of_face.assign(nf, -1);
    m.face_of_unknown.clear();
    for (std::int64_t f = 0; f < nf; ++f)
      if (face_kind(a, face_coords(a, f)[a]) == FaceKind::Interior) {
        m.unknown_of_face[f] = static_cast<int>(m.face_of_unknown.size());
        m.face_of_unknown.push_back(f);
      }
    const int n = static_cast<int>(m.face_of_unknown.size());
    std::vector<Eigen::Triplet<double>> trip;
    m.links.assign(static_cast<std::size_t>(n) * 2 * dim_, Link{});
    for (int r = 0; r < n; ++r) {
      const Index3 q = face_coords(a, m.face_of_unknown[r]);
      trip.emplace_back(r, r, 1.0);
      for (int b = 0; b < dim_; ++b)
        for (int side = 0; side < 2; ++side) {
          Link& l = m.links[static_cast<std::size_t>(r) * 2 * dim_ + 2 * b + side];
          l = momentum_link(a, q, b, side == 0 ? -1 : 1);
          if (l.kind == Link::Unknown) {
            l.unknown = m.unknown_of_face[l.face];
            trip.emplace_back(l.unknown, r, 0.0);
          }
        }
    }
    m.matrix.resize(n, n);
    m.matrix.setFromTriplets(trip.begin(), trip.end());
    m.matrix.makeCompressed();
    m.diag_entry.resize(n);
    for (int r = 0; r < n; ++r) {
      m.diag_entry[r] = entry_position(m.matrix, r, r);
      for (int k = 0; k < 2 * dim_; ++k) {
        Link& l = m.links[static_cast<std::size_t>(r) * 2 * dim_ + k];
        if (l.kind == Link::Unknown) l.entry = entry_position(m.matrix, l.unknown, r);
      }
    }
    m.rhs.setZero(n);
    m.x.setZero(n);
    m.solver.setup(dim_ == 2 ? fluid::LinearSolver::Direct : fluid::LinearSolver::JacobiCG,
                   m.matrix);
  }
}

// Per unit volume on the face of component a:
//   (m / dt + beta) u* - [d/dx_a ((4/3 mu + lambda) du_a/dx_a) + sum_b d/dx_b (mu du_a/dx_b)]
//     = m (u^n / dt - u^n . grad u^n) + beta u_f + a rho_s g - a grad p - grad P_s
//       + d/dx_a ((lambda - 2/3 mu)(tr D - D_aa)) + sum_b d/dx_b (mu du_b/dx_a)
// with m = a_f rho_s: the viscous terms of u_a itself implicit (an SPD system, as the fluid's
// predictor), the rest of div(tau) explicit (its transposed-gradient and bulk parts, small
// where the solids are nearly incompressible, MFIX's split).
int TwoFluidModel::solids_predictor(double dt) {
  const double rho_s = s_.ktgf.density;
  const auto p = fluid_.pressure();
  // D_aa and tr D of the cell at coordinates q.
  auto dilatation = [&](int a, Index3 q, double& daa) {
    double tr = 0.0;
    for (int b = 0; b < dim_; ++b) {
      Index3 hi = q;
      ++hi[b];
      const double d = (u_at(b, hi) - u_at(b, q)) / grid_.h[b];
      tr += d;
      if (b == a) daa = d;
    }
    return tr;
  };
  for (int a = 0; a < dim_; ++a)
    exec::parallel_for(grid_.face_count(a), [&](std::int64_t f) {
      const double u = us_[a][f];
      adv_flux_[a][f] = face_fraction(a, face_coords(a, f), u) * u;
    });
  int iterations = 0;
  for (int a = 0; a < dim_; ++a) {
    Momentum& mo = mom_[a];
    const auto uf = fluid_.face_velocity(a);
    double* values = mo.matrix.valuePtr();
    const double h = grid_.h[a];
    exec::parallel_for(static_cast<std::int64_t>(mo.face_of_unknown.size()), [&](std::int64_t r) {
      const std::int64_t f = mo.face_of_unknown[r];
      zero_column(mo.matrix, static_cast<int>(r));
      const Index3 q = face_coords(a, f);
      Index3 ql = q;
      --ql[a];
      const std::int64_t cl = cell(ql), cr = cell(q);
      const double am = std::max(0.5 * (alpha_[cl] + alpha_[cr]), a_floor_);
      const double m = am * rho_s;
      const double beta_f = 0.5 * (beta_[cl] + beta_[cr]);
      double daa_l = 0.0, daa_r = 0.0;
      const double tr_l = dilatation(a, ql, daa_l), tr_r = dilatation(a, q, daa_r);
      double rhs = am * rho_s * s_.fluid.gravity[a] - am * (p[cr] - p[cl]) / h -
                   (ps_[cr] - ps_[cl]) / h + beta_f * uf[f] +
                   ((lambda_[cr] - 2.0 / 3.0 * mu_[cr]) * (tr_r - daa_r) -
                    (lambda_[cl] - 2.0 / 3.0 * mu_[cl]) * (tr_l - daa_l)) /
                       h;
      double diag = m / dt + beta_f;
      const double u0 = us_[a][f];
      for (int b = 0; b < dim_; ++b) {
        Index3 up = q, dn = q;
        ++up[b];
        --dn[b];
        double k_up = 0.0, k_dn = 0.0;  // viscous link coefficients [kg/(m^3 s)]
        double g_up = 0.0, g_dn = 0.0;  // solids mass fluxes through the volume's faces along b
        if (b == a) {
          g_up = 0.5 * rho_s * (advective_flux(a, q) + advective_flux(a, up));
          g_dn = 0.5 * rho_s * (advective_flux(a, ql) + advective_flux(a, q));
          k_up = (4.0 / 3.0 * mu_[cr] + lambda_[cr]) / (h * h);
          k_dn = (4.0 / 3.0 * mu_[cl] + lambda_[cl]) / (h * h);
        } else {
          Index3 lu = ql, ru = q, ld = ql, rd = q;
          ++lu[b];
          ++ru[b];
          --ld[b];
          --rd[b];
          g_up = 0.5 * rho_s * (advective_flux(b, lu) + advective_flux(b, ru));
          g_dn = 0.5 * rho_s * (advective_flux(b, ql) + advective_flux(b, q));
          const double mu_up = cell_mean(mu_, ql, q, lu, ru);
          const double mu_dn = cell_mean(mu_, ql, q, ld, rd);
          k_up = mu_up / (grid_.h[b] * grid_.h[b]);
          k_dn = mu_dn / (grid_.h[b] * grid_.h[b]);
          // The transposed gradient on the edges above and below, explicit.
          rhs += (mu_up * (u_at(b, ru) - u_at(b, lu)) - mu_dn * (u_at(b, q) - u_at(b, ql))) /
                 (h * grid_.h[b]);
        }
        // Convection in the form m du/dt + sum_in G_in (u - u_in) / h (the conservative form less
        // u times continuity): only what flows in changes u, in proportion to its mass. The
        // form m (u . grad) u let the fall of empty faces above a bed (at the free-settling
        // speed) pull on the surface face with the surface cell's whole mass: a slugging
        // gas-fluidised column's pressure drop went from +48 % above its weight to +26 % with
        // this form alone (the rest was the implicit pressure, below). u of the face implicit,
        // the inflow's explicit: positive for any mass flux.
        if (g_up < 0.0) {
          diag -= g_up / grid_.h[b];
          rhs -= g_up * u_at(a, up) / grid_.h[b];
        }
        if (g_dn > 0.0) {
          diag += g_dn / grid_.h[b];
          rhs += g_dn * u_at(a, dn) / grid_.h[b];
        }
        for (int side = 0; side < 2; ++side) {
          const double k = side == 0 ? k_dn : k_up;
          const Link& l = mo.links[static_cast<std::size_t>(r) * 2 * dim_ + 2 * b + side];
          switch (l.kind) {
            case Link::Unknown:
              diag += k;
              values[l.entry] -= k;
              break;
            case Link::Known:  // an outlet face, at its last value
              diag += k;
              rhs += k * us_[a][l.face];
              break;
            case Link::None:  // a wall face along a: u = 0 there
              diag += k;
              break;
            case Link::Self:  // one cell across a periodic axis: no gradient
              break;
            case Link::Wall: {  // ghost u_w + r (u - u_w): k (1 - r) (u_w - u)
              const int ws = side == 0 ? 0 : 1;
              const double ratio = wall_ratio(b, ws, cr);
              diag += k * (1.0 - ratio);
              rhs += k * (1.0 - ratio) * wall_velocity(b, ws)[a];
              break;
            }
          }
        }
      }
      values[mo.diag_entry[r]] = diag;
      mo.rhs[r] = rhs + m * u0 / dt;
      mo.x[r] = u0;
      coef_[a][f] = 1.0 / (m / dt + beta_f);
      face_fraction_[a][f] = am;
      inertia_[a][f] = m / dt;
    });
    mo.solver.matrix_changed();
    if (!mo.face_of_unknown.empty()) {
      const fluid::SolveStats st =
          mo.solver.solve(mo.matrix, mo.rhs, mo.x, s_.tolerance, 1e-300, 100000);
      iterations += st.iterations;
    }
    for (std::size_t r = 0; r < mo.face_of_unknown.size(); ++r)
      ustar_[a][mo.face_of_unknown[r]] = mo.x[static_cast<Eigen::Index>(r)];
    // Walls: no normal velocity; outlets: zero gradient, outflow only; periodic images.
    for (std::int64_t f = 0; f < grid_.face_count(a); ++f) {
      const Index3 q = face_coords(a, f);
      const FaceKind kind = face_kind(a, q[a]);
      if (kind == FaceKind::Interior) continue;
      coef_[a][f] = 0.0;
      face_fraction_[a][f] = 0.0;
      inertia_[a][f] = 0.0;
      ustar_[a][f] = 0.0;
      if (kind == FaceKind::Outlet) {
        Index3 in = q;
        in[a] += q[a] == 0 ? 1 : -1;
        const double u = ustar_[a][grid_.face_index(a, in[0], in[1], in[2])];
        ustar_[a][f] = q[a] == 0 ? std::min(u, 0.0) : std::max(u, 0.0);
      } else if (kind == FaceKind::PeriodicImage) {
        Index3 z = q;
        z[a] = 0;
        ustar_[a][f] = ustar_[a][grid_.face_index(a, z[0], z[1], z[2])];
        coef_[a][f] = coef_[a][grid_.face_index(a, z[0], z[1], z[2])];
        const std::int64_t fz = grid_.face_index(a, z[0], z[1], z[2]);
        face_fraction_[a][f] = face_fraction_[a][fz];
        inertia_[a][f] = inertia_[a][fz];
      }
    }
  }
  return iterations;
}

// ---------------------------------------------------------------------------------------------
// Volume fraction with implicit solids pressure
// ---------------------------------------------------------------------------------------------

void TwoFluidModel::build_fraction_system() {
  const std::int64_t nc = grid_.cell_count();
  std::vector<Eigen::Triplet<double>> trip;
  rows_.assign(nc, Row{});
  for (std::int64_t c = 0; c < nc; ++c) {
    const auto q = grid_.cell_coords(c);
    trip.emplace_back(static_cast<int>(c), static_cast<int>(c), 1.0);
    Row& row = rows_[c];
    row.entry.fill(-1);
    row.face.fill(-1);
    for (int b = 0; b < dim_; ++b)
      for (int side = 0; side < 2; ++side) {
        Index3 fq = q;
        fq[b] += side;
        row.face[2 * b + side] = grid_.face_index(b, fq[0], fq[1], fq[2]);
        if (face_kind(b, fq[b]) != FaceKind::Interior &&
            face_kind(b, fq[b]) != FaceKind::PeriodicImage)
          continue;
        Index3 nq = q;
        nq[b] += side == 0 ? -1 : 1;
        const std::int64_t nb = cell(nq);
        if (nb == c) continue;  // one cell across a periodic axis: the link cancels
        row.entry[2 * b + side] = static_cast<int>(nb);  // the neighbour, for now
        trip.emplace_back(static_cast<int>(nb), static_cast<int>(c), 0.0);
      }
  }
  matrix_.resize(nc, nc);
  matrix_.setFromTriplets(trip.begin(), trip.end());
  matrix_.makeCompressed();
  for (std::int64_t c = 0; c < nc; ++c) {
    Row& row = rows_[c];
    row.diag = entry_position(matrix_, static_cast<int>(c), static_cast<int>(c));
    for (int s = 0; s < 6; ++s)
      if (row.entry[s] >= 0)
        row.entry[s] = entry_position(matrix_, row.entry[s], static_cast<int>(c));
  }
  rhs_.setZero(nc);
  x_.setZero(nc);
  const auto method = dim_ == 2 ? fluid::LinearSolver::Direct : fluid::LinearSolver::JacobiCG;
  solver_.setup(method, matrix_);
  theta_matrix_ = matrix_;  // the same pattern and positions
  theta_rhs_.setZero(nc);
  theta_x_.setZero(nc);
  theta_solver_.setup(method, theta_matrix_);
}

// The solids flux through every face: first-order upwind a times u*, then the implicit solids
// pressure. Its increment over the step, psi = (dP_s/da) delta per cell (delta = a~ - a^n),
// pushes the faces by its gradient, u~ = u* - c_f grad(psi), c_f = 1 / (m/dt + beta_f), and the
// flux F~ = a_up u* - a_f c_f grad(psi) must move a by delta = -dt div(F~):
//   psi / (dP_s/da) - dt div(a_f c_f grad(psi)) = -dt div(a_up u*),
// an SPD system for psi. The force is a gradient of a cell quantity, so over a column it sums to
// its ends (the form (dP_s/da)_f grad(delta) of an earlier version did not: with dP_s/da varying
// by orders of magnitude across a fluidised bed, it loaded the bed with a quarter of its weight
// at dt = 5e-4 s).
void TwoFluidModel::solids_pressure_step(double dt, TwoFluidReport& report) {
  const std::int64_t nc = grid_.cell_count();
  for (int a = 0; a < dim_; ++a)
    exec::parallel_for(grid_.face_count(a), [&](std::int64_t f) {
      const Index3 q = face_coords(a, f);
      const double u = ustar_[a][f];
      const double af = face_fraction(a, q, u);
      flux_[a][f] = af * u;
      carried_[a][f] = af;
    });
  double* values = matrix_.valuePtr();
  exec::parallel_for(nc, [&](std::int64_t c) {
    const Row& row = rows_[c];
    zero_column(matrix_, static_cast<int>(c));
    const Index3 qc = grid_.cell_coords(c);
    // Where P_s does not depend on a (no grains, no fluctuations) psi is 0 to round-off.
    double div = 0.0, diag = 1.0 / std::max(dps_[c], kMinPressureSlope);
    for (int b = 0; b < dim_; ++b)
      for (int side = 0; side < 2; ++side) {
        const std::int64_t f = row.face[2 * b + side];
        div += (side == 1 ? 1.0 : -1.0) * flux_[b][f] / grid_.h[b];
        const int e = row.entry[2 * b + side];
        if (e < 0) continue;
        Index3 nq = qc;
        nq[b] += side == 0 ? -1 : 1;
        const double af = 0.5 * (alpha_[c] + alpha_[cell(nq)]);
        const double k = dt * af * coef_[b][f] / (grid_.h[b] * grid_.h[b]);
        values[e] -= k;
        diag += k;
      }
    values[row.diag] = diag;
    rhs_[c] = -dt * div;
  });
  solver_.matrix_changed();
  x_.setZero();
  const fluid::SolveStats st = solver_.solve(matrix_, rhs_, x_, s_.tolerance, 1e-300, 100000);
  report.fraction_iterations = st.iterations;
  for (int a = 0; a < dim_; ++a)
    exec::parallel_for(grid_.face_count(a), [&](std::int64_t f) {
      const Index3 q = face_coords(a, f);
      const FaceKind kind = face_kind(a, q[a]);
      double u = ustar_[a][f];
      if (kind == FaceKind::Interior || kind == FaceKind::PeriodicImage) {
        Index3 ql = q;
        --ql[a];
        const std::int64_t cl = cell(ql), cr = cell(q);
        const double g = coef_[a][f] * (x_[cr] - x_[cl]) / grid_.h[a];
        u -= g;
        flux_[a][f] -= 0.5 * (alpha_[cl] + alpha_[cr]) * g;
      }
      us_[a][f] = u;
    });
  exec::parallel_for(nc, [&](std::int64_t c) { delta_[c] = -dt * flux_divergence(c); });
}

// The fluid step with the solids flux F~ sharing the pressure correction phi (mixture
// continuity; both phases respond to grad(phi) with the drag between them implicit, see
// VolumeAveragedNS::set_shared_phase), then the solids' share of the correction:
// u_s = u~ - r_s grad(phi), F = F~ - a_up r_s grad(phi), and a^{n+1} = a^n - dt div(F).
double TwoFluidModel::fluid_step(double dt, TwoFluidReport& report) {
  const std::int64_t nc = grid_.cell_count();
  for (std::int64_t c = 0; c < nc; ++c) {
    const double a = std::clamp(alpha_[c] + delta_[c], 0.0, a_max_);
    eps_[c] = 1.0 - a;
    eps_rate_[c] = -delta_[c] / dt;
  }
  // The fluid's drag source beta u_s with u_s of the cell the mean of its faces, so that the
  // exchange summed over the faces is the one the solids' face drag sees.
  exec::parallel_for(nc, [&](std::int64_t c) {
    us_cell_[c] = solids_velocity(c);
    source_[c] = beta_[c] * us_cell_[c];
  });
  fluid_.set_fluid_fraction(eps_, eps_rate_);
  fluid_.set_momentum_source(source_, beta_);
  fluid_.set_shared_phase({{flux_[0], flux_[1], flux_[2]},
                           {face_fraction_[0], face_fraction_[1], face_fraction_[2]},
                           {carried_[0], carried_[1], carried_[2]},
                           {inertia_[0], inertia_[1], inertia_[2]}});
  report.fluid = fluid_.step(dt);
  for (int a = 0; a < dim_; ++a) {
    const auto g = fluid_.correction_gradient(a);
    const auto r = fluid_.shared_response(a);
    exec::parallel_for(grid_.face_count(a), [&](std::int64_t f) {
      us_[a][f] -= r[f] * g[f];
      flux_[a][f] -= carried_[a][f] * r[f] * g[f];
    });
  }
  double clipped = 0.0;
  alpha_old_ = alpha_;
  for (std::int64_t c = 0; c < nc; ++c) {
    double a = alpha_[c] - dt * flux_divergence(c);
    if (a < 0.0) {
      clipped -= a;
      a = 0.0;
    } else if (a > a_max_) {
      clipped -= a - a_max_;
      a = a_max_;
    }
    alpha_[c] = a;
  }
  return clipped * grid_.cell_volume();
}

// ---------------------------------------------------------------------------------------------
// Step
// ---------------------------------------------------------------------------------------------

double TwoFluidModel::max_outflow_rate(const std::vector<double> (&u)[3]) const {
  double inv = 0.0;
  for (std::int64_t c = 0; c < grid_.cell_count(); ++c) {
    const auto q = grid_.cell_coords(c);
    double s = 0.0;
    for (int a = 0; a < dim_; ++a) {
      Index3 hi = q;
      ++hi[a];
      s += std::max(std::abs(u[a][grid_.face_index(a, q[0], q[1], q[2])]),
                    std::abs(u[a][grid_.face_index(a, hi[0], hi[1], hi[2])])) /
           grid_.h[a];
    }
    inv = std::max(inv, s);
  }
  return inv;
}

double TwoFluidModel::stable_dt() const {
  const double inv = max_outflow_rate(us_);
  double dt = inv > 0 ? s_.max_courant / inv : std::numeric_limits<double>::infinity();
  const double cfl1 = fluid_.max_cfl(1.0);
  if (cfl1 > 0) dt = std::min(dt, s_.fluid.max_courant / cfl1);
  return dt;
}

TwoFluidReport TwoFluidModel::step(double dt) {
  REQUIRE(dt > 0 && std::isfinite(dt), "two-fluid model: time step {} must be > 0", dt);
  return advance(dt, 0);
}

// One step of dt, or two of dt / 2 when the predicted solids velocities u* would give a Courant
// number above max_courant (stable_dt() predicts from the velocities of t^n; a front that
// accelerates can overshoot it). Nothing of the state changes before that check. The margin
// below 1 (the bound of the upwind update's positivity) leaves room for the pressure corrections
// that follow; what they still push outside [0, a_max] is clipped and reported.
TwoFluidReport TwoFluidModel::advance(double dt, int depth) {
  TwoFluidReport report;
  if (stale_) evaluate_closures();
  report.momentum_iterations = solids_predictor(dt);
  report.solids_courant = dt * max_outflow_rate(ustar_);
  if (report.solids_courant > s_.max_courant) {
    if (depth >= 20)  // a run's stop, not a program error: no source location
      throw Error(fmt::format(
          "two-fluid model: solids Courant number {:.3g} at t = {:.6g} s even with a step of "
          "{} s (solids velocity diverges)",
          report.solids_courant, time_, dt));
    TwoFluidReport first = advance(0.5 * dt, depth + 1);
    const TwoFluidReport second = advance(0.5 * dt, depth + 1);
    first.momentum_iterations += second.momentum_iterations;
    first.fraction_iterations += second.fraction_iterations;
    first.solids_courant = std::max(first.solids_courant, second.solids_courant);
    first.clipped_volume += second.clipped_volume;
    first.substeps += second.substeps;
    first.fluid = second.fluid;
    return first;
  }
  solids_pressure_step(dt, report);
  report.clipped_volume = fluid_step(dt, report);
  update_temperature(dt);  // finds the strain rates of t^{n+1}
  time_ += dt;
  evaluate_closures(true);  // at t^{n+1}: for stable_dt() and the next step
  return report;
}

}  // namespace gf::continuum
