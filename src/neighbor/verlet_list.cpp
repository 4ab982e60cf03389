// SPDX-License-Identifier: GPL-3.0-or-later
// Verlet list build from the cell list (threaded, two passes), skin criterion, slabs, and
// history transfer through re-orderings.
#include "neighbor/verlet_list.hpp"

#include <algorithm>
#include <bit>
#include <numeric>

#include "core/error.hpp"
#include "core/exec.hpp"

namespace gf {

namespace {

/// Frees a vector's memory (`v = {}` would pick the initializer-list assignment, which empties
/// the vector but keeps its capacity).
template <class V>
void release(V& v) {
  V().swap(v);
}

}  // namespace

std::span<const std::int64_t> VerletList::sort_and_build(ParticleStore& p, const Domain& domain,
                                                         double skin, const PairFilter& filter,
                                                         std::span<const std::int64_t> previous) {
  const std::size_t n = p.size();
  // (the first build has no previous list: nothing to carry, whatever was removed before it)
  const bool first = offsets_.empty();
  const std::size_t n_before = previous.empty() || first ? n : n_particles();
  REQUIRE(n < (std::size_t{1} << 31), "{} particles exceed the 32-bit neighbour index", n);
  REQUIRE(previous.empty() || previous.size() == n, "{} previous indices for {} particles",
          previous.size(), n);
  double r_max = 0;
  for (std::size_t i = 0; i < n; ++i) r_max = std::max(r_max, p.radius()[i]);
  cells_.build(domain, p.x(), n, 2 * r_max + skin);
  const auto& order = cells_.order();
  perm_.assign(order.begin(), order.end());
  p.permute(perm_);
  build_rows(domain, p.x(), p.radius(), n, skin, true, filter);
  if (!previous.empty() && !first) {
    // (build_rows reads perm_ as store indices; from here on it names the previous build's)
    for (auto& k : perm_) {
      k = previous[static_cast<std::size_t>(k)];  // -1: a grain new since then
      REQUIRE(k >= -1 && k < static_cast<std::int64_t>(n_before),
              "previous index {} outside the {} particles of the last build", k, n_before);
    }
  }
  carry_history(perm_, n_before);
  x_ref_.assign(p.x(), p.x() + n);

  // Slabs: cell layers across the slab axis. With a periodic slab axis the first and the last
  // slab interact, so three phases are used and the slab count must be a multiple of 3.
  const int layers = cells_.n_layers();
  const bool periodic = domain.periodic[static_cast<std::size_t>(cells_.slab_axis())];
  int n_slabs = periodic ? 3 * (layers / 3) : layers;
  n_phases_ = periodic ? 3 : 2;
  if (n_slabs < n_phases_) {
    n_slabs = 1;
    n_phases_ = 1;
  }
  slab_starts_.assign(static_cast<std::size_t>(n_slabs) + 1, static_cast<std::int64_t>(n));
  const int per_layer = cells_.cells_per_layer();
  for (int s = 0; s < n_slabs; ++s) {
    const int first_layer =
        static_cast<int>((static_cast<std::int64_t>(s) * layers + n_slabs - 1) / n_slabs);
    slab_starts_[static_cast<std::size_t>(s)] = cells_.begin(first_layer * per_layer);
  }
  slab_starts_[0] = 0;
  return perm_;
}

void VerletList::build(const Domain& domain, const Vec3* x, const double* r, std::size_t n,
                       double skin, const PairFilter& filter) {
  REQUIRE(n < (std::size_t{1} << 31), "{} particles exceed the 32-bit neighbour index", n);
  double r_max = 0;
  for (std::size_t i = 0; i < n; ++i) r_max = std::max(r_max, r[i]);
  cells_.build(domain, x, n, 2 * r_max + skin);
  build_rows(domain, x, r, n, skin, false, filter);
  perm_.resize(n);
  std::iota(perm_.begin(), perm_.end(), std::int64_t{0});
  carry_history(perm_, n);
  x_ref_.assign(x, x + n);
  slab_starts_.clear();
  n_phases_ = 1;
}

void VerletList::build_rows(const Domain& domain, const Vec3* x, const double* r, std::size_t n,
                            double skin, bool sorted, const PairFilter& filter) {
  skin_ = skin;
  // The reference positions are dead during a rebuild: freed here, set again once the old
  // histories are gone (24 bytes per particle less at the rebuild's peak).
  release(x_ref_);
  keep_old_histories();
  const auto& order = cells_.order();
  // In a sorted store the members of a cell are a contiguous index range.
  auto member = [&](std::int64_t k) {
    return sorted ? static_cast<std::int32_t>(k) : order[static_cast<std::size_t>(k)];
  };
  auto cell_of = [&](std::size_t i) {
    return sorted ? cells_.cell_of_particle(static_cast<std::size_t>(perm_[i]))
                  : cells_.cell_of_particle(i);
  };
  // Visits the neighbours j > i of i in ascending order when sorted (stencil cells ascending).
  // `memo` keeps the stencil of the last cell visited: in a sorted store the rows of one cell
  // follow each other, so a cell's stencil is found once, not once per grain.
  auto for_neighbours = [&](std::size_t i, StencilMemo& memo, auto&& emit) {
    const int c = cell_of(i);
    if (c != memo.cell) {
      memo.n = cells_.stencil(c, memo.cells);  // ascending
      memo.cell = c;
    }
    const Vec3 xi = x[i];
    const double ri = r[i] + skin;
    const auto first_j = static_cast<std::int64_t>(i) + 1;
    for (int s = 0; s < memo.n; ++s) {
      const std::int64_t end = cells_.begin(memo.cells[s] + 1);
      // Sorted: the members are the index range itself, so j > i starts at i + 1.
      for (std::int64_t k = sorted ? std::max(cells_.begin(memo.cells[s]), first_j)
                                   : cells_.begin(memo.cells[s]);
           k < end; ++k) {
        const std::int32_t j = member(k);
        if (!sorted && static_cast<std::size_t>(j) <= i) continue;
        const double cut = ri + r[j];
        if (norm2(domain.delta(xi, x[j])) < cut * cut &&
            (!filter || filter(static_cast<std::int32_t>(i), j)))
          emit(j);
      }
    }
  };
  build_rows_in_chunks(n, sorted, for_neighbours);
  shear_offset_ref_ = domain.shear_offset;
  refs_follow_wraps_ = follow_wraps_;
  ++n_builds_;
}

template <class ForNeighbours>
void VerletList::build_rows_in_chunks(std::size_t n, bool sorted, ForNeighbours& for_neighbours) {
  // One pass keeps each row in a buffer per chunk of rows, then the rows are copied into the
  // exact-size array (no growth slack: memory per particle is one of issue 3's figures). A
  // count-then-fill pair of passes would search every stencil twice, and with a filter (the
  // capsules' axis test, a narrow phase) test every candidate twice. The buffers (at most
  // 8 bytes per pair with their growth) are gone before the histories (24 bytes per pair) are
  // allocated, so the rebuild's peak is unchanged.
  const auto total_rows = static_cast<exec::index_t>(n);
  const exec::index_t n_chunks =
      exec::threaded(total_rows) ? static_cast<exec::index_t>(8 * exec::n_threads()) : 1;
  const exec::index_t rows_per_chunk =
      (total_rows + n_chunks - 1) / std::max<exec::index_t>(n_chunks, 1);
  std::vector<std::vector<std::int32_t>> chunk_rows(static_cast<std::size_t>(n_chunks));
  offsets_.assign(n + 1, 0);
  exec::parallel_for_dynamic(n_chunks, [&](exec::index_t c) {
    auto& buf = chunk_rows[static_cast<std::size_t>(c)];
    const exec::index_t first = c * rows_per_chunk;
    const exec::index_t last = std::min(total_rows, first + rows_per_chunk);
    StencilMemo memo;
    for (exec::index_t i = first; i < last; ++i) {
      const std::size_t begin = buf.size();
      for_neighbours(static_cast<std::size_t>(i), memo, [&](std::int32_t j) { buf.push_back(j); });
      if (!sorted) std::sort(buf.begin() + static_cast<std::ptrdiff_t>(begin), buf.end());
      offsets_[static_cast<std::size_t>(i) + 1] = static_cast<std::int64_t>(buf.size() - begin);
    }
  });
  for (std::size_t i = 0; i < n; ++i) offsets_[i + 1] += offsets_[i];
  neighbors_ = std::vector<std::int32_t>(static_cast<std::size_t>(offsets_[n]));
  exec::parallel_for_dynamic(n_chunks, [&](exec::index_t c) {
    auto& buf = chunk_rows[static_cast<std::size_t>(c)];
    const exec::index_t first = std::min(total_rows, c * rows_per_chunk);
    std::copy(buf.begin(), buf.end(),
              neighbors_.begin() + offsets_[static_cast<std::size_t>(first)]);
    release(buf);
  });
}

void VerletList::keep_old_histories() {
  // Compacts the current list in place to its entries with a non-zero history (touching pairs,
  // about half of the entries in a dense bed) and frees the rest before the new list is built:
  // the peak memory of a rebuild is then the new list plus the old contacts, not two lists.
  // A missing entry and a zero history carry the same thing, so results are unchanged.
  const std::size_t n = n_particles();
  std::int64_t w = 0;
  for (std::size_t a = 0; a < n; ++a) {
    const std::int64_t first = offsets_[a], last = offsets_[a + 1];
    offsets_[a] = w;
    for (std::int64_t k = first; k < last; ++k) {
      const auto ks = static_cast<std::size_t>(k);
      const Vec3& h = history_[ks];
      // Bitwise zero (a -0.0 component is kept, so the carried values are exactly the old ones).
      if ((std::bit_cast<std::uint64_t>(h.x) | std::bit_cast<std::uint64_t>(h.y) |
           std::bit_cast<std::uint64_t>(h.z)) == 0)
        continue;
      neighbors_[static_cast<std::size_t>(w)] = neighbors_[ks];
      history_[static_cast<std::size_t>(w)] = history_[ks];
      ++w;
    }
  }
  if (n > 0) offsets_[n] = w;
  const auto kept = static_cast<std::ptrdiff_t>(w);
  old_offsets_ = std::move(offsets_);
  old_neighbors_.assign(neighbors_.begin(), neighbors_.begin() + kept);
  old_history_.assign(history_.begin(), history_.begin() + kept);
  release(offsets_);
  release(neighbors_);
  release(history_);
}

void VerletList::carry_history(std::span<const std::int64_t> perm, std::size_t n_before) {
  const std::size_t n = n_particles();
  history_ = std::vector<Vec3>(neighbors_.size());
  if (old_offsets_.size() != n_before + 1) {  // first build, or an unexplained count change
    release(old_offsets_);
    release(old_neighbors_);
    release(old_history_);
    return;
  }
  exec::parallel_for(static_cast<exec::index_t>(n), [&](exec::index_t ii) {
    const auto i = static_cast<std::size_t>(ii);
    const std::int64_t oi = perm[i];
    if (oi < 0) return;  // a new grain: no history yet
    for (std::int64_t k = offsets_[i]; k < offsets_[i + 1]; ++k) {
      const std::int64_t oj =
          perm[static_cast<std::size_t>(neighbors_[static_cast<std::size_t>(k)])];
      if (oj < 0) continue;
      // The old list stored the pair in the row of its smaller (old) index.
      const std::int64_t a = std::min(oi, oj), b = std::max(oi, oj);
      const auto first = old_neighbors_.begin() + old_offsets_[static_cast<std::size_t>(a)];
      const auto last = old_neighbors_.begin() + old_offsets_[static_cast<std::size_t>(a) + 1];
      const auto it = std::lower_bound(first, last, static_cast<std::int32_t>(b));
      if (it == last || *it != b) continue;
      const Vec3 h = old_history_[static_cast<std::size_t>(it - old_neighbors_.begin())];
      // History is the displacement of the row particle relative to the other one.
      history_[static_cast<std::size_t>(k)] = oi < oj ? h : -h;
    }
  });
  release(old_offsets_);
  release(old_neighbors_);
  release(old_history_);
}

bool VerletList::needs_rebuild(const Domain& domain, const Vec3* x, std::size_t n) const {
  if (x_ref_.size() != n) return true;
  const double lim = displacement_limit(domain);
  if (lim <= 0) return true;
  const double lim2 = lim * lim;
  const Vec3* const ref = x_ref_.data();
  const bool periodic = domain.any_periodic();
  // Blocks of particles with one test per block (the largest squared displacement): no
  // branch per particle, and the minimum image only in periodic domains. Blocks are small so
  // that parallel_any still threads from ~130k particles on (it threads above 4096 items).
  constexpr std::size_t block = 32;
  const auto n_blocks = static_cast<exec::index_t>((n + block - 1) / block);
  return exec::parallel_any(n_blocks, [&](exec::index_t b) {
    const std::size_t first = static_cast<std::size_t>(b) * block;
    const std::size_t last = std::min(n, first + block);
    double d2max = 0;
    if (periodic) {
      for (std::size_t i = first; i < last; ++i)
        d2max = std::max(d2max, norm2(domain.delta(x[i], ref[i])));
    } else {
      for (std::size_t i = first; i < last; ++i) d2max = std::max(d2max, norm2(x[i] - ref[i]));
    }
    return d2max > lim2;
  });
}

void VerletList::restore(std::vector<std::int64_t> offsets, std::vector<std::int32_t> neighbors,
                         std::vector<Vec3> history, std::vector<Vec3> x_ref, double skin,
                         std::int64_t n_builds, std::vector<std::int64_t> slab_starts,
                         int n_phases) {
  REQUIRE(!offsets.empty() && static_cast<std::size_t>(offsets.back()) == neighbors.size() &&
              history.size() == neighbors.size() && x_ref.size() + 1 == offsets.size(),
          "inconsistent neighbour list in checkpoint");
  REQUIRE(n_phases >= 1 && n_phases <= 3, "inconsistent slab phases in checkpoint");
  offsets_ = std::move(offsets);
  neighbors_ = std::move(neighbors);
  history_ = std::move(history);
  x_ref_ = std::move(x_ref);
  refs_follow_wraps_ = false;  // (unless the checkpoint says so: set_refs_follow_wraps)
  skin_ = skin;
  n_builds_ = n_builds;
  slab_starts_ = std::move(slab_starts);
  n_phases_ = n_phases;
}

std::size_t VerletList::bytes() const {
  return offsets_.capacity() * 8 + neighbors_.capacity() * 4 + history_.capacity() * sizeof(Vec3) +
         x_ref_.capacity() * sizeof(Vec3) + old_offsets_.capacity() * 8 +
         old_neighbors_.capacity() * 4 + old_history_.capacity() * sizeof(Vec3) +
         perm_.capacity() * 8 + slab_starts_.capacity() * 8;
}

}  // namespace gf
