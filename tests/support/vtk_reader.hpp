// SPDX-License-Identifier: GPL-3.0-or-later
// Reads back the VTK XML files grainflow writes (appended raw binary blocks with UInt64 byte
// counts, core/vtk_xml.hpp), for tests of the particle, wall, finite-element and finite-volume
// writers.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/files.hpp"

namespace gf::test {

/// A parsed VTK XML file with appended raw data (core/vtk_xml.hpp): the XML header, its
/// DataArray tags keyed "Section/Name", and the raw appended bytes.
struct VtkFile {
  std::string header;
  std::string appended;  // bytes after the '_' marker up to the closing tag
  std::map<std::string, std::map<std::string, std::string>> arrays;  // "Section/Name" -> attrs

  /// `name="value"` pairs of one tag's text (without the angle brackets).
  static std::map<std::string, std::string> attributes(const std::string& tag) {
    std::map<std::string, std::string> a;
    std::size_t pos = tag.find(' ');
    while (pos != std::string::npos) {
      const std::size_t eq = tag.find("=\"", pos);
      if (eq == std::string::npos) break;
      const std::size_t end = tag.find('"', eq + 2);
      const std::size_t start = tag.find_first_not_of(' ', pos);
      a[tag.substr(start, eq - start)] = tag.substr(eq + 2, end - eq - 2);
      pos = end + 1;
    }
    return a;
  }

  /// The text of every tag in the header, in document order ("DataArray type=... /").
  std::vector<std::string> tags() const {
    std::vector<std::string> out;
    for (std::size_t pos = header.find('<'); pos != std::string::npos;
         pos = header.find('<', pos + 1))
      out.push_back(header.substr(pos + 1, header.find('>', pos) - pos - 1));
    return out;
  }

  explicit VtkFile(const std::filesystem::path& p) {
    const std::string text = read_text_file(p);
    const std::string open = "<AppendedData encoding=\"raw\">";
    const std::size_t pos = text.find(open);
    EXPECT_NE(pos, std::string::npos);
    header = text.substr(0, pos);
    const std::size_t mark = text.find('_', pos);
    const std::string tail = "\n  </AppendedData>\n</VTKFile>\n";
    EXPECT_EQ(text.substr(text.size() - tail.size()), tail);
    appended = text.substr(mark + 1, text.size() - tail.size() - mark - 1);
    // Each DataArray is keyed by its enclosing element (PointData, CellData, Points, Verts,
    // Polys, Lines, Cells).
    std::string section;
    std::uint64_t last_offset = 0;
    for (const std::string& t : tags()) {
      const std::string name = t.substr(0, t.find_first_of(" />"));
      if (name == "DataArray") {
        auto a = attributes(t);
        const std::uint64_t offset = std::stoull(a["offset"]);
        EXPECT_TRUE(arrays.empty() || offset > last_offset) << "blocks out of document order";
        last_offset = offset;
        arrays[section + "/" + a["Name"]] = a;
      } else if (name == "PointData" || name == "CellData" || name == "Points" || name == "Verts" ||
                 name == "Polys" || name == "Lines" || name == "Cells") {
        section = name;
      }
    }
  }

  std::string piece(const std::string& key) const {
    for (const std::string& t : tags())
      if (t.rfind("Piece ", 0) == 0) return attributes(t)[key];
    return "";
  }

  /// The values of one array; checks its declared type and component count.
  template <class T>
  std::vector<T> get(const std::string& key, const char* type, int n_components) const {
    auto it = arrays.find(key);
    if (it == arrays.end()) {
      ADD_FAILURE() << "no array " << key;
      return {};
    }
    const auto& a = it->second;
    EXPECT_EQ(a.at("type"), type) << key;
    EXPECT_EQ(a.at("format"), "appended") << key;
    EXPECT_EQ(std::stoi(a.at("NumberOfComponents")), n_components) << key;
    const std::size_t off = std::stoull(a.at("offset"));
    std::uint64_t n_bytes = 0;
    std::memcpy(&n_bytes, appended.data() + off, sizeof n_bytes);
    EXPECT_LE(off + sizeof n_bytes + n_bytes, appended.size()) << key;
    EXPECT_EQ(n_bytes % sizeof(T), 0u) << key;
    std::vector<T> v(n_bytes / sizeof(T));
    if (n_bytes > 0) std::memcpy(v.data(), appended.data() + off + sizeof n_bytes, n_bytes);
    return v;
  }

  /// Sum of the block sizes must equal the appended section: no stray or missing bytes.
  std::uint64_t blocks_size() const {
    std::uint64_t total = 0;
    for (const auto& [key, a] : arrays) {
      std::uint64_t n = 0;
      std::memcpy(&n, appended.data() + std::stoull(a.at("offset")), sizeof n);
      total += sizeof n + n;
    }
    return total;
  }
};

}  // namespace gf::test
