// SPDX-License-Identifier: GPL-3.0-or-later
// Graceful stop: SIGINT / SIGTERM set a flag that the time loops poll, so a run ends its step
// and writes its outputs (series, summaries, a checkpoint to restart from) instead of dying.
#pragma once

namespace gf::stop {

/// Installs handlers for SIGINT and SIGTERM that record the first signal and say on stderr that
/// the run will stop after its current step. A second signal of either kind gets the default
/// action: the process ends at once. Calling it again re-arms the handlers.
void install_handlers();

/// The signal that asked the program to stop (SIGINT or SIGTERM), or 0 when none has.
int requested();

/// Clears the request and restores the default actions of SIGINT and SIGTERM.
void reset();

/// "SIGINT", "SIGTERM", or "signal" for any other.
const char* signal_name(int sig);

/// The exit status of a program stopped by `sig`, as a shell reports a killed one: 128 + sig.
inline int exit_status(int sig) {
  return 128 + sig;
}

}  // namespace gf::stop
