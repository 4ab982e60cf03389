// SPDX-License-Identifier: GPL-3.0-or-later
// Typed errors and the REQUIRE / ASSERT checks; InputError maps to exit code 2.
#pragma once

#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace gf {

/// Any failure grainflow reports to the user.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The user's input (case file, CSV, command line) is wrong; the program exits with code 2.
class InputError : public Error {
 public:
  using Error::Error;
};

/// A file could not be read or written.
class IoError : public Error {
 public:
  using Error::Error;
};

namespace detail {
[[noreturn]] void throw_require(const char* cond, const char* file, int line,
                                const std::string& msg);
}

}  // namespace gf

/// Always-on check: throws gf::Error naming the condition, the source location and the message.
#define REQUIRE(cond, ...)                                                                         \
  do {                                                                                             \
    if (!(cond)) ::gf::detail::throw_require(#cond, __FILE__, __LINE__, fmt::format(__VA_ARGS__)); \
  } while (0)

/// Internal invariant, checked in debug builds only.
#ifndef NDEBUG
#define ASSERT(cond) REQUIRE(cond, "internal invariant violated")
#else
#define ASSERT(cond) ((void)0)
#endif
