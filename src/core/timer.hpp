// SPDX-License-Identifier: GPL-3.0-or-later
// Wall-clock timers per named stage of the time loop, for the end-of-run summary.
#pragma once

#include <array>
#include <chrono>
#include <string_view>

namespace gf {

enum class Stage { Neighbor, Force, Walls, Integrate, Output, Setup, Count };

constexpr std::array<std::string_view, static_cast<int>(Stage::Count)> stage_names = {
    "neighbor", "force", "walls", "integrate", "output", "setup"};

class StageTimers {
 public:
  using clock = std::chrono::steady_clock;

  void add(Stage s, double seconds) { total_[static_cast<int>(s)] += seconds; }
  double seconds(Stage s) const { return total_[static_cast<int>(s)]; }
  double loop_seconds() const {
    double t = 0;
    for (int i = 0; i < static_cast<int>(Stage::Setup); ++i) t += total_[i];
    return t;
  }

  /// Adds the time until destruction to a stage.
  class Scope {
   public:
    Scope(StageTimers& t, Stage s) : t_(t), s_(s), start_(clock::now()) {}
    ~Scope() { t_.add(s_, std::chrono::duration<double>(clock::now() - start_).count()); }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    StageTimers& t_;
    Stage s_;
    clock::time_point start_;
  };

 private:
  std::array<double, static_cast<int>(Stage::Count)> total_{};
};

}  // namespace gf
