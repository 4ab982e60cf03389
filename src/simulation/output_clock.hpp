// SPDX-License-Identifier: GPL-3.0-or-later
// The output times of a continuum run (series rows, ParaView snapshots, checkpoints).
#pragma once

#include <algorithm>

#include "io/input/continuum_input.hpp"

namespace gf {

/// When the series, the snapshots and the checkpoints of a continuum run (SPH, two-fluid) fall
/// due. The time loop steps to until() so that outputs land on their times exactly; after each
/// step the *_due() calls say what to write and move that schedule past the present time. The
/// three next_* times go into the checkpoints, so a restart continues the same schedule.
/// Every 0 of the schedule means: a series row every step, a snapshot only at the start and the
/// end (end_time), a checkpoint only at the end (the runner writes the final one).
struct OutputClock {
  OutputClock(const input::OutputSchedule& schedule, double end_time)
      : every(schedule),
        end(end_time),
        eps(1e-12 * end_time),
        next_vtk(schedule.vtk_every > 0 ? schedule.vtk_every : end_time),
        next_series(schedule.series_every),
        next_checkpoint(schedule.checkpoint_every > 0 ? schedule.checkpoint_every : 2 * end_time) {}

  /// The time the next step must not pass [s]: the end or the next output.
  [[nodiscard]] double until() const {
    double u = std::min(end, next_vtk);
    if (every.series_every > 0) u = std::min(u, next_series);
    if (every.checkpoint_every > 0) u = std::min(u, next_checkpoint);
    return u;
  }
  /// The run has reached its end time.
  [[nodiscard]] bool finished(double t) const { return t >= end - eps; }

  /// A series row is due at time t (every step when series_every is 0).
  bool series_due(double t) { return due(t, next_series, every.series_every); }
  /// A snapshot is due at time t.
  bool vtk_due(double t) { return due(t, next_vtk, every.vtk_every > 0 ? every.vtk_every : end); }
  /// A checkpoint is due at time t (never when checkpoint_every is 0).
  bool checkpoint_due(double t) {
    return every.checkpoint_every > 0 && due(t, next_checkpoint, every.checkpoint_every);
  }

  input::OutputSchedule every;
  double end, eps;
  double next_vtk, next_series, next_checkpoint;

 private:
  /// True if t has reached next (within eps), and then next moves past t by steps of period;
  /// a period of 0 is due every time and keeps next.
  bool due(double t, double& next, double period) const {
    if (period <= 0) return true;
    if (t < next - eps) return false;
    while (next <= t + eps) next += period;
    return true;
  }
};

}  // namespace gf
