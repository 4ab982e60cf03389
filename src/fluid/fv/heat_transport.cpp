// SPDX-License-Identifier: GPL-3.0-or-later
// Fluid temperature: implicit upwind convection and central diffusion on the flow's cells.
#include "fluid/fv/heat_transport.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "fluid/fv/limiter.hpp"

namespace gf::fluid {

namespace {

bool is_wall(BcKind k) {
  return k == BcKind::NoSlip || k == BcKind::MovingWall || k == BcKind::Periodic;
}

}  // namespace

FluidHeat::FluidHeat(const VolumeAveragedNS& flow, HeatSettings settings,
                     double initial_temperature)
    : grid_(flow.grid()), dim_(flow.grid().dimension), s_(settings) {
  REQUIRE(s_.heat_capacity > 0, "fluid heat: heat capacity must be > 0 J/(kg K), got {}",
          s_.heat_capacity);
  REQUIRE(s_.thermal_conductivity >= 0,
          "fluid heat: thermal conductivity must be >= 0 W/(m K), got {}", s_.thermal_conductivity);
  REQUIRE(std::isfinite(initial_temperature), "fluid heat: the initial temperature is not finite");
  REQUIRE(s_.thermal_expansion >= 0 && std::isfinite(s_.thermal_expansion),
          "fluid heat: thermal expansion must be >= 0 1/K, got {}", s_.thermal_expansion);
  REQUIRE(s_.thermal_expansion == 0 || std::isfinite(s_.reference_temperature),
          "fluid heat: buoyancy needs a finite reference temperature");
  REQUIRE(s_.convection != Convection::Central,
          "fluid heat: central convection of the temperature is unbounded at cell Peclet "
          "numbers above 2; use van_leer or upwind");
  rho_c_ = flow.settings().density * s_.heat_capacity;
  for (int f = 0; f < 6; ++f) {
    kinds_[f] = flow.settings().boundary[f].kind;
    if (f / 2 < dim_ && kinds_[f] == BcKind::VelocityInlet)
      REQUIRE(std::isfinite(s_.boundary_temperature[f]),
              "fluid heat: the inlet on {} needs the temperature of its inflow", box_face_name(f));
  }
  const std::int64_t nc = grid_.cell_count();
  REQUIRE(nc < (std::int64_t{1} << 31), "fluid heat: {} cells exceed the solver's index range", nc);
  const auto n = static_cast<std::size_t>(nc);
  t_.assign(n, initial_temperature);
  q_.assign(n, 0.0);
  k_.assign(n, 0.0);
  b_.resize(static_cast<Eigen::Index>(n));
  x_.resize(static_cast<Eigen::Index>(n));

  // The links of every cell and the matrix pattern (the diagonal and each distinct neighbour).
  const int per_cell = 2 * dim_;
  links_.assign(n * static_cast<std::size_t>(per_cell), Link{});
  std::vector<Eigen::Triplet<double>> pattern;
  pattern.reserve(n * static_cast<std::size_t>(per_cell + 1));
  for (std::int64_t c = 0; c < nc; ++c) {
    const auto ijk = grid_.cell_coords(c);
    pattern.emplace_back(static_cast<int>(c), static_cast<int>(c), 0.0);
    for (int a = 0; a < dim_; ++a)
      for (int s = 0; s < 2; ++s) {
        Link& l = links_[static_cast<std::size_t>(c) * per_cell + 2 * a + s];
        l.axis = static_cast<std::int8_t>(a);
        l.side = static_cast<std::int8_t>(s == 0 ? -1 : 1);
        std::array<int, 3> f = ijk;
        if (s == 1) f[a] += 1;  // the upper face of cell i is face i + 1
        l.face = grid_.face_index(a, f[0], f[1], f[2]);
        std::array<int, 3> q = ijk;
        q[a] += l.side;
        if (q[a] < 0 || q[a] >= grid_.n[a]) {
          if (!grid_.periodic[a]) {
            l.box_face = box_face_index(a, s);
            continue;
          }
          q[a] = grid_.fold(a, q[a]);
        }
        const std::int64_t nb = grid_.index(q[0], q[1], q[2]);
        if (nb == c) continue;  // one cell across a periodic axis: no link to itself
        l.neighbor = static_cast<int>(nb);
        pattern.emplace_back(static_cast<int>(c), l.neighbor, 0.0);
      }
  }
  a_.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  a_.setFromTriplets(pattern.begin(), pattern.end());  // duplicates (2 periodic cells) merged
  a_.makeCompressed();
  const auto entry = [&](std::int64_t row, int col) {
    const int* idx = a_.innerIndexPtr();
    const int* lo = idx + a_.outerIndexPtr()[row];
    const int* hi = idx + a_.outerIndexPtr()[row + 1];
    return static_cast<int>(std::lower_bound(lo, hi, col) - idx);
  };
  diag_.resize(n);
  for (std::int64_t c = 0; c < nc; ++c) {
    diag_[static_cast<std::size_t>(c)] = entry(c, static_cast<int>(c));
    for (int m = 0; m < per_cell; ++m) {
      Link& l = links_[static_cast<std::size_t>(c) * per_cell + m];
      if (l.neighbor >= 0) l.entry = entry(c, l.neighbor);
    }
  }
  // A light incomplete LU (fill 1 per row, small entries dropped): the matrix is diagonally
  // dominant (an M-matrix), so it converges in a few iterations, and a fuller factorisation
  // (Eigen's default fill 10) cost more per step than it saved.
  solver_.preconditioner().setFillfactor(1);
  solver_.preconditioner().setDroptol(1e-8);
  // Eigen 3.4's IncompleteLUT sets its status only in factorize(), and the solver's
  // analyzePattern() reads it: factorise the preconditioner once first (on the identity, the
  // step overwrites the values) so that no uninitialised status is read (UBSan caught it).
  for (const int d : diag_) a_.valuePtr()[d] = 1.0;
  solver_.preconditioner().analyzePattern(a_);
  solver_.preconditioner().factorize(a_);
  solver_.analyzePattern(a_);
  solver_.setTolerance(s_.tolerance);
  solver_.setMaxIterations(s_.max_iterations);
}

void FluidHeat::set_source(std::span<const double> q_explicit, std::span<const double> k) {
  REQUIRE(q_explicit.size() == t_.size() && k.size() == t_.size(),
          "fluid heat: {} and {} source values for {} cells", q_explicit.size(), k.size(),
          t_.size());
  std::copy(q_explicit.begin(), q_explicit.end(), q_.begin());
  std::copy(k.begin(), k.end(), k_.begin());
}

void FluidHeat::set_temperature(std::span<const double> t) {
  REQUIRE(t.size() == t_.size(), "fluid heat: {} temperatures for {} cells", t.size(), t_.size());
  std::copy(t.begin(), t.end(), t_.begin());
}

HeatStepReport FluidHeat::step(double dt, const VolumeAveragedNS& flow,
                               std::span<const double> eps_start) {
  REQUIRE(dt > 0, "fluid heat: step {} s", dt);
  const auto eps = flow.fluid_fraction();
  REQUIRE(eps_start.empty() || eps_start.size() == eps.size(),
          "fluid heat: {} start fluid fractions for {} cells", eps_start.size(), eps.size());
  // The inertia takes the fluid fraction at the step's start: eps^n (T^{n+1} - T^n) / dt +
  // sum_f F_f (T_f - T_c^{n+1}) is the conservative (eps^{n+1} T^{n+1} - eps^n T^n) / dt +
  // sum_f F_f T_f exactly when continuity holds discretely (eps^{n+1} - eps^n = -dt sum_f F_f),
  // and a uniform temperature stays uniform whatever it holds. With eps^{n+1} instead, moving
  // grains would create or destroy (eps^{n+1} - eps^n)(T^n - T^{n+1}) per step (a bed of hot
  // beads collapsing in water: 0.02 % of the heat it gave).
  const std::span<const double> eps0 = eps_start.empty() ? eps : eps_start;
  const std::array<std::span<const double>, 3> u{flow.face_velocity(0), flow.face_velocity(1),
                                                 flow.face_velocity(2)};
  const double k_f = s_.thermal_conductivity;
  const int per_cell = 2 * dim_;
  double* values = a_.valuePtr();
  const int* outer = a_.outerIndexPtr();
  const auto nc = static_cast<exec::index_t>(t_.size());
  const bool limited = s_.convection == Convection::VanLeer;
  // Row c: eps rho c / dt T_c + sum over the faces of (diffusion D + inflow rho c m) (T_c - T_nb)
  // + K T_c = eps rho c / dt T_c^n + q_c, per unit volume; a box face's T_nb is its temperature.
  // With van Leer, each interior face adds - rho c m_out (T_f - T_f,upwind) at T^n to the right
  // side (m_out: the face's outward eps u / h; T_f: the limited value from the far-upwind,
  // upwind and downwind cells; beyond an inlet the far-upwind value mirrors the inflow
  // temperature, beyond other box faces there is no correction).
  exec::parallel_for(nc, [&](exec::index_t c) {
    std::fill(values + outer[c], values + outer[c + 1], 0.0);
    const double eps_c = eps[c], inertia = eps0[c] * rho_c_ / dt;
    double diag = inertia + k_[c], rhs = inertia * t_[c] + q_[c];
    for (int m = 0; m < per_cell; ++m) {
      const Link& l = links_[static_cast<std::size_t>(c) * per_cell + m];
      const int a = l.axis;
      const double h = grid_.h[a];
      const double eps_f = l.neighbor >= 0 ? 0.5 * (eps_c + eps[l.neighbor]) : eps_c;
      const double inflow = std::max(0.0, -l.side * eps_f * u[a][l.face]) / h;  // 1/s
      if (l.neighbor >= 0) {
        const double w = eps_f * k_f / (h * h) + rho_c_ * inflow;
        diag += w;
        values[l.entry] -= w;
        if (limited) rhs -= rho_c_ * convection_correction(c, m, l.side * eps_f * u[a][l.face] / h);
        continue;
      }
      if (l.box_face < 0) continue;  // a periodic axis of one cell
      const BcKind kind = kinds_[l.box_face];
      const double t_b = s_.boundary_temperature[l.box_face];
      double w = 0.0;
      if (kind == BcKind::VelocityInlet)
        w = 2.0 * eps_c * k_f / (h * h) + rho_c_ * inflow;
      else if (kind == BcKind::PressureOutlet)
        w = std::isfinite(t_b) ? rho_c_ * inflow : 0.0;
      else if (is_wall(kind) && std::isfinite(t_b))
        w = 2.0 * eps_c * k_f / (h * h);
      if (w > 0) {
        diag += w;
        rhs += w * t_b;
      }
    }
    values[diag_[c]] += diag;
    b_[c] = rhs;
    x_[c] = t_[c];
  });

  // The pattern (and the preconditioner's fill-reducing ordering) was analysed once, in the
  // constructor; only the values change. Solved for the change over the step, A dT = b - A T^n:
  // the solver's relative tolerance then bounds the error by a fraction of the change, not of
  // T itself (300 K in a cell of 33 J/K is 1e4 J, whose 1e-12 would add up over a run to more
  // than a bead exchanges).
  solver_.factorize(a_);
  b_ -= a_ * x_;  // x_ holds T^n
  x_.setZero();
  x_ = solver_.solveWithGuess(b_, x_);
  // BiCGSTAB's own residual estimate can drift from the true one; the true one decides.
  const double residual = (b_ - a_ * x_).norm() / std::max(b_.norm(), 1e-300);
  if (solver_.info() != Eigen::Success || !(residual <= 100 * s_.tolerance))
    throw Error(fmt::format(
        "fluid heat: BiCGSTAB did not converge ({} iterations, relative residual {:.3g})",
        solver_.iterations(), residual));
  HeatStepReport r;
  r.iterations = static_cast<int>(solver_.iterations());
  for (std::size_t c = 0; c < t_.size(); ++c) t_[c] += x_[static_cast<Eigen::Index>(c)];

  // What crossed the box faces and what the particles gave, at the new temperatures (the flux
  // form: inflow at the face's temperature, outflow at the cell's).
  const double vol = grid_.cell_volume();
  for (std::size_t c = 0; c < t_.size(); ++c) {
    r.particle_heat += (q_[c] - k_[c] * t_[c]) * vol;
    for (int m = 0; m < per_cell; ++m) {
      const Link& l = links_[c * per_cell + m];
      if (l.box_face < 0) continue;
      const int a = l.axis;
      const double h = grid_.h[a], area = vol / h;
      const BcKind kind = kinds_[l.box_face];
      const double t_b = s_.boundary_temperature[l.box_face];
      const double into = -l.side * eps[c] * u[a][l.face] * area;  // m^3/s entering the box
      double q = 0.0;
      if (kind == BcKind::VelocityInlet || kind == BcKind::PressureOutlet) {
        const double t_in = std::isfinite(t_b) ? t_b : t_[c];
        q += rho_c_ * into * (into > 0 ? t_in : t_[c]);
      }
      if ((kind == BcKind::VelocityInlet || is_wall(kind)) && std::isfinite(t_b))
        q += 2.0 * eps[c] * k_f / h * area * (t_b - t_[c]);
      r.face_heat[static_cast<std::size_t>(l.box_face)] += q;
      r.boundary_heat += q;
    }
  }
  return r;
}

double FluidHeat::convection_correction(std::int64_t c, int m, double out) const {
  if (out == 0.0) return 0.0;
  const std::size_t per_cell = 2 * static_cast<std::size_t>(dim_);
  const Link& l = links_[static_cast<std::size_t>(c) * per_cell + static_cast<std::size_t>(m)];
  std::int64_t up = c, down = l.neighbor;
  const Link* far = nullptr;  // the upwind cell's link away from the face
  if (out > 0) {
    far = &links_[static_cast<std::size_t>(c) * per_cell + static_cast<std::size_t>(m ^ 1)];
  } else {
    up = l.neighbor;
    down = c;
    far = &links_[static_cast<std::size_t>(up) * per_cell + static_cast<std::size_t>(m)];
  }
  const double tu = t_[static_cast<std::size_t>(up)];
  double t_far = 0.0;
  if (far->neighbor >= 0) {
    t_far = t_[static_cast<std::size_t>(far->neighbor)];
  } else if (far->box_face >= 0 && kinds_[far->box_face] == BcKind::VelocityInlet) {
    // The inflow's temperature, half a cell away: the mirror value 2 T_b - T_u gives the
    // slope over a whole cell (the face next to an inlet would otherwise be first order and
    // offset the whole profile downstream by O(h)).
    t_far = 2.0 * s_.boundary_temperature[far->box_face] - tu;
  } else {
    return 0.0;
  }
  return out * (van_leer(t_far, tu, t_[static_cast<std::size_t>(down)]) - tu);
}

double FluidHeat::energy(const VolumeAveragedNS& flow) const {
  const auto eps = flow.fluid_fraction();
  double e = 0.0;
  for (std::size_t c = 0; c < t_.size(); ++c) e += eps[c] * t_[c];
  return e * rho_c_ * grid_.cell_volume();
}

void FluidHeat::add_buoyancy(const VolumeAveragedNS& flow, std::span<Vec3> s) const {
  REQUIRE(s.size() == t_.size(), "fluid heat: buoyancy into {} values for {} cells", s.size(),
          t_.size());
  if (s_.thermal_expansion == 0) return;
  const auto eps = flow.fluid_fraction();
  const Vec3 g = flow.settings().gravity;
  const double rho_beta = flow.settings().density * s_.thermal_expansion;
  for (std::size_t c = 0; c < t_.size(); ++c)
    s[c] += (-eps[c] * rho_beta * (t_[c] - s_.reference_temperature)) * g;
}

double FluidHeat::mean_temperature(const VolumeAveragedNS& flow) const {
  const auto eps = flow.fluid_fraction();
  double et = 0.0, e = 0.0;
  for (std::size_t c = 0; c < t_.size(); ++c) {
    et += eps[c] * t_[c];
    e += eps[c];
  }
  return e > 0 ? et / e : 0.0;
}

}  // namespace gf::fluid
