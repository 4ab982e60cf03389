// SPDX-License-Identifier: GPL-3.0-or-later
// Bodies moving through a 2D fluid_fem flow: harmonic mesh motion, quality check, remeshing.
#include "coupling/fem_dem/moving_bodies.hpp"

#include <fmt/format.h>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/error.hpp"
#include "core/log.hpp"

namespace gf::fem_dem {

namespace {

Vec2 rigid_map(const RigidPose& from, const RigidPose& to, Vec2 p) {
  const double a = to.angle - from.angle;
  const double c = std::cos(a), s = std::sin(a);
  const double dx = p.x - from.centre.x, dy = p.y - from.centre.y;
  return {to.centre.x + c * dx - s * dy, to.centre.y + s * dx + c * dy};
}

}  // namespace

double shape_quality(Vec2 a, Vec2 b, Vec2 c) {
  const double area = 0.5 * ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
  const auto sq = [](Vec2 p, Vec2 q) {
    return (p.x - q.x) * (p.x - q.x) + (p.y - q.y) * (p.y - q.y);
  };
  const double l2 = sq(a, b) + sq(b, c) + sq(c, a);
  return l2 > 0 ? 4.0 * std::sqrt(3.0) * area / l2 : 0.0;
}

std::vector<double> qualities(const fem::Mesh& mesh) {
  std::vector<double> q;
  q.reserve(mesh.cells.size());
  const auto& n = mesh.nodes;
  for (const auto& c : mesh.cells) q.push_back(shape_quality(n[c[0]], n[c[1]], n[c[2]]));
  return q;
}

MeshMotion::MeshMotion(const fem::Mesh& mesh, int n_bodies) : ref_nodes_(mesh.nodes) {
  const int nv = mesh.n_vertices;
  // Dirichlet vertices: -1 interior, 0 outline, 1 + b on body b
  std::vector<int> tag(nv, -1);
  for (const auto& e : mesh.boundary)
    for (int v : {e.a, e.b}) tag[v] = e.body >= 0 ? 1 + e.body : std::max(tag[v], 0);
  std::vector<int> interior(nv, -1);
  int n_in = 0;
  for (int v = 0; v < nv; ++v)
    if (tag[v] < 0) interior[v] = n_in++;
  // P1 stiffness on the straight triangles, split into interior-interior and interior-boundary
  std::vector<Eigen::Triplet<double>> kii;
  std::vector<std::vector<std::pair<int, double>>> kib(n_in);  // (boundary vertex, value)
  for (const auto& cell : mesh.cells) {
    const Vec2 p[3] = {mesh.nodes[cell[0]], mesh.nodes[cell[1]], mesh.nodes[cell[2]]};
    const double det =
        (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
    double gx[3], gy[3];
    for (int k = 0; k < 3; ++k) {
      const Vec2 q = p[(k + 1) % 3], r = p[(k + 2) % 3];
      gx[k] = (q.y - r.y) / det;
      gy[k] = (r.x - q.x) / det;
    }
    const double area = 0.5 * std::abs(det);
    for (int a = 0; a < 3; ++a) {
      const int ia = interior[cell[a]];
      if (ia < 0) continue;
      for (int b = 0; b < 3; ++b) {
        const double kab = area * (gx[a] * gx[b] + gy[a] * gy[b]);
        const int ib = interior[cell[b]];
        if (ib >= 0)
          kii.emplace_back(ia, ib, kab);
        else
          kib[ia].emplace_back(cell[b], kab);
      }
    }
  }
  Eigen::SparseMatrix<double> k(n_in, n_in);
  k.setFromTriplets(kii.begin(), kii.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  if (n_in > 0) {
    ldlt.compute(k);
    REQUIRE(ldlt.info() == Eigen::Success,
            "mesh motion: the Laplace matrix is not positive definite");
  }
  w_.assign(n_bodies, std::vector<double>(mesh.n_nodes(), 0.0));
  for (int b = 0; b < n_bodies; ++b) {
    auto& w = w_[b];
    for (int v = 0; v < nv; ++v)
      if (tag[v] == 1 + b) w[v] = 1.0;
    if (n_in > 0) {
      Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n_in);
      for (int i = 0; i < n_in; ++i)
        for (const auto& [v, kv] : kib[i]) rhs[i] -= kv * w[v];
      const Eigen::VectorXd x = ldlt.solve(rhs);
      for (int v = 0; v < nv; ++v)
        if (interior[v] >= 0) w[v] = x[interior[v]];
    }
    // midpoint nodes: the mean of their edge's ends (1 on the body, its curved edges included)
    for (const auto& cell : mesh.cells)
      for (int e = 0; e < 3; ++e) w[cell[3 + e]] = 0.5 * (w[cell[e]] + w[cell[(e + 1) % 3]]);
  }
}

std::vector<Vec2> MeshMotion::nodes(const std::vector<RigidPose>& reference,
                                    const std::vector<RigidPose>& now) const {
  std::vector<Vec2> x = ref_nodes_;
  for (std::size_t b = 0; b < w_.size(); ++b) {
    const double da = now[b].angle - reference[b].angle;
    const bool still = da == 0 && now[b].centre.x == reference[b].centre.x &&
                       now[b].centre.y == reference[b].centre.y;
    if (still) continue;
    for (std::size_t k = 0; k < x.size(); ++k) {
      const double w = w_[b][k];
      if (w == 0) continue;
      const Vec2 t = rigid_map(reference[b], now[b], ref_nodes_[k]);
      x[k].x += w * (t.x - ref_nodes_[k].x);
      x[k].y += w * (t.y - ref_nodes_[k].y);
    }
  }
  return x;
}

MovingBodyFlow::MovingBodyFlow(fem::FlowProblem problem, MovingBodyOptions options)
    : options_(options) {
  flow_ = std::make_unique<fem::NavierStokes>(std::move(problem));
  reference_spec_ = flow_->problem().spec;  // free polygons' centres are their centroids now
  for (const auto& b : reference_spec_.bodies) poses_.push_back({b.centre, 0.0});
  reference_poses_ = poses_;
  contact_loads_.resize(poses_.size());
  start_mesh();
}

void MovingBodyFlow::start_mesh() {
  motion_ = std::make_unique<MeshMotion>(flow_->mesh(), static_cast<int>(poses_.size()));
  reference_quality_ = qualities(flow_->mesh());
}

std::vector<RigidPose> MovingBodyFlow::predicted_poses(double dt) const {
  std::vector<RigidPose> p = poses_;
  for (std::size_t b = 0; b < p.size(); ++b) {
    const fem::BodyMotion v = flow_->body_velocity(static_cast<int>(b));
    fem::BodyMotion u = v;  // second-order Adams-Bashforth with variable steps
    if (previous_dt_ > 0 && !previous_velocity_.empty()) {
      const double r = dt / (2.0 * previous_dt_);
      const auto& o = previous_velocity_[b];
      u.velocity = {(1 + r) * v.velocity.x - r * o.velocity.x,
                    (1 + r) * v.velocity.y - r * o.velocity.y};
      u.angular_velocity = (1 + r) * v.angular_velocity - r * o.angular_velocity;
    }
    p[b].centre.x += dt * u.velocity.x;
    p[b].centre.y += dt * u.velocity.y;
    p[b].angle += dt * u.angular_velocity;
  }
  return p;
}

double MovingBodyFlow::quality_ratio(const std::vector<Vec2>& nodes, double& worst) const {
  double ratio = 1e300;
  worst = 1e300;
  const auto& cells = flow_->mesh().cells;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const double q = shape_quality(nodes[cells[c][0]], nodes[cells[c][1]], nodes[cells[c][2]]);
    worst = std::min(worst, q);
    ratio = std::min(ratio, q / reference_quality_[c]);
  }
  return ratio;
}

void MovingBodyFlow::set_external_load(int body, Vec2 force, double torque) {
  REQUIRE(flow_->is_free(body), "an external load acts on a free body only (body {} is not)", body);
  external_.resize(poses_.size());
  external_[body] = fem::BodyForce{force, torque};
}

fem::MeshSpec MovingBodyFlow::placed_spec(const std::vector<RigidPose>& poses) const {
  fem::MeshSpec spec = reference_spec_;
  for (std::size_t b = 0; b < poses.size(); ++b) {
    auto& body = spec.bodies[b];
    for (auto& v : body.vertices) v = rigid_map(reference_poses_[b], poses[b], v);
    body.centre = poses[b].centre;
  }
  return spec;
}

void MovingBodyFlow::remesh() {
  const auto start = std::chrono::steady_clock::now();
  fem::FlowProblem pb = flow_->problem();
  pb.spec = placed_spec(poses_);
  for (std::size_t b = 0; b < poses_.size(); ++b)
    pb.body_motion[b] = flow_->body_velocity(static_cast<int>(b));
  // The bodies are where the run put them, so a failure to mesh them is the run's, not the
  // input's: worded as a run error with the time and the narrowest gap.
  try {
    pb.mesh = fem::build_mesh(pb.spec);
  } catch (const InputError& e) {
    throw Error(fmt::format(
        "at t = {} s: the domain could not be meshed again around the bodies where they are "
        "(narrowest gap {}; a repulsion range of a few cells keeps them apart): {}",
        flow_->time(), describe(fem_dem::narrowest_gap(pb.spec)), e.what()));
  }
  auto next = std::make_unique<fem::NavierStokes>(std::move(pb));
  next->set_time(flow_->time());
  next->interpolate_from(*flow_);
  flow_ = std::move(next);
  reference_spec_ = flow_->problem().spec;
  reference_poses_ = poses_;
  start_mesh();
  ++remeshes_;
  remesh_seconds_ +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<RigidPose> MovingBodyFlow::mesh_poses(const std::vector<RigidPose>& poses) const {
  // A circle is the same set whatever its angle: its mesh translates only (the fluid slips
  // along the mesh there, which the ALE form allows), so a spinning disk needs no remeshing.
  std::vector<RigidPose> p = poses;
  for (std::size_t b = 0; b < p.size(); ++b)
    if (reference_spec_.bodies[b].kind == fem::BodyShape::Kind::Circle)
      p[b].angle = reference_poses_[b].angle;
  return p;
}

fem::StepResult MovingBodyFlow::step(double dt, int order, const fem::NewtonOptions& newton) {
  fem::StepResult r = try_step(dt, order, newton);
  if (!r.newton.converged) {
    reject_step();
    throw Error(!r.failure.empty()
                    ? r.failure
                    : fmt::format("at t = {} s: Newton did not converge in {} iterations (last "
                                  "update {:.3g}) in the step of {} s: lower the time step",
                                  flow_->time(), r.newton.iterations, r.newton.last_update, dt));
  }
  accept_step();
  return r;
}

fem::StepResult MovingBodyFlow::try_step(double dt, int order, const fem::NewtonOptions& newton,
                                         double rtol, double atol, bool neighbour_errors) {
  REQUIRE(!pending_, "MovingBodyFlow::try_step: the last step was neither accepted nor rejected");
  try {
    return try_step_or_throw(dt, order, newton, rtol, atol, neighbour_errors);
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {  // the mesh could not follow: the flow is where it was
    fem::StepResult r;
    r.failure = e.what();
    return r;
  }
}

fem::StepResult MovingBodyFlow::try_step_or_throw(double dt, int order,
                                                  const fem::NewtonOptions& newton, double rtol,
                                                  double atol, bool neighbour_errors) {
  std::vector<RigidPose> next = predicted_poses(dt);
  std::vector<Vec2> nodes = motion_->nodes(reference_poses_, mesh_poses(next));
  double worst = 0;
  if (quality_ratio(nodes, worst) < options_.remesh_ratio || worst < options_.remesh_quality) {
    remesh();
    nodes = motion_->nodes(reference_poses_, mesh_poses(next));
    const double ratio = quality_ratio(nodes, worst);
    if (!(worst > 0))  // (the narrowest gap: a film thinner than a cell inverts at any step)
      throw Error(fmt::format(
          "at t = {} s: a body moves farther in one step of {} s than the mesh next to it can "
          "follow (a fresh mesh inverts; quality ratio {:.3g}; narrowest gap {}, mesh size at "
          "the bodies {:.3g} m): lower the time step, or, where the gap is far below the mesh "
          "size, widen it (a larger repulsion force or range)",
          flow_->time(), dt, ratio, describe(fem_dem::narrowest_gap(placed_spec(poses_))),
          reference_spec_.h_body));
  }
  std::vector<fem::BodyMotion> velocity;
  for (std::size_t b = 0; b < poses_.size(); ++b)
    velocity.push_back(flow_->body_velocity(static_cast<int>(b)));
  // loads of the step: the caller's external ones plus the contacts' (repulsion and friction)
  // at the step's end poses, friction springs stretched by the step's displacement (with the
  // start's velocities instead, BDF2 amplifies a resting contact's oscillation: 2 % per step at
  // 20 steps per period); set on every step, so a new solver after a remesh has them too
  std::vector<fem::BodyForce> loads = external_;
  loads.resize(poses_.size());
  std::vector<fem::BodyForce> contact(poses_.size());
  ContactHistory history;  // the gaps' springs after this step, kept once it is accepted
  if (options_.collision.range > 0 && options_.collision.friction > 0) {
    std::vector<fem::BodyMotion> moved(poses_.size());
    for (std::size_t b = 0; b < poses_.size(); ++b) {
      moved[b].velocity = {(next[b].centre.x - poses_[b].centre.x) / dt,
                           (next[b].centre.y - poses_[b].centre.y) / dt};
      moved[b].angular_velocity = (next[b].angle - poses_[b].angle) / dt;
    }
    contact = collision_loads(placed_spec(next), options_.collision, moved, dt, history_, history);
  } else if (options_.collision.range > 0) {
    contact = collision_loads(placed_spec(next), options_.collision);
  }
  for (std::size_t b = 0; b < loads.size(); ++b) {
    loads[b].force.x += contact[b].force.x;
    loads[b].force.y += contact[b].force.y;
    loads[b].torque += contact[b].torque;
    if (flow_->is_free(static_cast<int>(b)))
      flow_->set_body_load(static_cast<int>(b), loads[b].force, loads[b].torque);
  }
  NarrowGap gap;
  if (options_.collision.range > 0) gap = fem_dem::narrowest_gap(placed_spec(next));
  std::vector<Vec2> centres;
  for (const auto& p : next) centres.push_back(p.centre);
  flow_->move_mesh(nodes, centres);
  // The error estimate of order k needs k + 1 known states: after a remesh (and at the start)
  // the history is shorter, and the step carries no estimate (error -1: the controller holds
  // the step instead of reading 0 as a flow at rest and growing it).
  const int known = std::max(1, flow_->available_order());
  const int k = std::clamp(order, 1, std::min(fem::kMaxBdfOrder, known));
  fem::StepResult r;
  try {
    r = flow_->try_step(dt, order, newton, rtol, atol, neighbour_errors);
  } catch (...) {
    flow_->reject_step();  // (moves the mesh back)
    throw;
  }
  if (known < k + 1) r.error = -1.0;
  pending_ = true;
  pending_poses_ = std::move(next);
  pending_history_ = std::move(history);
  pending_contact_ = std::move(contact);
  pending_velocity_ = std::move(velocity);
  pending_dt_ = dt;
  pending_gap_ = gap;
  return r;
}

void MovingBodyFlow::accept_step() {
  REQUIRE(pending_, "MovingBodyFlow::accept_step without a step");
  flow_->accept_step();
  poses_ = std::move(pending_poses_);
  if (options_.collision.friction > 0) history_ = std::move(pending_history_);
  contact_loads_ = std::move(pending_contact_);
  previous_velocity_ = std::move(pending_velocity_);
  previous_dt_ = pending_dt_;
  gap_ = pending_gap_;
  pending_ = false;
  watch_gap();
}

std::string MovingBodyFlow::describe(const NarrowGap& gap) const {
  const auto name = [this](int b) {
    return b < static_cast<int>(options_.body_names.size())
               ? fmt::format("'{}'", options_.body_names[b])
               : fmt::format("body {}", b);
  };
  if (gap.body < 0) return "none (no bodies)";
  return fmt::format(
      "{:.3g} m, between {} and {}", gap.g, name(gap.body),
      gap.other >= 0 ? name(gap.other) : fmt::format("the outline's edge {}", gap.edge));
}

void MovingBodyFlow::watch_gap() {
  // Without a core the law is bounded: a film far inside the range carries nearly F_0, the most
  // it can. With one, the force grows as the film thins, and a film deep in the core carries
  // many F_0 in a gap that needs cells and steps as small.
  const auto& model = options_.collision;
  const double scale = model.core > 0 ? model.core : model.range;
  const double f = options_.gap_warning;
  if (!(model.range > 0 && f > 0) || gap_.body < 0) return;
  if (gap_.g > 2.0 * f * scale) {  // the film opened again: warn anew when it next thins
    warned_gap_ = std::numeric_limits<double>::infinity();
    return;
  }
  // (an overlap, g <= 0, is said once until the film opens again)
  if (!(gap_.g < f * scale && gap_.g < 0.5 * warned_gap_) || warned_gap_ <= 0) return;
  warned_gap_ = gap_.g;
  ++gap_warnings_;
  log::warn(
      "at t = {:.6g} s the narrowest film is {} ({:.2g} % of the repulsion's {}): a film this "
      "thin pushes with up to {:.3g} x the force scale {:.3g} N/m{}. Raise "
      "moving_mesh.repulsion.force{}; grainflow check gives the step that then needs",
      flow_->time(), describe(gap_), 100.0 * gap_.g / scale, model.core > 0 ? "core" : "range",
      repulsion_scale(model, gap_.g), model.force,
      model.core > 0 ? " (at most 100 x, at 1 % of the core): so thin a film needs as small "
                       "cells and steps, and a larger load closes it"
                     : ", nearly the most it can: a larger load closes the film, and the mesh "
                       "then fails",
      model.core > 0 ? "" : ", or give it a core (moving_mesh.repulsion.core)");
}

void MovingBodyFlow::reject_step() {
  if (!pending_) return;  // (a step that failed before solving left the flow as it was)
  flow_->reject_step();
  pending_ = false;
}

namespace {

void put_poses(const std::vector<RigidPose>& p, std::vector<double>& out) {
  for (const auto& q : p) out.insert(out.end(), {q.centre.x, q.centre.y, q.angle});
}

std::vector<RigidPose> take_poses(const std::vector<double>& v) {
  std::vector<RigidPose> p;
  for (std::size_t i = 0; i + 2 < v.size(); i += 3) p.push_back({{v[i], v[i + 1]}, v[i + 2]});
  return p;
}

void put_loads(const std::vector<fem::BodyForce>& f, std::vector<double>& out) {
  for (const auto& l : f) out.insert(out.end(), {l.force.x, l.force.y, l.torque});
}

std::vector<fem::BodyForce> take_loads(const std::vector<double>& v) {
  std::vector<fem::BodyForce> f;
  for (std::size_t i = 0; i + 2 < v.size(); i += 3) f.push_back({{v[i], v[i + 1]}, v[i + 2]});
  return f;
}

}  // namespace

fem::MovingFlowState MovingBodyFlow::state() const {
  REQUIRE(!pending_, "MovingBodyFlow::state between try_step and accept_step / reject_step");
  fem::MovingFlowState s;
  s.reference_bodies = reference_spec_.bodies;
  s.body_density = flow_->problem().body_density;
  s.body_density.resize(poses_.size(), 0.0);  // (an empty list: all prescribed)
  s.reference_mesh = flow_->mesh();
  s.reference_mesh.nodes = motion_->reference_nodes();
  put_poses(reference_poses_, s.reference_poses);
  put_poses(poses_, s.poses);
  for (const auto& v : previous_velocity_)
    s.previous_velocity.insert(s.previous_velocity.end(),
                               {v.velocity.x, v.velocity.y, v.angular_velocity});
  s.previous_dt = previous_dt_;
  put_loads(external_, s.external_loads);
  put_loads(contact_loads_, s.contact_loads);
  for (const auto& [k, springs] : history_.entries()) {
    s.history_keys.push_back(k);
    s.history_stretch.push_back(springs.slide);
    s.history_roll.push_back(springs.roll);
  }
  s.remeshes = remeshes_;
  s.remesh_seconds = remesh_seconds_;
  return s;
}

void MovingBodyFlow::restore(const fem::NavierStokes::State& flow, const fem::MovingFlowState& s) {
  const std::size_t nb = poses_.size();
  auto per_body = [nb](const std::vector<double>& v, bool may_be_empty) {
    return v.size() == 3 * nb || (may_be_empty && v.empty());
  };
  bool same = s.reference_bodies.size() == nb && per_body(s.reference_poses, false) &&
              per_body(s.poses, false) && per_body(s.previous_velocity, true) &&
              per_body(s.external_loads, true) && per_body(s.contact_loads, false);
  for (std::size_t b = 0; same && b < nb; ++b) {
    same = s.body_density.size() == nb &&
           s.body_density[b] ==
               (flow_->is_free(static_cast<int>(b)) ? flow_->problem().body_density[b] : 0.0);
    const auto& now = reference_spec_.bodies[b];
    const auto& then = s.reference_bodies[b];
    same = same && now.kind == then.kind && now.radius == then.radius &&
           now.vertices.size() == then.vertices.size();
  }
  for (const auto& e : s.reference_mesh.boundary)
    same = same && e.outline_edge < static_cast<int>(reference_spec_.outline.size());
  REQUIRE(same,
          "moving-body state of another problem ({} bodies, expected {} of these shapes and "
          "densities)",
          s.reference_bodies.size(), nb);
  for (std::size_t b = 0; b < nb && !s.external_loads.empty(); ++b)
    REQUIRE(flow_->is_free(static_cast<int>(b)) ||
                (s.external_loads[3 * b] == 0 && s.external_loads[3 * b + 1] == 0 &&
                 s.external_loads[3 * b + 2] == 0),
            "moving-body state: a load on body {}, which is not free here", b);
  // The solver on the mesh as it was built around the bodies where they were then; the state
  // then moves its nodes to where they are.
  fem::FlowProblem pb = flow_->problem();
  pb.spec.bodies = s.reference_bodies;
  pb.mesh = s.reference_mesh;
  auto next = std::make_unique<fem::NavierStokes>(std::move(pb));
  fem::MeshSpec spec = next->problem().spec;  // (restore moves the centres)
  auto motion = std::make_unique<MeshMotion>(next->mesh(), static_cast<int>(nb));
  next->restore(flow);
  flow_ = std::move(next);
  reference_spec_ = std::move(spec);
  motion_ = std::move(motion);
  reference_quality_ = qualities(s.reference_mesh);
  reference_poses_ = take_poses(s.reference_poses);
  poses_ = take_poses(s.poses);
  previous_velocity_.clear();
  for (std::size_t i = 0; i < s.previous_velocity.size(); i += 3)
    previous_velocity_.push_back(
        {{s.previous_velocity[i], s.previous_velocity[i + 1]}, s.previous_velocity[i + 2]});
  previous_dt_ = s.previous_dt;
  external_ = take_loads(s.external_loads);
  contact_loads_ = take_loads(s.contact_loads);
  history_ = ContactHistory::from_entries(
      s.history_keys, s.history_stretch,
      s.history_roll.empty() ? std::vector<double>(s.history_keys.size(), 0.0) : s.history_roll);
  remeshes_ = static_cast<int>(s.remeshes);
  remesh_seconds_ = s.remesh_seconds;
  gap_ = options_.collision.range > 0 ? fem_dem::narrowest_gap(placed_spec(poses_)) : NarrowGap{};
  warned_gap_ = std::numeric_limits<double>::infinity();
  pending_ = false;
}

}  // namespace gf::fem_dem
