// SPDX-License-Identifier: GPL-3.0-or-later
// P2-P1 Navier-Stokes: pattern, assembly of residual and Jacobian, Newton, BDF steps, forces.
#include "fluid/fem/navier_stokes.hpp"

#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.hpp"
#include "fluid/fem/p2_element.hpp"

namespace gf::fem {

namespace {

constexpr int kQ = p2::Quadrature7::n;
constexpr int kGeo = 13;  // w*det, gx[6], gy[6]
const p2::Quadrature7 kRule;

struct RefShapes {
  double phi[kQ][6];
  double l[kQ][3];
  RefShapes() {
    for (int q = 0; q < kQ; ++q) {
      double dxi[6], deta[6];
      p2::shape(kRule.xi[q], kRule.eta[q], phi[q], dxi, deta);
      l[q][0] = 1.0 - kRule.xi[q] - kRule.eta[q];
      l[q][1] = kRule.xi[q];
      l[q][2] = kRule.eta[q];
    }
  }
};
const RefShapes kRef;

double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::array<Vec2, 6> cell_nodes(const Mesh& m, int c) {
  std::array<Vec2, 6> x;
  for (int k = 0; k < 6; ++k) x[k] = m.nodes[m.cells[c][k]];
  return x;
}

}  // namespace

NavierStokes::NavierStokes(FlowProblem problem) : problem_(std::move(problem)) {
  const Mesh& m = problem_.mesh;
  REQUIRE(problem_.outline_bc.size() == problem_.spec.outline.size(),
          "one boundary condition per outline edge");
  const std::size_t n_bodies = problem_.spec.bodies.size();
  problem_.body_motion.resize(n_bodies);
  problem_.body_density.resize(n_bodies, 0.0);
  REQUIRE(problem_.density > 0 && problem_.viscosity > 0, "density and viscosity must be positive");
  // Area and polar moment of area about the centroid of each body; a free body's centre is its
  // centroid (gravity acts there and its inertia is diagonal about it).
  for (std::size_t j = 0; j < n_bodies; ++j) {
    auto& b = problem_.spec.bodies[j];
    const BodyGeometry g = body_geometry(b);
    if (b.kind == BodyShape::Kind::Polygon && problem_.body_density[j] > 0) b.centre = g.centroid;
    body_area_.push_back(g.area);
    body_inertia_.push_back(g.polar_moment);
  }
  free_slot_.assign(n_bodies, -1);
  body_load_.assign(n_bodies, BodyForce{});
  for (std::size_t j = 0; j < n_bodies; ++j) {
    REQUIRE(problem_.body_density[j] >= 0, "body {}: density {} must be >= 0", j,
            problem_.body_density[j]);
    if (problem_.body_density[j] > 0) free_slot_[j] = n_free_++;
  }
  n2_ = m.n_nodes();
  n1_ = m.n_vertices;
  n_dofs_ = 2 * n2_ + n1_ + 3 * n_free_;
  x_.assign(n_dofs_, 0.0);
  for (std::size_t j = 0; j < n_bodies; ++j)
    if (free_slot_[j] >= 0) {
      const int d = body_dof(static_cast<int>(j));
      x_[d] = problem_.body_motion[j].velocity.x;
      x_[d + 1] = problem_.body_motion[j].velocity.y;
      x_[d + 2] = problem_.body_motion[j].angular_velocity;
    }

  // Dirichlet nodes: walls override inflow (corners), bodies separate.
  std::vector<int> node_src(n2_, -1);  // -1 free; 0 wall; 1 + k inflow edge k; -(2 + j) body j
  for (const auto& e : m.boundary) {
    int src = -1;
    if (e.body >= 0) {
      src = -(2 + e.body);
    } else {
      const auto& bc = problem_.outline_bc[e.outline_edge];
      if (bc.kind == OutlineBcKind::Wall) {
        src = bc.wall_velocity.x == 0 && bc.wall_velocity.y == 0 ? 0 : 1 + e.outline_edge;
        if (src > 0) {  // a sliding wall moves in its own line (a normal part would add mass)
          const Vec2 a = problem_.spec.outline[e.outline_edge],
                     b = problem_.spec.outline[(e.outline_edge + 1) % problem_.spec.outline.size()];
          const double ex = b.x - a.x, ey = b.y - a.y, len = std::hypot(ex, ey);
          const double normal = (bc.wall_velocity.x * -ey + bc.wall_velocity.y * ex) / len;
          REQUIRE(std::abs(normal) <= 1e-12 * std::hypot(bc.wall_velocity.x, bc.wall_velocity.y),
                  "outline edge {}: a wall velocity must lie along the edge (normal part {})",
                  e.outline_edge, normal);
        }
      } else if (bc.kind == OutlineBcKind::Inflow) {
        src = 1 + e.outline_edge;
      }
    }
    if (src == -1) continue;
    auto is_moving_wall = [&](int s) {
      return s >= 1 && problem_.outline_bc[s - 1].kind == OutlineBcKind::Wall;
    };
    for (int v : {e.a, e.b, e.mid}) {
      // a wall at rest wins, then a moving wall over an inflow
      if (node_src[v] == 0) continue;
      if (src != 0 && is_moving_wall(node_src[v]) && !is_moving_wall(src)) continue;
      node_src[v] = src;
    }
  }
  body_nodes_.assign(problem_.spec.bodies.size(), {});
  for (const auto& e : m.boundary)
    if (e.body >= 0)
      for (int v : {e.a, e.b, e.mid}) body_nodes_[e.body].push_back(v);
  for (auto& b : body_nodes_) {
    std::sort(b.begin(), b.end());
    b.erase(std::unique(b.begin(), b.end()), b.end());
  }
  dirichlet_.assign(n_dofs_, -1);
  for (int v = 0; v < n2_; ++v) {
    if (node_src[v] == -1) continue;
    for (int d : {v, n2_ + v}) {
      dirichlet_[d] = static_cast<int>(dirichlet_dofs_.size());
      dirichlet_dofs_.push_back(d);
    }
  }
  dirichlet_values_.assign(dirichlet_dofs_.size(), 0.0);
  dir_src_ = std::move(node_src);
  // Without an outflow edge the pressure is defined up to a constant (the continuity rows sum
  // to the boundary flux, which the Dirichlet data make zero): one continuity row is replaced by
  // p = 0 at vertex 0, so the LU does not factorise a singular matrix. (Before, the solves of a
  // closed domain stalled at a relative update of ~1e-10 in long runs.)
  const bool has_outflow =
      std::any_of(problem_.outline_bc.begin(), problem_.outline_bc.end(),
                  [](const OutlineBc& bc) { return bc.kind == OutlineBcKind::Outflow; });
  if (!has_outflow && n1_ > 0) {
    // at the vertex on the outline's first corner: a fixed place in every mesh of the domain, so
    // the pressure level does not jump when a moving mesh is rebuilt
    int v0 = 0;
    double best = std::numeric_limits<double>::infinity();
    for (int v = 0; v < n1_; ++v) {
      const double d = std::hypot(m.nodes[v].x - problem_.spec.outline[0].x,
                                  m.nodes[v].y - problem_.spec.outline[0].y);
      if (d < best) {
        best = d;
        v0 = v;
      }
    }
    pinned_pressure_ = 2 * n2_ + v0;
    dirichlet_[pinned_pressure_] = static_cast<int>(dirichlet_dofs_.size());  // a row to skip
  }

  precompute_geometry();
  build_pattern();
  build_locator();
  residual_.assign(n_dofs_, 0.0);
  reaction_.assign(n_dofs_, 0.0);
  hist_term_.assign(2 * n2_ + 3 * n_free_, 0.0);
  base_nodes_ = m.nodes;
  for (const auto& b : problem_.spec.bodies) base_centres_.push_back(b.centre);
  set_time(0.0);
}

void NavierStokes::set_body_motion(int body, const BodyMotion& motion) {
  problem_.body_motion.at(body) = motion;
  if (free_slot_[body] >= 0) {
    const int d = body_dof(body);
    x_[d] = motion.velocity.x;
    x_[d + 1] = motion.velocity.y;
    x_[d + 2] = motion.angular_velocity;
  }
  set_time(t_);
}

void NavierStokes::set_body_load(int body, Vec2 force, double torque) {
  REQUIRE(free_slot_.at(body) >= 0, "a load acts on a free body only (body {} is not)", body);
  body_load_[body] = BodyForce{force, torque};
}

BodyMotion NavierStokes::body_velocity(int body) const {
  if (free_slot_.at(body) < 0) return problem_.body_motion[body];
  const int d = body_dof(body);
  return BodyMotion{{x_[d], x_[d + 1]}, x_[d + 2]};
}

double NavierStokes::body_mass(int body) const {
  return problem_.body_density.at(body) * body_area_[body];
}

double NavierStokes::body_inertia(int body) const {
  return problem_.body_density.at(body) * body_inertia_[body];
}

void NavierStokes::refresh_free_body_values() {
  if (n_free_ == 0) return;
  const Mesh& m = problem_.mesh;
  for (std::size_t i = 0; i < dirichlet_dofs_.size(); i += 2) {
    const int v = dirichlet_dofs_[i];
    const int src = dir_src_[v];
    if (src > -2 || free_slot_[-(src + 2)] < 0) continue;
    const int j = -(src + 2);
    const int d = body_dof(j);
    const Vec2 c = problem_.spec.bodies[j].centre;
    const Vec2 p = m.nodes[v];
    dirichlet_values_[i] = x_[d] - x_[d + 2] * (p.y - c.y);
    dirichlet_values_[i + 1] = x_[d + 1] + x_[d + 2] * (p.x - c.x);
  }
}

void NavierStokes::move_mesh(const std::vector<Vec2>& nodes, const std::vector<Vec2>& centres) {
  REQUIRE(
      nodes.size() == problem_.mesh.nodes.size() && centres.size() == problem_.spec.bodies.size(),
      "move_mesh: {} nodes and {} centres for a mesh of {} nodes and {} bodies", nodes.size(),
      centres.size(), problem_.mesh.nodes.size(), problem_.spec.bodies.size());
  const bool was_moving = moving_;
  if (!moving_) {  // the mesh was fixed so far: every known state had these positions
    base_nodes_ = problem_.mesh.nodes;
    base_centres_ = body_centres();
    hist_nodes_.assign(hist_t_.size(), base_nodes_);
    hist_centres_.assign(hist_t_.size(), base_centres_);
    if (lu_.has_factors()) {  // assembled on the fixed mesh, without ALE terms
      factor_nodes_ = base_nodes_;
      factor_centres_ = base_centres_;
      factor_w_.clear();
    }
    moving_ = true;
  }
  // an inverted cell throws from precompute_geometry: the mesh then stays where it was
  std::vector<Vec2> old_nodes = nodes;
  std::swap(old_nodes, problem_.mesh.nodes);
  std::vector<Vec2> old_centres;
  for (std::size_t j = 0; j < centres.size(); ++j) {
    old_centres.push_back(problem_.spec.bodies[j].centre);
    problem_.spec.bodies[j].centre = centres[j];
  }
  try {
    precompute_geometry();
  } catch (...) {
    problem_.mesh.nodes = std::move(old_nodes);
    for (std::size_t j = 0; j < centres.size(); ++j)
      problem_.spec.bodies[j].centre = old_centres[j];
    precompute_geometry();
    if (!was_moving) {  // still a fixed mesh
      moving_ = false;
      hist_nodes_.clear();
      hist_centres_.clear();
      factor_nodes_.clear();
      factor_centres_.clear();
    }
    throw;
  }
  locator_stale_ = true;  // rebuilt when a point is located (probes, interpolation)
  set_time(t_);
}

void NavierStokes::set_time(double t) {
  t_ = t;
  const auto& spec = problem_.spec;
  const Mesh& m = problem_.mesh;
  for (std::size_t i = 0; i < dirichlet_dofs_.size(); i += 2) {
    const int v = dirichlet_dofs_[i];
    const int src = dir_src_[v];
    Vec2 u{0, 0};
    const Vec2 p = m.nodes[v];
    if (src >= 1) {
      const int k = src - 1;
      const auto& bc = problem_.outline_bc[k];
      if (bc.kind == OutlineBcKind::Wall) {  // a wall moving in its own line
        dirichlet_values_[i] = bc.wall_velocity.x;
        dirichlet_values_[i + 1] = bc.wall_velocity.y;
        continue;
      }
      const Vec2 a = spec.outline[k], b = spec.outline[(k + 1) % spec.outline.size()];
      const double len = std::hypot(b.x - a.x, b.y - a.y);
      const double s = std::clamp(
          ((p.x - a.x) * (b.x - a.x) + (p.y - a.y) * (b.y - a.y)) / (len * len), 0.0, 1.0);
      const double f = bc.time_function ? bc.time_function(t) : 1.0;
      const double mag = bc.u_max * f * (bc.parabolic ? 4.0 * s * (1.0 - s) : 1.0);
      // inward normal: the fluid is on the side of the outline's interior
      double nx = -(b.y - a.y) / len, ny = (b.x - a.x) / len;
      double area2 = 0;
      for (std::size_t j = 0; j < spec.outline.size(); ++j) {
        const Vec2 c = spec.outline[j], d = spec.outline[(j + 1) % spec.outline.size()];
        area2 += c.x * d.y - d.x * c.y;
      }
      if (area2 < 0) {
        nx = -nx;
        ny = -ny;
      }
      u = {mag * nx, mag * ny};
    } else if (src <= -2) {
      const int j = -(src + 2);
      const BodyMotion mo = body_velocity(j);
      const Vec2 c = spec.bodies[j].centre;
      u = {mo.velocity.x - mo.angular_velocity * (p.y - c.y),
           mo.velocity.y + mo.angular_velocity * (p.x - c.x)};
    }
    dirichlet_values_[i] = u.x;
    dirichlet_values_[i + 1] = u.y;
  }
  apply_dirichlet_to_solution();
}

void NavierStokes::apply_dirichlet_to_solution() {
  for (std::size_t i = 0; i < dirichlet_dofs_.size(); ++i)
    x_[dirichlet_dofs_[i]] = dirichlet_values_[i];
  if (pinned_pressure_ >= 0) x_[pinned_pressure_] = 0.0;
}

void NavierStokes::precompute_geometry() {
  const Mesh& m = problem_.mesh;
  geo_.resize(static_cast<std::size_t>(m.n_cells()) * kQ * kGeo);
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto x = cell_nodes(m, c);
    for (int q = 0; q < kQ; ++q) {
      double* g = &geo_[(static_cast<std::size_t>(c) * kQ + q) * kGeo];
      double phi[6];
      const double det = p2::gradients(x, kRule.xi[q], kRule.eta[q], phi, g + 1, g + 7);
      REQUIRE(det > 0, "cell {} is inverted or degenerate (det J = {})", c, det);
      g[0] = kRule.w[q] * det;
    }
  }
}

