// SPDX-License-Identifier: GPL-3.0-or-later
// Logging through spdlog: one stderr logger for the program, level set from the command line.
#pragma once

#include <spdlog/spdlog.h>

namespace gf::log {

void init(bool verbose, bool quiet);

template <class... Args>
void info(spdlog::format_string_t<Args...> fmt, Args&&... args) {
  spdlog::info(fmt, std::forward<Args>(args)...);
}
template <class... Args>
void warn(spdlog::format_string_t<Args...> fmt, Args&&... args) {
  spdlog::warn(fmt, std::forward<Args>(args)...);
}
template <class... Args>
void debug(spdlog::format_string_t<Args...> fmt, Args&&... args) {
  spdlog::debug(fmt, std::forward<Args>(args)...);
}

}  // namespace gf::log
