// SPDX-License-Identifier: GPL-3.0-or-later
// Reading chosen columns of a numeric CSV file with a header row (the run's own CSV outputs).
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace gf::test {

/// The values of the columns `names` (in that order) of every data row of the CSV file `path`;
/// a missing file or column is a test failure (and gives no rows).
inline std::vector<std::vector<double>> read_csv_columns(const std::filesystem::path& path,
                                                         const std::vector<std::string>& names) {
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) {
    ADD_FAILURE() << "cannot read " << path;
    return {};
  }
  auto split = [](const std::string& text) {
    std::vector<std::string> fields;
    std::stringstream ss(text);
    std::string f;
    while (std::getline(ss, f, ',')) fields.push_back(f);
    return fields;
  };
  const auto header = split(line);
  std::vector<std::size_t> index;
  for (const auto& n : names) {
    std::size_t k = 0;
    while (k < header.size() && header[k] != n) ++k;
    if (k == header.size()) {
      ADD_FAILURE() << path << " has no column " << n;
      return {};
    }
    index.push_back(k);
  }
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    const auto fields = split(line);
    std::vector<double> row;
    for (std::size_t k : index) row.push_back(k < fields.size() ? std::stod(fields[k]) : 0.0);
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace gf::test
