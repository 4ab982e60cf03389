// SPDX-License-Identifier: GPL-3.0-or-later
// CSV curves of validation tests for the plots of docs/validation/ (make_plots.py).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

namespace gf::test {

/// When GF_VALIDATION_OUT is set, validation tests write their curves there as CSV for the
/// plots of docs/validation/ (make_plots.py); otherwise nothing is written.
class Dump {
 public:
  Dump(const std::string& name, const std::string& header) {
    if (const char* dir = std::getenv("GF_VALIDATION_OUT")) {
      f_ = std::fopen((std::string(dir) + "/" + name + ".csv").c_str(), "w");
      if (f_) std::fprintf(f_, "%s\n", header.c_str());
    }
  }
  ~Dump() {
    if (f_) std::fclose(f_);
  }
  Dump(const Dump&) = delete;
  Dump& operator=(const Dump&) = delete;
  template <class... T>
  void row(T... v) {
    if (!f_) return;
    int k = 0;
    ((std::fprintf(f_, k++ ? ",%.10g" : "%.10g", static_cast<double>(v))), ...);
    std::fprintf(f_, "\n");
  }

 private:
  std::FILE* f_ = nullptr;
};

}  // namespace gf::test