void NavierStokes::build_pattern() {
  const Mesh& m = problem_.mesh;
  auto dof = [&](int c, int r) {
    if (r < 6) return m.cells[c][r];
    if (r < 12) return n2_ + m.cells[c][r - 6];
    return 2 * n2_ + m.cells[c][r - 12];
  };
  std::vector<Eigen::Triplet<double, int>> trip;
  trip.reserve(static_cast<std::size_t>(m.n_cells()) * 216 + dirichlet_dofs_.size());
  for (int c = 0; c < m.n_cells(); ++c)
    for (int r = 0; r < 15; ++r) {
      const int gr = dof(c, r);
      if (dirichlet_[gr] >= 0) continue;
      for (int s = 0; s < 15; ++s) {
        if (r >= 12 && s >= 12) continue;
        trip.emplace_back(gr, dof(c, s), 0.0);
      }
    }
  for (int d : dirichlet_dofs_) trip.emplace_back(d, d, 0.0);
  if (pinned_pressure_ >= 0) trip.emplace_back(pinned_pressure_, pinned_pressure_, 0.0);
  // Free bodies: node rows u - (V + Omega x r) = 0 couple to the body's unknowns; the body's
  // rows sum the momentum rows of its nodes (their columns) and carry the body's inertia.
  auto free_body_of = [&](int gdof) {  // body index of a free body's node dof, else -1
    const int v = gdof < n2_ ? gdof : gdof - n2_;
    if (gdof >= 2 * n2_ || dir_src_[v] > -2) return -1;
    const int j = -(dir_src_[v] + 2);
    return free_slot_[j] >= 0 ? j : -1;
  };
  if (n_free_ > 0) {
    for (int d : dirichlet_dofs_) {
      const int j = free_body_of(d);
      if (j < 0) continue;
      trip.emplace_back(d, body_dof(j) + (d < n2_ ? 0 : 1), 0.0);
      trip.emplace_back(d, body_dof(j) + 2, 0.0);
    }
    for (int c = 0; c < m.n_cells(); ++c)
      for (int r = 0; r < 12; ++r) {
        const int j = free_body_of(dof(c, r));
        if (j < 0) continue;
        for (int s = 0; s < 15; ++s) {
          trip.emplace_back(body_dof(j) + (r < 6 ? 0 : 1), dof(c, s), 0.0);
          trip.emplace_back(body_dof(j) + 2, dof(c, s), 0.0);
        }
      }
    for (std::size_t j = 0; j < free_slot_.size(); ++j)
      if (free_slot_[j] >= 0)
        for (int k = 0; k < 3; ++k)
          trip.emplace_back(body_dof(static_cast<int>(j)) + k, body_dof(static_cast<int>(j)) + k,
                            0.0);
  }
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> a(n_dofs_, n_dofs_);
  a.setFromTriplets(trip.begin(), trip.end());
  a.makeCompressed();
  col_ptr_.assign(a.outerIndexPtr(), a.outerIndexPtr() + n_dofs_ + 1);
  row_idx_.assign(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros());
  values_.assign(a.nonZeros(), 0.0);
  auto pos = [&](int row, int col) {
    const int* b = row_idx_.data() + col_ptr_[col];
    const int* e = row_idx_.data() + col_ptr_[col + 1];
    const int* it = std::lower_bound(b, e, row);
    REQUIRE(it != e && *it == row, "pattern misses ({}, {})", row, col);
    return static_cast<int>(it - row_idx_.data());
  };
  cell_map_.assign(static_cast<std::size_t>(m.n_cells()) * 225, -1);
  for (int c = 0; c < m.n_cells(); ++c)
    for (int r = 0; r < 15; ++r) {
      const int gr = dof(c, r);
      if (dirichlet_[gr] >= 0) continue;
      for (int s = 0; s < 15; ++s) {
        if (r >= 12 && s >= 12) continue;
        cell_map_[static_cast<std::size_t>(c) * 225 + r * 15 + s] = pos(gr, dof(c, s));
      }
    }
  diag_pos_.clear();
  for (int d : dirichlet_dofs_) diag_pos_.push_back(pos(d, d));
  if (pinned_pressure_ >= 0) pinned_pos_ = pos(pinned_pressure_, pinned_pressure_);
  free_cell_start_.assign(n_free_ > 0 ? m.n_cells() + 1 : 0, 0);
  free_entries_.clear();
  free_constraint_.assign(n_free_ > 0 ? dirichlet_dofs_.size() : 0, FreeConstraint{-1, -1});
  free_diag_.clear();
  if (n_free_ > 0) {
    for (int c = 0; c < m.n_cells(); ++c) {
      for (int r = 0; r < 12; ++r) {
        const int j = free_body_of(dof(c, r));
        if (j < 0) continue;
        for (int s = 0; s < 15; ++s)
          free_entries_.push_back({r, s, pos(body_dof(j) + (r < 6 ? 0 : 1), dof(c, s)),
                                   pos(body_dof(j) + 2, dof(c, s))});
      }
      free_cell_start_[c + 1] = static_cast<int>(free_entries_.size());
    }
    for (std::size_t i = 0; i < dirichlet_dofs_.size(); ++i) {
      const int d = dirichlet_dofs_[i];
      const int j = free_body_of(d);
      if (j < 0) continue;
      free_constraint_[i] = {pos(d, body_dof(j) + (d < n2_ ? 0 : 1)), pos(d, body_dof(j) + 2)};
    }
    for (std::size_t j = 0; j < free_slot_.size(); ++j)
      if (free_slot_[j] >= 0)
        for (int k = 0; k < 3; ++k)
          free_diag_.push_back(
              pos(body_dof(static_cast<int>(j)) + k, body_dof(static_cast<int>(j)) + k));
  }
  lu_.analyze(n_dofs_, col_ptr_.data(), row_idx_.data(), values_.data());
}

