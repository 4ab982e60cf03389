// SPDX-License-Identifier: GPL-3.0-or-later
// How a case file's scalar text reads as a number, an integer or a boolean: one rule for every
// reader (io/input's and the fluid_fem block's), strict where YAML 1.1 is loose.
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>

namespace gf {

/// The whole of `text` as a double (std::from_chars: decimal or scientific, "inf" / "nan" read
/// as such); a leading '+' is accepted. Nothing else: no hex, no "1,5", no trailing text.
inline std::optional<double> parse_double(std::string_view text) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty()) return std::nullopt;
  double v = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size()) return std::nullopt;
  return v;
}

/// The whole of `text` as an integer; also integral values written as 1e5 or 100000.0 (exact
/// below 2^53).
inline std::optional<std::int64_t> parse_integer(std::string_view text) {
  std::string_view t = text;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  std::int64_t i = 0;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), i);
  if (!t.empty() && ec == std::errc() && ptr == t.data() + t.size()) return i;
  const auto v = parse_double(text);
  if (!v || !std::isfinite(*v) || std::floor(*v) != *v || std::abs(*v) > 9.007199254740992e15)
    return std::nullopt;
  return static_cast<std::int64_t>(*v);
}

/// true / True / TRUE and false / False / FALSE; not YAML 1.1's yes, no, on, off, y, n.
inline std::optional<bool> parse_bool(std::string_view text) {
  if (text == "true" || text == "True" || text == "TRUE") return true;
  if (text == "false" || text == "False" || text == "FALSE") return false;
  return std::nullopt;
}

/// A scalar's tag as written, from yaml-cpp's Node::Tag(): "" when none (a plain scalar: "?"),
/// "!" for a quoted scalar, "!!str" for tag:yaml.org,2002:str (`density: !!str 2500`), "!local"
/// as is.
inline std::string given_tag(const std::string& yaml_tag) {
  if (yaml_tag.empty() || yaml_tag == "?") return "";
  constexpr std::string_view core = "tag:yaml.org,2002:";
  if (yaml_tag.compare(0, core.size(), core) == 0) return "!!" + yaml_tag.substr(core.size());
  return yaml_tag;
}

/// Whether a scalar with yaml-cpp tag `yaml_tag` may be read as one of `types` ("!!int",
/// "!!float", "!!bool"): it is plain or carries one of them. A quoted scalar or one tagged
/// otherwise (`!!str 2500`) was explicitly made something else.
inline bool tag_allows(const std::string& yaml_tag, std::initializer_list<std::string_view> types) {
  const std::string tag = given_tag(yaml_tag);
  return tag.empty() || std::find(types.begin(), types.end(), tag) != types.end();
}

}  // namespace gf
