// SPDX-License-Identifier: GPL-3.0-or-later
// Materials (density, Young's modulus, Poisson ratio) and symmetric per-type-pair tables.
#pragma once

#include <string>
#include <vector>

#include "core/error.hpp"

namespace gf {

struct Material {
  std::string name;
  double density = 0;         ///< kg/m^3
  double youngs_modulus = 0;  ///< Pa
  double poisson_ratio = 0;   ///< 1
};

/// Symmetric n x n table indexed by two material indices, filled before the time loop.
template <class T>
class PairTable {
 public:
  PairTable() = default;
  explicit PairTable(int n) : n_(n), data_(static_cast<std::size_t>(n) * n) {}
  int n() const { return n_; }
  T& operator()(int a, int b) { return data_[static_cast<std::size_t>(a) * n_ + b]; }
  const T& operator()(int a, int b) const { return data_[static_cast<std::size_t>(a) * n_ + b]; }
  /// Sets both (a, b) and (b, a).
  void set(int a, int b, const T& v) {
    (*this)(a, b) = v;
    (*this)(b, a) = v;
  }
  T* data() { return data_.data(); }
  const T* data() const { return data_.data(); }

 private:
  int n_ = 0;
  std::vector<T> data_;
};

}  // namespace gf