void NavierStokes::assemble(bool with_jacobian, bool newton_terms) {
  const double t0 = seconds_now();
  const Mesh& m = problem_.mesh;
  const double rho = problem_.density, mu = problem_.density * problem_.viscosity;
  const double a0 = alpha0_;
  const bool ale = moving_ && !mesh_w_.empty();
  refresh_free_body_values();
  std::fill(residual_.begin(), residual_.end(), 0.0);
  if (with_jacobian) std::fill(values_.begin(), values_.end(), 0.0);
  double ke[15][15];
  double re[15];
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto& cell = m.cells[c];
    double ux[6], uy[6], wx[6], wy[6], p[3], mx[6] = {}, my[6] = {};
    if (ale)
      for (int k = 0; k < 6; ++k) {
        mx[k] = mesh_w_[cell[k]].x;
        my[k] = mesh_w_[cell[k]].y;
      }
    for (int k = 0; k < 6; ++k) {
      ux[k] = x_[cell[k]];
      uy[k] = x_[n2_ + cell[k]];
      wx[k] = a0 * ux[k] + hist_term_[cell[k]];
      wy[k] = a0 * uy[k] + hist_term_[n2_ + cell[k]];
    }
    for (int k = 0; k < 3; ++k) p[k] = x_[2 * n2_ + cell[k]];
    std::fill(&re[0], &re[0] + 15, 0.0);
    if (with_jacobian) std::fill(&ke[0][0], &ke[0][0] + 225, 0.0);
    for (int q = 0; q < kQ; ++q) {
      const double* g = &geo_[(static_cast<std::size_t>(c) * kQ + q) * kGeo];
      const double w = g[0];
      const double* gx = g + 1;
      const double* gy = g + 7;
      const double* phi = kRef.phi[q];
      const double* l = kRef.l[q];
      double vx = 0, vy = 0, tx = 0, ty = 0, g00 = 0, g01 = 0, g10 = 0, g11 = 0;
      double cx = 0, cy = 0;  // ALE: convecting velocity u - w = (vx - cx, vy - cy)
      for (int k = 0; k < 6; ++k) {
        cx += mx[k] * phi[k];
        cy += my[k] * phi[k];
        vx += ux[k] * phi[k];
        vy += uy[k] * phi[k];
        tx += wx[k] * phi[k];
        ty += wy[k] * phi[k];
        g00 += ux[k] * gx[k];
        g01 += ux[k] * gy[k];
        g10 += uy[k] * gx[k];
        g11 += uy[k] * gy[k];
      }
      const double pq = p[0] * l[0] + p[1] * l[1] + p[2] * l[2];
      const double fx = w * rho * (tx + (vx - cx) * g00 + (vy - cy) * g01);
      const double fy = w * rho * (ty + (vx - cx) * g10 + (vy - cy) * g11);
      const double sxx = w * (mu * g00 - pq), sxy = w * mu * g01, syx = w * mu * g10,
                   syy = w * (mu * g11 - pq);
      for (int a = 0; a < 6; ++a) {
        re[a] += fx * phi[a] + sxx * gx[a] + sxy * gy[a];
        re[6 + a] += fy * phi[a] + syx * gx[a] + syy * gy[a];
      }
      const double dv = -w * (g00 + g11);
      for (int b = 0; b < 3; ++b) re[12 + b] += dv * l[b];
      if (!with_jacobian) continue;
      double adv[6];
      for (int k = 0; k < 6; ++k) adv[k] = (vx - cx) * gx[k] + (vy - cy) * gy[k];
      const double wr = w * rho, wm = w * mu;
      const double n00 = newton_terms ? wr * g00 : 0.0, n01 = newton_terms ? wr * g01 : 0.0;
      const double n10 = newton_terms ? wr * g10 : 0.0, n11 = newton_terms ? wr * g11 : 0.0;
      for (int a = 0; a < 6; ++a) {
        const double pa = phi[a];
        for (int b = 0; b < 6; ++b) {
          const double base =
              wr * (a0 * phi[b] + adv[b]) * pa + wm * (gx[b] * gx[a] + gy[b] * gy[a]);
          const double pp = phi[b] * pa;
          ke[a][b] += base + n00 * pp;
          ke[a][6 + b] += n01 * pp;
          ke[6 + a][b] += n10 * pp;
          ke[6 + a][6 + b] += base + n11 * pp;
        }
        for (int d = 0; d < 3; ++d) {
          ke[a][12 + d] -= w * l[d] * gx[a];
          ke[6 + a][12 + d] -= w * l[d] * gy[a];
          ke[12 + d][a] -= w * l[d] * gx[a];
          ke[12 + d][6 + a] -= w * l[d] * gy[a];
        }
      }
    }
    for (int r = 0; r < 6; ++r) {
      residual_[cell[r]] += re[r];
      residual_[n2_ + cell[r]] += re[6 + r];
    }
    for (int r = 0; r < 3; ++r) residual_[2 * n2_ + cell[r]] += re[12 + r];
    if (with_jacobian) {
      const int* map = &cell_map_[static_cast<std::size_t>(c) * 225];
      for (int r = 0; r < 15; ++r)
        for (int s = 0; s < 15; ++s) {
          const int at = map[r * 15 + s];
          if (at >= 0) values_[at] += ke[r][s];
        }
      if (n_free_ > 0) {
        // body rows: force = sum of the node rows, torque = sum of r x (node rows)
        const auto x = cell_nodes(m, c);
        for (int e = free_cell_start_[c]; e < free_cell_start_[c + 1]; ++e) {
          const auto& fe = free_entries_[e];
          const int node = fe.r % 6;
          const int j = -(dir_src_[cell[node]] + 2);
          const Vec2 ctr = problem_.spec.bodies[j].centre;
          const double arm = fe.r < 6 ? -(x[node].y - ctr.y) : x[node].x - ctr.x;
          values_[fe.pos_lin] += ke[fe.r][fe.s];
          values_[fe.pos_ang] += arm * ke[fe.r][fe.s];
        }
      }
    }
  }
  reaction_ = residual_;
  for (std::size_t i = 0; i < dirichlet_dofs_.size(); ++i) {
    const int d = dirichlet_dofs_[i];
    residual_[d] = x_[d] - dirichlet_values_[i];
    if (with_jacobian) values_[diag_pos_[i]] = 1.0;
  }
  if (pinned_pressure_ >= 0) {
    residual_[pinned_pressure_] = x_[pinned_pressure_];
    if (with_jacobian) values_[pinned_pos_] = 1.0;
  }
  if (n_free_ > 0) assemble_free_bodies(with_jacobian);
  assembly_seconds_ += seconds_now() - t0;
}

