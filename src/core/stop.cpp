// SPDX-License-Identifier: GPL-3.0-or-later
// SIGINT / SIGTERM handlers that only record the signal (async-signal-safe: a sig_atomic_t,
// write(2), signal(2), raise(3)), and the wall-time limit.
#include "core/stop.hpp"

#include <sys/prctl.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <optional>

namespace gf::stop {

namespace {

volatile std::sig_atomic_t g_signal = 0;
std::optional<std::chrono::steady_clock::time_point> g_deadline;

void say(const char* text) {
  // Nothing to do if stderr is gone; the flag is what matters.
  [[maybe_unused]] const auto n = ::write(STDERR_FILENO, text, std::strlen(text));
}

extern "C" void on_signal(int sig) {
  if (g_signal != 0) {  // second request: stop now, as without a handler
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
    std::raise(sig);
    return;
  }
  g_signal = sig;
  say(sig == SIGINT ? "\ngrainflow: SIGINT received: stopping after this step and writing the "
                      "outputs (a second signal stops at once)\n"
                    : "\ngrainflow: SIGTERM received: stopping after this step and writing the "
                      "outputs (a second signal stops at once)\n");
}

extern "C" void on_parent_gone(int) {
  if (g_signal != 0) return;  // stopping already: nothing more to ask
  g_signal = kParentGone;
  say("\ngrainflow: the sweep that started this run ended: stopping after this step and writing "
      "the outputs\n");
}

void set_action(int sig, void (*handler)(int)) {
  struct sigaction sa {};
  sa.sa_handler = handler;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;  // file and terminal writes of the run carry on undisturbed
  sigaction(sig, &sa, nullptr);
}

}  // namespace

void install_handlers() {
  g_signal = 0;
  set_action(SIGINT, on_signal);
  set_action(SIGTERM, on_signal);
  if (const char* parent = std::getenv(kParentEnv)) {
    // Linux: SIGUSR1 when the parent ends. Armed after the handler, so it stops gracefully;
    // a parent gone already (between spawn and here) is a stop request at once.
    set_action(SIGUSR1, on_parent_gone);
    ::prctl(PR_SET_PDEATHSIG, SIGUSR1);
    if (::getppid() != static_cast<pid_t>(std::atol(parent))) g_signal = kParentGone;
  }
}

void set_time_limit(double seconds) {
  g_deadline = std::chrono::steady_clock::now() +
               std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                   std::chrono::duration<double>(seconds));
}

int requested() {
  if (g_signal != 0) return g_signal;
  if (g_deadline && std::chrono::steady_clock::now() >= *g_deadline) return kTimeLimit;
  return 0;
}

void reset() {
  set_action(SIGINT, SIG_DFL);
  set_action(SIGTERM, SIG_DFL);
  set_action(SIGUSR1, SIG_DFL);
  g_signal = 0;
  g_deadline.reset();
}

const char* signal_name(int sig) {
  switch (sig) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    case kTimeLimit:
      return "time limit";
    case kParentGone:
      return "sweep ended";
    default:
      return "signal";
  }
}

}  // namespace gf::stop
