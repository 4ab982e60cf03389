// SPDX-License-Identifier: GPL-3.0-or-later
// Progress bar / progress lines with simulated time, %, ETA, particle-steps/s and contacts.
#include "core/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <string>

namespace gf {

Progress::Progress(double t_begin, double t_end, std::FILE* out, double line_interval_s)
    : t0_(t_begin),
      t1_(t_end),
      out_(out),
      tty_(::isatty(::fileno(out)) != 0),
      interval_(tty_ ? 0.2 : line_interval_s),
      start_(clock::now()),
      last_(start_) {}

void Progress::update(double t, std::int64_t particle_steps, std::int64_t n_contacts) {
  const auto now = clock::now();
  if (std::chrono::duration<double>(now - last_).count() < interval_) return;
  last_ = now;
  print(t, particle_steps, n_contacts, false);
}

void Progress::finish(double t, std::int64_t particle_steps, std::int64_t n_contacts) {
  print(t, particle_steps, n_contacts, true);
}

static std::string hms(double s) {
  if (!(s >= 0) || s > 1e7) return "--:--";
  const long v = static_cast<long>(s + 0.5);
  return v >= 3600 ? fmt::format("{}:{:02}:{:02}", v / 3600, (v / 60) % 60, v % 60)
                   : fmt::format("{:02}:{:02}", v / 60, v % 60);
}

void Progress::print(double t, std::int64_t particle_steps, std::int64_t n_contacts, bool final) {
  const double wall = std::chrono::duration<double>(clock::now() - start_).count();
  const double frac = t1_ > t0_ ? std::clamp((t - t0_) / (t1_ - t0_), 0.0, 1.0) : 1.0;
  const double eta = frac > 0 ? wall * (1 - frac) / frac : -1;
  const double rate = wall > 0 ? static_cast<double>(particle_steps) / wall : 0.0;
  const std::string tail =
      fmt::format("t = {:.4g} s  {:5.1f}%  ETA {}  {:.3g} particle-steps/s  {} contacts", t,
                  100 * frac, final ? hms(0) : hms(eta), rate, n_contacts);
  if (tty_) {
    constexpr int width = 30;
    const int filled = static_cast<int>(frac * width);
    std::string bar(filled, '#');
    bar.resize(width, '.');
    fmt::print(out_, "\r[{}] {}\x1b[K{}", bar, tail, final ? "\n" : "");
  } else {
    fmt::print(out_, "progress: {}\n", tail);
  }
  std::fflush(out_);
}

}  // namespace gf