void NavierStokes::assemble_free_bodies(bool with_jacobian) {
  // Node rows of a free body: u_i - (V + Omega e_z x (x_i - c)) = 0.
  const Mesh& m = problem_.mesh;
  if (with_jacobian)
    for (std::size_t i = 0; i < dirichlet_dofs_.size(); ++i) {
      const auto& fc = free_constraint_[i];
      if (fc.pos_lin < 0) continue;
      const int d = dirichlet_dofs_[i];
      const int v = d < n2_ ? d : d - n2_;
      const Vec2 c = problem_.spec.bodies[-(dir_src_[v] + 2)].centre;
      values_[fc.pos_lin] = -1.0;
      values_[fc.pos_ang] = d < n2_ ? m.nodes[v].y - c.y : -(m.nodes[v].x - c.x);
    }
  // Body rows: m dV/dt + sum_i R_i - (m - rho A) g = 0 and
  // I dOmega/dt + sum_i r_i x R_i + 2 mu A Omega = 0, where R_i are the momentum rows of the
  // body's nodes (minus the fluid's force on the body, see reaction_forces()).
  const double mu = problem_.density * problem_.viscosity;
  const Vec2 gravity = problem_.tilt.gravity(problem_.gravity, t_);  // (at the step's end)
  for (std::size_t j = 0; j < free_slot_.size(); ++j) {
    if (free_slot_[j] < 0) continue;
    const int b = static_cast<int>(j);
    const int d = body_dof(b);
    const int h = 2 * n2_ + 3 * free_slot_[j];
    const double mass = body_mass(b), inertia = body_inertia(b);
    const double buoyant = mass - problem_.density * body_area_[j];
    const Vec2 c = problem_.spec.bodies[j].centre;
    double fx = 0, fy = 0, tz = 0;
    for (int v : body_nodes_[j]) {
      const double rx = reaction_[v], ry = reaction_[n2_ + v];
      fx += rx;
      fy += ry;
      tz += (m.nodes[v].x - c.x) * ry - (m.nodes[v].y - c.y) * rx;
    }
    const BodyForce& load = body_load_[j];
    residual_[d] =
        mass * (alpha0_ * x_[d] + hist_term_[h]) + fx - buoyant * gravity.x - load.force.x;
    residual_[d + 1] =
        mass * (alpha0_ * x_[d + 1] + hist_term_[h + 1]) + fy - buoyant * gravity.y - load.force.y;
    residual_[d + 2] = inertia * (alpha0_ * x_[d + 2] + hist_term_[h + 2]) + tz +
                       2.0 * mu * body_area_[j] * x_[d + 2] - load.torque;
    if (with_jacobian) {
      const int f = 3 * free_slot_[j];
      values_[free_diag_[f]] += mass * alpha0_;
      values_[free_diag_[f + 1]] += mass * alpha0_;
      values_[free_diag_[f + 2]] += inertia * alpha0_ + 2.0 * mu * body_area_[j];
    }
  }
}

