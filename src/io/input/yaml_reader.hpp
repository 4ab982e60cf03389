// SPDX-License-Identifier: GPL-3.0-or-later
// Strict YAML reading over yaml-cpp: key paths, typed values, ranges, unknown keys, located errors.
//
// Every error is a gf::InputError whose message reads
//   FILE:LINE:COLUMN: error: KEY.PATH: expected WHAT, found 'VALUE'
// (lines and columns 1-based). A map is read through YamlMap, which rejects duplicate keys and
// keys outside the accepted list as soon as it is built.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/vec3.hpp"
#include "io/input/config.hpp"

namespace gf::input {

/// Records that an override (--set `text`, "path=value") replaced the value at key path `path`
/// of the document parsed last: errors at it, or inside it, then name the option, not a place
/// in the file (whose positions the value does not have). Forgotten at the next parse.
void note_override(std::string path, std::string text);

/// "FILE:LINE:COLUMN: error: KEY.PATH: MESSAGE"; LINE / COLUMN / KEY.PATH are left out when
/// unknown.
std::string format_error(const config::SourceLoc& loc, std::string_view message);

/// Throws gf::InputError with format_error(loc, message).
[[noreturn]] void throw_input_error(const config::SourceLoc& loc, std::string_view message);

/// Shortest round-trip text of a number ("0.5", "2e-05").
std::string number_text(double v);

/// Admissible interval of a number; infinite bounds mean unbounded.
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;
  bool max_exclusive = false;

  bool contains(double v) const;
  /// "> 0", ">= 0", "<= 1", "in (-1, 0.5)"; empty when unbounded.
  std::string describe() const;

  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range non_negative() {
    return {0.0, std::numeric_limits<double>::infinity(), false, false};
  }
  static Range at_least(double v) {
    return {v, std::numeric_limits<double>::infinity(), false, false};
  }
};

/// One YAML node together with the file it came from and its key path (e.g. "particles[0].fill").
class YamlNode {
 public:
  YamlNode(YAML::Node node, std::string path, std::shared_ptr<const std::string> file,
           YAML::Mark key_mark);

  /// Parses a whole file; a YAML syntax error becomes an InputError at its line and column.
  static YamlNode parse_file(const std::filesystem::path& file);
  /// Parses text; `file_label` names it in messages.
  static YamlNode parse_text(const std::string& text, const std::string& file_label);

  const YAML::Node& raw() const { return node_; }
  const std::string& path() const { return path_; }
  const std::string& file() const { return *file_; }
  /// Where the value starts (the key's position for an empty value).
  config::SourceLoc loc() const;
  /// Where the key that introduced this value is (the value's position for list items, the root).
  config::SourceLoc key_loc() const;
  int line() const { return loc().line; }

  bool is_null() const { return !node_.IsDefined() || node_.IsNull(); }
  bool is_map() const { return node_.IsMap(); }
  bool is_list() const { return node_.IsSequence(); }
  bool is_scalar() const { return node_.IsScalar(); }

  /// What the value looks like in a message: 'text' for a scalar, "a list of 2 items", "a map",
  /// "nothing".
  std::string found() const;
  /// Throws "PATH: MESSAGE" at this value.
  [[noreturn]] void fail(std::string_view message) const;
  /// Throws "PATH: expected WHAT, found ..." at this value.
  [[noreturn]] void fail_expected(std::string_view what) const;

