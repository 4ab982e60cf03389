// SPDX-License-Identifier: GPL-3.0-or-later
// Out-of-line part of REQUIRE, keeping the check itself small at every call site.
#include "core/error.hpp"

#include <string_view>

namespace gf::detail {

void throw_require(const char* cond, const char* file, int line, const std::string& msg) {
  // The source file relative to the project (src/..., apps/...), not the build machine's path.
  std::string_view f(file);
  for (const std::string_view top : {"/src/", "/apps/", "/tests/"})
    if (const auto at = f.rfind(top); at != std::string_view::npos) {
      f.remove_prefix(at + 1);
      break;
    }
  throw Error(fmt::format("{} (check '{}' failed at {}:{})", msg, cond, f, line));
}

}  // namespace gf::detail
