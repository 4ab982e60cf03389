// SPDX-License-Identifier: GPL-3.0-or-later
// Execution back ends: the only place that owns loops over particles (serial or OpenMP).
#pragma once

#include <cstddef>
#include <cstdint>

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace gf::exec {

using index_t = std::int64_t;

/// Number of threads the loops below use.
inline int n_threads() {
#if defined(_OPENMP)
  return omp_get_max_threads();
#else
  return 1;
#endif
}

/// Sets the number of threads (n <= 0 keeps the OMP_NUM_THREADS / runtime default).
inline void set_threads(int n) {
#if defined(_OPENMP)
  if (n > 0) omp_set_num_threads(n);
#else
  (void)n;
#endif
}

inline int thread_id() {
#if defined(_OPENMP)
  return omp_get_thread_num();
#else
  return 0;
#endif
}

/// Loops of at most this many iterations run serially: a parallel region costs a few
/// microseconds even when its `if` clause is false (libgomp starts a team of one and wakes its
/// barrier with a futex system call: 5-6 us each, measured), which on small grids was ~10 % of
/// a two-fluid step.
inline constexpr index_t kMinParallel = 4096;

/// True if a loop of n iterations (at least min_parallel) should start a parallel region.
inline bool threaded(index_t n, index_t min_parallel = kMinParallel) {
  return n > min_parallel && n_threads() > 1;
}

/// f(i) for i in [0, n); iterations must be independent.
template <class F>
void parallel_for(index_t n, F&& f) {
#if defined(_OPENMP)
  if (threaded(n)) {
#pragma omp parallel for schedule(static)
    for (index_t i = 0; i < n; ++i) f(i);
    return;
  }
#endif
  for (index_t i = 0; i < n; ++i) f(i);
}

/// f(i) for i in [0, n) with dynamic scheduling (uneven work per iteration, e.g. slabs of
/// particles); iterations must be independent. Threaded when n > 1.
template <class F>
void parallel_for_dynamic(index_t n, F&& f) {
#if defined(_OPENMP)
  if (threaded(n, 1)) {
#pragma omp parallel for schedule(dynamic, 1)
    for (index_t i = 0; i < n; ++i) f(i);
    return;
  }
#endif
  for (index_t i = 0; i < n; ++i) f(i);
}

/// True if pred(i) holds for some i in [0, n).
template <class P>
bool parallel_any(index_t n, P&& pred) {
  bool any = false;
#if defined(_OPENMP)
  if (threaded(n)) {
#pragma omp parallel for schedule(static) reduction(|| : any)
    for (index_t i = 0; i < n; ++i) any = any || pred(i);
    return any;
  }
#endif
  for (index_t i = 0; i < n && !any; ++i) any = pred(i);
  return any;
}

/// Largest of init and f(i) over [0, n) (exact whatever the thread count).
template <class F>
double parallel_max(index_t n, double init, F&& f) {
#if defined(_OPENMP)
  if (threaded(n)) {
#pragma omp parallel for schedule(static) reduction(max : init)
    for (index_t i = 0; i < n; ++i) {
      const double v = f(i);
      init = v > init ? v : init;
    }
    return init;
  }
#endif
  for (index_t i = 0; i < n; ++i) {
    const double v = f(i);
    init = v > init ? v : init;
  }
  return init;
}

/// Sum of f(i) over [0, n), with a deterministic order for a given thread count; threaded when
/// n > min_parallel (iterations that are themselves chunks of work take a smaller threshold).
template <class T, class F>
T parallel_sum(index_t n, T init, F&& f, index_t min_parallel = kMinParallel) {
#if defined(_OPENMP)
  const int nt = threaded(n, min_parallel) ? omp_get_max_threads() : 1;
  if (nt == 1) {
    for (index_t i = 0; i < n; ++i) init += f(i);
    return init;
  }
  T partial[256];
  for (int t = 0; t < nt && t < 256; ++t) partial[t] = T{};
#pragma omp parallel num_threads(nt)
  {
    const int t = omp_get_thread_num();
    T acc{};
#pragma omp for schedule(static)
    for (index_t i = 0; i < n; ++i) acc += f(i);
    partial[t] = acc;
  }
  for (int t = 0; t < nt; ++t) init += partial[t];
  return init;
#else
  for (index_t i = 0; i < n; ++i) init += f(i);
  return init;
#endif
}

}  // namespace gf::exec
