// SPDX-License-Identifier: GPL-3.0-or-later
// Dispatch of `fluid_fem:` cases from the grainflow command line.
#include "simulation/fem_case.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/stop.hpp"

namespace gf {

namespace fs = std::filesystem;

std::optional<fem::FemCaseConfig> load_fem_case(const fs::path& file, fs::path& output_dir) {
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(file.string());
  } catch (const YAML::BadFile&) {
    throw InputError(fmt::format("{}: error: cannot open the case file", file.string()));
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}:{}:{}: error: YAML syntax: {}", file.string(), e.mark.line + 1,
                                 e.mark.column + 1, e.msg));
  }
  if (!doc.IsMap() || !doc["fluid_fem"]) return std::nullopt;
  for (const auto& kv : doc) {
    const auto key = kv.first.as<std::string>();
    if (key != "name" && key != "fluid_fem" && key != "output") {
      const auto m = kv.first.Mark();
      throw InputError(fmt::format(
          "{}:{}:{}: error: {}: unknown key in a fluid_fem case; expected one of: name, "
          "fluid_fem, output",
          file.string(), m.line + 1, m.column + 1, key));
    }
  }
  output_dir = fs::path("out") / file.parent_path().filename();
  if (const auto out = doc["output"]) {
    const auto m = out.Mark();
    if (!out.IsMap() || out.size() != 1 || !out["directory"] || !out["directory"].IsScalar())
      throw InputError(
          fmt::format("{}:{}:{}: error: output: expected {{directory: FOLDER}} in a fluid_fem case "
                      "(the FEM outputs are configured in fluid_fem.output)",
                      file.string(), m.line + 1, m.column + 1));
    output_dir = out["directory"].as<std::string>();
  }
  return fem::parse_fluid_fem(doc["fluid_fem"], file.string());
}

int run_fem_case(const fem::FemCaseConfig& cfg, const fs::path& default_dir,
                 const RunOptions& opts) {
  const fs::path dir = opts.output.empty() ? default_dir : opts.output;
  prepare_output_dir(dir, opts.overwrite);
  log::info("fluid_fem run, output in '{}'", dir.string());
  const int sig = fem::run_fluid_fem(cfg, dir, opts.steps ? static_cast<int>(*opts.steps) : -1);
  if (sig)
    log::warn("fluid_fem run stopped by {}: outputs up to the last step written in '{}'",
              stop::signal_name(sig), dir.string());
  return sig;
}

}  // namespace gf
