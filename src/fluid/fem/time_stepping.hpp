// SPDX-License-Identifier: GPL-3.0-or-later
// Time loop over NavierStokes::try_step: fixed or adaptive BDF1/BDF2/BDF3 steps with rejection.
//
// Variable-step BDF2 (e.g. Hairer & Wanner, Solving ODEs II, sec. III.5): with omega =
// dt_n/dt_{n-1},
//   du/dt(t_{n+1}) ~ [(1+2 omega) u_{n+1} - (1+omega)^2 u_n + omega^2 u_{n-1}] / ((1+omega) dt_n).
// Local error estimated from the difference to the extrapolating predictor (Milne's device),
// on the velocities only (the pressure is an algebraic variable); the step is chosen as
// dt_new = dt 0.9 err^{-1/(k+1)}, limited so that omega <= 2 (BDF2 zero-stability needs < 2.414;
// BDF3: omega <= 1.5). BDF3 is the same construction one degree higher (NavierStokes::try_step).
//
// Variable order (TimeControl::variable_order, as DASSL / CVODE do it): start with BDF1; after
// k + 1 steps at order k, the error estimates that orders k - 1 and k + 1 would have had on the
// step just taken (divided differences of orders k and k + 2 through the newest states) give
// each order's next step, dt 0.9 err_j^{-1/(j+1)}; the order with the largest step is taken,
// one order at a time, a raise judged on twice its estimated error (the difference of order
// k + 2 is the least reliable), a lowering already on a tie. Two error rejections in a row
// lower the order.
#pragma once

#include <array>
#include <functional>
#include <limits>

#include "core/error.hpp"
#include "fluid/fem/navier_stokes.hpp"

namespace gf::fem {

struct TimeControl {
  int order = 2;  ///< 1 (implicit Euler), 2 (BDF2) or 3 (BDF3); the highest with variable_order
  bool variable_order = false;      ///< choose the order 1 ... order by the error estimates
                                    ///< (needs adaptive)
  double dt = 1e-2;                 ///< (initial) step [s]
  double t_end = 1.0;               ///< [s]
  bool adaptive = false;            ///< error control on velocities
  double rtol = 1e-3, atol = 1e-4;  ///< relative [-], absolute [m/s] velocity tolerances
  double dt_min = 1e-9;             ///< [s]; a smaller step needed is an error
  double dt_max = std::numeric_limits<double>::infinity();  ///< [s]
  int max_steps = -1;  ///< stop after this many accepted steps (< 0: no limit)
};

struct TimeStats {
  int steps = 0, rejected = 0, newton_iterations = 0, factorizations = 0;
  std::array<int, kMaxBdfOrder + 1> steps_at_order{};  ///< accepted steps by order (index 1-3)
  int stop_signal = 0;  ///< SIGINT / SIGTERM / time limit that ended the loop (core/stop.hpp)
};

/// The step controller between two steps: with NavierStokes::State, what a checkpoint keeps.
struct TimeLoopState {
  double dt = 0.0;         ///< [s] the next step to try; 0 before the first step (tc.dt is used)
  double dt_config = 0.0;  ///< [s] min(tc.dt, tc.dt_max) of the run that left this state
  int order = 0;           ///< the BDF order aimed at
  int same_order_steps = 0, error_rejections = 0;
};

/// The time loop cannot go on: Newton's method failed (its iterate not finite, or not
/// converging) or the error estimate stayed too large even at the smallest step allowed
/// (TimeControl::dt_min). The solver is left at the last accepted step.
class StepFailure : public Error {
 public:
  using Error::Error;
};

/// What integrate() advances: tentative steps of a flow solver, each then accepted or rejected.
/// NavierStokes on its fixed mesh (integrate(NavierStokes&, ...) wraps it), or a flow whose
/// bodies move with it (FemMovingFlow, fluid/fem/case.hpp).
class Stepper {
 public:
  virtual ~Stepper() = default;
  /// The flow solver as it is now (at the new time after a tentative step).
  [[nodiscard]] virtual const NavierStokes& flow() const = 0;
  /// A tentative step, as NavierStokes::try_step. A step that cannot be taken at this size for
  /// another reason than Newton's method (e.g. the mesh cannot follow the bodies) returns
  /// newton.converged = false with StepResult::failure saying why.
  virtual StepResult try_step(double dt, int order, const NewtonOptions& opt, double rtol,
                              double atol, bool neighbour_errors) = 0;
  virtual void accept_step() = 0;
  virtual void reject_step() = 0;
};

/// Integrates the stepper from its flow's time to tc.t_end, as integrate(NavierStokes&, ...)
/// below does (the steps' BDF order is the one the flow reports having used: lower than asked
/// for after a moving flow meshed again).
TimeStats integrate(Stepper& s, const TimeControl& tc, const NewtonOptions& opt,
                    const std::function<void(const NavierStokes&, double dt)>& observe,
                    TimeLoopState* loop = nullptr);

/// Integrates from ns.time() to tc.t_end; calls observe after every accepted step (when *loop,
/// if given, already holds the controller's choice for the next step); a step whose Newton solve
/// fails is retried with a quarter of the step, down to tc.dt_min (fixed steps: also at least
/// 1/1024 of tc.dt; they grow back to tc.dt after), else StepFailure is thrown. Ends early,
/// after a step, when SIGINT / SIGTERM asked the program to stop (TimeStats::stop_signal).
/// With `loop`, the controller starts from *loop (unless its dt is 0) and leaves its state there.
TimeStats integrate(NavierStokes& ns, const TimeControl& tc, const NewtonOptions& opt,
                    const std::function<void(const NavierStokes&, double dt)>& observe,
                    TimeLoopState* loop = nullptr);

}  // namespace gf::fem
