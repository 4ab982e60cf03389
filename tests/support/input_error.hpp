// SPDX-License-Identifier: GPL-3.0-or-later
// The message of the gf::InputError a piece of test code throws, for tests of input checks.
#pragma once

#include <string>
#include <utility>

#include "core/error.hpp"

namespace gf::test {

/// What `f()` throws as gf::InputError, or `none` when it throws nothing.
template <class F>
std::string input_error_of(F&& f, std::string none = "") {
  try {
    std::forward<F>(f)();
  } catch (const InputError& e) {
    return e.what();
  }
  return none;
}

}  // namespace gf::test