NewtonReport NavierStokes::newton(const NewtonOptions& opt) {
  apply_dirichlet_to_solution();
  NewtonReport rep;
  std::vector<double> rhs(n_dofs_), dx(n_dofs_);
  // A factorisation from an earlier step is kept while alpha0 (the BDF step) changed by < 20 %.
  bool need_fresh = !opt.reuse_factorization || !lu_.has_factors() || !factor_newton_ ||
                    std::abs(factor_alpha0_ - alpha0_) > 0.2 * std::abs(alpha0_) ||
                    (alpha0_ == 0) != (factor_alpha0_ == 0);
  double prev = std::numeric_limits<double>::infinity();
  // Picard iterations help a steady solve (alpha0 = 0) from a poor guess; a time step starts from
  // the extrapolated predictor, where they only cost (2D-2: 11 iterations per step with 10
  // Picard ones against 1 from a steady start).
  const int picard = alpha0_ == 0 ? opt.picard_iterations : 0;
  for (int it = 0; it < opt.max_iterations; ++it) {
    const bool newton_terms = it >= picard;
    const bool refactor = need_fresh || newton_terms != factor_newton_;
    assemble(refactor, newton_terms);
    if (refactor) {
      lu_.factorize(values_.data());
      factor_alpha0_ = alpha0_;
      factor_newton_ = newton_terms;
      factor_x_ = x_;
      if (moving_) {  // (a checkpoint rebuilds these factors where they were assembled)
        factor_nodes_ = problem_.mesh.nodes;
        factor_centres_ = body_centres();
        factor_w_ = mesh_w_;
      }
      ++rep.factorizations;
      need_fresh = !opt.reuse_factorization;
    }
    for (int i = 0; i < n_dofs_; ++i) rhs[i] = -residual_[i];
    lu_.solve(rhs.data(), dx.data());
    double du = 0, umax = 0;
    bool finite = true;
    for (int i = 0; i < n_dofs_; ++i) {
      x_[i] += dx[i];
      finite = finite && std::isfinite(x_[i]);
    }
    for (int i = 0; i < 2 * n2_; ++i) {
      du = std::max(du, std::abs(dx[i]));
      umax = std::max(umax, std::abs(x_[i]));
    }
    // (std::max passes over NaN: an iterate of NaN velocities had an update of 0 and counted as
    // converged; any non-finite unknown, pressures included, fails the iteration)
    const double update =
        finite ? du / std::max(umax, 1e-300) : std::numeric_limits<double>::quiet_NaN();
    rep.iterations = it + 1;
    rep.last_update = update;
    if (!std::isfinite(update)) break;
    if (opt.reuse_factorization && update > opt.max_contraction * prev) need_fresh = true;
    prev = update;
    if (update <= opt.tolerance && newton_terms) {
      rep.converged = true;
      break;
    }
  }
  assemble(false, true);  // residual at the final state: reaction forces
  return rep;
}

NewtonReport NavierStokes::solve_steady(const NewtonOptions& opt) {
  alpha0_ = 0.0;
  std::fill(hist_term_.begin(), hist_term_.end(), 0.0);
  return newton(opt);
}

StepResult NavierStokes::try_step(double dt, int order, const NewtonOptions& opt, double rtol,
                                  double atol, bool neighbour_errors) {
  REQUIRE(dt > 0, "time step must be positive, got {}", dt);
  if (hist_t_.empty()) {
    hist_t_.push_back(t_);
    hist_x_.push_back(x_);
    if (moving_) {
      hist_nodes_.assign(1, base_nodes_);
      hist_centres_.assign(1, base_centres_);
    }
  }
  const int k = std::clamp(order, 1, std::min(kMaxBdfOrder, static_cast<int>(hist_t_.size())));
  last_order_ = k;
  const double tn = hist_t_[0];
  const int nv = 2 * n2_ + 3 * n_free_;  // velocity-like unknowns (hist_dof(i))
  // Variable-step BDF-k: du/dt(t_{n+1}) is the derivative at tau_0 = t_{n+1} of the polynomial
  // through (tau_j, u_j), tau_j = the newest k states' times; the weight of u_j is the derivative
  // of its Lagrange basis polynomial at tau_0. alpha0 = sum_{m>0} 1 / (tau_0 - tau_m).
  const double tp = tn + dt;
  std::array<double, kMaxBdfOrder + 1> tau{};
  tau[0] = tp;
  for (int j = 1; j <= k; ++j) tau[j] = hist_t_[j - 1];
  alpha0_ = 0.0;
  for (int m = 1; m <= k; ++m) alpha0_ += 1.0 / (tp - tau[m]);
  std::fill(hist_term_.begin(), hist_term_.begin() + nv, 0.0);
  // ALE: the mesh velocity is the same BDF derivative of the node positions.
  if (moving_) {
    mesh_w_.resize(n2_);
    for (int i = 0; i < n2_; ++i)
      mesh_w_[i] = {alpha0_ * problem_.mesh.nodes[i].x, alpha0_ * problem_.mesh.nodes[i].y};
  }
  for (int j = 1; j <= k; ++j) {
    double w = 1.0;
    for (int m = 0; m <= k; ++m) {
      if (m == j) continue;
      if (m != 0) w *= tp - tau[m];
      w /= tau[j] - tau[m];
    }
    const auto& xj = hist_x_[j - 1];
    for (int i = 0; i < nv; ++i) hist_term_[i] += w * xj[hist_dof(i)];
    if (moving_) {
      const auto& nj = hist_nodes_[j - 1];
      for (int i = 0; i < n2_; ++i) {
        mesh_w_[i].x += w * nj[i].x;
        mesh_w_[i].y += w * nj[i].y;
      }
    }
  }
  // Predictor: extrapolation of degree k through the newest k+1 states (lower if fewer known).
  const int deg = std::min(k, static_cast<int>(hist_t_.size()) - 1);
  std::vector<double> xp(n_dofs_, 0.0);
  for (int j = 0; j <= deg; ++j) {
    double lj = 1;
    for (int i = 0; i <= deg; ++i)
      if (i != j) lj *= (tp - hist_t_[i]) / (hist_t_[j] - hist_t_[i]);
    for (int i = 0; i < n_dofs_; ++i) xp[i] += lj * hist_x_[j][i];
  }
  x_ = xp;
  set_time(tp);
  StepResult res;
  res.newton = newton(opt);
  if (deg == k) {
    // Milne's device: with D = u^(k+1) / (k+1)!, the corrector's error is D prod_{m=1..k}
    // (tau_0 - tau_m) / alpha0 (its derivative error over alpha0), the predictor's (degree-k
    // extrapolation through the newest k+1 states) D prod_{j=0..k} (t_{n+1} - t_{n-j}); their
    // difference x - xp is measured, so the corrector's error is f (x - xp), f = cc / (cc + cp)
    // (D cancels).
    double cc = 1.0 / alpha0_, cp = 1.0;
    for (int m = 1; m <= k; ++m) cc *= tp - tau[m];
    for (int j = 0; j <= k; ++j) cp *= tp - hist_t_[j];
    const double f = cc / (cc + cp);
    for (int i = 0; i < nv; ++i) xp[hist_dof(i)] = f * (x_[hist_dof(i)] - xp[hist_dof(i)]);
    res.error = velocity_norm(xp, rtol, atol);
  }
  if (neighbour_errors) {
    const int known = static_cast<int>(hist_t_.size());
    if (k > 1) res.error_lower = order_error(k - 1, rtol, atol);
    if (k < kMaxBdfOrder && known >= k + 2) res.error_higher = order_error(k + 1, rtol, atol);
  }
  return res;
}

