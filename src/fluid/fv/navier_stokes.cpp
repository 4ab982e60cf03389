// SPDX-License-Identifier: GPL-3.0-or-later
// Volume-averaged incompressible Navier-Stokes on a MAC grid: stencils, boundary conditions,
// the implicit momentum predictor and the pressure correction.
//
// One step (t^n -> t^{n+1}), per unit volume on the faces of component a:
//   1. predictor:  a_f u* - div(eps mu grad u*) = eps rho (c1 u^n - c2 u^{n-1}) / dt
//                  - rho (e1 C^n + e2 C^{n-1}) - eps grad p^n + eps rho g + S_explicit,
//      a_f = eps rho c0 / dt + K, C = eps u . grad u (explicit, extrapolated to t^{n+1});
//   2. correction: div(eps^2 / a_f grad phi) = div(eps u*) + d eps/dt,
//                  u^{n+1} = u* - (eps / a_f) grad phi,  p^{n+1} = p^n + phi
//      (with a shared phase, set_shared_phase: continuity of the mixture, and both phases'
//      responses to grad phi from their face momentum equations coupled by the drag K).
// Why incremental pressure correction and not PISO: with the viscous and drag terms implicit
// and convection explicit, the predictor is one SPD solve per component and the corrector one
// SPD solve; PISO's second corrector would only update the off-diagonal (viscous) part of the
// predictor, which the incremental form already carries at second order (Guermond, Minev &
// Shen, Comput. Methods Appl. Mech. Engrg. 195 (2006) 6011). Steady states are exact discrete
// steady solutions, independent of dt (phi = 0 there). Putting K into a_f, as OpenFOAM's and
// CFDEM's 1/A does, makes the corrected velocity satisfy the implicit drag balance: with
// only eps rho / dt in the correction the pressure of a packed bed would converge as
// (K dt / (eps rho + K dt))^n, i.e. not at all for strong drag.
//
// Boundary values outside the grid come from reflections (face_value): a Dirichlet value b on
// a boundary gives the ghost 2 b - u(mirror), zero gradient (outlet) the ghost u(mirror),
// periodic axes wrap. The same rule serves the convective fluxes, the limiter's far-upwind
// values and the viscous stencil, so every stencil sees the boundary the same way.
#include "fluid/fv/navier_stokes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "fluid/fv/limiter.hpp"

