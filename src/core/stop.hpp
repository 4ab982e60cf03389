// SPDX-License-Identifier: GPL-3.0-or-later
// Graceful stop: SIGINT / SIGTERM set a flag, and a wall-time limit expires, that the time loops
// poll, so a run ends its step and writes its outputs (series, summaries, a checkpoint to restart
// from) instead of dying.
#pragma once

#include <csignal>

namespace gf::stop {

/// Installs handlers for SIGINT and SIGTERM that record the first signal and say on stderr that
/// the run will stop after its current step. A second signal of either kind gets the default
/// action: the process ends at once. Calling it again re-arms the handlers.
/// A process started by `grainflow sweep` (kParentEnv set to the sweep's pid) is also asked to
/// stop when the sweep itself dies (SIGKILL, a crash): the kernel then sends it SIGUSR1, which
/// only ever asks for a graceful stop (kParentGone) — a run already stopping on the SIGTERM the
/// sweep passed on is not cut short by its sweep's death — so it ends its step and leaves a
/// checkpoint for `sweep --continue` instead of running on alone.
void install_handlers();

/// Environment variable naming the pid of a sweep that started this run.
inline constexpr const char* kParentEnv = "GRAINFLOW_SWEEP_PARENT";

/// What requested() returns once the wall-time limit has passed (no signal number is negative).
inline constexpr int kTimeLimit = -1;
/// ... and once the sweep that started this run has ended (see install_handlers).
inline constexpr int kParentGone = -2;

/// Asks the loops to stop once `seconds` (> 0) of wall time have passed from now (--max-hours).
void set_time_limit(double seconds);

/// The signal that asked the program to stop (SIGINT or SIGTERM), kTimeLimit when the time limit
/// has passed, kParentGone when the run's sweep ended, or 0. Cheap enough to call once per time
/// step (a clock read with a limit set).
int requested();

/// Clears the request and the time limit, and restores the default actions of SIGINT and SIGTERM.
void reset();

/// "SIGINT", "SIGTERM", "time limit", "sweep ended", or "signal" for any other.
const char* signal_name(int sig);

/// The exit status of a program stopped by `sig`: as a shell reports a killed one, 128 + sig;
/// 3 for the time limit (the run did not reach its end; its checkpoint continues it); that of
/// SIGTERM when its sweep ended.
inline int exit_status(int sig) {
  return sig == kTimeLimit ? 3 : sig == kParentGone ? 128 + SIGTERM : 128 + sig;
}

}  // namespace gf::stop