double NavierStokes::velocity_norm(const std::vector<double>& e, double rtol, double atol) const {
  // (free bodies' velocities count like fluid velocities)
  double sum = 0;
  int n = 0;
  for (int k = 0; k < 2 * n2_ + 3 * n_free_; ++k) {
    const int i = hist_dof(k);
    if (dirichlet_[i] >= 0) continue;
    const double w = e[i] / (atol + rtol * std::abs(x_[i]));
    sum += w * w;
    ++n;
  }
  return std::sqrt(sum / std::max(n, 1));
}

double NavierStokes::order_error(int j, double rtol, double atol) const {
  REQUIRE(j >= 1 && static_cast<int>(hist_t_.size()) >= j + 1,
          "order-{} error estimate needs {} known states", j, j + 1);
  // Points s_0 = t (the new state), s_i = t_{n+1-i}; the divided difference of order j + 1 is
  // sum_i u_i / prod_{l != i} (s_i - s_l) and approximates u^(j+1) / (j+1)!, the D of the
  // corrector error D prod_{m=1..j} (t - s_m) / alpha0 (see try_step).
  std::array<double, kMaxBdfOrder + 2> s{};
  s[0] = t_;
  for (int i = 1; i <= j + 1; ++i) s[i] = hist_t_[i - 1];
  double g = 1.0, alpha0 = 0.0;
  for (int m = 1; m <= j; ++m) {
    g *= t_ - s[m];
    alpha0 += 1.0 / (t_ - s[m]);
  }
  g /= alpha0;
  std::vector<double> e(n_dofs_, 0.0);
  for (int i = 0; i <= j + 1; ++i) {
    double c = g;
    for (int l = 0; l <= j + 1; ++l)
      if (l != i) c /= s[i] - s[l];
    const auto& u = i == 0 ? x_ : hist_x_[i - 1];
    for (int q = 0; q < 2 * n2_ + 3 * n_free_; ++q) e[hist_dof(q)] += c * u[hist_dof(q)];
  }
  return velocity_norm(e, rtol, atol);
}

void NavierStokes::accept_step() {
  hist_t_.insert(hist_t_.begin(), t_);
  hist_x_.insert(hist_x_.begin(), x_);
  if (moving_) {  // (a fixed mesh keeps no copies of its nodes)
    base_nodes_ = problem_.mesh.nodes;
    base_centres_ = body_centres();
    hist_nodes_.insert(hist_nodes_.begin(), base_nodes_);
    hist_centres_.insert(hist_centres_.begin(), base_centres_);
  }
  if (hist_t_.size() > kMaxBdfOrder + 1) {  // the predictor of order k uses k + 1 states
    hist_t_.pop_back();
    hist_x_.pop_back();
  }
  if (hist_nodes_.size() > hist_t_.size()) {
    hist_nodes_.pop_back();
    hist_centres_.pop_back();
  }
}

NavierStokes::State NavierStokes::state() const {
  State s;
  s.t = t_;
  s.last_order = last_order_;
  s.x = x_;
  s.hist_t = hist_t_;
  s.hist_x = hist_x_;
  s.alpha0 = alpha0_;
  s.hist_term = hist_term_;
  s.factorized = lu_.has_factors();
  if (s.factorized) {
    s.factor_x = factor_x_;
    s.factor_alpha0 = factor_alpha0_;
    s.factor_newton = factor_newton_;
  }
  s.moving = moving_;
  if (moving_) {
    s.nodes = problem_.mesh.nodes;
    s.centres = body_centres();
    s.hist_nodes = hist_nodes_;
    s.hist_centres = hist_centres_;
    s.mesh_w = mesh_w_;
    if (s.factorized) {
      s.factor_nodes = factor_nodes_;
      s.factor_centres = factor_centres_;
      s.factor_w = factor_w_;
    }
  }
  s.body_load = body_load_;
  return s;
}

std::vector<Vec2> NavierStokes::body_centres() const {
  std::vector<Vec2> c;
  c.reserve(problem_.spec.bodies.size());
  for (const auto& b : problem_.spec.bodies) c.push_back(b.centre);
  return c;
}

void NavierStokes::place_mesh(const std::vector<Vec2>& nodes, const std::vector<Vec2>& centres,
                              const std::vector<Vec2>& w) {
  problem_.mesh.nodes = nodes;
  for (std::size_t j = 0; j < centres.size(); ++j) problem_.spec.bodies[j].centre = centres[j];
  mesh_w_ = w;
  precompute_geometry();
  locator_stale_ = true;
}

