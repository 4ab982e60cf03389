// SPDX-License-Identifier: GPL-3.0-or-later
// Compile-time type lists: a model kind is registered by adding its type to one list.
#pragma once

#include <cstddef>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>

namespace gf {

template <class... Ts>
struct TypeList {
  static constexpr std::size_t size = sizeof...(Ts);
};

/// Calls f.template operator()<T>() for every T of the list, in order.
template <class... Ts, class F>
constexpr void for_each_type(TypeList<Ts...>, F&& f) {
  (f.template operator()<Ts>(), ...);
}

/// Index of the type whose static member `key` equals `key`, or -1.
template <class... Ts>
constexpr int index_of_key(TypeList<Ts...>, std::string_view key) {
  int idx = -1, i = 0;
  ((idx = (idx < 0 && Ts::key == key) ? i : idx, ++i), ...);
  return idx;
}

/// Calls f.template operator()<T>() for the type at runtime index `idx` (a switch, no virtual
/// call).
template <class... Ts, class F>
constexpr decltype(auto) dispatch_index(TypeList<Ts...>, int idx, F&& f) {
  using R = decltype(f.template operator()<std::tuple_element_t<0, std::tuple<Ts...>>>());
  if constexpr (std::is_void_v<R>) {
    int i = 0;
    ((i++ == idx ? (f.template operator()<Ts>(), true) : false) || ...);
  } else {
    R r{};
    int i = 0;
    ((i++ == idx ? (r = f.template operator()<Ts>(), true) : false) || ...);
    return r;
  }
}

}  // namespace gf
