// SPDX-License-Identifier: GPL-3.0-or-later
// Moving-body scenarios shared by tests/fem/test_fem_moving.cpp and bench/fem/moving.cpp (which
// writes their time series for the validation plots of docs/validation/fem/).
#pragma once

#include <cmath>
#include <functional>
#include <numbers>
#include <utility>

#include "core/error.hpp"
#include "coupling/fem_dem/moving_bodies.hpp"
#include "fluid/fem/navier_stokes.hpp"

namespace gf::fem_bench {

using namespace gf::fem;

/// Faxen's drag per unit length on a cylinder of radius a moving at U parallel to two plane
/// walls, midway between them at distance l from each, in Stokes flow (Happel & Brenner, "Low
/// Reynolds number hydrodynamics", 1965, sec. 7-4; Faxen 1946): F / (mu U) = 4 pi / (ln(1/k) -
/// 0.9157 + 1.7244 k^2 - 1.7302 k^4 + 2.4056 k^6 - 4.5913 k^8), k = a / l. The series is
/// accurate to well below 1e-4 for k <= 0.3.
inline double faxen_resistance(double k) {
  const double k2 = k * k;
  return 4 * std::numbers::pi /
         (std::log(1 / k) - 0.9157 + 1.7244 * k2 - 1.7302 * k2 * k2 + 2.4056 * k2 * k2 * k2 -
          4.5913 * k2 * k2 * k2 * k2);
}

/// A disk of radius r1 at the origin inside a fixed circular wall of radius r2 (a 256-gon), the
/// fluid of density 1 and kinematic viscosity nu: the Taylor-Couette annulus.
inline FlowProblem annulus(double r1, double r2, double h_body, double h_max, double nu) {
  FlowProblem pb;
  for (int k = 0; k < 256; ++k) {
    const double a = 2 * std::numbers::pi * k / 256;
    pb.spec.outline.push_back({r2 * std::cos(a), r2 * std::sin(a)});
  }
  BodyShape c;
  c.radius = r1;
  pb.spec.bodies = {c};
  pb.spec.h_body = h_body;
  pb.spec.h_max = h_max;
  pb.mesh = build_mesh(pb.spec);
  pb.viscosity = nu;
  pb.outline_bc.assign(256, OutlineBc{});
  return pb;
}

/// A vertical channel |x| < l, -length/2 < y < length/2, walls at the sides and bottom and a
/// do-nothing outflow at the top (it fixes the pressure level), with a disk of radius a at
/// (0, y0).
inline FlowProblem vertical_channel(double l, double length, double a, double y0, double h_body,
                                    double h_max) {
  FlowProblem pb;
  const double y = 0.5 * length;
  pb.spec.outline = {{-l, -y}, {l, -y}, {l, y}, {-l, y}};
  BodyShape disk;
  disk.radius = a;
  disk.centre = {0, y0};
  pb.spec.bodies = {disk};
  pb.spec.h_body = h_body;
  pb.spec.h_max = h_max;
  pb.spec.grading = 0.3;
  pb.mesh = build_mesh(pb.spec);
  OutlineBc wall, out;
  out.kind = OutlineBcKind::Outflow;
  pb.outline_bc = {wall, wall, out, wall};
  pb.density = 1.0;
  pb.viscosity = 1.0;
  return pb;
}

/// Newton work of a run.
struct StepTotals {
  int steps = 0, iterations = 0, factorizations = 0;
};

/// Calls `each` after every step of a fixed-step BDF2 run of `run` to t_end.
inline StepTotals run_steps(fem_dem::MovingBodyFlow& run, double dt, double t_end,
                            const std::function<void(const fem_dem::MovingBodyFlow&)>& each = {}) {
  NewtonOptions newton;
  newton.reuse_factorization = true;
  newton.tolerance = 1e-10;
  StepTotals totals;
  const int n = static_cast<int>(std::lround(t_end / dt));
  for (int s = 0; s < n; ++s) {
    const StepResult r = run.step(dt, 2, newton);
    ++totals.steps;
    totals.iterations += r.newton.iterations;
    totals.factorizations += r.newton.factorizations;
    if (each) each(run);
  }
  return totals;
}

/// A body (disk of radius 0.1, or a square of side 0.2 tilted by `tilt`) of density 2 settling
/// in a closed box 1 x 1.5 of fluid (rho 1, nu 0.05) under g = 10, onto the floor, with a
/// repulsion of range 0.03 and F_0 = 4 x its buoyant weight; BDF2 with dt = 0.01 s. Calls
/// each(run) after every step and returns the flow after t_end (its Newton work in *totals).
inline fem_dem::MovingBodyFlow settle_on_floor(
    bool square, double tilt, double t_end,
    const std::function<void(const fem_dem::MovingBodyFlow&)>& each = {},
    StepTotals* totals = nullptr) {
  FlowProblem pb;
  pb.spec.outline = {{-0.5, 0}, {0.5, 0}, {0.5, 1.5}, {-0.5, 1.5}};
  BodyShape b;
  if (square) {
    b.kind = BodyShape::Kind::Polygon;
    const double c = std::cos(tilt), s = std::sin(tilt);
    for (const auto& [x, y] : {std::pair{-0.1, -0.1}, {0.1, -0.1}, {0.1, 0.1}, {-0.1, 0.1}})
      b.vertices.push_back({c * x - s * y, 0.4 + s * x + c * y});
    b.centre = {0, 0.4};
  } else {
    b.radius = 0.1;
    b.centre = {0, 0.4};
  }
  pb.spec.bodies = {b};
  pb.spec.h_body = 0.02;
  pb.spec.h_max = 0.1;
  pb.mesh = build_mesh(pb.spec);
  pb.outline_bc.assign(4, OutlineBc{});
  pb.viscosity = 0.05;
  pb.body_density = {2.0};
  pb.gravity = {0, -10};
  fem_dem::MovingBodyOptions opt;
  const double area = square ? 0.04 : std::numbers::pi * 0.01;
  opt.collision = {0.03, 4 * (2.0 - 1.0) * 10 * area};
  fem_dem::MovingBodyFlow run(std::move(pb), opt);
  const StepTotals t = run_steps(run, 0.01, t_end, each);
  if (totals) *totals = t;
  return run;
}

/// One free body of density 2 in the closed box 1 x 1.5 (floor y = 0) of a fluid of density 1,
/// meshed with h_body 0.02, h_max 0.1: the problem of square_on_slope and disk_on_tilting_floor.
inline FlowProblem floor_box(const BodyShape& body, double viscosity, Vec2 gravity,
                             const GravityTilt& tilt) {
  FlowProblem pb;
  pb.spec.outline = {{-0.5, 0}, {0.5, 0}, {0.5, 1.5}, {-0.5, 1.5}};
  pb.spec.bodies = {body};
  pb.spec.h_body = 0.02;
  pb.spec.h_max = 0.1;
  pb.mesh = build_mesh(pb.spec);
  pb.outline_bc.assign(4, OutlineBc{});
  pb.viscosity = viscosity;
  pb.body_density = {2.0};
  pb.gravity = gravity;
  pb.tilt = tilt;
  return pb;
}

/// The square of settle_on_floor (side 0.2, density 2, in fluid of density 1 and nu = 0.05 unless
/// given, the
/// box 1 x 1.5, repulsion range 0.03 and F_0 = 4 x its buoyant weight W = 0.4 N/m) resting flat
/// on the floor with gravity 10 m/s^2 tilted by atan(tan_slope) towards +x -- a slope seen from
/// its own frame -- and Coulomb friction mu on the repulsion's gaps (the default tangential
/// stiffness 2 F_0 / rho). It starts at rest at the gap where the two lower corners carry
/// W cos(slope) (F_0 s^2 = W cos / 2, gap = rho (1 - s)); BDF2 with dt = 0.01 s to t_end, calling
/// each(run) after every step (Newton work in *totals).
inline fem_dem::MovingBodyFlow square_on_slope(
    double tan_slope, double mu, double t_end,
    const std::function<void(const fem_dem::MovingBodyFlow&)>& each = {},
    StepTotals* totals = nullptr, double viscosity = 0.05, const GravityTilt& tilt = {}) {
  const double cos_s = 1 / std::sqrt(1 + tan_slope * tan_slope), sin_s = tan_slope * cos_s;
  const double range = 0.03, weight = (2.0 - 1.0) * 10 * 0.04;
  const double y0 = 0.1 + range * (1 - std::sqrt(cos_s / 8));
  BodyShape b;
  b.kind = BodyShape::Kind::Polygon;
  for (const auto& [x, y] : {std::pair{-0.1, -0.1}, {0.1, -0.1}, {0.1, 0.1}, {-0.1, 0.1}})
    b.vertices.push_back({x, y0 + y});
  b.centre = {0, y0};
  FlowProblem pb = floor_box(b, viscosity, {10 * sin_s, -10 * cos_s}, tilt);
  fem_dem::MovingBodyOptions opt;
  opt.collision = {range, 4 * weight, mu};
  fem_dem::MovingBodyFlow run(std::move(pb), opt);
  const StepTotals t = run_steps(run, 0.01, t_end, each);
  if (totals) *totals = t;
  return run;
}

/// A disk (radius 0.1, density 2) resting in its film on the floor of the slope's box (fluid
/// density 1, viscosity nu, g = 10, repulsion range 0.03, force 4 W, friction mu, rolling
/// friction mu_r), the domain tilting as `tilt` says; `each` after every step of 0.01 s to t_end.
inline fem_dem::MovingBodyFlow disk_on_tilting_floor(
    double mu, double mu_r, double t_end, const GravityTilt& tilt,
    const std::function<void(const fem_dem::MovingBodyFlow&)>& each = {},
    double viscosity = 0.005) {
  const double range = 0.03, weight = (2.0 - 1.0) * 10 * std::numbers::pi * 0.01;
  BodyShape b;
  b.radius = 0.1;
  b.centre = {0, 0.1 + range * 0.5};  // where 4 W (s)^2 = W: s = 1/2
  FlowProblem pb = floor_box(b, viscosity, {0, -10}, tilt);
  fem_dem::MovingBodyOptions opt;
  opt.collision = {range, 4 * weight, mu};
  opt.collision.rolling_friction = mu_r;
  fem_dem::MovingBodyFlow run(std::move(pb), opt);
  run_steps(run, 0.01, t_end, each);
  return run;
}

/// Upward force [N/m] of the fluid on a disk (radius 0.1) held at the origin of a channel of
/// half-width 0.5 whose walls slide upwards at U, fed from below with the uniform velocity U
/// (y from -2.5 to 4, outflow at the top; nu = 0.02): the steady flow around a disk settling
/// at U, seen from the disk.
inline double drag_in_body_frame(double u) {
  FlowProblem pb;
  pb.spec.outline = {{-0.5, -2.5}, {0.5, -2.5}, {0.5, 4.0}, {-0.5, 4.0}};
  BodyShape disk;
  disk.radius = 0.1;
  pb.spec.bodies = {disk};
  pb.spec.h_body = 0.02;
  pb.spec.h_max = 0.1;
  pb.mesh = build_mesh(pb.spec);
  OutlineBc side, in, out;
  side.wall_velocity = {0, u};
  in.kind = OutlineBcKind::Inflow;
  in.parabolic = false;
  in.u_max = u;
  out.kind = OutlineBcKind::Outflow;
  pb.outline_bc = {in, side, out, side};
  pb.viscosity = 0.02;
  NavierStokes ns(std::move(pb));
  NewtonOptions opt;
  opt.picard_iterations = 3;
  REQUIRE(solve_steady_nested(ns, opt).converged, "steady solve at U = {} did not converge", u);
  return ns.reaction_forces()[0].force.y;
}

/// Stokes settling: a disk (radius 0.1, density 1.5) from rest at y = 0.5 in the channel of
/// half-width 0.5 and length 5 (fluid density 1, nu = 1), g = 100.
inline fem_dem::MovingBodyFlow stokes_settling(const fem_dem::MovingBodyOptions& options,
                                               double h_body) {
  FlowProblem pb = vertical_channel(0.5, 5.0, 0.1, 0.5, h_body, 0.1);
  pb.body_density = {1.5};
  pb.gravity = {0, -100};
  return fem_dem::MovingBodyFlow(std::move(pb), options);
}

/// Settling at Re ~ 10: a disk (radius 0.1, density 1.5) from rest at y = 1.5 in the channel of
/// half-width 0.5 and length 6 (fluid density 1, nu = 0.02), g = 30.
inline fem_dem::MovingBodyFlow re10_settling() {
  FlowProblem pb = vertical_channel(0.5, 6.0, 0.1, 1.5, 0.02, 0.1);
  pb.viscosity = 0.02;
  pb.body_density = {1.5};
  pb.gravity = {0, -30};
  return fem_dem::MovingBodyFlow(std::move(pb));
}

/// The speed U* [m/s] at which drag_in_body_frame balances the buoyant weight of the disk of
/// re10_settling (secant iteration from 0.9 and 1.0 m/s).
inline double re10_terminal_speed() {
  const double weight = 0.5 * 30 * std::numbers::pi * 0.01;
  double u0 = 0.9, u1 = 1.0, f0 = drag_in_body_frame(u0) - weight,
         f1 = drag_in_body_frame(u1) - weight;
  for (int it = 0; it < 4 && std::abs(f1) > 1e-6 * weight; ++it) {
    const double u2 = u1 - f1 * (u1 - u0) / (f1 - f0);
    u0 = u1;
    f0 = f1;
    u1 = u2;
    f1 = drag_in_body_frame(u1) - weight;
  }
  return u1;
}

}  // namespace gf::fem_bench
