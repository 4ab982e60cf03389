// SPDX-License-Identifier: GPL-3.0-or-later
// Strict YAML reading: located errors, typed values with ranges, duplicate and unknown keys.
#include "io/input/yaml_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "core/scalar_text.hpp"

namespace gf::input {

namespace {

/// The overrides (--set) applied to the document being read: key path and "path=value" text.
/// Cleared when a document is parsed, filled by note_override.
thread_local std::vector<std::pair<std::string, std::string>> g_overrides;

/// The override that gave the node at `path`, if any: its own key or a key inside its value.
const std::string* override_at(const std::string& path) {
  for (const auto& [p, text] : g_overrides)
    if (path == p || (path.size() > p.size() && path.compare(0, p.size(), p) == 0 &&
                      (path[p.size()] == '.' || path[p.size()] == '[')))
      return &text;
  return nullptr;
}

config::SourceLoc make_loc(const std::string& file, const YAML::Mark& m, const std::string& path) {
  config::SourceLoc loc;
  loc.file = file;
  loc.key_path = path;
  // A value given by --set was parsed from its own one-line text, so its positions are in that
  // line (0): it is named by the option instead of a place in the file. (Under an overridden
  // key no node of the file is left.)
  if (!m.is_null() && m.line == 0)
    if (const std::string* text = override_at(path)) {
      loc.file = fmt::format("{} (--set {})", file, *text);
      return loc;
    }
  if (!m.is_null() && m.line >= 0) {
    loc.line = m.line + 1;
    loc.column = m.column + 1;
  }
  return loc;
}

bool valid(const YAML::Mark& m) {
  return !m.is_null() && m.line >= 0;
}

std::string child_path(const std::string& parent, std::string_view key) {
  return parent.empty() ? std::string(key) : fmt::format("{}.{}", parent, key);
}

/// given_tag / tag_allows (core/scalar_text.hpp) for a node.
std::string given_tag(const YAML::Node& n) {
  return gf::given_tag(n.Tag());
}
bool readable_as(const YAML::Node& n, std::initializer_list<std::string_view> types) {
  return tag_allows(n.Tag(), types);
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t sub = prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Messages

std::string format_error(const config::SourceLoc& loc, std::string_view message) {
  std::string where = loc.file.empty() ? std::string("<input>") : loc.file;
  if (loc.line > 0) {
    where += fmt::format(":{}", loc.line);
    if (loc.column > 0) where += fmt::format(":{}", loc.column);
  }
  if (loc.key_path.empty()) return fmt::format("{}: error: {}", where, message);
  return fmt::format("{}: error: {}: {}", where, loc.key_path, message);
}

void throw_input_error(const config::SourceLoc& loc, std::string_view message) {
  throw InputError(format_error(loc, message));
}

std::string number_text(double v) {
  std::string s = fmt::format("{}", v);  // shortest text that reads back exactly
  // Large round numbers read better in exponent form: 10000000 -> 1e+07.
  const std::size_t zeros = s.size() - 1 - s.find_last_not_of('0');
  if (s.find_first_of(".e") == std::string::npos && zeros >= 6) {
    for (int p = 1; p <= 17; ++p) {
      std::string t = fmt::format("{:.{}g}", v, p);
      if (std::stod(t) == v) return t;
    }
  }
  return s;
}

std::string join(const std::vector<std::string>& items, std::string_view sep) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i) out += sep;
    out += items[i];
  }
  return out;
}

std::optional<std::string> closest_match(std::string_view word,
                                         const std::vector<std::string>& accepted) {
  std::optional<std::string> best;
  std::size_t best_d = (word.size() <= 3 ? 1 : std::max<std::size_t>(2, word.size() / 3)) + 1;
  for (const auto& a : accepted) {
    const std::size_t d = edit_distance(word, a);
    if (d < best_d) {
      best_d = d;
      best = a;
    }
  }
  return best;
}

bool Range::contains(double v) const {
  if (min_exclusive ? !(v > min) : !(v >= min)) return false;
  if (max_exclusive ? !(v < max) : !(v <= max)) return false;
  return true;
}

std::string Range::describe() const {
  const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
  if (has_min && has_max)
    return fmt::format("in {}{}, {}{}", min_exclusive ? "(" : "[", number_text(min),
                       number_text(max), max_exclusive ? ")" : "]");
  if (has_min) return fmt::format("{} {}", min_exclusive ? ">" : ">=", number_text(min));
  if (has_max) return fmt::format("{} {}", max_exclusive ? "<" : "<=", number_text(max));
  return {};
}

// ---------------------------------------------------------------------------------------------
// YamlNode