namespace gf::fluid {

namespace {

int wrap(int i, int n) {
  i %= n;
  return i < 0 ? i + n : i;
}

/// Adds v to entry (row, col) of a compressed column-major matrix whose pattern has it.
void add_entry(SpdSolver::Matrix& m, int row, int col, double v) {
  m.valuePtr()[entry_position(m, row, col)] += v;
}

}  // namespace

VolumeAveragedNS::VolumeAveragedNS(const Grid& grid, FluidSettings settings)
    : grid_(grid), s_(std::move(settings)) {
  check_settings();
  dim_ = grid_.dimension;
  closed_ = true;
  double p0 = 0.0;
  for (int a = 0; a < dim_; ++a) {
    for (int side = 1; side >= 0; --side) {
      if (bc(a, side).kind == BcKind::PressureOutlet) {
        closed_ = false;
        p0 = bc(a, side).pressure;
      }
    }
  }
  const auto nc = static_cast<std::size_t>(grid_.cell_count());
  for (int a = 0; a < dim_; ++a) {
    const auto nf = static_cast<std::size_t>(grid_.face_count(a));
    for (auto* v : {&u_[a], &u_old_[a], &u_new_[a], &conv_[a], &conv_old_[a], &a_face_[a],
                    &flux_[a], &fluid_response_[a], &shared_response_[a]})
      v->assign(nf, 0.0);
    eps_f_[a].assign(nf, 1.0);
  }
  p_.assign(nc, p0);
  eps_.assign(nc, 1.0);
  eps_rate_.assign(nc, 0.0);
  drag_.assign(nc, 0.0);
  source_.assign(nc, Vec3{});
  // Measured (docs/models/fluid_fv.md, "Linear solvers"): in 2D the sparse LDL^T of the
  // pressure matrix costs less than the CG iterations it saves even when eps changes every
  // step. In 3D its cost grows with the elimination front, the cross-section n_min x n_mid of
  // the two smallest cell counts, while Jacobi-CG's iterations grow with the longest side n_max.
  // Direct wins on quasi-2D slabs (n_min <= 2; per step, eps and K new every step: 8x2x30
  // 0.30 vs 0.46 ms, 32x2x32 1.8 vs 2.7, 100x2x100 41 vs 70) and on thin columns whose front
  // is small and no larger than their length (4x4x200 2.0 vs 6.9 ms, 6x6x100 3.2 vs 6.0,
  // 8x8x128 13 vs 19, 16x4x64 5.9 vs 7.3); it loses once the front grows (8x8x8 0.57 vs
  // 0.47 ms, 32x4x32 8.0 vs 6.3, 12^3 4.1 vs 1.9, 16^3 22 vs 5.2, 24^3 360 vs 26). Incomplete
  // Cholesky saves iterations but not time over Jacobi (and allocates in every factorisation).
  // The momentum matrices are strongly diagonal (eps rho / dt): Jacobi CG needs ~5-10
  // iterations.
  if (s_.pressure_solver == LinearSolver::Auto) {
    std::array<int, 3> n = grid_.n;
    std::sort(n.begin(), n.end());
    const int front = n[0] * n[1];
    const bool thin = n[0] <= 2 || (front <= 64 && front <= n[2]);
    s_.pressure_solver = dim_ == 2 || thin ? LinearSolver::Direct : LinearSolver::JacobiCG;
  }
  if (s_.momentum_solver == LinearSolver::Auto) s_.momentum_solver = LinearSolver::JacobiCG;
  build_face_tables();
  build_momentum_systems();
  build_pressure_system();
  refresh_boundary_faces(u_);
  for (int a = 0; a < dim_; ++a) u_old_[a] = u_[a];
}

void VolumeAveragedNS::check_settings() const {
  const Grid& g = grid_;
  REQUIRE(g.dimension == 2 || g.dimension == 3, "fluid grid: dimension must be 2 or 3, not {}",
          g.dimension);
  for (int a = 0; a < 3; ++a) {
    REQUIRE(g.n[a] >= 1, "fluid grid: {} cells along axis {} (at least 1 needed)", g.n[a], a);
    REQUIRE(g.h[a] > 0.0 && std::isfinite(g.h[a]), "fluid grid: cell size {} m along axis {}",
            g.h[a], a);
  }
  REQUIRE(g.dimension == 3 || g.n[2] == 1, "fluid grid: a 2D grid has one cell along z, not {}",
          g.n[2]);
  REQUIRE(s_.density > 0.0 && std::isfinite(s_.density),
          "fluid: density must be positive, got {} kg/m^3", s_.density);
  REQUIRE(s_.dynamic_viscosity > 0.0 && std::isfinite(s_.dynamic_viscosity),
          "fluid: dynamic viscosity must be positive, got {} Pa s", s_.dynamic_viscosity);
  REQUIRE(s_.time_order == 1 || s_.time_order == 2, "fluid: time_order must be 1 or 2, not {}",
          s_.time_order);
  REQUIRE(s_.max_courant > 0.0, "fluid: max_courant must be positive, got {}", s_.max_courant);
  REQUIRE(s_.pressure_tolerance > 0.0 && s_.momentum_tolerance > 0.0 && s_.max_iterations > 0,
          "fluid: solver tolerances and max_iterations must be positive");
  for (int a = 0; a < g.dimension; ++a) {
    const bool lo = bc(a, 0).kind == BcKind::Periodic, hi = bc(a, 1).kind == BcKind::Periodic;
    REQUIRE(lo == hi,
            "fluid boundary: face {} is periodic but face {} is not (periodic conditions come "
            "in pairs)",
            box_face_name(box_face_index(a, lo ? 0 : 1)),
            box_face_name(box_face_index(a, lo ? 1 : 0)));
    REQUIRE(lo == g.periodic[a],
            "fluid boundary: faces {} and {} are {}periodic but the grid's axis {} is {}periodic",
            box_face_name(box_face_index(a, 0)), box_face_name(box_face_index(a, 1)),
            lo ? "" : "not ", a, g.periodic[a] ? "" : "not ");
    for (int side = 0; side < 2; ++side) {
      const BoundaryCondition& b = bc(a, side);
      if (b.kind == BcKind::MovingWall) {
        REQUIRE(b.velocity[a] == 0.0,
                "fluid boundary: moving wall {} moves along its normal ({} m/s); a wall of the "
                "fixed grid can only slide in its plane",
                box_face_name(box_face_index(a, side)), b.velocity[a]);
      }
      if (b.kind == BcKind::PressureOutlet) {
        REQUIRE(std::isfinite(b.pressure), "fluid boundary: outlet {} has pressure {}",
                box_face_name(box_face_index(a, side)), b.pressure);
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Indexing, interpolation and boundary values

VolumeAveragedNS::Index3 VolumeAveragedNS::unflatten_face(int a, std::int64_t f) const {
  const std::array<int, 3> d = grid_.face_dims(a);
  return {static_cast<int>(f % d[0]), static_cast<int>((f / d[0]) % d[1]),
          static_cast<int>(f / (static_cast<std::int64_t>(d[0]) * d[1]))};
}

VolumeAveragedNS::Index3 VolumeAveragedNS::unflatten_cell(std::int64_t c) const {
  return grid_.cell_coords(c);
}

// Cells outside the grid: wrapped on periodic axes, else the nearest cell (eps has zero normal
// gradient at boundaries).
double VolumeAveragedNS::eps_cell(Index3 c) const {
  return eps_[grid_.index(grid_.fold(0, c[0]), grid_.fold(1, c[1]), grid_.fold(2, c[2]))];
}

bool VolumeAveragedNS::face_in_grid(int a, Index3 f) const {
  for (int b = 0; b < 3; ++b)
    if (f[b] < 0 || f[b] > grid_.n[b] - (b == a ? 0 : 1)) return false;
  return true;
}

double VolumeAveragedNS::eps_face(int a, Index3 f) const {
  if (face_in_grid(a, f)) return eps_f_[a][grid_.face_index(a, f[0], f[1], f[2])];
  Index3 lo = f;
  lo[a] -= 1;
  return 0.5 * (eps_cell(lo) + eps_cell(f));
}

// eps u of component a at face f, which may lie outside the grid.
double VolumeAveragedNS::eps_u(int a, Index3 f) const {
  if (face_in_grid(a, f)) return flux_[a][grid_.face_index(a, f[0], f[1], f[2])];
  return eps_face(a, f) * face_value(u_[a], a, f);
}

// The step's loops use these instead of unflattening face indices (divisions) and folding.
void VolumeAveragedNS::build_face_tables() {
  for (int a = 0; a < dim_; ++a) {
    const std::array<int, 3> d = grid_.face_dims(a);
    face_stride_[a] = {1, d[0], static_cast<std::int64_t>(d[0]) * d[1]};
    face_cells_[a].resize(static_cast<std::size_t>(grid_.face_count(a)));
    for (std::int64_t fi = 0; fi < grid_.face_count(a); ++fi) {
      const Index3 f = unflatten_face(a, fi);
      Index3 lo = f;
      lo[a] -= 1;
      auto folded = [&](const Index3& c) {
        return static_cast<int>(
            grid_.index(grid_.fold(0, c[0]), grid_.fold(1, c[1]), grid_.fold(2, c[2])));
      };
      face_cells_[a][fi] = {folded(lo), folded(f)};
    }
  }
}

void VolumeAveragedNS::update_face_fraction() {
  for (int a = 0; a < dim_; ++a) {
    exec::parallel_for(grid_.face_count(a), [&](exec::index_t fi) {
      const FaceCells& c = face_cells_[a][fi];
      eps_f_[a][fi] = 0.5 * (eps_[c[0]] + eps_[c[1]]);
    });
  }
}

// Velocity of the boundary (axis, side) in component c, at the point of the boundary nearest to
// the face q of component c.
double VolumeAveragedNS::boundary_velocity(int axis, int side, int c, Index3 q) const {
  const BoundaryCondition& b = bc(axis, side);
  switch (b.kind) {
    case BcKind::MovingWall:
      return b.velocity[c];
    case BcKind::VelocityInlet: {
      Vec3 x = grid_.face_center(c, q[0], q[1], q[2]);
      x[axis] = side == 0 ? grid_.lo[axis] : grid_.hi()[axis];
      const Vec3 v = b.profile ? b.profile(x) : b.velocity;
      if (!b.superficial) return v[c];
      Index3 cell = q;
      cell[axis] = side == 0 ? 0 : grid_.n[axis] - 1;
      return v[c] / eps_cell(cell);
    }
    default:
      return 0.0;
  }
}

// Component c of the face field u at face q (face counts along c, cells along the others),
// which may lie outside the grid; see the file header for the reflections.
double VolumeAveragedNS::face_value(const std::vector<double>& u, int c, Index3 q) const {
  for (int b = 0; b < dim_; ++b) {
    const int n = grid_.n[b];
    const int last = b == c ? n : n - 1;
    if (q[b] >= 0 && q[b] <= last) continue;
    if (grid_.periodic[b]) {
      q[b] = wrap(q[b], n);  // on the normal axis face n is the image of face 0
      continue;
    }
    const int side = q[b] < 0 ? 0 : 1;
    const bool zero_gradient = bc(b, side).kind == BcKind::PressureOutlet;
    Index3 mirror = q;
    if (b == c) {  // normal component: reflect about the boundary face, whose value is stored
      const int bf = side == 0 ? 0 : n;
      mirror[b] = 2 * bf - q[b];
      if (zero_gradient) return face_value(u, c, mirror);
      Index3 on = q;
      on[b] = bf;
      return 2.0 * face_value(u, c, on) - face_value(u, c, mirror);
    }
    // tangential component: reflect about the boundary plane
    mirror[b] = side == 0 ? -1 - q[b] : 2 * n - 1 - q[b];
    if (zero_gradient) return face_value(u, c, mirror);
    return 2.0 * boundary_velocity(b, side, c, mirror) - face_value(u, c, mirror);
  }
  return u[grid_.face_index(c, q[0], q[1], q[2])];
}

// Normal boundary faces carry their condition: 0 on walls, the inflow on inlets. Periodic image
// faces copy face 0. Outlet faces are unknowns and are left alone.
void VolumeAveragedNS::refresh_boundary_faces(std::vector<double> (&u)[3]) const {
  for (int a = 0; a < dim_; ++a) {
    const std::array<int, 3> d = grid_.face_dims(a);
    const int b1 = (a + 1) % 3, b2 = (a + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      const BcKind kind = bc(a, side).kind;
      if (kind == BcKind::PressureOutlet || (kind == BcKind::Periodic && side == 0)) continue;
      for (int j2 = 0; j2 < d[b2]; ++j2) {
        for (int j1 = 0; j1 < d[b1]; ++j1) {
          Index3 q{};
          q[a] = side == 0 ? 0 : grid_.n[a];
          q[b1] = j1;
          q[b2] = j2;
          const auto f = grid_.face_index(a, q[0], q[1], q[2]);
          if (kind == BcKind::Periodic) {
            Index3 q0 = q;
            q0[a] = 0;
            u[a][f] = u[a][grid_.face_index(a, q0[0], q0[1], q0[2])];
          } else if (kind == BcKind::VelocityInlet) {
            u[a][f] = boundary_velocity(a, side, a, q);
          } else {
            u[a][f] = 0.0;  // walls: no flow through (a moving wall slides in its plane)
          }
        }
      }
    }
  }
}

// Gradient along a of the cell field p at face fi (number i along a) of a momentum unknown. At
// an outlet face the boundary value sits half a cell away: the outlet pressure for p, zero for
// the correction. On a periodic axis the folded cells are the wrapped ones.
double VolumeAveragedNS::face_gradient(int a, std::int64_t fi, int i, const double* p,
                                       bool correction) const {
  const FaceCells& c = face_cells_[a][fi];
  const int n = grid_.n[a];
  if (!grid_.periodic[a] && (i == 0 || i == n)) {
    const double pb = correction ? 0.0 : bc(a, i == 0 ? 0 : 1).pressure;
    if (i == 0) return (p[c[1]] - pb) / (0.5 * grid_.h[a]);
    return (pb - p[c[0]]) / (0.5 * grid_.h[a]);
  }
  return (p[c[1]] - p[c[0]]) / grid_.h[a];
}

// ---------------------------------------------------------------------------------------------
// Momentum predictor

// Link of the viscous stencil of unknown face f (component a) towards f + s e_b. The flux
// mu eps (u_nb - u_f) / h_b crosses the control-volume face between them; eps there is the cell
// value (b = a: the interface is a cell centre) or the mean of the four cells around the edge.
// Only what does not change with eps or the boundary values is filled in (see refresh_link).
VolumeAveragedNS::Neighbor VolumeAveragedNS::momentum_neighbor(int a, Index3 f, int b,
                                                               int s) const {
  Neighbor nb;
  nb.axis = static_cast<std::int8_t>(b);
  nb.side = static_cast<std::int8_t>(s);
  Index3 q = f;
  q[b] += s;
  const int n = grid_.n[b];
  auto folded = [&](const Index3& c) {
    return static_cast<int>(
        grid_.index(grid_.fold(0, c[0]), grid_.fold(1, c[1]), grid_.fold(2, c[2])));
  };
  if (b == a) {
    Index3 c = f;
    c[a] = std::min(f[a], q[a]);
    nb.cells[0] = folded(c);
    nb.n_cells = 1;
  } else {
    Index3 c = f;
    c[b] = std::min(f[b], q[b]);
    for (int da = -1; da <= 0; ++da) {
      for (int db = 0; db <= 1; ++db) {
        Index3 e = c;
        e[a] += da;
        e[b] += db;
        nb.cells[nb.n_cells++] = folded(e);
      }
    }
  }
  const Momentum& m = mom_[a];
  auto unknown_at = [&](const Index3& i) {
    return m.unknown_of_face[grid_.face_index(a, i[0], i[1], i[2])];
  };
  const int self = unknown_at(f);
  if (b == a) {
    if (grid_.periodic[a]) {
      q[a] = wrap(q[a], n);
    } else if (q[a] < 0 || q[a] > n) {
      return nb;  // beyond an outlet face: zero normal gradient, no flux
    }
    const int k = unknown_at(q);
    if (k >= 0) {
      if (k == self) return {};
      nb.kind = Neighbor::Unknown;
      nb.unknown = k;
      // An outlet face's control volume is the half cell inside; per unit volume its inner
      // flux, over a distance h, counts twice (the row weight 1/2 restores symmetry).
      nb.doubled = !grid_.periodic[a] && (f[a] == 0 || f[a] == n);
    } else {
      nb.kind = Neighbor::Known;
      nb.face = grid_.face_index(a, q[0], q[1], q[2]);
    }
    return nb;
  }
  if (q[b] < 0 || q[b] >= n) {
    if (grid_.periodic[b]) {
      q[b] = wrap(q[b], n);
    } else {
      const int side = q[b] < 0 ? 0 : 1;
      if (bc(b, side).kind == BcKind::PressureOutlet) return {};  // zero gradient
      nb.kind = Neighbor::Dirichlet;
      return nb;
    }
  }
  const int k = unknown_at(q);
  if (k == self) return {};
  nb.kind = Neighbor::Unknown;
  nb.unknown = k;
  return nb;
}

// The parts of link nb of unknown face f (component a) that follow eps and the boundary values.
inline void VolumeAveragedNS::refresh_link(int a, const Index3& f, Neighbor& nb) const {
  if (nb.kind == Neighbor::None) return;
  double eps_link = 0.0;
  if (nb.n_cells == 1) {
    eps_link = eps_[nb.cells[0]];
  } else {
    for (int i = 0; i < 4; ++i) eps_link += 0.25 * eps_[nb.cells[i]];
  }
  const double h = grid_.h[nb.axis];
  nb.coefficient = s_.dynamic_viscosity * eps_link / (h * h);
  if (nb.doubled) nb.coefficient *= 2.0;
  if (nb.kind == Neighbor::Dirichlet)
    nb.value = boundary_velocity(nb.axis, nb.side < 0 ? 0 : 1, a, f);
}

void VolumeAveragedNS::build_momentum_systems() {
  for (int a = 0; a < dim_; ++a) {
    Momentum& m = mom_[a];
    const auto nf = grid_.face_count(a);
    const int n = grid_.n[a];
    m.unknown_of_face.assign(static_cast<std::size_t>(nf), -1);
    m.face_of_unknown.clear();
    m.coords.clear();
    for (std::int64_t f = 0; f < nf; ++f) {
      const int i = unflatten_face(a, f)[a];
      const bool unknown = grid_.periodic[a]
                               ? i < n
                               : (i > 0 && i < n) ||
                                     (i == 0 && bc(a, 0).kind == BcKind::PressureOutlet) ||
                                     (i == n && bc(a, 1).kind == BcKind::PressureOutlet);
      if (!unknown) continue;
      m.unknown_of_face[f] = static_cast<int>(m.face_of_unknown.size());
      m.face_of_unknown.push_back(f);
      m.coords.push_back(unflatten_face(a, f));
    }
    const auto nu = static_cast<int>(m.face_of_unknown.size());
    const int n_links = 2 * dim_;
    m.links.assign(static_cast<std::size_t>(nu) * n_links, Neighbor{});
    std::vector<Eigen::Triplet<double>> t;
    for (int r = 0; r < nu; ++r) {
      t.emplace_back(r, r, 0.0);
      for (int b = 0; b < dim_; ++b) {
        for (int s = 0; s < 2; ++s) {
          Neighbor& nb = m.links[r * n_links + 2 * b + s];
          nb = momentum_neighbor(a, m.coords[r], b, 2 * s - 1);
          if (nb.kind == Neighbor::Unknown) t.emplace_back(nb.unknown, r, 0.0);
        }
      }
    }
    m.matrix.resize(nu, nu);
    m.matrix.setFromTriplets(t.begin(), t.end());
    m.matrix.makeCompressed();
    m.diag_entry.resize(static_cast<std::size_t>(nu));
    for (int r = 0; r < nu; ++r) {
      m.diag_entry[r] = entry_position(m.matrix, r, r);
      for (int l = 0; l < n_links; ++l) {
        Neighbor& nb = m.links[r * n_links + l];
        if (nb.kind == Neighbor::Unknown) nb.entry = entry_position(m.matrix, nb.unknown, r);
      }
    }
    m.rhs.setZero(nu);
    m.x.setZero(nu);
    if (nu > 0) m.solver.setup(s_.momentum_solver, m.matrix);
  }
}

// Advective term eps u . grad u of component a at its unknown faces, in flux form:
// (1/V) sum over the control volume's faces of F_s (u_s - u_f), F_s = eps u_n A interpolated
// from the continuity fluxes of the neighbouring faces, u_s central, van Leer-limited or upwind.
// With central u_s this is the usual second-order MAC stencil; subtracting u_f sum F_s makes it the
// advective form exactly (uniform u gives zero whatever eps does).
//
// Stencil values inside the grid are read directly (strided indices from the unknown's face);
// only those outside go through the reflections of face_value / eps_u. The two give the same
// numbers, so which path a value takes does not change the result.
void VolumeAveragedNS::compute_convection(int a, std::vector<double>& out) const {
  const Momentum& m = mom_[a];
  const Convection scheme = s_.convection;
  const std::vector<double>& u = u_[a];
  exec::parallel_for(static_cast<exec::index_t>(m.face_of_unknown.size()), [&](exec::index_t r) {
    const std::int64_t fi = m.face_of_unknown[r];
    const Index3& f = m.coords[r];
    const double uf = u[fi];
    double c = 0.0;
    for (int b = 0; b < dim_; ++b) {
      const std::int64_t step = face_stride_[a][b];
      const int last = b == a ? grid_.n[b] : grid_.n[b] - 1;
      const double h = grid_.h[b];
      auto value = [&](int k) {  // u_a at f + k e_b
        const int qb = f[b] + k;
        if (qb >= 0 && qb <= last) return u[fi + k * step];
        Index3 q = f;
        q[b] = qb;
        return face_value(u, a, q);
      };
      for (int s = -1; s <= 1; s += 2) {
        const double flux = convecting_flux(a, f, fi, b, s);  // eps u . e_b [m/s]
        if (flux == 0.0) continue;
        const double un = value(s);
        double us;
        if (scheme == Convection::Central) {
          us = 0.5 * (uf + un);
        } else if (scheme == Convection::Upwind) {
          us = flux * s > 0.0 ? uf : un;
        } else if (flux * s > 0.0) {  // outflow: f is upwind
          us = van_leer(value(-s), uf, un);
        } else {
          us = van_leer(value(2 * s), un, uf);
        }
        c += s * flux * (us - uf) / h;
      }
    }
    out[fi] = c;
  });
}

// eps u . e_b at the face on side s along b of the control volume of unknown face f (index fi)
// of component a: the mean of the two continuity fluxes there (b = a: of f and its neighbour;
// b != a: of the two faces of component b that meet the control-volume face).
double VolumeAveragedNS::convecting_flux(int a, const Index3& f, std::int64_t fi, int b,
                                         int s) const {
  Index3 q = f;
  if (b == a) {
    q[a] += s;
    const bool inside = q[a] >= 0 && q[a] <= grid_.n[a];
    return 0.5 * (flux_[a][fi] + (inside ? flux_[a][fi + s * face_stride_[a][a]] : eps_u(a, q)));
  }
  if (s > 0) q[b] += 1;  // q: the upper of the two faces of component b
  if (f[a] >= 1 && f[a] < grid_.n[a]) {
    const std::int64_t hi = face_offset(b, q);
    return 0.5 * (flux_[b][hi - face_stride_[b][a]] + flux_[b][hi]);
  }
  Index3 lo = q;
  lo[a] -= 1;
  return 0.5 * (eps_u(b, lo) + eps_u(b, q));
}

// a_f = eps rho c0 / dt + K on every face (K: mean of the two cells): the predictor's diagonal
// and, through eps / a_f, the pressure-correction coefficient.
void VolumeAveragedNS::update_coefficients(double dt, double c0) {
  for (int a = 0; a < dim_; ++a) {
    exec::parallel_for(grid_.face_count(a), [&](exec::index_t fi) {
      const FaceCells& c = face_cells_[a][fi];
      const double k = 0.5 * (drag_[c[0]] + drag_[c[1]]);
      a_face_[a][fi] = eps_f_[a][fi] * s_.density * c0 / dt + k;
    });
    mom_[a].solver.matrix_changed();
  }
  psolver_.matrix_changed();
  coef_dt_ = dt;
  coef_c0_ = c0;
  coefficients_dirty_ = false;
}

StepReport VolumeAveragedNS::solve_momentum(double dt, const std::array<double, 5>& bdf) {
  const double c1 = bdf[1], c2 = bdf[2], e1 = bdf[3], e2 = bdf[4];
  StepReport rep;
  const bool assemble = assemble_;
  const double rho = s_.density;
  const int n_links = 2 * dim_;
  for (int a = 0; a < dim_; ++a) {
    Momentum& m = mom_[a];
    const auto nu = static_cast<exec::index_t>(m.face_of_unknown.size());
    std::copy(u_[a].begin(), u_[a].end(), u_new_[a].begin());
    if (nu == 0) continue;
    // The links' coefficients change only with eps and the boundary values: cached.
    const bool refresh = assemble || links_dirty_;
    double* values = m.matrix.valuePtr();
    exec::parallel_for(nu, [&](exec::index_t r) {
      const std::int64_t fi = m.face_of_unknown[r];
      const Index3& f = m.coords[r];
      const bool outlet_face = !grid_.periodic[a] && (f[a] == 0 || f[a] == grid_.n[a]);
      const double w = outlet_face ? 0.5 : 1.0;
      const double eps_f = eps_f_[a][fi];
      const FaceCells& cells = face_cells_[a][fi];
      const double source = 0.5 * (source_[cells[0]][a] + source_[cells[1]][a]);
      double rhs = eps_f * rho * (c1 * u_[a][fi] - c2 * u_old_[a][fi]) / dt -
                   rho * (e1 * conv_[a][fi] + e2 * conv_old_[a][fi]) -
                   eps_f * face_gradient(a, fi, f[a], p_.data(), false) +
                   eps_f * rho * s_.gravity[a] + source;
      double diag = a_face_[a][fi];
      if (assemble) zero_column(m.matrix, static_cast<int>(r));
      for (int l = 0; l < n_links; ++l) {
        Neighbor& nb = m.links[r * n_links + l];
        if (refresh) refresh_link(a, f, nb);
        switch (nb.kind) {
          case Neighbor::Unknown:
            diag += nb.coefficient;
            if (assemble) values[nb.entry] += -w * nb.coefficient;
            break;
          case Neighbor::Known:
            diag += nb.coefficient;
            rhs += nb.coefficient * u_[a][nb.face];
            break;
          case Neighbor::Dirichlet:  // ghost 2 u_b - u_f
            diag += 2.0 * nb.coefficient;
            rhs += 2.0 * nb.coefficient * nb.value;
            break;
          case Neighbor::None:
            break;
        }
      }
      if (assemble) values[m.diag_entry[r]] += w * diag;
      m.rhs[r] = w * rhs;
      m.x[r] = u_[a][fi];
    });
    // Absolute floor of the CG residual: the tolerance relative to the size of the time term
    // rho u / dt of the present velocity (a right-hand side that is exactly zero needs it).
    double u_ref = 0.0;
    for (double v : u_[a]) u_ref = std::max(u_ref, std::abs(v));
    const double atol =
        s_.momentum_tolerance * std::sqrt(static_cast<double>(nu)) * rho / dt * u_ref;
    const SolveStats st =
        m.solver.solve(m.matrix, m.rhs, m.x, s_.momentum_tolerance, atol, s_.max_iterations);
    rep.momentum_iterations += st.iterations;
    for (exec::index_t r = 0; r < nu; ++r) u_new_[a][m.face_of_unknown[r]] = m.x[r];
  }
  refresh_boundary_faces(u_new_);  // periodic images
  return rep;
}

// ---------------------------------------------------------------------------------------------
// Pressure correction

void VolumeAveragedNS::build_pressure_system() {
  const auto nc = grid_.cell_count();
  std::vector<Eigen::Triplet<double>> t;
  for (std::int64_t c = 0; c < nc; ++c) {
    const Index3 q = unflatten_cell(c);
    t.emplace_back(c, c, 0.0);
    for (int a = 0; a < dim_; ++a) {
      for (int s = -1; s <= 1; s += 2) {
        Index3 nq = q;
        nq[a] += s;
        if (nq[a] < 0 || nq[a] >= grid_.n[a]) {
          if (!grid_.periodic[a]) continue;
          nq[a] = wrap(nq[a], grid_.n[a]);
        }
        const auto nb = grid_.index(nq[0], nq[1], nq[2]);
        if (nb != c) t.emplace_back(nb, c, 0.0);
      }
    }
  }
  pmatrix_.resize(nc, nc);
  pmatrix_.setFromTriplets(t.begin(), t.end());
  pmatrix_.makeCompressed();
  prow_.resize(static_cast<std::size_t>(nc));
  for (std::int64_t c = 0; c < nc; ++c) {
    const Index3 q = unflatten_cell(c);
    PressureRow& row = prow_[c];
    row.diag = entry_position(pmatrix_, static_cast<int>(c), static_cast<int>(c));
    for (int a = 0; a < dim_; ++a) {
      row.face[a] = face_offset(a, q);
      for (int s = 0; s < 2; ++s) {
        Index3 nq = q;
        nq[a] += 2 * s - 1;
        int& entry = row.entry[2 * a + s];
        if (nq[a] < 0 || nq[a] >= grid_.n[a]) {
          if (!grid_.periodic[a]) {
            entry =
                bc(a, s).kind == BcKind::PressureOutlet ? PressureRow::kOutlet : PressureRow::kNone;
            continue;
          }
          nq[a] = wrap(nq[a], grid_.n[a]);
        }
        const auto nb = grid_.index(nq[0], nq[1], nq[2]);
        entry = nb == c ? PressureRow::kNone
                        : entry_position(pmatrix_, static_cast<int>(nb), static_cast<int>(c));
      }
    }
  }
  prhs_.setZero(nc);
  flux_scale_.setZero(nc);
  phi_.setZero(nc);
  psolver_.setup(s_.pressure_solver, pmatrix_);
}

void VolumeAveragedNS::solve_pressure(StepReport& rep) {
  const auto nc = grid_.cell_count();
  const bool assemble = assemble_;
  // Right-hand side -(div(eps u*) + d eps/dt) and, when eps, K or dt changed, the matrix
  // -div(eps^2 / a_f grad .) per unit volume; an outlet face is a Dirichlet face (phi = 0) half
  // a cell away from the centre.
  double* values = pmatrix_.valuePtr();
  exec::parallel_for(nc, [&](exec::index_t c) {
    const PressureRow& row = prow_[c];
    double div = 0.0, diag = 0.0, flux = std::abs(eps_rate_[c]);
    if (assemble) zero_column(pmatrix_, static_cast<int>(c));
    for (int a = 0; a < dim_; ++a) {
      const double h2 = grid_.h[a] * grid_.h[a];
      for (int s = 0; s < 2; ++s) {
        const std::int64_t fi = row.face[a] + s * face_stride_[a][a];  // the face on side s
        const double eps_f = eps_f_[a][fi];
        div += (2 * s - 1) * eps_f * u_new_[a][fi] / grid_.h[a];
        flux += std::abs(eps_f * u_new_[a][fi]) / grid_.h[a];
        if (shared_) {
          div += (2 * s - 1) * shared_flux_[a][fi] / grid_.h[a];
          flux += std::abs(shared_flux_[a][fi]) / grid_.h[a];
        }
        if (!assemble) continue;
        double k = eps_f * fluid_response_[a][fi] / h2;
        if (shared_) k += shared_carried_[a][fi] * shared_response_[a][fi] / h2;
        const int entry = row.entry[2 * a + s];
        if (entry == PressureRow::kOutlet) {
          diag += 2.0 * k;
        } else if (entry != PressureRow::kNone) {
          diag += k;
          values[entry] += -k;
        }
      }
    }
    if (assemble) values[row.diag] += diag;
    prhs_[c] = -(div + (shared_ ? 0.0 : eps_rate_[c]));
    flux_scale_[c] = flux;
  });
  if (closed_) {
    // Pure Neumann / periodic: A is singular with the constants as null space. The right-hand
    // side must sum to zero (net inflow = sum of d eps/dt V); what is left is removed uniformly
    // and reported. Then phi is fixed in cell 0 by symmetric elimination, which keeps A SPD.
    // The scale is that of the fluxes themselves (flux_scale_: sum of |eps u| / h over each
    // cell's faces and |d eps/dt|), not of the divergences: a divergence-free flow has
    // divergences of round-off size, and their sum must not be judged against itself.
    const double net = prhs_.sum(), scale = flux_scale_.sum();
    rep.compatibility_defect = scale > 0.0 ? std::abs(net) / scale : 0.0;
    REQUIRE(rep.compatibility_defect <= s_.max_compatibility_defect,
            "fluid: the domain has no pressure outlet, so the net inflow must balance "
            "sum(d eps/dt) V, but they differ by {:.3e} of the flux scale (at t = {} s)",
            rep.compatibility_defect, time_);
    prhs_.array() -= net / static_cast<double>(nc);
    prhs_[0] = 0.0;
    if (assemble) {
      zero_column(pmatrix_, 0);
      add_entry(pmatrix_, 0, 0, 1.0);
      for (int k = pmatrix_.outerIndexPtr()[0]; k < pmatrix_.outerIndexPtr()[1]; ++k) {
        const int row = pmatrix_.innerIndexPtr()[k];
        if (row != 0) {  // symmetric entry (0, row) lives in column `row`
          for (int l = pmatrix_.outerIndexPtr()[row]; l < pmatrix_.outerIndexPtr()[row + 1]; ++l)
            if (pmatrix_.innerIndexPtr()[l] == 0) pmatrix_.valuePtr()[l] = 0.0;
        }
      }
    }
  }
  double u_ref = 0.0, h_min = grid_.h[0];
  for (int a = 0; a < dim_; ++a) {
    for (double v : u_new_[a]) u_ref = std::max(u_ref, std::abs(v));
    h_min = std::min(h_min, grid_.h[a]);
  }
  // Absolute floor: a divergence below tolerance * U / h is as good as converged.
  const double atol = s_.pressure_tolerance * std::sqrt(static_cast<double>(nc)) * u_ref / h_min;
  const SolveStats st =
      psolver_.solve(pmatrix_, prhs_, phi_, s_.pressure_tolerance, atol, s_.max_iterations);
  rep.pressure_iterations = st.iterations;
  rep.pressure_residual = st.residual;
  // u = u* - (eps / a_f) grad phi on every face with a momentum equation; p += phi.
  for (int a = 0; a < dim_; ++a) {
    const Momentum& m = mom_[a];
    exec::parallel_for(static_cast<exec::index_t>(m.face_of_unknown.size()), [&](exec::index_t r) {
      const std::int64_t fi = m.face_of_unknown[r];
      u_new_[a][fi] -=
          fluid_response_[a][fi] * face_gradient(a, fi, m.coords[r][a], phi_.data(), true);
    });
  }
  refresh_boundary_faces(u_new_);
  if (shared_) {
    for (int a = 0; a < dim_; ++a)
      exec::parallel_for(grid_.face_count(a), [&](exec::index_t fi) {
        const int i = unflatten_face(a, fi)[a];
        const bool wall = !grid_.periodic[a] && (i == 0 || i == grid_.n[a]) &&
                          bc(a, i == 0 ? 0 : 1).kind != BcKind::PressureOutlet;
        grad_phi_[a][fi] = wall ? 0.0 : face_gradient(a, fi, i, phi_.data(), true);
      });
  }
  double mean = 0.0;
  for (std::int64_t c = 0; c < nc; ++c) {
    p_[c] += phi_[c];
    mean += p_[c];
  }
  if (closed_) {  // the pressure level is free: keep the mean at zero
    mean /= static_cast<double>(nc);
    for (double& v : p_) v -= mean;
  }
}

// ---------------------------------------------------------------------------------------------
// Inputs and the step

void VolumeAveragedNS::set_velocity(const std::function<Vec3(const Vec3&)>& u0) {
  for (int a = 0; a < dim_; ++a) {
    for (std::int64_t fi = 0; fi < grid_.face_count(a); ++fi) {
      const Index3 f = unflatten_face(a, fi);
      u_[a][fi] = u0(grid_.face_center(a, f[0], f[1], f[2]))[a];
    }
  }
  refresh_boundary_faces(u_);
  for (int a = 0; a < dim_; ++a) u_old_[a] = u_[a];
  history_ = 0;
}

void VolumeAveragedNS::set_pressure(std::span<const double> p) {
  REQUIRE(p.size() == p_.size(), "fluid: set_pressure got {} values for {} cells", p.size(),
          p_.size());
  for (std::size_t c = 0; c < p.size(); ++c) {
    REQUIRE(std::isfinite(p[c]), "fluid: pressure {} in cell {}", p[c], c);
    p_[c] = p[c];
  }
}

void VolumeAveragedNS::set_fluid_fraction(std::span<const double> eps,
                                          std::span<const double> eps_rate) {
  const auto nc = static_cast<std::size_t>(grid_.cell_count());
  REQUIRE(eps.size() == nc && eps_rate.size() == nc,
          "fluid: set_fluid_fraction got {} and {} values for {} cells", eps.size(),
          eps_rate.size(), nc);
  bool changed = false;
  for (std::size_t c = 0; c < nc; ++c) {
    REQUIRE(eps[c] > 0.0 && eps[c] <= 1.0, "fluid: fluid fraction {} in cell {} is not in (0, 1]",
            eps[c], c);
    REQUIRE(std::isfinite(eps_rate[c]), "fluid: d eps/dt in cell {} is {}", c, eps_rate[c]);
    changed = changed || eps[c] != eps_[c];
    eps_[c] = eps[c];
    eps_rate_[c] = eps_rate[c];
  }
  if (changed) {
    update_face_fraction();
    coefficients_dirty_ = true;
  }
}

void VolumeAveragedNS::set_shared_phase(const SharedPhase& phase) {
  bool any = false;
  for (int a = 0; a < dim_; ++a)
    for (const auto* f : {&phase.flux, &phase.fraction, &phase.carried, &phase.inertia})
      any = any || !(*f)[a].empty();
  shared_ = any;
  coefficients_dirty_ = true;  // the pressure matrix carries the response
  if (!any) return;
  for (int a = 0; a < dim_; ++a) {
    const auto nf = static_cast<std::size_t>(grid_.face_count(a));
    REQUIRE(phase.flux[a].size() == nf && phase.fraction[a].size() == nf &&
                phase.carried[a].size() == nf && phase.inertia[a].size() == nf,
            "fluid: set_shared_phase got {}, {}, {} and {} values for the {} faces normal to "
            "axis {}",
            phase.flux[a].size(), phase.fraction[a].size(), phase.carried[a].size(),
            phase.inertia[a].size(), nf, a);
    shared_flux_[a].assign(phase.flux[a].begin(), phase.flux[a].end());
    shared_fraction_[a].assign(phase.fraction[a].begin(), phase.fraction[a].end());
    shared_carried_[a].assign(phase.carried[a].begin(), phase.carried[a].end());
    shared_inertia_[a].assign(phase.inertia[a].begin(), phase.inertia[a].end());
    for (std::size_t f = 0; f < nf; ++f)
      REQUIRE(shared_fraction_[a][f] >= 0.0 && shared_fraction_[a][f] <= 1.0 &&
                  shared_carried_[a][f] >= 0.0 && shared_carried_[a][f] <= 1.0 &&
                  shared_inertia_[a][f] >= 0.0 && std::isfinite(shared_inertia_[a][f]),
              "fluid: shared phase on face {} of axis {}: fraction {}, carried {} (both in "
              "[0, 1]) and inertia {} (>= 0)",
              f, a, shared_fraction_[a][f], shared_carried_[a][f], shared_inertia_[a][f]);
    grad_phi_[a].assign(nf, 0.0);
  }
}

// Velocity per grad(phi) of the fluid and of the shared phase on every face: the fluid alone
// eps / A_f; with a shared phase the 2 x 2 system of set_shared_phase,
//   du = -(eps A_s + K a) / D grad(phi),  du_s = -(a A_f + K eps) / D grad(phi),
// D = A_s A_f - K^2 = inertia A_f + K eps rho c0 / dt > 0, A_s = inertia + K.
void VolumeAveragedNS::update_responses() {
  for (int a = 0; a < dim_; ++a)
    exec::parallel_for(grid_.face_count(a), [&](exec::index_t fi) {
      const double eps = eps_f_[a][fi], af = a_face_[a][fi];
      const double in = shared_ ? shared_inertia_[a][fi] : 0.0;
      if (in <= 0.0) {
        fluid_response_[a][fi] = eps / af;
        shared_response_[a][fi] = 0.0;
        return;
      }
      const FaceCells& c = face_cells_[a][fi];
      const double k = 0.5 * (drag_[c[0]] + drag_[c[1]]);
      const double as = shared_fraction_[a][fi], big_s = in + k;
      const double det = big_s * af - k * k;
      fluid_response_[a][fi] = (eps * big_s + k * as) / det;
      shared_response_[a][fi] = (as * af + k * eps) / det;
    });
}

void VolumeAveragedNS::set_momentum_source(std::span<const Vec3> s_explicit,
                                           std::span<const double> k) {
  const auto nc = static_cast<std::size_t>(grid_.cell_count());
  REQUIRE((s_explicit.empty() || s_explicit.size() == nc) && (k.empty() || k.size() == nc),
          "fluid: set_momentum_source got {} and {} values for {} cells (or pass none)",
          s_explicit.size(), k.size(), nc);
  bool changed = false;
  for (std::size_t c = 0; c < nc; ++c) {
    const double kc = k.empty() ? 0.0 : k[c];
    REQUIRE(kc >= 0.0 && std::isfinite(kc),
            "fluid: implicit drag coefficient {} kg/(m^3 s) in cell {} (must be >= 0)", kc, c);
    changed = changed || kc != drag_[c];
    drag_[c] = kc;
    source_[c] = s_explicit.empty() ? Vec3{} : s_explicit[c];
  }
  if (changed) coefficients_dirty_ = true;
}

void VolumeAveragedNS::set_boundary(BoxFace face, const BoundaryCondition& b) {
  const int i = box_face_index(face);
  REQUIRE(b.kind == s_.boundary[i].kind,
          "fluid boundary: set_boundary may change the values on face {}, not its kind",
          box_face_name(i));
  const BoundaryCondition old = s_.boundary[i];
  s_.boundary[i] = b;
  try {
    check_settings();
  } catch (...) {
    s_.boundary[i] = old;
    throw;
  }
  links_dirty_ = true;
}

VolumeAveragedNS::State VolumeAveragedNS::state() const {
  State st;
  st.time = time_;
  st.dt_prev = dt_prev_;
  st.n_steps = n_steps_;
  st.history = history_;
  auto add = [&](std::string name, std::vector<double> v) {
    st.arrays.emplace_back(std::move(name), std::move(v));
  };
  for (int a = 0; a < dim_; ++a) {
    const std::string k = std::to_string(a);
    add("u" + k, u_[a]);
    add("u_old" + k, u_old_[a]);
    add("conv_old" + k, conv_old_[a]);
    add("momentum_guess" + k,
        std::vector<double>(mom_[a].x.data(), mom_[a].x.data() + mom_[a].x.size()));
  }
  add("p", p_);
  add("phi_cell", phi_cell_);
  add("pressure_guess", std::vector<double>(phi_.data(), phi_.data() + phi_.size()));
  add("eps", eps_);
  add("eps_rate", eps_rate_);
  add("drag", drag_);
  std::vector<double> src(3 * source_.size());
  for (std::size_t c = 0; c < source_.size(); ++c)
    for (int a = 0; a < 3; ++a) src[3 * c + a] = source_[c][a];
  add("source", std::move(src));
  return st;
}

void VolumeAveragedNS::restore(const State& st) {
  auto get = [&](const std::string& name, std::size_t n) -> const std::vector<double>& {
    for (const auto& [key, v] : st.arrays)
      if (key == name) {
        REQUIRE(v.size() == n, "fluid restore: '{}' has {} values, the grid needs {}", name,
                v.size(), n);
        return v;
      }
    throw Error(fmt::format("fluid restore: no array '{}'", name));
  };
  for (int a = 0; a < dim_; ++a) {
    const std::string k = std::to_string(a);
    u_[a] = get("u" + k, u_[a].size());
    u_old_[a] = get("u_old" + k, u_old_[a].size());
    conv_old_[a] = get("conv_old" + k, conv_old_[a].size());
    const auto& x = get("momentum_guess" + k, static_cast<std::size_t>(mom_[a].x.size()));
    for (std::size_t i = 0; i < x.size(); ++i) mom_[a].x[static_cast<Eigen::Index>(i)] = x[i];
  }
  p_ = get("p", p_.size());
  phi_cell_ = get("phi_cell", phi_cell_.size());
  const auto& guess = get("pressure_guess", static_cast<std::size_t>(phi_.size()));
  for (std::size_t i = 0; i < guess.size(); ++i) phi_[static_cast<Eigen::Index>(i)] = guess[i];
  eps_ = get("eps", eps_.size());
  eps_rate_ = get("eps_rate", eps_rate_.size());
  drag_ = get("drag", drag_.size());
  const auto& src = get("source", 3 * source_.size());
  for (std::size_t c = 0; c < source_.size(); ++c)
    for (int a = 0; a < 3; ++a) source_[c][a] = src[3 * c + a];
  time_ = st.time;
  dt_prev_ = st.dt_prev;
  n_steps_ = st.n_steps;
  history_ = st.history;
  update_face_fraction();
  coefficients_dirty_ = true;
}

StepReport VolumeAveragedNS::step(double dt) {
  REQUIRE(dt > 0.0 && std::isfinite(dt), "fluid: time step must be positive, got {} s", dt);
  const double courant = max_cfl(dt);
  // A run's stop (NaN included), not a program error: no source location.
  if (!(courant <= s_.max_courant))
    throw Error(fmt::format(
        "fluid: dt = {} s gives a Courant number {:.3g} above max_courant = {} (convection is "
        "explicit); use dt <= {:.3g} s",
        dt, courant, s_.max_courant, dt * s_.max_courant / courant));
  refresh_boundary_faces(u_);
  // BDF1 / variable-step BDF2: du/dt ~ (c0 u^{n+1} - c1 u^n + c2 u^{n-1}) / dt, convection
  // extrapolated to t^{n+1} as e1 C^n + e2 C^{n-1}.
  const int order = s_.time_order == 2 && history_ > 0 ? 2 : 1;
  std::array<double, 5> bdf{1.0, 1.0, 0.0, 1.0, 0.0};
  if (order == 2) {
    const double w = dt / dt_prev_;
    bdf = {(1 + 2 * w) / (1 + w), 1 + w, w * w / (1 + w), 1 + w, -w};
  }
  assemble_ = coefficients_dirty_ || dt != coef_dt_ || bdf[0] != coef_c0_;
  if (assemble_) {
    update_coefficients(dt, bdf[0]);
    update_responses();
  }
  for (int a = 0; a < dim_; ++a) {
    exec::parallel_for(grid_.face_count(a),
                       [&](exec::index_t f) { flux_[a][f] = eps_f_[a][f] * u_[a][f]; });
  }
  for (int a = 0; a < dim_; ++a) compute_convection(a, conv_[a]);
  StepReport rep = solve_momentum(dt, bdf);
  rep.order = order;
  rep.courant = courant;
  rep.refactorized = assemble_;
  solve_pressure(rep);
  for (int a = 0; a < dim_; ++a) {
    std::swap(u_old_[a], u_[a]);
    std::swap(u_[a], u_new_[a]);
    std::swap(conv_old_[a], conv_[a]);
  }
  assemble_ = false;
  links_dirty_ = false;
  dt_prev_ = dt;
  time_ += dt;
  ++history_;
  ++n_steps_;
  return rep;
}

// ---------------------------------------------------------------------------------------------
// Results

Vec3 VolumeAveragedNS::cell_velocity(std::int64_t cell) const {
  const Index3 q = unflatten_cell(cell);
  Vec3 v{};
  for (int a = 0; a < dim_; ++a) {
    Index3 hi = q;
    hi[a] += 1;
    v[a] = 0.5 * (u_[a][grid_.face_index(a, q[0], q[1], q[2])] +
                  u_[a][grid_.face_index(a, hi[0], hi[1], hi[2])]);
  }
  return v;
}

Vec3 VolumeAveragedNS::pressure_gradient(std::int64_t cell) const {
  const Index3 q = unflatten_cell(cell);
  Vec3 g{};
  for (int a = 0; a < dim_; ++a) {
    double sum = 0.0;
    int count = 0;
    for (int side = 0; side < 2; ++side) {
      Index3 f = q;
      f[a] += side;
      const bool boundary = f[a] == 0 || f[a] == grid_.n[a];
      if (boundary && !grid_.periodic[a] && bc(a, side).kind != BcKind::PressureOutlet) continue;
      sum += face_gradient(a, face_offset(a, f), f[a], p_.data(), false);
      ++count;
    }
    g[a] = count > 0 ? sum / count : 0.0;
  }
  return g;
}

Mat3 VolumeAveragedNS::cell_velocity_gradient(std::int64_t cell) const {
  const Index3 q = unflatten_cell(cell);
  const Vec3 u_c = cell_velocity(cell);
  Mat3 g;
  for (int b = 0; b < dim_; ++b) {
    Vec3 u_side[2];
    double dist = 0.0;  // between the two points the difference is taken over
    for (int side = 0; side < 2; ++side) {
      Index3 nb = q;
      nb[b] += side == 0 ? -1 : 1;
      if ((nb[b] >= 0 && nb[b] < grid_.n[b]) || grid_.periodic[b]) {
        nb[b] = grid_.fold(b, nb[b]);
        u_side[side] = cell_velocity(grid_.index(nb[0], nb[1], nb[2]));
        dist += grid_.h[b];
      } else if (bc(b, side).kind == BcKind::PressureOutlet) {
        u_side[side] = u_c;  // zero normal gradient: a one-sided difference
      } else {
        for (int a = 0; a < dim_; ++a)
          if (a != b) u_side[side][a] = boundary_velocity(b, side, a, q);
        dist += 0.5 * grid_.h[b];
      }
    }
    if (dist == 0.0) continue;  // outlets on both sides of a single cell
    for (int a = 0; a < dim_; ++a)
      if (a != b) g.a[a][b] = (u_side[1][a] - u_side[0][a]) / dist;
  }
  for (int a = 0; a < dim_; ++a) {  // the cell's own faces, as in cell_velocity
    Index3 hi = q;
    hi[a] += 1;
    g.a[a][a] = (u_[a][grid_.face_index(a, hi[0], hi[1], hi[2])] -
                 u_[a][grid_.face_index(a, q[0], q[1], q[2])]) /
                grid_.h[a];
  }
  return g;
}

void VolumeAveragedNS::cell_velocity_gradients(std::span<Mat3> out) const {
  REQUIRE(out.size() == static_cast<std::size_t>(grid_.cell_count()),
          "fluid: cell_velocity_gradients needs {} entries, got {}", grid_.cell_count(),
          out.size());
  exec::parallel_for(grid_.cell_count(),
                     [&](exec::index_t c) { out[c] = cell_velocity_gradient(c); });
}

void VolumeAveragedNS::cell_velocities(std::span<Vec3> out) const {
  REQUIRE(out.size() == static_cast<std::size_t>(grid_.cell_count()),
          "fluid: cell_velocities needs {} entries, got {}", grid_.cell_count(), out.size());
  exec::parallel_for(grid_.cell_count(), [&](exec::index_t c) { out[c] = cell_velocity(c); });
}

void VolumeAveragedNS::pressure_gradients(std::span<Vec3> out) const {
  REQUIRE(out.size() == static_cast<std::size_t>(grid_.cell_count()),
          "fluid: pressure_gradients needs {} entries, got {}", grid_.cell_count(), out.size());
  exec::parallel_for(grid_.cell_count(), [&](exec::index_t c) { out[c] = pressure_gradient(c); });
}

double VolumeAveragedNS::max_cfl(double dt) const {
  double m = 0.0;
  for (std::int64_t c = 0; c < grid_.cell_count(); ++c) {
    const PressureRow& row = prow_[c];  // has the cell's lower faces
    double sum = 0.0;
    for (int a = 0; a < dim_; ++a) {
      const std::int64_t lo = row.face[a], hi = lo + face_stride_[a][a];
      sum += std::max(std::abs(u_[a][lo]), std::abs(u_[a][hi])) / grid_.h[a];
    }
    m = std::max(m, sum);
  }
  return m * dt;
}

double VolumeAveragedNS::mean_pressure(int axis, double coordinate) const {
  REQUIRE(axis >= 0 && axis < dim_, "fluid: mean_pressure on axis {} of a {}D grid", axis, dim_);
  const int n = grid_.n[axis];
  // Mean over the cells of layer i normal to the axis.
  auto layer = [&](int i) {
    double sum = 0.0;
    std::int64_t count = 0;
    for (std::int64_t c = 0; c < grid_.cell_count(); ++c) {
      if (unflatten_cell(c)[axis] != i) continue;
      sum += p_[c];
      ++count;
    }
    return sum / static_cast<double>(count);
  };
  const double t = (coordinate - grid_.lo[axis]) / grid_.h[axis] - 0.5;  // in cell-centre units
  auto lerp = [](double p0, double p1, double w) { return (1 - w) * p0 + w * p1; };
  if (t >= 0.0 && t <= n - 1) {
    if (n == 1) return layer(0);
    const int i = std::min(static_cast<int>(std::floor(t)), n - 2);
    return lerp(layer(i), layer(i + 1), t - i);
  }
  const int side = t < 0.0 ? 0 : 1;
  const int edge = side == 0 ? 0 : n - 1;
  const double d = side == 0 ? -t : t - (n - 1);  // distance beyond the last centre, in cells
  if (grid_.periodic[axis]) return lerp(layer(edge), layer(side == 0 ? n - 1 : 0), d);
  if (bc(axis, side).kind == BcKind::PressureOutlet)
    return lerp(layer(edge), bc(axis, side).pressure, std::min(2.0 * d, 1.0));
  if (n == 1) return layer(0);
  return lerp(layer(edge), layer(side == 0 ? 1 : n - 2), -d);  // linear extrapolation
}

double VolumeAveragedNS::pressure_drop(int axis, double x1, double x2) const {
  return mean_pressure(axis, x1) - mean_pressure(axis, x2);
}

double VolumeAveragedNS::flow_rate(int axis, int plane) const {
  REQUIRE(axis >= 0 && axis < dim_ && plane >= 0 && plane <= grid_.n[axis],
          "fluid: flow_rate through plane {} of axis {} is outside the grid", plane, axis);
  const double area = grid_.cell_volume() / grid_.h[axis];
  double q = 0.0;
  for (std::int64_t fi = 0; fi < grid_.face_count(axis); ++fi) {
    const Index3 f = unflatten_face(axis, fi);
    if (f[axis] == plane) q += eps_face(axis, f) * u_[axis][fi] * area;
  }
  return q;
}

double VolumeAveragedNS::superficial_velocity(int axis, int plane) const {
  double area = 1.0;
  for (int b = 0; b < 3; ++b)
    if (b != axis) area *= grid_.n[b] * grid_.h[b];
  return flow_rate(axis, plane) / area;
}

double VolumeAveragedNS::kinetic_energy() const {
  double e = 0.0;
  for (int a = 0; a < dim_; ++a) {
    for (std::int64_t fi = 0; fi < grid_.face_count(a); ++fi) {
      const Index3 f = unflatten_face(a, fi);
      const bool boundary = f[a] == 0 || f[a] == grid_.n[a];
      if (grid_.periodic[a] && f[a] == grid_.n[a]) continue;  // image of face 0
      const double w = boundary && !grid_.periodic[a] ? 0.5 : 1.0;
      e += w * 0.5 * s_.density * eps_face(a, f) * u_[a][fi] * u_[a][fi];
    }
  }
  return e * grid_.cell_volume();
}

double VolumeAveragedNS::divergence_norm() const {
  double m = 0.0;
  for (std::int64_t c = 0; c < grid_.cell_count(); ++c) {
    const Index3 q = unflatten_cell(c);
    double div = eps_rate_[c];
    for (int a = 0; a < dim_; ++a) {
      Index3 hi = q;
      hi[a] += 1;
      div += (eps_face(a, hi) * u_[a][grid_.face_index(a, hi[0], hi[1], hi[2])] -
              eps_face(a, q) * u_[a][grid_.face_index(a, q[0], q[1], q[2])]) /
             grid_.h[a];
    }
    m = std::max(m, std::abs(div));
  }
  return m;
}

}  // namespace gf::fluid
