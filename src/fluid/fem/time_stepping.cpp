// SPDX-License-Identifier: GPL-3.0-or-later
// Fixed / adaptive BDF time loop with step rejection on Newton failure or error estimate.
#include "fluid/fem/time_stepping.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace gf::fem {

TimeStats integrate(NavierStokes& ns, const TimeControl& tc, const NewtonOptions& opt,
                    const std::function<void(const NavierStokes&, double)>& observe) {
  REQUIRE(tc.order >= 1 && tc.order <= kMaxBdfOrder, "BDF order must be 1 to {}, got {}",
          kMaxBdfOrder, tc.order);
  REQUIRE(tc.dt > 0, "time step must be positive");
  TimeStats st;
  double dt = std::min(tc.dt, tc.dt_max);
  const double eps = 1e-12 * std::max(1.0, std::abs(tc.t_end));
  while (ns.time() < tc.t_end - eps && (tc.max_steps < 0 || st.steps < tc.max_steps)) {
    const double t = ns.time();
    double h = std::min(dt, tc.t_end - t);
    if (tc.t_end - t - h < 0.01 * h) h = tc.t_end - t;  // avoid a sliver step at the end
    const int order = std::min(tc.order, std::max(1, ns.available_order()));
    const StepResult r = ns.try_step(h, order, opt, tc.rtol, tc.atol);
    st.newton_iterations += r.newton.iterations;
    st.factorizations += r.newton.factorizations;
    if (!r.newton.converged) {
      ns.reject_step();
      ++st.rejected;
      dt = 0.25 * h;
      REQUIRE(dt >= tc.dt_min, "Newton failed at t = {} s even with step {} s", t, h);
      continue;
    }
    const double fac = r.error > 0 ? 0.9 * std::pow(r.error, -1.0 / (order + 1)) : 1.0;
    if (tc.adaptive && r.error > 1.0) {
      ns.reject_step();
      ++st.rejected;
      dt = h * std::max(0.2, fac);
      REQUIRE(dt >= tc.dt_min, "step size {} s below dt_min at t = {} s", dt, t);
      continue;
    }
    ns.accept_step();
    ++st.steps;
    if (observe) observe(ns, h);
    // Step growth bounded for zero-stability of variable-step BDF: ratios below 1 + sqrt(2)
    // for BDF2, about 1.5 for BDF3 (Calvo, Grande & Grigorieff, Numer. Math. 57, 1990).
    if (tc.adaptive) dt = std::min(tc.dt_max, h * std::clamp(fac, 0.2, order >= 3 ? 1.5 : 2.0));
  }
  return st;
}

}  // namespace gf::fem