YamlNode::YamlNode(YAML::Node node, std::string path, std::shared_ptr<const std::string> file,
                   YAML::Mark key_mark)
    : node_(std::move(node)), path_(std::move(path)), file_(std::move(file)), key_mark_(key_mark) {}

YamlNode YamlNode::parse_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in || std::filesystem::is_directory(file)) {
    config::SourceLoc loc;
    loc.file = file.string();
    throw_input_error(loc, std::filesystem::is_directory(file) ? "a folder, not a case file"
                           : std::filesystem::exists(file)     ? "cannot read the case file"
                                                               : "case file not found");
  }
  std::ostringstream s;
  s << in.rdbuf();
  return parse_text(s.str(), file.string());
}

void note_override(std::string path, std::string text) {
  g_overrides.emplace_back(std::move(path), std::move(text));
}

YamlNode YamlNode::parse_text(const std::string& text, const std::string& file_label) {
  g_overrides.clear();
  auto file = std::make_shared<const std::string>(file_label);
  std::vector<YAML::Node> docs;
  try {
    docs = YAML::LoadAll(text);
  } catch (const YAML::Exception& e) {
    config::SourceLoc loc = make_loc(file_label, e.mark, "");
    throw_input_error(loc, fmt::format("YAML syntax error: {}", e.msg));
  }
  if (docs.size() > 1) {
    config::SourceLoc loc = make_loc(file_label, docs[1].Mark(), "");
    throw_input_error(loc,
                      "YAML syntax error: expected one YAML document, found a second one here");
  }
  YAML::Node root = docs.empty() ? YAML::Node() : docs.front();
  return YamlNode(root, "", file, YAML::Mark());  // Mark() is line 0, column 0: the file's start
}

config::SourceLoc YamlNode::loc() const {
  // An empty value's mark points at whatever follows it; its key is the better place.
  if (node_.IsDefined() && !node_.IsNull() && valid(node_.Mark()))
    return make_loc(*file_, node_.Mark(), path_);
  if (valid(key_mark_)) return make_loc(*file_, key_mark_, path_);
  return make_loc(*file_, node_.IsDefined() ? node_.Mark() : YAML::Mark::null_mark(), path_);
}

config::SourceLoc YamlNode::key_loc() const {
  if (valid(key_mark_) && !path_.empty() && path_.back() != ']')
    return make_loc(*file_, key_mark_, path_);
  return loc();
}

std::string YamlNode::found() const {
  if (is_null()) return "nothing";
  if (node_.IsScalar()) {
    std::string s = node_.Scalar();
    if (s.size() > 60) s = s.substr(0, 57) + "...";
    const std::string tag = given_tag(node_);
    return fmt::format("'{}'{}", s,
                       tag.empty()  ? ""
                       : tag == "!" ? " (a quoted string)"
                                    : fmt::format(" (tagged {})", tag));
  }
  if (node_.IsSequence()) {
    const std::size_t n = node_.size();
    bool flat = n <= 6;
    for (const auto& item : node_) flat = flat && item.IsScalar();
    if (flat) {
      std::vector<std::string> parts;
      for (const auto& item : node_) parts.push_back(item.Scalar());
      return fmt::format("'[{}]'", join(parts));
    }
    return fmt::format("a list of {} item{}", n, n == 1 ? "" : "s");
  }
  return "a map";
}

void YamlNode::fail(std::string_view message) const {
  throw_input_error(loc(), message);
}

void YamlNode::fail_expected(std::string_view what) const {
  fail(fmt::format("expected {}, found {}", what, found()));
}

double YamlNode::as_number(const Range& range) const {
  const std::string desc = range.describe();
  const std::string what = desc.empty() ? "a number" : fmt::format("a number {}", desc);
  if (!node_.IsScalar() || !readable_as(node_, {"!!float", "!!int"})) fail_expected(what);
  const auto v = parse_double(node_.Scalar());
  if (!v) fail_expected(what);
  if (!std::isfinite(*v)) fail_expected(desc.empty() ? "a finite number" : what);
  if (!range.contains(*v)) fail_expected(what);
  return *v;
}

std::int64_t YamlNode::as_integer(const Range& range) const {
  const std::string desc = range.describe();
  const std::string what = desc.empty() ? "an integer" : fmt::format("an integer {}", desc);
  if (!node_.IsScalar() || !readable_as(node_, {"!!int", "!!float"})) fail_expected(what);
  const auto i = parse_integer(node_.Scalar());  // (also 1e5 or 100000.0)
  if (!i || !range.contains(static_cast<double>(*i))) fail_expected(what);
  return *i;
}

bool YamlNode::as_bool() const {
  if (node_.IsScalar() && readable_as(node_, {"!!bool"}))
    if (const auto b = parse_bool(node_.Scalar())) return *b;
  fail_expected("true or false");
}

