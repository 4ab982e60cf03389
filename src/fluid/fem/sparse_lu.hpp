// SPDX-License-Identifier: GPL-3.0-or-later
// Thin owner of an UMFPACK (SuiteSparse) LU factorisation: symbolic once, numeric many times.
#pragma once

#include <vector>

namespace gf::fem {

/// Sparse LU of a square matrix in compressed-column form (0-based, sorted row indices).
/// The symbolic analysis (column ordering) is computed once per pattern and kept; each
/// factorize() redoes only the numeric factorisation. The factorised values are copied, so
/// the caller may change its matrix while still solving with the old factors.
class SparseLu {
 public:
  SparseLu() = default;
  SparseLu(const SparseLu&) = delete;
  SparseLu& operator=(const SparseLu&) = delete;
  ~SparseLu();

  /// Symbolic analysis of the pattern (col_ptr has n+1 entries); frees earlier factors.
  void analyze(int n, const int* col_ptr, const int* row_idx, const double* values);
  /// Numeric factorisation with the pattern of analyze(); throws gf::Error when singular.
  void factorize(const double* values);
  /// Solves A x = b with the last factors.
  void solve(const double* b, double* x) const;

  [[nodiscard]] bool has_factors() const { return numeric_ != nullptr; }
  [[nodiscard]] int n_factorizations() const { return n_factorizations_; }
  [[nodiscard]] double factor_seconds() const { return factor_seconds_; }
  [[nodiscard]] double solve_seconds() const { return solve_seconds_; }

 private:
  void free_factors();
  int n_ = 0;
  std::vector<int> col_ptr_, row_idx_;
  std::vector<double> values_;
  void* symbolic_ = nullptr;
  void* numeric_ = nullptr;
  std::vector<double> control_;
  int n_factorizations_ = 0;
  double factor_seconds_ = 0.0;
  mutable double solve_seconds_ = 0.0;
};

}  // namespace gf::fem