void NavierStokes::restore(const State& s) {
  const auto n = static_cast<std::size_t>(n_dofs_);
  REQUIRE(s.x.size() == n && s.hist_term.size() == hist_term_.size() &&
              s.hist_x.size() == s.hist_t.size() && s.hist_t.size() <= kMaxBdfOrder + 1 &&
              (!s.factorized || s.factor_x.size() == n),
          "fluid_fem state of another problem: {} unknowns and {} history states, expected {}",
          s.x.size(), s.hist_t.size(), n);
  for (const auto& h : s.hist_x)
    REQUIRE(h.size() == n, "fluid_fem state: a history state of {} unknowns, expected {}", h.size(),
            n);
  const std::size_t nn = problem_.mesh.nodes.size(), nb = problem_.spec.bodies.size();
  REQUIRE(s.body_load.empty() || s.body_load.size() == nb,
          "fluid_fem state: loads of {} bodies, expected {}", s.body_load.size(), nb);
  if (s.moving) {
    auto fits = [&](const std::vector<Vec2>& nodes, const std::vector<Vec2>& centres) {
      return nodes.size() == nn && centres.size() == nb;
    };
    // (a moving mesh has taken a step: its velocity and node history are known)
    bool ok = fits(s.nodes, s.centres) && s.hist_nodes.size() == s.hist_t.size() &&
              s.hist_centres.size() == s.hist_t.size() && s.mesh_w.size() == nn;
    for (std::size_t k = 0; ok && k < s.hist_nodes.size(); ++k)
      ok = fits(s.hist_nodes[k], s.hist_centres[k]);
    if (s.factorized)
      ok = ok && fits(s.factor_nodes, s.factor_centres) &&
           (s.factor_w.empty() || s.factor_w.size() == nn);
    REQUIRE(ok, "fluid_fem state of a moving mesh of another size (expected {} nodes, {} bodies)",
            nn, nb);
  }
  if (!s.body_load.empty()) body_load_ = s.body_load;
  moving_ = s.moving;  // (before the factors: assemble() takes the ALE terms only when moving)
  if (s.factorized) {  // the same values in the same pattern give the same factors
    if (s.moving) place_mesh(s.factor_nodes, s.factor_centres, s.factor_w);
    x_ = s.factor_x;
    alpha0_ = s.factor_alpha0;
    assemble(true, s.factor_newton);
    lu_.factorize(values_.data());
    factor_x_ = s.factor_x;
    factor_alpha0_ = s.factor_alpha0;
    factor_newton_ = s.factor_newton;
    factor_nodes_ = s.factor_nodes;
    factor_centres_ = s.factor_centres;
    factor_w_ = s.factor_w;
  } else {  // as without factors: the next Newton solve factorises afresh
    factor_alpha0_ = -1.0;
    factor_newton_ = false;
    factor_x_.clear();
  }
  if (s.moving) {
    place_mesh(s.nodes, s.centres, s.mesh_w);
    hist_nodes_ = s.hist_nodes;
    hist_centres_ = s.hist_centres;
    base_nodes_ = s.nodes;  // (between steps the accepted state is where the mesh is)
    base_centres_ = s.centres;
  }
  hist_t_ = s.hist_t;
  hist_x_ = s.hist_x;
  last_order_ = s.last_order;
  alpha0_ = s.alpha0;
  hist_term_ = s.hist_term;
  set_time(s.t);
  // (after set_time: it imposes a free body's rigid velocity on its nodes exactly, where Newton
  // left it to rounding; a remesh interpolates those values)
  x_ = s.x;
  assemble(false, true);  // residual and reactions of the restored state, as after a solve
}

void NavierStokes::reject_step() {
  REQUIRE(!hist_t_.empty(), "reject_step without a step");
  x_ = hist_x_[0];
  if (moving_) {
    problem_.mesh.nodes = hist_nodes_[0];
    for (std::size_t j = 0; j < hist_centres_[0].size(); ++j)
      problem_.spec.bodies[j].centre = hist_centres_[0][j];
    precompute_geometry();
    locator_stale_ = true;
  }
  set_time(hist_t_[0]);
  x_ = hist_x_[0];  // (again: set_time imposes a free body's rigid velocity on its nodes exactly)
}

std::vector<BodyForce> NavierStokes::reaction_forces() const {
  std::vector<BodyForce> f(body_nodes_.size());
  for (std::size_t j = 0; j < body_nodes_.size(); ++j) {
    const Vec2 c = problem_.spec.bodies[j].centre;
    for (int v : body_nodes_[j]) {
      const double rx = -reaction_[v], ry = -reaction_[n2_ + v];
      const Vec2 p = problem_.mesh.nodes[v];
      f[j].force.x += rx;
      f[j].force.y += ry;
      f[j].torque += (p.x - c.x) * ry - (p.y - c.y) * rx;
    }
    // The Laplace form's reaction is the pseudo-traction (mu grad u - p I) n. For a rigid body
    // velocity on the surface, (grad u)^T n = omega t, whose moment is 2 omega A: add it back.
    f[j].torque -= 2.0 * problem_.density * problem_.viscosity *
                   body_velocity(static_cast<int>(j)).angular_velocity * body_area_[j];
  }
  return f;
}

std::vector<BodyForce> NavierStokes::stress_forces() const {
  const Mesh& m = problem_.mesh;
  std::vector<BodyForce> f(body_nodes_.size());
  const double mu = problem_.density * problem_.viscosity;
  const double gs[3] = {0.5 - std::sqrt(0.15), 0.5, 0.5 + std::sqrt(0.15)};
  const double gw[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
  for (const auto& e : m.boundary) {
    if (e.body < 0) continue;
    const auto x = cell_nodes(m, e.cell);
    const auto& cell = m.cells[e.cell];
    const Vec2 c = problem_.spec.bodies[e.body].centre;
    for (int q = 0; q < 3; ++q) {
      const double s = gs[q];
      double xi, eta, dxi_ds, deta_ds;
      if (e.local_edge == 0) {
        xi = s;
        eta = 0;
        dxi_ds = 1;
        deta_ds = 0;
      } else if (e.local_edge == 1) {
        xi = 1 - s;
        eta = s;
        dxi_ds = -1;
        deta_ds = 1;
      } else {
        xi = 0;
        eta = 1 - s;
        dxi_ds = 0;
        deta_ds = -1;
      }
      double phi[6], gx[6], gy[6], dxi[6], deta[6];
      p2::gradients(x, xi, eta, phi, gx, gy);
      p2::shape(xi, eta, phi, dxi, deta);
      double tx = 0, ty = 0, px = 0, py = 0;
      for (int k = 0; k < 6; ++k) {
        tx += x[k].x * (dxi[k] * dxi_ds + deta[k] * deta_ds);
        ty += x[k].y * (dxi[k] * dxi_ds + deta[k] * deta_ds);
        px += x[k].x * phi[k];
        py += x[k].y * phi[k];
      }
      double g00 = 0, g01 = 0, g10 = 0, g11 = 0;
      for (int k = 0; k < 6; ++k) {
        g00 += x_[cell[k]] * gx[k];
        g01 += x_[cell[k]] * gy[k];
        g10 += x_[n2_ + cell[k]] * gx[k];
        g11 += x_[n2_ + cell[k]] * gy[k];
      }
      const double l0 = 1 - xi - eta;
      const double p =
          x_[2 * n2_ + cell[0]] * l0 + x_[2 * n2_ + cell[1]] * xi + x_[2 * n2_ + cell[2]] * eta;
      // fluid on the left of the edge direction; body normal (into the fluid) = left normal
      const double nx = -ty, ny = tx;  // |t| ds_ref = ds, so n ds = (-ty, tx) ds_ref
      const double sxx = -p + 2 * mu * g00, syy = -p + 2 * mu * g11, sxy = mu * (g01 + g10);
      const double fx = gw[q] * (sxx * nx + sxy * ny), fy = gw[q] * (sxy * nx + syy * ny);
      f[e.body].force.x += fx;
      f[e.body].force.y += fy;
      f[e.body].torque += (px - c.x) * fy - (py - c.y) * fx;
    }
  }
  return f;
}

void NavierStokes::build_locator() const {
  locator_stale_ = false;
  const Mesh& m = problem_.mesh;
  Vec2 lo{1e300, 1e300}, hi{-1e300, -1e300};
  for (int v = 0; v < m.n_vertices; ++v) {
    lo = {std::min(lo.x, m.nodes[v].x), std::min(lo.y, m.nodes[v].y)};
    hi = {std::max(hi.x, m.nodes[v].x), std::max(hi.y, m.nodes[v].y)};
  }
  const double area = std::max((hi.x - lo.x) * (hi.y - lo.y), 1e-300);
  grid_h_ = std::sqrt(area / std::max(1, m.n_cells() / 2));
  grid_lo_ = lo;
  grid_nx_ = std::max(1, static_cast<int>(std::ceil((hi.x - lo.x) / grid_h_)));
  grid_ny_ = std::max(1, static_cast<int>(std::ceil((hi.y - lo.y) / grid_h_)));
  auto range = [&](int c, int& i0, int& i1, int& j0, int& j1) {
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (int k = 0; k < 3; ++k) {
      const Vec2 p = m.nodes[m.cells[c][k]];
      x0 = std::min(x0, p.x);
      x1 = std::max(x1, p.x);
      y0 = std::min(y0, p.y);
      y1 = std::max(y1, p.y);
    }
    i0 = std::clamp(static_cast<int>((x0 - lo.x) / grid_h_), 0, grid_nx_ - 1);
    i1 = std::clamp(static_cast<int>((x1 - lo.x) / grid_h_), 0, grid_nx_ - 1);
    j0 = std::clamp(static_cast<int>((y0 - lo.y) / grid_h_), 0, grid_ny_ - 1);
    j1 = std::clamp(static_cast<int>((y1 - lo.y) / grid_h_), 0, grid_ny_ - 1);
  };
  grid_start_.assign(static_cast<std::size_t>(grid_nx_) * grid_ny_ + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int> fill(grid_start_.begin(), grid_start_.end() - 1);
    for (int c = 0; c < m.n_cells(); ++c) {
      int i0, i1, j0, j1;
      range(c, i0, i1, j0, j1);
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
          const std::size_t b = static_cast<std::size_t>(j) * grid_nx_ + i;
          if (pass == 0)
            ++grid_start_[b + 1];
          else
            grid_cells_[fill[b]++] = c;
        }
    }
    if (pass == 0) {
      for (std::size_t b = 1; b < grid_start_.size(); ++b) grid_start_[b] += grid_start_[b - 1];
      grid_cells_.assign(grid_start_.back(), 0);
    }
  }
}

