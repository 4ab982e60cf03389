// SPDX-License-Identifier: GPL-3.0-or-later
// UMFPACK wrapper: keeps the symbolic analysis and reuses it for every numeric factorisation.
#include "fluid/fem/sparse_lu.hpp"

#include <suitesparse/umfpack.h>

#include <chrono>
#include <cstring>

#include "core/error.hpp"

namespace gf::fem {

namespace {
double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

SparseLu::~SparseLu() {
  free_factors();
}

void SparseLu::free_factors() {
  if (numeric_ != nullptr) umfpack_di_free_numeric(&numeric_);
  if (symbolic_ != nullptr) umfpack_di_free_symbolic(&symbolic_);
  numeric_ = nullptr;
  symbolic_ = nullptr;
}

void SparseLu::analyze(int n, const int* col_ptr, const int* row_idx, const double* values) {
  free_factors();
  n_ = n;
  col_ptr_.assign(col_ptr, col_ptr + n + 1);
  row_idx_.assign(row_idx, row_idx + col_ptr[n]);
  values_.assign(values, values + col_ptr[n]);
  control_.assign(UMFPACK_CONTROL, 0.0);
  umfpack_di_defaults(control_.data());
  control_[UMFPACK_IRSTEP] = 0;  // no iterative refinement: Newton corrects the residual anyway
  control_[UMFPACK_STRATEGY] =
      UMFPACK_STRATEGY_SYMMETRIC;  // measured faster on Taylor-Hood saddle points
  double info[UMFPACK_INFO];
  const int status = umfpack_di_symbolic(n, n, col_ptr_.data(), row_idx_.data(), values_.data(),
                                         &symbolic_, control_.data(), info);
  REQUIRE(status == UMFPACK_OK, "UMFPACK symbolic analysis failed with status {}", status);
}

void SparseLu::factorize(const double* values) {
  REQUIRE(symbolic_ != nullptr, "SparseLu::factorize before analyze");
  const double t0 = now();
  std::memcpy(values_.data(), values, values_.size() * sizeof(double));
  if (numeric_ != nullptr) umfpack_di_free_numeric(&numeric_);
  double info[UMFPACK_INFO];
  const int status = umfpack_di_numeric(col_ptr_.data(), row_idx_.data(), values_.data(), symbolic_,
                                        &numeric_, control_.data(), info);
  if (status != UMFPACK_OK) {
    if (numeric_ != nullptr) umfpack_di_free_numeric(&numeric_);
    numeric_ = nullptr;
    throw Error(fmt::format(
        "UMFPACK numeric factorisation failed with status {} (singular matrix?)", status));
  }
  ++n_factorizations_;
  factor_seconds_ += now() - t0;
}

void SparseLu::solve(const double* b, double* x) const {
  REQUIRE(numeric_ != nullptr, "SparseLu::solve without factors");
  const double t0 = now();
  double info[UMFPACK_INFO];
  const int status = umfpack_di_solve(UMFPACK_A, col_ptr_.data(), row_idx_.data(), values_.data(),
                                      x, b, numeric_, control_.data(), info);
  REQUIRE(status == UMFPACK_OK, "UMFPACK solve failed with status {}", status);
  solve_seconds_ += now() - t0;
}

}  // namespace gf::fem
