// SPDX-License-Identifier: GPL-3.0-or-later
// Loops of the Gear predictor-corrector kernels over bodies, run through core/exec.
#include "integrators/gear5.hpp"

#include "core/exec.hpp"

namespace gf {

void gear5_predict(std::size_t n, Gear5State* s, double dt) {
  exec::parallel_for(static_cast<exec::index_t>(n),
                     [&](exec::index_t i) { gear5_predict(s[i], dt); });
}

void gear5_correct(std::size_t n, Gear5State* s, const Vec3* force, const double* mass, double dt,
                   const Gear5Coefficients& c) {
  exec::parallel_for(static_cast<exec::index_t>(n), [&](exec::index_t i) {
    gear5_correct(s[i], (1.0 / mass[i]) * force[i], dt, c);
  });
}

}  // namespace gf
