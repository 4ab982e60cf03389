// SPDX-License-Identifier: GPL-3.0-or-later
// Atomic writes: all output goes through here.
#include "core/files.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/error.hpp"

namespace gf {

namespace fs = std::filesystem;

static fs::path temp_name(const fs::path& path) {
  return path.parent_path() / fmt::format(".{}.tmp{}", path.filename().string(), ::getpid());
}

void write_atomically_path(const fs::path& path,
                           const std::function<void(const fs::path&)>& write) {
  const fs::path tmp = temp_name(path);
  try {
    write(tmp);
    fs::rename(tmp, path);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

void write_atomically(const fs::path& path, const std::function<void(std::ostream&)>& write) {
  write_atomically_path(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw IoError(fmt::format("cannot open '{}' for writing", tmp.string()));
    write(out);
    out.flush();
    if (!out) throw IoError(fmt::format("error while writing '{}'", tmp.string()));
  });
}

std::string read_text_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(fmt::format("cannot open '{}' for reading", path.string()));
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> continued_csv_lines(const std::filesystem::path& file,
                                             const std::string& header,
                                             const std::function<bool(double)>& keep) {
  std::vector<std::string> lines;
  if (!std::filesystem::exists(file)) return lines;
  std::istringstream in(read_text_file(file));
  std::string line;
  std::getline(in, line);
  // Columns this build appends to the series that the file lacks.
  std::string padding;
  if (line != header) {
    if (!line.empty() && header.starts_with(line + ',')) {
      const std::string added = header.substr(line.size());
      for (char c : added)
        if (c == ',') padding += ",nan";
    } else {
      throw InputError(fmt::format(
          "{}: the series to continue has the columns '{}', this run writes '{}' (--append needs "
          "the same outputs as the run it continues)",
          file.string(), line, header));
    }
  }
  while (std::getline(in, line)) {
    char* end = nullptr;
    const double t = std::strtod(line.c_str(), &end);
    if (end == line.c_str() || !keep(t)) break;
    lines.push_back(line + padding);
  }
  return lines;
}

}  // namespace gf
