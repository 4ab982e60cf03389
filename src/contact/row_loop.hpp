// SPDX-License-Identifier: GPL-3.0-or-later
// The threaded loop over the rows of a half Verlet list, shared by the sphere and the
// non-spherical force loops.
#pragma once

#include <array>
#include <cstdint>

#include "core/exec.hpp"
#include "neighbor/verlet_list.hpp"

namespace gf::contact {

/// Runs slab(begin, end) over consecutive ranges of rows covering every particle: slab by slab
/// in phases (slabs of one phase never write to the same particles, so they run on different
/// threads without atomics), in the same order whatever the thread count, so the forces are
/// bit-identical with 1 or N threads. slab returns the number of touching pairs of its rows.
template <class Slab>
std::int64_t for_slab_ranges(const VerletList& list, Slab&& slab) {
  const auto slabs = list.slab_starts();
  const std::int64_t n = static_cast<std::int64_t>(list.n_particles());
  if (list.n_slabs() <= 1) return slab(std::int64_t{0}, n);
  const int n_phases = list.n_phases();
  std::int64_t touching = 0;
  // At most 1024 cell layers (CellList caps the grid), so the counts fit on the stack.
  std::array<std::int64_t, 1025> per_slab{};
  // Small systems stay on one thread (same order, so the same bits): a parallel region costs
  // more than a step of a few thousand particles.
  const bool threaded = n >= 8192 && exec::n_threads() > 1;
  for (int phase = 0; phase < n_phases; ++phase) {
    const std::int64_t count = (list.n_slabs() - phase + n_phases - 1) / n_phases;
    auto one = [&](exec::index_t k) {
      const auto s = static_cast<std::size_t>(phase + k * n_phases);
      per_slab[s] = slab(slabs[s], slabs[s + 1]);
    };
    if (threaded) {
      exec::parallel_for_dynamic(count, one);
    } else {
      for (exec::index_t k = 0; k < count; ++k) one(k);
    }
  }
  for (auto t : per_slab) touching += t;
  return touching;
}

/// Runs row(i) for every particle i (see for_slab_ranges); row returns its touching pairs.
template <class Row>
std::int64_t for_rows_in_slabs(const VerletList& list, Row&& row) {
  return for_slab_ranges(list, [&](std::int64_t begin, std::int64_t end) {
    std::int64_t t = 0;
    for (std::int64_t i = begin; i < end; ++i) t += row(i);
    return t;
  });
}

}  // namespace gf::contact