std::string YamlNode::as_string() const {
  if (!node_.IsScalar()) fail_expected("a string");
  return node_.Scalar();
}

std::string YamlNode::as_choice(std::initializer_list<std::string_view> choices) const {
  return as_choice(std::span<const std::string_view>(choices.begin(), choices.size()));
}

std::string YamlNode::as_choice(std::span<const std::string_view> choices) const {
  std::vector<std::string> names(choices.begin(), choices.end());
  const std::string what = fmt::format("one of {}", join(names));
  if (!node_.IsScalar()) fail_expected(what);
  const std::string s = node_.Scalar();
  if (std::find(names.begin(), names.end(), s) != names.end()) return s;
  if (auto near = closest_match(s, names))
    fail(fmt::format("expected {}, found '{}' (did you mean '{}'?)", what, s, *near));
  fail_expected(what);
}

Vec3 YamlNode::as_vec3() const {
  if (node_.IsSequence() && node_.size() == 2)
    fail(fmt::format(
        "expected 3 components in a 3D case ([x, y, z]), found {} (2 components are for "
        "dimension: 2)",
        found()));
  if (!node_.IsSequence() || node_.size() != 3) fail_expected("a list of 3 numbers [x, y, z]");
  const auto items = as_list();
  return {items[0].as_number(), items[1].as_number(), items[2].as_number()};
}

Vec3 YamlNode::as_direction() const {
  const Vec3 v = as_vec3();
  const double n = norm(v);
  if (!(n > 0)) fail_expected("a non-zero vector [x, y, z]");
  return v / n;
}

Vec3 YamlNode::as_vec(int dimension) const {
  if (dimension != 2) return as_vec3();
  if (node_.IsSequence() && node_.size() == 3)
    fail(fmt::format("expected 2 components in a 2D case ([x, y]; z is 0), found {}", found()));
  if (!node_.IsSequence() || node_.size() != 2) fail_expected("a list of 2 numbers [x, y]");
  const auto items = as_list();
  return {items[0].as_number(), items[1].as_number(), 0.0};
}

Vec3 YamlNode::as_direction(int dimension) const {
  if (dimension != 2) return as_direction();
  const Vec3 v = as_vec(dimension);
  const double n = norm(v);
  if (!(n > 0)) fail_expected("a non-zero vector [x, y]");
  return v / n;
}

std::vector<YamlNode> YamlNode::as_list(std::size_t min_items) const {
  if (!node_.IsSequence()) {
    fail_expected(min_items > 0 ? fmt::format("a list of at least {} item{}", min_items,
                                              min_items == 1 ? "" : "s")
                                : std::string("a list"));
  }
  if (node_.size() < min_items)
    fail_expected(
        fmt::format("a list of at least {} item{}", min_items, min_items == 1 ? "" : "s"));
  std::vector<YamlNode> out;
  out.reserve(node_.size());
  std::size_t i = 0;
  for (const auto& item : node_) {
    out.emplace_back(item, fmt::format("{}[{}]", path_, i), file_, item.Mark());
    ++i;
  }
  return out;
}

YamlNode YamlNode::child(const YAML::Node& value, const std::string& key,
                         YAML::Mark key_mark) const {
  return YamlNode(value, child_path(path_, key), file_, key_mark);
}

// ---------------------------------------------------------------------------------------------
// YamlMap

YamlMap::YamlMap(const YamlNode& node) : YamlMap(node, nullptr) {}

YamlMap::YamlMap(const YamlNode& node, const std::vector<std::string>* keys) : node_(node) {
  if (!node.raw().IsMap())
    node.fail_expected(keys ? fmt::format("a map with keys among: {}", join(*keys))
                            : "a map of 'key: value' entries");
  for (auto it = node.raw().begin(); it != node.raw().end(); ++it) {
    // Copies: yaml-cpp's iterator returns a temporary, a reference to its member would dangle.
    const YAML::Node k = it->first;
    const YAML::Node v = it->second;
    if (!k.IsScalar()) {
      YamlNode(k, node.path(), std::make_shared<const std::string>(node.file()), k.Mark())
          .fail_expected("a plain key");
    }
    for (const auto& e : entries_) {
      if (e.key == k.Scalar()) {
        throw_input_error(make_loc(node.file(), k.Mark(), child_path(node.path(), e.key)),
                          fmt::format("duplicate key '{}' (first given at line {})", e.key,
                                      e.key_node.Mark().line + 1));
      }
    }
    entries_.push_back({k.Scalar(), k, v});
  }
}

YamlMap::YamlMap(const YamlNode& node, std::vector<std::string> accepted)
    : YamlMap(node, &accepted) {
  accepted_ = std::move(accepted);
  check_keys(accepted_);
}

