// SPDX-License-Identifier: GPL-3.0-or-later
// Memory estimates of a case against the machine's memory (or GRAINFLOW_MEMORY_LIMIT).
//
// The bytes per item (memory_budget.hpp) are slopes of the peak resident set size
// (/usr/bin/time -v, "Maximum resident set size") between two sizes of the same case, a Release
// build, one thread, a few steps (so the fixed cost of the program cancels out):
//  - DEM grain: cases/dem/terrain_settling with an hcp fill at spacing 1.001 x the diameter
//    (every grain with its ~12 neighbours listed: a dense packing's Verlet list), 200 steps:
//    28356 grains 33.7 MB, 233421 grains 109.1 MB -> 386 B per grain (a loose cubic fill:
//    300-370 B). The particle store's columns (position, velocity, force, torque, angular
//    velocity, orientation, radius, mass, ...), the Verlet list with its contact history and
//    the fill's transient buffers. Taken as 400 B for spheres; disks, spherocylinders and
//    polygons: bytes_per_grain (memory_budget.hpp).
//  - neighbour cell: the same box, 2 m wide, holding 10 grains of radius 2 mm (cutoff 5 mm: 400^3
//    = 6.4e7 cells): 1.04 GB -> 16 B per cell, CellList's two 64-bit arrays (start_, fill_).
//    The grid is capped at 1024 cells per axis and, since 2026-12-05, at max(2^20, 8 per grain)
//    cells in all (CellList::grid): those 10 grains now get 2^20 cells, 17 MB.
//  - lattice site: a lattice fill that picks a volume_fraction's grains at random among its
//    sites first lists every site (a Vec3, 24 B) and shuffles their indices (8 B):
//    boundaries/fill.cpp. 32 B.
//  - SPH particle: cases/continuum/dam_break_cylinder (2D) at spacing 0.005 and 0.0025 m, 20
//    steps: 8976 particles 25.7 MB, 35904 particles 42.6 MB -> 644 B; a 3D box of water on a
//    floor at spacing 0.005 and 0.0033 m: 16896 and 60480 particles, 33.8 and 65.8 MB ->
//    752 B (more neighbours per particle in 3D: ~74 against ~21). Taken as 800 B.
//  - two-fluid cell: cases/two_fluid/bubbling_bed at 40 x 120 and 120 x 360 cells, 3 steps: 36.1
//    and 190.7 MB -> 4123 B per cell; a 3D bed at 10 x 10 x 30 and 20 x 20 x 60: 32.3 and
//    113.0 MB -> 3937 B (fields of both phases, the fraction and momentum matrices and their
//    solvers' work space). Taken as 4200 B.
//  - CFD-DEM fluid cell: cases/cfd_dem/fluidized_bed at 16 x 4 x 60 and 40 x 10 x 150 cells,
//    200 steps: 33.9 and 146.6 MB -> 2054 B per cell. Taken as 2200 B.
#include "io/input/memory_budget.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <utility>

#include "io/input/yaml_reader.hpp"
#include "neighbor/cell_list.hpp"

namespace gf::input {

namespace {

constexpr const char* kLimitVariable = "GRAINFLOW_MEMORY_LIMIT";

/// The value of GRAINFLOW_MEMORY_LIMIT in bytes, or nothing when it is not set.
std::optional<double> limit_from_environment() {
  const char* env = std::getenv(kLimitVariable);
  if (env == nullptr || *env == '\0') return std::nullopt;
  const std::string_view text(env);
  double v = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  std::string_view unit(ptr, static_cast<std::size_t>(text.data() + text.size() - ptr));
  while (!unit.empty() && unit.front() == ' ') unit.remove_prefix(1);
  // [k|K|M|G|T][i][B]: powers of 1000, or of 1024 with the i
  std::optional<double> factor;
  if (!unit.empty() && unit.back() == 'B') unit.remove_suffix(1);
  if (unit.empty()) {
    factor = 1.0;
  } else {
    const std::string_view prefixes = "kMGT";
    const std::size_t p = prefixes.find(unit.front() == 'K' ? 'k' : unit.front());
    unit.remove_prefix(1);
    if (p != std::string_view::npos && (unit.empty() || unit == "i"))
      factor = std::pow(unit.empty() ? 1000.0 : 1024.0, static_cast<double>(p + 1));
  }
  if (ec != std::errc() || ptr == text.data() || !factor || !std::isfinite(v) || !(v > 0))
    throw_input_error(
        config::SourceLoc{kLimitVariable, 0, 0, ""},
        fmt::format("expected a memory size in bytes (such as 8e9, 512M, 16G or 16GiB), found '{}'",
                    text));
  return v * *factor;
}

}  // namespace

double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page = sysconf(_SC_PAGESIZE);
  double bytes =
      pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 0.0;
  // In a container (a CI runner, docker --memory) the limit is the control group's, not the
  // host's: cgroup v2 memory.max ("max" when none), v1 memory.limit_in_bytes (a huge number).
  for (const char* f :
       {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    std::ifstream in(f);
    double limit = 0;
    if (in >> limit && limit > 0 && (bytes <= 0 || limit < bytes)) bytes = limit;
  }
  return bytes;
}

double memory_limit_bytes() {
  if (const auto env = limit_from_environment()) return *env;
  const double phys = physical_memory_bytes();
  return phys > 0 ? phys : std::numeric_limits<double>::infinity();
}

std::string bytes_text(double bytes) {
  static const char* const units[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
  int u = 0;
  while (u < 6 && bytes >= 999.5) {
    bytes /= 1000;
    ++u;
  }
  if (bytes >= 999.5) return fmt::format("{:.3g} EB", bytes);  // (beyond exabytes)
  return fmt::format("{:.3g} {}", bytes, units[u]);
}

double neighbour_cells(const Vec3& length, double cutoff, int dimension, double particles) {
  Vec3 l = length;
  if (dimension == 2) l.z = 2.0 * std::max(cutoff, 1e-3);
  if (!(cutoff > 0)) return 1024.0 * 1024.0 * 1024.0;
  const double n = std::clamp(std::isfinite(particles) ? particles : 0.0, 0.0, kMaxIndexed);
  const auto nc = CellList::grid(l, cutoff, static_cast<std::size_t>(n));
  return static_cast<double>(nc[0]) * nc[1] * nc[2];
}

std::optional<std::string> check_memory_use(const config::SourceLoc& loc, std::string_view what,
                                            double bytes) {
  const double limit = memory_limit_bytes();
  const bool from_env = limit_from_environment().has_value();
  const std::string machine =
      from_env ? fmt::format("the limit {} sets is {}", kLimitVariable, bytes_text(limit))
               : fmt::format("this machine has {}", bytes_text(limit));
  if (!(bytes <= limit))
    throw_input_error(loc, fmt::format("expected a case that fits in memory ({}), found that {} "
                                       "need about {}",
                                       machine, what, bytes_text(bytes)));
  if (bytes > 0.5 * limit)
    return fmt::format("{}: {} need about {} of memory, more than half of it ({})",
                       loc.key_path.empty() ? std::string("the case") : loc.key_path, what,
                       bytes_text(bytes), machine);
  return std::nullopt;
}

}  // namespace gf::input
