// SPDX-License-Identifier: GPL-3.0-or-later
// Run progress: a redrawn bar on a terminal, one line every few seconds otherwise.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>

namespace gf {

class Progress {
 public:
  /// `out` is where progress goes (stderr by default); the bar is used only when it is a terminal.
  Progress(double t_begin, double t_end, std::FILE* out = stderr, double line_interval_s = 5.0);

  /// Reports the state after a step; cheap when nothing is due.
  void update(double t, std::int64_t particle_steps, std::int64_t n_contacts);
  /// Final line (newline after a bar).
  void finish(double t, std::int64_t particle_steps, std::int64_t n_contacts);

 private:
  void print(double t, std::int64_t particle_steps, std::int64_t n_contacts, bool final);

  using clock = std::chrono::steady_clock;
  double t0_, t1_;
  std::FILE* out_;
  bool tty_;
  double interval_;
  clock::time_point start_, last_;
};

}  // namespace gf
