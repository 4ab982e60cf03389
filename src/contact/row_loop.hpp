// SPDX-License-Identifier: GPL-3.0-or-later
// The threaded loop over the rows of a half Verlet list, shared by the sphere and the
// non-spherical force loops.
#pragma once

#include <array>
#include <cstdint>

#include "core/exec.hpp"
#include "neighbor/verlet_list.hpp"

namespace gf::contact {

/// Runs row(i) for every particle i: slab by slab in phases (slabs of one phase never write to
/// the same particles, so they run on different threads without atomics), in the same order
/// whatever the thread count, so the forces are bit-identical with 1 or N threads.
template <class Row>
std::int64_t for_rows_in_slabs(const VerletList& list, Row&& row) {
  const auto slabs = list.slab_starts();
  const std::int64_t n = static_cast<std::int64_t>(list.n_particles());
  if (list.n_slabs() <= 1) {
    std::int64_t touching = 0;
    for (std::int64_t i = 0; i < n; ++i) touching += row(i);
    return touching;
  }
  const int n_phases = list.n_phases();
  std::int64_t touching = 0;
  // At most 1024 cell layers (CellList caps the grid), so the counts fit on the stack.
  std::array<std::int64_t, 1025> per_slab{};
  // Small systems stay on one thread (same order, so the same bits): a parallel region costs
  // more than a step of a few thousand particles.
  const bool threaded = n >= 8192 && exec::n_threads() > 1;
  for (int phase = 0; phase < n_phases; ++phase) {
    const std::int64_t count = (list.n_slabs() - phase + n_phases - 1) / n_phases;
    auto slab = [&](exec::index_t k) {
      const auto s = static_cast<std::size_t>(phase + k * n_phases);
      std::int64_t t = 0;
      for (std::int64_t i = slabs[s]; i < slabs[s + 1]; ++i) t += row(i);
      per_slab[s] = t;
    };
    if (threaded) {
      exec::parallel_for_dynamic(count, slab);
    } else {
      for (exec::index_t k = 0; k < count; ++k) slab(k);
    }
  }
  for (auto t : per_slab) touching += t;
  return touching;
}

}  // namespace gf::contact
