// SPDX-License-Identifier: GPL-3.0-or-later
// Verlet list build from the cell list, skin criterion, and history transfer.
#include "neighbor/verlet_list.hpp"

#include <algorithm>

#include "core/error.hpp"

namespace gf {

void VerletList::build(const Domain& domain, const Vec3* x, const double* r, std::size_t n, double skin) {
  REQUIRE(n < (std::size_t{1} << 31), "{} particles exceed the 32-bit neighbour index", n);
  skin_ = skin;
  double r_max = 0;
  for (std::size_t i = 0; i < n; ++i) r_max = std::max(r_max, r[i]);
  const double cutoff = 2 * r_max + skin;
  cells_.build(domain, x, n, cutoff);

  // Keep the old list for the history transfer.
  const bool had_list = n_particles() == n;
  old_offsets_.swap(offsets_);
  old_neighbors_.swap(neighbors_);
  old_history_.swap(history_);

  offsets_.assign(n + 1, 0);
  neighbors_.clear();
  int stencil[27];
  const auto& order = cells_.order();
  for (std::size_t i = 0; i < n; ++i) {
    const int c = cells_.cell_of(x[i]);
    const int ns = cells_.stencil(c, stencil);
    const std::size_t first = neighbors_.size();
    for (int s = 0; s < ns; ++s) {
      const int cc = stencil[s];
      for (std::int64_t k = cells_.begin(cc); k < cells_.begin(cc + 1); ++k) {
        const std::int32_t j = order[static_cast<std::size_t>(k)];
        if (static_cast<std::size_t>(j) <= i) continue;
        const Vec3 d = domain.delta(x[i], x[j]);
        const double cut = r[i] + r[j] + skin;
        if (norm2(d) < cut * cut) neighbors_.push_back(j);
      }
    }
    // Sorted neighbours: deterministic force summation order and fast history lookup.
    std::sort(neighbors_.begin() + static_cast<std::ptrdiff_t>(first), neighbors_.end());
    offsets_[i + 1] = static_cast<std::int64_t>(neighbors_.size());
  }

  history_.assign(neighbors_.size(), Vec3{});
  if (had_list) {
    for (std::size_t i = 0; i < n; ++i) {
      std::int64_t o = old_offsets_[i];
      const std::int64_t o_end = old_offsets_[i + 1];
      for (std::int64_t k = offsets_[i]; k < offsets_[i + 1] && o < o_end; ++k) {
        const std::int32_t j = neighbors_[k];
        while (o < o_end && old_neighbors_[o] < j) ++o;
        if (o < o_end && old_neighbors_[o] == j) history_[k] = old_history_[o];
      }
    }
  }
  x_ref_.assign(x, x + n);
  ++n_builds_;
}

bool VerletList::needs_rebuild(const Domain& domain, const Vec3* x, std::size_t n) const {
  if (x_ref_.size() != n) return true;
  const double lim2 = 0.25 * skin_ * skin_;
  for (std::size_t i = 0; i < n; ++i)
    if (norm2(domain.delta(x[i], x_ref_[i])) > lim2) return true;
  return false;
}

void VerletList::restore(std::vector<std::int64_t> offsets, std::vector<std::int32_t> neighbors,
                         std::vector<Vec3> history, std::vector<Vec3> x_ref, double skin, std::int64_t n_builds) {
  REQUIRE(!offsets.empty() && static_cast<std::size_t>(offsets.back()) == neighbors.size() &&
              history.size() == neighbors.size() && x_ref.size() + 1 == offsets.size(),
          "inconsistent neighbour list in checkpoint");
  offsets_ = std::move(offsets);
  neighbors_ = std::move(neighbors);
  history_ = std::move(history);
  x_ref_ = std::move(x_ref);
  skin_ = skin;
  n_builds_ = n_builds;
}

std::size_t VerletList::bytes() const {
  return offsets_.capacity() * 8 + neighbors_.capacity() * 4 + history_.capacity() * sizeof(Vec3) +
         x_ref_.capacity() * sizeof(Vec3) + old_offsets_.capacity() * 8 + old_neighbors_.capacity() * 4 +
         old_history_.capacity() * sizeof(Vec3);
}

}  // namespace gf
