// SPDX-License-Identifier: GPL-3.0-or-later
// Fixed / adaptive BDF time loop with step rejection on Newton failure or error estimate.
#include "fluid/fem/time_stepping.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "core/stop.hpp"

namespace gf::fem {

namespace {

/// NavierStokes on its fixed mesh as a Stepper.
class FixedMesh final : public Stepper {
 public:
  explicit FixedMesh(NavierStokes& ns) : ns_(ns) {}
  [[nodiscard]] const NavierStokes& flow() const override { return ns_; }
  StepResult try_step(double dt, int order, const NewtonOptions& opt, double rtol, double atol,
                      bool neighbour_errors) override {
    return ns_.try_step(dt, order, opt, rtol, atol, neighbour_errors);
  }
  void accept_step() override { ns_.accept_step(); }
  void reject_step() override { ns_.reject_step(); }

 private:
  NavierStokes& ns_;
};

}  // namespace

TimeStats integrate(NavierStokes& ns, const TimeControl& tc, const NewtonOptions& opt,
                    const std::function<void(const NavierStokes&, double)>& observe,
                    TimeLoopState* loop) {
  FixedMesh s(ns);
  return integrate(s, tc, opt, observe, loop);
}

TimeStats integrate(Stepper& s, const TimeControl& tc, const NewtonOptions& opt,
                    const std::function<void(const NavierStokes&, double)>& observe,
                    TimeLoopState* loop) {
  REQUIRE(tc.order >= 1 && tc.order <= kMaxBdfOrder, "BDF order must be 1 to {}, got {}",
          kMaxBdfOrder, tc.order);
  REQUIRE(tc.dt > 0, "time step must be positive");
  REQUIRE(!tc.variable_order || tc.adaptive, "variable BDF order needs adaptive steps");
  TimeStats st;
  double dt = std::min(tc.dt, tc.dt_max);
  const double eps = 1e-12 * std::max(1.0, std::abs(tc.t_end));
  int order = tc.variable_order ? 1 : tc.order;  // the order aimed at
  int same_order_steps = 0, error_rejections = 0;
  const double dt_config = dt;
  // The smallest step a failed Newton solve may be retried with: time.adaptive.dt_min, and for
  // fixed steps five quarterings of the step asked for (1/1024 of it). Fixed steps cut to get
  // past a hard stretch grow back to the step asked for (x2, x1.5 at BDF3, per accepted step
  // whose Newton solve needed at most half its iterations); they used to stay cut for the rest of
  // the run, down to 1e-9 s, so that a run that could not take its step crawled on instead of
  // failing.
  const double dt_floor = tc.adaptive ? tc.dt_min : std::max(tc.dt_min, dt_config / 1024.0);
  if (loop && loop->dt > 0) {  // continue a run (checkpoint)
    // The controller's step, unless the case now asks for another initial / fixed step.
    if (loop->dt_config == dt_config) dt = loop->dt;
    order = std::clamp(loop->order, 1, tc.order);
    same_order_steps = loop->same_order_steps;
    error_rejections = loop->error_rejections;
  }
  auto keep_state = [&] {
    if (loop) *loop = {dt, dt_config, order, same_order_steps, error_rejections};
  };
  // Step factor 0.9 err^{-1/(k+1)} that would bring an error estimate err of order k to 0.9^(k+1).
  // An estimate of exactly zero (a flow at rest, data that are polynomials of low degree in t)
  // allows any step: the growth limits below then apply.
  auto factor = [](double err, int k) {
    return err > 0 ? 0.9 * std::pow(err, -1.0 / (k + 1)) : std::numeric_limits<double>::infinity();
  };
  while (s.flow().time() < tc.t_end - eps && (tc.max_steps < 0 || st.steps < tc.max_steps)) {
    if ((st.stop_signal = stop::requested())) break;
    const double t = s.flow().time();
    double h = std::min(dt, tc.t_end - t);
    if (tc.t_end - t - h < 0.01 * h) h = tc.t_end - t;  // avoid a sliver step at the end
    const int asked = std::min(order, std::max(1, s.flow().available_order()));
    const bool choose = tc.variable_order && asked == order && same_order_steps >= asked + 1;
    const StepResult r = s.try_step(h, asked, opt, tc.rtol, tc.atol, choose);
    // (a moving flow that meshed again restarts its BDF history: a lower order)
    const int k = r.newton.converged ? s.flow().last_order() : asked;
    st.newton_iterations += r.newton.iterations;
    st.factorizations += r.newton.factorizations;
    if (!r.newton.converged) {
      s.reject_step();
      ++st.rejected;
      // A quarter of the step, but the floor itself is tried before giving up.
      if (h <= dt_floor * (1.0 + 1e-9))
        throw StepFailure(fmt::format(
            "{} on the step from t = {} s even with the step cut to {:.3g} s "
            "(the smallest step allowed is {:.3g} s): {}",
            r.failure.empty() ? "Newton's method failed" : "the step failed", t, h, dt_floor,
            !r.failure.empty() ? r.failure
            : std::isfinite(r.newton.last_update)
                ? fmt::format("no convergence in {} iterations (last relative update {:.3g})",
                              r.newton.iterations, r.newton.last_update)
                : std::string("the velocity or pressure became non-finite")));
      dt = std::max(0.25 * h, dt_floor);
      continue;
    }
    // (no estimate: hold the step)
    double fac = r.error < 0 ? 1.0 : factor(r.error, k);
    if (tc.adaptive && r.error > 1.0) {
      s.reject_step();
      ++st.rejected;
      if (tc.variable_order && ++error_rejections >= 2 && order > 1) {
        --order;
        same_order_steps = 0;
        error_rejections = 0;
      }
      dt = h * std::max(0.2, fac);
      if (dt < tc.dt_min)
        throw StepFailure(
            fmt::format("the error estimate asks for a step of {:.3g} s from t = {} s, below "
                        "time.adaptive.dt_min = {:.3g} s",
                        dt, t, tc.dt_min));
      continue;
    }
    error_rejections = 0;
    s.accept_step();
    ++st.steps;
    ++st.steps_at_order[k];
    ++same_order_steps;
    if (choose) {
      int next = k;
      if (r.error_lower >= 0 && factor(r.error_lower, k - 1) >= fac) {
        next = k - 1;
        fac = factor(r.error_lower, k - 1);
      }
      if (k < tc.order && r.error_higher >= 0 && factor(2 * r.error_higher, k + 1) > fac) {
        next = k + 1;
        fac = factor(2 * r.error_higher, k + 1);
      }
      if (next != order) {
        order = next;
        same_order_steps = 0;
      }
    }
    // Step growth bounded for zero-stability of variable-step BDF: ratios below 1 + sqrt(2)
    // for BDF2, about 1.5 for BDF3 (Calvo, Grande & Grigorieff, Numer. Math. 57, 1990).
    if (tc.adaptive)
      dt = std::min(tc.dt_max, h * std::clamp(fac, 0.2, order >= 3 ? 1.5 : 2.0));
    else if (dt < dt_config && 2 * r.newton.iterations <= opt.max_iterations)
      // (only after a step whose Newton solve converged with room to spare: one that needed
      // most of its iterations would fail again at twice the step, and the step would swing
      // between cut and grown, one attempt in three rejected)
      dt = std::min(dt_config, dt * (order >= 3 ? 1.5 : 2.0));
    keep_state();  // the observer may checkpoint: the controller is ready for the next step
    if (observe) observe(s.flow(), h);
  }
  keep_state();
  return st;
}

}  // namespace gf::fem
