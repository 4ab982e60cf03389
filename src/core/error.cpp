// SPDX-License-Identifier: GPL-3.0-or-later
// Out-of-line part of REQUIRE, keeping the check itself small at every call site.
#include "core/error.hpp"

namespace gf::detail {

void throw_require(const char* cond, const char* file, int line, const std::string& msg) {
  throw Error(fmt::format("{} (check '{}' failed at {}:{})", msg, cond, file, line));
}

}  // namespace gf::detail
