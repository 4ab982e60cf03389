// SPDX-License-Identifier: GPL-3.0-or-later
// Graceful stop: SIGINT / SIGTERM set a flag, and a wall-time limit expires, that the time loops
// poll, so a run ends its step and writes its outputs (series, summaries, a checkpoint to restart
// from) instead of dying.
#pragma once

namespace gf::stop {

/// Installs handlers for SIGINT and SIGTERM that record the first signal and say on stderr that
/// the run will stop after its current step. A second signal of either kind gets the default
/// action: the process ends at once. Calling it again re-arms the handlers.
/// A process started by `grainflow sweep` (kParentEnv set to the sweep's pid) is also asked to
/// stop when the sweep itself dies (SIGKILL, a crash): the kernel then sends it SIGTERM, so it
/// ends its step and leaves a checkpoint for `sweep --continue` instead of running on alone.
void install_handlers();

/// Environment variable naming the pid of a sweep that started this run.
inline constexpr const char* kParentEnv = "GRAINFLOW_SWEEP_PARENT";

/// What requested() returns once the wall-time limit has passed (no signal number is negative).
inline constexpr int kTimeLimit = -1;

/// Asks the loops to stop once `seconds` (> 0) of wall time have passed from now (--max-hours).
void set_time_limit(double seconds);

/// The signal that asked the program to stop (SIGINT or SIGTERM), kTimeLimit when the time limit
/// has passed, or 0. Cheap enough to call once per time step (a clock read with a limit set).
int requested();

/// Clears the request and the time limit, and restores the default actions of SIGINT and SIGTERM.
void reset();

/// "SIGINT", "SIGTERM", "time limit", or "signal" for any other.
const char* signal_name(int sig);

/// The exit status of a program stopped by `sig`: as a shell reports a killed one, 128 + sig;
/// 3 for the time limit (the run did not reach its end; its checkpoint continues it).
inline int exit_status(int sig) {
  return sig == kTimeLimit ? 3 : 128 + sig;
}

}  // namespace gf::stop
