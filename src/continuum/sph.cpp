// SPDX-License-Identifier: GPL-3.0-or-later
// Weakly compressible SPH: particle set-up, neighbour lists and the three passes of a step.
#include "continuum/sph.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "continuum/rheology_registry.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/mat3.hpp"

namespace gf::continuum {

namespace {

/// Lattice points p0 + (i + 1/2) dx e0 + (j + 1/2) dx e1 [+ (k + 1/2) dx e2] for the counts n.
template <class F>
void lattice(int dimension, const Vec3& p0, const Vec3 e[3], const long n[3], double dx, F&& f) {
  for (long k = 0; k < (dimension == 3 ? n[2] : 1); ++k)
    for (long j = 0; j < n[1]; ++j)
      for (long i = 0; i < n[0]; ++i) {
        Vec3 x = p0 + ((i + 0.5) * dx) * e[0] + ((j + 0.5) * dx) * e[1];
        if (dimension == 3) x += ((k + 0.5) * dx) * e[2];
        f(x);
      }
}

/// Lattice points of spacing dx filling the box [lo, hi] (counts rounded to whole spacings).
template <class F>
void box_lattice(int dimension, const Vec3& lo, const Vec3& hi, double dx, F&& f) {
  const Vec3 e[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  long n[3] = {1, 1, 1};
  for (int k = 0; k < dimension; ++k)
    n[k] = std::max(1L, std::lround(std::floor((hi[k] - lo[k]) / dx + 1e-6)));
  lattice(dimension, lo, e, n, dx, f);
}

/// Lattice points of spacing dx of the cylinder's frame (e0, e1 across, e2 along the unit axis
/// ax; 2D: a disk about z), centred on it, inside the cylinder of radius `radius` (and length
/// `length` in 3D, centred on `center`) but not deeper than `thickness` (> 0) below its surface.
template <class F>
void cylinder_lattice(int dimension, const Vec3& center, const Vec3& axis, double radius,
                      double length, double thickness, double dx, F&& f) {
  const Vec3 ax = dimension == 2 ? Vec3{0, 0, 1} : normalized(axis);
  Vec3 e0 = std::fabs(ax.x) < 0.9 ? cross(ax, Vec3{1, 0, 0}) : cross(ax, Vec3{0, 1, 0});
  if (dimension == 2) e0 = {1, 0, 0};
  e0 = normalized(e0);
  const Vec3 e[3] = {e0, cross(ax, e0), ax};
  const long m = std::lround(std::ceil(radius / dx));
  long n[3] = {2 * m, 2 * m, 1};
  if (dimension == 3) n[2] = std::max(1L, std::lround(std::floor(length / dx + 1e-6)));
  const Vec3 p0 = center - (m * dx) * e[0] - (m * dx) * e[1] -
                  (dimension == 3 ? (0.5 * n[2] * dx) * e[2] : Vec3{});
  lattice(dimension, p0, e, n, dx, [&](const Vec3& x) {
    const Vec3 d = x - center;
    const Vec3 radial = d - dot(d, ax) * ax;
    const double r = norm(radial);
    if (r <= radius && (thickness <= 0 || r >= radius - thickness)) f(x);
  });
}

/// Rotation by `angle` [rad] about the unit vector k (Rodrigues' formula):
/// R = cos(angle) I + sin(angle) [k]x + (1 - cos(angle)) k k^T.
Mat3 rotation_about(const Vec3& k, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Mat3 r = c * Mat3::identity() + (1.0 - c) * outer(k, k);
  r.a[0][1] -= s * k.z;
  r.a[0][2] += s * k.y;
  r.a[1][0] += s * k.z;
  r.a[1][2] -= s * k.x;
  r.a[2][0] -= s * k.y;
  r.a[2][1] += s * k.x;
  return r;
}

/// effective_shear_viscosity (continuum/ktgf.hpp) with the kinetic theory's mu_s [Pa s] given
/// instead of evaluated once more: schaeffer_johnson_jackson mu_s + Schaeffer's viscosity of the
/// Johnson-Jackson pressure above a_min; mu_i_switch the dense rheology's viscosity above the
/// frictional limit, mu_s below. (Checked against effective_shear_viscosity in debug builds and
/// by the unit test SphSolver.KineticTheoryStateMatchesTheClosures.)
double dense_shear_viscosity(double mu_s, double a, double gamma_dot, double pressure,
                             const FrictionalParams& f, const RheologyParams& dense) {
  if (f.model == index_of_key(FrictionalModels{}, SchaefferJohnsonJackson::key))
    return a > f.min_fraction
               ? mu_s + schaeffer_viscosity(johnson_jackson_pressure(a, f), gamma_dot, f)
               : mu_s;
  return a > f.frictional_limit ? apparent_viscosity(gamma_dot, pressure, dense) : mu_s;
}

}  // namespace

SphSolver::SphSolver(const SphConfig& cfg) : cfg_(cfg) {
  REQUIRE(cfg_.dimension == 2 || cfg_.dimension == 3, "SPH: dimension must be 2 or 3");
  REQUIRE(cfg_.spacing > 0 && cfg_.smoothing_ratio > 0 && cfg_.density > 0 &&
              cfg_.sound_speed > 0 && cfg_.eos_exponent >= 1,
          "SPH: spacing, smoothing ratio, density and sound speed must be positive");
  if (cfg_.kinetic_theory) {
    const auto& kt = *cfg_.kinetic_theory;
    REQUIRE(kt.closures.density > 0 && kt.closures.diameter > 0,
            "SPH: kinetic theory needs the grains' diameter and density");
    const double a0 = cfg_.density / kt.closures.density;
    REQUIRE(a0 > 0 && a0 < 1,
            "SPH: kinetic theory: the reference density {} kg/m^3 must be "
            "the bulk density a0 rho_s of the dense packing (a0 = {} is not a volume fraction)",
            cfg_.density, a0);
    REQUIRE(kt.closures.packing_limit <= 0 || a0 < 0.99 * kt.closures.packing_limit,
            "SPH: kinetic theory: the dense packing a0 = rho0 / rho_s = {} must lie below the "
            "radial distribution's packing limit {} (by 1 %)",
            a0, kt.closures.packing_limit);
    REQUIRE(kt.dense.model != index_of_key(FrictionalModels{}, SchaefferJohnsonJackson::key) ||
                a0 < 0.99 * kt.dense.max_fraction,
            "SPH: kinetic theory: the dense packing a0 = rho0 / rho_s = {} must lie below the "
            "frictional pressure's max_fraction {} (by 1 %)",
            a0, kt.dense.max_fraction);
    REQUIRE(kt.min_temperature > 0, "SPH: kinetic theory: min_temperature must be positive");
  }
  w_ = WendlandC2(cfg_.dimension, cfg_.smoothing_ratio * cfg_.spacing);
  volume0_ = std::pow(cfg_.spacing, cfg_.dimension);
  b_eos_ = cfg_.density * cfg_.sound_speed * cfg_.sound_speed / cfg_.eos_exponent;
  cell_domain_ = cfg_.domain;
  if (cfg_.dimension == 2) {
    cell_domain_.lo.z = -w_.support();
    cell_domain_.hi.z = w_.support();
    cell_domain_.periodic[2] = false;
  }
  for (int k = 0; k < cfg_.dimension; ++k) {
    const double len = cfg_.domain.hi[k] - cfg_.domain.lo[k];
    REQUIRE(len > 0, "SPH: the domain is empty along axis {}", k);
    REQUIRE(!cfg_.domain.periodic[k] || len >= 2.0 * w_.support(),
            "SPH: the periodic length {} m along axis {} is below twice the kernel support {} m "
            "(2 x 2h, h = smoothing_ratio x spacing)",
            len, k, 2.0 * w_.support());
  }
  {
    // The Brookshaw / Morris Laplacian of |x|^2 (exactly 2d) on the ideal lattice.
    const double dx = cfg_.spacing;
    const long m = std::lround(std::ceil(w_.support() / dx)) + 1;
    double sum = 0.0, moment = 0.0;
    for (long k = (cfg_.dimension == 3 ? -m : 0); k <= (cfg_.dimension == 3 ? m : 0); ++k)
      for (long j = -m; j <= m; ++j)
        for (long i = -m; i <= m; ++i) {
          const double r = dx * std::sqrt(static_cast<double>(i * i + j * j + k * k));
          if (r > 0 && r < w_.support()) {
            sum += -2.0 * volume0_ * r * r * r * w_.derivative(r) / (r * r + 0.01 * w_.h * w_.h);
            moment += -volume0_ * r * w_.derivative(r);  // (x_j - x_i) . grad_i W_ij
          }
        }
    laplacian_scale_ = 2.0 * cfg_.dimension / sum;
    gradient_scale_ = cfg_.dimension / moment;
  }
  build_particles();
  build_neighbours();
  // No two particles closer than dx/2: overlapping blocks or fluid inside a wall.
  for (std::size_t i = 0; i < p_.size(); ++i)
    for (auto k = nbr_start_[i]; k < nbr_start_[i + 1]; ++k) {
      const auto j = static_cast<std::size_t>(nbr_[static_cast<std::size_t>(k)]);
      if (j < i) continue;
      const double r = norm(cfg_.domain.delta(p_.x[i], p_.x[j]));
      if (r < 0.5 * cfg_.spacing) {
        const auto what = [&](std::size_t q) {
          return p_.wall_index[q] >= 0
                     ? fmt::format("wall '{}'",
                                   cfg_.walls[static_cast<std::size_t>(p_.wall_index[q])].name)
                     : std::string("a fluid block");
        };
        throw InputError(fmt::format(
            "SPH: particles of {} and {} overlap at ({:.6g}, {:.6g}, {:.6g}) m (closer than half "
            "the spacing): blocks must not overlap each other or a wall",
            what(i), what(j), p_.x[i].x, p_.x[i].y, p_.x[i].z));
      }
    }
  // First accelerations (dt = 0: nothing moves).
  if (cfg_.kinetic_theory) refresh_kinetic_theory();
  extrapolate_walls();
  continuity_and_strain(0.0);
  extrapolate_walls();
  momentum();
  update_max_speed();
}

void SphSolver::update_max_speed() {
  // (a NaN speed counts as infinite: max() would drop it)
  v_max_ = exec::parallel_max(static_cast<exec::index_t>(n_fluid_), 0.0, [&](exec::index_t i) {
    const double s = norm(p_.v[static_cast<std::size_t>(i)]);
    return std::isfinite(s) ? s : std::numeric_limits<double>::infinity();
  });
}

double SphSolver::pressure_of(double rho) const {
  return b_eos_ * (std::pow(rho / cfg_.density, cfg_.eos_exponent) - 1.0) +
         cfg_.background_pressure;
}

double SphSolver::density_of(double pressure) const {
  const double base = std::max(1e-3, 1.0 + (pressure - cfg_.background_pressure) / b_eos_);
  return cfg_.density * std::pow(base, 1.0 / cfg_.eos_exponent);
}

void SphSolver::build_particles() {
  const int dim = cfg_.dimension;
  const double dx = cfg_.spacing;
  // Hydrostatic start: along the axis k closest to gravity, p = rho0 |g_k| (depth below the
  // block's top along that axis) (an incline in its own frame: p = rho0 g cos(theta) depth).
  int ka = 0;
  for (int k = 1; k < dim; ++k)
    if (std::fabs(cfg_.gravity[k]) > std::fabs(cfg_.gravity[ka])) ka = k;
  const double g = std::fabs(cfg_.gravity[ka]);
  Vec3 up{};
  up[ka] = cfg_.gravity[ka] > 0 ? -1.0 : 1.0;
  auto add = [&](const Vec3& x, const Vec3& v, double rho, int wall) {
    p_.id.push_back(static_cast<std::int64_t>(p_.id.size()));
    p_.x.push_back(x);
    p_.v.push_back(v);
    p_.a.push_back({});
    p_.rho.push_back(rho);
    p_.drho.push_back(0.0);
    p_.p.push_back(pressure_of(rho));
    p_.mass.push_back(rho * volume0_);
    p_.eta.push_back(0.0);
    p_.gamma_dot.push_back(0.0);
    p_.u_wall.push_back(wall >= 0 ? v : Vec3{});
    p_.v_ghost.push_back(wall >= 0 ? v : Vec3{});
    p_.wall_index.push_back(wall);
    p_.theta.push_back(wall < 0 && cfg_.kinetic_theory
                           ? std::max(cfg_.kinetic_theory->initial_temperature,
                                      cfg_.kinetic_theory->min_temperature)
                           : 0.0);
    p_.dv_viscous.push_back({});
  };
  for (const auto& b : cfg_.blocks) {
    std::vector<Vec3> pts;
    auto take = [&](const Vec3& x) { pts.push_back(x); };
    if (b.shape == SphBlock::Shape::Box)
      box_lattice(dim, b.lo, b.hi, dx, take);
    else
      cylinder_lattice(dim, b.center, b.axis, b.radius, b.length, b.thickness, dx, take);
    REQUIRE(!pts.empty(), "SPH: a fluid block holds no particle at spacing {} m", dx);
    double top = -std::numeric_limits<double>::infinity();
    for (const auto& x : pts) top = std::max(top, dot(up, x));
    top += 0.5 * dx;
    REQUIRE(!(b.hydrostatic && b.volume_fraction && cfg_.kinetic_theory),
            "SPH: a block with a volume fraction starts at rest pressure, not hydrostatic");
    const double rho_block = cfg_.kinetic_theory && b.volume_fraction
                                 ? *b.volume_fraction * cfg_.kinetic_theory->closures.density
                                 : cfg_.density;
    for (const auto& x : pts) {
      const double p = b.hydrostatic ? cfg_.density * g * (top - dot(up, x)) : 0.0;
      add(x, b.velocity, b.hydrostatic ? density_of(p + cfg_.background_pressure) : rho_block, -1);
    }
  }
  n_fluid_ = p_.size();
  REQUIRE(n_fluid_ > 0, "SPH: the blocks hold no particle (spacing {} m)", dx);
  wall_motion_.assign(cfg_.walls.size(), {});
  free_slip_.assign(cfg_.walls.size(), 0);
  slip_length_.assign(cfg_.walls.size(), 0.0);
  jj_shear_.assign(cfg_.walls.size(), 0.0);
  jj_dissipation_.assign(cfg_.walls.size(), 0.0);
  jj_wall_.assign(cfg_.walls.size(), 0);
  for (std::size_t w = 0; w < cfg_.walls.size(); ++w) {
    const auto& wall = cfg_.walls[w];
    auto& motion = wall_motion_[w];
    free_slip_[w] = wall.free_slip ? 1 : 0;
    REQUIRE(wall.slip_length >= 0.0, "SPH: wall '{}': slip length {} m must not be negative",
            wall.name, wall.slip_length);
    slip_length_[w] = wall.slip_length;
    if (wall.johnson_jackson) {
      const auto& jj = *wall.johnson_jackson;
      if (!cfg_.kinetic_theory)
        throw InputError(fmt::format(
            "SPH: wall '{}': the Johnson-Jackson wall condition (specularity, wall_restitution) "
            "needs kinetic_theory (a granular temperature)",
            wall.name));
      REQUIRE(!wall.free_slip && wall.slip_length == 0.0,
              "SPH: wall '{}': a Johnson-Jackson wall is neither free-slip nor has a slip length",
              wall.name);
      REQUIRE(jj.specularity >= 0.0 && jj.specularity <= 1.0 && jj.wall_restitution >= 0.0 &&
                  jj.wall_restitution <= 1.0,
              "SPH: wall '{}': specularity {} and wall restitution {} must lie in [0, 1]",
              wall.name, jj.specularity, jj.wall_restitution);
      // a / a_max with a_max the dense packing rho0 / rho_s: rho_s / a_max = rho_s^2 / rho0
      const double rho_s = cfg_.kinetic_theory->closures.density;
      const double rho_per_amax = rho_s * rho_s / cfg_.density;
      const double pi = std::numbers::pi, sqrt3 = std::numbers::sqrt3;
      jj_shear_[w] = pi * sqrt3 / 6.0 * jj.specularity * rho_per_amax;
      jj_dissipation_[w] =
          sqrt3 * pi / 4.0 * (1.0 - jj.wall_restitution * jj.wall_restitution) * rho_per_amax;
      jj_wall_[w] = 1;
      any_jj_ = true;
    }
    motion.c0 = wall.rotation_center.value_or(
        wall.shape == SphWall::Shape::Box ? 0.5 * (wall.lo + wall.hi) : wall.center);
    motion.velocity = wall.velocity;
    motion.omega = wall.angular_velocity;
    if (dim == 2) {
      REQUIRE(motion.omega.x == 0 && motion.omega.y == 0,
              "SPH: wall '{}': a 2D wall rotates about z only (angular velocity ({}, {}, {}) "
              "rad/s)",
              wall.name, motion.omega.x, motion.omega.y, motion.omega.z);
      motion.c0.z = 0.0;
      motion.velocity.z = 0.0;
    }
    motion.rate = norm(motion.omega);
    motion.rotates = motion.rate > 0.0;
    motion.translates = norm2(motion.velocity) > 0.0;
    motion.axis = motion.rotates ? motion.omega / motion.rate : Vec3{0, 0, 1};
    REQUIRE(wall.initial_angle == 0.0 || dim == 2 || motion.rotates,
            "SPH: wall '{}': an initial angle in 3D needs a non-zero angular velocity (its axis)",
            wall.name);
    const bool turned = wall.initial_angle != 0.0;
    const Mat3 turn = rotation_about(motion.axis, wall.initial_angle);
    const auto before = p_.size();
    auto put = [&](Vec3 x) {
      if (turned) x = motion.c0 + turn * (x - motion.c0);
      for (int k = 0; k < dim; ++k)
        if (!cfg_.domain.periodic[k] && (x[k] < cfg_.domain.lo[k] || x[k] > cfg_.domain.hi[k]))
          throw InputError(fmt::format(
              "SPH: wall '{}' reaches outside the domain (a particle at ({:.6g}, {:.6g}, {:.6g}) "
              "m); a wall must lie inside domain.min .. domain.max",
              wall.name, x.x, x.y, x.z));
      add(x, wall.velocity, cfg_.density, static_cast<int>(w));
    };
    if (wall.shape == SphWall::Shape::Box)
      box_lattice(dim, wall.lo, wall.hi, dx, put);
    else
      cylinder_lattice(dim, wall.center, wall.axis, wall.radius, wall.length, wall.thickness, dx,
                       put);
    REQUIRE(p_.size() > before, "SPH: wall '{}' holds no particle at spacing {} m", wall.name, dx);
  }
  wall_x0_.assign(p_.x.begin() + static_cast<std::ptrdiff_t>(n_fluid_), p_.x.end());
  move_walls(0.0, false);
  for (std::size_t i = n_fluid_; i < p_.size(); ++i) p_.v_ghost[i] = p_.u_wall[i];
}

Vec3 SphSolver::wall_center(std::size_t wall) const {
  const auto& m = wall_motion_.at(wall);
  return m.c0 + t_ * m.velocity;
}

void SphSolver::move_walls(double t, bool positions) {
  // (one rotation per wall, not per particle)
  std::vector<Mat3> rot(wall_motion_.size());
  for (std::size_t w = 0; w < wall_motion_.size(); ++w)
    if (wall_motion_[w].rotates)
      rot[w] = rotation_about(wall_motion_[w].axis, wall_motion_[w].rate * t);
  const Domain& dom = cfg_.domain;
  exec::parallel_for(static_cast<exec::index_t>(p_.size() - n_fluid_), [&](exec::index_t wi) {
    const auto ww = static_cast<std::size_t>(wi);
    const auto i = n_fluid_ + ww;
    const auto w = static_cast<std::size_t>(p_.wall_index[i]);
    const auto& m = wall_motion_[w];
    if (m.rotates) {
      const Vec3 r = rot[w] * (wall_x0_[ww] - m.c0);
      p_.u_wall[i] = m.velocity + cross(m.omega, r);
      if (positions) p_.x[i] = (m.c0 + t * m.velocity) + r;
    } else {
      p_.u_wall[i] = m.velocity;
      if (positions && m.translates) p_.x[i] = wall_x0_[ww] + t * m.velocity;
    }
    if (positions) dom.wrap(p_.x[i]);
  });
}

void SphSolver::build_neighbours() {
  const std::size_t n = p_.size();
  // Verlet list: pairs within the support plus a skin, kept until a particle has moved by half
  // the skin (the kernel is zero beyond the support, so listed pairs beyond it add nothing).
  const double rc = w_.support() + skin();
  cells_.build(cell_domain_, p_.x.data(), n, rc);
  const double rc2 = rc * rc;
  nbr_start_.assign(n + 1, 0);
  // Pass 1 counts, pass 2 fills: each particle lists its own neighbours (no shared writes).
  auto visit = [&](std::size_t i, auto&& take) {
    int stencil[36];
    const int ns = cells_.stencil(cells_.cell_of_particle(i), stencil);
    const bool wall_i = i >= n_fluid_;
    for (int s = 0; s < ns; ++s)
      for (auto k = cells_.begin(stencil[s]); k < cells_.begin(stencil[s] + 1); ++k) {
        const auto j = static_cast<std::size_t>(cells_.order()[static_cast<std::size_t>(k)]);
        if (j == i || (wall_i && j >= n_fluid_)) continue;
        if (norm2(cfg_.domain.delta(p_.x[i], p_.x[j])) < rc2) take(j);
      }
  };
  exec::parallel_for(static_cast<exec::index_t>(n), [&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    std::int64_t c = 0;
    visit(i, [&](std::size_t) { ++c; });
    nbr_start_[i + 1] = c;
  });
  for (std::size_t i = 0; i < n; ++i) nbr_start_[i + 1] += nbr_start_[i];
  nbr_.resize(static_cast<std::size_t>(nbr_start_[n]));
  exec::parallel_for(static_cast<exec::index_t>(n), [&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    auto k = static_cast<std::size_t>(nbr_start_[i]);
    // (in the cell list's stable order: the sums below run in one order whatever the thread
    // count)
    visit(i, [&](std::size_t j) { nbr_[k++] = static_cast<std::int32_t>(j); });
  });
  x_built_ = p_.x;
}

void SphSolver::continuity_and_strain(double dt) {
  const Domain& dom = cfg_.domain;
  const bool kt = cfg_.kinetic_theory.has_value();
  if (kt) {
    div_v_.resize(n_fluid_);
    heat_.resize(n_fluid_);
    conductivity_.resize(n_fluid_, 0.0);
    kt_closures_.resize(n_fluid_);
  }
  if (kt && any_jj_) johnson_jackson_heat();
  const double delta_hc = cfg_.density_diffusion * w_.h * cfg_.sound_speed;
  const double inv_c2 = 1.0 / (cfg_.sound_speed * cfg_.sound_speed);
  const double gs = gradient_scale_;
  const int dim = cfg_.dimension;
  exec::parallel_for(static_cast<exec::index_t>(n_fluid_), [&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    const Vec3 vi = p_.v[i];
    const double rho_i = p_.rho[i];
    double drho = 0.0, conduction = 0.0;
    Mat3 grad{}, m{};
    for (auto k = nbr_start_[i]; k < nbr_start_[i + 1]; ++k) {
      const auto j = static_cast<std::size_t>(nbr_[static_cast<std::size_t>(k)]);
      const Vec3 d = dom.delta(p_.x[i], p_.x[j]);  // r_ij = x_i - x_j
      const double r = norm(d);
      if (r <= 0.0) continue;
      const double dw = w_.derivative(r);
      const Vec3 gw = (dw / r) * d;  // grad_i W_ij
      const bool wall = j >= n_fluid_;
      const double vol_j = wall ? volume0_ : p_.mass[j] / p_.rho[j];
      drho += gs * p_.mass[j] * dot(vi - (wall ? p_.u_wall[j] : p_.v[j]), gw);
      if (!wall && delta_hc > 0.0) {
        const double hydro = cfg_.density * dot(cfg_.gravity, -d) * inv_c2;
        drho += delta_hc * vol_j * 2.0 * (p_.rho[j] - rho_i - hydro) / (r * r) * dot(-d, gw);
      }
      // The rheology's shear rate from the fluid alone (the correction L_i makes the one-sided
      // sum next to a wall exact for linear fields): with the walls' mirrored velocities it came
      // out ten times too large next to a bed in a creeping mu(I) layer, whose viscosity then
      // dropped and whose bed layer slipped.
      if (!wall) {
        grad = grad + outer(vol_j * (p_.v[j] - vi), gw);
        m = m + outer(-vol_j * d, gw);
        // (1 / rho) div(kappa grad Theta) by the Morris form of the viscous term; no conduction
        // into walls (adiabatic, or the Johnson-Jackson flux: johnson_jackson_heat)
        if (kt)
          conduction += laplacian_coefficient(i, j, r, dw, conductivity_[i], conductivity_[j]) *
                        (p_.theta[j] - p_.theta[i]);
      }
    }
    // Kernel-gradient correction where the support is populated enough to invert it.
    if (dim == 2) m.a[2][2] = 1.0;
    if (determinant(m) > 0.1) grad = grad * inverse_symmetric(m);
    double dd = 0.0;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const double s = 0.5 * (grad.a[a][b] + grad.a[b][a]);
        dd += s * s;
      }
    p_.drho[i] = drho;
    p_.gamma_dot[i] = std::sqrt(2.0 * dd);
    if (kt) {
      div_v_[i] = grad.a[0][0] + grad.a[1][1] + grad.a[2][2];
      heat_[i] = conduction;
    }
  });
  // With implicit viscosity the conduction is implicit too (its explicit limit
  // 0.125 h^2 1.5 rho / kappa is as stiff as the viscous one in a dense bed)
  const bool implicit_heat = kt && cfg_.implicit_viscosity && dt > 0.0;
  if (implicit_heat) theta_rhs_.resize(n_fluid_), theta_diag_.resize(n_fluid_);
  exec::parallel_for(static_cast<exec::index_t>(n_fluid_), [&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    p_.rho[i] += dt * p_.drho[i];
    if (kt) {
      // (the particle's one evaluation of the closures this step: at its new density, for the
      // balance at the old Theta and the state at the new one)
      kt_closures_[i] = kinetic_theory_closures(p_.rho[i]);
      const auto [rhs, diag] = temperature_balance(i, dt);
      if (implicit_heat) {
        theta_rhs_[i] = rhs;
        theta_diag_[i] = diag;
      } else {
        p_.theta[i] = std::max((rhs + dt * (2.0 / 3.0) * heat_[i]) / diag,
                               cfg_.kinetic_theory->min_temperature);
        kinetic_theory_state(i);
      }
    } else {
      p_.p[i] = pressure_of(p_.rho[i]);
      p_.eta[i] = apparent_viscosity(p_.gamma_dot[i], p_.p[i], cfg_.rheology);
    }
  });
  if (implicit_heat) {
    implicit_conduction_step(dt);
    exec::parallel_for(static_cast<exec::index_t>(n_fluid_), [&](exec::index_t ii) {
      kinetic_theory_state(static_cast<std::size_t>(ii));
    });
  }
  if (kt) update_kinetic_theory_limits();
}

void SphSolver::implicit_conduction_step(double dt) {
  // diag_i Theta_i - dt (2/3) sum_j k_ij (Theta_j - Theta_i) = rhs_i over fluid neighbours j
  // (k_ij the Morris coefficients of kappa): strictly diagonally dominant (diag_i >= 1), so
  // BiCGSTAB with a diagonal preconditioner converges, as for the viscous step.
  const auto nf = static_cast<Eigen::Index>(n_fluid_);
  auto& rows = visc_rows_;
  rows.resize(n_fluid_);
  Eigen::VectorXd rhs(nf), guess(nf);
  exec::parallel_for(static_cast<exec::index_t>(n_fluid_), [&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    auto& row = rows[i];
    row.clear();
    double diag = theta_diag_[i];
    for (auto k = nbr_start_[i]; k < nbr_start_[i + 1]; ++k) {
      const auto j = static_cast<std::size_t>(nbr_[static_cast<std::size_t>(k)]);
      if (j >= n_fluid_) continue;  // adiabatic walls
      const double r = norm(cfg_.domain.delta(p_.x[i], p_.x[j]));
      if (r <= 0.0 || r >= w_.support()) continue;
      const double c =
          dt * (2.0 / 3.0) *
          laplacian_coefficient(i, j, r, w_.derivative(r), conductivity_[i], conductivity_[j]);
      diag += c;
      row.emplace_back(ii, static_cast<Eigen::Index>(j), -c);
    }
    row.emplace_back(ii, ii, diag);
    rhs(ii) = theta_rhs_[i];
    guess(ii) = p_.theta[i];
  });
  auto& all = visc_triplets_;
  all.clear();
  for (const auto& r : rows) all.insert(all.end(), r.begin(), r.end());
  Eigen::SparseMatrix<double, Eigen::RowMajor> a(nf, nf);
  a.setFromTriplets(all.begin(), all.end());
  Eigen::BiCGSTAB<Eigen::SparseMatrix<double, Eigen::RowMajor>,
                  Eigen::DiagonalPreconditioner<double>>
      solver;
  solver.setTolerance(1e-10);
  solver.compute(a);
  const Eigen::VectorXd theta = solver.solveWithGuess(rhs, guess);
  REQUIRE(solver.info() == Eigen::Success,
          "SPH: implicit heat conduction did not converge ({} iterations, error {})",
          solver.iterations(), solver.error());
  const double floor = cfg_.kinetic_theory->min_temperature;
  for (Eigen::Index i = 0; i < nf; ++i)
    p_.theta[static_cast<std::size_t>(i)] = std::max(theta(i), floor);
}

double SphSolver::laplacian_coefficient(std::size_t i, std::size_t j, double r, double dw,
                                        double q_i, double q_j) const {
  return -laplacian_scale_ * p_.mass[j] / (p_.rho[i] * p_.rho[j]) * (q_i + q_j) * dw * r /
         (r * r + 0.01 * w_.h * w_.h);
}

SphSolver::TemperatureBalance SphSolver::temperature_balance(std::size_t i, double dt) const {
  // (3/2) rho dTheta/dt = eta_k (gamma_dot^2 - 2/3 div^2) + lambda div^2 - P_k div - gamma
  //                      + div(kappa grad Theta),
  // eta_k, lambda, P_k, kappa, gamma of the closure set at the new density and the old Theta.
  // The sinks, gamma ~ Theta^(3/2) and P_k div ~ Theta where the material expands, are taken
  // implicitly (linearised about the old Theta), the sources explicitly: Theta stays positive
  // at any step, and a gas cooling alone follows Haff's law to first order in dt / tau.
  const auto& c = kt_closures_[i];
  const double rho = p_.rho[i], theta = p_.theta[i], sq = std::sqrt(theta);
  const double div = div_v_[i];
  const double gd2 = p_.gamma_dot[i] * p_.gamma_dot[i];
  double source = c.shear_viscosity * sq * std::max(0.0, gd2 - 2.0 / 3.0 * div * div) +
                  c.bulk_viscosity * sq * div * div;  // [W/m^3]
  double sink = c.dissipation * theta * sq;           // [W/m^3]
  if (div < 0.0)
    source -= c.pressure * theta * div;
  else
    sink += c.pressure * theta * div;
  if (any_jj_) {
    // Johnson-Jackson walls: slip work in, inelastic wall collisions out (~ Theta^(3/2) of the
    // fluid next to the wall: implicit like gamma)
    source += jj_source_[i];
    sink += jj_sink_[i];
  }
  const double k = 2.0 / (3.0 * rho);
  return {theta + dt * k * source, 1.0 + dt * k * sink / theta};
}

double SphSolver::volume_fraction_for_closures(double rho) const {
  // a = rho / rho_s, kept below the radial distribution's packing limit (where g0 diverges):
  // the dense pressure holds a near rho0 / rho_s, 1 % below it at least (checked at set-up)
  const auto& kt = *cfg_.kinetic_theory;
  double a = rho / kt.closures.density;
  if (kt.closures.packing_limit > 0) a = std::min(a, 0.999 * kt.closures.packing_limit);
  return std::min(a, 0.999);
}

SphSolver::KtClosures SphSolver::kinetic_theory_closures(double rho) const {
  const auto& kt = *cfg_.kinetic_theory;
  KtClosures c;
  c.a = volume_fraction_for_closures(rho);
  const auto pr = ktgf_properties(c.a, 1.0, kt.closures);  // (one g0, every closure, Theta = 1)
  c.g0 = pr.g0;
  c.pressure = pr.pressure;
  c.shear_viscosity = pr.shear_viscosity;
  c.bulk_viscosity = pr.bulk_viscosity;
  c.conductivity = pr.conductivity;
  c.dissipation = pr.dissipation;
  // Sound speed of the gas, c^2 = dP/drho at fixed Theta + (dP/dTheta) (dTheta/drho) at fixed
  // entropy = dP/drho|_Theta + 2 P^2 / (3 rho^2 Theta) (P linear in Theta; 5/3 Theta for a
  // dilute gas) = Theta (dP1/drho + 2 P1^2 / (3 rho^2)), P1 = P / Theta; dP1/drho by a forward
  // difference
  const double da = 1e-6 * c.a;
  const double dp =
      (solids_pressure(c.a + da, 1.0, kt.closures) - c.pressure) / (da * kt.closures.density);
  c.sound_speed = std::sqrt(std::max(0.0, dp + 2.0 * c.pressure * c.pressure / (3.0 * rho * rho)));
  return c;
}

void SphSolver::kinetic_theory_state(std::size_t i) {
  // p = P_k(a, Theta) + max(0, Tait(rho)) [+ P_f(a)] - lambda div v: the kinetic theory's
  // pressure everywhere, the weakly compressible pressure of the dense packing only where it
  // is compressed beyond rho0 (a granular gas takes no tension), the frictional pressure of
  // schaeffer_johnson_jackson, and the bulk viscous stress
  const auto& kt = *cfg_.kinetic_theory;
  const auto& c = kt_closures_[i];
  const double theta = p_.theta[i], sq = std::sqrt(theta);
  // (Tait's pressure exceeds p_b only above rho0: no pow() for a gas)
  const double tait =
      p_.rho[i] > cfg_.density ? pressure_of(p_.rho[i]) - cfg_.background_pressure : 0.0;
  double p = c.pressure * theta + std::max(0.0, tait) + cfg_.background_pressure -
             c.bulk_viscosity * sq * div_v_[i];
  if (kt.dense.model == index_of_key(FrictionalModels{}, SchaefferJohnsonJackson::key))
    p += johnson_jackson_pressure(std::min(c.a, kt.dense.max_fraction * 0.999), kt.dense);
  p_.p[i] = p;
  p_.eta[i] = dense_shear_viscosity(c.shear_viscosity * sq, c.a, p_.gamma_dot[i], std::max(p, 0.0),
                                    kt.dense, cfg_.rheology);
  ASSERT(
      std::fabs(p_.eta[i] - effective_shear_viscosity(c.a, theta, p_.gamma_dot[i], std::max(p, 0.0),
                                                      kt.closures, kt.dense, cfg_.rheology)
                                .viscosity) <= 1e-12 * p_.eta[i]);
  conductivity_[i] = c.conductivity * sq;
}

void SphSolver::update_kinetic_theory_limits() {
  const auto nf = static_cast<exec::index_t>(n_fluid_);
  kt_sound_max_ = exec::parallel_max(nf, 0.0, [&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    return kt_closures_[i].sound_speed * std::sqrt(p_.theta[i]);
  });
  kt_diffusivity_max_ = exec::parallel_max(nf, 0.0, [&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    // (implicit viscosity: viscosity and conduction both implicit, no limit)
    if (cfg_.implicit_viscosity) return 0.0;
    return std::max(p_.eta[i], conductivity_[i] / 1.5) / p_.rho[i];
  });
}

void SphSolver::refresh_kinetic_theory() {
  kt_closures_.resize(n_fluid_);
  conductivity_.resize(n_fluid_);
  exec::parallel_for(static_cast<exec::index_t>(n_fluid_), [&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    kt_closures_[i] = kinetic_theory_closures(p_.rho[i]);
    conductivity_[i] = kt_closures_[i].conductivity * std::sqrt(p_.theta[i]);  // (as a step does)
  });
  update_kinetic_theory_limits();
}

double SphSolver::johnson_jackson_grip(std::size_t wall, double sum_ag, double sum_w, double eta,
                                       double dist) const {
  // C = (pi sqrt(3) / 6) phi' (a / a_max) rho_s g0 sqrt(Theta) from the kernel mean of
  // a g0 sqrt(Theta); s = d / (d + eta / C) (phi' = 0: s = 0, free slip)
  const double dc = dist * jj_shear_[wall] * sum_ag / sum_w;
  return dc > 0.0 ? dc / (dc + eta) : 0.0;
}

void SphSolver::johnson_jackson_heat() {
  // Per wall particle of a Johnson-Jackson wall: q dS / sum_f V_f W_wf, with
  // q = C |u_slip|^2 - (sqrt(3) pi / 4) (1 - e_w^2) (a / a_max) rho_s g0 Theta^(3/2) from the
  // kernel means of the fluid it sees (u_slip its velocity at the mirror surface relative to the
  // wall, tangential), and dS the particle's surface element as in the wall loads; fluid particle
  // i then receives q dS W_wi / sum_f V_f W_wf [W/m^3] (the sum over i of V_i times it is q dS).
  const Domain& dom = cfg_.domain;
  const std::size_t nw = p_.size() - n_fluid_;
  jj_heat_.resize(nw);
  exec::parallel_for(static_cast<exec::index_t>(nw), [&](exec::index_t wi) {
    const auto ww = static_cast<std::size_t>(wi);
    const auto w = n_fluid_ + ww;
    const auto wall = static_cast<std::size_t>(p_.wall_index[w]);
    jj_heat_[ww] = {};
    if (!jj_wall_[wall]) return;
    double sum_w = 0.0, sum_vw = 0.0, sum_eta = 0.0, sum_ag = 0.0, sum_ag3 = 0.0;
    Vec3 sum_v{}, sum_d{}, area{};
    for (auto k = nbr_start_[w]; k < nbr_start_[w + 1]; ++k) {
      const auto f = static_cast<std::size_t>(nbr_[static_cast<std::size_t>(k)]);
      const Vec3 d = dom.delta(p_.x[w], p_.x[f]);
      const double r = norm(d);
      const double wk = w_.value(r);
      if (!(wk > 0.0)) continue;
      const double vol = p_.mass[f] / p_.rho[f];
      const double theta = p_.theta[f], ag = kt_closures_[f].a * kt_closures_[f].g0;
      sum_w += wk;
      sum_vw += vol * wk;
      sum_eta += p_.eta[f] * wk;
      sum_v += wk * p_.v[f];
      sum_d += wk * d;
      sum_ag += ag * std::sqrt(theta) * wk;
      sum_ag3 += ag * theta * std::sqrt(theta) * wk;
      area += (vol * w_.derivative(r) / r) * d;
    }
    if (!(sum_vw > 0.0)) return;
    const auto& mo = wall_motion_[wall];
    Vec3 u_m = p_.u_wall[w];  // the wall's velocity at the mirror surface (as extrapolate_walls)
    if (mo.rotates) u_m -= (0.5 / sum_w) * cross(mo.omega, sum_d);
    const double s =
        johnson_jackson_grip(wall, sum_ag, sum_w, sum_eta / sum_w, 0.5 * norm(sum_d) / sum_w);
    Vec3 slip = (1.0 - s) * (sum_v / sum_w - u_m);
    if (norm2(sum_d) > 0.0) {
      const Vec3 n = normalized(sum_d);
      slip -= dot(slip, n) * n;
    }
    // n dS = 2 V_w sum_f V_f W'(r) (x_w - x_f) / r, lattice-normalised (see wall_particle_loads)
    const double ds = 2.0 * gradient_scale_ * volume0_ * norm(area);
    const double c = jj_shear_[wall] * sum_ag / sum_w;  // C [kg/(m^2 s)]
    jj_heat_[ww] = {c * norm2(slip) * ds / sum_vw,
                    jj_dissipation_[wall] * sum_ag3 / sum_w * ds / sum_vw};
  });
  // Each fluid particle's share (a pass of its own: the neighbour loop of
  // continuity_and_strain stays as it is without these walls)
  jj_source_.resize(n_fluid_);
  jj_sink_.resize(n_fluid_);
  exec::parallel_for(static_cast<exec::index_t>(n_fluid_), [&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    double in = 0.0, out = 0.0;
    for (auto k = nbr_start_[i]; k < nbr_start_[i + 1]; ++k) {
      const auto j = static_cast<std::size_t>(nbr_[static_cast<std::size_t>(k)]);
      if (j < n_fluid_ || !jj_wall_[static_cast<std::size_t>(p_.wall_index[j])]) continue;
      const auto& h = jj_heat_[j - n_fluid_];
      const double wk = w_.value(norm(dom.delta(p_.x[i], p_.x[j])));
      in += h.production * wk;
      out += h.dissipation * wk;
    }
    jj_source_[i] = in;
    jj_sink_[i] = out;
  });
}

void SphSolver::extrapolate_walls() {
  const Domain& dom = cfg_.domain;
  const bool kt = cfg_.kinetic_theory.has_value();
  const std::size_t n = p_.size();
  inv_wsum_.resize(n - n_fluid_);
  u_mirror_.resize(n - n_fluid_);
  mirror_weight_.resize(n - n_fluid_);
  exec::parallel_for(static_cast<exec::index_t>(n - n_fluid_), [&](exec::index_t wi) {
    const auto ww = static_cast<std::size_t>(wi);
    const auto w = n_fluid_ + ww;
    const auto wall = static_cast<std::size_t>(p_.wall_index[w]);
    const auto& mo = wall_motion_[wall];
    const double slip = free_slip_[wall] ? 0.0 : slip_length_[wall];
    const bool jj = jj_wall_[wall] != 0;
    double sum_w = 0.0, sum_p = 0.0, sum_eta = 0.0, sum_rho = 0.0, sum_ag = 0.0;
    Vec3 sum_rho_r{}, sum_v{}, sum_d{};
    for (auto k = nbr_start_[w]; k < nbr_start_[w + 1]; ++k) {
      const auto f = static_cast<std::size_t>(nbr_[static_cast<std::size_t>(k)]);
      const Vec3 d = dom.delta(p_.x[w], p_.x[f]);
      const double wk = w_.value(norm(d));
      sum_w += wk;
      sum_p += p_.p[f] * wk;
      sum_eta += p_.eta[f] * wk;
      sum_rho += p_.rho[f] * wk;
      sum_rho_r += (p_.rho[f] * wk) * d;
      sum_v += wk * p_.v[f];
      if (mo.rotates || slip > 0.0 || jj) sum_d += wk * d;
      if (jj) sum_ag += kt_closures_[f].a * kt_closures_[f].g0 * std::sqrt(p_.theta[f]) * wk;
    }
    double pw = cfg_.background_pressure;
    inv_wsum_[ww] = sum_w > 0.0 ? 1.0 / sum_w : 0.0;
    u_mirror_[ww] = p_.u_wall[w];
    mirror_weight_[ww] = 1.0;
    if (sum_w > 0.0) {
      // g - a_w, a_w = Omega x (Omega x (x_w - c)) = Omega x (u_w - V) (a translating wall does
      // not accelerate)
      const Vec3 g_rel =
          mo.rotates ? cfg_.gravity - cross(mo.omega, p_.u_wall[w] - mo.velocity) : cfg_.gravity;
      pw = (sum_p + dot(g_rel, sum_rho_r)) / sum_w;
      // A rotating wall's velocity at the midpoint of x_w and the fluid's centroid x~ (where the
      // mirror assumption puts the surface): u_w + Omega x (x~ - x_w) / 2
      if (mo.rotates) u_mirror_[ww] -= (0.5 / sum_w) * cross(mo.omega, sum_d);
      if (jj) {
        // Johnson-Jackson: Navier slip of the local length b = eta / C, d / (d + b) = s
        const double s =
            johnson_jackson_grip(wall, sum_ag, sum_w, sum_eta / sum_w, 0.5 * norm(sum_d) / sum_w);
        u_mirror_[ww] = s * u_mirror_[ww];
        mirror_weight_[ww] = 2.0 * s - 1.0;
      } else if (slip > 0.0) {
        // Navier slip at the mirror surface, a distance d = |x~ - x_w| / 2 from the fluid's
        // centroid: the fluid's velocity there is u_s = (d u + b v~) / (d + b) (u_s - u =
        // b (v~ - u_s) / d), and the mirror image of v~ about u_s is v_w = 2 u_s - v~ =
        // 2 d / (d + b) u - (d - b) / (d + b) v~
        const double dist = 0.5 * norm(sum_d) / sum_w;
        u_mirror_[ww] = (dist / (dist + slip)) * u_mirror_[ww];
        mirror_weight_[ww] = (dist - slip) / (dist + slip);
      }
      p_.v_ghost[w] = 2.0 * u_mirror_[ww] - (mirror_weight_[ww] / sum_w) * sum_v;
      p_.eta[w] = sum_eta / sum_w;
    } else {
      p_.v_ghost[w] = p_.u_wall[w];
      p_.eta[w] = 0.0;
    }
    p_.p[w] = pw;
    p_.rho[w] = std::max(density_of(pw), kt ? cfg_.density : 0.0);
    p_.mass[w] = p_.rho[w] * volume0_;
  });
}

double SphSolver::viscous_coefficient(std::size_t i, std::size_t j, double r, double dw) const {
  return laplacian_coefficient(i, j, r, dw, p_.eta[i], p_.eta[j]);
}

Vec3 SphSolver::pair_acceleration(std::size_t i, std::size_t j, bool viscous) const {
  const Vec3 d = cfg_.domain.delta(p_.x[i], p_.x[j]);
  const double r = norm(d);
  if (r <= 0.0) return {};
  const double h2 = w_.h * w_.h;
  const double dw = w_.derivative(r);
  const Vec3 gw = (dw / r) * d;
  const bool wall = j >= n_fluid_;
  const double rho_i = p_.rho[i];
  const double mj_rr = p_.mass[j] / (rho_i * p_.rho[j]);
  Vec3 acc = (-gradient_scale_ * mj_rr * (p_.p[i] + p_.p[j])) * gw;
  const Vec3 vij = p_.v[i] - (wall ? p_.v_ghost[j] : p_.v[j]);
  if (viscous && viscous_partner(j)) acc -= viscous_coefficient(i, j, r, dw) * vij;
  const double vr = dot(vij, d);
  if (vr < 0.0 && cfg_.artificial_viscosity > 0.0) {
    const double pi_ij = -cfg_.artificial_viscosity * w_.h * cfg_.sound_speed * vr /
                         (0.5 * (rho_i + p_.rho[j]) * (r * r + 0.01 * h2));
    acc -= (p_.mass[j] * pi_ij) * gw;
  }
  return acc;
}

void SphSolver::momentum() {
  exec::parallel_for(static_cast<exec::index_t>(n_fluid_), [&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    Vec3 acc = cfg_.gravity;
    for (auto k = nbr_start_[i]; k < nbr_start_[i + 1]; ++k)
      acc += pair_acceleration(i, static_cast<std::size_t>(nbr_[static_cast<std::size_t>(k)]),
                               !cfg_.implicit_viscosity);
    p_.a[i] = acc;
  });
  const auto nf = static_cast<exec::index_t>(n_fluid_);
  a_max_ = exec::parallel_max(
      nf, 0.0, [&](exec::index_t i) { return norm(p_.a[static_cast<std::size_t>(i)]); });
  eta_max_ = exec::parallel_max(
      nf, 0.0, [&](exec::index_t i) { return p_.eta[static_cast<std::size_t>(i)]; });
}

std::vector<SphSolver::WallLoad> SphSolver::wall_particle_loads() const {
  const std::size_t nw = p_.size() - n_fluid_;
  std::vector<WallLoad> out(nw);
  exec::parallel_for(static_cast<exec::index_t>(nw), [&](exec::index_t ww) {
    const auto w = n_fluid_ + static_cast<std::size_t>(ww);
    const auto& mo = wall_motion_[static_cast<std::size_t>(p_.wall_index[w])];
    // (the surface term is a shear traction: none on a free-slip wall)
    const bool sheared_turning = mo.rotates && viscous_partner(w);
    WallLoad l;
    Vec3 area{};  // n dS
    for (auto k = nbr_start_[w]; k < nbr_start_[w + 1]; ++k) {
      const auto i = static_cast<std::size_t>(nbr_[static_cast<std::size_t>(k)]);
      // minus what w exerts on fluid particle i (actio = reactio), applied at their midpoint
      const Vec3 f = -p_.mass[i] * pair_acceleration(i, w, true);
      const Vec3 d = cfg_.domain.delta(p_.x[w], p_.x[i]);  // x_w - x_i
      l.force += f;
      l.moment += cross(-0.5 * d, f);
      const double r = norm(d);
      if (sheared_turning && r > 0.0) area += (p_.mass[i] / p_.rho[i] * w_.derivative(r) / r) * d;
    }
    if (sheared_turning) {
      // eta (grad v)^T n = eta n x Omega on the wall's surface, with
      // n dS = 2 V_w sum_f V_f W'(r) (x_w - x_f) / r (the fluid's kernel sum seen from a wall
      // particle covers half the kernel at a plane surface), lattice-normalised like the
      // pressure gradient
      area = (2.0 * gradient_scale_ * volume0_) * area;
      l.force += p_.eta[w] * cross(area, mo.omega);
    }
    out[static_cast<std::size_t>(ww)] = l;
  });
  return out;
}

SphWallLoads SphSolver::wall_loads() const {
  const auto per_particle = wall_particle_loads();
  std::vector<Mat3> rot(wall_motion_.size());
  for (std::size_t w = 0; w < wall_motion_.size(); ++w)
    rot[w] = rotation_about(wall_motion_[w].axis, wall_motion_[w].rate * t_);
  SphWallLoads out;
  out.force.resize(cfg_.walls.size());
  out.torque.resize(cfg_.walls.size());
  for (std::size_t k = 0; k < per_particle.size(); ++k) {
    // (x_w - c(t) from the rigid motion, not from x_w: unaffected by periodic wrapping)
    const auto w = static_cast<std::size_t>(p_.wall_index[n_fluid_ + k]);
    const auto& mo = wall_motion_[w];
    const Vec3 r0 = wall_x0_[k] - mo.c0;
    const auto& l = per_particle[k];
    out.force[w] += l.force;
    out.torque[w] += cross(mo.rotates ? rot[w] * r0 : r0, l.force) + l.moment;
  }
  return out;
}

void SphSolver::implicit_viscous_step(double dt) {
  // Backward Euler for dv_i/dt = sum_j k_ij (v_j - v_i) (the Morris term, k_ij >= 0, viscosities
  // of this step), with the walls' mirrored velocities v_w = 2 u_m - s sum_f alpha_wf v_f
  // (alpha_wf = W_wf / sum W_w) taken at the new velocities too, so that no-slip holds however
  // stiff the layer next to a wall is. One matrix, one solve per velocity component. The matrix
  // is strictly diagonally dominant (diagonal 1 + dt sum_j k_ij, off-diagonal magnitudes summing
  // to at most dt sum_j k_ij), so BiCGSTAB with an incomplete LU converges.
  const auto nf = static_cast<Eigen::Index>(n_fluid_);
  auto& rows = visc_rows_;  // kept between steps: no allocation once they have grown
  rows.resize(n_fluid_);
  Eigen::MatrixXd rhs(nf, 3);
  exec::parallel_for(static_cast<exec::index_t>(n_fluid_), [&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    auto& row = rows[i];
    row.clear();
    double diag = 1.0;
    Vec3 b = p_.v[i];
    for (auto k = nbr_start_[i]; k < nbr_start_[i + 1]; ++k) {
      const auto j = static_cast<std::size_t>(nbr_[static_cast<std::size_t>(k)]);
      const double r = norm(cfg_.domain.delta(p_.x[i], p_.x[j]));
      if (r <= 0.0 || r >= w_.support() || !viscous_partner(j)) continue;
      const double c = dt * viscous_coefficient(i, j, r, w_.derivative(r));
      diag += c;
      if (j < n_fluid_) {
        row.emplace_back(ii, static_cast<Eigen::Index>(j), -c);
        continue;
      }
      b += (2.0 * c) * u_mirror_[j - n_fluid_];
      const double inv = mirror_weight_[j - n_fluid_] * inv_wsum_[j - n_fluid_];
      for (auto q = nbr_start_[j]; q < nbr_start_[j + 1]; ++q) {
        const auto f = static_cast<std::size_t>(nbr_[static_cast<std::size_t>(q)]);
        const double wk = w_.value(norm(cfg_.domain.delta(p_.x[j], p_.x[f])));
        if (wk > 0.0) row.emplace_back(ii, static_cast<Eigen::Index>(f), c * wk * inv);
      }
    }
    row.emplace_back(ii, ii, diag);
    for (int d = 0; d < 3; ++d) rhs(ii, d) = b[d];
  });
  auto& all = visc_triplets_;
  all.clear();
  for (const auto& r : rows) all.insert(all.end(), r.begin(), r.end());
  Eigen::SparseMatrix<double, Eigen::RowMajor> a(nf, nf);
  a.setFromTriplets(all.begin(), all.end());  // duplicates (several walls to one f) are summed
  // (a diagonal preconditioner: 400 steps of the column collapse in 2.1 s against 8.7 s with an
  // incomplete LU, whose factorisation each step costs more than the iterations it saves)
  Eigen::BiCGSTAB<Eigen::SparseMatrix<double, Eigen::RowMajor>,
                  Eigen::DiagonalPreconditioner<double>>
      solver;
  solver.setTolerance(1e-10);
  solver.compute(a);
  REQUIRE(solver.info() == Eigen::Success, "SPH: implicit viscous step: factorisation failed");
  // Each solve starts from the velocities plus the previous step's viscous change, which varies
  // slowly from step to step: 18.4 instead of 23.5 iterations per component over the first 3000
  // steps of cases/continuum/granular_dam_break (2026-12-03). The change is part of the
  // checkpoint, so that a continued run starts its solves from the same guess (bit-identical).
  for (int d = 0; d < cfg_.dimension; ++d) {
    Eigen::VectorXd guess(nf);
    for (Eigen::Index i = 0; i < nf; ++i) {
      const auto k = static_cast<std::size_t>(i);
      guess(i) = p_.v[k][d] + p_.dv_viscous[k][d];
    }
    const Eigen::VectorXd v = solver.solveWithGuess(rhs.col(d), guess);
    REQUIRE(solver.info() == Eigen::Success,
            "SPH: implicit viscous step did not converge ({} iterations, error {})",
            solver.iterations(), solver.error());
    for (Eigen::Index i = 0; i < nf; ++i) {
      const auto k = static_cast<std::size_t>(i);
      p_.dv_viscous[k][d] = v(i) - p_.v[k][d];
      p_.v[k][d] = v(i);
    }
    last_viscous_iterations_ = static_cast<int>(solver.iterations());
    viscous_iterations_total_ += solver.iterations();
    ++viscous_solves_;
  }
}

double SphSolver::stable_step() const {
  const double h = w_.h;
  double dt = cfg_.cfl * h / (std::max(cfg_.sound_speed, kt_sound_max_) + v_max_);
  if (a_max_ > 0) dt = std::min(dt, 0.25 * std::sqrt(h / a_max_));
  if (eta_max_ > 0 && !cfg_.implicit_viscosity)
    dt = std::min(dt, 0.125 * h * h * cfg_.density / eta_max_);
  // (a granular gas: its own density, and its heat conduction, explicit also with implicit
  // viscosity)
  if (kt_diffusivity_max_ > 0) dt = std::min(dt, 0.125 * h * h / kt_diffusivity_max_);
  return std::min(dt, cfg_.max_step);
}

bool SphSolver::moved_beyond_skin() const {
  const double half2 = 0.25 * skin() * skin();
  return exec::parallel_any(static_cast<exec::index_t>(p_.size()), [&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    return norm2(cfg_.domain.min_image(p_.x[i] - x_built_[i])) > half2;
  });
}

bool SphSolver::remove_escaped() {
  const Domain& dom = cfg_.domain;
  auto outside = [&](const Vec3& x) {
    for (int k = 0; k < cfg_.dimension; ++k)
      if (!dom.periodic[k] && (x[k] < dom.lo[k] || x[k] > dom.hi[k])) return true;
    return false;
  };
  std::size_t keep = 0;
  const std::size_t n = p_.size();
  std::vector<char> drop(n, 0);
  bool any = false;
  for (std::size_t i = 0; i < n_fluid_; ++i) any = any || (drop[i] = outside(p_.x[i]));
  if (!any) return false;
  auto compact = [&](auto& field) {
    std::size_t o = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (!drop[i]) field[o++] = field[i];
    field.resize(o);
  };
  compact(p_.id);
  compact(p_.x);
  compact(p_.v);
  compact(p_.a);
  compact(p_.rho);
  compact(p_.drho);
  compact(p_.p);
  compact(p_.mass);
  compact(p_.eta);
  compact(p_.gamma_dot);
  compact(p_.u_wall);
  compact(p_.v_ghost);
  compact(p_.wall_index);
  compact(p_.theta);
  compact(p_.dv_viscous);
  if (cfg_.kinetic_theory) {
    // (per fluid particle, from its own density and temperature: they follow it)
    auto compact_fluid = [&](auto& field) {
      std::size_t o = 0;
      for (std::size_t i = 0; i < n_fluid_; ++i)
        if (!drop[i]) field[o++] = field[i];
      field.resize(o);
    };
    compact_fluid(conductivity_);
    compact_fluid(kt_closures_);
  }
  for (std::size_t i = 0; i < n_fluid_; ++i) keep += drop[i] ? 0 : 1;
  n_removed_ += n_fluid_ - keep;
  n_fluid_ = keep;
  return true;
}

void SphSolver::step(double until) {
  double dt = stable_step();
  if (until > t_) dt = std::min(dt, until - t_);
  const Domain& dom = cfg_.domain;
  exec::parallel_for(static_cast<exec::index_t>(n_fluid_), [&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    p_.v[i] += (0.5 * dt) * p_.a[i];
    p_.x[i] += dt * p_.v[i];
    dom.wrap(p_.x[i]);
  });
  move_walls(t_ + dt, true);  // (t_ + dt: the time this step ends at, as below)
  const bool removed = remove_escaped();
  if (removed || moved_beyond_skin()) build_neighbours();
  continuity_and_strain(dt);
  extrapolate_walls();
  momentum();
  exec::parallel_for(static_cast<exec::index_t>(n_fluid_), [&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    p_.v[i] += (0.5 * dt) * p_.a[i];
  });
  if (cfg_.implicit_viscosity) implicit_viscous_step(dt);
  update_max_speed();
  t_ += dt;
  dt_last_ = dt;
  ++steps_;
}

SphState SphSolver::state() const {
  SphState s;
  s.particles = p_;
  s.x_built = x_built_;
  s.n_fluid = n_fluid_;
  s.n_removed = n_removed_;
  s.t = t_;
  s.dt_last = dt_last_;
  s.a_max = a_max_;
  s.v_max = v_max_;
  s.eta_max = eta_max_;
  s.steps = steps_;
  return s;
}

void SphSolver::restore(const SphState& s) {
  const std::size_t walls = p_.size() - n_fluid_;
  const auto& q = s.particles;
  const std::size_t n = q.size();
  const bool sizes_ok = q.id.size() == n && q.v.size() == n && q.a.size() == n &&
                        q.rho.size() == n && q.drho.size() == n && q.p.size() == n &&
                        q.mass.size() == n && q.eta.size() == n && q.gamma_dot.size() == n &&
                        q.u_wall.size() == n && q.v_ghost.size() == n && q.wall_index.size() == n &&
                        q.theta.size() == n && q.dv_viscous.size() == n && s.x_built.size() == n &&
                        s.n_fluid <= n;
  if (!sizes_ok || n - s.n_fluid != walls)
    throw InputError(fmt::format(
        "SPH: the checkpoint holds {} wall particles, this case builds {}: it belongs to another "
        "case (or another spacing)",
        sizes_ok ? n - s.n_fluid : 0, walls));
  p_ = q;
  n_fluid_ = s.n_fluid;
  n_removed_ = s.n_removed;
  t_ = s.t;
  dt_last_ = s.dt_last;
  a_max_ = s.a_max;
  v_max_ = s.v_max;
  eta_max_ = s.eta_max;
  steps_ = s.steps;
  // The list as the uninterrupted run has it: built at the positions of its last build.
  std::vector<Vec3> now = std::move(p_.x);
  p_.x = s.x_built;
  build_neighbours();
  p_.x = std::move(now);
  // (the closures, conductivities and step limits the next step reads, from the state they came
  // from)
  if (cfg_.kinetic_theory) refresh_kinetic_theory();
}

SphSummary SphSolver::summary() const {
  SphSummary s;
  s.n_fluid = n_fluid_;
  const double inf = std::numeric_limits<double>::infinity();
  s.min_position = {inf, inf, inf};
  s.max_position = {-inf, -inf, -inf};
  for (std::size_t i = 0; i < n_fluid_; ++i) {
    s.kinetic_energy += 0.5 * p_.mass[i] * norm2(p_.v[i]);
    s.max_speed = std::max(s.max_speed, norm(p_.v[i]));
    for (int k = 0; k < 3; ++k) {
      s.min_position[k] = std::min(s.min_position[k], p_.x[i][k]);
      s.max_position[k] = std::max(s.max_position[k], p_.x[i][k]);
    }
    s.max_density_error = std::max(s.max_density_error, std::fabs(p_.rho[i] / cfg_.density - 1));
    s.max_viscosity = std::max(s.max_viscosity, p_.eta[i]);
  }
  if (cfg_.kinetic_theory && n_fluid_ > 0) {
    double m = 0.0, mt = 0.0;
    s.min_volume_fraction = inf;
    s.max_volume_fraction = 0.0;
    for (std::size_t i = 0; i < n_fluid_; ++i) {
      m += p_.mass[i];
      mt += p_.mass[i] * p_.theta[i];
      const double a = p_.rho[i] / cfg_.kinetic_theory->closures.density;
      s.min_volume_fraction = std::min(s.min_volume_fraction, a);
      s.max_volume_fraction = std::max(s.max_volume_fraction, a);
    }
    s.mean_temperature = mt / m;
  }
  return s;
}

}  // namespace gf::continuum