int NavierStokes::locate(Vec2 p, double& l1, double& l2) const {
  if (locator_stale_) build_locator();
  const Mesh& m = problem_.mesh;
  int best = -1;
  double best_out = std::numeric_limits<double>::infinity();
  auto test = [&](int c) {
    const Vec2 a = m.nodes[m.cells[c][0]], b = m.nodes[m.cells[c][1]], d = m.nodes[m.cells[c][2]];
    const double det = (b.x - a.x) * (d.y - a.y) - (d.x - a.x) * (b.y - a.y);
    const double s = ((p.x - a.x) * (d.y - a.y) - (d.x - a.x) * (p.y - a.y)) / det;
    const double t = ((b.x - a.x) * (p.y - a.y) - (p.x - a.x) * (b.y - a.y)) / det;
    const double out = std::max({-s, -t, s + t - 1.0});
    if (out < best_out) {
      best_out = out;
      best = c;
      l1 = s;
      l2 = t;
    }
    return out <= 0;
  };
  // search rings of buckets around p until a containing cell is found (or the grid is exhausted)
  const int ci = static_cast<int>(std::floor((p.x - grid_lo_.x) / grid_h_));
  const int cj = static_cast<int>(std::floor((p.y - grid_lo_.y) / grid_h_));
  const int max_ring = std::max(grid_nx_, grid_ny_) + 1;
  for (int ring = 0; ring <= max_ring; ++ring) {
    for (int j = cj - ring; j <= cj + ring; ++j)
      for (int i = ci - ring; i <= ci + ring; ++i) {
        if (std::max(std::abs(i - ci), std::abs(j - cj)) != ring) continue;
        if (i < 0 || j < 0 || i >= grid_nx_ || j >= grid_ny_) continue;
        const std::size_t b = static_cast<std::size_t>(j) * grid_nx_ + i;
        for (int k = grid_start_[b]; k < grid_start_[b + 1]; ++k)
          if (test(grid_cells_[k])) return best;
      }
    if (best >= 0 && ring >= 1) break;  // outside the mesh: nearest cell nearby, extrapolate
  }
  return best;
}

void NavierStokes::interpolate_from(const NavierStokes& other) {
  const Mesh& m = problem_.mesh;
  for (int k = 0; k < n2_; ++k) {
    const Vec2 u = other.velocity_at(m.nodes[k]);
    x_[k] = u.x;
    x_[n2_ + k] = u.y;
  }
  for (int v = 0; v < n1_; ++v) x_[2 * n2_ + v] = other.pressure_at(m.nodes[v]);
  apply_dirichlet_to_solution();
}

double NavierStokes::pressure_at(Vec2 p) const {
  double s = 0, t = 0;
  const int c = locate(p, s, t);
  const auto& cell = problem_.mesh.cells[c];
  return x_[2 * n2_ + cell[0]] * (1 - s - t) + x_[2 * n2_ + cell[1]] * s +
         x_[2 * n2_ + cell[2]] * t;
}

Vec2 NavierStokes::velocity_at(Vec2 p) const {
  double s = 0, t = 0;
  const int c = locate(p, s, t);
  const auto& cell = problem_.mesh.cells[c];
  double phi[6], dxi[6], deta[6];
  p2::shape(s, t, phi, dxi, deta);
  Vec2 u;
  for (int k = 0; k < 6; ++k) {
    u.x += x_[cell[k]] * phi[k];
    u.y += x_[n2_ + cell[k]] * phi[k];
  }
  return u;
}

NewtonReport solve_steady_nested(NavierStokes& ns, const NewtonOptions& opt, double coarsen) {
  FlowProblem coarse_pb = ns.problem();
  coarse_pb.spec.h_max *= coarsen;
  coarse_pb.spec.h_body *= coarsen;
  for (auto& b : coarse_pb.spec.boxes) b.h *= coarsen;
  // The coarse mesh only gives a first guess: where the geometry cannot be meshed that coarsely
  // (a gap that its curved cells would fold over), Newton starts from the given state instead.
  try {
    coarse_pb.mesh = build_mesh(coarse_pb.spec);
  } catch (const Error&) {
    return ns.solve_steady(opt);
  }
  NavierStokes coarse(std::move(coarse_pb));
  coarse.set_time(ns.time());
  NewtonOptions co = opt;
  co.tolerance = std::max(opt.tolerance, 1e-6);
  co.reuse_factorization = true;
  const NewtonReport cr = coarse.solve_steady(co);
  NewtonOptions fo = opt;
  fo.reuse_factorization = true;
  fo.picard_iterations = 0;
  if (cr.converged) ns.interpolate_from(coarse);
  NewtonReport r = ns.solve_steady(fo);
  r.factorizations += cr.factorizations;
  return r;
}

}  // namespace gf::fem
