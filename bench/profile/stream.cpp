// SPDX-License-Identifier: GPL-3.0-or-later
// STREAM-like memory-bandwidth probe (copy, triad, read-only sum) at several working-set sizes,
// with 1..T OpenMP threads, plus a scalar double FMA-throughput probe (the core's flop rate
// for code that does not vectorise). Built by build.sh, not part of the CMake build.
// Usage: stream [max_threads] [sizes_MiB...]   (default: 2 threads; 1 8 64 256 2048 MiB)
// Bandwidth counts the bytes the kernel names (STREAM convention: triad = 24 B per element,
// no write-allocate traffic), best of the repetitions.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Result {
  double copy, triad, sum;
};

Result bandwidth(std::size_t bytes_total, int threads) {
  // Three arrays for triad share the footprint.
  const std::size_t n = std::max<std::size_t>(bytes_total / (3 * sizeof(double)), 1024);
  double* a = static_cast<double*>(std::aligned_alloc(64, n * sizeof(double)));
  double* b = static_cast<double*>(std::aligned_alloc(64, n * sizeof(double)));
  double* c = static_cast<double*>(std::aligned_alloc(64, n * sizeof(double)));
  const long ln = static_cast<long>(n);
#pragma omp parallel for num_threads(threads) schedule(static)
  for (long i = 0; i < ln; ++i) {
    a[i] = 1.0;
    b[i] = 2.0;
    c[i] = 0.5;
  }
  // Enough repetitions for >= ~0.2 s per kernel.
  const int reps =
      static_cast<int>(std::clamp<std::size_t>((std::size_t{1} << 31) / (n * 24), 5, 2000));
  double best_copy = 1e30, best_triad = 1e30, best_sum = 1e30;
  volatile double sink = 0;
  const double s = 1.0000001;
  for (int r = 0; r < reps; ++r) {
    double t0 = now();
#pragma omp parallel for num_threads(threads) schedule(static)
    for (long i = 0; i < ln; ++i) c[i] = a[i];
    double t1 = now();
    best_copy = std::min(best_copy, t1 - t0);
    t0 = now();
#pragma omp parallel for num_threads(threads) schedule(static)
    for (long i = 0; i < ln; ++i) a[i] = b[i] + s * c[i];
    t1 = now();
    best_triad = std::min(best_triad, t1 - t0);
    double acc = 0;
    t0 = now();
#pragma omp parallel for simd num_threads(threads) schedule(static) reduction(+ : acc)
    for (long i = 0; i < ln; ++i) acc += a[i];
    t1 = now();
    sink = sink + acc;
    best_sum = std::min(best_sum, t1 - t0);
  }
  std::free(a);
  std::free(b);
  std::free(c);
  const double GB = 1e9;
  return {16.0 * n / best_copy / GB, 24.0 * n / best_triad / GB, 8.0 * n / best_sum / GB};
}

/// Scalar double FMAs per second per thread with 8 independent chains (no vectorisation: the
/// contact kernel is scalar code).
double fma_rate(int threads) {
  const long iters = 200'000'000;
  double best = 1e30;
  for (int rep = 0; rep < 3; ++rep) {
    const double t0 = now();
    double total = 0;
#pragma omp parallel num_threads(threads) reduction(+ : total)
    {
      double x0 = 1, x1 = 1.1, x2 = 1.2, x3 = 1.3, x4 = 1.4, x5 = 1.5, x6 = 1.6, x7 = 1.7;
      const double m = 0.9999999, k = 1e-9;
      for (long i = 0; i < iters; ++i) {
        // Scalar on purpose: the asm barrier keeps the compiler from vectorising the chains.
        asm volatile("" : "+x"(x0), "+x"(x1), "+x"(x2), "+x"(x3));
        x0 = x0 * m + k;
        x1 = x1 * m + k;
        x2 = x2 * m + k;
        x3 = x3 * m + k;
        x4 = x4 * m + k;
        x5 = x5 * m + k;
        x6 = x6 * m + k;
        x7 = x7 * m + k;
      }
      total = x0 + x1 + x2 + x3 + x4 + x5 + x6 + x7;
    }
    volatile double sink = total;
    (void)sink;
    best = std::min(best, now() - t0);
  }
  return 8.0 * iters * threads / best;  // FMAs per second, all threads together
}

}  // namespace

int main(int argc, char** argv) {
  int max_threads = argc > 1 ? std::atoi(argv[1]) : 2;
  std::vector<double> sizes_mib;
  for (int k = 2; k < argc; ++k) sizes_mib.push_back(std::atof(argv[k]));
  if (sizes_mib.empty()) sizes_mib = {1, 8, 64, 256, 2048};
  std::printf("# footprint_MiB threads copy_GB/s triad_GB/s sum_GB/s\n");
  for (double mib : sizes_mib)
    for (int t = 1; t <= max_threads; ++t) {
      const Result r = bandwidth(static_cast<std::size_t>(mib * 1024 * 1024), t);
      std::printf("%10.0f %3d %8.1f %8.1f %8.1f\n", mib, t, r.copy, r.triad, r.sum);
      std::fflush(stdout);
    }
  for (int t = 1; t <= max_threads; ++t)
    std::printf("# scalar FMA rate, %d thread(s): %.2f G FMA/s\n", t, fma_rate(t) / 1e9);
  return 0;
}
