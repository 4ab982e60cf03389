// SPDX-License-Identifier: GPL-3.0-or-later
// Seeded random generator whose whole state can be saved to and restored from a string.
#pragma once

#include <cstdint>
#include <random>
#include <sstream>
#include <string>

namespace gf {

class Rng {
 public:
  explicit Rng(std::uint64_t seed = 5489u) : engine_(seed) {}

  double uniform(double a = 0.0, double b = 1.0) {
    return std::uniform_real_distribution<double>(a, b)(engine_);
  }
  double normal(double mean, double sd) {
    return std::normal_distribution<double>(mean, sd)(engine_);
  }
  std::mt19937_64& engine() { return engine_; }

  std::string state() const {
    std::ostringstream s;
    s << engine_;
    return s.str();
  }
  void set_state(const std::string& st) {
    std::istringstream s(st);
    s >> engine_;
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace gf