void YamlMap::check_keys(const std::vector<std::string>& accepted, std::string_view what) const {
  for (const auto& e : entries_) {
    if (std::find(accepted.begin(), accepted.end(), e.key) != accepted.end()) continue;
    std::string hint;
    if (auto near = closest_match(e.key, accepted))
      hint = fmt::format(" (did you mean '{}'?)", *near);
    throw_input_error(make_loc(node_.file(), e.key_node.Mark(), child_path(node_.path(), e.key)),
                      fmt::format("unknown key '{}'{}; {}: {}", e.key, hint, what, join(accepted)));
  }
}

const YamlMap::Entry* YamlMap::lookup(std::string_view key) const {
  for (const auto& e : entries_)
    if (e.key == key) return &e;
  return nullptr;
}

YamlNode YamlMap::value_node(const Entry& e) const {
  return node_.child(e.value, e.key, e.key_node.Mark());
}

bool YamlMap::has(std::string_view key) const {
  const Entry* e = lookup(key);
  return e && !(e->value.IsNull());
}

YamlNode YamlMap::at(std::string_view key) const {
  if (const Entry* e = lookup(key)) return value_node(*e);
  config::SourceLoc loc = node_.key_loc();
  loc.key_path = child_path(node_.path(), key);
  // A key present but not accepted may be a misspelling of the missing one.
  std::vector<std::string> others;
  for (const auto& e : entries_)
    if (std::find(accepted_.begin(), accepted_.end(), e.key) == accepted_.end())
      others.push_back(e.key);
  std::string hint;
  if (auto near = closest_match(key, others))
    hint = fmt::format(" (is '{}' a misspelling of it?)", *near);
  throw_input_error(loc,
                    fmt::format("missing required key '{}' in {}{}", key,
                                node_.path().empty() ? std::string("the top level of the case file")
                                                     : fmt::format("'{}'", node_.path()),
                                hint));
}

std::optional<YamlNode> YamlMap::find(std::string_view key) const {
  const Entry* e = lookup(key);
  if (!e || e->value.IsNull()) return std::nullopt;
  return value_node(*e);
}

double YamlMap::number(std::string_view key, const Range& range) const {
  return at(key).as_number(range);
}

double YamlMap::number_or(std::string_view key, double fallback, const Range& range) const {
  auto n = find(key);
  return n ? n->as_number(range) : fallback;
}

std::optional<double> YamlMap::optional_number(std::string_view key, const Range& range) const {
  auto n = find(key);
  if (!n) return std::nullopt;
  return n->as_number(range);
}

std::int64_t YamlMap::integer(std::string_view key, const Range& range) const {
  return at(key).as_integer(range);
}

std::string YamlMap::string(std::string_view key) const {
  return at(key).as_string();
}

Vec3 YamlMap::vec3(std::string_view key) const {
  return at(key).as_vec3();
}

Vec3 YamlMap::vec3_or(std::string_view key, const Vec3& fallback) const {
  auto n = find(key);
  return n ? n->as_vec3() : fallback;
}

bool YamlMap::boolean_or(std::string_view key, bool fallback) const {
  auto n = find(key);
  return n ? n->as_bool() : fallback;
}

std::vector<std::pair<YamlNode, YamlNode>> YamlMap::entries() const {
  std::vector<std::pair<YamlNode, YamlNode>> out;
  for (const auto& e : entries_) {
    YamlNode v = value_node(e);
    out.emplace_back(node_.child(e.key_node, e.key, e.key_node.Mark()), v);
  }
  return out;
}

std::string YamlMap::exactly_one_of(const std::vector<std::string>& keys) const {
  std::vector<const Entry*> present;
  for (const auto& k : keys)
    if (const Entry* e = lookup(k)) present.push_back(e);
  if (present.empty()) {
    node_.fail(fmt::format("expected one of the keys {}, found none of them", join(keys)));
  }
  if (present.size() > 1) {
    // Report at the later of the two in the document.
    const Entry* a = present[0];
    const Entry* b = present[1];
    if (b->key_node.Mark().pos < a->key_node.Mark().pos) std::swap(a, b);
    throw_input_error(make_loc(node_.file(), b->key_node.Mark(), child_path(node_.path(), b->key)),
                      fmt::format("give only one of {}; found both '{}' (line {}) and '{}'",
                                  join(keys), a->key, a->key_node.Mark().line + 1, b->key));
  }
  return present.front()->key;
}

std::optional<YamlNode> YamlMap::find_either(std::string_view key, std::string_view alias) const {
  if (has(key) && has(alias)) exactly_one_of({std::string(key), std::string(alias)});
  return has(key) ? find(key) : find(alias);
}

}  // namespace gf::input