  /// A finite number within `range`. Quoted strings and values tagged as anything but a number
  /// (`!!str 2500`) are not numbers; `!!float` and `!!int` are accepted.
  double as_number(const Range& range = {}) const;
  /// An integer (written as 12, 1e5 or 100000.0) within `range`; tags as for as_number.
  std::int64_t as_integer(const Range& range = {}) const;
  /// true or false (the YAML 1.1 forms yes/no/on/off are refused as ambiguous; so are quoted
  /// values and tags other than `!!bool`).
  bool as_bool() const;
  /// A scalar as text.
  std::string as_string() const;
  /// A non-empty scalar from `choices`.
  std::string as_choice(std::initializer_list<std::string_view> choices) const;
  /// The same over a list kept elsewhere (e.g. a model's names next to its enum).
  std::string as_choice(std::span<const std::string_view> choices) const;
  /// [x, y, z].
  Vec3 as_vec3() const;
  /// [x, y, z], not zero, returned normalised to unit length.
  Vec3 as_direction() const;
  /// A vector of a case of dimension `dimension`: [x, y, z] in 3D, [x, y] in 2D (z = 0). The
  /// other length is refused with "expected 2 components in a 2D case" (or 3 in 3D).
  Vec3 as_vec(int dimension) const;
  /// as_vec(dimension), not zero, returned normalised to unit length.
  Vec3 as_direction(int dimension) const;
  /// The items of a list, each with path "PATH[i]"; at least `min_items` of them.
  std::vector<YamlNode> as_list(std::size_t min_items = 0) const;

  /// The node of a child with key `key` (no lookup: the caller found it).
  YamlNode child(const YAML::Node& value, const std::string& key, YAML::Mark key_mark) const;

 private:
  YAML::Node node_;
  std::string path_;
  std::shared_ptr<const std::string> file_;
  YAML::Mark key_mark_;
};

/// A YAML map read strictly: duplicate keys and keys outside the accepted list are errors.
class YamlMap {
 public:
  /// Checks that `node` is a map with scalar, distinct keys that are all in `accepted`.
  YamlMap(const YamlNode& node, std::vector<std::string> accepted);
  /// Open map (the keys are names, e.g. `materials:`): only checks map-ness and distinct keys.
  explicit YamlMap(const YamlNode& node);

  const YamlNode& node() const { return node_; }
  const std::vector<std::string>& accepted() const { return accepted_; }

  bool has(std::string_view key) const;
  /// The value of a required key; missing or empty -> error at the map naming the key.
  YamlNode at(std::string_view key) const;
  /// The value of an optional key; an explicitly empty value counts as absent.
  std::optional<YamlNode> find(std::string_view key) const;

  double number(std::string_view key, const Range& range = {}) const;
  double number_or(std::string_view key, double fallback, const Range& range = {}) const;
  std::optional<double> optional_number(std::string_view key, const Range& range = {}) const;
  std::int64_t integer(std::string_view key, const Range& range = {}) const;
  std::string string(std::string_view key) const;
  Vec3 vec3(std::string_view key) const;
  Vec3 vec3_or(std::string_view key, const Vec3& fallback) const;
  bool boolean_or(std::string_view key, bool fallback) const;

  /// Keys and values in document order; the value's path is "PATH.KEY".
  std::vector<std::pair<YamlNode, YamlNode>> entries() const;
  /// Throws at the first key not in `accepted`: "unknown key 'k' (did you mean ...?); `what`: a,
  /// b".
  void check_keys(const std::vector<std::string>& accepted,
                  std::string_view what = "accepted keys") const;
  /// Throws "[missing key]" at the map when none or more than one of `keys` is present; returns the
  /// one.
  std::string exactly_one_of(const std::vector<std::string>& keys) const;
  /// The value of an optional key that may also be spelled `alias` (both must be accepted);
  /// both present: an error at the later, as exactly_one_of's.
  std::optional<YamlNode> find_either(std::string_view key, std::string_view alias) const;

 private:
  struct Entry {
    std::string key;
    YAML::Node key_node;
    YAML::Node value;
  };
  YamlMap(const YamlNode& node, const std::vector<std::string>* keys);
  const Entry* lookup(std::string_view key) const;
  YamlNode value_node(const Entry& e) const;

  YamlNode node_;
  std::vector<Entry> entries_;
  std::vector<std::string> accepted_;
};

/// "a, b, c" (for messages).
std::string join(const std::vector<std::string>& items, std::string_view sep = ", ");

/// The accepted item closest to `word` by edit distance, if it is close enough to be a likely typo.
std::optional<std::string> closest_match(std::string_view word,
                                         const std::vector<std::string>& accepted);

}  // namespace gf::input
