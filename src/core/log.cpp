// SPDX-License-Identifier: GPL-3.0-or-later
// Sets up the stderr logger.
#include "core/log.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>

namespace gf::log {

void init(bool verbose, bool quiet) {
  auto logger = spdlog::stderr_color_mt("grainflow");
  logger->set_pattern("%^[%l]%$ %v");
  logger->set_level(quiet ? spdlog::level::warn
                          : (verbose ? spdlog::level::debug : spdlog::level::info));
  spdlog::set_default_logger(logger);
}

}  // namespace gf::log
