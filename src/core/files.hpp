// SPDX-License-Identifier: GPL-3.0-or-later
// Atomic file writes (temporary file, then rename) so a failed run never leaves a half file.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace gf {

/// Writes a file by calling `write` on a stream to `path.tmp`, then renames it over `path`.
void write_atomically(const std::filesystem::path& path,
                      const std::function<void(std::ostream&)>& write);

/// Writes a file through a callback that receives a temporary path, then renames it.
void write_atomically_path(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path&)>& write);

/// Full contents of a text file; throws IoError naming the file.
std::string read_text_file(const std::filesystem::path& path);

/// For continuing a time-series CSV that an earlier run wrote (--append): its data lines, in
/// order, while `keep(t)` holds for a line's first field t (a line whose first field is not a
/// number ends them). The file's first line must equal `header` (else InputError naming both),
/// or be its first columns: a series written by an earlier build before columns were added at
/// the end, whose lines then get "nan" in those columns. A missing file has no lines.
std::vector<std::string> continued_csv_lines(const std::filesystem::path& file,
                                             const std::string& header,
                                             const std::function<bool(double)>& keep);

}  // namespace gf
